//! The Rust mirror of shaders/shared/ray.wgsl, intersect.wgsl and bvh.wgsl: the same
//! ray math in f32, bit for bit, so it can be tested exhaustively on the
//! CPU (the GPU path is tested too, in tests/). The traversal here is the
//! plain one (nearer child first, a leaf's triangles at once); the shader
//! interleaves a leaf's triangles with the walk to the next leaf and keeps
//! the TLAS and BLAS loops apart, for SIMD CPU drivers. The closest hit is
//! the same either way: no box that can hold it is culled, and ties go to
//! the lower primitive id (tests/rays_gpu.rs checks the GPU against brute
//! force bit for bit).

use glam::Vec3;

use super::scene::{InstanceGpu, INSTANCE_MESH, INSTANCE_SPHERE, TLAS_LEAF};
use super::BvhNode;
use crate::scene::{SphereGpu, TriangleGpu};

/// 1 + 2 gamma(3): Ize's bound on the slab test's rounding (PBRT 3.9.2).
pub const IZE_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
/// Private traversal stack depth (as in WGSL).
pub const STACK: usize = 64;
/// Sphere primitives are numbered after this bit, triangles below it.
pub const SPHERE_BIT: u32 = 0x8000_0000;

/// A ray with what the watertight test precomputes (Woop et al. 2013).
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    /// Origin.
    pub o: Vec3,
    /// Direction (need not be unit: `t` is in units of its length).
    pub d: Vec3,
    /// `safe_inverse(d)`, for the slab test.
    pub inv: Vec3,
    k: [usize; 3],
    s: Vec3,
    /// f32::MAX on an axis the ray runs parallel to (|d| < 1e-30), else 0.
    pub slack: Vec3,
}

/// 1/d with tiny components replaced by +-1e30 (keeps 0 * inf out of the
/// slab test; the sign of zero is kept).
pub fn safe_inverse(d: Vec3) -> Vec3 {
    let f = |x: f32| if x.abs() < 1e-30 { 1e30f32.copysign(x) } else { 1.0 / x };
    Vec3::new(f(d.x), f(d.y), f(d.z))
}

impl Ray {
    /// A ray from `o` along `d`, with the watertight test's shear precomputed.
    pub fn new(o: Vec3, d: Vec3) -> Ray {
        let a = d.abs();
        let kz = if a.x > a.y { if a.x > a.z { 0 } else { 2 } } else if a.y > a.z { 1 } else { 2 };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let s = Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        let slack = Vec3::from(d.to_array().map(|x| if x.abs() < 1e-30 { f32::MAX } else { 0.0 }));
        Ray { o, d, inv: safe_inverse(d), k: [kx, ky, kz], s, slack }
    }
}

/// Watertight ray/triangle: returns (t, b1, b2) with t in (0, tmax).
/// Edges are inclusive, so a ray through a shared edge hits a triangle.
pub fn hit_triangle(r: &Ray, p0: Vec3, p1: Vec3, p2: Vec3, tmax: f32) -> Option<(f32, f32, f32)> {
    let [kx, ky, kz] = r.k;
    let a = p0 - r.o;
    let b = p1 - r.o;
    let c = p2 - r.o;
    let ax = a[kx] - r.s.x * a[kz];
    let ay = a[ky] - r.s.y * a[kz];
    let bx = b[kx] - r.s.x * b[kz];
    let by = b[ky] - r.s.y * b[kz];
    let cx = c[kx] - r.s.x * c[kz];
    let cy = c[ky] - r.s.y * c[kz];
    // Each edge function as a difference of products with one rounding
    // (Kahan's fma trick): its sign is exact, so a ray through a shared
    // edge hits one of the two triangles, never neither (Woop et al. fall
    // back to double precision when an edge rounds to zero; on the GPU the
    // fma costs less than the plain products plus a fallback, which a SIMD
    // CPU driver runs for every triangle whether any lane needs it or not).
    let u = diff_of_products(cx, by, cy, bx);
    let v = diff_of_products(ax, cy, ay, cx);
    let w = diff_of_products(bx, ay, by, ax);
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 || det.is_nan() {
        return None;
    }
    let az = r.s.z * a[kz];
    let bz = r.s.z * b[kz];
    let cz = r.s.z * c[kz];
    let t = u * az + v * bz + w * cz;
    // t and det with det's sign taken off both (exact), as the shader does.
    let sign = det.to_bits() & 0x8000_0000;
    let ts = f32::from_bits(t.to_bits() ^ sign);
    if ts <= 0.0 || ts > tmax * det.abs() {
        return None;
    }
    let inv = 1.0 / det;
    let t = t * inv;
    if !(t > 0.0 && t < tmax) {
        return None;
    }
    Some((t, v * inv, w * inv))
}

/// A bound on the error of the distance `hit_triangle` computes for ray r
/// and the triangle (pbrt-v4's, Pharr et al. 6.8.4: from the sheared
/// vertices' sizes through the edge functions and their sum), as
/// `triangle_t_error` in intersect.wgsl; `f32::MAX` where it cannot say.
pub fn triangle_t_error(r: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> f32 {
    use super::offset::gamma;
    let [kx, ky, kz] = r.k;
    let shear = |p: Vec3| {
        let a = p - r.o;
        Vec3::new(a[kx] - r.s.x * a[kz], a[ky] - r.s.y * a[kz], r.s.z * a[kz])
    };
    let (a, b, c) = (shear(p0), shear(p1), shear(p2));
    let u = diff_of_products(c.x, b.y, c.y, b.x);
    let v = diff_of_products(a.x, c.y, a.y, c.x);
    let w = diff_of_products(b.x, a.y, b.y, a.x);
    let det = u + v + w;
    let max_z = a.z.abs().max(b.z.abs()).max(c.z.abs());
    let max_x = a.x.abs().max(b.x.abs()).max(c.x.abs());
    let max_y = a.y.abs().max(b.y.abs()).max(c.y.abs());
    let max_e = u.abs().max(v.abs()).max(w.abs());
    let delta_z = gamma(3.0) * max_z;
    let delta_x = gamma(5.0) * (max_x + max_z);
    let delta_y = gamma(5.0) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2.0) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let delta_t = 3.0 * (gamma(3.0) * max_e * max_z + delta_e * max_z + delta_z * max_e) / det.abs();
    if delta_t.is_finite() && det != 0.0 && delta_t < f32::MAX { delta_t } else { f32::MAX }
}

/// a*b - c*d with one rounding (Kahan): exact sign even when the two
/// products nearly cancel.
pub fn diff_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = (-c).mul_add(d, cd);
    let dop = a.mul_add(b, -cd);
    dop + err
}

/// Ray/sphere with the precision fix of Ray Tracing Gems ch. 7 (`d` unit
/// length): nearest t in (tmin, tmax).
pub fn hit_sphere(o: Vec3, d: Vec3, center: Vec3, radius: f32, tmin: f32, tmax: f32) -> Option<f32> {
    if d.dot(d) <= 0.0 {
        return None; // a zero direction goes nowhere
    }
    let f = o - center;
    let b = -f.dot(d);
    let l = f + b * d;
    let disc = radius * radius - l.dot(l);
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let c = f.dot(f) - radius * radius;
    let q = b + if b >= 0.0 { 1.0 } else { -1.0 } * disc.sqrt();
    let (mut t0, mut t1) = (if q == 0.0 { 0.0 } else { c / q }, q);
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    if t0 > tmin && t0 < tmax {
        return Some(t0);
    }
    if t1 > tmin && t1 < tmax {
        return Some(t1);
    }
    None
}

/// Slab test with Ize's conservative far bound; the entry distance if the
/// box is entered in [0, tmax]. On an axis the ray runs parallel to (a zero
/// or tiny direction component) the slab is widened to all t by `slack`:
/// 0 * 1e30 would make it end at t = 0, and a box is kept whether or not
/// the origin is between its planes (conservative; cheaper on SIMD CPU
/// drivers than an exact inside test per box). Minima and maxima by
/// compare and select, as the shader takes them (see ray.wgsl): a NaN
/// only lowers near and raises far, so the box is kept.
pub fn hit_box(r: &Ray, bmin: Vec3, bmax: Vec3, tmax: f32) -> Option<f32> {
    let t0 = (bmin - r.o) * r.inv;
    let t1 = (bmax - r.o) * r.inv;
    let first = t0.cmplt(t1);
    let lo = Vec3::select(first, t0, t1) - r.slack;
    let hi = Vec3::select(first, t1, t0) + r.slack;
    let near = larger(larger(larger(lo.x, lo.y), lo.z), 0.0);
    let far = smaller(smaller(smaller(hi.x, hi.y), hi.z), tmax) * IZE_SCALE;
    (near <= far).then_some(near)
}

/// `a` if it is the larger, else `b` (also where either is NaN).
fn larger(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `a` if it is the smaller, else `b` (also where either is NaN).
fn smaller(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// Read-only view of the scene geometry, as on the GPU.
pub struct Geometry<'a> {
    /// Spheres, as `SceneData::spheres`.
    pub spheres: &'a [SphereGpu],
    /// Triangles in BLAS leaf order, as `SceneData::triangles`.
    pub triangles: &'a [TriangleGpu],
    /// The TLAS then the BLASes (`SceneData::bvh`).
    pub nodes: &'a [BvhNode],
    /// The TLAS instances (`SceneData::instances`).
    pub instances: &'a [InstanceGpu],
}

/// The closest hit of a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Distance along the ray, in units of the direction's length.
    pub t: f32,
    /// Triangle index, or sphere index | SPHERE_BIT.
    pub prim: u32,
}

fn closer(t: f32, prim: u32, best: &Option<Hit>, tmax: f32) -> bool {
    match best {
        None => t < tmax,
        // Ties go to the lower primitive id, so order never matters.
        Some(b) => t < b.t || (t == b.t && prim < b.prim),
    }
}

impl Geometry<'_> {
    fn test_sphere(&self, r: &Ray, i: u32, best: &mut Option<Hit>, tmax: f32) {
        let s = &self.spheres[i as usize];
        let limit = best.map_or(tmax, |b| b.t).min(tmax);
        // Accept t == limit too, for the tie rule.
        if let Some(t) = hit_sphere(r.o, r.d, Vec3::from(s.center), s.radius, 0.0, next_up(limit)) {
            if closer(t, i | SPHERE_BIT, best, tmax) {
                *best = Some(Hit { t, prim: i | SPHERE_BIT });
            }
        }
    }

    fn test_triangle(&self, r: &Ray, i: u32, best: &mut Option<Hit>, tmax: f32) {
        let tri = &self.triangles[i as usize];
        let limit = best.map_or(tmax, |b| b.t).min(tmax);
        if let Some((t, _, _)) = hit_triangle(r, Vec3::from(tri.p0), Vec3::from(tri.p1), Vec3::from(tri.p2), next_up(limit)) {
            if closer(t, i, best, tmax) {
                *best = Some(Hit { t, prim: i });
            }
        }
    }

    /// Closest hit by testing everything (the reference).
    pub fn closest_brute(&self, r: &Ray, tmax: f32) -> Option<Hit> {
        let mut best = None;
        for i in 0..self.spheres.len() as u32 {
            self.test_sphere(r, i, &mut best, tmax);
        }
        for i in 0..self.triangles.len() as u32 {
            self.test_triangle(r, i, &mut best, tmax);
        }
        best
    }

    /// Tests a sphere (kind 0) or a triangle (kind 1).
    fn test(&self, r: &Ray, kind: u32, i: u32, best: &mut Option<Hit>, tmax: f32) {
        if kind == 0 {
            self.test_sphere(r, i, best, tmax);
        } else {
            self.test_triangle(r, i, best, tmax);
        }
    }

    /// Closest hit through the TLAS and BLASes.
    pub fn closest(&self, r: &Ray, tmax: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.traverse(r, tmax, |g, kind, i, b| {
            g.test(r, kind, i, b, tmax);
            false
        }, &mut best);
        best
    }

    /// `closest` with the traversal started from `entries` (node indices,
    /// the last tested first) instead of the root: a camera ray starting
    /// from the camera's cut of a BLAS (`crate::bvh::entry`).
    pub fn closest_from(&self, r: &Ray, tmax: f32, entries: &[u32]) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.traverse_from(r, tmax, Some(entries), |g, kind, i, b| {
            g.test(r, kind, i, b, tmax);
            false
        }, &mut best);
        best
    }

    /// Whether anything is hit in (0, tmax) (shadow rays; stops at the first).
    pub fn any(&self, r: &Ray, tmax: f32) -> bool {
        let mut best: Option<Hit> = None;
        self.traverse(r, tmax, |g, kind, i, b| {
            g.test(r, kind, i, b, tmax);
            b.is_some()
        }, &mut best);
        best.is_some()
    }

    /// Stack traversal, nearer child first. `visit(kind, index)` tests a
    /// sphere (kind 0) or triangle (kind 1) and returns true to stop.
    fn traverse(&self, r: &Ray, tmax: f32, visit: impl FnMut(&Self, u32, u32, &mut Option<Hit>) -> bool, best: &mut Option<Hit>) {
        self.traverse_from(r, tmax, None, visit, best);
    }

    /// `traverse` from the root (`entries` None) or from the nodes listed,
    /// each pushed if its box is hit, in order (the last on top).
    fn traverse_from(
        &self,
        r: &Ray,
        tmax: f32,
        entries: Option<&[u32]>,
        mut visit: impl FnMut(&Self, u32, u32, &mut Option<Hit>) -> bool,
        best: &mut Option<Hit>,
    ) {
        // NaN, infinite and zero rays miss (a zero direction is parallel to
        // every slab and would keep every box).
        let finite = r.o.is_finite() && r.d.is_finite() && r.d != Vec3::ZERO;
        if self.nodes.is_empty() || !finite {
            return;
        }
        // Spheres that are no TLAS instance are tested apart, first
        // (`SceneData::spheres_apart`, SPHERES_APART in intersect.wgsl).
        if !self.instances.iter().any(|i| i.kind == INSTANCE_SPHERE) {
            for i in 0..self.spheres.len() as u32 {
                if visit(self, 0, i, best) {
                    return;
                }
            }
        }
        let mut stack = [(0u32, 0.0f32); STACK];
        let mut sp = 0;
        for &i in entries.unwrap_or(&[0]) {
            let node = self.nodes[i as usize];
            if let Some(t) = hit_box(r, node.bounds().min, node.bounds().max, tmax) {
                if sp < STACK {
                    stack[sp] = (i, t);
                    sp += 1;
                }
            }
        }
        while sp > 0 {
            sp -= 1;
            let (index, t_near) = stack[sp];
            let limit = best.map_or(tmax, |b| b.t).min(tmax);
            // The same slack hit_box gives its far bound.
            if t_near > limit * IZE_SCALE {
                continue;
            }
            let node = self.nodes[index as usize];
            if node.count & TLAS_LEAF != 0 {
                for k in node.left_first..node.left_first + (node.count & !TLAS_LEAF) {
                    let inst = self.instances[k as usize];
                    if inst.kind == INSTANCE_MESH {
                        let root = self.nodes[inst.index as usize];
                        if let Some(t) = hit_box(r, root.bounds().min, root.bounds().max, limit) {
                            if sp < STACK {
                                stack[sp] = (inst.index, t);
                                sp += 1;
                            }
                        }
                    } else if visit(self, 0, inst.index, best) {
                        return;
                    }
                }
            } else if node.count > 0 {
                for i in node.left_first..node.left_first + node.count {
                    if visit(self, 1, i, best) {
                        return;
                    }
                }
            } else {
                let (a, b) = (node.left_first, node.left_first + 1);
                let ta = hit_box(r, self.nodes[a as usize].bounds().min, self.nodes[a as usize].bounds().max, limit);
                let tb = hit_box(r, self.nodes[b as usize].bounds().min, self.nodes[b as usize].bounds().max, limit);
                let mut push = |n: u32, t: f32| {
                    if sp < STACK {
                        stack[sp] = (n, t);
                        sp += 1;
                    }
                };
                match (ta, tb) {
                    (Some(ta), Some(tb)) if ta <= tb => {
                        push(b, tb);
                        push(a, ta);
                    }
                    (Some(ta), Some(tb)) => {
                        push(a, ta);
                        push(b, tb);
                    }
                    (Some(ta), None) => push(a, ta),
                    (None, Some(tb)) => push(b, tb),
                    (None, None) => {}
                }
            }
        }
    }
}

/// The next f32 above x (x finite); used so a hit at exactly the current
/// best distance is still reported and the tie rule can decide.
pub fn next_up(x: f32) -> f32 {
    if x.is_nan() || x == f32::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f32::from_bits(1);
    }
    let bits = x.to_bits();
    f32::from_bits(if x > 0.0 { bits + 1 } else { bits - 1 })
}
