//! naga validation errors as a shader's author reads them: at the failing
//! statement's line, in words with WGSL types (no GPU: validation is pure).

use std::path::{Path, PathBuf};

use crate::error::UserError;
use crate::shader::{from_source, source};

const HEAD: &str = "\
@group(0) @binding(0) var albedo: texture_storage_2d<rgba32float, write>;
@group(0) @binding(1) var history: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var<storage, read> weights: array<f32>;

fn tint(c: vec3f, k: u32) -> vec3f {
    return c * f32(k);
}
";

/// `body` as the body of a compute entry point after HEAD, with `extra`
/// (more functions) after it.
fn shader(body: &str, extra: &str) -> String {
    format!(
        "{HEAD}\n@compute @workgroup_size(8, 8)\nfn main(@builtin(global_invocation_id) id: vec3u) {{\n    let shown = vec3f(0.5, 0.25, 1.0);\n{body}\n}}\n{extra}"
    )
}

/// The error validating `text` as the pass shader `t.wgsl` in `dir`.
fn error_in(dir: &Path, text: &str) -> UserError {
    let src = source::expand_text(text, &dir.join("t.wgsl"), dir).unwrap_or_else(|e| panic!("{e}"));
    match from_source(src) {
        Ok(_) => panic!("validates:\n{text}"),
        Err(e) => e,
    }
}

fn error(text: &str) -> UserError {
    error_in(Path::new(env!("CARGO_MANIFEST_DIR")), text)
}

/// The 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap_or_else(|| panic!("no `{needle}`")) + 1
}

/// Checks that `e` is a validation error at `line` that says each of
/// `words` and nothing of naga's internals.
fn assert_worded(e: &UserError, line: usize, words: &[&str]) {
    let text = e.to_string();
    let at = e.location.as_ref().map_or(0, |l| l.line);
    assert_eq!(at, line, "wrong line: {text}");
    assert!(text.contains("WGSL validation error: "), "{text}");
    for internal in ["Vector {", "Scalar {", "Scalar(", "Handle", "Some(", "None", "naga::", "{non-WGSL", "{unnamed"] {
        assert!(!text.contains(internal), "`{internal}` in: {text}");
    }
    let handle = text.as_bytes().windows(3).any(|w| w[0] == b'[' && w[1].is_ascii_digit() && (w[2] == b']' || w[2].is_ascii_digit()));
    assert!(!handle, "a handle in: {text}");
    for word in words {
        assert!(text.contains(word), "no `{word}` in: {text}");
    }
}

#[test]
fn a_vec3_stored_into_an_rgba_texture_is_the_store_s_line() {
    let text = shader("    textureStore(albedo, id.xy, shown);", "");
    let e = error(&text);
    assert_worded(
        &e,
        line_of(&text, "textureStore(albedo"),
        &["`shown`", "vec3<f32>", "vec4<f32>", "`albedo`", "texture_storage_2d<rgba32float, write>"],
    );
    assert_eq!(e.location.as_ref().unwrap().col, 5, "{e}");
}

#[test]
fn an_f32_if_condition_is_the_if_s_line() {
    // A `let` (its span is where it is defined) and a `var` (naga gives no span).
    let text = shader("    let r = shown.x;\n    if r {\n        return;\n    }", "");
    assert_worded(&error(&text), line_of(&text, "if r"), &["`if` condition", "`r`", "f32", "bool"]);
    let text = shader("    var r = shown.x;\n    r *= 2.0;\n    if r {\n        return;\n    }", "");
    assert_worded(&error(&text), line_of(&text, "if r"), &["`r`", "f32"]);
}

#[test]
fn a_wrong_return_type_is_the_return_s_line() {
    let extra = "fn luma(c: vec3f) -> vec3f {\n    let l = dot(c, vec3f(0.3));\n    return l;\n}\n";
    let text = shader("    textureStore(albedo, id.xy, vec4f(luma(shown), 1.0));", extra);
    let e = error(&text);
    assert_worded(&e, line_of(&text, "return l;"), &["fn `luma`", "`return`", "`l` (f32)", "returns vec3<f32>"]);
    // No `return` at all: the function's closing brace, not its first line.
    let extra = "fn pick(a: f32) -> u32 {\n    if a > 0.0 {\n        return 1u;\n    }\n}\n";
    let text = shader("    let p = pick(shown.x);", extra);
    let last = text.lines().count();
    assert_worded(&error(&text), last, &["fn `pick`", "without a `return`", "u32"]);
}

#[test]
fn a_wrong_argument_to_a_user_function_is_the_call_s_line() {
    let text = shader("    let k = 2i;\n    let c = tint(shown, k);", "");
    assert_worded(&error(&text), line_of(&text, "tint(shown, k)"), &["argument 2 of `tint`", "u32", "`k` (i32)"]);
    // Written in place, the argument itself (its column).
    let text = shader("    let c = tint(shown, i32(id.x));", "");
    let e = error(&text);
    assert_worded(&e, line_of(&text, "tint(shown"), &["`i32(id.x)` (i32)", "u32"]);
    let col = text.lines().nth(line_of(&text, "tint(shown") - 1).unwrap().find("i32(").unwrap() + 1;
    assert_eq!(e.location.as_ref().unwrap().col, col, "{e}");
}

#[test]
fn a_wrong_argument_count_says_how_many() {
    let text = shader("    let c = tint(shown);", "");
    assert_worded(&error(&text), line_of(&text, "tint(shown)"), &["`tint` takes 2 arguments", "passes 1"]);
}

#[test]
fn mismatched_operands_and_select_values_name_both_types() {
    let text = shader("    let t = shown * id;", "");
    assert_worded(&error(&text), line_of(&text, "shown * id"), &["`*`", "`shown` (vec3<f32>)", "`id` (vec3<u32>)"]);
    let text = shader("    let s = select(shown, 1.0, id.x > 2u);", "");
    assert_worded(&error(&text), line_of(&text, "select("), &["select", "vec3<f32>", "`1.0` is f32"]);
}

#[test]
fn writes_to_read_only_resources_are_the_write_s_line() {
    // naga points at the declaration; the error is the store.
    let text = shader("    textureStore(history, id.xy, vec4f(shown, 1.0));", "");
    assert_worded(
        &error(&text),
        line_of(&text, "textureStore(history"),
        &["`history`", "texture_storage_2d<rgba32float, read>", "cannot be written"],
    );
    // In a function the entry point calls: that function's line, named.
    let extra = "fn keep(id: vec3u) {\n    textureStore(history, id.xy, vec4f(1.0));\n}\n";
    let text = shader("    keep(id);", extra);
    assert_worded(&error(&text), line_of(&text, "textureStore(history"), &["fn `keep`", "cannot be written"]);
    let text = shader("    let before = textureLoad(albedo, id.xy);", "");
    assert_worded(&error(&text), line_of(&text, "textureLoad(albedo"), &["`albedo`", "cannot be read"]);
    let text = shader("    weights[id.x] = shown.x;", "");
    assert_worded(&error(&text), line_of(&text, "weights[id.x] ="), &["`weights`", "var<storage, read>", "read-only"]);
}

#[test]
fn an_error_in_an_imported_module_names_that_file_and_line() {
    let dir: PathBuf = std::env::temp_dir().join(format!("glint-words-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("shared")).unwrap();
    let helper = "// Tone helpers.\n\nfn brighten(c: vec3f) -> vec3f {\n    let l = dot(c, vec3f(0.3));\n    return l;\n}\n";
    std::fs::write(dir.join("shared/tone.wgsl"), helper).unwrap();
    let text = format!("#import tone\n{}", shader("    textureStore(albedo, id.xy, vec4f(brighten(shown), 1.0));", ""));
    let e = error_in(&dir, &text);
    assert!(e.location.as_ref().unwrap().file.ends_with("shared/tone.wgsl"), "{e}");
    assert_worded(&e, line_of(helper, "return l;"), &["fn `brighten`", "`l` (f32)", "vec3<f32>"]);
    // A type the module may not use, in a function nothing calls.
    let wide = "// Never called.\n\nfn widen(x: f32) -> f64 {\n    return f64(x);\n}\n";
    std::fs::write(dir.join("shared/wide.wgsl"), wide).unwrap();
    let text = format!("#import wide\n{}", shader("", ""));
    let e = error_in(&dir, &text);
    assert!(e.location.as_ref().unwrap().file.ends_with("shared/wide.wgsl"), "{e}");
    assert_worded(&e, line_of(wide, "fn widen"), &["`f64`", "FLOAT64"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_texture_coordinates_are_the_store_s_line() {
    let text = shader("    let px = id.x;\n    textureStore(albedo, px, vec4f(shown, 1.0));", "");
    assert_worded(&error(&text), line_of(&text, "textureStore(albedo, px"), &["textureStore", "`px` (u32)", "2d texture"]);
}
