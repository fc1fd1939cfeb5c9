//! The Rust mirror of shaders/shared/sampling.wgsl and rng.wgsl: the same
//! formulas, so they can be tested exhaustively on the CPU.

use glam::{DVec3, Mat3, Vec2, Vec3};

/// π in f32.
pub const PI: f32 = std::f32::consts::PI;

/// An orthonormal basis with `n` as its third column (Duff et al. 2017).
pub fn basis(n: Vec3) -> Mat3 {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = Vec3::new(b, s + n.y * n.y * a, -n.y);
    Mat3::from_cols(t, bt, n)
}

/// Cosine-weighted direction around `n`; pdf = cos(theta) / pi.
pub fn sample_cosine(n: Vec3, u: Vec2) -> Vec3 {
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u.x).max(0.0).sqrt());
    (basis(n) * local).normalize()
}

/// Uniform direction in the cone around `axis` whose half-angle has
/// 1 - cos = `one_minus_cos` (given so, since for a far light the cosine
/// rounds to 1 in f32); pdf = cone_pdf(one_minus_cos).
pub fn sample_cone(axis: Vec3, one_minus_cos: f32, u: Vec2) -> Vec3 {
    let a = u.x * one_minus_cos;
    let cos_t = 1.0 - a;
    let sin_t = (a * (2.0 - a)).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let local = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
    (basis(axis) * local).normalize()
}

/// The path tracer's glossy lobe: the mirror direction `r` blended toward
/// a cosine-distributed direction around `n` by `roughness` (0 < roughness
/// <= 1; the path tracer uses `r` itself at 0); pdf = `glossy_pdf`.
pub fn sample_glossy(r: Vec3, n: Vec3, roughness: f32, u: Vec2) -> Vec3 {
    (r * (1.0 - roughness) + sample_cosine(n, u) * roughness).normalize()
}

/// The solid-angle pdf of `sample_glossy`, by a change of variables (it
/// has no simpler closed form). With a = (1 - roughness) r and c the
/// cosine sample, d is the direction of v = a + roughness c: v lies on the
/// sphere of radius `roughness` about a, so the c giving d solve
/// |lambda d - a| = roughness for lambda = |v| > 0 (one root when
/// roughness >= 1/2, which puts the origin inside that sphere; up to two
/// inside a cone about r otherwise). Projecting that sphere onto the unit
/// sphere scales solid angle by roughness^2 |c . d| / lambda^2, so
/// pdf(d) = sum over the roots of (c . n / pi) lambda^2 / (roughness^2 |c . d|).
pub fn glossy_pdf(r: DVec3, n: DVec3, roughness: f64, d: DVec3) -> f64 {
    let a = (1.0 - roughness) * r;
    let ad = a.dot(d);
    let disc = ad * ad - a.length_squared() + roughness * roughness;
    if disc <= 0.0 || roughness <= 0.0 {
        return 0.0;
    }
    let root = disc.sqrt();
    let mut pdf = 0.0;
    for lambda in [ad + root, ad - root] {
        if lambda <= 0.0 {
            continue;
        }
        let c = (lambda * d - a) / roughness;
        // c . d = (lambda - a . d) / roughness = +-root / roughness.
        let cd = c.dot(d).abs();
        if cd > 0.0 {
            pdf += c.dot(n).max(0.0) / std::f64::consts::PI * lambda * lambda / (roughness * roughness * cd);
        }
    }
    pdf
}

/// cos of the half-angle a sphere of radius r subtends at distance d > r.
pub fn sphere_cos_max(d: f32, r: f32) -> f32 {
    let s = r / d;
    (1.0 - s * s).max(0.0).sqrt()
}

/// 1 - sphere_cos_max(d, r) without the cancellation: s^2 / (1 + cos).
pub fn sphere_one_minus_cos(d: f32, r: f32) -> f32 {
    let s = r / d;
    s * s / (1.0 + (1.0 - s * s).max(0.0).sqrt())
}

/// 1 / (2 pi (1 - cos_max)); the floor keeps an underflowed cone finite.
pub fn cone_pdf(one_minus_cos: f32) -> f32 {
    1.0 / (2.0 * PI * one_minus_cos.max(1e-37))
}

/// The PCG hash of rng.wgsl.
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// A random stream, as `Rng` in rng.wgsl.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rng {
    /// The PCG state.
    pub state: u32,
}

impl Rng {
    /// The stream for one pixel of one frame of one pass (`rng_for`).
    pub fn new(pixel: (u32, u32), frame_index: u32, salt: u32, seed: u32) -> Rng {
        let mut h = pcg_hash(seed ^ 0x9e37_79b9);
        h = pcg_hash(h ^ salt);
        h = pcg_hash(h ^ frame_index);
        h = pcg_hash(h ^ pixel.1);
        h = pcg_hash(h ^ pixel.0);
        Rng { state: h }
    }

    /// The next 32 random bits (PCG, as `rand_u32`).
    pub fn next_u32(&mut self) -> u32 {
        self.state = self.state.wrapping_mul(747796405).wrapping_add(2891336453);
        let s = self.state;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277803737);
        (word >> 22) ^ word
    }

    /// Uniform in [0, 1): 24 random bits (`rand_f32`).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16777216.0)
    }

    /// Two of them (`rand2`).
    pub fn next2(&mut self) -> Vec2 {
        let a = self.next_f32();
        let b = self.next_f32();
        Vec2::new(a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Low-discrepancy points for deterministic estimates.
    fn hammersley(i: u32, n: u32) -> Vec2 {
        Vec2::new((i as f32 + 0.5) / n as f32, i.reverse_bits() as f32 / 4294967296.0)
    }

    fn normals() -> Vec<Vec3> {
        let mut v = vec![Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
        v.push(Vec3::new(0.0, 1e-7, -1.0).normalize()); // near the n.z = -1 seam
        for i in 0..200 {
            let u = hammersley(i, 200);
            let z = 1.0 - 2.0 * u.x;
            let r = (1.0 - z * z).max(0.0).sqrt();
            v.push(Vec3::new(r * (2.0 * PI * u.y).cos(), r * (2.0 * PI * u.y).sin(), z));
        }
        v
    }

    #[test]
    fn basis_is_orthonormal_everywhere() {
        for n in normals() {
            let m = basis(n);
            for (a, b) in [(0, 1), (1, 2), (0, 2)] {
                assert!(m.col(a).dot(m.col(b)).abs() < 1e-5, "{n:?}");
            }
            for c in 0..3 {
                assert!((m.col(c).length() - 1.0).abs() < 1e-5, "{n:?}");
            }
            assert!((m.col(0).cross(m.col(1)) - n).length() < 1e-4, "not right-handed at {n:?}");
        }
    }

    #[test]
    fn cosine_samples_stay_in_the_hemisphere_with_the_right_mean() {
        for n in normals() {
            let count = 4096;
            let mut mean_cos = 0.0;
            for i in 0..count {
                let d = sample_cosine(n, hammersley(i, count));
                let c = d.dot(n);
                assert!(c >= -1e-6, "{n:?} {d:?}");
                mean_cos += c / count as f32;
            }
            // E[cos] under cos/pi is 2/3.
            assert!((mean_cos - 2.0 / 3.0).abs() < 2e-3, "{n:?}: {mean_cos}");
        }
    }

    /// A light of radius 1 at distance 1e4 (and smaller and farther): the
    /// cone pdf is finite and within 1e-3 relative of the exact value, and
    /// its samples stay inside the cone without all collapsing onto the axis.
    #[test]
    fn far_light_cone_does_not_cancel() {
        for (r, d) in [(1.0f32, 1e4f32), (1.0, 1e6), (1e-3, 1e3), (0.3, 0.31), (2.0, 1e5)] {
            let s = f64::from(r) / f64::from(d);
            let exact_omc = s * s / (1.0 + (1.0 - s * s).sqrt());
            let exact_pdf = 1.0 / (2.0 * std::f64::consts::PI * exact_omc);
            let pdf = cone_pdf(sphere_one_minus_cos(d, r));
            assert!(pdf.is_finite(), "r {r} d {d}: pdf {pdf}");
            let rel = (f64::from(pdf) - exact_pdf).abs() / exact_pdf;
            assert!(rel < 1e-3, "r {r} d {d}: pdf {pdf} vs {exact_pdf} ({rel:.2e})");
            let axis = Vec3::new(0.3, 0.9, -0.2).normalize();
            let mut off_axis = 0;
            for i in 0..256 {
                let dir = sample_cone(axis, sphere_one_minus_cos(d, r), hammersley(i, 256));
                assert!(dir.is_finite());
                // 1 - cos of the sample, measured in f64 against the axis.
                let cos = (dir.as_dvec3().dot(axis.as_dvec3()) / dir.as_dvec3().length()).min(1.0);
                assert!(1.0 - cos <= exact_omc * 1.01 + 1e-12, "r {r} d {d}: sample outside the cone");
                off_axis += usize::from(dir != axis);
            }
            assert!(off_axis > 128, "r {r} d {d}: samples collapse onto the axis");
        }
        // The cancelling form this replaced: 1 - cos_max is 0 at 1e4.
        assert_eq!(1.0 - sphere_cos_max(1e4, 1.0), 0.0);
    }

    /// Irradiance from a sphere light estimated by cone sampling equals the
    /// analytic pi L sin^2(theta_max) cos(theta) for a sphere above the horizon.
    #[test]
    fn cone_sampling_estimates_sphere_light_irradiance() {
        let (l, r) = (3.0f32, 0.3f32);
        for (d, tilt) in [(1.0f32, 0.0f32), (2.0, 0.5), (5.0, 1.0), (1.5, 0.9)] {
            let n = Vec3::Y;
            let axis = Vec3::new(tilt.sin(), tilt.cos(), 0.0);
            let cos_max = sphere_cos_max(d, r);
            let one_minus_cos = sphere_one_minus_cos(d, r);
            let count = 16384;
            let mut e = 0.0f64;
            for i in 0..count {
                let dir = sample_cone(axis, one_minus_cos, hammersley(i, count));
                assert!(dir.dot(axis) >= cos_max - 1e-5);
                e += f64::from(l * dir.dot(n).max(0.0) / cone_pdf(one_minus_cos)) / f64::from(count);
            }
            let exact = f64::from(PI * l * (r / d) * (r / d) * tilt.cos());
            assert!((e - exact).abs() / exact < 2e-3, "d {d} tilt {tilt}: {e} vs {exact}");
        }
    }

    #[test]
    fn pcg_hash_is_the_published_one() {
        // Reference values of pcg_hash (Jarzynski & Olano 2020).
        assert_eq!(pcg_hash(0), 129708002);
        assert_ne!(pcg_hash(1), pcg_hash(2));
    }
}
