//! Plain-old-data records uploaded to the GPU. Each mirrors a struct in
//! `shaders/shared/scene.wgsl` byte for byte (a test checks the layouts
//! against naga's reflection of that file).

use bytemuck::{Pod, Zeroable};

/// `struct Sphere` (32 bytes). `light` is the index into the light array
/// for sphere lights, -1 otherwise.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct SphereGpu {
    /// Centre, relative to the packing origin.
    pub center: [f32; 3],
    /// Radius (world units).
    pub radius: f32,
    /// Index into the material array.
    pub material: u32,
    /// Index into the light array for a sphere light, else -1.
    pub light: i32,
    /// The `ObjectId` it belongs to.
    pub object: u32,
    /// Padding; zero.
    pub _pad: u32,
}

/// `struct Triangle` (48 bytes): world-space vertices, what intersection
/// reads (three texels of the `scene_geometry` texture). Shading normals
/// live apart (`TriangleNormalsGpu`), so what traversal touches stays small.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct TriangleGpu {
    /// First vertex, relative to the packing origin.
    pub p0: [f32; 3],
    /// Index into the material array.
    pub material: u32,
    /// Second vertex.
    pub p1: [f32; 3],
    /// The `ObjectId` of its mesh instance.
    pub object: u32,
    /// Third vertex.
    pub p2: [f32; 3],
    /// Padding; zero.
    pub _pad0: u32,
}

/// `struct TriangleNormals` (48 bytes): the shading normals of the triangle
/// with the same index.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct TriangleNormalsGpu {
    /// Unit shading normal at `p0`.
    pub n0: [f32; 3],
    /// Padding; zero.
    pub _pad1: f32,
    /// Unit shading normal at `p1`.
    pub n1: [f32; 3],
    /// Padding; zero.
    pub _pad2: f32,
    /// Unit shading normal at `p2`.
    pub n2: [f32; 3],
    /// Padding; zero.
    pub _pad3: f32,
}

/// `struct Mesh` (32 bytes): a world-space bounding box over the triangles
/// `first .. first + count` of the triangle array.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MeshGpu {
    /// The box's minimum corner.
    pub bmin: [f32; 3],
    /// Index of its first triangle.
    pub first: u32,
    /// The box's maximum corner.
    pub bmax: [f32; 3],
    /// Number of triangles.
    pub count: u32,
}

/// `MaterialGpu::model` of the thesis material: Lambert diffuse plus a
/// specular lobe taken with probability `specular`.
pub const MATERIAL_THESIS: u32 = 0;
/// `MaterialGpu::model` of glTF's metallic-roughness material (src/brdf.rs):
/// `albedo` is the base colour, `roughness` glTF's perceptual roughness.
pub const MATERIAL_METALLIC_ROUGHNESS: u32 = 1;

/// `struct Material` (48 bytes, three texels).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MaterialGpu {
    /// Diffuse reflectance (the base colour), linear RGB in 0..1.
    pub albedo: [f32; 3],
    /// Probability of the specular lobe, 0..1. Metallic-roughness: the
    /// stand-in the passes that shade the thesis lobes only (the hybrid
    /// graphs' lights and reflections) use, F0's share: metallic + 0.04
    /// (1 - metallic).
    pub specular: f32,
    /// Emitted radiance, linear RGB.
    pub emission: [f32; 3],
    /// Thesis: how far the specular lobe leans from the mirror direction
    /// (0) toward a diffuse one (1). Metallic-roughness: GGX's alpha is
    /// its square.
    pub roughness: f32,
    /// Metalness, 0..1 (metallic-roughness only).
    pub metallic: f32,
    /// `MATERIAL_THESIS` or `MATERIAL_METALLIC_ROUGHNESS`.
    pub model: u32,
    /// `MATERIAL_SINGLE_SIDED` or 0.
    pub flags: u32,
    /// Padding to the third texel's end.
    pub _pad: u32,
}

/// `MaterialGpu::flags`: glTF's `doubleSided: false`. Rays meet only the
/// front (counter-clockwise) face of its triangles; from behind they pass
/// through (shaders/shared/scene.wgsl, `face_passes`).
pub const MATERIAL_SINGLE_SIDED: u32 = 1;

impl MaterialGpu {
    /// A thesis material.
    pub const fn thesis(albedo: [f32; 3], specular: f32, emission: [f32; 3], roughness: f32) -> MaterialGpu {
        MaterialGpu { albedo, specular, emission, roughness, metallic: 0.0, model: MATERIAL_THESIS, flags: 0, _pad: 0 }
    }

    /// A metallic-roughness material.
    pub const fn metal_rough(base: [f32; 3], metallic: f32, roughness: f32, emission: [f32; 3]) -> MaterialGpu {
        let specular = metallic + crate::brdf::DIELECTRIC_F0 * (1.0 - metallic);
        MaterialGpu { albedo: base, specular, emission, roughness, metallic, model: MATERIAL_METALLIC_ROUGHNESS, flags: 0, _pad: 0 }
    }

    /// Whether it is a metallic-roughness material.
    pub fn is_metal_rough(&self) -> bool {
        self.model == MATERIAL_METALLIC_ROUGHNESS
    }

    /// Whether it is a coat: a specular share between 0 and 1 over a
    /// diffuse base (the test shared/path.wgsl makes before taking both
    /// lobes, SPLIT_LOBES).
    pub fn is_coat(&self) -> bool {
        self.specular > 0.0 && self.specular < 1.0 && !self.is_metal_rough()
    }

    /// Whether rays meet only its triangles' front faces.
    pub fn is_single_sided(&self) -> bool {
        self.flags & MATERIAL_SINGLE_SIDED != 0
    }
}

/// `LightGpu::kind` of a point light.
pub const LIGHT_POINT: u32 = 0;
/// `LightGpu::kind` of a sphere light.
pub const LIGHT_SPHERE: u32 = 1;
/// `Light::kind` of a directional light: `position` is the unit direction
/// toward it, `color` its irradiance.
pub const LIGHT_DIRECTIONAL: u32 = 2;
/// `Light::kind` of the environment light (`environment::Environment`):
/// `position` is (width, height, rotation) of its map in
/// `scene_environment`; always the last light.
pub const LIGHT_ENVIRONMENT: u32 = 3;

/// `struct Light` (32 bytes). Point light: `color` is intensity I (W/sr),
/// radius 0. Sphere light: `color` is radiance L, and the light also appears
/// in the sphere array (with an emissive material) so rays can hit it.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LightGpu {
    /// Centre, relative to the packing origin.
    pub position: [f32; 3],
    /// Sphere radius; 0 for a point light.
    pub radius: f32,
    /// Intensity I (point) or radiance L (sphere), linear RGB.
    pub color: [f32; 3],
    /// `LIGHT_POINT` or `LIGHT_SPHERE`.
    pub kind: u32,
    /// A spot light's cone (`SpotCone::gpu`); (0, 0, 0, 1) for no cone.
    pub spot: [f32; 4],
}

/// The vertex attributes of the triangle with the same index, three texels
/// of `scene_uvs` (48 bytes; only in scenes with textures or vertex
/// colours): texture coordinates, packed tangents and packed colours.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct TriangleUvGpu {
    /// At `p0`.
    pub uv0: [f32; 2],
    /// At `p1`.
    pub uv1: [f32; 2],
    /// At `p2`.
    pub uv2: [f32; 2],
    /// The tangents at `p0`, `p1`, `p2` (`pack_tangent`).
    pub tangents: [u32; 3],
    /// The vertex colours at `p0`, `p1`, `p2` (`pack_color`).
    pub colors: [u32; 3],
}

/// A tangent as 10-bit signed normalised x, y, z and the bitangent's sign
/// in the top two bits (1 for -1); zero is no tangent
/// (`shared/textures.wgsl`, `unpack_tangent`).
pub fn pack_tangent(t: glam::Vec4) -> u32 {
    let q = |x: f32| ((x.clamp(-1.0, 1.0) * 511.0).round() as i32 as u32) & 0x3ff;
    q(t.x) | (q(t.y) << 10) | (q(t.z) << 20) | (u32::from(t.w < 0.0) << 30)
}

/// A colour in [0, 1] as unsigned normalised 11-bit red and green and
/// 10-bit blue, each stored as 1 - c so that zero is white: a shader that
/// reads the attributes of a scene without any (the generic one, bound to
/// an empty texture) multiplies by one (`shared/textures.wgsl`,
/// `unpack_color`).
pub fn pack_color(c: glam::Vec3) -> u32 {
    let q = |x: f32, max: f32| ((1.0 - x.clamp(0.0, 1.0)) * max).round() as u32;
    q(c.x, 2047.0) | (q(c.y, 2047.0) << 11) | (q(c.z, 1023.0) << 22)
}

/// `struct MaterialTextures` (160 bytes, ten texels): a material's texture
/// slots (`texture_classes::TextureLayout::slot`, `NO_TEXTURE` for none),
/// their wrap modes (2 bits each: base s, base t, emissive s, emissive t,
/// metallic-roughness s, t, normal s, t; 0 repeat, 1 clamp, 2 mirror) and
/// their uv transforms (two rows each).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MaterialTexturesGpu {
    /// Base colour slot.
    pub base: u32,
    /// Emission slot.
    pub emissive: u32,
    /// Wrap modes.
    pub wrap: u32,
    /// alphaMode MASK: the surface is there where the base colour
    /// texture's alpha (1 without one) is at least this; 0 for opaque.
    pub alpha_threshold: f32,
    /// Base colour uv transform, row 0 (w unused).
    pub base_u: [f32; 4],
    /// Row 1.
    pub base_v: [f32; 4],
    /// Emission uv transform, row 0.
    pub emissive_u: [f32; 4],
    /// Row 1.
    pub emissive_v: [f32; 4],
    /// Metallic-roughness slot.
    pub metallic_roughness: u32,
    /// Normal texture slot.
    pub normal: u32,
    /// The normal texture's scale.
    pub normal_scale: f32,
    /// Padding.
    pub _pad: u32,
    /// Metallic-roughness uv transform, row 0.
    pub metallic_roughness_u: [f32; 4],
    /// Row 1.
    pub metallic_roughness_v: [f32; 4],
    /// Normal uv transform, row 0.
    pub normal_u: [f32; 4],
    /// Row 1.
    pub normal_v: [f32; 4],
}

impl Default for MaterialTexturesGpu {
    fn default() -> Self {
        let (u, v) = ([1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]);
        MaterialTexturesGpu {
            base: u32::MAX,
            emissive: u32::MAX,
            wrap: 0,
            alpha_threshold: 0.0,
            base_u: u,
            base_v: v,
            emissive_u: u,
            emissive_v: v,
            metallic_roughness: u32::MAX,
            normal: u32::MAX,
            normal_scale: 1.0,
            _pad: 0,
            metallic_roughness_u: u,
            metallic_roughness_v: v,
            normal_u: u,
            normal_v: v,
        }
    }
}

/// Everything the GPU needs of a scene, as flat arrays.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneData {
    /// Spheres: sphere objects, then one per visible sphere light.
    pub spheres: Vec<SphereGpu>,
    /// Every mesh instance's triangles, mesh after mesh.
    pub triangles: Vec<TriangleGpu>,
    /// Parallel to `triangles`.
    pub normals: Vec<TriangleNormalsGpu>,
    /// Parallel to `triangles` in a scene with textures, else empty.
    pub uvs: Vec<TriangleUvGpu>,
    /// By material id (`NO_TEXTURE` slots where a material has none).
    pub material_textures: Vec<MaterialTexturesGpu>,
    /// One per mesh instance with triangles, in `ObjectId` order.
    pub meshes: Vec<MeshGpu>,
    /// Every material, indexed by material id.
    pub materials: Vec<MaterialGpu>,
    /// Lights, in the order of the scene's `lights`.
    pub lights: Vec<LightGpu>,
    /// The lights' clusters, which follow them in `scene_lights` (none
    /// with few lights: `light_clusters::clustered`).
    pub light_clusters: super::light_clusters::LightClusters,
    /// Radiance of rays that leave the scene, linear RGB (without an
    /// environment light).
    pub background: [f32; 3],
    /// The environment light's map and sampling tables
    /// (`environment::Environment::texels`; empty without one), shared:
    /// it never changes while the scene animates.
    pub environment: std::sync::Arc<Vec<[u32; 4]>>,
    /// The two-level BVH (filled by `bvh::scene::SceneBvh::update`).
    pub bvh: Vec<crate::bvh::BvhNode>,
    /// The TLAS instances (filled with `bvh`).
    pub instances: Vec<crate::bvh::scene::InstanceGpu>,
}

/// Scenes with at most this many primitives (spheres and triangles) are
/// traced flat: every ray tests every primitive, no BVH. A loop every SIMD
/// lane runs in step beats a divergent stack traversal there (the Cornell
/// box, 13 primitives, traces 2-4x faster flat on lavapipe); the hits are
/// identical either way (ties go to the lower id).
pub const FLAT_LIMIT: usize = 32;

/// Scenes that are not flat with at most this many spheres test them in a
/// loop before walking the BVH (`SceneData::spheres_apart`); more are
/// TLAS instances. The loop over a Cornell box's 34 spheres (32 of them
/// small lights) made realtime.ron's frame 0.55x what the instances
/// cost, over 64 spheres 0.78x, over 130 1.0x (docs/acceleration.md,
/// "Spheres apart").
pub const SPHERES_APART_LIMIT: usize = 64;

impl SceneData {
    /// Whether rays test every primitive instead of walking the BVH
    /// (`FLAT_LIMIT`).
    pub fn is_flat(&self) -> bool {
        // The flat path's occluder lists are built from light positions,
        // which a directional or environment light has not.
        // (Nor do their loops test a face's side.)
        self.spheres.len() + self.triangles.len() <= FLAT_LIMIT
            && !self.alpha_masked()
            && !self.materials.iter().any(MaterialGpu::is_single_sided)
            && !self.lights.iter().any(|l| l.kind == LIGHT_DIRECTIONAL || l.kind == LIGHT_ENVIRONMENT)
    }

    /// Whether rays test the spheres in a loop of their own before walking
    /// the BVH, which then holds the meshes alone (the `SPHERES_APART`
    /// override of shaders/shared/intersect.wgsl): a scene that is not flat
    /// with at most SPHERES_APART_LIMIT spheres (light spheres included).
    /// On a CPU driver a TLAS instance costs a ray that crosses it far more
    /// than a sphere test: thesis-env3's 15 small light spheres more than
    /// doubled its path pass as instances (docs/acceleration.md, "Spheres
    /// apart").
    pub fn spheres_apart(&self) -> bool {
        !self.spheres.is_empty() && self.spheres.len() <= SPHERES_APART_LIMIT && !self.is_flat()
    }

    /// Whether some material is alpha-tested (alphaMode MASK): its
    /// triangles are tested where traversal meets them, which the flat
    /// loops do not do.
    pub fn alpha_masked(&self) -> bool {
        self.material_textures.iter().any(|m| m.alpha_threshold > 0.0)
    }

    /// Whether the triangles come in pairs 2k, 2k + 1 that share an edge
    /// as a quad's two halves do, (a, b, c) and (a, c, d), bit for bit (the
    /// `FLAT_PAIRS` override of shaders/shared/flat.wgsl). Motion keeps it:
    /// both halves' shared vertices come from the same mesh vertices
    /// through the same transform.
    pub fn flat_pairs(&self) -> bool {
        let same = |p: [f32; 3], q: [f32; 3]| p.map(f32::to_bits) == q.map(f32::to_bits);
        self.triangles.len().is_multiple_of(2) && self.triangles.chunks_exact(2).all(|t| same(t[1].p0, t[0].p0) && same(t[1].p1, t[0].p2))
    }

    /// The sphere of the last light, when that light is a sphere light (the
    /// `FLAT_LAST_LIGHT_SPHERE` override of shaders/shared/flat.wgsl): a
    /// shadow ray toward a point sampled on a sphere light's visible cap
    /// ends short of that sphere, so the sphere cannot block it. Motion
    /// keeps it: it moves things, it does not renumber them.
    pub fn last_light_sphere(&self) -> Option<usize> {
        let last = self.lights.len().checked_sub(1)?;
        if self.lights[last].kind != LIGHT_SPHERE {
            return None;
        }
        self.spheres.iter().position(|s| usize::try_from(s.light).ok() == Some(last))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec4};

    /// `unpack_tangent` and `unpack_color` of shared/textures.wgsl.
    fn unpack_tangent(v: u32) -> Vec4 {
        let s = |shift: u32| (((v >> shift) & 0x3ff) as i32) << 22 >> 22;
        Vec4::new(s(0) as f32 / 511.0, s(10) as f32 / 511.0, s(20) as f32 / 511.0, if v & 0x4000_0000 != 0 { -1.0 } else { 1.0 })
    }

    fn unpack_color(v: u32) -> Vec3 {
        Vec3::ONE - Vec3::new((v & 0x7ff) as f32 / 2047.0, ((v >> 11) & 0x7ff) as f32 / 2047.0, (v >> 22) as f32 / 1023.0)
    }

    #[test]
    fn tangents_and_colours_pack_to_what_the_shader_reads() {
        for t in [Vec4::new(1.0, 0.0, 0.0, 1.0), Vec4::new(0.0, -1.0, 0.0, -1.0), Vec4::new(0.6, -0.48, 0.64, -1.0), Vec4::new(-0.36, 0.48, -0.8, 1.0)] {
            let back = unpack_tangent(pack_tangent(t));
            assert!((back - t).abs().max_element() <= 0.5 / 511.0 + 1e-6, "{t} -> {back}");
            assert_ne!(pack_tangent(t), 0, "a tangent is never read as none");
        }
        for c in [Vec3::ONE, Vec3::ZERO, Vec3::new(0.25, 0.001, 0.999)] {
            let back = unpack_color(pack_color(c));
            assert!((back - c).abs().max_element() <= 0.5 / 1023.0 + 1e-6, "{c} -> {back}");
        }
        assert_eq!(pack_color(Vec3::ONE), 0, "white is zero, what an empty texture reads");
        assert_eq!(unpack_color(pack_color(Vec3::ONE)), Vec3::ONE, "white stays exactly white");
    }
}
