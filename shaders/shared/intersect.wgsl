// Ray queries against the scene: `trace_closest` and `trace_any`, every
// pass goes through them. Two-level BVH traversal with a fixed private
// stack, nearer child first, over the tests of ray.wgsl. A NaN/Inf/zero
// ray fails every box test and ends as a miss.
// Mirrored in Rust by src/bvh/ray.rs.
#import bvh
#import loop_budget
#import ray
#import textures

const NO_HIT: u32 = NO_OBJECT;
const SPHERE_BIT: u32 = 0x80000000u;
const STACK_SIZE: u32 = 64u;
// Far more steps than any valid traversal takes: a hard stop.
const MAX_STEPS: u32 = 4194304u;

struct Hit {
    t: f32,
    // The hit point on the surface itself: from the barycentrics (triangle)
    // or projected onto the sphere, not o + t d, whose error grows with |o|
    // and t (Ray Tracing Gems ch. 6); offset_ray needs it accurate.
    position: vec3f,
    // Geometric and shading normals (unit length, not yet faced to the ray).
    geo_normal: vec3f,
    normal: vec3f,
    // A conservative bound on |position - the true surface point|, per
    // component, from the operands of the arithmetic that computed it
    // (hit_error_*): offset_ray moves a new ray's origin past it.
    error: vec3f,
    material: u32,
    object: u32,
    // Index of the sphere light hit, or -1.
    light: i32,
    // The triangle hit (what shared/textures.wgsl reads uvs of), NO_HIT
    // for a sphere or a miss.
    prim: u32,
}

fn hit_found(h: Hit) -> bool {
    return h.object != NO_HIT;
}

fn no_hit(tmax: f32) -> Hit {
    return Hit(tmax, vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), 0u, NO_HIT, -1, NO_HIT);
}

// The traversal stacks. Module-scope private memory is zero-initialised
// once per invocation, not once per call. The TLAS and each BLAS have
// their own (their depths are bounded separately: TLAS_MAX_DEPTH and
// BLAS_MAX_DEPTH in src/bvh/build/mod.rs). The TLAS's entries are (node, entry
// distance bits); the BLAS's are node references alone (node_ref), without
// the distance: lavapipe stores and loads dynamically indexed private
// memory one lane and one component at a time on every trip of the loop.
// A popped node beyond the closest hit now costs a trip (its children's
// boxes miss) or its leaf's triangle tests; the distance cost every trip
// (primary rays in alternated rounds: knot 0.87-0.92x the time, Sponza
// 0.83-0.93x, dragon 0.73-1.07x).
// One slot more than a traversal fills: traverse_blas stores to slot sp on
// every trip, pushed or not, and sp reaches STACK_SIZE when it is full.
var<private> stack: array<u32, STACK_SIZE + 1u>;
var<private> tlas_stack: array<vec2u, TLAS_STACK_SIZE>;
const TLAS_STACK_SIZE: u32 = 16u;

struct Closest {
    t: f32,
    prim: u32,
    uv: vec2f,
}

fn closer(t: f32, prim: u32, best: Closest) -> bool {
    return t < best.t || (t == best.t && prim < best.prim);
}

// Every sphere and triangle, no BVH: what `glint bench stress --brute-force`
// measures the BVH against (the thesis's setup), and the path for tiny
// scenes (FLAT_SCENE below).
override BRUTE_FORCE: bool = false;

// Its loops test their count at the bottom (`continuing { break if }`): a
// `for` loop tests at the top, so on SIMD CPU drivers its last trip runs
// the whole body under an empty lane mask before the loop sees that every
// lane has left. The path tracer took 0.95x the time without that trip.
fn brute_force(r: Ray, tmax: f32, any_hit: bool) -> Closest {
    var best = Closest(tmax, NO_HIT, vec2f(0.0));
    if test_spheres(r, tmax, any_hit, &best) {
        return best;
    }
    if SCENE_MESHES {
        test_triangles(r, 0u, frame.n_triangles, tmax, any_hit, &best);
    }
    return best;
}

// Tests every sphere into `best`; true when any_hit and one was hit (stop).
fn test_spheres(r: Ray, tmax: f32, any_hit: bool, best: ptr<function, Closest>) -> bool {
    if !SCENE_SPHERES || frame.n_spheres == 0u {
        return false;
    }
    var i = 0u;
    loop {
        loop_trips += 1u;
        if test_sphere(r, i, tmax, any_hit, best) {
            return true;
        }
        continuing {
            i++;
            break if i >= frame.n_spheres;
        }
    }
    return false;
}

// Tests sphere i into `best`; true when any_hit and it was hit (stop).
fn test_sphere(r: Ray, i: u32, tmax: f32, any_hit: bool, best: ptr<function, Closest>) -> bool {
    let s = load_sphere(i);
    let t = ray_sphere(r.o, r.d, s.geo.xyz, s.geo.w, 0.0, next_up((*best).t));
    let prim = i | SPHERE_BIT;
    if t > 0.0 && t < tmax && closer(t, prim, *best) {
        *best = Closest(t, prim, vec2f(0.0));
        return any_hit;
    }
    return false;
}

// Tests triangles first .. first + count into `best`; true when any_hit
// and something was hit (stop).
fn test_triangles(r: Ray, first: u32, count: u32, tmax: f32, any_hit: bool, best: ptr<function, Closest>) -> bool {
    if count == 0u {
        return false;
    }
    var i = first;
    loop {
        loop_trips += 1u;
        let tri = load_triangle(i);
        let h = hit_triangle(r, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, next_up((*best).t));
        if h.x > r.tmin && h.x < tmax && closer(h.x, i, *best) && face_passes(bitcast<u32>(tri.p0.w), r.d, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz) {
            *best = Closest(h.x, i, h.yz);
            if any_hit && !alpha_tested(bitcast<u32>(tri.p0.w)) {
                return true;
            }
        }
        continuing {
            i++;
            break if i >= first + count;
        }
    }
    return false;
}

// Set per scene by the engine (FLAT_LIMIT in src/scene/gpu_types.rs):
// scenes of a few primitives test them all, flat; a loop every SIMD lane
// runs in step beats a divergent stack traversal there. As a pipeline
// constant rather than a test of the scene counts, the path not taken is
// compiled out: CPU drivers run every path of a shader, taken or not, and
// the traversal code no longer fitting the instruction cache next to the
// flat loop cost more than the loop itself.
override FLAT_SCENE: bool = false;

// Set per scene by the engine (`SceneData::spheres_apart`): a scene that is
// not flat with at most FLAT_LIMIT spheres tests them all in a loop before
// its BVH, whose TLAS then holds the meshes alone. On a CPU driver a TLAS
// instance costs a ray that crosses it a trip of the TLAS loop and, where
// lanes reach a mesh leaf on different trips, another run of the BLAS
// loop: thesis-env3's 15 small light spheres as instances more than
// doubled its path pass; a sphere test in a loop every lane runs in step
// costs little.
override SPHERES_APART: bool = false;

// Set per scene by the engine (`is_one_mesh` in src/scene/buffers.rs): the
// TLAS is one leaf holding one mesh and nothing else, so traversal starts
// at that mesh's BLAS. A ray that misses everything still runs every loop
// of the traversal once under its lane mask, so the TLAS loop and the
// instance loop around the BLAS cost a single-mesh scene (an OBJ) about a
// third of its primary rays when most of them miss.
override ONE_MESH: bool = false;

// `glint bench rays --trips` sets this: traverse_blas counts its trips
// (one box pair or one triangle each) into the two counters below, which
// the bench's primary rays hand back. Trip counts do not swing with the
// machine as times do. Off, the counting is compiled out.
override COUNT_TRIPS: bool = false;
var<private> trips_node: u32;
var<private> trips_triangle: u32;

// Why the loops below look the way they do: SIMD CPU drivers (lavapipe)
// run every branch of a loop body under a lane mask, taken or not, so an
// iteration costs the sum of all its paths. The TLAS loop (few steps)
// holds the instance code; the BLAS loop (most steps) holds only boxes
// and triangles, and fetches four texels a step, the same four for both
// kinds of work: a child pair (two nodes) or a triangle (three texels and
// one spare), from scene_geometry. The visited node stays in registers;
// only the farther child of a pair goes through the stack (dynamically
// indexed private memory is expensive there too).

// Where traverse_blas starts (a constant at every call, so each caller's
// shader keeps one way): at the root; from the camera's entries (a ray
// from the camera in any direction); from the entries of `pixel`'s screen
// tile (a camera ray through that pixel, at any sub-pixel offset).
const ENTER_AT_ROOT: u32 = 0u;
const ENTER_FROM_CAMERA: u32 = 1u;
const ENTER_FROM_TILE: u32 = 2u;

// Traverses the BLAS whose root is `root_ref` (node_ref; its box already
// hit) into `best`; true
// when any_hit and something was hit (stop). Camera rays (`enter`) start
// from the camera's entries (scene_entries) or their tile's (scene_tiles)
// where the engine gave some: every camera ray would otherwise walk the
// same nodes around the camera first (inside Sponza 17 of its 49.4 node
// trips), and the rays of a tile mostly the same nodes below them too.
// Any cut of the tree gives the same hits; a tile's leaves out only what
// its rays cannot reach.
fn traverse_blas(r: Ray, root_ref: u32, tmax: f32, any_hit: bool, best: ptr<function, Closest>, enter: u32, pixel: vec2u) -> bool {
    let node_base = node_texel_base();
    // The node in hand as a packed reference (node_ref): what a visit
    // needs is in the parent's child texels, so no step reloads a node.
    var current = root_ref;
    var have_current = true;
    var sp = 0u;
    var entries = 0u;
    var first_texel = 0u;
    if enter == ENTER_FROM_CAMERA {
        entries = min(scene_entries.count.x, MAX_CAMERA_ENTRIES);
        have_current = entries == 0u;
    }
    if enter == ENTER_FROM_TILE {
        let log2 = scene_entries.count.y;
        let tile_x = pixel.x >> log2;
        let tile = (pixel.y >> log2) * scene_entries.count.z + tile_x;
        if log2 != 0u && tile_x < scene_entries.count.z && tile < MAX_TILES && all(pixel < frame.size) {
            first_texel = tile * TILE_TEXELS + 1u;
            entries = min(scene_texel(scene_tiles, first_texel - 1u).x, MAX_TILE_ENTRIES);
            // No entries: the tile's frustum misses the BLAS.
            have_current = false;
        }
    }
    if entries > 0u {
        // The entries whose boxes the ray hits go on the stack, the last
        // on top: the loop below starts by popping it. Nothing of this
        // runs in the loop: a test there would cost every trip of every
        // ray (the knot's shadow rays 1.06-1.09x the time with one).
        var e = 0u;
        loop {
            var lo: vec4f;
            var hi: vec4f;
            if enter == ENTER_FROM_TILE {
                lo = bitcast<vec4f>(scene_texel(scene_tiles, first_texel + 2u * e));
                hi = bitcast<vec4f>(scene_texel(scene_tiles, first_texel + 2u * e + 1u));
            } else {
                lo = bitcast<vec4f>(scene_entries.entries[2u * e]);
                hi = bitcast<vec4f>(scene_entries.entries[2u * e + 1u]);
            }
            stack[sp] = bitcast<u32>(lo.w);
            if hit_box(r, lo.xyz, hi.xyz, tmax) >= 0.0 {
                sp += 1u;
            }
            continuing {
                e++;
                break if e >= entries;
            }
        }
    }
    // Triangles of the leaf reached still to test, one per step.
    var tri = 0u;
    var tri_end = 0u;
    for (var steps = 0u; steps < MAX_STEPS; steps++) {
        // The top entry is loaded on every trip, taken or not, and the
        // farther child below stored on every trip, pushed or not: lavapipe
        // loads and stores private memory lane by lane, and under a branch
        // it tests each lane's mask and keeps the old value lane by lane
        // too (primary rays 0.96x the time on the knot and Sponza, 0.97x
        // on the dragon, alternated; identical hits).
        loop_trips += 1u;
        let top = stack[max(sp, 1u) - 1u];
        if !have_current && tri >= tri_end && sp > 0u {
            sp -= 1u;
            have_current = true;
            current = top;
        }
        let first = current & REF_FIRST;
        let count = current >> REF_COUNT_SHIFT;
        // A leaf in hand becomes the triangles to test (none are pending:
        // nodes are taken in hand only once the last leaf is done).
        if have_current && count > 0u {
            tri = first;
            tri_end = first + count;
            have_current = false;
        }
        let test_triangle = tri < tri_end;
        if COUNT_TRIPS {
            trips_node += u32(!test_triangle && have_current);
            trips_triangle += u32(test_triangle);
        }
        let base = select(node_base + 2u * first, 3u * tri, test_triangle);
        let t0 = bitcast<vec4f>(scene_texel(scene_geometry, base));
        let t1 = bitcast<vec4f>(scene_texel(scene_geometry, base + 1u));
        let t2 = bitcast<vec4f>(scene_texel(scene_geometry, base + 2u));
        let t3 = bitcast<vec4f>(scene_texel(scene_geometry, base + 3u));
        // An interior node's children are the pair (t0, t1), (t2, t3):
        // tested in every lane (the lanes run both kinds of work anyway).
        let ta = hit_box(r, t0.xyz, t1.xyz, (*best).t);
        let tb = hit_box(r, t2.xyz, t3.xyz, (*best).t);
        let swap = tb >= 0.0 && (ta < 0.0 || tb < ta);
        let t_first = select(ta, tb, swap);
        let t_second = select(tb, ta, swap);
        let ref_a = node_ref(BvhNode(t0, t1));
        let ref_b = node_ref(BvhNode(t2, t3));
        // The farther child, in the slot above the top: kept only if sp
        // moves past it below.
        stack[sp] = select(ref_b, ref_a, swap);
        if test_triangle {
            let h = hit_triangle(r, t0.xyz, t1.xyz, t2.xyz, next_up((*best).t));
            if h.x > r.tmin && h.x < tmax && closer(h.x, tri, *best) && face_passes(bitcast<u32>(t0.w), r.d, t0.xyz, t1.xyz, t2.xyz) {
                *best = Closest(h.x, tri, h.yz);
                if any_hit && !alpha_tested(bitcast<u32>(t0.w)) {
                    return true;
                }
            }
            tri += 1u;
        } else if have_current {
            // Visit the nearer next; push the farther.
            have_current = t_first >= 0.0;
            current = select(ref_a, ref_b, swap);
            if t_first >= 0.0 && t_second >= 0.0 && sp < STACK_SIZE {
                sp += 1u;
            }
        }
        if !have_current && tri >= tri_end && sp == 0u {
            break;
        }
    }
    return false;
}

// Whether a ray can hit anything: a NaN or infinite origin or direction
// cannot (infinities would otherwise enter every box at t = 0 and walk the
// whole tree), nor can a zero direction (parallel to every slab, it would
// keep every box).
fn traceable(r: Ray) -> bool {
    let finite = all(abs(r.o) <= vec3f(3.40282347e38)) && all(abs(r.d) <= vec3f(3.40282347e38));
    return finite && !all(r.d == vec3f(0.0));
}

// Traverses the scene. any_hit: stop at the first hit (shadow rays).
fn traverse(r: Ray, tmax: f32, any_hit: bool) -> Closest {
    return traverse_from(r, tmax, any_hit, ENTER_AT_ROOT, vec2u(0u));
}

// `traverse` for the closest hit of a ray that starts at the camera
// (frame.camera.origin), which may start from the camera's entries.
fn traverse_camera(r: Ray, tmax: f32) -> Closest {
    return traverse_from(r, tmax, false, ENTER_FROM_CAMERA, vec2u(0u));
}

// `traverse_camera` for a ray through pixel `pixel` (camera_dir's ray at
// any sub-pixel offset), which may start from its screen tile's entries.
fn traverse_pixel(r: Ray, pixel: vec2u, tmax: f32) -> Closest {
    return traverse_from(r, tmax, false, ENTER_FROM_TILE, pixel);
}

// Alpha-tested triangles (SCENE_ALPHA_MASK) are tested after traversal,
// not in its loops: traversal takes every triangle as opaque (a shadow
// ray stops early only at one that is), and where the closest hit is an
// alpha-tested triangle its alpha lets through, the ray is traced again
// beyond it. The loops then hold no texture code: a CPU driver runs the
// code of a loop under a lane mask whenever any lane needs it, and one
// alpha-tested gate cost the dungeon's hybrid frame 1.75x with the test
// in the loops. At most MAX_ALPHA_LAYERS see-through hits a ray.
const MAX_ALPHA_LAYERS: u32 = 256u;

fn traverse_from(r: Ray, tmax: f32, any_hit: bool, enter: u32, pixel: vec2u) -> Closest {
    if !SCENE_ALPHA_MASK {
        return traverse_opaque(r, tmax, any_hit, enter, pixel);
    }
    var ray = r;
    var best = Closest(tmax, NO_HIT, vec2f(0.0));
    for (var layer = 0u; layer < MAX_ALPHA_LAYERS; layer++) {
        best = traverse_opaque(ray, tmax, any_hit, enter, pixel);
        if best.prim == NO_HIT || (best.prim & SPHERE_BIT) != 0u {
            break;
        }
        let material = scene_texel(scene_geometry, 3u * best.prim).w;
        if alpha_passes(material, best.prim, best.uv) {
            break;
        }
        ray.tmin = best.t;
        best = Closest(tmax, NO_HIT, vec2f(0.0));
    }
    return best;
}

// traverse_from with every triangle opaque, hits beyond r.tmin.
fn traverse_opaque(r: Ray, tmax: f32, any_hit: bool, enter: u32, pixel: vec2u) -> Closest {
    if !traceable(r) {
        return Closest(tmax, NO_HIT, vec2f(0.0));
    }
    if BRUTE_FORCE {
        return brute_force(r, tmax, any_hit);
    }
    if FLAT_SCENE {
        // Shadow rays too test every primitive: the lanes run the loop in
        // step, and the exit the first hit would take cost more than it
        // saved (lights_point 0.89x the time without it, pathtrace 0.95x).
        return brute_force(r, tmax, false);
    }
    var best = Closest(tmax, NO_HIT, vec2f(0.0));
    if SPHERES_APART && test_spheres(r, tmax, any_hit, &best) {
        return best;
    }
    if ONE_MESH {
        // No root box test: the BLAS tests its root's children first thing,
        // inside the mesh's box, so the hits are the same.
        traverse_blas(r, scene_entries.count.w, tmax, any_hit, &best, enter, pixel);
        return best;
    }
    let root = load_node(0);
    let t_root = hit_box(r, root.lo.xyz, root.hi.xyz, tmax);
    if t_root < 0.0 {
        return best;
    }
    // The loop ends at the bottom, so a TLAS that is one leaf (a single
    // mesh) takes one trip: a trip that breaks at the top would still run
    // the whole body, masked, on SIMD CPU drivers.
    var current = 0u;
    var sp = 0u;
    for (var steps = 0u; steps < MAX_STEPS; steps++) {
        loop_trips += 1u;
        var next = false;
        let node = load_node(current);
        if (node_count(node) & TLAS_LEAF) != 0u {
            let end = node_first(node) + (node_count(node) & ~TLAS_LEAF);
            for (var k = node_first(node); k < end; k++) {
                let inst = load_instance(k);
                // No box test before a BLAS: its root's children are
                // tested first thing, and the leaf's box bounds the root.
                // A constant where the scene has instances of one kind.
                let is_mesh = SCENE_MESHES && (!SCENE_SPHERES || inst.v.x == INSTANCE_MESH);
                if is_mesh {
                    if traverse_blas(r, node_ref(load_node(inst.v.y)), tmax, any_hit, &best, ENTER_AT_ROOT, vec2u(0u)) {
                        return best;
                    }
                } else if test_sphere(r, inst.v.y, tmax, any_hit, &best) {
                    return best;
                }
            }
        } else {
            let a = node_first(node);
            let na = load_node(a);
            let nb = load_node(a + 1u);
            let ta = hit_box(r, na.lo.xyz, na.hi.xyz, best.t);
            let tb = hit_box(r, nb.lo.xyz, nb.hi.xyz, best.t);
            let swap = tb >= 0.0 && (ta < 0.0 || tb < ta);
            let t_first = select(ta, tb, swap);
            let t_second = select(tb, ta, swap);
            if t_first >= 0.0 {
                current = select(a, a + 1u, swap);
                next = true;
                if t_second >= 0.0 && sp < TLAS_STACK_SIZE {
                    tlas_stack[sp] = vec2u(select(a + 1u, a, swap), bitcast<u32>(t_second));
                    sp += 1u;
                }
            }
        }
        // The same slack hit_box gives its far bound.
        while !next && sp > 0u {
            sp -= 1u;
            let top = tlas_stack[sp];
            next = bitcast<f32>(top.y) <= best.t * IZE_SCALE;
            current = top.x;
        }
        if !next {
            break;
        }
    }
    return best;
}

// The closest hit along a unit-length ray in (0, tmax).
fn trace_closest(ro: vec3f, rd: vec3f, tmax: f32) -> Hit {
    return closest_hit(traverse(make_ray(ro, rd), tmax, false), ro, rd, tmax);
}

// trace_closest for a ray from the camera (frame.camera.origin), which may
// start from the camera's entries (traverse_camera). The same hits.
fn trace_closest_from_camera(rd: vec3f, tmax: f32) -> Hit {
    let ro = frame.camera.origin;
    return closest_hit(traverse_camera(make_ray(ro, rd), tmax), ro, rd, tmax);
}

// trace_closest for the camera ray through `pixel` (rd: camera_dir's, at
// any sub-pixel offset), which may start from its tile's entries
// (traverse_pixel). The same hits.
fn trace_closest_through(pixel: vec2u, rd: vec3f, tmax: f32) -> Hit {
    let ro = frame.camera.origin;
    return closest_hit(traverse_pixel(make_ray(ro, rd), pixel, tmax), ro, rd, tmax);
}

// The Hit for traversal's closest primitive along ro + t rd.
fn closest_hit(c: Closest, ro: vec3f, rd: vec3f, tmax: f32) -> Hit {
    if c.prim == NO_HIT {
        return no_hit(tmax);
    }
    if SCENE_SPHERES && (!SCENE_MESHES || (c.prim & SPHERE_BIT) != 0u) {
        let s = load_sphere(c.prim & ~SPHERE_BIT);
        let n = normalize(ro + c.t * rd - s.geo.xyz);
        return Hit(c.t, s.geo.xyz + s.geo.w * n, n, n, hit_error_sphere(s.geo.xyz, s.geo.w), s.ids.x, s.ids.z, bitcast<i32>(s.ids.y), NO_HIT);
    }
    let tri = load_triangle(c.prim);
    let p0 = tri.p0.xyz;
    let p1 = tri.p1.xyz;
    let p2 = tri.p2.xyz;
    let gn = normalize(cross(p1 - p0, p2 - p0));
    let tn = load_normals(c.prim);
    var sn = (1.0 - c.uv.x - c.uv.y) * tn.n0 + c.uv.x * tn.n1 + c.uv.y * tn.n2;
    sn = select(gn, normalize(sn), dot(sn, sn) > 1e-12);
    // Two ways to the point, each with its error bound: interpolated from
    // the vertices (its error grows with their size: a triangle a million
    // units across is off by 0.1 anywhere on it), or along the ray (its
    // error grows with the ray's origin and length). The hit takes the
    // ray's only where it is far tighter (RAY_POINT_GAIN): an interpolated
    // point lies inside the triangle's edges and planes exactly as its
    // vertices do (a card standing on a floor never dips below it), which
    // the shadow-ray occluder lists rely on (src/scene/origins.rs).
    let b0 = 1.0 - c.uv.x - c.uv.y;
    let p_bary = b0 * p0 + c.uv.x * p1 + c.uv.y * p2;
    let e_bary = hit_error_triangle(vec3f(b0, c.uv), p0, p1, p2);
    let p_ray = ro + c.t * rd;
    let e_ray = f32_gamma(3.0) * (abs(ro) + abs(c.t * rd)) + abs(rd) * triangle_t_error(make_ray(ro, rd), p0, p1, p2);
    let along_ray = RAY_POINT_GAIN * (e_ray.x + e_ray.y + e_ray.z) < e_bary.x + e_bary.y + e_bary.z;
    let p = select(p_bary, p_ray, along_ray);
    let error = select(e_bary, e_ray, along_ray);
    return Hit(c.t, p, gn, sn, error, bitcast<u32>(tri.p0.w), bitcast<u32>(tri.p1.w), -1, c.prim);
}

// How much tighter the ray's point must be than the interpolated one to
// be taken (a triangle far larger than the ray's length).
const RAY_POINT_GAIN: f32 = 64.0;

// A bound on the error of the distance t hit_triangle computes for ray r
// and the triangle (pbrt-v4's, Pharr et al. 6.8.4: from the sheared
// vertices' sizes through the edge functions and their sum); 3e38 where it
// cannot say (a ray along the triangle's plane).
fn triangle_t_error(r: Ray, p0: vec3f, p1: vec3f, p2: vec3f) -> f32 {
    let a = shear(r, p0);
    let b = shear(r, p1);
    let c = shear(r, p2);
    let u = diff_of_products(c.x, b.y, c.y, b.x);
    let v = diff_of_products(a.x, c.y, a.y, c.x);
    let w = diff_of_products(b.x, a.y, b.y, a.x);
    let det = u + v + w;
    let max_z = max(abs(a.z), max(abs(b.z), abs(c.z)));
    let max_x = max(abs(a.x), max(abs(b.x), abs(c.x)));
    let max_y = max(abs(a.y), max(abs(b.y), abs(c.y)));
    let max_e = max(abs(u), max(abs(v), abs(w)));
    let delta_z = f32_gamma(3.0) * max_z;
    let delta_x = f32_gamma(5.0) * (max_x + max_z);
    let delta_y = f32_gamma(5.0) * (max_y + max_z);
    let delta_e = 2.0 * (f32_gamma(2.0) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let delta_t = 3.0 * (f32_gamma(3.0) * max_e * max_z + delta_e * max_z + delta_z * max_e) / abs(det);
    return select(3.0e38, delta_t, delta_t == delta_t && abs(det) > 0.0 && delta_t < 3.0e38);
}

// pbrt's gamma(n): n rounded f32 operations in a row are off by at most
// this share of the exact result (n u / (1 - n u), u = 2^-24).
fn f32_gamma(n: f32) -> f32 {
    return n * 5.96046448e-8 / (1.0 - n * 5.96046448e-8);
}

// The error of a triangle hit interpolated from barycentrics b (pbrt-v4,
// Pharr et al. 6.8.4): the interpolation's seven rounded operations
// (b0 = 1 - b1 - b2 included) relative to the sum of the terms' sizes. It
// is large where the vertices are far apart or far from the origin, and 0
// along an axis all three vertices share exactly (a plane z = 0).
fn hit_error_triangle(b: vec3f, p0: vec3f, p1: vec3f, p2: vec3f) -> vec3f {
    return f32_gamma(7.0) * (abs(b.x * p0) + abs(b.y * p1) + abs(b.z * p2));
}

// The error of a sphere hit c + r n, n the normalised direction from the
// centre (pbrt-v4 6.8.5 bounds the reprojected point by gamma(5) of its
// size; the centre's addition adds one more rounding of both terms).
fn hit_error_sphere(c: vec3f, r: f32) -> vec3f {
    return f32_gamma(6.0) * (abs(c) + vec3f(r));
}

// A hit's normals faced against the ray `rd` (surfaces are two-sided): the
// geometric one, and the shading one, which falls back to the geometric
// one where interpolation left it facing along the ray.
struct Facing {
    ng: vec3f,
    n: vec3f,
}

fn facing(hit: Hit, rd: vec3f) -> Facing {
    let flip = select(1.0, -1.0, dot(hit.geo_normal, rd) > 0.0);
    let ng = hit.geo_normal * flip;
    var n = hit.normal * flip;
    if dot(n, rd) > 0.0 {
        n = ng;
    }
    return Facing(ng, n);
}

// Whether anything blocks the ray in (0, tmax) (shadow rays; exits early).
fn trace_any(ro: vec3f, rd: vec3f, tmax: f32) -> bool {
    return traverse(make_ray(ro, rd), tmax, true).prim != NO_HIT;
}

// Moves surface point p, whose error is bounded by `error` (Hit.error),
// off the surface along the unit normal `n` (pointing to the side the new
// ray leaves from): by the error's extent along the normal (pbrt-v4,
// Pharr et al. 6.8.6), so the origin is on that side of the true surface
// whatever the rounding, and by at least OFFSET_ULPS ULPs of the point's
// largest coordinate: the new ray's own intersection tests round at that
// size (shearing a neighbour's vertices loses a smaller offset, and a
// coplanar neighbour would then shadow it; pbrt rejects such hits with a
// bound on t in every test instead, which a CPU driver pays for on every
// triangle). Both scale with the operands, never with the scene's size.
fn offset_ray(p: vec3f, n: vec3f, error: vec3f) -> vec3f {
    return offset_by(p, n, dot(abs(n), error));
}

// `offset_ray` for a point whose error along `n` is at most `d` (a
// G-buffer's: gbuffer_offset_error).
fn offset_by(p: vec3f, n: vec3f, d: f32) -> vec3f {
    let largest = max(abs(p.x), max(abs(p.y), abs(p.z)));
    // The power of two at or below it, times 2^-23: its ULP.
    let ulp = bitcast<f32>(bitcast<u32>(largest) & 0x7f800000u) * 1.1920929e-7;
    return p + max(d, max(OFFSET_ULPS * ulp, TINY_OFFSET)) * n;
}

// ULPs of the largest coordinate a ray origin moves off its surface at
// least (Wächter and Binder, Ray Tracing Gems ch. 6, move each coordinate
// by 256 of its own).
const OFFSET_ULPS: f32 = 256.0;

// The least offset: at a point within 1e-27 of the origin, far below any
// size a scene holds (the README's range is 1e15 across).
const TINY_OFFSET: f32 = 1e-30;

// What a G-buffer keeps of a hit's error for the passes that offset rays
// from it (offset_by): its extent along any unit direction (the sum of
// its components bounds dot(abs(u), error) for every unit u), so a pass
// may offset along the shading normal the G-buffer stores or along the
// geometric one.
fn gbuffer_offset_error(hit: Hit) -> f32 {
    return hit.error.x + hit.error.y + hit.error.z;
}
