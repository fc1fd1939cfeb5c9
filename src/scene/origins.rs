//! `scene_origins`: a flat scene's triangles as seen from the points many
//! rays start at (`crate::bvh::origin`), rebuilt on the CPU whenever the
//! camera or the scene moves. Row `ORIGIN_CAMERA` is for the camera's
//! primary rays, row `ORIGIN_LIGHT` for the shadow rays toward light 0,
//! traced from the light (shaders/shared/origins.wgsl); the shaders use
//! them where a pass traces its one ray of that kind at the top level,
//! which is where the flat sweep pays (shaders/shared/flat.wgsl). Each row
//! holds `FLAT_LIMIT` triangles of three texels; a scene that is not flat
//! has a zeroed table, which no shader reads.

use glam::Vec3;

use super::buffers::FLAT_LIMIT;
use super::SceneData;
use crate::bvh::origin::origin_edges;

/// The row of the camera's position.
pub const ORIGIN_CAMERA: usize = 0;
/// The row of light 0's position.
pub const ORIGIN_LIGHT: usize = 1;
/// Rows in the table.
pub const ORIGIN_ROWS: usize = 2;
/// Texels a row takes: three per triangle slot.
pub const ORIGIN_ROW_TEXELS: usize = 3 * FLAT_LIMIT;

/// The table for `data` with the camera at `camera` (both relative to the
/// scene's rebasing origin, as the GPU sees them): `ORIGIN_ROWS` rows of
/// `ORIGIN_ROW_TEXELS` texels.
pub fn origin_table(data: &SceneData, camera: [f32; 3]) -> Vec<[f32; 4]> {
    let mut table = vec![[0.0; 4]; ORIGIN_ROWS * ORIGIN_ROW_TEXELS];
    if data.spheres.len() + data.triangles.len() > FLAT_LIMIT {
        return table;
    }
    let light = data.lights.first().map(|l| l.position);
    for (row, origin) in [(ORIGIN_CAMERA, Some(camera)), (ORIGIN_LIGHT, light)] {
        let Some(o) = origin else { continue };
        for (k, t) in data.triangles.iter().enumerate() {
            let edges = origin_edges(t.p0.into(), t.p1.into(), t.p2.into(), Vec3::from(o));
            let at = row * ORIGIN_ROW_TEXELS + 3 * k;
            table[at..at + 3].copy_from_slice(&edges);
        }
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{LightGpu, SphereGpu, TriangleGpu};

    fn triangle(z: f32) -> TriangleGpu {
        TriangleGpu { p0: [-1.0, -1.0, z], material: 0, p1: [1.0, -1.0, z], object: 0, p2: [0.0, 1.0, z], _pad0: 0 }
    }

    #[test]
    fn rows_hold_each_triangle_seen_from_the_camera_and_light_0() {
        let light = LightGpu { position: [0.0, 3.0, 0.0], radius: 0.1, color: [1.0; 3], kind: 1 };
        let data = SceneData { triangles: vec![triangle(-1.0), triangle(-2.0)], lights: vec![light], ..Default::default() };
        let camera = [0.5, 0.0, 4.0];
        let table = origin_table(&data, camera);
        assert_eq!(table.len(), ORIGIN_ROWS * ORIGIN_ROW_TEXELS);
        let t = &data.triangles[1];
        let from = |o: [f32; 3]| origin_edges(t.p0.into(), t.p1.into(), t.p2.into(), o.into());
        assert_eq!(table[3..6], from(camera));
        assert_eq!(table[ORIGIN_ROW_TEXELS + 3..ORIGIN_ROW_TEXELS + 6], from(light.position));
        // Unused slots stay zero: their edge functions are 0, det 0, a miss.
        assert_eq!(table[6], [0.0; 4]);
        // The shader's slot count and row layout.
        let wgsl = include_str!("../../shaders/shared/origins.wgsl");
        assert!(wgsl.contains(&format!("const ORIGIN_ROW_TEXELS: u32 = {ORIGIN_ROW_TEXELS}u;")));
        assert!(wgsl.contains(&format!("const ORIGIN_LIGHT: u32 = {ORIGIN_LIGHT}u;")));
    }

    #[test]
    fn scenes_beyond_the_flat_limit_and_without_lights_leave_rows_zero() {
        let sphere = SphereGpu { center: [0.0; 3], radius: 1.0, material: 0, light: -1, object: 0, _pad: 0 };
        let big = SceneData { triangles: vec![triangle(-1.0)], spheres: vec![sphere; FLAT_LIMIT], ..Default::default() };
        assert!(origin_table(&big, [0.0; 3]).iter().all(|t| *t == [0.0; 4]));
        let dark = SceneData { triangles: vec![triangle(-1.0)], ..Default::default() };
        let table = origin_table(&dark, [0.0, 0.0, 3.0]);
        assert_ne!(table[0], [0.0; 4]);
        assert!(table[ORIGIN_ROW_TEXELS..].iter().all(|t| *t == [0.0; 4]));
    }
}
