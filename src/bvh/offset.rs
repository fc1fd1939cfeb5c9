//! The Rust mirror of `offset_ray` in shaders/shared/intersect.wgsl: moves a
//! surface point off the surface along the geometric normal (Wächter and
//! Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
//! Tracing Gems ch. 6), bit for bit as the WGSL does it.

use glam::Vec3;

/// Below this magnitude (times the scene's offset scale) a component is
/// offset by a fixed float amount (the integer ULP offset would be tiny
/// near zero).
pub const ORIGIN: f32 = 1.0 / 32.0;
/// The fixed offset near the origin (times the scene's offset scale).
pub const FLOAT_SCALE: f32 = 1.0 / 65536.0;
/// ULPs of offset per unit of normal component elsewhere.
pub const INT_SCALE: f32 = 256.0;

/// One component: `bitcast<f32>(bitcast<i32>(p) + select(of_i, -of_i, p < 0.0))`
/// when |p| >= ORIGIN * scale, else `p + FLOAT_SCALE * scale * n`.
#[inline]
fn offset_component(p: f32, n: f32, scale: f32) -> f32 {
    if p.abs() < ORIGIN * scale {
        // FLOAT_SCALE * scale * n is exact (powers of two, barring
        // underflow), so a fused multiply-add on the GPU rounds the same way.
        return p + FLOAT_SCALE * scale * n;
    }
    // WGSL's f32 -> i32 conversion truncates toward zero and saturates, as
    // `as` does (NaN: 0 in Rust; WGSL leaves NaN unspecified).
    let of_i = (INT_SCALE * n) as i32;
    // WGSL i32 arithmetic wraps.
    let delta = if p < 0.0 { of_i.wrapping_neg() } else { of_i };
    f32::from_bits((p.to_bits() as i32).wrapping_add(delta) as u32)
}

/// `offset_ray(p, n)` for a scene of offset scale 1 (see `offset_scale`).
pub fn offset_ray(p: Vec3, n: Vec3) -> Vec3 {
    offset_ray_scaled(p, n, 1.0)
}

/// `offset_ray(p, n)` in WGSL: p moved off the surface toward the side `n`
/// (the geometric normal, pointing to the side the new ray leaves from)
/// points to. `scale` is the scene's offset scale (`frame.offset_scale`):
/// the near-origin threshold and fixed offset grow with the scene, so a
/// scene scaled by a power of two gets its offsets scaled by the same
/// power of two, bit for bit (the integer ULP offset is scale-free).
pub fn offset_ray_scaled(p: Vec3, n: Vec3, scale: f32) -> Vec3 {
    Vec3::new(offset_component(p.x, n.x, scale), offset_component(p.y, n.y, scale), offset_component(p.z, n.z, scale))
}

/// The offset scale of a scene whose bounds span `extent` (the longest
/// side): the power of two at or below extent / 2, so scenes about 2 units
/// across (the Cornell box) get 1 and keep the offsets of Wächter and
/// Binder's paper; clamped to [2^-60, 2^60], and 1 for an empty or
/// non-finite extent.
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
    fn offsets_scale_with_the_scene_bit_for_bit() {
        let points = [Vec3::new(0.3, -0.01, 0.0), Vec3::new(-1.0, 0.02, 0.5), Vec3::new(1e-3, -0.7, 0.03125), Vec3::ZERO];
        let normals = [Vec3::X, Vec3::new(0.6, -0.8, 0.0), Vec3::new(-0.267, 0.534, -0.801)];
        for k in [-40, -17, -4, -1, 0, 3, 16, 40] {
            let s = 2f32.powi(k);
            for p in points {
                for n in normals {
                    let scaled = offset_ray_scaled(p * s, n, s);
                    let want = offset_ray(p, n) * s;
                    assert_eq!(scaled.to_array().map(f32::to_bits), want.to_array().map(f32::to_bits), "p {p:?} n {n:?} scale 2^{k}");
                }
            }
        }
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
