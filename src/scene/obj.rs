//! OBJ/MTL reading through tobj: local-space triangles with unit normals and
//! MTL materials mapped to ours. Errors are plain messages; the loader adds
//! the scene file and line.

use std::path::Path;

use glam::{Vec2, Vec3};

use super::gpu_types::MaterialGpu;

/// One triangle as read: `material` indexes `ObjFile::materials`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ObjTriangle {
    pub p: [Vec3; 3],
    pub n: [Vec3; 3],
    /// `vt` at the vertices, v flipped to glTF's top-left origin (zero
    /// where the OBJ has none).
    pub uv: [Vec2; 3],
    pub material: Option<usize>,
}

#[derive(Debug)]
pub(crate) struct ObjFile {
    pub triangles: Vec<ObjTriangle>,
    pub materials: Vec<MaterialGpu>,
    /// Per material: its name and its `map_Kd` file, beside the MTL.
    pub diffuse_maps: Vec<Option<(String, std::path::PathBuf)>>,
    /// Per material: its name, its normal map (`map_Bump`, `bump` or
    /// `norm`: tangent-space normals, as Blender and most exporters write
    /// them) and the map's `-bm` scale (1 without one).
    pub normal_maps: Vec<Option<(String, std::path::PathBuf, f32)>>,
}

/// Reads `path`. A missing MTL library is not an error (the faces then
/// have no material and the scene's fallback applies); an MTL that exists
/// but fails to parse, or a `usemtl` naming a material no library defines,
/// is. Errors name the OBJ or MTL line where one is to blame.
/// `check_materials` is false when the scene overrides the OBJ's materials.
pub(crate) fn read(path: &Path, check_materials: bool) -> Result<ObjFile, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj(path, &options).map_err(|e| {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        match first_bad_line(&text, &e) {
            Some((line, what)) => format!("OBJ file {}:{line}: {e}: {what}", path.display()),
            None => format!("cannot read OBJ file {}: {e}", path.display()),
        }
    })?;
    let materials = match materials {
        Ok(m) => m,
        Err(tobj::LoadError::OpenFileFailed) => Vec::new(),
        Err(e) => return Err(format!("OBJ file {}: its MTL library could not be read: {e}", path.display())),
    };
    if check_materials && models.iter().any(|m| m.mesh.material_id.is_none()) {
        check_usemtl(path, &materials)?;
    }
    let dir = path.parent().unwrap_or(Path::new(""));
    let diffuse_maps = materials.iter().map(|m| m.diffuse_texture.as_deref().map(|t| (m.name.clone(), dir.join(map_file(t))))).collect();
    let normal_maps = materials
        .iter()
        .map(|m| {
            let value = m.normal_texture.as_deref().or_else(|| m.unknown_param.get("norm").map(String::as_str))?;
            Some(bump_scale(value).map(|scale| (m.name.clone(), dir.join(map_file(value)), scale)))
        })
        .map(Option::transpose)
        .collect::<Result<Vec<_>, String>>()
        .map_err(|e| format!("OBJ file {}: its MTL library: {e}", path.display()))?;
    let materials = materials
        .iter()
        .map(map_material)
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("OBJ file {}: {e}", path.display()))?;

    let mut triangles = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let material = mesh.material_id.filter(|&m| m < materials.len());
        let vec3 = |data: &[f32], i: u32| -> Option<Vec3> {
            let i = i as usize * 3;
            data.get(i..i + 3).map(Vec3::from_slice)
        };
        let has_normals = mesh.normals.len() == mesh.positions.len();
        let has_uvs = mesh.texcoords.len() / 2 == mesh.positions.len() / 3;
        let uv = |i: u32| -> Vec2 {
            let i = i as usize * 2;
            mesh.texcoords.get(i..i + 2).filter(|_| has_uvs).map_or(Vec2::ZERO, |t| Vec2::new(t[0], 1.0 - t[1]))
        };
        for face in mesh.indices.chunks_exact(3) {
            let mut p = [Vec3::ZERO; 3];
            let mut n = [Vec3::ZERO; 3];
            for k in 0..3 {
                p[k] = vec3(&mesh.positions, face[k]).ok_or_else(|| {
                    format!(
                        "OBJ file {}: face index {} out of range",
                        path.display(),
                        face[k] + 1
                    )
                })?;
                if !p[k].is_finite() {
                    return Err(format!(
                        "OBJ file {}: vertex {} of object \"{}\" is not finite ({})",
                        path.display(),
                        face[k] + 1,
                        model.name,
                        p[k]
                    ));
                }
                if has_normals {
                    n[k] = vec3(&mesh.normals, face[k]).unwrap_or(Vec3::ZERO);
                }
            }
            // Zero-area triangles can never be hit properly and have no
            // normal: drop them. In f64: the cross product of edges above
            // about 1e19 (and its squared length above 1e17) overflows f32,
            // and a huge triangle must reach the range check, not vanish.
            let [a, b, c] = p.map(|v| v.as_dvec3());
            let Some(flat) = (b - a).cross(c - a).try_normalize().map(|n| n.as_vec3()) else {
                continue;
            };
            // A missing or broken vertex normal falls back to the face normal.
            let n = n.map(|v| v.try_normalize().unwrap_or(flat));
            triangles.push(ObjTriangle { p, n, uv: [uv(face[0]), uv(face[1]), uv(face[2])], material });
        }
    }
    if triangles.is_empty() {
        return Err(format!(
            "OBJ file {} has no triangles (of non-zero area)",
            path.display()
        ));
    }
    Ok(ObjFile {
        triangles,
        materials,
        diffuse_maps,
        normal_maps,
    })
}

/// The `-bm` option of a normal map line (`map_Bump -bm 0.5 n.png`), 1
/// without one; other options are skipped.
fn bump_scale(value: &str) -> Result<f32, String> {
    let words: Vec<&str> = value.split_whitespace().collect();
    match words.iter().position(|w| *w == "-bm") {
        None => Ok(1.0),
        Some(i) => match words.get(i + 1).map(|w| w.parse::<f32>()) {
            Some(Ok(s)) if s.is_finite() => Ok(s),
            _ => Err(format!("`{}`: -bm takes a finite number (the normal map's scale)", value.trim())),
        },
    }
}

/// The file a `map_Kd` line names: its last word after options (`-s 2 2 1
/// wood.png`), else the whole of it (a name with spaces).
fn map_file(value: &str) -> &str {
    let value = value.trim();
    if value.starts_with('-') {
        value.split_whitespace().last().unwrap_or(value)
    } else {
        value
    }
}

/// The first line of an OBJ that the loader's error `e` can be blamed on:
/// a `v`/`vn`/`vt` line whose numbers do not parse, or an `f` line with a
/// bad or out-of-range index. (tobj reports the kind of error, not where.)
fn first_bad_line(text: &str, e: &tobj::LoadError) -> Option<(usize, String)> {
    use tobj::LoadError::*;
    let keyword = match e {
        PositionParseError => "v",
        NormalParseError => "vn",
        TexcoordParseError => "vt",
        FaceParseError | InvalidPolygon | FaceVertexOutOfBounds | FaceTexCoordOutOfBounds | FaceNormalOutOfBounds => "f",
        _ => return None,
    };
    let mut counts = [0i64; 3]; // v, vt, vn seen so far
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let Some(head) = words.next() else { continue };
        let args: Vec<&str> = words.collect();
        let floats = |n: usize| args.len() >= n && args.iter().take(n).all(|a| a.parse::<f32>().is_ok());
        let bad = match head {
            "v" => {
                counts[0] += 1;
                (head == keyword && !floats(3)).then(|| format!("`{}` needs three numbers", line.trim()))
            }
            "vt" => {
                counts[1] += 1;
                (head == keyword && !floats(1)).then(|| format!("`{}` needs numbers", line.trim()))
            }
            "vn" => {
                counts[2] += 1;
                (head == keyword && !floats(3)).then(|| format!("`{}` needs three numbers", line.trim()))
            }
            "f" if keyword == "f" => face_problem(&args, counts).map(|p| format!("`{}`: {p}", line.trim())),
            _ => None,
        };
        if let Some(what) = bad {
            return Some((i + 1, what));
        }
    }
    None
}

/// What is wrong with the vertices of an `f` line, given how many
/// positions, texture coordinates and normals came before it.
fn face_problem(args: &[&str], counts: [i64; 3]) -> Option<String> {
    if args.len() < 3 {
        return Some(format!("a face needs at least 3 vertices, it has {}", args.len()));
    }
    for a in args {
        for (k, part) in a.split('/').enumerate().take(3) {
            if part.is_empty() && k > 0 {
                continue;
            }
            let Ok(index) = part.parse::<i64>() else {
                return Some(format!("`{part}` is not a vertex index"));
            };
            let n = counts[k];
            let resolved = if index < 0 { n + index + 1 } else { index };
            if index == 0 || resolved < 1 || resolved > n {
                let what = ["position", "texture coordinate", "normal"][k];
                return Some(format!("{what} index {index} is out of range (1..={n} so far)"));
            }
        }
    }
    None
}

/// Every `usemtl` of the OBJ names a material its libraries define;
/// otherwise the error names the OBJ line (a garbage MTL made faces
/// silently fall back to the default material). Without any library file
/// on disk the fallback is what docs/usage.md ("Bad input") promises, and no error.
fn check_usemtl(path: &Path, materials: &[tobj::Material]) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read OBJ file {}: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let libraries_exist = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("mtllib"))
        .any(|lib| dir.join(lib.trim()).is_file());
    if !libraries_exist {
        return Ok(());
    }
    for (i, line) in text.lines().enumerate() {
        let Some(name) = line.trim().strip_prefix("usemtl") else { continue };
        let name = name.trim();
        if !name.is_empty() && !materials.iter().any(|m| m.name == name) {
            let defined = if materials.is_empty() {
                "its MTL libraries define no materials (no `newmtl` line)".to_string()
            } else {
                format!("its MTL libraries define: {}", materials.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", "))
            };
            return Err(format!("OBJ file {}:{}: usemtl `{name}`: no such material; {defined}", path.display(), i + 1));
        }
    }
    Ok(())
}

/// MTL → material: Kd→albedo, Ks→specular (max component), Ns→roughness
/// sqrt(2/(Ns+2)) (the Beckmann/Phong correspondence; Ns absent counts as 0,
/// i.e. fully rough), Ke→emission. Values are clamped to their ranges.
fn map_material(m: &tobj::Material) -> Result<MaterialGpu, String> {
    let albedo = m.diffuse.unwrap_or([0.8; 3]);
    let ks = m.specular.unwrap_or([0.0; 3]);
    let emission = m.emissive.unwrap_or([0.0; 3]);
    let ns = m.shininess.unwrap_or(0.0);
    let all = albedo
        .iter()
        .chain(&ks)
        .chain(&emission)
        .chain(std::iter::once(&ns));
    if !all.into_iter().all(|v| v.is_finite()) {
        return Err(format!(
            "material \"{}\" has a NaN or infinite value",
            m.name
        ));
    }
    let specular = ks.iter().fold(0.0f32, |a, &b| a.max(b)).clamp(0.0, 1.0);
    let roughness = if specular > 0.0 {
        (2.0 / (ns.max(0.0) + 2.0)).sqrt().clamp(0.0, 1.0)
    } else {
        1.0
    };
    Ok(MaterialGpu::thesis(albedo.map(|c| c.clamp(0.0, 1.0)), specular, emission.map(|c| c.max(0.0)), roughness))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_mtl_values() {
        let m = tobj::Material {
            name: "m".into(),
            diffuse: Some([0.5, 2.0, -1.0]),
            specular: Some([0.2, 0.6, 0.1]),
            shininess: Some(98.0),
            emissive: Some([1.0, 2.0, 3.0]),
            ..Default::default()
        };
        let g = map_material(&m).unwrap();
        assert_eq!(g.albedo, [0.5, 1.0, 0.0]);
        assert_eq!(g.specular, 0.6);
        assert!((g.roughness - 0.02f32.sqrt()).abs() < 1e-6);
        assert_eq!(g.emission, [1.0, 2.0, 3.0]);

        let plain = map_material(&tobj::Material::default()).unwrap();
        assert_eq!(
            (plain.albedo, plain.specular, plain.roughness),
            ([0.8; 3], 0.0, 1.0)
        );

        let bad = tobj::Material {
            diffuse: Some([f32::NAN, 0.0, 0.0]),
            ..Default::default()
        };
        assert!(map_material(&bad).is_err());
    }
}
