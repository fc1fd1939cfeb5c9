//! Sample loops split across dispatches (issue 16): lavapipe ends every
//! loop of an invocation after 65535 iterations in all, so one dispatch of
//! `pathtrace.spp = 600` came out 41% too dark. The engine now splits a
//! pass's sample count (a params member `X` with a sibling `X_done`) into
//! dispatches of at most `SAMPLES_PER_DISPATCH` (src/graph/compile/split.rs).
//! A pass that renders several texels per invocation
//! (`texels_per_invocation`) renders the same image as one texel each.

mod common;

use common::*;
use glint::graph::desc::ParamValue;
use glint::graph::edit::{GraphEdits, ParamSet};
use glint::graph::{CompileOptions, FLAT_SAMPLES_PER_DISPATCH, SAMPLES_PER_DISPATCH};
use glint::scene::SceneFeatures;
use glint::metrics;

fn with_spp(spp: i64) -> CompileOptions {
    let set = vec![ParamSet { pass: "pathtrace".into(), param: "spp".into(), value: ParamValue::Int(spp) }];
    CompileOptions { edits: GraphEdits { set, ..Default::default() }, ..Default::default() }
}

/// A split pass as the schedule has it: name, entry, spp, spp_done, texels
/// per invocation.
type Dispatch = (String, String, Option<ParamValue>, Option<ParamValue>, u32);

fn graph() -> std::path::PathBuf {
    repo().join("passes/pathtrace.ron")
}

/// The pathtrace dispatches of a compiled graph.
fn dispatches(g: &glint::graph::CompiledGraph) -> Vec<Dispatch> {
    g.schedule
        .passes
        .iter()
        .filter(|p| p.name.starts_with("pathtrace"))
        .map(|p| {
            let params = p.params.as_ref().expect("params");
            (p.name.clone(), p.entry.clone(), params.values.get("spp").cloned(), params.values.get("spp_done").cloned(), p.texels_per_invocation)
        })
        .collect()
}

/// A graph compiled for `features` (shaders from the repo).
fn compile_for(features: &SceneFeatures, graph: &std::path::Path, options: &CompileOptions) -> Result<glint::graph::CompiledGraph, String> {
    glint::graph::load_and_compile(graph, &repo().join("shaders"), features, options).map_err(|e| e.to_string())
}

#[test]
fn a_large_sample_count_becomes_several_dispatches() {
    assert_eq!((SAMPLES_PER_DISPATCH, FLAT_SAMPLES_PER_DISPATCH), (8, 32));
    let scene = load_scene("cornell.ron");
    assert!(scene.compile_features().flat, "the Cornell box is traced flat");
    let g = compile(&scene, &graph(), &with_spp(20));
    let int = |n| Some(ParamValue::Int(n));
    // The shipped pass renders 32 texels per invocation in a flat scene, so
    // its first dispatch takes 1 sample per texel; the rest take up to 8,
    // one texel per invocation, shares as equal as can be.
    let rest = |texels| {
        vec![
            ("pathtrace".to_string(), "main".to_string(), int(1), int(0), texels),
            ("pathtrace#2".to_string(), "main_more".to_string(), int(7), int(1), 1),
            ("pathtrace#3".to_string(), "main_more".to_string(), int(6), int(8), 1),
            ("pathtrace#4".to_string(), "main_more".to_string(), int(6), int(14), 1),
        ]
    };
    assert_eq!(dispatches(&g), rest(32));
    // Where rays walk a BVH, a trace loops far longer: 8 texels at most.
    let bvh = SceneFeatures { flat: false, ..scene.features };
    let g = compile_for(&bvh, &graph(), &with_spp(20)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(dispatches(&g), rest(8));
    // One texel per invocation: dispatches of up to 8, as equal as can be.
    let text = std::fs::read_to_string(graph()).expect("pathtrace.ron");
    let dir = std::env::temp_dir().join(format!("glint-sample-loops-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let one_texel = dir.join("pathtrace.ron");
    std::fs::write(&one_texel, text.replace("texels_per_invocation: 32", "texels_per_invocation: 1")).expect("write");
    let g1 = compile(&scene, &one_texel, &with_spp(20));
    let spp: Vec<Option<ParamValue>> = g1.schedule.passes.iter().filter(|p| p.name.starts_with("pathtrace")).map(|p| p.params.as_ref().expect("params").values.get("spp").cloned()).collect();
    assert_eq!(spp, vec![int(7), int(7), int(6)]);
    // Up to 8, one dispatch, as written.
    let one = compile(&scene, &one_texel, &with_spp(8));
    assert_eq!(one.schedule.passes.iter().filter(|p| p.name.starts_with("pathtrace")).count(), 1);
    // A sampled pass takes no more texels' samples per invocation than the
    // scene's budget: 9 stays 9 in a flat scene, 8 where rays walk a BVH.
    std::fs::write(&one_texel, text.replace("texels_per_invocation: 32", "texels_per_invocation: 9")).expect("write");
    let nine = compile(&scene, &one_texel, &with_spp(1));
    assert_eq!(dispatches(&nine), vec![("pathtrace".to_string(), "main".to_string(), int(1), int(0), 9)]);
    let capped = compile_for(&bvh, &one_texel, &with_spp(1)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(dispatches(&capped), vec![("pathtrace".to_string(), "main".to_string(), int(1), int(0), 8)]);
    std::fs::write(&one_texel, text.replace("texels_per_invocation: 32", "texels_per_invocation: 0")).expect("write");
    let e = glint::graph::load_and_compile(&one_texel, &repo().join("shaders"), &scene.features, &with_spp(1)).unwrap_err().to_string();
    assert!(e.contains("`texels_per_invocation` is 0; give 1 to 64"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    // The engine's member is not the user's, and a frame has a ceiling.
    let mut set_done = with_spp(20);
    set_done.edits.set.push(ParamSet { pass: "pathtrace".into(), param: "spp_done".into(), value: ParamValue::Int(3) });
    let e = glint::graph::load_and_compile(&graph(), &repo().join("shaders"), &scene.features, &set_done).unwrap_err().to_string();
    assert!(e.contains("`spp_done` is set by the engine"), "{e}");
    let e = glint::graph::load_and_compile(&graph(), &repo().join("shaders"), &scene.features, &with_spp(4_000_000_000)).unwrap_err().to_string();
    assert!(e.contains("at most 8192 samples a frame"), "{e}");
}

#[test]
fn spp_600_is_600_accumulated_frames() {
    let Some(gpu) = gpu() else { return };
    let size = (32, 32);
    let scene = || load_scene("cornell.ron");
    let one_frame = render_with(gpu, scene(), &graph(), size, 1, &with_spp(600));
    let frames = render(gpu, scene(), &graph(), size, 600, None);
    let (a, b) = (mean(&frames), mean(&one_frame));
    let rel = metrics::rel_mse(&frames, &one_frame);
    eprintln!("spp 600 in one frame: mean {b:.5} against {a:.5} from 600 frames; relMSE {rel:.5}");
    // Before the split the one-frame image had 59% of the light.
    // Independent 600-sample renders of this size differ by up to about 0.6%.
    assert!((b / a - 1.0).abs() < 0.02, "mean {b} against {a}");
    assert!(rel < 0.01, "relMSE {rel}");
    // set_param of a split count recompiles: the same bits as --set.
    let compiled = compile(&scene(), &graph(), &CompileOptions::default());
    let mut s = session(gpu, scene(), &compiled, size, 1);
    s.set_param("pathtrace", "spp", ParamValue::Int(600)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.split_total("pathtrace", "spp"), Some(600), "the total over the split dispatches");
    assert_eq!(s.split_total("pathtrace", "max_depth"), None);
    s.frame(0.0);
    let live = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    assert!(live.data == one_frame.data, "set_param differs from --set");
}

fn mean(img: &glint::gpu::readback::ImageF32) -> f64 {
    img.data.iter().map(|p| f64::from(p[0] + p[1] + p[2])).sum::<f64>() / img.data.len() as f64
}

/// The shipped path tracer renders 32 texels per invocation in a flat scene
/// and 8 in a BVH scene, starting a new path in a lane as soon as one
/// ends; the image is that of one texel per
/// invocation, bit for bit (each texel draws its own random numbers), at a
/// size no dispatch divides evenly, in a flat scene and in a BVH scene,
/// and so is the G-buffer it writes with FIRST_HIT.
#[test]
fn texels_per_invocation_keep_the_image() {
    let Some(gpu) = gpu() else { return };
    let size = (67, 35);
    for scene_name in ["cornell.ron", "moving-lights.ron"] {
        for output in [None, Some("gbuf_pos"), Some("gbuf_normal")] {
            let options = CompileOptions { output: output.map(str::to_string), ..Default::default() };
            // The shipped graph stores no first hit: the G-buffer's comes
            // from the path tracer that stores it.
            let path = if output.is_some() { pathtrace_with_gbuffer("texels-first-hit") } else { graph() };
            let shipped = compile(&load_scene(scene_name), &path, &options);
            let pass = shipped.schedule.passes.iter().find(|p| p.name == "pathtrace").expect("pathtrace pass");
            let texels = if scene_name == "cornell.ron" { 32 } else { 8 };
            assert_eq!(pass.texels_per_invocation, texels, "{scene_name}");
            let reference = {
                let mut g = shipped.clone();
                for p in &mut g.schedule.passes {
                    p.texels_per_invocation = 1;
                }
                render_compiled(gpu, load_scene(scene_name), &g, size, 2)
            };
            for texels in [texels, 3] {
                let mut g = shipped.clone();
                for p in g.schedule.passes.iter_mut().filter(|p| p.name == "pathtrace") {
                    p.texels_per_invocation = texels;
                }
                let img = render_compiled(gpu, load_scene(scene_name), &g, size, 2);
                assert!(img.data == reference.data, "{scene_name} {output:?}: {texels} texels per invocation differ from 1");
            }
        }
    }
}
