//! Records a compiled `Schedule` as wgpu compute dispatches. An executor is
//! built from a schedule and its pipelines (from the cache) in one go:
//! textures, params buffers and the bind groups of both history parities;
//! a frame then only records dispatches. A rebuilt executor takes over the
//! textures of the one it replaces wherever their descriptors are the same,
//! so a shader edit keeps what does not depend on it.
//!
//! Timing (docs/ARCHITECTURE.md, "Timing"): with `Timing::Gpu` the passes
//! carry timestamp writes read back frames later, without waiting; with
//! `Timing::WallPerPass` (profiling on CPU adapters, whose timestamps do
//! not bracket the work) each pass is submitted alone and waited for.

use std::sync::Arc;

mod textures;

use crate::error::UserError;
use crate::format::TexFormat;
use crate::gpu::timing::PassTimer;
use crate::gpu::Gpu;
use crate::graph::frame_kind::FrameKind;
use crate::graph::pipelines::{wgpu_format, CachedPipeline};
use crate::graph::desc::RunMode;
use crate::graph::runs::{RunGpu, RunState, RUN_BYTES};
use crate::graph::schedule::*;
use crate::graph::tile_pool;

/// What records after a frame's passes, in its command encoder
/// (`Executor::run_frame_with`).
pub struct FrameHook<'a> {
    /// The resource whose final version it gets (None, or a name the
    /// schedule lacks: the output).
    pub resource: Option<&'a str>,
    /// Records into the encoder, given the texture and its format.
    pub record: &'a mut dyn FnMut(&mut wgpu::CommandEncoder, &wgpu::Texture, TexFormat),
}

/// How a frame is timed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// Not timed: submit and go on.
    None,
    /// GPU timestamps around each pass, read back a frame or two later.
    Gpu,
    /// Each pass submitted alone and timed on the CPU clock (profiling).
    WallPerPass,
}

impl Timing {
    /// Whether the adapter's timestamps measure the work: on GPUs they do;
    /// on CPU adapters (lavapipe) they do not bracket the dispatches.
    pub fn stamps_bracket_work(gpu: &Gpu) -> bool {
        gpu.timestamps && gpu.info.device_type != wgpu::DeviceType::Cpu
    }

    /// Per-pass timings without stalling where the adapter allows it:
    /// timestamps on GPUs, none on CPU adapters unless `profile` asks for
    /// per-pass wall time (which submits passes one by one).
    pub fn for_adapter(gpu: &Gpu, profile: bool) -> Timing {
        if Self::stamps_bracket_work(gpu) {
            Timing::Gpu
        } else if profile {
            Timing::WallPerPass
        } else {
            Timing::None
        }
    }
}

/// Milliseconds per pass of one frame, by pass name.
#[derive(Debug, Clone, PartialEq)]
pub struct PassTimings {
    /// The executor's frame counter when the frame was recorded.
    pub frame: u64,
    /// (pass name, milliseconds) for each pass that ran, in schedule order.
    pub passes: Vec<(String, f64)>,
}

impl PassTimings {
    /// The sum over the passes, milliseconds.
    pub fn total(&self) -> f64 {
        self.passes.iter().map(|(_, ms)| ms).sum()
    }
}

struct PassGpu {
    pipeline: Arc<CachedPipeline>,
    /// (group index, bind group) for parity 0 and 1.
    bind_groups: [Vec<(u32, wgpu::BindGroup)>; 2],
    workgroups: [u32; 3],
    params: Option<wgpu::Buffer>,
    /// The `run` uniform, for passes that bind one.
    run: Option<wgpu::Buffer>,
    /// The work list of a pass with a `listed` entry.
    work_list: Option<WorkList>,
    /// The tile pool, for passes that bind one.
    tile_pool: Option<tile_pool::PassPool>,
}

/// A pass's work list (Target::WorkList) and its indirect dispatch.
struct WorkList {
    list: wgpu::Buffer,
    args: wgpu::Buffer,
}

/// A texture of the executor with what decides whether a rebuild may keep it.
#[derive(Clone)]
struct Physical {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    key: TextureKey,
}

#[derive(Debug, Clone, PartialEq)]
struct TextureKey {
    label: String,
    format: TexFormat,
    size: (u32, u32),
    usage: wgpu::TextureUsages,
}

/// Records a `Schedule`'s frames: owns its textures, params buffers, bind
/// groups, timers and run counters.
pub struct Executor {
    /// The schedule it runs.
    pub schedule: Schedule,
    /// The render size (width, height) its screen-sized textures have.
    pub size: (u32, u32),
    textures: Vec<Physical>,
    passes: Vec<PassGpu>,
    /// Sizes the second dispatch of passes with a tile pool (one for all).
    pool_fixup: Option<tile_pool::Fixup>,
    timer: Option<PassTimer>,
    parity: u8,
    frame: u64,
    /// Per pass: dispatches so far (see `RunMode`).
    runs: Vec<RunState>,
    /// This frame's `run` records, copied into each pass's `run` uniform
    /// before its dispatch (one submit, several values).
    run_records: Option<wgpu::Buffer>,
    /// Textures taken over from the executor this one replaced.
    pub textures_kept: usize,
    /// What kind of frame this is: passes whose shader declares its
    /// per-frame constants run the pipeline made for it
    /// (graph/frame_kind.rs). The session sets it before each frame.
    pub frame_kind: FrameKind,
    /// Whether this frame has a last frame in its history (passes that
    /// run `OnSceneChangeWithHistory` need one). The session sets it
    /// before each frame.
    pub has_history: bool,
    /// Frames the image has stood still before this one, for passes that
    /// thin their frames (`RunMode::ThinWhenStill`); None: a frame shown
    /// in full, where they all run. The session sets it before each frame.
    pub still_frames: Option<u32>,
}

/// What the executor binds for an engine resource.
pub type EngineBindings<'a> = dyn Fn(EngineResource) -> wgpu::BindingResource<'a> + 'a;

impl Executor {
    /// Creates textures (or takes `previous`'s where the descriptor is the
    /// same), params buffers and bind groups. `pipelines` are the schedule's
    /// pipelines in pass order; `engine` binds the frame uniform and scene
    /// arrays. Everything is created inside error scopes.
    pub fn new(
        gpu: &Gpu,
        schedule: &Schedule,
        pipelines: &[Arc<CachedPipeline>],
        engine: &EngineBindings<'_>,
        size: (u32, u32),
        previous: Option<&Executor>,
    ) -> Result<Executor, UserError> {
        check_memory(gpu, schedule, size)?;
        let device = &gpu.device;
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let invalid = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let built = Self::create(gpu, schedule, pipelines, engine, size, previous);
        let invalid = pollster::block_on(invalid.pop());
        let oom = pollster::block_on(oom.pop());
        let executor = built?;
        // Out of memory first: the validation errors that follow it are
        // about the objects it left invalid.
        if let Some(e) = oom {
            return Err(UserError::new(format!(
                "graph `{}` at {}x{}: {} ran out of memory for its textures ({:.2} GiB in all): {e}; render smaller",
                schedule.name,
                size.0,
                size.1,
                gpu.describe(),
                texture_bytes(schedule, size) as f64 / GIB
            )));
        }
        if let Some(e) = invalid {
            return Err(UserError::new(format!("graph `{}`: {} refused its textures or bind groups: {e}", schedule.name, gpu.describe())));
        }
        Ok(executor)
    }

    fn create(
        gpu: &Gpu,
        schedule: &Schedule,
        pipelines: &[Arc<CachedPipeline>],
        engine: &EngineBindings<'_>,
        size: (u32, u32),
        previous: Option<&Executor>,
    ) -> Result<Executor, UserError> {
        let device = &gpu.device;
        if pipelines.len() != schedule.passes.len() {
            return Err(UserError::new(format!("graph `{}`: {} pipelines for {} passes", schedule.name, pipelines.len(), schedule.passes.len())));
        }
        let max = gpu.max_texture_side();
        let mut spare: Vec<Physical> = previous.map(|p| p.textures.clone()).unwrap_or_default();
        let mut textures_kept = 0;
        let mut textures = Vec::new();
        for t in &schedule.textures {
            let (w, h) = t.size.resolve(size);
            if w > max || h > max {
                return Err(UserError::new(format!(
                    "texture `{}` would be {w}x{h}, beyond this adapter's limit of {max}x{max}; render smaller",
                    t.label
                )));
            }
            // Every texture can be sampled, whatever the passes do: the
            // viewer's present pass shows any of them (src/viewer/present.rs).
            let mut usage = wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING;
            if t.usage.storage {
                usage |= wgpu::TextureUsages::STORAGE_BINDING;
            }
            if t.persistent {
                // A volume loaded from a file is written into it.
                usage |= wgpu::TextureUsages::COPY_DST;
            }
            let key = TextureKey { label: t.label.clone(), format: t.format, size: (w, h), usage };
            if let Some(i) = spare.iter().position(|p| p.key == key) {
                textures.push(spare.swap_remove(i));
                textures_kept += 1;
                continue;
            }
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some(&t.label),
                size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu_format(t.format),
                usage,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            textures.push(Physical { texture, view, key });
        }

        let mut passes = Vec::new();
        let mut pool_fixup = None;
        for (sp, pipeline) in schedule.passes.iter().zip(pipelines) {
            let params = sp.params.as_ref().map(|p| {
                let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&sp.name),
                    size: (p.bytes.len() as u64).max(16).next_multiple_of(16),
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                gpu.queue.write_buffer(&buffer, 0, &p.bytes);
                buffer
            });
            let run = sp.bindings.iter().any(|b| b.target == Target::Run).then(|| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&sp.name),
                    size: RUN_BYTES,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            });
            // The count and the dispatch's x are zeroed before each run;
            // y and z stay 1.
            let work_list = sp.bindings.iter().any(|b| b.target == Target::WorkList).then(|| {
                let (w, h) = sp.dispatch.resolve(size);
                let list = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&sp.name),
                    size: WORK_LIST_HEADER + 4 * u64::from(w) * u64::from(h),
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                gpu.queue.write_buffer(&list, 0, bytemuck::cast_slice(&[0u32, 0, 1, 1]));
                // A buffer bound writable cannot also be a dispatch's
                // indirect buffer: the groups are copied out to this one.
                let args = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&sp.name),
                    size: 12,
                    usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                WorkList { list, args }
            });
            let tile_pool = sp.bindings.iter().any(|b| b.target == Target::TilePool).then(|| {
                let fixup = pool_fixup.get_or_insert_with(|| tile_pool::Fixup::new(device));
                let per_group = sp.workgroup_size.iter().product::<u32>();
                tile_pool::PassPool::new(device, &gpu.queue, fixup, &sp.name, size, per_group)
            });
            let make_groups = |parity: u8| -> Result<Vec<(u32, wgpu::BindGroup)>, UserError> {
                let mut groups = Vec::new();
                for (g, layout) in &pipeline.layouts {
                    let mut entries = Vec::new();
                    for b in sp.bindings.iter().filter(|b| b.group == *g) {
                        let resource = match &b.target {
                            Target::Texture(t) => wgpu::BindingResource::TextureView(&textures[t.resolve(parity)].view),
                            Target::Params => match &params {
                                Some(p) => p.as_entire_binding(),
                                None => return Err(UserError::new(format!("pass `{}`: `params` has no layout", sp.name))),
                            },
                            Target::Engine(e) => engine(e.to_owned()),
                            Target::Run => match &run {
                                Some(r) => r.as_entire_binding(),
                                None => return Err(UserError::new(format!("pass `{}`: `run` has no buffer", sp.name))),
                            },
                            Target::WorkList => match &work_list {
                                Some(l) => l.list.as_entire_binding(),
                                None => return Err(UserError::new(format!("pass `{}`: `work_list` has no buffer", sp.name))),
                            },
                            Target::TilePool => match &tile_pool {
                                Some(pool) => pool.buffer.as_entire_binding(),
                                None => return Err(UserError::new(format!("pass `{}`: `tile_pool` has no buffer", sp.name))),
                            },
                        };
                        entries.push(wgpu::BindGroupEntry { binding: b.binding, resource });
                    }
                    groups.push((*g, device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(&sp.name), layout, entries: &entries })));
                }
                Ok(groups)
            };
            let bind_groups = [make_groups(0)?, make_groups(1)?];
            let workgroups = match tile_pool {
                Some(_) => tile_pool::workgroups(gpu.info.device_type, sp.workgroup_size, size),
                // Within the adapter's limits (`graph::check_dispatches`
                // said so, located in the graph file, before this).
                None => sp.workgroups(size).map(|n| u32::try_from(n).unwrap_or(u32::MAX)),
            };
            passes.push(PassGpu {
                pipeline: Arc::clone(pipeline),
                bind_groups,
                workgroups,
                params,
                run,
                work_list,
                tile_pool,
            });
        }
        let most: u64 = schedule.passes.iter().map(|p| u64::from(dispatches_at_most(p.run))).sum();
        let run_records = passes.iter().any(|p| p.run.is_some()).then(|| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("run records"),
                size: most.max(1) * RUN_BYTES,
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let timer = gpu.timestamps.then(|| PassTimer::new(device, &gpu.queue, passes.len()));
        // Keep the history parity of the executor replaced when the ping-pong
        // layout is the same, so kept history textures stay in step.
        let parity = previous.filter(|p| p.schedule.flips_parity == schedule.flips_parity).map_or(0, |p| p.parity);
        let runs = vec![RunState::default(); passes.len()];
        Ok(Executor { schedule: schedule.clone(), size, textures, passes, pool_fixup, timer, parity, frame: 0, runs, run_records, textures_kept, frame_kind: FrameKind::GENERIC, has_history: false, still_frames: None })
    }

    /// Dispatches every pipeline of every pass once with no workgroups, so
    /// that a driver that compiles a pipeline's machine code at its first
    /// dispatch (llvmpipe does) compiles them all now, not in the first
    /// frame of each kind (the first thinned frame took about 2 s with a
    /// cold shader cache; docs/realtime.md). Writes nothing.
    pub fn warm_pipelines(&self, gpu: &Gpu) {
        let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("warm pipelines") });
        for p in &self.passes {
            let bind_groups = &p.bind_groups[usize::from(self.parity)];
            for pipeline in p.pipeline.all() {
                let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("warm"), timestamp_writes: None });
                cp.set_pipeline(pipeline);
                for (g, bg) in bind_groups {
                    cp.set_bind_group(*g, bg, &[]);
                }
                cp.dispatch_workgroups(0, 0, 0);
            }
        }
        gpu.queue.submit([enc.finish()]);
        let _ = gpu.device.poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(crate::gpu::gpu_timeout()) });
    }

    /// Writes pass `pass`'s packed params (after `PassParams::set`).
    pub fn write_params(&self, queue: &wgpu::Queue, pass: usize, bytes: &[u8]) {
        if let Some(Some(buffer)) = self.passes.get(pass).map(|p| p.params.as_ref()) {
            queue.write_buffer(buffer, 0, bytes);
        }
    }

    /// Records dispatch `k` of pass `i`: first the copy of its `run`
    /// record (at `record` in the records buffer), then the compute pass.
    fn encode_pass(&self, enc: &mut wgpu::CommandEncoder, i: usize, record: u64, timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>) {
        let (p, sp) = (&self.passes[i], &self.schedule.passes[i]);
        if let (Some(run), Some(records)) = (&p.run, &self.run_records) {
            enc.copy_buffer_to_buffer(records, record * RUN_BYTES, run, 0, RUN_BYTES);
        }
        let bind_groups = &p.bind_groups[usize::from(self.parity)];
        let (entry, listed) = p.pipeline.for_frame(self.frame_kind);
        // A second, indirect dispatch: the listed entry over the texels the
        // entry listed (a work list, emptied first), or the entry again
        // over the chunks of a tile pool its invocations left.
        let second = match (listed, &p.work_list, &p.tile_pool, &self.pool_fixup) {
            (Some(listed), Some(list), _, _) => {
                enc.clear_buffer(&list.list, 0, Some(8));
                Some((listed, &list.args))
            }
            (_, _, Some(pool), Some(_)) => {
                pool.encode_fill(enc);
                Some((entry, pool.args()))
            }
            _ => None,
        };
        let Some((second_pipeline, args)) = second else {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(&sp.name), timestamp_writes });
            cp.set_pipeline(entry);
            for (g, bg) in bind_groups {
                cp.set_bind_group(*g, bg, &[]);
            }
            cp.dispatch_workgroups(p.workgroups[0], p.workgroups[1], p.workgroups[2]);
            return;
        };
        // The timestamps bracket both dispatches.
        {
            let first = timestamp_writes.as_ref().map(|t| wgpu::ComputePassTimestampWrites {
                query_set: t.query_set,
                beginning_of_pass_write_index: t.beginning_of_pass_write_index,
                end_of_pass_write_index: None,
            });
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(&sp.name), timestamp_writes: first });
            cp.set_pipeline(entry);
            for (g, bg) in bind_groups {
                cp.set_bind_group(*g, bg, &[]);
            }
            cp.dispatch_workgroups(p.workgroups[0], p.workgroups[1], p.workgroups[2]);
        }
        match (&p.work_list, &p.tile_pool, &self.pool_fixup) {
            (Some(list), _, _) => enc.copy_buffer_to_buffer(&list.list, 4, &list.args, 0, 12),
            (None, Some(pool), Some(fixup)) => pool.encode_leftover(enc, fixup),
            _ => {}
        }
        let end = timestamp_writes.map(|t| wgpu::ComputePassTimestampWrites {
            query_set: t.query_set,
            beginning_of_pass_write_index: None,
            end_of_pass_write_index: t.end_of_pass_write_index,
        });
        let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(&sp.name), timestamp_writes: end });
        cp.set_pipeline(second_pipeline);
        for (g, bg) in bind_groups {
            cp.set_bind_group(*g, bg, &[]);
        }
        cp.dispatch_workgroups_indirect(args, 0);
    }

    /// This frame's dispatches: per pass, how many (0 for a pass that does
    /// not run) and where its first record is; writes the records.
    fn plan_runs(&mut self, gpu: &Gpu, epoch: u32) -> Vec<(u32, u64)> {
        let mut records: Vec<RunGpu> = Vec::new();
        let mut plan = Vec::with_capacity(self.passes.len());
        for (i, sp) in self.schedule.passes.iter().enumerate() {
            let inputs_ran = sp.inputs_from.iter().any(|&p| p < i && plan.get(p).is_some_and(|&(n, _): &(u32, u64)| n > 0));
            let (these, next) = self.runs[i].plan(sp.run, epoch, inputs_ran, self.has_history, self.still_frames);
            self.runs[i] = next;
            plan.push((these.len() as u32, records.len() as u64));
            records.extend(these);
        }
        if let Some(buffer) = &self.run_records {
            if !records.is_empty() {
                gpu.queue.write_buffer(buffer, 0, bytemuck::cast_slice(&records));
            }
        }
        plan
    }

    /// Whether the graph thins its still frames and none of its passes
    /// that do runs in a frame `still` frames into a still image (None: a
    /// frame shown in full): the frame kind THINNED (frame_kind.rs).
    pub fn thins(&self, still: Option<u32>) -> bool {
        let mut thinning = self.schedule.passes.iter().filter_map(|sp| sp.run.thin_runs(still)).peekable();
        thinning.peek().is_some() && thinning.all(|runs| !runs)
    }

    /// Whether a pass that fills persistent resources on its own schedule
    /// (a bake: not every frame, not only after its inputs) will run in the
    /// next frame with the scene at `epoch`.
    pub fn updates_persistent(&self, epoch: u32) -> bool {
        self.schedule.passes.iter().zip(&self.runs).any(|(sp, st)| {
            sp.run.bakes() && !st.plan(sp.run, epoch, false, self.has_history, self.still_frames).0.is_empty()
        })
    }

    /// The bakes' progress: iterations run since the scene last changed,
    /// and iterations to run, summed over the progressive passes that
    /// stop (`Progressive(until: ...)`); None when there are none.
    pub fn bake_progress(&self) -> Option<(u32, u32)> {
        let mut progress = None;
        for (sp, st) in self.schedule.passes.iter().zip(&self.runs) {
            if let RunMode::Progressive { until: Some(u), .. } = sp.run {
                let (done, total) = progress.unwrap_or((0, 0));
                progress = Some((done + st.since_change.min(u), total + u));
            }
        }
        progress
    }

    /// Marks every pass that does not run every frame as done for the
    /// scene at `epoch` (a volume loaded from a file): it runs again only
    /// when the scene changes. A progressive pass counts as `until`
    /// iterations in (forever-running ones go on).
    pub fn finish_runs(&mut self, epoch: u32) {
        for (sp, st) in self.schedule.passes.iter().zip(&mut self.runs) {
            let n = match sp.run {
                RunMode::EveryFrame | RunMode::Progressive { until: None, .. } => continue,
                RunMode::Progressive { until: Some(u), .. } => u,
                _ => 1,
            };
            *st = RunState { iteration: n, since_change: n, last_epoch: Some(epoch) };
        }
    }

    /// Forgets how often each pass ran: `Once` and progressive passes start
    /// over as in a new executor (a restart of the session).
    pub fn restart_runs(&mut self) {
        self.runs.fill(RunState::default());
    }

    /// Records and submits one frame with the scene at `epoch` (which
    /// decides the passes that run on a scene change). Returns the per-pass
    /// timings that are ready: with `Timing::WallPerPass` this frame's (each
    /// pass submitted alone and waited for); with `Timing::Gpu` those of
    /// earlier frames whose timestamps have arrived (possibly none), never
    /// waiting. A pass that did not run is absent from its frame's timings.
    pub fn run_frame(&mut self, gpu: &Gpu, timing: Timing, epoch: u32) -> Vec<PassTimings> {
        self.run_frame_with(gpu, timing, epoch, None)
    }

    /// `run_frame`, and `hook` records what follows the frame into its
    /// last command encoder: it gets the frame's output, or the final
    /// version of the resource named (a viewer copies what it shows). In the
    /// same submission, as a CPU driver makes a second submission wait for
    /// the first to finish.
    pub fn run_frame_with(&mut self, gpu: &Gpu, timing: Timing, epoch: u32, mut hook: Option<FrameHook<'_>>) -> Vec<PassTimings> {
        self.frame += 1;
        let plan = self.plan_runs(gpu, epoch);
        let mut ready = Vec::new();
        if timing == Timing::WallPerPass {
            let mut passes = Vec::with_capacity(self.passes.len());
            for (i, &(count, first)) in plan.iter().enumerate() {
                if count == 0 {
                    continue;
                }
                let start = std::time::Instant::now();
                let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(&self.schedule.passes[i].name) });
                for k in 0..u64::from(count) {
                    self.encode_pass(&mut enc, i, first + k, None);
                }
                gpu.queue.submit([enc.finish()]);
                gpu.wait();
                passes.push((self.schedule.passes[i].name.clone(), start.elapsed().as_secs_f64() * 1e3));
            }
            if let Some(h) = &mut hook {
                let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("after the frame") });
                self.run_hook(&mut enc, h);
                gpu.queue.submit([enc.finish()]);
            }
            ready.push(PassTimings { frame: self.frame, passes });
        } else {
            let timed = timing == Timing::Gpu && self.timer.as_mut().is_some_and(|t| t.begin_frame());
            let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
            for (i, &(count, first)) in plan.iter().enumerate() {
                for k in 0..count {
                    let writes = if timed { self.timer.as_ref().and_then(|t| t.writes(i, k == 0, k + 1 == count)) } else { None };
                    self.encode_pass(&mut enc, i, first + u64::from(k), writes);
                }
            }
            if timed {
                if let Some(t) = &mut self.timer {
                    t.resolve(&mut enc, self.frame, plan.iter().map(|&(count, _)| count > 0).collect());
                }
            }
            if let Some(h) = &mut hook {
                self.run_hook(&mut enc, h);
            }
            gpu.queue.submit([enc.finish()]);
            if timed {
                if let Some(t) = &mut self.timer {
                    t.after_submit();
                }
            }
            ready = self.collect_timings(gpu, false);
        }
        if self.schedule.flips_parity {
            self.parity ^= 1;
        }
        ready
    }

    /// GPU timings that have arrived; with `wait`, first waits for every
    /// frame in flight (the end of a run).
    pub fn collect_timings(&mut self, gpu: &Gpu, wait: bool) -> Vec<PassTimings> {
        let Some(t) = &mut self.timer else { return Vec::new() };
        if wait && t.in_flight() {
            gpu.wait();
        } else {
            let _ = gpu.device.poll(wgpu::PollType::Poll);
        }
        t.collect()
            .into_iter()
            .map(|s| PassTimings {
                frame: s.frame,
                passes: self.schedule.passes.iter().zip(s.ms).filter_map(|(p, ms)| Some((p.name.clone(), ms?))).collect(),
            })
            .collect()
    }

    /// The passes' names, in schedule order.
    pub fn pass_names(&self) -> Vec<&str> {
        self.schedule.passes.iter().map(|p| p.name.as_str()).collect()
    }
}

/// The most dispatches a pass running `mode` makes in one frame.
fn dispatches_at_most(mode: RunMode) -> u32 {
    match mode {
        RunMode::Progressive { per_frame, .. } => per_frame,
        _ => 1,
    }
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The bytes of one physical texture at `size`.
fn one_texture_bytes(t: &PhysicalTexture, size: (u32, u32)) -> u64 {
    let (w, h) = t.size.resolve(size);
    u64::from(w) * u64::from(h) * t.format.bytes_per_pixel()
}

/// The bytes of every texture the executor creates at `size` (a history
/// resource's two textures are two physical textures).
fn texture_bytes(schedule: &Schedule, size: (u32, u32)) -> u64 {
    schedule.textures.iter().map(|t| one_texture_bytes(t, size)).sum()
}

/// Refuses, before creating anything, a schedule whose textures cannot fit:
/// on a CPU adapter (lavapipe), textures live in system memory, so more
/// than 3/4 of what the system has available is refused with the figures;
/// a GPU's memory cannot be queried, so there the out-of-memory error
/// scope around creation reports it.
fn check_memory(gpu: &Gpu, schedule: &Schedule, size: (u32, u32)) -> Result<(), UserError> {
    if gpu.info.device_type != wgpu::DeviceType::Cpu {
        return Ok(());
    }
    let Some(available) = available_memory() else { return Ok(()) };
    let need = texture_bytes(schedule, size);
    if need as f64 <= 0.75 * available as f64 {
        return Ok(());
    }
    let mut largest: Vec<(u64, &str)> = schedule.textures.iter().map(|t| (one_texture_bytes(t, size), t.label.as_str())).collect();
    largest.sort_by_key(|l| std::cmp::Reverse(l.0));
    let list: Vec<String> = largest.iter().take(3).map(|(b, l)| format!("{l} {:.2} GiB", *b as f64 / GIB)).collect();
    Err(UserError::new(format!(
        "graph `{}` at {}x{} needs {:.2} GiB of textures (largest: {}), more than 3/4 of the {:.2} GiB this machine has available for {}; render smaller",
        schedule.name,
        size.0,
        size.1,
        need as f64 / GIB,
        list.join(", "),
        available as f64 / GIB,
        gpu.describe()
    )))
}

/// MemAvailable from /proc/meminfo (Linux), in bytes, or less where a
/// cgroup v2 memory limit leaves less.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    let system = kib.checked_mul(1024)?;
    let read = |f: &str| std::fs::read_to_string(f).ok().and_then(|t| t.trim().parse::<u64>().ok());
    let cgroup = read("/sys/fs/cgroup/memory.max").map(|max| max.saturating_sub(read("/sys/fs/cgroup/memory.current").unwrap_or(0)));
    Some(cgroup.map_or(system, |c| c.min(system)))
}
