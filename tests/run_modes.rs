//! Passes that run when needed (issue 13, engine support): `run: Once |
//! OnSceneChange | EveryFrame | Progressive(per_frame, until)`, persistent
//! resources that keep what such a pass wrote, the `run` uniform, graph
//! `dispatch` sizes and per-pass timings of the passes that ran.
//! tests/graphs/runs.ron gives each mode a counter (shaders/test_runs.wgsl).

mod common;

use common::*;
use glint::graph::executor::Timing;
use glint::graph::CompileOptions;

fn runs_graph() -> std::path::PathBuf {
    repo().join("tests/graphs/runs.ron")
}

/// Per counter (every, once, change, prog): dispatches seen, the last
/// dispatch's iteration, its since_change and its frame's count.
fn counters(s: &glint::session::Session) -> Vec<[f32; 4]> {
    let row = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    row.data[..4].to_vec()
}

#[test]
fn each_mode_runs_as_often_as_it_says() {
    let Some(gpu) = gpu() else { return };
    let scene = load_scene("cornell.ron");
    let g = compile(&scene, &runs_graph(), &CompileOptions::default());
    let mut s = session(gpu, scene, &g, (4, 4), 1);
    for _ in 0..4 {
        s.frame(0.0);
    }
    let c = counters(&s);
    assert_eq!(c[0], [4.0, 3.0, 3.0, 1.0], "every frame");
    assert_eq!(c[1], [1.0, 0.0, 0.0, 1.0], "once");
    assert_eq!(c[2], [1.0, 0.0, 0.0, 1.0], "on scene change, static scene");
    // 3 + 3 + 1 iterations, then done at until = 7.
    assert_eq!(c[3], [7.0, 6.0, 6.0, 1.0], "progressive");

    // A restart (as after set_param) runs them again from the start.
    s.restart();
    s.frame(0.0);
    let c = counters(&s);
    assert_eq!(c[1], [2.0, 0.0, 0.0, 1.0], "once after a restart");
    assert_eq!(c[3], [10.0, 2.0, 2.0, 3.0], "progressive after a restart");
}

#[test]
fn a_moving_scene_reruns_scene_passes_and_restarts_progressive_ones() {
    let Some(gpu) = gpu() else { return };
    let scene = load_scene("moving-lights.ron");
    let g = compile(&scene, &runs_graph(), &CompileOptions::default());
    let mut s = session(gpu, scene, &g, (4, 4), 1);
    for f in 0..4 {
        s.frame(0.1 * f as f32);
    }
    let c = counters(&s);
    assert_eq!(c[1][0], 1.0, "once");
    assert_eq!(c[2], [4.0, 3.0, 0.0, 1.0], "on scene change: every frame the lights move");
    // The count starts over each frame, so it never reaches until = 7.
    assert_eq!(c[3], [12.0, 11.0, 2.0, 3.0], "progressive");
}

#[test]
fn timings_name_only_the_passes_that_ran() {
    let Some(gpu) = gpu() else { return };
    let scene = load_scene("cornell.ron");
    let g = compile(&scene, &runs_graph(), &CompileOptions::default());
    let mut s = session(gpu, scene, &g, (4, 4), 1);
    s.timing = Timing::WallPerPass;
    let names = |t: Vec<glint::graph::executor::PassTimings>| -> Vec<String> { t[0].passes.iter().map(|(n, _)| n.clone()).collect() };
    assert_eq!(names(s.frame(0.0)), ["every", "once", "change", "prog", "gather"]);
    assert_eq!(names(s.frame(0.0)), ["every", "prog", "gather"]);
    s.frame(0.0);
    assert_eq!(names(s.frame(0.0)), ["every", "gather"]);
}

fn compile_variant(name: &str, from: &str, to: &str) -> Result<glint::graph::CompiledGraph, String> {
    let text = std::fs::read_to_string(runs_graph()).expect("runs.ron");
    assert!(text.contains(from), "{from}");
    let path = scratch("run-variants").join(format!("{name}.ron"));
    std::fs::write(&path, text.replace(from, to)).expect("write");
    let scene = load_scene("cornell.ron");
    glint::graph::load_and_compile(&path, &repo().join("shaders"), &scene.features, &CompileOptions::default()).map_err(|e| e.to_string())
}

#[test]
fn run_modes_and_persistent_resources_are_checked() {
    let e = compile_variant("once-transient", r#""once": Texture(format: Rgba32Float, size: Fixed(1, 1), persistent: true)"#, r#""once": Texture(format: Rgba32Float, size: Fixed(1, 1))"#).unwrap_err();
    assert!(e.contains("pass `once`") && e.contains("`once`, which is not persistent") && e.contains(".ron:"), "{e}");
    let e = compile_variant("per-frame-0", "per_frame: 3", "per_frame: 0").unwrap_err();
    assert!(e.contains("between 1 and 64 iterations a frame"), "{e}");
    let e = compile_variant("until-0", "until: 7", "until: 0").unwrap_err();
    assert!(e.contains("never runs"), "{e}");
    let e = compile_variant("both", r#"size: Fixed(1, 1), persistent: true),
        "once""#, r#"size: Fixed(1, 1), persistent: true, history: true),
        "once""#).unwrap_err();
    assert!(e.contains("both `history`") && e.contains(".ron:"), "{e}");
    let e = compile_variant("tiles", "size: Fixed(4, 1))", "size: ProbeTiles(4, 1))").unwrap_err();
    assert!(e.contains("needs the graph's `probes:"), "{e}");
    let e = compile_variant("bad-run", "run: Once,", "run: Sometimes,").unwrap_err();
    assert!(e.contains(".ron:") && e.contains("Sometimes"), "{e}");
}

#[test]
fn probe_tiles_size_an_atlas_and_graph_check_says_when_passes_run() {
    let g = compile_variant(
        "atlas",
        "output: \"row\",",
        "output: \"row\",\n    probes: (mode: Thesis, level: 3),",
    )
    .expect("compiles");
    let text = glint::graph::report::text(&g.schedule, (8, 8));
    for want in ["runs once, after the graph is built", "runs once, then whenever the scene changes", "runs 3 iterations a frame until 7", "runs every frame", "persistent"] {
        assert!(text.contains(want), "`{want}` missing from:\n{text}");
    }
    let tiled = compile_variant("atlas2", "\"row\": Texture(format: Rgba32Float, size: Fixed(4, 1))", "\"row\": Texture(format: Rgba32Float, size: ProbeTiles(4, 1))");
    assert!(tiled.unwrap_err().contains("needs the graph's `probes:"));
    let text = std::fs::read_to_string(runs_graph()).expect("runs.ron");
    let text = text
        .replace("\"row\": Texture(format: Rgba32Float, size: Fixed(4, 1))", "\"row\": Texture(format: Rgba32Float, size: ProbeTiles(3, 2))")
        .replace("output: \"row\",", "output: \"row\",\n    probes: (mode: Ddgi, level: 3),");
    // (Not tiles.ron: the test above writes that one, maybe at the same time.)
    let path = scratch("run-variants").join("ddgi-tiles.ron");
    std::fs::write(&path, text).expect("write");
    let scene = load_scene("cornell.ron");
    let g = glint::graph::load_and_compile(&path, &repo().join("shaders"), &scene.features, &CompileOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    // 4 probes per axis: 16 tiles of 3 across, 4 of 2 down.
    assert_eq!(g.schedule.output_format, glint::format::TexFormat::Rgba32Float);
    let out = g.schedule.textures.iter().find(|t| t.label.starts_with("row")).expect("row texture");
    assert_eq!(out.size.resolve((8, 8)), (48, 8));
}
