//! `glint bake`: builds a graph's irradiance volume alone (the passes that
//! fill its persistent resources; the image passes are culled), with a
//! progress bar, and reports seconds and MiB; `--out` saves it for
//! `glint render --volume`. `glint bench bake` redoes the thesis's tables
//! 3.1 and 3.2 with it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};

use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::desc::{FrameGraph, ParamValue, ProbeMode, ResourceDesc, RunMode, SizeDesc};
use crate::graph::{self, CompileOptions};
use crate::scene::{self, Feature};
use crate::session::{Session, SessionOptions};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Mode {
    Thesis,
    Ddgi,
}

#[derive(Args, Debug, Clone)]
pub struct BakeArgs {
    pub scene: PathBuf,
    /// The graph whose volume to bake.
    #[arg(long, default_value = "passes/irradiance.ron")]
    pub graph: PathBuf,
    #[arg(long, value_enum, default_value = "thesis")]
    pub mode: Mode,
    /// Probe level L: (L+1)^3 probes (default: the graph's).
    #[arg(long)]
    pub level: Option<u32>,
    /// Thesis mode: samples per axis S of each hemisphere map (default: the graph's).
    #[arg(long)]
    pub spa: Option<u32>,
    /// Paths per bucket (thesis) or updates (ddgi) (default: the graph's `until`).
    #[arg(long)]
    pub paths: Option<u32>,
    /// Bounces per path (thesis); ddgi: 1 is direct light at ray hits only,
    /// more is every bounce through the volume.
    #[arg(long)]
    pub bounces: Option<u32>,
    /// Thesis mode: 0 path traced, 1 Greger et al.'s diffuse radiance.
    #[arg(long)]
    pub method: Option<u32>,
    /// Iterations per frame (at most 64; thesis mode: DDGI updates once a
    /// frame).
    #[arg(long, default_value_t = 64)]
    pub per_frame: u32,
    /// Save the volume here (for `glint render --volume`).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// What one bake measured.
pub struct Baked {
    pub seconds: f64,
    /// `Scene::content_hash` of the scene as loaded (for the volume file).
    pub scene_hash: u64,
    /// The irradiance volume shading reads (thesis: (L+1)^3 2 S^2 16 bytes).
    pub volume_bytes: u64,
    /// Every persistent texture, the bake's working ones included.
    pub all_bytes: u64,
    pub session: Session,
}

const MIB: f64 = 1024.0 * 1024.0;

pub fn run(args: BakeArgs) -> Result<(), UserError> {
    let gpu = Gpu::new()?;
    let scene_file = args.scene.clone();
    let b = bake(&gpu, &args, true)?;
    out!(
        "baked {} ({:?} mode) in {:.2} s: volume {:.2} MiB ({} bytes; {:.2} MiB with the bake's working textures)",
        scene_file.display(),
        args.mode,
        b.seconds,
        b.volume_bytes as f64 / MIB,
        b.volume_bytes,
        b.all_bytes as f64 / MIB
    );
    if let Some(out) = &args.out {
        let header = b.session.volume_header(&scene_file.display().to_string(), b.scene_hash, settings(&args))?;
        b.session.save_volume(out, header)?;
        out!("wrote {}", out.display());
    }
    Ok(())
}

fn settings(args: &BakeArgs) -> Vec<(String, String)> {
    let mut s = Vec::new();
    for (k, v) in [("spa", args.spa), ("paths", args.paths), ("bounces", args.bounces)] {
        if let Some(v) = v {
            s.push((k.to_string(), v.to_string()));
        }
    }
    s
}

/// The graph as the bake runs it: mode, level, map size, path count and
/// bounces applied, and the progressive passes `per_frame` at a time.
fn edited_graph(args: &BakeArgs) -> Result<FrameGraph, UserError> {
    let mut g = FrameGraph::load(&args.graph)?;
    let Some(probes) = &mut g.probes else {
        return Err(UserError::in_file(&args.graph, "this graph has no probe grid (`probes:`) to bake"));
    };
    probes.mode = match args.mode {
        Mode::Thesis => ProbeMode::Thesis,
        Mode::Ddgi => ProbeMode::Ddgi,
    };
    if let Some(l) = args.level {
        if !(1..=crate::graph::desc::MAX_PROBE_LEVEL).contains(&l) {
            return Err(UserError::new(format!("--level {l}: between 1 and {}", crate::graph::desc::MAX_PROBE_LEVEL)));
        }
        probes.level = l;
    }
    if !(1..=64).contains(&args.per_frame) {
        return Err(UserError::new(format!("--per-frame {}: between 1 and 64", args.per_frame)));
    }
    if let Some(s) = args.spa {
        if args.mode != Mode::Thesis || !(1..=64).contains(&s) {
            return Err(UserError::new(format!("--spa {s}: samples per axis of the thesis's maps, 1 to 64 (thesis mode only)")));
        }
        for r in ["thesis_radiance", "thesis_irradiance"] {
            match g.resources.get_mut(r) {
                Some(ResourceDesc::Texture(t)) => t.size = SizeDesc::ProbeTiles(2 * s, s),
                None => return Err(UserError::in_file(&args.graph, format!("--spa: the graph has no `{r}`"))),
            }
        }
    }
    let feature = if args.mode == Mode::Thesis { Feature::ThesisProbes } else { Feature::DdgiProbes };
    for p in g.passes.iter_mut().filter(|p| p.requires.contains(&feature)) {
        if let RunMode::Progressive { per_frame, until } = &mut p.run {
            if let Some(n) = args.paths {
                if n == 0 {
                    return Err(UserError::new("--paths 0 bakes nothing; give at least 1"));
                }
                *until = Some(n);
            }
            // DDGI's blends follow each trace one for one (they run when
            // their input changed, once a frame): one update a frame.
            if args.mode == Mode::Thesis {
                *per_frame = args.per_frame.min(until.unwrap_or(args.per_frame));
            }
        }
        if let (Some(m), Some(v)) = (args.method, p.params.get_mut("method")) {
            *v = ParamValue::Int(i64::from(m));
        }
        if let (Some(b), Some(v)) = (args.bounces, p.params.get_mut("bounces")) {
            *v = ParamValue::Int(match args.mode {
                Mode::Thesis => i64::from(b),
                Mode::Ddgi => i64::from(b > 1),
            });
        }
    }
    Ok(g)
}

/// Bakes `args.scene`'s volume: every frame until no pass that fills a
/// persistent resource runs any more.
pub fn bake(gpu: &Gpu, args: &BakeArgs, progress: bool) -> Result<Baked, UserError> {
    let scene = scene::load(&args.scene)?;
    let scene_hash = scene.content_hash();
    let desc = edited_graph(args)?;
    let shader_dir = graph::shader_dir_for(&args.graph);
    let shaders = graph::load_shaders(&desc, &shader_dir)?;
    let volume = if args.mode == Mode::Thesis { "thesis_irradiance" } else { "ddgi_irradiance" };
    if !desc.resources.contains_key(volume) {
        return Err(UserError::in_file(&args.graph, format!("the graph has no `{volume}` for {:?} mode", args.mode)));
    }
    let options = CompileOptions { output: Some(volume.to_string()), ..Default::default() };
    let compiled = graph::compile_loaded(&args.graph, desc, shaders, &scene.compile_features(), &options)?;
    let total: u64 = compiled
        .schedule
        .passes
        .iter()
        .filter_map(|p| match p.run {
            RunMode::Progressive { per_frame, until: Some(u) } => Some(u64::from(u.div_ceil(per_frame))),
            _ => None,
        })
        .max()
        .unwrap_or(1);
    let mut session = Session::with_graph(gpu, scene, compiled, shader_dir, SessionOptions::new((8, 8)))?;
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template("baking {bar:40} {pos}/{len} frames, {elapsed} (eta {eta})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    if !progress {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let start = Instant::now();
    let mut frames = 0u64;
    while session.baking() {
        session.frame(0.0);
        session.gpu.wait();
        frames += 1;
        bar.set_position(frames.min(total));
        if frames > 100_000 {
            return Err(UserError::new("the bake has not finished after 100000 frames: a progressive pass without `until`?"));
        }
    }
    // Each frame was waited for: the clock stops after the last one's work.
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let bytes = |(_, _, (w, h)): &(String, crate::format::TexFormat, (u32, u32))| u64::from(*w) * u64::from(*h) * 16;
    let resources = session.executor.persistent_resources();
    let volume_bytes = resources.iter().filter(|r| r.0 == volume).map(bytes).sum();
    let all_bytes = resources.iter().map(bytes).sum();
    Ok(Baked { seconds, scene_hash, volume_bytes, all_bytes, session })
}

/// Loads a saved volume into a session that has not rendered yet (so its
/// scene is as loaded: `glint render --volume`).
pub fn load_into(session: &mut Session, scene_file: &Path, path: &Path) -> Result<(), UserError> {
    let hash = session.scene.scene.content_hash();
    let header = session.volume_header(&scene_file.display().to_string(), hash, Vec::new())?;
    session.load_volume(path, &header)
}

#[derive(Args, Debug)]
pub struct BakeBenchArgs {
    pub scene: PathBuf,
    #[arg(long, default_value = "passes/irradiance.ron")]
    pub graph: PathBuf,
    /// Probe levels (the thesis: 3 to 7).
    #[arg(long, value_delimiter = ',', default_value = "3,4,5,6,7")]
    pub levels: Vec<u32>,
    /// Samples per axis (the thesis: 5 to 25).
    #[arg(long, value_delimiter = ',', default_value = "5,10,15,20,25")]
    pub spa: Vec<u32>,
    /// Paths per bucket (the thesis: 1024).
    #[arg(long, default_value_t = 16)]
    pub paths: u32,
    /// Bounces per path (the thesis: 4).
    #[arg(long, default_value_t = 4)]
    pub bounces: u32,
    /// Write the tables here (Markdown) as well as to stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Tables 3.1 (path traced) and 3.2 (diffuse radiance, Greger et al.):
/// seconds to bake and MiB of the volume, per level and samples per axis.
pub fn bake_tables(args: BakeBenchArgs) -> Result<(), UserError> {
    let gpu = Gpu::new()?;
    let mut text = format!(
        "# Irradiance volume bakes (thesis tables 3.1 and 3.2), redone\n\n{} on {}; {} paths per bucket, {} bounces; seconds to bake, MiB of the volume ((L+1)^3 x 2 S^2 x 16 bytes).\n",
        args.scene.display(),
        gpu.describe(),
        args.paths,
        args.bounces
    );
    for (title, method) in [("Table 3.1: path traced", 0), ("Table 3.2: diffuse radiance (Greger et al.)", 1)] {
        text.push_str(&format!("\n## {title}\n\n| | {} |\n|---|{}\n", args.spa.iter().map(|s| format!("{s} SPA")).collect::<Vec<_>>().join(" | "), "---|".repeat(args.spa.len())));
        for &level in &args.levels {
            let mut row = format!("| L{level} |");
            for &spa in &args.spa {
                let bake_args = BakeArgs {
                    scene: args.scene.clone(),
                    graph: args.graph.clone(),
                    mode: Mode::Thesis,
                    level: Some(level),
                    spa: Some(spa),
                    paths: Some(args.paths),
                    bounces: Some(args.bounces),
                    per_frame: 64,
                    out: None,
                    method: Some(method),
                };
                let b = bake(&gpu, &bake_args, false)?;
                row.push_str(&format!(" {:.2} s {:.2} MiB |", b.seconds, b.volume_bytes as f64 / (1024.0 * 1024.0)));
                eprintln!("L{level} {spa} SPA: {:.2} s", b.seconds);
            }
            text.push_str(&row);
            text.push('\n');
        }
    }
    out!("{text}");
    if let Some(path) = &args.out {
        std::fs::write(path, &text).map_err(|e| UserError::in_file(path, format!("cannot write: {e}")))?;
    }
    Ok(())
}
