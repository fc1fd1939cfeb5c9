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

/// `ThinWhenStill(after, every)`: every frame until the image has stood
/// still `after` frames, then one in `every`; every frame while the
/// camera moves; and in a frame shown in full.
#[test]
fn thin_when_still_runs_one_still_frame_in_every() {
    let Some(gpu) = gpu() else { return };
    let g = compile_variant("thin", "run: Once,", "run: ThinWhenStill(after: 2, every: 3),").unwrap_or_else(|e| panic!("{e}"));
    let scene = load_scene("cornell.ron");
    let mut s = session(gpu, scene, &g, (4, 4), 1);
    let mut seen = Vec::new();
    for _ in 0..8 {
        s.frame(0.0);
        seen.push(counters(&s)[1][0]);
    }
    // Still frames 0..7: it runs in 0, 1 (before `after`), 3 and 6.
    assert_eq!(seen, [1.0, 2.0, 2.0, 3.0, 3.0, 3.0, 4.0, 4.0]);
    s.show_next_in_full();
    s.frame(0.0);
    assert_eq!(counters(&s)[1][0], 5.0, "a frame shown in full");
    s.frame(0.0);
    assert_eq!(counters(&s)[1][0], 6.0, "still frame 9");
    s.frame(0.0);
    assert_eq!(counters(&s)[1][0], 6.0, "still frame 10 thins again");
    // A camera that moves every frame restarts the count every frame.
    for k in 0..3 {
        s.scene.scene.camera.position.x += 0.01 * (k + 1) as f64;
        s.frame(0.0);
    }
    assert_eq!(counters(&s)[1][0], 9.0, "a moving camera");
}

/// runs.ron with each (from, to) replaced, compiled.
fn compile_edited(name: &str, edits: &[(&str, &str)]) -> Result<glint::graph::CompiledGraph, String> {
    let mut text = std::fs::read_to_string(runs_graph()).expect("runs.ron");
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    let path = scratch("run-variants").join(format!("{name}.ron"));
    std::fs::write(&path, text).expect("write");
    let scene = load_scene("cornell.ron");
    glint::graph::load_and_compile(&path, &repo().join("shaders"), &scene.features, &CompileOptions::default()).map_err(|e| e.to_string())
}

#[test]
fn thinned_passes_write_only_what_passes_of_their_run_read() {
    const THIN: &str = "run: ThinWhenStill(after: 2, every: 3), dispatch: Fixed(4, 1),";
    const ROW: &str = "size: Fixed(4, 1))";
    let e = compile_edited("thin-every-0", &[("run: Once,", "run: ThinWhenStill(after: 2, every: 0),")]).unwrap_err();
    assert!(e.contains("every: 0") && e.contains(".ron:"), "{e}");
    // The output is kept through the frames the pass skips: persistent.
    let e = compile_edited("thin-output", &[("dispatch: Fixed(4, 1),", THIN)]).unwrap_err();
    assert!(e.contains("pass `gather`") && e.contains("`row`, which is not persistent") && e.contains("other than the output"), "{e}");
    compile_edited("thin-output-kept", &[("dispatch: Fixed(4, 1),", THIN), (ROW, "size: Fixed(4, 1), persistent: true)")]).unwrap_or_else(|e| panic!("{e}"));
    // A transient it writes may be read by passes of its own run only:
    // `first` gathers the counters into `t`, which `second` copies out.
    let graph = |second_run: &str, out: &str| {
        format!(
            r#"FrameGraph(
    name: "thin",
    resources: {{
        "every": Texture(format: Rgba32Float, size: Fixed(1, 1), persistent: true),
        "t": Texture(format: Rgba32Float, size: Fixed(4, 1)),
        "row": Texture(format: Rgba32Float, size: Fixed(4, 1){out}),
    }},
    passes: [
        Pass(name: "every", shader: "test_runs.wgsl", entry: "count", bind: {{ "counter": "every" }}),
        Pass(name: "first", shader: "test_runs.wgsl", entry: "gather", run: ThinWhenStill(after: 2, every: 3), dispatch: Fixed(4, 1),
             bind: {{ "a": "every", "b": "every", "c": "every", "d": "every", "row": "t" }}),
        Pass(name: "second", shader: "test_runs.wgsl", entry: "gather", {second_run} dispatch: Fixed(4, 1),
             bind: {{ "a": "t", "b": "every", "c": "every", "d": "every" }}),
    ],
    output: "row",
)"#
        )
    };
    let compile_text = |name: &str, text: String| {
        let path = scratch("run-variants").join(format!("{name}.ron"));
        std::fs::write(&path, text).expect("write");
        let scene = load_scene("cornell.ron");
        glint::graph::load_and_compile(&path, &repo().join("shaders"), &scene.features, &CompileOptions::default()).map_err(|e| e.to_string())
    };
    let e = compile_text("thin-transient", graph("", "")).unwrap_err();
    assert!(e.contains("pass `second`") && e.contains("reads `t`, which pass `first` writes") && e.contains(".ron:"), "{e}");
    compile_text("thin-transient-ok", graph("run: ThinWhenStill(after: 2, every: 3),", ", persistent: true")).unwrap_or_else(|e| panic!("{e}"));
}
