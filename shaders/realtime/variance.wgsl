// The denoiser's variance (SVGF): the variance of each pixel's mean of
// lum(I), the demodulated radiance's luminance. Once its history holds
// `min_history` samples, its own moments' estimate (temporal.wgsl's
// `filter_in`.w) blurred over 3x3 pixels (SVGF's Gaussian: a few samples'
// moments are noisy); before that, the spread of its 5x5 neighbours' means
// on the same surface, whose weighted mean also replaces its own while
// history is shorter than `blur_history` (one or two samples alone are
// mostly noise), fading out by twice that. Being a mean's variance (of n
// samples), it falls as history grows, and with it what the à-trous
// filter's colour test lets through: a still image tends to the
// unfiltered mean.
#import realtime_common

struct Params {
    min_history: f32, // ui: 1..16 "history for temporal variance"
    depth_sigma: f32, // ui: 0.1..16 log "depth sigma (pixel footprints)"
    boost: f32, // ui: 1..16 "variance boost at one sample"
    blur_history: f32, // ui: 0..64 "history replaced by the neighbours' mean below"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var illum: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var filter_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var guide: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var filtered: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let p = vec2i(id.xy);
    let own = textureLoad(filter_in, p);
    let n = max(textureLoad(illum, p).a, 1.0);
    // The neighbours' spread stands for the variance below min_history;
    // their mean replaces the pixel's below blur_history, then fades out
    // by 2 blur_history (a sudden stop shows as a burst of noise).
    let spatial_variance = n < params.min_history;
    let blur = clamp(2.0 - n / max(params.blur_history, 1e-6), 0.0, 1.0);
    let gp = load_guide(guide, p);
    let size = vec2i(frame.size);
    var value = own.rgb;
    var var_mean = 0.0;
    if spatial_variance || blur > 0.0 {
        // A loop of 25 trips where a lane needs it, none elsewhere (a CPU
        // driver runs a loop as long as its busiest lane).
        let taps = select(0u, 25u, gp.surface) * u32(frame.exact_one);
        var sum = vec3f(0.0);
        var s1 = 0.0;
        var s2 = 0.0;
        var wsum = 0.0;
        let plane_scale = plane_scale(gp, params.depth_sigma);
        // The tap's offset, stepped through the 5x5 in rows without an
        // integer division (a SIMD CPU driver divides one lane at a time).
        var d = vec2i(-2, -2);
        for (var k = 0u; k < taps; k++) {
            let q = clamp(p + d, vec2i(0), size - 1);
            var w = 1.0;
            if k != 12u {
                w = geometry_weight(gp, load_guide(guide, q), plane_scale * inverseSqrt(f32(dot(d, d))), 0.0);
            }
            d.x += 1;
            if d.x > 2 {
                d = vec2i(-2, d.y + 1);
            }
            let iq = textureLoad(filter_in, q).rgb;
            let l = luminance(iq);
            sum += w * iq;
            s1 += w * l;
            s2 += w * l * l;
            wsum += w;
        }
        if wsum > 0.0 {
            value = mix(value, sum / wsum, blur);
            let mu = s1 / wsum;
            // The spread of the neighbours' means (each of about n
            // samples, so already a mean's variance), boosted while
            // history is this short by `boost` at one sample, falling to
            // 1 at min_history (SVGF boosts by 4 / n).
            let t = clamp((n - 1.0) / max(params.min_history - 1.0, 1.0), 0.0, 1.0);
            var_mean = max(s2 / wsum - mu * mu, 0.0) * mix(params.boost, 1.0, t);
        }
    }
    if !spatial_variance {
        // 1/4, 1/2, 1/4 in each axis over the 3x3 pixels, surfaces or not:
        // only the noise's level is blurred.
        var_mean = 0.0;
        let taps = 9u * u32(frame.exact_one);
        var d = vec2i(-1, -1);
        for (var k = 0u; k < taps; k++) {
            let q = clamp(p + d, vec2i(0), size - 1);
            let kernel = select(0.5, 0.25, d.x != 0) * select(0.5, 0.25, d.y != 0);
            var_mean += kernel * textureLoad(filter_in, q).a;
            d.x += 1;
            if d.x > 1 {
                d = vec2i(-1, d.y + 1);
            }
        }
    }
    textureStore(filtered, id.xy, vec4f(value, var_mean));
}
