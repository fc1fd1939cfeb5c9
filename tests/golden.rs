//! Golden images: every pass of every shipped graph, rendered small on the
//! GPU (lavapipe in CI) and compared with FLIP against tests/golden/.
//! GLINT_BLESS=1 rewrites the goldens; a missing golden fails under CI=true
//! and is written otherwise. On failure, `-actual.png` and `-diff.png` land
//! in target/golden/.

mod common;

use common::*;
use glint::gpu::readback::ImageF32;
use glint::graph::edit::{GraphEdits, ParamSet};
use glint::graph::{self, CompileOptions};
use glint::image_io;
use glint::metrics;
use std::f32::consts::PI;
use std::path::Path;

const SIZE: (u32, u32) = (64, 64);
const FRAMES: u32 = 4;
const MAX_MEAN: f32 = 0.02;
const MAX_P99: f32 = 0.2;

/// Maps a resource to something a PNG can show.
fn visualize(resource: &str, mut img: ImageF32) -> ImageF32 {
    for p in &mut img.data {
        match resource {
            "gbuf_pos" | "gbuf_normal" | "bench_hit" | "bench_normal" => {
                for c in p.iter_mut().take(3) {
                    *c = image_io::srgb_to_linear((*c * 0.5 + 0.5).clamp(0.0, 1.0));
                }
                p[3] = 1.0;
            }
            // What the textures multiply the base colour by (unorm16
            // pairs; the u32s arrive as f32, exact in their high halves).
            "gbuf_material" => {
                let lo = |v: f32| (v as u32 & 0xffff) as f32 / 65535.0;
                let hi = |v: f32| (v as u32 >> 16) as f32 / 65535.0;
                *p = [lo(p[0]), hi(p[0]), lo(p[1]), 1.0];
            }
            "gbuf_id" => {
                let (m, o) = (p[0] as u32, p[1] as u32);
                let h = |x: u32, k: u32| (x.wrapping_mul(2654435761).wrapping_add(k) >> 24) as f32 / 255.0;
                *p = if o == u32::MAX { [0.0; 4] } else { [h(m, 1), h(o, 2), h(m ^ o, 3), 1.0] };
            }
            // Distances (inf on a miss), occlusion and bounce distances.
            "bench_out" => *p = [p[0] / 8.0, p[1], p[2] / 8.0, 1.0],
            // Hit records: distance / 8 and the barycentrics (the
            // primitive in w left out).
            "bench_query" => *p = [p[0] / 8.0, p[1], p[2], 1.0],
            // Octahedral normal, distance / 8, sample count / frames.
            "accum_geo" => *p = [p[0] * 0.5 + 0.5, p[1] * 0.5 + 0.5, p[2] / 8.0, 1.0],
            // The sample count (a) over the frames rendered; the Kahan
            // compensation (rgb, f32 bits) is rounding noise by definition,
            // not an image: any change of arithmetic reshuffles it.
            "accum_comp" => {
                let v = p[3] / FRAMES as f32;
                *p = [v, v, v, 1.0];
            }
            // Irradiance as the radiance of a white diffuse surface.
            "thesis_irradiance" => *p = [p[0] / PI, p[1] / PI, p[2] / PI, 1.0],
            // The bake's radiance, and its path count over 256 in alpha.
            "thesis_radiance" => p[3] = 1.0,
            "ddgi_irradiance" => *p = [p[0] / PI, p[1] / PI, p[2] / PI, 1.0],
            // Rays: radiance (distance and direction rows shown as colour).
            "ddgi_rays" => *p = [p[0], p[1], p[2], 1.0],
            // Mean distance and its square over 4 (the Cornell box's scale).
            "ddgi_distance" => *p = [p[0] / 2.0, p[1] / 4.0, 0.0, 1.0],
            // Offset (x, y, z) from the grid point, scaled, and on/off.
            "ddgi_state" => *p = [p[0] * 2.0 + 0.5, p[1] * 2.0 + 0.5, p[2] * 2.0 + 0.5, 1.0],
            // Edge strengths and the mask: one channel shown grey.
            "edges" | "edges_h" | "edges_blur" | "mask" => *p = [p[0], p[0], p[0], 1.0],
            // The real-time denoiser's history and steps (realtime.ron):
            // their colours as they are; w holds a count, a moment or a
            // variance, left out.
            // Temporal gradients: zero in still frames (the goldens').
            "gradient" => *p = [p[0], p[1], 0.0, 1.0],
            "rt_illum" | "rt_color" | "rt_albedo" | "filt_in" | "filt_0" | "filt_1" | "filt_2" | "filt_3" | "filt_4" => p[3] = 1.0,
            "rt_geo" => *p = [p[0] * 0.5 + 0.5, p[1] * 0.5 + 0.5, p[2] / 8.0, 1.0],
            // The real-time path pass's first hit position (f32 bits) and
            // sample (shared/realtime_common.wgsl, pack_sample): the
            // sample's green channel, grey (the u32s arrive as f32, which
            // keeps the exponent and green and blue mantissas exact, not red).
            "gbuf_sample" | "gbuf_sample_di" => {
                let w = p[3] as u32;
                let e = (w >> 24) as i32;
                let g = if e >= 8 { ((w >> 8) & 0xff) as f32 * 2f32.powi(e - 134) } else { 0.0 };
                *p = [g, g, g, 1.0];
            }
            // f32 bits and a packed normal: shown as which pixels the
            // filters treat as a surface (white).
            "guide" => {
                let v = if p[3] as u32 == u32::MAX { 0.0 } else { 1.0 };
                *p = [v, v, v, 1.0];
            }
            // Direct light by resampling (realtime-restir.ron): which
            // pixels have a surface for it (white; the record is f32 bits),
            // and each reservoir's candidate count M (grey, 100 white).
            "di_surface" => {
                let v = if p[0] + p[1] + p[2] > 0.0 { 1.0 } else { 0.0 };
                *p = [v, v, v, 1.0];
            }
            "di_res" | "rt_reservoir" => {
                let v = ((p[0] as u32) >> 20) as f32 / 100.0;
                *p = [v, v, v, 1.0];
            }
            // -1 not specular (black), 0 shaded (grey), 1 reused (white).
            "reflect_reuse" => {
                let v = (p[0] + 1.0) * 0.5;
                *p = [v, v, v, 1.0];
            }
            _ => {}
        }
    }
    img
}

fn check(name: &str, actual: &ImageF32, failures: &mut Vec<String>) {
    let golden = repo().join("tests/golden").join(format!("{name}.png"));
    let out_dir = repo().join("target/golden");
    let bless = std::env::var("GLINT_BLESS").is_ok_and(|v| v == "1");
    if bless || !golden.exists() {
        if !bless && std::env::var("CI").is_ok_and(|v| v == "true") {
            failures.push(format!("{name}: golden {} is missing (run with GLINT_BLESS=1 and commit it)", golden.display()));
            return;
        }
        image_io::save(actual, &golden).unwrap_or_else(|e| panic!("{e}"));
        eprintln!("wrote golden {}", golden.display());
        return;
    }
    let reference = image_io::load(&golden).unwrap_or_else(|e| panic!("{e}"));
    if (reference.width, reference.height) != (actual.width, actual.height) {
        failures.push(format!("{name}: golden is {}x{}, render is {}x{}", reference.width, reference.height, actual.width, actual.height));
        return;
    }
    // Compare what the PNG holds: the actual image quantised the same way.
    let quantised = {
        let path = out_dir.join(format!("{name}-actual.png"));
        image_io::save(actual, &path).unwrap_or_else(|e| panic!("{e}"));
        image_io::load(&path).unwrap_or_else(|e| panic!("{e}"))
    };
    let (stats, diff) = metrics::flip(&reference, &quantised);
    if stats.mean > MAX_MEAN || stats.p99 > MAX_P99 {
        let diff_path = out_dir.join(format!("{name}-diff.png"));
        let _ = image::RgbImage::from_raw(actual.width, actual.height, diff).map(|d| d.save(&diff_path));
        failures.push(format!(
            "{name}: FLIP mean {:.4} (max {MAX_MEAN}), p99 {:.4} (max {MAX_P99}); see {}",
            stats.mean,
            stats.p99,
            diff_path.display()
        ));
    } else {
        let _ = std::fs::remove_file(out_dir.join(format!("{name}-actual.png")));
    }
}

/// Renders every resource every pass of `graph` writes, as that pass left
/// it: a resource a later pass overwrites is rendered with the graph cut
/// after the pass (`stop_after`).
fn golden_graph(graph_file: &str, scene_file: &str, failures: &mut Vec<String>) -> usize {
    golden_variant(&repo().join("passes").join(graph_file), scene_file, "", &[], failures)
}

/// `golden_graph` of the graph at `graph_path` with `--set` edits, the
/// goldens named after its file and `variant`.
fn golden_variant(graph_path: &Path, scene_file: &str, variant: &str, set: &[&str], failures: &mut Vec<String>) -> usize {
    let Some(gpu) = gpu() else { return 0 };
    let graph_file = graph_path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
    let features = load_scene(scene_file).features;
    let set: Vec<ParamSet> = set.iter().map(|s| s.parse().unwrap_or_else(|e| panic!("{e}"))).collect();
    let base = CompileOptions { edits: GraphEdits { set: set.clone(), ..Default::default() }, ..Default::default() };
    let full = graph::load_and_compile(graph_path, &repo().join("shaders"), &features, &base).unwrap_or_else(|e| panic!("{e}"));
    let mut count = 0;
    for pass in &full.schedule.passes {
        for written in &pass.writes {
            let resource = written.split('@').next().unwrap_or(written);
            let last_writer = full.schedule.passes.iter().rev().find(|p| p.writes.iter().any(|w| w.starts_with(&format!("{resource}@"))));
            let stop_after = (last_writer.map(|p| &p.name) != Some(&pass.name)).then(|| pass.name.clone());
            let options = CompileOptions {
                output: Some(resource.to_string()),
                edits: GraphEdits { stop_after, set: set.clone(), ..Default::default() },
                ..Default::default()
            };
            let img = render_with(gpu, load_scene(scene_file), graph_path, SIZE, FRAMES, &options);
            let name = format!(
                "{}{variant}-{}-{}-{resource}",
                graph_file.trim_end_matches(".ron"),
                scene_file.trim_end_matches(".ron"),
                pass.name
            );
            check(&name, &visualize(resource, img), failures);
            count += 1;
        }
    }
    count
}

#[test]
fn golden_images_of_every_pass() {
    let mut failures = Vec::new();
    let mut count = 0;
    for (graph, scene) in [
        ("direct.ron", "cornell.ron"),
        ("direct.ron", "cornell-point.ron"),
        ("direct.ron", "moving-lights.ron"),
        ("bench-rays.ron", "cornell.ron"),
        ("hybrid.ron", "cornell.ron"),
        ("hybrid.ron", "cornell-point.ron"),
        ("hybrid.ron", "moving-lights.ron"),
        ("hybrid-point.ron", "cornell.ron"),
        ("hybrid-point.ron", "moving-lights.ron"),
        ("irradiance.ron", "cornell.ron"),
        ("hybrid-gi.ron", "cornell.ron"),
        ("realtime.ron", "cornell.ron"),
        ("realtime-restir.ron", "moving-lights.ron"),
        // Textures (base colour, alpha mask, normal, metallic-roughness) and
        // glTF's metallic-roughness material.
        ("hybrid.ron", "textured.ron"),
        // An environment light (a map with a sun), no other light.
        ("hybrid.ron", "sky.ron"),
    ] {
        count += golden_graph(graph, scene, &mut failures);
    }
    count += golden_variant(&repo().join("passes/irradiance.ron"), "cornell.ron", "-ddgi", &["probes.mode=ddgi"], &mut failures);
    // pathtrace.ron stores no G-buffer (no pass of it reprojects): its
    // goldens are of the graph with the path tracer that also stores the
    // first hit (pathtrace_gbuffer.wgsl), which leaves every other output
    // as it was.
    let stored = pathtrace_with_gbuffer("golden-first-hit");
    for scene in ["cornell.ron", "textured.ron", "cornell-pbr.ron", "sky.ron"] {
        count += golden_variant(&stored, scene, "", &[], &mut failures);
    }
    // Debug views: passes that run only when their resource is the output;
    // and the bench's query pass, which nothing in its graph reads (the
    // bench keeps it with `also_compute`).
    for (graph, scene, variant, view) in [
        ("irradiance.ron", "cornell.ron", "", "probe_view"),
        ("irradiance.ron", "cornell.ron", "-ddgi", "probe_view"),
        ("bench-rays.ron", "cornell.ron", "", "bench_query"),
    ] {
        let Some(gpu) = gpu() else { break };
        let set: Vec<ParamSet> = if variant == "-ddgi" { vec!["probes.mode=ddgi".parse().unwrap_or_else(|e| panic!("{e}"))] } else { vec![] };
        let options = CompileOptions { output: Some(view.to_string()), edits: GraphEdits { set, ..Default::default() }, ..Default::default() };
        let img = render_with(gpu, load_scene(scene), &repo().join("passes").join(graph), SIZE, FRAMES, &options);
        let name = format!("{}{variant}-{}-{view}", graph.trim_end_matches(".ron"), scene.trim_end_matches(".ron"));
        check(&name, &visualize(view, img), &mut failures);
        count += 1;
    }
    // The real-time graph's first frame, where the variance pass takes
    // the neighbours' spread (at frame 4, above, each pixel's own moments).
    for (resource, stop_after) in [("filt_0", Some("variance")), ("direct_0", Some("variance")), ("output", None)] {
        let Some(gpu) = gpu() else { break };
        let options = CompileOptions { output: Some(resource.to_string()), edits: GraphEdits { stop_after: stop_after.map(String::from), ..Default::default() }, ..Default::default() };
        let img = render_with(gpu, load_scene("cornell.ron"), &repo().join("passes/realtime.ron"), SIZE, 1, &options);
        check(&format!("realtime-first-frame-cornell-{resource}"), &visualize(resource, img), &mut failures);
        count += 1;
    }
    if gpu().is_some() {
        assert!(count >= 90, "expected a golden per pass output, got {count}");
    }
    assert!(failures.is_empty(), "golden mismatches:\n{}", failures.join("\n"));
}
