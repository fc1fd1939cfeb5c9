// Test pass (tests/accumulate_extremes.rs): adds `steps` samples of the
// known sequence of src/mean.rs (`test_sequence`) to each pixel's running
// mean with mean_add, starting where the last frame stopped; frame k adds
// samples k * steps .. (k + 1) * steps - 1. So many frames of accumulation
// in a few dispatches, through the same WGSL as accumulate.wgsl.
#import frame
#import mean

struct Params {
    steps: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var mean_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var comp_prev: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var mean_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var comp_out: texture_storage_2d<rgba32uint, write>;

fn test_sequence(p: u32, k: u32) -> vec3f {
    let a = (k * 7919u + p * 104729u) % 1000u;
    let b = (k * 31u + p) % 977u;
    return vec3f(f32(a) * 0.001 + 0.5, f32(b) * 0.001 + 3.0, f32(a ^ b) * 0.0005 + 0.25);
}

@compute @workgroup_size(8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let size = textureDimensions(mean_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    var m = Mean(vec3f(0.0), vec3f(0.0));
    var count = 0u;
    if frame.frame_index > 0u {
        let c = textureLoad(comp_prev, id.xy);
        m = Mean(textureLoad(mean_prev, id.xy).rgb, bitcast<vec3f>(c.rgb));
        count = c.a;
    }
    let p = id.y * size.x + id.x;
    for (var i = 0u; i < params.steps; i++) {
        m = mean_add(m, test_sequence(p, count), count, frame.exact_one);
        count += 1u;
    }
    textureStore(mean_out, id.xy, vec4f(m.value, 1.0));
    textureStore(comp_out, id.xy, vec4u(bitcast<vec3u>(m.comp), count));
}
