//! Screen-space reuse in the reflections pass: it changes where colours
//! come from, not the picture, and it does reuse on the Cornell box.

mod common;

use common::*;
use glint::graph::CompileOptions;
use glint::metrics;
use glint::stats::{ReuseShare, REFLECT_REUSE};

fn hybrid_with_reuse(reuse: u32) -> std::path::PathBuf {
    let dir = scratch("reflections");
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
    let Some(gpu) = gpu() else { return };
    let size = (96, 96);
    let with = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(1), size, 32, None);
    let without = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(0), size, 32, None);
    let (flip, _) = metrics::flip(&without, &with);
    assert!(flip.mean < 0.05, "reuse changes the picture: FLIP mean {}", flip.mean);

    let share = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(1), size, 1, Some("reflect_reuse"));
    let ReuseShare { reused, specular } = ReuseShare::of(&share);
    assert!(specular > 100, "the mirror sphere covers {specular} pixels");
    assert!(reused > 0, "no reflection ray was served from screen space");
    eprintln!("reflection rays served from screen space: {reused} of {specular} ({:.1} %)", 100.0 * reused as f64 / specular as f64);
    let off = render(gpu, load_scene("cornell.ron"), &hybrid_with_reuse(0), size, 1, Some("reflect_reuse"));
    assert!(off.data.iter().all(|p| p[0] <= 0.0), "reuse 0 still reused");

    // The stat `glint render` prints: the same record, read back from the
    // full graph with the resource kept out of the texture pool.
    let scene = load_scene("cornell.ron");
    let options = CompileOptions { keep: vec![REFLECT_REUSE.to_string()], ..Default::default() };
    let compiled = glint::graph::load_and_compile(&hybrid_with_reuse(1), &repo().join("shaders"), &scene.features, &options)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut r = session(gpu, scene, &compiled, size, 1);
    r.frame(0.0);
    let kept = r.read_resource(REFLECT_REUSE).expect("kept").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ReuseShare::of(&kept), ReuseShare { reused, specular });
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
