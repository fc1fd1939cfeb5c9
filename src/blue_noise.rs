//! Blue-noise ranks for screen-space sample decorrelation (Ulichney's
//! void-and-cluster method, 1993): a 64x64 tile, tiled over the screen,
//! whose ranks 0..4095 are spread so that neighbouring pixels get far
//! apart values. A path's first-hit random numbers taken from it (rotated
//! per frame) leave its error as blue noise in screen space, which a
//! denoiser's low-pass filter removes better than white noise (Heitz and
//! Belcour 2019; `shaders/shared/blue_noise.wgsl` says how it is used).
//!
//! Generated once per process, deterministically, from fixed seeds.

use std::sync::OnceLock;

/// Pixels along a side of the tile.
pub const SIDE: usize = 64;
/// Independent tiles: one per channel of the texture shaders read.
pub const CHANNELS: usize = 4;
/// The Gaussian's standard deviation in pixels (Ulichney's 1.5 to 2).
const SIGMA: f32 = 1.9;
/// The Gaussian is cut at this many pixels from its centre (its weight there is e^-6.8).
const RADIUS: i32 = 7;

/// The tiles, one texel per pixel with a rank 0..4095 per channel, in
/// row-major order: what the `blue_noise` engine texture holds.
pub fn texels() -> &'static [[u32; CHANNELS]] {
    static TEXELS: OnceLock<Vec<[u32; CHANNELS]>> = OnceLock::new();
    TEXELS.get_or_init(|| {
        let tiles: Vec<Vec<u32>> = (0..CHANNELS).map(|c| void_and_cluster(0x6c69_6e74 ^ c as u64)).collect();
        (0..SIDE * SIDE).map(|i| std::array::from_fn(|c| tiles[c][i])).collect()
    })
}

/// Splat energy: adds `sign` times the toroidal Gaussian centred on `at`.
fn splat(energy: &mut [f32], kernel: &[f32], at: usize, sign: f32) {
    let (cx, cy) = ((at % SIDE) as i32, (at / SIDE) as i32);
    let width = (2 * RADIUS + 1) as usize;
    for dy in -RADIUS..=RADIUS {
        let y = (cy + dy).rem_euclid(SIDE as i32) as usize;
        for dx in -RADIUS..=RADIUS {
            let x = (cx + dx).rem_euclid(SIDE as i32) as usize;
            let k = kernel[(dy + RADIUS) as usize * width + (dx + RADIUS) as usize];
            energy[y * SIDE + x] += sign * k;
        }
    }
}

/// The index of the largest (`max`) or smallest energy among pixels whose
/// state is `on`; the first such on ties.
fn extreme(energy: &[f32], set: &[bool], on: bool, max: bool) -> usize {
    let mut best = usize::MAX;
    for i in 0..energy.len() {
        if set[i] != on {
            continue;
        }
        let better = best == usize::MAX || if max { energy[i] > energy[best] } else { energy[i] < energy[best] };
        if better {
            best = i;
        }
    }
    best
}

/// One tile's ranks: a permutation of 0..SIDE^2.
fn void_and_cluster(seed: u64) -> Vec<u32> {
    let n = SIDE * SIDE;
    let width = (2 * RADIUS + 1) as usize;
    let kernel: Vec<f32> = (0..width * width)
        .map(|i| {
            let (dx, dy) = ((i % width) as f32 - RADIUS as f32, (i / width) as f32 - RADIUS as f32);
            (-(dx * dx + dy * dy) / (2.0 * SIGMA * SIGMA)).exp()
        })
        .collect();
    // A tenth of the pixels on, at random (splitmix64)...
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let mut set = vec![false; n];
    let mut on = 0;
    while on < n / 10 {
        let i = (next() % n as u64) as usize;
        if !set[i] {
            set[i] = true;
            on += 1;
        }
    }
    let mut energy = vec![0.0f32; n];
    for i in (0..n).filter(|&i| set[i]) {
        splat(&mut energy, &kernel, i, 1.0);
    }
    // ...moved from the tightest cluster to the largest void until stable.
    for _ in 0..n {
        let cluster = extreme(&energy, &set, true, true);
        set[cluster] = false;
        splat(&mut energy, &kernel, cluster, -1.0);
        let void = extreme(&energy, &set, false, false);
        set[void] = true;
        splat(&mut energy, &kernel, void, 1.0);
        if void == cluster {
            break;
        }
    }
    let mut rank = vec![0u32; n];
    // The initial points ranked by taking clusters away...
    let (mut taken, mut taken_energy) = (set.clone(), energy.clone());
    for r in (0..on).rev() {
        let cluster = extreme(&taken_energy, &taken, true, true);
        taken[cluster] = false;
        splat(&mut taken_energy, &kernel, cluster, -1.0);
        rank[cluster] = r as u32;
    }
    // ...and the rest by filling voids.
    for r in on..n {
        let void = extreme(&energy, &set, false, false);
        set[void] = true;
        splat(&mut energy, &kernel, void, 1.0);
        rank[void] = r as u32;
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The variance of channel `c`'s 3x3 box means (toroidal) over what
    /// white noise's would be (a ninth of the pixels' variance): the share
    /// of its error a small blur leaves.
    fn box_variance_ratio(c: usize) -> f64 {
        let t = texels();
        let at = |x: usize, y: usize| t[(y % SIDE) * SIDE + x % SIDE][c] as f64;
        let mean = (SIDE * SIDE - 1) as f64 / 2.0;
        let var = ((SIDE * SIDE) as f64).powi(2) / 12.0;
        let mut sum = 0.0;
        for y in 0..SIDE {
            for x in 0..SIDE {
                let box_mean = (0..9).map(|k| at(x + SIDE - 1 + k % 3, y + SIDE - 1 + k / 3)).sum::<f64>() / 9.0;
                sum += (box_mean - mean).powi(2);
            }
        }
        sum / t.len() as f64 / (var / 9.0)
    }

    #[test]
    fn every_channel_is_a_permutation_of_the_ranks() {
        for c in 0..CHANNELS {
            let mut ranks: Vec<u32> = texels().iter().map(|v| v[c]).collect();
            ranks.sort_unstable();
            assert!(ranks.iter().enumerate().all(|(i, &r)| r == i as u32), "channel {c}");
        }
    }

    #[test]
    fn a_small_blur_removes_most_of_it_and_channels_are_independent() {
        for c in 0..CHANNELS {
            // White noise: 1. These tiles: about 0.22.
            let ratio = box_variance_ratio(c);
            assert!(ratio < 0.35, "channel {c}: a 3x3 blur keeps {ratio:.2} of white noise's variance");
        }
        let t = texels();
        let mean = (SIDE * SIDE - 1) as f64 / 2.0;
        let var = ((SIDE * SIDE) as f64).powi(2) / 12.0;
        for (a, b) in [(0, 1), (1, 2), (2, 3), (0, 3)] {
            let cov: f64 = t.iter().map(|v| (v[a] as f64 - mean) * (v[b] as f64 - mean)).sum::<f64>() / t.len() as f64;
            assert!((cov / var).abs() < 0.05, "channels {a} and {b} correlate: {:.3}", cov / var);
        }
    }
}
