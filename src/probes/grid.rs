//! A regular grid of probes and the trilinear weights of a point's cell.
//!
//! The thesis's volume (chapter 3): (L+1)^3 probes spanning the scene's
//! bounds shrunk by a padding on every side (0.1 of the extent by default),
//! so the outermost probes sit inside the scene rather than on its walls.
//! A point is shaded from the eight probes of its cell; a point outside
//! the grid is clamped to the nearest cell (its weights then lean on the
//! nearest face), and a NaN position falls back to the first cell.

use glam::{UVec3, Vec3};

/// A regular grid of probes: probe (i, j, k) sits at `origin + spacing * (i, j, k)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeGrid {
    /// The position of probe (0, 0, 0).
    pub origin: Vec3,
    /// Distance between neighbouring probes, per axis (> 0).
    pub spacing: Vec3,
    /// Probes per axis (each at least 2, so every point has a cell).
    pub counts: UVec3,
}

/// The default padding: the share of the extent left free on each side.
pub const DEFAULT_PADDING: f32 = 0.1;

/// An axis whose extent is under this share of the largest is flat.
pub const FLAT_SHARE: f32 = 1e-3;
/// A flat axis's probe layer: its thickness as a share of the largest
/// extent, and its lift off the plane as a share of that thickness.
pub const FLAT_THICKNESS: f32 = 0.25;
/// See FLAT_THICKNESS.
pub const FLAT_LIFT: f32 = 0.05;

impl ProbeGrid {
    /// `level + 1` probes per axis over `lo..hi` shrunk by `padding` of the
    /// extent on each side. `None` when the bounds are not finite.
    ///
    /// A flat axis (an extent under FLAT_SHARE of the largest: a scene in
    /// one plane) gets a layer of probes on one side of its plane, the side
    /// of `toward` (where the light is), FLAT_THICKNESS of the largest
    /// extent thick and starting FLAT_LIFT of that above the plane: probes
    /// on the plane itself would see half their rays start on its surface,
    /// and a layer on both sides would average the lit side with the dark.
    /// Points on the plane clamp to the nearest layer.
    pub fn over_bounds(lo: Vec3, hi: Vec3, level: u32, padding: f32, toward: Vec3) -> Option<ProbeGrid> {
        if !(lo.is_finite() && hi.is_finite()) || level == 0 || !(0.0..0.5).contains(&padding) {
            return None;
        }
        let extent = (hi - lo).max(Vec3::ZERO);
        let largest = extent.max_element();
        let pad = extent * padding;
        let (lo, hi) = (lo + pad, hi - pad);
        let span = (hi - lo).max(Vec3::ZERO);
        let flat = if largest > 0.0 { extent.cmplt(Vec3::splat(FLAT_SHARE * largest)) } else { glam::BVec3::TRUE };
        // A point (every axis flat) gets a unit cube's layers.
        let thick = if largest > 0.0 { FLAT_THICKNESS * largest } else { 1.0 };
        let plane = (lo + hi) * 0.5;
        let above = Vec3::select(toward.cmplt(plane), Vec3::ZERO, Vec3::ONE).cmpeq(Vec3::ONE);
        let lift = FLAT_LIFT * thick;
        let flat_origin = Vec3::select(above, plane + Vec3::splat(lift), plane - Vec3::splat(lift + thick));
        let origin = Vec3::select(flat, flat_origin, lo);
        let span = Vec3::select(flat, Vec3::splat(thick), span.max(Vec3::splat(f32::MIN_POSITIVE)));
        Some(ProbeGrid { origin, spacing: span / level as f32, counts: UVec3::splat(level + 1) })
    }

    /// Probes in all.
    pub fn probe_count(&self) -> u32 {
        self.counts.x * self.counts.y * self.counts.z
    }

    /// The linear index of probe (i, j, k): x fastest.
    pub fn index(&self, p: UVec3) -> u32 {
        p.x + self.counts.x * (p.y + self.counts.y * p.z)
    }

    /// The world position of probe (i, j, k).
    pub fn position(&self, p: UVec3) -> Vec3 {
        self.origin + self.spacing * p.as_vec3()
    }

    /// The cell of point `x` (its lowest probe, every component at most
    /// counts - 2) and the position within it in [0, 1]^3, clamped.
    pub fn cell(&self, x: Vec3) -> (UVec3, Vec3) {
        let g = (x - self.origin) / self.spacing;
        let last = (self.counts - UVec3::splat(2)).as_vec3();
        // NaN compares false, so `max` and `min` below would keep it:
        // replace it first.
        let g = Vec3::select(g.cmpeq(g), g, Vec3::ZERO);
        let g = g.clamp(Vec3::ZERO, last + Vec3::ONE);
        let base = g.floor().min(last);
        (base.as_uvec3(), (g - base).clamp(Vec3::ZERO, Vec3::ONE))
    }

    /// The eight probes of `x`'s cell with their trilinear weights
    /// (non-negative, summing to 1).
    pub fn trilinear(&self, x: Vec3) -> [(u32, f32); 8] {
        let (base, f) = self.cell(x);
        std::array::from_fn(|corner| {
            let c = UVec3::new(corner as u32 & 1, (corner as u32 >> 1) & 1, (corner as u32 >> 2) & 1);
            let w = Vec3::select(c.cmpeq(UVec3::ONE), f, Vec3::ONE - f);
            (self.index(base + c), w.x * w.y * w.z)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> ProbeGrid {
        ProbeGrid::over_bounds(Vec3::splat(-1.0), Vec3::splat(1.0), 7, DEFAULT_PADDING, Vec3::ZERO).unwrap()
    }

    fn check(g: &ProbeGrid, x: Vec3) -> [(u32, f32); 8] {
        let w = g.trilinear(x);
        let sum: f32 = w.iter().map(|e| e.1).sum();
        assert!((sum - 1.0).abs() < 1e-5, "{x}: weights sum to {sum}");
        assert!(w.iter().all(|&(i, wt)| i < g.probe_count() && wt >= 0.0), "{x}: {w:?}");
        w
    }

    #[test]
    fn the_thesis_grid_has_l_plus_one_cubed_probes_inside_the_padding() {
        let g = grid();
        assert_eq!(g.probe_count(), 512);
        assert!((g.position(UVec3::ZERO) - Vec3::splat(-0.8)).length() < 1e-6);
        assert!((g.position(UVec3::splat(7)) - Vec3::splat(0.8)).length() < 1e-5);
        // The thesis's memory: 8^3 probes, two 25 x 25 maps of RGBA f32.
        assert_eq!(u64::from(g.probe_count()) * 2 * 25 * 25 * 16, 10_240_000);
        assert_eq!(10_240_000.0 / 1048576.0, 9.765625);
    }

    #[test]
    fn a_probe_position_takes_all_its_weight() {
        let g = grid();
        for p in [UVec3::ZERO, UVec3::new(3, 4, 5), UVec3::splat(7), UVec3::new(7, 0, 7)] {
            let w = check(&g, g.position(p));
            let best = w.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
            assert_eq!(best.0, g.index(p));
            assert!((best.1 - 1.0).abs() < 1e-4, "{p}: {w:?}");
        }
    }

    #[test]
    fn weights_hold_at_the_max_face_outside_and_at_nan() {
        let g = grid();
        // The max face: the last cell, all weight on the last probes.
        let (base, f) = g.cell(Vec3::splat(0.8));
        assert_eq!(base, UVec3::splat(6));
        assert!((f - Vec3::ONE).abs().max_element() < 1e-4, "{f}");
        check(&g, Vec3::splat(0.8));
        // Outside: clamped to the nearest cell.
        for x in [Vec3::splat(5.0), Vec3::splat(-5.0), Vec3::new(0.0, 100.0, -0.3), Vec3::new(f32::INFINITY, 0.0, f32::NEG_INFINITY)] {
            let w = check(&g, x);
            let inside = check(&g, x.clamp(Vec3::splat(-0.8), Vec3::splat(0.8)));
            assert_eq!(w.map(|e| e.0), inside.map(|e| e.0), "{x}");
        }
        // NaN: the first cell, valid weights.
        for x in [Vec3::NAN, Vec3::new(0.2, f32::NAN, 0.1)] {
            let w = check(&g, x);
            assert!(w.iter().all(|e| e.1.is_finite()), "{x}: {w:?}");
        }
        // Linear along an axis between two probes.
        let (a, b) = (g.position(UVec3::new(2, 3, 3)), g.position(UVec3::new(3, 3, 3)));
        let w = check(&g, a.lerp(b, 0.25));
        let of = |p: UVec3| w.iter().find(|e| e.0 == g.index(p)).map_or(0.0, |e| e.1);
        assert!((of(UVec3::new(2, 3, 3)) - 0.75).abs() < 1e-4 && (of(UVec3::new(3, 3, 3)) - 0.25).abs() < 1e-4, "{w:?}");
    }

    #[test]
    fn bad_bounds_and_flat_scenes() {
        assert!(ProbeGrid::over_bounds(Vec3::NAN, Vec3::ONE, 7, 0.1, Vec3::ZERO).is_none());
        assert!(ProbeGrid::over_bounds(Vec3::ZERO, Vec3::ONE, 0, 0.1, Vec3::ZERO).is_none());
        assert!(ProbeGrid::over_bounds(Vec3::ZERO, Vec3::ONE, 3, 0.5, Vec3::ZERO).is_none());
        // A flat scene (a single quad in y = -1, the light above it): a
        // layer of probes above the plane, none on it, the plane's points
        // taking the lowest layer.
        let (lo, hi) = (Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, -1.0, 1.0));
        let g = ProbeGrid::over_bounds(lo, hi, 3, 0.1, Vec3::new(0.0, 0.5, 0.0)).unwrap();
        assert!(g.spacing.min_element() > 0.0);
        let (lowest, highest) = (g.position(UVec3::ZERO).y, g.position(UVec3::splat(3)).y);
        assert!(lowest > -1.0 + 1e-3 && (lowest - (-1.0 + 0.025)).abs() < 1e-5, "{lowest}");
        assert!((highest - lowest - 0.5).abs() < 1e-5, "{highest}");
        let (base, f) = g.cell(Vec3::new(0.1, -1.0, 0.2));
        assert_eq!((base.y, f.y), (0, 0.0));
        check(&g, Vec3::new(0.1, -1.0, 0.2));
        // The light below: the layer below.
        let g = ProbeGrid::over_bounds(lo, hi, 3, 0.1, Vec3::new(0.0, -3.0, 0.0)).unwrap();
        assert!(g.position(UVec3::splat(3)).y < -1.0 - 1e-3);
        // Nearly flat (a millionth of the width) counts as flat; the other
        // axes keep their padding.
        let g = ProbeGrid::over_bounds(lo, hi + Vec3::new(0.0, 2e-6, 0.0), 3, 0.1, Vec3::ZERO).unwrap();
        assert!(g.position(UVec3::ZERO).y > -1.0 + 1e-3);
        assert!((g.position(UVec3::ZERO).x - (-0.8)).abs() < 1e-5);
        // A point: unit layers on every axis.
        let g = ProbeGrid::over_bounds(Vec3::ZERO, Vec3::ZERO, 3, 0.1, Vec3::ONE).unwrap();
        assert!(g.spacing.min_element() > 0.0);
    }
}
