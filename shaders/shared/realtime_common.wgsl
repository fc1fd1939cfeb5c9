// What the real-time denoiser's passes share (shaders/realtime/): the
// `guide` texture temporal.wgsl writes and the spatial passes read, the
// edge-stopping weights between two pixels' surfaces (SVGF, Schied et
// al. 2017), and how much light changed around a pixel (the gradients).
#import frame
#import reproject

// guide's w where a pixel shows no lit surface (a miss, a light): the
// filters neither blur it nor blur it into its neighbours.
const NO_SURFACE: u32 = 0xffffffffu;

fn luminance(c: vec3f) -> f32 {
    return dot(c, vec3f(0.2126, 0.7152, 0.0722));
}

// One pixel's surface as guide holds it: the hit relative to the camera,
// the shading normal (`surface` false: no lit surface), and whether it was
// seen through a mirror (`mirror`: GUIDE_MIRROR_BIT or 0; geometry_exponent).
struct Guide {
    p: vec3f,
    n: vec3f,
    surface: bool,
    mirror: u32,
}

// guide's w: a unit normal, x and y in 11 bits, z in 9, each mapped from
// -1..1, and GUIDE_MIRROR_BIT where the surface was seen through a mirror
// (THROUGH_MIRRORS). Decoding takes shifts and one multiply-add per
// component and no normalisation (a packed octahedral normal's decode cost
// a quarter of an à-trous step on a CPU driver); the components are within
// 1/511 of the normal's, which geometry_weight's test by the normals'
// difference tolerates. Never NO_SURFACE: all ones decodes to (1, 1, 1),
// not a unit normal.
const GUIDE_MIRROR_BIT: u32 = 0x80000000u;

fn pack_guide_normal(n: vec3f, through_mirror: bool) -> u32 {
    let q = vec3u(round((clamp(n, vec3f(-1.0), vec3f(1.0)) * 0.5 + 0.5) * vec3f(2047.0, 2047.0, 511.0)));
    return q.x | (q.y << 11u) | (q.z << 22u) | select(0u, GUIDE_MIRROR_BIT, through_mirror);
}

fn unpack_guide_normal(w: u32) -> vec3f {
    let q = vec3u(w & 0x7ffu, (w >> 11u) & 0x7ffu, (w >> 22u) & 0x1ffu);
    return vec3f(q) * vec3f(2.0 / 2047.0, 2.0 / 2047.0, 2.0 / 511.0) - 1.0;
}

// The path pass's first hit beside its position and sample (`gbuf_sample`,
// pack_position_sample), in one texel (`gbuf_hit`, rgba32uint), so that
// the path pass stores two texels a pixel (a CPU driver runs a store in
// the path loop on every trip, under its lane mask):
//   x: the shading normal facing the ray, octahedral in two 16-bit snorms
//      (within about 5e-5; guide's 11-11-10 packing, within 1e-3, moved
//      a grazing light's shading by percents);
//   y: the albedo, 10 bits a channel in [0, 1], bit 30 set where what the
//      hit shows depends on the view, bit 31 where it is a lit surface
//      (an object that does not glow);
//   z: the hit's error bound (f32 bits, what its rays are offset by;
//      MISS_ERROR_BITS where the ray hit nothing), its sign bit set where
//      the hit was seen through a mirror (THROUGH_MIRRORS);
//   w: the light the hit received directly (SPLIT_DIRECT, shared/path.wgsl;
//      else 0), shared-exponent RGB9E5.
// The albedo's and the direct light's rounding cost nothing in the end:
// the denoiser divides and multiplies by the same albedo, and the direct
// light's rounding only moves light between what it filters and what it
// does not.
const VIEW_DEPENDENT_BIT: u32 = 0x40000000u;
const LIT_SURFACE_BIT: u32 = 0x80000000u;
// The error bound of a miss (-1.0): no bound is negative.
const MISS_ERROR_BITS: u32 = 0xbf800000u;

// gbuf_hit's error word for a first hit (`pos` its path_primary_pos: w < 0
// on a miss), with its sign set where the hit was seen through a mirror
// (a bound of exactly 1 seen through one would read as a miss, so it grows
// by one ulp: still a bound).
fn first_hit_error_bits(pos: vec4f, error_bits: u32, through_mirror: bool) -> u32 {
    if pos.w < 0.0 {
        return MISS_ERROR_BITS;
    }
    let error = select(error_bits, error_bits | 0x80000000u, through_mirror);
    return error + u32(error == MISS_ERROR_BITS);
}

fn pack_first_hit(normal: vec4f, albedo: vec4f, error_bits: u32, direct: vec3f) -> vec4u {
    let flags = select(0u, VIEW_DEPENDENT_BIT, normal.w > 0.0) | select(0u, LIT_SURFACE_BIT, albedo.w > 0.0);
    return vec4u(pack2x16snorm(normal_to_oct(normal.xyz)), pack_albedo(albedo.rgb) | flags, error_bits, pack_rgb9e5(direct));
}

// The albedo's 10 bits a channel (gbuf_hit's y without its flags).
fn pack_albedo(albedo: vec3f) -> u32 {
    let q = vec3u(round(clamp(albedo, vec3f(0.0), vec3f(1.0)) * 1023.0));
    return q.r | (q.g << 10u) | (q.b << 20u);
}

fn unpack_albedo(y: u32) -> vec3f {
    return vec3f(vec3u(y & 0x3ffu, (y >> 10u) & 0x3ffu, (y >> 20u) & 0x3ffu)) / 1023.0;
}

// `gbuf_sample` in a frame whose filter does not run (THINNED, with
// THIN_STORES on the path pass and `temporal`): only what `temporal`
// folds into the history, in one texel, so that the path pass stores one
// texel a pixel there instead of two:
//   x: the sample (pack_sample);
//   y: the albedo (pack_albedo), LIT_SURFACE_BIT set where the hit is a
//      lit surface and not a miss;
//   z: the light the hit received directly, RGB9E5 (as gbuf_hit's w).
// The same bits as gbuf_sample's w and gbuf_hit's y and w, so the history
// is the same bit for bit; gbuf_hit is left as it was.
fn pack_thin_sample(sample_bits: u32, albedo: vec3f, surface: bool, direct: vec3f) -> vec4u {
    return vec4u(sample_bits, pack_albedo(albedo) | select(0u, LIT_SURFACE_BIT, surface), pack_rgb9e5(direct), 0u);
}

// What gbuf_hit holds, unpacked.
struct FirstHit {
    miss: bool,
    n: vec3f,
    view_dependent: bool,
    lit: bool,
    albedo: vec3f,
    error: f32,
    direct: vec3f,
    through_mirror: bool,
}

fn unpack_first_hit(h: vec4u) -> FirstHit {
    let albedo = unpack_albedo(h.y);
    let miss = h.z == MISS_ERROR_BITS;
    return FirstHit(miss, oct_to_normal(unpack2x16snorm(h.x)), (h.y & VIEW_DEPENDENT_BIT) != 0u, (h.y & LIT_SURFACE_BIT) != 0u, albedo, bitcast<f32>(h.z & 0x7fffffffu), unpack_rgb9e5(h.w), !miss && h.z >= 0x80000000u);
}

// RGB in 32 bits: a 9-bit mantissa a channel and a shared 5-bit exponent
// (the format of Vulkan's E5B9G9R9), for values from 0 to 65408
// (clamped; not finite: 0).
const RGB9E5_MAX: f32 = 65408.0;

fn pack_rgb9e5(c_in: vec3f) -> u32 {
    let finite = c_in == c_in & abs(c_in) < vec3f(3.0e38);
    let c = select(vec3f(0.0), clamp(c_in, vec3f(0.0), vec3f(RGB9E5_MAX)), finite);
    let top = max(c.r, max(c.g, c.b));
    // The exponent of the largest channel, biased by 15 (and at least
    // -16), read from its f32 bits (0 and subnormals read -127), and the
    // power of two its mantissas are counted in, as its reciprocal: exact
    // bit operations where log2, exp2 and three divisions cost the path
    // pass 2.5% (this runs on every trip of its loop on a CPU driver).
    var e = max(-16, i32((bitcast<u32>(top) >> 23u) & 0xffu) - 127) + 16;
    var inv_scale = bitcast<f32>(u32(151 - e) << 23u);
    if round(top * inv_scale) >= 512.0 {
        e += 1;
        inv_scale *= 0.5;
    }
    let m = vec3u(round(c * inv_scale));
    return m.r | (m.g << 9u) | (m.b << 18u) | (u32(e) << 27u);
}

fn unpack_rgb9e5(v: u32) -> vec3f {
    let m = vec3f(vec3u(v & 0x1ffu, (v >> 9u) & 0x1ffu, (v >> 18u) & 0x1ffu));
    return m * exp2(f32(i32(v >> 27u) - 24));
}

// `gbuf_sample` of the real-time graphs (rgba32uint): the first hit's position
// (f32 bits; a miss's ray direction) and the pixel's sample in w, eight
// bits a channel under the largest channel's exponent (pack_sample).
fn pack_position_sample(pos: vec3f, sample: vec3f, u: f32) -> vec4u {
    return vec4u(bitcast<vec3u>(pos), pack_sample(sample, u));
}

struct PositionSample {
    p: vec3f,
    sample: vec3f,
}

fn unpack_position_sample(v: vec4u) -> PositionSample {
    return PositionSample(bitcast<vec3f>(v.xyz), unpack_sample(v.w));
}

// A radiance sample in 32 bits: an 8-bit mantissa a channel and the f32
// exponent of the largest (from 2^-119; below, 0). Each channel is
// rounded down or up at random (`u` uniform in [0, 1)), so its expected
// value is the sample's: the pixel's mean over frames stays unbiased
// where rounding to nearest would shift a constant dark channel by up to
// half a step (1/512 of the largest). Negative and not finite: 0.
fn pack_sample(c_in: vec3f, u: f32) -> u32 {
    let c = select(vec3f(0.0), c_in, c_in > vec3f(0.0) & c_in < vec3f(3.0e38));
    let top = max(c.r, max(c.g, c.b));
    let e = (bitcast<u32>(top) >> 23u) & 0xffu;
    if e < 8u {
        return 0u;
    }
    // 2^(134 - e): the largest channel to [128, 256).
    let scale = bitcast<f32>((261u - e) << 23u);
    let m = vec3u(min(floor(c * scale + u), vec3f(255.0)));
    return m.r | (m.g << 8u) | (m.b << 16u) | (e << 24u);
}

fn unpack_sample(v: u32) -> vec3f {
    let e = v >> 24u;
    let m = vec3f(vec3u(v & 0xffu, (v >> 8u) & 0xffu, (v >> 16u) & 0xffu));
    // 2^(e - 134); e is 0 only for a sample of 0.
    return m * bitcast<f32>(select(0u, (e - 7u) << 23u, e >= 8u));
}

fn load_guide(t: texture_storage_2d<rgba32uint, read>, q: vec2i) -> Guide {
    let g = textureLoad(t, q);
    return Guide(bitcast<vec3f>(g.xyz), unpack_guide_normal(g.w), g.w != NO_SURFACE, g.w & GUIDE_MIRROR_BIT);
}

// 1 / (depth_sigma pixel footprints at p's distance): geometry_weight's
// plane test per pixel of distance, computed once per pixel.
fn plane_scale(p: Guide, depth_sigma: f32) -> f32 {
    let footprint = length(p.p) * 2.0 * frame.camera.tan_half_fov / f32(frame.size.y);
    return 1.0 / (depth_sigma * footprint + 1e-20);
}

// How sharply the normals' test falls: exp(-NORMAL_SHARPNESS |n_p - n_q|^2),
// which for unit normals is exp(-2 NORMAL_SHARPNESS (1 - cos)), about
// cos^8 near cos 1: 0.34 at 30 degrees, 0.10 at 45, 3e-4 at 90 (a room's
// corner). SVGF's cos^64 (32 here) left curved surfaces, whose neighbours'
// normals differ by a few degrees, almost unfiltered: sharpness 4 lowers
// every scene's first frame FLIP (docs/realtime.md, "The normals' test").
const NORMAL_SHARPNESS: f32 = 4.0;

// How much pixel q's surface counts toward pixel p's, times exp(-extra)
// (one exponential for both surface tests and the caller's own): normals
// within a narrow cone, and q's hit near p's tangent plane, within
// `depth_sigma` pixel footprints per pixel of distance (`scale`:
// plane_scale over the distance in pixels). Between two pixels that both
// show what a mirror shows the normals alone: the real-time path pass
// unfolds those hits into the camera's view (shaders/realtime/path.wgsl),
// and behind a curved mirror the unfolded points do not lie in the
// tangent planes of the unfolded normals.
fn geometry_weight(p: Guide, q: Guide, scale: f32, extra: f32) -> f32 {
    return exp(-geometry_exponent(p, q, scale) - extra);
}

// The exponent of geometry_weight (its weight is exp(-it)); NO_WEIGHT
// where either pixel has no surface.
const NO_WEIGHT: f32 = 1.0e30;

fn geometry_exponent(p: Guide, q: Guide, scale: f32) -> f32 {
    let dn = p.n - q.n;
    let plane = select(abs(dot(q.p - p.p, p.n)), 0.0, (p.mirror & q.mirror) != 0u);
    return select(NO_WEIGHT, NORMAL_SHARPNESS * dot(dn, dn) + plane * scale, p.surface && q.surface);
}

// Pixels per side of a gradient stratum (shaders/realtime/gradient.wgsl).
const GRADIENT_STRATUM: f32 = 3.0;

// The share of the light around last frame's pixel position `then`
// that changed this frame, from the 3x3 strata of `gradient` (written by
// gradient.wgsl in frames whose scene changed) around it. `mean_change`:
// the change of their sum, |sum(new - old)| / sum(max): how much the
// light's mean changed, single paths' changes of opposite sign cancelling
// (the denoiser's history, which holds a mean). Otherwise the sum of the
// paths' own changes, sum(|new - old|) / sum(max) (a reservoir holds
// samples: one that changed is stale even where the mean did not).
fn changed_share(gradient: texture_storage_2d<rgba32float, read>, then: vec2f, mean_change: bool) -> f32 {
    let c = vec2i(floor(then / GRADIENT_STRATUM));
    let strata = vec2i(textureDimensions(gradient));
    var diff = 0.0;
    var scale = 0.0;
    let taps = 9u * u32(frame.exact_one);
    for (var k = 0u; k < taps; k++) {
        let q = clamp(c + vec2i(i32(k % 3u) - 1, i32(k / 3u) - 1), vec2i(0), strata - 1);
        let g = textureLoad(gradient, q);
        diff += select(g.z, g.x, mean_change);
        scale += g.y;
    }
    return select(0.0, clamp(abs(diff) / scale, 0.0, 1.0), scale > 0.0);
}
