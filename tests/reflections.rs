//! Screen-space reuse in the reflections pass: it changes where colours
//! come from, not the picture, and it does reuse on the Cornell box.

mod common;

use common::*;
use glint::graph::CompileOptions;
use glint::metrics;
use glint::stats::{ReuseShare, REFLECT_REUSE};

/// hybrid.ron with `reuse` set, written under a scratch folder named for
/// the test (tests run in parallel in one process).
fn hybrid_with_reuse(reuse: u32, test: &str) -> std::path::PathBuf {
    let dir = scratch(&format!("reflections-{test}"));
    std::fs::create_dir_all(dir.join("passes")).unwrap();
    let text = std::fs::read_to_string(repo().join("passes/hybrid.ron"))
        .unwrap()
        .replace("reuse: 1 }", &format!("reuse: {reuse} }}"));
    let path = dir.join("passes").join(format!("hybrid-reuse{reuse}.ron"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn reuse_matches_tracing_and_is_used() {
    const TEST: &str = "matches";
    let Some(gpu) = gpu() else { return };
    let size = (96, 96);
    let with = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(1, TEST), size, 32, None);
    let without = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(0, TEST), size, 32, None);
    let (flip, _) = metrics::flip(&without, &with);
    assert!(flip.mean < 0.05, "reuse changes the picture: FLIP mean {}", flip.mean);

    let share = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(1, TEST), size, 1, Some("reflect_reuse"));
    let ReuseShare { reused, traced, specular } = ReuseShare::of(&share);
    // (Cornell's mirror sphere is a thesis mirror: every ray is traced.)
    assert_eq!(traced, specular);
    assert!(specular > 100, "the mirror sphere covers {specular} pixels");
    assert!(reused > 0, "no reflection ray was served from screen space");
    eprintln!("reflection rays served from screen space: {reused} of {specular} ({:.1} %)", 100.0 * reused as f64 / specular as f64);
    let off = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(0, TEST), size, 1, Some("reflect_reuse"));
    assert!(off.data.iter().all(|p| p[0] <= 0.0), "reuse 0 still reused");

    // The stat `glint render` prints: the same record, read back from the
    // full graph with the resource kept out of the texture pool.
    let scene = load_scene("cornell.ron");
    let options = CompileOptions { keep: vec![REFLECT_REUSE.to_string()], ..Default::default() };
    let compiled = glint::graph::load_and_compile(&hybrid_with_reuse(1, TEST), &repo().join("shaders"), &scene.features, &options)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut r = session(gpu, scene, &compiled, size, 1);
    r.frame(0.0);
    let kept = r.read_resource(REFLECT_REUSE).expect("kept").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ReuseShare::of(&kept), ReuseShare { reused, traced, specular });
    assert!(r.read_resource("gbuf_id").is_none(), "only kept resources can be read");
}

#[test]
fn no_reflections_pass_without_specular_materials() {
    let (desc, shaders) = {
        let path = repo().join("passes/hybrid.ron");
        let features = load_scene("cornell-diffuse.ron").features;
        let g = glint::graph::load_and_compile(&path, &repo().join("shaders"), &features, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
        (g.schedule, g.shaders.len())
    };
    assert!(shaders > 0);
    assert!(desc.passes.iter().all(|p| p.name != "reflections"));
    assert!(desc.culled.iter().any(|c| c.name == "reflections"));
}

/// A face of an object hidden behind another face of the same object, seen
/// in a mirror: its hit projects onto the pixel of the front face (same
/// object, same normal). Reuse must see that the G-buffer point is not on
/// the hit's plane and trace instead: the front face is unlit (the light is
/// behind it), the hidden one lit.
#[test]
fn reuse_does_not_take_a_hidden_face_of_the_same_object() {
    const TEST: &str = "hidden";
    let Some(gpu) = gpu() else { return };
    let dir = scratch("reflections-hidden");
    std::fs::create_dir_all(&dir).unwrap();
    // Two squares facing +z, one object: z = 0 in front, z = -2 behind it.
    std::fs::write(
        dir.join("faces.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv -1 -1 -2\nv 1 -1 -2\nv 1 1 -2\nv -1 1 -2\nf 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n",
    )
    .unwrap();
    let text = r#"Scene(camera: Camera(position: (0.0, 0.0, 5.0), target: (1.0, 0.0, -1.0), vfov_deg: 60.0),
        materials: { "white": Material(albedo: (0.8, 0.8, 0.8)), "mirror": Material(albedo: (1.0, 1.0, 1.0), specular: 1.0) },
        objects: [
            Mesh(path: "faces.obj", material: "white"),
            Quad(vertices: [(2.35, -0.6, -1.36), (2.65, -0.6, -0.64), (2.65, 0.6, -0.64), (2.35, 0.6, -1.36)], material: "mirror"),
        ],
        lights: [ PointLight(position: (0.0, 0.0, -1.0), intensity: (2.0, 2.0, 2.0)) ])"#;
    let scene = || glint::scene::parse(text, &dir.join("hidden.ron")).unwrap_or_else(|e| panic!("{e}"));
    let size = (64, 64);
    let with = render(gpu, scene(), &hybrid_with_reuse(1, TEST), size, 8, None);
    let without = render(gpu, scene(), &hybrid_with_reuse(0, TEST), size, 8, None);
    let sum = |img: &glint::gpu::readback::ImageF32| img.data.iter().map(|p| f64::from(p[0])).sum::<f64>();
    let (a, b) = (sum(&without), sum(&with));
    eprintln!("hidden face in a mirror: image sum {b:.3} with reuse, {a:.3} traced");
    assert!((b / a - 1.0).abs() < 0.02, "reuse took the front face's colour for the hidden one: {b} against {a}");
    std::fs::remove_dir_all(&dir).ok();
}
