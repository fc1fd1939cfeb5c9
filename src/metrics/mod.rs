//! Image error against a reference (FLIP via nv-flip, relMSE, PSNR) and
//! timing statistics.

use crate::gpu::readback::ImageF32;
use crate::image_io::to_srgb8;

/// FLIP's default viewing condition: 0.7 m from a 0.7 m wide 3840 px monitor.
pub const PIXELS_PER_DEGREE: f32 = 67.0;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlipStats {
    pub mean: f32,
    /// The 99th percentile of per-pixel error.
    pub p99: f32,
    pub max: f32,
}

/// LDR FLIP between two linear images (both sRGB-encoded and clamped first,
/// as they would be shown). Also returns the error map as magma RGB8.
pub fn flip(reference: &ImageF32, test: &ImageF32) -> (FlipStats, Vec<u8>) {
    let (w, h) = (reference.width, reference.height);
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &to_srgb8(reference));
    let t = nv_flip::FlipImageRgb8::with_data(w, h, &to_srgb8(test));
    let err = nv_flip::flip(r, t, PIXELS_PER_DEGREE);
    let mut pool = nv_flip::FlipPool::from_image(&err);
    let stats = FlipStats { mean: pool.mean(), p99: pool.get_percentile(0.99, false), max: pool.max_value() };
    let colored = err.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    (stats, colored)
}

/// Relative MSE: mean over pixels and channels of (x - y)^2 / (y^2 + eps).
pub fn rel_mse(reference: &ImageF32, test: &ImageF32) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for (r, t) in reference.data.iter().zip(&test.data) {
        for c in 0..3 {
            let (r, t) = (f64::from(r[c]), f64::from(t[c]));
            sum += (t - r) * (t - r) / (r * r + 1e-2);
            n += 1;
        }
    }
    sum / n.max(1) as f64
}

/// PSNR in dB over values clamped to [0, 1].
pub fn psnr(reference: &ImageF32, test: &ImageF32) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for (r, t) in reference.data.iter().zip(&test.data) {
        for c in 0..3 {
            let d = f64::from(r[c].clamp(0.0, 1.0)) - f64::from(t[c].clamp(0.0, 1.0));
            sum += d * d;
            n += 1;
        }
    }
    let mse = sum / n.max(1) as f64;
    if mse == 0.0 { f64::INFINITY } else { 10.0 * (1.0 / mse).log10() }
}

/// Median of a sample (NaN-free input); 0 for an empty one.
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 { v[m] } else { 0.5 * (v[m - 1] + v[m]) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_odd_even() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&[]), 0.0);
    }

    #[test]
    fn identical_images_have_no_error() {
        let mut a = ImageF32::new(16, 16);
        for (i, p) in a.data.iter_mut().enumerate() {
            *p = [(i % 7) as f32 / 7.0, 0.5, 0.25, 1.0];
        }
        let (s, _) = flip(&a, &a);
        assert_eq!(s.mean, 0.0);
        assert_eq!(rel_mse(&a, &a), 0.0);
        assert!(psnr(&a, &a).is_infinite());
        let mut b = a.clone();
        b.data[5] = [1.0, 0.0, 1.0, 1.0];
        assert!(flip(&a, &b).0.mean > 0.0);
    }
}
