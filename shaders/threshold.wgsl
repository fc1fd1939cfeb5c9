// The noise mask: 1 where the blurred edges exceed the threshold. The
// threshold is `params.threshold`, or the PID controller's
// (`frame.mask_threshold`, driven by frame time) when `use_pid` is 1.
#import frame

struct Params {
    threshold: f32, // ui: 0..1
    use_pid: u32, // ui: bool "threshold from the PID"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var blurred: texture_storage_2d<r32float, read>;
@group(0) @binding(2) var mask: texture_storage_2d<r32float, write>;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let t = select(params.threshold, frame.mask_threshold, params.use_pid == 1u);
    let e = textureLoad(blurred, id.xy).x;
    textureStore(mask, id.xy, vec4f(select(0.0, 1.0, e > t), 0.0, 0.0, 1.0));
}
