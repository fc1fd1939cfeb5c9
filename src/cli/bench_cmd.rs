//! `glint bench rays`: BVH build speed and primary/shadow/diffuse ray
//! throughput on a mesh, through the engine's own graph and traversal.
//! The primary rays are timed twice: as a bare ray query (`query`: the hit
//! records alone, the work Embree's rtcIntersect1 does, tools/embree) and
//! as the pass the other rays start from (`primary`: also the surface
//! points and normals).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, Subcommand};

pub use super::stress::StressArgs;
use crate::error::UserError;
use crate::gpu::readback::ImageF32;
use crate::gpu::Gpu;
use crate::graph::executor::Timing;
use crate::graph::{self, CompileOptions};
use crate::metrics::median;
use crate::session::{check_size, Session, SessionOptions};

#[derive(Subcommand, Debug)]
pub enum BenchCommand {
    /// Ray throughput on an OBJ mesh.
    Rays(RaysArgs),
    /// Two frame graphs on one scene, frame by frame in turn: the median
    /// ratio of their frame (and, with --profile, pass) times.
    Frames(super::bench_frames::FramesArgs),
    /// The thesis's stress test: add copies of the scene's first mesh until
    /// a frame takes longer than the target; report the triangles reached.
    Stress(StressArgs),
    /// Frames and milliseconds until a graph's image is within a FLIP mean
    /// of its own converged result; with --camera-path, the error after
    /// N frames of camera motion.
    Converge(super::converge_cmd::ConvergeArgs),
    /// The thesis's tables 3.1 and 3.2: bake seconds and MiB over probe
    /// levels and samples per axis, path traced and by diffuse radiance.
    Bake(super::bake_cmd::BakeBenchArgs),
    /// The thesis's chapter-4 results redone here (table 4.1, light
    /// scaling, the stress test, the post-processing effect, the speed-up
    /// against the path tracer), written to DIR/thesis.md.
    Thesis(super::thesis_cmd::ThesisArgs),
}



#[derive(Args, Debug)]
pub struct RaysArgs {
    #[arg(long)]
    pub obj: PathBuf,
    #[arg(long, default_value = "1920x1080", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// ox,oy,oz,tx,ty,tz,vfov_deg (up is +y); f64, as scene positions.
    #[arg(long, value_parser = parse_camera)]
    pub camera: [f64; 7],
    #[arg(long, default_value_t = 5)]
    pub runs: u32,
    /// Write the primary hit distance (inf on a miss) as a 1-channel EXR
    /// (or a greyscale `Pf` PFM when the name ends in .pfm).
    #[arg(long)]
    pub hitdist: Option<PathBuf>,
    /// Count each primary ray's BLAS traversal trips on the GPU (box pairs
    /// and triangles; see src/cli/trips.rs) and print their means. The
    /// counting costs time: compare times from runs without it.
    #[arg(long)]
    pub trips: bool,
    /// Another checkout (its passes/bench-rays.ron and shaders/) timed
    /// against this one in the same process, run by run in turn: prints
    /// its times as `vs_*` and the median of the per-run ratios, which a
    /// machine whose speed swings within minutes leaves far steadier than
    /// two separate runs.
    #[arg(long)]
    pub vs: Option<PathBuf>,
}

/// The passes `glint bench rays` times, by name in bench-rays.ron.
const TIMED: [&str; 4] = ["query", "primary", "shadow", "diffuse"];

fn parse_camera(s: &str) -> Result<[f64; 7], String> {
    let v: Vec<f64> = s.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|e| format!("`{s}`: {e}"))?;
    let arr: [f64; 7] = v.try_into().map_err(|_| format!("`{s}`: give 7 numbers: ox,oy,oz,tx,ty,tz,vfov_deg"))?;
    if arr.iter().any(|x| !x.is_finite()) || !(arr[6] > 0.0 && arr[6] < 180.0) {
        return Err(format!("`{s}`: all values must be finite and vfov in (0, 180)"));
    }
    Ok(arr)
}

pub fn run(cmd: BenchCommand) -> Result<(), UserError> {
    match cmd {
        BenchCommand::Rays(args) => rays(args),
        BenchCommand::Frames(args) => super::bench_frames::run(args),
        BenchCommand::Stress(args) => super::stress::run(args),
        BenchCommand::Converge(args) => super::converge_cmd::run(args),
        BenchCommand::Bake(args) => super::bake_cmd::bake_tables(args),
        BenchCommand::Thesis(args) => super::thesis_cmd::run(args),
    }
}

fn rays(args: RaysArgs) -> Result<(), UserError> {
    if let Some(path) = &args.hitdist {
        hitdist_is_pfm(path)?;
    }
    let obj = std::fs::canonicalize(&args.obj)
        .map_err(|e| UserError::in_file(&args.obj, format!("cannot open the OBJ: {e}")))?;
    let c = args.camera;
    let text = format!(
        "Scene(camera: Camera(position: ({:e}, {:e}, {:e}), target: ({:e}, {:e}, {:e}), vfov_deg: {}),\n\
         materials: {{ \"white\": Material(albedo: (0.8, 0.8, 0.8)) }},\n\
         objects: [ Mesh(path: {:?}, material: \"white\") ])",
        c[0], c[1], c[2], c[3], c[4], c[5], c[6], obj.display().to_string()
    );
    let load_start = Instant::now();
    // The scene is made from the arguments: errors name them, not a file.
    let scene_origin = Path::new("(the scene bench rays made of --obj and --camera)");
    let scene = crate::scene::parse(&text, scene_origin)?;
    let load_ms = load_start.elapsed().as_secs_f64() * 1e3;
    let triangles = scene.triangle_count();
    // The builder is timed on the triangles in the OBJ's order: the
    // renderer's copy is already in BVH leaf order, which builds faster.
    let bounds: Vec<crate::bvh::Aabb> = scene.pack().triangles.iter().map(crate::bvh::scene::tri_bounds).collect();
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    let graph_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("passes/bench-rays.ron");
    let graph_path = if Path::new("passes/bench-rays.ron").is_file() { PathBuf::from("passes/bench-rays.ron") } else { graph_path };
    let other = match &args.vs {
        Some(dir) => Some(bench_session(&gpu, crate::scene::parse(&text, scene_origin)?, &dir.join("passes/bench-rays.ron"), &args)?),
        None => None,
    };
    let mut session = bench_session(&gpu, scene, &graph_path, &args)?;
    let build = session.scene.bvh_stats;
    out!("adapter={}", gpu.describe());
    out!("triangles={triangles}");
    out!("obj_load_ms={load_ms:.1}");
    // The renderer's build ran once, in memory the process had never
    // touched; the builder is then timed as the ray passes are, median of
    // `--runs` builds of the mesh (in the OBJ's triangle order) after that
    // warm-up, its working array kept between builds as SceneBvh keeps it.
    out!("bvh_first_build_ms={:.1}", build.build_ms);
    out!("bvh_update_ms={:.1}", build.blas_ms + build.tlas_ms);
    let mut builder = crate::bvh::BvhBuilder::default();
    let build_ms: Vec<f64> = (0..args.runs.max(1))
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(builder.build(&bounds, crate::bvh::BLAS_MAX_DEPTH));
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    let build_ms = median(&build_ms);
    out!("bvh_build_ms={build_ms:.1}");
    out!("bvh_build_mtri_per_s={:.2}", bounds.len() as f64 / (build_ms * 1e3));
    out!("bvh_nodes={}", session.scene.buffers.data.bvh.len());

    // Warm up (pipeline compilation, first-touch), then time each pass.
    let names = TIMED;
    let mut other = other.map(|s| (s, vec![Vec::new(); names.len()]));
    for s in std::iter::once(&mut session).chain(other.as_mut().map(|(s, _)| s)) {
        s.timing = Timing::WallPerPass;
        s.frame(0.0);
    }
    let mut wall: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut stamps: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for run in 0..args.runs.max(1) {
        // The other checkout first on every other run, so that neither
        // always follows the other.
        if let Some((s, w)) = other.as_mut().filter(|_| run % 2 == 1) {
            time_frame(s, w);
        }
        time_frame(&mut session, &mut wall);
        if let Some((s, w)) = other.as_mut().filter(|_| run % 2 == 0) {
            time_frame(s, w);
        }
        if Timing::stamps_bracket_work(&gpu) {
            session.timing = Timing::Gpu;
            session.frame(0.0);
            let t = session.finish();
            record(&mut stamps, t);
        }
    }
    // What a camera move costs the CPU before its frame: the screen tiles'
    // cuts (src/bvh/tiles.rs) for this camera, median of `--runs` builds.
    let table_ms: Vec<f64> = (0..args.runs.max(1))
        .filter_map(|_| {
            let start = Instant::now();
            std::hint::black_box(session.scene.buffers.rebuild_tile_table())?;
            Some(start.elapsed().as_secs_f64() * 1e3)
        })
        .collect();
    if !table_ms.is_empty() {
        out!("tile_table_ms={:.2}", median(&table_ms));
    }
    let out = session.read_output()?;
    let pixels = (args.size.0 * args.size.1) as f64;
    let hits = out.data.iter().filter(|p| p[0].is_finite()).count() as f64;
    out!("primary_rays={pixels}");
    out!("secondary_rays_each={hits}");
    // Rays each pass traces, in the order of `names`.
    let counts = [pixels, pixels, hits, hits];
    for i in 0..names.len() {
        if wall[i].is_empty() {
            continue;
        }
        let w = median(&wall[i]);
        out!("{}_ms_wall={w:.3}", names[i]);
        out!("{}_mrays_per_s_wall={:.2}", names[i], counts[i] / (w * 1e3));
        // The fastest run: on a machine whose speed swings, slowdowns only
        // add, so two builds compare best by their minima.
        let fastest = wall[i].iter().copied().fold(f64::INFINITY, f64::min);
        out!("{}_ms_wall_min={fastest:.3}", names[i]);
        if !stamps[i].is_empty() {
            let g = median(&stamps[i]);
            out!("{}_ms_gpu={g:.3}", names[i]);
            out!("{}_mrays_per_s_gpu={:.2}", names[i], counts[i] / (g.max(1e-6) * 1e3));
        }
    }
    if let Some((_, vs)) = &other {
        print_vs(&wall, vs);
    }
    if let Some(path) = &args.hitdist {
        write_hitdist(&out, path)?;
        out!("hitdist={}", path.display());
    }
    if args.trips {
        print_trips(&session, args.size.0)?;
    }
    Ok(())
}

/// The bench graph at `graph_path` (its shaders beside it) compiled for
/// `scene`, as a session.
fn bench_session(gpu: &Gpu, scene: crate::scene::Scene, graph_path: &Path, args: &RaysArgs) -> Result<Session, UserError> {
    let shader_dir = graph::shader_dir_for(graph_path);
    let options = CompileOptions { keep: vec!["bench_normal".into()], also_compute: vec!["bench_query".into()], ..CompileOptions::default() };
    let mut compiled = graph::load_and_compile(graph_path, &shader_dir, &scene.compile_features(), &options)?;
    if args.trips {
        for pass in compiled.schedule.passes.iter_mut().filter(|p| p.name == "primary") {
            pass.constants.push(("COUNT_TRIPS".into(), 1.0));
        }
    }
    Session::with_graph(gpu, scene, compiled, shader_dir, SessionOptions::new(args.size))
}

/// Appends each pass's timings to `into`, by name: a graph edited to
/// have other passes times only these.
fn record(into: &mut [Vec<f64>], timings: Vec<crate::graph::executor::PassTimings>) {
    for t in timings {
        for (name, m) in t.passes {
            if let Some(i) = TIMED.iter().position(|n| *n == name) {
                into[i].push(m);
            }
        }
    }
}

/// One frame with every pass timed by the wall clock, into `wall`.
fn time_frame(session: &mut Session, wall: &mut [Vec<f64>]) {
    session.timing = Timing::WallPerPass;
    let t = session.frame(0.0);
    record(wall, t);
}

/// The `--vs` checkout's times and, per pass, the median over runs of
/// this checkout's time over the other's in the same run.
fn print_vs(wall: &[Vec<f64>], vs: &[Vec<f64>]) {
    for (i, name) in TIMED.iter().enumerate() {
        if vs[i].is_empty() {
            continue;
        }
        out!("vs_{name}_ms_wall={:.3}", median(&vs[i]));
        let fastest = vs[i].iter().copied().fold(f64::INFINITY, f64::min);
        out!("vs_{name}_ms_wall_min={fastest:.3}");
        if let Some((ratio, lo, hi)) = crate::metrics::paired_ratios(&wall[i], &vs[i]) {
            out!("{name}_over_vs={ratio:.3} (runs {lo:.3}-{hi:.3})");
        }
    }
}

/// The primary rays' trip counts (bench_normal.w, see `--trips`).
fn print_trips(session: &Session, width: u32) -> Result<(), UserError> {
    let normals = session.read_resource("bench_normal").ok_or_else(|| UserError::new("bench-rays.ron wrote no `bench_normal` to count trips in"))??;
    let codes: Vec<f32> = normals.data.iter().map(|p| p[3]).collect();
    let s = super::trips::trip_stats(&codes, width as usize);
    out!("trips_node_per_ray={:.3}", s.node_per_ray);
    out!("trips_triangle_per_ray={:.3}", s.triangle_per_ray);
    out!("trips_per_ray={:.3}", s.per_ray);
    out!("trips_group_max_per_ray={:.3}", s.group_max_per_ray);
    Ok(())
}

/// The x channel (primary hit distance, inf on a miss) as a 1-channel EXR.
/// `--hitdist` writes EXR or PFM, chosen by the extension; anything else
/// is refused before the benchmark runs.
fn hitdist_is_pfm(path: &Path) -> Result<bool, UserError> {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("pfm") => Ok(true),
        Some("exr") => Ok(false),
        _ => Err(UserError::in_file(path, "--hitdist writes an .exr or a .pfm; name the file so")),
    }
}

fn write_hitdist(img: &ImageF32, path: &Path) -> Result<(), UserError> {
    use exr::prelude::*;
    if hitdist_is_pfm(path)? {
        return crate::image_io::save_pfm_grey(img, path);
    }
    let samples: Vec<f32> = img.data.iter().map(|p| p[0]).collect();
    let channel = AnyChannel::new("Z", FlatSamples::F32(samples));
    let layer = Layer::new(
        (img.width as usize, img.height as usize),
        LayerAttributes::named("hitdist"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(smallvec::smallvec![channel]),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| UserError::in_file(path, format!("cannot write the EXR: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hitdist_exr_round_trips_with_inf() {
        let mut img = ImageF32::new(3, 2);
        for (i, p) in img.data.iter_mut().enumerate() {
            p[0] = if i == 4 { f32::INFINITY } else { i as f32 * 1.5 };
        }
        let path = std::env::temp_dir().join(format!("glint-hitdist-{}.exr", std::process::id()));
        write_hitdist(&img, &path).unwrap();
        let read = exr::prelude::read_first_flat_layer_from_file(&path).unwrap();
        let layer = &read.layer_data;
        assert_eq!((layer.size.0, layer.size.1), (3, 2));
        assert_eq!(layer.channel_data.list.len(), 1);
        let values: Vec<f32> = layer.channel_data.list[0].sample_data.values_as_f32().collect();
        let want: Vec<f32> = img.data.iter().map(|p| p[0]).collect();
        assert_eq!(values, want);
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn camera_argument_is_checked() {
        assert!(parse_camera("0,0,5,0,0,0,45").is_ok());
        assert!(parse_camera("0,0,5,0,0,0").is_err());
        assert!(parse_camera("0,0,5,0,0,0,180").is_err());
        assert!(parse_camera("0,0,NaN,0,0,0,45").is_err());
    }
}

