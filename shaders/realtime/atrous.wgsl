// One iteration of the denoiser's edge-stopping à-trous wavelet filter
// (SVGF): a 3x3 B-spline kernel with its taps STEP pixels apart (the
// graph runs it at steps 1, 2, 4, 8, 16), each tap weighted by its surface
// (normal and plane, shared/realtime_common.wgsl) and by how far its
// demodulated colour lies from this pixel's in units of the standard
// deviation of their difference (the variances of the two means,
// `filtered_in`.w), or, where that lets more through, how far its and
// the opposite tap's mean lies (a gradient's two sides cancel there, so
// the wider steps filter smooth gradients too; docs/realtime.md, "Taps
// in pairs"). The variance is filtered with the squared weights for the
// next iteration.
//
// Entry `main` writes the next iteration's input; `last` is the final
// iteration and remodulates: R + A (F - I), the filtered demodulated
// light F brought back onto the pixel's unbiased mean R (with one sample
// this is A F, SVGF's remodulation; as the filter fades, F tends to I and
// the image to R, the plain mean of the path tracer's samples, whatever
// the jittered rays saw at an edge, where A I is not R). Pixels without a
// lit surface (A = 0) show R.
//
// SPLIT_DIRECT graphs filter the first hit's direct light apart, by its
// own variance: `main_split` filters it beside the rest (the same surface
// weights, its own colour test), and `last_split` adds it the same way:
// A (Fd - Dd), Fd its filtered result and Dd its unfiltered mean
// (temporal.wgsl's `direct_in`).
//
// Once the camera and scene have stood still for `until_frames` frames
// (0: never), an iteration passes its input through, and the pass costs
// a load and a store (realtime.ron stops its wide steps so: by then
// their taps reach surfaces whose light differs by more than the means'
// noise, and remove little; docs/realtime.md, "In the limit"). Over the
// second half of those frames it fades into its input (docs/realtime.md,
// "Still frames thinned, and the wide steps faded out").
#import realtime_common

override STEP: i32 = 1;
// Whether a tap may pass the pair's colour test too (below; 0 takes each
// tap's own test alone: for measuring what the pairs bring).
override PAIRS: bool = true;
// SPLIT_DIRECT steps: the still frames after which the direct light is no
// longer filtered (0: never), fading out over the second half of them as
// `until_frames` does. Its samples at the first hit see every light, so
// its mean is soon certain, and the filter's taps then only bend it where
// a penumbra meets the umbra or the lit floor (docs/realtime.md, "The
// direct light's filter fades out").
override DIRECT_UNTIL_FRAMES: u32 = 0u;
// The colour tests' sigma once the image has stood still for 16 frames
// (0: `sigma_l` throughout), reached linearly from `sigma_l` at 8. The
// means' noise falls as 1/sqrt(n), so the tests let less and less through;
// a wider sigma makes the narrow steps, which never stop, fade more slowly
// (docs/realtime.md, "A wider colour test once still").
override STILL_SIGMA_L: f32 = 0.0;
// This pixel's colour sigma this frame (set by filter_at).
var<private> colour_sigma: f32;

struct Params {
    sigma_l: f32, // ui: 0.5..64 log "luminance sigma"
    depth_sigma: f32, // ui: 0.1..16 log "depth sigma (pixel footprints)"
    until_frames: u32, // ui: 0..4096 "still frames filtered (0: always)"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var filtered_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var guide: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var filtered: texture_storage_2d<rgba32float, write>;
// `last` only: the history's means this frame, and the image.
@group(0) @binding(4) var illum: texture_storage_2d<rgba32float, read>;
@group(0) @binding(5) var color: texture_storage_2d<rgba32float, read>;
@group(0) @binding(6) var albedo: texture_storage_2d<rgba32float, read>;
@group(0) @binding(7) var output: texture_storage_2d<rgba32float, write>;
// `last_split` only: the filtered direct light and its unfiltered mean.
@group(0) @binding(8) var direct: texture_storage_2d<rgba32float, read>;
@group(0) @binding(9) var direct_in: texture_storage_2d<rgba32float, read>;
// `main_split` only: the direct light's input and output, as
// filtered_in and filtered.
@group(0) @binding(10) var direct_filtered_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(11) var direct_filtered: texture_storage_2d<rgba32float, write>;

// This iteration at pixel p: the filtered light and the variance of it,
// and with `with_direct` the same for the direct light (`dtex`, its own
// colour test, the same surface weights). Textures are arguments so that
// `main` and `last` pass `tex` twice and bind no direct light; a constant
// `with_direct` is folded away where the driver inlines the call.
struct Filtered {
    light: vec4f,
    direct: vec4f,
}

fn filter_at(p: vec2i, tex: texture_storage_2d<rgba32float, read>, dtex: texture_storage_2d<rgba32float, read>, with_direct: bool) -> Filtered {
    // Once the image has stood still long enough the step passes its
    // input through, reading nothing else (the condition is the same for
    // every lane, so a SIMD driver skips what follows).
    if passes_through() {
        return Filtered(textureLoad(tex, p), select(vec4f(0.0), textureLoad(dtex, p), with_direct));
    }
    // All nine texels loaded first, surface or not: loaded under the
    // surface test's lane mask, the steps took 1.05-1.12x the time on
    // lavapipe (docs/realtime.md, "Cost at 1280x720").
    let w = Window(
        load_texel(p + vec2i(-STEP, -STEP), tex, dtex, with_direct), load_texel(p + vec2i(STEP, STEP), tex, dtex, with_direct),
        load_texel(p + vec2i(0, -STEP), tex, dtex, with_direct), load_texel(p + vec2i(0, STEP), tex, dtex, with_direct),
        load_texel(p + vec2i(STEP, -STEP), tex, dtex, with_direct), load_texel(p + vec2i(-STEP, STEP), tex, dtex, with_direct),
        load_texel(p + vec2i(-STEP, 0), tex, dtex, with_direct), load_texel(p + vec2i(STEP, 0), tex, dtex, with_direct),
    );
    return filter_window(load_texel(p, tex, dtex, with_direct), w, with_direct);
}

fn passes_through() -> bool {
    return params.until_frames > 0u && frame.accum_count >= params.until_frames;
}

// A texel a step reads: its two signals and its surface, and whether it
// lies in the image (a tap outside gets none of its weight; its texel is
// the nearest one inside).
struct Texel {
    light: vec4f,
    direct: vec4f,
    guide: Guide,
    inside: bool,
}

fn load_texel(q: vec2i, tex: texture_storage_2d<rgba32float, read>, dtex: texture_storage_2d<rgba32float, read>, with_direct: bool) -> Texel {
    let c = clamp(q, vec2i(0), vec2i(frame.size) - 1);
    var d = vec4f(0.0);
    if with_direct {
        d = textureLoad(dtex, c);
    }
    return Texel(textureLoad(tex, c), d, load_guide(guide, c), all(q == c));
}

// A pixel's eight taps, in opposite pairs (a, b): up and left of the
// centre (up-left, up, up-right, left), and opposite.
struct Window {
    a0: Texel,
    b0: Texel,
    a1: Texel,
    b1: Texel,
    a2: Texel,
    b2: Texel,
    a3: Texel,
    b3: Texel,
}

// This iteration at the pixel whose texel is `own`, from its window.
fn filter_window(own: Texel, w: Window, with_direct: bool) -> Filtered {
    colour_sigma = params.sigma_l;
    if STILL_SIGMA_L > 0.0 {
        colour_sigma = mix(params.sigma_l, STILL_SIGMA_L, clamp((f32(frame.accum_count) - 8.0) / 8.0, 0.0, 1.0));
    }
    let gp = own.guide;
    // 1/4, 1/2, 1/4 in each axis; the centre's weight is (1/2)^2.
    var sums = Both(centre_sums(own.light), centre_sums(own.direct));
    // The taps off the centre, where a lane has a surface to filter, in
    // opposite pairs. Written out, the four pairs take plain steps
    // 0.92-0.96x the time of a loop over them on lavapipe
    // (docs/realtime.md, "Cost at 1280x720").
    if gp.surface {
        let axis = plane_scale(gp, params.depth_sigma) / f32(STEP);
        let diagonal = axis * (1.0 / sqrt(2.0));
        let c = Centre(gp, own.light, own.direct);
        sums = add_taps(sums, c, w.a0, w.b0, diagonal, 0.0625, with_direct);
        sums = add_taps(sums, c, w.a1, w.b1, axis, 0.125, with_direct);
        sums = add_taps(sums, c, w.a2, w.b2, diagonal, 0.0625, with_direct);
        sums = add_taps(sums, c, w.a3, w.b3, axis, 0.125, with_direct);
    }
    let filtered = Filtered(normalised(sums.light), normalised(sums.direct));
    // Over the second half of `until_frames` the step fades into its input,
    // so that it stops without a jump in noise (a uniform test: the frames
    // before keep the filtered value exactly).
    let fade = still_share(params.until_frames);
    let fade_d = fade * still_share(DIRECT_UNTIL_FRAMES);
    if fade < 1.0 || fade_d < 1.0 {
        return Filtered(mix(own.light, filtered.light, fade), mix(own.direct, filtered.direct, fade_d));
    }
    return filtered;
}

// Pixel pairs (the `_pairs` entries, run with the graph's
// `texels_per_invocation: 2`): an invocation filters pixels p and
// p + (STEP, 0), whose windows share six of their nine texels, loading 12
// texels for both instead of 18 (a texel load is most of a step's cost on
// a CPU driver). Each pixel's arithmetic is the single entries', so the
// images are the same bit for bit.
struct Pair {
    a: Filtered,
    b: Filtered,
}

fn filter_pair(p: vec2i, tex: texture_storage_2d<rgba32float, read>, dtex: texture_storage_2d<rgba32float, read>, with_direct: bool) -> Pair {
    let s = STEP;
    if passes_through() {
        return Pair(filter_at(p, tex, dtex, with_direct), filter_at(p + vec2i(s, 0), tex, dtex, with_direct));
    }
    // Rows -STEP, 0, STEP; columns -STEP, 0, STEP, 2 STEP.
    let t00 = load_texel(p + vec2i(-s, -s), tex, dtex, with_direct);
    let t01 = load_texel(p + vec2i(0, -s), tex, dtex, with_direct);
    let t02 = load_texel(p + vec2i(s, -s), tex, dtex, with_direct);
    let t03 = load_texel(p + vec2i(2 * s, -s), tex, dtex, with_direct);
    let t10 = load_texel(p + vec2i(-s, 0), tex, dtex, with_direct);
    let t11 = load_texel(p, tex, dtex, with_direct);
    let t12 = load_texel(p + vec2i(s, 0), tex, dtex, with_direct);
    let t13 = load_texel(p + vec2i(2 * s, 0), tex, dtex, with_direct);
    let t20 = load_texel(p + vec2i(-s, s), tex, dtex, with_direct);
    let t21 = load_texel(p + vec2i(0, s), tex, dtex, with_direct);
    let t22 = load_texel(p + vec2i(s, s), tex, dtex, with_direct);
    let t23 = load_texel(p + vec2i(2 * s, s), tex, dtex, with_direct);
    return Pair(
        filter_window(t11, Window(t00, t22, t01, t21, t02, t20, t10, t12), with_direct),
        filter_window(t12, Window(t01, t23, t02, t22, t03, t21, t11, t13), with_direct),
    );
}

// How many pairs a row holds: pixel x with x + STEP for every x whose
// x / STEP is even (the last such x may have no partner in the row).
fn row_pairs() -> u32 {
    let s = u32(STEP);
    let w = frame.size.x;
    return (w / (2u * s)) * s + min(w % (2u * s), s);
}

// The first pixel of a row's pair j.
fn pair_x(j: u32) -> u32 {
    let s = u32(STEP);
    return (j / s) * 2u * s + j % s;
}

// A pair's two values stored (the second where it lies in the image).
fn store_pair(p: vec2i, a: vec4f, b: vec4f) {
    textureStore(filtered, p, a);
    if p.x + STEP < i32(frame.size.x) {
        textureStore(filtered, p + vec2i(STEP, 0), b);
    }
}

// A step's share of its output: 1 until half of `until_frames` still
// frames (0: always), then falling linearly to 0 at `until_frames`. The
// variance is mixed alike: an upper bound on the variance of the mix
// (the deviations' mix bounds the mix's deviation; the square is convex).
fn still_share(until_frames: u32) -> f32 {
    if until_frames == 0u {
        return 1.0;
    }
    let u = f32(until_frames);
    return clamp(2.0 * (u - f32(frame.accum_count)) / u, 0.0, 1.0);
}

// The pixel a step filters: its surface and its two signals.
struct Centre {
    guide: Guide,
    light: vec4f,
    direct: vec4f,
}

// Both signals' sums.
struct Both {
    light: Sums,
    direct: Sums,
}

// Taps a and b added to both signals' sums, weighed by their surfaces
// (`scale`: the plane test's, per unit of distance) and colours, `kernel`
// the B-spline's weight of each.
fn add_taps(s: Both, c: Centre, ta: Texel, tb: Texel, scale: f32, kernel: f32, with_direct: bool) -> Both {
    // The surface tests' exponents (a pair needs both taps in the image).
    let ea = select(NO_WEIGHT, geometry_exponent(c.guide, ta.guide, scale), ta.inside);
    let eb = select(NO_WEIGHT, geometry_exponent(c.guide, tb.guide, scale), tb.inside);
    var out = s;
    out.light = add_pair(s.light, c.light, ta.light, tb.light, ea, eb, kernel);
    if with_direct {
        out.direct = add_pair(s.direct, c.direct, ta.direct, tb.direct, ea, eb, kernel);
    }
    return out;
}

// One signal's weighted sums: of the values (the variances by the squared
// weights) and of the weights.
struct Sums {
    sum: vec4f,
    w: f32,
}

fn centre_sums(own: vec4f) -> Sums {
    return Sums(vec4f(0.25 * own.rgb, 0.0625 * own.a), 0.25);
}

// Taps a and b of a pair added, each weighed by its surface test times its
// own colour test or the pair's, whichever lets more through (as
// exp(-min(x, y)): one exponential a tap). `ea`, `eb`: the surface
// tests' exponents.
fn add_pair(s: Sums, own: vec4f, ta: vec4f, tb: vec4f, ea: f32, eb: f32, kernel: f32) -> Sums {
    let pair = select(NO_WEIGHT, max(ea, eb) + pair_test(own, ta, tb), PAIRS);
    let wa = kernel * exp(-min(ea + colour_test(own, ta), pair));
    let wb = kernel * exp(-min(eb + colour_test(own, tb), pair));
    return Sums(s.sum + vec4f(wa * ta.rgb + wb * tb.rgb, wa * wa * ta.a + wb * wb * tb.a), s.w + wa + wb);
}

// The filtered value and the variance of it.
fn normalised(s: Sums) -> vec4f {
    return vec4f(s.sum.rgb / s.w, s.sum.a / (s.w * s.w));
}

// How far two opposite taps' mean lies from the pixel's colour, in units
// of the deviation of their difference (the three means' noise).
fn pair_test(own: vec4f, a: vec4f, b: vec4f) -> f32 {
    let m = 0.5 * (a.rgb + b.rgb) - own.rgb;
    let colour = max(abs(m.r), max(abs(m.g), abs(m.b)));
    return colour / (colour_sigma * sqrt(own.a + 0.25 * (a.a + b.a)) + 1e-20);
}

// How far a tap's demodulated colour lies from the pixel's, in units of
// the difference's own deviation (both means' noise): a symmetric test, so
// a noisy pixel that its neighbours smooth also spreads into them and the
// filter keeps the image's energy.
fn colour_test(own: vec4f, tap: vec4f) -> f32 {
    let colour = max(abs(tap.r - own.r), max(abs(tap.g - own.g), abs(tap.b - own.b)));
    return colour / (colour_sigma * sqrt(own.a + tap.a) + 1e-20);
}

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    textureStore(filtered, id.xy, filter_at(vec2i(id.xy), filtered_in, filtered_in, false).light);
}

// `main` for the direct light too (SPLIT_DIRECT graphs' first steps).
@compute @workgroup_size(128, 1)
fn main_split(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let f = filter_at(vec2i(id.xy), filtered_in, direct_filtered_in, true);
    textureStore(filtered, id.xy, f.light);
    textureStore(direct_filtered, id.xy, f.direct);
}

@compute @workgroup_size(128, 1)
fn last(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    remodulate(id.xy, vec3f(0.0));
}

@compute @workgroup_size(128, 1)
fn last_split(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    remodulate(id.xy, textureLoad(direct, id.xy).rgb - textureLoad(direct_in, id.xy).rgb);
}

// The pairs' entries: `main` and `last_split` two pixels an invocation
// (`main_split`'s pairs, which load the direct light too, took 1.09x its
// time: twelve texels of three textures held at once). A row may hold a
// few more pairs than half its width, but never more than the dispatch's
// whole workgroups of 128 lanes cover while 2 STEP divides 256 (the
// graphs' steps are powers of two up to 16). (A loop over pairs, for any
// STEP, took 1.4-1.7x the time on lavapipe.)
@compute @workgroup_size(128, 1)
fn main_pairs(@builtin(global_invocation_id) id: vec3u) {
    if id.x < row_pairs() && id.y < frame.size.y {
        let p = vec2i(vec2u(pair_x(id.x), id.y));
        let f = filter_pair(p, filtered_in, filtered_in, false);
        store_pair(p, f.a.light, f.b.light);
    }
}

@compute @workgroup_size(128, 1)
fn last_split_pairs(@builtin(global_invocation_id) id: vec3u) {
    if id.x < row_pairs() && id.y < frame.size.y {
        let p = vec2i(vec2u(pair_x(id.x), id.y));
        let f = filter_pair(p, filtered_in, filtered_in, false);
        let pa = vec2u(p);
        remodulate_filtered(pa, f.a.light.rgb, textureLoad(direct, pa).rgb - textureLoad(direct_in, pa).rgb);
        let pb = pa + vec2u(u32(STEP), 0u);
        if pb.x < frame.size.x {
            remodulate_filtered(pb, f.b.light.rgb, textureLoad(direct, pb).rgb - textureLoad(direct_in, pb).rgb);
        }
    }
}

// The image: R + A (F - I + extra), F this iteration's filtered light.
fn remodulate(pixel: vec2u, extra: vec3f) {
    remodulate_filtered(pixel, filter_at(vec2i(pixel), filtered_in, filtered_in, false).light.rgb, extra);
}

fn remodulate_filtered(pixel: vec2u, f: vec3f, extra: vec3f) {
    let i = textureLoad(illum, pixel).rgb;
    let r = textureLoad(color, pixel).rgb;
    let a = textureLoad(albedo, pixel).rgb;
    textureStore(output, pixel, vec4f(max(r + a * (f - i + extra), vec3f(0.0)), 1.0));
}
