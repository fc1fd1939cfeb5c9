//! glTF files in scenes (issue 41, part 1): a glTF copy of the torus knot
//! (scenes/meshes/knot.gltf, written by tools/obj_to_gltf.py from
//! knot.obj) renders the image of the OBJ, placed by the RON object or by
//! the file's own nodes; a glTF file opens as a scene of its own; broken
//! files exit 2 naming the file and the glTF path.

mod common;

use std::process::Command;

use common::*;
use glint::metrics;

fn glint(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(args)
        .current_dir(repo())
        .env("WGPU_BACKEND", std::env::var("WGPU_BACKEND").unwrap_or_else(|_| "vulkan".into()))
        .output()
        .expect("run glint");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "glint panicked: {stderr}");
    (out.status.code().unwrap_or(-1), stderr)
}

const PLACED: &str = r#"translate: (0.0, -0.572, -0.1), scale: 0.25, rotate_deg: (0.0, 25.0, 0.0)"#;

/// knot.gltf with its root node carrying moving-lights.ron's placement of
/// the knot, in `dir` beside a copy of its buffer.
fn placed_copy(dir: &std::path::Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("scenes/meshes/knot.gltf")).expect("read knot.gltf");
    let q = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.0, 25f64.to_radians(), 0.0);
    let placement = format!(r#""name": "placement", "translation": [0.0, -0.572, -0.1], "rotation": [{}, {}, {}, {}], "scale": [0.25, 0.25, 0.25],"#, q.x, q.y, q.z, q.w);
    let text = text.replacen(r#""name": "placement","#, &placement, 1);
    assert!(text.contains("\"scale\""), "knot.gltf's root node is named \"placement\"");
    std::fs::copy(repo().join("scenes/meshes/knot.bin"), dir.join("knot.bin")).expect("copy knot.bin");
    let path = dir.join("knot-placed.gltf");
    std::fs::write(&path, text).expect("write");
    path
}

#[test]
fn a_gltf_mesh_renders_the_image_of_the_same_obj_mesh() {
    let Some(gpu) = gpu() else { return };
    let dir = scratch("gltf-knot");
    let placed = placed_copy(&dir);
    let text = std::fs::read_to_string(repo().join("scenes/moving-lights.ron")).expect("read scene");
    let obj = format!(r#"Mesh(path: "meshes/knot.obj", {PLACED})"#);
    assert!(text.contains(&obj), "moving-lights.ron places the knot as {obj}");
    let by_ron = text.replace(&obj, &format!(r#"Gltf(path: "meshes/knot.gltf", {PLACED})"#));
    let by_nodes = text.replace(&obj, &format!("Gltf(path: {:?})", placed.display().to_string()));
    let graph = repo().join("passes/pathtrace.ron");
    let reference = render(gpu, scene_from(&text), &graph, (64, 64), 8, None);
    for (how, scene) in [("the RON object", by_ron), ("the file's nodes", by_nodes)] {
        let image = render(gpu, scene_from(&scene), &graph, (64, 64), 8, None);
        let (flip, _) = metrics::flip(&reference, &image);
        eprintln!("placed by {how}: FLIP {:.5} against the OBJ", flip.mean);
        assert!(flip.mean <= 0.002, "placed by {how}: FLIP {} against the OBJ", flip.mean);
    }
}

#[test]
fn a_gltf_file_opens_as_a_scene_and_broken_ones_exit_2() {
    let dir = scratch("gltf-cli");
    let png = dir.join("knot.png");
    let (code, stderr) = glint(&["render", "scenes/meshes/knot.gltf", "--graph", "passes/hybrid.ron", "--size", "32x32", "--out", png.to_str().expect("utf-8")]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("no perspective camera") && stderr.contains("default sphere light"), "the defaults are said: {stderr}");
    assert!(png.exists());

    // An index past the vertices, in a RON scene and opened directly.
    let text = std::fs::read_to_string(repo().join("scenes/meshes/knot.gltf")).expect("read");
    std::fs::copy(repo().join("scenes/meshes/knot.bin"), dir.join("knot.bin")).expect("copy");
    let broken = text.replacen(r#""count": 2000,"#, r#""count": 1000,"#, 2);
    assert_ne!(broken, text, "knot.gltf has 2000 vertices");
    std::fs::write(dir.join("broken.gltf"), broken).expect("write");
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, "Scene(\n  camera: Camera(position: (0.0, 0.0, 4.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  objects: [\n    Gltf(path: \"broken.gltf\"),\n  ],\n)\n").expect("write");
    for (file, at) in [(scene.clone(), "scene.ron:4"), (dir.join("broken.gltf"), "broken.gltf")] {
        let (code, stderr) = glint(&["render", file.to_str().expect("utf-8"), "--size", "16x16", "--out", png.to_str().expect("utf-8")]);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(at) && stderr.contains("broken.gltf") && stderr.contains("meshes[0].primitives[0].indices"), "{stderr}");
    }
    // A file that is not there.
    std::fs::write(&scene, "Scene(camera: Camera(position: (0.0, 0.0, 4.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  objects: [Gltf(path: \"gone.glb\")])\n").expect("write");
    let (code, stderr) = glint(&["render", scene.to_str().expect("utf-8"), "--size", "16x16", "--out", png.to_str().expect("utf-8")]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("scene.ron:2") && stderr.contains("glTF file \"gone.glb\" not found"), "{stderr}");
}

#[test]
fn camera_n_picks_a_gltf_camera() {
    use gltf::json::Value;
    let dir = scratch("gltf-cameras");
    std::fs::copy(repo().join("scenes/meshes/knot.bin"), dir.join("knot.bin")).expect("copy");
    let text = std::fs::read_to_string(repo().join("scenes/meshes/knot.gltf")).expect("read");
    let mut v: Value = gltf::json::deserialize::from_str(&text).expect("knot.gltf is JSON");
    // Camera 0 in front of the knot, camera 1 far off to the side looking away.
    v["cameras"] = gltf::json::deserialize::from_str(r#"[{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]"#).expect("json");
    let nodes = v["nodes"].as_array_mut().expect("nodes");
    nodes.push(gltf::json::deserialize::from_str(r#"{"camera": 0, "translation": [0, 0, 5]}"#).expect("json"));
    nodes.push(gltf::json::deserialize::from_str(r#"{"camera": 0, "translation": [50, 0, 0], "rotation": [0, -0.7071068, 0, 0.7071068]}"#).expect("json"));
    v["scenes"][0]["nodes"] = gltf::json::deserialize::from_str("[0, 2, 3]").expect("json");
    let file = dir.join("cameras.gltf");
    std::fs::write(&file, gltf::json::serialize::to_string(&v).expect("json")).expect("write");
    let (f, out) = (file.to_str().expect("utf-8"), dir.join("c.exr"));
    let mean = |camera: &str| -> f64 {
        let (code, stderr) = glint(&["render", f, "--graph", "passes/direct.ron", "--size", "24x24", "--camera", camera, "--out", out.to_str().expect("utf-8")]);
        assert_eq!(code, 0, "{stderr}");
        mean_rgb(&glint::image_io::load(&out).expect("read the image"))
    };
    let (front, away) = (mean("0"), mean("1"));
    assert!(front > 0.01, "camera 0 sees the lit knot: mean {front}");
    assert_eq!(away, 0.0, "camera 1 looks away from it");
    let (code, stderr) = glint(&["render", f, "--size", "24x24", "--camera", "2", "--out", out.to_str().expect("utf-8")]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--camera 2") && stderr.contains("2 perspective camera(s)"), "{stderr}");
}
