//! `glint bench rays --trips`: the BLAS traversal trips of each primary
//! ray, counted on the GPU (the `COUNT_TRIPS` override in
//! shaders/shared/intersect.wgsl) and summarised here. A trip is one turn
//! of the traversal loop: a box pair or one triangle. On a SIMD CPU driver
//! a trip costs the same whichever it does, and a group of lanes runs as
//! many trips as its busiest lane, so the summary gives both the mean per
//! ray and the mean over runs of `GROUP` pixels of their largest count.
//! Unlike times, these counts do not swing with the machine: they compare
//! trees and traversal orders exactly.

/// Pixels a SIMD group covers in a row of a `@workgroup_size(64, 1)`
/// pass on lavapipe (8 lanes of 32 bits in 256-bit registers).
pub const GROUP: usize = 8;

/// How bench_rays.wgsl packs a ray's counts into one f32: node trips +
/// 4096 x triangle trips, each capped at 4095.
const FIELD: u32 = 4096;

/// A ray's (node trips, triangle trips) from its packed value.
pub fn decode(code: f32) -> (u32, u32) {
    let c = if code.is_finite() && code >= 0.0 { code as u32 } else { 0 };
    (c % FIELD, c / FIELD)
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TripStats {
    pub rays: usize,
    pub node_per_ray: f64,
    pub triangle_per_ray: f64,
    pub per_ray: f64,
    /// The mean, over runs of GROUP pixels within a row, of the largest
    /// count of the run (what a SIMD group pays).
    pub group_max_per_ray: f64,
}

/// Summarises the packed counts of a `width`-pixel-wide image, row by row.
pub fn trip_stats(codes: &[f32], width: usize) -> TripStats {
    let rays = codes.len();
    let (mut node, mut tri, mut group_max) = (0u64, 0u64, 0u64);
    for row in codes.chunks(width.max(1)) {
        for run in row.chunks(GROUP) {
            let mut most = 0u64;
            for &c in run {
                let (n, t) = decode(c);
                node += u64::from(n);
                tri += u64::from(t);
                most = most.max(u64::from(n + t));
            }
            // A run shorter than GROUP (the row's end) is still one group.
            group_max += most * run.len() as u64;
        }
    }
    let per = |x: u64| if rays == 0 { 0.0 } else { x as f64 / rays as f64 };
    TripStats { rays, node_per_ray: per(node), triangle_per_ray: per(tri), per_ray: per(node + tri), group_max_per_ray: per(group_max) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn code(node: u32, tri: u32) -> f32 {
        (node + FIELD * tri) as f32
    }

    #[test]
    fn decode_splits_the_two_counts_and_refuses_garbage() {
        assert_eq!(decode(code(37, 5)), (37, 5));
        assert_eq!(decode(code(4095, 4095)), (4095, 4095));
        assert_eq!(decode(0.0), (0, 0));
        assert_eq!(decode(f32::NAN), (0, 0));
        assert_eq!(decode(-3.0), (0, 0));
    }

    #[test]
    fn stats_average_per_ray_and_take_each_groups_busiest_lane() {
        // Two rows of 10: runs of 8 and 2 per row.
        let mut codes = vec![code(1, 0); 20];
        codes[3] = code(10, 2); // first run of row 0: its max is 12
        codes[19] = code(2, 1); // second run of row 1: max 3
        let s = trip_stats(&codes, 10);
        assert_eq!(s.rays, 20);
        assert!((s.node_per_ray - (18.0 + 10.0 + 2.0) / 20.0).abs() < 1e-12);
        assert!((s.triangle_per_ray - 3.0 / 20.0).abs() < 1e-12);
        assert!((s.per_ray - 33.0 / 20.0).abs() < 1e-12);
        // Runs: row 0 [max 12 x 8, max 1 x 2], row 1 [1 x 8, 3 x 2].
        assert!((s.group_max_per_ray - (96.0 + 2.0 + 8.0 + 6.0) / 20.0).abs() < 1e-12);
    }

    #[test]
    fn an_empty_image_has_no_trips() {
        let s = trip_stats(&[], 4);
        assert_eq!((s.rays, s.per_ray, s.group_max_per_ray), (0, 0.0, 0.0));
    }
}
