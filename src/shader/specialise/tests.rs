use std::path::Path;

use super::*;
use crate::shader::{from_source, source};

fn shader(text: &str) -> Shader {
    let src = source::expand_text(text, Path::new("test.wgsl"), Path::new("shaders")).expect("no imports");
    from_source(src).expect("the test shader is valid")
}

fn function_names(m: &Module) -> Vec<String> {
    m.functions.iter().filter_map(|(_, f)| f.name.clone()).collect()
}

const FLAGGED: &str = "
override FLAG: bool = true;
@group(0) @binding(0) var<storage, read_write> out: array<f32>;
fn heavy(x: f32) -> f32 { var s = 0.0; for (var i = 0; i < 8; i++) { s += sin(x * f32(i)); } return s; }
fn light(x: f32) -> f32 { return x * 2.0; }
@compute @workgroup_size(1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    var v = light(f32(id.x));
    if FLAG {
        let h = heavy(v);
        v += h;
    } else {
        v -= 1.0;
    }
    out[id.x] = v;
}
@compute @workgroup_size(1)
fn other() { out[0] = heavy(1.0); }
";

#[test]
fn a_branch_on_a_false_constant_and_the_functions_only_it_called_are_gone() {
    let s = shader(FLAGGED);
    let off = specialised_module(&s, "main", &[("FLAG", 0.0)]).unwrap();
    assert_eq!(function_names(&off), vec!["light".to_string()]);
    assert_eq!(off.entry_points.len(), 1, "only the pipeline's entry point is kept");
    let on = specialised_module(&s, "main", &[("FLAG", 1.0)]).unwrap();
    let mut names = function_names(&on);
    names.sort();
    assert_eq!(names, vec!["heavy".to_string(), "light".to_string()]);
    // No `if` is left in the entry point either way.
    for m in [&off, &on] {
        let ifs = m.entry_points[0].function.body.iter().filter(|s| matches!(s, Statement::If { .. })).count();
        assert_eq!(ifs, 0);
    }
}

#[test]
fn the_default_applies_when_no_constant_is_given_and_other_entries_keep_their_calls() {
    let s = shader(FLAGGED);
    let default = specialised_module(&s, "main", &[]).unwrap();
    assert!(function_names(&default).contains(&"heavy".to_string()));
    let other = specialised_module(&s, "other", &[("FLAG", 0.0)]).unwrap();
    assert_eq!(function_names(&other), vec!["heavy".to_string()]);
}

#[test]
fn a_branch_on_a_runtime_value_stays() {
    let s = shader(&FLAGGED.replace("if FLAG {", "if id.x > 3u {"));
    let m = specialised_module(&s, "main", &[("FLAG", 0.0)]).unwrap();
    assert!(function_names(&m).contains(&"heavy".to_string()));
}

#[test]
fn an_unknown_constant_is_an_error_in_words() {
    let s = shader(FLAGGED);
    let e = specialised_module(&s, "main", &[("NOPE", 1.0)]).unwrap_err();
    assert!(e.contains("NOPE"), "{e}");
}

/// The G-buffer pass of a scene without textures loses the texture code:
/// the driver no longer compiles what the scene can never run. The lights
/// pass has none either way: it reads the G-buffer's texture factors.
#[test]
fn the_gbuffer_pass_of_an_untextured_scene_has_no_texture_code() {
    let s = crate::shader::load(Path::new("shaders"), "gbuffer.wgsl").unwrap();
    let plain = specialised_module(&s, "main", &[("SCENE_TEXTURES", 0.0), ("SCENE_METALLIC_ROUGHNESS", 0.0)]).unwrap();
    let textured = specialised_module(&s, "main", &[("SCENE_TEXTURES", 1.0), ("SCENE_METALLIC_ROUGHNESS", 1.0)]).unwrap();
    let (p, t) = (function_names(&plain), function_names(&textured));
    assert!(!p.contains(&"sample_material".to_string()), "{p:?}");
    assert!(t.contains(&"sample_material".to_string()), "{t:?}");
    assert!(p.len() < t.len(), "{} functions against {}", p.len(), t.len());
    let lights = crate::shader::load(Path::new("shaders"), "lights.wgsl").unwrap();
    let lit = specialised_module(&lights, "main", &[("SCENE_TEXTURES", 1.0), ("SCENE_METALLIC_ROUGHNESS", 1.0)]).unwrap();
    assert!(!function_names(&lit).contains(&"sample_material".to_string()));
}

/// `!FLAG || x` is true with FLAG false whatever x is; naga lowers it to a
/// temporary and two `if`s, and the code after the early return goes.
#[test]
fn a_short_circuit_decided_by_a_constant_removes_the_code_after_its_return() {
    let s = shader(
        "
override FLAG: bool = true;
@group(0) @binding(0) var<storage, read_write> out: array<f32>;
fn heavy(x: f32) -> f32 { var s = 0.0; for (var i = 0; i < 8; i++) { s += sin(x * f32(i)); } return s; }
fn value(i: u32) -> f32 {
    if !FLAG || i == 7u {
        return 1.0;
    }
    return heavy(f32(i));
}
@compute @workgroup_size(1)
fn main(@builtin(global_invocation_id) id: vec3u) { out[id.x] = value(id.x); }
",
    );
    let off = specialised_module(&s, "main", &[("FLAG", 0.0)]).unwrap();
    assert_eq!(function_names(&off), vec!["value".to_string()]);
    let on = specialised_module(&s, "main", &[("FLAG", 1.0)]).unwrap();
    assert!(function_names(&on).contains(&"heavy".to_string()));
}

/// Every shipped shader's every entry point specialises to a valid module
/// with its defaults and with every boolean override false (each scene
/// feature compiled out): resolving `if`s never leaves naga's validator
/// something it refuses.
#[test]
fn every_shipped_entry_point_specialises_to_a_valid_module() {
    let dir = Path::new("shaders");
    let names = source::pass_shaders(dir).unwrap();
    assert!(names.len() > 20, "{names:?}");
    let mut checked = 0;
    for name in names {
        let s = crate::shader::load(dir, &name).unwrap();
        let bools: Vec<&str> = s.info.overrides.iter().filter(|o| o.scalar == crate::shader::ScalarType::Bool).map(|o| o.name.as_str()).collect();
        let unset: Vec<(&str, f64)> = s.info.overrides.iter().filter(|o| !o.has_default).map(|o| (o.name.as_str(), 1.0)).collect();
        for e in &s.info.entry_points {
            let mut off: Vec<(&str, f64)> = bools.iter().map(|b| (*b, 0.0)).collect();
            off.extend(unset.iter().filter(|(k, _)| !bools.contains(k)).copied());
            for constants in [&unset, &off] {
                if let Err(err) = specialised_module(&s, &e.name, constants) {
                    panic!("{name} `{}` with {constants:?}: {err}", e.name);
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 40, "{checked}");
}
