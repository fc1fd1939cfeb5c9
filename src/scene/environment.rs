//! An environment light (docs/scenes.md, "Environment"): radiance that
//! arrives from infinitely far away, a latitude-longitude map (or one
//! colour) turned about the vertical axis, importance-sampled by a
//! piecewise-constant distribution over the map (pbrt-v4's
//! `PiecewiseConstant2D`, Mitsuba's `envmap`): a row by the marginal
//! distribution, a texel within it by the row's conditional one, each
//! texel weighted by the luminance the bilinear filter averages over it,
//! times sin(theta) at its centre.
//!
//! This is the Rust mirror of shaders/shared/environment.wgsl: the same
//! mapping, layout and search, so the sampler is tested here (chi-square,
//! src/chi2.rs) and on the GPU against this.
//!
//! Mapping (Mitsuba 3's): u = atan2(x, -z) / 2 pi (wrapped to [0, 1)),
//! v = acos(y) / pi, texel rows from the top (v = 0, straight up).

use glam::{Vec2, Vec3};

use super::gpu_types::{LightGpu, LIGHT_ENVIRONMENT};
use crate::brdf::luminance;
use crate::sampling::PI;

/// Maps wider or taller than this are halved (box filter) until they fit:
/// a sampling table per texel costs memory and search steps, lighting needs
/// no finer, and the map and its tables then always fit their texture.
pub const MAX_WIDTH: u32 = 2048;

/// The size of the map a constant colour becomes: fine enough that the
/// sin(theta) weights make sampling close to uniform over the sphere.
const CONSTANT_SIZE: [u32; 2] = [32, 16];

/// A loaded environment light.
#[derive(Debug, Clone, PartialEq)]
pub struct Environment {
    /// Texels across (u).
    pub width: u32,
    /// Rows (v), the first straight up.
    pub height: u32,
    /// Radiance per texel, linear RGB, rows first, times the intensity.
    pub radiance: Vec<Vec3>,
    /// Turn about +y, radians: the map's direction d shows in world
    /// direction R_y(rotation) d.
    pub rotation: f32,
    /// The sampling density in (u, v) of each texel (integrates to 1).
    pdf: Vec<f32>,
    /// Each row's conditional CDF, the value at the end of each texel
    /// (the last of a row exactly 1).
    conditional: Vec<f32>,
    /// The marginal CDF over rows, at the end of each row.
    marginal: Vec<f32>,
}

impl Environment {
    /// One colour from every direction.
    pub fn constant(radiance: Vec3, rotation: f32) -> Environment {
        let [w, h] = CONSTANT_SIZE;
        Environment::from_texels(w, h, vec![radiance; (w * h) as usize], rotation)
    }

    /// A `width x height` map (rows from the top), already scaled by the
    /// intensity; texels must be finite and non-negative (the loader
    /// checks). Wider or taller than `MAX_WIDTH`: halved until it fits.
    pub fn from_texels(width: u32, height: u32, radiance: Vec<Vec3>, rotation: f32) -> Environment {
        let (mut w, mut h, mut texels) = (width.max(1), height.max(1), radiance);
        while w > MAX_WIDTH || h > MAX_WIDTH {
            (w, h, texels) = halve(w, h, &texels);
        }
        // Each texel weighs what the bilinear radiance averages over it:
        // (1/8, 3/4, 1/8) of its row's and column's neighbours (wrapping
        // across, clamped at the poles). Weighting the texel alone left the
        // halo a bright texel spreads into its neighbours with their small
        // pdf: fireflies around a small sun.
        let lum: Vec<f64> = texels.iter().map(|c| f64::from(luminance(*c).max(0.0))).collect();
        let (wi, hi) = (i64::from(w), i64::from(h));
        let at = |x: i64, y: i64| lum[(y.clamp(0, hi - 1) * wi + x.rem_euclid(wi)) as usize];
        let taps = [(-1i64, 0.125f64), (0, 0.75), (1, 0.125)];
        let mut weights = vec![0.0f64; texels.len()];
        for y in 0..hi {
            let sin_theta = f64::from((PI * (y as f32 + 0.5) / h as f32).sin());
            for x in 0..wi {
                let mut sum = 0.0;
                for (dy, wy) in taps {
                    for (dx, wx) in taps {
                        sum += wy * wx * at(x + dx, y + dy);
                    }
                }
                weights[(y * wi + x) as usize] = sum * sin_theta;
            }
        }
        // A black map still needs a distribution (its samples carry no
        // light): sin(theta) alone, uniform over the sphere.
        if weights.iter().all(|&x| x <= 0.0) {
            for y in 0..h {
                let sin_theta = f64::from((PI * (y as f32 + 0.5) / h as f32).sin());
                weights[(y * w) as usize..((y + 1) * w) as usize].fill(sin_theta);
            }
        }
        let total: f64 = weights.iter().sum();
        let cells = f64::from(w) * f64::from(h);
        let pdf = weights.iter().map(|&x| (x / total * cells) as f32).collect();
        let mut conditional = Vec::with_capacity(texels.len());
        let mut row_sums = Vec::with_capacity(h as usize);
        for row in weights.chunks_exact(w as usize) {
            let sum: f64 = row.iter().sum();
            row_sums.push(sum);
            conditional.extend(cdf(row, sum));
        }
        let marginal = cdf(&row_sums, total);
        Environment { width: w, height: h, radiance: texels, rotation, pdf, conditional, marginal }
    }

    /// Its size on the GPU, for `graph check` and `render`: the map and
    /// its sampling tables.
    pub fn describe(&self) -> String {
        format!("{}x{}, {:.1} MiB with its sampling tables", self.width, self.height, (self.texel_count() * 16) as f64 / 1048576.0)
    }

    /// How many texels `texels` writes: the map, each row's CDF in whole
    /// texels, the marginal CDF.
    fn texel_count(&self) -> usize {
        self.radiance.len() + self.width.div_ceil(4) as usize * self.height as usize + self.height.div_ceil(4) as usize
    }

    /// The light record: `position` (width, height, rotation), colour the
    /// mean radiance (what the path's light choice weighs the environment
    /// by, shaders/shared/light_choice.wgsl; its own light comes from the
    /// map).
    pub fn light_gpu(&self) -> LightGpu {
        LightGpu {
            position: [self.width as f32, self.height as f32, self.rotation],
            radius: 0.0,
            color: self.mean_radiance().to_array(),
            kind: LIGHT_ENVIRONMENT,
            spot: [0.0, 0.0, 0.0, 1.0],
        }
    }

    /// The radiance averaged over the sphere of directions (each row
    /// weighed by the solid angle it covers).
    pub fn mean_radiance(&self) -> Vec3 {
        let (mut sum, mut weight) = (Vec3::ZERO, 0.0f32);
        for (y, row) in self.radiance.chunks_exact(self.width as usize).enumerate() {
            let sin_theta = (PI * (y as f32 + 0.5) / self.height as f32).sin();
            sum += row.iter().copied().sum::<Vec3>() * sin_theta;
            weight += sin_theta * self.width as f32;
        }
        if weight > 0.0 { sum / weight } else { Vec3::ZERO }
    }

    /// The `scene_environment` texels: per texel (r, g, b, pdf) as f32
    /// bits, rows first; then each row's conditional CDF, four values a
    /// texel, rows padded to whole texels; then the marginal CDF, four a
    /// texel.
    pub fn texels(&self) -> Vec<[u32; 4]> {
        let mut out = Vec::with_capacity(self.texel_count());
        for (c, p) in self.radiance.iter().zip(&self.pdf) {
            out.push([c.x.to_bits(), c.y.to_bits(), c.z.to_bits(), p.to_bits()]);
        }
        for row in self.conditional.chunks_exact(self.width as usize) {
            out.extend(pack4(row));
        }
        out.extend(pack4(&self.marginal));
        out
    }

    /// The texel direction `dir` (unit, world) falls in.
    fn texel_of(&self, dir: Vec3) -> usize {
        let uv = uv_of(dir, self.rotation);
        let x = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        (y * self.width + x) as usize
    }

    /// The radiance seen looking along `dir`: bilinear between texel
    /// centres, wrapping across u, clamped in v (as Mitsuba's `envmap`).
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        let p = uv_of(dir, self.rotation) * Vec2::new(w as f32, h as f32) - 0.5;
        let f = p.floor();
        let t = p - f;
        let at = |x: i64, y: i64| self.radiance[(y.clamp(0, h - 1) * w + x.rem_euclid(w)) as usize];
        let (x, y) = (f.x as i64, f.y as i64);
        let top = at(x, y).lerp(at(x + 1, y), t.x);
        let bottom = at(x, y + 1).lerp(at(x + 1, y + 1), t.x);
        top.lerp(bottom, t.y)
    }

    /// The solid-angle pdf `sample` draws `dir` with.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let sin_theta = (1.0 - (dir.y * dir.y).min(1.0)).sqrt();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.pdf[self.texel_of(dir)] / (2.0 * PI * PI * sin_theta)
    }

    /// A direction drawn with density `pdf`, from `u` in [0, 1)^2, and
    /// that pdf.
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let (row, dv) = search(&self.marginal, u.y);
        let w = self.width as usize;
        let (col, du) = search(&self.conditional[row * w..(row + 1) * w], u.x);
        let uv = Vec2::new((col as f32 + du) / self.width as f32, (row as f32 + dv) / self.height as f32);
        let dir = dir_of(uv, self.rotation);
        let sin_theta = (PI * uv.y).sin();
        let pdf = if sin_theta > 0.0 { self.pdf[row * w + col] / (2.0 * PI * PI * sin_theta) } else { 0.0 };
        (dir, pdf)
    }
}

/// Reads a latitude-longitude map (EXR or PFM, linear) for an
/// environment; `scale` multiplies it. A texel that is not finite is an
/// error. Negative components are clamped to 0: real HDR files carry a
/// few, small, from their compression (Blender's studio HDRIs down to 2.4%
/// of their mean luminance); one below -5% of the mean is worth a warning,
/// returned with the map.
pub fn load_map(path: &std::path::Path, scale: Vec3, rotation: f32) -> Result<(Environment, Option<String>), String> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("exr" | "pfm")) {
        return Err("an environment map must be an .exr or .pfm file (linear radiance, latitude-longitude)".into());
    }
    let img = crate::image_io::load(path).map_err(|e| e.to_string())?;
    let mut texels = Vec::with_capacity(img.data.len());
    let (mut clamped, mut lowest, mut sum) = (0usize, 0.0f32, 0.0f64);
    for (i, p) in img.data.iter().enumerate() {
        let c = Vec3::new(p[0], p[1], p[2]);
        if !c.is_finite() {
            let (x, y) = (i as u32 % img.width, i as u32 / img.width);
            return Err(format!("texel ({x}, {y}) (from the top left) is {c}: radiance must be finite"));
        }
        clamped += usize::from(c.min_element() < 0.0);
        lowest = lowest.min(c.min_element());
        sum += f64::from(luminance(c.max(Vec3::ZERO)));
        texels.push(c.max(Vec3::ZERO) * scale);
    }
    let mean = sum / texels.len().max(1) as f64;
    let note = (f64::from(lowest) < -0.05 * mean)
        .then(|| format!("{clamped} texel(s) with negative components (down to {lowest}, the map's mean luminance is {mean:.4}) clamped to 0"));
    Ok((Environment::from_texels(img.width, img.height, texels, rotation), note))
}

/// The CDF at the end of each cell of `weights` (summing to `sum`), the
/// last exactly 1; all zero weights: uniform.
fn cdf(weights: &[f64], sum: f64) -> Vec<f32> {
    let n = weights.len();
    let mut acc = 0.0;
    let mut out: Vec<f32> = weights
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            acc += x;
            if sum > 0.0 {
                (acc / sum) as f32
            } else {
                (i + 1) as f32 / n as f32
            }
        })
        .collect();
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
    out
}

/// The first cell whose CDF value exceeds `u` (a cell of zero weight is
/// never chosen) and where `u` falls within it, in [0, 1).
fn search(cdf: &[f32], u: f32) -> (usize, f32) {
    let (mut lo, mut hi) = (0usize, cdf.len() - 1);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if cdf[mid] > u {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    let start = if lo == 0 { 0.0 } else { cdf[lo - 1] };
    let width = cdf[lo] - start;
    let t = if width > 0.0 { ((u - start) / width).clamp(0.0, 0.99999994) } else { 0.5 };
    (lo, t)
}

fn pack4(values: &[f32]) -> Vec<[u32; 4]> {
    values
        .chunks(4)
        .map(|c| {
            let mut t = [0u32; 4];
            for (dst, v) in t.iter_mut().zip(c) {
                *dst = v.to_bits();
            }
            t
        })
        .collect()
}

/// Halves a map across and down (2x2 box; an odd last column or row is
/// averaged with itself).
fn halve(w: u32, h: u32, texels: &[Vec3]) -> (u32, u32, Vec<Vec3>) {
    let (nw, nh) = (w.div_ceil(2), h.div_ceil(2).max(1));
    let at = |x: u32, y: u32| texels[(y.min(h - 1) * w + x.min(w - 1)) as usize];
    let mut out = Vec::with_capacity((nw * nh) as usize);
    for y in 0..nh {
        for x in 0..nw {
            out.push((at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1)) * 0.25);
        }
    }
    (nw, nh, out)
}

/// Where world direction `dir` (unit) lies on the map: (u, v) in [0, 1].
pub fn uv_of(dir: Vec3, rotation: f32) -> Vec2 {
    // Into the map's frame: turned back by the rotation about +y.
    let (s, c) = rotation.sin_cos();
    let x = c * dir.x - s * dir.z;
    let z = s * dir.x + c * dir.z;
    let mut u = x.atan2(-z) / (2.0 * PI);
    if u < 0.0 {
        u += 1.0;
    }
    Vec2::new(u, dir.y.clamp(-1.0, 1.0).acos() / PI)
}

/// The world direction at (u, v) of the map: the inverse of `uv_of`.
pub fn dir_of(uv: Vec2, rotation: f32) -> Vec3 {
    let phi = 2.0 * PI * uv.x;
    let theta = PI * uv.y;
    let (st, ct) = theta.sin_cos();
    let (x, z) = (phi.sin() * st, -phi.cos() * st);
    let (s, c) = rotation.sin_cos();
    Vec3::new(c * x + s * z, ct, -s * x + c * z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chi2::{sidak, test, Grid};

    /// A sky: a bright sun, a horizon band and a dark ground, 64x32.
    fn sky(rotation: f32) -> Environment {
        let (w, h) = (64u32, 32u32);
        let mut texels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let v = (y as f32 + 0.5) / h as f32;
                let mut c = if v < 0.5 { Vec3::new(0.3, 0.5, 1.0) * (1.0 - v) } else { Vec3::splat(0.05) };
                if (x, y) == (40, 9) || (x, y) == (41, 9) {
                    c = Vec3::new(400.0, 380.0, 300.0);
                }
                texels.push(c);
            }
        }
        Environment::from_texels(w, h, texels, rotation)
    }

    #[test]
    fn the_mean_radiance_weighs_rows_by_their_solid_angle() {
        let c = Vec3::new(0.2, 0.4, 0.8);
        assert!((Environment::constant(c, 0.0).mean_radiance() - c).abs().max_element() < 1e-6);
        // Bright upper half, black lower half: half the sphere, 1.0.
        let (w, h) = (8u32, 64u32);
        let texels = (0..h).flat_map(|y| (0..w).map(move |_| if y < h / 2 { Vec3::ONE } else { Vec3::ZERO })).collect();
        let half = Environment::from_texels(w, h, texels, 0.0).mean_radiance();
        assert!((half.x - 0.5).abs() < 1e-3, "{half}");
        // The light record carries it.
        let env = sky(0.3);
        assert_eq!(env.light_gpu().color, env.mean_radiance().to_array());
    }

    #[test]
    fn directions_and_map_coordinates_are_inverse() {
        for rot in [0.0, 1.1, -2.5] {
            for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.75), (0.3, 0.99)] {
                let uv = Vec2::new(u, v);
                let back = uv_of(dir_of(uv, rot), rot);
                assert!((back - uv).abs().max_element() < 1e-5, "{uv} -> {back} at {rot}");
            }
        }
        // Mitsuba's frame: u = 0.5 looks down +z... and the top row is +y.
        assert!((dir_of(Vec2::new(0.0, 0.5), 0.0) - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!((dir_of(Vec2::new(0.25, 0.5), 0.0) - Vec3::X).length() < 1e-6);
        assert!(dir_of(Vec2::new(0.7, 0.0), 0.0).y > 0.9999);
        // A quarter turn takes the map's +x to world -z.
        assert!((dir_of(Vec2::new(0.25, 0.5), PI / 2.0) - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
    }

    #[test]
    fn the_pdf_integrates_to_one_and_sampling_follows_it() {
        let env = sky(0.7);
        // The pdf over the sphere, by the midpoint rule.
        let grid = Grid { rows: 200, cols: 400 };
        let e = grid.expected(1, 2, |d| f64::from(env.pdf(d.normalize())));
        let total: f64 = e.iter().sum();
        assert!((total - 1.0).abs() < 5e-3, "the pdf integrates to {total}");
        // Each sample's pdf is the pdf of its direction.
        let mut rng = 0x9e3779b9u32;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 17;
            rng ^= rng << 5;
            (rng >> 8) as f32 / 16777216.0
        };
        for _ in 0..2000 {
            let (d, pdf) = env.sample(Vec2::new(next(), next()));
            assert!((d.length() - 1.0).abs() < 1e-5);
            let again = env.pdf(d);
            assert!((pdf - again).abs() <= 1e-3 * pdf.max(1.0), "sample pdf {pdf}, pdf() {again} at {d}");
        }
        // Chi-square over blocks of 4x4 texels, where the pdf is constant
        // per texel, so the expected counts are exact (a grid of
        // directions needs quadrature, which the sun's few texels defeat);
        // the samples are binned by the map coordinates of their
        // directions, so the mapping is tested as well.
        let (bw, bh) = (env.width as usize / 4, env.height as usize / 4);
        let n = 400_000;
        let mut counts = vec![0u64; bw * bh];
        for _ in 0..n {
            let (d, _) = env.sample(Vec2::new(next(), next()));
            let uv = uv_of(d, env.rotation);
            let (x, y) = (((uv.x * bw as f32) as usize).min(bw - 1), ((uv.y * bh as f32) as usize).min(bh - 1));
            counts[y * bw + x] += 1;
        }
        let mut expected = vec![0.0f64; bw * bh];
        for (i, p) in env.pdf.iter().enumerate() {
            let (x, y) = (i % env.width as usize / 4, i / env.width as usize / 4);
            expected[y * bw + x] += f64::from(*p) * n as f64 / env.pdf.len() as f64;
        }
        let r = test(&counts, &expected);
        assert!(r.p_value > sidak(0.01, 1), "chi2 {:.1}, dof {}, p {:.5}", r.chi2, r.dof, r.p_value);
    }

    #[test]
    fn the_sun_takes_its_share_of_samples() {
        let env = sky(0.0);
        let sun = |d: Vec3| env.radiance[env.texel_of(d)].x > 100.0;
        // The sampling mass of the sun's texels (their pdf over the cells).
        let share_lum = (0..env.radiance.len())
            .filter(|&i| env.radiance[i].x > 100.0)
            .map(|i| env.pdf[i] / (env.width * env.height) as f32)
            .sum::<f32>();
        assert!(share_lum > 0.3, "the sun holds {share_lum} of the sampling mass");
        let n = 20_000;
        let hits = (0..n).filter(|i| sun(env.sample(Vec2::new((*i as f32 + 0.5) / n as f32, ((i * 7919) % n) as f32 / n as f32)).0)).count();
        let share = hits as f32 / n as f32;
        assert!((share - share_lum).abs() < 0.02, "sun drawn {share}, holds {share_lum} of the weight");
    }

    #[test]
    fn a_constant_colour_is_sampled_almost_uniformly_and_a_wide_or_tall_map_is_halved() {
        let env = Environment::constant(Vec3::splat(2.0), 0.0);
        for d in [Vec3::X, Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.3, -0.9, 0.3).normalize()] {
            let ratio = env.pdf(d) * 4.0 * PI;
            assert!((ratio - 1.0).abs() < 0.15, "{d}: {ratio}");
            assert_eq!(env.radiance(d), Vec3::splat(2.0));
        }
        let wide = Environment::from_texels(5000, 2500, vec![Vec3::ONE; 5000 * 2500], 0.0);
        assert_eq!((wide.width, wide.height), (1250, 625));
        let tall = Environment::from_texels(3, 5000, vec![Vec3::ONE; 3 * 5000], 0.0);
        assert_eq!((tall.width, tall.height), (1, 1250));
        assert_eq!(wide.radiance[0], Vec3::ONE);
        // Texels: the map, each row's CDF in whole texels, the marginal.
        let t = Environment::constant(Vec3::ONE, 0.0).texels();
        assert_eq!(t.len(), 32 * 16 + 8 * 16 + 4);
        assert_eq!(f32::from_bits(t[32 * 16 + 7][3]), 1.0, "a row's CDF ends at 1");
        assert_eq!(f32::from_bits(t[32 * 16 + 8 * 16 + 3][3]), 1.0, "the marginal ends at 1");
        // A black map is still a distribution.
        let black = Environment::from_texels(8, 4, vec![Vec3::ZERO; 32], 0.0);
        assert!(black.pdf(Vec3::X) > 0.0 && black.sample(Vec2::splat(0.3)).1 > 0.0);
    }
}
