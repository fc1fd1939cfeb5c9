//! Frame-graph compile tests without a GPU or naga: hand-made shader
//! reflections, graphs parsed from RON text, every error path, culling,
//! ordering, versions, params, pooling and history; then the shipped graphs
//! with the real shaders.

use std::collections::BTreeMap;
use std::path::Path;

use super::compile::{compile, CompileError, CompileOptions, ErrorKind};
use super::desc::{FrameGraph, SizeDesc, TexFormat};
use super::schedule::*;
use crate::error::{Location, UserError};
use crate::scene::{Feature, SceneFeatures};
use crate::shader::{
    BindingInfo, BindingKind, EntryInfo, OverrideInfo, ParamMember, ParamsLayout, SampleType, ScalarType, ShaderInfo,
    StorageAccess,
};

const F16: TexFormat = TexFormat::Rgba16Float;
const F32: TexFormat = TexFormat::Rgba32Float;

// ---------------------------------------------------------------------------
// Shader reflections by hand.

fn tex() -> BindingKind {
    BindingKind::SampledTexture { sample: SampleType::Float }
}

fn utex() -> BindingKind {
    BindingKind::SampledTexture { sample: SampleType::Uint }
}

fn out(format: TexFormat) -> BindingKind {
    BindingKind::StorageTexture { format, access: StorageAccess::Write }
}

fn inout(format: TexFormat) -> BindingKind {
    BindingKind::StorageTexture { format, access: StorageAccess::ReadWrite }
}

fn uniform(type_name: &str) -> BindingKind {
    BindingKind::Uniform { type_name: type_name.into(), size: 16 }
}

/// How shaders declare the scene's per-primitive arrays.
fn scene_array() -> BindingKind {
    BindingKind::StorageTexture { format: TexFormat::Rgba32Uint, access: StorageAccess::Read }
}

fn storage(read_only: bool) -> BindingKind {
    BindingKind::Storage { read_only }
}

/// Where binding `n` of a test shader is declared: line `n + 1` of its file.
fn decl(file: &str, n: u32) -> Location {
    Location::at(file, n as usize + 1, 0)
}

/// An entry point using `bindings` in order, at group 0, binding 0, 1, ...
fn entry(file: &str, name: &str, workgroup_size: [u32; 3], bindings: &[(&str, BindingKind)]) -> EntryInfo {
    let bindings = (0u32..)
        .zip(bindings)
        .map(|(n, (name, kind))| BindingInfo {
            name: name.to_string(),
            group: 0,
            binding: n,
            kind: kind.clone(),
            location: decl(file, n),
        })
        .collect();
    EntryInfo { name: name.into(), workgroup_size, bindings }
}

/// A shader with one 8x8 entry point `main`.
fn shader(file: &str, bindings: &[(&str, BindingKind)]) -> ShaderInfo {
    ShaderInfo { name: file.into(), entry_points: vec![entry(file, "main", [8, 8, 1], bindings)], overrides: vec![], params: None }
}

/// The shaders every test can use; tests point their variables at graph
/// resources with `bind`.
fn kit() -> Vec<ShaderInfo> {
    vec![
        shader("gen.wgsl", &[("dst", out(F16))]),
        shader("gen32.wgsl", &[("dst", out(F32))]),
        shader("filter.wgsl", &[("src", tex()), ("dst", out(F16))]),
        shader("filter32.wgsl", &[("src", tex()), ("dst", out(F32))]),
        shader("mix.wgsl", &[("a", tex()), ("b", tex()), ("dst", out(F16))]),
        shader("edit.wgsl", &[("img", inout(F16))]),
    ]
}

fn member(name: &str, offset: u32, scalar: ScalarType, components: u32) -> ParamMember {
    ParamMember { name: name.into(), offset, scalar, components, limit: None }
}

/// `struct Params { gain: f32, count: u32, bias: i32, tint: vec3<f32> }`.
fn params_shader() -> ShaderInfo {
    let mut s = shader("p.wgsl", &[("params", uniform("Params")), ("dst", out(F16))]);
    s.params = Some(ParamsLayout {
        size: 32,
        members: vec![
            member("gain", 0, ScalarType::F32, 1),
            member("count", 4, ScalarType::U32, 1),
            member("bias", 8, ScalarType::I32, 1),
            member("tint", 16, ScalarType::F32, 3),
        ],
    });
    s
}

/// `override MODE: u32 = ..; override FAST: bool = ..; override SCALE: f32;`
fn constants_shader() -> ShaderInfo {
    let o = |name: &str, scalar, has_default| OverrideInfo { name: name.into(), scalar, has_default };
    let mut s = shader("c.wgsl", &[("dst", out(F16))]);
    s.overrides = vec![o("MODE", ScalarType::U32, true), o("FAST", ScalarType::Bool, true), o("SCALE", ScalarType::F32, false)];
    s
}

// ---------------------------------------------------------------------------
// Graphs from RON text, compiled.

/// A graph named "test": `resources` and `passes` are the bodies of the map
/// and the list.
fn graph(resources: &str, passes: &str, output: &str) -> FrameGraph {
    let text = format!(
        "FrameGraph(\n    name: \"test\",\n    resources: {{\n{resources}\n    }},\n    passes: [\n{passes}\n    ],\n    output: \"{output}\",\n)\n"
    );
    FrameGraph::parse(&text, Path::new("test.ron")).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Screen-sized `Rgba16Float` resource declarations.
fn f16(names: &[&str]) -> String {
    names.iter().map(|n| format!("\"{n}\": Texture(format: Rgba16Float),\n")).collect()
}

fn build(g: &FrameGraph, extra: &[ShaderInfo], features: SceneFeatures, output: Option<&str>) -> Result<Schedule, CompileError> {
    let shaders: BTreeMap<String, ShaderInfo> = kit().into_iter().chain(extra.iter().cloned()).map(|s| (s.name.clone(), s)).collect();
    compile(g, &shaders, &features, &CompileOptions { output: output.map(str::to_string), ..Default::default() })
}

fn ok_with(g: &FrameGraph, extra: &[ShaderInfo]) -> Schedule {
    build(g, extra, SceneFeatures::all(), None).unwrap_or_else(|e| panic!("{e}"))
}

fn ok(g: &FrameGraph) -> Schedule {
    ok_with(g, &[])
}

fn fail_in(g: &FrameGraph, extra: &[ShaderInfo], features: SceneFeatures) -> CompileError {
    match build(g, extra, features, None) {
        Ok(s) => panic!("compiled, order {:?}", order(&s)),
        Err(e) => e,
    }
}

fn fail_with(g: &FrameGraph, extra: &[ShaderInfo]) -> CompileError {
    fail_in(g, extra, SceneFeatures::all())
}

fn fail(g: &FrameGraph) -> CompileError {
    fail_with(g, &[])
}

/// Asserts an error's kind, pass, shader location and that its message
/// mentions each of `words`.
fn check(e: &CompileError, kind: ErrorKind, pass: Option<&str>, at: Option<Location>, words: &[&str]) {
    assert_eq!((e.kind, e.pass.as_deref(), &e.shader_location), (kind, pass, &at), "{e}");
    for w in words {
        assert!(e.message.contains(w), "`{w}` not in: {e}");
    }
}

fn order(s: &Schedule) -> Vec<&str> {
    s.passes.iter().map(|p| p.name.as_str()).collect()
}

fn pass<'a>(s: &'a Schedule, name: &str) -> &'a ScheduledPass {
    s.passes.iter().find(|p| p.name == name).unwrap_or_else(|| panic!("no pass {name} in {:?}", order(s)))
}

/// The versions a scheduled pass reads and writes: `"lit@1 x@2 -> lit@2"`.
fn io(s: &Schedule, name: &str) -> String {
    let p = pass(s, name);
    format!("{} -> {}", p.reads.join(" "), p.writes.join(" "))
}

fn version<'a>(s: &'a Schedule, resource: &str, n: u32) -> &'a VersionInfo {
    s.versions.iter().find(|v| v.resource == resource && v.version == n).unwrap_or_else(|| panic!("no {resource}@{n}"))
}

fn culled(name: &str, reason: CullReason) -> CulledPass {
    CulledPass { name: name.into(), reason }
}

fn features(f: impl FnOnce(&mut SceneFeatures)) -> SceneFeatures {
    let mut s = SceneFeatures::default();
    f(&mut s);
    s
}

/// Bytes of a 64x64 texture with this many bytes per pixel.
const fn px64(bytes_per_pixel: u64) -> u64 {
    64 * 64 * bytes_per_pixel
}

// ---------------------------------------------------------------------------
// Errors: names.

#[test]
fn unknown_resource() {
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "filter.wgsl", bind: { dst: "out" }),"#, "out");
    let e = fail(&g);
    check(&e, ErrorKind::UnknownResource, Some("a"), Some(decl("filter.wgsl", 0)), &["`src`", "declare it under `resources`"]);
    assert!(e.to_string().contains("(declared at filter.wgsl:1)"), "{e}");
}

#[test]
fn unknown_shader() {
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "nope.wgsl", bind: { dst: "out" }),"#, "out");
    check(&fail(&g), ErrorKind::UnknownShader, Some("a"), None, &["`nope.wgsl` not found"]);
}

fn two_entries() -> ShaderInfo {
    let b = [("src", tex()), ("dst", out(F16))];
    ShaderInfo {
        name: "blur.wgsl".into(),
        entry_points: vec![entry("blur.wgsl", "horizontal", [64, 1, 1], &b), entry("blur.wgsl", "vertical", [1, 64, 1], &b)],
        overrides: vec![],
        params: None,
    }
}

fn blur_graph(entry: &str) -> FrameGraph {
    let passes = format!(
        r#"Pass(name: "x", shader: "gen.wgsl", bind: {{ dst: "x" }}),
           Pass(name: "blur", shader: "blur.wgsl", {entry} bind: {{ src: "x", dst: "out" }}),"#
    );
    graph(&f16(&["x", "out"]), &passes, "out")
}

#[test]
fn unknown_entry() {
    let e = fail_with(&blur_graph(r#"entry: Some("diagonal"),"#), &[two_entries()]);
    check(&e, ErrorKind::UnknownEntry, Some("blur"), None, &["[horizontal, vertical]", "`diagonal` is not one of them"]);
}

#[test]
fn ambiguous_entry() {
    let e = fail_with(&blur_graph(""), &[two_entries()]);
    check(&e, ErrorKind::UnknownEntry, Some("blur"), None, &["[horizontal, vertical]", "name one with `entry:`"]);
}

#[test]
fn entry_picked_by_name() {
    let s = ok_with(&blur_graph(r#"entry: Some("vertical"),"#), &[two_entries()]);
    let p = pass(&s, "blur");
    assert_eq!((p.entry.as_str(), p.workgroup_size), ("vertical", [1, 64, 1]));
}

#[test]
fn bind_of_an_unused_variable() {
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "out", "nope": "out" }),"#, "out");
    check(&fail(&g), ErrorKind::UnknownBinding, Some("a"), None, &["`bind` maps `nope`", "uses: dst"]);
}

#[test]
fn duplicate_pass_names() {
    let g = graph(
        &f16(&["x", "out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "a", shader: "filter.wgsl", bind: { src: "x", dst: "out" }),"#,
        "out",
    );
    check(&fail(&g), ErrorKind::DuplicatePass, Some("a"), None, &["unique"]);
}

#[test]
fn unknown_output() {
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "out" }),"#, "nope");
    check(&fail(&g), ErrorKind::UnknownOutput, None, None, &["`nope`", "declared: out"]);
    // The same through the options.
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "out" }),"#, "out");
    let e = build(&g, &[], SceneFeatures::all(), Some("debug")).unwrap_err();
    check(&e, ErrorKind::UnknownOutput, None, None, &["`debug`"]);
}

// ---------------------------------------------------------------------------
// Errors: formats and access.

#[test]
fn storage_format_differs_from_the_resource() {
    let g = graph(r#""out": Texture(format: Rgba32Float),"#, r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "out" }),"#, "out");
    check(
        &fail(&g),
        ErrorKind::FormatMismatch,
        Some("a"),
        Some(decl("gen.wgsl", 0)),
        &["texture_storage_2d<rgba16float, write>", "declared Rgba32Float"],
    );
}

#[test]
fn sample_type_differs_from_the_resource() {
    // texture_2d<u32> of a float resource.
    let ids = shader("ids.wgsl", &[("id", utex()), ("dst", out(F16))]);
    let g = graph(
        &f16(&["x", "out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "b", shader: "ids.wgsl", bind: { id: "x", dst: "out" }),"#,
        "out",
    );
    check(&fail_with(&g, &[ids]), ErrorKind::FormatMismatch, Some("b"), Some(decl("ids.wgsl", 0)), &["texture_2d<u32>", "Rgba16Float"]);
    // texture_2d<f32> of a uint resource.
    let g = graph(
        r#""x": Texture(format: R32Uint), "out": Texture(format: Rgba16Float),"#,
        r#"Pass(name: "b", shader: "filter.wgsl", bind: { src: "x", dst: "out" }),"#,
        "out",
    );
    check(&fail(&g), ErrorKind::FormatMismatch, Some("b"), Some(decl("filter.wgsl", 0)), &["texture_2d<f32>", "R32Uint"]);
}

/// A graph with one pass running `file`, whose `dst` writes `out`.
fn one_pass(file: &str, bind: &str) -> FrameGraph {
    let passes = format!(r#"Pass(name: "a", shader: "{file}", bind: {{ dst: "out", {bind} }}),"#);
    graph(&f16(&["x", "out"]), &passes, "out")
}

#[test]
fn buffer_bound_to_a_texture() {
    let cfg = shader("cfg.wgsl", &[("settings", uniform("Settings")), ("dst", out(F16))]);
    let e = fail_with(&one_pass("cfg.wgsl", r#""settings": "x""#), &[cfg]);
    check(&e, ErrorKind::WrongAccess, Some("a"), Some(decl("cfg.wgsl", 0)), &["var<uniform> of type Settings", "`x` is a texture"]);

    let buf = shader("buf.wgsl", &[("data", storage(true)), ("dst", out(F16))]);
    let e = fail_with(&one_pass("buf.wgsl", r#""data": "x""#), &[buf]);
    check(&e, ErrorKind::WrongAccess, Some("a"), Some(decl("buf.wgsl", 0)), &["var<storage, read>", "`x` is a texture"]);

    let p = shader("p.wgsl", &[("params", storage(true)), ("dst", out(F16))]);
    let e = fail_with(&one_pass("p.wgsl", ""), &[p]);
    check(&e, ErrorKind::WrongAccess, Some("a"), Some(decl("p.wgsl", 0)), &["`params` must be a var<uniform>"]);
}

#[test]
fn wrong_access_to_engine_resources() {
    let bad = shader("bad.wgsl", &[("scene_meshes", storage(false)), ("dst", out(F16))]);
    let e = fail_with(&one_pass("bad.wgsl", ""), &[bad]);
    check(
        &e,
        ErrorKind::WrongAccess,
        Some("a"),
        Some(decl("bad.wgsl", 0)),
        &["engine resource `scene_meshes`", "var<storage, read>", "declares var<storage, read_write>"],
    );

    // The per-primitive arrays are read-only rgba32uint storage textures.
    let wrong_format = BindingKind::StorageTexture { format: TexFormat::Rgba32Float, access: StorageAccess::Read };
    let writable = BindingKind::StorageTexture { format: TexFormat::Rgba32Uint, access: StorageAccess::ReadWrite };
    for kind in [storage(true), utex(), wrong_format, writable] {
        let bad = shader("bad.wgsl", &[("scene_geometry", kind), ("dst", out(F16))]);
        let e = fail_with(&one_pass("bad.wgsl", ""), &[bad]);
        check(&e, ErrorKind::WrongAccess, Some("a"), Some(decl("bad.wgsl", 0)), &["engine resource `scene_geometry`", "texture_storage_2d<rgba32uint, read>"]);
    }

    let e = fail(&one_pass("filter.wgsl", r#"src: "frame""#));
    check(&e, ErrorKind::WrongAccess, Some("a"), Some(decl("filter.wgsl", 0)), &["`frame`", "var<uniform>", "texture_2d<f32>"]);
}

#[test]
fn one_pass_writes_a_resource_twice() {
    let split = shader("split.wgsl", &[("left", out(F16)), ("right", out(F16))]);
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "split.wgsl", bind: { left: "out", right: "out" }),"#, "out");
    let e = fail_with(&g, &[split]);
    check(&e, ErrorKind::WrongAccess, Some("a"), Some(decl("split.wgsl", 1)), &["`left` and `right` both bind `out`"]);
}

#[test]
fn one_pass_reads_what_it_modifies_in_place() {
    let peek = shader("peek.wgsl", &[("src", tex()), ("img", inout(F16))]);
    let g = graph(
        &f16(&["out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "out" }),
           Pass(name: "b", shader: "peek.wgsl", bind: { src: "out", img: "out" }),"#,
        "out",
    );
    let e = fail_with(&g, &[peek]);
    check(&e, ErrorKind::WrongAccess, Some("b"), Some(decl("peek.wgsl", 0)), &["`src` reads `out` while `img` modifies it in place"]);
}

// ---------------------------------------------------------------------------
// Errors: versions, ordering and unwritten reads.

#[test]
fn two_writers_of_one_version() {
    let g = graph(
        &f16(&["x", "out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "b", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "c", shader: "filter.wgsl", bind: { src: "x", dst: "out" }),"#,
        "out",
    );
    check(&fail(&g), ErrorKind::DuplicateWriter, Some("b"), None, &["`x`", "pass `a` also does", "two writers of one version"]);
}

#[test]
fn cycle_names_its_passes() {
    let cycle = r#"Pass(name: "left", shader: "filter.wgsl", bind: { src: "y", dst: "x" }),
                   Pass(name: "right", shader: "filter.wgsl", bind: { src: "x", dst: "y" }),"#;
    // `left` reads `y` ahead of its writer: a forward reference.
    let e = fail(&graph(&f16(&["x", "y"]), cycle, "y"));
    check(&e, ErrorKind::Cycle, None, None, &["cycle: left -> right -> left"]);
    // The same with a pass downstream of the cycle first in the file.
    let sink = r#"Pass(name: "sink", shader: "filter.wgsl", bind: { src: "x", dst: "out" }),"#;
    let e = fail(&graph(&f16(&["x", "y", "out"]), &format!("{sink}\n{cycle}"), "out"));
    check(&e, ErrorKind::Cycle, None, None, &["left", "right"]);
    assert!(!e.message.contains("sink"), "{e}");
    // Three passes, against file order: p -> r -> q -> p.
    let e = fail(&graph(
        &f16(&["a", "b", "c"]),
        r#"Pass(name: "p", shader: "filter.wgsl", bind: { src: "c", dst: "a" }),
           Pass(name: "q", shader: "filter.wgsl", bind: { src: "b", dst: "c" }),
           Pass(name: "r", shader: "filter.wgsl", bind: { src: "a", dst: "b" }),"#,
        "a",
    ));
    check(&e, ErrorKind::Cycle, None, None, &["cycle: p -> r -> q -> p"]);
}

#[test]
fn output_that_nothing_writes() {
    let g = graph(&f16(&["x", "out"]), r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),"#, "out");
    check(&fail(&g), ErrorKind::UnwrittenRead, None, None, &["output `out` is written by no pass"]);
    // Its only writer culled for the scene.
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "gen.wgsl", requires: [Motion], bind: { dst: "out" }),"#, "out");
    check(&fail_in(&g, &[], SceneFeatures::default()), ErrorKind::UnwrittenRead, None, None, &["`a` culled: it requires [Motion]"]);
}

#[test]
fn read_of_a_resource_whose_writer_was_culled() {
    let g = graph(
        &f16(&["refl", "out"]),
        r#"Pass(name: "spec", shader: "gen.wgsl", requires: [Specular], bind: { dst: "refl" }),
           Pass(name: "final", shader: "filter.wgsl", bind: { src: "refl", dst: "out" }),"#,
        "out",
    );
    let e = fail_in(&g, &[], SceneFeatures::default());
    check(&e, ErrorKind::UnwrittenRead, Some("final"), None, &["reads `refl`", "`spec` culled: it requires [Specular]"]);
}

#[test]
fn modify_in_place_before_any_write() {
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "edit.wgsl", bind: { img: "out" }),"#, "out");
    check(&fail(&g), ErrorKind::UnwrittenRead, Some("a"), None, &["reads and modifies `out`", "no earlier pass writes it"]);
}

// ---------------------------------------------------------------------------
// Errors: params and constants.

fn with_params(params: &str) -> FrameGraph {
    let passes = format!(r#"Pass(name: "a", shader: "p.wgsl", params: {{ {params} }}, bind: {{ dst: "out" }}),"#);
    graph(&f16(&["out"]), &passes, "out")
}

fn param_error(params: &str) -> CompileError {
    fail_with(&with_params(params), &[params_shader()])
}

#[test]
fn missing_param() {
    let e = param_error("gain: 1.0, count: 3, tint: (0.0, 0.0, 0.0)");
    check(&e, ErrorKind::MissingParam, Some("a"), None, &["param `bias` is missing"]);
}

#[test]
fn unknown_param() {
    let e = param_error("gain: 1.0, count: 3, bias: 0, tint: (0.0, 0.0, 0.0), gian: 2.0");
    check(&e, ErrorKind::UnknownParam, Some("a"), None, &["unknown param `gian`", "takes: gain, count, bias, tint"]);
    // A shader without a `params` uniform takes none.
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "gen.wgsl", params: { gain: 1.0 }, bind: { dst: "out" }),"#, "out");
    check(&fail(&g), ErrorKind::UnknownParam, Some("a"), None, &["`gain`", "gen.wgsl has no `params` uniform"]);
}

#[test]
fn bad_param() {
    let e = param_error("gain: 1.0, count: 1.5, bias: 0, tint: (0.0, 0.0, 0.0)");
    check(&e, ErrorKind::BadParam, Some("a"), None, &["param `count` is U32", "1.5 does not fit"]);
    // A float literal is no integer, even when whole.
    let e = param_error("gain: 1.0, count: 2.0, bias: 0, tint: (0.0, 0.0, 0.0)");
    check(&e, ErrorKind::BadParam, Some("a"), None, &["param `count`", "write an integer"]);
    let e = param_error("gain: 1.0, count: -1, bias: 0, tint: (0.0, 0.0, 0.0)");
    check(&e, ErrorKind::BadParam, Some("a"), None, &["param `count`"]);
    let e = param_error("gain: 1.0, count: 1, bias: 0, tint: (0.0, 0.0)");
    check(&e, ErrorKind::BadParam, Some("a"), None, &["param `tint` needs 3 value(s), got 2"]);
    let e = param_error("gain: (1.0, 2.0), count: 1, bias: 0, tint: (0.0, 0.0, 0.0)");
    check(&e, ErrorKind::BadParam, Some("a"), None, &["param `gain` needs 1 value(s), got 2"]);
}

fn with_constants(constants: &str) -> FrameGraph {
    let passes = format!(r#"Pass(name: "a", shader: "c.wgsl", constants: {{ {constants} }}, bind: {{ dst: "out" }}),"#);
    graph(&f16(&["out"]), &passes, "out")
}

#[test]
fn unknown_constant() {
    let e = fail_with(&with_constants("SCALE: 1.0, MOOD: 2"), &[constants_shader()]);
    check(&e, ErrorKind::UnknownConstant, Some("a"), None, &["unknown constant `MOOD`", "overrides: MODE, FAST, SCALE"]);
}

#[test]
fn missing_constant() {
    let e = fail_with(&with_constants("MODE: 2"), &[constants_shader()]);
    check(&e, ErrorKind::MissingConstant, Some("a"), None, &["override `SCALE` has no default"]);
}

#[test]
fn the_engines_per_frame_constants_are_not_the_graphs() {
    for name in crate::graph::frame_kind::FRAME_CONSTANTS {
        let mut shader = constants_shader();
        shader.overrides.push(OverrideInfo { name: name.into(), scalar: ScalarType::Bool, has_default: true });
        let e = fail_with(&with_constants(&format!("SCALE: 1.0, {name}: 1")), &[shader]);
        check(&e, ErrorKind::BadParam, Some("a"), None, &[&format!("constant `{name}` is set by the engine per frame")]);
    }
}

#[test]
fn bad_constant() {
    let e = fail_with(&with_constants("SCALE: 1.0, FAST: 2"), &[constants_shader()]);
    check(&e, ErrorKind::BadParam, Some("a"), None, &["constant `FAST` = 2 does not fit the shader's `override FAST: bool`: give 0 or 1"]);
    let e = fail_with(&with_constants("SCALE: 1.0, MODE: 0.5"), &[constants_shader()]);
    check(&e, ErrorKind::BadParam, Some("a"), None, &["constant `MODE` = 0.5 does not fit the shader's `override MODE: u32`"]);
    // Within the type's range, not only of its kind (the driver refused
    // 1e30 with a bare "Validation Error").
    let e = fail_with(&with_constants("SCALE: 1.0, MODE: 1e30"), &[constants_shader()]);
    check(&e, ErrorKind::BadParam, Some("a"), None, &["constant `MODE` = 1e30 does not fit", "an integer from 0 to 4294967295"]);
    let e = fail_with(&with_constants("SCALE: 1e39, MODE: 1"), &[constants_shader()]);
    check(&e, ErrorKind::BadParam, Some("a"), None, &["constant `SCALE` = 1e39 does not fit the shader's `override SCALE: f32`"]);
}

// ---------------------------------------------------------------------------
// Params, constants and bindings.

#[test]
fn params_packed_at_their_offsets() {
    let s = ok_with(&with_params("gain: 1.5, count: 3, bias: -2, tint: [0.25, 0.5, 1.0]"), &[params_shader()]);
    let mut want = [0u8; 32];
    want[0..4].copy_from_slice(&1.5f32.to_le_bytes());
    want[4..8].copy_from_slice(&3u32.to_le_bytes());
    want[8..12].copy_from_slice(&(-2i32).to_le_bytes());
    for (i, x) in [0.25f32, 0.5, 1.0].into_iter().enumerate() {
        want[16 + 4 * i..20 + 4 * i].copy_from_slice(&x.to_le_bytes());
    }
    assert_eq!(s.passes[0].params.as_ref().map(|p| &p.bytes[..]), Some(&want[..]));
    // An integer is fine for an f32 member; a RON tuple for a vector.
    let s = ok_with(&with_params("gain: 2, count: 0, bias: 0, tint: (1.0, 1.0, 1.0)"), &[params_shader()]);
    let p = &s.passes[0].params.as_ref().unwrap().bytes;
    assert_eq!((&p[0..4], &p[16..20]), (&2f32.to_le_bytes()[..], &1f32.to_le_bytes()[..]));
}

#[test]
fn constants_passed_through() {
    let s = ok_with(&with_constants("SCALE: 0.5, MODE: 2"), &[constants_shader()]);
    assert_eq!(s.passes[0].constants, vec![("MODE".to_string(), 2.0), ("SCALE".to_string(), 0.5)]);
}

#[test]
fn engine_resources_and_params_bound_by_name() {
    let mut shade = shader(
        "shade.wgsl",
        &[
            ("params", uniform("Params")),
            ("frame", uniform("Frame")),
            ("scene_spheres", scene_array()),
            ("scene_lights", scene_array()),
            ("dst", out(F16)),
        ],
    );
    shade.params = Some(ParamsLayout { size: 16, members: vec![member("samples", 0, ScalarType::U32, 1)] });
    let g = graph(&f16(&["out"]), r#"Pass(name: "a", shader: "shade.wgsl", params: { samples: 4 }, bind: { dst: "out" }),"#, "out");
    let s = ok_with(&g, &[shade]);
    let targets: Vec<(&str, u32, &Target)> = s.passes[0].bindings.iter().map(|b| (b.name.as_str(), b.binding, &b.target)).collect();
    assert_eq!(
        targets,
        [
            ("params", 0, &Target::Params),
            ("frame", 1, &Target::Engine(EngineResource::Frame)),
            ("scene_spheres", 2, &Target::Engine(EngineResource::Spheres)),
            ("scene_lights", 3, &Target::Engine(EngineResource::Lights)),
            ("dst", 4, &Target::Texture(TexRef::Fixed(0))),
        ]
    );
    assert_eq!(s.passes[0].params.as_ref().map(|p| p.bytes.clone()), Some(4u32.to_le_bytes().into_iter().chain([0; 12]).collect()));
}

// ---------------------------------------------------------------------------
// Culling.

/// `base` writes lit@1, `spec` (requires Specular and Motion) reads it and
/// writes lit@2, `shade` reads the newest `lit`.
fn spec_graph() -> FrameGraph {
    graph(
        r#""lit": Texture(format: Rgba16Float),
           "out": Texture(format: Rgba16Float),"#,
        r#"Pass(name: "base", shader: "gen.wgsl", bind: { dst: "lit" }),
           Pass(name: "spec", shader: "filter.wgsl", requires: [Spheres, Specular, Motion], bind: { "src": "lit", "dst": "lit" }),
           Pass(name: "shade", shader: "filter.wgsl", bind: { "src": "lit", "dst": "out" }),"#,
        "out",
    )
}

#[test]
fn culled_by_requires_then_readers_see_the_previous_version() {
    let g = spec_graph();
    let s = ok(&g);
    assert_eq!(order(&s), ["base", "spec", "shade"]);
    assert!(s.culled.is_empty());
    assert_eq!(io(&s, "spec"), "lit@1 -> lit@2");
    assert_eq!(io(&s, "shade"), "lit@2 -> out@1");

    let s = build(&g, &[], features(|f| f.spheres = true), None).unwrap();
    assert_eq!(order(&s), ["base", "shade"]);
    assert_eq!(s.culled, [culled("spec", CullReason::Requires(vec![Feature::Specular, Feature::Motion]))]);
    assert_eq!(io(&s, "shade"), "lit@1 -> out@1");
    assert!(s.versions.iter().all(|v| v.resource != "lit" || v.version == 1));
}

/// x feeds the output `out` and a debug chain dbg -> dbg2 nothing reads.
const DEBUG_CHAIN: &str = r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "debug", shader: "filter.wgsl", bind: { src: "x", dst: "dbg" }),
           Pass(name: "debug2", shader: "filter.wgsl", bind: { src: "dbg", dst: "dbg2" }),
           Pass(name: "b", shader: "filter.wgsl", bind: { src: "x", dst: "out" }),"#;

#[test]
fn culled_when_unreachable() {
    let passes = format!(r#"{DEBUG_CHAIN}
           Pass(name: "spec", shader: "gen.wgsl", requires: [Specular], bind: {{ dst: "dbg2" }}),"#);
    let g = graph(&f16(&["x", "dbg", "dbg2", "out"]), &passes, "out");
    let s = build(&g, &[], SceneFeatures::default(), None).unwrap();
    assert_eq!(order(&s), ["a", "b"]);
    assert_eq!(
        s.culled,
        [
            culled("debug", CullReason::Unreachable),
            culled("debug2", CullReason::Unreachable),
            culled("spec", CullReason::Requires(vec![Feature::Specular])),
        ]
    );
    assert!(s.versions.iter().all(|v| !v.resource.starts_with("dbg")));
    assert_eq!(s.textures.len(), 2);
}

/// `also_compute` keeps a pass that no output reads, and the passes it
/// reads from, and lists its resource among the kept ones (which
/// `lifetimes` holds to the frame's end); a name the graph does not
/// declare changes nothing.
#[test]
fn also_compute_keeps_what_no_output_reads() {
    let g = graph(&f16(&["x", "dbg", "dbg2", "out"]), DEBUG_CHAIN, "out");
    let shaders: BTreeMap<String, ShaderInfo> = kit().into_iter().map(|s| (s.name.clone(), s)).collect();
    let with = |also: &[&str]| {
        let options = CompileOptions { also_compute: also.iter().map(|s| s.to_string()).collect(), ..Default::default() };
        compile(&g, &shaders, &SceneFeatures::all(), &options).unwrap_or_else(|e| panic!("{e}"))
    };
    let s = with(&["dbg2", "nothing"]);
    let mut passes = order(&s);
    passes.sort();
    assert_eq!(passes, ["a", "b", "debug", "debug2"]);
    assert!(s.culled.is_empty());
    assert!(s.kept.iter().any(|k| k == "dbg2"));
    assert!(!s.kept.iter().any(|k| k == "nothing"));
    let s = with(&["dbg"]);
    assert_eq!(s.culled, [culled("debug2", CullReason::Unreachable)]);
}

#[test]
fn output_option_overrides_the_output() {
    let g = graph(
        &f16(&["x", "y", "out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "b", shader: "filter.wgsl", bind: { src: "x", dst: "y" }),
           Pass(name: "c", shader: "filter.wgsl", bind: { src: "y", dst: "out" }),"#,
        "out",
    );
    let s = build(&g, &[], SceneFeatures::all(), Some("x")).unwrap();
    assert_eq!(order(&s), ["a"]);
    assert_eq!(s.culled, [culled("b", CullReason::Unreachable), culled("c", CullReason::Unreachable)]);
    assert_eq!((s.output_resource.as_str(), s.output, s.output_format), ("x", TexRef::Fixed(0), F16));
    assert_eq!(s.textures.len(), 1);
}

// ---------------------------------------------------------------------------
// Order and versions.

#[test]
fn forward_reference_orders_by_data_then_file() {
    let g = graph(
        &f16(&["x", "y", "out"]),
        r#"Pass(name: "late", shader: "mix.wgsl", bind: { a: "x", b: "y", dst: "out" }),
           Pass(name: "mid", shader: "gen.wgsl", bind: { dst: "y" }),
           Pass(name: "early", shader: "gen.wgsl", bind: { dst: "x" }),"#,
        "out",
    );
    let s = ok(&g);
    assert_eq!(order(&s), ["mid", "early", "late"]);
    assert_eq!(io(&s, "late"), "x@1 y@1 -> out@1");
    let x = version(&s, "x", 1);
    assert_eq!((x.first_use, x.last_use), (Some(1), Some(2)));
}

#[test]
fn independent_passes_keep_file_order() {
    let g = graph(
        &f16(&["x", "y", "z", "out"]),
        r#"Pass(name: "c", shader: "gen.wgsl", bind: { dst: "z" }),
           Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "b", shader: "mix.wgsl", bind: { a: "x", b: "z", dst: "y" }),
           Pass(name: "d", shader: "mix.wgsl", bind: { a: "y", b: "z", dst: "out" }),"#,
        "out",
    );
    assert_eq!(order(&ok(&g)), ["c", "a", "b", "d"]);
}

#[test]
fn versions_of_a_chain() {
    let g = graph(
        &f16(&["lit", "out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "lit" }),
           Pass(name: "b", shader: "filter.wgsl", bind: { src: "lit", dst: "lit" }),
           Pass(name: "c", shader: "filter.wgsl", bind: { src: "lit", dst: "lit" }),
           Pass(name: "d", shader: "mix.wgsl", bind: { a: "lit", b: "lit", dst: "out" }),"#,
        "out",
    );
    let s = ok(&g);
    let all: Vec<String> = order(&s).iter().map(|p| format!("{p}: {}", io(&s, p))).collect();
    assert_eq!(all, ["a:  -> lit@1", "b: lit@1 -> lit@2", "c: lit@2 -> lit@3", "d: lit@3 lit@3 -> out@1"]);
    let uses: Vec<_> = s.versions.iter().map(|v| (format!("{}@{}", v.resource, v.version), v.first_use, v.last_use)).collect();
    for want in [("lit@1".to_string(), Some(0), Some(1)), ("lit@3".into(), Some(2), Some(3)), ("out@1".into(), Some(3), None)] {
        assert!(uses.contains(&want), "{want:?} not in {uses:?}");
    }
}

#[test]
fn in_place_write_waits_for_readers_of_the_old_version() {
    // `early` reads lit@1 (a forward reference) and z, which is written last
    // in the file; `touch` must not modify lit in place before `early` ran.
    let g = graph(
        &f16(&["lit", "z", "peek", "out"]),
        r#"Pass(name: "early", shader: "mix.wgsl", bind: { a: "lit", b: "z", dst: "peek" }),
           Pass(name: "make", shader: "gen.wgsl", bind: { dst: "lit" }),
           Pass(name: "touch", shader: "edit.wgsl", bind: { img: "lit" }),
           Pass(name: "late", shader: "gen.wgsl", bind: { dst: "z" }),
           Pass(name: "final", shader: "mix.wgsl", bind: { a: "peek", b: "lit", dst: "out" }),"#,
        "out",
    );
    let s = ok(&g);
    assert_eq!(order(&s), ["make", "late", "early", "touch", "final"]);
    assert_eq!(io(&s, "early"), "lit@1 z@1 -> peek@1");
    assert_eq!(io(&s, "touch"), "lit@1 -> lit@2");
    assert_eq!(io(&s, "final"), "peek@1 lit@2 -> out@1");
}

#[test]
fn dispatch_from_the_first_written_texture() {
    let two = shader("two.wgsl", &[("half", out(F16)), ("full", out(F16))]);
    let g = graph(
        r#""half": Texture(format: Rgba16Float, size: Scaled(0.5)),
           "full": Texture(format: Rgba16Float),
           "out":  Texture(format: Rgba16Float, size: Fixed(100, 50)),"#,
        r#"Pass(name: "a", shader: "two.wgsl"),
           Pass(name: "b", shader: "mix.wgsl", bind: { a: "half", b: "full", dst: "out" }),"#,
        "out",
    );
    let s = ok_with(&g, &[two]);
    assert_eq!(pass(&s, "a").dispatch, SizeDesc::Scaled(0.5));
    assert_eq!(pass(&s, "b").dispatch, SizeDesc::Fixed(100, 50));
}

// ---------------------------------------------------------------------------
// Physical textures.

#[test]
fn pooling_reuses_textures_across_disjoint_lifetimes() {
    // lit@1..lit@4: each lives from its writer to the next pass.
    let g = graph(
        &f16(&["lit"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "lit" }),
           Pass(name: "b", shader: "filter.wgsl", bind: { src: "lit", dst: "lit" }),
           Pass(name: "c", shader: "filter.wgsl", bind: { src: "lit", dst: "lit" }),
           Pass(name: "d", shader: "filter.wgsl", bind: { src: "lit", dst: "lit" }),"#,
        "lit",
    );
    let s = ok(&g);
    assert_eq!(s.textures.len(), 2);
    let tex: Vec<TexRef> = (1..=4).map(|n| version(&s, "lit", n).texture).collect();
    assert_eq!(tex, [TexRef::Fixed(0), TexRef::Fixed(1), TexRef::Fixed(0), TexRef::Fixed(1)]);
    assert_eq!(s.output, TexRef::Fixed(1));
    assert_eq!(s.memory((64, 64)), MemoryStats { textures: 2, bytes: 2 * px64(8), bytes_saved: 2 * px64(8) });
    assert!(s.textures.iter().all(|t| t.usage == TexUsage { sampled: true, storage: true } && !t.history));
}

#[test]
fn no_pooling_when_lifetimes_overlap() {
    let g = graph(
        &f16(&["x", "y", "out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "b", shader: "gen.wgsl", bind: { dst: "y" }),
           Pass(name: "c", shader: "mix.wgsl", bind: { a: "x", b: "y", dst: "out" }),"#,
        "out",
    );
    let s = ok(&g);
    assert_eq!(s.memory((64, 64)), MemoryStats { textures: 3, bytes: 3 * px64(8), bytes_saved: 0 });
}

/// x (Rgba16Float, half size) -> y (Rgba32Float) -> z (Rgba16Float, `z_size`):
/// x and z have disjoint lifetimes.
fn format_chain(z_size: &str) -> Schedule {
    let resources = format!(
        r#""x": Texture(format: Rgba16Float, size: Scaled(0.5)),
           "y": Texture(format: Rgba32Float, size: Scaled(0.5)),
           "z": Texture(format: Rgba16Float, size: {z_size}),"#
    );
    ok(&graph(
        &resources,
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "x" }),
           Pass(name: "b", shader: "filter32.wgsl", bind: { src: "x", dst: "y" }),
           Pass(name: "c", shader: "filter.wgsl", bind: { src: "y", dst: "z" }),"#,
        "z",
    ))
}

#[test]
fn pooling_only_within_one_format_and_size() {
    // x and z share a descriptor; y (another format) between them does not.
    let s = format_chain("Scaled(0.5)");
    assert_eq!(s.textures.len(), 2);
    assert_eq!(version(&s, "z", 1).texture, version(&s, "x", 1).texture);
    assert_eq!(s.memory((64, 64)).bytes_saved, px64(8) / 4);
    // Another size: no reuse.
    let s = format_chain("Screen");
    assert_eq!(s.memory((64, 64)), MemoryStats { textures: 3, bytes: px64(8) / 4 + px64(16) / 4 + px64(8), bytes_saved: 0 });
}

#[test]
fn in_place_writes_share_one_texture() {
    let g = graph(
        &f16(&["lit", "out"]),
        r#"Pass(name: "a", shader: "gen.wgsl", bind: { dst: "lit" }),
           Pass(name: "b", shader: "edit.wgsl", bind: { img: "lit" }),
           Pass(name: "c", shader: "edit.wgsl", bind: { img: "lit" }),
           Pass(name: "d", shader: "filter.wgsl", bind: { src: "lit", dst: "out" }),"#,
        "out",
    );
    let s = ok(&g);
    assert_eq!(io(&s, "c"), "lit@2 -> lit@3");
    let tex: Vec<TexRef> = (1..=3).map(|n| version(&s, "lit", n).texture).collect();
    assert_eq!(tex, [TexRef::Fixed(0); 3]);
    assert_eq!(s.output, TexRef::Fixed(1));
    assert_eq!(s.memory((64, 64)), MemoryStats { textures: 2, bytes: 2 * px64(8), bytes_saved: 2 * px64(8) });
}

/// `trace` writes `lit`; `acc` reads it and writes `accum` (a history
/// resource) out of place, reading last frame's through `prev`, or in place.
fn history(in_place: bool) -> Schedule {
    let (acc, bind) = if in_place {
        (shader("acc.wgsl", &[("src", tex()), ("accum", inout(F32))]), r#"src: "lit""#)
    } else {
        (shader("acc.wgsl", &[("src", tex()), ("prev", tex()), ("accum", out(F32))]), r#"src: "lit", "prev": "accum""#)
    };
    let passes = format!(
        r#"Pass(name: "trace", shader: "gen32.wgsl", bind: {{ dst: "lit" }}),
           Pass(name: "acc", shader: "acc.wgsl", bind: {{ {bind} }}),"#
    );
    let g = graph(
        r#""lit":   Texture(format: Rgba32Float),
           "accum": Texture(format: Rgba32Float, history: true),"#,
        &passes,
        "accum",
    );
    ok_with(&g, &[acc])
}

#[test]
fn history_written_out_of_place_ping_pongs() {
    let s = history(false);
    assert_eq!(io(&s, "acc"), "lit@1 accum@0 -> accum@1");
    assert!(s.flips_parity);
    let TexRef::PingPong { textures: [t0, t1], slot: 0, flips: true } = version(&s, "accum", 0).texture else {
        panic!("{:?}", version(&s, "accum", 0));
    };
    assert_ne!(t0, t1);
    assert!(s.textures[t0].history && s.textures[t1].history);
    assert_eq!(s.output, TexRef::PingPong { textures: [t0, t1], slot: 1, flips: true });
    assert_eq!(version(&s, "accum", 1).texture, s.output);
    // This frame writes what the next one reads.
    assert_eq!(s.output.resolve(0), version(&s, "accum", 0).texture.resolve(1));
    assert_eq!(s.output.resolve(1), version(&s, "accum", 0).texture.resolve(0));
    assert_eq!(s.memory((64, 64)), MemoryStats { textures: 3, bytes: 3 * px64(16), bytes_saved: 0 });
}

#[test]
fn history_written_in_place_keeps_one_texture() {
    let s = history(true);
    assert_eq!(io(&s, "acc"), "lit@1 accum@0 -> accum@1");
    assert!(!s.flips_parity);
    let t = version(&s, "accum", 0).texture;
    assert!(matches!(t, TexRef::Fixed(i) if s.textures[i].history));
    assert_eq!((version(&s, "accum", 1).texture, s.output), (t, t));
    assert_eq!(s.textures.iter().filter(|t| t.history).count(), 1);
}

// ---------------------------------------------------------------------------
// The shipped graphs, with the real shaders (naga, no GPU).

fn shipped(graph: &str, scene: &str) -> Result<Schedule, UserError> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let features = crate::scene::load(&root.join("scenes").join(scene))?.compile_features();
    let g = super::load_and_compile(&root.join("passes").join(graph), &root.join("shaders"), &features, &CompileOptions::default())?;
    Ok(g.schedule)
}

#[test]
fn shipped_direct_culls_the_missing_light_kind() -> Result<(), UserError> {
    let s = shipped("direct.ron", "cornell-point.ron")?;
    assert_eq!(s.culled, [culled("lights_area", CullReason::Requires(vec![Feature::AreaLights]))]);
    assert_eq!(order(&s), ["gbuffer", "albedo", "lights_point", "accumulate"]);
    assert!(io(&s, "lights_point").ends_with(" lit@1 gbuf_material@1 -> lit@2"), "{}", io(&s, "lights_point"));
    assert_eq!(io(&s, "accumulate"), "lit@2 accum@0 gbuf_pos@1 gbuf_normal@1 accum_geo@0 accum_comp@0 -> accum@1 accum_geo@1 accum_comp@1");

    let s = shipped("direct.ron", "cornell.ron")?;
    assert_eq!(s.culled, [culled("lights_point", CullReason::Requires(vec![Feature::PointLights]))]);
    assert_eq!(order(&s), ["gbuffer", "albedo", "lights_area", "accumulate"]);
    assert!(s.flips_parity);
    Ok(())
}

#[test]
fn shipped_pathtrace_keeps_everything() -> Result<(), UserError> {
    for scene in ["cornell.ron", "cornell-point.ron"] {
        let s = shipped("pathtrace.ron", scene)?;
        assert!(s.culled.is_empty());
        assert_eq!(order(&s), ["pathtrace", "accumulate"]);
        assert_eq!(io(&s, "accumulate"), "radiance@1 accum@0 accum_comp@0 -> accum@1 accum_comp@1");
        assert!(s.flips_parity);
    }
    Ok(())
}

#[test]
fn a_byte_order_mark_is_skipped_and_bad_sizes_are_refused() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/passes/direct.ron")).unwrap();
    let path = std::path::Path::new("direct.ron");
    assert!(FrameGraph::parse(&format!("\u{feff}{text}"), path).is_ok());
    for (size, says) in [("Scaled(NaN)", "Scaled(NaN)"), ("Scaled(-1.0)", "Scaled(-1)"), ("Scaled(inf)", "Scaled(inf)"), ("Fixed(0, 8)", "is empty")] {
        let bad = text.replacen("Texture(format: Rgba32Float)", &format!("Texture(format: Rgba32Float, size: {size})"), 1);
        let e = FrameGraph::parse(&bad, path).unwrap_err().to_string();
        assert!(e.starts_with("direct.ron:") && e.contains(says), "{size}: {e}");
    }
}

#[test]
fn errors_point_at_the_pass_not_a_namesake() {
    // The graph, a resource and a comment all say "blur" before the pass.
    let text = "// \"blur\" runs last\nFrameGraph(name: \"blur\",\n  resources: { \"blur\": Texture(format: Rgba32Float) },\n  passes: [\n    Pass(name: \"a\", shader: \"a.wgsl\", bind: { \"src\": \"blur\" }),\n    Pass(\n      name: \"blur\", shader: \"blur.wgsl\"),\n  ],\n  output: \"blur\")\n";
    let e = CompileError { kind: ErrorKind::UnknownShader, pass: Some("blur".into()), shader_location: None, message: "x".into() };
    let located = super::locate(&e, Path::new("g.ron"), text).to_string();
    assert!(located.starts_with("g.ron:7:"), "{located}");
}

mod graph_constants;
mod listed;
mod pooled;
