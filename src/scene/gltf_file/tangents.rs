//! Per-vertex tangents for normal-mapped glTF primitives that carry none:
//! MikkTSpace (the glTF specification's choice, and what Blender bakes
//! normal textures against), so a normal texture baked with smoothly varying
//! tangents shows no seams at triangle edges.

use glam::{Vec2, Vec3, Vec4};

/// Triangles as MikkTSpace reads them: one face a triangle, its corners
/// given directly (MikkTSpace welds equal corners itself).
struct Corners<'a> {
    p: &'a [[Vec3; 3]],
    n: &'a [[Vec3; 3]],
    uv: &'a [[Vec2; 3]],
    out: Vec<[Vec4; 3]>,
}

impl bevy_mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.p.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.p[face][vert].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.n[face][vert].to_array()
    }

    // MikkTSpace's bitangent follows +v; glTF's v runs down the image and
    // its normal textures' +y points up it, so the tangents are made in
    // (u, 1 - v), as Blender's exporter makes them, and w then gives the
    // image's up direction as the glTF specification's
    // bitangent = cross(normal, tangent.xyz) * tangent.w.
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let t = self.uv[face][vert];
        [t.x, 1.0 - t.y]
    }

    fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
        // None (a degenerate face with no neighbour to borrow from) stays
        // zero: the shader then takes the triangle's own uv frame.
        if let Some(t) = t {
            self.out[face][vert] = Vec4::from_array(t.tangent_encoded());
        }
    }
}

/// MikkTSpace tangents (xyz unit, w the bitangent's sign) at the corners of
/// triangles with positions `p`, unit normals `n` and texture coordinates
/// `uv`; zero where none could be made.
pub(crate) fn generate(p: &[[Vec3; 3]], n: &[[Vec3; 3]], uv: &[[Vec2; 3]]) -> Vec<[Vec4; 3]> {
    let mut c = Corners { p, n, uv, out: vec![[Vec4::ZERO; 3]; p.len()] };
    // The error type has no values: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut c);
    c.out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit quad in the xy plane facing +z as two triangles, with the
    /// uvs `uv` at corners (-1,-1), (1,-1), (1,1), (-1,1).
    fn quad(uv: [Vec2; 4]) -> Vec<[Vec4; 3]> {
        let p = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0)];
        let tris = [[0, 1, 2], [0, 2, 3]];
        let pos: Vec<[Vec3; 3]> = tris.iter().map(|t| t.map(|i| p[i])).collect();
        let uvs: Vec<[Vec2; 3]> = tris.iter().map(|t| t.map(|i| uv[i])).collect();
        generate(&pos, &[[Vec3::Z; 3]; 2], &uvs)
    }

    #[test]
    fn tangents_follow_u_and_w_points_up_the_image() {
        // glTF's usual layout: u along +x, v down the image (v = 0 at the
        // top, y = 1). The bitangent cross(n, t) w must point up the
        // image, +y.
        let t = quad([Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.0)]);
        for c in t.iter().flatten() {
            assert!((c.truncate() - Vec3::X).length() < 1e-5 && c.w == 1.0, "{c}");
            assert!((Vec3::Z.cross(c.truncate()) * c.w - Vec3::Y).length() < 1e-5);
        }
        // The image mirrored left to right: u runs along -x, the image's
        // up is still +y, so w turns negative.
        let t = quad([Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0), Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0)]);
        for c in t.iter().flatten() {
            assert!((c.truncate() + Vec3::X).length() < 1e-5 && c.w == -1.0, "{c}");
            assert!((Vec3::Z.cross(c.truncate()) * c.w - Vec3::Y).length() < 1e-5);
        }
        // Turned a quarter: u runs along -y, v along -x (the image's up
        // along +x).
        let t = quad([Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.0), Vec2::new(0.0, 1.0)]);
        for c in t.iter().flatten() {
            assert!((c.truncate() + Vec3::Y).length() < 1e-5, "{c}");
            assert!((Vec3::Z.cross(c.truncate()) * c.w - Vec3::X).length() < 1e-5);
        }
    }

    #[test]
    fn shared_corners_get_one_smooth_tangent() {
        // Two quads meeting at a crease along x = 0 (a roof, normals
        // smoothed along the ridge): the ridge's corners share a tangent.
        let ridge = [Vec3::new(0.0, -1.0, 1.0), Vec3::new(0.0, 1.0, 1.0)];
        let (left, right) = ([Vec3::new(-1.0, -1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0)], [Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)]);
        let nl = Vec3::new(-1.0, 0.0, 1.0).normalize();
        let nr = Vec3::new(1.0, 0.0, 1.0).normalize();
        let p = vec![[left[0], ridge[0], ridge[1]], [left[0], ridge[1], left[1]], [ridge[0], right[0], right[1]], [ridge[0], right[1], ridge[1]]];
        let n = vec![[nl, Vec3::Z, Vec3::Z], [nl, Vec3::Z, nl], [Vec3::Z, nr, nr], [Vec3::Z, nr, Vec3::Z]];
        let uv = vec![
            [Vec2::new(0.0, 1.0), Vec2::new(0.5, 1.0), Vec2::new(0.5, 0.0)],
            [Vec2::new(0.0, 1.0), Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.0)],
            [Vec2::new(0.5, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0)],
            [Vec2::new(0.5, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.5, 0.0)],
        ];
        let t = generate(&p, &n, &uv);
        let ridge_tangents = [t[0][1], t[0][2], t[1][1], t[2][0], t[3][0], t[3][2]];
        for c in ridge_tangents {
            assert!((c - ridge_tangents[0]).length() < 1e-5, "{c} against {}", ridge_tangents[0]);
            assert!(c.truncate().dot(Vec3::Z).abs() < 1e-5 && (c.x - 1.0).abs() < 1e-5, "the ridge's tangent lies along it, across the normal: {c}");
        }
        // Away from the ridge each side's tangent runs down its own slope.
        assert!((t[0][0].truncate() - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-4, "{}", t[0][0]);
    }
}
