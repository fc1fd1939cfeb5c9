// Progressive accumulation: the running mean of `src` over the frames
// since the last reset. The engine resets (accum_count = 0) when the
// scene epoch or the camera changes. `accum_prev` is last frame's result.
#import frame

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var accum_prev: texture_2d<f32>;
@group(0) @binding(2) var accum: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let x = textureLoad(src, id.xy, 0);
    if frame.accum_count == 0u {
        textureStore(accum, id.xy, vec4f(x.rgb, 1.0));
        return;
    }
    let prev = textureLoad(accum_prev, id.xy, 0);
    let n = f32(frame.accum_count);
    textureStore(accum, id.xy, vec4f(prev.rgb + (x.rgb - prev.rgb) / (n + 1.0), 1.0));
}
