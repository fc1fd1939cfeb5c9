//! Next-event estimation toward one light a bounce, chosen by what each
//! light could bring (NEE_ONE, shaders/shared/light_choice.wgsl), on the
//! GPU path: the path tracer with it converges to the path tracer that
//! samples every light, with lights of every kind and of very different
//! strengths, a surface that faces away from some of them, and a glossy
//! coat whose bounce rays meet the sphere lights (weighed by multiple
//! importance sampling against the choice's probability); and so does
//! the choice through clusters of a scene with more lights than the
//! choice weighs one by one (src/scene/light_clusters.rs).

mod common;

use common::*;
use glint::graph::CompileOptions;
use glint::scene::Scene;

const SIZE: (u32, u32) = (32, 32);
const FRAMES: usize = 256;
const BLOCK: usize = 8;

/// An open corner (floor, back and left walls) under a sky, a sun, a
/// strong and a weak sphere light, a point light behind the left wall's
/// plane and a spot light aimed at the floor.
fn every_kind_of_light() -> Scene {
    scene_from(&every_kind_of_light_text())
}

fn every_kind_of_light_text() -> String {
    String::from(
        r#"Scene(
    camera: Camera(position: (0.0, 1.0, 3.0), target: (0.0, 0.6, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 55.0),
    environment: Environment(color: (0.15, 0.2, 0.3)),
    materials: {
        "white": Material(albedo: (0.7, 0.7, 0.7)),
        "red": Material(albedo: (0.6, 0.1, 0.1)),
        "coat": Material(albedo: (0.2, 0.4, 0.7), specular: 0.5, roughness: 0.3),
    },
    objects: [
        Quad(vertices: [(-2.0, 0.0, -2.0), (-2.0, 0.0, 2.0), (2.0, 0.0, 2.0), (2.0, 0.0, -2.0)], material: "white"),
        Quad(vertices: [(-2.0, 0.0, -2.0), (2.0, 0.0, -2.0), (2.0, 2.5, -2.0), (-2.0, 2.5, -2.0)], material: "white"),
        Quad(vertices: [(-2.0, 0.0, -2.0), (-2.0, 2.5, -2.0), (-2.0, 2.5, 2.0), (-2.0, 0.0, 2.0)], material: "red"),
        Sphere(center: (-0.5, 0.5, -0.5), radius: 0.5, material: "coat"),
        Sphere(center: (0.8, 0.35, 0.2), radius: 0.35, material: "white"),
    ],
    lights: [
        SphereLight(center: (0.6, 1.8, -1.0), radius: 0.3, radiance: (30.0, 28.0, 25.0)),
        SphereLight(center: (-1.5, 0.4, 1.0), radius: 0.08, radiance: (5.0, 5.0, 8.0)),
        PointLight(position: (-2.5, 1.5, 0.0), intensity: (4.0, 4.0, 4.0)),
        SpotLight(position: (1.2, 2.2, 0.8), direction: (0.0, -1.0, 0.0), intensity: (6.0, 5.0, 4.0), outer_deg: 30.0),
        DirectionalLight(direction: (0.3, -1.0, -0.4), irradiance: (1.5, 1.4, 1.2)),
    ],
)"#,
    )
}

/// passes/pathtrace.ron choosing one light a bounce, in a scratch folder
/// of the test's own (`name`: tests run at once, and one must not read
/// the file while another writes it).
fn pathtrace_one_light(name: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("passes/pathtrace.ron")).expect("read pathtrace.ron");
    let from = "constants: { FIRST_HIT: 0 }";
    assert!(text.contains(from), "pathtrace.ron no longer has `{from}`");
    let path = scratch(&format!("light-choice-{}", name.replace(' ', "-"))).join("pathtrace.ron");
    std::fs::write(&path, text.replace(from, "constants: { FIRST_HIT: 0, NEE_ONE: 1 }")).expect("write the graph");
    path
}

/// Each frame's sample (`radiance`), as the mean luminance of each
/// BLOCK x BLOCK block.
fn block_samples(gpu: &glint::gpu::Gpu, scene: Scene, graph: &std::path::Path, frames: usize) -> Vec<Vec<f64>> {
    let options = CompileOptions { keep: vec!["radiance".to_string()], ..Default::default() };
    let compiled = compile(&scene, graph, &options);
    let mut s = session(gpu, scene, &compiled, SIZE, 1);
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    (0..frames)
        .map(|_| {
            s.frame(0.0);
            let img = s.read_resource("radiance").expect("kept").unwrap_or_else(|e| panic!("{e}"));
            let mut blocks = vec![0.0; (w / BLOCK) * (h / BLOCK)];
            for (i, p) in img.data.iter().enumerate() {
                let (x, y) = (i % w, i / w);
                blocks[(y / BLOCK) * (w / BLOCK) + x / BLOCK] += luminance(p) / (BLOCK * BLOCK) as f64;
            }
            blocks
        })
        .collect()
}

/// Per block, the mean over frames and its standard error.
fn block_stats(frames: &[Vec<f64>]) -> Vec<(f64, f64)> {
    let n = frames.len() as f64;
    (0..frames[0].len())
        .map(|b| {
            let mean = frames.iter().map(|f| f[b]).sum::<f64>() / n;
            let var = frames.iter().map(|f| (f[b] - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (mean, (var / n).sqrt())
        })
        .collect()
}

/// The block whose two means lie the most standard errors apart, and how
/// many.
fn worst_block(a: &[(f64, f64)], b: &[(f64, f64)]) -> (f64, usize) {
    let mut worst = (0.0f64, 0);
    for (i, ((ma, ea), (mb, eb))) in a.iter().zip(b).enumerate() {
        let z = (ma - mb).abs() / (ea * ea + eb * eb).sqrt().max(1e-9);
        if z > worst.0 {
            worst = (z, i);
        }
    }
    worst
}

#[test]
fn one_light_chosen_by_what_it_brings_keeps_the_mean_of_every_light() {
    let Some(gpu) = gpu() else { return };
    let one = block_stats(&block_samples(gpu, every_kind_of_light(), &pathtrace_one_light("kinds"), FRAMES));
    let every = block_stats(&block_samples(gpu, every_kind_of_light(), &repo().join("passes/pathtrace.ron"), FRAMES));
    let (worst, at) = worst_block(&one, &every);
    let (t1, t_all) = (one.iter().map(|s| s.0).sum::<f64>(), every.iter().map(|s| s.0).sum::<f64>());
    eprintln!(
        "{FRAMES} frames: mean luminance {:.5} with one light chosen a bounce, {:.5} with every light; worst block {at} at {worst:.2} standard errors",
        t1 / one.len() as f64,
        t_all / every.len() as f64
    );
    // Sixteen blocks: 4.5 standard errors is far beyond chance for any of
    // them; a choice whose weights or MIS probabilities were wrong moves
    // whole blocks by tens of them.
    assert!(worst < 4.5, "block {at}: {:?} with one light chosen against {:?} with every light ({worst:.2} standard errors)", one[at], every[at]);
    assert!((t1 / t_all - 1.0).abs() < 0.01, "the image's mean {t1} against {t_all}");
}

/// A box lit by 257 point lights of three strengths, 0.6 under its ceiling
/// (nearer, the rare choice of the nearest light makes a heavy tail):
/// more than light_choice.wgsl weighs one by one, so the choice goes
/// through clusters (src/scene/light_clusters.rs).
fn clustered_lights() -> Scene {
    let mut lights = String::new();
    for i in 0..257 {
        let (x, z) = (-0.9 + 1.8 * ((i % 17) as f64) / 16.0, -0.9 + 1.8 * ((i / 17) as f64) / 15.0);
        let k = [0.02, 0.1, 0.5][i % 3];
        lights += &format!("PointLight(position: ({x:.3}, 0.4, {z:.3}), intensity: ({k}, {k}, {k})),\n");
    }
    scene_from(&format!(
        r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.4), target: (0.0, 0.0, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 40.0),
    materials: {{ "white": Material(albedo: (0.7, 0.7, 0.7)) }},
    objects: [
        Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, 1.0), (1.0, -1.0, -1.0)], material: "white"),
        Quad(vertices: [(-1.0, 1.0, -1.0), (1.0, 1.0, -1.0), (1.0, 1.0, 1.0), (-1.0, 1.0, 1.0)], material: "white"),
        Quad(vertices: [(-1.0, -1.0, -1.0), (1.0, -1.0, -1.0), (1.0, 1.0, -1.0), (-1.0, 1.0, -1.0)], material: "white"),
        Sphere(center: (0.0, -0.6, 0.0), radius: 0.4, material: "white"),
    ],
    lights: [
{lights}    ],
)"#
    ))
}

#[test]
fn lights_chosen_through_clusters_keep_the_mean() {
    let Some(gpu) = gpu() else { return };
    assert_one_light_keeps_the_mean(gpu, clustered_lights, "257 lights", 64);
}

/// pathtrace.ron choosing one light a bounce against every light, each
/// for `frames` frames of `scene`: every block's mean within 4.5
/// standard errors.
fn assert_one_light_keeps_the_mean(gpu: &glint::gpu::Gpu, scene: fn() -> Scene, what: &str, frames: usize) {
    let one = block_stats(&block_samples(gpu, scene(), &pathtrace_one_light(what), frames));
    let every = block_stats(&block_samples(gpu, scene(), &repo().join("passes/pathtrace.ron"), frames));
    let (worst, at) = worst_block(&one, &every);
    eprintln!("{what}, {frames} frames: worst block {at} at {worst:.2} standard errors");
    assert!(worst < 4.5, "{what}, block {at}: {:?} with one light chosen against {:?} with every light ({worst:.2} standard errors)", one[at], every[at]);
}

/// every_kind_of_light's scene with 80 more small lights, sphere, point
/// and spot lights in turn, on a grid under its top: the sky and the sun
/// become clusters of their own, and the coat's bounce rays meet sphere
/// lights of every cluster (their MIS probability through the clusters).
fn every_kind_in_clusters() -> Scene {
    let base = every_kind_of_light_text();
    let mut more = String::new();
    for i in 0..80 {
        let (x, z) = (-1.8 + 3.6 * ((i % 10) as f64) / 9.0, -1.8 + 3.6 * ((i / 10) as f64) / 7.0);
        more += &match i % 3 {
            0 => format!("SphereLight(center: ({x:.3}, 2.2, {z:.3}), radius: 0.15, radiance: (4.0, 3.6, 3.0)),\n"),
            1 => format!("PointLight(position: ({x:.3}, 2.0, {z:.3}), intensity: (0.3, 0.3, 0.4)),\n"),
            _ => format!("SpotLight(position: ({x:.3}, 2.1, {z:.3}), direction: (0.1, -1.0, 0.0), intensity: (0.5, 0.4, 0.3), outer_deg: 40.0),\n"),
        };
    }
    let at = base.find("    lights: [\n").expect("the scene's lights") + "    lights: [\n".len();
    scene_from(&format!("{}{more}{}", &base[..at], &base[at..]))
}

#[test]
fn every_kind_of_light_in_clusters_keeps_the_mean() {
    let Some(gpu) = gpu() else { return };
    // (With the MIS probability's share within the cluster left out, a
    // deliberate bug, its worst block lay 5.2 standard errors off at 128
    // frames; hence 256.)
    assert_one_light_keeps_the_mean(gpu, every_kind_in_clusters, "85 lights of every kind", 256);
}

/// A clustered scene with lights at f32's limits: a sphere light of
/// radiance 3e38 and radius 1e-20 and two point lights of intensity 3e38
/// near the floor's far corners, in clusters of their own, among 70
/// ordinary ones: the clusters' bounds and powers are built finite, and
/// realtime.ron's image stays finite.
#[test]
fn clusters_of_extreme_lights_stay_finite() {
    let Some(gpu) = gpu() else { return };
    let mut lights = String::from(
        "SphereLight(center: (0.2, 0.5, 0.0), radius: 1e-20, radiance: (3e38, 3e38, 3e38)),\n\
         PointLight(position: (-0.8, -0.7, -0.8), intensity: (3e38, 3e38, 3e38)),\n\
         PointLight(position: (0.8, -0.7, 0.8), intensity: (3e38, 3e38, 3e38)),\n",
    );
    for i in 0..70 {
        let (x, z) = (-0.9 + 1.8 * ((i % 10) as f64) / 9.0, -0.9 + 1.8 * ((i / 10) as f64) / 6.0);
        lights += &format!("PointLight(position: ({x:.3}, 0.8, {z:.3}), intensity: (0.05, 0.05, 0.05)),\n");
    }
    let scene = scene_from(&format!(
        r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.4), target: (0.0, 0.0, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 40.0),
    materials: {{ "white": Material(albedo: (0.7, 0.7, 0.7)) }},
    objects: [
        Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, 1.0), (1.0, -1.0, -1.0)], material: "white"),
        Quad(vertices: [(-1.0, -1.0, -1.0), (1.0, -1.0, -1.0), (1.0, 1.0, -1.0), (-1.0, 1.0, -1.0)], material: "white"),
    ],
    lights: [
{lights}    ],
)"#
    ));
    let img = render(gpu, scene, &repo().join("passes/realtime.ron"), (32, 32), 4, None);
    let bad = img.data.iter().filter(|p| !p.iter().all(|c| c.is_finite())).count();
    assert_eq!(bad, 0, "{bad} pixels not finite");
}
