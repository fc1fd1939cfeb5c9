//! Tests of the BVH and the ray math on the CPU mirror (docs/acceleration.md
//! and docs/tests.md): BVH traversal against brute force, watertightness, offsetting
//! ray origins off surfaces, ray/sphere precision, and NaN/Inf/zero rays.
//!
//! Every scene is built as the renderer builds it: world-space triangles in
//! `MeshGpu` ranges plus spheres in a `SceneData`, then `SceneBvh::update`.
//! `update` reorders the triangles within each mesh, so brute force always
//! runs on the same, reordered, data as the BVH.
//!
//! The statistics printed with `eprintln!` show with `--nocapture`.

use std::time::Instant;

use bytemuck::Zeroable;
use glam::{DVec3, Vec3};

use super::offset::{offset_ray, ray_point_error, sphere_error, triangle_error, triangle_hit};
use super::{BLAS_MAX_DEPTH, TLAS_MAX_DEPTH};
use super::ray::{hit_sphere, hit_triangle, next_up, triangle_t_error, Geometry, Hit, Ray, SPHERE_BIT, STACK};
use super::scene::{SceneBvh, INSTANCE_MESH, INSTANCE_SPHERE, TLAS_LEAF};
use super::{Aabb, BvhNode};
use crate::scene::{MeshGpu, SceneData, SphereGpu, TriangleGpu, SPHERES_APART_LIMIT};

const INF: f32 = f32::INFINITY;

// ---------------------------------------------------------------------------
// Helpers: a deterministic RNG, scene building, comparison.

/// PCG32 (O'Neill), XSH RR output.
struct Rng {
    state: u64,
    inc: u64,
}

impl Rng {
    fn new(seed: u64) -> Rng {
        let mut r = Rng { state: 0, inc: (seed << 1) | 1 };
        r.next_u32();
        r.state = r.state.wrapping_add(0x853c_49e6_748f_ea9b ^ seed);
        r.next_u32();
        r
    }

    fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in [0, 1) with 53 random bits.
    fn f64(&mut self) -> f64 {
        let hi = (self.next_u32() as u64) << 21;
        let lo = (self.next_u32() >> 11) as u64;
        (hi | lo) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }

    fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.f64()).exp()
    }

    fn below(&mut self, n: usize) -> usize {
        ((self.f64() * n as f64) as usize).min(n - 1)
    }

    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len())]
    }

    fn sign(&mut self) -> f64 {
        if self.next_u32() & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }

    /// Uniform on the unit sphere.
    fn unit(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }

    fn in_box(&mut self, half: f64) -> DVec3 {
        DVec3::new(self.range(-half, half), self.range(-half, half), self.range(-half, half))
    }

    /// A unit direction making cosine `cos` with unit `n`, random around it.
    fn around(&mut self, n: DVec3, cos: f64) -> DVec3 {
        let (t, b) = n.any_orthonormal_pair();
        let phi = self.range(0.0, std::f64::consts::TAU);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        (n * cos + (t * phi.cos() + b * phi.sin()) * sin).normalize()
    }

    /// A direction in the hemisphere around unit `n`, steep to grazing.
    fn hemisphere(&mut self, n: DVec3) -> DVec3 {
        let cos = self.hemisphere_cos();
        self.around(n, cos)
    }

    /// A direction around unit `n` with a cosine uniform in [lo, hi].
    fn cone(&mut self, n: DVec3, lo: f64, hi: f64) -> DVec3 {
        let cos = self.range(lo, hi);
        self.around(n, cos)
    }

    /// A cosine for a direction in a hemisphere: a third uniform, a third
    /// grazing (log-uniform down to 1e-4), a third steep.
    fn hemisphere_cos(&mut self) -> f64 {
        match self.below(3) {
            0 => self.range(1e-3, 1.0),
            1 => self.log_range(1e-4, 0.1),
            _ => 1.0 - self.log_range(1e-6, 0.5),
        }
    }
}

fn tri(a: Vec3, b: Vec3, c: Vec3) -> TriangleGpu {
    TriangleGpu { p0: a.to_array(), p1: b.to_array(), p2: c.to_array(), ..TriangleGpu::zeroed() }
}

fn corners(t: &TriangleGpu) -> [Vec3; 3] {
    [Vec3::from(t.p0), Vec3::from(t.p1), Vec3::from(t.p2)]
}

fn add_mesh(data: &mut SceneData, tris: &[TriangleGpu]) {
    let first = data.triangles.len() as u32;
    let mut b = Aabb::EMPTY;
    for t in tris {
        for p in corners(t) {
            b.grow(p);
        }
    }
    data.meshes.push(MeshGpu { bmin: b.min.to_array(), first, bmax: b.max.to_array(), count: tris.len() as u32 });
    data.triangles.extend_from_slice(tris);
}

fn add_sphere(data: &mut SceneData, c: Vec3, r: f32) {
    let object = data.spheres.len() as u32;
    data.spheres.push(SphereGpu { center: c.to_array(), radius: r, material: 0, light: -1, object, _pad: 0 });
}

fn built(mut data: SceneData) -> SceneData {
    SceneBvh::default().update(&mut data);
    data
}

fn geometry(data: &SceneData) -> Geometry<'_> {
    Geometry { spheres: &data.spheres, triangles: &data.triangles, nodes: &data.bvh, instances: &data.instances }
}

fn f(v: DVec3) -> Vec3 {
    v.as_vec3()
}

fn d(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// The spacing of f32 values at |x|.
fn ulp(x: f32) -> f32 {
    let a = x.abs();
    f32::from_bits(a.to_bits() + 1) - a
}

fn same_hit(a: Option<Hit>, b: Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => a.t.to_bits() == b.t.to_bits() && a.prim == b.prim,
        _ => false,
    }
}

/// Runs rays through the BVH and brute force and collects disagreements.
struct Compare<'a> {
    name: &'static str,
    g: Geometry<'a>,
    rays: usize,
    hits: usize,
    failed: usize,
    failures: Vec<String>,
    causes: std::collections::BTreeMap<&'static str, usize>,
}

impl<'a> Compare<'a> {
    fn new(name: &'static str, data: &'a SceneData) -> Compare<'a> {
        Compare { name, g: geometry(data), rays: 0, hits: 0, failed: 0, failures: Vec::new(), causes: Default::default() }
    }

    /// `closest` must equal `closest_brute` bit for bit and `any` must agree
    /// on hit or miss. Returns the brute-force hit.
    fn ray(&mut self, o: Vec3, dir: Vec3, tmax: f32) -> Option<Hit> {
        let r = Ray::new(o, dir);
        let brute = self.g.closest_brute(&r, tmax);
        let bvh = self.g.closest(&r, tmax);
        let any = self.g.any(&r, tmax);
        self.rays += 1;
        self.hits += brute.is_some() as usize;
        if !same_hit(bvh, brute) || any != brute.is_some() {
            self.failed += 1;
            let why = self.diagnose(o, dir, tmax, bvh, brute);
            let seen = self.causes.entry(why).or_default();
            *seen += 1;
            if *seen <= 3 {
                self.failures.push(format!(
                    "o {o:?} d {dir:?} tmax {tmax:?}: closest {bvh:?}, brute force {brute:?}, any {any} [{why}]"
                ));
            }
        }
        brute
    }

    /// The ray with tmax = inf, then, if it hits, with tmax at the hit (the
    /// hit must not count), just above it (it must) and halfway.
    fn ray_bounds(&mut self, o: Vec3, dir: Vec3) {
        if let Some(h) = self.ray(o, dir, INF) {
            self.ray(o, dir, h.t);
            self.ray(o, dir, next_up(h.t));
            self.ray(o, dir, h.t * 0.5);
        }
    }

    /// A guess at why the two disagree, for the failure message.
    fn diagnose(&self, o: Vec3, dir: Vec3, tmax: f32, bvh: Option<Hit>, brute: Option<Hit>) -> &'static str {
        if !(0.5..2.0).contains(&dir.length()) {
            return "direction not unit length";
        }
        // The hit one of them found and the other did not (or lost on a tie).
        let h = match (bvh, brute) {
            (Some(a), Some(b)) if a.t == b.t => return "tie at the same t resolved differently",
            (Some(a), Some(b)) if a.t > b.t && (b.t as f64) > 1e-5 * (1.0 + o.length() as f64) => {
                return "closest returned a farther hit than brute force"
            }
            (None, Some(b)) if b.t < tmax && b.t as f64 > (1.0 - 1e-6) * tmax as f64 => {
                return "a hit just below tmax missed"
            }
            (Some(a), Some(b)) => if a.t < b.t { a } else { b },
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => return "any disagrees",
        };
        if h.prim & SPHERE_BIT != 0 {
            return "sphere";
        }
        let [a, b, c] = corners(&self.g.triangles[h.prim as usize]).map(d);
        let p = d(o) + d(dir) * h.t as f64;
        let size = (b - a).length().max((c - a).length()).max(1e-30);
        let off = (closest_on_triangle(p, a, b, c) - p).length();
        if off > 1e-3 * size + 1e-6 * p.length() {
            return "phantom hit: the hit point is off the triangle";
        }
        if (h.t as f64) < 1e-5 * (1.0 + o.length() as f64) {
            return "hit at t within rounding of 0";
        }
        if dir.to_array().iter().any(|x| x.abs() < 1e-30) {
            return "a zero direction component (a ray in a box face plane?)";
        }
        "other"
    }

    fn finish(self) {
        eprintln!("{}: {} rays, {} hits, {} disagreements {:?}", self.name, self.rays, self.hits, self.failed, self.causes);
        assert!(
            self.failed == 0,
            "{}: BVH and brute force disagree on {} of {} rays, e.g.\n{}",
            self.name,
            self.failed,
            self.rays,
            self.failures.join("\n")
        );
    }
}

/// Depth (in nodes, root = 1) of the deepest leaf reached from the TLAS root
/// through the BLASes.
fn tree_depth(nodes: &[BvhNode], instances: &[super::scene::InstanceGpu]) -> usize {
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, depth)) = stack.pop() {
        deepest = deepest.max(depth);
        let n = nodes[i];
        if n.count & TLAS_LEAF != 0 {
            for k in n.left_first..n.left_first + (n.count & !TLAS_LEAF) {
                let inst = instances[k as usize];
                if inst.kind == INSTANCE_MESH {
                    stack.push((inst.index as usize, depth + 1));
                }
            }
        } else if n.count == 0 {
            stack.push((n.left_first as usize, depth + 1));
            stack.push((n.left_first as usize + 1, depth + 1));
        }
    }
    deepest
}

/// A point on a random one of `tris` (in f32): a vertex, a point on an edge
/// (lerp between its two endpoints) or inside.
fn point_on(rng: &mut Rng, tris: &[TriangleGpu]) -> Vec3 {
    let [a, b, c] = corners(&tris[rng.below(tris.len())]);
    let e = [(a, b), (b, c), (c, a)][rng.below(3)];
    match rng.below(3) {
        0 => [a, b, c][rng.below(3)],
        1 => {
            let s = rng.f64() as f32;
            e.0.lerp(e.1, rng.pick(&[0.5, 0.25, s]))
        }
        _ => {
            let (mut u, mut v) = (rng.f64(), rng.f64());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            f(d(a) + (d(b) - d(a)) * u + (d(c) - d(a)) * v)
        }
    }
}

// ---------------------------------------------------------------------------
// 1. BVH == brute force.

fn random_soup(rng: &mut Rng, sizes: &[usize], spheres: usize) -> SceneData {
    let mut data = SceneData::default();
    for &n in sizes {
        let centre = rng.in_box(20.0);
        let spread = rng.range(1.0, 10.0);
        let tris: Vec<TriangleGpu> = (0..n)
            .map(|k| {
                let c = centre + rng.in_box(spread);
                let s = rng.log_range(0.01, 2.0);
                let mut p = [c + rng.unit() * s, c + rng.unit() * s, c + rng.unit() * s];
                // A few degenerate ones: a repeated vertex, collinear, a point.
                match k % 97 {
                    1 => p[2] = p[0],
                    2 => p[2] = (p[0] + p[1]) * 0.5,
                    3 => p = [p[0]; 3],
                    _ => {}
                }
                tri(f(p[0]), f(p[1]), f(p[2]))
            })
            .collect();
        add_mesh(&mut data, &tris);
    }
    for _ in 0..spheres {
        add_sphere(&mut data, f(rng.in_box(20.0)), rng.log_range(0.05, 3.0) as f32);
    }
    built(data)
}

#[test]
fn bvh_matches_brute_force_on_random_soups() {
    let mut rng = Rng::new(1);
    let data = random_soup(&mut rng, &[1, 2, 3, 10, 64, 500, 3000], 16);
    let mut cmp = Compare::new("random soup", &data);
    for i in 0..6000 {
        let o = rng.in_box(30.0);
        let dir = if i % 2 == 0 {
            rng.unit()
        } else {
            // Aimed at a vertex, an edge or the inside of a triangle, or at a sphere.
            let target = if i % 10 == 1 && !data.spheres.is_empty() {
                let s = data.spheres[rng.below(data.spheres.len())];
                d(Vec3::from(s.center)) + rng.unit() * (s.radius as f64 * rng.range(0.0, 1.05))
            } else {
                d(point_on(&mut rng, &data.triangles))
            };
            (target - o).normalize()
        };
        cmp.ray_bounds(f(o), f(dir));
    }
    cmp.finish();
}

/// Up to SPHERES_APART_LIMIT spheres are tested apart, before the BVH,
/// whose TLAS then holds the meshes alone (SPHERES_APART); more are TLAS
/// instances. Both ways find what testing everything finds.
#[test]
fn spheres_are_tested_apart_up_to_their_limit_and_as_instances_beyond() {
    let mut rng = Rng::new(9);
    let apart = random_soup(&mut rng, &[40, 500], 16);
    assert!(apart.spheres_apart());
    assert!(apart.instances.iter().all(|i| i.kind == INSTANCE_MESH), "{:?}", apart.instances);
    let many = random_soup(&mut rng, &[40, 500], SPHERES_APART_LIMIT + 8);
    assert!(!many.spheres_apart());
    assert_eq!(many.instances.iter().filter(|i| i.kind == INSTANCE_SPHERE).count(), SPHERES_APART_LIMIT + 8);
    for (name, data) in [("spheres apart", &apart), ("spheres as instances", &many)] {
        let mut cmp = Compare::new(name, data);
        for i in 0..3000 {
            let o = rng.in_box(30.0);
            let target = if i % 2 == 0 {
                let s = data.spheres[rng.below(data.spheres.len())];
                d(Vec3::from(s.center)) + rng.unit() * (s.radius as f64 * rng.range(0.0, 1.05))
            } else {
                d(point_on(&mut rng, &data.triangles))
            };
            cmp.ray_bounds(f(o), f((target - o).normalize()));
        }
        cmp.finish();
    }
}

/// Directions with components exactly +0.0, -0.0, +1e-30 and -1e-30 in every
/// combination with ordinary components (scaled so the direction has unit
/// length; the special components stay exact). Directions made only of
/// special components are left out: all zeros are a bad ray (section 5), and
/// a direction like (1e-30, 0, 0) is not unit length, which glint's rays are
/// (the slab test stands in +-1e30 for 1/0, which assumes |d| ~ 1: with
/// |d| ~ 1e-30 hits lie at t ~ 1e31 and the boxes are culled).
#[test]
fn bvh_matches_brute_force_with_zero_and_tiny_direction_components() {
    let mut rng = Rng::new(2);
    let data = random_soup(&mut rng, &[1, 3, 100, 2000], 12);
    let mut cmp = Compare::new("+-0 and +-1e-30 direction components", &data);
    const SPECIAL: [f32; 4] = [0.0, -0.0, 1e-30, -1e-30];
    for pattern in 0..125 {
        let pick = [pattern % 5, pattern / 5 % 5, pattern / 25];
        if pick.iter().all(|&k| k < 4) {
            continue;
        }
        for k in 0..60 {
            let mut ordinary = DVec3::ZERO;
            for a in 0..3 {
                if pick[a] == 4 {
                    ordinary[a] = rng.sign() * rng.range(0.05, 1.0);
                }
            }
            let ordinary = ordinary.normalize();
            let mut dir = [0.0f32; 3];
            for a in 0..3 {
                dir[a] = if pick[a] < 4 { SPECIAL[pick[a]] } else { ordinary[a] as f32 };
            }
            let dir = Vec3::from(dir);
            let o = if k % 2 == 0 {
                f(rng.in_box(30.0))
            } else {
                // Back from a vertex, edge or inner point along the ray: the
                // special components keep the target's coordinates exactly.
                point_on(&mut rng, &data.triangles) - dir * 40.0
            };
            cmp.ray_bounds(o, dir);
        }
    }
    cmp.finish();
}

/// Steps of axis-aligned quads (two triangles each) in two meshes: risers at
/// x = xs[i], treads at y = ys[i + 1], split along z at zs. Returns the scene
/// and the coordinates used.
fn stairs() -> (SceneData, Vec<f32>, Vec<f32>, Vec<f32>) {
    const STEPS: usize = 16;
    let xs: Vec<f32> = (0..=STEPS).map(|i| i as f32 * 0.3 - 2.0).collect();
    let ys: Vec<f32> = (0..=STEPS).map(|i| i as f32 * 0.17 - 1.0).collect();
    let zs: Vec<f32> = (0..=4).map(|k| k as f32 * 0.55 - 1.1).collect();
    let quad = |a: Vec3, b: Vec3, c: Vec3, dd: Vec3, flip: bool| {
        if flip {
            [tri(a, b, c), tri(a, c, dd)]
        } else {
            [tri(a, b, dd), tri(b, c, dd)]
        }
    };
    let mut data = SceneData::default();
    for half in [0..STEPS / 2, STEPS / 2..STEPS] {
        let mut tris = Vec::new();
        for i in half {
            for k in 0..zs.len() - 1 {
                let flip = (i + k) % 2 == 0;
                let (z0, z1) = (zs[k], zs[k + 1]);
                let (x0, x1, y0, y1) = (xs[i], xs[i + 1], ys[i], ys[i + 1]);
                // Riser at x0 from y0 to y1, tread at y1 from x0 to x1.
                tris.extend(quad(
                    Vec3::new(x0, y0, z0),
                    Vec3::new(x0, y1, z0),
                    Vec3::new(x0, y1, z1),
                    Vec3::new(x0, y0, z1),
                    flip,
                ));
                tris.extend(quad(
                    Vec3::new(x0, y1, z0),
                    Vec3::new(x1, y1, z0),
                    Vec3::new(x1, y1, z1),
                    Vec3::new(x0, y1, z1),
                    !flip,
                ));
            }
        }
        add_mesh(&mut data, &tris);
    }
    (built(data), xs, ys, zs)
}

/// The coordinates plus the midpoints between neighbours.
fn with_midpoints(v: &[f32]) -> Vec<f32> {
    let mut out = v.to_vec();
    out.extend(v.windows(2).map(|w| (w[0] + w[1]) * 0.5));
    out
}

#[test]
fn bvh_matches_brute_force_on_axis_aligned_rays_over_stairs() {
    let mut rng = Rng::new(3);
    let (data, xs, ys, zs) = stairs();
    let mut cmp = Compare::new("axis-aligned rays over stairs", &data);
    let coords = [with_midpoints(&xs), with_midpoints(&ys), with_midpoints(&zs)];
    // Where rays along each axis start: outside both ends and at some of the
    // vertex coordinates (in the planes of the quads).
    let starts = |v: &[f32]| {
        let mut s = vec![v[0] - 1.0, v[v.len() - 1] + 1.0];
        s.extend(v.iter().step_by(5));
        s
    };
    const OTHER: [f32; 4] = [0.0, -0.0, 1e-30, -1e-30];
    for axis in 0..3 {
        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut points: Vec<(f32, f32)> = Vec::new();
        for &u in &coords[a1] {
            for &v in &coords[a2] {
                points.push((u, v));
            }
        }
        // Points along the quads' diagonals (shared edges), when this axis
        // is perpendicular to some quads: y for treads (x, z), x for risers (y, z).
        let diagonal = |p: &[f32], q: &[f32], rng: &mut Rng, points: &mut Vec<(f32, f32)>| {
            for w in p.windows(2) {
                for z in q.windows(2) {
                    for s in [0.25f32, 0.5, 0.75, rng.f64() as f32] {
                        points.push((w[0] + (w[1] - w[0]) * s, z[0] + (z[1] - z[0]) * s));
                        points.push((w[0] + (w[1] - w[0]) * s, z[1] + (z[0] - z[1]) * s));
                    }
                }
            }
        };
        match axis {
            0 => diagonal(&ys, &zs, &mut rng, &mut points),
            1 => {
                let mut zx = Vec::new();
                diagonal(&zs, &xs, &mut rng, &mut zx);
                points.extend(zx); // (z, x): a1 = z, a2 = x for the y axis
            }
            _ => {}
        }
        for &(u, v) in &points {
            for &s0 in &starts(&coords[axis]) {
                for sign in [1.0f32, -1.0] {
                    for variant in 0..2 {
                        let mut dir = [0.0f32; 3];
                        dir[axis] = sign;
                        if variant == 1 {
                            dir[a1] = rng.pick(&OTHER);
                            dir[a2] = rng.pick(&OTHER);
                        }
                        let mut o = [0.0f32; 3];
                        o[axis] = s0;
                        o[a1] = u;
                        o[a2] = v;
                        cmp.ray(Vec3::from(o), Vec3::from(dir), INF);
                    }
                }
            }
        }
    }
    cmp.finish();
}

/// Zero-thickness meshes in the plane y = 0: a grid with shared vertices, a
/// random soup, and a soup whose vertices have y = -0.0.
fn flat() -> (SceneData, Vec<f32>) {
    let mut rng = Rng::new(4);
    let grid: Vec<f32> = (0..=16).map(|i| i as f32 * 0.625 - 5.0).collect();
    let mut data = SceneData::default();
    let mut tris = Vec::new();
    for i in 0..16 {
        for k in 0..16 {
            let p = |a: usize, b: usize| Vec3::new(grid[a], 0.0, grid[b]);
            if (i + k) % 2 == 0 {
                tris.push(tri(p(i, k), p(i + 1, k), p(i + 1, k + 1)));
                tris.push(tri(p(i, k), p(i + 1, k + 1), p(i, k + 1)));
            } else {
                tris.push(tri(p(i, k), p(i + 1, k), p(i, k + 1)));
                tris.push(tri(p(i + 1, k), p(i + 1, k + 1), p(i, k + 1)));
            }
        }
    }
    add_mesh(&mut data, &tris);
    for y in [0.0f32, -0.0] {
        let tris: Vec<TriangleGpu> = (0..300)
            .map(|_| {
                let c = rng.in_box(6.0);
                let s = rng.log_range(0.01, 2.0);
                let mut p = [c + rng.unit() * s, c + rng.unit() * s, c + rng.unit() * s].map(f);
                for q in &mut p {
                    q.y = y;
                }
                tri(p[0], p[1], p[2])
            })
            .collect();
        add_mesh(&mut data, &tris);
    }
    (built(data), grid)
}

#[test]
fn bvh_matches_brute_force_on_a_flat_mesh() {
    let mut rng = Rng::new(5);
    let (data, grid) = flat();
    let mut cmp = Compare::new("flat mesh y = 0", &data);
    let grid = with_midpoints(&grid);
    let target = |rng: &mut Rng| {
        if rng.below(2) == 0 {
            Vec3::new(rng.pick(&grid), 0.0, rng.pick(&grid))
        } else {
            point_on(rng, &data.triangles)
        }
    };
    for _ in 0..3000 {
        // Along the plane, in it (y = +-0) or just off it (origins closer
        // to it than the triangle test resolves: the next test).
        let y = rng.pick(&[0.0f32, -0.0, 0.0, -0.0, 1e-30, -1e-30, 1e-7, -1e-7]);
        let dy = rng.pick(&[0.0f32, -0.0, 1e-30, -1e-30]);
        let o = if rng.below(2) == 0 { f(rng.in_box(7.0)) } else { target(&mut rng) };
        let h = DVec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0)).normalize();
        cmp.ray(Vec3::new(o.x, y, o.z), Vec3::new(h.x as f32, dy, h.z as f32), INF);
    }
    for _ in 0..3000 {
        // Crossing it, toward grid vertices and edges or points on the triangles.
        let o = rng.in_box(8.0);
        let o = if rng.below(4) == 0 { DVec3::new(o.x, rng.sign() * rng.log_range(1e-6, 1e-2), o.z) } else { o };
        cmp.ray_bounds(f(o), f((d(target(&mut rng)) - o).normalize()));
    }
    for _ in 0..2000 {
        // Perpendicular to it, exactly through grid coordinates.
        let t = target(&mut rng);
        let sy = rng.sign() as f32;
        let dir = Vec3::new(rng.pick(&[0.0, -0.0, 1e-30, -1e-30]), sy, rng.pick(&[0.0, -0.0, 1e-30, -1e-30]));
        cmp.ray_bounds(Vec3::new(t.x, -sy * rng.range(0.5, 5.0) as f32, t.z), dir);
    }
    cmp.finish();
}

/// Rays along the flat mesh from 1e-45 above or below it (the smallest
/// subnormal): the triangle test loses that offset in its shear, so it sees
/// an origin in the plane and reports hits at t within its rounding error
/// of 0 (~1e-8 here), also for rays leaving the plane, while the slab test
/// resolves the offset and culls those boxes (or enters them at a t that
/// differs by more than the tie rule can absorb). A disagreement between
/// two answers both within rounding error, for origins no closer to a
/// surface than glint ever starts a ray (offset_ray moves them 1.5e-5 off at
/// least): the criterion cannot be met here without an absolute slack in
/// the culling or an error bound on t (PBRT's deltaT, which however also
/// drops valid grazing hits, e.g. the one in
/// `the_traversal_keeps_a_box_whose_rounded_entry_is_just_past_the_limit`).
#[test]
#[ignore = "known limit: an origin 1e-45 off a plane can report t ~ 1e-8 (the shear loses the offset); glint never starts rays there (offset_ray moves them at least 256 ulps of their largest coordinate off)"]
fn bvh_matches_brute_force_on_a_flat_mesh_from_origins_within_rounding_of_it() {
    let mut rng = Rng::new(25);
    let (data, grid) = flat();
    let mut cmp = Compare::new("flat mesh y = 0, origins 1e-45 off it", &data);
    let grid = with_midpoints(&grid);
    for _ in 0..3000 {
        let y = rng.pick(&[1e-45f32, -1e-45]);
        let dy = rng.pick(&[0.0f32, -0.0, 1e-30, -1e-30]);
        let o = if rng.below(2) == 0 {
            Vec3::new(rng.pick(&grid), 0.0, rng.pick(&grid))
        } else {
            point_on(&mut rng, &data.triangles)
        };
        let h = DVec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0)).normalize();
        cmp.ray(Vec3::new(o.x, y, o.z), Vec3::new(h.x as f32, dy, h.z as f32), INF);
    }
    cmp.finish();
}

// ---------------------------------------------------------------------------
// 1b. Minimal reproductions of what the comparisons above found.

/// Found by the random soup (the one disagreement there): a collinear
/// triangle (its third vertex is the midpoint of an edge) and a ray passing
/// 33 units from it. On the f32 projected coordinates the edge functions are
/// u = v = 1.3e-5 and w = -2.6e-5 exactly (no hit), but u and v are
/// differences of products near 514 and round to 0, so the sign test
/// passes and the ray "hits" at the depth of p2. Woop et al. (2013)
/// recompute u, v, w in double precision when any of them is 0; the mirror
/// and intersect.wgsl do not. The BVH hides it here (the phantom point is
/// outside every box), brute force does not.
#[test]
fn hit_triangle_reports_no_phantom_hit_on_a_collinear_triangle() {
    let p = [
        Vec3::new(-19.169868, -7.18088, -3.6718163),
        Vec3::new(-19.143301, -7.1943803, -3.6705532),
        Vec3::new(-19.156584, -7.18763, -3.6711848),
    ];
    let r = Ray::new(Vec3::new(9.628756, -28.261326, 10.742591), Vec3::new(0.2390095, 0.33463237, -0.9115348));
    if let Some((t, b1, b2)) = hit_triangle(&r, p[0], p[1], p[2], INF) {
        let at = d(r.o) + d(r.d) * t as f64;
        let off = (closest_on_triangle(at, d(p[0]), d(p[1]), d(p[2])) - at).length();
        panic!("hit at t = {t} (barycentrics {b1}, {b2}), the point {at} is {off} from the triangle");
    }
}

/// Found over the stairs and the flat mesh: a ray lying exactly in a face
/// plane of a node box, with a zero direction component, misses the box
/// although a triangle on that face is hit (edges are inclusive): for that
/// slab (b - o) * inv is 0 * -1e30 = -0 (d = -0.0, o on the min face) or
/// 0 * 1e30 = 0 (d = +0.0, o on the max face), so the slab ends at t = 0.
/// A ray along a floor plane thus passes under the bottom edge of a wall
/// standing on it, and ties between triangles sharing an edge that lies in
/// a box face go to whichever box was not culled.
#[test]
fn a_ray_in_a_box_face_plane_hits_the_triangles_on_that_face() {
    // A riser at x = -2: bottom edge at y = -1 (the box's min y), top vertex
    // at y = -0.83 (its max y), z from -1.1 to -0.55.
    let t = tri(Vec3::new(-2.0, -1.0, -1.1), Vec3::new(-2.0, -0.83, -0.55), Vec3::new(-2.0, -1.0, -0.55));
    let mut data = SceneData::default();
    add_mesh(&mut data, &[t]);
    let data = built(data);
    let g = geometry(&data);
    let node = data.bvh[data.instances[0].index as usize];
    let mut wrong = Vec::new();
    for (o, dir) in [
        (Vec3::new(-3.0, -1.0, -0.8), Vec3::new(1.0, -0.0, 0.0)),
        (Vec3::new(-3.0, -0.83, -0.55), Vec3::new(1.0, 0.0, 0.0)),
        (Vec3::new(-3.0, -0.9, -0.55), Vec3::new(1.0, 0.0, 0.0)),
    ] {
        let r = Ray::new(o, dir);
        let brute = g.closest_brute(&r, INF);
        assert!(brute.is_some(), "the triangle test itself misses o {o:?} d {dir:?}");
        let (closest, any) = (g.closest(&r, INF), g.any(&r, INF));
        if closest != brute || !any {
            wrong.push(format!(
                "o {o:?} d {dir:?}: brute force {brute:?}, closest {closest:?}, any {any}; \
                 hit_box on the BLAS root [{:?}, {:?}]: {:?}",
                node.bmin,
                node.bmax,
                super::ray::hit_box(&r, node.bounds().min, node.bounds().max, INF)
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// A ray parallel to a slab: `slack` widens that slab to every t, so the
/// box is kept whether the origin lies between its planes or not (the
/// conservative answer), and the other axes decide the entry.
#[test]
fn a_ray_parallel_to_a_slab_keeps_the_box_on_either_side_of_it() {
    let (bmin, bmax) = (Vec3::ZERO, Vec3::ONE);
    for y in [0.0, 0.5, 1.0, 1.0 + 1e-6, -3.0, 1e6] {
        let r = Ray::new(Vec3::new(-2.0, y, 0.5), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(super::ray::hit_box(&r, bmin, bmax, INF), Some(2.0), "origin y = {y}");
    }
    // So far off that the slab's distances overflow to -inf: culled, which
    // is exact (a direction component under 1e-30 would enter past 1e60).
    let far_off = Ray::new(Vec3::new(-2.0, 1e30, 0.5), Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(super::ray::hit_box(&far_off, bmin, bmax, INF), None);
    let behind = Ray::new(Vec3::new(2.0, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(super::ray::hit_box(&behind, bmin, bmax, INF), None);
}

/// Found on the flat mesh: a box (the triangle's, which lies in the box's
/// face y = 0) is entered at t = 11.212806 after rounding, and the triangle
/// is hit at t = 11.212804. With tmax = 11.212805 in between, hit_box keeps
/// the box (its far bound gets Ize's slack) but the traversal's
/// `t_near > limit` check, which has none, drops it: `closest` and `any`
/// miss a hit inside (0, tmax). Against the best hit so far instead of tmax
/// the same makes closest return a farther hit than brute force.
#[test]
fn the_traversal_keeps_a_box_whose_rounded_entry_is_just_past_the_limit() {
    let mut data = SceneData::default();
    add_mesh(&mut data, &[tri(Vec3::new(3.125, 0.0, -1.875), Vec3::new(3.75, 0.0, -1.25), Vec3::new(3.125, 0.0, -1.25))]);
    let data = built(data);
    let g = geometry(&data);
    let r = Ray::new(Vec3::new(-6.880955, -0.00017891785, -6.190253), Vec3::new(0.91099787, 1.5956564e-5, 0.4124111));
    let tmax = 11.212805;
    let brute = g.closest_brute(&r, tmax);
    assert!(brute.is_some_and(|h| h.t < tmax));
    assert_eq!(g.closest(&r, tmax), brute, "closest");
    assert!(g.any(&r, tmax), "any");
}

/// Found on the flat mesh: the origin is 1e-45 below the plane y = 0 of the
/// triangle and the ray leaves the plane (d.y < 0): the plane is crossed at
/// t = -8e-16, behind the origin. hit_triangle loses the 1e-45 in the shear
/// (a.y - s.y a.z) and reports t = 7.4e-9 > 0; the slab test resolves it and
/// culls the box, so the BVH and brute force disagree. Such hits are within
/// the rounding error of t from 0; a bound on that error (PBRT's deltaT:
/// accept only t > deltaT) rejects them.
#[test]
#[ignore = "known limit: an origin 1e-45 off a plane can report t ~ 1e-8 (the shear loses the offset); glint never starts rays there (offset_ray moves them at least 256 ulps of their largest coordinate off)"]
fn hit_triangle_reports_no_hit_behind_an_origin_within_rounding_of_its_plane() {
    let p = [Vec3::new(1.6430417, -0.0, 3.0250278), Vec3::new(2.5107923, -0.0, 3.2195532), Vec3::new(3.6618335, -0.0, 2.1710413)];
    let r = Ray::new(Vec3::new(2.1875, -1e-45, 3.125), Vec3::new(-0.5469806, -1.7649993e-30, 0.8371453));
    assert_eq!(hit_triangle(&r, p[0], p[1], p[2], INF), None);
}

// ---------------------------------------------------------------------------
// 2. Watertightness.

/// A UV sphere: rings of `n_lon` shared vertices at `n_lat - 1` latitudes
/// plus the poles, computed in f64 and rounded to f32 once.
fn uv_sphere(c: DVec3, r: f64, n_lat: usize, n_lon: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    use std::f64::consts::{PI, TAU};
    let mut v = vec![f(c + DVec3::new(0.0, r, 0.0))];
    for i in 1..n_lat {
        let th = PI * i as f64 / n_lat as f64;
        for j in 0..n_lon {
            let ph = TAU * j as f64 / n_lon as f64;
            v.push(f(c + r * DVec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin())));
        }
    }
    v.push(f(c - DVec3::new(0.0, r, 0.0)));
    let south = (v.len() - 1) as u32;
    let ring = |i: usize, j: usize| (1 + (i - 1) * n_lon + j % n_lon) as u32;
    let mut t = Vec::new();
    for j in 0..n_lon {
        t.push([0, ring(1, j + 1), ring(1, j)]);
        for i in 1..n_lat - 1 {
            t.push([ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)]);
            t.push([ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)]);
        }
        t.push([south, ring(n_lat - 1, j), ring(n_lat - 1, j + 1)]);
    }
    (v, t)
}

/// The point of triangle abc closest to p (Ericson, Real-Time Collision
/// Detection 5.1.5), in f64.
fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Rays from outside a closed, finely tessellated sphere far from the
/// origin, aimed at points of its surface: random points on triangles,
/// vertices, points on shared edges, from steep to grazing. Every ray is
/// checked (in f64, on the f32 ray as traced) to pass strictly inside the
/// mesh's inscribed ball, so it must cross the surface: a miss is a crack.
fn watertight_sphere(seed: u64, centre: DVec3, radius: f64, rays: usize) -> (usize, usize, usize, f64) {
    let mut rng = Rng::new(seed);
    let (v, idx) = uv_sphere(centre, radius, 200, 200);
    // Two meshes (north and south), so rays cross BLAS boundaries too.
    let tris: Vec<TriangleGpu> = idx.iter().map(|t| tri(v[t[0] as usize], v[t[1] as usize], v[t[2] as usize])).collect();
    let mut data = SceneData::default();
    let (north, south): (Vec<_>, Vec<_>) = tris.iter().partition(|t| d(Vec3::from(t.p0)).y >= centre.y);
    add_mesh(&mut data, &north);
    add_mesh(&mut data, &south);
    let data = built(data);
    let g = geometry(&data);
    // The mesh lies between r_in and r_out from the centre.
    let r_in = tris
        .iter()
        .map(|t| {
            let [a, b, c] = corners(t).map(d);
            (closest_on_triangle(centre, a, b, c) - centre).length()
        })
        .fold(f64::INFINITY, f64::min);
    let r_out = v.iter().map(|p| (d(*p) - centre).length()).fold(0.0, f64::max);
    // Aim the rays' lines within this distance of the centre.
    let inner = r_in - 1e-4 * radius;
    eprintln!(
        "watertight: r = {radius}: {} triangles, inscribed {r_in:.6}, circumscribed {r_out:.6} (f32 spacing {})",
        tris.len(),
        ulp(centre.max_element() as f32)
    );
    let (mut closest_misses, mut any_misses, mut regenerated) = (0, 0, 0);
    let mut examples = Vec::new();
    let start = Instant::now();
    let mut n = 0;
    while n < rays {
        // The target on the surface.
        let t = &tris[rng.below(tris.len())];
        let [a, b, c] = corners(t).map(d);
        let target = match n % 3 {
            0 => {
                let (mut u, mut w) = (rng.f64(), rng.f64());
                if u + w > 1.0 {
                    (u, w) = (1.0 - u, 1.0 - w);
                }
                a + (b - a) * u + (c - a) * w
            }
            1 => [a, b, c][rng.below(3)],
            _ => {
                let (p, q) = [(a, b), (b, c), (c, a)][rng.below(3)];
                p.lerp(q, rng.f64())
            }
        };
        // The incoming direction at angle alpha to the tangent plane: its line
        // passes |target - centre| cos(alpha) from the centre, <= inner.
        let out = target - centre;
        let rt = out.length();
        let alpha_min = (inner / rt).min(1.0).acos();
        let alpha = match (n / 3) % 3 {
            0 => rng.range(alpha_min.sin(), 1.0).asin(),
            1 => alpha_min * rng.range(1.0, 1.5),
            _ => alpha_min * (1.0 + 1e-3),
        };
        let (e1, e2) = (out / rt).any_orthonormal_pair();
        let phi = rng.range(0.0, std::f64::consts::TAU);
        let dir = -(out / rt) * alpha.sin() + (e1 * phi.cos() + e2 * phi.sin()) * alpha.cos();
        let dist = rng.log_range(0.2, 50.0) * radius;
        let o = f(target - dir * dist);
        let dir = f((target - d(o)).normalize());
        // Check the f32 ray: outside, toward the centre, its line inside.
        let (od, dd) = (d(o), d(dir).normalize());
        let to_c = centre - od;
        let perp = (to_c - dd * to_c.dot(dd)).length();
        if !(to_c.length() > r_out && to_c.dot(dd) > 0.0 && perp < r_in) {
            regenerated += 1;
            continue;
        }
        n += 1;
        let r = Ray::new(o, dir);
        let hit = g.closest(&r, INF);
        let any = g.any(&r, INF);
        if hit.is_none() {
            closest_misses += 1;
            if examples.len() < 8 {
                let brute = g.closest_brute(&r, INF);
                examples.push(format!("o {o:?} d {dir:?} (kind {}, brute force {brute:?})", n % 3));
            }
        }
        any_misses += !any as usize;
    }
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "watertight: r = {radius}: {rays} rays, {closest_misses} closest misses, {any_misses} any misses, \
         {regenerated} rays regenerated, {:.2} us per ray (closest + any)",
        secs * 1e6 / rays as f64
    );
    for e in &examples {
        eprintln!("  miss: {e}");
    }
    (closest_misses, any_misses, rays, secs)
}

#[test]
fn tessellated_sphere_far_from_origin_is_watertight() {
    let centre = DVec3::new(1e5, -3e4, 7e4);
    let mut misses = 0;
    let mut total = 0;
    for (seed, radius) in [(6, 1.0), (7, 10.0)] {
        let (closest, any, rays, _) = watertight_sphere(seed, centre, radius, 500_000);
        misses += closest.max(any);
        total += rays;
    }
    let rate = misses as f64 / total as f64;
    assert!(rate <= 2e-5, "{misses} misses in {total} rays ({rate:e})");
}

// ---------------------------------------------------------------------------
// 3. Self-intersection.

/// A point whose components have random signs and magnitudes from 1e-6 to 1e6.
fn scattered_point(rng: &mut Rng) -> DVec3 {
    DVec3::new(
        rng.sign() * rng.log_range(1e-6, 1e6),
        rng.sign() * rng.log_range(1e-6, 1e6),
        rng.sign() * rng.log_range(1e-6, 1e6),
    )
}

#[derive(Default)]
struct SelfHits {
    surfaces: usize,
    skipped: usize,
    rays: usize,
    self_hits: usize,
    shadow_rays: usize,
    blocked: usize,
    /// Sphere hits from outside where dot(n, dir) > 0 all the same.
    sign_flips: usize,
    examples: Vec<String>,
}

impl SelfHits {
    /// A shadow ray from `o` to an unoccluded `light` (when one can be cast)
    /// must not be blocked.
    fn shadow_ray(&mut self, g: &Geometry, o: Vec3, light: Vec3, what: &str) {
        if let Some(blocked) = shadow_blocked(g, o, light) {
            self.shadow_rays += 1;
            if blocked {
                self.blocked += 1;
                self.fail(format!("{what}: the shadow ray from {o:?} to {light:?} is blocked"));
            }
        }
    }

    fn fail(&mut self, what: String) {
        if self.examples.len() < 10 {
            self.examples.push(what);
        }
    }

    fn report(&self, name: &str) {
        eprintln!(
            "{name}: {} surface points ({} skipped), {} rays from them, {} hit the surface again; \
             {} shadow rays, {} blocked; {} grazing hits from outside with dot(n, d) > 0",
            self.surfaces, self.skipped, self.rays, self.self_hits, self.shadow_rays, self.blocked, self.sign_flips
        );
        for e in &self.examples {
            eprintln!("  {e}");
        }
    }
}

/// From the offset point `o2` (surface normal `n`, facing the side the
/// first ray came from), rays into n's hemisphere, steep to grazing: none may
/// hit the same primitive (`hits` tests it alone, `g` the scene with it).
fn leave_surface(
    rng: &mut Rng,
    stats: &mut SelfHits,
    g: &Geometry,
    o2: Vec3,
    n: Vec3,
    hits: &dyn Fn(Vec3, Vec3) -> Option<f32>,
    what: &str,
) {
    let nd = d(n).normalize();
    for _ in 0..12 {
        let dir = f(rng.hemisphere(nd));
        if d(dir).dot(d(n)) <= 0.0 {
            continue;
        }
        stats.rays += 1;
        let closest = g.closest(&Ray::new(o2, dir), INF);
        if let Some(t) = hits(o2, dir) {
            stats.self_hits += 1;
            stats.fail(format!("{what}: from {o2:?} along {dir:?} (n {n:?}) hits itself at t = {t:e} (closest: {closest:?})"));
        } else if closest.is_some() {
            stats.self_hits += 1;
            stats.fail(format!("{what}: from {o2:?} along {dir:?}: the scene reports {closest:?}"));
        }
    }
}

/// A shadow ray as glint traces one (lights.wgsl `sample_light` and
/// `light_visible`): toward `light` from the offset point, to 1 - 1e-4 of
/// the distance. True when blocked.
fn shadow_blocked(g: &Geometry, o2: Vec3, light: Vec3) -> Option<bool> {
    let to = light - o2;
    let dist = to.length();
    if dist.is_nan() || dist <= 0.0 {
        return None;
    }
    Some(g.any(&Ray::new(o2, to / dist), dist * (1.0 - 1e-4)))
}

/// How the hit point is computed from a hit (each with its error bound,
/// src/bvh/offset.rs).
#[derive(Clone, Copy, PartialEq)]
enum HitPoint {
    /// p = o + t d.
    Distance,
    /// From the barycentrics (triangles) or projected onto the sphere, as
    /// Wächter and Binder recommend (Ray Tracing Gems ch. 6).
    Surface,
    /// What `closest_hit` in intersect.wgsl takes: the barycentric point,
    /// or o + t d where that is far tighter (the sphere's projection).
    Chosen,
}

/// A loose bound on the error of a sphere hit's t (the test's own: the
/// root's rounding relative to the distances involved).
fn sphere_t_error(o: Vec3, dir: Vec3, c: Vec3, r: f32, t: f32) -> f32 {
    use super::offset::gamma;
    gamma(16.0) * ((o - c).length() + r + t.abs()) / dir.length()
}

/// Triangles of every size from 1e-6 to 1e6 (but at least `min_ulps` f32
/// spacings of their position) with coordinates from 1e-6 to 1e6, hit from
/// 0.01 to `far` triangle sizes away.
fn self_intersection_triangles(seed: u64, cases: usize, min_ulps: f64, far: f64, hit_point: HitPoint) -> SelfHits {
    let mut rng = Rng::new(seed);
    let mut stats = SelfHits::default();
    while stats.surfaces < cases {
        let m = scattered_point(&mut rng);
        let lo = (min_ulps * ulp(m.abs().max_element() as f32) as f64).max(1e-6);
        let size = rng.log_range(lo, 1e6f64.max(2.0 * lo));
        let v = [m + rng.unit() * size, m + rng.unit() * size, m + rng.unit() * size].map(f);
        let [a, b, c] = v.map(d);
        let normal = (b - a).cross(c - a);
        if normal.length() < 0.05 * (b - a).length_squared().max((c - a).length_squared()) {
            continue; // a sliver
        }
        let normal = normal.normalize();
        let (mut u, mut w) = (rng.range(0.01, 0.99), rng.range(0.01, 0.99));
        if u + w > 0.99 {
            (u, w) = (0.99 - u, 0.99 - w);
        }
        let target = a + (b - a) * u.max(0.005) + (c - a) * w.max(0.005);
        let side = normal * rng.sign();
        let from = rng.hemisphere(side);
        let o = f(target + from * rng.log_range(0.01, far) * size);
        let dir = f((target - d(o)).normalize());
        let mut data = SceneData::default();
        add_mesh(&mut data, &[tri(v[0], v[1], v[2])]);
        let data = built(data);
        let g = geometry(&data);
        let Some(h) = g.closest(&Ray::new(o, dir), INF) else {
            stats.skipped += 1;
            continue;
        };
        stats.surfaces += 1;
        // As the renderer: the hit point, the geometric normal turned toward
        // the incoming ray, the offset origin.
        let ray = Ray::new(o, dir);
        let (_, b1, b2) = hit_triangle(&ray, v[0], v[1], v[2], INF).unwrap();
        let b0 = 1.0 - b1 - b2;
        let t_error = triangle_t_error(&ray, v[0], v[1], v[2]);
        let (p, error) = match hit_point {
            HitPoint::Distance => (o + h.t * dir, ray_point_error(o, dir, h.t, t_error)),
            HitPoint::Surface => (b0 * v[0] + b1 * v[1] + b2 * v[2], triangle_error([b0, b1, b2], v)),
            HitPoint::Chosen => triangle_hit(o, dir, h.t, b1, b2, v, t_error),
        };
        let mut n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        if n.dot(dir) > 0.0 {
            n = -n;
        }
        let o2 = offset_ray(p, n, error);
        let hits = |o: Vec3, dir: Vec3| hit_triangle(&Ray::new(o, dir), v[0], v[1], v[2], INF).map(|h| h.0);
        let what = format!("triangle {v:?}, hit from {o:?} along {dir:?} at {p:?}");
        leave_surface(&mut rng, &mut stats, &g, o2, n, &hits, &what);
        // Point lights on the lit side: nothing can block them.
        let facing = if normal.dot(d(n)) > 0.0 { normal } else { -normal };
        for _ in 0..4 {
            let light = f(d(p) + rng.cone(facing, 1e-2, 1.0) * rng.log_range(1e-3, 1e3) * size);
            if (d(light) - a).dot(facing) <= 1e-3 * (d(light) - d(p)).length() {
                continue;
            }
            stats.shadow_ray(&g, o2, light, &what);
        }
    }
    stats
}

/// Spheres of radius 1e-4 to 1e4 (but at least `min_ulps` f32 spacings of
/// their centre) centred at coordinates from 1e-6 to 1e6, hit from outside,
/// from 0.01 to `far` radii away.
fn self_intersection_spheres(seed: u64, cases: usize, min_ulps: f32, far: f64, hit_point: HitPoint) -> SelfHits {
    let mut rng = Rng::new(seed);
    let mut stats = SelfHits::default();
    while stats.surfaces < cases {
        let c = f(scattered_point(&mut rng));
        let r = rng.log_range(1e-4, 1e4) as f32;
        if r < min_ulps * ulp(c.abs().max_element()) {
            continue;
        }
        let (cd, rd) = (d(c), r as f64);
        let n0 = rng.unit();
        let target = cd + n0 * rd;
        let from = rng.hemisphere(n0);
        let o = f(target + from * rng.log_range(0.01, far) * rd);
        let dir = f((target - d(o)).normalize());
        // Outside by more than the f32 sphere test can resolve.
        if (d(o) - cd).length() <= rd + 1e-5 * rd + 8.0 * ulp(o.abs().max_element()) as f64 {
            continue;
        }
        let mut data = SceneData::default();
        add_sphere(&mut data, c, r);
        let data = built(data);
        let g = geometry(&data);
        let Some(h) = g.closest(&Ray::new(o, dir), INF) else {
            stats.skipped += 1;
            continue;
        };
        stats.surfaces += 1;
        let mut p = o + h.t * dir;
        let mut error = ray_point_error(o, dir, h.t, sphere_t_error(o, dir, c, r, h.t));
        if hit_point != HitPoint::Distance {
            p = c + (p - c) * (r / (p - c).length());
            error = sphere_error(c, r);
        }
        // As intersect.wgsl: n = (p - c) / r, turned toward the ray.
        // The ray came from outside, so the facing normal is the outward one.
        // (At grazing incidence the sign of dot(n, dir) that glint uses to
        // turn n toward the ray is not reliable; counted, not used.)
        let n = (p - c) / r;
        stats.sign_flips += (n.dot(dir) > 0.0) as usize;
        let o2 = offset_ray(p, n, error);
        let hits = |o: Vec3, dir: Vec3| hit_sphere(o, dir, c, r, 0.0, INF);
        let what = format!("sphere {c:?} r {r:?}, hit from {o:?} along {dir:?} at {p:?}");
        leave_surface(&mut rng, &mut stats, &g, o2, n, &hits, &what);
        for _ in 0..4 {
            let light = f(target + rng.cone(n0, 1e-2, 1.0) * rng.log_range(1e-3, 1e3) * rd);
            // Unoccluded: the segment stays outside the sphere (f64).
            let (a, b) = (d(o2), d(light));
            let s = ((cd - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            if (a + (b - a) * s - cd).length() <= rd * (1.0 + 1e-6) {
                continue;
            }
            stats.shadow_ray(&g, o2, light, &what);
        }
    }
    stats
}

/// The criterion as stated: the hit point (along the ray, from the
/// barycentrics, or as `closest_hit` picks between them), offset by its
/// error bound along the geometric normal turned toward the incoming ray
/// (src/bvh/offset.rs); then rays into n's hemisphere must never hit the
/// triangle again, and shadow rays to point lights on that side (tmax =
/// distance * (1 - 1e-4)) must never be blocked. Triangles of 1e-6 to 1e6
/// with coordinates from 1e-6 to 1e6 (at least 4096 f32 spacings of their
/// position: smaller ones snap to a grid too coarse for them), incoming
/// rays from 0.01 to 1000 triangle sizes away.
///
/// Before the error bounds (a fixed 256 ULPs of each coordinate, and a
/// scene-sized step near zero) o + t d did self-intersect here: its error
/// is a few spacings of |o| and of t, which exceed 256 spacings of |p|
/// when the ray starts far from p (a ground plane near y = 0 seen from
/// afar). Its bound says so, and the offset follows it.
#[test]
fn offset_origins_never_hit_their_own_triangle() {
    for (seed, hit_point, what) in [(8, HitPoint::Distance, "p = o + t d"), (18, HitPoint::Surface, "p from barycentrics"), (28, HitPoint::Chosen, "p as closest_hit picks it")] {
        let stats = self_intersection_triangles(seed, 20_000, 4096.0, 1000.0, hit_point);
        stats.report(&format!("self-intersection, triangles, {what}"));
        assert!(stats.self_hits == 0 && stats.blocked == 0, "{what}: see the report above");
    }
}

/// The same for spheres, from outside, new rays into the outward
/// hemisphere, radii down to 16 f32 spacings of the centre: the point
/// along the ray, and projected onto the sphere (c + (p - c) r / |p - c|,
/// what intersect.wgsl takes).
#[test]
fn offset_origins_never_hit_their_own_sphere() {
    for (seed, hit_point, what) in [(9, HitPoint::Distance, "p = o + t d"), (19, HitPoint::Surface, "p projected onto the sphere")] {
        let stats = self_intersection_spheres(seed, 20_000, 16.0, 1000.0, hit_point);
        stats.report(&format!("self-intersection, spheres, {what}"));
        assert!(stats.self_hits == 0 && stats.blocked == 0, "{what}: see the report above");
    }
}

// ---------------------------------------------------------------------------
// 4. Ray/sphere precision.

/// The nearer root of |o + t d - c| = r in f64 for the f32 inputs, or None.
fn sphere_root_f64(o: Vec3, dir: Vec3, c: Vec3, r: f32) -> Option<f64> {
    let (o, dir, c, r) = (d(o), d(dir), d(c), r as f64);
    let f = o - c;
    let a = dir.length_squared();
    let b = f.dot(dir);
    // The discriminant from the perpendicular distance, as in the f32 code.
    let l = f - dir * (b / a);
    let disc = a * (r * r - l.length_squared());
    if disc < 0.0 {
        return None;
    }
    let q = -(b + b.signum() * disc.sqrt());
    let (t0, t1) = ((f.length_squared() - r * r) / q, q / a);
    let (t0, t1) = (t0.min(t1), t0.max(t1));
    if t0 > 0.0 {
        Some(t0)
    } else if t1 > 0.0 {
        Some(t1)
    } else {
        None
    }
}

/// The textbook ray/sphere test in f32 (b^2 - c), for comparison.
fn hit_sphere_naive(o: Vec3, dir: Vec3, c: Vec3, r: f32) -> Option<f32> {
    let f = o - c;
    let b = f.dot(dir);
    let disc = b * b - (f.dot(f) - r * r);
    if disc < 0.0 {
        return None;
    }
    let t0 = -b - disc.sqrt();
    let t1 = -b + disc.sqrt();
    [t0, t1].into_iter().find(|t| *t > 0.0)
}

#[derive(Default, Debug)]
#[allow(dead_code)] // read through Debug
struct SpherePrecision {
    rays: usize,
    misses: usize,
    /// Largest |t - t_exact| in units of the f32 spacing at t_exact.
    max_ulps: f64,
    /// Largest | |o + t d - c| - r | / r with p in f64 from the f32 t.
    max_radial: f64,
    /// The same for the exact t rounded to f32: the best an f32 t can do.
    max_radial_rounded: f64,
    /// The same for the textbook formula (misses counted apart).
    max_radial_naive: f64,
    naive_misses: usize,
    /// Misses of rays within 4 f32 spacings (at the sphere's distance) of the
    /// silhouette, where the f32 ray data cannot decide, and the closest to
    /// the centre of those (over r).
    silhouette_misses: usize,
    min_rho_missed: f64,
    /// Hits where the exact root says miss.
    false_hits: usize,
}

/// Rays toward points within `spread` * r of the centre of spheres of radius
/// r at distance `dist` from `origin_at(c)` in random directions.
fn sphere_precision(seed: u64, r: f32, dist: f64, spread: f64, near: Option<f64>, rays: usize) -> SpherePrecision {
    let mut rng = Rng::new(seed);
    let mut out = SpherePrecision { min_rho_missed: f64::INFINITY, ..Default::default() };
    for _ in 0..rays {
        let c = f(rng.unit() * dist);
        // From the world origin, or from a point `near` radii from the sphere.
        let o = match near {
            None => Vec3::ZERO,
            Some(k) => f(d(c) + rng.unit() * (k * r as f64)),
        };
        let target = d(c) + rng.unit() * (rng.f64().cbrt() * spread * r as f64);
        let dir = f((target - d(o)).normalize());
        // How close to the silhouette the f32 ray passes: perpendicular
        // distance of the centre from its line, over r (f64).
        let (od, dd) = (d(o), d(dir).normalize());
        let rho = (d(c) - od - dd * (d(c) - od).dot(dd)).length() / r as f64;
        let Some(exact) = sphere_root_f64(o, dir, c, r) else {
            out.false_hits += hit_sphere(o, dir, c, r, 0.0, INF).is_some() as usize;
            continue;
        };
        out.rays += 1;
        let radial = |t: f64| ((d(o) + d(dir) * t - d(c)).length() - r as f64).abs() / r as f64;
        let mut data = SceneData::default();
        add_sphere(&mut data, c, r);
        let data = built(data);
        let hit = geometry(&data).closest(&Ray::new(o, dir), INF);
        assert_eq!(hit.map(|h| h.t), hit_sphere(o, dir, c, r, 0.0, INF), "closest and hit_sphere differ");
        match hit {
            None if rho <= 1.0 - 4.0 * ulp(dist as f32) as f64 / r as f64 => out.misses += 1,
            None => {
                out.silhouette_misses += 1;
                out.min_rho_missed = out.min_rho_missed.min(rho);
            }
            Some(h) => {
                let t = h.t as f64;
                out.max_ulps = out.max_ulps.max((t - exact).abs() / ulp(exact as f32) as f64);
                out.max_radial = out.max_radial.max(radial(t));
            }
        }
        out.max_radial_rounded = out.max_radial_rounded.max(radial(exact as f32 as f64));
        match hit_sphere_naive(o, dir, c, r) {
            None => out.naive_misses += 1,
            Some(t) => out.max_radial_naive = out.max_radial_naive.max(radial(t as f64)),
        }
    }
    out
}

/// Ray Tracing Gems ch. 7 (r = 1 at 1e5, r = 1e-3 at 1e3, rays from the
/// origin toward the centre's neighbourhood).
///
/// The criterion |(|p - c| - r)| / r < 1e-5 cannot be met by any f32 t here:
/// t ~ 1e5 has a spacing of 0.0078 (1e3: 6.1e-5), so even the exact distance
/// rounded to f32 puts p = o + t d (evaluated in f64) up to half that off the
/// surface: 3.9e-3 r (3.1e-2 r). (The f32 hit point is no better: its
/// coordinates have the same spacing.) What the precise formula can and does
/// deliver is a t within a few f32 spacings of the exact root (checked here),
/// every ray toward the inner 99 % of the disc hitting, where the textbook
/// formula misses or is off by orders of magnitude more; and the 1e-5
/// criterion itself for rays that start near the sphere (next test).
#[test]
fn ray_sphere_is_precise_far_from_the_origin() {
    for (seed, r, dist) in [(10, 1.0f32, 1e5), (11, 1e-3, 1e3)] {
        let s = sphere_precision(seed, r, dist, 0.99, None, 20_000);
        eprintln!("sphere r = {r} at {dist} from the ray origin: {s:?}");
        assert_eq!(s.misses, 0, "r = {r} at {dist}: rays clear of the silhouette missed");
        assert!(s.max_ulps <= 8.0, "r = {r} at {dist}: t off by {} f32 spacings", s.max_ulps);
        // The textbook formula, for contrast: misses and errors of order r.
        assert!(s.naive_misses > 0 || s.max_radial_naive > 100.0 * s.max_radial);
    }
}

/// The 1e-5 criterion where f32 can represent it: the same spheres (far from
/// the world origin) and ray origins 2 to 20 radii from them.
#[test]
fn ray_sphere_is_precise_for_nearby_origins_far_from_the_world_origin() {
    for (seed, r, dist) in [(12, 1.0f32, 1e5), (13, 1e-3, 1e3), (14, 1e4, 1e6), (15, 1e-4, 1.0)] {
        let s = sphere_precision(seed, r, dist, 0.99, Some(20.0), 20_000);
        eprintln!("sphere r = {r} at {dist}, rays from 20 r away: {s:?}");
        assert_eq!(s.misses, 0);
        assert!(s.max_ulps <= 8.0, "r = {r} at {dist}: t off by {} f32 spacings", s.max_ulps);
        assert!(s.max_radial < 1e-5, "r = {r} at {dist}: the hit is {} r off the surface", s.max_radial);
    }
}

// ---------------------------------------------------------------------------
// 5. NaN, Inf and zero rays; bounded stack.

/// A scene around the world origin: soups, spheres containing the origin,
/// and spheres elsewhere.
fn scene_around_origin(rng: &mut Rng) -> SceneData {
    let mut data = SceneData::default();
    for n in [1, 50, 400] {
        let tris: Vec<TriangleGpu> = (0..n)
            .map(|_| {
                let c = rng.in_box(2.0);
                let s = rng.log_range(0.05, 2.0);
                tri(f(c + rng.unit() * s), f(c + rng.unit() * s), f(c + rng.unit() * s))
            })
            .collect();
        add_mesh(&mut data, &tris);
    }
    add_sphere(&mut data, Vec3::ZERO, 0.5);
    add_sphere(&mut data, Vec3::new(0.1, -0.2, 0.05), 3.0);
    for _ in 0..5 {
        add_sphere(&mut data, f(rng.in_box(3.0)), 0.4);
    }
    built(data)
}

/// Every combination of `o_values` in the components of o and `d_values` in
/// those of d. A ray with a NaN or infinite component or an all-zero
/// direction must hit nothing (and nothing may panic); the others must
/// agree with brute force when `brute` is set.
fn bad_rays(g: &Geometry, o_values: &[f32], d_values: &[f32], brute: bool) -> (usize, usize, Vec<String>) {
    let (mut rays, mut bad_rays) = (0, 0);
    let mut wrong = Vec::new();
    let mut failures = std::collections::BTreeMap::<&str, usize>::new();
    let (no, nd) = (o_values.len(), d_values.len());
    for i in 0..no.pow(3) * nd.pow(3) {
        let (io, id) = (i % no.pow(3), i / no.pow(3));
        let o = Vec3::new(o_values[io % no], o_values[io / no % no], o_values[io / no / no]);
        let dir = Vec3::new(d_values[id % nd], d_values[id / nd % nd], d_values[id / nd / nd]);
        let bad = !o.is_finite() || !dir.is_finite() || dir == Vec3::ZERO;
        for tmax in [INF, 10.0] {
            let r = Ray::new(o, dir);
            let closest = g.closest(&r, tmax);
            let any = g.any(&r, tmax);
            rays += 1;
            bad_rays += bad as usize;
            if bad && (closest.is_some() || any) {
                *failures.entry(if o.is_finite() && dir.is_finite() { "d = 0" } else { "NaN or Inf" }).or_default() += 1;
                if wrong.len() < 10 {
                    wrong.push(format!("o {o:?} d {dir:?} tmax {tmax:?}: closest {closest:?}, any {any}"));
                }
            } else if !bad && brute {
                let b = g.closest_brute(&r, tmax);
                if (!same_hit(closest, b) || any != b.is_some()) && wrong.len() < 10 {
                    wrong.push(format!("o {o:?} d {dir:?} tmax {tmax:?}: closest {closest:?}, any {any}, brute force {b:?}"));
                }
            }
        }
    }
    if !failures.is_empty() {
        wrong.insert(0, format!("bad rays that hit something: {failures:?}"));
    }
    (rays, bad_rays, wrong)
}

const NAN_INF_ZERO: [f32; 6] = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.0, -0.0, 0.25];
/// The same with the largest finite value and the smallest subnormal.
const EXTREMES: [f32; 6] = [f32::NAN, f32::INFINITY, 0.0, 0.25, f32::MAX, -1e-45];

#[test]
fn nan_inf_and_zero_rays_hit_nothing() {
    let mut rng = Rng::new(16);
    let data = scene_around_origin(&mut rng);
    let g = geometry(&data);
    let mut wrong = Vec::new();
    for (o_values, d_values) in [(&NAN_INF_ZERO, &NAN_INF_ZERO), (&EXTREMES, &EXTREMES)] {
        let (rays, bad, w) = bad_rays(&g, o_values, d_values, true);
        eprintln!("NaN/Inf/zero: {rays} rays, {bad} with a NaN or Inf component or d = 0, {} wrong", w.len());
        wrong.extend(w);
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Rays with a zero direction from inside a sphere: the minimal case.
#[test]
fn a_zero_direction_inside_a_sphere_hits_nothing() {
    let mut data = SceneData::default();
    add_sphere(&mut data, Vec3::ZERO, 1.0);
    let data = built(data);
    let g = geometry(&data);
    for dir in [Vec3::ZERO, Vec3::new(-0.0, 0.0, -0.0)] {
        let r = Ray::new(Vec3::new(0.25, 0.0, 0.0), dir);
        assert_eq!(hit_sphere(r.o, r.d, Vec3::ZERO, 1.0, 0.0, INF), None, "hit_sphere, d = {dir:?}");
        assert_eq!(g.closest(&r, INF), None, "closest, d = {dir:?}");
        assert!(!g.any(&r, INF), "any, d = {dir:?}");
    }
}

/// 100k triangles at one spot (identical, and within a few f32 spacings):
/// a tree of identical boxes that every ray through the spot walks entirely.
/// No stack overrun, the same answers as brute force, and bad rays miss.
#[test]
fn a_hundred_thousand_triangles_at_one_spot() {
    let mut rng = Rng::new(17);
    let p = [Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.5, 2.0, 3.0), Vec3::new(1.0, 2.5, 3.1)];
    let mut data = SceneData::default();
    add_mesh(&mut data, &vec![tri(p[0], p[1], p[2]); 100_000]);
    let jitter = |v: Vec3, rng: &mut Rng| {
        Vec3::from(v.to_array().map(|x| f32::from_bits((x.to_bits() as i32 + rng.below(5) as i32 - 2) as u32)))
    };
    let tris: Vec<TriangleGpu> =
        (0..100_000).map(|_| tri(jitter(p[0], &mut rng), jitter(p[1], &mut rng), jitter(p[2], &mut rng))).collect();
    add_mesh(&mut data, &tris);
    let data = built(data);
    let depth = tree_depth(&data.bvh, &data.instances);
    eprintln!("100k triangles at one spot (twice): {} nodes, depth {depth}", data.bvh.len());
    assert!(depth < STACK, "depth {depth} exceeds the traversal stack of {STACK}");
    let mut cmp = Compare::new("100k triangles at one spot", &data);
    for _ in 0..200 {
        let target = d(p[0]).lerp(d(p[1]), rng.f64()).lerp(d(p[2]), rng.f64() * 0.9);
        let o = target + rng.unit() * rng.range(0.5, 10.0);
        cmp.ray(f(o), f((target - o).normalize()), INF);
    }
    cmp.finish();
    let (_, _, wrong) = bad_rays(&geometry(&data), &NAN_INF_ZERO, &NAN_INF_ZERO, false);
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Triangles graded in size by powers of 4 (4^-60 .. 4^60) made the plain
/// SAH builder peel off one per level: a BVH 66 deep, deeper than the
/// 64-entry traversal stack, so pushes were dropped. The builder now bounds
/// the depth (median splits once a subtree could not fit otherwise): the
/// tree fits the stack with the TLAS above it, and rays from next to a
/// small triangle out along +x (inside every box, so the stack grows by one
/// per level) find exactly what brute force finds.
#[test]
fn graded_meshes_build_trees_that_fit_the_traversal_stack() {
    let mut tris = Vec::new();
    for k in (-60..=60).rev() {
        let s = 4f64.powi(k);
        tris.push(tri(f(DVec3::new(s, 0.0, 0.0)), f(DVec3::new(2.0 * s, s, 0.0)), f(DVec3::new(2.0 * s, 0.0, s))));
    }
    let mut data = SceneData::default();
    add_mesh(&mut data, &tris);
    let data = built(data);
    let depth = tree_depth(&data.bvh, &data.instances);
    let mut rng = Rng::new(18);
    let mut cmp = Compare::new("graded mesh", &data);
    for k in (-60..=40).step_by(4) {
        let s = 4f64.powi(k);
        for _ in 0..4 {
            let o = DVec3::new(rng.range(0.2, 0.9), rng.range(0.01, 0.1), rng.range(0.01, 0.1)) * s;
            let dir = DVec3::new(1.0, rng.range(1e-4, 1e-2), rng.range(1e-4, 1e-2)).normalize();
            cmp.ray(f(o), f(dir), INF);
        }
    }
    eprintln!("{} triangles, depth {depth} (stack {STACK})", tris.len());
    assert!(depth as u32 <= BLAS_MAX_DEPTH + TLAS_MAX_DEPTH, "depth {depth}");
    assert!(depth < STACK);
    cmp.finish();
}

/// Boxes graded by powers of 2 along a diagonal: the unbounded SAH builder
/// peels one off per level; the bounded one stays within its limit.
#[test]
fn build_depth_is_bounded() {
    let bounds: Vec<Aabb> = (-120..120)
        .map(|k| Aabb { min: Vec3::splat(2f32.powi(k)), max: Vec3::splat(2f32.powi(k + 1)) })
        .collect();
    for max_depth in [8, 20, BLAS_MAX_DEPTH, u32::MAX] {
        let bvh = super::build_with_depth(&bounds, max_depth);
        let mut deepest = 0;
        let mut stack = vec![(0usize, 1u32)];
        let mut seen = 0;
        while let Some((i, d)) = stack.pop() {
            deepest = deepest.max(d);
            let n = bvh.nodes[i];
            if n.count > 0 {
                seen += n.count as usize;
            } else {
                stack.push((n.left_first as usize, d + 1));
                stack.push((n.left_first as usize + 1, d + 1));
            }
        }
        assert_eq!(seen, bounds.len());
        eprintln!("max {max_depth}: depth {deepest}");
        if max_depth == u32::MAX {
            assert!(deepest > BLAS_MAX_DEPTH, "the input should be deep without a bound: {deepest}");
        } else {
            assert!(deepest <= max_depth, "max {max_depth}: depth {deepest}");
        }
    }
}

/// Moving instances change how many nodes the TLAS needs (a sphere sliding
/// along x through a row of others takes 7 or 9 here). The node array must
/// keep its length and the BLAS roots their places, or the GPU, which
/// uploads arrays of unchanged length in place, would walk stale nodes.
#[test]
fn moving_instances_keep_the_node_array_in_place() {
    let mut rng = Rng::new(77);
    let mut data = random_soup(&mut rng, &[200, 50], 0);
    for k in 0..12 {
        add_sphere(&mut data, Vec3::new(k as f32 * 2.0, 0.0, 0.0), 0.5);
    }
    let mut bvh = SceneBvh::default();
    bvh.update(&mut data);
    let (len, instances) = (data.bvh.len(), data.instances.len());
    let roots: Vec<u32> = data.instances.iter().filter(|i| i.kind == INSTANCE_MESH).map(|i| i.index).collect();
    for step in 0..40 {
        data.spheres[0].center[0] = step as f32 * 0.6 - 2.0;
        data.spheres[5].center[1] = (step as f32 * 0.37).sin() * 3.0;
        bvh.update(&mut data);
        assert_eq!(data.bvh.len(), len, "step {step}: node count changed");
        assert_eq!(data.instances.len(), instances);
        let mut now: Vec<u32> = data.instances.iter().filter(|i| i.kind == INSTANCE_MESH).map(|i| i.index).collect();
        now.sort_unstable();
        let mut before = roots.clone();
        before.sort_unstable();
        assert_eq!(now, before, "step {step}: BLAS roots moved");
        let mut cmp = Compare::new("moving instances", &data);
        for _ in 0..200 {
            let o = rng.in_box(30.0);
            cmp.ray_bounds(f(o), f(rng.unit()));
        }
        cmp.finish();
    }
}
