//! The loaded scene: an hecs world of entities, its components, the local
//! mesh store, and the `animate` system.

use std::path::PathBuf;

use glam::{DVec3, Quat, Vec2, Vec3, Vec4};

use super::features::SceneFeatures;
use super::gpu_types::MaterialGpu;

/// The viewpoint. `vfov_deg` is the full vertical angle. Positions are
/// f64, as every position in the world is: the GPU sees them rebased on an
/// origin near the camera (`SceneGpu::origin`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: DVec3,
    /// The point looked at.
    pub target: DVec3,
    /// Up direction (need not be unit, nor orthogonal to the view).
    pub up: Vec3,
    /// Full vertical field of view, degrees.
    pub vfov_deg: f32,
}

/// A loaded scene. Entities carry `ObjectId` (objects first, in file order,
/// then lights), `Transform`, and one of `SphereShape`, `MeshShape` or
/// `Light`; movers also carry `Motion` and `BasePosition`.
pub struct Scene {
    /// The entities.
    pub world: hecs::World,
    /// The viewpoint as loaded.
    pub camera: Camera,
    /// Radiance of rays that leave the scene, linear RGB (a scene with an
    /// environment light has none).
    pub background: Vec3,
    /// The environment light, if any.
    pub environment: Option<super::environment::Environment>,
    /// Its texels (`Environment::texels`), made once: every pack shares them.
    pub(super) environment_texels: std::sync::Arc<Vec<[u32; 4]>>,
    /// What the scene holds (which passes and code it needs).
    pub features: SceneFeatures,
    /// The scene file (used in messages and to resolve mesh paths).
    pub path: PathBuf,
    /// The perspective cameras of the scene's glTF files, placed (what
    /// `--camera N` picks from; `use_camera`).
    pub cameras: Vec<Camera>,
    /// The OBJ and glTF files, images and environment map the scene
    /// loaded (hot reload watches them).
    pub mesh_files: Vec<PathBuf>,
    /// Local-space triangles, indexed by `MeshShape::mesh`.
    pub(super) meshes: Vec<MeshData>,
    /// Every material, indexed by `MaterialId` and the triangles' `material`.
    pub(super) materials: Vec<MaterialGpu>,
    /// The textures each material samples, by material id (empty when no
    /// material has any).
    pub(super) material_textures: Vec<MaterialTextures>,
    /// The images those textures read (sRGB RGBA8).
    pub(super) textures: Vec<TextureImage>,
}

/// Which images a material's textures read, and how.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MaterialTextures {
    /// Base colour (multiplies the albedo), sRGB.
    pub base_color: Option<TextureSlot>,
    /// Emission (multiplies the emission), sRGB.
    pub emissive: Option<TextureSlot>,
    /// alphaMode MASK: (cutoff, the base colour factor's alpha); the
    /// surface is there where factor x texture alpha >= cutoff.
    pub alpha_mask: Option<(f32, f32)>,
    /// Metallic-roughness (green: roughness, blue: metalness; they multiply
    /// the factors), linear.
    pub metallic_roughness: Option<TextureSlot>,
    /// Tangent-space normals, linear, with glTF's `scale` (x and y
    /// multiplied by it).
    pub normal: Option<(TextureSlot, f32)>,
}

/// One texture of a material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureSlot {
    /// Index into the scene's textures.
    pub texture: usize,
    /// (s, t) wrap modes: 0 repeat, 1 clamp to edge, 2 mirrored repeat.
    pub wrap: [u32; 2],
    /// uv' = (row 0 . (u, v, 1), row 1 . (u, v, 1)).
    pub transform: [[f32; 3]; 2],
}

/// An image a texture reads: `width x height` RGBA8 texels, rows top
/// first; sRGB colour, or data (`linear`: normals, metalness and
/// roughness), which is filtered as it is.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureImage {
    /// Texels across.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width x height x 4` bytes.
    pub rgba: Vec<u8>,
    /// Data rather than sRGB colour.
    pub linear: bool,
}

impl TextureImage {
    /// Decodes a PNG or JPEG file's bytes.
    pub fn decode(bytes: &[u8]) -> Result<TextureImage, String> {
        let decoded = image::load_from_memory(bytes).map_err(|e| format!("cannot decode the image (glint reads PNG and JPEG): {e}"))?;
        let rgba = decoded.to_rgba8();
        let (width, height) = rgba.dimensions();
        if width == 0 || height == 0 {
            return Err(format!("the image is empty ({width}x{height})"));
        }
        Ok(TextureImage { width, height, rgba: rgba.into_raw(), linear: false })
    }
}

impl Scene {
    /// Advance `Motion` components to absolute time `t` seconds (not a
    /// delta). Returns true if anything moved.
    pub fn animate(&mut self, t: f32) -> bool {
        animate(&mut self.world, t)
    }

    /// The local-space mesh store (for building one BLAS per mesh).
    pub fn meshes(&self) -> &[MeshData] {
        &self.meshes
    }

    /// Views from `cameras[n]` (the scene's glTF cameras, 0 the first),
    /// or says how many there are.
    pub fn use_camera(&mut self, n: usize) -> Result<(), crate::error::UserError> {
        match self.cameras.get(n) {
            Some(c) => {
                self.camera = *c;
                Ok(())
            }
            None => Err(crate::error::UserError::in_file(
                &self.path,
                format!("--camera {n}: the scene's glTF files have {} perspective camera(s){}", self.cameras.len(), if self.cameras.is_empty() { "" } else { " (numbered from 0)" }),
            )),
        }
    }

    /// The textures of each material, by material id (empty: none has any).
    pub fn material_textures(&self) -> &[MaterialTextures] {
        &self.material_textures
    }

    /// The images the materials' textures read.
    pub fn textures(&self) -> &[TextureImage] {
        &self.textures
    }

    /// Every material of the scene, indexed by material id.
    pub fn materials(&self) -> &[MaterialGpu] {
        &self.materials
    }
}

/// Local-space triangles of one mesh: an OBJ file or a quad.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshData {
    /// Local-space triangles, in file order.
    pub triangles: Vec<LocalTriangle>,
}

/// Positions, unit shading normals, texture coordinates and material id
/// of one triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalTriangle {
    /// Vertex positions.
    pub p: [Vec3; 3],
    /// Unit shading normals at the vertices.
    pub n: [Vec3; 3],
    /// Texture coordinates at the vertices (zero where the mesh has none).
    pub uv: [Vec2; 3],
    /// Tangents at the vertices (xyz unit, w the bitangent's sign), for
    /// normal textures; zero where the mesh has none (the triangle's uvs
    /// then give the frame).
    pub tangent: [Vec4; 3],
    /// Vertex colours, multiplying the base colour (one where the mesh has
    /// none).
    pub color: [Vec3; 3],
    /// Index into the scene's materials.
    pub material: u32,
}

impl LocalTriangle {
    /// A triangle without tangents or vertex colours.
    pub fn plain(p: [Vec3; 3], n: [Vec3; 3], uv: [Vec2; 3], material: u32) -> Self {
        LocalTriangle { p, n, uv, tangent: [Vec4::ZERO; 3], color: [Vec3::ONE; 3], material }
    }
}

/// Placement of an entity: world = translation + rotation * (scale * local).
/// The translation is f64 (a scene may sit far from the origin); local
/// coordinates are f32, relative to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// World position of the local origin.
    pub translation: DVec3,
    /// Rotation applied after the scale.
    pub rotation: Quat,
    /// Uniform, so normals only need the rotation.
    pub scale: f32,
}

impl Transform {
    /// No translation, rotation or scaling.
    pub const IDENTITY: Transform = Transform {
        translation: DVec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: 1.0,
    };

    /// A pure translation.
    pub fn from_translation(translation: DVec3) -> Self {
        Transform {
            translation,
            ..Transform::IDENTITY
        }
    }

    /// The world position of local point `p`, in f64.
    pub fn point(&self, p: Vec3) -> DVec3 {
        self.translation + self.rotation.as_dquat() * (f64::from(self.scale) * p.as_dvec3())
    }

    /// The position of local point `p` relative to `origin`, rounded to f32
    /// once (what the GPU sees, `Scene::pack_at`).
    pub fn point_from(&self, origin: DVec3, p: Vec3) -> Vec3 {
        ((self.translation - origin) + self.rotation.as_dquat() * (f64::from(self.scale) * p.as_dvec3())).as_vec3()
    }

    /// Local normal `n` rotated into the world, unit length (`n` itself if that fails).
    pub fn normal(&self, n: Vec3) -> Vec3 {
        (self.rotation * n).normalize_or(n)
    }
}

/// Position in the `objects` list, then lights continue the numbering.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ObjectId(pub u32);

/// Position in the `lights` list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LightIndex(pub u32);

/// A sphere object centred on its `Transform::translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereShape {
    /// Radius (world units).
    pub radius: f32,
}

/// A mesh instance: an index into `Scene::meshes()`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshShape {
    /// Index into `Scene::meshes()`.
    pub mesh: usize,
}

/// Material of a sphere (or of a sphere light: its emissive material).
/// Mesh triangles carry their own material ids.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaterialId(pub u32);

/// A light at its `Transform::translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Radiance L, uniform over the sphere.
    Sphere {
        /// Radius (world units).
        radius: f32,
        /// Radiance L, linear RGB.
        radiance: Vec3,
    },
    /// Intensity I (W/sr).
    Point {
        /// Intensity I (W/sr), linear RGB.
        intensity: Vec3,
    },
    /// Light from infinitely far away (a sun): irradiance E on a surface
    /// facing it, arriving along `direction` (unit, the way it travels).
    /// Its entity's position means nothing.
    Directional {
        /// Irradiance E (W/m^2) on a surface facing the light, linear RGB.
        irradiance: Vec3,
        /// The way the light travels (unit).
        direction: Vec3,
    },
}

/// A point light's cone (a spot light): full intensity within
/// `cos_inner` of `direction`, none beyond `cos_outer`, and between them
/// glTF's smooth step (KHR_lights_punctual): clamp((cos - cos_outer) /
/// (cos_inner - cos_outer), 0, 1) squared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotCone {
    /// Where the cone points (unit, world).
    pub direction: Vec3,
    /// Cosine of the inner angle.
    pub cos_inner: f32,
    /// Cosine of the outer angle (below `cos_inner`).
    pub cos_outer: f32,
}

impl SpotCone {
    /// (axis, offset) as the GPU takes them: the factor is clamp(axis . d
    /// + offset, 0, 1)^2 for the unit direction d from the light.
    pub fn gpu(&self) -> [f32; 4] {
        let scale = 1.0 / (self.cos_inner - self.cos_outer).max(1e-3);
        let a = self.direction * scale;
        [a.x, a.y, a.z, -self.cos_outer * scale]
    }
}

/// Where `Linear` motion starts (the position written in the file).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BasePosition(pub DVec3);

/// How an entity's translation depends on time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// `center + radius * (cos φ u + sin φ v)`, φ = 2π t / period + phase;
    /// `u`, `v` are orthonormal and `u × v` is the axis (counter-clockwise
    /// seen from the axis tip). The position written in the file is not used.
    Orbit {
        /// The orbit's centre.
        center: DVec3,
        /// Unit direction at φ = 0.
        u: DVec3,
        /// Unit direction at φ = π/2.
        v: DVec3,
        /// Orbit radius (world units).
        radius: f32,
        /// Seconds per turn.
        period_s: f32,
        /// Angle at t = 0, radians.
        phase_rad: f32,
    },
    /// `base + velocity * t`.
    Linear {
        /// World units per second.
        velocity: DVec3,
    },
}

impl Motion {
    /// An orbit around `axis` (any length but zero; `None` when zero or not finite).
    pub fn orbit(
        center: DVec3,
        axis: Vec3,
        radius: f32,
        period_s: f32,
        phase_deg: f32,
    ) -> Option<Motion> {
        let n = axis.as_dvec3().try_normalize()?;
        let (u, _) = n.any_orthonormal_pair();
        let v = n.cross(u);
        Some(Motion::Orbit {
            center,
            u,
            v,
            radius,
            period_s,
            phase_rad: phase_deg.to_radians(),
        })
    }

    /// Position at absolute time `t`.
    pub fn position(&self, base: DVec3, t: f32) -> DVec3 {
        match *self {
            Motion::Orbit {
                center,
                u,
                v,
                radius,
                period_s,
                phase_rad,
            } => {
                // Wrap the time first so that large t keeps its precision.
                let turns = (t / period_s).rem_euclid(1.0);
                let phi = f64::from(std::f32::consts::TAU * turns + phase_rad);
                center + f64::from(radius) * (phi.cos() * u + phi.sin() * v)
            }
            Motion::Linear { velocity } => base + velocity * f64::from(t),
        }
    }
}

/// The animate system: moves every `Motion` entity to time `t`. Returns true
/// if any translation changed. A non-finite `t` moves nothing.
pub fn animate(world: &mut hecs::World, t: f32) -> bool {
    if !t.is_finite() {
        return false;
    }
    let mut moved = false;
    for (transform, motion, base) in world.query_mut::<(&mut Transform, &Motion, &BasePosition)>() {
        let p = motion.position(base.0, t);
        if p.is_finite() && p != transform.translation {
            transform.translation = p;
            moved = true;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_basis_is_right_handed() {
        for axis in [Vec3::Y, Vec3::X, -Vec3::Z, Vec3::new(1.0, 2.0, -3.0)] {
            let Some(Motion::Orbit { u, v, .. }) = Motion::orbit(DVec3::ZERO, axis, 1.0, 1.0, 0.0)
            else {
                panic!("orbit")
            };
            let axis = axis.as_dvec3();
            assert!(u.dot(axis).abs() < 1e-12 && v.dot(axis).abs() < 1e-12);
            assert!((u.cross(v) - axis.normalize()).length() < 1e-12);
        }
        assert!(Motion::orbit(DVec3::ZERO, Vec3::ZERO, 1.0, 1.0, 0.0).is_none());
        assert!(Motion::orbit(DVec3::ZERO, Vec3::NAN, 1.0, 1.0, 0.0).is_none());
    }

    #[test]
    fn orbit_position_is_periodic() {
        let m = Motion::orbit(DVec3::new(0.0, 1.0, 0.0), Vec3::Y, 0.5, 4.0, 90.0).unwrap();
        let a = m.position(DVec3::ZERO, 1.0);
        let b = m.position(DVec3::ZERO, 5.0);
        let c = m.position(DVec3::ZERO, 4001.0);
        assert!((a - b).length() < 1e-5 && (a - c).length() < 1e-4);
        assert!(((a - DVec3::Y).length() - 0.5).abs() < 1e-5);
    }

    #[test]
    fn far_orbits_keep_their_precision() {
        // At 1e7 an f32 position has a resolution of 1: the orbit is f64.
        let centre = DVec3::new(1e7, -3e6, 7e6);
        let m = Motion::orbit(centre, Vec3::Y, 0.25, 4.0, 0.0).unwrap();
        for t in [0.0, 0.3, 1.7] {
            let r = (m.position(DVec3::ZERO, t) - centre).length();
            assert!((r - 0.25).abs() < 1e-7, "{r}");
        }
    }

    #[test]
    fn transform_applies_scale_rotation_translation() {
        let t = Transform {
            translation: DVec3::new(1.0, 0.0, 0.0),
            rotation: Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
            scale: 2.0,
        };
        // Rotating +x by 90° about +y gives -z.
        assert!((t.point(Vec3::X) - DVec3::new(1.0, 0.0, -2.0)).length() < 1e-6);
        let far = Transform { translation: DVec3::new(1e7 + 0.5, 0.0, 0.0), ..t };
        let rebased = far.point_from(DVec3::new(1e7, 0.0, 0.0), Vec3::X);
        assert!((rebased - Vec3::new(0.5, 0.0, -2.0)).length() < 1e-6, "{rebased}");
        assert!((t.normal(Vec3::X) - Vec3::NEG_Z).length() < 1e-6);
    }
}
