// Test pass (tests/accumulate_extremes.rs): writes into `lit` what a broken
// pass might, by column and frame: NaN, +Inf, -Inf, 1e30, negative values
// and plain ones, so accumulation can be checked to contain them.
//   column 0: NaN on even frames, 1.0 on odd ones
//   column 1: +Inf on every frame
//   column 2: -Inf on odd frames, 2.0 on even ones
//   column 3: 1e30 on frame 0, then 1.0
//   column 4: -1 (and a NaN in blue on frame 1)
//   column 5: 0.5
#import frame

@group(0) @binding(0) var lit: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(64, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let f = frame.frame_index;
    let inf = bitcast<f32>(0x7f800000u);
    let nan = bitcast<f32>(0x7fc00000u);
    let even = f % 2u == 0u;
    var v = vec3f(0.5);
    switch id.x % 6u {
        case 0u: { v = select(vec3f(1.0), vec3f(nan), even); }
        case 1u: { v = vec3f(inf); }
        case 2u: { v = select(vec3f(-inf), vec3f(2.0), even); }
        case 3u: { v = select(vec3f(1.0), vec3f(1e30), f == 0u); }
        case 4u: { v = vec3f(-1.0, -1.0, select(-1.0, nan, f == 1u)); }
        default: {}
    }
    textureStore(lit, id.xy, vec4f(v, 1.0));
}
