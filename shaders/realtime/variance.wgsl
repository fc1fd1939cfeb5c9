// The denoiser's variance (SVGF): the variance of each pixel's mean of
// lum(I), the demodulated radiance's luminance. Once its history holds
// `min_history` samples, its own moments' estimate (temporal.wgsl's
// `filter_in`.w) blurred over 3x3 pixels (SVGF's Gaussian: a few samples'
// moments are noisy); before that, the spread of its neighbours' means on
// the same surface (a 3x3 with its taps two pixels apart: a 5x5 footprint
// in 9 taps), whose weighted mean also replaces its own while
// history is shorter than `blur_history` (one or two samples alone are
// mostly noise), fading out by three times that. Being a mean's variance (of n
// samples), it falls as history grows, and with it what the à-trous
// filter's colour test lets through: a still image tends to the
// unfiltered mean.
#import realtime_common

struct Params {
    min_history: f32, // ui: 1..16 "history for temporal variance"
    depth_sigma: f32, // ui: 0.1..16 log "depth sigma (pixel footprints)"
    boost: f32, // ui: 1..32 "variance boost at one sample"
    direct_boost: f32, // ui: 1..32 "the direct light's boost (entry split)"
    blur_history: f32, // ui: 0..64 "history replaced by the neighbours' mean below"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var illum: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var filter_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var guide: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var filtered: texture_storage_2d<rgba32float, write>;

// Entry `split` only (SPLIT_DIRECT graphs): the direct light's input
// and output, as filter_in and filtered. Its variance is estimated the
// same way, with the same surface weights; its mean is never blurred.
@group(0) @binding(5) var direct_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(6) var direct_filtered: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    textureStore(filtered, id.xy, estimate(vec2i(id.xy), filter_in, filter_in, false).light);
}

@compute @workgroup_size(128, 1)
fn split(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let e = estimate(vec2i(id.xy), filter_in, direct_in, true);
    textureStore(filtered, id.xy, e.light);
    textureStore(direct_filtered, id.xy, e.direct);
}

// A signal's running sums over the neighbours: the weighted mean and the
// luminance's first two moments.
struct Spread {
    sum: vec3f,
    s1: f32,
    s2: f32,
}

fn spread_add(s: Spread, w: f32, c: vec3f) -> Spread {
    let l = luminance(c);
    return Spread(s.sum + w * c, s.s1 + w * l, s.s2 + w * l * l);
}

// The spread of the neighbours' means (each of about n samples, so
// already a mean's variance), boosted by `boost` at one sample, falling as
// 1 + (boost - 1) / n^2 (SVGF boosts by 4 / n): one sample's neighbours
// are few and as noisy as the pixel, and their spread underestimates it.
fn spread_variance(s: Spread, wsum: f32, n: f32, boost: f32) -> f32 {
    let mu = s.s1 / wsum;
    return max(s.s2 / wsum - mu * mu, 0.0) * (1.0 + (boost - 1.0) / (n * n));
}

// How far apart the spread's taps lie while history is short.
const SPREAD_STEP: i32 = 2;

// The history from which the direct light's variance is its own moments'
// (two samples are the fewest that have a spread).
const DIRECT_MOMENTS_FROM: f32 = 2.0;

struct Estimate {
    light: vec4f,
    direct: vec4f,
}

// The pixel's mean and the variance of it, for the light (`tex`) and with
// `with_direct` the direct light (`dtex`). Textures are arguments so that
// `main` passes `tex` twice and binds no direct light; a constant
// `with_direct` is folded away where the driver inlines the call.
fn estimate(p: vec2i, tex: texture_storage_2d<rgba32float, read>, dtex: texture_storage_2d<rgba32float, read>, with_direct: bool) -> Estimate {
    let own = textureLoad(tex, p);
    var own_d = vec4f(0.0);
    if with_direct {
        own_d = textureLoad(dtex, p);
    }
    let n = max(textureLoad(illum, p).a, 1.0);
    // The neighbours' spread stands for the variance below min_history;
    // their mean replaces the pixel's below blur_history, then fades out
    // by 3 blur_history (a sudden stop shows as a burst of noise).
    let spatial_variance = n < params.min_history;
    // The direct light's own moments stand for its variance from 2 samples
    // on: they tell noise (a penumbra's samples disagree) from an edge
    // (its pixels' samples agree), which the neighbours' spread cannot.
    let temporal_direct = with_direct && n >= DIRECT_MOMENTS_FROM;
    let blur = clamp((3.0 - n / max(params.blur_history, 1e-6)) / 2.0, 0.0, 1.0);
    // A 3x3 of neighbours, SPREAD_STEP pixels apart for the spread
    // (the 5x5's 25 taps measured the same first frames over 12 seeds at
    // 1.8x this pass's time: docs/realtime.md, "The spread in nine taps"),
    // next to each other once history is long enough for the moments,
    // whose variance is blurred over them; the direct light's taps are next
    // to each other once its moments count. Written out and loaded first,
    // whatever the pixel needs of them: a CPU driver runs every branch and
    // loop under lane masks, and loads in them cost more (docs/realtime.md,
    // "Cost at 1280x720").
    let step = select(1, SPREAD_STEP, spatial_variance);
    let step_d = select(step, 1, temporal_direct);
    var s = Sums(
        spread_add(Spread(vec3f(0.0), 0.0, 0.0), 1.0, own.rgb),
        Spread(vec3f(0.0), 0.0, 0.0),
        1.0,
        0.25 * own.a,
        0.25 * own_d.a,
    );
    if with_direct && !temporal_direct {
        s.direct = spread_add(s.direct, 1.0, own_d.rgb);
    }
    let gp = load_guide(guide, p);
    let c = Centre(p, gp, plane_scale(gp, params.depth_sigma), step, step_d, with_direct && !temporal_direct);
    s = add_neighbours(s, c, vec2i(-1, -1), 0.0625, tex, dtex, with_direct);
    s = add_neighbours(s, c, vec2i(0, -1), 0.125, tex, dtex, with_direct);
    s = add_neighbours(s, c, vec2i(1, -1), 0.0625, tex, dtex, with_direct);
    s = add_neighbours(s, c, vec2i(-1, 0), 0.125, tex, dtex, with_direct);
    // (wsum >= 1: the centre counts with weight 1.)
    let value = mix(own.rgb, s.light.sum / s.wsum, blur);
    // Below min_history the spread; above, the moments' variance blurred
    // 1/4, 1/2, 1/4 in each axis over the 3x3 pixels, surfaces or not (only
    // the noise's level is blurred).
    let var_mean = select(s.blurred, spread_variance(s.light, s.wsum, n, params.boost), spatial_variance);
    var var_d = 0.0;
    if with_direct {
        var_d = select(spread_variance(s.direct, s.wsum, n, params.direct_boost), s.blurred_d, temporal_direct);
    }
    return Estimate(vec4f(value, var_mean), vec4f(own_d.rgb, var_d));
}

// The pixel whose neighbours are summed: its surface, and how far apart
// its taps lie.
struct Centre {
    p: vec2i,
    guide: Guide,
    plane_scale: f32,
    step: i32,
    step_d: i32,
    // Whether the direct light takes the spread (else its moments' blur).
    direct_spread: bool,
}

// The running sums over the neighbours: the spreads, their weights, and
// the moments' variances blurred.
struct Sums {
    light: Spread,
    direct: Spread,
    wsum: f32,
    blurred: f32,
    blurred_d: f32,
}

// The neighbours at d and -d added, `kernel` the blur's weight of each.
fn add_neighbours(s: Sums, c: Centre, d: vec2i, kernel: f32, tex: texture_storage_2d<rgba32float, read>, dtex: texture_storage_2d<rgba32float, read>, with_direct: bool) -> Sums {
    let size = vec2i(frame.size);
    let qa = clamp(c.p + d * c.step, vec2i(0), size - 1);
    let qb = clamp(c.p - d * c.step, vec2i(0), size - 1);
    let ta = textureLoad(tex, qa);
    let tb = textureLoad(tex, qb);
    let scale = c.plane_scale * inverseSqrt(f32(dot(d, d) * c.step * c.step));
    let wa = geometry_weight(c.guide, load_guide(guide, qa), scale, 0.0);
    let wb = geometry_weight(c.guide, load_guide(guide, qb), scale, 0.0);
    var out = s;
    out.light = spread_add(spread_add(s.light, wa, ta.rgb), wb, tb.rgb);
    out.wsum = s.wsum + (wa + wb);
    out.blurred = s.blurred + kernel * (ta.a + tb.a);
    if with_direct {
        let da = textureLoad(dtex, clamp(c.p + d * c.step_d, vec2i(0), size - 1));
        let db = textureLoad(dtex, clamp(c.p - d * c.step_d, vec2i(0), size - 1));
        out.blurred_d = s.blurred_d + kernel * (da.a + db.a);
        if c.direct_spread {
            out.direct = spread_add(spread_add(s.direct, wa, da.rgb), wb, db.rgb);
        }
    }
    return out;
}
