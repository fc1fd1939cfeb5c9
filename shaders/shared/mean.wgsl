// The running mean behind accumulation, made to hold over millions of
// frames and against bad samples (mirrored in src/mean.rs).
//
// - mean_add is Kahan-compensated: the rounding error of each update is
//   carried in `comp` and taken back from the next one, so after 1e6
//   samples the mean is within about 1e-7 relative of the exact mean of
//   what was added (a plain running mean drifts by sqrt(n) roundings).
// - Counts are u32.
// - clean_sample keeps non-finite values out (checked by bits: a compiler
//   may assume `x != x` is false) and negative radiance at zero.

#import finite

struct Mean {
    value: vec3f,
    comp: vec3f,
}

// Adds sample `x` to a mean of `count` samples. `one` must be 1.0 at run
// time and unknown when the shader is compiled (pass frame.exact_one):
// without it the compiler may rewrite (t - m) - y, with t = m + y, as 0,
// and the compensation is gone (Mesa's NIR does: float ops not marked
// exact are reassociated, and WGSL has no way to mark them).
fn mean_add(m: Mean, x: vec3f, count: u32, one: f32) -> Mean {
    let y = (x - m.value) / f32(count + 1u) - m.comp;
    let t = (m.value + y) * one;
    return Mean(t, (t - m.value) - y);
}

// A sample fit to accumulate, or `valid` false when it holds NaN or Inf.
// Negative components become 0; with `clamp_max` > 0 a sample brighter
// than that (largest component) is scaled down to it, keeping its hue
// (a firefly clamp: biased, off by default).
struct Sample {
    value: vec3f,
    valid: bool,
}

fn clean_sample(x: vec3f, clamp_max: f32) -> Sample {
    if !all_finite(x) {
        return Sample(vec3f(0.0), false);
    }
    var v = max(x, vec3f(0.0));
    let m = max(v.x, max(v.y, v.z));
    if clamp_max > 0.0 && m > clamp_max {
        v *= clamp_max / m;
    }
    return Sample(v, true);
}
