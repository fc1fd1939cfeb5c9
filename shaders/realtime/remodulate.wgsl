// The denoiser's last step: the filtered demodulated radiance F times the
// albedo, applied as a correction to the pixel's unbiased mean R:
// R + A (F - I). With one sample this is A F, SVGF's remodulation; as the
// filter fades (F tends to I) it tends to R, the plain mean of the path
// tracer's samples, whatever the jittered rays saw at an edge (where
// A I is not R). Pixels without a lit surface (A = 0) show R.
#import frame

@group(0) @binding(0) var filtered: texture_storage_2d<rgba32float, read>;
@group(0) @binding(1) var illum: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var color: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var albedo: texture_storage_2d<rgba32float, read>;
@group(0) @binding(4) var output: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let f = textureLoad(filtered, id.xy).rgb;
    let i = textureLoad(illum, id.xy).rgb;
    let r = textureLoad(color, id.xy).rgb;
    let a = textureLoad(albedo, id.xy).rgb;
    textureStore(output, id.xy, vec4f(max(r + a * (f - i), vec3f(0.0)), 1.0));
}
