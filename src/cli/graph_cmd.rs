//! `glint graph check` and `glint shaders`.

use std::path::PathBuf;

use clap::Args;

use crate::error::UserError;
use crate::graph::{self, report, CompileOptions};
use crate::scene::{self, SceneFeatures};
use crate::shader;

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// The graph file (RON).
    pub file: PathBuf,
    /// Cull and specialise for this scene's features (else: all features).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Print Graphviz instead of text.
    #[arg(long)]
    pub dot: bool,
    /// Render size for the memory figures.
    #[arg(long, default_value = "256x256", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Shader folder (default: ../shaders next to the graph's folder).
    #[arg(long)]
    pub shaders: Option<PathBuf>,
    #[command(flatten)]
    pub edits: super::render_cmd::EditArgs,
}

pub fn check(args: CheckArgs) -> Result<(), UserError> {
    let mut textures = None;
    let mut environment = None;
    let features = match &args.scene {
        Some(path) => {
            let s = scene::load(path)?;
            textures = crate::scene::texture_classes::describe(s.textures());
            environment = s.environment.as_ref().map(|e| e.describe());
            s.compile_features()
        }
        None => SceneFeatures::all(),
    };
    let dir = args.shaders.clone().unwrap_or_else(|| graph::shader_dir_for(&args.file));
    let compiled = graph::load_and_compile(&args.file, &dir, &features, &CompileOptions { output: None, edits: args.edits.edits(), no_specialise: args.edits.no_specialise, no_cull: args.edits.no_cull, ..Default::default() })?;
    if args.dot {
        out_raw!("{}", report::dot(&compiled.schedule));
    } else {
        out_raw!("{}", report::text(&compiled.schedule, args.size));
        if let Some(t) = textures {
            out!("scene textures: {t}");
        }
        if let Some(e) = environment {
            out!("environment map: {e}");
        }
    }
    Ok(())
}

pub fn check_shaders(files: Vec<String>, dir: Option<PathBuf>) -> Result<(), UserError> {
    let dir = dir.unwrap_or_else(|| PathBuf::from("shaders"));
    let files = if files.is_empty() { shader_files(&dir)? } else { files };
    let mut failed = Vec::new();
    for f in &files {
        match shader::load(&dir, f) {
            Ok(s) => out!("ok   {f} ({} entry points)", s.info.entry_points.len()),
            Err(e) => {
                out!("FAIL {e}");
                failed.push(e);
            }
        }
    }
    match failed.into_iter().next() {
        None => Ok(()),
        Some(e) => Err(e),
    }
}

/// The pass shaders under `dir` (`shader::source::pass_shaders`).
pub fn shader_files(dir: &std::path::Path) -> Result<Vec<String>, UserError> {
    crate::shader::source::pass_shaders(dir).map_err(|e| UserError::in_file(dir, format!("cannot list shaders: {e}")))
}
