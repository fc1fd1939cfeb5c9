//! Embedding glint: drive a `Session` from Rust the way an application
//! embeds an engine. It loads a scene, picks a graph, sets a param, renders
//! frames, reads the image back and writes it.
//!
//! ```sh
//! cargo run --release --example embed -- scenes/cornell.ron passes/pathtrace.ron 16 out.png
//! ```
//!
//! On a machine without a GPU, Mesa's lavapipe runs it (`WGPU_BACKEND=vulkan`).

use std::path::PathBuf;
use std::process::ExitCode;

use glint::error::UserError;
use glint::gpu::Gpu;
use glint::graph::desc::ParamValue;
use glint::session::{Session, SessionOptions};

fn run() -> Result<(), UserError> {
    let mut args = std::env::args().skip(1);
    let mut arg = |default: &str| args.next().unwrap_or_else(|| default.to_string());
    let scene_path = PathBuf::from(arg("scenes/cornell.ron"));
    let graph_path = PathBuf::from(arg("passes/pathtrace.ron"));
    let frames: u32 = arg("16").parse().map_err(|e| UserError::new(format!("frames: {e}")))?;
    let out = PathBuf::from(arg("embed.png"));

    // The adapter (WGPU_BACKEND picks the API), the scene, and the graph
    // compiled against the scene; each step's error names its file.
    let gpu = Gpu::new()?;
    let scene = glint::scene::load(&scene_path)?;
    let mut options = SessionOptions::new((128, 128));
    options.seed = 7;
    let mut session = Session::new(&gpu, scene, &graph_path, options)?;

    // A param as a slider in the viewer sets it: by pass and name, checked
    // against the shader's `Params` struct. The path tracer's bounce limit
    // here; any other graph keeps its own.
    if session.param("pathtrace", "max_depth").is_some() {
        session.set_param("pathtrace", "max_depth", ParamValue::Int(4))?;
    }

    // Frames accumulate while camera and scene stand still. Scene time is
    // in seconds: moving lights follow it.
    for i in 0..frames {
        session.frame(i as f32 / 30.0);
    }
    let image = session.read_output()?;
    let mean = image.data.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).sum::<f32>() / image.data.len() as f32;
    glint::image_io::save(&image, &out)?;
    println!(
        "{} with {}: {frames} frames on {}, {}x{}, mean {mean:.4}, written to {}",
        scene_path.display(),
        graph_path.display(),
        gpu.describe(),
        image.width,
        image.height,
        out.display()
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
