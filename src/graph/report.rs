//! Human-readable and Graphviz views of a schedule (`glint graph check`).

use std::fmt::Write;

use crate::graph::schedule::{CullReason, Schedule, TexRef};
use crate::scene::Feature;

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

fn tex_name(t: TexRef) -> String {
    match t {
        TexRef::Fixed(i) => format!("t{i}"),
        TexRef::PingPong { textures, .. } => format!("t{}/t{}", textures[0], textures[1]),
    }
}

/// The schedule as text: order, culled passes and why, resources with
/// lifetimes, physical textures and memory at `screen`.
pub fn text(s: &Schedule, screen: (u32, u32)) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "graph `{}`; scene features: [{}]", s.name, s.features.names().join(", "));
    let _ = writeln!(o, "\norder:");
    for (i, p) in s.passes.iter().enumerate() {
        let consts = if p.constants.is_empty() {
            String::new()
        } else {
            format!(" constants {{{}}}", p.constants.iter().map(|(k, v)| format!("{k}: {v}")).collect::<Vec<_>>().join(", "))
        };
        let entry = match &p.listed {
            Some(l) => format!("{}, then {l} over its work list", p.entry),
            None => p.entry.clone(),
        };
        let _ = writeln!(
            o,
            "  {i}. {} ({}:{entry}){consts}\n       runs {}; reads [{}]  writes [{}]",
            p.name,
            p.shader,
            p.run.describe(),
            p.reads.join(", "),
            p.writes.join(", ")
        );
    }
    let _ = writeln!(o, "\nculled:");
    if s.culled.is_empty() {
        let _ = writeln!(o, "  (none)");
    }
    for c in &s.culled {
        let why = match &c.reason {
            CullReason::Requires(f) if f.iter().all(|f| matches!(f, Feature::ThesisProbes | Feature::DdgiProbes)) => format!(
                "requires {}; the graph's probes.mode is another",
                f.iter().map(|f| format!("{f:?}")).collect::<Vec<_>>().join(", ")
            ),
            CullReason::Requires(f) => format!(
                "requires {}; the scene has none",
                f.iter().map(|f| format!("{f:?}")).collect::<Vec<_>>().join(", ")
            ),
            CullReason::Unreachable => "contributes neither to the output nor to a history or persistent resource".into(),
        };
        let _ = writeln!(o, "  {}: {why}", c.name);
    }
    let _ = writeln!(o, "\nspecialised (override constants, for every shader that declares them):");
    if s.specialisations.is_empty() {
        let _ = writeln!(o, "  (none: generic shaders)");
    }
    for sp in &s.specialisations {
        let _ = writeln!(o, "  {} = {}: {}", sp.constant, sp.value, sp.reason);
    }
    let _ = writeln!(o, "\nresources (version: texture, produced at .. last read at):");
    for v in &s.versions {
        let at = |x: Option<usize>| x.map(|i| i.to_string()).unwrap_or_else(|| "-".into());
        let _ = writeln!(
            o,
            "  {}@{}: {}, {} .. {}",
            v.resource,
            v.version,
            tex_name(v.texture),
            if v.version == 0 { "previous frame".to_string() } else { at(v.first_use) },
            at(v.last_use)
        );
    }
    let _ = writeln!(o, "\nphysical textures at {}x{}:", screen.0, screen.1);
    for (i, t) in s.textures.iter().enumerate() {
        let (w, h) = t.size.resolve(screen);
        let _ = writeln!(
            o,
            "  t{i}: {:?} {w}x{h}{} <- {}",
            t.format,
            if t.persistent { " persistent" } else if t.history { " history" } else { "" },
            t.label
        );
    }
    let m = s.memory(screen);
    let _ = writeln!(
        o,
        "\nmemory: {} textures, {} bytes ({:.2} MiB); pooling saves {} bytes ({:.2} MiB)",
        m.textures,
        m.bytes,
        mib(m.bytes),
        m.bytes_saved,
        mib(m.bytes_saved)
    );
    let _ = writeln!(o, "output: {} in {}", s.output_resource, tex_name(s.output));
    o
}

/// Graphviz: passes as boxes, resource versions as ellipses.
pub fn dot(s: &Schedule) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "digraph \"{}\" {{\n  rankdir=LR;", s.name);
    for p in &s.passes {
        let _ = writeln!(o, "  \"{}\" [shape=box];", p.name);
        for r in &p.reads {
            let _ = writeln!(o, "  \"{r}\" -> \"{}\";", p.name);
        }
        for w in &p.writes {
            let _ = writeln!(o, "  \"{}\" -> \"{w}\";", p.name);
        }
    }
    for c in &s.culled {
        let _ = writeln!(o, "  \"{}\" [shape=box, style=dashed, color=gray];", c.name);
    }
    let _ = writeln!(o, "}}");
    o
}
