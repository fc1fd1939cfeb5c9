//! A glTF mesh's primitives as triangles: each accessor checked (type,
//! count, range in its buffer, finite values) before it is read, strips and
//! fans unrolled, flat normals where a primitive has none, MikkTSpace
//! tangents where a normal-mapped one has none.

use glam::{Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

/// One triangle of a glTF mesh in the mesh's space. `material` is the
/// glTF material index, None for the default material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GltfTriangle {
    pub p: [Vec3; 3],
    pub n: [Vec3; 3],
    /// TEXCOORD_0 at the vertices (zero where the primitive has none).
    pub uv: [Vec2; 3],
    /// Tangents (xyz unit, w the bitangent's sign) of normal-mapped
    /// primitives, the file's TANGENT or MikkTSpace's; zero elsewhere.
    pub tangent: [Vec4; 3],
    /// COLOR_0's red, green and blue (one where the primitive has none).
    pub color: [Vec3; 3],
    pub material: Option<usize>,
}

/// The triangles of `mesh`; `buffers` are the file's buffer bytes.
pub(crate) fn triangles(mesh: &gltf::Mesh, buffers: &[Vec<u8>]) -> Result<Vec<GltfTriangle>, String> {
    let mut out = Vec::new();
    for prim in mesh.primitives() {
        let at = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
        let mode = prim.mode();
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            return Err(format!("{at}.mode: {mode:?} ({}); glint renders triangles, triangle strips and fans only", mode.as_gl_enum()));
        }
        let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let position = prim.get(&gltf::Semantic::Positions).ok_or_else(|| format!("{at}.attributes: no POSITION"))?;
        let pos_at = format!("{at}.attributes.POSITION");
        check(&position, &[Dimensions::Vec3], &[DataType::F32], buffers, &pos_at)?;
        let p: Vec<Vec3> = reader.read_positions().ok_or_else(|| unreadable(&pos_at))?.map(Vec3::from_array).collect();
        if let Some(k) = p.iter().position(|v| !v.is_finite()) {
            return Err(format!("{pos_at}: vertex {k} is not finite ({:?})", p[k].to_array()));
        }
        let normals = match prim.get(&gltf::Semantic::Normals) {
            None => None,
            Some(acc) => {
                let n_at = format!("{at}.attributes.NORMAL");
                check(&acc, &[Dimensions::Vec3], &[DataType::F32], buffers, &n_at)?;
                let n = per_vertex(reader.read_normals().ok_or_else(|| unreadable(&n_at))?.collect(), p.len(), &n_at, ("normal", "normals"))?;
                Some(n.into_iter().map(Vec3::from_array).collect::<Vec<_>>())
            }
        };
        let uvs = match prim.get(&gltf::Semantic::TexCoords(0)) {
            None => None,
            Some(acc) => {
                let t_at = format!("{at}.attributes.TEXCOORD_0");
                check(&acc, &[Dimensions::Vec2], &[DataType::F32, DataType::U8, DataType::U16], buffers, &t_at)?;
                if acc.data_type() != DataType::F32 && !acc.normalized() {
                    return Err(format!("{t_at}: integer texture coordinates must be normalized (glTF)"));
                }
                let t = reader.read_tex_coords(0).ok_or_else(|| unreadable(&t_at))?.into_f32().collect();
                let t = per_vertex(t, p.len(), &t_at, ("coordinate", "texture coordinates"))?;
                Some(t.into_iter().map(Vec2::from_array).collect::<Vec<_>>())
            }
        };
        // glTF: tangents are ignored where normals are generated.
        let normal_mapped = prim.material().normal_texture().is_some() && uvs.is_some();
        let tangents = if normal_mapped && normals.is_some() { read_tangents(&prim, &reader, buffers, &at, p.len())? } else { None };
        let colors = read_colors(&prim, &reader, buffers, &at, p.len())?;
        let indices: Vec<u32> = match prim.indices() {
            None => (0..p.len() as u32).collect(),
            Some(acc) => {
                let i_at = format!("{at}.indices");
                check(&acc, &[Dimensions::Scalar], &[DataType::U8, DataType::U16, DataType::U32], buffers, &i_at)?;
                let idx: Vec<u32> = reader.read_indices().ok_or_else(|| unreadable(&i_at))?.into_u32().collect();
                if let Some(k) = idx.iter().position(|&i| i as usize >= p.len()) {
                    return Err(format!("{i_at}: index {k} is {}, beyond the {} vertices of POSITION", idx[k], p.len()));
                }
                idx
            }
        };
        let material = prim.material().index();
        let first = out.len();
        for [a, b, c] in unroll(mode, &indices) {
            let (a, b, c) = (a as usize, b as usize, c as usize);
            let pt = [p[a], p[b], p[c]];
            let flat = (pt[1] - pt[0]).cross(pt[2] - pt[0]).normalize_or_zero();
            let n = match &normals {
                // A zero normal in the file falls back to the face's.
                Some(n) => [n[a], n[b], n[c]].map(|v| v.try_normalize().unwrap_or(flat)),
                None => [flat; 3],
            };
            let uv = uvs.as_ref().map_or([Vec2::ZERO; 3], |t| [t[a], t[b], t[c]]);
            let tangent = tangents.as_ref().map_or([Vec4::ZERO; 3], |t| [t[a], t[b], t[c]]);
            let color = colors.as_ref().map_or([Vec3::ONE; 3], |col| [col[a], col[b], col[c]]);
            out.push(GltfTriangle { p: pt, n, uv, tangent, color, material });
        }
        if normal_mapped && tangents.is_none() {
            let tris = &mut out[first..];
            let (p, n, uv): (Vec<_>, Vec<_>, Vec<_>) = tris.iter().map(|t| (t.p, t.n, t.uv)).collect();
            for (t, made) in tris.iter_mut().zip(super::tangents::generate(&p, &n, &uv)) {
                t.tangent = made;
            }
        }
    }
    Ok(out)
}

/// A primitive's TANGENT (None without one), checked: VEC4 floats, one a
/// vertex, finite, w of +1 or -1 (its sign taken), xyz normalised (a zero
/// one stays zero: the shader then takes the triangle's uv frame).
fn read_tangents<'a, 's, F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>>(prim: &gltf::Primitive, reader: &gltf::mesh::Reader<'a, 's, F>, buffers: &[Vec<u8>], at: &str, vertices: usize) -> Result<Option<Vec<Vec4>>, String> {
    let Some(acc) = prim.get(&gltf::Semantic::Tangents) else { return Ok(None) };
    let t_at = format!("{at}.attributes.TANGENT");
    check(&acc, &[Dimensions::Vec4], &[DataType::F32], buffers, &t_at)?;
    let t = per_vertex(reader.read_tangents().ok_or_else(|| unreadable(&t_at))?.collect(), vertices, &t_at, ("tangent", "tangents"))?;
    Ok(Some(t.into_iter().map(Vec4::from_array).map(|v| v.truncate().normalize_or_zero().extend(if v.w < 0.0 { -1.0 } else { 1.0 })).collect()))
}

/// A primitive's COLOR_0 (None without one): RGB or RGBA of floats or
/// normalised bytes or shorts, one a vertex, finite; clamped to [0, 1] (a
/// linear multiplier of the base colour). Its alpha is not read.
fn read_colors<'a, 's, F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>>(prim: &gltf::Primitive, reader: &gltf::mesh::Reader<'a, 's, F>, buffers: &[Vec<u8>], at: &str, vertices: usize) -> Result<Option<Vec<Vec3>>, String> {
    let Some(acc) = prim.get(&gltf::Semantic::Colors(0)) else { return Ok(None) };
    let c_at = format!("{at}.attributes.COLOR_0");
    check(&acc, &[Dimensions::Vec3, Dimensions::Vec4], &[DataType::F32, DataType::U8, DataType::U16], buffers, &c_at)?;
    if acc.data_type() != DataType::F32 && !acc.normalized() {
        return Err(format!("{c_at}: integer colours must be normalized (glTF)"));
    }
    let c = per_vertex(reader.read_colors(0).ok_or_else(|| unreadable(&c_at))?.into_rgb_f32().collect(), vertices, &c_at, ("colour", "colours"))?;
    Ok(Some(c.into_iter().map(|v| Vec3::from_array(v).clamp(Vec3::ZERO, Vec3::ONE)).collect()))
}

/// An attribute's `values` at `at`, checked: one for each of `vertices`
/// positions, every component finite; `(one, many)` name them in errors.
fn per_vertex<const N: usize>(values: Vec<[f32; N]>, vertices: usize, at: &str, (one, many): (&str, &str)) -> Result<Vec<[f32; N]>, String> {
    if values.len() != vertices {
        return Err(format!("{at}: {} {many} for {vertices} positions", values.len()));
    }
    if let Some(k) = values.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
        return Err(format!("{at}: {one} {k} is not finite ({:?})", values[k]));
    }
    Ok(values)
}

/// The triangles (as vertex index triples, counter-clockwise front faces)
/// of a list, strip or fan of `indices`.
pub(crate) fn unroll(mode: Mode, indices: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
            .map(|k| {
                let (a, b, c) = (indices[k], indices[k + 1], indices[k + 2]);
                // Every other triangle of a strip turns the other way
                // (the glTF spec's order).
                if k % 2 == 0 { [a, b, c] } else { [a, c, b] }
            })
            .collect(),
        Mode::TriangleFan => (1..indices.len().saturating_sub(1)).map(|k| [indices[k], indices[k + 1], indices[0]]).collect(),
        _ => indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}

fn unreadable(at: &str) -> String {
    format!("{at}: the accessor could not be read (it has no bufferView, or its sparse data lies outside its buffer)")
}

/// Checks an accessor before it is read: its type and component type, a
/// count of at least one, and that every element lies inside its buffer
/// view and the view inside its buffer.
pub(crate) fn check(acc: &gltf::Accessor, dims: &[Dimensions], types: &[DataType], buffers: &[Vec<u8>], at: &str) -> Result<(), String> {
    let name = format!("{at} (accessors[{}])", acc.index());
    if !dims.contains(&acc.dimensions()) || !types.contains(&acc.data_type()) {
        fn want<T: std::fmt::Debug>(d: &[T]) -> String {
            d.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(" or ")
        }
        return Err(format!(
            "{name}: is {:?} of {:?}; glint reads {} of {}",
            acc.dimensions(),
            acc.data_type(),
            want(dims),
            want(types)
        ));
    }
    if acc.count() == 0 {
        return Err(format!("{name}: has count 0 (glTF needs at least 1)"));
    }
    let Some(view) = acc.view() else { return Ok(()) };
    let buffer = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > buffer) {
        return Err(format!(
            "{name}: its bufferView {} covers bytes {}..{} of buffers[{}], which holds {buffer}",
            view.index(),
            view.offset(),
            view.offset().saturating_add(view.length()),
            view.buffer().index()
        ));
    }
    let size = acc.size();
    let stride = view.stride().unwrap_or(size);
    let end = (acc.count() - 1).checked_mul(stride).and_then(|x| x.checked_add(acc.offset())).and_then(|x| x.checked_add(size));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{name}: {} elements of {size} bytes, {stride} apart from byte {}, run past the {} bytes of bufferViews[{}]",
            acc.count(),
            acc.offset(),
            view.length(),
            view.index()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_unroll_counter_clockwise() {
        assert_eq!(unroll(Mode::Triangles, &[0, 1, 2, 3, 4, 5, 6]), vec![[0, 1, 2], [3, 4, 5]]);
        assert_eq!(unroll(Mode::TriangleStrip, &[0, 1, 2, 3, 4]), vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
        assert_eq!(unroll(Mode::TriangleFan, &[0, 1, 2, 3]), vec![[1, 2, 0], [2, 3, 0]]);
        assert!(unroll(Mode::TriangleStrip, &[0, 1]).is_empty());
    }
}
