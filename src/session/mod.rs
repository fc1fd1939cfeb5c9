//! The live engine (docs/ARCHITECTURE.md, "The session"): one object that
//! owns the scene on the GPU, the compiled graph, the pipeline cache, the
//! executor and the frame state. `glint render`, `converge`, `bench`, the
//! tests and the viewer all render through it.
//!
//! Every change (`reload_shaders`, `reload_graph`, `reload_scene`,
//! `set_graph`, `set_enabled`) is built aside by a `RebuildJob` and
//! swapped in by `commit` only when every step succeeded; on failure the
//! session is unchanged and the error is returned. `set_param` writes the
//! pass's params buffer, without a recompile. Objects replaced by a swap are
//! kept until the GPU has finished the frames that used them.

pub mod frame_loop;
pub mod frame_uniform;
mod volume;
pub mod rebuild;
pub mod scene_gpu;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::error::UserError;
use crate::gpu::readback::ImageF32;
use crate::gpu::Gpu;
use crate::graph::desc::ParamValue;
use crate::graph::edit::ParamSet;
use crate::graph::executor::{Executor, FrameHook, PassTimings, Timing};
use crate::graph::frame_kind::FrameKind;
use crate::graph::pipelines::PipelineCache;
use crate::graph::tile_pool;
use crate::graph::{self, CompileOptions, CompiledGraph};
use crate::scene::Scene;
use frame_uniform::{CameraGpu, FrameGpu};
use crate::scene::origins::Viewpoints;
use rebuild::{Rebuild, RebuildJob, RebuildKind};
use scene_gpu::SceneGpu;

/// The noise-mask threshold without a frame-time target (and the PID's
/// starting point): masks the strongest noise of a one-sample frame.
pub const DEFAULT_MASK_THRESHOLD: f32 = 0.1;

/// Checks a render size against the adapter.
pub fn check_size(gpu: &Gpu, size: (u32, u32)) -> Result<(), UserError> {
    let max = gpu.max_texture_side();
    if size.0 == 0 || size.1 == 0 {
        return Err(UserError::new(format!("the size {}x{} is empty; give --size WxH with both at least 1", size.0, size.1)));
    }
    if size.0 > max || size.1 > max {
        return Err(UserError::new(format!(
            "the size {}x{} is beyond this adapter's limit of {max}x{max} ({}); render smaller",
            size.0,
            size.1,
            gpu.describe()
        )));
    }
    Ok(())
}

/// How a session renders.
#[derive(Debug, Clone)]
pub struct SessionOptions {
    /// Render size in pixels, (width, height): at least 1 and at most the
    /// adapter's largest texture side (`check_size`).
    pub size: (u32, u32),
    /// Random seed of every pass's samples (the frame uniform's `seed`).
    pub seed: u32,
    /// Output override, `--set`/`--skip`/`--stop-after`, kept resources.
    pub compile: CompileOptions,
    /// The shader folder (default: next to the graph's folder).
    pub shader_dir: Option<PathBuf>,
    /// Whether every pipeline is dispatched once before the first frame
    /// (`Executor::warm_pipelines`), and again when another graph, scene
    /// or pass set replaces the running one: a driver that compiles at the
    /// first dispatch then does not stall the first frame of each kind.
    /// For sessions whose frames are watched or timed (the viewer, `glint
    /// trade`, `glint bench frames`); a hot reload of an edited file is
    /// not warmed, so that its first frame shows as soon as it can.
    pub warm_pipelines: bool,
}

impl SessionOptions {
    /// `size` with seed 1, default compile options and the shader folder
    /// next to the graph's.
    pub fn new(size: (u32, u32)) -> SessionOptions {
        SessionOptions { size, seed: 1, compile: CompileOptions::default(), shader_dir: None, warm_pipelines: false }
    }
}

/// What the running session is made of, as paths (absolute and canonical
/// where the files exist, as the watcher reports them).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sources {
    /// The shader folder.
    pub shader_dir: PathBuf,
    /// The graph file.
    pub graph: PathBuf,
    /// The scene file; None for a scene not loaded from a file.
    pub scene: Option<PathBuf>,
    /// The mesh files the scene loads.
    pub meshes: Vec<PathBuf>,
}

/// What a committed rebuild did.
#[derive(Debug, Clone, PartialEq)]
pub struct ReloadReport {
    /// What the rebuild was for.
    pub kind: RebuildKind,
    /// Passes whose pipeline was built (not found in the cache).
    pub rebuilt: Vec<String>,
    /// Textures taken over from the replaced executor.
    pub textures_kept: usize,
    /// Milliseconds from the start of the rebuild to the swap.
    pub ms: f64,
}

impl ReloadReport {
    /// "1 pass rebuilt", "3 passes rebuilt".
    pub fn passes_rebuilt(&self) -> String {
        match self.rebuilt.len() {
            1 => "1 pass rebuilt".to_string(),
            n => format!("{n} passes rebuilt"),
        }
    }
}

/// Frame counters behind the `frame` uniform.
#[derive(Debug, Clone, Copy, Default)]
struct FrameState {
    frame_index: u32,
    accum_count: u32,
    epoch_frames: u32,
    history_frames: u32,
    /// Last frame's `FrameGpu::cone_scale`.
    cone_scale: f32,
    /// The next frame is shown in full: every pass that thins its frames
    /// (`RunMode::ThinWhenStill`) runs in it (`Session::show_next_in_full`).
    full_next: bool,
    /// Last frame's camera (world, f64: re-expressed relative to the
    /// current origin each frame, so a rebase keeps reprojection right) and
    /// scene epoch.
    last: Option<(crate::scene::Camera, u32)>,
}

/// Replaced GPU objects, dropped once the frames submitted before the swap
/// have finished.
struct Retired {
    done: Arc<AtomicBool>,
    _executor: Executor,
    _scene: Option<SceneGpu>,
    _pipelines: PipelineCache,
}

/// The live engine: the scene on the GPU, the compiled graph, its
/// pipelines and executor, and the frame counters (see the module doc).
pub struct Session {
    /// The adapter, device and queue it renders with.
    pub gpu: Gpu,
    /// The scene on the GPU; the camera is `scene.scene.camera`.
    pub scene: SceneGpu,
    /// The compiled graph being run (compile options: `options()`).
    pub graph: CompiledGraph,
    /// Runs `graph`'s schedule; owns its textures and the output.
    pub executor: Executor,
    shader_dir: PathBuf,
    options: CompileOptions,
    pipelines: PipelineCache,
    frame_buffer: wgpu::Buffer,
    /// Render size in pixels, (width, height); change it with `resize`
    /// (the executor's textures have this size).
    pub size: (u32, u32),
    /// Random seed written into the frame uniform.
    pub seed: u32,
    /// Written into the frame uniform; the PID controller moves it.
    pub mask_threshold: f32,
    /// How frames are timed (see `Timing::for_adapter`).
    pub timing: Timing,
    state: FrameState,
    retired: Vec<Retired>,
    /// SessionOptions::warm_pipelines.
    warm_pipelines: bool,
    /// Pipelines built since the session started (cache misses).
    pub pipelines_built: usize,
    /// Bumped by every commit: what was derived from the graph or its
    /// shaders (the viewer's param hints) is stale when it changes.
    pub generation: u64,
}

impl Session {
    /// Loads the graph at `graph_path` and its shaders, compiles it for the
    /// scene and builds everything.
    pub fn new(gpu: &Gpu, scene: Scene, graph_path: &Path, options: SessionOptions) -> Result<Session, UserError> {
        let shader_dir = options.shader_dir.clone().unwrap_or_else(|| graph::shader_dir_for(graph_path));
        let compiled = graph::load_and_compile(graph_path, &shader_dir, &scene.compile_features(), &options.compile)?;
        Self::with_graph(gpu, scene, compiled, shader_dir, options)
    }

    /// A session for an already compiled graph (tests and benchmarks that
    /// adjust the schedule before it is built).
    pub fn with_graph(gpu: &Gpu, scene: Scene, graph: CompiledGraph, shader_dir: PathBuf, options: SessionOptions) -> Result<Session, UserError> {
        check_size(gpu, options.size)?;
        let shader_dir = std::fs::canonicalize(&shader_dir).unwrap_or(shader_dir);
        let scene = SceneGpu::new(gpu, scene)?;
        let frame_buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameGpu>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut constants = scene.engine_constants();
        constants.push(tile_pool::constant(gpu.info.device_type));
        let set = PipelineCache::default().build(&gpu.device, gpu.pipeline_cache.as_deref(), &graph, &constants)?;
        graph::check_dispatches(&graph, options.size, gpu.device.limits().max_compute_workgroups_per_dimension)?;
        let executor = Executor::new(gpu, &graph.schedule, &set.per_pass, &|e| scene.binding(e, &frame_buffer), options.size, None)?;
        if options.warm_pipelines {
            executor.warm_pipelines(gpu);
        }
        Ok(Session {
            gpu: gpu.clone(),
            pipelines_built: set.built.len(),
            generation: 0,
            pipelines: set.cache,
            scene,
            graph,
            executor,
            shader_dir,
            options: options.compile,
            frame_buffer,
            size: options.size,
            seed: options.seed,
            mask_threshold: DEFAULT_MASK_THRESHOLD,
            timing: Timing::None,
            state: FrameState::default(),
            retired: Vec::new(),
            warm_pipelines: options.warm_pipelines,
        })
    }

    /// Renders one frame at absolute scene time `time` seconds. Returns the
    /// per-pass timings that are ready (see `Executor::run_frame`).
    pub fn frame(&mut self, time: f32) -> Vec<PassTimings> {
        self.frame_with(time, None)
    }

    /// `frame`, with `hook` recorded after the frame's passes in the same
    /// submission (`Executor::run_frame_with`).
    pub fn frame_with(&mut self, time: f32, hook: Option<FrameHook<'_>>) -> Vec<PassTimings> {
        self.release_retired();
        let world_camera = self.scene.scene.camera;
        self.scene.update(&self.gpu.queue, time, world_camera.position);
        let origin = self.scene.origin;
        let camera = CameraGpu::new(&world_camera, origin, self.size);
        let epoch = self.scene.buffers.epoch;
        let st = &mut self.state;
        let prev_camera = match st.last {
            Some((c, e)) => {
                let c = CameraGpu::new(&c, origin, self.size);
                if c != camera || e != epoch {
                    st.accum_count = 0;
                }
                if e != epoch {
                    st.epoch_frames = 0;
                }
                c
            }
            None => camera,
        };
        let cone_scale = frame_uniform::cone_scale(st.accum_count);
        let prev_cone_scale = if st.last.is_some() { st.cone_scale } else { cone_scale };
        let grid = self.scene.probe_grid(self.executor.schedule.probes);
        // DDGI relocates probes up to 0.45 of a cell from their grid points.
        let probes = grid.map(|g| (g.origin - 0.5 * g.spacing, g.position(g.counts - glam::UVec3::ONE) + 0.5 * g.spacing));
        self.scene.buffers.set_origins(&self.gpu.queue, &Viewpoints { camera: camera.origin.into(), probes, pixels: Some(camera.pixel_camera(self.size)) });
        let data = &self.scene.buffers.data;
        let still = if std::mem::take(&mut st.full_next) { None } else { Some(st.accum_count) };
        let frame = FrameGpu {
            camera,
            prev_camera,
            size: [self.size.0, self.size.1],
            frame_index: st.frame_index,
            accum_count: st.accum_count,
            time,
            seed: self.seed,
            scene_epoch: epoch,
            n_spheres: data.spheres.len() as u32,
            n_instances: data.instances.len() as u32,
            n_triangles: data.triangles.len() as u32,
            n_lights: data.lights.len() as u32,
            mask_threshold: self.mask_threshold,
            background: data.background,
            epoch_frames: st.epoch_frames,
            exact_one: 1.0,
            offset_scale: self.scene.offset_scale,
            history_frames: st.history_frames,
            cone_scale,
            probe_origin: grid.map_or([0.0; 3], |g| g.origin.to_array()),
            probe_n: grid.map_or(0, |g| g.counts.x),
            probe_spacing: grid.map_or([0.0; 3], |g| g.spacing.to_array()),
            prev_cone_scale,
            n_light_clusters: data.light_clusters.count,
            _pad: [0; 3],
        };
        self.gpu.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&frame));
        // The kind of frame picks the passes' per-frame pipelines
        // (graph/frame_kind.rs; as a specialisation: not with
        // --no-specialise).
        let specialise = self.executor.schedule.specialise;
        self.executor.frame_kind = FrameKind {
            camera_still: specialise && bytemuck::bytes_of(&frame.camera) == bytemuck::bytes_of(&frame.prev_camera),
            scene_still: specialise && (st.epoch_frames > 0 || st.history_frames == 0),
            no_history: specialise && st.history_frames == 0,
            thinned: specialise && self.executor.thins(still),
        };
        self.executor.has_history = st.history_frames > 0;
        self.executor.still_frames = still;
        let timings = self.executor.run_frame_with(&self.gpu, self.timing, epoch, hook);
        st.last = Some((world_camera, epoch));
        st.cone_scale = cone_scale;
        st.frame_index = st.frame_index.wrapping_add(1);
        st.accum_count = st.accum_count.saturating_add(1);
        st.epoch_frames = st.epoch_frames.saturating_add(1);
        st.history_frames = st.history_frames.saturating_add(1);
        timings
    }

    /// Waits for the frames in flight and returns their GPU timings.
    pub fn finish(&mut self) -> Vec<PassTimings> {
        self.executor.collect_timings(&self.gpu, true)
    }

    /// Drops all accumulated history (as a scene change would).
    pub fn reset_accumulation(&mut self) {
        self.state.accum_count = 0;
        self.state.epoch_frames = 0;
        self.state.history_frames = 0;
    }

    /// Starts over as a new session would: history dropped and the frame
    /// index back at 0, so the frames after a change equal a fresh render
    /// with the new settings.
    pub fn restart(&mut self) {
        self.state = FrameState::default();
        self.executor.restart_runs();
    }

    /// Runs every pass in the next frame, those that thin their frames
    /// while the image stands still included: for a frame that is kept
    /// (`glint render`'s last, a viewer's last before it stops at its
    /// sample target).
    pub fn show_next_in_full(&mut self) {
        self.state.full_next = true;
    }

    /// Frames accumulated since the last reset.
    pub fn accumulated(&self) -> u32 {
        self.state.accum_count
    }

    /// Whether the next frame would only add samples to the last one's:
    /// the camera is where it was, nothing in the scene moves and no bake
    /// is running. (A param, graph or scene change restarts the count.)
    pub fn still(&self) -> bool {
        self.state.last.is_some_and(|(c, _)| c == self.scene.scene.camera) && !self.graph.schedule.features.motion && !self.baking()
    }

    /// Reads the last frame's output back to the CPU (waits for the GPU).
    pub fn read_output(&self) -> Result<ImageF32, UserError> {
        self.executor.read_output(&self.gpu)
    }

    /// A kept resource's final version (see `Executor::read_resource`).
    pub fn read_resource(&self, resource: &str) -> Option<Result<ImageF32, UserError>> {
        self.executor.read_resource(&self.gpu, resource)
    }

    /// The files this session is made of, for the watcher.
    pub fn sources(&self) -> Sources {
        let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
        let scene = &self.scene.scene;
        Sources {
            shader_dir: self.shader_dir.clone(),
            graph: canon(&self.graph.path),
            scene: scene.path.is_file().then(|| canon(&scene.path)),
            meshes: scene.mesh_files.iter().map(|m| canon(m)).collect(),
        }
    }

    /// The shader folder (canonical where it exists).
    pub fn shader_dir(&self) -> &Path {
        &self.shader_dir
    }

    /// The compile options in force: the command line's plus live changes.
    pub fn options(&self) -> &CompileOptions {
        &self.options
    }

    /// Passes switched off with `set_enabled` (or `--skip`).
    pub fn disabled(&self) -> &[String] {
        &self.options.edits.skip
    }

    /// Sets one param of a scheduled pass. Checked against the reflected
    /// layout with the same errors as `--set`; applies from the next frame
    /// without a recompile and restarts accumulation.
    pub fn set_param(&mut self, pass: &str, name: &str, value: ParamValue) -> Result<(), UserError> {
        let schedule = &mut self.executor.schedule;
        let Some(index) = schedule.passes.iter().position(|p| p.name == pass) else {
            let known: Vec<&str> = schedule.passes.iter().map(|p| p.name.as_str()).collect();
            return Err(UserError::new(format!("no scheduled pass `{pass}`; passes: {}", known.join(", "))));
        };
        let sp = &mut schedule.passes[index];
        let Some(params) = sp.params.as_mut() else {
            return Err(UserError::new(format!("pass `{pass}`: param `{name}` given, but {} has no `params` uniform", sp.shader)));
        };
        // A sample count the engine splits across dispatches changes how
        // many passes there are: recompile, as --set would.
        if params.member(&format!("{name}_done")).is_some() || name.ends_with("_done") && params.member(name.trim_end_matches("_done")).is_some() {
            let mut job = self.job(RebuildKind::Edits);
            let sets = &mut job.options.edits.set;
            sets.retain(|s| !(s.pass == pass && s.param == name));
            sets.push(ParamSet { pass: pass.to_string(), param: name.to_string(), value });
            let rebuild = job.run()?;
            self.commit(rebuild)?;
            self.restart();
            return Ok(());
        }
        params.set(name, value.clone()).map_err(|e| UserError::new(format!("pass `{pass}`: {}", e.message())))?;
        let params = params.clone();
        self.executor.write_params(&self.gpu.queue, index, &params.bytes);
        if let Some(p) = self.graph.schedule.passes.iter_mut().find(|p| p.name == pass) {
            p.params = Some(params);
        }
        let sets = &mut self.options.edits.set;
        sets.retain(|s| !(s.pass == pass && s.param == name));
        sets.push(ParamSet { pass: pass.to_string(), param: name.to_string(), value });
        self.restart();
        Ok(())
    }

    /// A param's current value, if the pass is scheduled and has it.
    pub fn param(&self, pass: &str, name: &str) -> Option<&ParamValue> {
        let sp = self.executor.schedule.passes.iter().find(|p| p.name == pass)?;
        sp.params.as_ref()?.values.get(name)
    }

    /// A sample count the engine splits across dispatches (a member with
    /// an `_done` sibling; graph/compile/split.rs), summed over the pass
    /// and its `pass#k` continuations; None when `name` is not one.
    pub fn split_total(&self, pass: &str, name: &str) -> Option<i64> {
        let first = self.executor.schedule.passes.iter().find(|p| p.name == pass)?;
        first.params.as_ref()?.member(&format!("{name}_done"))?;
        let more = format!("{pass}#");
        let shares = self.executor.schedule.passes.iter().filter(|p| p.name == pass || p.name.starts_with(&more));
        Some(shares.filter_map(|p| match p.params.as_ref()?.values.get(name)? {
            ParamValue::Int(n) => Some(*n),
            _ => None,
        }).sum())
    }

    // -- rebuilds ----------------------------------------------------------

    /// A rebuild of `kind`, to run on any thread and then `commit`.
    pub fn job(&self, kind: RebuildKind) -> RebuildJob {
        RebuildJob {
            gpu: self.gpu.clone(),
            kind,
            graph: self.graph.clone(),
            shader_dir: self.shader_dir.clone(),
            options: self.options.clone(),
            cache: self.pipelines.clone(),
            camera: self.scene.scene.camera,
            engine_constants: self.scene.engine_constants(),
            preset: Vec::new(),
        }
    }

    /// Swaps a finished rebuild in. The executor is made here (textures
    /// kept where their descriptors match, new bind groups); if that fails
    /// nothing changes. Accumulation restarts: the image changed.
    pub fn commit(&mut self, mut r: Rebuild) -> Result<ReloadReport, UserError> {
        if let (Some(s), false) = (&mut r.scene, matches!(r.kind, RebuildKind::OpenScene(_))) {
            // The camera as it is now (it may have moved while the rebuild ran).
            s.scene.camera = self.scene.scene.camera;
        }
        // Shaders saved back to what is running (an edit reverted, a save
        // of the same text) change nothing: the history stays.
        let same_text = |a: &CompiledGraph, b: &CompiledGraph| {
            a.shaders.len() == b.shaders.len() && a.shaders.iter().all(|(n, s)| b.shaders.get(n).is_some_and(|t| t.source.text == s.source.text))
        };
        let unchanged = matches!(r.kind, RebuildKind::Shaders(_)) && r.pipelines.built.is_empty() && same_text(&r.graph, &self.graph);
        let scene = r.scene.as_ref().unwrap_or(&self.scene);
        let frame_buffer = &self.frame_buffer;
        graph::check_dispatches(&r.graph, self.size, self.gpu.device.limits().max_compute_workgroups_per_dimension)?;
        let executor = Executor::new(&self.gpu, &r.graph.schedule, &r.pipelines.per_pass, &|e| scene.binding(e, frame_buffer), self.size, Some(&self.executor))?;
        let report = ReloadReport {
            kind: r.kind,
            rebuilt: r.pipelines.built.clone(),
            textures_kept: executor.textures_kept,
            ms: r.started.elapsed().as_secs_f64() * 1e3,
        };
        if self.warm_pipelines && !matches!(report.kind, RebuildKind::Shaders(_) | RebuildKind::Graph(_) | RebuildKind::Scene(_)) {
            executor.warm_pipelines(&self.gpu);
        }
        let old_executor = std::mem::replace(&mut self.executor, executor);
        let old_scene = r.scene.map(|s| std::mem::replace(&mut self.scene, s));
        let old_pipelines = std::mem::replace(&mut self.pipelines, r.pipelines.cache);
        self.retire(old_executor, old_scene, old_pipelines);
        self.graph = r.graph;
        self.options = r.options;
        self.pipelines_built += report.rebuilt.len();
        self.generation += 1;
        if !unchanged {
            self.restart();
        }
        // The new executor's first frame runs every pass: a pass that thins
        // still frames would otherwise leave an output it never wrote.
        self.state.full_next = true;
        Ok(report)
    }

    fn run_job(&mut self, kind: RebuildKind) -> Result<ReloadReport, UserError> {
        let rebuild = self.job(kind).run()?;
        self.commit(rebuild)
    }

    /// Reloads every shader whose import closure holds one of `files` and
    /// rebuilds exactly the pipelines whose source changed.
    pub fn reload_shaders(&mut self, files: &[PathBuf]) -> Result<ReloadReport, UserError> {
        self.run_job(RebuildKind::Shaders(files.to_vec()))
    }

    /// Re-reads the graph file, keeping the params set where pass and name
    /// still match.
    pub fn reload_graph(&mut self, path: &Path) -> Result<ReloadReport, UserError> {
        self.run_job(RebuildKind::Graph(path.to_path_buf()))
    }

    /// Runs another graph (params set for the old one are dropped).
    pub fn set_graph(&mut self, path: &Path) -> Result<ReloadReport, UserError> {
        self.run_job(RebuildKind::SwitchGraph(path.to_path_buf()))
    }

    /// Runs another graph at another size with these params set (a machine
    /// profile), in one rebuild: all of it or nothing.
    pub fn switch_profile(&mut self, path: &Path, params: Vec<ParamSet>, size: (u32, u32)) -> Result<ReloadReport, UserError> {
        check_size(&self.gpu, size)?;
        let rebuild = self.switch_job(path, params).run()?;
        self.commit_sized(rebuild, size)
    }

    /// `switch_profile`'s rebuild, to run on any thread and then
    /// `commit_sized` (the viewer builds it while it keeps presenting).
    pub fn switch_job(&self, path: &Path, params: Vec<ParamSet>) -> RebuildJob {
        let mut job = self.job(RebuildKind::SwitchGraph(path.to_path_buf()));
        job.preset = params;
        job
    }

    /// `commit` at another render size; on failure the old size stays.
    pub fn commit_sized(&mut self, rebuild: Rebuild, size: (u32, u32)) -> Result<ReloadReport, UserError> {
        check_size(&self.gpu, size)?;
        let old = self.size;
        self.size = size;
        let result = self.commit(rebuild);
        if result.is_err() {
            self.size = old;
        }
        result
    }

    /// Reloads the scene file (and its meshes), keeping the camera.
    pub fn reload_scene(&mut self, path: &Path) -> Result<ReloadReport, UserError> {
        self.run_job(RebuildKind::Scene(path.to_path_buf()))
    }

    /// Replaces the scene with another file's, camera and all.
    pub fn open_scene(&mut self, path: &Path) -> Result<ReloadReport, UserError> {
        self.run_job(RebuildKind::OpenScene(path.to_path_buf()))
    }

    /// Switches a pass on or off, as `--skip` does (whatever then feeds
    /// nothing is culled).
    pub fn set_enabled(&mut self, pass: &str, enabled: bool) -> Result<ReloadReport, UserError> {
        if !self.graph.desc.passes.iter().any(|p| p.name == pass) {
            let known: Vec<&str> = self.graph.desc.passes.iter().map(|p| p.name.as_str()).collect();
            return Err(UserError::new(format!("no pass `{pass}` in graph `{}`; passes: {}", self.graph.desc.name, known.join(", "))));
        }
        let mut job = self.job(RebuildKind::Edits);
        job.options.edits.skip.retain(|s| s != pass);
        if !enabled {
            job.options.edits.skip.push(pass.to_string());
        }
        let rebuild = job.run()?;
        self.commit(rebuild)
    }

    /// Keeps these resources' final versions out of the texture pool, so
    /// they can be read back or shown after the frame (the viewer's
    /// resource view). Recompiles.
    pub fn set_kept(&mut self, resources: Vec<String>) -> Result<ReloadReport, UserError> {
        let mut job = self.job(RebuildKind::Edits);
        job.options.keep = resources;
        let rebuild = job.run()?;
        self.commit(rebuild)
    }

    /// Renders at another size from the next frame (a machine profile's
    /// resolution scale, a resized window). On failure the old size stays.
    pub fn resize(&mut self, size: (u32, u32)) -> Result<ReloadReport, UserError> {
        check_size(&self.gpu, size)?;
        let old = self.size;
        self.size = size;
        let result = self.job(RebuildKind::Edits).run().and_then(|r| self.commit(r));
        if result.is_err() {
            self.size = old;
        }
        result
    }

    fn retire(&mut self, executor: Executor, scene: Option<SceneGpu>, pipelines: PipelineCache) {
        let done = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&done);
        self.gpu.queue.on_submitted_work_done(move || flag.store(true, Ordering::Release));
        self.retired.push(Retired { done, _executor: executor, _scene: scene, _pipelines: pipelines });
    }

    fn release_retired(&mut self) {
        if self.retired.is_empty() {
            return;
        }
        let _ = self.gpu.device.poll(wgpu::PollType::Poll);
        self.retired.retain(|r| !r.done.load(Ordering::Acquire));
    }

    /// Replaced objects still waiting for the GPU (for tests).
    pub fn retired_count(&self) -> usize {
        self.retired.len()
    }

    /// Waits for the GPU and drops every replaced object now.
    pub fn release_all(&mut self) {
        self.gpu.wait();
        self.release_retired();
    }
}
