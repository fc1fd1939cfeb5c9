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
    let mut scene = scene_from(SCENE);
    assert!(scene.animate(end));
    let mut fresh = session(gpu, scene, &compiled, size, 1);
    fresh.frame(end);
    let full = fresh.read_output().unwrap_or_else(|e| panic!("{e}"));

    let hits = full.data.iter().filter(|p| p[0].is_finite()).count();
    assert!(hits > size.0 as usize * size.1 as usize / 10, "the scene should fill the view ({hits} hits)");
    let differ = incremental.data.iter().zip(&full.data).filter(|(a, b)| a[0].to_bits() != b[0].to_bits() || a[1] != b[1]).count();
    assert_eq!(differ, 0, "{differ} pixels differ between incremental and fresh uploads");
}
