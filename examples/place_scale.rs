//! The place-and-scale table of docs/acceleration.md ("Any place, any
//! scale"): the Cornell box moved and scaled as
//! text (tests/common/scene_text.rs), rendered with every shipped graph,
//! FLIP mean against the untouched box with the same seed.
//!
//!   WGPU_BACKEND=vulkan cargo run --release --example place_scale [SIZE=128] [FRAMES=256] [SCENE=scenes/cornell.ron]

#[path = "../tests/common/scene_text.rs"]
mod scene_text;

use std::path::{Path, PathBuf};

use glint::gpu::readback::ImageF32;
use glint::gpu::Gpu;
use glint::metrics;
use glint::session::{Session, SessionOptions};

/// (label, scale, offset): the variants the extremes issue tried, then the
/// far ends of the ranges glint promises.
const CASES: [(&str, f64, [f64; 3]); 14] = [
    ("moved by (1e2, -3e1, 7e1)", 1.0, [1e2, -3e1, 7e1]),
    ("moved by (1e3, -3e2, 7e2)", 1.0, [1e3, -3e2, 7e2]),
    ("moved by (1e4, -3e3, 7e3)", 1.0, [1e4, -3e3, 7e3]),
    ("moved by (1e5, -3e4, 7e4)", 1.0, [1e5, -3e4, 7e4]),
    ("moved by (-7e6, 3e6, -5e6)", 1.0, [-7e6, 3e6, -5e6]),
    ("moved by (0, 0, 1e7)", 1.0, [0.0, 0.0, 1e7]),
    ("scaled by 1e5", 1e5, [0.0; 3]),
    ("scaled by 1e4", 1e4, [0.0; 3]),
    ("scaled by 1e-3", 1e-3, [0.0; 3]),
    ("scaled by 1e-4", 1e-4, [0.0; 3]),
    ("scaled by 1e-5", 1e-5, [0.0; 3]),
    ("scaled by 1e-5, moved by (3e2, -1e2, 2e2)", 1e-5, [3e2, -1e2, 2e2]),
    ("scaled by 1e-3, moved by (-2e3, 5e2, 1e3)", 1e-3, [-2e3, 5e2, 1e3]),
    ("scaled by 1e3, moved by (5e6, -8e6, 1e6)", 1e3, [5e6, -8e6, 1e6]),
];

const GRAPHS: [&str; 4] = ["direct.ron", "hybrid-point.ron", "hybrid.ron", "pathtrace.ron"];

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |i: usize, default: u32| args.get(i).map_or(Ok(default), |a| a.parse::<u32>().map_err(|e| format!("`{a}`: {e}")));
    let size = number(0, 128)?;
    let frames = number(1, 256)?;
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let scene_path = args.get(2).map_or_else(|| repo.join("scenes/cornell.ron"), PathBuf::from);
    let text = std::fs::read_to_string(&scene_path).map_err(|e| format!("{}: {e}", scene_path.display()))?;
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    let shown = scene_path.strip_prefix(&repo).unwrap_or(&scene_path);
    println!("{} at {size}x{size}, {frames} frames, seed 1, FLIP mean against the untouched scene ({}):\n", shown.display(), gpu.describe());
    println!("| variant | {} |", GRAPHS.join(" | "));
    println!("|---|{}", "---|".repeat(GRAPHS.len()));
    let graphs: Vec<PathBuf> = GRAPHS.iter().map(|g| repo.join("passes").join(g)).collect();
    let mut references = Vec::new();
    for g in &graphs {
        references.push(render(&gpu, &text, &scene_path, g, size, frames)?);
    }
    let mut worst = 0.0f32;
    for (label, scale, offset) in CASES {
        let moved = scene_text::transformed(&text, scale, offset);
        let mut cells = Vec::new();
        for (g, reference) in graphs.iter().zip(&references) {
            let image = render(&gpu, &moved, &scene_path, g, size, frames)?;
            let flip = metrics::flip(reference, &image).0.mean;
            worst = worst.max(flip);
            cells.push(format!("{flip:.5}"));
        }
        println!("| {label} | {} |", cells.join(" | "));
    }
    println!("\nworst: {worst:.5}");
    Ok(())
}

fn render(gpu: &Gpu, text: &str, scene_path: &Path, graph: &Path, size: u32, frames: u32) -> Result<ImageF32, String> {
    let scene = glint::scene::parse(text, scene_path).map_err(|e| e.to_string())?;
    let mut session = Session::new(gpu, scene, graph, SessionOptions::new((size, size))).map_err(|e| e.to_string())?;
    for _ in 0..frames {
        session.frame(0.0);
    }
    session.read_output().map_err(|e| e.to_string())
}
