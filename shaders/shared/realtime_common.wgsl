// What the real-time denoiser's passes share (shaders/realtime/): the
// `guide` texture temporal.wgsl writes and the spatial passes read, the
// edge-stopping weights between two pixels' surfaces (SVGF, Schied et
// al. 2017), and how much light changed around a pixel (the gradients).
#import frame

// guide's w where a pixel shows no lit surface (a miss, a light): the
// filters neither blur it nor blur it into its neighbours.
const NO_SURFACE: u32 = 0xffffffffu;

fn luminance(c: vec3f) -> f32 {
    return dot(c, vec3f(0.2126, 0.7152, 0.0722));
}

// One pixel's surface as guide holds it: the hit relative to the camera
// and the shading normal (`surface` false: no lit surface).
struct Guide {
    p: vec3f,
    n: vec3f,
    surface: bool,
}

fn load_guide(t: texture_storage_2d<rgba32uint, read>, q: vec2i) -> Guide {
    let g = textureLoad(t, q);
    let surface = g.w != NO_SURFACE;
    let o = unpack2x16snorm(g.w);
    var n = vec3f(o, 1.0 - abs(o.x) - abs(o.y));
    if n.z < 0.0 {
        n = vec3f((1.0 - abs(n.yx)) * select(vec2f(-1.0), vec2f(1.0), n.xy >= vec2f(0.0)), n.z);
    }
    return Guide(bitcast<vec3f>(g.xyz), normalize(n), surface);
}

// How much pixel q's surface counts toward pixel p's, `dist` pixels away:
// normals within a narrow cone (cos^64), and q's hit near p's tangent plane
// (within `depth_sigma` pixel footprints per pixel of distance).
fn geometry_weight(p: Guide, q: Guide, dist: f32, depth_sigma: f32) -> f32 {
    if !p.surface || !q.surface {
        return 0.0;
    }
    var c = max(dot(p.n, q.n), 0.0);
    c = c * c;
    c = c * c;
    c = c * c;
    c = c * c;
    c = c * c;
    c = c * c;
    // One pixel's footprint at p's distance.
    let footprint = length(p.p) * 2.0 * frame.camera.tan_half_fov / f32(frame.size.y);
    let plane = abs(dot(q.p - p.p, p.n));
    return c * exp(-plane / (depth_sigma * footprint * dist + 1e-20));
}

// Pixels per side of a gradient stratum (shaders/realtime/gradient.wgsl).
const GRADIENT_STRATUM: f32 = 3.0;

// The share of the light around last frame's pixel position `then`
// that changed this frame: the 3x3 strata of `gradient` (written by
// gradient.wgsl in frames whose scene changed) around it, summed.
fn changed_share(gradient: texture_storage_2d<rgba32float, read>, then: vec2f) -> f32 {
    let c = vec2i(floor(then / GRADIENT_STRATUM));
    let strata = vec2i(textureDimensions(gradient));
    var diff = 0.0;
    var scale = 0.0;
    let taps = 9u * u32(frame.exact_one);
    for (var k = 0u; k < taps; k++) {
        let q = clamp(c + vec2i(i32(k % 3u) - 1, i32(k / 3u) - 1), vec2i(0), strata - 1);
        let g = textureLoad(gradient, q);
        diff += g.x;
        scale += g.y;
    }
    return select(0.0, clamp(diff / scale, 0.0, 1.0), scale > 0.0);
}
