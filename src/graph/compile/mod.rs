//! `compile`: a pure function of (graph, shader reflections, scene features)
//! to a `Schedule`, in named steps, one module each (docs/ARCHITECTURE.md,
//! "The frame graph"):
//! 1. `validate`: names, formats, access, params and constants;
//! 2. and 3. `cull`: passes whose `requires` the scene lacks, then passes
//!    that reach neither the output nor a history write (`versions` assigns
//!    the resource versions between the two);
//! 4. `order`: topological, stable by file order, cycles named;
//! 5. `lifetimes`: first and last use of each physical group;
//! 6. `textures`: pooling transients by descriptor;
//! 7. `emit`: the `Schedule`.

mod cull;
mod emit;
mod lifetimes;
mod order;
mod split;
mod textures;
mod validate;
mod versions;

use std::collections::BTreeMap;

use crate::error::Location;
use crate::graph::desc::{FrameGraph, PassDesc, ResourceDesc, SizeDesc};
use crate::graph::edit::GraphEdits;
use crate::graph::params::PassParams;
use crate::graph::schedule::*;
use crate::scene::SceneFeatures;
use crate::shader::{BindingInfo, EntryInfo, ShaderInfo};
use cull::{cull_by_requires, cull_unreachable};
use emit::emit_schedule;
use lifetimes::compute_lifetimes;
use order::order_passes;
pub use split::{FLAT_SAMPLES_PER_DISPATCH, SAMPLES_PER_DISPATCH};
use textures::assign_textures;
use validate::validate;
use versions::{assign_groups, assign_versions, check_output_written, writers_of};

/// What kind of mistake a `CompileError` reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// Two passes share a name.
    DuplicatePass,
    /// A pass names a shader that is not in shaders/ (or lies outside it).
    UnknownShader,
    /// A pass's entry point (or `listed` entry, or a split loop's `ENTRY_more`)
    /// is missing or unfit.
    UnknownEntry,
    /// `bind` maps a variable the entry point does not use.
    UnknownBinding,
    /// A binding names neither a graph resource nor an engine resource.
    UnknownResource,
    /// A binding's texel format differs from its resource's.
    FormatMismatch,
    /// A binding's type or access does not fit what it binds.
    WrongAccess,
    /// Two passes write one version of a resource, or a write would discard earlier ones.
    DuplicateWriter,
    /// A pass reads a resource no earlier pass writes, or no pass writes the output.
    UnwrittenRead,
    /// The output is not a declared resource.
    UnknownOutput,
    /// Passes depend on each other in a cycle.
    Cycle,
    /// The shader's `params` has a member the pass does not give.
    MissingParam,
    /// The pass gives a param the shader's `params` lacks.
    UnknownParam,
    /// A param or constant value does not fit, or the engine sets it.
    BadParam,
    /// An override without a default is not given in `constants`.
    MissingConstant,
    /// `constants` names an override the shader does not declare.
    UnknownConstant,
    /// A `--set`, `--skip` or `--stop-after` edit does not apply.
    BadEdit,
    /// A pass's `run` mode is out of range or writes what it may not.
    BadRun,
    /// A size, dispatch or `texels_per_invocation` no texture or dispatch can have.
    BadSize,
}

/// A graph compile error. `pass` and `shader_location` say where; the caller
/// adds the graph file's line (see `graph::locate`).
#[derive(Debug, Clone, PartialEq)]
pub struct CompileError {
    /// What kind of mistake.
    pub kind: ErrorKind,
    /// The pass at fault, if one is.
    pub pass: Option<String>,
    /// Where the shader declares the binding at fault, if one is.
    pub shader_location: Option<Location>,
    /// What is wrong and how to fix it.
    pub message: String,
}

impl std::fmt::Display for CompileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(p) = &self.pass {
            write!(f, "pass `{p}`: ")?;
        }
        write!(f, "{}", self.message)?;
        if let Some(loc) = &self.shader_location {
            write!(f, " (declared at {loc})")?;
        }
        Ok(())
    }
}

fn err(kind: ErrorKind, pass: Option<&str>, message: impl Into<String>) -> CompileError {
    CompileError { kind, pass: pass.map(str::to_string), shader_location: None, message: message.into() }
}

fn err_at(kind: ErrorKind, pass: &str, b: &BindingInfo, message: impl Into<String>) -> CompileError {
    CompileError {
        kind,
        pass: Some(pass.to_string()),
        shader_location: Some(b.location.clone()),
        message: message.into(),
    }
}

/// How `compile` departs from the graph as written: another output, edits,
/// resources kept for reading back, no specialisation, no culling.
#[derive(Debug, Clone, Default)]
pub struct CompileOptions {
    /// Render this resource instead of the graph's `output` (debug views,
    /// per-pass golden images).
    pub output: Option<String>,
    /// `--set`, `--skip`, `--stop-after` (see graph::edit).
    pub edits: GraphEdits,
    /// Resources whose final version is kept (not pooled) until the frame
    /// ends, so the engine can read it back for stats. Absent or unwritten
    /// ones are ignored.
    pub keep: Vec<String>,
    /// Resources computed even where the output does not need them (a
    /// benchmark timing a pass of its own), and kept as `keep` keeps them.
    pub also_compute: Vec<String>,
    /// Leave every shader generic: no override constants from the scene's
    /// features (`--no-specialise`; see scene::specialise).
    pub no_specialise: bool,
    /// Keep the passes whose `requires` the scene lacks (`--no-cull`: to
    /// measure what culling saves; they run on a scene without their work).
    pub no_cull: bool,
}

/// What one binding of a validated pass refers to.
#[derive(Debug, Clone, PartialEq)]
enum Bound {
    Read(String),
    Write { resource: String, in_place: bool },
    Engine(EngineResource),
    Params,
    Run,
    WorkList,
    TilePool,
}

#[derive(Debug, Clone)]
struct PassPlan<'a> {
    desc: &'a PassDesc,
    entry: &'a EntryInfo,
    /// The entry run over the texels `entry` lists (`PassDesc::listed`).
    listed: Option<&'a EntryInfo>,
    bindings: Vec<(&'a BindingInfo, Bound)>,
    params: Option<PassParams>,
    constants: Vec<(String, f64)>,
}

impl PassPlan<'_> {
    fn reads(&self) -> impl Iterator<Item = &str> {
        self.bindings.iter().filter_map(|(_, b)| match b {
            Bound::Read(r) => Some(r.as_str()),
            Bound::Write { resource, in_place: true } => Some(resource.as_str()),
            _ => None,
        })
    }
    fn writes(&self) -> impl Iterator<Item = (&str, bool)> {
        self.bindings.iter().filter_map(|(_, b)| match b {
            Bound::Write { resource, in_place } => Some((resource.as_str(), *in_place)),
            _ => None,
        })
    }
}

/// Compiles a graph. `shaders` maps shader file names to their reflection.
pub fn compile(
    desc: &FrameGraph,
    shaders: &BTreeMap<String, ShaderInfo>,
    features: &SceneFeatures,
    options: &CompileOptions,
) -> Result<Schedule, CompileError> {
    let edited;
    let desc = if options.edits.is_empty() {
        desc
    } else {
        edited = options.edits.apply(desc).map_err(|m| err(ErrorKind::BadEdit, None, m))?;
        &edited
    };
    let split;
    let desc = match split::split_sample_loops(desc, shaders, features)? {
        Some(expanded) => {
            split = expanded;
            &split
        }
        None => desc,
    };
    let probed;
    let desc = match resolve_probe_sizes(desc)? {
        Some(resolved) => {
            probed = resolved;
            &probed
        }
        None => desc,
    };
    let plans = validate(desc, shaders)?;
    let output = options.output.clone().unwrap_or_else(|| desc.output.clone());
    if !desc.resources.contains_key(&output) {
        return Err(err(
            ErrorKind::UnknownOutput,
            None,
            format!("output `{output}` is not a declared resource; declared: {}", names(desc.resources.keys())),
        ));
    }
    let writers = writers_of(&plans);
    let cull_for = if options.no_cull { SceneFeatures::all() } else { *features };
    let (plans, mut culled) = cull_by_requires(plans, &cull_for, desc.probes.map(|p| p.mode));
    let mut versions = assign_versions(desc, &plans, &writers, &culled)?;
    check_output_written(&writers, &versions, &culled, &output)?;
    let (plans, unreachable) = cull_unreachable(desc, plans, &mut versions, &output, &options.also_compute);
    culled.extend(unreachable);
    culled.sort_by_key(|c| desc.passes.iter().position(|p| p.name == c.name));
    let groups = assign_groups(desc, &mut versions);
    let order = order_passes(&plans, &versions, &groups)?;
    let mut kept: Vec<&str> = vec![output.as_str()];
    for r in options.keep.iter().chain(&options.also_compute) {
        if versions.latest(r).is_some() && !kept.contains(&r.as_str()) {
            kept.push(r);
        }
    }
    let lifetimes = compute_lifetimes(&order, &mut versions, &groups, &kept);
    let (textures, group_refs) = assign_textures(desc, &versions, &groups, &lifetimes);
    let mut schedule = emit_schedule(desc, features, &plans, &order, &versions, &groups, &group_refs, textures, culled, &output);
    schedule.kept = kept.iter().map(|r| r.to_string()).collect();
    schedule.specialise = !options.no_specialise;
    if schedule.specialise {
        schedule.specialisations = crate::scene::specialise::specialisations(features);
    }
    Ok(schedule)
}

/// `ProbeTiles` sizes (resources and dispatches) as `Fixed` for the graph's
/// probe grid; None when the graph has none to resolve.
fn resolve_probe_sizes(desc: &FrameGraph) -> Result<Option<FrameGraph>, CompileError> {
    let tiled = |s: &SizeDesc| matches!(s, SizeDesc::ProbeTiles(..));
    let any = desc.resources.values().any(|ResourceDesc::Texture(t)| tiled(&t.size)) || desc.passes.iter().any(|p| p.dispatch.as_ref().is_some_and(tiled));
    if !any {
        return Ok(None);
    }
    let mut g = desc.clone();
    let check = |s: SizeDesc, pass: Option<&str>| -> Result<SizeDesc, CompileError> {
        if let SizeDesc::ProbeTiles(w, h) = s {
            desc.check_tiles(w, h).map_err(|m| err(ErrorKind::BadSize, pass, m))?;
        }
        Ok(s.for_probes(desc.probes.map_or(1, |p| p.per_axis())))
    };
    for ResourceDesc::Texture(t) in g.resources.values_mut() {
        t.size = check(t.size, None)?;
    }
    for p in &mut g.passes {
        if let Some(d) = p.dispatch {
            p.dispatch = Some(check(d, Some(&p.name))?);
        }
    }
    Ok(Some(g))
}

fn names<'a>(it: impl Iterator<Item = &'a String>) -> String {
    let v: Vec<&str> = it.map(String::as_str).collect();
    if v.is_empty() { "(none)".into() } else { v.join(", ") }
}

