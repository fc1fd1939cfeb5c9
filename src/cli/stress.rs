//! `glint bench stress`: how many triangles fit a frame-time target. Each
//! step renders the scene with copies of its first mesh, doubling them
//! until a frame takes `--target-ms` (`thesis_cmd` times its stress scenes
//! with the same step).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::executor::Timing;
use crate::graph::{self, CompileOptions};
use crate::metrics::median;
use crate::session::{check_size, Session, SessionOptions};

/// `glint bench stress`'s arguments.
#[derive(Args, Debug)]
pub struct StressArgs {
    pub scene: PathBuf,
    #[arg(long)]
    pub graph: PathBuf,
    #[arg(long)]
    pub target_ms: f64,
    #[arg(long, default_value = "256x256", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Test every triangle for every ray instead of using the BVH.
    #[arg(long)]
    pub brute_force: bool,
    /// Frames timed per step (median).
    #[arg(long, default_value_t = 3)]
    pub frames: u32,
}

/// Median wall milliseconds per frame of `scene` with `copies` extra copies
/// of its first mesh, and the triangle count.
fn stress_step(gpu: &Gpu, args: &StressArgs, copies: usize) -> Result<(f64, usize), UserError> {
    let scene = crate::scene::load(&args.scene)?;
    let step = StressStep { scene_path: &args.scene, graph: &args.graph, size: args.size, frames: args.frames, brute_force: args.brute_force, edits: Default::default() };
    stress_frame(gpu, scene, &step, copies)
}

/// One step of the stress test: the scene with `copies` copies of its
/// first mesh, rendered with `graph`.
pub(super) struct StressStep<'a> {
    pub scene_path: &'a Path,
    pub graph: &'a Path,
    pub size: (u32, u32),
    /// Frames timed (median), after one untimed.
    pub frames: u32,
    pub brute_force: bool,
    pub edits: crate::graph::edit::GraphEdits,
}

/// The median frame milliseconds and the triangle count of `scene` with
/// `copies` copies of its first mesh (of more than two triangles) on a grid
/// in a cube around it, each a little smaller.
pub(super) fn stress_frame(gpu: &Gpu, mut scene: crate::scene::Scene, args: &StressStep, copies: usize) -> Result<(f64, usize), UserError> {
    use crate::scene::{MeshShape, ObjectId, Transform};
    let Some((shape, base, material)) = scene
        .world
        .query::<(&MeshShape, &Transform, Option<&crate::scene::MaterialId>)>()
        .iter()
        .find(|(m, _, _)| scene.meshes().get(m.mesh).is_some_and(|d| d.triangles.len() > 2))
        .map(|(m, t, mat)| (*m, *t, mat.copied()))
    else {
        return Err(UserError::in_file(args.scene_path, "the stress test needs a scene with a mesh of more than two triangles"));
    };
    let next_id = scene.world.query::<&ObjectId>().iter().map(|id| id.0).max().unwrap_or(0) + 1;
    // Copies on a grid in a cube around the original, each a little smaller.
    let side = (copies as f32).cbrt().ceil().max(1.0) as usize;
    for k in 0..copies {
        let (i, j, l) = (k % side, (k / side) % side, k / (side * side));
        let cell = glam::DVec3::new(i as f64, j as f64, l as f64) / side as f64 - glam::DVec3::splat(0.5);
        let mut t = base;
        t.scale *= 0.5 / side as f32;
        t.translation = base.translation + cell * 1.5;
        let entity = scene.world.spawn((ObjectId(next_id + k as u32), t, shape));
        if let Some(m) = material {
            let _ = scene.world.insert_one(entity, m);
        }
    }
    let triangles = scene.triangle_count();
    let shader_dir = graph::shader_dir_for(args.graph);
    let mut compiled = graph::load_and_compile(args.graph, &shader_dir, &scene.compile_features(), &CompileOptions { edits: args.edits.clone(), ..CompileOptions::default() })?;
    if args.brute_force {
        for pass in &mut compiled.schedule.passes {
            let has = compiled.shaders.get(&pass.shader).is_some_and(|s| s.info.overrides.iter().any(|o| o.name == "BRUTE_FORCE"));
            if has {
                pass.constants.push(("BRUTE_FORCE".into(), 1.0));
            }
        }
    }
    let mut session = Session::with_graph(gpu, scene, compiled, shader_dir, SessionOptions::new(args.size))?;
    session.timing = Timing::WallPerPass;
    session.frame(0.0);
    let mut ms = Vec::new();
    for _ in 0..args.frames.max(1) {
        let start = Instant::now();
        session.frame(0.0);
        ms.push(start.elapsed().as_secs_f64() * 1e3);
    }
    Ok((median(&ms), triangles))
}

/// Where `bench stress` stops doubling.
const MAX_STRESS_TRIANGLES: usize = 50_000_000;
/// The largest `--target-ms` (a minute a frame).
const MAX_STRESS_TARGET_MS: f64 = 60_000.0;

/// `glint bench stress`.
pub(super) fn run(args: StressArgs) -> Result<(), UserError> {
    // Steps double the triangles until a frame takes the target; a target
    // no frame of MAX_STRESS_TRIANGLES reaches would run for hours.
    if !(args.target_ms.is_finite() && args.target_ms > 0.0 && args.target_ms <= MAX_STRESS_TARGET_MS) {
        return Err(UserError::new(format!(
            "--target-ms {}: give a frame time in milliseconds above 0 and at most {MAX_STRESS_TARGET_MS} (the steps stop at {MAX_STRESS_TRIANGLES} triangles anyway)",
            crate::error::figure(args.target_ms)
        )));
    }
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    out!("adapter={}", gpu.describe());
    out!("mode={}", if args.brute_force { "brute-force" } else { "bvh" });
    let mut copies = 0usize;
    let mut reached = 0usize;
    loop {
        let (ms, tris) = match stress_step(&gpu, &args, copies) {
            Ok(step) => step,
            // Past the adapter's texture or buffer limits: report what fit.
            Err(e) if reached > 0 => {
                out!("stopped_early=\"{e}\"");
                break;
            }
            Err(e) => return Err(e),
        };
        out!("step copies={copies} triangles={tris} frame_ms={ms:.2}");
        if ms > args.target_ms {
            break;
        }
        reached = tris;
        if tris > MAX_STRESS_TRIANGLES {
            out!("stopped_at_cap=\"{MAX_STRESS_TRIANGLES} triangles, under the target\"");
            break;
        }
        copies = (copies * 2).max(1);
    }
    out!("target_ms={}", args.target_ms);
    out!("triangles_within_target={reached}");
    Ok(())
}

