//! The GPU path against analytic answers: a furnace for the path tracer,
//! sphere-light and point-light irradiance on a plane for the direct
//! lighting pass and the path tracer.

mod common;

use common::*;
use glam::Vec3;

/// A closed sphere around the camera, albedo a and emission Le everywhere:
/// every pixel converges to Le / (1 - a).
#[test]
fn furnace_path_tracer() {
    let Some(gpu) = gpu() else { return };
    let scene = scene_from(
        r#"Scene(
            camera: Camera(position: (0.0, 0.0, 0.0), target: (0.0, 0.0, -1.0), vfov_deg: 60.0),
            materials: { "grey": Material(albedo: (0.5, 0.5, 0.5), emission: (1.0, 1.0, 1.0)) },
            objects: [ Sphere(center: (0.0, 0.0, 0.0), radius: 5.0, material: "grey") ],
        )"#,
    );
    let img = render(gpu, scene, &repo().join("passes/pathtrace.ron"), (32, 32), 128, None);
    let mean = mean_rgb(&img);
    assert!((mean - 2.0).abs() < 0.02, "furnace mean {mean}, expected 2.0");
    for p in &img.data {
        assert!((f64::from(p[0]) - 2.0).abs() < 0.5, "pixel {p:?} far from 2.0");
    }
}

const PLANE_SCENE: &str = r#"Scene(
    camera: Camera(position: (0.0, 2.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 50.0),
    materials: { "grey": Material(albedo: (0.5, 0.5, 0.5)) },
    objects: [ Quad(vertices: [(-20.0, 0.0, -20.0), (-20.0, 0.0, 20.0), (20.0, 0.0, 20.0), (20.0, 0.0, -20.0)], material: "grey") ],
    lights: [ LIGHT ],
)"#;

/// A graph without jitter so each pixel sees one fixed surface point.
fn fixed_point_graph(samples: u32) -> std::path::PathBuf {
    let dir = scratch("fixed-graph");
    // A file per call: tests run in parallel.
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = dir.join(format!("direct-fixed-{samples}-{n}.ron"));
    let text = std::fs::read_to_string(repo().join("passes/direct.ron"))
        .unwrap()
        .replace("params: { jitter: 1 }", "params: { jitter: 0 }")
        .replace("params: { samples: 1,", &format!("params: {{ samples: {samples},"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Checks radiance on the plane y = 0 against `expected(p)` where the
/// G-buffer says the pixel sees the plane.
fn check_plane(light: &str, graph: &std::path::Path, frames: u32, expected: impl Fn(Vec3) -> f32, tol_pixel: f32, tol_mean: f32) {
    let Some(gpu) = gpu() else { return };
    let text = PLANE_SCENE.replace("LIGHT", light);
    let size = (48, 48);
    let pos = render(gpu, scene_from(&text), &fixed_point_graph(1), size, 1, Some("gbuf_pos"));
    let img = render(gpu, scene_from(&text), graph, size, frames, None);
    let (mut sum_err, mut n, mut worst) = (0.0f64, 0usize, 0.0f32);
    let on_plane = |x: i64, y: i64| {
        let (w, h) = (i64::from(size.0), i64::from(size.1));
        let p = pos.data[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize];
        p[3] > 0.0 && p[1].abs() < 1e-3
    };
    for (i, (p, c)) in pos.data.iter().zip(&img.data).enumerate() {
        let (x, y) = ((i % size.0 as usize) as i64, (i / size.0 as usize) as i64);
        // Only pixels wholly on the plane (jittered samples stay there),
        // within 2 units of the light's foot (well above its horizon).
        let whole = (-1..=1).all(|dy| (-1..=1).all(|dx| on_plane(x + dx, y + dy)));
        if !whole || Vec3::new(p[0], 0.0, p[2]).length() > 2.0 {
            continue;
        }
        let want = expected(Vec3::new(p[0], p[1], p[2]));
        let rel = (c[0] - want).abs() / want;
        worst = worst.max(rel);
        sum_err += f64::from(c[0] - want) / f64::from(want);
        n += 1;
    }
    assert!(n > 300, "too few plane pixels: {n}");
    let mean = (sum_err / n as f64).abs() as f32;
    assert!(worst < tol_pixel, "worst pixel relative error {worst}");
    assert!(mean < tol_mean, "mean relative error {mean}");
}

const SPHERE_LIGHT: &str = "SphereLight(center: (0.0, 1.0, 0.0), radius: 0.25, radiance: (4.0, 4.0, 4.0))";

/// Radiance of a Lambertian plane (albedo 0.5) lit by a sphere light fully
/// above its horizon: L_o = rho L r^2 cos(theta) / d^2 (exact for a sphere).
fn sphere_light_answer(p: Vec3) -> f32 {
    let c = Vec3::new(0.0, 1.0, 0.0);
    let d = c - p;
    let cos = d.y / d.length();
    0.5 * 4.0 * 0.25 * 0.25 * cos / d.length_squared()
}

#[test]
fn area_light_irradiance_on_a_plane() {
    check_plane(SPHERE_LIGHT, &fixed_point_graph(16), 16, sphere_light_answer, 0.03, 0.005);
}

#[test]
fn point_light_irradiance_on_a_plane() {
    let light = "PointLight(position: (0.0, 1.0, 0.0), intensity: (2.0, 2.0, 2.0))";
    let answer = |p: Vec3| {
        let d = Vec3::new(0.0, 1.0, 0.0) - p;
        0.5 / std::f32::consts::PI * 2.0 * (d.y / d.length()) / d.length_squared()
    };
    check_plane(light, &fixed_point_graph(1), 1, answer, 1e-3, 1e-4);
}

/// The plane sees nothing but the light, so the path tracer (NEE + MIS)
/// must converge to the same analytic answer. Pixel jitter blurs edges only.
#[test]
fn path_tracer_matches_area_light_answer() {
    check_plane(SPHERE_LIGHT, &repo().join("passes/pathtrace.ron"), 256, sphere_light_answer, 0.25, 0.01);
}
