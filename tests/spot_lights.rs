//! Spot lights (a point light with glTF's cone): on a floor below one,
//! every graph that shades point lights gives the point light's image
//! inside the inner cone and nothing beyond the outer one.

mod common;

use common::*;

const FLOOR: &str = r#"Scene(
    camera: Camera(position: (0.0, 3.0, 0.0), target: (0.0, 0.0, 0.0), up: (0.0, 0.0, -1.0), vfov_deg: 60.0),
    materials: { "white": Material(albedo: (0.8, 0.8, 0.8)) },
    objects: [Quad(vertices: [(-2.0, 0.0, -2.0), (-2.0, 0.0, 2.0), (2.0, 0.0, 2.0), (2.0, 0.0, -2.0)], material: "white")],
    lights: [LIGHT],
)"#;

#[test]
fn a_spot_light_is_its_point_light_inside_the_cone_and_dark_outside() {
    let Some(gpu) = gpu() else { return };
    let point = FLOOR.replace("LIGHT", "PointLight(position: (0.0, 1.0, 0.0), intensity: (2.0, 2.0, 2.0))");
    // Inner 30 degrees (0.577 on the floor, 10.7 pixels), outer 35 (0.70, 13 pixels).
    let spot = FLOOR.replace("LIGHT", "SpotLight(position: (0.0, 1.0, 0.0), direction: (0.0, -2.0, 0.0), intensity: (2.0, 2.0, 2.0), inner_deg: 30.0, outer_deg: 35.0)");
    let size = 64u32;
    let region = |img: &glint::gpu::readback::ImageF32, keep: &dyn Fn(f32) -> bool| -> (f64, usize) {
        let (mut sum, mut n) = (0.0, 0);
        for y in 0..size {
            for x in 0..size {
                let r = ((x as f32 + 0.5 - 32.0).powi(2) + (y as f32 + 0.5 - 32.0).powi(2)).sqrt();
                if keep(r) {
                    sum += luminance(&img.get(x, y));
                    n += 1;
                }
            }
        }
        (sum / n as f64, n)
    };
    for graph in ["direct.ron", "hybrid-point.ron", "pathtrace.ron", "realtime.ron", "realtime-restir.ron"] {
        let path = repo().join("passes").join(graph);
        let a = render(gpu, scene_from(&point), &path, (size, size), 16, None);
        let b = render(gpu, scene_from(&spot), &path, (size, size), 16, None);
        let (inner_point, n) = region(&a, &|r| r < 9.0);
        let (inner_spot, _) = region(&b, &|r| r < 9.0);
        let (outer_spot, m) = region(&b, &|r| (15.0..30.0).contains(&r));
        let (outer_point, _) = region(&a, &|r| (15.0..30.0).contains(&r));
        eprintln!("{graph}: inside {inner_spot:.4} (point {inner_point:.4}, {n} px), outside {outer_spot:.6} (point {outer_point:.4}, {m} px)");
        assert!(inner_point > 0.1 && outer_point > 0.05, "{graph}: the point light lights the floor");
        assert!((inner_spot / inner_point - 1.0).abs() < 0.02, "{graph}: inside the inner cone {inner_spot} against the point light's {inner_point}");
        // (The real-time graphs' spatial filter carries a trace of the
        // lit disc a few pixels out while their history is short.)
        assert!(outer_spot < 0.005 * outer_point, "{graph}: beyond the outer cone {outer_spot}");
    }
}

/// A directional light (a sun) of irradiance E straight down on the
/// floor: radiance albedo E / pi at every floor pixel, in every graph; and
/// at 60 degrees, half of it.
#[test]
fn a_directional_light_gives_albedo_e_over_pi_everywhere() {
    let Some(gpu) = gpu() else { return };
    for (direction, cos) in [("(0.0, -1.0, 0.0)", 1.0), ("(0.0, -0.5, -0.8660254)", 0.5)] {
        let scene = FLOOR.replace("LIGHT", &format!("DirectionalLight(direction: {direction}, irradiance: (2.0, 2.0, 2.0))"));
        let want = 0.8 * 2.0 * cos / std::f64::consts::PI;
        for graph in ["direct.ron", "hybrid-point.ron", "pathtrace.ron", "realtime.ron"] {
            let img = render(gpu, scene_from(&scene), &repo().join("passes").join(graph), (32, 32), 8, None);
            // The floor fills the view (2 units each side, 1.73 seen).
            let got = mean_rgb(&img);
            eprintln!("{graph}, cos {cos}: {got:.4} against {want:.4}");
            assert!((got / want - 1.0).abs() < 0.01, "{graph}, cos {cos}: {got} against albedo E cos / pi = {want}");
        }
    }
}
