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

use std::path::PathBuf;

use clap::Args;

use super::trade_run::{cached_reference, file_safe, pathtracer_beside, step_together, ReferenceSpec, Run};
use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::executor::Timing;
use crate::session::check_size;
use crate::trade::sweep::{Setting, Sweep};
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
    /// Settings to render every graph with (docs/trade.md, "Sweeps"):
    /// param values, resolution scale, PID target, specialisation.
    #[arg(long)]
    pub sweep: Option<PathBuf>,
    /// Leave every shader generic (without a sweep; a sweep says it per setting).
    #[arg(long)]
    pub no_specialise: bool,
    /// In motion: scene time advances 1/30 s a frame (moving lights and
    /// objects), the camera follows --camera-path, and every
    /// --reference-every-th frame is compared with a reference of that
    /// instant held still.
    #[arg(long)]
    pub animate: bool,
    /// With --animate: orbit:DEG_PER_S or keys:FILE.ron, as `render`.
    #[arg(long, requires = "animate")]
    pub camera_path: Option<String>,
    /// With --animate: compare every K-th frame.
    #[arg(long, default_value_t = 4, requires = "animate")]
    pub reference_every: u32,
    /// The graph rendering the reference, still or (with --animate) each
    /// instant's (default: pathtrace.ron beside the first graph).
    #[arg(long, conflicts_with = "reference")]
    pub reference_graph: Option<PathBuf>,
    /// Render every graph with seeds 1..=N: trade.csv and the tables hold
    /// the mean over the seeds, frame by frame, and trade.md their spread
    /// (one seed's error is one draw of a random variable). Still only.
    #[arg(long, default_value_t = 1, conflicts_with = "animate")]
    pub seeds: u32,
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: TradeArgs) -> Result<(), UserError> {
    if args.frames == 0 || args.reference_frames < 2 || args.seeds == 0 {
        return Err(UserError::new("--frames and --seeds must be at least 1 and --reference-frames at least 2"));
    }
    let settings = match &args.sweep {
        Some(path) => {
            if args.no_specialise {
                return Err(UserError::new("--no-specialise with --sweep: say `specialise: false` in the sweep's settings instead"));
            }
            Sweep::load(path)?.settings
        }
        None => vec![Setting { specialise: !args.no_specialise, ..Setting::plain() }],
    };
    std::fs::create_dir_all(&args.out).map_err(|e| UserError::in_file(&args.out, format!("cannot create the folder: {e}")))?;
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    if args.animate {
        if args.reference.is_some() {
            return Err(UserError::new("--reference with --animate: each compared frame has a reference of its own instant, rendered by --reference-graph"));
        }
        let request = super::trade_motion::MotionRequest {
            scene: &args.scene,
            graphs: &args.graphs,
            size: args.size,
            frames: args.frames,
            reference_frames: args.reference_frames,
            camera_path: args.camera_path.as_deref(),
            reference_every: args.reference_every,
            reference_graph: args.reference_graph.as_deref(),
            out: &args.out,
        };
        return super::trade_motion::run(&request, &gpu, &settings);
    }
    let reference = match &args.reference {
        Some(path) => {
            let img = super::load_finite(path)?;
            if (img.width, img.height) != args.size {
                return Err(UserError::in_file(path, format!("the reference is {}x{}, --size is {}x{}", img.width, img.height, args.size.0, args.size.1)));
            }
            image_io::save(&img, &args.out.join("reference.exr"))?;
            img
        }
        None => {
            let pathtracer = args.reference_graph.clone().unwrap_or_else(|| pathtracer_beside(&args.graphs));
            let spec = ReferenceSpec { scene: &args.scene, size: args.size, frames: args.reference_frames, dir: &args.out, stem: "reference", pathtracer: &pathtracer, time: 0.0, camera: None };
            cached_reference(&gpu, &spec)?
        }
    };
    let mut curves = Vec::new();
    let mut seed_runs = Vec::new();
    let mut panels = vec![crate::trade::plot::Panel { label: "reference".into(), image: image_io::to_srgb8(&reference), flip_map: None }];
    let mut variants = Vec::new();
    for (graph, setting) in args.graphs.iter().flat_map(|g| settings.iter().map(move |s| (g, s))) {
        let desc = crate::graph::FrameGraph::load(graph)?;
        if let Some(missing) = setting.passes().into_iter().find(|p| !desc.passes.iter().any(|q| q.name == *p)) {
            out!("{} [{}]: skipped, the graph has no pass `{missing}`", graph.display(), setting.name);
            continue;
        }
        variants.push((graph, setting));
    }
    for ((curve, last), runs) in measure_seeds(&args, &gpu, &variants, &reference)? {
        let file = if curve.setting.is_empty() { format!("{}-final.exr", curve.graph) } else { format!("{}-{}-final.exr", curve.graph, file_safe(&curve.setting)) };
        image_io::save(&last, &args.out.join(file))?;
        let (flip, map) = metrics::flip(&reference, &last);
        panels.push(crate::trade::plot::Panel { label: curve.label(), image: image_io::to_srgb8(&last), flip_map: Some((map, f64::from(flip.mean))) });
        out!(
            "{}: {} frames, {:.1} ms in all, final FLIP {:.4}",
            curve.label(),
            curve.samples.len(),
            curve.samples.last().map_or(0.0, |s| s.cum_ms),
            curve.samples.last().map_or(f64::NAN, |s| s.flip)
        );
        seed_runs.push((curve.label(), runs));
        curves.push(curve);
    }
    let csv_path = args.out.join("trade.csv");
    std::fs::write(&csv_path, crate::trade::csv(&curves)).map_err(|e| UserError::in_file(&csv_path, e.to_string()))?;
    let how = format!(
        "{} at {}x{} on {}; {} frames per graph{}; frame times are {}; error of the accumulated image against {}.",
        args.scene.display(),
        args.size.0,
        args.size.1,
        gpu.describe(),
        args.frames,
        if args.seeds > 1 { format!(", each frame's figures the mean over seeds 1 to {} (the graphs in turn seed by seed, in reverse order every other seed)", args.seeds) } else { String::new() },
        if Timing::stamps_bracket_work(&gpu) { "GPU timestamps" } else { "wall clock, each frame waited for (this adapter's timestamps do not bracket the work)" },
        args.reference.as_ref().map_or(format!("pathtrace.ron at {} samples per pixel", args.reference_frames), |p| p.display().to_string())
    );
    let png_path = args.out.join("trade.png");
    crate::trade::plot::draw(&png_path, &format!("{}: error against time", args.scene.display()), &curves)
        .map_err(|e| UserError::in_file(&png_path, format!("cannot draw the plot: {e}")))?;
    let compare_path = args.out.join("compare.png");
    crate::trade::plot::compare(&compare_path, args.size, &panels).map_err(|e| UserError::in_file(&compare_path, format!("cannot draw the comparison: {e}")))?;
    let md_path = args.out.join("trade.md");
    let mut md = crate::trade::markdown("Speed against accuracy", &how, &curves);
    if args.seeds > 1 {
        md += &crate::trade::seeds::markdown(&seed_runs);
    }
    std::fs::write(&md_path, md).map_err(|e| UserError::in_file(&md_path, e.to_string()))?;
    out!("wrote {}, {}, {} and {}", csv_path.display(), md_path.display(), png_path.display(), compare_path.display());
    Ok(())
}

/// Every graph and setting rendered with seeds 1..=`args.seeds`, seed by
/// seed, each seed's runs one after another, in reverse order every other
/// seed (A B, B A, A B, ...): this machine's speed drifts over minutes,
/// and a graph whose seeds all ran first would carry the drift into the
/// graphs' ratio. Each run renders its frames alone, as when a user runs
/// it (with a frame each in turn the graphs share the caches:
/// docs/trade.md, "Over seeds"). For each: the mean curve with seed 1's
/// final image, and each seed's curve.
type Measured = ((crate::trade::Curve, crate::gpu::readback::ImageF32), Vec<crate::trade::Curve>);

fn measure_seeds(args: &TradeArgs, gpu: &Gpu, variants: &[(&PathBuf, &Setting)], reference: &crate::gpu::readback::ImageF32) -> Result<Vec<Measured>, UserError> {
    let mut per_variant: Vec<Vec<crate::trade::Curve>> = variants.iter().map(|_| Vec::new()).collect();
    let mut first_images: Vec<Option<crate::gpu::readback::ImageF32>> = variants.iter().map(|_| None).collect();
    for seed in 1..=args.seeds {
        let mut order: Vec<usize> = (0..variants.len()).collect();
        if seed % 2 == 0 {
            order.reverse();
        }
        for i in order {
            let (graph, setting) = variants[i];
            let mut run = Run::with_seed(gpu, scene::load(&args.scene)?, graph, setting, args.size, seed)?;
            let what = format!("{} seed {seed}", run.graph);
            step_together(std::slice::from_mut(&mut run), args.frames, Some(reference), &what)?;
            let (curve, last) = run.finish();
            if let Some(last) = last {
                first_images[i].get_or_insert(last);
            }
            per_variant[i].push(curve);
        }
    }
    per_variant
        .into_iter()
        .zip(first_images)
        .map(|(runs, image)| {
            let curve = crate::trade::seeds::mean_over_seeds(&runs).ok_or_else(|| UserError::new("no seed was rendered"))?;
            let image = image.ok_or_else(|| UserError::new("no seed was rendered"))?;
            Ok(((curve, image), runs))
        })
        .collect()
}
