//! Specialisation (issue 14): shaders compiled for what a scene has give
//! the same image as the generic shaders, on every shipped scene; and the
//! constants do reach the shaders (a wrong specialisation changes it).

mod common;

use common::*;
use glint::graph::{self, CompileOptions};
use glint::metrics::flip;

const SIZE: (u32, u32) = (32, 32);
const FRAMES: u32 = 2;

fn shipped_scenes() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(repo().join("scenes"))
        .expect("scenes/")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".ron"))
        .filter(|n| !asset_not_fetched(n))
        .collect();
    names.sort();
    names
}

/// Whether scene `name` is one whose asset a script fetches (it says
/// `tools/fetch-...`, as scenes/dungeon.ron does) and that asset's file
/// cannot be read: the repository does not hold such assets, so a fresh
/// clone skips them. Any other error still fails the test.
fn asset_not_fetched(name: &str) -> bool {
    let path = repo().join("scenes").join(name);
    let fetched = std::fs::read_to_string(&path).is_ok_and(|t| t.contains("tools/fetch-"));
    let missing = fetched && glint::scene::load(&path).is_err_and(|e| ["not found", "cannot read"].iter().any(|m| e.to_string().contains(m)));
    if missing {
        eprintln!("{name}: its asset is not fetched; skipped");
    }
    missing
}

#[test]
fn specialised_shaders_render_what_generic_ones_do_on_every_shipped_scene() {
    let Some(gpu) = gpu() else { return };
    let generic = CompileOptions { no_specialise: true, ..Default::default() };
    let mut specialised_somewhere = false;
    // hybrid-gi holds every pass of the hybrids; the path tracer the rest.
    for graph in ["passes/hybrid-gi.ron", "passes/pathtrace.ron"] {
        for name in shipped_scenes() {
            let path = repo().join(graph);
            let special = compile(&load_scene(&name), &path, &CompileOptions::default());
            specialised_somewhere |= !special.schedule.specialisations.is_empty();
            let a = render_compiled(gpu, load_scene(&name), &special, SIZE, FRAMES);
            let b = render_with(gpu, load_scene(&name), &path, SIZE, FRAMES, &generic);
            let (stats, _) = flip(&b, &a);
            assert!(stats.mean < 1e-4, "{graph} on {name}: specialised against generic, FLIP {}", stats.mean);
        }
    }
    assert!(specialised_somewhere, "no shipped scene was specialised: the test compares nothing");
}

#[test]
fn a_wrong_specialisation_changes_the_image() {
    let Some(gpu) = gpu() else { return };
    // The Cornell box has a mirror sphere; shaders told there is no
    // specular surface shade it as diffuse.
    let scene = load_scene("cornell.ron");
    let mut features = scene.features;
    assert!(features.specular);
    features.specular = false;
    let path = repo().join("passes/pathtrace.ron");
    let wrong = graph::load_and_compile(&path, &repo().join("shaders"), &features, &CompileOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(wrong.schedule.specialisations.iter().any(|s| s.constant == "SCENE_SPECULAR" && !s.value));
    let a = render_compiled(gpu, scene, &wrong, SIZE, FRAMES);
    let b = render(gpu, load_scene("cornell.ron"), &path, SIZE, FRAMES, None);
    let (stats, _) = flip(&b, &a);
    assert!(stats.mean > 0.01, "SCENE_SPECULAR = false did not reach the shader: FLIP {}", stats.mean);
}

#[test]
fn graph_constants_win_over_specialisation() {
    // A graph that sets a specialisation constant itself keeps its value.
    let scene = load_scene("cornell-diffuse.ron");
    let text = std::fs::read_to_string(repo().join("passes/pathtrace.ron")).expect("pathtrace.ron");
    let text = text.replacen("constants: { FIRST_HIT: 0 }", "constants: { FIRST_HIT: 0, SCENE_SPECULAR: 1 }", 1);
    assert!(text.contains("SCENE_SPECULAR"), "pathtrace.ron no longer has `constants: {{ FIRST_HIT: 0 }}`");
    let dir = scratch("specialise-constants");
    let path = dir.join("pathtrace.ron");
    std::fs::write(&path, text).expect("write");
    let g = graph::load_and_compile(&path, &repo().join("shaders"), &scene.features, &CompileOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let pass = &g.schedule.passes[0];
    assert_eq!(pass.constants, [("FIRST_HIT".to_string(), 0.0), ("SCENE_SPECULAR".to_string(), 1.0)]);
    let shader = &g.shaders[&pass.shader];
    let mut engine = vec![];
    engine.extend(g.schedule.specialisations.iter().map(|s| s.as_constant()));
    let got = graph::pipelines::pass_constants(pass, shader, &engine);
    assert!(got.contains(&("SCENE_SPECULAR".to_string(), 1.0)), "{got:?}");
    assert!(got.contains(&("SCENE_POINT_LIGHTS".to_string(), 0.0)), "{got:?}");
}

/// realtime.ron's temporal pass runs a pipeline per kind of frame
/// (src/graph/frame_kind.rs): a first frame's without history, a still
/// camera's that takes each pixel's own texel instead of reprojecting, a
/// still scene's without the gradients' tests. The same image as the
/// generic pipeline's, with the scene still and with its lights moving.
#[test]
fn the_denoisers_per_frame_pipelines_give_the_generic_image() {
    let Some(gpu) = gpu() else { return };
    let path = repo().join("passes/realtime.ron");
    let generic = CompileOptions { no_specialise: true, ..Default::default() };
    for (name, dt) in [("cornell.ron", 0.0), ("moving-lights.ron", 1.0 / 30.0)] {
        let images: Vec<_> = [CompileOptions::default(), generic.clone()]
            .iter()
            .map(|options| {
                let compiled = compile(&load_scene(name), &path, options);
                let mut s = session(gpu, load_scene(name), &compiled, SIZE, 1);
                for _ in 0..6 {
                    s.frame(dt);
                }
                s.read_output().unwrap_or_else(|e| panic!("{e}"))
            })
            .collect();
        let (stats, _) = flip(&images[1], &images[0]);
        assert!(stats.mean < 1e-4, "realtime.ron on {name}: per-frame pipelines against generic, FLIP {}", stats.mean);
    }
}

/// realtime.ron's wide à-trous steps filter two pixels an invocation
/// (`main_pairs`, `last_split_pairs`: the two windows share six texels):
/// the image is the one-pixel entries' bit for bit, at sizes whose rows
/// end in a pixel without its pair, in still frames and in motion.
#[test]
fn paired_filter_steps_make_the_one_pixel_steps_image() {
    let Some(gpu) = gpu() else { return };
    const PAIRS: &str = "_pairs\", texels_per_invocation: 2,";
    let text = std::fs::read_to_string(repo().join("passes/realtime.ron")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(text.matches(PAIRS).count(), 3, "realtime.ron's wide steps no longer run in pairs as this test expects");
    let single = scratch("pairs").join("realtime.ron");
    std::fs::write(&single, text.replace(PAIRS, "\",")).unwrap_or_else(|e| panic!("{e}"));
    for (name, size, dt) in [("cornell.ron", (37, 29), 0.0), ("moving-lights.ron", (50, 21), 1.0 / 30.0)] {
        let images: Vec<_> = [repo().join("passes/realtime.ron"), single.clone()]
            .iter()
            .map(|graph| {
                let compiled = compile(&load_scene(name), graph, &CompileOptions::default());
                let mut s = session(gpu, load_scene(name), &compiled, size, 1);
                for _ in 0..4 {
                    s.frame(dt);
                }
                s.read_output().unwrap_or_else(|e| panic!("{e}"))
            })
            .collect();
        assert!(images[0].data == images[1].data, "{name} at {size:?}: the paired steps' image differs from the one-pixel steps'");
    }
}

/// Sessions whose frames are watched or timed dispatch every pipeline once
/// with no workgroups before the first frame (`warm_pipelines`: a driver
/// that compiles at the first dispatch then does not stall the first frame
/// of each kind). The dispatches write nothing: the images are the same bit
/// for bit, through the thinned still frames, in motion, and on a graph
/// whose passes bake a volume and list their work.
#[test]
fn warming_the_pipelines_changes_no_image() {
    let Some(gpu) = gpu() else { return };
    for (graph, name, frames, dt) in [
        ("realtime.ron", "cornell.ron", 11, 0.0),
        ("realtime.ron", "moving-lights.ron", 4, 1.0 / 30.0),
        ("hybrid-gi.ron", "cornell.ron", 3, 0.0),
    ] {
        let images: Vec<_> = [false, true]
            .iter()
            .map(|&warm| {
                let scene = load_scene(name);
                let compiled = compile(&scene, &repo().join("passes").join(graph), &CompileOptions::default());
                let options = glint::session::SessionOptions { warm_pipelines: warm, ..glint::session::SessionOptions::new(SIZE) };
                let mut s = glint::session::Session::with_graph(gpu, scene, compiled, repo().join("shaders"), options).unwrap_or_else(|e| panic!("{e}"));
                for k in 0..frames {
                    s.frame(k as f32 * dt);
                }
                s.read_output().unwrap_or_else(|e| panic!("{e}"))
            })
            .collect();
        assert!(images[0].data == images[1].data, "{graph} on {name}: the image differs once the pipelines were warmed");
    }
}
