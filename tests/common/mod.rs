//! Helpers shared by the GPU integration tests.
#![allow(dead_code)]

pub mod scene_text;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use glint::gpu::readback::ImageF32;
use glint::gpu::Gpu;
use glint::graph::{self, CompileOptions};
use glint::scene::Scene;
use glint::session::{Session, SessionOptions};

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shared GPU context. Without an adapter the GPU tests are skipped
/// locally but fail under CI=true (CI must have lavapipe).
pub fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Option<Gpu>> = OnceLock::new();
    let g = GPU.get_or_init(|| {
        if std::env::var_os("WGPU_BACKEND").is_none() {
            // SAFETY of intent: tests run in one process; set before any wgpu call.
            unsafe { std::env::set_var("WGPU_BACKEND", "vulkan") };
        }
        if std::env::var_os("NODEVICE_SELECT").is_none() {
            // As `glint` does: no Wayland probe from Mesa's device-select layer.
            unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
        }
        match Gpu::new() {
            Ok(g) => Some(g),
            Err(e) if std::env::var("CI").is_ok_and(|v| v == "true") => panic!("CI needs a GPU adapter: {e}"),
            Err(e) => {
                eprintln!("skipping GPU test: {e}");
                None
            }
        }
    });
    g.as_ref()
}

/// Renders `frames` frames of `scene` with the graph at `graph_path` and
/// returns `output` (or the graph's output).
pub fn render(
    gpu: &Gpu,
    scene: Scene,
    graph_path: &Path,
    size: (u32, u32),
    frames: u32,
    output: Option<&str>,
) -> ImageF32 {
    let options = CompileOptions { output: output.map(str::to_string), ..Default::default() };
    render_with(gpu, scene, graph_path, size, frames, &options)
}

/// `render` with full compile options (graph edits included).
pub fn render_with(gpu: &Gpu, scene: Scene, graph_path: &Path, size: (u32, u32), frames: u32, options: &CompileOptions) -> ImageF32 {
    let compiled = compile(&scene, graph_path, options);
    render_compiled(gpu, scene, &compiled, size, frames)
}

/// The graph compiled for `scene` (to adjust before `render_compiled`).
pub fn compile(scene: &Scene, graph_path: &Path, options: &CompileOptions) -> graph::CompiledGraph {
    graph::load_and_compile(graph_path, &repo().join("shaders"), &scene.compile_features(), options).unwrap_or_else(|e| panic!("{e}"))
}

/// A session for an already compiled graph (shaders from the repo).
pub fn session(gpu: &Gpu, scene: Scene, compiled: &graph::CompiledGraph, size: (u32, u32), seed: u32) -> Session {
    let options = SessionOptions { seed, ..SessionOptions::new(size) };
    Session::with_graph(gpu, scene, compiled.clone(), repo().join("shaders"), options).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders `frames` frames of an already compiled graph; its output (the
/// last frame shown in full, as `glint render` writes it).
pub fn render_compiled(gpu: &Gpu, scene: Scene, compiled: &graph::CompiledGraph, size: (u32, u32), frames: u32) -> ImageF32 {
    let mut s = session(gpu, scene, compiled, size, 1);
    run_frames(&mut s, frames, 0.0);
    s.read_output().unwrap_or_else(|e| panic!("{e}"))
}

/// `frames` frames at scene time `time`, the last shown in full (a graph
/// whose filter thins its still frames, `ThinWhenStill`, runs it there).
pub fn run_frames(s: &mut Session, frames: u32, time: f32) {
    for f in 0..frames {
        if f + 1 == frames {
            s.show_next_in_full();
        }
        s.frame(time);
    }
}

pub fn load_scene(name: &str) -> Scene {
    glint::scene::load(&repo().join("scenes").join(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// A scene from RON text (meshes resolved relative to scenes/).
pub fn scene_from(text: &str) -> Scene {
    glint::scene::parse(text, &repo().join("scenes/test-scene.ron")).unwrap_or_else(|e| panic!("{e}"))
}

/// A unique scratch folder under target/.
pub fn scratch(name: &str) -> PathBuf {
    let dir = repo().join("target/test-scratch").join(format!("{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// Copies a folder tree (files and subfolders).
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create folder");
    for e in std::fs::read_dir(from).expect("read folder") {
        let e = e.expect("folder entry");
        let target = to.join(e.file_name());
        if e.file_type().expect("file type").is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), &target).expect("copy file");
        }
    }
}

/// A scratch copy of the repo's `shaders/`, `passes/` and `scenes/` to edit
/// (its canonical path, as the watcher and the session report paths).
pub fn workspace(name: &str) -> PathBuf {
    let dir = scratch(name);
    for sub in ["shaders", "passes", "scenes"] {
        let _ = std::fs::remove_dir_all(dir.join(sub));
        copy_dir(&repo().join(sub), &dir.join(sub));
    }
    std::fs::canonicalize(&dir).expect("canonical scratch dir")
}

/// passes/pathtrace.ron with the path tracer that also stores the camera
/// ray's first hit (shaders/pathtrace_gbuffer.wgsl, FIRST_HIT 1) into
/// `gbuf_pos` and `gbuf_normal`, written to a scratch folder: its path.
pub fn pathtrace_with_gbuffer(name: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("passes/pathtrace.ron")).expect("read pathtrace.ron");
    let mut stored = text.clone();
    for (from, to) in [
        ("shader: \"pathtrace.wgsl\"", "shader: \"pathtrace_gbuffer.wgsl\""),
        ("FIRST_HIT: 0", "FIRST_HIT: 1"),
        (
            "\"radiance\": Texture(format: Rgba32Float),",
            "\"radiance\": Texture(format: Rgba32Float),\n        \"gbuf_pos\": Texture(format: Rgba32Float),\n        \"gbuf_normal\": Texture(format: Rgba16Float),",
        ),
    ] {
        assert!(stored.contains(from), "pathtrace.ron no longer has `{from}`");
        stored = stored.replacen(from, to, 1);
    }
    let dir = scratch(name);
    let path = dir.join("pathtrace.ron");
    std::fs::write(&path, stored).expect("write the graph");
    path
}

/// A Cornell box lit by one sphere light that moves with `Linear` motion:
/// at time 0 it is left of centre, at time 1 right of it.
pub const JUMPING_LIGHT: &str = r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.4), target: (0.0, 0.0, 0.0), up: (0.0, 1.0, 0.0), vfov_deg: 40.0),
    materials: {
        "white": Material(albedo: (0.725, 0.71, 0.68)),
        "red":   Material(albedo: (0.63, 0.065, 0.05)),
        "green": Material(albedo: (0.14, 0.45, 0.091)),
    },
    objects: [
        Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, 1.0), (1.0, -1.0, -1.0)], material: "white"),
        Quad(vertices: [(-1.0, 1.0, -1.0), (1.0, 1.0, -1.0), (1.0, 1.0, 1.0), (-1.0, 1.0, 1.0)], material: "white"),
        Quad(vertices: [(-1.0, -1.0, -1.0), (1.0, -1.0, -1.0), (1.0, 1.0, -1.0), (-1.0, 1.0, -1.0)], material: "white"),
        Quad(vertices: [(-1.0, -1.0, -1.0), (-1.0, 1.0, -1.0), (-1.0, 1.0, 1.0), (-1.0, -1.0, 1.0)], material: "red"),
        Quad(vertices: [(1.0, -1.0, -1.0), (1.0, -1.0, 1.0), (1.0, 1.0, 1.0), (1.0, 1.0, -1.0)], material: "green"),
        Sphere(center: (-0.1, -0.65, -0.3), radius: 0.35, material: "white"),
    ],
    lights: [
        SphereLight(center: (-0.7, 0.2, 0.3), radius: 0.12, radiance: (12.0, 12.0, 12.0),
                    motion: Linear(velocity: (1.4, 0.0, 0.0))),
    ],
)"#;

/// The mean over an image's pixels of the mean of r, g and b.
pub fn mean_rgb(img: &ImageF32) -> f64 {
    img.data.iter().map(|p| f64::from(p[0] + p[1] + p[2]) / 3.0).sum::<f64>() / img.data.len() as f64
}

/// A pixel's luminance (Rec. 709 weights, as the shaders' `luminance`).
pub fn luminance(p: &[f32; 4]) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

/// Runs the glint binary in the repository root with `env` added (on
/// Vulkan unless WGPU_BACKEND says otherwise): (exit code, stdout,
/// stderr). A panic fails the test whatever the exit code.
pub fn run_glint(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_glint"));
    cmd.args(args).current_dir(repo()).env("WGPU_BACKEND", std::env::var("WGPU_BACKEND").unwrap_or_else(|_| "vulkan".into()));
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("run glint");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "glint panicked: {stderr}");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into_owned(), stderr)
}

/// `glint render SCENE` through the binary with the path tracer, 32x32, 4
/// frames, read back (the material tests' quads and cards).
pub fn path_traced_32(scene: &Path) -> ImageF32 {
    let out = scene.with_extension("exr");
    let (code, _, stderr) = run_glint(&["render", scene.to_str().expect("utf-8"), "--graph", "passes/pathtrace.ron", "--size", "32x32", "--frames", "4", "--out", out.to_str().expect("utf-8")], &[]);
    assert_eq!(code, 0, "{stderr}");
    glint::image_io::load(&out).expect("read the image")
}

/// The mean of the 4x4 pixels about the centre of a 32x32 image.
pub fn centre_32(img: &ImageF32) -> glam::Vec3 {
    let mut sum = glam::Vec3::ZERO;
    for y in 14..18 {
        for x in 14..18 {
            let p = img.get(x, y);
            sum += glam::Vec3::new(p[0], p[1], p[2]);
        }
    }
    sum / 16.0
}
