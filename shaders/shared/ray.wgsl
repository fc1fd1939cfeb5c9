// A ray and its tests against one box, triangle or sphere: watertight
// triangles (Woop, Benthin, Wald 2013), conservative slabs (Ize), precise
// spheres (Ray Tracing Gems ch. 7). intersect.wgsl traverses the scene
// with them. Mirrored in Rust by src/bvh/ray.rs.

// 1 + 2 gamma(3), Ize's bound on the slab test's rounding.
const IZE_SCALE: f32 = 1.0000003576;

// A ray with the watertight test's per-ray constants.
struct Ray {
    o: vec3f,
    d: vec3f,
    inv: vec3f,
    // permute(r, v) = (v[kx], v[ky], v[kz]) by selects: (kx, ky, kz) == 1
    // and == 2 per component. Dynamic vector indexing becomes memory
    // traffic on CPU drivers, a 0/1 matrix product costs 15 flops.
    is1: vec3<bool>,
    is2: vec3<bool>,
    s: vec3f,
    // f32::MAX on an axis the ray runs parallel to (|d| < 1e-30), else 0.
    slack: vec3f,
    // Triangle hits count beyond this distance only: 0, or where a
    // retraced ray's alpha-tested hit let it through (intersect.wgsl).
    tmin: f32,
}

fn permute(r: Ray, v: vec3f) -> vec3f {
    return select(select(vec3f(v.x), vec3f(v.y), r.is1), vec3f(v.z), r.is2);
}

// 1/d with tiny components replaced by +-1e30 (keeps 0 * inf out of the slabs).
fn safe_inverse(d: vec3f) -> vec3f {
    let negative = (bitcast<vec3u>(d) & vec3u(0x80000000u)) != vec3u(0u);
    let big = select(vec3f(1e30), vec3f(-1e30), negative);
    return select(1.0 / d, big, abs(d) < vec3f(1e-30));
}

fn make_ray(o: vec3f, d: vec3f) -> Ray {
    let a = abs(d);
    var kz = 2u;
    if a.x > a.y {
        if a.x > a.z { kz = 0u; }
    } else if a.y > a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if select(select(d.x, d.y, kz == 1u), d.z, kz == 2u) < 0.0 {
        let t = kx;
        kx = ky;
        ky = t;
    }
    let k = vec3u(kx, ky, kz);
    let slack = select(vec3f(0.0), vec3f(3.40282347e38), abs(d) < vec3f(1e-30));
    let r = Ray(o, d, safe_inverse(d), k == vec3u(1u), k == vec3u(2u), vec3f(0.0), slack, 0.0);
    let pd = permute(r, d);
    return Ray(o, d, r.inv, r.is1, r.is2, vec3f(pd.x / pd.z, pd.y / pd.z, 1.0 / pd.z), slack, 0.0);
}

// Entry distance of the box in [0, tmax], or -1 on a miss. On an axis the
// ray runs parallel to, `slack` widens the slab to all t: the box is kept
// whether or not the origin lies between its planes (conservative; an
// exact inside test per box cost 12% of the primary rays on the 1M knot).
//
// Its minima and maxima are compares and selects, not min() and max(),
// which must return the operand that is not NaN: lavapipe pays for that
// with an unordered compare and a blend on every call, and with one
// compare shared by each axis's minimum and maximum, x86's own min and
// max remain (primary rays 0.92-0.93x the time on the 1M knot). A NaN (an
// origin or box near f32::MAX) leaves operands out of these maxima and
// minima, which only lowers near and raises far: the box is kept.
fn hit_box(r: Ray, bmin: vec3f, bmax: vec3f, tmax: f32) -> f32 {
    let t0 = (bmin - r.o) * r.inv;
    let t1 = (bmax - r.o) * r.inv;
    let t0_first = t0 < t1;
    let lo = select(t1, t0, t0_first) - r.slack;
    let hi = select(t0, t1, t0_first) + r.slack;
    let near = larger(larger(larger(lo.x, lo.y), lo.z), 0.0);
    let far = smaller(smaller(smaller(hi.x, hi.y), hi.z), tmax) * IZE_SCALE;
    return select(-1.0, near, near <= far);
}

// max(a, b) and min(a, b) as x86 computes them: b where either is NaN.
fn larger(a: f32, b: f32) -> f32 {
    return select(b, a, a > b);
}

fn smaller(a: f32, b: f32) -> f32 {
    return select(b, a, a < b);
}

// a*b - c*d with one rounding where fma is fused (Kahan).
fn diff_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = fma(-c, d, cd);
    let dop = fma(a, b, -cd);
    return dop + err;
}

// Watertight ray/triangle: (t, b1, b2) with t in (0, tmax), or t = -1.
fn hit_triangle(r: Ray, p0: vec3f, p1: vec3f, p2: vec3f, tmax: f32) -> vec3f {
    return hit_sheared(shear(r, p0), shear(r, p1), shear(r, p2), tmax);
}

// Vertex p in the ray's sheared frame (Woop et al.): (x, y) relative to the
// ray's axis, z scaled. Triangles that share a vertex can share this.
fn shear(r: Ray, p: vec3f) -> vec3f {
    let a = permute(r, p - r.o);
    return vec3f(a.x - r.s.x * a.z, a.y - r.s.y * a.z, r.s.z * a.z);
}

// The watertight test on vertices already sheared (`shear`).
fn hit_sheared(a: vec3f, b: vec3f, c: vec3f, tmax: f32) -> vec3f {
    // Each edge function as a difference of products with one rounding
    // (Kahan's fma trick): its sign is exact, so a ray through a shared
    // edge hits one of the two triangles, never neither. Always, not as a
    // fallback when a plain product difference rounds to zero: a SIMD CPU
    // driver runs the fallback for every triangle, so the plain products
    // were pure cost (the path tracer 0.91x the time without them).
    let u = diff_of_products(c.x, b.y, c.y, b.x);
    let v = diff_of_products(a.x, c.y, a.y, c.x);
    let w = diff_of_products(b.x, a.y, b.y, a.x);
    let miss = vec3f(-1.0, 0.0, 0.0);
    // Edge functions of both signs: outside. Written out as three tests
    // each side, the driver's compiler turns this into min() and max() and
    // pays for their NaN rule (see hit_box); compares and selects instead.
    // Where a NaN changes this test, det below is NaN and the triangle
    // misses either way.
    if smaller(smaller(u, v), w) < 0.0 && larger(larger(u, v), w) > 0.0 {
        return miss;
    }
    let det = u + v + w;
    if !(det != 0.0) {
        return miss;
    }
    let t = u * a.z + v * b.z + w * c.z;
    // t and det with det's sign taken off both (exact): in range when
    // 0 < t' <= tmax |det|.
    let sign = bitcast<u32>(det) & 0x80000000u;
    let ts = bitcast<f32>(bitcast<u32>(t) ^ sign);
    if ts <= 0.0 || ts > tmax * abs(det) {
        return miss;
    }
    let inv = 1.0 / det;
    let tt = t * inv;
    if !(tt > 0.0 && tt < tmax) {
        return miss;
    }
    return vec3f(tt, v * inv, w * inv);
}

// Ray/sphere with the precision fix of Ray Tracing Gems ch. 7: the
// discriminant from the perpendicular distance, the smaller root from c / q.
// `rd` must be unit length. Nearest t in (tmin, tmax), or -1.
fn ray_sphere(ro: vec3f, rd: vec3f, center: vec3f, radius: f32, tmin: f32, tmax: f32) -> f32 {
    if !(dot(rd, rd) > 0.0) {
        return -1.0; // a zero direction goes nowhere
    }
    let f = ro - center;
    let b = -dot(f, rd);
    let l = f + b * rd;
    let disc = radius * radius - dot(l, l);
    if !(disc >= 0.0) {
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

// The next float above x (x >= 0 finite): a hit at exactly the best distance
// still counts, and ties go to the lower primitive id (as in the mirror).
fn next_up(x: f32) -> f32 {
    return select(bitcast<f32>(bitcast<u32>(x) + 1u), bitcast<f32>(1u), x == 0.0);
}
