// The denoiser's temporal gradients (A-SVGF: Schied et al. 2018): in a
// frame whose scene changed (a light or an object moved), one pixel of
// each 3x3 stratum traces last frame's path again, from last frame's
// camera with last frame's random numbers, through the scene as it is
// now. Where nothing that path met has changed it gives last frame's
// sample exactly; the difference is how much the light there changed,
// without the noise two independent samples would differ by. Writes per
// stratum (new - old, max(new, old), |new - old|) in luminance;
// temporal.wgsl turns the 3x3 strata around each pixel into the share of
// its history to drop, restir.wgsl into the share of its reservoir's.
// In frames where the scene did not change every gradient would be zero:
// nothing is traced or written.
//
// Entry `with_reservoirs` is realtime-restir.ron's (see there).
#import path
#import restir

struct Params {
    max_depth: u32, // ui: 1..64 limit "max bounces"
    rr_depth: u32, // ui: 0..16 "roulette from bounce"
}

@group(0) @binding(0) var<uniform> params: Params;
// Last frame's `geo` history: its w holds each pixel's sample luminance.
@group(0) @binding(1) var geo_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var gradient: texture_storage_2d<rgba32float, write>;
// `with_reservoirs`: last frame's final reservoirs (restir.wgsl).
@group(0) @binding(3) var reservoir_prev: texture_storage_2d<rgba32uint, read>;

// Pixels per stratum side (temporal.wgsl reads the strata with it).
const STRATUM: u32 = 3u;
const PICK_SALT: u32 = 0x67726164u;

// Last frame's path of the stratum's picked pixel traced again: the
// pixel and the light it brings now (without its first hit's direct
// light under FIRST_DIRECT_APART).
struct Replay {
    pixel: vec2u,
    light: vec3f,
}

fn replay(id: vec2u) -> Replay {
    let prev_frame = frame.frame_index - 1u;
    // Which pixel of the stratum, by a hash of stratum and frame.
    var pick = rng_for(id, prev_frame, PICK_SALT, frame.seed);
    let offset = vec2u(rand_u32(&pick) % STRATUM, rand_u32(&pick) % STRATUM);
    let pixel = min(id * STRATUM + offset, frame.size - 1u);
    var flat = scene_flat;
    let rng_key = rng_frame_key(prev_frame, PATH_RENDER_SALT, frame.seed);
    var rng = rng_at(rng_key, pixel);
    start_blue_noise(pixel, prev_frame);
    let cam = frame.prev_camera;
    let rd = camera_dir(cam, pixel, rand2(&rng));
    path_primary_direct = vec3f(0.0);
    return Replay(pixel, trace_path(&flat, cam.origin, rd, last_pixel_spread(), params.max_depth, params.rr_depth, true, &rng));
}

// Whether this stratum has a gradient to write: only in frames whose
// scene changed, with a last frame in the history (the same for every
// invocation, so no lane pays for the other side; temporal.wgsl reads
// the gradients only then: other frames leave the texture as it was).
fn wanted(id: vec2u) -> bool {
    return all(id < textureDimensions(gradient)) && frame.epoch_frames == 0u && frame.history_frames > 0u;
}

fn store_gradient(id: vec2u, r: Replay, light: vec3f) {
    let now = luminance(max(light, vec3f(0.0)));
    let then = textureLoad(geo_prev, vec2i(r.pixel)).w;
    textureStore(gradient, id, vec4f(now - then, max(now, then), abs(now - then), 1.0));
}

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !wanted(id.xy) {
        return;
    }
    let r = replay(id.xy);
    store_gradient(id.xy, r, r.light);
}

// realtime-restir.ron's (FIRST_DIRECT_APART): the path's first-hit direct
// light came from restir.wgsl's reservoir, so last frame's reservoir is
// shaded again at the hit the path finds now.
@compute @workgroup_size(128, 1)
fn with_reservoirs(@builtin(global_invocation_id) id: vec3u) {
    if !wanted(id.xy) {
        return;
    }
    let r = replay(id.xy);
    var light = r.light;
    if path_primary_pos.w >= 0.0 {
        // The normal as restir.wgsl reads it back (packed).
        let ng = oct_to_normal(unpack2x16snorm(pack2x16snorm(normal_to_oct(path_primary_ng))));
        let s = make_surface(path_primary_pos.xyz, path_primary_normal.xyz, ng, path_primary_direct, bitcast<f32>(path_primary_ids.z));
        light += shade_reservoir(s, decode_reservoir(textureLoad(reservoir_prev, vec2i(r.pixel))));
    }
    store_gradient(id.xy, r, light);
}
