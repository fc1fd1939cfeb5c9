// The denoiser's temporal step (SVGF, Schied et al. 2017): this frame's
// path-traced sample, demodulated by its first hit's albedo, joins the
// pixel's reprojected history as a running mean, with the luminance's
// second moment for the variance and the history length.
//
// What each history texture keeps, per pixel (all means over the same
// `n` samples):
//   illum:  the demodulated light I (radiance, less the first hit's
//           direct light under SPLIT_DIRECT, over the albedo: what the
//           filter smooths), n in w;
//   color:  the radiance R itself, direct light and all (the unbiased
//           mean remodulation falls back to as the filter fades), the
//           second moment of lum(I) in w;
//   albedo: the first hit's albedo A (jittered rays see both sides of an
//           edge), the second moment of lum(D / A) in w (D the first
//           hit's direct light under SPLIT_DIRECT);
//   geo:    the octahedral normal and hit distance (-1: no lit surface),
//           for the next frame's reprojection, and this frame's sample
//           luminance in w, for the next frame's gradients.
//
// History is kept while lights move: instead of dropping it all whenever
// the scene changes (accumulate.wgsl), each pixel keeps what is still
// right. In a frame whose scene changed, the temporal gradients
// (gradient.wgsl: last frame's paths traced again in the changed scene)
// of the 3x3 strata around where the pixel was last frame give the share
// of its light that changed, lambda; its history is cut to at most
// (1 - g lambda) / (g lambda) samples (g `gradient_gain`), so that the new
// sample weighs at least g lambda (A-SVGF's alpha). While the scene moves
// the history is also capped at `moving_history`. A still scene keeps it
// all, so a still image converges to the path tracer's mean.
//
// Entry `split` also writes `direct_in`, the direct light's filter input
// (SPLIT_DIRECT graphs filter it apart, with its own variance): its mean
// over the albedo, (R - A I) / A, and the variance of that mean from the
// pixel's own moments.
//
// Also writes `guide`, what the spatial passes test neighbours with: the
// hit relative to the camera (f32 bits) and the packed normal with whether
// the hit was seen through a mirror (NO_SURFACE for misses and lights,
// which the filters leave alone).
#import reproject
#import finite
#import realtime_common

struct Params {
    normal_cos: f32, // ui: 0..1 "normal cos"
    depth_tol: f32, // ui: 0.0001..0.1 log "depth tolerance"
    max_history: u32, // ui: 0..4096 "max history (0: none)"
    moving_history: u32, // ui: 0..256 "history while the scene moves (0: no cap)"
    gradient_gain: f32, // ui: 0..16 "gradient gain (0: gradients off)"
}

// Set by the engine per frame (src/graph/frame_kind.rs), each compiling
// out code whose branch the frame decides (a CPU driver runs both sides of
// a branch under lane masks). CAMERA_STILL: the camera is bit for bit
// last frame's, so each pixel's history is its own texel, and the
// reprojection's arithmetic is not compiled in (at 1280x720 a still
// frame's pass takes 0.62x the time). SCENE_STILL: the scene did not
// change, so no history is tested against gradients (0.75x). NO_HISTORY:
// a first frame, with no history to read.
override CAMERA_STILL: bool = false;
override SCENE_STILL: bool = false;
override NO_HISTORY: bool = false;

@group(0) @binding(0) var<uniform> params: Params;
// The first hit's position and the pixel's sample
// (shared/realtime_common.wgsl, pack_position_sample).
@group(0) @binding(2) var gbuf_sample: texture_storage_2d<rgba32uint, read>;
// The rest of the first hit (shared/realtime_common.wgsl, pack_first_hit).
@group(0) @binding(3) var gbuf_hit: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(5) var illum_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(6) var color_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(7) var albedo_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(8) var geo_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(9) var illum: texture_storage_2d<rgba32float, write>;
@group(0) @binding(10) var color: texture_storage_2d<rgba32float, write>;
@group(0) @binding(11) var albedo: texture_storage_2d<rgba32float, write>;
@group(0) @binding(12) var geo: texture_storage_2d<rgba32float, write>;
@group(0) @binding(13) var guide: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(14) var gradient: texture_storage_2d<rgba32float, read>;
// The filter's input: the demodulated mean and the variance of that mean
// from the pixel's own moments (variance.wgsl refines it).
@group(0) @binding(15) var filter_in: texture_storage_2d<rgba32float, write>;
// Entry `split` only: the direct light's filter input, as filter_in.
@group(0) @binding(16) var direct_in: texture_storage_2d<rgba32float, write>;

// Whether the scene changed since last frame, with a last frame in the
// history (a new session's first frame has none).
fn scene_changed() -> bool {
    return !SCENE_STILL && !NO_HISTORY && frame.epoch_frames == 0u && frame.history_frames > 0u;
}

// A pixel's history, or this frame's sample as one.
struct State {
    illum: vec3f,
    color: vec3f,
    albedo: vec3f,
    m2: f32,
    m2_direct: f32,
    n: f32,
}

fn no_state() -> State {
    return State(vec3f(0.0), vec3f(0.0), vec3f(0.0), 0.0, 0.0, 0.0);
}

fn load_state(q: vec2i) -> State {
    let i = textureLoad(illum_prev, q);
    let c = textureLoad(color_prev, q);
    let a = textureLoad(albedo_prev, q);
    let s = State(i.rgb, c.rgb, a.rgb, c.a, a.a, i.a);
    // History that is not finite (it should never be) starts over.
    if !all_finite(s.illum) || !all_finite(s.color) || !all_finite(vec3f(s.m2, s.n, s.m2_direct)) {
        return no_state();
    }
    return s;
}

// Weighted sum of states (the bilinear blend of history taps).
fn blend(a: State, b: State, w: f32) -> State {
    return State(a.illum + w * b.illum, a.color + w * b.color, a.albedo + w * b.albedo, a.m2 + w * b.m2, a.m2_direct + w * b.m2_direct, a.n + w * b.n);
}

// Last frame's history at this pixel: the bilinear taps around where its
// hit was last frame that saw the same surface, blended; the length the
// smallest of theirs (never more samples than the least-sampled tap had).
// View-dependent pixels (a specular share) keep none once the camera moves.
fn reprojected(pixel: vec2u, g: vec4f, n: vec3f, view_dependent: bool) -> State {
    let miss = g.w < 0.0;
    let fp = footprint(pixel, g, view_dependent);
    if !fp.valid {
        return no_state();
    }
    var sum = no_state();
    var count = 3.0e38;
    var weight = 0.0;
    for (var k = 0u; k < fp.taps; k++) {
        let tap = footprint_tap(fp, k);
        let q = tap.q;
        let w = tap.w;
        if w <= 0.0 {
            continue;
        }
        // A still camera in a still scene sees the same surfaces (testing
        // would drop silhouettes, whose jittered hits differ); after a
        // scene change it may not: what moved (a light's own pixels, an
        // object) is tested.
        if (!fp.still || scene_changed()) && !same_surface(q, textureLoad(geo_prev, q), g.xyz, n, miss, params.normal_cos, params.depth_tol) {
            continue;
        }
        let h = load_state(q);
        sum = blend(sum, h, w);
        count = min(count, h.n);
        weight += w;
    }
    if weight < 1e-3 || count < 1.0 {
        return no_state();
    }
    var h = blend(no_state(), sum, 1.0 / weight);
    h.n = count;
    return h;
}

// A still camera's history at this pixel: its own texel, kept unless the
// scene changed and what the texel saw is no longer this pixel's surface
// (an object or a light moved through it).
fn still_history(pixel: vec2u, g: vec4f, n: vec3f) -> State {
    let q = vec2i(pixel);
    var h = load_state(q);
    if scene_changed() && !same_surface(q, textureLoad(geo_prev, q), g.xyz, n, g.w < 0.0, params.normal_cos, params.depth_tol) {
        h = no_state();
    }
    if h.n < 1.0 {
        h = no_state();
    }
    return h;
}

// Demodulated by the albedo: channels without albedo 0 (remodulation
// multiplies them by it again).
fn demodulate(l: vec3f, a: vec3f) -> vec3f {
    return select(vec3f(0.0), l / max(a, vec3f(1e-3)), a > vec3f(1e-3));
}

// With THIN_STORES (set with the path pass's, realtime/path.wgsl): in a
// frame whose filter does not run (THINNED, from the engine like the
// flags above; always a still frame with history) the path pass stores
// only what the history takes (pack_thin_sample), and this pass writes
// only the history: no filter input or guide, which no pass reads there.
override THIN_STORES: bool = false;
override THINNED: bool = false;

fn thinned() -> bool {
    return THIN_STORES && THINNED;
}

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    if thinned() {
        thin_step(id.xy);
        return;
    }
    temporal_step(id.xy);
}

@compute @workgroup_size(128, 1)
fn split(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    if thinned() {
        thin_step(id.xy);
        return;
    }
    textureStore(direct_in, id.xy, temporal_step(id.xy));
}

// This frame's sample of a pixel as the history takes it.
struct Sample {
    // The radiance R (0 where not finite: `valid` false).
    l: vec3f,
    // The albedo A (0 where the hit is no lit surface).
    a: vec3f,
    // The demodulated light I, and lum(I) and lum(D / A).
    i: vec3f,
    lum_i: f32,
    lum_d: f32,
    valid: bool,
}

fn take_sample(radiance: vec3f, surface: bool, albedo: vec3f, direct: vec3f) -> Sample {
    let a = select(vec3f(0.0), albedo, surface);
    var l = radiance;
    let valid = all_finite(l);
    l = select(vec3f(0.0), max(l, vec3f(0.0)), valid);
    // The light the hit received directly stays out of the filtered
    // signal (SPLIT_DIRECT): R holds it, entry `split` hands it to a filter
    // of its own, and this one sees the rest, the noisier light of later
    // bounces.
    let d = select(vec3f(0.0), min(direct, l), surface);
    let i = demodulate(l - d, a);
    return Sample(l, a, i, luminance(i), luminance(demodulate(d, a)), valid);
}

// The history `h`, cut to `n` samples, with the sample added (`h.n` the
// new length).
fn fold(h_in: State, n_in: f32, s: Sample) -> State {
    var h = h_in;
    var n = n_in;
    if s.valid {
        let k = 1.0 / (n + 1.0);
        h.illum = mix(h.illum, s.i, k);
        h.color = mix(h.color, s.l, k);
        h.albedo = mix(h.albedo, s.a, k);
        h.m2 = mix(h.m2, s.lum_i * s.lum_i, k);
        h.m2_direct = mix(h.m2_direct, s.lum_d * s.lum_d, k);
        n += 1.0;
    }
    h.n = n;
    return h;
}

fn store_history(pixel: vec2u, h: State) {
    textureStore(illum, pixel, vec4f(h.illum, h.n));
    textureStore(color, pixel, vec4f(h.color, h.m2));
    textureStore(albedo, pixel, vec4f(h.albedo, h.m2_direct));
}

// The pixel's temporal step in a frame whose filter does not run: a still
// frame (the filter thins only those), so the history is the pixel's own
// texel, as still_history keeps it in a still scene. `geo` keeps last
// frame's normal and distance (this frame's jittered hit is not stored)
// with this frame's sample luminance for the gradients.
fn thin_step(pixel: vec2u) {
    let t = textureLoad(gbuf_sample, pixel);
    let s = take_sample(unpack_sample(t.x), (t.y & LIT_SURFACE_BIT) != 0u, unpack_albedo(t.y), unpack_rgb9e5(t.z));
    var h = load_state(vec2i(pixel));
    if h.n < 1.0 {
        h = no_state();
    }
    var n = h.n;
    if params.max_history > 0u {
        n = min(n, f32(params.max_history));
    }
    store_history(pixel, fold(h, n, s));
    textureStore(geo, pixel, vec4f(textureLoad(geo_prev, pixel).xyz, luminance(s.l)));
}

// The pixel's temporal step; returns the direct light's filter input.
fn temporal_step(pixel: vec2u) -> vec4f {
    let ps = unpack_position_sample(textureLoad(gbuf_sample, pixel));
    let hit = unpack_first_hit(textureLoad(gbuf_hit, pixel));
    let miss = hit.miss;
    // The hit and its distance from the camera (-1: a miss, whose xyz is
    // its ray's direction), as reprojection takes them.
    let g = vec4f(ps.p, select(length(ps.p - frame.camera.origin), -1.0, miss));
    let surface = !miss && hit.lit;
    let s = take_sample(ps.sample, surface, hit.albedo, hit.direct);

    var h = no_state();
    if !NO_HISTORY && frame.history_frames > 0u {
        if CAMERA_STILL {
            h = still_history(pixel, g, hit.n);
        } else {
            h = reprojected(pixel, g, hit.n, hit.view_dependent);
        }
    }
    var n = h.n;
    if params.max_history > 0u {
        n = min(n, f32(params.max_history));
    }
    if scene_changed() && params.moving_history > 0u {
        n = min(n, f32(params.moving_history));
    }
    if scene_changed() && params.gradient_gain > 0.0 && n > 0.0 {
        let then = project(frame.prev_camera, select(g.xyz, miss_point(frame.prev_camera, g.xyz), miss));
        let lambda = min(params.gradient_gain * changed_share(gradient, then.xy, true), 1.0);
        n = min(n, (1.0 - lambda) / max(lambda, 1e-6));
    }
    h = fold(h, n, s);
    n = h.n;
    store_history(pixel, h);
    let m1 = luminance(h.illum);
    textureStore(filter_in, pixel, vec4f(h.illum, max(h.m2 - m1 * m1, 0.0) / max(n, 1.0)));
    textureStore(geo, pixel, vec4f(select(normal_to_oct(hit.n), vec2f(0.0), miss), select(g.w, -1.0, miss), luminance(s.l)));
    let rel = g.xyz - frame.camera.origin;
    textureStore(guide, pixel, vec4u(bitcast<vec3u>(rel), select(NO_SURFACE, pack_guide_normal(hit.n, hit.through_mirror), surface)));
    // The direct light's mean: what R holds beyond A I (exactly the mean
    // of D where the albedo did not vary over the samples).
    let direct = demodulate(max(h.color - h.albedo * h.illum, vec3f(0.0)), h.albedo);
    let m1_direct = luminance(direct);
    return vec4f(direct, max(h.m2_direct - m1_direct * m1_direct, 0.0) / max(n, 1.0));
}
