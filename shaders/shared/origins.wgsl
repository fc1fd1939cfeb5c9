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

// The table is scene_origins (shared/scene.wgsl).

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
    return Ray(o, d, vec3f(0.0), no, no, vec3f(0.0), vec3f(0.0), 0.0);
}

fn origin_triangle(row: u32, d: vec3f, k: u32, tmax: f32, best: ptr<function, Closest>) {
    if k < FLAT_TRIANGLES {
        let h = hit_from_origin(row, k, d, next_up((*best).t));
        if h.x > 0.0 && h.x < tmax && closer(h.x, k, *best) {
            *best = Closest(h.x, k, h.yz);
        }
    }
}

fn origin_triangles4(row: u32, d: vec3f, k: u32, tmax: f32, best: ptr<function, Closest>) {
    origin_triangle(row, d, k, tmax, best);
    origin_triangle(row, d, k + 1u, tmax, best);
    origin_triangle(row, d, k + 2u, tmax, best);
    origin_triangle(row, d, k + 3u, tmax, best);
}

// The closest triangle in (0, tmax) along the ray from row `row`'s origin
// into `best`, every slot written out as in flat_sweep.
fn origin_sweep(row: u32, d: vec3f, tmax: f32, best: ptr<function, Closest>) {
    origin_triangles4(row, d, 0u, tmax, best);
    origin_triangles4(row, d, 4u, tmax, best);
    origin_triangles4(row, d, 8u, tmax, best);
    origin_triangles4(row, d, 12u, tmax, best);
    origin_triangles4(row, d, 16u, tmax, best);
    origin_triangles4(row, d, 20u, tmax, best);
    origin_triangles4(row, d, 24u, tmax, best);
    origin_triangles4(row, d, 28u, tmax, best);
}

// trace_closest from the camera (frame.camera.origin) along the unit
// direction rd, for a shader's one camera ray outside any loop or branch:
// on flat scenes the sweep above, the same hits as trace_closest up to the
// rounding of the two triangle tests.
fn trace_camera(rd: vec3f, tmax: f32) -> Hit {
    if BRUTE_FORCE || !FLAT_SCENE {
        return trace_closest_from_camera(rd, tmax);
    }
    return sweep_camera(rd, tmax);
}

// trace_camera for the ray through `pixel` (rd: camera_dir's for it, at any
// sub-pixel offset; the G-buffer's), which may start from the pixel's
// tile's entries (traverse_pixel) where the scene is not flat.
fn trace_camera_pixel(pixel: vec2u, rd: vec3f, tmax: f32) -> Hit {
    if BRUTE_FORCE || !FLAT_SCENE {
        return trace_closest_through(pixel, rd, tmax);
    }
    return sweep_camera(rd, tmax);
}

// The flat scene's sweep for trace_camera.
fn sweep_camera(rd: vec3f, tmax: f32) -> Hit {
    let ro = frame.camera.origin;
    let r = plain_ray(ro, rd);
    var best = flat_sphere_sweep(r, tmax);
    origin_sweep(ORIGIN_CAMERA, rd, tmax, &best);
    let ok = traceable(r);
    return closest_hit(Closest(select(tmax, best.t, ok), select(NO_HIT, best.prim, ok), best.uv), ro, rd, tmax);
}

// trace_any(o, rd, tmax) for a shadow ray toward light 0 as a point light
// (`light`: its position, rd: the unit direction from o to it): on flat
// scenes light 0's occluders (the triangles that can shadow it at all) are
// tested along the ray from the light to o, where the segment from o to
// tmax is t in (1 - tmax / |o - light|, 1). The same verdicts as trace_any
// up to the rounding of the two triangle tests.
fn trace_any_from_light(light: vec3f, o: vec3f, rd: vec3f, tmax: f32) -> bool {
    if BRUTE_FORCE || !FLAT_SCENE {
        return trace_any(o, rd, tmax);
    }
    let r = plain_ray(o, rd);
    var blocked = flat_sphere_sweep(r, tmax).prim != NO_HIT;
    let back = o - light;
    let near = max(1.0 - tmax / length(back), 0.0);
    let n = occluder_count(0u);
    if SCENE_MESHES && n > 0u {
        var j = 0u;
        loop {
            let h = hit_from_origin(ORIGIN_LIGHT, occluder(0u, j), back, 1.0);
            blocked = blocked || h.x > near;
            continuing {
                j++;
                break if j >= n;
            }
        }
    }
    return blocked && traceable(r);
}
