// Rays that share an origin, on flat scenes: the camera's primary rays, and
// the shadow rays toward light 0 when a pass traces them as point-light
// rays (those are traced from the light, backwards). For rays from one
// point the engine has each triangle's three edge planes through that
// point in `scene_origins` (src/scene/origins.rs, src/bvh/origin.rs, which
// mirrors hit_from_origin), so a triangle test is three dot products and a
// division instead of the watertight test's shear and permutation; it is
// watertight the same way (a shared edge's two planes are exact negations).
// On lavapipe the Cornell box's G-buffer pass took about 0.75x the time.
// Spheres are tested as the flat sweep tests them.
#import flat

@group(1) @binding(9) var scene_origins: texture_storage_2d<rgba32uint, read>;

// Mirrors src/scene/origins.rs: the camera's row, light 0's row, and the
// texels of a row (three per triangle slot).
const ORIGIN_CAMERA: u32 = 0u;
const ORIGIN_LIGHT: u32 = 1u;
const ORIGIN_ROW_TEXELS: u32 = 96u;

// Triangle k against the ray from row `row`'s origin along d (any length):
// (t, b1, b2) with t in (0, tmax) in units of d, or t = -1. Inclusive
// edges. No branches: a CPU driver runs them all under a lane mask anyway.
// A zero det gives t = inf or NaN, which fails the range test.
fn hit_from_origin(row: u32, k: u32, d: vec3f, tmax: f32) -> vec3f {
    let at = row * ORIGIN_ROW_TEXELS + 3u * k;
    let e0 = bitcast<vec4f>(scene_texel(scene_origins, at));
    let e1 = bitcast<vec4f>(scene_texel(scene_origins, at + 1u));
    let e2 = bitcast<vec4f>(scene_texel(scene_origins, at + 2u));
    let u = dot(d, e0.xyz);
    let v = dot(d, e1.xyz);
    let w = dot(d, e2.xyz);
    let outside = (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0);
    let inv = 1.0 / (u + v + w);
    let t = e0.w * inv;
    let hit = !outside && t > 0.0 && t < tmax;
    return select(vec3f(-1.0, 0.0, 0.0), vec3f(t, v * inv, w * inv), hit);
}

// A Ray with only its origin and direction: what the sphere test and
// traceable read (the watertight triangle test's constants are unused).
fn plain_ray(o: vec3f, d: vec3f) -> Ray {
    let no = vec3<bool>(false);
    return Ray(o, d, vec3f(0.0), no, no, vec3f(0.0), vec3f(0.0));
}

fn origin_triangle(row: u32, d: vec3f, k: u32, tmin: f32, tmax: f32, best: ptr<function, Closest>) {
    if k < FLAT_TRIANGLES {
        let h = hit_from_origin(row, k, d, next_up((*best).t));
        if h.x > tmin && h.x < tmax && closer(h.x, k, *best) {
            *best = Closest(h.x, k, h.yz);
        }
    }
}

fn origin_triangles4(row: u32, d: vec3f, k: u32, tmin: f32, tmax: f32, best: ptr<function, Closest>) {
    origin_triangle(row, d, k, tmin, tmax, best);
    origin_triangle(row, d, k + 1u, tmin, tmax, best);
    origin_triangle(row, d, k + 2u, tmin, tmax, best);
    origin_triangle(row, d, k + 3u, tmin, tmax, best);
}

// The closest triangle in (tmin, tmax) along the ray from row `row`'s
// origin into `best`, every slot written out as in flat_sweep.
fn origin_sweep(row: u32, d: vec3f, tmin: f32, tmax: f32, best: ptr<function, Closest>) {
    origin_triangles4(row, d, 0u, tmin, tmax, best);
    origin_triangles4(row, d, 4u, tmin, tmax, best);
    origin_triangles4(row, d, 8u, tmin, tmax, best);
    origin_triangles4(row, d, 12u, tmin, tmax, best);
    origin_triangles4(row, d, 16u, tmin, tmax, best);
    origin_triangles4(row, d, 20u, tmin, tmax, best);
    origin_triangles4(row, d, 24u, tmin, tmax, best);
    origin_triangles4(row, d, 28u, tmin, tmax, best);
}

// trace_closest from the camera (frame.camera.origin) along the unit
// direction rd, for a shader's one camera ray outside any loop or branch
// (the G-buffer's): on flat scenes the sweep above, the same hits as
// trace_closest up to the rounding of the two triangle tests.
fn trace_camera(rd: vec3f, tmax: f32) -> Hit {
    let ro = frame.camera.origin;
    if BRUTE_FORCE || !FLAT_SCENE {
        return trace_closest(ro, rd, tmax);
    }
    let r = plain_ray(ro, rd);
    var best = flat_sphere_sweep(r, tmax);
    origin_sweep(ORIGIN_CAMERA, rd, 0.0, tmax, &best);
    let ok = traceable(r);
    return closest_hit(Closest(select(tmax, best.t, ok), select(NO_HIT, best.prim, ok), best.uv), ro, rd, tmax);
}

// trace_any(o, rd, tmax) for a shadow ray toward light 0 as a point light
// (`light`: its position, rd: the unit direction from o to it), for a
// shader's one shadow ray outside any loop or branch: on flat scenes the
// triangles are tested along the ray from the light to o, where the
// segment from o to tmax is t in (1 - tmax / |o - light|, 1). The same
// verdicts as trace_any up to the rounding of the two triangle tests.
fn trace_any_from_light(light: vec3f, o: vec3f, rd: vec3f, tmax: f32) -> bool {
    if BRUTE_FORCE || !FLAT_SCENE {
        return trace_any(o, rd, tmax);
    }
    let r = plain_ray(o, rd);
    let spheres = flat_sphere_sweep(r, tmax);
    let back = o - light;
    let near = max(1.0 - tmax / length(back), 0.0);
    var best = Closest(1.0, NO_HIT, vec2f(0.0));
    origin_sweep(ORIGIN_LIGHT, back, near, 1.0, &best);
    let blocked = spheres.prim != NO_HIT || best.prim != NO_HIT;
    return blocked && traceable(r);
}
