//! The frame graph: RON schema (`desc`), the pure `compile` step, the
//! compiled `Schedule`, the `params` packer, printing (`report`), the
//! pipeline cache and the wgpu `executor` (docs/ARCHITECTURE.md).

pub mod compile;
pub mod desc;
pub mod edit;
pub mod executor;
pub mod frame_kind;
pub mod params;
pub mod pipelines;
pub mod report;
pub mod runs;
pub mod schedule;
pub mod tile_pool;
#[cfg(test)]
mod tests;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::{line_of, Location, UserError};
use crate::scene::SceneFeatures;
use crate::shader::{self, Shader, ShaderInfo};
pub use compile::{compile, CompileError, CompileOptions, ErrorKind, FLAT_SAMPLES_PER_DISPATCH, SAMPLES_PER_DISPATCH};
pub use desc::FrameGraph;
pub use schedule::*;

/// A graph with its shaders loaded and its schedule compiled.
#[derive(Debug, Clone)]
pub struct CompiledGraph {
    /// The graph file.
    pub path: PathBuf,
    /// The graph as parsed, before edits.
    pub desc: FrameGraph,
    /// The loaded shaders, by the name passes give them.
    pub shaders: BTreeMap<String, Shader>,
    /// The compiled schedule.
    pub schedule: Schedule,
}

/// The `shaders/` folder for a graph file: `../shaders` next to its folder,
/// else `./shaders`, else the one this crate was built from.
pub fn shader_dir_for(graph: &Path) -> PathBuf {
    let beside = graph.parent().and_then(Path::parent).map(|p| p.join("shaders"));
    let candidates = [beside, Some(PathBuf::from("shaders")), Some(Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders"))];
    candidates
        .into_iter()
        .flatten()
        .find(|p| p.is_dir())
        .unwrap_or_else(|| PathBuf::from("shaders"))
}

/// Loads every shader a graph names. A missing file is left out (compile
/// then reports it against the pass); a broken one is an error here.
pub fn load_shaders(desc: &FrameGraph, dir: &Path) -> Result<BTreeMap<String, Shader>, UserError> {
    let mut shaders = BTreeMap::new();
    for pass in &desc.passes {
        if shaders.contains_key(&pass.shader) || !shader::source::is_inside(&pass.shader) || !dir.join(&pass.shader).is_file() {
            continue;
        }
        shaders.insert(pass.shader.clone(), shader::load(dir, &pass.shader)?);
    }
    Ok(shaders)
}

/// The expanded sources of every shader a graph names (imports read, no
/// naga yet); missing files are left out as in `load_shaders`.
pub fn load_sources(desc: &FrameGraph, dir: &Path) -> Result<BTreeMap<String, shader::ShaderSource>, UserError> {
    let mut sources = BTreeMap::new();
    for pass in &desc.passes {
        if sources.contains_key(&pass.shader) || !shader::source::is_inside(&pass.shader) || !dir.join(&pass.shader).is_file() {
            continue;
        }
        sources.insert(pass.shader.clone(), shader::source::load(dir, &pass.shader)?);
    }
    Ok(sources)
}

/// Each shader's reflection, by name (what `compile` takes).
pub fn reflections(shaders: &BTreeMap<String, Shader>) -> BTreeMap<String, ShaderInfo> {
    shaders.iter().map(|(k, s)| (k.clone(), s.info.clone())).collect()
}

/// Turns a compile error into a user error located in the graph file at the
/// pass it concerns.
pub fn locate(e: &CompileError, path: &Path, text: &str) -> UserError {
    let line = match &e.pass {
        Some(p) => pass_line(text, p),
        None if e.kind == ErrorKind::UnknownOutput || e.kind == ErrorKind::UnwrittenRead => line_of(text, "output"),
        None if e.kind == ErrorKind::UnknownConstant => line_of(text, "constants:"),
        None => line_of(text, "passes"),
    };
    UserError::at(Location::at(path, line.unwrap_or(0), 0), e.to_string())
}

/// Each pass's workgroups at render size `size` within `limit` a side
/// (the adapter's `max_compute_workgroups_per_dimension`): a graph's
/// `dispatch` may ask for more than any device runs, which the driver
/// would refuse frame after frame. The error names the pass's line.
pub fn check_dispatches(graph: &CompiledGraph, size: (u32, u32), limit: u32) -> Result<(), UserError> {
    for sp in &graph.schedule.passes {
        if sp.bindings.iter().any(|b| b.target == schedule::Target::TilePool) {
            continue;
        }
        let groups = sp.workgroups(size);
        if groups.iter().all(|&n| n <= u64::from(limit)) {
            continue;
        }
        let (w, h) = sp.dispatch.resolve(size);
        let [x, y, _] = sp.workgroup_size;
        let text = std::fs::read_to_string(&graph.path).unwrap_or_default();
        let name = sp.name.split('#').next().unwrap_or(&sp.name);
        let line = pass_line(&text, name).unwrap_or(0);
        let message = format!(
            "pass `{name}`: its dispatch of {w}x{h} invocations makes {}x{} workgroups of {x}x{y}; this adapter runs at most {limit} a side: make the dispatch smaller",
            groups[0], groups[1]
        );
        return Err(UserError::at(Location::at(&graph.path, line, 0), message));
    }
    Ok(())
}

/// The line of the pass named `pass`: the `"pass"` that follows `name:`
/// after the `passes:` key (the graph's own name, a resource or a binding
/// may be spelled the same), else its first mention. Comments are skipped.
pub(crate) fn pass_line(text: &str, pass: &str) -> Option<usize> {
    let code = crate::error::blank_comments(text);
    let quoted = format!("\"{pass}\"");
    let start = code.find("passes").unwrap_or(0);
    let mut from = start;
    while let Some(at) = code[from..].find(&quoted).map(|i| from + i) {
        let before = code[..at].trim_end();
        if before.ends_with(':') && before[..before.len() - 1].trim_end().ends_with("name") {
            return Some(code[..at].matches('\n').count() + 1);
        }
        from = at + quoted.len();
    }
    line_of(&code[start..], &quoted).map(|l| l + code[..start].matches('\n').count()).or_else(|| line_of(&code, &quoted))
}

/// Loads a graph file and its shaders and compiles it for a scene.
pub fn load_and_compile(
    path: &Path,
    shader_dir: &Path,
    features: &SceneFeatures,
    options: &CompileOptions,
) -> Result<CompiledGraph, UserError> {
    let text = crate::error::read_user_text(path, "graph file")?;
    let desc = FrameGraph::parse(&text, path)?;
    let shaders = load_shaders(&desc, shader_dir)?;
    compile_loaded(path, desc, shaders, features, options)
}

/// Compiles an already parsed graph with its loaded shaders; errors are
/// located in the graph file at `path`.
pub fn compile_loaded(
    path: &Path,
    desc: FrameGraph,
    shaders: BTreeMap<String, Shader>,
    features: &SceneFeatures,
    options: &CompileOptions,
) -> Result<CompiledGraph, UserError> {
    let schedule = compile(&desc, &reflections(&shaders), features, options).map_err(|e| {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        locate(&e, path, &text)
    })?;
    Ok(CompiledGraph { path: path.to_path_buf(), desc, shaders, schedule })
}
