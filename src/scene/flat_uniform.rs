//! `scene_flat`: a flat scene's triangles and spheres again, in a uniform
//! buffer (`struct FlatScene` in `shaders/shared/scene.wgsl`).
//!
//! The textures serve any scene, but a texel fetch costs the same whether
//! the lanes of a SIMD group ask for one address or eight. A flat scene's
//! loops visit every primitive in the same order on every lane, and where
//! a shader writes those visits out slot by slot (shaders/shared/flat.wgsl),
//! each slot is a constant offset into this buffer: lavapipe then loads a
//! component once and broadcasts it, where the texel fetch gathered it per
//! lane.

use crate::scene::{SceneData, FLAT_LIMIT};

/// Texels (16 bytes) of one triangle and of one sphere: the records of
/// `TriangleGpu` and `SphereGpu`.
const TRIANGLE_TEXELS: usize = 3;
const SPHERE_TEXELS: usize = 2;

/// Bytes of `struct FlatScene`: FLAT_LIMIT triangle slots, then FLAT_LIMIT
/// sphere slots.
pub const FLAT_UNIFORM_BYTES: usize = FLAT_LIMIT * (TRIANGLE_TEXELS + SPHERE_TEXELS) * 16;

/// The buffer's contents for `data`: its triangles from slot 0 and its
/// spheres after the last triangle slot, the rest zero; all zero where the
/// scene is not flat (no shader reads it then: FLAT_SCENE is off).
pub fn flat_uniform(data: &SceneData) -> Vec<u8> {
    let mut bytes = vec![0u8; FLAT_UNIFORM_BYTES];
    if !data.is_flat() {
        return bytes;
    }
    let triangles: &[u8] = bytemuck::cast_slice(&data.triangles);
    let spheres: &[u8] = bytemuck::cast_slice(&data.spheres);
    let sphere_base = FLAT_LIMIT * TRIANGLE_TEXELS * 16;
    bytes[..triangles.len()].copy_from_slice(triangles);
    bytes[sphere_base..sphere_base + spheres.len()].copy_from_slice(spheres);
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SphereGpu, TriangleGpu};

    fn tri(k: f32) -> TriangleGpu {
        TriangleGpu { p0: [k, 0.0, 0.0], material: 3, p1: [0.0, k, 0.0], object: 4, p2: [0.0, 0.0, k], _pad0: 0 }
    }

    fn sphere(k: f32) -> SphereGpu {
        SphereGpu { center: [k, k, k], radius: 0.5, material: 1, light: -1, object: 9, _pad: 0 }
    }

    #[test]
    fn triangles_then_spheres_in_their_slots() {
        let data = SceneData { triangles: vec![tri(1.0), tri(2.0)], spheres: vec![sphere(5.0)], ..Default::default() };
        let bytes = flat_uniform(&data);
        assert_eq!(bytes.len(), FLAT_UNIFORM_BYTES);
        assert_eq!(&bytes[48..96], bytemuck::bytes_of(&tri(2.0)));
        let sphere_base = FLAT_LIMIT * 48;
        assert_eq!(&bytes[sphere_base..sphere_base + 32], bytemuck::bytes_of(&sphere(5.0)));
        assert!(bytes[96..sphere_base].iter().all(|&b| b == 0), "empty triangle slots are zero");
    }

    #[test]
    fn the_shader_struct_has_flat_limit_slots() {
        let wgsl = include_str!("../../shaders/shared/scene.wgsl");
        assert!(wgsl.contains(&format!("    triangles: array<vec4u, {}>,", FLAT_LIMIT * TRIANGLE_TEXELS)), "scene.wgsl's FlatScene triangles");
        assert!(wgsl.contains(&format!("    spheres: array<vec4u, {}>,", FLAT_LIMIT * SPHERE_TEXELS)), "scene.wgsl's FlatScene spheres");
        let flat = include_str!("../../shaders/shared/flat.wgsl");
        assert!(flat.contains(&format!("override FLAT_LAST_LIGHT_SPHERE: u32 = {FLAT_LIMIT}u;")), "no light sphere by default");
        // trace_pair writes out every slot, four a call.
        for k in (0..FLAT_LIMIT).step_by(4) {
            assert!(flat.contains(&format!("    pair_spheres4(flat, a, b, {k}u, shadow_tmax, shadow_light, &sweep);")), "sphere slot {k}");
        }
        for k in (0..FLAT_LIMIT / 2).step_by(4) {
            assert!(flat.contains(&format!("    pair_quads4(flat, a, {k}u, &best);")), "quad slot {k}");
        }
    }

    #[test]
    fn the_last_lights_sphere() {
        use crate::scene::{LightGpu, LIGHT_POINT, LIGHT_SPHERE};
        let light = |kind| LightGpu { position: [0.0; 3], radius: 0.1, color: [1.0; 3], kind, spot: [0.0, 0.0, 0.0, 1.0] };
        let lit = |light: i32| SphereGpu { light, ..sphere(1.0) };
        let data = |lights: Vec<LightGpu>, spheres: Vec<SphereGpu>| SceneData { lights, spheres, ..Default::default() };
        assert_eq!(data(vec![], vec![sphere(1.0)]).last_light_sphere(), None);
        assert_eq!(data(vec![light(LIGHT_SPHERE)], vec![sphere(1.0), lit(0)]).last_light_sphere(), Some(1));
        // The last light's, not the first's; none for a point light last.
        assert_eq!(data(vec![light(LIGHT_SPHERE), light(LIGHT_SPHERE)], vec![lit(1), lit(0)]).last_light_sphere(), Some(0));
        assert_eq!(data(vec![light(LIGHT_SPHERE), light(LIGHT_POINT)], vec![lit(0)]).last_light_sphere(), None);
        // A sphere light without a sphere (no material: rays cannot hit it).
        assert_eq!(data(vec![light(LIGHT_SPHERE)], vec![sphere(1.0)]).last_light_sphere(), None);
    }

    #[test]
    fn a_scene_counts_as_flat_as_it_packs() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        for name in ["cornell.ron", "cornell-point.ron", "cornell-diffuse.ron", "moving-lights.ron", "thesis-env1.ron", "thesis-stress.ron"] {
            let mut scene = crate::scene::load(&root.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(scene.is_flat(), scene.pack().is_flat(), "{name}");
            assert_eq!(scene.compile_features().flat, scene.is_flat(), "{name}");
            // Lights added after loading count as they pack.
            scene.multiply_lights(40);
            assert_eq!(scene.compile_features().flat, scene.pack().is_flat(), "{name} with more lights");
        }
        let cornell = crate::scene::load(&root.join("cornell.ron")).unwrap_or_else(|e| panic!("{e}"));
        assert!(cornell.is_flat() && cornell.compile_features().flat);
    }

    #[test]
    fn a_full_flat_scene_fits_and_a_bvh_scene_is_left_out() {
        let full = SceneData { triangles: vec![tri(1.0); FLAT_LIMIT / 2], spheres: vec![sphere(1.0); FLAT_LIMIT / 2], ..Default::default() };
        assert!(full.is_flat());
        assert_eq!(flat_uniform(&full).len(), FLAT_UNIFORM_BYTES);
        let big = SceneData { triangles: vec![tri(1.0); FLAT_LIMIT + 1], ..Default::default() };
        assert!(flat_uniform(&big).iter().all(|&b| b == 0));
    }
}
