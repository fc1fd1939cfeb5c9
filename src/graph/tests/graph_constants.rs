//! Graph-wide constants (FrameGraph::constants): set once for every pass
//! whose shader declares the override.

use super::*;

/// Passes `a` and `b` of constants_shader (MODE, FAST, SCALE), and `copy`
/// of the kit's blur shader, which declares none of them; `a_constants`
/// are pass a's own, `graph_constants` the graph's.
fn two_passes(a_constants: &str, graph_constants: &str) -> FrameGraph {
    let text = format!(
        r#"FrameGraph(
    name: "test",
    constants: {{ {graph_constants} }},
    resources: {{
        "x": Texture(format: Rgba16Float),
        "y": Texture(format: Rgba16Float),
    }},
    passes: [
        Pass(name: "a", shader: "c.wgsl", constants: {{ {a_constants} }}, bind: {{ dst: "x" }}),
        Pass(name: "b", shader: "c.wgsl", bind: {{ dst: "y" }}),
    ],
    output: "y",
)
"#
    );
    FrameGraph::parse(&text, Path::new("test.ron")).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

#[test]
fn a_graph_constant_reaches_every_pass_that_declares_it_and_a_pass_may_set_its_own() {
    let g = two_passes("MODE: 3", "SCALE: 0.5, MODE: 2");
    // Each pass writes what it shows alone (the other is culled).
    let shown = |output: &str| build(&g, &[constants_shader()], SceneFeatures::all(), Some(output)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(pass(&shown("x"), "a").constants, vec![("MODE".to_string(), 3.0), ("SCALE".to_string(), 0.5)]);
    assert_eq!(pass(&shown("y"), "b").constants, vec![("MODE".to_string(), 2.0), ("SCALE".to_string(), 0.5)]);
}

#[test]
fn a_graph_constant_no_shader_declares_is_an_error() {
    let e = fail_with(&two_passes("", "SCALE: 1.0, MOOD: 2"), &[constants_shader()]);
    check(&e, ErrorKind::UnknownConstant, None, None, &["graph constant `MOOD`", "no pass's shader declares"]);
    let located = super::super::locate(&e, Path::new("g.ron"), "FrameGraph(\n    name: \"g\",\n    constants: { MOOD: 2 },\n");
    assert!(located.to_string().contains("g.ron:3"), "{located}");
}

#[test]
fn a_graph_constant_is_checked_against_each_shader() {
    let e = fail_with(&two_passes("", "SCALE: 1.0, FAST: 2"), &[constants_shader()]);
    check(&e, ErrorKind::BadParam, Some("a"), None, &["constant `FAST` = 2 does not fit the shader's `override FAST: bool`", "(from the graph's `constants`)"]);
    // A pass's own value is checked in place of the graph's.
    let e = fail_with(&two_passes("MODE: 0.5", "SCALE: 1.0"), &[constants_shader()]);
    check(&e, ErrorKind::BadParam, Some("a"), None, &["constant `MODE` = 0.5 does not fit"]);
    assert!(!e.message.contains("from the graph"), "{e}");
}

#[test]
fn the_engines_per_frame_constants_are_not_the_graphs_either() {
    let mut shader = constants_shader();
    shader.overrides.push(OverrideInfo { name: "CAMERA_STILL".into(), scalar: ScalarType::Bool, has_default: true });
    let e = fail_with(&two_passes("", "SCALE: 1.0, CAMERA_STILL: 1"), &[shader]);
    check(&e, ErrorKind::BadParam, Some("a"), None, &["constant `CAMERA_STILL` is set by the engine per frame"]);
}
