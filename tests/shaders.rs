//! Every shader in shaders/ parses and validates with naga, and the WGSL
//! structs match their Rust mirrors byte for byte. No GPU needed.

mod common;

use common::repo;
use glint::session::frame_uniform::{CameraGpu, FrameGpu};
use glint::bvh::scene::InstanceGpu;
use glint::bvh::BvhNode;
use glint::scene::{LightGpu, MaterialGpu, MeshGpu, SphereGpu, TriangleGpu, TriangleNormalsGpu};
use std::mem::{offset_of, size_of};

#[test]
fn every_shader_validates() {
    let dir = repo().join("shaders");
    let mut n = 0;
    let passes = glint::shader::source::pass_shaders(&dir).unwrap();
    assert!(passes.iter().any(|p| p.starts_with("realtime/")), "the shaders in folders are listed: {passes:?}");
    for name in passes {
        glint::shader::load(&dir, &name).unwrap_or_else(|e| panic!("{e}"));
        n += 1;
    }
    for entry in std::fs::read_dir(dir.join("shared")).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".wgsl") {
            // A module with hooks (`// hook: fn name(..)`, functions the
            // importing shader defines) validates with empty ones.
            let path = dir.join("shared").join(&name);
            let mut text = std::fs::read_to_string(&path).unwrap();
            let hooks: Vec<String> = text.lines().filter_map(|l| l.trim().strip_prefix("// hook: ")).map(|sig| format!("{sig} {{}}\n")).collect();
            text.extend(hooks);
            let source = glint::shader::source::expand_text(&text, &path, &dir).unwrap_or_else(|e| panic!("{e}"));
            glint::shader::from_source(source).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 10, "only {n} shaders found");
}

/// (size, [(member, offset)]) of a WGSL struct, from naga.
fn wgsl_layout(module: &naga::Module, name: &str) -> (u32, Vec<(String, u32)>) {
    let ty = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("no struct {name}")).1;
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("{name} is not a struct") };
    (*span, members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset)).collect())
}

#[test]
fn wgsl_structs_match_rust() {
    let shader = glint::shader::load(&repo().join("shaders"), "shared/scene.wgsl").unwrap_or_else(|e| panic!("{e}"));
    let m = &shader.module;
    macro_rules! check {
        ($wgsl:literal, $rust:ty, [$($field:ident),*]) => {{
            let (size, members) = wgsl_layout(m, $wgsl);
            assert_eq!(size as usize, size_of::<$rust>(), "size of {}", $wgsl);
            $(
                let off = members.iter().find(|(n, _)| n == stringify!($field)).unwrap_or_else(|| panic!("{}.{}", $wgsl, stringify!($field))).1;
                assert_eq!(off as usize, offset_of!($rust, $field), "{}.{}", $wgsl, stringify!($field));
            )*
        }};
    }
    check!("Camera", CameraGpu, [origin, tan_half_fov, right, aspect, up, forward]);
    check!("Frame", FrameGpu, [camera, prev_camera, size, frame_index, accum_count, time, seed, scene_epoch, n_spheres, n_instances, n_triangles, n_lights, mask_threshold, background, epoch_frames, exact_one, offset_scale]);
    check!("TriangleNormals", TriangleNormalsGpu, [n0, n1, n2]);
    check!("Mesh", MeshGpu, [bmin, first, bmax, count]);
    check!("Material", MaterialGpu, [albedo, specular, emission, roughness]);
    check!("Light", LightGpu, [position, radius, color, kind, spot]);
    // Structs the shaders read as whole vec4s: each WGSL member holds the
    // Rust fields at the given byte offsets into it (a vec3 at 0, then w at 12).
    packed(m, "Sphere", size_of::<SphereGpu>(), &[
        ("geo", &[("center", offset_of!(SphereGpu, center), 0), ("radius", offset_of!(SphereGpu, radius), 12)]),
        ("ids", &[("material", offset_of!(SphereGpu, material), 0), ("light", offset_of!(SphereGpu, light), 4), ("object", offset_of!(SphereGpu, object), 8)]),
    ]);
    packed(m, "Triangle", size_of::<TriangleGpu>(), &[
        ("p0", &[("p0", offset_of!(TriangleGpu, p0), 0), ("material", offset_of!(TriangleGpu, material), 12)]),
        ("p1", &[("p1", offset_of!(TriangleGpu, p1), 0), ("object", offset_of!(TriangleGpu, object), 12)]),
        ("p2", &[("p2", offset_of!(TriangleGpu, p2), 0)]),
    ]);
    let bvh = glint::shader::load(&repo().join("shaders"), "shared/bvh.wgsl").unwrap_or_else(|e| panic!("{e}"));
    packed(&bvh.module, "BvhNode", size_of::<BvhNode>(), &[
        ("lo", &[("bmin", offset_of!(BvhNode, bmin), 0), ("left_first", offset_of!(BvhNode, left_first), 12)]),
        ("hi", &[("bmax", offset_of!(BvhNode, bmax), 0), ("count", offset_of!(BvhNode, count), 12)]),
    ]);
    packed(&bvh.module, "Instance", size_of::<InstanceGpu>(), &[
        ("v", &[("kind", offset_of!(InstanceGpu, kind), 0), ("index", offset_of!(InstanceGpu, index), 4)]),
    ]);
}

/// (Rust field, its offset, where it must sit in the WGSL member).
type Lanes<'a> = &'a [(&'a str, usize, usize)];

/// Checks a WGSL struct of vec4 members against its Rust mirror: the same
/// size, and each member's Rust fields where the member says.
fn packed(m: &naga::Module, wgsl: &str, rust_size: usize, members: &[(&str, Lanes)]) {
    let (size, layout) = wgsl_layout(m, wgsl);
    assert_eq!(size as usize, rust_size, "size of {wgsl}");
    for (member, fields) in members {
        let base = layout.iter().find(|(n, _)| n == member).unwrap_or_else(|| panic!("{wgsl}.{member}")).1 as usize;
        for (field, offset, within) in fields.iter() {
            assert_eq!(*offset, base + within, "{wgsl}.{member}: Rust field {field}");
        }
    }
}

#[test]
fn shader_errors_point_at_the_original_file_and_line() {
    let dir = common::scratch("bad-shader");
    std::fs::create_dir_all(dir.join("shared")).unwrap();
    std::fs::write(dir.join("shared/helper.wgsl"), "fn helper() -> f32 {\n    return 1.0;\n}\n").unwrap();
    // A type error on line 4 of the pass file, after an import.
    std::fs::write(dir.join("bad.wgsl"), "#import helper\n\n@compute @workgroup_size(1)\nfn main() { let x: u32 = helper(); }\n").unwrap();
    let err = glint::shader::load(&dir, "bad.wgsl").unwrap_err().to_string();
    assert!(err.contains("bad.wgsl:4"), "{err}");
    // A syntax error inside the imported file points into it.
    std::fs::write(dir.join("shared/helper.wgsl"), "fn helper() -> f32 {\n    return 1.0 +;\n}\n").unwrap();
    let err = glint::shader::load(&dir, "bad.wgsl").unwrap_err().to_string();
    assert!(err.contains("helper.wgsl:2"), "{err}");
}
