//! OBJ/MTL reading through tobj: local-space triangles with unit normals and
//! MTL materials mapped to ours. Errors are plain messages; the loader adds
//! the scene file and line.

use std::path::Path;

use glam::Vec3;

use super::gpu_types::MaterialGpu;

/// One triangle as read: `material` indexes `ObjFile::materials`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ObjTriangle {
    pub p: [Vec3; 3],
    pub n: [Vec3; 3],
    pub material: Option<usize>,
}

#[derive(Debug)]
pub(crate) struct ObjFile {
    pub triangles: Vec<ObjTriangle>,
    pub materials: Vec<MaterialGpu>,
}

/// Reads `path`. A missing or unreadable MTL library is not an error: the
/// faces then have no material and the scene's fallback applies.
pub(crate) fn read(path: &Path) -> Result<ObjFile, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj(path, &options)
        .map_err(|e| format!("cannot read OBJ file {}: {e}", path.display()))?;
    let materials = materials
        .unwrap_or_default()
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
            // normal: drop them.
            let Some(flat) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else {
                continue;
            };
            // A missing or broken vertex normal falls back to the face normal.
            let n = n.map(|v| v.try_normalize().unwrap_or(flat));
            triangles.push(ObjTriangle { p, n, material });
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
    })
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
    Ok(MaterialGpu {
        albedo: albedo.map(|c| c.clamp(0.0, 1.0)),
        specular,
        emission: emission.map(|c| c.max(0.0)),
        roughness,
    })
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
