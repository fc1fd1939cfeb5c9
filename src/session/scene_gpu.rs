//! The scene on the GPU: the hecs world, its BVH and the scene buffers,
//! kept in step. Built whole (on load or reload, possibly on another
//! thread) and updated in place when things move.
//!
//! Camera-relative rendering: the world is f64; the GPU sees it relative to
//! `origin`, which starts at the world origin and jumps to a grid point near
//! the camera whenever the camera gets farther from it than a few scene
//! sizes (`update`). So a scene anywhere renders with the precision it has
//! at the origin, and a camera that stays near its scene never rebases.

use glam::DVec3;

use crate::bvh::scene::{BuildStats, SceneBvh};
use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::EngineResource;
use crate::scene::buffers::{scene_texture_rows, SceneBuffers, SCENE_TEXTURE_WIDTH};
use crate::scene::texture_arrays::TextureArrays;
use crate::scene::{Light, Scene, SceneData, Transform, FLAT_LIMIT};

/// The override in `shaders/shared/intersect.wgsl` the engine sets from the
/// scene (unless a graph sets it): whether rays test every primitive
/// instead of walking the BVH.
pub const FLAT_SCENE: &str = "FLAT_SCENE";
/// The override in `shaders/shared/intersect.wgsl` the engine sets from the
/// scene: whether traversal starts at the BLAS of the scene's only mesh.
pub const ONE_MESH: &str = "ONE_MESH";
/// The override in `shaders/shared/intersect.wgsl` the engine sets from the
/// scene: whether rays test the spheres in a loop before the BVH, which
/// then holds no sphere (`SceneData::spheres_apart`).
pub const SPHERES_APART: &str = "SPHERES_APART";
/// The overrides in `shaders/shared/flat.wgsl` the engine sets from the
/// scene: how many spheres and triangles a flat scene has (0 otherwise), so
/// the primary-ray sweep there tests exactly those.
pub const FLAT_SPHERES: &str = "FLAT_SPHERES";
/// With `FLAT_SPHERES`: how many triangles a flat scene has (0 otherwise).
pub const FLAT_TRIANGLES: &str = "FLAT_TRIANGLES";
/// The override in `shaders/shared/flat.wgsl` the engine sets from the
/// scene: a flat scene's triangles pair up as quads (`SceneData::flat_pairs`).
pub const FLAT_PAIRS: &str = "FLAT_PAIRS";
/// The override in `shaders/shared/flat.wgsl` the engine sets from the
/// scene: the sphere slot of the last light's own sphere in a flat scene
/// (`SceneData::last_light_sphere`; FLAT_LIMIT where there is none), which
/// trace_pair's shadow ray toward that light leaves out.
pub const FLAT_LAST_LIGHT_SPHERE: &str = "FLAT_LAST_LIGHT_SPHERE";

/// The scene on the GPU: the scene, its BVH and its buffers, kept in step
/// (see the module doc).
pub struct SceneGpu {
    /// The scene (world, f64), animated to the last `update`'s time; the
    /// session's camera is `scene.camera`.
    pub scene: Scene,
    /// The scene's two-level BVH.
    pub bvh: SceneBvh,
    /// The last BVH update (build on load, refit/TLAS rebuild on motion).
    pub bvh_stats: BuildStats,
    /// The scene arrays on the GPU (positions relative to `origin`).
    pub buffers: SceneBuffers,
    /// The scene's textures, by size class, and their sampler.
    pub textures: TextureArrays,
    /// How long `new` took, by stage.
    pub load: LoadTimes,
    /// The ray-offset scale of the scene as loaded (its size does not change
    /// when things move enough to matter: a power of two near half the
    /// extent).
    pub offset_scale: f32,
    /// What the GPU's positions are relative to (world, f64): a multiple of
    /// `offset_scale` in each component.
    pub origin: DVec3,
    /// The world bounds as loaded (what a probe grid spans: it stays put
    /// while lights and objects move).
    pub bounds: Option<(DVec3, DVec3)>,
    /// A pinned origin is never moved by `update` (set with `pin_origin`:
    /// tests that trace in world coordinates).
    pinned: bool,
}

/// Where `SceneGpu::new`'s time went, in milliseconds.
#[derive(Debug, Clone, Copy, Default)]
pub struct LoadTimes {
    /// Packing the scene's arrays and building its BVH.
    pub pack_and_bvh_ms: f64,
    /// Uploading the scene's arrays.
    pub buffers_ms: f64,
    /// Resampling the textures to their classes, their mips, and uploading.
    pub textures_ms: f64,
}

/// The camera may get this many offset scales (about half the scene's
/// extent each) away from the origin, in any axis, before the scene is
/// rebased on it: positions on the GPU then stay within a few extents of
/// the origin, where f32 keeps the precision the scene has at the world
/// origin. Cameras that stay near their scene never rebase.
pub const REBASE_SCALES: f64 = 8.0;

impl SceneGpu {
    /// Packs the scene, builds its BVH and uploads it, inside error scopes:
    /// a driver that refuses the buffers is a clear error.
    pub fn new(gpu: &Gpu, scene: Scene) -> Result<SceneGpu, UserError> {
        let start = std::time::Instant::now();
        let ms_since = |t: std::time::Instant| t.elapsed().as_secs_f64() * 1e3;
        let mut bvh = SceneBvh::default();
        let bounds = scene.bounds();
        let extent = bounds.map_or(0.0, |(lo, hi)| (hi - lo).max_element());
        let offset_scale = crate::bvh::offset::offset_scale(extent as f32);
        let origin = rebased_origin(DVec3::ZERO, scene.camera.position, offset_scale).unwrap_or(DVec3::ZERO);
        let mut data = scene.pack_at(origin);
        let bvh_stats = bvh.update(&mut data);
        check_scene_sizes(gpu, &data)?;
        let oom = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let invalid = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pack_and_bvh_ms = ms_since(start);
        let at = std::time::Instant::now();
        let buffers = SceneBuffers::new(&gpu.device, &gpu.queue, data);
        let buffers_ms = ms_since(at);
        let at = std::time::Instant::now();
        let textures = TextureArrays::new(&gpu.device, &gpu.queue, scene.textures());
        let load = LoadTimes { pack_and_bvh_ms, buffers_ms, textures_ms: ms_since(at) };
        // Both scopes are popped before any error returns: a scope left
        // pushed would swallow the device's later errors.
        let refused = [pollster::block_on(invalid.pop()), pollster::block_on(oom.pop())];
        if let Some(e) = refused.into_iter().flatten().next() {
            return Err(UserError::new(format!("{} refused the scene's buffers or textures: {e}; use fewer or smaller meshes and textures", gpu.describe())));
        }
        let textures = textures.map_err(|e| UserError::in_file(&scene.path, e))?;
        Ok(SceneGpu { scene, bvh, bvh_stats, buffers, textures, load, offset_scale, origin, bounds, pinned: false })
    }

    /// The graph's probe grid over the bounds as loaded, relative to the
    /// current origin (f64 until the subtraction, like every position).
    /// A flat scene's probe layer goes to the side of its lights (their
    /// mean position; the camera's where there are none).
    pub fn probe_grid(&self, probes: Option<crate::graph::desc::ProbesDesc>) -> Option<crate::probes::ProbeGrid> {
        let (p, (lo, hi)) = (probes?, self.bounds?);
        // (Every frame: a sum over the lights, no allocation. A directional
        // light has no place.)
        let (sum, n) = self
            .scene
            .world
            .query::<(&Transform, &Light)>()
            .iter()
            .filter(|(_, l)| !matches!(l, Light::Directional { .. }))
            .fold((DVec3::ZERO, 0.0), |(s, n), (t, _)| (s + t.translation, n + 1.0));
        let toward = if n > 0.0 { sum / n } else { self.scene.camera.position };
        crate::probes::ProbeGrid::over_bounds((lo - self.origin).as_vec3(), (hi - self.origin).as_vec3(), p.level, p.padding, (toward - self.origin).as_vec3())
    }

    /// Moves the scene to time `t` and, unless the origin is pinned,
    /// rebases it on a grid point near `camera` when the camera is too far
    /// from the current origin; packs, updates the BVH and uploads once for
    /// both. A rebase alone keeps the epoch (nothing moved, history stays).
    pub fn update(&mut self, queue: &wgpu::Queue, t: f32, camera: DVec3) {
        let moved = self.scene.animate(t);
        let rebase = if self.pinned { None } else { rebased_origin(self.origin, camera, self.offset_scale) };
        if let Some(origin) = rebase {
            self.origin = origin;
        }
        if moved || rebase.is_some() {
            let mut data = self.scene.pack_at(self.origin);
            self.bvh_stats = self.bvh.update(&mut data);
            if moved {
                self.buffers.update(queue, data);
            } else {
                self.buffers.rebase(queue, data);
            }
        }
    }

    /// Rebases on `origin` and keeps it there, wherever the camera goes.
    pub fn pin_origin(&mut self, queue: &wgpu::Queue, origin: DVec3) {
        self.pinned = true;
        self.rebase(queue, origin);
    }

    /// Re-expresses the GPU's positions relative to `origin` (refitting the
    /// BVH: every box moved by the same amount), keeping the epoch.
    pub fn rebase(&mut self, queue: &wgpu::Queue, origin: DVec3) {
        self.origin = origin;
        let mut data = self.scene.pack_at(origin);
        self.bvh_stats = self.bvh.update(&mut data);
        self.buffers.rebase(queue, data);
    }

    /// Override constants the engine gives every shader that declares them.
    pub fn engine_constants(&self) -> Vec<(&'static str, f64)> {
        let flag = |on: bool| f64::from(u8::from(on));
        let flat = self.buffers.is_flat();
        let count = |n: usize| if flat { n as f64 } else { 0.0 };
        vec![
            (FLAT_SCENE, flag(flat)),
            (ONE_MESH, flag(self.buffers.is_one_mesh())),
            (SPHERES_APART, flag(self.buffers.data.spheres_apart())),
            (FLAT_SPHERES, count(self.buffers.data.spheres.len())),
            (FLAT_TRIANGLES, count(self.buffers.data.triangles.len())),
            (FLAT_PAIRS, flag(flat && self.buffers.data.flat_pairs())),
            (FLAT_LAST_LIGHT_SPHERE, self.buffers.data.last_light_sphere().filter(|_| flat).unwrap_or(FLAT_LIMIT) as f64),
        ]
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
            EngineResource::Materials => wgpu::BindingResource::TextureView(b.materials.view()),
            EngineResource::Lights => wgpu::BindingResource::TextureView(b.lights.view()),
            EngineResource::Origins => wgpu::BindingResource::TextureView(b.origins.view()),
            EngineResource::Flat => b.flat.as_entire_binding(),
            EngineResource::Entries => b.entries.as_entire_binding(),
            EngineResource::Tiles => wgpu::BindingResource::TextureView(b.tiles.view()),
            EngineResource::BlueNoise => wgpu::BindingResource::TextureView(b.blue_noise.view()),
            EngineResource::Uvs => wgpu::BindingResource::TextureView(b.uvs.view()),
            EngineResource::MaterialTextures => wgpu::BindingResource::TextureView(b.material_textures.view()),
            EngineResource::Images256 => wgpu::BindingResource::TextureView(&self.textures.views[0]),
            EngineResource::Images512 => wgpu::BindingResource::TextureView(&self.textures.views[1]),
            EngineResource::Images1024 => wgpu::BindingResource::TextureView(&self.textures.views[2]),
            EngineResource::Images2048 => wgpu::BindingResource::TextureView(&self.textures.views[3]),
            EngineResource::Sampler => wgpu::BindingResource::Sampler(&self.textures.sampler),
            EngineResource::Environment => wgpu::BindingResource::TextureView(b.environment.view()),
        }
    }
}

/// The origin to rebase on when `camera` is more than `REBASE_SCALES`
/// offset scales from `origin` in some axis (`None`: keep `origin`): the
/// camera rounded to a multiple of the offset scale, so rebased positions
/// are exact differences of nearby grid values.
pub fn rebased_origin(origin: DVec3, camera: DVec3, offset_scale: f32) -> Option<DVec3> {
    let grid = f64::from(offset_scale);
    if !camera.is_finite() || (camera - origin).abs().max_element() <= REBASE_SCALES * grid {
        return None;
    }
    Some((camera / grid).round() * grid)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_origin_follows_a_far_camera_on_a_grid() {
        // Near the origin (within 8 offset scales): no rebase.
        assert_eq!(rebased_origin(DVec3::ZERO, DVec3::new(0.0, 0.0, 3.4), 1.0), None);
        assert_eq!(rebased_origin(DVec3::ZERO, DVec3::new(-8.0, 8.0, 0.0), 1.0), None);
        // Farther: the camera rounded to the grid.
        assert_eq!(rebased_origin(DVec3::ZERO, DVec3::new(1e7 + 0.3, -2.7, 3.4), 1.0), Some(DVec3::new(1e7, -3.0, 3.0)));
        let grid = 1.0 / 1024.0;
        let o = rebased_origin(DVec3::ZERO, DVec3::new(0.1, 0.0, 0.0), grid).expect("rebases");
        assert_eq!((o.x / f64::from(grid)).fract(), 0.0);
        assert!((o.x - 0.1).abs() <= f64::from(grid) / 2.0);
        // Measured from the current origin, not the world's.
        assert_eq!(rebased_origin(o, DVec3::new(0.1 + 7.0 * f64::from(grid), 0.0, 0.0), grid), None);
        assert_eq!(rebased_origin(DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0), 1.0), None);
    }
}
