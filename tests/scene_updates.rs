//! Moving lights and meshes are uploaded in place, only the texels that
//! changed (src/scene/buffers.rs): after several frames of motion the
//! GPU must hold exactly what a fresh upload of the moved scene holds.

mod common;

use common::*;

const SCENE: &str = r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.4), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),
    materials: { "white": Material(albedo: (0.7, 0.7, 0.7)) },
    objects: [
        Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, 1.0), (1.0, -1.0, -1.0)], material: "white"),
        Mesh(path: "meshes/knot.obj", material: "white", translate: (0.0, -0.4, 0.0), scale: 0.2,
             motion: Linear(velocity: (0.15, 0.05, 0.0))),
        Sphere(center: (-0.5, 0.3, 0.0), radius: 0.2, material: "white",
               motion: Orbit(center: (0.0, 0.3, 0.0), axis: (0.0, 1.0, 0.0), radius: 0.5, period_s: 4.0)),
    ],
    lights: [
        SphereLight(center: (0.5, 0.7, 0.0), radius: 0.1, radiance: (8.0, 8.0, 8.0),
                    motion: Orbit(center: (0.0, 0.7, 0.0), axis: (0.0, 1.0, 0.0), radius: 0.5, period_s: 3.0)),
    ],
)"#;

/// One frame of the scene `text` already moved to time `end` when the
/// session is made (one full upload).
fn fresh_at(gpu: &glint::gpu::Gpu, text: &str, compiled: &glint::graph::CompiledGraph, size: (u32, u32), end: f32) -> glint::gpu::readback::ImageF32 {
    let mut scene = scene_from(text);
    assert!(scene.animate(end));
    let mut fresh = session(gpu, scene, compiled, size, 1);
    fresh.frame(end);
    fresh.read_output().unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn incremental_uploads_match_a_fresh_upload() {
    let Some(gpu) = gpu() else { return };
    let graph = repo().join("passes/bench-rays.ron");
    let size = (96, 96);
    let end = 2.5;

    // Moved frame by frame: each update writes the texels that changed.
    let scene = scene_from(SCENE);
    let compiled = compile(&scene, &graph, &Default::default());
    let mut moved = session(gpu, scene, &compiled, size, 1);
    for t in [0.0, 0.4, 1.1, 1.7, end] {
        moved.frame(t);
    }
    let incremental = moved.read_output().unwrap_or_else(|e| panic!("{e}"));

    // The scene already at `end` when the renderer is made: one full upload.
    let full = fresh_at(gpu, SCENE, &compiled, size, end);

    let hits = full.data.iter().filter(|p| p[0].is_finite()).count();
    assert!(hits > size.0 as usize * size.1 as usize / 10, "the scene should fill the view ({hits} hits)");
    let differ = incremental.data.iter().zip(&full.data).filter(|(a, b)| a[0].to_bits() != b[0].to_bits() || a[1] != b[1]).count();
    assert_eq!(differ, 0, "{differ} pixels differ between incremental and fresh uploads");
}

/// A flat scene (a floor, a box of quads and a sphere) lit by an orbiting
/// sphere light in point mode.
const FLAT: &str = r#"Scene(
    camera: Camera(position: (0.0, 0.6, 3.4), target: (0.0, -0.3, 0.0), vfov_deg: 40.0),
    materials: { "white": Material(albedo: (0.7, 0.7, 0.7)) },
    objects: [
        Quad(vertices: [(-2.0, -1.0, -2.0), (-2.0, -1.0, 2.0), (2.0, -1.0, 2.0), (2.0, -1.0, -2.0)], material: "white"),
        Quad(vertices: [(-0.3, -1.0, 0.2), (0.3, -1.0, 0.2), (0.3, -0.2, 0.2), (-0.3, -0.2, 0.2)], material: "white"),
        Quad(vertices: [(-0.3, -0.2, 0.2), (0.3, -0.2, 0.2), (0.3, -0.2, -0.4), (-0.3, -0.2, -0.4)], material: "white"),
        Sphere(center: (-0.9, -0.6, 0.3), radius: 0.4, material: "white"),
    ],
    lights: [
        SphereLight(center: (0.8, 0.9, 0.0), radius: 0.1, radiance: (8.0, 8.0, 8.0),
                    motion: Orbit(center: (0.0, 0.9, 0.0), axis: (0.0, 1.0, 0.0), radius: 0.8, period_s: 3.0)),
    ],
)"#;

/// The camera's and the light's triangle tables (src/scene/origins.rs)
/// follow motion: after frames with the light orbiting and the camera
/// elsewhere, the G-buffer and point shadows equal a fresh render's, bit
/// for bit.
#[test]
fn origin_tables_follow_the_camera_and_the_light() {
    let Some(gpu) = gpu() else { return };
    let graph = repo().join("tests/graphs/point-shadows.ron");
    let size = (96, 64);
    let end = 2.2;
    let scene = scene_from(FLAT);
    let camera = scene.camera;
    let compiled = compile(&scene, &graph, &Default::default());
    let mut moved = session(gpu, scene, &compiled, size, 1);
    for (k, t) in [0.0, 0.7, 1.3, end].into_iter().enumerate() {
        let mut c = camera;
        c.position.x += if k == 3 { 0.0 } else { 0.5 - 0.3 * k as f64 };
        moved.scene.scene.camera = c;
        moved.frame(t);
    }
    let incremental = moved.read_output().unwrap_or_else(|e| panic!("{e}"));

    let full = fresh_at(gpu, FLAT, &compiled, size, end);

    // Some pixels lit and some in shadow, or the test shows nothing.
    let lit = full.data.iter().filter(|p| p[0] > 0.0).count();
    assert!(lit > 1000 && lit < full.data.len() - 500, "{lit} lit pixels");
    let differ = incremental.data.iter().zip(&full.data).filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits)).count();
    assert_eq!(differ, 0, "{differ} pixels differ between a moved session and a fresh one");
}

/// The flat scene's uniform copy (`scene_flat`, src/scene/flat_uniform.rs),
/// which the path tracer's bounce and shadow rays read, follows motion:
/// after frames with the light orbiting, the path tracer's raw radiance
/// equals, bit for bit, that of a session made with the scene already
/// moved, at the same frame index.
#[test]
fn the_flat_uniform_follows_motion() {
    let Some(gpu) = gpu() else { return };
    let graph = repo().join("passes/pathtrace.ron");
    let size = (64, 48);
    let end = 2.2;
    let scene = scene_from(FLAT);
    assert!(scene.is_flat());
    let options = glint::graph::CompileOptions { output: Some("radiance".into()), ..Default::default() };
    let compiled = compile(&scene, &graph, &options);
    let times = [0.0, 0.7, 1.3, end];
    let mut moved = session(gpu, scene, &compiled, size, 1);
    for t in times {
        moved.frame(t);
    }
    let incremental = moved.read_output().unwrap_or_else(|e| panic!("{e}"));

    let mut still = scene_from(FLAT);
    assert!(still.animate(end));
    let mut fresh = session(gpu, still, &compiled, size, 1);
    for _ in times {
        fresh.frame(end);
    }
    let full = fresh.read_output().unwrap_or_else(|e| panic!("{e}"));

    let lit = full.data.iter().filter(|p| p[0] > 0.0).count();
    assert!(lit > full.data.len() / 4, "{lit} lit pixels");
    let differ = incremental.data.iter().zip(&full.data).filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits)).count();
    assert_eq!(differ, 0, "{differ} pixels differ between a moved session and a fresh one");
}
