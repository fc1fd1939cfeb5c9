//! The Rust mirror of the ray offsets in shaders/shared/intersect.wgsl:
//! every hit carries a conservative bound on its position's error,
//! computed from the operands of the arithmetic that produced it (pbrt-v4,
//! Pharr et al. 6.8), and a new ray leaves a surface by that bound along
//! the normal, and by at least `OFFSET_ULPS` ULPs of the point's largest
//! coordinate (the resolution at which the next ray's own intersection
//! tests round). Nothing here depends on the scene's size: a huge
//! primitive far away no longer inflates every other surface's offset.
//!
//! `offset_scale` remains for what it also was: the grid the GPU's origin
//! is rebased on (src/session/scene_gpu.rs).

use glam::Vec3;

/// ULPs of a point's largest coordinate a ray origin moves off its
/// surface at least (Wächter and Binder, Ray Tracing Gems ch. 6, move each
/// coordinate by 256 of its own).
pub const OFFSET_ULPS: f32 = 256.0;

/// The least offset, for a point within 1e-27 of the origin.
pub const TINY_OFFSET: f32 = 1e-30;

/// How much tighter a triangle hit's point along the ray must be than the
/// interpolated one to be taken (`triangle_hit`).
pub const RAY_POINT_GAIN: f32 = 64.0;

/// pbrt's gamma(n): n rounded f32 operations in a row are off by at most
/// this share of the exact result, n u / (1 - n u) with u = 2^-24.
pub fn gamma(n: f32) -> f32 {
    let u = f32::EPSILON * 0.5;
    n * u / (1.0 - n * u)
}

/// The error bound of a triangle point interpolated from barycentrics
/// `b` (b0 = 1 - b1 - b2 included): gamma(7) of the terms' sizes.
pub fn triangle_error(b: [f32; 3], p: [Vec3; 3]) -> Vec3 {
    gamma(7.0) * ((b[0] * p[0]).abs() + (b[1] * p[1]).abs() + (b[2] * p[2]).abs())
}

/// The error bound of a sphere point c + r n (n the normalised direction
/// from the centre).
pub fn sphere_error(c: Vec3, r: f32) -> Vec3 {
    gamma(6.0) * (c.abs() + Vec3::splat(r))
}

/// The error bound of the point o + t d, given a bound `t_error` on t.
pub fn ray_point_error(o: Vec3, d: Vec3, t: f32, t_error: f32) -> Vec3 {
    gamma(3.0) * (o.abs() + (t * d).abs()) + d.abs() * t_error
}

/// A triangle hit's point and its error bound, as `closest_hit` picks
/// them: interpolated from the barycentrics (b1, b2), or along the ray
/// where that is RAY_POINT_GAIN times tighter (`t_error`: the bound on the
/// hit distance, `ray::triangle_t_error`).
pub fn triangle_hit(o: Vec3, d: Vec3, t: f32, b1: f32, b2: f32, p: [Vec3; 3], t_error: f32) -> (Vec3, Vec3) {
    let b0 = 1.0 - b1 - b2;
    let p_bary = b0 * p[0] + b1 * p[1] + b2 * p[2];
    let e_bary = triangle_error([b0, b1, b2], p);
    let p_ray = o + t * d;
    let e_ray = ray_point_error(o, d, t, t_error);
    if RAY_POINT_GAIN * e_ray.element_sum() < e_bary.element_sum() {
        (p_ray, e_ray)
    } else {
        (p_bary, e_bary)
    }
}

/// `offset_ray(p, n, error)` in WGSL: p moved off its surface toward the
/// side the unit normal `n` points to, by the error's extent along n and
/// by at least OFFSET_ULPS ULPs of p's largest coordinate.
pub fn offset_ray(p: Vec3, n: Vec3, error: Vec3) -> Vec3 {
    offset_by(p, n, n.abs().dot(error))
}

/// `offset_by(p, n, d)` in WGSL: `offset_ray` for a point whose error
/// along n is at most `d`.
pub fn offset_by(p: Vec3, n: Vec3, d: f32) -> Vec3 {
    let largest = p.abs().max_element();
    let ulp = f32::from_bits(largest.to_bits() & 0x7f80_0000) * f32::EPSILON;
    p + d.max((OFFSET_ULPS * ulp).max(TINY_OFFSET)) * n
}

/// The origin-rebasing grid of a scene whose bounds span `extent` (the
/// longest side): the power of two at or below extent / 2, clamped to
/// [2^-60, 2^60], and 1 for an empty or non-finite extent.
pub fn offset_scale(extent: f32) -> f32 {
    if !(extent.is_finite() && extent > 0.0) {
        return 1.0;
    }
    let e = (extent * 0.5).log2().floor().clamp(-60.0, 60.0);
    2f32.powi(e as i32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_scale_with_the_point_not_the_scene() {
        // The same point and normal move by the same amount however large
        // the scene around them is: nothing here takes its size.
        let (p, n) = (Vec3::new(0.3, 0.0, -0.2), Vec3::Y);
        let o = offset_by(p, n, 0.0);
        // 256 ULPs of 0.3 (ULP 2^-25) along +y.
        assert_eq!(o, Vec3::new(0.3, 256.0 * 2f32.powi(-25), -0.2));
        // Scaled by a power of two, the offset scales with it, exactly.
        for k in [-40, -17, -1, 3, 16, 40] {
            let s = 2f32.powi(k);
            assert_eq!(offset_by(p * s, n, 0.0), o * s, "2^{k}");
        }
        // A larger error bound wins.
        assert_eq!(offset_by(p, n, 1e-3), p + 1e-3 * n);
        // At the origin: the least offset.
        assert_eq!(offset_by(Vec3::ZERO, -Vec3::Z, 0.0), Vec3::new(0.0, 0.0, -TINY_OFFSET));
    }

    #[test]
    fn error_bounds_come_from_the_operands() {
        // A triangle in the plane z = 0: no error across it, however large.
        let big = [Vec3::new(-1e9, -1e9, 0.0), Vec3::new(1e9, -1e9, 0.0), Vec3::new(0.0, 1e9, 0.0)];
        let e = triangle_error([0.25, 0.25, 0.5], big);
        assert_eq!(e.z, 0.0);
        assert!(e.x > 100.0 && e.y > 100.0, "{e}");
        // Hit 4.4 units from the camera: the point along the ray is far
        // tighter and is taken.
        let (p, err) = triangle_hit(Vec3::new(0.0, 0.0, 4.4), -Vec3::Z, 4.4, 0.25, 0.5, big, 1e-6);
        assert!(err.element_sum() < 1e-5 && p.z.abs() < 1e-5, "{p} {err}");
        // A unit triangle seen from afar keeps its interpolated point.
        let unit = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let (p, err) = triangle_hit(Vec3::new(0.2, 0.2, 1e4), -Vec3::Z, 1e4, 0.2, 0.2, unit, 1e-3);
        assert_eq!(p, Vec3::new(0.2, 0.2, 0.0));
        assert_eq!(err, triangle_error([0.6, 0.2, 0.2], unit));
        assert!(gamma(7.0) > 7.0 * 5.9e-8 && gamma(7.0) < 7.0 * 6.0e-8);
    }

    #[test]
    fn offset_scale_is_a_power_of_two_near_half_the_extent() {
        assert_eq!(offset_scale(2.0), 1.0);
        assert_eq!(offset_scale(3.9), 1.0);
        assert_eq!(offset_scale(4.0), 2.0);
        assert_eq!(offset_scale(2e-4), 2f32.powi(-14));
        assert_eq!(offset_scale(2e4), 8192.0);
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(offset_scale(bad), 1.0);
        }
        assert_eq!(offset_scale(1e30), 2f32.powi(60));
    }
}
