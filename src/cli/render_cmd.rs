//! `glint render`: headless rendering to a file, with timings.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use crate::error::UserError;
use crate::gpu::Gpu;
use crate::camera_path::CameraPath;
use crate::graph::executor::Timing;
use crate::graph::edit::{GraphEdits, ParamSet};
use crate::graph::{self, CompileOptions};
use crate::machines::{DeviceType, Machines};
use crate::metrics::median;
use crate::control::{Pid, PidConfig};
use crate::render::{check_size, Renderer, DEFAULT_MASK_THRESHOLD};
use crate::stats::{ReuseShare, REFLECT_REUSE};
use crate::{image_io, scene};

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene file (RON).
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
    #[arg(long, default_value_t = 0.0)]
    pub time: f32,
    /// Seconds the scene advances per frame (0: a still image).
    #[arg(long, default_value_t = 0.0)]
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
}

impl EditArgs {
    pub fn edits(&self) -> GraphEdits {
        GraphEdits { set: self.set.clone(), skip: self.skip.clone(), stop_after: self.stop_after.clone() }
    }
}

/// Picks the graph: `--graph`, else the machine profile's graph, with the
/// profile's frame-time target for the PID controller.
fn choose_graph(args: &RenderArgs, gpu: &Gpu) -> Result<(PathBuf, Option<f64>), UserError> {
    if let Some(g) = &args.graph {
        return Ok((g.clone(), None));
    }
    let machines = Path::new("passes/machines.ron");
    let machines = if machines.is_file() {
        machines.to_path_buf()
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("passes/machines.ron")
    };
    let m = Machines::load(&machines)?;
    let p = m.pick(DeviceType::of(gpu.info.device_type), &gpu.info.name);
    eprintln!("glint: machine profile `{}`: {} (target {} ms)", p.name, p.graph, p.target_ms);
    Ok((machines.parent().unwrap_or(Path::new(".")).join(&p.graph), Some(f64::from(p.target_ms))))
}

pub fn run(args: RenderArgs) -> Result<(), UserError> {
    if args.frames == 0 {
        return Err(UserError::new("--frames 0 renders nothing; give at least 1"));
    }
    for out in &args.out {
        let ext = out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("png") | Some("exr") | Some("pfm")) {
            return Err(UserError::in_file(out, "the output must end in .png, .exr or .pfm"));
        }
    }
    let scene = scene::load(&args.scene)?;
    let camera_path = args.camera_path.as_deref().map(CameraPath::parse).transpose()?;
    let base_camera = scene.camera;
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    let (graph_path, profile_target) = choose_graph(&args, &gpu)?;
    let options = CompileOptions { output: args.output.clone(), edits: args.edits.edits(), keep: vec![REFLECT_REUSE.to_string()] };
    let compiled = graph::load_and_compile(&graph_path, &graph::shader_dir_for(&graph_path), &scene.features, &options)?;
    eprintln!(
        "glint: {} on {}, graph `{}` ({} passes, {} culled), {}x{}, {} frame(s)",
        args.scene.display(),
        gpu.describe(),
        compiled.schedule.name,
        compiled.schedule.passes.len(),
        compiled.schedule.culled.len(),
        args.size.0,
        args.size.1,
        args.frames
    );
    let mut renderer = Renderer::new(&gpu, scene, &compiled, args.size, args.seed)?;
    let bar = indicatif::ProgressBar::new(u64::from(args.frames));
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {elapsed} (eta {eta})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let timing = Timing::for_adapter(&gpu);
    let mut pid = match args.target_ms.or(profile_target) {
        Some(t) if t.is_finite() && t > 0.0 => Some((t, Pid::new(PidConfig::frame_time(), f64::from(DEFAULT_MASK_THRESHOLD)))),
        Some(t) => return Err(UserError::new(format!("--target-ms {t}: give a positive number of milliseconds"))),
        None => None,
    };
    let start = Instant::now();
    let mut frame_ms = Vec::new();
    let mut pass_ms: Vec<Vec<f64>> = vec![Vec::new(); renderer.executor.pass_names().len()];
    for i in 0..args.frames {
        let t0 = Instant::now();
        let time = args.time + args.dt * i as f32;
        if let Some(path) = &camera_path {
            renderer.scene.camera = path.at(&base_camera, time);
        }
        let ms = renderer.frame(&gpu, time, timing)?;
        let ms_wall = t0.elapsed().as_secs_f64() * 1e3;
        frame_ms.push(ms_wall);
        if let Some((target, pid)) = &mut pid {
            // GPU time where timestamps bracket the work, else wall time.
            let measured = match (&ms, timing) {
                (Some(ms), Timing::Gpu) => ms.iter().sum(),
                _ => ms_wall,
            };
            renderer.mask_threshold = pid.update(*target, measured, ms_wall / 1e3) as f32;
        }
        if let Some(ms) = ms {
            for (acc, m) in pass_ms.iter_mut().zip(ms) {
                acc.push(m);
            }
        }
        if start.elapsed().as_secs_f32() > 1.0 {
            bar.set_position(u64::from(i + 1));
        }
    }
    bar.finish_and_clear();
    let image = renderer.read_output(&gpu)?;
    for out in &args.out {
        image_io::save(&image, out)?;
    }
    let gpu_total: f64 = pass_ms.iter().map(|v| median(v)).sum();
    let how = match timing {
        Timing::Gpu => "GPU timestamps",
        _ => "wall clock, each pass submitted alone",
    };
    let outs: Vec<String> = args.out.iter().map(|p| p.display().to_string()).collect();
    out!(
        "wrote {} ({}x{}); {} frames in {:.2} s; median {:.2} ms/frame wall; sum of pass medians {:.2} ms ({how})",
        outs.join(", "),
        args.size.0,
        args.size.1,
        args.frames,
        start.elapsed().as_secs_f64(),
        median(&frame_ms),
        gpu_total
    );
    for (name, ms) in renderer.executor.pass_names().iter().zip(&pass_ms) {
        if !ms.is_empty() {
            out!("  {name:<16} {:8.3} ms (median)", median(ms));
        }
    }
    if pid.is_some() {
        out!("  mask threshold (PID): {:.4}", renderer.mask_threshold);
    }
    if let Some(reuse) = renderer.executor.read_resource(&gpu, REFLECT_REUSE) {
        let s = ReuseShare::of(&reuse?);
        out!(
            "  reflections: {:.1}% of reflection rays reused from screen space ({} of {} specular pixels, last frame)",
            s.share() * 100.0,
            s.reused,
            s.specular
        );
    }
    let mem = compiled.schedule.memory(args.size);
    out!("  textures: {} physical, {} bytes (pooling saved {} bytes)", mem.textures, mem.bytes, mem.bytes_saved);
    Ok(())
}
