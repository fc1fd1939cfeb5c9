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

fn parse_sets(sets: &[&str]) -> Vec<ParamSet> {
    sets.iter().map(|s| s.parse().unwrap_or_else(|e| panic!("{e}"))).collect()
}

/// Renders `frames` frames of irradiance.ron in ddgi mode with `sets` and
/// reads back `output`.
fn ddgi_run(scene: glint::scene::Scene, sets: &[&str], output: &str, frames: u32) -> glint::gpu::readback::ImageF32 {
    let gpu = gpu().expect("gpu");
    let mut all = vec!["probes.mode=ddgi"];
    all.extend_from_slice(sets);
    let options = CompileOptions { output: Some(output.into()), edits: GraphEdits { set: parse_sets(&all), ..Default::default() }, ..Default::default() };
    let g = compile(&scene, &repo().join("passes/irradiance.ron"), &options);
    let mut s = session(gpu, scene, &g, (16, 16), 1);
    for _ in 0..frames {
        s.frame(0.0);
    }
    s.read_output().unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn furnace_every_ddgi_probe_texel_holds_the_analytic_irradiance() {
    if gpu().is_none() {
        return;
    }
    // Two-sided surfaces (the sphere's inside is the room); every bounce,
    // one more per update, over 256 updates.
    let sets = ["probes.level=3", "probes.padding=0.25", "ddgi_trace.solid_backfaces=0"];
    let atlas = ddgi_run(scene_from(FURNACE), &sets, "ddgi_irradiance", 257);
    assert_eq!((atlas.width, atlas.height), (16 * 8, 4 * 8));
    // All bounces: emission / (1 - albedo) = 2.
    let want = std::f64::consts::PI * 2.0;
    let mut worst = 0.0f64;
    for p in &atlas.data {
        for c in &p[..3] {
            worst = worst.max((f64::from(*c) / want - 1.0).abs());
        }
    }
    eprintln!("ddgi furnace: irradiance {want:.4} expected; worst texel off by {:.3}%", 100.0 * worst);
    assert!(worst <= 0.025, "a probe texel is {:.2}% off the analytic irradiance {want:.4}", 100.0 * worst);
}

#[test]
fn a_ddgi_probe_inside_a_sphere_moves_out_or_switches_off() {
    if gpu().is_none() {
        return;
    }
    let scene = load_scene("cornell.ron");
    // Level 4 over the box [-1, 1]^3 padded by 0.1: probes 0.4 apart from
    // -0.8; probe (1, 0, 1) at (-0.4, -0.8, -0.4) is inside the white sphere
    // (centre (-0.4, -0.65, -0.3), radius 0.35).
    let state = ddgi_run(scene, &[], "ddgi_state", 8);
    let n = 5;
    let probe = 1 + n * n; // (1, 0, 1)
    let s = state.data[probe];
    let at = glam::Vec3::new(-0.4 + s[0], -0.8 + s[1], -0.4 + s[2]);
    let from_centre = (at - glam::Vec3::new(-0.4, -0.65, -0.3)).length();
    eprintln!("probe inside the sphere: offset ({:.3}, {:.3}, {:.3}), {from_centre:.3} from the centre, on = {}", s[0], s[1], s[2], s[3]);
    assert!(from_centre > 0.35 || s[3] == 0.0, "still inside and on: {s:?}");
    // A probe in open space stays on its grid point.
    let open = state.data[2 + n * (2 + n * 2)];
    assert_eq!(open, [0.0, 0.0, 0.0, 1.0]);
}

/// Two rooms, [-2, 0.3] and [0.3, 2] in x (y and z in [-1, 1]), split by
/// a wall 0.04 thick: a tenth of the probe spacing at level 4 (0.4 in y
/// and z, 0.8 in x; probes at x = -1.6, -0.8, 0, 0.8, 1.6, so the wall
/// runs between two layers of probes). A sphere light in the left room
/// only. `camera` is placed by the caller.
fn two_rooms(camera: &str) -> String {
    format!(
        r#"Scene(
    camera: {camera},
    background: (0.0, 0.0, 0.0),
    materials: {{ "white": Material(albedo: (0.8, 0.8, 0.8)) }},
    objects: [
        Quad(vertices: [(-2.0, -1.0, -1.0), (-2.0, -1.0, 1.0), (2.0, -1.0, 1.0), (2.0, -1.0, -1.0)], material: "white"),
        Quad(vertices: [(-2.0, 1.0, -1.0), (2.0, 1.0, -1.0), (2.0, 1.0, 1.0), (-2.0, 1.0, 1.0)], material: "white"),
        Quad(vertices: [(-2.0, -1.0, -1.0), (2.0, -1.0, -1.0), (2.0, 1.0, -1.0), (-2.0, 1.0, -1.0)], material: "white"),
        Quad(vertices: [(-2.0, -1.0, 1.0), (-2.0, 1.0, 1.0), (2.0, 1.0, 1.0), (2.0, -1.0, 1.0)], material: "white"),
        Quad(vertices: [(-2.0, -1.0, -1.0), (-2.0, 1.0, -1.0), (-2.0, 1.0, 1.0), (-2.0, -1.0, 1.0)], material: "white"),
        Quad(vertices: [(2.0, -1.0, -1.0), (2.0, -1.0, 1.0), (2.0, 1.0, 1.0), (2.0, 1.0, -1.0)], material: "white"),
        // The wall: its two faces, each facing its room.
        Quad(vertices: [(0.28, -1.0, -1.0), (0.28, -1.0, 1.0), (0.28, 1.0, 1.0), (0.28, 1.0, -1.0)], material: "white"),
        Quad(vertices: [(0.32, -1.0, -1.0), (0.32, 1.0, -1.0), (0.32, 1.0, 1.0), (0.32, -1.0, 1.0)], material: "white"),
    ],
    lights: [ SphereLight(center: (-1.0, 0.5, 0.0), radius: 0.1, radiance: (50.0, 50.0, 50.0)) ],
)"#
    )
}

/// Mean of the indirect light the volume (`mode` thesis or ddgi) puts on
/// what `camera` sees.
fn indirect_seen(camera: &str, mode: &str) -> f64 {
    let scene = scene_from(&two_rooms(camera));
    let (sets, last) = if mode == "ddgi" {
        (parse_sets(&["probes.mode=ddgi", "ddgi_trace.emitters=0"]), "irradiance_ddgi")
    } else {
        (parse_sets(&["thesis_radiance.emitters=0"]), "irradiance")
    };
    let options = CompileOptions {
        output: Some("lit".into()),
        edits: GraphEdits { set: sets, stop_after: Some(last.into()), ..Default::default() },
        ..Default::default()
    };
    let g = compile(&scene, &repo().join("passes/irradiance.ron"), &options);
    let mut s = session(gpu().expect("gpu"), scene, &g, (32, 32), 1);
    for _ in 0..64 {
        s.frame(0.0);
    }
    mean_rgb(&s.read_output().unwrap_or_else(|e| panic!("{e}")))
}

#[test]
fn ddgi_light_does_not_leak_through_a_thin_wall() {
    if gpu().is_none() {
        return;
    }
    // Each camera in its room, looking at the wall and the floor by it.
    let in_lit = "Camera(position: (-1.9, 0.0, 0.0), target: (0.3, -0.5, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 60.0)";
    let in_dark = "Camera(position: (1.9, 0.0, 0.0), target: (0.3, -0.5, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 60.0)";
    let (lit, dark) = (indirect_seen(in_lit, "ddgi"), indirect_seen(in_dark, "ddgi"));
    eprintln!("leak (ddgi): indirect light seen in the lit room {lit:.5}, in the dark room {dark:.6} ({:.3}%)", 100.0 * dark / lit);
    assert!(lit > 0.01, "the lit room has indirect light: {lit}");
    assert!(dark < 0.01 * lit, "the dark room gets {:.2}% of the lit room's indirect light", 100.0 * dark / lit);
    // The thesis's volume has no visibility: its probes on the lit side
    // light the dark side of the wall. The scene shows a leak when there is one.
    let (lit, dark) = (indirect_seen(in_lit, "thesis"), indirect_seen(in_dark, "thesis"));
    eprintln!("leak (thesis): lit room {lit:.5}, dark room {dark:.6} ({:.3}%)", 100.0 * dark / lit);
    assert!(dark > 0.01 * lit, "the thesis volume was expected to leak: {:.3}%", 100.0 * dark / lit);
}

/// Mean over texels of |a - b| over the mean of b (rgb).
fn relative_difference(a: &glint::gpu::readback::ImageF32, b: &glint::gpu::readback::ImageF32) -> f64 {
    let (mut diff, mut sum) = (0.0f64, 0.0f64);
    for (p, q) in a.data.iter().zip(&b.data) {
        for c in 0..3 {
            diff += f64::from((p[c] - q[c]).abs());
            sum += f64::from(q[c]);
        }
    }
    diff / sum.max(1e-30)
}

/// Frames for hybrid-gi's volume to follow a light: the three lights of
/// moving-lights.ron (120 degrees apart) stand still until the volume has
/// converged, then jump 60 degrees on (1 s of their orbit), as far from
/// where they were as they get. Each frame after the jump the volume is
/// compared with one converged with the lights there: the frames until the
/// difference is a tenth, and a twentieth, of what it was at the jump.
#[test]
fn ddgi_follows_a_moving_light_within_a_bounded_number_of_frames() {
    let Some(gpu) = gpu() else { return };
    let graph = repo().join("passes/hybrid-gi.ron");
    let options = CompileOptions { output: Some("ddgi_irradiance".into()), ..Default::default() };
    let converged_at = |t: f32, seed: u32| {
        let scene = load_scene("moving-lights.ron");
        let g = compile(&scene, &graph, &options);
        let mut s = session(gpu, scene, &g, (8, 8), seed);
        for _ in 0..257 {
            s.frame(t);
        }
        s
    };
    let target = converged_at(1.0, 1).read_output().unwrap_or_else(|e| panic!("{e}"));
    // Two converged volumes differ by their noise: the floor.
    let floor = relative_difference(&converged_at(1.0, 2).read_output().unwrap_or_else(|e| panic!("{e}")), &target);
    let mut s = converged_at(0.0, 1);
    let at_jump = relative_difference(&s.read_output().unwrap_or_else(|e| panic!("{e}")), &target);
    let mut errors = Vec::new();
    for _ in 0..120 {
        s.frame(1.0);
        errors.push(relative_difference(&s.read_output().unwrap_or_else(|e| panic!("{e}")), &target) / at_jump);
    }
    let within = |share: f64| errors.iter().position(|&e| e <= share).map_or(usize::MAX, |i| i + 1);
    eprintln!(
        "follow: the volume differs by {:.1}% at the jump (two converged volumes: {:.1}%); half of that left after {} frames, a quarter after {}, a tenth after {}",
        100.0 * at_jump,
        100.0 * floor,
        within(0.5),
        within(0.25),
        within(0.1)
    );
    assert!(at_jump > 4.0 * floor, "the jump should change the volume well beyond its noise: {at_jump} vs {floor}");
    assert!(within(0.5) <= 20 && within(0.25) <= 40, "the volume follows too slowly: {errors:?}");
}

/// The shaders' maps and grid (shaders/shared/probes.wgsl) against their
/// Rust mirrors (src/probes/), on the axes, the diagonals, a spiral of
/// directions, points in and around the grid and a NaN point.
#[test]
fn the_gpu_maps_and_grid_match_the_rust_mirror() {
    use glam::Vec3;
    use glint::probes::mapping::{hemisphere_bucket, oct_encode};
    let Some(gpu) = gpu() else { return };
    let scene = load_scene("cornell.ron");
    let g = compile(&scene, &repo().join("tests/graphs/probes.ron"), &CompileOptions::default());
    let mut s = session(gpu, scene, &g, (8, 8), 1);
    s.frame(0.0);
    let out = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    let grid = s.scene.probe_grid(s.executor.schedule.probes).expect("a grid");
    let count = out.width as usize;
    let dir = |i: usize| -> Vec3 {
        if i < 26 {
            let k = if i >= 13 { i + 1 } else { i } as i32;
            return Vec3::new((k % 3 - 1) as f32, ((k / 3) % 3 - 1) as f32, (k / 9 - 1) as f32).normalize();
        }
        let (j, n) = ((i - 26) as f32, (count - 26) as f32);
        let z = 1.0 - (2.0 * j + 1.0) / n;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = j * 2.399_963_2;
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    let point = |i: usize| -> Vec3 {
        if i == 0 {
            return Vec3::NAN;
        }
        let t = i as f32 / count as f32;
        let n = grid.counts.x as f32;
        let lo = grid.origin - grid.spacing * n;
        let span = 3.0 * grid.spacing * n;
        lo + span * Vec3::new(t, t * 7.0, t * 13.0).fract()
    };
    let (mut texel_misses, mut cell_misses) = (Vec::new(), Vec::new());
    let mut worst_oct = 0.0f32;
    for i in 0..count {
        let d = dir(i);
        let (upper, u, v) = hemisphere_bucket(d, 5);
        let gpu_t = out.data[i];
        let want = ((u + if upper { 0 } else { 5 }) as f32, v as f32);
        if (gpu_t[0], gpu_t[1]) != want {
            texel_misses.push((i, d, want, (gpu_t[0], gpu_t[1])));
        }
        let e = out.data[count + i];
        let rust_e = oct_encode(d);
        worst_oct = worst_oct.max((rust_e.x - e[0]).abs()).max((rust_e.y - e[1]).abs()).max(e[2]);
        let (base, f) = grid.cell(point(i));
        let (gb, gf) = (out.data[2 * count + i], out.data[3 * count + i]);
        let base_ok = base.as_vec3() == Vec3::new(gb[0], gb[1], gb[2]);
        let f_ok = (f - Vec3::new(gf[0], gf[1], gf[2])).abs().max_element() < 1e-4;
        if !(base_ok && f_ok) {
            cell_misses.push((i, point(i), base, f, gb, gf));
        }
    }
    // A direction on a bucket's edge may round either way on either side.
    assert!(texel_misses.len() <= 2, "hemisphere texels differ: {texel_misses:?}");
    assert!(worst_oct < 1e-5, "octahedral encoding or round trip off by {worst_oct}");
    assert!(cell_misses.is_empty(), "cells differ: {cell_misses:?}");
}

/// A flat scene: one quad in y = -1, a point light above it (issue 40).
const FLAT: &str = r#"Scene(
    camera: Camera(position: (0.0, 2.0, 3.0), target: (0.0, -1.0, 0.0), vfov_deg: 50.0),
    materials: { "white": Material(albedo: (0.8, 0.8, 0.8)) },
    objects: [ Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, 1.0), (1.0, -1.0, -1.0)], material: "white") ],
    lights: [ PointLight(position: (0.0, 0.0, 0.0), intensity: (1.0, 1.0, 1.0)) ],
)"#;

fn mean_of(graph: &str, scene: &str, frames: u32) -> f64 {
    mean_rgb(&render(gpu().expect("gpu"), scene_from(scene), &repo().join(graph), (24, 24), frames, None))
}

/// The volume of a flat scene lit by a point light: a probe layer above
/// the plane (not a grid of zero thickness on it), holding the point
/// light (a delta no probe ray finds) in the bucket it lies in. Before,
/// the image's mean was 1.2e-4 against direct light's 0.112 (issue 40).
#[test]
fn a_flat_scene_lit_by_a_point_light_has_its_light_in_the_volume() {
    if gpu().is_none() {
        return;
    }
    let direct = mean_of("passes/direct.ron", FLAT, 4);
    let volume = mean_of("passes/irradiance.ron", FLAT, 17);
    eprintln!("flat scene: direct.ron mean {direct:.5}, irradiance.ron {volume:.5}");
    assert!(direct > 0.01, "{direct}");
    assert!((volume / direct - 1.0).abs() < 0.08, "irradiance.ron's mean {volume:.5} against direct.ron's {direct:.5}");
}
