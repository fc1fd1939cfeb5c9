//! Image error against a reference (FLIP via nv-flip, relMSE, PSNR) and
//! timing statistics.

use crate::gpu::readback::ImageF32;
use crate::image_io::to_srgb8;

/// FLIP's default viewing condition: 0.7 m from a 0.7 m wide 3840 px monitor.
pub const PIXELS_PER_DEGREE: f32 = 67.0;

/// FLIP error over an image (0: identical, 1: most different).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlipStats {
    /// Mean per-pixel error.
    pub mean: f32,
    /// The 99th percentile of per-pixel error.
    pub p99: f32,
    /// Largest per-pixel error.
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

/// How many pixels of `img` hold a NaN or infinite colour value, and the
/// first of them (x, y); `None` when all are finite.
pub fn non_finite(img: &ImageF32) -> Option<(usize, u32, u32)> {
    let bad = |p: &[f32; 4]| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite());
    let first = img.data.iter().position(bad)?;
    let count = img.data.iter().filter(|p| bad(p)).count();
    let w = img.width.max(1) as usize;
    Some((count, (first % w) as u32, (first / w) as u32))
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

/// Relative error of `test` against `reference` after averaging both over
/// `block`x`block` pixel blocks, per channel: |t - r| / max(r, floor).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockError {
    /// Mean over blocks and channels.
    pub mean: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Largest.
    pub max: f64,
    /// Mean luminance of test over reference.
    pub luminance_ratio: f64,
}

/// The `BlockError` of `test` against `reference` over `block`x`block` blocks
/// (whole blocks only); `floor` keeps dark references from dividing by nearly 0.
pub fn block_relative_error(reference: &ImageF32, test: &ImageF32, block: u32, floor: f64) -> BlockError {
    let block = block.max(1);
    let (bw, bh) = (reference.width / block, reference.height / block);
    let mut errs = Vec::new();
    let average = |img: &ImageF32, bx: u32, by: u32, c: usize| {
        let mut sum = 0.0;
        for y in by * block..(by + 1) * block {
            for x in bx * block..(bx + 1) * block {
                sum += f64::from(img.get(x, y)[c]);
            }
        }
        sum / f64::from(block * block)
    };
    for by in 0..bh {
        for bx in 0..bw {
            for c in 0..3 {
                let (r, t) = (average(reference, bx, by, c), average(test, bx, by, c));
                errs.push((t - r).abs() / r.max(floor));
            }
        }
    }
    let lum = |img: &ImageF32| img.data.iter().map(|p| 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])).sum::<f64>();
    errs.sort_by(f64::total_cmp);
    let n = errs.len().max(1);
    BlockError {
        mean: errs.iter().sum::<f64>() / n as f64,
        p95: errs.get(((n as f64 * 0.95) as usize).min(n - 1)).copied().unwrap_or(0.0),
        max: errs.last().copied().unwrap_or(0.0),
        luminance_ratio: lum(test) / lum(reference).max(1e-30),
    }
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

/// Runs of A and B timed in turn, pair by pair: the median of the ratios
/// a / b and their range; None without a pair.
pub fn paired_ratios(a: &[f64], b: &[f64]) -> Option<(f64, f64, f64)> {
    let ratios: Vec<f64> = a.iter().zip(b).map(|(x, y)| x / y).collect();
    if ratios.is_empty() {
        return None;
    }
    let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Some((median(&ratios), lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paired_ratios_take_the_median_and_range_pair_by_pair() {
        assert_eq!(paired_ratios(&[2.0, 3.0, 8.0], &[1.0, 3.0, 4.0]), Some((2.0, 1.0, 2.0)));
        // Pairs only: the longer side's extra runs are left out.
        assert_eq!(paired_ratios(&[1.0, 9.0], &[2.0]), Some((0.5, 0.5, 0.5)));
        assert_eq!(paired_ratios(&[], &[1.0]), None);
    }

    #[test]
    fn median_odd_even() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&[]), 0.0);
    }

    #[test]
    fn block_error_of_a_scaled_image() {
        let mut a = ImageF32::new(16, 16);
        for p in &mut a.data {
            *p = [0.5, 0.25, 1.0, 1.0];
        }
        let mut b = a.clone();
        for p in &mut b.data {
            for c in p.iter_mut().take(3) {
                *c *= 1.1;
            }
        }
        let e = block_relative_error(&a, &b, 8, 0.01);
        assert!((e.mean - 0.1).abs() < 1e-6 && (e.max - 0.1).abs() < 1e-6, "{e:?}");
        assert!((e.luminance_ratio - 1.1).abs() < 1e-6);
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
