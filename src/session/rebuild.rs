//! Rebuilds built aside (docs/ARCHITECTURE.md, "Reload protocol").
//!
//! A `RebuildJob` holds everything a rebuild needs (handles, the current
//! graph description and shaders, the pipeline cache), so it can run on
//! any thread: it reloads what changed (shaders through naga, the graph
//! file, the scene and its BVH), recompiles the schedule and builds the
//! pipelines that are not in the cache, each inside an error scope. Its
//! result, a `Rebuild`, is swapped in by `Session::commit` at a frame
//! boundary. Any error leaves the session as it was.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::desc::FrameGraph;
use crate::graph::edit::ParamSet;
use crate::graph::pipelines::{PipelineCache, PipelineSet};
use crate::graph::tile_pool;
use crate::graph::{self, CompileOptions, CompiledGraph};
use crate::scene::Camera;
use crate::session::scene_gpu::SceneGpu;
use crate::shader::Shader;

/// What a rebuild was for (the report and the overlay say it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RebuildKind {
    /// These files changed; every shader whose import closure holds one is
    /// reloaded.
    Shaders(Vec<PathBuf>),
    /// The graph file was edited (params the user set are kept where the
    /// pass and the name still match).
    Graph(PathBuf),
    /// Another graph replaces the running one.
    SwitchGraph(PathBuf),
    /// The scene (or one of its meshes) changed; the camera is kept.
    Scene(PathBuf),
    /// Another scene file replaces the running one, with its own camera.
    OpenScene(PathBuf),
    /// Compile options changed (a pass enabled or disabled).
    Edits,
}

impl RebuildKind {
    /// "shader", "graph" or "scene": what the last good one of is kept.
    pub fn what(&self) -> &'static str {
        match self {
            RebuildKind::Shaders(_) => "shader",
            RebuildKind::Graph(_) | RebuildKind::SwitchGraph(_) | RebuildKind::Edits => "graph",
            RebuildKind::Scene(_) | RebuildKind::OpenScene(_) => "scene",
        }
    }
}

/// A rebuild ready to run on any thread. Cloning is cheap enough to keep
/// one as a template (the viewer's reload thread starts its jobs from it).
#[derive(Clone)]
pub struct RebuildJob {
    pub(super) gpu: Gpu,
    pub(super) kind: RebuildKind,
    pub(super) graph: CompiledGraph,
    pub(super) shader_dir: PathBuf,
    pub(super) options: CompileOptions,
    pub(super) cache: PipelineCache,
    pub(super) camera: Camera,
    /// The current scene's engine constants (a scene rebuild uses its own).
    pub(super) engine_constants: Vec<(&'static str, f64)>,
    /// Params a graph switch starts with (a machine profile's overrides).
    pub(super) preset: Vec<ParamSet>,
}

/// A finished rebuild, waiting for `Session::commit`.
pub struct Rebuild {
    /// What it was for.
    pub kind: RebuildKind,
    /// The recompiled graph.
    pub graph: CompiledGraph,
    /// Its pipelines, and the cache that holds them.
    pub pipelines: PipelineSet,
    /// The reloaded scene (None: the session keeps its own).
    pub scene: Option<SceneGpu>,
    /// The compile options `graph` was compiled with.
    pub options: CompileOptions,
    /// When the job started running (`ReloadReport::ms` counts from it).
    pub started: Instant,
}

/// Same path, whether or not either side is canonical (a file replaced by
/// rename may not exist for a moment).
pub fn same_file(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    a == b || canon(a) == canon(b)
}

/// Whether a shader's import closure holds any of `files`.
pub fn depends_on(shader: &Shader, files: &[PathBuf]) -> bool {
    shader.source.files.iter().any(|f| files.iter().any(|c| same_file(f, c)))
}

/// Keeps the `--set`s and live params whose pass and param still exist in
/// `desc` with `shaders` (a graph edit keeps what still matches).
fn matching_sets(sets: &[ParamSet], desc: &FrameGraph, shaders: &BTreeMap<String, Shader>) -> Vec<ParamSet> {
    sets.iter()
        .filter(|s| {
            desc.passes.iter().any(|p| {
                p.name == s.pass
                    && shaders
                        .get(&p.shader)
                        .and_then(|sh| sh.info.params.as_ref())
                        .is_some_and(|l| l.members.iter().any(|m| m.name == s.param))
            })
        })
        .cloned()
        .collect()
}

/// Shaders whose expanded text is what `loaded` already holds are taken
/// from there (no naga parse and validation again); the rest are parsed.
fn reuse_unchanged(
    sources: BTreeMap<String, crate::shader::ShaderSource>,
    loaded: &BTreeMap<String, Shader>,
) -> Result<BTreeMap<String, Shader>, UserError> {
    sources
        .into_iter()
        .map(|(name, src)| match loaded.get(&name) {
            Some(s) if s.source.text == src.text => Ok((name, s.clone())),
            _ => crate::shader::from_source(src).map(|s| (name, s)),
        })
        .collect()
}

impl RebuildJob {
    /// What the job rebuilds for.
    pub fn kind(&self) -> &RebuildKind {
        &self.kind
    }

    /// The same job for another kind of change.
    pub fn with_kind(mut self, kind: RebuildKind) -> RebuildJob {
        self.kind = kind;
        self
    }

    /// Takes in what a finished rebuild produced, so the next job starts
    /// from it even before the session has committed it.
    pub fn absorb(&mut self, r: &Rebuild) {
        self.graph = r.graph.clone();
        self.options = r.options.clone();
        self.cache = r.pipelines.cache.clone();
        if let Some(s) = &r.scene {
            self.engine_constants = s.engine_constants();
        }
    }

    /// Runs the rebuild on a thread of its own; its result arrives on the
    /// channel (nothing arrives if the thread could not start: the error
    /// says so).
    pub fn spawn(self) -> Result<std::sync::mpsc::Receiver<Result<Rebuild, UserError>>, UserError> {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::Builder::new()
            .name("glint rebuild".into())
            .spawn(move || {
                // Nobody listening (the rebuild was superseded) is fine.
                let _ = tx.send(self.run());
            })
            .map_err(|e| UserError::new(format!("cannot start a rebuild thread: {e}")))?;
        Ok(rx)
    }

    /// Runs the rebuild. Nothing of the session is touched.
    pub fn run(self) -> Result<Rebuild, UserError> {
        let started = Instant::now();
        let RebuildJob { gpu, kind, graph: current, shader_dir, mut options, cache, camera, engine_constants, preset } = self;
        let mut scene = None;
        let (desc, shaders, path) = match &kind {
            RebuildKind::Shaders(files) => {
                let mut shaders = current.shaders.clone();
                for (name, shader) in shaders.iter_mut() {
                    if depends_on(shader, files) {
                        *shader = crate::shader::load(&shader_dir, name)?;
                    }
                }
                (current.desc.clone(), shaders, current.path.clone())
            }
            RebuildKind::Graph(path) | RebuildKind::SwitchGraph(path) => {
                let desc = FrameGraph::load(path)?;
                let shaders = reuse_unchanged(graph::load_sources(&desc, &shader_dir)?, &current.shaders)?;
                if matches!(kind, RebuildKind::SwitchGraph(_)) {
                    options.edits.set = preset;
                    options.edits.skip.clear();
                    options.edits.stop_after = None;
                    options.output = None;
                } else {
                    options.edits.set = matching_sets(&options.edits.set, &desc, &shaders);
                    options.edits.skip.retain(|s| desc.passes.iter().any(|p| &p.name == s));
                    if options.edits.stop_after.as_ref().is_some_and(|s| !desc.passes.iter().any(|p| &p.name == s)) {
                        options.edits.stop_after = None;
                    }
                    if options.output.as_ref().is_some_and(|o| !desc.resources.contains_key(o)) {
                        options.output = None;
                    }
                }
                (desc, shaders, path.clone())
            }
            RebuildKind::Scene(path) | RebuildKind::OpenScene(path) => {
                let mut loaded = crate::scene::load(path)?;
                if matches!(kind, RebuildKind::Scene(_)) {
                    loaded.camera = camera;
                }
                scene = Some(SceneGpu::new(&gpu, loaded)?);
                (current.desc.clone(), current.shaders.clone(), current.path.clone())
            }
            RebuildKind::Edits => (current.desc.clone(), current.shaders.clone(), current.path.clone()),
        };
        let features = scene.as_ref().map_or(current.schedule.features, |s| s.scene.compile_features());
        let graph = graph::compile_loaded(&path, desc, shaders, &features, &options)?;
        let mut constants = scene.as_ref().map_or(engine_constants, |s| s.engine_constants());
        constants.push(tile_pool::constant(gpu.info.device_type));
        let pipelines = cache.build(&gpu.device, gpu.pipeline_cache.as_deref(), &graph, &constants)?;
        Ok(Rebuild { kind, graph, pipelines, scene, options, started })
    }
}
