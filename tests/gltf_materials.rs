//! glTF metallic-roughness and normal textures on the GPU: a quad facing
//! the camera under a sun, alone against a black sky, so the path tracer's
//! image is the direct light f(v, l) E cos(n, l) (src/brdf.rs) and
//! nothing else.

mod common;

use common::*;
use glam::Vec3;
use glint::brdf::{self, MetalRough};

/// A quad filling a 32x32 view (camera at z = 2), u along +x and v down
/// (glTF's), its material `material` (JSON) reading 1x1 images `texels`
/// (texture i is image i, repeat), lit by a sun travelling along `sun`.
fn quad_scene(dir: &std::path::Path, name: &str, material: &str, texels: &[[u8; 4]], sun: Vec3) -> std::path::PathBuf {
    quad_scene_with(dir, name, material, texels, sun, &[])
}

/// `quad_scene` with more float attributes at its four corners: (name,
/// glTF type, values).
fn quad_scene_with(dir: &std::path::Path, name: &str, material: &str, texels: &[[u8; 4]], sun: Vec3, extra: &[(&str, &str, Vec<f32>)]) -> std::path::PathBuf {
    use base64::Engine as _;
    let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b);
    let images: Vec<String> = texels
        .iter()
        .map(|t| {
            let img = image::RgbaImage::from_raw(1, 1, t.to_vec()).expect("image");
            let mut png = std::io::Cursor::new(Vec::new());
            img.write_to(&mut png, image::ImageFormat::Png).expect("encode");
            format!(r#"{{"uri": "data:image/png;base64,{}"}}"#, b64(png.get_ref()))
        })
        .collect();
    let textures: Vec<String> = (0..texels.len()).map(|i| format!(r#"{{"source": {i}}}"#)).collect();
    let pos: [[f32; 3]; 4] = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    let uv: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let mut blob: Vec<u8> = pos.iter().flatten().chain(uv.iter().flatten()).flat_map(|x| x.to_le_bytes()).collect();
    blob.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    blob.extend([0u8; 4]);
    let (mut attributes, mut accessors, mut views) = (String::new(), String::new(), String::new());
    for (k, (attr, ty, values)) in extra.iter().enumerate() {
        attributes += &format!(r#", "{attr}": {}"#, k + 3);
        accessors += &format!(r#", {{"bufferView": {}, "componentType": 5126, "count": 4, "type": "{ty}"}}"#, k + 3);
        views += &format!(r#", {{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, blob.len(), 4 * values.len());
        blob.extend(values.iter().flat_map(|x| x.to_le_bytes()));
    }
    let gltf = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1{attributes}}}, "indices": 2, "material": 0}}]}}],
  "materials": [{material}], "textures": [{}], "images": [{}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}}, {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}{accessors}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}{views}],
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}]}}"#,
        textures.join(", "),
        images.join(", "),
        blob.len(),
        b64(&blob)
    );
    std::fs::write(dir.join(format!("{name}.gltf")), gltf).expect("write");
    let scene = dir.join(format!("{name}.ron"));
    let vfov = 2.0 * 0.5f64.atan().to_degrees();
    std::fs::write(
        &scene,
        format!(
            "Scene(camera: Camera(position: (0.0, 0.0, 2.0), target: (0.0, 0.0, 0.0), vfov_deg: {vfov}), objects: [Gltf(path: \"{name}.gltf\")], lights: [DirectionalLight(direction: ({}, {}, {}), irradiance: (1.0, 1.0, 1.0))])",
            sun.x, sun.y, sun.z
        ),
    )
    .expect("write");
    scene
}

/// The rough white dielectric the normal-texture tests use.
const BENT_MATERIAL: &str = r#"{"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 1}, "normalTexture": {"index": 0}}"#;

/// A normal texture's texel as the normal it encodes.
fn decode(t: [u8; 4]) -> Vec3 {
    Vec3::new(t[0] as f32, t[1] as f32, t[2] as f32) / 255.0 * 2.0 - Vec3::ONE
}

/// The centre pixel of `scene` rendered by `graph` at 32x32, 2 frames.
fn centre_rendered(scene: &std::path::Path, graph: &str) -> Vec3 {
    let scene = glint::scene::load(scene).unwrap_or_else(|e| panic!("{e}"));
    centre_32(&render(gpu().expect("gpu"), scene, &repo().join(graph), (32, 32), 2, None))
}

/// Asserts that `img`'s centre is the direct light of a sun toward `l` on
/// the rough white dielectric with shading normal `n`, seen along +z:
/// f(v, l) E cos (src/brdf.rs), within 3%.
fn assert_lit_as_bent(img: &glint::gpu::readback::ImageF32, n: Vec3, l: Vec3, what: &str) {
    let m = MetalRough { base: Vec3::ONE, metallic: 0.0, roughness: 1.0 };
    let want = brdf::eval(&m, n, Vec3::Z, l) * n.dot(l).max(0.0);
    let got = centre_32(img);
    eprintln!("{what}: {:.4} (want {:.4})", got.x, want.x);
    assert!((got - want).abs().max_element() <= 0.03 * want.max_element() + 1e-3, "{what}: {got}, want {want}");
}

#[test]
fn a_metallic_roughness_texture_multiplies_the_factors() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("gltf-mr-texture");
    let sun = Vec3::new(-0.3, 0.0, -1.0);
    // Green 128 is roughness 0.502, blue 255 metalness 1, times the factors
    // (1, 1); the same as untextured factors (1, 0.502), not as (0, 0.502).
    let textured = quad_scene(&dir, "textured", r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.3, 1], "metallicRoughnessTexture": {"index": 0}}}"#, &[[0, 128, 255, 255]], sun);
    let factors = |name: &str, metallic: f32| {
        let material = format!(r#"{{"pbrMetallicRoughness": {{"baseColorFactor": [0.9, 0.6, 0.3, 1], "metallicFactor": {metallic}, "roughnessFactor": 0.502}}}}"#);
        path_traced_32(&quad_scene(&dir, name, &material, &[], sun))
    };
    let (img, metal, dielectric) = (path_traced_32(&textured), factors("metal", 1.0), factors("dielectric", 0.0));
    let (same, _) = glint::metrics::flip(&metal, &img);
    let (other, _) = glint::metrics::flip(&dielectric, &img);
    eprintln!("textured against factors (1, 0.502): FLIP {:.4}; against (0, 0.502): {:.4}", same.mean, other.mean);
    assert!(same.mean <= 0.01, "the textured quad is not the metal of the same roughness: FLIP {}", same.mean);
    assert!(other.mean > 0.1, "the texture's metalness did not show: FLIP {} against the dielectric", other.mean);
}

#[test]
fn a_normal_texture_bends_the_shading_normal_its_way() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("gltf-normal-texture");
    let material = BENT_MATERIAL;
    // A flat texel changes nothing; one bent toward +x in the image (u)
    // bends the normal toward world +x, one bent toward the image's top
    // toward world +y (the image's top is v = 0, at y = 1): each faces its
    // own sun head-on, and the other's at 60 degrees.
    let flat = [128, 128, 255, 255];
    let (right, up) = ([218, 128, 218, 255], [128, 218, 218, 255]);
    let plain = path_traced_32(&quad_scene(&dir, "plain", r#"{"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 1}}"#, &[], Vec3::new(-1.0, 0.0, -1.0)));
    let (flat_flip, _) = glint::metrics::flip(&plain, &path_traced_32(&quad_scene(&dir, "flat", material, &[flat], Vec3::new(-1.0, 0.0, -1.0))));
    eprintln!("a flat normal texture against none: FLIP {:.4}", flat_flip.mean);
    assert!(flat_flip.mean <= 0.01, "a flat normal texture changed the image: FLIP {}", flat_flip.mean);
    for (name, texel, world) in [("right", right, Vec3::X), ("up", up, Vec3::Y)] {
        let c = decode(texel);
        let n = (world * c.x.max(c.y) + Vec3::Z * c.z).normalize();
        for (sun_name, toward) in [("x", Vec3::new(1.0, 0.0, 1.0)), ("y", Vec3::new(0.0, 1.0, 1.0))] {
            let l = toward.normalize();
            let img = path_traced_32(&quad_scene(&dir, &format!("{name}-{sun_name}"), material, &[texel], -l));
            assert_lit_as_bent(&img, n, l, &format!("normal bent {name}, sun toward {sun_name}"));
        }
    }
}

#[test]
fn a_normal_texture_bends_in_the_frame_of_the_files_tangents() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("gltf-tangents");
    // A texel bent toward the texture's +x, in a frame whose tangent the
    // file turns to world +y (and whose bitangent, cross(n, t) w with w =
    // -1, to +x): the normal bends toward +y, not along u (+x).
    let right = [218u8, 128, 218, 255];
    let c = decode(right);
    // (glTF ignores a primitive's tangents where it has no normals.)
    let attributes = [("NORMAL", "VEC3", [0.0, 0.0, 1.0].repeat(4)), ("TANGENT", "VEC4", [0.0, 1.0, 0.0, -1.0].repeat(4))];
    for (sun_name, toward) in [("x", Vec3::new(1.0, 0.0, 1.0)), ("y", Vec3::new(0.0, 1.0, 1.0))] {
        let l = toward.normalize();
        let n = (Vec3::Y * c.x + Vec3::Z * c.z).normalize();
        let img = path_traced_32(&quad_scene_with(&dir, &format!("turned-{sun_name}"), BENT_MATERIAL, &[right], -l, &attributes));
        assert_lit_as_bent(&img, n, l, &format!("the file's tangent along +y, sun toward {sun_name}"));
    }
}

#[test]
fn vertex_colours_multiply_the_base_colour() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("gltf-vertex-colours");
    let sun = Vec3::new(0.0, 0.0, -1.0);
    let tint = [1.0, 0.5, 0.25];
    let coloured = quad_scene_with(&dir, "coloured", r#"{"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 1}}"#, &[], sun, &[("COLOR_0", "VEC3", tint.repeat(4))]);
    let factor = quad_scene(&dir, "factor", r#"{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1], "metallicFactor": 0, "roughnessFactor": 1}}"#, &[], sun);
    for graph in ["passes/pathtrace.ron", "passes/hybrid.ron"] {
        let (got, want) = (centre_rendered(&coloured, graph), centre_rendered(&factor, graph));
        eprintln!("{graph}: vertex colours {got}, base colour factor {want}");
        assert!(want.x > 0.1 && (got - want).abs().max_element() <= 0.005 * want.max_element(), "{graph}: {got} against {want}");
    }
}

#[test]
fn a_single_sided_material_is_seen_from_its_front_only() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("gltf-single-sided");
    // An emitter, so either face shows whatever lights it; the sun comes
    // from the side, along the quad.
    let sun = Vec3::new(1.0, 0.0, 0.0);
    for (name, material, from_behind) in [
        ("single", r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}, "emissiveFactor": [1, 0.5, 0.25]}"#, false),
        ("double", r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}, "emissiveFactor": [1, 0.5, 0.25], "doubleSided": true}"#, true),
    ] {
        let front = quad_scene(&dir, name, material, &[[255, 255, 255, 255]], sun);
        let text = std::fs::read_to_string(&front).expect("read");
        let behind = dir.join(format!("{name}-behind.ron"));
        std::fs::write(&behind, text.replace("position: (0.0, 0.0, 2.0)", "position: (0.0, 0.0, -2.0)")).expect("write");
        for graph in ["passes/pathtrace.ron", "passes/hybrid.ron"] {
            let (f, b) = (centre_rendered(&front, graph), centre_rendered(&behind, graph));
            eprintln!("{name}-sided, {graph}: from the front {f}, from behind {b}");
            assert!((f - Vec3::new(1.0, 0.5, 0.25)).abs().max_element() < 0.02, "{name}-sided, {graph}: the front shows {f}");
            if from_behind {
                assert!((b - f).abs().max_element() < 0.02, "{name}-sided, {graph}: the back shows {b}, the front {f}");
            } else {
                assert!(b.max_element() < 1e-6, "{name}-sided, {graph}: rays from behind met the quad: {b}");
            }
        }
    }
}
