// Direct light at each pixel's first hit by reservoir resampling (ReSTIR
// DI: Bitterli et al. 2020; Wyman et al.'s 2023 course notes), over all
// the scene's lights, for the diffuse lobe the path pass leaves apart
// (shared/path.wgsl FIRST_DIRECT_APART). Samples and weights:
// shared/restir.wgsl.
//
// `main`: `candidates` light samples (a light chosen uniformly, a point on
// it by cone sampling) resampled into one by p̂ (RIS), then, with
// `temporal`, resampled with last frame's reservoir where this pixel's hit
// was, if that pixel saw the same surface (its M capped at `history_m`
// times `candidates`, `moving_m` times in frames whose scene changed, and
// by the temporal gradients where light changed).
// `last`: resampled with `spatial` neighbours' reservoirs within `radius`
// pixels whose surface is alike (normals within `normal_cos`, the
// neighbour's hit within `depth_tol` of this pixel's distance from its
// tangent plane). Both weigh the reservoirs by pairwise MIS
// (shared/restir.wgsl), which keeps the result unbiased. Then one shadow
// ray toward the chosen sample, its light added to the path pass's
// sample (`gbuf_sample_out`: gbuf_sample with the sum); the reservoir is kept
// for the next frame.
#import restir
#import path
#import realtime_common

// Set by the engine per frame (src/graph/frame_kind.rs): no last frame's
// reservoir to read (NO_HISTORY), no gradients to test (SCENE_STILL).
override SCENE_STILL: bool = false;
override NO_HISTORY: bool = false;

struct Params {
    candidates: u32, // ui: 1..64 "light candidates a pixel"
    temporal: u32, // ui: 0..1 "reuse last frame's reservoir"
    history_m: f32, // ui: 0..64 "history M (x candidates)"
    moving_m: f32, // ui: 0..64 "history M while the scene moves (x candidates)"
    gradient_gain: f32, // ui: 0..16 "gradient gain (0: gradients off)"
    spatial: u32, // ui: 0..8 "spatial neighbours"
    radius: f32, // ui: 1..64 "neighbour radius (pixels)"
    normal_cos: f32, // ui: 0..1 "normal cos"
    depth_tol: f32, // ui: 0.001..1 log "depth tolerance"
}

@group(0) @binding(0) var<uniform> params: Params;
// The first hit's position and the path's sample (realtime_common.wgsl,
// pack_position_sample).
@group(0) @binding(1) var gbuf_sample: texture_storage_2d<rgba32uint, read>;
// The rest of the first hit (shared/realtime_common.wgsl,
// pack_first_hit): its normal, and its error bound, what a surface's
// shadow rays are offset by.
@group(0) @binding(2) var gbuf_hit: texture_storage_2d<rgba32uint, read>;
// The path pass's record for this pass: the factor the hit's light
// arrives with (f32 bits) and the packed geometric normal.
@group(0) @binding(3) var di_surface: texture_storage_2d<rgba32uint, read>;
// `main`: last frame's reservoirs and geometry (temporal.wgsl's `geo`).
@group(0) @binding(4) var reservoir_prev: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(5) var geo_prev: texture_storage_2d<rgba32float, read>;
// This frame's reservoirs after `main`.
@group(0) @binding(6) var reservoir_out: texture_storage_2d<rgba32uint, write>;
// `main`: the temporal gradients (gradient.wgsl), read in frames whose
// scene changed.
@group(0) @binding(11) var gradient: texture_storage_2d<rgba32float, read>;
// `last`:
@group(0) @binding(7) var reservoir_in: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(9) var reservoir: texture_storage_2d<rgba32uint, write>;
// gbuf_sample with the direct light added to the sample.
@group(0) @binding(10) var gbuf_sample_out: texture_storage_2d<rgba32uint, write>;

const CANDIDATE_SALT: u32 = 0x72657331u;
const SPATIAL_SALT: u32 = 0x72657332u;
// The repacked sample's rounding (pack_sample).
const DITHER_SALT: u32 = 0x72657333u;

fn surface_at(q: vec2i) -> Surface {
    let g = bitcast<vec3f>(textureLoad(gbuf_sample, q).xyz);
    let t = textureLoad(di_surface, q);
    let ng = oct_to_normal(unpack2x16snorm(t.w));
    let first = unpack_first_hit(textureLoad(gbuf_hit, q));
    var s = make_surface(g, first.n, ng, bitcast<vec3f>(t.xyz), first.error);
    s.valid = s.valid && !first.miss;
    return s;
}

// Where last frame's hit of pixel q was: its camera ray, jittered as the
// path pass jittered it then (the first two numbers of that pixel's path
// stream, shared/path.wgsl), at the distance `geo_prev` keeps, with its
// normal (which stands in for the geometric one).
fn previous_surface(q: vec2i, g: vec4f) -> Surface {
    var rng = rng_at(rng_frame_key(frame.frame_index - 1u, PATH_RENDER_SALT, frame.seed), vec2u(q));
    let dir = camera_dir(frame.prev_camera, vec2u(q), rand2(&rng));
    let n = oct_to_normal(g.xy);
    // The point o + t d: its error from its operands (pbrt's bound for a
    // multiply and an add), and the bound of a triangle's interpolation
    // at it, as the hit it stands for had at least that.
    let p = frame.prev_camera.origin + g.z * dir;
    let error = f32_gamma(9.0) * dot(abs(frame.prev_camera.origin) + abs(g.z * dir), vec3f(1.0));
    return make_surface(p, n, n, vec3f(1.0), error);
}

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let s = surface_at(vec2i(id.xy));
    var r = empty_reservoir();
    if !s.valid {
        textureStore(reservoir_out, id.xy, encode_reservoir(r));
        return;
    }
    var rng = rng_for(id.xy, frame.frame_index, CANDIDATE_SALT, frame.seed);
    let candidates = max(params.candidates, 1u);
    for (var k = 0u; k < candidates; k++) {
        let c = draw_candidate(s, &rng);
        stream(&r, c.light, c.oct, c.p_hat, c.w, 1.0, rand_f32(&rng));
    }
    // The candidates share this surface: W = w_sum / (M p̂).
    let ok = r.light != NO_SAMPLE && r.p_hat > 0.0;
    r.w = select(0.0, r.w / (r.m * r.p_hat), ok);
    if params.temporal != 0u && !NO_HISTORY && frame.history_frames > 0u {
        let then = project(frame.prev_camera, s.p);
        let q = vec2i(floor(then.xy));
        let inside = then.z > 0.0 && all(q >= vec2i(0)) && all(q < vec2i(frame.size));
        let g = textureLoad(geo_prev, select(vec2i(0), q, inside));
        if inside && same_surface(q, g, s.p, s.n, false, params.normal_cos, params.depth_tol) {
            var prev = decode_reservoir(textureLoad(reservoir_prev, q));
            var cap = params.history_m;
            if frame.epoch_frames == 0u {
                cap = params.moving_m;
            }
            var m_max = cap * f32(candidates);
            // Where the light changed, last frame's reservoir weighs its
            // sample by how the light was (a light that moved closer
            // stays dark, then fades in over its history): cut it as
            // temporal.wgsl cuts the denoiser's history, to (1 - g lambda)
            // / (g lambda) times this frame's candidates.
            if !SCENE_STILL && frame.epoch_frames == 0u && params.gradient_gain > 0.0 {
                let lambda = min(params.gradient_gain * changed_share(gradient, then.xy, false), 1.0);
                m_max = min(m_max, f32(candidates) * (1.0 - lambda) / max(lambda, 1e-6));
            }
            prev.m = min(prev.m, floor(m_max));
            var pw = pairwise_begin(s, r, 1u);
            pairwise_add(&pw, s, previous_surface(q, g), prev, true, &rng);
            r = pairwise_end(&pw, &rng);
        }
    }
    textureStore(reservoir_out, id.xy, encode_reservoir(r));
}

@compute @workgroup_size(128, 1)
fn last(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let pixel = vec2i(id.xy);
    let s = surface_at(pixel);
    var r = empty_reservoir();
    var direct = vec3f(0.0);
    if s.valid {
        var rng = rng_for(id.xy, frame.frame_index, SPATIAL_SALT, frame.seed);
        let spatial = min(params.spatial, 8u);
        var pw = pairwise_begin(s, decode_reservoir(textureLoad(reservoir_in, pixel)), spatial);
        let depth = length(s.p - frame.camera.origin);
        for (var k = 0u; k < spatial; k++) {
            let u = rand2(&rng);
            let a = 2.0 * PI * u.y;
            let q = pixel + vec2i(round(params.radius * sqrt(u.x) * vec2f(cos(a), sin(a))));
            let inside = any(q != pixel) && all(q >= vec2i(0)) && all(q < vec2i(frame.size));
            // (A neighbour off the image loads this pixel instead and is
            // not taken: no branch around the loads, which a CPU driver
            // would run under a mask anyway.)
            let qc = select(pixel, q, inside);
            let sq = surface_at(qc);
            let alike = inside && sq.valid && dot(sq.n, s.n) >= params.normal_cos && abs(dot(sq.p - s.p, s.n)) <= params.depth_tol * depth;
            pairwise_add(&pw, s, sq, decode_reservoir(textureLoad(reservoir_in, qc)), alike, &rng);
        }
        r = pairwise_end(&pw, &rng);
        direct = shade_reservoir(s, r);
    }
    textureStore(reservoir, id.xy, encode_reservoir(r));
    let before = unpack_position_sample(textureLoad(gbuf_sample, pixel));
    var dither = rng_for(id.xy, frame.frame_index, DITHER_SALT, frame.seed);
    textureStore(gbuf_sample_out, id.xy, pack_position_sample(before.p, before.sample + direct, rand_f32(&dither)));
}
