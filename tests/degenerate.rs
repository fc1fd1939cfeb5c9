//! Degenerate scenes (issue 12, part 5) render in every shipped graph
//! without a non-finite pixel (checked by bits), and with the right answer
//! where one exists:
//! - a camera inside a closed diffuse sphere lit by a point light at its
//!   centre: every pixel sees the irradiance I / r^2, so the direct graphs
//!   give rho I / (pi r^2) and the path tracer, with every interreflection,
//!   rho I / (pi r^2 (1 - rho));
//! - a sphere light inside an opaque sphere lights nothing: the image is
//!   the one without that light;
//! - radiance 1e6 (the box's light times 1e5) is the box times 1e5;
//! - a camera on a wall sees what a camera a hair inside the room sees;
//! - a light touching the ceiling renders as one a hair below it;
//! - a light of radius 1e-20 (its cone underflows f32) adds nothing.
//!
//! A sphere light of radius 0 is a load error that points at PointLight
//! (tests in src/scene/tests.rs).

mod common;

use common::*;
use glint::gpu::readback::ImageF32;
use glint::metrics;

const GRAPHS: [&str; 4] = ["direct.ron", "hybrid-point.ron", "hybrid.ron", "pathtrace.ron"];
const SIZE: (u32, u32) = (64, 64);

fn draw(text: &str, graph: &str, frames: u32) -> ImageF32 {
    let image = render(gpu().expect("gpu"), scene_from(text), &repo().join("passes").join(graph), SIZE, frames, None);
    let bad = image.data.iter().flatten().filter(|v| !v.is_finite()).count();
    assert_eq!(bad, 0, "{graph}: {bad} non-finite values in the output");
    image
}

fn mean(image: &ImageF32) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in &image.data {
        for c in 0..3 {
            m[c] += f64::from(p[c]) / image.data.len() as f64;
        }
    }
    m
}

fn cornell() -> String {
    std::fs::read_to_string(repo().join("scenes/cornell.ron")).expect("read cornell.ron")
}

/// The box with `extra` added to its objects and `light` to its lights.
fn cornell_with(object: &str, light: &str) -> String {
    cornell()
        .replacen("    ],\n    lights: [", &format!("{object}\n    ],\n    lights: ["), 1)
        .replacen("radiance: (10.0, 10.0, 10.0)),", &format!("radiance: (10.0, 10.0, 10.0)),\n{light}"), 1)
}

#[test]
fn camera_inside_a_lit_sphere_gets_the_analytic_radiance() {
    if gpu().is_none() {
        return;
    }
    let (rho, intensity, radius) = (0.5, 4.0, 2.0);
    let text = format!(
        "Scene(camera: Camera(position: (0.3, -0.2, 0.5), target: (0.0, 0.0, -1.0), vfov_deg: 70.0),\n\
         materials: {{ \"grey\": Material(albedo: ({rho}, {rho}, {rho})) }},\n\
         objects: [ Sphere(center: (0.0, 0.0, 0.0), radius: {radius}, material: \"grey\") ],\n\
         lights: [ PointLight(position: (0.0, 0.0, 0.0), intensity: ({intensity}, {intensity}, {intensity})) ])"
    );
    let direct = rho * intensity / (std::f64::consts::PI * radius * radius);
    for graph in GRAPHS {
        let image = draw(&text, graph, 64);
        let want = if graph == "pathtrace.ron" { direct / (1.0 - rho) } else { direct };
        let got = mean(&image)[0];
        eprintln!("camera inside a sphere, {graph}: mean {got:.6}, analytic {want:.6}");
        assert!((got / want - 1.0).abs() < 0.01, "{graph}: mean {got}, analytic {want}");
        if graph != "pathtrace.ron" {
            // No noise in direct light from a point: every pixel is exact.
            let worst = image.data.iter().map(|p| (f64::from(p[0]) / want - 1.0).abs()).fold(0.0, f64::max);
            assert!(worst < 1e-4, "{graph}: a pixel off by {worst:e} relative");
        }
    }
}

#[test]
fn a_camera_inside_a_sphere_light_sees_its_radiance() {
    // The inside of a sphere light shows its radiance, as the outside does
    // (lights are two-sided emitters; nothing inside one is lit by it).
    if gpu().is_none() {
        return;
    }
    let text = "Scene(camera: Camera(position: (0.0, 0.0, 0.0), target: (0.0, 0.0, -1.0), vfov_deg: 60.0),\n\
         lights: [ SphereLight(center: (0.5, 0.0, 0.0), radius: 5.0, radiance: (2.0, 3.0, 4.0)) ])";
    for graph in GRAPHS {
        let image = draw(text, graph, 4);
        let worst = image.data.iter().map(|p| (p[0] - 2.0).abs().max((p[1] - 3.0).abs()).max((p[2] - 4.0).abs())).fold(0.0f32, f32::max);
        eprintln!("camera inside a sphere light, {graph}: mean {:.4?}", mean(&image));
        assert!(worst < 1e-5, "{graph}: the inside of the light is not its radiance (off by {worst})");
    }
}

#[test]
fn a_light_inside_an_opaque_sphere_lights_nothing() {
    if gpu().is_none() {
        return;
    }
    let shell = "        Sphere(center: (0.5, 0.2, -0.5), radius: 0.2, material: \"white\"),";
    let hidden = "        SphereLight(center: (0.5, 0.2, -0.5), radius: 0.05, radiance: (1000.0, 1000.0, 1000.0)),";
    let tiny = "        SphereLight(center: (-0.5, 0.2, 0.0), radius: 1e-20, radiance: (1.0, 1.0, 1.0)),";
    let without = cornell_with(shell, "");
    for (what, light) in [("a light inside a sphere", hidden), ("a light of radius 1e-20", tiny)] {
        let with = cornell_with(shell, light);
        for graph in GRAPHS {
            let (a, b) = (mean(&draw(&without, graph, 32)), mean(&draw(&with, graph, 32)));
            let rel = (0..3).map(|c| (b[c] / a[c] - 1.0).abs()).fold(0.0, f64::max);
            eprintln!("{what}, {graph}: mean {b:.5?} against {a:.5?} without it ({rel:.2e} relative)");
            // Sampling the extra light changes the random streams, not the
            // expectation: 32 frames at 64x64 agree within 2%.
            assert!(rel < 0.02, "{what} changed the image of {graph}: {b:?} against {a:?}");
        }
    }
}

#[test]
fn radiance_1e6_is_the_box_times_1e5() {
    if gpu().is_none() {
        return;
    }
    let bright = cornell().replacen("radiance: (10.0, 10.0, 10.0)", "radiance: (1e6, 1e6, 1e6)", 1);
    for graph in GRAPHS {
        let (a, b) = (draw(&cornell(), graph, 8), draw(&bright, graph, 8));
        let scaled = ImageF32 { data: b.data.iter().map(|p| [p[0] / 1e5, p[1] / 1e5, p[2] / 1e5, p[3]]).collect(), ..b };
        let (flip, _) = metrics::flip(&a, &scaled);
        eprintln!("radiance 1e6, {graph}: FLIP mean {:.5} against the box times 1e5", flip.mean);
        if graph == "hybrid.ron" {
            // Its noise mask thresholds absolute luminance, so a brighter
            // image refines more pixels: other samples, same expectation.
            assert!(flip.mean < 0.05, "{graph}: FLIP mean {}", flip.mean);
        } else {
            // The same samples, scaled: equal up to rounding.
            let worst = a.data.iter().zip(&scaled.data).flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() / p[c].abs().max(1e-3))).fold(0.0f32, f32::max);
            assert!(worst < 1e-3, "{graph}: radiance is not linear: a pixel off by {worst:e}");
        }
    }
}

#[test]
fn a_camera_on_a_wall_sees_what_one_just_inside_sees() {
    if gpu().is_none() {
        return;
    }
    let on = cornell().replacen("position: (0.0, 0.0, 3.4), target: (0.0, 0.0, 0.0)", "position: (0.0, 0.0, -1.0), target: (0.0, 0.0, 1.0)", 1);
    let inside = on.replacen("position: (0.0, 0.0, -1.0)", "position: (0.0, 0.0, -0.999)", 1);
    let touching = cornell().replacen("center: (0.0, 0.75, 0.0), radius: 0.15", "center: (0.0, 0.85, 0.0), radius: 0.15", 1);
    let below = cornell().replacen("center: (0.0, 0.75, 0.0), radius: 0.15", "center: (0.0, 0.8499, 0.0), radius: 0.15", 1);
    for (what, a, b) in [("a camera on the back wall", &on, &inside), ("a light touching the ceiling", &touching, &below)] {
        for graph in GRAPHS {
            let (flip, _) = metrics::flip(&draw(b, graph, 16), &draw(a, graph, 16));
            eprintln!("{what}, {graph}: FLIP mean {:.5} against a hair away", flip.mean);
            assert!(flip.mean < 0.02, "{what}, {graph}: FLIP mean {}", flip.mean);
        }
    }
}

/// smallpt's room (walls are spheres of radius 1e4): the huge walls set
/// the scene's offset scale; no pixel of the path-traced room is black (no
/// shadow-ray self-intersection in its corners).
#[test]
fn huge_sphere_walls_leave_no_black_pixel() {
    if gpu().is_none() {
        return;
    }
    let text = r#"Scene(camera: Camera(position: (50.0, 52.0, 295.6), target: (50.0, 51.957388, 294.6), vfov_deg: 30.0),
  materials: { "red": Material(albedo: (0.75, 0.25, 0.25)), "blue": Material(albedo: (0.25, 0.25, 0.75)), "grey": Material(albedo: (0.75, 0.75, 0.75)) },
  objects: [
    Sphere(center: (10001.0, 40.8, 81.6), radius: 10000.0, material: "red"),
    Sphere(center: (-9901.0, 40.8, 81.6), radius: 10000.0, material: "blue"),
    Sphere(center: (50.0, 40.8, 10000.0), radius: 10000.0, material: "grey"),
    Sphere(center: (50.0, 10000.0, 81.6), radius: 10000.0, material: "grey"),
    Sphere(center: (50.0, -9918.4, 81.6), radius: 10000.0, material: "grey"),
    Sphere(center: (27.0, 16.5, 47.0), radius: 16.5, material: "grey"),
  ],
  lights: [ SphereLight(center: (50.0, 70.0, 81.6), radius: 5.0, radiance: (50.0, 50.0, 50.0)) ])"#;
    let image = draw(text, "pathtrace.ron", 32);
    let black = image.data.iter().filter(|p| p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0).count();
    assert_eq!(black, 0, "{black} black pixels in smallpt's room");
}

/// A scene of one mesh and nothing else (an OBJ beside a point light: the
/// TLAS is that mesh alone, ONE_MESH) renders in every shipped graph. The
/// path tracer's and realtime.ron's shaders crashed lavapipe (a segfault
/// in its queue thread) on such a scene; each graph runs in a process of
/// its own, so a crash fails this test instead of ending the test run.
#[test]
fn a_scene_of_one_mesh_renders_in_every_graph() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("one-mesh");
    let scene = dir.join("chair.ron");
    let mesh = repo().join("scenes/meshes/chair.obj");
    std::fs::write(
        &scene,
        format!("Scene(camera: Camera(position: (0.0, 1.0, 4.0), target: (0.0, 0.5, 0.0), vfov_deg: 40.0),\n  objects: [Mesh(path: {mesh:?})],\n  lights: [PointLight(position: (1.0, 3.0, 3.0), intensity: (10.0, 10.0, 10.0))])\n"),
    )
    .unwrap();
    let mut failed = Vec::new();
    for graph in ["direct.ron", "hybrid-point.ron", "hybrid.ron", "hybrid-gi.ron", "irradiance.ron", "pathtrace.ron", "realtime.ron", "realtime-restir.ron"] {
        let out = dir.join(graph.replace(".ron", ".png"));
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
            .args(["render", &scene.display().to_string(), "--graph", &repo().join("passes").join(graph).display().to_string(), "--size", "32x32", "--frames", "2", "--out"])
            .arg(&out)
            .env("WGPU_BACKEND", "vulkan")
            .output()
            .expect("run glint");
        if !run.status.success() {
            failed.push(format!("{graph}: {} {}", run.status, String::from_utf8_lossy(&run.stderr)));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
    std::fs::remove_dir_all(&dir).ok();
}
