// Reprojection's pieces, shared by accumulate.wgsl and the real-time
// denoiser (shaders/realtime/temporal.wgsl): the octahedral normal a
// history's `geo` record keeps, and the test that a history texel saw the
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
