//! Direction <-> texel maps for probe textures.
//!
//! Hemisphere maps (the thesis, chapter 3): a point of the unit square goes
//! to the unit disk by Shirley and Chiu's concentric map (area preserving,
//! continuous, low distortion), and the disk to the hemisphere z >= 0 by
//! the equal-area lift (x, y) -> (x s, y s, 1 - r^2), s = sqrt(2 - r^2).
//! Equal areas on the square are equal solid angles, so S x S buckets
//! share the hemisphere evenly. A probe keeps two maps, z >= 0 and z < 0
//! (mirrored in z).
//!
//! Octahedral maps (DDGI): the sphere projected onto the octahedron
//! |x| + |y| + |z| = 1 and unfolded onto the square [-1, 1]^2, the lower
//! half folded over the diagonals.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Shirley-Chiu: the square [-1, 1]^2 onto the unit disk.
pub fn square_to_disk(p: Vec2) -> Vec2 {
    let (a, b) = (p.x, p.y);
    if a == 0.0 && b == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if a.abs() > b.abs() { (a, FRAC_PI_4 * (b / a)) } else { (b, FRAC_PI_2 - FRAC_PI_4 * (a / b)) };
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// The inverse of `square_to_disk`.
pub fn disk_to_square(d: Vec2) -> Vec2 {
    let r = d.length();
    if r == 0.0 {
        return Vec2::ZERO;
    }
    // phi in [-pi/4, 7pi/4): one octant pair per side of the square.
    let mut phi = d.y.atan2(d.x);
    if phi < -FRAC_PI_4 {
        phi += 2.0 * PI;
    }
    if phi < FRAC_PI_4 {
        Vec2::new(r, phi * r / FRAC_PI_4)
    } else if phi < 3.0 * FRAC_PI_4 {
        Vec2::new(-(phi - FRAC_PI_2) * r / FRAC_PI_4, r)
    } else if phi < 5.0 * FRAC_PI_4 {
        Vec2::new(-r, -(phi - PI) * r / FRAC_PI_4)
    } else {
        Vec2::new((phi - 3.0 * FRAC_PI_2) * r / FRAC_PI_4, -r)
    }
}

/// A point of the unit square [0, 1]^2 onto the hemisphere z >= 0, with
/// equal area.
pub fn square_to_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_disk(u * 2.0 - Vec2::ONE);
    let r2 = d.length_squared().min(1.0);
    let s = (2.0 - r2).sqrt();
    Vec3::new(d.x * s, d.y * s, 1.0 - r2).normalize()
}

/// The inverse of `square_to_hemisphere` for a unit direction with z >= 0
/// (a direction below the horizon is mirrored: its |z| is used).
pub fn hemisphere_to_square(d: Vec3) -> Vec2 {
    // 1 - r^2 = z, so r^2 = 1 - z and the disk point is (x, y) / s.
    let r2 = (1.0 - d.z.abs()).clamp(0.0, 1.0);
    let s = (2.0 - r2).sqrt();
    let disk = Vec2::new(d.x, d.y) / s;
    // Keep the radius exact (x and y carry rounding).
    let len = disk.length();
    let disk = if len > 0.0 { disk * (r2.sqrt() / len) } else { disk };
    (disk_to_square(disk) + Vec2::ONE) * 0.5
}

/// The bucket of direction `d` in a probe's two S x S hemisphere maps:
/// (upper map, column, row).
pub fn hemisphere_bucket(d: Vec3, s: u32) -> (bool, u32, u32) {
    let u = hemisphere_to_square(d);
    let cell = |x: f32| ((x * s as f32) as u32).min(s.saturating_sub(1));
    (d.z >= 0.0, cell(u.x), cell(u.y))
}

/// The direction at the centre of a bucket (the inverse of
/// `hemisphere_bucket`).
pub fn bucket_direction(upper: bool, i: u32, j: u32, s: u32) -> Vec3 {
    let d = square_to_hemisphere(Vec2::new((i as f32 + 0.5) / s as f32, (j as f32 + 0.5) / s as f32));
    if upper { d } else { Vec3::new(d.x, d.y, -d.z) }
}

/// +1 or -1 (never 0): which side of an axis the octahedron folds to.
fn sign_not_zero(v: Vec2) -> Vec2 {
    Vec2::new(if v.x >= 0.0 { 1.0 } else { -1.0 }, if v.y >= 0.0 { 1.0 } else { -1.0 })
}

/// A unit direction onto the octahedral square [-1, 1]^2.
pub fn oct_encode(d: Vec3) -> Vec2 {
    let p = Vec2::new(d.x, d.y) / (d.x.abs() + d.y.abs() + d.z.abs());
    if d.z < 0.0 {
        (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign_not_zero(p)
    } else {
        p
    }
}

/// The inverse of `oct_encode` (unit length).
pub fn oct_decode(e: Vec2) -> Vec3 {
    let mut v = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
    if v.z < 0.0 {
        let folded = (Vec2::ONE - Vec2::new(v.y.abs(), v.x.abs())) * sign_not_zero(Vec2::new(v.x, v.y));
        v.x = folded.x;
        v.y = folded.y;
    }
    v.normalize()
}

/// The texel of direction `d` in an n x n octahedral map (no border).
pub fn oct_texel(d: Vec3, n: u32) -> (u32, u32) {
    let u = (oct_encode(d) + Vec2::ONE) * 0.5;
    let cell = |x: f32| ((x * n as f32) as u32).min(n.saturating_sub(1));
    (cell(u.x), cell(u.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points of the square on a grid with the centre, corners, edges and
    /// diagonals on it.
    fn grid(n: usize) -> Vec<Vec2> {
        let mut v = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                v.push(Vec2::new(i as f32 / n as f32, j as f32 / n as f32));
            }
        }
        v
    }

    #[test]
    fn concentric_map_round_trips_everywhere() {
        // 40 divides evenly: centre, corners, axes and diagonals included.
        for u in grid(40) {
            let p = u * 2.0 - Vec2::ONE;
            let d = square_to_disk(p);
            assert!(d.length() <= 1.0 + 1e-6, "{p} -> {d}");
            let back = disk_to_square(d);
            assert!((back - p).abs().max_element() < 1e-5, "{p} -> {d} -> {back}");
        }
    }

    #[test]
    fn hemisphere_map_round_trips_and_is_equal_area() {
        for u in grid(40) {
            let d = square_to_hemisphere(u);
            assert!((d.length() - 1.0).abs() < 1e-5 && d.z >= 0.0, "{u} -> {d}");
            let back = hemisphere_to_square(d);
            // The square's rim is one circle on the hemisphere's rim: its
            // points come back on the rim of the square, not necessarily
            // where they started when two rim points share a direction.
            assert!((back - u).abs().max_element() < 1e-5 || d.z < 1e-6, "{u} -> {d} -> {back}");
        }
        // Buckets are cells of the square: a uniform grid of the square,
        // mapped to the hemisphere and back, fills every bucket of a 5 x 5
        // map equally (the round trip lands each point in its own cell).
        let s = 5;
        let mut counts = vec![0u32; (s * s) as usize];
        let n = 500;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (upper, a, b) = hemisphere_bucket(square_to_hemisphere(u), s);
                assert!(upper);
                counts[(b * s + a) as usize] += 1;
            }
        }
        let want = (n * n) as u32 / (s * s);
        assert!(counts.iter().all(|&c| c == want), "{counts:?}");
        // Equal area: the solid angle of each bucket by quasi-Monte Carlo
        // over the hemisphere (z uniform is uniform in solid angle) is
        // 2 pi / 25 within 3%.
        let mut hits = vec![0u32; (s * s) as usize];
        let m = 200_000u32;
        for k in 0..m {
            let z = (k as f32 + 0.5) / m as f32;
            let phi = (k as f32 * 0.618_034).fract() * 2.0 * PI;
            let r = (1.0 - z * z).sqrt();
            let (_, a, b) = hemisphere_bucket(Vec3::new(r * phi.cos(), r * phi.sin(), z), s);
            hits[(b * s + a) as usize] += 1;
        }
        let mean = m as f32 / (s * s) as f32;
        assert!(hits.iter().all(|&h| (h as f32 / mean - 1.0).abs() < 0.03), "{hits:?}");
    }

    #[test]
    fn buckets_and_their_directions_agree() {
        let s = 7;
        for upper in [true, false] {
            for i in 0..s {
                for j in 0..s {
                    let d = bucket_direction(upper, i, j, s);
                    assert_eq!(hemisphere_bucket(d, s), (upper, i, j), "{d}");
                }
            }
        }
    }

    fn directions() -> Vec<Vec3> {
        let mut v = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        for x in [-1.0f32, 0.0, 1.0] {
            for y in [-1.0f32, 0.0, 1.0] {
                for z in [-1.0f32, 0.0, 1.0] {
                    if x != 0.0 || y != 0.0 || z != 0.0 {
                        v.push(Vec3::new(x, y, z).normalize());
                    }
                }
            }
        }
        for k in 0..2000 {
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / 2000.0;
            let phi = k as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            v.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        v
    }

    #[test]
    fn octahedral_map_round_trips() {
        for d in directions() {
            let e = oct_encode(d);
            assert!(e.abs().max_element() <= 1.0 + 1e-6, "{d} -> {e}");
            let back = oct_decode(e);
            assert!((back - d).abs().max_element() < 1e-5, "{d} -> {e} -> {back}");
        }
        for u in grid(40) {
            let e = u * 2.0 - Vec2::ONE;
            let d = oct_decode(e);
            let again = oct_encode(d);
            // The square's outer edge is folded onto itself: a point there
            // is the same direction as its mirror image (the four corners
            // are all -z).
            let same = (again - e).abs().max_element() < 1e-5;
            let mirrored = e.abs().max_element() > 1.0 - 1e-6 && (again.abs() - e.abs()).abs().max_element() < 1e-5;
            assert!(same || mirrored, "{e} -> {d} -> {again}");
        }
    }

    #[test]
    fn directions_either_side_of_a_seam_land_in_neighbouring_texels() {
        let n = 8;
        let eps = 1e-4;
        // Hemisphere maps: across the diagonal seams of the concentric
        // map, near its centre and along its axes.
        for (a, b) in [(0.3f32, 0.3f32), (-0.5, 0.5), (0.0, 0.7), (0.7, 0.0)] {
            let p = Vec2::new(a, b);
            let t = Vec2::new(-b, a).normalize_or_zero() * eps;
            let (d0, d1) = (square_to_hemisphere((p - t + Vec2::ONE) * 0.5), square_to_hemisphere((p + t + Vec2::ONE) * 0.5));
            let (_, i0, j0) = hemisphere_bucket(d0, n);
            let (_, i1, j1) = hemisphere_bucket(d1, n);
            assert!(i0.abs_diff(i1) <= 1 && j0.abs_diff(j1) <= 1, "{p}: ({i0},{j0}) vs ({i1},{j1})");
        }
        // Octahedral: across the equator (the fold) and the axes.
        for d in [Vec3::new(1.0, 0.3, 0.0), Vec3::new(-0.2, 1.0, 0.0), Vec3::new(0.5, 0.0, 0.5), Vec3::new(0.0, 0.5, -0.5)] {
            let d = d.normalize();
            let side = if d.z == 0.0 { Vec3::Z } else { d.cross(Vec3::Z).normalize() };
            let (a, b) = (oct_texel((d + side * eps).normalize(), n), oct_texel((d - side * eps).normalize(), n));
            // Across the fold the neighbour is the mirrored texel of the
            // other half: adjacent in the unfolded map's wrap-around.
            let wrap = |x: u32, y: u32| x.abs_diff(y) <= 1 || x + y == n - 1;
            assert!(wrap(a.0, b.0) && wrap(a.1, b.1), "{d}: {a:?} vs {b:?}");
        }
    }
}
