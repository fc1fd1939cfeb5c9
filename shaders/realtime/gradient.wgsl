// The denoiser's temporal gradients (A-SVGF: Schied et al. 2018): in a
// frame whose scene changed (a light or an object moved), one pixel of
// each 3x3 stratum traces last frame's path again, from last frame's
// camera with last frame's random numbers, through the scene as it is
// now. Where nothing that path met has changed it gives last frame's
// sample exactly; the difference is how much the light there changed,
// without the noise two independent samples would differ by. Writes per
// stratum (|new - old|, max(new, old)) in luminance; temporal.wgsl turns
// the 3x3 strata around each pixel into the share of its history to drop.
// In frames where the scene did not change every gradient would be zero:
// nothing is traced or written.
#import path
#import realtime_common

struct Params {
    max_depth: u32, // ui: 1..64 limit "max bounces"
    rr_depth: u32, // ui: 0..16 "roulette from bounce"
}

@group(0) @binding(0) var<uniform> params: Params;
// Last frame's `geo` history: its w holds each pixel's sample luminance.
@group(0) @binding(1) var geo_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var gradient: texture_storage_2d<rgba32float, write>;

// Pixels per stratum side (temporal.wgsl reads the strata with it).
const STRATUM: u32 = 3u;
const PICK_SALT: u32 = 0x67726164u;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let strata = textureDimensions(gradient);
    if any(id.xy >= strata) {
        return;
    }
    // Only frames whose scene changed, with a last frame in the history:
    // the same for every invocation, so no lane pays for the other side.
    // (temporal.wgsl reads the gradients only then: other frames leave
    // the texture as it was.)
    if frame.epoch_frames != 0u || frame.history_frames == 0u {
        return;
    }
    {
        let prev_frame = frame.frame_index - 1u;
        // Which pixel of the stratum, by a hash of stratum and frame.
        var pick = rng_for(id.xy, prev_frame, PICK_SALT, frame.seed);
        let offset = vec2u(rand_u32(&pick) % STRATUM, rand_u32(&pick) % STRATUM);
        let pixel = min(id.xy * STRATUM + offset, frame.size - 1u);
        var flat = scene_flat;
        var rng = rng_at(rng_frame_key(prev_frame, PATH_RENDER_SALT, frame.seed), pixel);
        let cam = frame.prev_camera;
        let rd = camera_dir(cam, pixel, rand2(&rng));
        let now = luminance(max(trace_path(&flat, cam.origin, rd, params.max_depth, params.rr_depth, true, &rng), vec3f(0.0)));
        let then = textureLoad(geo_prev, vec2i(pixel)).w;
        textureStore(gradient, id.xy, vec4f(abs(now - then), max(now, then), 0.0, 1.0));
    }
}
