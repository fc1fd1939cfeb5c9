// Ray queries against the scene. Every pass traces through `trace_closest`
// and `trace_any`; the acceleration structure lives behind them.
// For now: spheres brute force, triangles brute force per mesh behind the
// mesh's bounding box.
#import scene

const NO_HIT: u32 = 0xffffffffu;

struct Hit {
    t: f32,
    // Geometric and shading normals (unit length, not yet faced to the ray).
    geo_normal: vec3f,
    normal: vec3f,
    material: u32,
    object: u32,
    // Index of the sphere light hit, or -1.
    light: i32,
}

fn hit_found(h: Hit) -> bool {
    return h.object != NO_HIT;
}

fn no_hit(tmax: f32) -> Hit {
    return Hit(tmax, vec3f(0.0), vec3f(0.0), 0u, NO_HIT, -1);
}

// Ray/sphere with the precision fix of Ray Tracing Gems ch. 7: the
// discriminant from the perpendicular distance, and the smaller root from
// c / q. `rd` must be unit length. Returns the nearest t in (tmin, tmax), or -1.
fn ray_sphere(ro: vec3f, rd: vec3f, center: vec3f, radius: f32, tmin: f32, tmax: f32) -> f32 {
    let f = ro - center;
    let b = -dot(f, rd);
    let l = f + b * rd;
    let disc = radius * radius - dot(l, l);
    if disc < 0.0 {
        return -1.0;
    }
    let c = dot(f, f) - radius * radius;
    let q = b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc);
    var t0 = select(c / q, 0.0, q == 0.0);
    var t1 = q;
    if t0 > t1 {
        let tmp = t0;
        t0 = t1;
        t1 = tmp;
    }
    if t0 > tmin && t0 < tmax {
        return t0;
    }
    if t1 > tmin && t1 < tmax {
        return t1;
    }
    return -1.0;
}

// Slab test; true if the box is entered before tmax.
fn ray_box(ro: vec3f, inv_rd: vec3f, bmin: vec3f, bmax: vec3f, tmax: f32) -> bool {
    let t0 = (bmin - ro) * inv_rd;
    let t1 = (bmax - ro) * inv_rd;
    let tnear = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z));
    let tfar = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
    return tnear <= tfar && tfar >= 0.0 && tnear < tmax;
}

// Ray/triangle (Moller-Trumbore). Returns (t, u, v); t < 0 on a miss.
fn ray_triangle(ro: vec3f, rd: vec3f, p0: vec3f, p1: vec3f, p2: vec3f) -> vec3f {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = cross(rd, e2);
    let det = dot(e1, pv);
    if abs(det) < 1e-20 {
        return vec3f(-1.0, 0.0, 0.0);
    }
    let inv = 1.0 / det;
    let tv = ro - p0;
    let u = dot(tv, pv) * inv;
    if u < 0.0 || u > 1.0 {
        return vec3f(-1.0, 0.0, 0.0);
    }
    let qv = cross(tv, e1);
    let v = dot(rd, qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return vec3f(-1.0, 0.0, 0.0);
    }
    return vec3f(dot(e2, qv) * inv, u, v);
}

fn safe_inverse(d: vec3f) -> vec3f {
    let tiny = 1e-30;
    return 1.0 / select(d, vec3f(tiny), abs(d) < vec3f(tiny));
}

// The closest hit along a unit-length ray in (0, tmax).
fn trace_closest(ro: vec3f, rd: vec3f, tmax: f32) -> Hit {
    var best = no_hit(tmax);
    var best_tri = NO_HIT;
    var best_uv = vec2f(0.0);
    for (var i = 0u; i < frame.n_spheres; i++) {
        let s = scene_spheres[i];
        let t = ray_sphere(ro, rd, s.center, s.radius, 0.0, best.t);
        if t > 0.0 {
            let n = (ro + t * rd - s.center) / s.radius;
            best = Hit(t, n, n, s.material, s.object, s.light);
        }
    }
    let inv_rd = safe_inverse(rd);
    for (var m = 0u; m < frame.n_meshes; m++) {
        let mesh = scene_meshes[m];
        if !ray_box(ro, inv_rd, mesh.bmin, mesh.bmax, best.t) {
            continue;
        }
        for (var k = 0u; k < mesh.count; k++) {
            let tri = scene_triangles[mesh.first + k];
            let r = ray_triangle(ro, rd, tri.p0, tri.p1, tri.p2);
            if r.x > 0.0 && r.x < best.t {
                best.t = r.x;
                best_tri = mesh.first + k;
                best_uv = r.yz;
                best.object = tri.object;
            }
        }
    }
    if best_tri != NO_HIT {
        let tri = scene_triangles[best_tri];
        let gn = normalize(cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
        var sn = (1.0 - best_uv.x - best_uv.y) * tri.n0 + best_uv.x * tri.n1 + best_uv.y * tri.n2;
        sn = select(gn, normalize(sn), dot(sn, sn) > 1e-12);
        best = Hit(best.t, gn, sn, tri.material, tri.object, -1);
    }
    return best;
}

// Whether anything blocks the ray in (0, tmax) (shadow rays; exits early).
fn trace_any(ro: vec3f, rd: vec3f, tmax: f32) -> bool {
    for (var i = 0u; i < frame.n_spheres; i++) {
        let s = scene_spheres[i];
        if ray_sphere(ro, rd, s.center, s.radius, 0.0, tmax) > 0.0 {
            return true;
        }
    }
    let inv_rd = safe_inverse(rd);
    for (var m = 0u; m < frame.n_meshes; m++) {
        let mesh = scene_meshes[m];
        if !ray_box(ro, inv_rd, mesh.bmin, mesh.bmax, tmax) {
            continue;
        }
        for (var k = 0u; k < mesh.count; k++) {
            let tri = scene_triangles[mesh.first + k];
            let r = ray_triangle(ro, rd, tri.p0, tri.p1, tri.p2);
            if r.x > 0.0 && r.x < tmax {
                return true;
            }
        }
    }
    return false;
}

// Moves a surface point off the surface along the geometric normal `n`
// (pointing to the side the new ray leaves from), by a few ULPs scaled to
// the magnitude of p (Wachter & Binder, Ray Tracing Gems ch. 6).
fn offset_ray(p: vec3f, n: vec3f) -> vec3f {
    let origin = 1.0 / 32.0;
    let float_scale = 1.0 / 65536.0;
    let int_scale = 256.0;
    let of_i = vec3i(int_scale * n);
    let p_i = vec3f(
        bitcast<f32>(bitcast<i32>(p.x) + select(of_i.x, -of_i.x, p.x < 0.0)),
        bitcast<f32>(bitcast<i32>(p.y) + select(of_i.y, -of_i.y, p.y < 0.0)),
        bitcast<f32>(bitcast<i32>(p.z) + select(of_i.z, -of_i.z, p.z < 0.0)),
    );
    return select(p_i, p + float_scale * n, abs(p) < vec3f(origin));
}
