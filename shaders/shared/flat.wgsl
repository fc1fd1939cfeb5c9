// The primary-ray sweep of a flat scene (at most FLAT_LIMIT primitives,
// src/scene/gpu_types.rs), written out slot by slot instead of looped: the
// engine's counts (FLAT_SPHERES, FLAT_TRIANGLES) fold the unused slots
// away, and each texel load has a constant address. At the top level of a
// shader this takes 0.71x the time of the loop on lavapipe (the gbuffer
// pass at 1280x720: 30 against 42 ms). Inside a loop or a branch it costs
// more than the loop (lights_point 54-77 against 38 ms): there every
// value the straight code computes is written under the lane mask, and a
// loop's last, fully masked trip runs all of it again. So only
// trace_primary and closest_primary (below) and origins.wgsl take it with
// texel loads;
// trace_pair, inside the path tracer's bounce loop, writes its sweep out
// from the scene_flat uniform instead, whose constant-offset loads are one
// broadcast load each (see trace_pair).
#import intersect

// Slots of each kind written out below (FLAT_LIMIT in src/scene/gpu_types.rs).
const FLAT_SLOTS: u32 = 32u;

// How many slots of each kind hold primitives: set by the engine from the
// scene (0 where it is not flat, which leaves no test at all).
override FLAT_SPHERES: u32 = 0u;
override FLAT_TRIANGLES: u32 = 0u;
// Set by the engine (`SceneData::flat_pairs`): a flat scene's triangles
// come in pairs 2k, 2k + 1 that share an edge as a quad's do, (a, b, c)
// and (a, c, d). trace_pair's bounce ray then loads a pair's four vertices
// once and shears each once (pathtrace 0.71-0.94x the time in 5
// alternated rounds on the Cornell box), with the same hits.
override FLAT_PAIRS: bool = false;

fn flat_sphere(r: Ray, k: u32, tmax: f32, best: ptr<function, Closest>) {
    if k < FLAT_SPHERES {
        test_sphere(r, k, tmax, false, best);
    }
}

fn flat_triangle(r: Ray, k: u32, tmax: f32, best: ptr<function, Closest>) {
    if k < FLAT_TRIANGLES {
        let tri = load_triangle(k);
        let h = hit_triangle(r, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, next_up((*best).t));
        if h.x > 0.0 && h.x < tmax && closer(h.x, k, *best) {
            *best = Closest(h.x, k, h.yz);
        }
    }
}

fn flat_spheres4(r: Ray, k: u32, tmax: f32, best: ptr<function, Closest>) {
    flat_sphere(r, k, tmax, best);
    flat_sphere(r, k + 1u, tmax, best);
    flat_sphere(r, k + 2u, tmax, best);
    flat_sphere(r, k + 3u, tmax, best);
}

fn flat_triangles4(r: Ray, k: u32, tmax: f32, best: ptr<function, Closest>) {
    flat_triangle(r, k, tmax, best);
    flat_triangle(r, k + 1u, tmax, best);
    flat_triangle(r, k + 2u, tmax, best);
    flat_triangle(r, k + 3u, tmax, best);
}

// The spheres of a flat scene along o + t d, closest first, as flat_sweep.
fn flat_sphere_sweep(r: Ray, tmax: f32) -> Closest {
    var best = Closest(tmax, NO_HIT, vec2f(0.0));
    flat_spheres4(r, 0u, tmax, &best);
    flat_spheres4(r, 4u, tmax, &best);
    flat_spheres4(r, 8u, tmax, &best);
    flat_spheres4(r, 12u, tmax, &best);
    flat_spheres4(r, 16u, tmax, &best);
    flat_spheres4(r, 20u, tmax, &best);
    flat_spheres4(r, 24u, tmax, &best);
    flat_spheres4(r, 28u, tmax, &best);
    return best;
}

// The closest hit in (0, tmax) among the flat scene's primitives, ties to
// the lower id: what brute_force finds, bit for bit.
fn flat_sweep(r: Ray, tmax: f32) -> Closest {
    var best = flat_sphere_sweep(r, tmax);
    flat_triangles4(r, 0u, tmax, &best);
    flat_triangles4(r, 4u, tmax, &best);
    flat_triangles4(r, 8u, tmax, &best);
    flat_triangles4(r, 12u, tmax, &best);
    flat_triangles4(r, 16u, tmax, &best);
    flat_triangles4(r, 20u, tmax, &best);
    flat_triangles4(r, 24u, tmax, &best);
    flat_triangles4(r, 28u, tmax, &best);
    return best;
}

// trace_closest for a shader's one ray outside any loop or branch (the ray
// benchmark's primary ray; the G-buffer's takes trace_camera_pixel in
// origins.wgsl): flat scenes then take the written-out sweep above, which
// costs more than the loop anywhere else. The same hits, bit for bit.
fn trace_primary(ro: vec3f, rd: vec3f, tmax: f32) -> Hit {
    return closest_hit(closest_primary(ro, rd, tmax), ro, rd, tmax);
}

// trace_primary's ray query alone: the closest primitive, its distance
// and barycentrics.
fn closest_primary(ro: vec3f, rd: vec3f, tmax: f32) -> Closest {
    let r = make_ray(ro, rd);
    if BRUTE_FORCE || !FLAT_SCENE {
        return traverse(r, tmax, false);
    }
    // No branch around the sweep: an untraceable ray sweeps too (it hits
    // nothing there; a zero direction's tests give NaN) and is then a miss.
    let c = flat_sweep(r, tmax);
    let ok = traceable(r);
    return Closest(select(tmax, c.t, ok), select(NO_HIT, c.prim, ok), c.uv);
}

// closest_primary for the camera ray through `pixel` (rd: camera_dir's,
// from frame.camera.origin), which on scenes that are not flat may start
// from the pixel's tile's entries (traverse_pixel). The same hits.
fn closest_pixel(pixel: vec2u, rd: vec3f, tmax: f32) -> Closest {
    let ro = frame.camera.origin;
    if BRUTE_FORCE || !FLAT_SCENE {
        return traverse_pixel(make_ray(ro, rd), pixel, tmax);
    }
    return closest_primary(ro, rd, tmax);
}

// A ray's closest hit and a shadow ray's verdict, traced together.
struct PairHit {
    hit: Hit,
    // Whether anything lies on the shadow ray in (0, shadow_tmax).
    blocked: bool,
}

// Set by the engine (`SceneData::last_light_sphere`): the sphere slot of
// the last light's own sphere (FLAT_SLOTS: none). A shadow ray toward a
// point sampled on a sphere light's visible cap ends short of the sphere
// (shadow_ray_length), so the sphere cannot block it, and trace_pair's
// shadow ray toward that light leaves it out.
override FLAT_LAST_LIGHT_SPHERE: u32 = 32u;

// The closest hit along ro + t rd (a miss without `want_hit`) and whether
// anything blocks the shadow ray so + t sd in (0, shadow_tmax) toward
// light `shadow_light` (NO_LIGHT: any; shadow_tmax 0: no shadow ray).
// Flat scenes test each sphere once for both rays, and the shadow ray
// against the light's occluders alone; elsewhere these are two
// traversals. The same answers as trace_closest and trace_any, bit for bit.
//
// The spheres and the quads (FLAT_PAIRS) are written out slot by slot from
// `flat`, a copy of the scene_flat uniform that the entry point makes
// first thing (`var flat = scene_flat;`), where each load has a constant
// offset. Read from the uniform inside a loop, a constant offset is still
// loaded lane by lane and component by component: lavapipe loads it once
// and broadcasts it only where every lane of the SIMD group must be
// running, as at the top of an entry point (pathtrace 0.82x the frame on
// the Cornell box at 1280 x 720 against reading the uniform here). Texel
// fetches in the loop had cost more still (the uniform took the loops
// 0.97-0.98x the time).
fn trace_pair(flat: ptr<function, FlatScene>, ro: vec3f, rd: vec3f, want_hit: bool, so: vec3f, sd: vec3f, shadow_tmax: f32, shadow_light: u32) -> PairHit {
    let tmax = 3.0e38;
    if BRUTE_FORCE || !FLAT_SCENE {
        var hit = no_hit(tmax);
        if want_hit {
            hit = trace_closest(ro, rd, tmax);
        }
        return PairHit(hit, shadow_tmax > 0.0 && trace_any(so, sd, shadow_tmax));
    }
    let a = make_ray(ro, rd);
    let b = make_ray(so, sd);
    var sweep = PairSweep(Closest(tmax, NO_HIT, vec2f(0.0)), false);
    pair_spheres4(flat, a, b, 0u, shadow_tmax, shadow_light, &sweep);
    pair_spheres4(flat, a, b, 4u, shadow_tmax, shadow_light, &sweep);
    pair_spheres4(flat, a, b, 8u, shadow_tmax, shadow_light, &sweep);
    pair_spheres4(flat, a, b, 12u, shadow_tmax, shadow_light, &sweep);
    pair_spheres4(flat, a, b, 16u, shadow_tmax, shadow_light, &sweep);
    pair_spheres4(flat, a, b, 20u, shadow_tmax, shadow_light, &sweep);
    pair_spheres4(flat, a, b, 24u, shadow_tmax, shadow_light, &sweep);
    pair_spheres4(flat, a, b, 28u, shadow_tmax, shadow_light, &sweep);
    var best = sweep.best;
    pair_quads4(flat, a, 0u, &best);
    pair_quads4(flat, a, 4u, &best);
    pair_quads4(flat, a, 8u, &best);
    pair_quads4(flat, a, 12u, &best);
    // Triangles that do not pair up: a loop that tests at the bottom (see
    // brute_force).
    if SCENE_MESHES && frame.n_triangles > 0u && !FLAT_PAIRS {
        var i = 0u;
        loop {
            let tri = load_triangle(i);
            let h = hit_triangle(a, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, next_up(best.t));
            if h.x > 0.0 && h.x < tmax && closer(h.x, i, best) {
                best = Closest(h.x, i, h.yz);
            }
            continuing {
                i++;
                break if i >= frame.n_triangles;
            }
        }
    }
    var blocked = sweep.blocked;
    if SCENE_MESHES && frame.n_triangles > 0u {
        blocked = blocked || occluders_block(b, shadow_light, shadow_tmax);
    }
    // Rays traverse() would refuse (NaN, infinite, zero) miss. The sweep
    // ran for every lane anyway; the hit is dropped where none is wanted.
    let ok = want_hit && traceable(a);
    let c = Closest(select(tmax, best.t, ok), select(NO_HIT, best.prim, ok), best.uv);
    return PairHit(closest_hit(c, ro, rd, tmax), blocked && traceable(b));
}

// What trace_pair's sphere slots find: the ray's closest hit so far and
// whether the shadow ray is blocked.
struct PairSweep {
    best: Closest,
    blocked: bool,
}

// Sphere slot k for both of trace_pair's rays (the shadow ray's test as
// brute_force's: bound next_up(tmax), then < tmax).
fn pair_sphere(flat: ptr<function, FlatScene>, a: Ray, b: Ray, k: u32, shadow_tmax: f32, shadow_light: u32, sweep: ptr<function, PairSweep>) {
    if SCENE_SPHERES && k < FLAT_SPHERES {
        let s = flat_sphere_at(flat, k);
        let t = ray_sphere(a.o, a.d, s.geo.xyz, s.geo.w, 0.0, next_up((*sweep).best.t));
        let prim = k | SPHERE_BIT;
        if t > 0.0 && t < 3.0e38 && closer(t, prim, (*sweep).best) {
            (*sweep).best = Closest(t, prim, vec2f(0.0));
        }
        // Folds to a constant where the scene has one light (the path
        // tracer's shadow ray goes to the last light).
        let own_light = k == FLAT_LAST_LIGHT_SPHERE && shadow_light + 1u == max(light_count(), 1u);
        if !own_light {
            let ts = ray_sphere(b.o, b.d, s.geo.xyz, s.geo.w, 0.0, next_up(shadow_tmax));
            (*sweep).blocked = (*sweep).blocked || (ts > 0.0 && ts < shadow_tmax);
        }
    }
}

fn pair_spheres4(flat: ptr<function, FlatScene>, a: Ray, b: Ray, k: u32, shadow_tmax: f32, shadow_light: u32, sweep: ptr<function, PairSweep>) {
    pair_sphere(flat, a, b, k, shadow_tmax, shadow_light, sweep);
    pair_sphere(flat, a, b, k + 1u, shadow_tmax, shadow_light, sweep);
    pair_sphere(flat, a, b, k + 2u, shadow_tmax, shadow_light, sweep);
    pair_sphere(flat, a, b, k + 3u, shadow_tmax, shadow_light, sweep);
}

// Quad slot k (FLAT_PAIRS): triangles 2k = (a, b, c) and 2k + 1 =
// (a, c, d), their four vertices loaded and sheared once.
fn pair_quad(flat: ptr<function, FlatScene>, r: Ray, k: u32, best: ptr<function, Closest>) {
    let i = 2u * k;
    if SCENE_MESHES && FLAT_PAIRS && i < FLAT_TRIANGLES {
        let tri = flat_triangle_at(flat, i);
        let d = flat_triangle_at(flat, i + 1u).p2.xyz;
        let sa = shear(r, tri.p0.xyz);
        let sc = shear(r, tri.p2.xyz);
        let h = hit_sheared(sa, shear(r, tri.p1.xyz), sc, next_up((*best).t));
        if h.x > 0.0 && h.x < 3.0e38 && closer(h.x, i, *best) {
            *best = Closest(h.x, i, h.yz);
        }
        let h2 = hit_sheared(sa, sc, shear(r, d), next_up((*best).t));
        if h2.x > 0.0 && h2.x < 3.0e38 && closer(h2.x, i + 1u, *best) {
            *best = Closest(h2.x, i + 1u, h2.yz);
        }
    }
}

fn pair_quads4(flat: ptr<function, FlatScene>, r: Ray, k: u32, best: ptr<function, Closest>) {
    pair_quad(flat, r, k, best);
    pair_quad(flat, r, k + 1u, best);
    pair_quad(flat, r, k + 2u, best);
    pair_quad(flat, r, k + 3u, best);
}

// Whether one of light `light`'s occluders (a flat scene's triangles that
// can shadow it at all: occluder_count in shared/scene.wgsl) lies on r in
// (0, tmax). In a room around its light that is none, and the loop's one
// masked trip is all a shadow ray pays for the walls.
fn occluders_block(r: Ray, light: u32, tmax: f32) -> bool {
    let n = occluder_count(light);
    let bound = next_up(tmax);
    var blocked = false;
    if SCENE_MESHES && n > 0u {
        var j = 0u;
        loop {
            let tri = load_triangle(occluder(light, j));
            let h = hit_triangle(r, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, bound);
            blocked = blocked || (h.x > 0.0 && h.x < tmax);
            continuing {
                j++;
                break if j >= n;
            }
        }
    }
    return blocked;
}

// trace_any for a shadow ray toward light `light` (NO_LIGHT: any): on flat
// scenes every sphere and the light's occluders, in loops (a shadow ray
// inside a loop; see flat_sweep for why not written out). The same
// verdicts as trace_any, bit for bit: the triangles left out cannot block
// a shadow ray toward that light.
fn trace_shadow(light: u32, o: vec3f, rd: vec3f, tmax: f32) -> bool {
    if BRUTE_FORCE || !FLAT_SCENE {
        return trace_any(o, rd, tmax);
    }
    let r = make_ray(o, rd);
    let bound = next_up(tmax);
    var blocked = false;
    if SCENE_SPHERES && frame.n_spheres > 0u {
        var i = 0u;
        loop {
            let s = load_sphere(i);
            let t = ray_sphere(r.o, r.d, s.geo.xyz, s.geo.w, 0.0, bound);
            blocked = blocked || (t > 0.0 && t < tmax);
            continuing {
                i++;
                break if i >= frame.n_spheres;
            }
        }
    }
    blocked = blocked || occluders_block(r, light, tmax);
    return blocked && traceable(r);
}
