// Progressive accumulation: a per-pixel running mean of `src`. Entry
// `main` as below; `reset` is mode 0 without the G-buffer and `geo`.
//   mode 0 (the thesis): the history is dropped whenever the camera or the
//          scene changes (frame.accum_count = 0).
//   mode 1: the history survives camera motion. Each pixel's G-buffer hit is
//          projected with last frame's camera; the four history texels
//          around where this pixel's centre was are blended bilinearly,
//          keeping only those whose stored hit lies on this pixel's surface
//          plane (within depth_tol of the distance) with a normal within
//          normal_cos; disocclusions start over, and so do specular
//          surfaces (gbuf_normal.w > 0: what they show depends on the
//          view, so their history is wrong once it moves). A scene change (moving
//          lights or objects, frame.epoch_frames = 0) still drops it all.
// `geo` keeps what the next frame checks against: the octahedral normal,
// the hit distance (-1 on a miss) and the pixel's sample count (as a float,
// for viewing; the count itself is the u32 in `comp`).
// `comp` (rgba32uint) holds the mean's Kahan compensation (rgb, f32 bits)
// and the sample count (a): see shared/mean.wgsl.
// max_history > 0 caps the count (an exponential average past it).
// A sample holding NaN or Inf is not accumulated (the pixel keeps its
// history); negative radiance counts as 0; clamp_max > 0 scales samples
// brighter than it down to it (a firefly clamp, biased; 0 = off).
#import mean
#import reproject

struct Params {
    mode: u32, // ui: 0..1 "mode (0 reset, 1 reproject)"
    depth_tol: f32, // ui: 0.0001..0.1 log "depth tolerance"
    normal_cos: f32, // ui: 0..1 "normal cos"
    max_history: u32, // ui: 0..4096 "max history (0: none)"
    clamp_max: f32, // ui: 0..1000 "firefly clamp (0: off)"
}

// Set by the engine per frame (a second pipeline, chosen when the frame's
// camera is bit for bit last frame's: src/graph/pipelines.rs): then every
// pixel's motion is exactly zero and its one history tap is its own
// texel, so mode 1 skips the projection, the tap loop and the surface test
// it would otherwise run, at least masked, for every pixel (accumulate
// took about 0.45x the time with the camera still).
override CAMERA_STILL: bool = false;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var src: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var accum_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var accum: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var gbuf_pos: texture_storage_2d<rgba32float, read>;
@group(0) @binding(5) var gbuf_normal: texture_storage_2d<rgba16float, read>;
@group(0) @binding(6) var geo_prev: texture_storage_2d<rgba32float, read>;
@group(0) @binding(7) var geo: texture_storage_2d<rgba32float, write>;
@group(0) @binding(8) var comp_prev: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(9) var comp: texture_storage_2d<rgba32uint, write>;

// A pixel's history: its mean and how many samples made it.
struct History {
    mean: Mean,
    count: u32,
}

fn load_history(q: vec2i) -> History {
    let c = textureLoad(comp_prev, q);
    let m = Mean(textureLoad(accum_prev, q).rgb, bitcast<vec3f>(c.rgb));
    // History that is not finite (it should never be) starts over.
    if !all_finite(m.value) || !all_finite(m.comp) {
        return History(Mean(vec3f(0.0), vec3f(0.0)), 0u);
    }
    return History(m, c.a);
}

// Whether history texel `q`, whose `geo` record is `g`, saw the same
// surface as this pixel's hit `p` (normal `n`), or, for a miss, also a miss.
fn agrees(q: vec2i, g: vec4f, p: vec3f, n: vec3f, miss: bool) -> bool {
    return same_surface(q, g, p, n, miss, params.normal_cos, params.depth_tol);
}

// Last frame's history at this pixel, or none: the mean and compensation
// blended over the accepted taps, the count the smallest of theirs (an
// integer, and never more samples than the least-sampled tap had).
fn reprojected(pixel: vec2u, g: vec4f, n: vec3f, view_dependent: bool) -> History {
    let none = History(Mean(vec3f(0.0), vec3f(0.0)), 0u);
    let miss = g.w < 0.0;
    let fp = footprint(pixel, g, view_dependent);
    if !fp.valid {
        return none;
    }
    var value = vec3f(0.0);
    var compensation = vec3f(0.0);
    var count = 0xffffffffu;
    var weight = 0.0;
    for (var k = 0u; k < fp.taps; k++) {
        let tap = footprint_tap(fp, k);
        let q = tap.q;
        let w = tap.w;
        if w <= 0.0 {
            continue;
        }
        // A still camera sees the same footprint: no test needed (it would
        // otherwise reject silhouette pixels whose jittered samples differ).
        if !fp.still && !agrees(q, textureLoad(geo_prev, q), g.xyz, n, miss) {
            continue;
        }
        let h = load_history(q);
        value += w * h.mean.value;
        compensation += w * h.mean.comp;
        count = min(count, h.count);
        weight += w;
    }
    if weight < 1e-3 || count == 0u {
        return none;
    }
    return History(Mean(value / weight, compensation / weight), count);
}

// What `reprojected` gives when the camera has not moved, bit for bit:
// motion is zero, so the one tap is this pixel's own texel with weight 1
// (for finite G-buffer data; a NaN position has no motion to reproject).
fn still_history(h: History, g: vec4f) -> History {
    let miss = g.w < 0.0;
    let cam = frame.prev_camera;
    let then_z = dot(select(g.xyz, miss_point(cam, g.xyz), miss) - cam.origin, cam.forward);
    if then_z <= 0.0 || h.count == 0u {
        return History(Mean(vec3f(0.0), vec3f(0.0)), 0u);
    }
    // The blend starts from +0, so a -0 there comes out +0.
    let value = select(h.mean.value, vec3f(0.0), h.mean.value == vec3f(0.0));
    let comp = select(h.mean.comp, vec3f(0.0), h.mean.comp == vec3f(0.0));
    return History(Mean(value, comp), h.count);
}

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let g = textureLoad(gbuf_pos, id.xy);
    let nw = textureLoad(gbuf_normal, id.xy);
    let n = nw.xyz;
    var history = History(Mean(vec3f(0.0), vec3f(0.0)), 0u);
    // This pixel's own history, which mode 0 and a still camera's mode 1
    // both read: loaded once (a load in each branch ran twice, the two
    // branches under their lane masks).
    let own = load_history(vec2i(id.xy));
    if params.mode == 0u {
        if frame.accum_count > 0u {
            history = own;
            history.count = frame.accum_count;
        }
    } else if frame.epoch_frames > 0u {
        if CAMERA_STILL {
            history = still_history(own, g);
        } else {
            history = reprojected(id.xy, g, n, nw.w > 0.0);
        }
    }
    let count = add_sample(id.xy, history);
    textureStore(geo, id.xy, vec4f(normal_to_oct(n), select(g.w, -1.0, g.w < 0.0), f32(count)));
}

// Mode 0 alone, without the geometry: `src` into the pixel's own history,
// which any camera or scene change drops. For a graph that never
// reprojects (pathtrace.ron): no G-buffer to read and no `geo` to write,
// so its first pass need not store a G-buffer either.
@compute @workgroup_size(128, 1)
fn reset(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    var history = History(Mean(vec3f(0.0), vec3f(0.0)), 0u);
    if frame.accum_count > 0u {
        history = load_history(vec2i(id.xy));
        history.count = frame.accum_count;
    }
    add_sample(id.xy, history);
}

// Adds this frame's sample of `src` to `history` and stores the mean and
// its compensation and count; returns the count.
fn add_sample(id: vec2u, history: History) -> u32 {
    let sample = clean_sample(textureLoad(src, id).rgb, params.clamp_max);
    var count = history.count;
    if params.max_history > 0u {
        count = min(count, params.max_history);
    }
    var m = history.mean;
    if sample.valid {
        m = mean_add(m, sample.value, count, frame.exact_one);
        count += 1u;
    }
    textureStore(accum, id, vec4f(m.value, 1.0));
    textureStore(comp, id, vec4u(bitcast<vec3u>(m.comp), count));
    return count;
}
