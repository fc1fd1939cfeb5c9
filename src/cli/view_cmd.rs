//! `glint view` and `glint machines`.

use std::path::PathBuf;

use clap::Args;

use crate::error::UserError;
use crate::gpu::Gpu;
use crate::machines::{self, DeviceType, Machines};
use crate::viewer::{self, ViewOptions};

#[derive(Args, Debug)]
pub struct ViewArgs {
    /// The scene file (RON), or an OBJ or glTF file opened as a scene.
    pub scene: PathBuf,
    /// View from the scene's glTF camera N (0: the first).
    #[arg(long)]
    pub camera: Option<usize>,
    /// Frame graph (default: from passes/machines.ron for this adapter).
    #[arg(long)]
    pub graph: Option<PathBuf>,
    /// Render size (a machine profile's resolution scale applies to it).
    #[arg(long, default_value = "640x360", value_parser = super::parse_size)]
    pub size: (u32, u32),
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Render this many frames in the window, write --screenshot and exit.
    #[arg(long, requires = "screenshot")]
    pub frames: Option<u32>,
    /// Where --frames writes the window (PNG; the graph output goes beside
    /// it as a linear EXR).
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// The folder F12 writes screenshots into (default: the working folder).
    #[arg(long)]
    pub screenshot_dir: Option<PathBuf>,
    /// Stop rendering a still image once it has accumulated this many
    /// frames (the panel shows the progress; moving the camera goes on).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub stop_at: Option<u32>,
}

pub fn run(args: ViewArgs) -> Result<(), UserError> {
    if let Some(p) = &args.screenshot {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            return Err(UserError::in_file(p, "the screenshot must end in .png"));
        }
    }
    if let Some(d) = &args.screenshot_dir {
        if !d.is_dir() {
            return Err(UserError::in_file(d, "--screenshot-dir is not a folder (create it first)"));
        }
    }
    viewer::run(ViewOptions {
        scene: args.scene,
        camera: args.camera,
        graph: args.graph,
        size: args.size,
        seed: args.seed,
        frames: args.frames,
        screenshot: args.screenshot,
        screenshot_dir: args.screenshot_dir,
        sample_target: args.stop_at,
    })
}

pub fn machines() -> Result<(), UserError> {
    let path = Machines::default_path();
    let m = Machines::load(&path)?;
    let gpu = Gpu::new()?;
    let index = m.pick_index(DeviceType::of(gpu.info.device_type), &gpu.info.name);
    let picked = index.map_or(&m.default, |i| &m.profiles[i]);
    out!("adapter: {}", gpu.describe());
    out!("profile: `{}` ({}), from {}", picked.name, m.rule(index), path.display());
    out!("");
    for (i, p) in m.profiles.iter().chain([&m.default]).enumerate() {
        let mark = if index == Some(i) || (index.is_none() && i == m.profiles.len()) { "*" } else { " " };
        let matches = match (&p.device_type, &p.name_contains) {
            (None, None) if i == m.profiles.len() => "default".to_string(),
            (t, n) => format!("{}{}", t.map_or("any type".into(), |t| format!("{t:?}")), n.as_ref().map_or(String::new(), |n| format!(", name contains \"{n}\""))),
        };
        out!(
            "{mark} {:<28} {:<34} graph {:<18} scale {:<5} target {} ms{}",
            p.name,
            matches,
            p.graph,
            p.resolution_scale,
            p.target_ms,
            if p.params.is_empty() { String::new() } else { format!(", params {:?}", machines::param_sets(p)?.iter().map(|s| format!("{}.{}", s.pass, s.param)).collect::<Vec<_>>()) }
        );
    }
    Ok(())
}
