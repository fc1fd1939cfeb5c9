//! The real-time graph's denoiser (passes/realtime.ron) on the GPU path:
//! a still image tends to the path tracer's mean, the variance it filters
//! by falls with history, a light that jumps drops history where its
//! light changed, and only there, without leaving a ghost, and what a
//! mirror shows is not blended with the surface seen beside it, and
//! thinning the filter's still frames changes no image it makes.

mod common;

use common::*;
use glint::gpu::readback::ImageF32;
use glint::graph::CompileOptions;
use glint::metrics;
use glint::session::Session;

const SIZE: (u32, u32) = (48, 48);
const PAIRS_SIZE: u32 = 192;

fn realtime() -> std::path::PathBuf {
    repo().join("passes/realtime.ron")
}

fn keep(resources: &[&str]) -> CompileOptions {
    CompileOptions { keep: resources.iter().map(|r| r.to_string()).collect(), ..Default::default() }
}

fn read(s: &Session, resource: &str) -> ImageF32 {
    s.read_resource(resource).unwrap_or_else(|| panic!("{resource} not kept")).unwrap_or_else(|e| panic!("{e}"))
}

fn mean_luminance(img: &ImageF32) -> f64 {
    img.data.iter().map(luminance).sum::<f64>() / img.data.len() as f64
}

/// `frames` still frames of `graph` at `time`; its output.
fn still(gpu: &glint::gpu::Gpu, scene: glint::scene::Scene, graph: &std::path::Path, frames: u32, time: f32) -> ImageF32 {
    still_at(gpu, scene, graph, frames, time, SIZE)
}

fn still_at(gpu: &glint::gpu::Gpu, scene: glint::scene::Scene, graph: &std::path::Path, frames: u32, time: f32, size: (u32, u32)) -> ImageF32 {
    let compiled = compile(&scene, graph, &CompileOptions::default());
    let mut s = session(gpu, scene, &compiled, size, 1);
    run_frames(&mut s, frames, time);
    s.read_output().unwrap_or_else(|e| panic!("{e}"))
}


#[test]
fn a_still_image_tends_to_the_path_tracers_mean() {
    let Some(gpu) = gpu() else { return };
    let reference = still(gpu, load_scene("cornell.ron"), &repo().join("passes/pathtrace.ron"), 512, 0.0);
    let first = still(gpu, load_scene("cornell.ron"), &realtime(), 1, 0.0);
    let converged = still(gpu, load_scene("cornell.ron"), &realtime(), 512, 0.0);
    let (f1, _) = metrics::flip(&reference, &first);
    let (f512, _) = metrics::flip(&reference, &converged);
    let (l_ref, l_rt) = (mean_luminance(&reference), mean_luminance(&converged));
    eprintln!("FLIP against pathtrace.ron at 512 frames: 1 frame {:.4}, 512 frames {:.4}; mean luminance {l_rt:.5} against {l_ref:.5}", f1.mean, f512.mean);
    // The filter fades as history grows: what is left is both images' noise.
    assert!(f512.mean < 0.5 * f1.mean, "512 frames ({:.4}) not far below 1 frame ({:.4})", f512.mean, f1.mean);
    assert!(f512.mean < 0.06, "512 still frames are FLIP {:.4} from the path tracer's mean", f512.mean);
    assert!((l_rt / l_ref - 1.0).abs() < 0.02, "mean luminance {l_rt} against the path tracer's {l_ref}: biased");
}

#[test]
fn one_light_a_bounce_keeps_the_path_tracers_mean_with_several_lights() {
    // moving-lights at time 0: three sphere lights, each bounce of the
    // real-time graph's paths samples one of them (NEE_ONE).
    let Some(gpu) = gpu() else { return };
    let reference = still(gpu, load_scene("moving-lights.ron"), &repo().join("passes/pathtrace.ron"), 256, 0.0);
    let converged = still(gpu, load_scene("moving-lights.ron"), &realtime(), 256, 0.0);
    let (l_ref, l_rt) = (mean_luminance(&reference), mean_luminance(&converged));
    let (flip, _) = metrics::flip(&reference, &converged);
    eprintln!("moving-lights, 256 frames each: mean luminance {l_rt:.5} against the path tracer's {l_ref:.5}; FLIP {:.4}", flip.mean);
    assert!((l_rt / l_ref - 1.0).abs() < 0.02, "mean luminance {l_rt} against the path tracer's {l_ref}: biased");
}

#[test]
fn the_filters_variance_falls_with_history() {
    let Some(gpu) = gpu() else { return };
    let scene = load_scene("cornell-diffuse.ron");
    let compiled = compile(&scene, &realtime(), &keep(&["filt_0", "rt_illum"]));
    let mut s = session(gpu, scene, &compiled, SIZE, 1);
    let mut means = Vec::new();
    for frame in 1..=64u32 {
        if frame == 16 || frame == 64 {
            // (The filter's passes thin their still frames: these two run.)
            s.show_next_in_full();
        }
        s.frame(0.0);
        if frame == 16 || frame == 64 {
            let v = read(&s, "filt_0");
            let n = read(&s, "rt_illum");
            means.push(v.data.iter().map(|p| p[3] as f64).sum::<f64>() / v.data.len() as f64);
            // Every pixel's history holds every frame (a still camera).
            assert!(n.data.iter().all(|p| p[3] == frame as f32), "history lengths after {frame} still frames: {:?}", n.data.iter().map(|p| p[3]).take(8).collect::<Vec<_>>());
        }
    }
    eprintln!("mean variance of the pixel means: {:.3e} at 16 frames, {:.3e} at 64", means[0], means[1]);
    // The variance of a mean of n samples falls as 1/n: 4x fewer frames,
    // about 4x the variance (2x slack for the estimate's own noise).
    assert!(means[1] < means[0] / 2.0, "variance did not fall with history: {means:?}");
}

/// The issue's light-jump test, at 64x64.
const JUMP_SIZE: (u32, u32) = (64, 64);

#[test]
fn a_light_jump_drops_stale_history_where_light_changed_and_leaves_no_ghost() {
    let Some(gpu) = gpu() else { return };
    let scene = scene_from(JUMPING_LIGHT);
    let compiled = compile(&scene, &realtime(), &keep(&["rt_illum"]));
    // Converged images before and after the jump, and a fresh start at the
    // new position: the error a graph without stale history would have.
    let pathtrace = repo().join("passes/pathtrace.ron");
    let before = still_at(gpu, scene_from(JUMPING_LIGHT), &pathtrace, 256, 0.0, JUMP_SIZE);
    let after = still_at(gpu, scene_from(JUMPING_LIGHT), &pathtrace, 256, 1.0, JUMP_SIZE);
    const SETTLE: u32 = 8;
    let fresh = still_at(gpu, scene_from(JUMPING_LIGHT), &realtime(), SETTLE, 1.0, JUMP_SIZE);

    let mut s = session(gpu, scene, &compiled, JUMP_SIZE, 1);
    for _ in 0..32 {
        s.frame(0.0);
    }
    for _ in 0..SETTLE {
        s.frame(1.0);
    }
    let jumped = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    let lengths = read(&s, "rt_illum");
    let (f_jumped, _) = metrics::flip(&after, &jumped);
    let (f_fresh, _) = metrics::flip(&after, &fresh);
    eprintln!("{SETTLE} frames after the jump: FLIP {:.4}; a fresh start's {SETTLE} frames: {:.4}", f_jumped.mean, f_fresh.mean);

    // Where the light changed by more than half, history started over
    // after the jump; where it changed by under 10%, it was kept (capped
    // by the gradients and at `moving_history` in the jump's frame).
    let (mut changed, mut changed_reset, mut same, mut same_kept) = (0, 0, 0, 0);
    for ((b, a), n) in before.data.iter().zip(&after.data).zip(&lengths.data) {
        let (lb, la) = (luminance(b), luminance(a));
        if lb.max(la) < 0.02 {
            continue;
        }
        let change = (la - lb).abs() / lb.max(la);
        if change > 0.5 {
            changed += 1;
            changed_reset += usize::from(n[3] <= SETTLE as f32);
        } else if change < 0.1 {
            same += 1;
            same_kept += usize::from(n[3] > SETTLE as f32);
        }
    }
    eprintln!("changed by > 50%: {changed_reset} of {changed} started over; by < 10%: {same_kept} of {same} kept history");
    assert!(f_jumped.mean <= 1.2 * f_fresh.mean, "a ghost: {SETTLE} frames after the jump FLIP {:.4}, a fresh start {:.4}", f_jumped.mean, f_fresh.mean);
    assert!(changed > 50 && same > 50, "the scene should have both: {changed} changed, {same} unchanged pixels");
    assert!(changed_reset as f64 >= 0.8 * changed as f64, "stale history kept: {changed_reset} of {changed} changed pixels started over");
    assert!(same_kept as f64 >= 0.8 * same as f64, "good history dropped: {same_kept} of {same} unchanged pixels kept it");
}

/// The first hit's direct light stays out of the indirect light's filter
/// (SPLIT_DIRECT in passes/realtime.ron): with direct light alone (paths
/// that end at their first hit, `max_depth` 1) and the two steps that
/// filter the direct light told to keep every pixel (`sigma_l` 0), the
/// first frame is the path pass's own sample, its shadow edges and noise
/// untouched, with one light and with three. With the whole sample
/// filtered (SPLIT_DIRECT 0), a pixel moved by 7.9 times its light. And
/// once the image has stood still for 24 frames the direct light's own
/// filter has faded out (`DIRECT_UNTIL_FRAMES`): the 25th frame is the
/// samples' mean with the filter as it ships (0.4% at most; with the fade
/// taken out, a pixel at a shadow's edge moved by 1.29 times its light).
#[test]
fn direct_light_alone_passes_the_filter_untouched() {
    let Some(gpu) = gpu() else { return };
    for name in ["cornell.ron", "moving-lights.ron"] {
        for (frames, filtered) in [(1, false), (25, true)] {
            let scene = load_scene(name);
            // (The history's radiance mean: after one frame, the sample.)
            let compiled = compile(&scene, &realtime(), &keep(&["rt_color"]));
            let mut s = session(gpu, scene, &compiled, SIZE, 1);
            direct_only(&mut s, filtered);
            run_frames(&mut s, frames, 0.0);
            let out = s.read_output().unwrap_or_else(|e| panic!("{e}"));
            let raw = read(&s, "rt_color");
            // The sample's 8-bit mantissas (shared/realtime_common.wgsl,
            // pack_sample) and the direct light's 9-bit ones (RGB9E5)
            // differ by up to a step of the sample's largest channel, and
            // the difference is what the filter smooths (up to about three
            // steps, 1.2%, in a pixel): measured against that channel.
            let largest = |r: &[f32; 4]| f64::from(r[0].max(r[1]).max(r[2]));
            let worst = out.data.iter().zip(&raw.data).map(|(o, r)| (luminance(o) - luminance(r)).abs() / largest(r).max(1e-2)).fold(0.0, f64::max);
            let lit = raw.data.iter().filter(|p| luminance(p) > 1e-2).count();
            eprintln!("{name}, {frames} frame(s): {lit} lit pixels; the largest change the filter made {worst:.2e} of a pixel's largest channel");
            assert!(lit > SIZE.0 as usize * SIZE.1 as usize / 4, "{name}: too little is lit to test anything");
            assert!(worst < 0.03, "{name}, {frames} frame(s): the filter changed a pixel by {worst:.3} of its direct light's largest channel");
        }
    }
}

/// The first hit's direct light kept apart (SPLIT_DIRECT) is all of it:
/// what a light its bounce ray meets brings, as multiple importance
/// sampling weighs it against the light samples, counts there too. Kept
/// with the rest, it was a narrow peak on cornell's ceiling above the
/// light, which the wide filter steps flattened: there the direct light
/// kept apart was 0.92-0.94x direct.ron's. Over 256 still frames its mean
/// times the albedo is direct.ron's within 4% where the lit surfaces are
/// brightest.
#[test]
fn the_direct_light_kept_apart_is_all_of_it() {
    let Some(gpu) = gpu() else { return };
    const SIZE: (u32, u32) = (32, 32);
    const FRAMES: u32 = 256;
    let compiled = compile(&load_scene("cornell.ron"), &realtime(), &keep(&["direct_in", "rt_albedo"]));
    let mut s = session(gpu, load_scene("cornell.ron"), &compiled, SIZE, 1);
    run_frames(&mut s, FRAMES, 0.0);
    let (kept, albedo) = (read(&s, "direct_in"), read(&s, "rt_albedo"));
    let truth = render(gpu, load_scene("cornell.ron"), &repo().join("passes/direct.ron"), SIZE, FRAMES, None);
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    let lit = |x: usize, y: usize| albedo.data[y * w + x][..3].iter().any(|&a| a > 0.0);
    // Pixels whose 3x3 neighbours are all lit surfaces (not the light's
    // outline, which the two graphs' jitters cover differently).
    let mut inner: Vec<usize> = (1..h - 1)
        .flat_map(|y| (1..w - 1).map(move |x| (x, y)))
        .filter(|&(x, y)| (0..9).all(|k| lit(x + k % 3 - 1, y + k / 3 - 1)))
        .map(|(x, y)| y * w + x)
        .collect();
    inner.sort_by(|&a, &b| luminance(&truth.data[b]).total_cmp(&luminance(&truth.data[a])));
    let brightest = &inner[..8];
    let product = |i: usize| std::array::from_fn::<f32, 4, _>(|c| if c < 3 { kept.data[i][c] * albedo.data[i][c] } else { 1.0 });
    let ratio = brightest.iter().map(|&i| luminance(&product(i))).sum::<f64>() / brightest.iter().map(|&i| luminance(&truth.data[i])).sum::<f64>();
    eprintln!("the direct light kept apart, times the albedo, over direct.ron's where brightest: {ratio:.4}");
    assert!((ratio - 1.0).abs() < 0.04, "the direct light kept apart is {ratio:.4}x direct.ron's where the lit surfaces are brightest");
}

/// Paths end at their first hit; `filtered` false makes the steps that
/// filter the direct light keep every pixel as it is (the indirect light,
/// which they filter too, is then nothing).
fn direct_only(s: &mut Session, filtered: bool) {
    use glint::graph::desc::ParamValue;
    s.set_param("path", "max_depth", ParamValue::Int(1)).unwrap_or_else(|e| panic!("{e}"));
    if !filtered {
        for pass in ["atrous_1", "atrous_2"] {
            s.set_param(pass, "sigma_l", ParamValue::Float(0.0)).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

/// The direct light's own filter (realtime.ron's first two à-trous
/// steps, steered by its variance) brings the first frame of direct
/// light alone closer to its converged mean than leaving it unfiltered
/// where one light sample a pixel is mostly noise: thesis-env3's one light
/// is a large sphere seen through windows, its patches are penumbra
/// almost everywhere (at 48x48 relMSE 0.085 filtered against 0.223).
#[test]
fn the_direct_lights_filter_lowers_its_first_frames_error_in_penumbrae() {
    let Some(gpu) = gpu() else { return };
    let name = "thesis-env3.ron";
    let compiled = compile(&load_scene(name), &realtime(), &CompileOptions::default());
    let run = |filtered: bool, frames: u32| {
        let mut s = session(gpu, load_scene(name), &compiled, SIZE, 1);
        direct_only(&mut s, filtered);
        run_frames(&mut s, frames, 0.0);
        s.read_output().unwrap_or_else(|e| panic!("{e}"))
    };
    let reference = run(false, 256);
    let err = |img: &ImageF32| metrics::rel_mse(&reference, img);
    let (filtered, raw) = (err(&run(true, 1)), err(&run(false, 1)));
    eprintln!("{name}, direct light alone, first frame against 256 frames: relMSE {filtered:.5} filtered, {raw:.5} unfiltered");
    assert!(filtered < 0.5 * raw, "the direct light's filter took its first frame's relMSE from {raw:.5} only to {filtered:.5}");
}

/// A red coat (specular share 0.5 over a diffuse base) filling most of
/// the view, lit by a sphere light it reflects, inside a grey box.
const COAT_SCENE: &str = r#"Scene(
    camera: Camera(position: (0.0, 1.0, 2.2), target: (0.0, 1.0, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 50.0),
    background: (0.0, 0.0, 0.0),
    materials: {
        "grey": Material(albedo: (0.6, 0.6, 0.6)),
        "coat": Material(albedo: (0.7, 0.12, 0.08), specular: 0.5),
    },
    objects: [
        Quad(vertices: [(-2.0, 0.0, -2.0), (-2.0, 0.0, 3.0), (2.0, 0.0, 3.0), (2.0, 0.0, -2.0)], material: "grey"),
        Quad(vertices: [(-2.0, 0.0, -2.0), (2.0, 0.0, -2.0), (2.0, 2.5, -2.0), (-2.0, 2.5, -2.0)], material: "grey"),
        Quad(vertices: [(-2.0, 2.5, -2.0), (2.0, 2.5, -2.0), (2.0, 2.5, 3.0), (-2.0, 2.5, 3.0)], material: "grey"),
        Sphere(center: (0.0, 1.0, 0.0), radius: 0.8, material: "coat"),
    ],
    lights: [
        SphereLight(center: (0.9, 2.0, 1.4), radius: 0.2, radiance: (20.0, 19.0, 17.0)),
    ],
)"#;

#[test]
fn a_coats_two_lobes_taken_together_keep_the_mean_and_lower_the_noise() {
    // SPLIT_LOBES (shared/path.wgsl): a coat's recorded hit takes both its
    // lobes, each weighted by its share, where the path tracer picks one.
    let Some(gpu) = gpu() else { return };
    let reference = still(gpu, scene_from(COAT_SCENE), &repo().join("passes/pathtrace.ron"), 256, 0.0);
    let split = still(gpu, scene_from(COAT_SCENE), &realtime(), 256, 0.0);
    let (l_ref, l_rt) = (mean_luminance(&reference), mean_luminance(&split));
    eprintln!("coat, 256 frames each: mean luminance {l_rt:.5} against the path tracer's {l_ref:.5}");
    assert!((l_rt / l_ref - 1.0).abs() < 0.02, "mean luminance {l_rt} against the path tracer's {l_ref}: biased");
    // One frame's samples, with the lobes split and without, against the
    // converged image (relMSE): the split's is far smaller (no coin
    // between a light's reflection and the diffuse base).
    let spread = |split: bool| {
        let text = std::fs::read_to_string(realtime()).unwrap_or_else(|e| panic!("{e}"));
        let graph = scratch("coat-lobes").join(format!("realtime-{split}.ron"));
        std::fs::write(&graph, text.replace("SPLIT_LOBES: 1", if split { "SPLIT_LOBES: 1" } else { "SPLIT_LOBES: 0" }))
            .unwrap_or_else(|e| panic!("{e}"));
        let scene = scene_from(COAT_SCENE);
        let compiled = compile(&scene, &graph, &keep(&["rt_color"]));
        let mut s = session(gpu, scene, &compiled, SIZE, 1);
        s.frame(0.0);
        let img = read(&s, "rt_color");
        let error = img.data.iter().zip(&reference.data).map(|(p, r)| {
            let (l, lr) = (luminance(p), luminance(r));
            (l - lr) * (l - lr) / (lr * lr + 1e-2)
        });
        error.sum::<f64>() / img.data.len() as f64
    };
    let (one, both) = (spread(false), spread(true));
    eprintln!("one frame's samples, relMSE: one lobe at random {one:.3}, both lobes {both:.3}");
    assert!(both < 0.8 * one, "both lobes' samples: relMSE {both:.3}, one lobe's {one:.3}");
}

/// The à-trous taps in opposite pairs (shaders/realtime/atrous.wgsl,
/// `PAIRS`): a tap also counts when its and the opposite tap's mean is
/// close to the pixel's colour, where a smooth gradient's two sides
/// cancel, so the wider steps filter the box's shaded walls and floor
/// where each tap's own colour test refuses them. The fourth frame's
/// error against the path tracer's converged image falls.
#[test]
fn taps_in_pairs_filter_smooth_gradients() {
    let Some(gpu) = gpu() else { return };
    // The gradients are smooth over a step's taps at a few hundred pixels,
    // not at 48 (where the box's shading curves across a step).
    let size = (PAIRS_SIZE, PAIRS_SIZE);
    let render = |graph: &std::path::Path, frames: u32| {
        let scene = load_scene("cornell.ron");
        let compiled = compile(&scene, graph, &CompileOptions::default());
        let mut s = session(gpu, scene, &compiled, size, 1);
        run_frames(&mut s, frames, 0.0);
        s.read_output().unwrap_or_else(|e| panic!("{e}"))
    };
    let reference = render(&repo().join("passes/pathtrace.ron"), 512);
    let text = std::fs::read_to_string(realtime()).unwrap_or_else(|e| panic!("{e}"));
    let error = |pairs: bool, frames: u32| {
        let graph = scratch("atrous-pairs").join(format!("realtime-{pairs}.ron"));
        let edited = if pairs { text.clone() } else { text.replace("constants: { STEP:", "constants: { PAIRS: 0, STEP:") };
        std::fs::write(&graph, edited).unwrap_or_else(|e| panic!("{e}"));
        let img = render(&graph, frames);
        (metrics::rel_mse(&reference, &img), metrics::flip(&reference, &img).0.mean)
    };
    // (At 192x192: relMSE 0.00448 against 0.00467, FLIP 0.0652 against
    // 0.0663; the same driver gives the same images.)
    let (with, without) = (error(true, 4), error(false, 4));
    eprintln!("cornell, frame 4 against 512 path-traced frames: relMSE {:.5} / FLIP {:.5} with pairs, {:.5} / {:.5} without", with.0, with.1, without.0, without.1);
    assert!(with.0 < 0.98 * without.0 && with.1 < without.1, "frame 4 with pairs: relMSE {:.5}, FLIP {:.5}; without: {:.5}, {:.5}", with.0, with.1, without.0, without.1);
}

/// A dark mirror sphere standing on a floor under a white sky: the floor
/// seen in the mirror is about half as bright as the floor beside it.
const MIRROR_ON_FLOOR: &str = r#"Scene(
    camera: Camera(position: (0.0, 0.9, 2.6), target: (0.0, 0.35, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 40.0),
    background: (1.0, 1.0, 1.0),
    materials: {
        "floor": Material(albedo: (0.6, 0.6, 0.6)),
        "mirror": Material(albedo: (0.3, 0.3, 0.3), specular: 1.0),
    },
    objects: [
        Quad(vertices: [(-20.0, 0.0, -20.0), (-20.0, 0.0, 20.0), (20.0, 0.0, 20.0), (20.0, 0.0, -20.0)], material: "floor"),
        Sphere(center: (0.0, 0.5, 0.0), radius: 0.5, material: "mirror"),
    ],
    lights: [],
)"#;

#[test]
fn a_mirrors_outline_keeps_its_contrast_in_the_first_frame() {
    // At the mirror sphere's foot it shows the floor, in the plane of the
    // floor beside it, darkened by its colour. Unfolded into the camera's
    // view (UNFOLD_MIRRORS) that floor faces the camera behind the sphere,
    // and divided by the mirror's colour with its own albedo it is lit as
    // the floor is: the filters neither blend the two floors nor smear the
    // mirror's colour into the floor beside it (both did until session 36:
    // the outline's contrast measured 0.964 against the path tracer's 0.451).
    let Some(gpu) = gpu() else { return };
    let size = (64, 64);
    let render = |graph: &std::path::Path, frames: u32, seed: u32, kept: &[&str]| {
        let scene = scene_from(MIRROR_ON_FLOOR);
        let compiled = compile(&scene, graph, &keep(kept));
        let mut s = session(gpu, scene, &compiled, size, seed);
        run_frames(&mut s, frames, 0.0);
        let out = s.read_output().unwrap_or_else(|e| panic!("{e}"));
        (out, kept.first().map(|r| read(&s, r)))
    };
    let (reference, _) = render(&repo().join("passes/pathtrace.ron"), 256, 1, &[]);
    let text = std::fs::read_to_string(realtime()).unwrap_or_else(|e| panic!("{e}"));
    // The graph's constants, which the path pass takes, come first.
    let constants = "constants: { THROUGH_MIRRORS: 1,";
    assert!(text.contains(constants), "realtime.ron's constants changed");
    let folded = scratch("mirrors-unfolded").join("realtime-folded.ron");
    std::fs::write(&folded, text.replacen(constants, "constants: { UNFOLD_MIRRORS: 0, THROUGH_MIRRORS: 1,", 1)).unwrap_or_else(|e| panic!("{e}"));
    // What the mirror shows: the pixels whose guide the unfolding changes
    // (0 no surface, guide's NO_SURFACE; 1 seen directly; 2 in the mirror).
    let guide = |graph: &std::path::Path| render(graph, 1, 1, &["guide"]).1.unwrap_or_else(|| panic!("guide not read"));
    let (unfolded, own) = (guide(&realtime()), guide(&folded));
    let kind = |i: usize| match (unfolded.data[i], own.data[i]) {
        (u, _) if u[3] >= 4.0e9 => 0,
        (u, o) if u == o => 1,
        _ => 2,
    };
    // The pixels on either side of where the mirror's floor meets the floor:
    // both hits face up (the y of guide's packed normal, bits 11-21, with
    // the hits' own normals).
    let up = |i: usize| ((own.data[i][3] as u64 >> 11) & 0x7ff) as f64 * 2.0 / 2047.0 - 1.0 > 0.95;
    let w = size.0 as usize;
    let n = unfolded.data.len();
    let meets = |i: usize, j: usize| j < n && up(i) && up(j) && kind(i) != 0 && kind(j) != 0 && kind(i) != kind(j);
    let mut sides = [Vec::new(), Vec::new()];
    for i in 0..n {
        if (i % w + 1 < w && meets(i, i + 1)) || meets(i, i + w) || (i % w > 0 && meets(i, i - 1)) || (i >= w && meets(i, i - w)) {
            sides[kind(i) - 1].push(i);
        }
    }
    // The contrast across it: the mean luminance on the mirror's side over
    // the floor's (a blend pulls it toward 1), in the first frame over seeds,
    // unfolded and not.
    let mean = |img: &glint::gpu::readback::ImageF32, pixels: &Vec<usize>| pixels.iter().map(|&i| luminance(&img.data[i])).sum::<f64>() / pixels.len() as f64;
    let contrast = |img: &glint::gpu::readback::ImageF32| mean(img, &sides[1]) / mean(img, &sides[0]);
    let seeds = 4;
    let mut first = [0.0f64; 2];
    for seed in 1..=seeds {
        for (k, graph) in [realtime(), folded.clone()].iter().enumerate() {
            first[k] += contrast(&render(graph, 1, seed, &[]).0) / seeds as f64;
        }
    }
    let truth = contrast(&reference);
    eprintln!(
        "{} + {} pixels on the two sides of the mirror sphere's outline; their contrast (mirror / floor): {truth:.3} in the path tracer's image, {:.3} in the first frame unfolded, {:.3} not",
        sides[0].len(),
        sides[1].len(),
        first[0],
        first[1]
    );
    assert!(sides.iter().all(|s| s.len() > 10), "{} and {} pixels where the mirror meets the floor", sides[0].len(), sides[1].len());
    assert!((first[0] / truth - 1.0).abs() < 0.15, "contrast {:.3} in the first frame against the path tracer's {truth:.3}", first[0]);
}

/// The filter's passes thin their still frames (`ThinWhenStill(after: 8,
/// every: 4)` in passes/realtime.ron): in the frames they skip the image
/// stays what their last run made, and a frame they run in (or one shown
/// in full) is the image the graph makes without thinning, bit for bit,
/// though in the frames they skip the path pass and `temporal` store only
/// what the history takes (THIN_STORES under the THINNED frame kind).
#[test]
fn thinned_still_frames_keep_the_last_image_and_change_no_filtered_one() {
    let Some(gpu) = gpu() else { return };
    const THIN: &str = "run: ThinWhenStill(after: 8, every: 4), ";
    let text = std::fs::read_to_string(realtime()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(text.matches(THIN).count(), 6, "realtime.ron's filter passes no longer thin as this test expects");
    let unthinned = scratch("thin-frames").join("realtime.ron");
    std::fs::write(&unthinned, text.replace(THIN, "")).unwrap_or_else(|e| panic!("{e}"));
    let size = (32, 32);
    let out = |s: &Session| s.read_output().unwrap_or_else(|e| panic!("{e}"));
    let start = |graph: &std::path::Path| {
        let scene = load_scene("cornell.ron");
        let compiled = compile(&scene, graph, &CompileOptions::default());
        session(gpu, scene, &compiled, size, 1)
    };
    let (mut thin, mut full) = (start(&realtime()), start(&unthinned));
    let mut shown = Vec::new();
    for frame in 1..=11 {
        thin.frame(0.0);
        full.frame(0.0);
        shown.push((out(&thin), out(&full)));
        let (t, f) = &shown[frame - 1];
        // Still frames 0..=8 run the filter (8: one in 4), 9 and 10 not.
        if frame <= 9 {
            assert!(t.data == f.data, "frame {frame}: the thinned graph's image differs from the unthinned one's");
        } else {
            assert!(t.data == shown[8].0.data, "frame {frame}: the image changed in a frame the filter skips");
            assert!(t.data != f.data, "frame {frame}: the unthinned graph's image should have moved on");
        }
    }
    thin.show_next_in_full();
    thin.frame(0.0);
    full.frame(0.0);
    assert!(out(&thin).data == out(&full).data, "a frame shown in full differs from the unthinned graph's");
    // A frame loop that stops at 11 samples (the viewer's --stop-at) shows
    // its last frame in full: the unthinned graph's 11th.
    use glint::session::frame_loop::{Clock, FrameLoop};
    let mut stopping = start(&realtime());
    let mut frames = FrameLoop::new(0.0, Clock::Fixed { dt: 0.0 }, stopping.scene.scene.camera);
    frames.sample_target = Some(11);
    for _ in 0..14 {
        frames.step(&mut stopping);
    }
    assert_eq!(stopping.accumulated(), 11);
    assert!(out(&stopping).data == shown[10].1.data, "the frame loop's last frame before its sample target was not shown in full");
}

/// A wide à-trous step stops without a jump in the image: over the second
/// half of its `until_frames` it fades into its input, so the frame where
/// it stops changes the image about as much as the frames before it (a
/// sudden stop changed it by the step's whole share: the noise it had
/// taken out came back at once).
#[test]
fn a_wide_step_fades_out_before_it_stops() {
    let Some(gpu) = gpu() else { return };
    // realtime.ron's step 4 stops at 128 still frames (the stop that cost
    // most when it was sudden, docs/realtime.md).
    const STOP: u32 = 128;
    let text = std::fs::read_to_string(realtime()).unwrap_or_else(|e| panic!("{e}"));
    assert!(text.contains("until_frames: 128 },\n             constants: { STEP: 4 }"), "realtime.ron's step 4 no longer stops at {STOP} frames");
    let scene = load_scene("cornell.ron");
    let compiled = compile(&scene, &realtime(), &CompileOptions::default());
    let mut s = session(gpu, scene, &compiled, (64, 64), 1);
    let mut shown = Vec::new();
    for still in 0..=STOP {
        if still + 3 >= STOP {
            s.show_next_in_full();
        }
        s.frame(0.0);
        if still + 3 >= STOP {
            shown.push(s.read_output().unwrap_or_else(|e| panic!("{e}")));
        }
    }
    let change = |a: &ImageF32, b: &ImageF32| a.data.iter().zip(&b.data).map(|(p, q)| (luminance(p) - luminance(q)).abs()).sum::<f64>() / a.data.len() as f64;
    let before = change(&shown[0], &shown[1]).max(change(&shown[1], &shown[2]));
    let at_stop = change(&shown[2], &shown[3]);
    eprintln!("mean luminance change a frame: {before:.3e} before the stop, {at_stop:.3e} where it stops");
    assert!(at_stop < 1.5 * before, "the image jumped where step 4 stopped: {at_stop:.3e} against {before:.3e} a frame before");
}
