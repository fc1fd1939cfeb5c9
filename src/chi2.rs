//! Chi-square goodness-of-fit tests of the direction samplers, on the Rust
//! mirror (src/sampling.rs), in the manner of pbrt-v4's `bsdfs_test.cpp`
//! and Mitsuba 3's `chi2.py`: about 1e6 samples binned on a grid of
//! directions; expected counts from the pdf integrated over each cell;
//! cells expecting fewer than 5 samples pooled; a sample in a cell the pdf
//! gives zero fails outright; the p-value from the chi-square distribution,
//! against alpha = 0.01 with a Sidak correction for the number of tests.

use glam::Vec3;

/// A grid over the sphere: `rows` bands of equal height in cos(theta) over
/// [-1, 1] (equal solid angle) by `cols` sectors in phi.
#[derive(Debug, Clone, Copy)]
pub struct Grid {
    pub rows: usize,
    pub cols: usize,
}

impl Grid {
    pub fn cells(&self) -> usize {
        self.rows * self.cols
    }

    pub fn cell_of(&self, d: Vec3) -> usize {
        let z = f64::from(d.z / d.length()).clamp(-1.0, 1.0);
        let row = (((z + 1.0) * 0.5 * self.rows as f64) as usize).min(self.rows - 1);
        let mut phi = f64::from(d.y).atan2(f64::from(d.x));
        if phi < 0.0 {
            phi += std::f64::consts::TAU;
        }
        let col = ((phi / std::f64::consts::TAU * self.cols as f64) as usize).min(self.cols - 1);
        row * self.cols + col
    }

    /// Expected counts of `n` samples from solid-angle pdf `pdf`: the pdf
    /// integrated over each cell by the midpoint rule on `sub` x `sub`
    /// points (dω = d(cos θ) dφ).
    pub fn expected(&self, n: usize, sub: usize, pdf: impl Fn(Vec3) -> f64) -> Vec<f64> {
        let dz = 2.0 / self.rows as f64;
        let dphi = std::f64::consts::TAU / self.cols as f64;
        let mut e = vec![0.0; self.cells()];
        for row in 0..self.rows {
            for col in 0..self.cols {
                let mut sum = 0.0;
                for i in 0..sub {
                    for j in 0..sub {
                        let z = -1.0 + dz * (row as f64 + (i as f64 + 0.5) / sub as f64);
                        let phi = dphi * (col as f64 + (j as f64 + 0.5) / sub as f64);
                        let s = (1.0 - z * z).max(0.0).sqrt();
                        sum += pdf(Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32));
                    }
                }
                e[row * self.cols + col] = n as f64 * sum * dz * dphi / (sub * sub) as f64;
            }
        }
        e
    }
}

/// The result of one test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    pub chi2: f64,
    pub dof: usize,
    pub p_value: f64,
    /// Samples that fell in cells the pdf gives (next to) nothing.
    pub in_zero_cells: u64,
}

/// Pearson's test of observed against expected counts. Cells expecting
/// fewer than 5 are pooled (smallest first) until the pool reaches 5;
/// samples in cells expecting less than 1e-9 of a sample make p = 0.
pub fn test(observed: &[u64], expected: &[f64]) -> Outcome {
    let mut cells: Vec<(f64, u64)> = expected.iter().copied().zip(observed.iter().copied()).collect();
    let in_zero_cells: u64 = cells.iter().filter(|(e, _)| *e < 1e-9).map(|(_, o)| o).sum();
    cells.retain(|(e, _)| *e >= 1e-9);
    cells.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut chi2, mut bins) = (0.0, 0usize);
    let (mut pool_e, mut pool_o) = (0.0, 0u64);
    for (e, o) in cells {
        if e < 5.0 || pool_e > 0.0 && pool_e < 5.0 {
            pool_e += e;
            pool_o += o;
            if pool_e < 5.0 {
                continue;
            }
            let d = pool_o as f64 - pool_e;
            chi2 += d * d / pool_e;
            bins += 1;
            (pool_e, pool_o) = (0.0, 0);
            continue;
        }
        let d = o as f64 - e;
        chi2 += d * d / e;
        bins += 1;
    }
    if pool_e > 0.0 {
        let d = pool_o as f64 - pool_e;
        chi2 += d * d / pool_e;
        bins += 1;
    }
    let dof = bins.saturating_sub(1).max(1);
    let p_value = if in_zero_cells > 0 { 0.0 } else { gamma_q(dof as f64 / 2.0, chi2 / 2.0) };
    Outcome { chi2, dof, p_value, in_zero_cells }
}

/// The per-test significance for `tests` tests at overall level `alpha`.
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests as f64)
}

fn ln_gamma(x: f64) -> f64 {
    // Lanczos (g = 7, n = 9).
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let mut a = C[0];
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised upper incomplete gamma function Q(a, x): the chi-square
/// distribution's survival function at 2x with 2a degrees of freedom.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let ln_front = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        // Series for P, then Q = 1 - P.
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (1.0 - sum * ln_front.exp()).clamp(0.0, 1.0)
    } else {
        // Continued fraction (modified Lentz).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (ln_front.exp() * h).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{basis, glossy_pdf, sample_cone, sample_cosine, sample_glossy, sphere_one_minus_cos, Rng, PI};
    use glam::{DVec3, Vec2};

    const SAMPLES: usize = 1_000_000;
    /// Cosine normals, cones and glossy lobes: the tests this module runs,
    /// for Sidak.
    const TESTS: usize = 16;

    #[test]
    fn gamma_q_matches_known_values() {
        // chi-square survival: Q(k/2, x/2).
        let cases = [(1.0, 3.841_458_820_694_124, 0.05), (10.0, 18.307_038_053_275_14, 0.05), (100.0, 135.806_723_550_06, 0.01), (4.0, 0.297_107_463_471_747_2, 0.99)];
        for (k, x, p) in cases {
            let q = gamma_q(k / 2.0, x / 2.0);
            assert!((q - p).abs() < 1e-6, "Q({k}/2, {x}/2) = {q}, want {p}");
        }
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    }

    fn draws(seed: u32) -> impl Iterator<Item = Vec2> {
        (0..SAMPLES as u32).map(move |i| Rng::new((i & 0xffff, i >> 16), 0, 0xc41, seed).next2())
    }

    fn observed(grid: Grid, samples: impl Iterator<Item = Vec3>) -> Vec<u64> {
        let mut o = vec![0u64; grid.cells()];
        for d in samples {
            o[grid.cell_of(d)] += 1;
        }
        o
    }

    fn cosine_outcome(n: Vec3, sampler: impl Fn(Vec3, Vec2) -> Vec3) -> Outcome {
        let grid = Grid { rows: 20, cols: 40 };
        let o = observed(grid, draws(7).map(|u| sampler(n, u)));
        let e = grid.expected(SAMPLES, 8, |d| f64::from(d.dot(n).max(0.0)) / std::f64::consts::PI);
        test(&o, &e)
    }

    #[test]
    fn cosine_hemisphere_passes_chi_square() {
        let level = sidak(0.01, TESTS);
        for n in [Vec3::Z, Vec3::NEG_Z, Vec3::new(1.0, 2.0, 3.0).normalize(), Vec3::new(0.01, -0.3, -0.95).normalize()] {
            let r = cosine_outcome(n, sample_cosine);
            eprintln!("cosine hemisphere around {n:?}: chi2 {:.1}, dof {}, p {:.4}", r.chi2, r.dof, r.p_value);
            assert_eq!(r.in_zero_cells, 0, "{n:?}: samples below the horizon");
            assert!(r.p_value > level, "{n:?}: p {} <= {level}", r.p_value);
        }
        // A wrong sampler (uniform in cos instead of in cos^2) fails.
        let wrong = |n: Vec3, u: Vec2| {
            let (c, phi) = (u.x, 2.0 * PI * u.y);
            let s = (1.0 - c * c).max(0.0).sqrt();
            (basis(n) * Vec3::new(s * phi.cos(), s * phi.sin(), c)).normalize()
        };
        let r = cosine_outcome(Vec3::Z, wrong);
        assert!(r.p_value < 1e-6, "the test cannot tell a wrong sampler: p {}", r.p_value);
    }

    /// The cone in its own frame: u = (1 - cos θ) / (1 - cos θmax) in
    /// [0, 1] is uniform, as is φ, for a uniform cone; a sample with u > 1
    /// lies outside it (a zero-pdf cell). This resolves cones too narrow for
    /// a grid over the whole sphere (a light of radius 1 at 1e4).
    fn cone_outcome(axis: Vec3, one_minus_cos: f32, sampler: impl Fn(Vec3, f32, Vec2) -> Vec3) -> Outcome {
        let (rows, cols) = (20usize, 40usize);
        let frame = basis(axis).transpose();
        let mut o = vec![0u64; rows * cols + 1];
        for u in draws(11) {
            let d = sampler(axis, one_minus_cos, u);
            let l = (frame * d).as_dvec3().normalize();
            let v = (1.0 - l.z) / f64::from(one_minus_cos);
            if v > 1.0 + 1e-3 {
                o[rows * cols] += 1;
                continue;
            }
            let row = ((v * rows as f64) as usize).min(rows - 1);
            let mut phi = l.y.atan2(l.x);
            if phi < 0.0 {
                phi += std::f64::consts::TAU;
            }
            let col = ((phi / std::f64::consts::TAU * cols as f64) as usize).min(cols - 1);
            o[row * cols + col] += 1;
        }
        let mut e = vec![SAMPLES as f64 / (rows * cols) as f64; rows * cols];
        e.push(0.0);
        test(&o, &e)
    }

    #[test]
    fn sphere_light_cone_passes_chi_square() {
        let level = sidak(0.01, TESTS);
        let axis = Vec3::new(-0.2, 0.5, 0.84).normalize();
        for (r, d) in [(0.3f32, 0.31f32), (0.3, 1.0), (0.15, 3.0), (1.0, 1e4)] {
            let omc = sphere_one_minus_cos(d, r);
            let out = cone_outcome(axis, omc, sample_cone);
            eprintln!("cone r {r} d {d} (1 - cos {omc:.3e}): chi2 {:.1}, dof {}, p {:.4}", out.chi2, out.dof, out.p_value);
            assert_eq!(out.in_zero_cells, 0, "r {r} d {d}: samples outside the cone");
            assert!(out.p_value > level, "r {r} d {d}: p {} <= {level}", out.p_value);
        }
        // The cancelling form it replaced: at 1e4 every sample sits on the
        // axis, which the test sees.
        let collapsed = |axis: Vec3, omc: f32, u: Vec2| {
            let cos_t = 1.0 - u.x * (1.0 - (1.0 - omc));
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            (basis(axis) * Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)).normalize()
        };
        let out = cone_outcome(axis, sphere_one_minus_cos(1e4, 1.0), collapsed);
        assert!(out.p_value < 1e-6, "the test cannot tell a collapsed cone: p {}", out.p_value);
    }

    /// The glossy lobe binned about `r`: rows by angle from r up to the
    /// lobe's edge theta_max (roughness < 1/2: sin theta_max = roughness /
    /// (1 - roughness); else the whole sphere), spaced so that theta =
    /// theta_max (1 - (1 - s)^2) for rows uniform in s. Near a narrow
    /// lobe's edge the pdf grows like 1 / sqrt(theta_max - theta); in s the
    /// integrand is smooth, so the midpoint rule gets the expected counts
    /// right (on a grid of cos theta it did not: chi2 6217 on 68 dof at
    /// grazing incidence). A sample past the edge lands in a zero-pdf cell.
    fn glossy_outcome(n: Vec3, r: Vec3, roughness: f32, sampler: impl Fn(Vec3, Vec3, f32, Vec2) -> Vec3) -> Outcome {
        let (rows, cols, sub) = (40usize, 80usize, 16usize);
        let rough = f64::from(roughness);
        let theta_max = if rough < 0.5 { (rough / (1.0 - rough)).asin() } else { std::f64::consts::PI };
        let to_world = basis(r).as_dmat3();
        let to_local = to_world.transpose();
        let tau = std::f64::consts::TAU;
        let mut o = vec![0u64; rows * cols + 1];
        for u in draws(13) {
            let l = (to_local * sampler(r, n, roughness, u).as_dvec3()).normalize();
            let theta = l.z.clamp(-1.0, 1.0).acos();
            if theta > theta_max * (1.0 + 1e-4) {
                o[rows * cols] += 1;
                continue;
            }
            let s = 1.0 - (1.0 - (theta / theta_max).min(1.0)).sqrt();
            let row = ((s * rows as f64) as usize).min(rows - 1);
            let phi = l.y.atan2(l.x).rem_euclid(tau);
            let col = ((phi / tau * cols as f64) as usize).min(cols - 1);
            o[row * cols + col] += 1;
        }
        let (n64, r64) = (n.as_dvec3(), r.as_dvec3());
        let (ds, dphi) = (1.0 / rows as f64, tau / cols as f64);
        let mut e = vec![0.0; rows * cols + 1];
        for row in 0..rows {
            for col in 0..cols {
                let mut sum = 0.0;
                for i in 0..sub {
                    for j in 0..sub {
                        let s = ds * (row as f64 + (i as f64 + 0.5) / sub as f64);
                        let phi = dphi * (col as f64 + (j as f64 + 0.5) / sub as f64);
                        let theta = theta_max * (1.0 - (1.0 - s) * (1.0 - s));
                        let dtheta_ds = 2.0 * theta_max * (1.0 - s);
                        let l = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                        sum += glossy_pdf(r64, n64, rough, to_world * l) * theta.sin() * dtheta_ds;
                    }
                }
                e[row * cols + col] = SAMPLES as f64 * sum * ds * dphi / (sub * sub) as f64;
            }
        }
        test(&o, &e)
    }

    #[test]
    fn glossy_pdf_integrates_to_one() {
        let n = DVec3::new(0.1, 0.3, 0.95).normalize();
        for (incident, roughness) in [(0.2, 0.25), (1.3, 0.25), (0.2, 0.5), (1.3, 0.75), (0.7, 1.0)] {
            let r = reflected(n.as_vec3(), incident).as_dvec3();
            let grid = Grid { rows: 200, cols: 400 };
            let total: f64 = grid.expected(1, 8, |l| glossy_pdf(r, n, roughness, (basis(n.as_vec3()) * l).as_dvec3().normalize())).iter().sum();
            assert!((total - 1.0).abs() < 5e-3, "incident {incident} roughness {roughness}: integral {total}");
        }
        // roughness 1 is the cosine lobe.
        let d = DVec3::new(0.3, -0.2, 0.9).normalize();
        assert!((glossy_pdf(DVec3::Z, n, 1.0, d) - d.dot(n) / std::f64::consts::PI).abs() < 1e-12);
    }

    /// The mirror direction of a ray arriving at `theta` radians from `n`.
    fn reflected(n: Vec3, theta: f32) -> Vec3 {
        let (t, _) = n.any_orthonormal_pair();
        let incoming = -(n * theta.cos() + t * theta.sin());
        incoming - 2.0 * incoming.dot(n) * n
    }

    #[test]
    fn glossy_lobe_passes_chi_square() {
        let level = sidak(0.01, TESTS);
        let n = Vec3::new(0.1, 0.3, 0.95).normalize();
        // Near-normal and grazing incidence; narrow (two preimages of a
        // direction, a cone about r) to wide (one preimage) lobes.
        for (incident, roughness) in [(0.2f32, 0.25f32), (1.3, 0.25), (0.2, 0.5), (1.3, 0.5), (0.2, 0.75), (1.3, 0.75), (0.7, 0.9), (1.5, 1.0)] {
            let r = reflected(n, incident);
            let out = glossy_outcome(n, r, roughness, sample_glossy);
            eprintln!("glossy lobe, incidence {incident} rad, roughness {roughness}: chi2 {:.1}, dof {}, p {:.4}", out.chi2, out.dof, out.p_value);
            assert_eq!(out.in_zero_cells, 0, "incidence {incident} roughness {roughness}: samples where the pdf is 0");
            assert!(out.p_value > level, "incidence {incident} roughness {roughness}: p {} <= {level}", out.p_value);
        }
        // A plausible mistake, blending toward a uniform hemisphere
        // direction instead of a cosine one, fails.
        let uniform = |r: Vec3, n: Vec3, roughness: f32, u: Vec2| {
            let (c, phi) = (u.x, 2.0 * PI * u.y);
            let s = (1.0 - c * c).max(0.0).sqrt();
            let h = basis(n) * Vec3::new(s * phi.cos(), s * phi.sin(), c);
            (r * (1.0 - roughness) + h * roughness).normalize()
        };
        let out = glossy_outcome(n, reflected(n, 0.7), 0.75, uniform);
        assert!(out.p_value < 1e-6, "the test cannot tell a wrong glossy sampler: p {}", out.p_value);
    }
}
