//! `glint trade`: every graph against the truth. Renders each graph frame
//! after frame and records, per frame, its milliseconds and the error of
//! the accumulated image against a reference (FLIP mean, relMSE, PSNR);
//! writes trade.csv, trade.md, trade.png, compare.png (`crate::trade`),
//! the reference and each graph's final image into the output folder.
//!
//! Without `--reference`, the reference is `pathtrace.ron` rendered for
//! `--reference-frames` frames (converged: its own FLIP against the same
//! render at half the frames is printed), cached in the output folder with
//! a header of scene hash, size, frames and engine version; a cached one
//! whose header differs is rendered again, never used.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use crate::error::UserError;
use crate::gpu::readback::ImageF32;
use crate::gpu::Gpu;
use crate::graph::executor::Timing;
use crate::graph::CompileOptions;
use crate::session::{check_size, Session, SessionOptions};
use crate::trade::{Curve, Sample};
use crate::{image_io, metrics, scene};

#[derive(Args, Debug)]
pub struct TradeArgs {
    pub scene: PathBuf,
    /// Graph files, comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    pub graphs: Vec<PathBuf>,
    /// A reference image (.exr/.pfm, linear); default: the path tracer, converged.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    #[arg(long, default_value = "128x128", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Frames per graph.
    #[arg(long, default_value_t = 64)]
    pub frames: u32,
    /// Frames of the path-traced reference.
    #[arg(long, default_value_t = 1024)]
    pub reference_frames: u32,
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: TradeArgs) -> Result<(), UserError> {
    if args.frames == 0 || args.reference_frames < 2 {
        return Err(UserError::new("--frames must be at least 1 and --reference-frames at least 2"));
    }
    std::fs::create_dir_all(&args.out).map_err(|e| UserError::in_file(&args.out, format!("cannot create the folder: {e}")))?;
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    let reference = match &args.reference {
        Some(path) => {
            let img = image_io::load(path)?;
            if (img.width, img.height) != args.size {
                return Err(UserError::in_file(path, format!("the reference is {}x{}, --size is {}x{}", img.width, img.height, args.size.0, args.size.1)));
            }
            image_io::save(&img, &args.out.join("reference.exr"))?;
            img
        }
        None => cached_reference(&gpu, &args)?,
    };
    let mut curves = Vec::new();
    let mut panels = vec![crate::trade::plot::Panel { label: "reference".into(), image: image_io::to_srgb8(&reference), flip_map: None }];
    for graph in &args.graphs {
        let (curve, last) = measure(&gpu, &args, graph, &reference)?;
        image_io::save(&last, &args.out.join(format!("{}-final.exr", curve.graph)))?;
        let (flip, map) = metrics::flip(&reference, &last);
        panels.push(crate::trade::plot::Panel { label: curve.graph.clone(), image: image_io::to_srgb8(&last), flip_map: Some((map, f64::from(flip.mean))) });
        out!(
            "{}: {} frames, {:.1} ms in all, final FLIP {:.4}",
            curve.graph,
            curve.samples.len(),
            curve.samples.last().map_or(0.0, |s| s.cum_ms),
            curve.samples.last().map_or(f64::NAN, |s| s.flip)
        );
        curves.push(curve);
    }
    let csv_path = args.out.join("trade.csv");
    std::fs::write(&csv_path, crate::trade::csv(&curves)).map_err(|e| UserError::in_file(&csv_path, e.to_string()))?;
    let how = format!(
        "{} at {}x{} on {}; {} frames per graph; frame times are {}; error of the accumulated image against {}.",
        args.scene.display(),
        args.size.0,
        args.size.1,
        gpu.describe(),
        args.frames,
        if Timing::stamps_bracket_work(&gpu) { "GPU timestamps" } else { "wall clock, each frame waited for (this adapter's timestamps do not bracket the work)" },
        args.reference.as_ref().map_or(format!("pathtrace.ron at {} samples per pixel", args.reference_frames), |p| p.display().to_string())
    );
    let png_path = args.out.join("trade.png");
    crate::trade::plot::draw(&png_path, &format!("{}: error against time", args.scene.display()), &curves)
        .map_err(|e| UserError::in_file(&png_path, format!("cannot draw the plot: {e}")))?;
    let compare_path = args.out.join("compare.png");
    crate::trade::plot::compare(&compare_path, args.size, &panels).map_err(|e| UserError::in_file(&compare_path, format!("cannot draw the comparison: {e}")))?;
    let md_path = args.out.join("trade.md");
    std::fs::write(&md_path, crate::trade::markdown("Speed against accuracy", &how, &curves)).map_err(|e| UserError::in_file(&md_path, e.to_string()))?;
    out!("wrote {}, {}, {} and {}", csv_path.display(), md_path.display(), png_path.display(), compare_path.display());
    Ok(())
}

fn session_for(gpu: &Gpu, scene_path: &Path, graph: &Path, size: (u32, u32), seed: u32) -> Result<Session, UserError> {
    let scene = scene::load(scene_path)?;
    let mut options = SessionOptions::new(size);
    options.seed = seed;
    options.compile = CompileOptions::default();
    Session::new(gpu, scene, graph, options)
}

/// Renders `graph` frame after frame; each frame's time (GPU timestamps
/// where they bracket the work, else the wall clock around a frame that is
/// waited for) and its error. The readback is not timed.
fn measure(gpu: &Gpu, args: &TradeArgs, graph: &Path, reference: &ImageF32) -> Result<(Curve, ImageF32), UserError> {
    let name = graph.file_stem().map_or("graph".into(), |s| s.to_string_lossy().into_owned());
    let mut session = session_for(gpu, &args.scene, graph, args.size, 1)?;
    let gpu_timed = Timing::stamps_bracket_work(gpu);
    session.timing = if gpu_timed { Timing::Gpu } else { Timing::None };
    let bar = indicatif::ProgressBar::new(u64::from(args.frames));
    let mut samples = Vec::new();
    let mut cum = 0.0;
    let mut last = ImageF32::new(1, 1);
    for frame in 1..=args.frames {
        let start = Instant::now();
        session.frame(0.0);
        session.gpu.wait();
        let wall = start.elapsed().as_secs_f64() * 1e3;
        let ms = if gpu_timed { session.finish().last().map_or(wall, |t| t.total()) } else { wall };
        cum += ms;
        last = session.read_output()?;
        let (flip, _) = metrics::flip(reference, &last);
        samples.push(Sample {
            graph: name.clone(),
            setting: String::new(),
            frame,
            ms,
            cum_ms: cum,
            flip: f64::from(flip.mean),
            relmse: metrics::rel_mse(reference, &last),
            psnr: metrics::psnr(reference, &last),
        });
        bar.set_position(u64::from(frame));
    }
    bar.finish_and_clear();
    Ok((Curve { graph: name, setting: String::new(), samples }, last))
}

/// What a cached reference was rendered from.
#[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct ReferenceKey {
    scene_hash: u64,
    size: (u32, u32),
    frames: u32,
    engine: String,
}

/// The path tracer's converged image, from the cache in the output folder
/// when its key matches, else rendered (with a progress bar) and cached.
fn cached_reference(gpu: &Gpu, args: &TradeArgs) -> Result<ImageF32, UserError> {
    let key = ReferenceKey {
        scene_hash: scene::load(&args.scene)?.content_hash(),
        size: args.size,
        frames: args.reference_frames,
        engine: format!("glint {}", env!("CARGO_PKG_VERSION")),
    };
    let image_path = args.out.join("reference.exr");
    let key_path = args.out.join("reference.ron");
    let cached = std::fs::read_to_string(&key_path).ok().and_then(|t| ron::from_str::<ReferenceKey>(&t).ok());
    if cached.as_ref() == Some(&key) {
        if let Ok(img) = image_io::load(&image_path) {
            out!("reference: cached {} ({} samples per pixel)", image_path.display(), key.frames);
            return Ok(img);
        }
    } else if cached.is_some() {
        out!("reference: the cached one is stale (scene, size, frames or engine changed); rendering again");
    }
    // The path tracer beside the first graph (passes/ as shipped).
    let graph = args.graphs.first().and_then(|g| g.parent()).map_or(PathBuf::from("passes/pathtrace.ron"), |p| p.join("pathtrace.ron"));
    let mut session = session_for(gpu, &args.scene, &graph, args.size, 7)?;
    let bar = indicatif::ProgressBar::new(u64::from(args.reference_frames));
    bar.set_style(indicatif::ProgressStyle::with_template("reference {bar:40} {pos}/{len} frames (eta {eta})").unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()));
    let mut half = None;
    for f in 1..=args.reference_frames {
        session.frame(0.0);
        if f == args.reference_frames / 2 {
            half = Some(session.read_output()?);
        }
        bar.set_position(u64::from(f));
    }
    bar.finish_and_clear();
    let img = session.read_output()?;
    if let Some(h) = half {
        let (flip, _) = metrics::flip(&img, &h);
        out!(
            "reference: pathtrace.ron, {} samples per pixel; at half of them it was FLIP {:.4} from the final image (how converged it is)",
            args.reference_frames,
            flip.mean
        );
    }
    image_io::save(&img, &image_path)?;
    let text = ron::to_string(&key).map_err(|e| UserError::new(e.to_string()))?;
    std::fs::write(&key_path, text).map_err(|e| UserError::in_file(&key_path, e.to_string()))?;
    Ok(img)
}
