// Ground truth (thesis 2.4): Monte Carlo path tracing with Lambertian
// diffuse and a specular lobe chosen with probability `specular` (mirror
// direction blended toward a diffuse one by `roughness`). Next-event
// estimation on the diffuse lobe, combined with BSDF sampling by the power
// heuristic, so the image converges to the same answer as plain path
// tracing. Russian roulette after `rr_depth` bounces.
#import path

struct Params {
    spp: u32, // ui: 1..64 "samples per pixel"
    max_depth: u32, // ui: 1..64 limit "max bounces"
    rr_depth: u32, // ui: 0..16 "roulette from bounce"
    // Samples already in `radiance` from earlier dispatches this frame: the
    // engine splits spp across dispatches of at most 8 (drivers bound the
    // loop iterations of one invocation; src/graph/compile/split.rs).
    spp_done: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var radiance: texture_storage_2d<rgba32float, write>;
// The camera ray's first hit, as the G-buffer stores it (for reprojection
// in accumulate): position and distance (direction and -1 on a miss), and
// the normal facing the camera with the specular share in w.
@group(0) @binding(2) var gbuf_pos: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var gbuf_normal: texture_storage_2d<rgba16float, write>;
// `radiance` again, for the later dispatches of a split frame (main_more).
@group(0) @binding(4) var radiance_acc: texture_storage_2d<rgba32float, read_write>;

const SALT: u32 = 0x70617468u;

// The sum of this dispatch's `spp` samples of pixel `id`. Each dispatch of
// a split frame draws its own random stream (the first one's is what an
// unsplit frame draws).
fn sample_sum(id: vec2u) -> vec3f {
    var rng = rng_for(id, frame.frame_index, SALT + params.spp_done * 0x9e3779b9u, frame.seed);
    let spp = max(params.spp, 1u);
    var sum = vec3f(0.0);
    for (var s = 0u; s < spp; s++) {
        let rd = camera_dir(frame.camera, id, rand2(&rng));
        sum += trace_path(frame.camera.origin, rd, params.max_depth, params.rr_depth, true, &rng);
    }
    return sum;
}

@compute @workgroup_size(64, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let sum = sample_sum(id.xy);
    textureStore(radiance, id.xy, vec4f(sum / f32(max(params.spp, 1u)), 1.0));
    textureStore(gbuf_pos, id.xy, path_primary_pos);
    textureStore(gbuf_normal, id.xy, path_primary_normal);
}

// A later dispatch of a split frame: the mean of spp_done samples already
// in radiance_acc, updated with this dispatch's spp more.
@compute @workgroup_size(64, 1)
fn main_more(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let sum = sample_sum(id.xy);
    let before = textureLoad(radiance_acc, id.xy).rgb;
    let n = f32(params.spp_done) + f32(max(params.spp, 1u));
    textureStore(radiance_acc, id.xy, vec4f(before + (sum - f32(max(params.spp, 1u)) * before) / n, 1.0));
}
