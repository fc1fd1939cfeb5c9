// The denoiser's variance (SVGF): each pixel's variance of lum(I), the
// demodulated radiance's luminance, from the moments of its 3x3
// neighbours on the same surface once its history holds `min_history`
// samples; before that, from its neighbours' means in a 5x5 window,
// whose weighted mean also replaces its own (one or two samples alone are
// mostly noise). Written as the variance
// of the pixel's *mean* (of n samples: over n), which the à-trous filter's
// luminance test scales with: as history grows the filter lets less
// through, and a still image tends to the unfiltered mean.
#import realtime_common

struct Params {
    min_history: f32, // ui: 1..16 "history for temporal variance"
    depth_sigma: f32, // ui: 0.1..16 log "depth sigma (pixel footprints)"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var illum: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var color: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var guide: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var filtered: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let p = vec2i(id.xy);
    let own = textureLoad(illum, p);
    let n = max(own.a, 1.0);
    let short = n < params.min_history;
    let gp = load_guide(guide, p);
    // A short history looks at 5x5 neighbours, a long one at 3x3 (its own
    // estimate blurred, as SVGF blurs it before each filter step): a loop
    // of 25 or 9 trips, none for a pixel without a surface.
    let radius = select(1, 2, short);
    let width = u32(2 * radius + 1);
    let taps = select(0u, width * width, gp.surface) * u32(frame.exact_one);
    let size = vec2i(frame.size);
    var sum = vec3f(0.0);
    var s1 = 0.0;
    var s2 = 0.0;
    var var_sum = 0.0;
    var wsum = 0.0;
    for (var k = 0u; k < taps; k++) {
        let d = vec2i(i32(k % width), i32(k / width)) - radius;
        let q = clamp(p + d, vec2i(0), size - 1);
        var w = 1.0;
        if any(d != vec2i(0)) {
            w = geometry_weight(gp, load_guide(guide, q), length(vec2f(d)), params.depth_sigma);
        }
        let iq = textureLoad(illum, q);
        let l = luminance(iq.rgb);
        let nq = max(iq.a, 1.0);
        sum += w * iq.rgb;
        s1 += w * l;
        s2 += w * l * l;
        var_sum += w * max(textureLoad(color, q).a - l * l, 0.0) / nq;
        wsum += w;
    }
    var value = own.rgb;
    var var_mean = 0.0;
    if wsum > 0.0 {
        if short {
            value = sum / wsum;
            let mu = s1 / wsum;
            // The spread of the neighbours' means (each of about n
            // samples, so already a mean's variance), boosted while
            // history is this short (SVGF's 4 / n).
            var_mean = max(s2 / wsum - mu * mu, 0.0) * (params.min_history / n);
        } else {
            // The moments' estimate alone: the neighbours' spread would
            // hold their real differences too, which do not fall with
            // history, and the filter would never fade.
            var_mean = var_sum / wsum;
        }
    }
    textureStore(filtered, id.xy, vec4f(value, var_mean));
}
