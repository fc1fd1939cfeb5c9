//! `glint bench converge`: how fast a graph's image approaches its own
//! converged result (the thesis's figure 4.14 measurement), and, with a
//! moving camera, how far from it the image is after N frames.
//!
//! The reference is the same graph rendered for `--reference-frames` frames
//! with a still camera (at the last frame's camera) and another seed, so its
//! noise is independent of the measured run. The scene is held at `--time`;
//! only the camera moves.

use std::path::PathBuf;

use clap::Args;

use super::render_cmd::EditArgs;
use crate::camera_path::CameraPath;
use crate::error::UserError;
use crate::gpu::readback::ImageF32;
use crate::gpu::Gpu;
use crate::graph::executor::Timing;
use crate::graph::{self, CompileOptions};
use crate::metrics::{self, median};
use crate::session::{check_size, Session, SessionOptions};
use crate::scene;

#[derive(Args, Debug)]
pub struct ConvergeArgs {
    pub scene: PathBuf,
    #[arg(long)]
    pub graph: PathBuf,
    #[arg(long, default_value = "256x256", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Frames accumulated for the converged reference.
    #[arg(long, default_value_t = 1024)]
    pub reference_frames: u32,
    /// Still camera: report the first frame whose FLIP mean against the
    /// reference is at or below each of these; stop at the smallest.
    #[arg(long, default_value = "0.05", value_delimiter = ',')]
    pub flip: Vec<f32>,
    /// Most frames (still camera), or exactly this many (--camera-path).
    #[arg(long, default_value_t = 256)]
    pub frames: u32,
    /// Move the camera during the measured frames (orbit:DEG_PER_S or
    /// keys:FILE.ron); the error is then reported after the last frame.
    #[arg(long)]
    pub camera_path: Option<String>,
    /// Camera-path seconds per frame.
    #[arg(long, default_value_t = 1.0 / 30.0, value_parser = super::parse_seconds)]
    pub dt: f32,
    /// Scene time (moving lights and objects are held there).
    #[arg(long, default_value_t = 0.0, value_parser = super::parse_seconds)]
    pub time: f32,
    /// Save the reference and the last measured image (.png/.exr/.pfm).
    #[arg(long)]
    pub reference_out: Option<PathBuf>,
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub edits: EditArgs,
}

/// Seeds of the reference and of the measured run (independent noise).
const REFERENCE_SEED: u32 = 0x5eed_0001;
const RUN_SEED: u32 = 1;

pub fn run(args: ConvergeArgs) -> Result<(), UserError> {
    if args.frames == 0 || args.reference_frames == 0 {
        return Err(UserError::new("--frames and --reference-frames must be at least 1"));
    }
    if !args.dt.is_finite() || !args.time.is_finite() || args.flip.is_empty() || args.flip.iter().any(|f| f.is_nan() || *f <= 0.0) {
        return Err(UserError::new("--dt and --time must be finite and --flip positive"));
    }
    let path = args.camera_path.as_deref().map(CameraPath::parse).transpose()?;
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    let scene0 = scene::load(&args.scene)?;
    if let Some(path) = &path {
        path.check(&scene0.camera)?;
    }
    let options = CompileOptions { output: None, edits: args.edits.edits(), no_specialise: args.edits.no_specialise, no_cull: args.edits.no_cull, ..Default::default() };
    let compiled = graph::load_and_compile(&args.graph, &graph::shader_dir_for(&args.graph), &scene0.compile_features(), &options)?;
    let base = scene0.camera;
    let camera_at = |frame: u32| match &path {
        Some(p) => p.at(&base, args.dt * frame as f32),
        None => base,
    };
    let passes: Vec<String> = compiled.schedule.passes.iter().map(|p| p.name.clone()).collect();
    out!("adapter={}", gpu.describe());
    out!("graph={} passes={}", compiled.schedule.name, passes.join(","));
    out!("size={}x{}", args.size.0, args.size.1);

    // The reference: a still camera where the measured run ends.
    let shader_dir = graph::shader_dir_for(&args.graph);
    let session_options = |seed: u32| SessionOptions { seed, compile: options.clone(), shader_dir: Some(shader_dir.clone()), ..SessionOptions::new(args.size) };
    let mut reference_session = Session::with_graph(&gpu, scene0, compiled.clone(), shader_dir.clone(), session_options(REFERENCE_SEED))?;
    reference_session.scene.scene.camera = camera_at(args.frames - 1);
    for _ in 0..args.reference_frames {
        reference_session.frame(args.time);
    }
    let reference = reference_session.read_output()?;
    drop(reference_session);
    out!("reference_frames={}", args.reference_frames);
    if let Some(p) = &args.reference_out {
        crate::image_io::save(&reference, p)?;
    }

    let mut session = Session::with_graph(&gpu, scene::load(&args.scene)?, compiled, shader_dir.clone(), session_options(RUN_SEED))?;
    // Frame time is what counts here: GPU timestamps where they bracket the
    // work, else the wall time of the whole frame (waited for).
    session.timing = if Timing::stamps_bracket_work(&gpu) { Timing::Gpu } else { Timing::None };
    // One untimed frame first: drivers may finish compiling on first use.
    session.frame(args.time);
    session.finish();
    session.reset_accumulation();
    let mut frame_ms = Vec::new();
    let mut reached: Vec<Option<(u32, f64)>> = vec![None; args.flip.len()];
    let strictest = args.flip.iter().copied().fold(f32::INFINITY, f32::min);
    let mut last: Option<(ImageF32, f32)> = None;
    for i in 0..args.frames {
        session.scene.scene.camera = camera_at(i);
        let start = std::time::Instant::now();
        session.frame(args.time);
        let stamps = session.finish();
        let ms = match stamps.last() {
            Some(t) if session.timing == Timing::Gpu => t.total(),
            _ => start.elapsed().as_secs_f64() * 1e3,
        };
        frame_ms.push(ms);
        // With a moving camera only the last frame is compared.
        if path.is_some() && i + 1 < args.frames {
            continue;
        }
        let image = session.read_output()?;
        let (flip, _) = metrics::flip(&reference, &image);
        let total: f64 = frame_ms.iter().sum();
        out!("step frame={} flip={:.5} ms_total={total:.1}", i + 1, flip.mean);
        last = Some((image, flip.mean));
        for (r, threshold) in reached.iter_mut().zip(&args.flip) {
            if path.is_none() && r.is_none() && flip.mean <= *threshold {
                *r = Some((i + 1, total));
            }
        }
        if path.is_none() && flip.mean <= strictest {
            break;
        }
    }
    out!("frame_ms_median={:.3}", median(&frame_ms));
    if let Some((image, flip_mean)) = &last {
        out!("final_flip_mean={flip_mean:.5}");
        out!("final_relmse={:.6}", metrics::rel_mse(&reference, image));
        if let Some(p) = &args.out {
            crate::image_io::save(image, p)?;
        }
    }
    if path.is_none() {
        for (r, threshold) in reached.iter().zip(&args.flip) {
            match r {
                Some((frames, ms)) => out!("flip<={threshold} frames={frames} ms={ms:.1}"),
                None => out!("flip<={threshold} frames=none (not reached in {} frames)", args.frames),
            }
        }
    }
    Ok(())
}
