//! The glTF reader on files written here: a triangle in a data URI, then
//! each way of breaking it.

use base64::Engine as _;
use gltf::json::Value;

use super::*;

/// Positions (f32 x 3 each) then u16 indices, as one buffer.
fn buffer(positions: &[[f32; 3]], indices: &[u16]) -> Vec<u8> {
    let mut b: Vec<u8> = positions.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    b.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    b
}

const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// A one-triangle glTF: mesh 0 placed by node 0 under node 1, its buffer
/// as `uri` (None: the GLB chunk).
fn triangle_json(uri: Option<&str>, bytes: usize) -> Value {
    let mut buffer = format!(r#"{{"byteLength": {bytes}}}"#);
    if let Some(uri) = uri {
        buffer = format!(r#"{{"byteLength": {bytes}, "uri": "{uri}"}}"#);
    }
    let text = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [1]}}],
  "nodes": [{{"mesh": 0, "scale": [2, 2, 2]}}, {{"children": [0], "translation": [1e9, 0, 0]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}}
  ],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 6}}],
  "buffers": [{buffer}]
}}"#
    );
    gltf::json::deserialize::from_str(&text).expect("fixture JSON")
}

fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

/// A scratch folder of its own for each test, removed when dropped.
struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        std::fs::remove_dir_all(&self.0).ok();
    }
}

fn scratch(name: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("glint-gltf-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    Scratch(dir)
}

fn write_json(dir: &Path, v: &Value) -> PathBuf {
    let path = dir.join("t.gltf");
    std::fs::write(&path, gltf::json::serialize::to_string_pretty(v).expect("serialise")).expect("write");
    path
}

/// The error reading `v` (with the triangle's bytes in a data URI).
fn error_of(name: &str, edit: impl FnOnce(&mut Value), positions: &[[f32; 3]], indices: &[u16]) -> String {
    let bytes = buffer(positions, indices);
    let mut v = triangle_json(Some(&data_uri(&bytes)), bytes.len());
    edit(&mut v);
    let dir = scratch(name);
    let path = write_json(&dir, &v);
    match read(&path) {
        Ok(_) => panic!("{name}: the broken file was read"),
        Err(e) => {
            eprintln!("{name}: {e}");
            assert!(e.contains("t.gltf"), "{name}: the message names the file: {e}");
            e
        }
    }
}

#[test]
fn a_triangle_in_a_data_uri_is_placed_by_its_nodes_in_f64() {
    let bytes = buffer(&TRIANGLE, &[0, 1, 2]);
    let dir = scratch("data-uri");
    let path = write_json(&dir, &triangle_json(Some(&data_uri(&bytes)), bytes.len()));
    let f = read(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.instances.len(), 1);
    assert_eq!(f.meshes[0].len(), 1);
    let t = f.meshes[0][0];
    assert_eq!(t.p, TRIANGLE.map(Vec3::from_array));
    assert_eq!(t.n, [Vec3::Z; 3], "flat normals where the file has none");
    assert_eq!(t.material, None, "the default material");
    // Parent at x = 1e9 (beyond f32's integer precision), child scaled by 2.
    let (lo, hi) = f.bounds().expect("bounds");
    assert_eq!(lo, DVec3::new(1e9, 0.0, 0.0));
    assert_eq!(hi, DVec3::new(1e9 + 2.0, 2.0, 0.0));
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
}

#[test]
fn a_glb_and_an_external_buffer_read_the_same() {
    let bytes = buffer(&TRIANGLE, &[0, 1, 2]);
    let dir = scratch("glb");
    // External, with a space in its percent-encoded name.
    std::fs::write(dir.join("tri angle.bin"), &bytes).expect("write");
    let external = read(&write_json(&dir, &triangle_json(Some("tri%20angle.bin"), bytes.len()))).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(external.files, vec![dir.join("tri angle.bin")]);
    // GLB: header, JSON chunk (padded with spaces), BIN chunk.
    let mut json = gltf::json::serialize::to_vec(&triangle_json(None, bytes.len())).expect("json");
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bytes.len();
    let mut glb = Vec::new();
    glb.extend(b"glTF");
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&json);
    glb.extend((bytes.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bytes);
    std::fs::write(dir.join("t.glb"), &glb).expect("write");
    let binary = read(&dir.join("t.glb")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(binary.meshes, external.meshes);
    assert_eq!(binary.instances, external.instances);
    // A GLB cut short says so.
    std::fs::write(dir.join("short.glb"), &glb[..30]).expect("write");
    let e = read(&dir.join("short.glb")).expect_err("a short GLB was read");
    assert!(e.contains("short.glb") && e.contains("GLB"), "{e}");
}

#[test]
fn strips_normals_lights_cameras_and_materials_convert() {
    let bytes = buffer(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]], &[]);
    let mut v = triangle_json(Some(&data_uri(&bytes)), bytes.len());
    let prim = &mut v["meshes"][0]["primitives"][0];
    prim.as_object_mut().expect("object").remove("indices");
    prim["mode"] = Value::from(5);
    prim["material"] = Value::from(0);
    v["accessors"].as_array_mut().expect("array").truncate(1);
    v["accessors"][0]["count"] = Value::from(4);
    v["accessors"][0]["max"] = gltf::json::deserialize::from_str("[1, 1, 0]").expect("json");
    v["bufferViews"] = gltf::json::deserialize::from_str(r#"[{"buffer": 0, "byteLength": 48}]"#).expect("json");
    v["materials"] = gltf::json::deserialize::from_str(
        r#"[{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 1], "metallicFactor": 0.25, "roughnessFactor": 0.75},
             "emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}]"#,
    )
    .expect("json");
    v["extensionsUsed"] = gltf::json::deserialize::from_str(r#"["KHR_lights_punctual", "KHR_materials_emissive_strength", "EXT_other"]"#).expect("json");
    v["extensions"] = gltf::json::deserialize::from_str(r#"{"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 0.5, 0.25], "intensity": 683}, {"type": "spot", "spot": {}}, {"type": "directional", "intensity": 1366}]}}"#).expect("json");
    v["cameras"] = gltf::json::deserialize::from_str(r#"[{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}]"#).expect("json");
    v["nodes"] = gltf::json::deserialize::from_str(
        r#"[{"mesh": 0}, {"children": [0, 2, 3, 4, 5]}, {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 3, 0]},
            {"camera": 0, "translation": [0, 0, 5]}, {"extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"extensions": {"KHR_lights_punctual": {"light": 2}}, "rotation": [-0.7071068, 0, 0, 0.7071068]}]"#,
    )
    .expect("json");
    let f = read(&write_json(&scratch("strip"), &v)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.meshes[0].len(), 2, "a strip of four vertices is two triangles");
    assert!(f.meshes[0].iter().all(|t| t.n == [Vec3::Z; 3]), "both face +z: the strip's second triangle turns back");
    // (Single-sided: glTF's default.)
    let single = MaterialGpu { flags: crate::scene::MATERIAL_SINGLE_SIDED, ..MaterialGpu::metal_rough([0.5, 0.25, 1.0], 0.25, 0.75, [4.0, 2.0, 0.0]) };
    assert_eq!(f.materials, vec![single]);
    assert_eq!(f.lights[0], PointLight { position: DVec3::new(0.0, 3.0, 0.0), intensity: Vec3::new(1.0, 0.5, 0.25), spot: None, directional: None }, "683 cd is 1 W/sr");
    // The spot light: glTF's default cone (0 to pi/4) down the node's -z.
    let spot = f.lights[1].spot.expect("a cone");
    assert_eq!(spot.direction, Vec3::NEG_Z);
    assert!((spot.cos_inner - 1.0).abs() < 1e-6 && (spot.cos_outer - std::f32::consts::FRAC_PI_4.cos()).abs() < 1e-6, "{spot:?}");
    // The sun: 1366 lux is 2 W/m^2; turned -90 degrees about x, its -z
    // points down.
    let sun = f.lights[2];
    assert_eq!(sun.intensity, Vec3::splat(2.0));
    assert!(sun.directional.expect("directional").abs_diff_eq(Vec3::NEG_Y, 1e-6), "{sun:?}");
    let c = f.cameras[0];
    assert_eq!((c.position, c.target), (DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, 4.0)), "a glTF camera looks down -z");
    assert!((c.vfov_deg - 0.5f64.to_degrees()).abs() < 1e-6);
    let warnings = f.warnings.join("\n");
    assert!(warnings.contains("EXT_other") && !warnings.contains("KHR_lights_punctual"), "{warnings}");
}

#[test]
fn each_broken_file_names_what_is_wrong_and_where() {
    let t = &TRIANGLE;
    let e = error_of("json", |v| v["asset"] = Value::from(3), t, &[0, 1, 2]);
    assert!(e.contains("t.gltf:26:12: not glTF JSON: invalid type") && !e.contains(" at line"), "{e}");
    let e = error_of("missing-buffer", |v| v["buffers"][0]["uri"] = Value::from("gone.bin"), t, &[0, 1, 2]);
    assert!(e.contains("buffers[0].uri") && e.contains("gone.bin"), "{e}");
    let e = error_of("vec2", |v| v["accessors"][0]["type"] = Value::from("VEC2"), t, &[0, 1, 2]);
    assert!(e.contains("meshes[0].primitives[0].attributes.POSITION") && e.contains("Vec2"), "{e}");
    let e = error_of("count", |v| v["accessors"][0]["count"] = Value::from(4), t, &[0, 1, 2]);
    assert!(e.contains("attributes.POSITION") && e.contains("run past"), "{e}");
    let e = error_of("index", |_| {}, t, &[0, 1, 7]);
    assert!(e.contains("meshes[0].primitives[0].indices") && e.contains("index 2 is 7"), "{e}");
    let e = error_of("points", |v| v["meshes"][0]["primitives"][0]["mode"] = Value::from(0), t, &[0, 1, 2]);
    assert!(e.contains("primitives[0].mode") && e.contains("Points"), "{e}");
    let e = error_of("nan", |_| {}, &[[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2]);
    assert!(e.contains("attributes.POSITION") && e.contains("vertex 1 is not finite"), "{e}");
    let e = error_of("required", |v| v["extensionsRequired"] = gltf::json::deserialize::from_str(r#"["KHR_draco_mesh_compression"]"#).expect("json"), t, &[0, 1, 2]);
    assert!(e.contains("extensionsRequired[0]") && e.contains("KHR_draco_mesh_compression"), "{e}");
    let e = error_of("bad-ref", |v| v["nodes"][0]["mesh"] = Value::from(9), t, &[0, 1, 2]);
    assert!(e.contains("nodes[0].mesh: refers to an item the file does not have"), "{e}");
    let e = error_of("cycle", |v| v["nodes"][0]["children"] = gltf::json::deserialize::from_str("[1]").expect("json"), t, &[0, 1, 2]);
    assert!(e.contains("cycle") || e.contains("cannot be a root"), "{e}");
    let e = error_of("metallic", |v| v["materials"] = gltf::json::deserialize::from_str(r#"[{"pbrMetallicRoughness": {"metallicFactor": 2}}]"#).expect("json"), t, &[0, 1, 2]);
    assert!(e.contains("materials[0].pbrMetallicRoughness.metallicFactor") && e.contains("outside 0..1"), "{e}");
}

/// A 2x1 PNG: red, then green.
fn png() -> Vec<u8> {
    let img = image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, 255, 0, 255, 0, 255]).expect("image");
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).expect("encode");
    out.into_inner()
}

#[test]
fn textures_uvs_and_transforms_are_read() {
    let mut bytes = buffer(&TRIANGLE, &[0, 1, 2]);
    let uv_offset = bytes.len();
    bytes.extend([0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0].iter().flat_map(|x| x.to_le_bytes()));
    let mut v = triangle_json(Some(&data_uri(&bytes)), bytes.len());
    v["bufferViews"].as_array_mut().expect("views").push(gltf::json::deserialize::from_str(&format!(r#"{{"buffer": 0, "byteOffset": {uv_offset}, "byteLength": 24}}"#)).expect("json"));
    v["accessors"].as_array_mut().expect("accessors").push(gltf::json::deserialize::from_str(r#"{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}"#).expect("json"));
    v["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = Value::from(2);
    v["meshes"][0]["primitives"][0]["material"] = Value::from(0);
    v["images"] = gltf::json::deserialize::from_str(&format!(r#"[{{"uri": "data:image/png;base64,{}"}}]"#, base64::engine::general_purpose::STANDARD.encode(png()))).expect("json");
    v["samplers"] = gltf::json::deserialize::from_str(r#"[{"wrapS": 33071, "wrapT": 33648}]"#).expect("json");
    v["textures"] = gltf::json::deserialize::from_str(r#"[{"source": 0, "sampler": 0}]"#).expect("json");
    v["materials"] = gltf::json::deserialize::from_str(
        r#"[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0, 1], "rotation": 1.5707964, "scale": [0.5, 0.5]}}}},
             "emissiveTexture": {"index": 0}}]"#,
    )
    .expect("json");
    v["extensionsUsed"] = gltf::json::deserialize::from_str(r#"["KHR_texture_transform"]"#).expect("json");
    let f = read(&write_json(&scratch("textures"), &v)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.meshes[0][0].uv, [glam::Vec2::new(0.0, 0.0), glam::Vec2::new(1.0, 0.0), glam::Vec2::new(0.0, 1.0)]);
    let image = f.images[0].as_ref().expect("the image is decoded");
    assert_eq!((image.width, image.height, &image.rgba[..8]), (2, 1, &[255, 0, 0, 255, 0, 255, 0, 255][..]));
    let base = f.material_textures[0].base_color.expect("a base colour texture");
    assert_eq!(base.wrap, [Wrap::Clamp, Wrap::Mirror]);
    // The extension's example: a quarter turn, half size, offset (0, 1)
    // reads the image's lower left quadrant: (0, 0) at (0, 1), (1, 0) at
    // (0, 0.5), (0, 1) at (0.5, 1).
    let m = base.transform;
    let at = |u: f32, v: f32| (m[0][0] * u + m[0][1] * v + m[0][2], m[1][0] * u + m[1][1] * v + m[1][2]);
    for ((u, v), (x, y)) in [((0.0, 0.0), (0.0, 1.0)), ((1.0, 0.0), (0.0, 0.5)), ((0.0, 1.0), (0.5, 1.0))] {
        let (gx, gy) = at(u, v);
        assert!((gx - x).abs() < 1e-6 && (gy - y).abs() < 1e-6, "({u}, {v}) -> ({gx}, {gy}), want ({x}, {y})");
    }
    let emissive = f.material_textures[0].emissive.expect("an emissive texture");
    assert_eq!((emissive.wrap, emissive.transform), ([Wrap::Clamp, Wrap::Mirror], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), "the same texture, without a transform");
    // An image that is not one says so.
    v["images"] = gltf::json::deserialize::from_str(r#"[{"uri": "data:image/png;base64,AAAA"}]"#).expect("json");
    let e = read(&write_json(&scratch("bad-image"), &v)).expect_err("a broken image was read");
    assert!(e.contains("images[0]") && e.contains("cannot decode"), "{e}");
}

#[test]
fn what_glint_leaves_out_is_said_once_each() {
    let bytes = buffer(&TRIANGLE, &[0, 1, 2]);
    let mut v = triangle_json(Some(&data_uri(&bytes)), bytes.len());
    // A morph target reads the positions' accessor.
    let prim = &mut v["meshes"][0]["primitives"][0];
    prim["targets"] = gltf::json::deserialize::from_str(r#"[{"POSITION": 0}]"#).expect("json");
    prim["material"] = Value::from(0);
    v["materials"] = gltf::json::deserialize::from_str(r#"[{"name": "one side"}]"#).expect("json");
    let dir = scratch("left-out");
    let path = write_json(&dir, &v);
    let f = read(&path).unwrap_or_else(|e| panic!("{e}"));
    let warnings = f.warnings.join("\n");
    assert!(warnings.contains("1 primitive(s) have morph targets"), "{warnings}");
    // A single-sided material is rendered as one now, and not said.
    assert!(!warnings.contains("single-sided"), "{warnings}");
    assert!(f.materials[0].is_single_sided());
    assert!(!warnings.contains("TEXCOORD_1") && !warnings.contains("TANGENT") && !warnings.contains("COLOR_0"), "{warnings}");
}

/// The triangle with more attributes after its positions and indices:
/// `extra` is (name, accessor JSON without its bufferView, bytes).
fn with_attributes(name: &str, material: &str, extra: &[(&str, &str, Vec<u8>)]) -> Result<GltfFile, String> {
    let mut bytes = buffer(&TRIANGLE, &[0, 1, 2]);
    let mut views = vec![r#"{"buffer": 0, "byteLength": 36}"#.to_string(), r#"{"buffer": 0, "byteOffset": 36, "byteLength": 6}"#.to_string()];
    let mut accessors = Vec::new();
    for (k, (_, acc, data)) in extra.iter().enumerate() {
        views.push(format!(r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, bytes.len(), data.len()));
        accessors.push(format!(r#"{{"bufferView": {}, {acc}}}"#, k + 2));
        bytes.extend(data);
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
    }
    let mut v = triangle_json(Some(&data_uri(&bytes)), bytes.len());
    v["buffers"][0]["byteLength"] = Value::from(bytes.len());
    v["bufferViews"] = gltf::json::deserialize::from_str(&format!("[{}]", views.join(", "))).expect("json");
    for (k, acc) in accessors.iter().enumerate() {
        v["accessors"].as_array_mut().expect("accessors").push(gltf::json::deserialize::from_str(acc).expect("json"));
        v["meshes"][0]["primitives"][0]["attributes"][extra[k].0] = Value::from(k + 2);
    }
    v["meshes"][0]["primitives"][0]["material"] = Value::from(0);
    v["materials"] = gltf::json::deserialize::from_str(&format!("[{material}]")).expect("json");
    v["textures"] = gltf::json::deserialize::from_str(r#"[{"source": 0}]"#).expect("json");
    // A 1x1 PNG (a flat normal).
    let mut png = std::io::Cursor::new(Vec::new());
    image::RgbaImage::from_raw(1, 1, vec![128, 128, 255, 255]).expect("image").write_to(&mut png, image::ImageFormat::Png).expect("png");
    v["images"] = gltf::json::deserialize::from_str(&format!(r#"[{{"uri": "{}"}}]"#, data_uri(png.get_ref()).replace("octet-stream", "png").replace("application", "image"))).expect("json");
    read(&write_json(&scratch(name), &v))
}

fn floats(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

const NORMAL_MAPPED: &str = r#"{"normalTexture": {"index": 0}}"#;

/// The triangle's texture coordinates (u along +x, v down), as a
/// `with_attributes` attribute.
fn uvs() -> (&'static str, &'static str, Vec<u8>) {
    ("TEXCOORD_0", r#""componentType": 5126, "count": 3, "type": "VEC2""#, floats(&[0.0, 1.0, 1.0, 1.0, 0.0, 0.0]))
}

/// The triangle's normals, all +z.
fn normals() -> (&'static str, &'static str, Vec<u8>) {
    ("NORMAL", r#""componentType": 5126, "count": 3, "type": "VEC3""#, floats(&[0.0, 0.0, 1.0].repeat(3)))
}

#[test]
fn tangents_and_vertex_colours_are_read_or_made() {
    // The file's tangents: normalised, w reduced to its sign.
    let tangents = ("TANGENT", r#""componentType": 5126, "count": 3, "type": "VEC4""#, floats(&[0.0, 2.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1.0]));
    let f = with_attributes("tangents", NORMAL_MAPPED, &[normals(), uvs(), tangents]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.meshes[0][0].tangent, [glam::Vec4::new(0.0, 1.0, 0.0, -1.0); 3]);
    // Without them, MikkTSpace's: u along +x, the image's up +y.
    let f = with_attributes("mikktspace", NORMAL_MAPPED, &[normals(), uvs()]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.meshes[0][0].tangent, [glam::Vec4::new(1.0, 0.0, 0.0, 1.0); 3]);
    // Without a normal texture, no tangents at all.
    let f = with_attributes("no-normal-texture", "{}", &[normals(), uvs()]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.meshes[0][0].tangent, [glam::Vec4::ZERO; 3]);
    // Colours as normalised bytes (RGBA; alpha not read), and their absence.
    let colours = ("COLOR_0", r#""componentType": 5121, "normalized": true, "count": 3, "type": "VEC4""#, vec![255, 0, 0, 255, 0, 51, 0, 255, 0, 0, 255, 0]);
    let f = with_attributes("colours", "{}", &[colours]).unwrap_or_else(|e| panic!("{e}"));
    let want = [glam::Vec3::X, glam::Vec3::new(0.0, 0.2, 0.0), glam::Vec3::Z];
    assert!(f.meshes[0][0].color.iter().zip(want).all(|(c, w)| (*c - w).length() < 1e-6), "{:?}", f.meshes[0][0].color);
    let f = with_attributes("no-colours", "{}", &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.meshes[0][0].color, [glam::Vec3::ONE; 3]);
}

#[test]
fn broken_tangents_and_colours_name_their_accessor() {
    for (name, attr, want) in [
        ("tangent-vec3", ("TANGENT", r#""componentType": 5126, "count": 3, "type": "VEC3""#, floats(&[1.0, 0.0, 0.0].repeat(3))), "attributes.TANGENT (accessors[4]): is Vec3"),
        ("tangent-nan", ("TANGENT", r#""componentType": 5126, "count": 3, "type": "VEC4""#, floats(&[f32::NAN, 0.0, 0.0, 1.0].repeat(3))), "attributes.TANGENT: tangent 0 is not finite"),
        ("colour-integers", ("COLOR_0", r#""componentType": 5121, "count": 3, "type": "VEC3""#, vec![255; 9]), "attributes.COLOR_0: integer colours must be normalized"),
        ("colour-count", ("COLOR_0", r#""componentType": 5126, "count": 2, "type": "VEC3""#, floats(&[1.0; 6])), "attributes.COLOR_0: 2 colours for 3 positions"),
    ] {
        let e = with_attributes(name, NORMAL_MAPPED, &[normals(), uvs(), attr]).expect_err(name);
        eprintln!("{name}: {e}");
        assert!(e.contains("t.gltf") && e.contains(&format!("meshes[0].primitives[0].{want}")), "{name}: {e}");
    }
}
