//! `glint bench thesis`: the thesis's chapter-4 results (4.3), redone on
//! the machine at hand and written to DIR/thesis.md with the adapter
//! named:
//! - table 4.1: frame times in the three reference environments
//!   (`scenes/thesis-env{1,2,3}.ron`), the hybrid against the path tracer
//!   at 2 samples per pixel and 4 bounces (and the shipped ground truth
//!   and hybrid-gi beside them);
//! - light scaling (4.3.1/4.3.2): environment 3 with three times its
//!   lights; the stress scene with 1, 2 and 4;
//! - the stress test (4.3.2): copies of a 104-triangle mesh until a hybrid
//!   frame takes longer than the target, and the path tracer there;
//! - post-processing (4.3.3): frame time and time to settle with and
//!   without the noise mask and its refinement;
//! - the convergence speed-up against the path tracer (`trade::speed_up`).
//!
//! Graphs measured together are stepped in alternation, a frame each in
//! turn: this machine's speed drifts over minutes, and alternation gives
//! every graph the same drift.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use clap::Args;

use super::stress::{stress_frame, StressStep};
use super::trade_run::{cached_reference, step_together, ReferenceSpec, Run};
use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::desc::ParamValue;
use crate::graph::executor::Timing;
use crate::metrics::median;
use crate::session::check_size;
use crate::trade::sweep::Setting;
use crate::trade::{speed_up, Curve};

#[derive(Args, Debug)]
pub struct ThesisArgs {
    #[arg(long, default_value = "128x128", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Frames per graph in each measurement.
    #[arg(long, default_value_t = 48)]
    pub frames: u32,
    /// Samples per pixel of the path-traced references.
    #[arg(long, default_value_t = 1024)]
    pub reference_frames: u32,
    /// The stress test's frame-time target (the thesis's 60 FPS).
    #[arg(long, default_value_t = 16.7)]
    pub stress_target_ms: f64,
    /// The stress test adds copies up to this many triangles.
    #[arg(long, default_value_t = 50_000)]
    pub stress_max_triangles: usize,
    /// The folder with the thesis scenes and passes/ (default: the current
    /// folder if it has them, else the one glint was built from).
    #[arg(long)]
    pub root: Option<PathBuf>,
    #[arg(long)]
    pub out: PathBuf,
}

/// The thesis's figures, quoted beside ours (table 4.1, 4.3.1-4.3.3).
const THESIS_FPS: [(&str, f64, f64); 3] = [("1", 160.0, 135.0), ("2", 263.0, 170.0), ("3", 168.0, 46.0)];

struct Paths {
    envs: [PathBuf; 3],
    stress: PathBuf,
    hybrid: PathBuf,
    hybrid_gi: PathBuf,
    realtime: PathBuf,
    pathtrace: PathBuf,
}

impl Paths {
    fn under(root: &Path) -> Paths {
        Paths {
            envs: [1, 2, 3].map(|i| root.join(format!("scenes/thesis-env{i}.ron"))),
            stress: root.join("scenes/thesis-stress.ron"),
            hybrid: root.join("passes/hybrid.ron"),
            hybrid_gi: root.join("passes/hybrid-gi.ron"),
            realtime: root.join("passes/realtime.ron"),
            pathtrace: root.join("passes/pathtrace.ron"),
        }
    }
}

/// The thesis's path tracer for table 4.1: 2 samples per pixel, 4 bounces
/// (5 path segments), no Russian roulette before them.
fn thesis_pathtracer() -> Setting {
    let mut s = Setting { name: "2 spp, 4 bounces".into(), ..Setting::plain() };
    s.params.insert("pathtrace.spp".into(), ParamValue::Int(2));
    s.params.insert("pathtrace.max_depth".into(), ParamValue::Int(5));
    s.params.insert("pathtrace.rr_depth".into(), ParamValue::Int(5));
    s
}

/// The hybrid without its post-processing (noise mask and refinement).
fn without_mask() -> Setting {
    Setting { name: "no mask".into(), skip: vec!["refine".into()], ..Setting::plain() }
}

fn med_ms(c: &Curve) -> f64 {
    median(&c.samples.iter().map(|s| s.ms).collect::<Vec<_>>())
}

fn fps(ms: f64) -> String {
    format!("{:.1} ms ({:.0} FPS)", ms, 1e3 / ms)
}

pub fn run(args: ThesisArgs) -> Result<(), UserError> {
    if args.frames < 2 || args.reference_frames < 2 {
        return Err(UserError::new("--frames and --reference-frames must be at least 2"));
    }
    if !(args.stress_target_ms.is_finite() && args.stress_target_ms > 0.0) {
        return Err(UserError::new("--stress-target-ms must be a positive number of milliseconds"));
    }
    let root = match &args.root {
        Some(r) => r.clone(),
        None if Path::new("scenes/thesis-env1.ron").is_file() => PathBuf::from("."),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")),
    };
    let paths = Paths::under(&root);
    std::fs::create_dir_all(&args.out).map_err(|e| UserError::in_file(&args.out, format!("cannot create the folder: {e}")))?;
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    let mut md = String::new();
    let _ = writeln!(md, "# The thesis's results, redone\n");
    let _ = writeln!(
        md,
        "Adapter: **{}**. Size {}x{}; {} frames per graph; frame times are {}; the graphs of each table rendered in alternation, a frame each in turn. \
         References: `pathtrace.ron` at {} samples per pixel. Made by `glint bench thesis --size {}x{} --frames {} --out DIR`.\n",
        gpu.describe(),
        args.size.0,
        args.size.1,
        args.frames,
        if Timing::stamps_bracket_work(&gpu) { "GPU timestamps" } else { "wall clock, each frame waited for" },
        args.reference_frames,
        args.size.0,
        args.size.1,
        args.frames
    );

    // Table 4.1, post-processing and the speed-ups, per environment.
    let mut table = String::from(
        "| environment | triangles | lights | hybrid | path tracer, 2 spp, 4 bounces | thesis (hybrid / path tracer) | hybrid-gi | realtime | pathtrace.ron (1 spp) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut post = String::from(
        "| environment | with mask: frame | to FLIP 0.05 | to FLIP 0.02 | without: frame | to FLIP 0.05 | to FLIP 0.02 |\n|---|---|---|---|---|---|---|\n",
    );
    let mut speed = String::from("| environment | graph | settles at FLIP | in | path tracer reaches it in | speed-up |\n|---|---|---|---|---|---|\n");
    for (i, env) in paths.envs.iter().enumerate() {
        let n = i + 1;
        let scene = crate::scene::load(env)?;
        let (triangles, lights) = (scene.triangle_count(), scene.features.lights);
        let spec = ReferenceSpec { scene: env, size: args.size, frames: args.reference_frames, dir: &args.out, stem: &format!("env{n}-reference"), pathtracer: &paths.pathtrace, time: 0.0, camera: None };
        let reference = cached_reference(&gpu, &spec)?;
        let load = || crate::scene::load(env);
        let mut runs = vec![
            Run::new(&gpu, load()?, &paths.hybrid, &Setting::plain(), args.size)?,
            Run::new(&gpu, load()?, &paths.pathtrace, &thesis_pathtracer(), args.size)?,
            Run::new(&gpu, load()?, &paths.hybrid_gi, &Setting::plain(), args.size)?,
            Run::new(&gpu, load()?, &paths.pathtrace, &Setting::plain(), args.size)?,
            Run::new(&gpu, load()?, &paths.realtime, &Setting::plain(), args.size)?,
        ];
        step_together(&mut runs, args.frames, Some(&reference), &format!("environment {n}"))?;
        let curves: Vec<Curve> = runs.into_iter().map(|r| r.finish().0).collect();
        let [hybrid, pt2, gi, pt, rt] = [&curves[0], &curves[1], &curves[2], &curves[3], &curves[4]];
        let (_, th_h, th_p) = THESIS_FPS[i];
        let _ = writeln!(
            table,
            "| {n} | {triangles} | {lights} | {} | {} | {th_h:.0} / {th_p:.0} FPS | {} | {} | {} |",
            fps(med_ms(hybrid)),
            fps(med_ms(pt2)),
            fps(med_ms(gi)),
            fps(med_ms(rt)),
            fps(med_ms(pt))
        );
        post.push_str(&post_processing(&gpu, &args, &paths, env, n)?);
        post.push('\n');
        for g in [hybrid, gi, rt] {
            if let Some(s) = speed_up(g, pt) {
                let slow = s.slow_ms.map_or(format!("not in {:.0} ms", s.slow_total_ms), |ms| format!("{ms:.0} ms"));
                let _ = writeln!(speed, "| {n} | {} | {:.3} | {:.0} ms | {slow} | {} |", g.graph, s.flip, s.fast_ms, s.describe());
            }
        }
        out!("environment {n}: hybrid {:.1} ms, path tracer (2 spp, 4 bounces) {:.1} ms", med_ms(hybrid), med_ms(pt2));
    }
    let _ = writeln!(md, "## Table 4.1: frame time per reference environment\n\nMedian frame time (frames per second). The thesis's figures are its GPU's, at its resolution; compare the ratios.\n\n{table}");
    let _ = writeln!(
        md,
        "## Convergence speed-up against the path tracer\n\nEach graph's FLIP mean against the reference settles at its best plus {:.0}%; the speed-up is the time `pathtrace.ron` needs to reach that FLIP over the time the graph needs (the thesis reports about 3000x). Below 1, the path tracer got there first.\n\n{speed}",
        crate::trade::SETTLE_MARGIN * 100.0
    );
    let _ = writeln!(
        md,
        "## Post-processing (4.3.3)\n\n`hybrid.ron` with its noise mask and refinement (sobel, blur, threshold, refine) and without them (`--skip refine`): median frame time, and the time (frames) until the image is within a FLIP mean of its own converged image (`hybrid.ron` at {} frames: the mask only adds samples, so both converge to it; this is the noise the thesis's figure 4.14 shows, not the bias against the path tracer). The thesis: 395 FPS without, 170 with; converged in 150 ms (50 frames) without, 59 ms (10 frames) with.\n\n{post}",
        own_frames(&args)
    );

    // Light scaling: environment 3 with three times its lights, the
    // stress scene with 1, 2 and 4.
    let mut lights = String::from("| scene | lights | hybrid | path tracer, 2 spp, 4 bounces | realtime |\n|---|---|---|---|---|\n");
    for (scene_path, factors) in [(&paths.envs[2], &[1u32, 3][..]), (&paths.stress, &[1, 2, 4][..])] {
        let mut runs = Vec::new();
        let mut counts = Vec::new();
        for &k in factors {
            for (graph, setting) in [(&paths.hybrid, Setting::plain()), (&paths.pathtrace, thesis_pathtracer()), (&paths.realtime, Setting::plain())] {
                let mut scene = crate::scene::load(scene_path)?;
                scene.multiply_lights(k);
                counts.push(scene.features.lights);
                runs.push(Run::new(&gpu, scene, graph, &setting, args.size)?);
            }
        }
        step_together(&mut runs, args.frames, None, "light scaling")?;
        let name = scene_path.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
        for (three, count) in runs.chunks(3).zip(counts.chunks(3)) {
            let ms = |k: usize| median(&three[k].frame_ms());
            let _ = writeln!(lights, "| {name} | {} | {:.1} ms | {:.1} ms | {:.1} ms |", count[0], ms(0), ms(1), ms(2));
        }
    }
    let _ = writeln!(
        md,
        "## Light scaling (4.3.1, 4.3.2)\n\nMedian frame time as lights are added (copies of each light beside it, as bright). The thesis: environment 3 fell from 168 to 70 FPS with three times its lights; the stress scene from 66 to 53 (2 lights) and 37 FPS (4), its path tracer stayed at 4 FPS.\n\n{lights}"
    );

    // The stress test.
    let stress = stress_test(&gpu, &args, &paths)?;
    let _ = writeln!(md, "## Stress test (4.3.2)\n\n{stress}");

    let md_path = args.out.join("thesis.md");
    std::fs::write(&md_path, &md).map_err(|e| UserError::in_file(&md_path, e.to_string()))?;
    out!("wrote {}", md_path.display());
    Ok(())
}

/// Frames of the hybrid's own converged image.
fn own_frames(args: &ThesisArgs) -> u32 {
    (args.reference_frames / 4).max(2)
}

/// One row of the post-processing table: the hybrid with and without its
/// mask, in alternation, against the hybrid's own converged image.
fn post_processing(gpu: &Gpu, args: &ThesisArgs, paths: &Paths, env: &Path, n: usize) -> Result<String, UserError> {
    let mut own = Run::new(gpu, crate::scene::load(env)?, &paths.hybrid, &Setting::plain(), args.size)?;
    step_together(std::slice::from_mut(&mut own), own_frames(args), None, &format!("environment {n}, hybrid converging"))?;
    let converged = own.read()?;
    let mut runs = vec![
        Run::new(gpu, crate::scene::load(env)?, &paths.hybrid, &Setting::plain(), args.size)?,
        Run::new(gpu, crate::scene::load(env)?, &paths.hybrid, &without_mask(), args.size)?,
    ];
    step_together(&mut runs, args.frames, Some(&converged), &format!("environment {n}, post-processing"))?;
    let curves: Vec<Curve> = runs.into_iter().map(|r| r.finish().0).collect();
    let to = |c: &Curve, flip: f64| -> String {
        c.samples.iter().find(|s| s.flip <= flip).map_or(format!("not in {} frames", c.samples.len()), |s| {
            format!("{:.0} ms, {}", s.cum_ms, crate::trade::frames_text(s.frame))
        })
    };
    let (with, without) = (&curves[0], &curves[1]);
    Ok(format!(
        "| {n} | {:.1} ms | {} | {} | {:.1} ms | {} | {} |",
        med_ms(with),
        to(with, 0.05),
        to(with, 0.02),
        med_ms(without),
        to(without, 0.05),
        to(without, 0.02)
    ))
}

/// Copies of the stress scene's 104-triangle mesh, doubling up to the
/// triangle cap: the hybrid's and the path tracer's frame at each count,
/// and the most triangles the hybrid renders within the target.
fn stress_test(gpu: &Gpu, args: &ThesisArgs, paths: &Paths) -> Result<String, UserError> {
    let step = |graph, edits| StressStep { scene_path: &paths.stress, graph, size: args.size, frames: 3, brute_force: false, edits };
    let hybrid = step(paths.hybrid.as_path(), Default::default());
    let pt_edits = crate::graph::edit::GraphEdits { set: thesis_pathtracer().param_sets(), ..Default::default() };
    let pathtracer = step(paths.pathtrace.as_path(), pt_edits);
    let mut o = String::from("| copies | triangles | hybrid | path tracer, 2 spp, 4 bounces |\n|---|---|---|---|\n");
    let (mut copies, mut within) = (0usize, None);
    loop {
        let (ms, tris) = stress_frame(gpu, crate::scene::load(&paths.stress)?, &hybrid, copies)?;
        let (pt_ms, _) = stress_frame(gpu, crate::scene::load(&paths.stress)?, &pathtracer, copies)?;
        let _ = writeln!(o, "| {copies} | {tris} | {ms:.1} ms | {pt_ms:.1} ms |");
        out!("stress: {copies} copies, {tris} triangles, hybrid {ms:.1} ms, path tracer {pt_ms:.1} ms");
        if ms <= args.stress_target_ms {
            within = Some(tris);
        }
        if tris >= args.stress_max_triangles {
            break;
        }
        copies = (copies * 2).max(1);
    }
    let within = match within {
        Some(t) => format!("The most triangles the hybrid rendered within {} ms: **{t}**.", args.stress_target_ms),
        None => format!("The hybrid took longer than {} ms a frame at every count, even with no copies.", args.stress_target_ms),
    };
    Ok(format!(
        "Copies of the scene's 104-triangle mesh, doubling, up to {} triangles; median of 3 frames each. The thesis, without a BVH, stopped at about 21 thousand triangles \
         where its hybrid fell to 66 FPS (its path tracer: 4 FPS). {within}\n\n{o}",
        args.stress_max_triangles
    ))
}
