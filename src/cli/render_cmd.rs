//! `glint render`: headless rendering to a file, with timings.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::camera_path::CameraPath;
use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::edit::{GraphEdits, ParamSet};
use crate::graph::executor::Timing;
use crate::graph::CompileOptions;
use crate::metrics::median;
use crate::session::frame_loop::{Clock, FrameLoop, FrameTarget};
use crate::session::{check_size, Session, SessionOptions};
use crate::stats::{ReuseShare, REFLECT_REUSE};
use crate::{image_io, scene};

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene file (RON), or an OBJ or glTF file opened as a scene.
    pub scene: PathBuf,
    /// Frame graph (default: from passes/machines.ron for this adapter).
    #[arg(long)]
    pub graph: Option<PathBuf>,
    #[arg(long, default_value = "256x256", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Frames to render (accumulated when the graph accumulates).
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Scene time in seconds (moving lights and objects).
    #[arg(long, default_value_t = 0.0, value_parser = super::parse_seconds)]
    pub time: f32,
    /// Seconds the scene advances per frame (0: a still image).
    #[arg(long, default_value_t = 0.0, value_parser = super::parse_seconds)]
    pub dt: f32,
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Output file: .png (sRGB), .exr or .pfm (linear); repeat for several.
    #[arg(long, required = true)]
    pub out: Vec<PathBuf>,
    /// Write this graph resource instead of the graph's output (debugging).
    #[arg(long)]
    pub output: Option<String>,
    /// Frame-time target in ms: a PID controller then drives the noise-mask
    /// threshold from the measured frame time (graphs with a mask).
    #[arg(long)]
    pub target_ms: Option<f64>,
    /// Move the camera: orbit:DEG_PER_S, or keys:FILE.ron with
    /// [Key(time_s, position, target), ...]; evaluated at each frame's time
    /// (--time + --dt * frame).
    #[arg(long)]
    pub camera_path: Option<String>,
    /// View from the scene's glTF camera N (0: the first; a glTF file
    /// opened directly starts from camera 0).
    #[arg(long)]
    pub camera: Option<usize>,
    /// Per-pass times on CPU adapters (lavapipe), whose timestamps do not
    /// bracket the work: each pass is then submitted alone and waited for,
    /// which costs frame time. GPUs always report per-pass timestamps.
    #[arg(long)]
    pub profile: bool,
    /// Start from a baked irradiance volume (`glint bake --out`): refused
    /// when it was baked for another scene or probe grid.
    #[arg(long)]
    pub volume: Option<PathBuf>,
    /// Keep running: re-render and rewrite the outputs after every good
    /// save of a shader, the graph, the scene or its meshes (Ctrl-C ends).
    #[arg(long)]
    pub watch: bool,
    #[command(flatten)]
    pub edits: EditArgs,
}

/// Graph variants from the command line (see graph::edit).
#[derive(Args, Debug, Clone, Default)]
pub struct EditArgs {
    /// Override a pass param: --set accumulate.mode=0 (repeatable).
    #[arg(long = "set", value_name = "PASS.PARAM=VALUE")]
    pub set: Vec<ParamSet>,
    /// Remove passes (comma-separated); what then feeds nothing is culled.
    #[arg(long, value_delimiter = ',', value_name = "PASS")]
    pub skip: Vec<String>,
    /// Drop every pass after this one (with --output: view this pass's own
    /// write of a resource that later passes overwrite).
    #[arg(long, value_name = "PASS")]
    pub stop_after: Option<String>,
    /// Leave every shader generic: no override constants compiling out
    /// what the scene lacks (`graph check --scene` lists them).
    #[arg(long)]
    pub no_specialise: bool,
    /// Keep the passes whose `requires` the scene lacks (to measure what
    /// culling saves).
    #[arg(long)]
    pub no_cull: bool,
}

impl EditArgs {
    pub fn edits(&self) -> GraphEdits {
        GraphEdits { set: self.set.clone(), skip: self.skip.clone(), stop_after: self.stop_after.clone() }
    }
}

fn check_outputs(outs: &[PathBuf]) -> Result<(), UserError> {
    for out in outs {
        let ext = out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("png") | Some("exr") | Some("pfm")) {
            return Err(UserError::in_file(out, "the output must end in .png, .exr or .pfm"));
        }
    }
    Ok(())
}

/// The session and frame loop `render` (and `render --watch`) run.
pub(super) struct Prepared {
    pub session: Session,
    pub frames: FrameLoop,
    /// Seconds reading the scene's files (images decoded).
    pub read_s: f64,
}

pub(super) fn prepare(args: &RenderArgs) -> Result<Prepared, UserError> {
    if args.frames == 0 {
        return Err(UserError::new("--frames 0 renders nothing; give at least 1"));
    }
    check_outputs(&args.out)?;
    let read = Instant::now();
    let mut scene = scene::load(&args.scene)?;
    let read_s = read.elapsed().as_secs_f64();
    if let Some(n) = args.camera {
        scene.use_camera(n)?;
    }
    warn_if_empty(&scene);
    let camera_path = args.camera_path.as_deref().map(CameraPath::parse).transpose()?;
    if let Some(path) = &camera_path {
        path.check(&scene.camera)?;
    }
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    let choice = crate::machines::choose(&gpu, args.graph.as_deref())?;
    let graph_path = choice.graph.clone();
    let target = args.target_ms.or(choice.target_ms).map(FrameTarget::new).transpose()?;
    let mut options = SessionOptions::new(choice.scaled(args.size));
    options.seed = args.seed;
    let mut edits = args.edits.edits();
    // The profile's params first, so a --set of the same param wins.
    edits.set = choice.params.iter().cloned().chain(edits.set).collect();
    options.compile = CompileOptions {
        output: args.output.clone(),
        edits,
        keep: vec![REFLECT_REUSE.to_string()],
        no_specialise: args.edits.no_specialise,
        no_cull: args.edits.no_cull,
        ..CompileOptions::default()
    };
    let mut frames = FrameLoop::new(args.time, Clock::Fixed { dt: args.dt }, scene.camera);
    frames.camera_path = camera_path;
    frames.target = target;
    let mut session = Session::new(&gpu, scene, &graph_path, options)?;
    session.timing = Timing::for_adapter(&gpu, args.profile);
    if let Some(volume) = &args.volume {
        super::bake_cmd::load_into(&mut session, &args.scene, volume)?;
    }
    Ok(Prepared { session, frames, read_s })
}

/// Renders `frames` frames from the loop's start and writes the outputs.
pub(super) fn render_frames(args: &RenderArgs, session: &mut Session, frames: &mut FrameLoop, quiet: bool) -> Result<(), UserError> {
    let bar = indicatif::ProgressBar::new(u64::from(args.frames));
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {elapsed} (eta {eta})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    for i in 0..args.frames {
        if i + 1 == args.frames {
            // The image written is filtered in full, whatever thins.
            session.show_next_in_full();
        }
        frames.step(session);
        if !quiet && start.elapsed().as_secs_f32() > 1.0 {
            bar.set_position(u64::from(i + 1));
        }
    }
    frames.finish(session);
    bar.finish_and_clear();
    let mut image = session.read_output()?;
    if upscaled(session, args.size) {
        // A machine profile's resolution scale: upscale to the size asked for.
        image = image_io::resize_bilinear(&image, args.size.0, args.size.1);
    }
    for out in &args.out {
        image_io::save(&image, out)?;
    }
    Ok(())
}

/// Whether the output is a render at a machine profile's scale, written
/// upscaled to the size asked for (an output of its own fixed size is
/// written as it is).
fn upscaled(session: &Session, asked: (u32, u32)) -> bool {
    session.size != asked && session.executor.output_size() == session.size
}

/// Renders; `--watch` then goes on in `watch_cmd`, with what this returns.
pub(super) fn run(args: &RenderArgs) -> Result<(Session, FrameLoop), UserError> {
    let Prepared { mut session, mut frames, read_s } = prepare(args)?;
    eprintln!(
        "glint: {} on {}, graph `{}` ({} passes, {} culled), {}x{}, {} frame(s)",
        args.scene.display(),
        session.gpu.describe(),
        session.graph.schedule.name,
        session.graph.schedule.passes.len(),
        session.graph.schedule.culled.len(),
        args.size.0,
        args.size.1,
        args.frames
    );
    let start = Instant::now();
    render_frames(args, &mut session, &mut frames, false)?;
    print_summary(args, &session, &frames, start.elapsed().as_secs_f64());
    print_load(&session, read_s);
    Ok((session, frames))
}

fn print_summary(args: &RenderArgs, session: &Session, frames: &FrameLoop, seconds: f64) {
    let how = match session.timing {
        Timing::Gpu => "GPU timestamps",
        Timing::WallPerPass => "wall clock, each pass submitted alone (--profile)",
        Timing::None => "not timed per pass on this adapter; --profile submits passes one by one to time them",
    };
    let medians = frames.stats.pass_medians();
    let pass_total: f64 = medians.iter().map(|(_, ms)| ms).sum();
    let outs: Vec<String> = args.out.iter().map(|p| p.display().to_string()).collect();
    let passes = if medians.is_empty() { format!("per pass: {how}") } else { format!("sum of pass medians {pass_total:.2} ms ({how})") };
    // The file's size; a machine profile's scale renders smaller and
    // upscales, which is said too.
    let (rw, rh) = session.executor.output_size();
    let ((w, h), rendered) = if upscaled(session, args.size) { (args.size, format!(", rendered at {rw}x{rh}")) } else { ((rw, rh), String::new()) };
    out!(
        "wrote {} ({w}x{h}{rendered}); {} frames in {seconds:.2} s; median {:.2} ms/frame wall; {passes}",
        outs.join(", "),
        args.frames,
        median(&frames.stats.frame_ms),
    );
    for (name, ms) in &medians {
        out!("  {name:<16} {ms:8.3} ms (median)");
    }
    if frames.target.is_some() {
        out!("  mask threshold (PID): {:.4}", session.mask_threshold);
    }
    if let Some(Ok(reuse)) = session.read_resource(REFLECT_REUSE) {
        let s = ReuseShare::of(&reuse);
        out!(
            "  reflections: {:.1}% of reflection rays reused from screen space ({} of {} traced, of {} specular pixels, last frame)",
            s.share() * 100.0,
            s.reused,
            s.traced,
            s.specular
        );
    }
    let mem = session.graph.schedule.memory(args.size);
    out!("  textures: {} physical, {} bytes (pooling saved {} bytes)", mem.textures, mem.bytes, mem.bytes_saved);
    if let Some(t) = crate::scene::texture_classes::describe(session.scene.scene.textures()) {
        out!("  scene textures: {t}");
    }
    if let Some(e) = &session.scene.scene.environment {
        out!("  environment map: {}", e.describe());
    }
}

/// Where loading the scene went: its files, its BVH, its upload.
fn print_load(session: &Session, read_s: f64) {
    let l = session.scene.load;
    let s = |ms: f64| ms / 1e3;
    out!(
        "  scene load: {:.2} s (files and images {read_s:.2} s, arrays and BVH {:.2} s, buffers {:.2} s, textures with mips {:.2} s)",
        read_s + s(l.pack_and_bvh_ms + l.buffers_ms + l.textures_ms),
        s(l.pack_and_bvh_ms),
        s(l.buffers_ms),
        s(l.textures_ms)
    );
}

/// An empty scene is valid, but its image says nothing: say why it is
/// black (or only background).
fn warn_if_empty(scene: &scene::Scene) {
    // Lights carry an ObjectId too (numbered after the objects).
    let lights = scene.world.query::<&crate::scene::LightIndex>().iter().count();
    let objects = scene.world.query::<&crate::scene::ObjectId>().iter().count() - lights;
    if objects == 0 {
        let what = if scene.environment.is_some() { "the environment" } else { "the background" };
        eprintln!("warning: {} has no objects and {lights} lights: the image is {what}", scene.path.display());
    } else if lights == 0 && !scene.features.emissive && scene.environment.is_none() {
        eprintln!("warning: {} has no lights and no emissive material: the image is black but for the background", scene.path.display());
    }
}
