//! The real-time graph's denoiser (passes/realtime.ron) on what it must
//! not change: a constant image stays constant, an edge between two
//! albedos stays sharp, and a disocclusion starts its pixels' history over
//! while the rest keeps its history.
//!
//! The first two light a plane by a uniform background alone: every path
//! sample of it is exactly albedo x background (the plane's one bounce
//! sees only the background), so whatever the denoiser changes shows. The
//! path pass hands the denoiser each sample rounded to an 8-bit mantissa
//! under its largest channel's exponent, down or up at random
//! (shared/realtime_common.wgsl, pack_sample): a filter that only
//! averages keeps every pixel within one such step of the light.

mod common;

use common::*;
use glint::graph::CompileOptions;

const SIZE: (u32, u32) = (48, 48);
const BACKGROUND: [f32; 3] = [0.8, 0.7, 0.6];

fn realtime() -> std::path::PathBuf {
    repo().join("passes/realtime.ron")
}

/// The plane z = 0 facing a camera at z = 3: albedo `left` for x < `edge`
/// and `right` beyond, lit by the background alone.
fn plane(left: [f32; 3], right: [f32; 3], edge: f32) -> glint::scene::Scene {
    let [r, g, b] = BACKGROUND;
    scene_from(&format!(
        r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 40.0),
    background: ({r}, {g}, {b}),
    materials: {{ "left": Material(albedo: ({}, {}, {})), "right": Material(albedo: ({}, {}, {})) }},
    objects: [
        Quad(vertices: [(-10.0, -10.0, 0.0), ({edge}, -10.0, 0.0), ({edge}, 10.0, 0.0), (-10.0, 10.0, 0.0)], material: "left"),
        Quad(vertices: [({edge}, -10.0, 0.0), (10.0, -10.0, 0.0), (10.0, 10.0, 0.0), ({edge}, 10.0, 0.0)], material: "right"),
    ],
    lights: [],
)"#,
        left[0], left[1], left[2], right[0], right[1], right[2]
    ))
}

fn lit(albedo: [f32; 3]) -> [f32; 3] {
    [albedo[0] * BACKGROUND[0], albedo[1] * BACKGROUND[1], albedo[2] * BACKGROUND[2]]
}

/// One step of a sample's rounding (pack_sample): the largest channel's
/// power of two over 128.
fn sample_step(c: [f32; 3]) -> f32 {
    2f32.powi(c[0].max(c[1]).max(c[2]).log2().floor() as i32 - 7)
}

/// Within one rounding step of `b` (what averaging rounded samples of it
/// gives), and 1e-4 for arithmetic.
fn close(a: [f32; 4], b: [f32; 3]) -> bool {
    (0..3).all(|c| (a[c] - b[c]).abs() <= sample_step(b) + 1e-4 * b[c].max(1e-3))
}

#[test]
fn a_constant_image_stays_constant() {
    let Some(gpu) = gpu() else { return };
    let white = [0.7, 0.7, 0.7];
    let scene = plane(white, white, 0.0);
    let compiled = compile(&scene, &realtime(), &CompileOptions::default());
    let mut s = session(gpu, scene, &compiled, SIZE, 1);
    for frame in 1..=16 {
        s.frame(0.0);
        if [1, 2, 8, 16].contains(&frame) {
            let out = s.read_output().unwrap_or_else(|e| panic!("{e}"));
            let off = out.data.iter().filter(|p| !close(**p, lit(white))).count();
            assert_eq!(off, 0, "frame {frame}: {off} pixels moved off the constant {:?}, e.g. {:?}", lit(white), out.data.iter().find(|p| !close(**p, lit(white))));
        }
    }
}

#[test]
fn an_edge_between_two_albedos_stays_sharp() {
    let Some(gpu) = gpu() else { return };
    let (white, red) = ([0.7, 0.7, 0.7], [0.63, 0.065, 0.05]);
    // The edge through the middle of column 24 (of 48).
    let scene = plane(white, red, 0.0);
    let compiled = compile(&scene, &realtime(), &CompileOptions::default());
    let mut s = session(gpu, scene, &compiled, SIZE, 1);
    for frame in 1..=8 {
        s.frame(0.0);
        if [1, 8].contains(&frame) {
            let out = s.read_output().unwrap_or_else(|e| panic!("{e}"));
            // Every column but the one the edge crosses shows its own
            // side's albedo: nothing blurs across. Not bit for bit: the
            // denoiser divides by the albedo rounded to 10 bits
            // (shared/realtime_common.wgsl, pack_first_hit), so the two
            // sides' demodulated light differs by that rounding (up to
            // 0.75% on red's dark channels), which the filter may mix;
            // a blur of red into white would move white's green by 90%.
            // And the samples' rounding (a step of the largest channel,
            // 8.6% of red's green), which averaging keeps within a step.
            let mut worst = [0.0f32; 2];
            for (i, p) in out.data.iter().enumerate() {
                let x = i as u32 % SIZE.0;
                let (side, want) = match x {
                    0..=22 => (0, lit(white)),
                    25.. => (1, lit(red)),
                    _ => continue,
                };
                for c in 0..3 {
                    worst[side] = worst[side].max(((p[c] - want[c]).abs() - sample_step(want)).max(0.0) / want[c]);
                }
            }
            eprintln!("frame {frame}: beyond a rounding step, the largest relative difference from the white side's light {:.2e}, from the red side's {:.2e}", worst[0], worst[1]);
            assert!(worst[0] <= 5e-3 && worst[1] <= 5e-3, "frame {frame}: a side moved off its own light by {worst:?}: the edge blurs");
        }
    }
}

/// A wall at z = -1 behind a sphere (centre (0, 0, 0.5), radius 0.4), lit
/// by a sphere light; the camera at (x, 0, 3) looking along -z.
const OCCLUDER: &str = r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 40.0),
    materials: { "white": Material(albedo: (0.7, 0.7, 0.7)), "red": Material(albedo: (0.63, 0.065, 0.05)) },
    objects: [
        Quad(vertices: [(-10.0, -10.0, -1.0), (10.0, -10.0, -1.0), (10.0, 10.0, -1.0), (-10.0, 10.0, -1.0)], material: "white"),
        Sphere(center: (0.0, 0.0, 0.5), radius: 0.4, material: "red"),
    ],
    lights: [ SphereLight(center: (0.0, 1.5, 2.0), radius: 0.2, radiance: (20.0, 20.0, 20.0)) ],
)"#;

/// Whether the segment from `from` to `to` passes within `r` of the
/// occluder's centre.
fn passes_sphere(from: [f64; 3], to: [f64; 3], r: f64) -> bool {
    let c = [0.0, 0.0, 0.5];
    let d: Vec<f64> = (0..3).map(|k| to[k] - from[k]).collect();
    let f: Vec<f64> = (0..3).map(|k| from[k] - c[k]).collect();
    let len2: f64 = d.iter().map(|v| v * v).sum();
    let t = (-(0..3).map(|k| f[k] * d[k]).sum::<f64>() / len2).clamp(0.0, 1.0);
    (0..3).map(|k| (f[k] + t * d[k]).powi(2)).sum::<f64>() < r * r
}

#[test]
fn a_disocclusion_starts_history_over_and_only_there() {
    let Some(gpu) = gpu() else { return };
    let scene = scene_from(OCCLUDER);
    let options = CompileOptions { keep: vec!["rt_illum".to_string()], ..Default::default() };
    let compiled = compile(&scene, &realtime(), &options);
    let mut s = session(gpu, scene, &compiled, SIZE, 1);
    for _ in 0..8 {
        s.frame(0.0);
    }
    // Strafe right: the wall left of the sphere comes into view.
    let shift = 1.0;
    s.scene.scene.camera.position.x += shift;
    s.scene.scene.camera.target.x += shift;
    s.frame(0.0);
    let n = s.read_resource("rt_illum").expect("kept").unwrap_or_else(|e| panic!("{e}"));
    let (w, h) = (SIZE.0 as f64, SIZE.1 as f64);
    let tan = (20.0f64).to_radians().tan();
    let (mut revealed, mut revealed_new, mut kept, mut kept_old) = (0, 0, 0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            // The pixel's ray through its centre, to the wall.
            let sx = (2.0 * (x as f64 + 0.5) / w - 1.0) * tan;
            let sy = (1.0 - 2.0 * (y as f64 + 0.5) / h) * tan;
            let eye = [shift, 0.0, 3.0];
            let wall = [eye[0] + 4.0 * sx, 4.0 * sy, -1.0];
            let before = [0.0, 0.0, 3.0];
            let count = n.data[(y * SIZE.0 + x) as usize][3];
            // Well clear of the sphere's outline in both frames (jittered
            // rays and bilinear taps reach about a pixel).
            if passes_sphere(eye, wall, 0.48) {
                continue;
            }
            if passes_sphere(before, wall, 0.32) {
                revealed += 1;
                revealed_new += (count == 1.0) as u32;
            } else if !passes_sphere(before, wall, 0.48) && (wall[0] / 4.0).abs() < tan * (1.0 - 2.0 / w) {
                // (In the first frames' view too, a pixel from its edge.)
                kept += 1;
                kept_old += (count >= 8.0) as u32;
            }
        }
    }
    eprintln!("revealed wall pixels starting over: {revealed_new} of {revealed}; wall pixels in view both frames keeping 8+ frames: {kept_old} of {kept}");
    assert!(revealed >= 20, "only {revealed} pixels revealed: the test's geometry is off");
    assert_eq!(revealed_new, revealed, "revealed pixels kept history they cannot have had");
    assert!(kept_old as f64 >= 0.98 * kept as f64, "only {kept_old} of {kept} pixels seen in both frames kept their history");
}
