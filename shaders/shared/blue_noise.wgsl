// Blue-noise random numbers (src/blue_noise.rs: four 64x64 tiles of ranks,
// tiled over the screen). Where a path's first hit draws its numbers from
// here, neighbouring pixels draw far-apart ones, so the image's error is
// blue noise, which a denoiser's spatial filter removes better than white
// (Heitz and Belcour 2019). Over frames each pixel's numbers move along a
// Kronecker sequence (the golden ratio in 1D, Roberts' R2 in 2D): a pixel's
// own samples are then a low-discrepancy sequence, each still uniform.
// The numbers are the ranks' bins' lower ends moved along the sequence,
// the same for every seed: a white-noise jitter within each rank's 1/4096
// took eight draws a pixel on every trip of the path loop (the path pass
// 0.97-0.99x without it at 1280x720), and a random shift per seed made the
// temporal gradients miss a moved light's change (docs/realtime.md, "No
// jitter within a rank's bin").

@group(1) @binding(13) var blue_noise: texture_storage_2d<rgba32uint, read>;

const BLUE_NOISE_SIDE: u32 = 64u;

// The ranks of the four tiles at `pixel`, shifted by `shift` pixels (a
// second set of dimensions, nearly uncorrelated with the first), in [0, 1).
fn blue_noise_ranks(pixel: vec2u, shift: vec2u) -> vec4f {
    let q = (pixel + shift) % BLUE_NOISE_SIDE;
    let r = textureLoad(blue_noise, vec2u(q.y * BLUE_NOISE_SIDE + q.x, 0u));
    return vec4f(r) * (1.0 / 4096.0);
}

// Eight blue-noise numbers for `pixel` in frame `k`, as four pairs, each
// pair rotated along R2 (so a pair is a low-discrepancy 2D sequence over
// frames).
struct BlueNoise {
    a: vec4f,
    b: vec4f,
}

fn blue_noise_at(pixel: vec2u, k: u32) -> BlueNoise {
    // fract(k * R2) in 32-bit fixed point (R2 = (0.75487766, 0.56984029)
    // times 2^32), exact however large k grows; its top 24 bits as f32.
    let step = vec2f(vec2u(k * 3242174890u, k * 2447445414u) >> vec2u(8u)) * (1.0 / 16777216.0);
    let rot = vec4f(step, step.yx);
    return BlueNoise(
        fract(blue_noise_ranks(pixel, vec2u(0u)) + rot),
        fract(blue_noise_ranks(pixel, vec2u(32u, 21u)) + rot.zwxy),
    );
}
