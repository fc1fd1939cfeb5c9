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

@compute @workgroup_size(64, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let step = select(vec2i(1, 0), vec2i(0, 1), AXIS == 1u);
    let r = i32(min(params.radius, 32u));
    let inv = 1.0 / (2.0 * max(params.sigma, 1e-3) * max(params.sigma, 1e-3));
    var sum = 0.0;
    var weight = 0.0;
    for (var k = -r; k <= r; k++) {
        let q = clamp(vec2i(id.xy) + k * step, vec2i(0), vec2i(frame.size) - 1);
        let w = exp(-f32(k * k) * inv);
        sum += w * textureLoad(src, q).x;
        weight += w;
    }
    textureStore(dst, id.xy, vec4f(sum / weight, 0.0, 0.0, 1.0));
}
