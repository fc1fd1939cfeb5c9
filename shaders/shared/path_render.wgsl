// The path tracer's passes (thesis 2.4), shared by shaders/pathtrace.wgsl,
// shaders/pathtrace_gbuffer.wgsl and the real-time graphs' path passes:
// its params, its radiance output, the `main` and `main_more` entries. The
// importing shader defines the hook below, which `main` calls once per
// pixel with its sample and the camera ray's first hit (shared/path.wgsl's
// path_primary_pos / _normal / _ids, kept with FIRST_HIT): pathtrace.wgsl
// stores the sample in `radiance` and drops the hit, pathtrace_gbuffer.wgsl
// stores the hit as the G-buffer does, and the real-time path passes pack
// the sample beside the hit. So a graph binds only what a pass of it
// reads. (A CPU driver runs a store in `main`'s loop on every trip, under
// its lane mask: each texel stored there costs about a tenth of the
// real-time path pass.)
// hook: fn store_sample(pixel: vec2u, radiance: vec3f, pos: vec4f, normal: vec4f, ids: vec4u)
// (with SPLIT_DIRECT, `path_pixel_direct` holds the pixel's mean of the
// first hit's direct light, shared/path.wgsl).
#import path

var<private> path_pixel_direct: vec3f;

// A uniform number in [0, 1) for pixel `pixel`'s sample this frame, from
// a stream of its own (the path's numbers stay what they were): what a
// path pass that packs its sample rounds with (realtime_common.wgsl).
// The stream's frame key is hashed once, before `render`'s loop: a CPU
// driver runs the hook on every trip of the loop and does not hoist what
// depends on uniforms only (hashing it there cost the real-time path
// pass 3%).
const SAMPLE_DITHER_SALT: u32 = 0x64697468u;

var<private> path_dither_key: u32;

fn sample_dither(pixel: vec2u) -> f32 {
    var rng = rng_at(path_dither_key, pixel);
    return rand_f32(&rng);
}

// A new path: no first hit recorded, no direct light counted.
fn start_first_hit() {
    path_primary_pos = vec4f(0.0);
    path_primary_normal = vec4f(0.0);
    path_primary_ids = vec4u(NO_HIT, NO_HIT, 0u, NO_HIT);
    path_primary_open = true;
    path_primary_direct = vec3f(0.0);
    path_primary_albedo = vec4f(0.0);
    path_direct = vec3f(0.0);
    path_direct_from = vec3f(0.0);
    path_direct_state = 0u;
    path_lobe_pending = false;
    path_lobe_traced = false;
}

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
// `radiance` again, for the later dispatches of a split frame (main_more).
@group(0) @binding(4) var radiance_acc: texture_storage_2d<rgba32float, read_write>;


// The first dispatch (`main`) renders several texels per invocation, the
// graph's `texels_per_invocation`: texels k, k + L, k + 2L, ... in row-major
// order for invocation k of the L dispatched. Each lane starts its next
// path as soon as one ends, and traces the new camera ray together with
// the ended path's last shadow ray. A SIMD group then runs as many bounce
// trips as its lanes need in all, where with one texel per invocation it
// ran as many as its longest path needed (on the Cornell box 3.73 trips
// per group of 8 against 2.66 per path). Each texel's random numbers are
// its own, so the image is the same whatever the dispatch.
fn render(flat: ptr<function, FlatScene>, id: vec3u, groups: vec3u) {
    let lanes = groups.x * 64u * groups.y;
    let n = frame.size.x * frame.size.y;
    var p = id.y * groups.x * 64u + id.x;
    if p >= n {
        return;
    }
    let spp = max(params.spp, 1u);
    let max_depth = params.max_depth;
    var pixel = vec2u(p % frame.size.x, p / frame.size.x);
    // The step from one texel of this lane to its next, as a 2D offset:
    // a SIMD CPU driver divides integers one lane at a time, so the next
    // pixel is stepped to, not divided out, on every trip.
    let step = vec2u(lanes % frame.size.x, lanes / frame.size.x);
    let rng_key = rng_frame_key(frame.frame_index, PATH_RENDER_SALT + params.spp_done * 0x9e3779b9u, frame.seed);
    var rng = rng_at(rng_key, pixel);
    start_blue_noise(pixel, frame.frame_index);
    path_dither_key = rng_frame_key(frame.frame_index, SAMPLE_DITHER_SALT, frame.seed);
    var s = 0u;
    var sum = vec3f(0.0);
    var direct_sum = vec3f(0.0);
    var st = new_path(frame.camera.origin, camera_dir(frame.camera, pixel, rand2(&rng)), pixel_spread());
    // A scene of one mesh and nothing else (ONE_MESH) takes the plain
    // traversal: lavapipe (Mesa 22.3.6) crashed in its queue thread running
    // the tile-entry traversal of a one-mesh scene beside the entry's copy
    // of scene_flat (tests/degenerate.rs, an OBJ opened on its own).
    var hit: Hit;
    if ONE_MESH {
        hit = trace_closest(frame.camera.origin, st.rd, 3.0e38);
    } else {
        hit = trace_closest_through(pixel, st.rd, 3.0e38);
    }
    start_first_hit();
    loop {
        var b = ended_bounce();
        if st.depth < max_depth {
            b = path_bounce(&st, hit, params.rr_depth, true, &rng);
        }
        // A coat's specular lobe waiting (SPLIT_LOBES, shared/path.wgsl)
        // is this path's next ray once its diffuse lobe's path ends.
        let ends = b.ended || !b.go_on || st.depth + 1u >= max_depth;
        let switch_lobe = lobe_follows(ends);
        let path_done = ends && !switch_lobe;
        let pixel_done = path_done && s + 1u >= spp;
        let next_p = p + lanes;
        let lane_done = pixel_done && next_p >= n;
        var next_pixel = pixel + step;
        if next_pixel.x >= frame.size.x {
            next_pixel = vec2u(next_pixel.x - frame.size.x, next_pixel.y + 1u);
        }
        // The ray to trace: the path's next, or the next path's camera ray.
        var ro = b.o;
        var rd = st.rd;
        if switch_lobe {
            ro = path_lobe_o;
            rd = path_lobe_dir;
        } else if path_done && !lane_done {
            if pixel_done {
                rng = rng_at(rng_key, next_pixel);
                start_blue_noise(next_pixel, frame.frame_index);
            }
            ro = frame.camera.origin;
            rd = camera_dir(frame.camera, select(pixel, next_pixel, pixel_done), rand2(&rng));
        }
        let next = trace_pair(flat, ro, rd, !lane_done, b.o, b.shadow_dir, b.shadow_tmax, b.shadow_light);
        if !next.blocked {
            st.result += b.shadowed_light;
        }
        end_direct(st.result);
        if path_done {
            sum += finite_or_zero(st.result);
            if SPLIT_DIRECT {
                direct_sum += finite_or_zero(path_direct_total(st.result));
            }
            s += 1u;
            if pixel_done {
                path_pixel_direct = direct_sum / f32(spp);
                store_sample(pixel, sum / f32(spp), path_primary_pos, path_primary_normal, path_primary_ids);
                if lane_done {
                    break;
                }
                p = next_p;
                pixel = next_pixel;
                s = 0u;
                sum = vec3f(0.0);
                direct_sum = vec3f(0.0);
            }
            st = new_path(ro, rd, pixel_spread());
            start_first_hit();
        } else if switch_lobe {
            start_lobe(&st);
        } else {
            st.depth += 1u;
        }
        hit = next.hit;
    }
}

@compute @workgroup_size(64, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(num_workgroups) groups: vec3u) {
    // First thing, where every lane runs (see trace_pair).
    var flat = scene_flat;
    render(&flat, id, groups);
}

// The sum of this dispatch's `spp` samples of pixel `id`. Each dispatch of
// a split frame draws its own random stream (the first one's is what an
// unsplit frame draws).
fn sample_sum(flat: ptr<function, FlatScene>, id: vec2u) -> vec3f {
    var rng = rng_for(id, frame.frame_index, PATH_RENDER_SALT + params.spp_done * 0x9e3779b9u, frame.seed);
    let spp = max(params.spp, 1u);
    var sum = vec3f(0.0);
    for (var s = 0u; s < spp; s++) {
        let rd = camera_dir(frame.camera, id, rand2(&rng));
        sum += trace_path(flat, frame.camera.origin, rd, pixel_spread(), params.max_depth, params.rr_depth, true, &rng);
    }
    return sum;
}

// The later dispatches of a split spp (src/graph/compile/split.rs), one
// texel per invocation, blending into what the earlier ones left.
@compute @workgroup_size(128, 1)
fn main_more(@builtin(global_invocation_id) id: vec3u) {
    var flat = scene_flat;
    if !in_frame(id) {
        return;
    }
    let sum = sample_sum(&flat, id.xy);
    let before = textureLoad(radiance_acc, id.xy).rgb;
    let n = f32(params.spp_done) + f32(max(params.spp, 1u));
    textureStore(radiance_acc, id.xy, vec4f(before + (sum - f32(max(params.spp, 1u)) * before) / n, 1.0));
}
