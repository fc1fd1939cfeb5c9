//! One frame, end to end: animate the scene, upload what changed, fill the
//! frame uniform (resetting accumulation on a scene or camera change), run
//! the schedule.

use wgpu::util::DeviceExt;

use crate::error::UserError;
use crate::gpu::frame::{CameraGpu, FrameGpu};
use crate::gpu::readback::ImageF32;
use crate::gpu::scene_buffers::{scene_texture_rows, SceneBuffers, SCENE_TEXTURE_WIDTH};
use crate::bvh::scene::{BuildStats, SceneBvh};
use crate::gpu::Gpu;
use crate::graph::executor::{Executor, Timing};
use crate::graph::CompiledGraph;
use crate::scene::Scene;

/// The noise-mask threshold without a frame-time target (and the PID's
/// starting point): masks the strongest noise of a one-sample frame.
pub const DEFAULT_MASK_THRESHOLD: f32 = 0.1;

pub struct Renderer {
    pub scene: Scene,
    pub buffers: SceneBuffers,
    pub bvh: SceneBvh,
    /// The last BVH update (build on load, refit/TLAS rebuild on motion).
    pub bvh_stats: BuildStats,
    pub executor: Executor,
    frame_buffer: wgpu::Buffer,
    pub size: (u32, u32),
    pub seed: u32,
    /// Written into the frame uniform; the PID controller moves it.
    pub mask_threshold: f32,
    frame_index: u32,
    accum_count: u32,
    epoch_frames: u32,
    last: Option<(CameraGpu, u32)>,
}

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

/// Every scene array must fit its binding on this adapter: the texture
/// arrays within the largest texture side in rows, the storage arrays
/// within one storage binding.
fn check_scene_sizes(gpu: &Gpu, data: &crate::scene::SceneData) -> Result<(), UserError> {
    let too_big = |what: &str, count: usize, bytes: usize, limit: String| {
        UserError::new(format!(
            "the scene has {count} {what} ({:.0} MiB), more than {limit} on this adapter ({}); use fewer or smaller meshes",
            bytes as f64 / 1048576.0,
            gpu.describe()
        ))
    };
    let max_rows = u64::from(gpu.max_texture_side());
    if max_rows < u64::from(SCENE_TEXTURE_WIDTH) {
        return Err(UserError::new(format!(
            "{} takes textures up to {max_rows} texels wide; glint's scene textures are {SCENE_TEXTURE_WIDTH} wide",
            gpu.describe()
        )));
    }
    let geometry = std::mem::size_of_val(data.triangles.as_slice()) + std::mem::size_of_val(data.bvh.as_slice());
    let textures = [
        ("triangles (with their BVH nodes)", geometry, data.triangles.len()),
        ("triangle normals", std::mem::size_of_val(data.normals.as_slice()), data.normals.len()),
        ("spheres", std::mem::size_of_val(data.spheres.as_slice()), data.spheres.len()),
        ("instances", std::mem::size_of_val(data.instances.as_slice()), data.instances.len()),
    ];
    for (what, bytes, count) in textures {
        if scene_texture_rows(bytes) > max_rows {
            let limit = format!("{max_rows} rows of {SCENE_TEXTURE_WIDTH} texels hold");
            return Err(too_big(what, count, bytes, limit));
        }
    }
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let buffers = [
        ("meshes", std::mem::size_of_val(data.meshes.as_slice()), data.meshes.len()),
        ("materials", std::mem::size_of_val(data.materials.as_slice()), data.materials.len()),
        ("lights", std::mem::size_of_val(data.lights.as_slice()), data.lights.len()),
    ];
    for (what, bytes, count) in buffers {
        if bytes as u64 > limit {
            return Err(too_big(what, count, bytes, format!("one buffer binding holds ({:.0} MiB)", limit as f64 / 1048576.0)));
        }
    }
    Ok(())
}

impl Renderer {
    pub fn new(gpu: &Gpu, scene: Scene, graph: &CompiledGraph, size: (u32, u32), seed: u32) -> Result<Renderer, UserError> {
        check_size(gpu, size)?;
        let mut bvh = SceneBvh::default();
        let mut data = scene.pack();
        let bvh_stats = bvh.update(&mut data);
        check_scene_sizes(gpu, &data)?;
        // Sizes are checked above; a driver that still refuses (out of
        // memory for a large scene) gets a clear error, not a panic.
        let oom = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let invalid = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let buffers = SceneBuffers::new(&gpu.device, &gpu.queue, data);
        let refused = [pollster::block_on(invalid.pop()), pollster::block_on(oom.pop())];
        if let Some(e) = refused.into_iter().flatten().next() {
            return Err(UserError::new(format!("{} refused the scene's buffers: {e}; use fewer or smaller meshes", gpu.describe())));
        }
        let frame_buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&FrameGpu::zeroed_frame()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let executor = Executor::new(gpu, graph, &frame_buffer, &buffers, size)?;
        Ok(Renderer { scene, buffers, bvh, bvh_stats, executor, frame_buffer, size, seed, mask_threshold: DEFAULT_MASK_THRESHOLD, frame_index: 0, accum_count: 0, epoch_frames: 0, last: None })
    }

    /// Renders one frame at absolute time `time` seconds. When timed, waits
    /// for it and returns per-pass milliseconds.
    pub fn frame(&mut self, gpu: &Gpu, time: f32, timing: Timing) -> Result<Option<Vec<f64>>, UserError> {
        if self.scene.animate(time) {
            let mut data = self.scene.pack();
            self.bvh_stats = self.bvh.update(&mut data);
            self.buffers.update(&gpu.queue, data);
        }
        let camera = CameraGpu::new(&self.scene.camera, self.size);
        let epoch = self.buffers.epoch;
        let prev_camera = match self.last {
            Some((c, e)) => {
                if c != camera || e != epoch {
                    self.accum_count = 0;
                }
                if e != epoch {
                    self.epoch_frames = 0;
                }
                c
            }
            None => camera,
        };
        let data = &self.buffers.data;
        let frame = FrameGpu {
            camera,
            prev_camera,
            size: [self.size.0, self.size.1],
            frame_index: self.frame_index,
            accum_count: self.accum_count,
            time,
            seed: self.seed,
            scene_epoch: epoch,
            n_spheres: data.spheres.len() as u32,
            n_instances: data.instances.len() as u32,
            n_triangles: data.triangles.len() as u32,
            n_lights: data.lights.len() as u32,
            mask_threshold: self.mask_threshold,
            background: data.background,
            epoch_frames: self.epoch_frames,
        };
        gpu.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&frame));
        let ms = self.executor.run_frame(gpu, timing)?;
        self.last = Some((camera, epoch));
        self.frame_index = self.frame_index.wrapping_add(1);
        self.accum_count = self.accum_count.saturating_add(1);
        self.epoch_frames = self.epoch_frames.saturating_add(1);
        Ok(ms)
    }

    /// Drops all accumulated history (as a scene change would).
    pub fn reset_accumulation(&mut self) {
        self.accum_count = 0;
        self.epoch_frames = 0;
    }

    pub fn read_output(&self, gpu: &Gpu) -> Result<ImageF32, UserError> {
        self.executor.read_output(gpu)
    }
}

impl FrameGpu {
    fn zeroed_frame() -> FrameGpu {
        bytemuck::Zeroable::zeroed()
    }
}
