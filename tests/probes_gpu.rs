//! The irradiance volume on the GPU (issue 13): the furnace (inside a
//! closed sphere of albedo 0.5 with uniform emission, every probe texel
//! holds the analytic irradiance), and the shaders' maps and grid against
//! their Rust mirrors (src/probes/).

mod common;

use common::*;
use glint::graph::desc::ParamValue;
use glint::graph::edit::{GraphEdits, ParamSet};
use glint::graph::CompileOptions;

fn set(pass: &str, param: &str, value: ParamValue) -> ParamSet {
    ParamSet { pass: pass.into(), param: param.into(), value }
}

/// A closed sphere of radius 1, albedo 0.5, emitting radiance 1, no lights.
const FURNACE: &str = r#"Scene(
    camera: Camera(position: (0.0, 0.0, 0.0), target: (0.0, 0.0, -1.0), up: (0.0, 1.0, 0.0), vfov_deg: 60.0),
    background: (0.0, 0.0, 0.0),
    materials: { "glow": Material(albedo: (0.5, 0.5, 0.5), emission: (1.0, 1.0, 1.0)) },
    objects: [ Sphere(center: (0.0, 0.0, 0.0), radius: 1.0, material: "glow") ],
    lights: [],
)"#;

const BOUNCES: i64 = 16;

/// Radiance everywhere inside: emission plus its reflections, each bounce
/// scaled by the albedo, for the bounces a path takes.
fn furnace_radiance() -> f64 {
    (0..BOUNCES).map(|d| 0.5f64.powi(d as i32)).sum()
}

#[test]
fn furnace_every_thesis_probe_texel_holds_the_analytic_irradiance() {
    let Some(gpu) = gpu() else { return };
    let scene = scene_from(FURNACE);
    // Padding 0.25: the grid's corners (0.5, 0.5, 0.5) lie inside the sphere.
    let edits = GraphEdits {
        set: vec![
            set("probes", "level", ParamValue::Int(3)),
            set("probes", "padding", ParamValue::Float(0.25)),
            set("thesis_radiance", "bounces", ParamValue::Int(BOUNCES)),
        ],
        ..Default::default()
    };
    let options = CompileOptions { output: Some("thesis_irradiance".into()), edits, ..Default::default() };
    let g = compile(&scene, &repo().join("passes/irradiance.ron"), &options);
    let mut s = session(gpu, scene, &g, (16, 16), 1);
    // 256 paths per bucket at 16 a frame.
    for _ in 0..17 {
        s.frame(0.0);
    }
    let atlas = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    // 4^3 probes, tiles of 16 x 8.
    assert_eq!((atlas.width, atlas.height), (16 * 16, 4 * 8));
    let want = std::f64::consts::PI * furnace_radiance();
    let mut worst = 0.0f64;
    for p in &atlas.data {
        for c in &p[..3] {
            worst = worst.max((f64::from(*c) / want - 1.0).abs());
        }
    }
    eprintln!("furnace: irradiance {want:.4} expected; worst texel off by {:.3}%", 100.0 * worst);
    assert!(worst <= 0.025, "a probe texel is {:.2}% off the analytic irradiance {want:.4}", 100.0 * worst);
}
