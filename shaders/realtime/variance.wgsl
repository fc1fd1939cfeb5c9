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
    let gp = load_guide(guide, p);
    let size = vec2i(frame.size);
    var value = own.rgb;
    var var_mean = 0.0;
    var var_d = 0.0;
    // The 3x3 blur of the moments' variance (below), summed in the
    // neighbours' loop where its taps are the same pixels (step 1): a
    // texel load is what a CPU driver's pass costs.
    var sum = select(0.0, 0.25 * own.a, !spatial_variance);
    var sum_d = select(0.0, 0.25 * own_d.a, temporal_direct);
    var blurred = false;
    var blurred_d = false;
    if spatial_variance || blur > 0.0 {
        // A 3x3 of neighbours, SPREAD_STEP pixels apart for the spread
        // (the 5x5's 25 taps measured the same first frames over 12 seeds
        // at 1.8x this pass's time: docs/realtime.md, "The spread in nine
        // taps"), next to each other while only the blur fades out.
        let step = select(1, SPREAD_STEP, spatial_variance);
        // The centre, then the other taps in opposite pairs, d and -d (half
        // the loop's trips: a CPU driver pays for each trip's bookkeeping).
        let pairs = select(0u, 4u, gp.surface) * u32(frame.exact_one);
        var light = spread_add(Spread(vec3f(0.0), 0.0, 0.0), 1.0, own.rgb);
        var direct = Spread(vec3f(0.0), 0.0, 0.0);
        if with_direct && !temporal_direct {
            direct = spread_add(direct, 1.0, own_d.rgb);
        }
        var wsum = 1.0;
        let plane_scale = plane_scale(gp, params.depth_sigma);
        // d stepped through the rows above the centre and the centre row's
        // left half, without an integer division (a SIMD CPU driver
        // divides one lane at a time).
        blurred = !spatial_variance && pairs == 4u;
        blurred_d = blurred && temporal_direct;
        var d = vec2i(-1, -1);
        for (var k = 0u; k < pairs; k++) {
            let qa = clamp(p + d * step, vec2i(0), size - 1);
            let qb = clamp(p - d * step, vec2i(0), size - 1);
            let scale = plane_scale * inverseSqrt(f32(dot(d, d) * step * step));
            let wa = geometry_weight(gp, load_guide(guide, qa), scale, 0.0);
            let wb = geometry_weight(gp, load_guide(guide, qb), scale, 0.0);
            let kernel = select(0.5, 0.25, d.x != 0) * select(0.5, 0.25, d.y != 0);
            d.x += 1;
            if d.x > 1 {
                d = vec2i(-1, d.y + 1);
            }
            let ta = textureLoad(tex, qa);
            let tb = textureLoad(tex, qb);
            light = spread_add(spread_add(light, wa, ta.rgb), wb, tb.rgb);
            if blurred {
                sum += kernel * (ta.a + tb.a);
            }
            if with_direct && (!temporal_direct || blurred_d) {
                let da = textureLoad(dtex, qa);
                let db = textureLoad(dtex, qb);
                if blurred_d {
                    sum_d += kernel * (da.a + db.a);
                } else {
                    direct = spread_add(spread_add(direct, wa, da.rgb), wb, db.rgb);
                }
            }
            wsum += wa + wb;
        }
        // (wsum >= 1: the centre counts with weight 1.)
        value = mix(value, light.sum / wsum, blur);
        if spatial_variance {
            var_mean = spread_variance(light, wsum, n, params.boost);
        }
        if with_direct && !temporal_direct {
            var_d = spread_variance(direct, wsum, n, params.direct_boost);
        }
    }
    let blur_light = !spatial_variance && !blurred;
    let blur_direct = temporal_direct && !blurred_d;
    if blur_light || blur_direct {
        // 1/4, 1/2, 1/4 in each axis over the 3x3 pixels, surfaces or not:
        // only the noise's level is blurred. The centre, then opposite
        // pairs, as above.
        let pairs = 4u * u32(frame.exact_one);
        var d = vec2i(-1, -1);
        for (var k = 0u; k < pairs; k++) {
            let qa = clamp(p + d, vec2i(0), size - 1);
            let qb = clamp(p - d, vec2i(0), size - 1);
            let kernel = select(0.5, 0.25, d.x != 0) * select(0.5, 0.25, d.y != 0);
            if blur_light {
                sum += kernel * (textureLoad(tex, qa).a + textureLoad(tex, qb).a);
            }
            if blur_direct {
                sum_d += kernel * (textureLoad(dtex, qa).a + textureLoad(dtex, qb).a);
            }
            d.x += 1;
            if d.x > 1 {
                d = vec2i(-1, 0);
            }
        }
    }
    if !spatial_variance {
        var_mean = sum;
    }
    if temporal_direct {
        var_d = sum_d;
    }
    return Estimate(vec4f(value, var_mean), vec4f(own_d.rgb, var_d));
}
