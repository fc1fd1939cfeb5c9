// Separable Gaussian blur of a one-channel image: run twice, once per axis
// (`AXIS` 0 = horizontal, 1 = vertical), to close the gaps in the noise mask.
#import frame

override AXIS: u32 = 0u;

struct Params {
    sigma: f32, // ui: 0.25..8 log
    radius: u32, // ui: 0..16 limit
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var src: texture_storage_2d<r32float, read>;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let step = select(vec2i(1, 0), vec2i(0, 1), AXIS == 1u);
    let r = i32(min(params.radius, 32u));
    let inv = 1.0 / (2.0 * max(params.sigma, 1e-3) * max(params.sigma, 1e-3));
    let c = vec2i(id.xy);
    let last = vec2i(frame.size) - 1;
    // The taps in pairs from the centre out, the weights exp(-k^2 inv) by
    // recurrence: w(k+1) = w(k) g(k), g(k) = exp(-(2k + 1) inv), g(k+1) =
    // g(k) exp(-2 inv). Two exp a texel instead of one a tap (a SIMD CPU
    // driver's exp is a long polynomial); every factor is at most 1, so
    // far weights underflow to 0 as the exact ones are.
    var sum = textureLoad(src, c).x;
    var weight = 1.0;
    var w = 1.0;
    var g = exp(-inv);
    let h = exp(-2.0 * inv);
    for (var k = 1; k <= r; k++) {
        w *= g;
        g *= h;
        let a = textureLoad(src, clamp(c + k * step, vec2i(0), last)).x;
        let b = textureLoad(src, clamp(c - k * step, vec2i(0), last)).x;
        sum += w * (a + b);
        weight += 2.0 * w;
    }
    textureStore(dst, id.xy, vec4f(sum / weight, 0.0, 0.0, 1.0));
}
