//! The scene on the GPU: the hecs world, its BVH and the scene buffers,
//! kept in step. Built whole (on load or reload, possibly on another
//! thread) and updated in place when things move.

use crate::bvh::scene::{BuildStats, SceneBvh};
use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::EngineResource;
use crate::scene::buffers::{scene_texture_rows, SceneBuffers, SCENE_TEXTURE_WIDTH};
use crate::scene::{Scene, SceneData};

/// The override in `shaders/shared/intersect.wgsl` the engine sets from the
/// scene (unless a graph sets it): whether rays test every primitive
/// instead of walking the BVH.
pub const FLAT_SCENE: &str = "FLAT_SCENE";

pub struct SceneGpu {
    pub scene: Scene,
    pub bvh: SceneBvh,
    /// The last BVH update (build on load, refit/TLAS rebuild on motion).
    pub bvh_stats: BuildStats,
    pub buffers: SceneBuffers,
    /// The ray-offset scale of the scene as loaded (its size does not change
    /// when things move enough to matter: a power of two near half the
    /// extent).
    pub offset_scale: f32,
}

impl SceneGpu {
    /// Packs the scene, builds its BVH and uploads it, inside error scopes:
    /// a driver that refuses the buffers is a clear error.
    pub fn new(gpu: &Gpu, scene: Scene) -> Result<SceneGpu, UserError> {
        let mut bvh = SceneBvh::default();
        let mut data = scene.pack();
        let offset_scale = crate::bvh::offset::offset_scale(extent(&data));
        let bvh_stats = bvh.update(&mut data);
        check_scene_sizes(gpu, &data)?;
        let oom = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let invalid = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let buffers = SceneBuffers::new(&gpu.device, &gpu.queue, data);
        let refused = [pollster::block_on(invalid.pop()), pollster::block_on(oom.pop())];
        if let Some(e) = refused.into_iter().flatten().next() {
            return Err(UserError::new(format!("{} refused the scene's buffers: {e}; use fewer or smaller meshes", gpu.describe())));
        }
        Ok(SceneGpu { scene, bvh, bvh_stats, buffers, offset_scale })
    }

    /// Moves the scene to time `t` and uploads what changed.
    pub fn animate(&mut self, queue: &wgpu::Queue, t: f32) {
        if self.scene.animate(t) {
            let mut data = self.scene.pack();
            self.bvh_stats = self.bvh.update(&mut data);
            self.buffers.update(queue, data);
        }
    }

    /// Override constants the engine gives every shader that declares them.
    pub fn engine_constants(&self) -> Vec<(&'static str, f64)> {
        vec![(FLAT_SCENE, f64::from(u8::from(self.buffers.is_flat())))]
    }

    /// What a scene engine resource binds to; the frame uniform is the
    /// session's.
    pub fn binding<'a>(&'a self, e: EngineResource, frame: &'a wgpu::Buffer) -> wgpu::BindingResource<'a> {
        let b = &self.buffers;
        match e {
            EngineResource::Frame => frame.as_entire_binding(),
            EngineResource::Spheres => wgpu::BindingResource::TextureView(b.spheres.view()),
            EngineResource::Geometry => wgpu::BindingResource::TextureView(b.geometry.view()),
            EngineResource::Normals => wgpu::BindingResource::TextureView(b.normals.view()),
            EngineResource::Instances => wgpu::BindingResource::TextureView(b.instances.view()),
            EngineResource::Meshes => b.meshes.as_entire_binding(),
            EngineResource::Materials => b.materials.as_entire_binding(),
            EngineResource::Lights => b.lights.as_entire_binding(),
        }
    }
}

/// The longest side of the bounds of every triangle and sphere (0 for an
/// empty scene).
fn extent(data: &SceneData) -> f32 {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    let mut grow = |p: [f32; 3], r: f32| {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c] - r);
            hi[c] = hi[c].max(p[c] + r);
        }
    };
    for t in &data.triangles {
        for p in [t.p0, t.p1, t.p2] {
            grow(p, 0.0);
        }
    }
    for s in &data.spheres {
        grow(s.center, s.radius);
    }
    (0..3).map(|c| hi[c] - lo[c]).filter(|e| e.is_finite()).fold(0.0, f32::max)
}

/// Every scene array must fit its binding on this adapter: the texture
/// arrays within the largest texture side in rows, the storage arrays
/// within one storage binding.
fn check_scene_sizes(gpu: &Gpu, data: &SceneData) -> Result<(), UserError> {
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
