//! Direct light by reservoir resampling (passes/realtime.ron's `restir_*`
//! passes, shaders/realtime/restir.wgsl) on the GPU path: with one
//! candidate and no reuse it is plain light sampling, and with reuse its
//! mean is direct.ron's, with one light and with 64.
//!
//! The real-time graph is run with paths of one bounce
//! (`max_depth: 1`: the path pass then adds only what the camera ray
//! sees emitted) and without the view through mirrors, so its sample
//! with the resampled direct light added (`gbuf_sample_di`) is emission
//! plus direct light, what direct.ron converges to. The samples are read
//! back from the history's running mean of them (`rt_color`): the n-th
//! frame's is n R_n - (n - 1) R_(n-1).

mod common;

use common::*;
use glint::graph::CompileOptions;
use glint::scene::Scene;

const SIZE: (u32, u32) = (32, 32);

/// passes/realtime.ron with one-bounce paths, no view through mirrors and
/// `edits` (text replacements) in a scratch folder.
fn direct_realtime(name: &str, edits: &[(&str, &str)]) -> std::path::PathBuf {
    let mut text = std::fs::read_to_string(repo().join("passes/realtime-restir.ron")).expect("read realtime-restir.ron");
    let base = [("max_depth: 64, rr_depth: 4 },\n             // The G", "max_depth: 1, rr_depth: 4 },\n             // The G"), ("THROUGH_MIRRORS: 1", "THROUGH_MIRRORS: 0")];
    for (from, to) in base.iter().chain(edits) {
        assert!(text.contains(from), "realtime-restir.ron no longer has `{from}`");
        text = text.replace(from, to);
    }
    let path = scratch(name).join("realtime.ron");
    std::fs::write(&path, text).expect("write the graph");
    path
}

/// `resource`'s luminance, pixel by pixel, in each of `frames` still
/// frames.
fn frames_of(gpu: &glint::gpu::Gpu, scene: Scene, graph: &std::path::Path, resource: &str, frames: u32) -> Vec<Vec<f64>> {
    let options = CompileOptions { keep: vec![resource.to_string()], ..Default::default() };
    let compiled = compile(&scene, graph, &options);
    let mut s = session(gpu, scene, &compiled, SIZE, 1);
    (0..frames)
        .map(|_| {
            s.frame(0.0);
            let img = s.read_resource(resource).expect("kept").unwrap_or_else(|e| panic!("{e}"));
            img.data.iter().map(luminance).collect()
        })
        .collect()
}

/// The real-time graph's samples, pixel by pixel (their luminance), in
/// each of `frames` still frames: from its running mean of them.
fn samples_of(gpu: &glint::gpu::Gpu, scene: Scene, graph: &std::path::Path, frames: u32) -> Vec<Vec<f64>> {
    let means = frames_of(gpu, scene, graph, "rt_color", frames);
    let mut before = vec![0.0; means[0].len()];
    means
        .iter()
        .enumerate()
        .map(|(k, mean)| {
            let n = k as f64 + 1.0;
            let sample = mean.iter().zip(&before).map(|(m, b)| n * m - (n - 1.0) * b).collect();
            before.clone_from(mean);
            sample
        })
        .collect()
}

/// Per pixel, the mean and variance over frames.
fn pixel_stats(frames: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let f = frames.len() as f64;
    let n = frames[0].len();
    let mean: Vec<f64> = (0..n).map(|i| frames.iter().map(|fr| fr[i]).sum::<f64>() / f).collect();
    let var = (0..n).map(|i| frames.iter().map(|fr| (fr[i] - mean[i]).powi(2)).sum::<f64>() / f).collect();
    (mean, var)
}

fn average(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// 64 small sphere lights of four colours in a grid under the ceiling of
/// a box holding a sphere and a block.
fn sixty_four_lights() -> Scene {
    let mut lights = String::new();
    for i in 0..8 {
        for j in 0..8 {
            let (x, z) = (-0.8 + 0.23 * i as f64, -0.8 + 0.23 * j as f64);
            let c = [(6.0, 1.0, 1.0), (1.0, 6.0, 1.0), (1.0, 1.0, 6.0), (4.0, 4.0, 4.0)][(i + j) % 4];
            lights += &format!("SphereLight(center: ({x:.3}, 0.85, {z:.3}), radius: 0.04, radiance: ({:.1}, {:.1}, {:.1})),\n", c.0, c.1, c.2);
        }
    }
    scene_from(&format!(
        r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.4), target: (0.0, 0.0, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 40.0),
    materials: {{ "white": Material(albedo: (0.725, 0.71, 0.68)), "red": Material(albedo: (0.63, 0.065, 0.05)) }},
    objects: [
        Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, 1.0), (1.0, -1.0, -1.0)], material: "white"),
        Quad(vertices: [(-1.0, 1.0, -1.0), (1.0, 1.0, -1.0), (1.0, 1.0, 1.0), (-1.0, 1.0, 1.0)], material: "white"),
        Quad(vertices: [(-1.0, -1.0, -1.0), (1.0, -1.0, -1.0), (1.0, 1.0, -1.0), (-1.0, 1.0, -1.0)], material: "white"),
        Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, 1.0, -1.0), (-1.0, 1.0, 1.0), (-1.0, -1.0, 1.0)], material: "red"),
        Sphere(center: (-0.4, -0.65, -0.3), radius: 0.35, material: "white"),
        Sphere(center: (0.45, -0.6, 0.25), radius: 0.4, material: "red"),
    ],
    lights: [
{lights}    ],
)"#
    ))
}

#[test]
fn one_candidate_without_reuse_is_plain_light_sampling() {
    let Some(gpu) = gpu() else { return };
    let plain = direct_realtime("restir-plain", &[("candidates: 4, temporal: 1", "candidates: 1, temporal: 0"), ("spatial: 3", "spatial: 0")]);
    let frames = 96;
    let (m_rs, v_rs) = pixel_stats(&samples_of(gpu, load_scene("cornell.ron"), &plain, frames));
    // direct.ron's light pass, one sample of the one light a frame.
    let (m_ls, v_ls) = pixel_stats(&frames_of(gpu, load_scene("cornell.ron"), &repo().join("passes/direct.ron"), "lit", frames));
    let (mr, ml) = (average(&m_rs), average(&m_ls));
    let (vr, vl) = (average(&v_rs), average(&v_ls));
    eprintln!("one candidate, no reuse: mean {mr:.5} against light sampling's {ml:.5}; mean pixel variance {vr:.4e} against {vl:.4e}");
    assert!((mr / ml - 1.0).abs() < 0.02, "mean {mr} against light sampling's {ml}");
    assert!((vr / vl - 1.0).abs() < 0.15, "pixel variance {vr:.4e} against light sampling's {vl:.4e}: not the same estimator");
}

/// Frames of each graph. Reused samples are correlated from frame to
/// frame (a sample lives on in the history and spreads to neighbours), so
/// a mean needs more frames than independent samples would: at 256
/// frames the spread of 32-frame batch means understated a block's error
/// by half.
const FRAMES: u32 = 512;

/// Batches the frames are split into for the error of a mean (of 64
/// frames each: longer than a sample lives on).
const BATCHES: usize = 8;

/// A region's mean over all frames and the standard error of that mean,
/// from the batch means of its per-frame means over the pixels `inside`.
fn region_mean(frames: &[Vec<f64>], inside: &[usize]) -> (f64, f64) {
    let per_frame: Vec<f64> = frames.iter().map(|f| inside.iter().map(|&i| f[i]).sum::<f64>() / inside.len() as f64).collect();
    let len = per_frame.len() / BATCHES;
    let batches: Vec<f64> = per_frame.chunks(len).take(BATCHES).map(|c| c.iter().sum::<f64>() / c.len() as f64).collect();
    let mean = batches.iter().sum::<f64>() / BATCHES as f64;
    let var = batches.iter().map(|b| (b - mean).powi(2)).sum::<f64>() / (BATCHES - 1) as f64;
    (mean, (var / BATCHES as f64).sqrt())
}

/// The real-time graph's direct light with reuse against direct.ron's
/// over `frames` still frames each, on the lit surfaces (pixels whose 3x3
/// neighbourhood shows no light: a light's own pixels differ by where the
/// two graphs' jittered rays fell), over the whole image and in 8x8
/// blocks: (the whole image's two means, the largest difference of a
/// region in standard errors, that region's two means).
fn reuse_against_direct(scene: impl Fn() -> Scene, name: &str, frames: u32) -> (f64, f64, f64, (f64, f64)) {
    let gpu = gpu().expect("checked by the caller");
    let graph = direct_realtime(name, &[]);
    let rs = samples_of(gpu, scene(), &graph, frames);
    let dr = frames_of(gpu, scene(), &repo().join("passes/direct.ron"), "lit", frames);
    let (m_dr, _) = pixel_stats(&dr);
    let (w, h) = (SIZE.0 as i32, SIZE.1 as i32);
    let lit = |x: i32, y: i32| {
        (-1..=1).all(|dy| (-1..=1).all(|dx| m_dr[((y + dy).clamp(0, h - 1) * w + (x + dx).clamp(0, w - 1)) as usize] < 4.0))
    };
    let region = |x0: i32, y0: i32, side: i32| -> Vec<usize> {
        (y0..y0 + side).flat_map(|y| (x0..x0 + side).map(move |x| (x, y))).filter(|&(x, y)| lit(x, y)).map(|(x, y)| (y * w + x) as usize).collect()
    };
    let mut regions = vec![region(0, 0, w)];
    for by in (0..h).step_by(8) {
        for bx in (0..w).step_by(8) {
            regions.push(region(bx, by, 8));
        }
    }
    let (mut whole, mut worst, mut worst_means) = ((0.0, 0.0), 0.0f64, (0.0, 0.0));
    for (k, inside) in regions.iter().enumerate().filter(|(_, r)| r.len() >= 16) {
        let ((a, ea), (b, eb)) = (region_mean(&rs, inside), region_mean(&dr, inside));
        if k == 0 {
            whole = (a, b);
        }
        // Half a percent of slack for what the two graphs do differently
        // without bias (the G-buffer's half-float normal, for one).
        let z = ((a - b).abs() - 0.005 * b).max(0.0) / (ea * ea + eb * eb).sqrt().max(1e-4 * b);
        if z > worst {
            (worst, worst_means) = (z, (a, b));
        }
    }
    (whole.0, whole.1, worst, worst_means)
}

#[test]
fn reuse_keeps_direct_lights_mean_with_one_light_and_with_64() {
    let Some(_) = gpu() else { return };
    for (label, scene) in [("1 light", (|| load_scene("cornell.ron")) as fn() -> Scene), ("64 lights", sixty_four_lights)] {
        let (rs, dr, z, (a, b)) = reuse_against_direct(scene, &format!("restir-{}", label.replace(' ', "-")), FRAMES);
        eprintln!("{label}, {FRAMES} frames: mean {rs:.5} with reuse against direct.ron's {dr:.5}; the largest difference of a region (the image or a 8x8 block), less 0.5%, {z:.2} standard errors ({a:.5} against {b:.5})");
        // Four standard errors: 17 regions, each a 1-in-16000 chance.
        assert!(z < 4.0, "{label}: a region's mean with reuse is {a} against direct.ron's {b}, {z:.1} standard errors apart: biased");
    }
}

/// A light that jumps (tests/realtime.rs's test, on realtime-restir.ron):
/// last frame's reservoirs weigh their samples by how the light was, so
/// where light changed the temporal gradients cut them as they cut the
/// denoiser's history, and 8 frames after the jump the image is as good
/// as a fresh start's (without the cut: FLIP 0.116 against 0.071).
#[test]
fn a_light_jump_leaves_no_ghost_in_the_reservoirs() {
    let Some(gpu) = gpu() else { return };
    let image = |graph: &str, frames_before: u32, frames_after: u32| {
        let scene = scene_from(JUMPING_LIGHT);
        let compiled = compile(&scene, &repo().join(graph), &CompileOptions::default());
        let mut s = session(gpu, scene, &compiled, (48, 48), 1);
        for _ in 0..frames_before {
            s.frame(0.0);
        }
        for _ in 0..frames_after {
            s.frame(1.0);
        }
        s.read_output().unwrap_or_else(|e| panic!("{e}"))
    };
    let after = image("passes/pathtrace.ron", 0, 256);
    let (jumped, _) = glint::metrics::flip(&after, &image("passes/realtime-restir.ron", 32, 8));
    let (fresh, _) = glint::metrics::flip(&after, &image("passes/realtime-restir.ron", 0, 8));
    eprintln!("8 frames after the jump: FLIP {:.4}; a fresh start's 8 frames: {:.4}", jumped.mean, fresh.mean);
    assert!(jumped.mean <= 1.2 * fresh.mean, "a ghost: 8 frames after the jump FLIP {:.4}, a fresh start {:.4}", jumped.mean, fresh.mean);
}
