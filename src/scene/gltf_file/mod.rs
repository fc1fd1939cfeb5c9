//! glTF 2.0 files (`.gltf` with external or data-URI buffers, and `.glb`):
//! the default scene's node hierarchy flattened into mesh instances with
//! f64 world matrices, the materials, `KHR_lights_punctual` point lights
//! and perspective cameras. Errors are plain messages naming the glTF path
//! (`meshes[3].primitives[0].attributes.NORMAL`); the scene loader adds the
//! file and line.

mod buffers;
mod geometry;
mod materials;
mod nodes;
mod tangents;
mod textures;

use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3, Vec3};

pub(crate) use geometry::GltfTriangle;
pub(crate) use materials::DEFAULT as DEFAULT_MATERIAL;
pub(crate) use textures::{MaterialTextures, TextureRef, Wrap};
use super::world::TextureImage;

use super::gpu_types::MaterialGpu;

/// Lumens per watt: glTF's photometric light units to glint's radiometric
/// ones, as Blender's glTF importer converts them (docs/scenes.md).
pub(crate) const LUMENS_PER_WATT: f32 = 683.0;

/// Extensions glint acts on; a file may require these. Textures (and so
/// `KHR_texture_transform`) are not read yet: their factors are.
const UNDERSTOOD: &[&str] = &["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform"];

/// A glTF file, read and checked.
#[derive(Debug)]
pub(crate) struct GltfFile {
    /// The triangles of each glTF mesh in its own space, by glTF mesh
    /// index; empty for meshes no node places.
    pub meshes: Vec<Vec<GltfTriangle>>,
    /// By glTF material index.
    pub materials: Vec<MaterialGpu>,
    /// The textures each material samples, by glTF material index.
    pub material_textures: Vec<MaterialTextures>,
    /// By glTF image index: decoded where a material's texture uses it.
    pub images: Vec<Option<TextureImage>>,
    /// Each placement of a mesh, in node order.
    pub instances: Vec<Instance>,
    pub lights: Vec<PointLight>,
    pub cameras: Vec<GltfCamera>,
    /// The buffer files read beside the glTF (for hot reload).
    pub files: Vec<PathBuf>,
    /// What glint leaves out of this file, one line each.
    pub warnings: Vec<String>,
}

/// A mesh placed by a node: world = `matrix` x mesh space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Instance {
    pub mesh: usize,
    pub matrix: DMat4,
}

/// A `KHR_lights_punctual` point or spot light in glint's units (W/sr).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PointLight {
    pub position: DVec3,
    pub intensity: Vec3,
    /// A spot light's cone (its direction in the file's world).
    pub spot: Option<super::world::SpotCone>,
    /// A directional light's direction of travel (the file's world);
    /// `intensity` is then its irradiance (lux / 683).
    pub directional: Option<Vec3>,
}

/// A perspective camera placed by a node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GltfCamera {
    pub position: DVec3,
    pub target: DVec3,
    pub up: DVec3,
    pub vfov_deg: f64,
}

impl GltfFile {
    /// World-space bounds of every instance's triangles (None with none).
    pub(crate) fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut b: Option<(DVec3, DVec3)> = None;
        for inst in &self.instances {
            for t in self.meshes.get(inst.mesh).into_iter().flatten() {
                for p in t.p {
                    let w = inst.matrix.transform_point3(p.as_dvec3());
                    b = Some(b.map_or((w, w), |(lo, hi)| (lo.min(w), hi.max(w))));
                }
            }
        }
        b
    }
}

/// A glTF file read for this scene, and where its pieces went.
pub(crate) struct GltfLoaded {
    pub path: PathBuf,
    pub file: GltfFile,
    /// The scene material id of the file's material 0 (None until added).
    pub materials_base: Option<u32>,
    /// The glTF default material's id in the scene, once used.
    pub default_material: Option<u32>,
    /// Per glTF mesh: its scene mesh for instances that share it, and how
    /// far that mesh reaches from its origin.
    pub shared: Vec<Option<(usize, f64)>>,
}

impl GltfLoaded {
    pub(crate) fn new(path: PathBuf, file: GltfFile) -> Self {
        let shared = vec![None; file.meshes.len()];
        GltfLoaded { path, file, materials_base: None, default_material: None, shared }
    }
}

/// Reads the glTF or GLB file at `path`.
pub(crate) fn read(path: &Path) -> Result<GltfFile, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read glTF file {}: {e}", path.display()))?;
    let in_file = |e: String| format!("glTF file {}: {e}", path.display());
    // A JSON error's message starts with its line and column (file:line:col).
    let (root, blob) = parse(&bytes).map_err(|e| if e.starts_with(':') { format!("glTF file {}{e}", path.display()) } else { in_file(e) })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    read_root(root, blob, dir).map_err(in_file)
}

/// The JSON root and the GLB binary chunk of a file's bytes.
fn parse(bytes: &[u8]) -> Result<(gltf::json::Root, Option<Vec<u8>>), String> {
    if !bytes.starts_with(b"glTF") {
        let json_error = |e: gltf::json::Error| {
            let text = e.to_string();
            let what = text.rsplit_once(" at line ").map_or(text.as_str(), |(w, _)| w);
            format!(":{}:{}: not glTF JSON: {what}", e.line(), e.column())
        };
        return Ok((gltf::json::deserialize::from_slice(bytes).map_err(json_error)?, None));
    }
    // The header's length is checked first: the reader subtracts from it.
    let length = bytes.get(8..12).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    if length.is_none_or(|n| n < 20 || n as usize > bytes.len()) {
        return Err(format!("a GLB file whose header gives {} bytes in a file of {}", length.unwrap_or(0), bytes.len()));
    }
    let glb = gltf::Glb::from_slice(bytes).map_err(|e| format!("not a valid GLB file: {e}"))?;
    let root = gltf::json::deserialize::from_slice(&glb.json).map_err(|e| format!("the GLB's JSON chunk is not glTF JSON: {e}"))?;
    Ok((root, glb.bin.map(|b| b.into_owned())))
}

fn read_root(root: gltf::json::Root, blob: Option<Vec<u8>>, dir: &Path) -> Result<GltfFile, String> {
    for (i, ext) in root.extensions_required.iter().enumerate() {
        if !UNDERSTOOD.contains(&ext.as_str()) {
            return Err(format!("extensionsRequired[{i}]: the file requires {ext}, which glint does not support (it reads {})", UNDERSTOOD.join(", ")));
        }
    }
    let ignored: Vec<String> = root.extensions_used.iter().filter(|e| !UNDERSTOOD.contains(&e.as_str())).cloned().collect();
    let doc = gltf::Document::from_json(root).map_err(|e| match e {
        gltf::Error::Validation(list) => {
            use gltf::json::validation::Error as V;
            let say = |e: &V| match e {
                V::IndexOutOfBounds => "refers to an item the file does not have",
                V::Invalid => "is not a valid value",
                V::Missing => "is missing",
                V::Oversize => "is too large",
                V::Unsupported => "needs an extension glint does not support",
            };
            let shown: Vec<String> = list.iter().take(5).map(|(path, err)| format!("{path}: {}", say(err))).collect();
            let more = if list.len() > 5 { format!(" (and {} more)", list.len() - 5) } else { String::new() };
            format!("not valid glTF: {}{more}", shown.join("; "))
        }
        other => other.to_string(),
    })?;
    let buffers = buffers::read(&doc, blob, dir)?;
    let placed = nodes::walk(&doc)?;
    let mut meshes = vec![Vec::new(); doc.meshes().len()];
    let mut read = vec![false; meshes.len()];
    for inst in &placed.instances {
        if !read[inst.mesh] {
            let mesh = doc.meshes().nth(inst.mesh).ok_or_else(|| format!("meshes[{}]: missing", inst.mesh))?;
            meshes[inst.mesh] = geometry::triangles(&mesh, &buffers.data)?;
            read[inst.mesh] = true;
        }
    }
    let materials = doc.materials().map(|m| materials::convert(&m)).collect::<Result<Vec<_>, _>>()?;
    let material_textures =
        doc.materials().map(|m| textures::material_textures(&m, &format!("materials[{}]", m.index().unwrap_or(0)))).collect::<Result<Vec<_>, _>>()?;
    let mut wanted = Vec::new();
    for t in material_textures.iter().flat_map(|m| [m.base_color, m.emissive, m.metallic_roughness, m.normal.map(|n| n.0)]).flatten() {
        if !wanted.contains(&t.image) {
            wanted.push(t.image);
        }
    }
    let mut images = vec![None; doc.images().len()];
    let mut files = buffers.files;
    for (&i, (image, file)) in wanted.iter().zip(textures::decode_all(&doc, &wanted, &buffers.data, dir)?) {
        images[i] = Some(image);
        files.extend(file);
    }
    let mut warnings = placed.warnings;
    if !ignored.is_empty() {
        warnings.push(format!("extensions glint ignores: {}", ignored.join(", ")));
    }
    warnings.extend(materials::left_out(&doc));
    if doc.animations().len() > 0 {
        warnings.push(format!("{} animation(s) are not played: glint shows the file's rest pose", doc.animations().len()));
    }
    Ok(GltfFile { meshes, materials, material_textures, images, instances: placed.instances, lights: placed.lights, cameras: placed.cameras, files, warnings })
}

#[cfg(test)]
mod tests;
