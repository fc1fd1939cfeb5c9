//! The Rust mirror of `offset_ray` in shaders/shared/intersect.wgsl: moves a
//! surface point off the surface along the geometric normal (Wächter and
//! Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
//! Tracing Gems ch. 6), bit for bit as the WGSL does it.

use glam::Vec3;

/// Below this magnitude a component is offset by a fixed float amount
/// (the integer ULP offset would be tiny near zero).
pub const ORIGIN: f32 = 1.0 / 32.0;
/// The fixed offset scale near the origin.
pub const FLOAT_SCALE: f32 = 1.0 / 65536.0;
/// ULPs of offset per unit of normal component elsewhere.
pub const INT_SCALE: f32 = 256.0;

/// One component: `bitcast<f32>(bitcast<i32>(p) + select(of_i, -of_i, p < 0.0))`
/// when |p| >= ORIGIN, else `p + FLOAT_SCALE * n`.
#[inline]
fn offset_component(p: f32, n: f32) -> f32 {
    if p.abs() < ORIGIN {
        // FLOAT_SCALE * n is exact (a power of two, barring underflow), so a
        // fused multiply-add on the GPU rounds the same way.
        return p + FLOAT_SCALE * n;
    }
    // WGSL's f32 -> i32 conversion truncates toward zero and saturates, as
    // `as` does (NaN: 0 in Rust; WGSL leaves NaN unspecified).
    let of_i = (INT_SCALE * n) as i32;
    // WGSL i32 arithmetic wraps.
    let delta = if p < 0.0 { of_i.wrapping_neg() } else { of_i };
    f32::from_bits((p.to_bits() as i32).wrapping_add(delta) as u32)
}

/// `offset_ray(p, n)`: p moved off the surface toward the side `n` (the
/// geometric normal, pointing to the side the new ray leaves from) points to.
pub fn offset_ray(p: Vec3, n: Vec3) -> Vec3 {
    Vec3::new(offset_component(p.x, n.x), offset_component(p.y, n.y), offset_component(p.z, n.z))
}
