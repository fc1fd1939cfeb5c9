//! The Rust mirror of `shaders/shared/mean.wgsl`: the Kahan-compensated
//! running mean behind accumulation, and the sample clean-up that keeps
//! NaN, Inf and negative radiance out of the history. The same f32
//! operations in the same order, so the CPU tests speak for the shader.

/// A running mean and the rounding error carried to its next update.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Mean {
    /// The mean so far, RGB.
    pub value: [f32; 3],
    /// Kahan compensation: the rounding error the next update takes back.
    pub comp: [f32; 3],
}

/// Adds `x` to a mean of `count` samples (`mean_add` in WGSL; Rust does
/// not reassociate floats, so the WGSL's opaque `one` is not needed here).
pub fn mean_add(m: Mean, x: [f32; 3], count: u32) -> Mean {
    let n = (count + 1) as f32;
    let mut out = m;
    for (c, xc) in x.iter().enumerate() {
        let y = (xc - m.value[c]) / n - m.comp[c];
        let t = m.value[c] + y;
        out.value[c] = t;
        out.comp[c] = (t - m.value[c]) - y;
    }
    out
}

/// Whether every component is finite, by bits (`all_finite` in WGSL).
pub fn all_finite(v: [f32; 3]) -> bool {
    v.iter().all(|x| x.to_bits() & 0x7f80_0000 != 0x7f80_0000)
}

/// The sample to accumulate, or None when it holds NaN or Inf
/// (`clean_sample` in WGSL): negatives become 0, and with `clamp_max` > 0
/// a sample whose largest component exceeds it is scaled down to it.
pub fn clean_sample(x: [f32; 3], clamp_max: f32) -> Option<[f32; 3]> {
    if !all_finite(x) {
        return None;
    }
    let mut v = x.map(|c| c.max(0.0));
    let m = v[0].max(v[1]).max(v[2]);
    if clamp_max > 0.0 && m > clamp_max {
        let s = clamp_max / m;
        v = v.map(|c| c * s);
    }
    Some(v)
}

/// The known sequence the accumulation tests add (`test_mean.wgsl` draws
/// the same one): sample `k` of pixel `p`, in [0.5, 1.5) and [3, 4).
pub fn test_sequence(p: u32, k: u32) -> [f32; 3] {
    let a = (k.wrapping_mul(7919).wrapping_add(p.wrapping_mul(104_729))) % 1000;
    let b = (k.wrapping_mul(31).wrapping_add(p)) % 977;
    [a as f32 * 0.001 + 0.5, b as f32 * 0.001 + 3.0, (a ^ b) as f32 * 0.0005 + 0.25]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f32, b: f64) -> f64 {
        ((f64::from(a) - b) / b).abs()
    }

    #[test]
    fn a_million_samples_stay_within_1e_6_of_the_exact_mean() {
        let n = 1_000_000u32;
        let mut m = Mean::default();
        let mut plain = [0.0f32; 3];
        let mut exact = [0.0f64; 3];
        for k in 0..n {
            let x = test_sequence(3, k);
            m = mean_add(m, x, k);
            for c in 0..3 {
                plain[c] += (x[c] - plain[c]) / (k + 1) as f32;
                exact[c] += f64::from(x[c]);
            }
        }
        let exact = exact.map(|s| s / f64::from(n));
        let err = (0..3).map(|c| rel(m.value[c], exact[c])).fold(0.0, f64::max);
        let plain_err = (0..3).map(|c| rel(plain[c], exact[c])).fold(0.0, f64::max);
        eprintln!("1e6 samples: compensated mean error {err:.2e}, plain running mean {plain_err:.2e}");
        assert!(err <= 1e-6, "compensated mean drifted by {err}");
        // The test can tell: without the compensation the mean drifts.
        assert!(plain_err > 1e-6, "the plain mean was already exact ({plain_err}): the test cannot fail");
    }

    #[test]
    fn bad_samples_are_kept_out() {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::from_bits(0x7fc0_0001)] {
            assert_eq!(clean_sample([1.0, bad, 0.5], 0.0), None);
        }
        assert_eq!(clean_sample([-1.0, 1e30, 2.0], 0.0), Some([0.0, 1e30, 2.0]));
        assert_eq!(clean_sample([8.0, 4.0, 2.0], 2.0), Some([2.0, 1.0, 0.5]));
        assert_eq!(clean_sample([1.0, 0.5, 0.0], 2.0), Some([1.0, 0.5, 0.0]));
        assert!(all_finite([f32::MAX, -f32::MAX, f32::MIN_POSITIVE / 2.0]));
    }
}
