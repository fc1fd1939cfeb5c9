//! Triangles seen from one point: the camera for primary rays, a point
//! light for the shadow rays toward it (traced from the light). For rays
//! that all start at `o`, each edge of a triangle spans a plane with `o`,
//! and a ray's edge function is the dot product of its direction with that
//! plane's normal (the triple product of the direction and the edge's two
//! vertices relative to `o`). The engine computes the three normals per
//! triangle per origin on the CPU, in f64, once a frame
//! (`crate::scene::origins`); a ray then tests a triangle with three dot
//! products and a division instead of Woop's shear and permutation
//! (shaders/shared/origins.wgsl; the Cornell box's G-buffer pass took
//! about 0.75x the time).
//!
//! Watertight as Woop's test is: an edge's normal for the neighbour that
//! shares it is computed from the same two vertices in the other order,
//! and `cross` below is antisymmetric bit for bit, so the two triangles'
//! edge functions are exact negations: a ray through the shared edge hits
//! one of them, never neither. Precise far from the world origin too: the
//! vertices are taken relative to `o` exactly (f32 differences in f64).

use glam::{DVec3, Vec3};

/// a x b with each component a difference of two products, so
/// cross(b, a) == -cross(a, b) bit for bit (no fused operations, which
/// would round the two orders differently). Products of f32 differences
/// are exact in f64; only the subtraction rounds.
fn cross(a: DVec3, b: DVec3) -> DVec3 {
    DVec3::new(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)
}

/// The three texels origins.wgsl reads for triangle (p0, p1, p2) seen from
/// `o`: the normals of the planes through `o` and the edges opposite p0,
/// p1 and p2 (a ray's barycentric weights, unnormalised), and in the
/// first texel's w the triple product of the vertices relative to `o`
/// (t times the weights' sum).
pub fn origin_edges(p0: Vec3, p1: Vec3, p2: Vec3, o: Vec3) -> [[f32; 4]; 3] {
    let o = o.as_dvec3();
    let (a, b, c) = (p0.as_dvec3() - o, p1.as_dvec3() - o, p2.as_dvec3() - o);
    let n0 = cross(b, c);
    let n1 = cross(c, a);
    let n2 = cross(a, b);
    let volume = a.dot(n0);
    let texel = |n: DVec3, w: f64| [n.x as f32, n.y as f32, n.z as f32, w as f32];
    [texel(n0, volume), texel(n1, 0.0), texel(n2, 0.0)]
}

/// The Rust mirror of `hit_from_origin` in origins.wgsl: the ray from the
/// edges' origin along `d` (any length) against the triangle; (t, b1, b2)
/// with t in (0, tmax) in units of `d`, or None. Edges are inclusive.
pub fn hit_from_origin(e: &[[f32; 4]; 3], d: Vec3, tmax: f32) -> Option<(f32, f32, f32)> {
    let edge = |i: usize| d.dot(Vec3::new(e[i][0], e[i][1], e[i][2]));
    let (u, v, w) = (edge(0), edge(1), edge(2));
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 || det.is_nan() {
        return None;
    }
    let inv = 1.0 / det;
    let t = e[0][3] * inv;
    if !(t > 0.0 && t < tmax) {
        return None;
    }
    Some((t, v * inv, w * inv))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::ray::{hit_triangle, Ray};

    /// A small deterministic generator (xorshift) for the tests' rays.
    struct Rand(u64);
    impl Rand {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
        fn dir(&mut self) -> Vec3 {
            let z = 1.0 - 2.0 * self.next();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f32::consts::TAU * self.next();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        }
    }

    #[test]
    fn a_shared_edge_has_exactly_negated_normals() {
        let o = Vec3::new(0.3, -0.7, 5.1);
        let (p, q) = (Vec3::new(-1.0, 0.25, 0.1), Vec3::new(0.9, -0.4, -0.3));
        // (a, p, q) and (b, q, p) share the edge p-q in opposite order.
        let ea = origin_edges(Vec3::new(0.1, 1.0, 0.2), p, q, o);
        let eb = origin_edges(Vec3::new(0.2, -1.3, 0.0), q, p, o);
        // Edge p-q is opposite the first vertex in both.
        for k in 0..3 {
            assert_eq!(ea[0][k].to_bits(), (-eb[0][k]).to_bits());
        }
    }

    #[test]
    fn hits_agree_with_the_watertight_test() {
        let mut rng = Rand(0x9e37_79b9_7f4a_7c15);
        let o = Vec3::new(0.2, 0.1, 3.4);
        let (mut hits, mut differ) = (0, 0);
        for _ in 0..200 {
            let v = [0; 3].map(|_| Vec3::new(rng.next(), rng.next(), rng.next()) * 2.0 - 1.0);
            let e = origin_edges(v[0], v[1], v[2], o);
            for _ in 0..200 {
                let d = (Vec3::new(rng.next(), rng.next(), rng.next()) * 2.0 - 1.0 - o).normalize();
                let woop = hit_triangle(&Ray::new(o, d), v[0], v[1], v[2], 1e30);
                let ours = hit_from_origin(&e, d, 1e30);
                match (woop, ours) {
                    (Some(a), Some(b)) => {
                        hits += 1;
                        assert!((a.0 - b.0).abs() <= 1e-5 * a.0, "t {} vs {}", a.0, b.0);
                        assert!((a.1 - b.1).abs() < 1e-4 && (a.2 - b.2).abs() < 1e-4, "{a:?} vs {b:?}");
                    }
                    (None, None) => {}
                    // Rounding may differ on a ray that grazes an edge.
                    (a, b) => {
                        let bary = a.or(b).map(|h| h.1.min(h.2).min(1.0 - h.1 - h.2)).unwrap_or(1.0);
                        assert!(bary.abs() < 1e-5, "{a:?} vs {b:?}");
                        differ += 1;
                    }
                }
            }
        }
        assert!(hits > 1000, "{hits} hits");
        assert!(differ <= 2, "{differ} edge rays differ");
    }

    #[test]
    fn a_far_closed_mesh_is_watertight_from_inside() {
        // An octahedron at Embree's watertight test location, its vertices
        // the f32 they round to; rays from its centre in every direction,
        // and rays through each vertex and along each edge's midpoint.
        let c = DVec3::new(148376.0, 1234.0, -223423.0);
        let r = 2.0;
        let v: Vec<Vec3> = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z].iter().map(|&a| (c + a * r).as_vec3()).collect();
        let faces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
        let o = c.as_vec3();
        let tables: Vec<_> = faces.iter().map(|f| origin_edges(v[f[0]], v[f[1]], v[f[2]], o)).collect();
        let mut rng = Rand(12345);
        let mut dirs: Vec<Vec3> = (0..100_000).map(|_| rng.dir()).collect();
        dirs.extend(v.iter().map(|&p| p - o));
        for f in faces {
            for k in 0..3 {
                dirs.push((v[f[k]] + v[f[(k + 1) % 3]]) * 0.5 - o);
            }
        }
        for d in dirs {
            let hit = tables.iter().filter_map(|e| hit_from_origin(e, d, f32::MAX)).next();
            let t = hit.map(|h| h.0 * d.length());
            assert!(t.is_some_and(|t| t > 0.5 * r as f32 && t < 1.01 * r as f32), "{d:?}: {t:?}");
        }
    }

    #[test]
    fn degenerate_rays_and_triangles_miss() {
        let o = Vec3::ZERO;
        let e = origin_edges(Vec3::new(-1.0, -1.0, -2.0), Vec3::new(1.0, -1.0, -2.0), Vec3::new(0.0, 1.0, -2.0), o);
        assert!(hit_from_origin(&e, Vec3::NEG_Z, 10.0).is_some());
        assert!(hit_from_origin(&e, Vec3::NEG_Z, 2.0).is_none(), "t must be under tmax");
        assert!(hit_from_origin(&e, Vec3::Z, 10.0).is_none(), "behind the origin");
        assert!(hit_from_origin(&e, Vec3::ZERO, 10.0).is_none());
        assert!(hit_from_origin(&e, Vec3::splat(f32::NAN), 10.0).is_none());
        // A triangle seen edge-on (its plane through the origin).
        let flat = origin_edges(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, -1.0), Vec3::new(0.0, 0.0, -3.0), o);
        assert!(hit_from_origin(&flat, Vec3::NEG_Z, 10.0).is_none());
        // A collapsed triangle.
        let p = Vec3::new(0.0, 0.0, -2.0);
        assert!(hit_from_origin(&origin_edges(p, p, p, o), Vec3::NEG_Z, 10.0).is_none());
    }
}
