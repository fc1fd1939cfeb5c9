// Counter-based randomness: a PCG hash of (pixel, frame, pass, sample, seed),
// so the same inputs give the same image on the same driver.

fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct Rng {
    state: u32,
}

// A stream for one pixel of one frame of one pass (`salt` names the pass).
fn rng_for(pixel: vec2u, frame_index: u32, salt: u32, seed: u32) -> Rng {
    return rng_at(rng_frame_key(frame_index, salt, seed), pixel);
}

// rng_for in two steps, for a shader that starts many pixels' streams: the
// hash of (seed, salt, frame) is the same for all of them.
fn rng_frame_key(frame_index: u32, salt: u32, seed: u32) -> u32 {
    var h = pcg_hash(seed ^ 0x9e3779b9u);
    h = pcg_hash(h ^ salt);
    return pcg_hash(h ^ frame_index);
}

fn rng_at(key: u32, pixel: vec2u) -> Rng {
    return Rng(pcg_hash(pcg_hash(key ^ pixel.y) ^ pixel.x));
}

fn rand_u32(rng: ptr<function, Rng>) -> u32 {
    (*rng).state = (*rng).state * 747796405u + 2891336453u;
    let s = (*rng).state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform in [0, 1): 24 random bits.
fn rand_f32(rng: ptr<function, Rng>) -> f32 {
    return f32(rand_u32(rng) >> 8u) * (1.0 / 16777216.0);
}

fn rand2(rng: ptr<function, Rng>) -> vec2f {
    let a = rand_f32(rng);
    let b = rand_f32(rng);
    return vec2f(a, b);
}
