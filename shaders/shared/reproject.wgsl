// Reprojection's pieces, shared by accumulate.wgsl and the real-time
// denoiser (shaders/realtime/temporal.wgsl): the octahedral normal a
// history's `geo` record keeps, where a pixel's hit was last frame and the
// bilinear taps around it, and the test that a history texel saw the
// surface this pixel sees.
#import frame

// A unit normal as two numbers in [-1, 1] (octahedral; 0 for a zero vector).
fn normal_to_oct(n: vec3f) -> vec2f {
    let l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if l1 == 0.0 {
        return vec2f(0.0);
    }
    var p = n.xy / l1;
    if n.z < 0.0 {
        p = (1.0 - abs(p.yx)) * select(vec2f(-1.0), vec2f(1.0), p >= vec2f(0.0));
    }
    return p;
}

fn oct_to_normal(p: vec2f) -> vec3f {
    var n = vec3f(p, 1.0 - abs(p.x) - abs(p.y));
    if n.z < 0.0 {
        n = vec3f((1.0 - abs(n.yx)) * select(vec2f(-1.0), vec2f(1.0), n.xy >= vec2f(0.0)), n.z);
    }
    let l = length(n);
    return select(n / l, vec3f(0.0), l == 0.0);
}

// Whether history texel `q`, whose `geo` record `g` holds (octahedral
// normal, hit distance or -1 on a miss), saw the same surface as this
// pixel's hit `p` (normal `n`) or, for a miss, also a miss: normals within
// `normal_cos`, and the texel's hit within `depth_tol` of the distance from
// this pixel's surface plane.
fn same_surface(q: vec2i, g: vec4f, p: vec3f, n: vec3f, miss: bool, normal_cos: f32, depth_tol: f32) -> bool {
    if miss || g.z < 0.0 {
        return miss && g.z < 0.0;
    }
    if dot(oct_to_normal(g.xy), n) < normal_cos {
        return false;
    }
    // The texel's hit, rebuilt through its centre (its jitter is unknown;
    // the error lies along the surface, not across it).
    let q_pos = frame.prev_camera.origin + g.z * camera_dir(frame.prev_camera, vec2u(q), vec2f(0.5));
    return abs(dot(q_pos - p, n)) <= depth_tol * length(p - frame.prev_camera.origin);
}

// Where pixel `pixel`'s hit (G-buffer position `g`: a miss is a direction,
// projected as a point at infinity) was on last frame's image: the
// bilinear taps around it. `valid` false: no history (behind last frame's
// camera, or a view-dependent surface seen from a camera that moved).
struct Footprint {
    valid: bool,
    // The camera has not moved for this pixel: its one tap is its own texel.
    still: bool,
    i0: vec2i,
    f: vec2f,
    nx: u32,
    // Only the taps with weight: one for a still camera or a whole-pixel
    // shift, two or four otherwise. The count is multiplied by a uniform
    // the compiler cannot know (1), which keeps the caller's tap loop a
    // loop: a loop with a small known bound is unrolled into ifs, and CPU
    // drivers run every if under a lane mask, taken or not, while a loop
    // runs only as many trips as its busiest SIMD lane needs.
    taps: u32,
}

fn footprint(pixel: vec2u, g: vec4f, view_dependent: bool) -> Footprint {
    var fp = Footprint(false, false, vec2i(0), vec2f(0.0), 1u, 0u);
    let miss = g.w < 0.0;
    let now = project(frame.camera, select(g.xyz, miss_point(frame.camera, g.xyz), miss));
    let then = project(frame.prev_camera, select(g.xyz, miss_point(frame.prev_camera, g.xyz), miss));
    let motion = then.xy - now.xy;
    fp.still = all(motion == vec2f(0.0));
    // Behind last frame's camera: not on its image, unless the camera
    // stood still (a point that a mirror shows can lie behind it).
    if then.z <= 0.0 && !fp.still {
        return fp;
    }
    if view_dependent && !fp.still {
        return fp;
    }
    fp.valid = true;
    // Texel centres sit at i + 0.5: bilinear taps around the old centre.
    let base = vec2f(pixel) + motion;
    fp.i0 = vec2i(floor(base));
    fp.f = base - floor(base);
    fp.nx = select(1u, 2u, fp.f.x > 0.0);
    fp.taps = fp.nx * select(1u, 2u, fp.f.y > 0.0) * u32(frame.exact_one);
    return fp;
}

// Tap k of a footprint: its texel and bilinear weight (0: skip it, no
// weight or outside the image).
struct Tap {
    q: vec2i,
    w: f32,
}

fn footprint_tap(fp: Footprint, k: u32) -> Tap {
    // k % nx and k / nx for nx in {1, 2}, without an integer division
    // (a SIMD CPU driver divides one lane at a time).
    let d = vec2i(i32(k & (fp.nx - 1u)), i32(k >> (fp.nx - 1u)));
    let q = fp.i0 + d;
    let w = select(1.0 - fp.f.x, fp.f.x, d.x == 1) * select(1.0 - fp.f.y, fp.f.y, d.y == 1);
    let outside = any(q < vec2i(0)) || any(q >= vec2i(frame.size));
    return Tap(q, select(w, 0.0, outside));
}
