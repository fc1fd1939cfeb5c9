//! `scene_origins`: what the CPU works out once a frame about a flat scene
//! (at most `FLAT_LIMIT` primitives) for the rays the shaders trace most.
//!
//! - Its triangles seen from the points many rays start at
//!   (`crate::bvh::origin`): row `ORIGIN_CAMERA` for the camera's primary
//!   rays, row `ORIGIN_LIGHT` for the shadow rays toward light 0, traced
//!   from the light (shaders/shared/origins.wgsl). Three texels a
//!   triangle slot.
//! - Per light (the first `OCCLUDER_LIGHTS`), the triangles that can block
//!   a shadow ray toward it at all (`can_occlude`): a count, then one
//!   triangle index a texel. Shadow rays test only those
//!   (shaders/shared/flat.wgsl); in a room, the walls, floor and ceiling
//!   around a light shadow nothing from it.
//!
//! A scene that is not flat has a zeroed table, which no shader reads.

use glam::{DVec3, Vec3};

use super::{LightGpu, SceneData, FLAT_LIMIT};
use crate::bvh::origin::origin_edges;

/// The row of the camera's position.
pub const ORIGIN_CAMERA: usize = 0;
/// The row of light 0's position.
pub const ORIGIN_LIGHT: usize = 1;
/// Rows of triangle edge planes.
pub const ORIGIN_ROWS: usize = 2;
/// Texels such a row takes: three per triangle slot.
pub const ORIGIN_ROW_TEXELS: usize = 3 * FLAT_LIMIT;
/// Lights with an occluder list; shadow rays toward later lights test
/// every triangle.
pub const OCCLUDER_LIGHTS: usize = 8;
/// Texels an occluder list takes: the count, then one index a texel.
pub const OCCLUDER_ROW_TEXELS: usize = 1 + FLAT_LIMIT;
/// Texels in the table.
pub const ORIGIN_TABLE_TEXELS: usize = ORIGIN_ROWS * ORIGIN_ROW_TEXELS + OCCLUDER_LIGHTS * OCCLUDER_ROW_TEXELS;

/// Where rays can start this frame, besides the scene's surfaces: the
/// camera, and the box the graph's probes can be in (their grid, widened
/// by the distance relocation may move them) when it has probes.
#[derive(Debug, Clone, Copy)]
pub struct Viewpoints {
    /// The camera position, relative to the packing origin.
    pub camera: Vec3,
    /// The box the probes can be in (min, max), when the graph has probes.
    pub probes: Option<(Vec3, Vec3)>,
    /// The camera's pixels, for the screen tiles' entries
    /// (`crate::bvh::tiles`); None: no tile table.
    pub pixels: Option<crate::bvh::tiles::PixelCamera>,
}

impl Viewpoints {
    fn points(&self) -> Vec<DVec3> {
        let mut points = vec![self.camera.as_dvec3()];
        if let Some((lo, hi)) = self.probes {
            for corner in 0..8 {
                let pick = |bit: usize, a: f32, b: f32| f64::from(if corner & bit == 0 { a } else { b });
                points.push(DVec3::new(pick(1, lo.x, hi.x), pick(2, lo.y, hi.y), pick(4, lo.z, hi.z)));
            }
        }
        points
    }
}

/// The table for `data` (positions relative to the scene's rebasing
/// origin, as the GPU sees them). With `cull` false every light's list
/// holds every triangle (what tests compare the lists against).
pub fn origin_table(data: &SceneData, view: &Viewpoints, cull: bool) -> Vec<[u32; 4]> {
    let mut table = vec![[0u32; 4]; ORIGIN_TABLE_TEXELS];
    if !data.is_flat() {
        return table;
    }
    let light = data.lights.first().map(|l| l.position);
    for (row, origin) in [(ORIGIN_CAMERA, Some(view.camera)), (ORIGIN_LIGHT, light.map(Vec3::from))] {
        let Some(o) = origin else { continue };
        for (k, t) in data.triangles.iter().enumerate() {
            let edges = origin_edges(t.p0.into(), t.p1.into(), t.p2.into(), o);
            let at = row * ORIGIN_ROW_TEXELS + 3 * k;
            for (texel, e) in table[at..at + 3].iter_mut().zip(edges) {
                *texel = e.map(f32::to_bits);
            }
        }
    }
    let points = view.points();
    let tolerance = 1e-6 * extent(data).max(1e-30);
    for (i, l) in data.lights.iter().take(OCCLUDER_LIGHTS).enumerate() {
        let at = ORIGIN_ROWS * ORIGIN_ROW_TEXELS + i * OCCLUDER_ROW_TEXELS;
        let list: Vec<u32> = (0..data.triangles.len()).filter(|&k| !cull || can_occlude(data, k, l, &points, tolerance)).map(|k| k as u32).collect();
        table[at][0] = list.len() as u32;
        for (j, k) in list.into_iter().enumerate() {
            table[at + 1 + j][0] = k;
        }
    }
    table
}

/// The largest side of the box around the scene's primitives.
fn extent(data: &SceneData) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for t in &data.triangles {
        for p in [t.p0, t.p1, t.p2] {
            lo = lo.min(Vec3::from(p).as_dvec3());
            hi = hi.max(Vec3::from(p).as_dvec3());
        }
    }
    for s in &data.spheres {
        let (c, r) = (Vec3::from(s.center).as_dvec3(), f64::from(s.radius));
        lo = lo.min(c - r);
        hi = hi.max(c + r);
    }
    (hi - lo).max_element().max(0.0)
}

/// Whether triangle `k` can block a shadow ray toward light `l`. It cannot
/// when its plane has the whole light strictly on one side and everything
/// rays can start from or reach on that side too (closed: on the plane
/// counts, within `tolerance` for rounding): the other triangles, every
/// sphere, the camera and the probe box (`points`). Then every shadow ray
/// runs between two points of that closed half-space, which is convex, so
/// it never crosses the plane inside the triangle. Points on the plane
/// itself (the triangle, coplanar neighbours) are shaded from the front,
/// where every ray comes from, and offset_ray moves their shadow rays'
/// origins to that side.
pub fn can_occlude(data: &SceneData, k: usize, l: &LightGpu, points: &[DVec3], tolerance: f64) -> bool {
    let t = &data.triangles[k];
    let [p0, p1, p2] = [t.p0, t.p1, t.p2].map(|p| Vec3::from(p).as_dvec3());
    let Some(n) = (p1 - p0).cross(p2 - p0).try_normalize() else { return false };
    let height = |p: DVec3| n.dot(p - p0);
    let light = height(Vec3::from(l.position).as_dvec3());
    let radius = f64::from(l.radius);
    // (NaN heights keep the triangle.)
    if light.is_nan() || light.abs() <= radius + tolerance {
        return true;
    }
    let side = light.signum();
    let in_front = |p: DVec3| side * height(p) >= -tolerance;
    let triangles = data.triangles.iter().enumerate().filter(|&(j, _)| j != k);
    let vertices_in_front = triangles.flat_map(|(_, u)| [u.p0, u.p1, u.p2]).all(|p| in_front(Vec3::from(p).as_dvec3()));
    let spheres_in_front = data.spheres.iter().all(|s| side * height(Vec3::from(s.center).as_dvec3()) - f64::from(s.radius) >= -tolerance);
    !(vertices_in_front && spheres_in_front && points.iter().all(|&p| in_front(p)))
}

#[cfg(test)]
mod tests;
