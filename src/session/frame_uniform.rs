//! The `frame` uniform: camera, previous camera, frame counters and scene
//! counts. Mirrors `struct Frame` in `shaders/shared/frame.wgsl`.

use bytemuck::{Pod, Zeroable};
use glam::{DVec3, Vec3};

use crate::bvh::tiles::PixelCamera;
use crate::scene::Camera;

/// A camera as the shaders see it (`struct Camera` in frame.wgsl): an
/// orthonormal basis and the position relative to the scene's origin.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct CameraGpu {
    /// Position, relative to the scene's rebasing origin.
    pub origin: [f32; 3],
    /// tan(vfov / 2)
    pub tan_half_fov: f32,
    /// Unit vector to the image's right.
    pub right: [f32; 3],
    /// width / height
    pub aspect: f32,
    /// Unit vector to the image's top.
    pub up: [f32; 3],
    /// Padding (WGSL layout).
    pub _pad0: f32,
    /// Unit view direction.
    pub forward: [f32; 3],
    /// Padding (WGSL layout).
    pub _pad1: f32,
}

impl CameraGpu {
    /// An orthonormal camera basis (right-handed, looking along `forward`),
    /// its position relative to `origin` (the scene's rebasing origin).
    pub fn new(c: &Camera, origin: DVec3, size: (u32, u32)) -> CameraGpu {
        let forward = (c.target - c.position).try_normalize().map_or(Vec3::NEG_Z, |f| f.as_vec3());
        let right = forward.cross(c.up).try_normalize().unwrap_or(Vec3::X);
        let up = right.cross(forward);
        CameraGpu {
            origin: (c.position - origin).as_vec3().to_array(),
            tan_half_fov: (c.vfov_deg.to_radians() * 0.5).tan(),
            right: right.to_array(),
            aspect: size.0 as f32 / size.1.max(1) as f32,
            up: up.to_array(),
            _pad0: 0.0,
            forward: forward.to_array(),
            _pad1: 0.0,
        }
    }

    /// The primary ray direction through pixel `(x, y)` at sub-pixel
    /// offset `(jx, jy)` in [0, 1): the same formula as `camera_ray` in WGSL.
    pub fn ray_dir(&self, x: f32, y: f32, jx: f32, jy: f32, size: (u32, u32)) -> Vec3 {
        self.pixel_camera(size).dir(x + jx, y + jy)
    }

    /// What maps a pixel of a `size` image to its ray (the screen tiles'
    /// frusta are made of it: `crate::bvh::tiles`).
    pub fn pixel_camera(&self, size: (u32, u32)) -> PixelCamera {
        PixelCamera {
            origin: Vec3::from(self.origin),
            forward: Vec3::from(self.forward),
            right: Vec3::from(self.right),
            up: Vec3::from(self.up),
            tan_half_fov: self.tan_half_fov,
            aspect: self.aspect,
            size,
        }
    }
}

/// The `frame` uniform, written once per frame (`struct Frame` in
/// `shaders/shared/frame.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FrameGpu {
    /// This frame's camera.
    pub camera: CameraGpu,
    /// The last frame's camera, relative to this frame's origin (for
    /// reprojection); the same as `camera` on the first frame and after
    /// `Session::restart`.
    pub prev_camera: CameraGpu,
    /// Render size in pixels, (width, height).
    pub size: [u32; 2],
    /// Frames rendered since start (drives per-frame randomness).
    pub frame_index: u32,
    /// Frames already in the accumulation history (0 = reset).
    pub accum_count: u32,
    /// Scene time, seconds.
    pub time: f32,
    /// The session's random seed.
    pub seed: u32,
    /// Bumped whenever anything visible in the scene changed
    /// (`SceneBuffers::epoch`).
    pub scene_epoch: u32,
    /// Number of spheres.
    pub n_spheres: u32,
    /// Number of TLAS instances.
    pub n_instances: u32,
    /// Number of triangles, over every mesh instance.
    pub n_triangles: u32,
    /// Number of lights.
    pub n_lights: u32,
    /// The noise-mask threshold (PID output when a target is set).
    pub mask_threshold: f32,
    /// Radiance of rays that leave the scene, linear RGB.
    pub background: [f32; 3],
    /// Frames since the scene (lights, objects) last changed; 0 = every
    /// pixel's history is stale. Camera motion does not reset it.
    pub epoch_frames: u32,
    /// Always 1.0; shaders cannot know it at compile time, so a product
    /// with it keeps compensated arithmetic from being folded away.
    pub exact_one: f32,
    /// The scene's origin-rebasing grid (`bvh::offset::offset_scale`; ray
    /// offsets no longer use it).
    pub offset_scale: f32,
    /// Frames since history was last dropped (a new session, a restart or
    /// `reset_accumulation`): 0 = no history texture holds anything yet.
    /// Neither camera motion nor scene changes reset it, so a denoiser
    /// that judges staleness itself keeps its history while lights move.
    pub history_frames: u32,
    /// What camera rays' cones are narrowed by (`cone_scale`): texture
    /// footprints shrink as samples add up, so a converged image is not
    /// blurred twice (by the level of detail and by the pixel's samples).
    pub cone_scale: f32,
    /// The graph's probe grid (see `probes::ProbeGrid`), relative to the
    /// scene's origin like every position: probe (0, 0, 0), the spacing,
    /// probes per axis (0 for a graph without probes).
    pub probe_origin: [f32; 3],
    /// Probes per axis (0: no probes).
    pub probe_n: u32,
    /// Distance between neighbouring probes, per axis.
    pub probe_spacing: [f32; 3],
    /// Last frame's `cone_scale` (a pass that traces last frame's paths
    /// again reads textures as they were read then).
    pub prev_cone_scale: f32,
    /// How many clusters the lights are in (`scene::light_clusters`; 0:
    /// few lights, each weighed at every choice).
    pub n_light_clusters: u32,
    /// (The uniform's size a multiple of 16 bytes.)
    pub _pad: [u32; 3],
}

/// The factor camera-ray cones are narrowed by once `accumulated` samples
/// a pixel are in the history: 1 / sqrt(accumulated + 1), no less than 1/8
/// (pbrt-v4 scales its ray differentials alike). Texture levels are chosen
/// for one sample's footprint; the pixel's jittered samples already
/// average over the pixel, so a converged image wants finer levels.
pub fn cone_scale(accumulated: u32) -> f32 {
    (1.0 / ((accumulated as f32) + 1.0).sqrt()).max(0.125)
}

#[cfg(test)]
mod tests {
    use super::cone_scale;

    #[test]
    fn cones_narrow_with_the_samples_taken_down_to_an_eighth() {
        assert_eq!(cone_scale(0), 1.0);
        assert_eq!(cone_scale(3), 0.5);
        assert_eq!(cone_scale(15), 0.25);
        assert_eq!(cone_scale(63), 0.125);
        assert_eq!(cone_scale(u32::MAX), 0.125);
        assert!((1..100).all(|n| cone_scale(n) <= cone_scale(n - 1)), "never widens");
    }
}
