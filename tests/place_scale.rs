//! Any place and any scale (issue 12, parts 1 and 2): the Cornell boxes
//! moved anywhere within 1e7 of the origin, scaled by 1e-5 .. 1e5, or both
//! (positions and radii scaled, radiance unchanged, point intensities
//! times s^2; tests/common/scene_text.rs) render the image of the untouched
//! box in every shipped graph, with the same seed.
//!
//! What made them fail: positions were parsed as f32 (at 1e7 a float's
//! resolution is 1), and `offset_ray`'s near-origin offset was absolute.
//! Now the world is f64 and the GPU sees it rebased on a grid point near
//! the camera (src/session/scene_gpu.rs), and every ray leaves its hit by
//! that hit's own error bound (src/bvh/offset.rs).
//! `cargo run --release --example place_scale` prints the table in
//! docs/acceleration.md ("Any place, any scale").

mod common;

use common::scene_text::transformed;
use common::*;
use glint::metrics;

/// (scale, offset): axes and signs mixed, up to 1e7 from the origin.
const CASES: [(f64, [f64; 3]); 8] = [
    (1.0, [1e2, -3e1, 7e1]),
    (1.0, [-1e5, 3e4, -7e4]),
    (1.0, [7e6, -3e6, 5e6]),
    (1.0, [0.0, 0.0, -1e7]),
    (1e-5, [0.0; 3]),
    (1e5, [0.0; 3]),
    (1e-3, [-2e3, 5e2, 1e3]),
    (1e3, [5e6, -8e6, 1e6]),
];

const GRAPHS: [&str; 4] = ["direct.ron", "hybrid-point.ron", "hybrid.ron", "pathtrace.ron"];

#[test]
fn any_place_and_scale_renders_the_same_image() {
    let Some(gpu) = gpu() else { return };
    let size = (64, 64);
    let mut worst = (0.0f32, String::new());
    for scene in ["cornell.ron", "cornell-point.ron"] {
        let text = std::fs::read_to_string(repo().join("scenes").join(scene)).expect("read scene");
        for graph in GRAPHS {
            let path = repo().join("passes").join(graph);
            let reference = render(gpu, scene_from(&text), &path, size, 8, None);
            for (s, offset) in CASES {
                let image = render(gpu, scene_from(&transformed(&text, s, offset)), &path, size, 8, None);
                let (flip, _) = metrics::flip(&reference, &image);
                let case = format!("{scene} {graph} scaled by {s:e}, moved by {offset:?}");
                eprintln!("{case}: FLIP mean {:.5}", flip.mean);
                if flip.mean > worst.0 {
                    worst = (flip.mean, case.clone());
                }
                assert!(flip.mean <= 0.01, "{case}: FLIP mean {} against the untouched box", flip.mean);
            }
        }
    }
    eprintln!("worst FLIP mean: {:.5} ({})", worst.0, worst.1);
}

#[test]
fn the_text_transform_moves_and_scales_every_field() {
    let text = "Scene(camera: Camera(position: (0.0, 1.5, -2.0), target: (0.0, 0.0, 0.0)),\n  Sphere(center: (1.0, 2.0, 3.0), radius: 0.5, material: \"m\"),\n  Quad(vertices: [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0)], material: \"m\"),\n  PointLight(position: (0.0, 1.0, 0.0), intensity: (2.0, 2.0, 2.0), motion: Orbit(center: (0.0, 0.0, 0.0), axis: (0.0, 1.0, 0.0), radius: 0.25, period_s: 4.0)),\n  // radius: 7.0\n)";
    let t = transformed(text, 10.0, [100.0, 0.0, -1.0]);
    assert!(t.contains("position: (1e2, 1.5e1, -2.1e1)"), "{t}");
    assert!(t.contains("center: (1.1e2, 2e1, 2.9e1), radius: 5e0,"), "{t}");
    assert!(t.contains("vertices: [(1.1e2, 0e0, -1e0), (1e2, 1e1, -1e0)]"), "{t}");
    assert!(t.contains("intensity: (2e2, 2e2, 2e2)"), "{t}");
    assert!(t.contains("Orbit(center: (1e2, 0e0, -1e0), axis: (0.0, 1.0, 0.0), radius: 2.5e0, period_s: 4.0)"), "{t}");
    assert!(t.contains("// radius: 7.0"), "{t}");
}
