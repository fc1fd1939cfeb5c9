//! Ray offsets from per-hit error bounds (issue 40), on the GPU: every hit
//! carries a bound on its position's error from the operands
//! (shaders/shared/intersect.wgsl, mirrored by src/bvh/offset.rs), so no
//! surface's offset depends on the size of the scene around it. Before,
//! the offsets near the origin were a share of the scene's extent: one
//! huge triangle, or a huge quad beside a unit box, moved every shadow
//! ray's origin by units, and the images went black.

mod common;

use common::*;
use glint::metrics;

/// `graph` (under passes/) on the scene `text`, `frames` frames.
fn draw(text: &str, graph: &str, size: (u32, u32), frames: u32) -> glint::gpu::readback::ImageF32 {
    render(gpu().expect("gpu"), scene_from(text), &repo().join("passes").join(graph), size, frames, None)
}

/// One triangle in the plane z = 0 (`tri.obj`, 2 units across) scaled by
/// `s`, the camera `view` units in front of it, a point light above it.
fn triangle_scene(obj: &std::path::Path, s: f64, view: f64) -> String {
    format!(
        "Scene(camera: Camera(position: (0.0, 0.0, {z:e}), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n\
         materials: {{ \"white\": Material(albedo: (0.8, 0.8, 0.8)) }},\n\
         objects: [ Mesh(path: {obj:?}, scale: {s:e}, material: \"white\") ],\n\
         lights: [ PointLight(position: ({lx:e}, {ly:e}, {lz:e}), intensity: ({i:e}, {i:e}, {i:e})) ])",
        z = 4.4 * view,
        lx = 0.3 * view,
        ly = 0.2 * view,
        lz = 2.0 * view,
        i = 4.0 * view * view,
    )
}

/// A triangle from 1e-6 to 1e12 across, seen from 4.4 of its sizes (the
/// same image at every scale), and triangles from 1e3 to 1e12 across seen
/// from 4.4 units (the same image: a plane filling the view). Before: all
/// black from 1e6 on.
#[test]
fn a_triangle_of_any_size_at_any_distance_is_lit() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("offsets-triangle");
    let obj = dir.join("tri.obj");
    std::fs::write(&obj, "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let size = (32, 32);
    let reference = draw(&triangle_scene(&obj, 1.0, 1.0), "direct.ron", size, 2);
    assert!(mean_rgb(&reference) > 0.02, "{}", mean_rgb(&reference));
    let mut failed = Vec::new();
    for s in [1e-6, 1e-3, 1e3, 1e6, 1e9, 1e12] {
        let image = draw(&triangle_scene(&obj, s, s), "direct.ron", size, 2);
        let (flip, _) = metrics::flip(&reference, &image);
        eprintln!("triangle {s:e} seen from {:e}: FLIP {:.5}", 4.4 * s, flip.mean);
        if flip.mean > 0.01 {
            failed.push(format!("size {s:e} seen from {:e}: FLIP {:.4}", 4.4 * s, flip.mean));
        }
    }
    let filling = draw(&triangle_scene(&obj, 1e3, 1.0), "direct.ron", size, 2);
    for s in [1e6, 1e9, 1e12] {
        let image = draw(&triangle_scene(&obj, s, 1.0), "direct.ron", size, 2);
        let (flip, _) = metrics::flip(&filling, &image);
        eprintln!("triangle {s:e} seen from 4.4: FLIP {:.5} against 1e3", flip.mean);
        if flip.mean > 0.01 {
            failed.push(format!("size {s:e} seen from 4.4: FLIP {:.4} against size 1e3", flip.mean));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
    std::fs::remove_dir_all(&dir).ok();
}

/// The Cornell box beside a quad 1e9 across far behind the camera (the
/// scene's extent is now 1e9): the same image as the box alone. Before,
/// every offset grew with the extent (units), and the image went black.
#[test]
fn one_huge_quad_leaves_the_rest_of_the_scene_as_it_was() {
    if gpu().is_none() {
        return;
    }
    let text = std::fs::read_to_string(repo().join("scenes/cornell.ron")).unwrap();
    let quad = "        Quad(vertices: [(-5e8, -5e8, 1e9), (5e8, -5e8, 1e9), (5e8, 5e8, 1e9), (-5e8, 5e8, 1e9)], material: \"white\"),\n    ],\n    lights:";
    let with_quad = text.replacen("    ],\n    lights:", quad, 1);
    assert_ne!(with_quad, text, "cornell.ron's objects list changed shape");
    for graph in ["direct.ron", "hybrid.ron"] {
        let alone = draw(&text, graph, (48, 48), 4);
        let beside = draw(&with_quad, graph, (48, 48), 4);
        let (flip, _) = metrics::flip(&alone, &beside);
        eprintln!("{graph}: FLIP {:.5} with a 1e9 quad in the scene", flip.mean);
        assert!(flip.mean <= 0.01, "{graph}: FLIP {} with a 1e9 quad in the scene (means {} and {})", flip.mean, mean_rgb(&alone), mean_rgb(&beside));
    }
}

/// A sphere light around the camera and the scene lights it from every
/// direction: a floor under a uniform sky of radiance 1 has radiance
/// albedo x 1 (irradiance pi L). Before: all black (sampling gave nothing
/// from inside a light), while the path tracer, hitting the light's
/// inside, lit it.
#[test]
fn a_sphere_light_around_the_camera_lights_the_scene() {
    if gpu().is_none() {
        return;
    }
    let scene = "Scene(camera: Camera(position: (0.0, 1.0, 0.01), target: (0.0, -1.0, 0.0), vfov_deg: 30.0),\n\
        materials: { \"white\": Material(albedo: (0.8, 0.8, 0.8)) },\n\
        objects: [ Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, 1.0), (1.0, -1.0, -1.0)], material: \"white\") ],\n\
        lights: [ SphereLight(center: (0.0, 0.0, 0.0), radius: 5.0, radiance: (1.0, 1.0, 1.0)) ])";
    for graph in ["direct.ron", "pathtrace.ron"] {
        let image = draw(scene, graph, (16, 16), 128);
        // The view looks straight down on the floor, which fills it.
        let m = mean_rgb(&image);
        eprintln!("{graph}: floor radiance {m:.4} (albedo x L = 0.8)");
        assert!((m / 0.8 - 1.0).abs() < 0.05, "{graph}: floor radiance {m} where albedo x L is 0.8");
    }
}
