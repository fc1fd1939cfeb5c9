//! `glint trade --animate`: every graph in motion against the truth of
//! each instant. Frame k (from 0) renders the scene at time k / 30 s with
//! the camera on `--camera-path` at that time; every `--reference-every`-th
//! frame is compared with a reference of that instant (the reference graph
//! at `--reference-frames` frames, time and camera held still, cached in
//! the output folder by what it was rendered from). trade.csv keeps one
//! row per compared frame (its cumulative time counts every frame);
//! trade.md adds the mean and 95th percentile FLIP in motion and, with
//! `--reference-every 1`, the flicker: the mean FLIP between consecutive
//! frames less the references' own.

use std::path::{Path, PathBuf};

use super::trade_run::{cached_reference, file_safe, pathtracer_beside, Motion, ReferenceSpec, Run};
use crate::camera_path::CameraPath;
use crate::error::UserError;
use crate::gpu::readback::ImageF32;
use crate::gpu::Gpu;
use crate::trade::motion::{motion_markdown, MotionRow};
use crate::trade::sweep::Setting;
use crate::{image_io, metrics, scene};

/// Scene time per frame: 30 frames a second of scene time.
pub const FRAME_DT: f32 = 1.0 / 30.0;

/// What `trade --animate` was asked (`glint trade`'s arguments).
pub(super) struct MotionRequest<'a> {
    pub scene: &'a Path,
    pub graphs: &'a [PathBuf],
    pub size: (u32, u32),
    pub frames: u32,
    pub reference_frames: u32,
    pub camera_path: Option<&'a str>,
    pub reference_every: u32,
    pub reference_graph: Option<&'a Path>,
    pub out: &'a Path,
}

pub(super) fn run(args: &MotionRequest, gpu: &Gpu, settings: &[Setting]) -> Result<(), UserError> {
    if args.reference_every == 0 || args.reference_every > args.frames {
        return Err(UserError::new(format!("--reference-every {}: give 1 to --frames ({})", args.reference_every, args.frames)));
    }
    let path = args.camera_path.map(CameraPath::parse).transpose()?;
    let base = scene::load(args.scene)?.camera;
    if let Some(p) = &path {
        p.check(&base)?;
    }
    let motion = Motion { dt: FRAME_DT, path, base };
    let reference_graph = args.reference_graph.map_or_else(|| pathtracer_beside(args.graphs), Path::to_path_buf);
    // The compared frames (1-based) and their references.
    let compared: Vec<u32> = (1..=args.frames).filter(|f| f % args.reference_every == 0).collect();
    let mut references = Vec::new();
    for &f in &compared {
        let time = (f - 1) as f32 * FRAME_DT;
        let spec = ReferenceSpec {
            scene: args.scene,
            size: args.size,
            frames: args.reference_frames,
            dir: args.out,
            stem: &format!("reference-f{f:04}"),
            pathtracer: &reference_graph,
            time,
            camera: Some(motion.camera_at(time)),
        };
        references.push(cached_reference(gpu, &spec)?);
    }
    // The references' own flicker: FLIP between consecutive instants.
    let reference_flicker = (args.reference_every == 1).then(|| mean_consecutive_flip(&references));
    let mut curves = Vec::new();
    let mut rows = Vec::new();
    for (graph, setting) in args.graphs.iter().flat_map(|g| settings.iter().map(move |s| (g, s))) {
        let desc = crate::graph::FrameGraph::load(graph)?;
        if let Some(missing) = setting.passes().into_iter().find(|p| !desc.passes.iter().any(|q| q.name == *p)) {
            out!("{} [{}]: skipped, the graph has no pass `{missing}`", graph.display(), setting.name);
            continue;
        }
        let mut run = Run::new(gpu, scene::load(args.scene)?, graph, setting, args.size)?;
        run.animate(motion.clone());
        let bar = indicatif::ProgressBar::new(u64::from(args.frames));
        let mut outputs = Vec::new();
        let mut next = 0;
        for f in 1..=args.frames {
            let reference = (compared.get(next) == Some(&f)).then(|| &references[next]);
            run.step(reference)?;
            if reference.is_some() {
                next += 1;
                outputs.push(run.read()?);
            }
            bar.set_position(u64::from(f));
        }
        bar.finish_and_clear();
        let (mut curve, last) = run.finish();
        curve.samples.retain(|s| !s.flip.is_nan());
        let flicker = reference_flicker.map(|r| mean_consecutive_flip(&outputs) - r);
        let row = MotionRow::new(curve.label(), &curve, flicker);
        out!("{}: {} compared frames, FLIP mean {:.4}, p95 {:.4}", row.label, curve.samples.len(), row.mean, row.p95);
        if let Some(img) = last {
            let file = if setting.name.is_empty() { format!("{}-final.exr", curve.graph) } else { format!("{}-{}-final.exr", curve.graph, file_safe(&setting.name)) };
            image_io::save(&img, &args.out.join(file))?;
        }
        rows.push(row);
        curves.push(curve);
    }
    let csv_path = args.out.join("trade.csv");
    std::fs::write(&csv_path, crate::trade::csv(&curves)).map_err(|e| UserError::in_file(&csv_path, e.to_string()))?;
    let how = format!(
        "{} at {}x{} on {}, in motion: scene time {:.4} s a frame{}; {} frames per graph, every {}-th compared with {} at {} frames, time and camera held still.",
        args.scene.display(),
        args.size.0,
        args.size.1,
        gpu.describe(),
        FRAME_DT,
        args.camera_path.map_or(String::new(), |p| format!(", camera {p}")),
        args.frames,
        args.reference_every,
        reference_graph.display(),
        args.reference_frames
    );
    let md_path = args.out.join("trade.md");
    let text = format!("{}\n{}", crate::trade::markdown("Speed against accuracy, in motion", &how, &curves), motion_markdown(&rows));
    std::fs::write(&md_path, text).map_err(|e| UserError::in_file(&md_path, e.to_string()))?;
    let png_path = args.out.join("trade.png");
    crate::trade::plot::draw(&png_path, &format!("{}: error against time, in motion", args.scene.display()), &curves)
        .map_err(|e| UserError::in_file(&png_path, format!("cannot draw the plot: {e}")))?;
    out!("wrote {}, {} and {}", csv_path.display(), md_path.display(), png_path.display());
    Ok(())
}

/// The mean FLIP between each image and the next.
fn mean_consecutive_flip(images: &[ImageF32]) -> f64 {
    let pairs: Vec<f64> = images.windows(2).map(|w| f64::from(metrics::flip(&w[0], &w[1]).0.mean)).collect();
    if pairs.is_empty() {
        return 0.0;
    }
    pairs.iter().sum::<f64>() / pairs.len() as f64
}
