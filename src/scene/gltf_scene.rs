//! A glTF file opened as a scene (`glint view model.glb`, `glint render
//! model.gltf`): the file's first perspective camera and its point lights.
//! With no camera, one on +z frames the bounds; with no light, a default
//! sphere light as for an OBJ (`obj_scene::framing`). Each default is said
//! once on stderr.

use std::path::Path;

use glam::DVec3;

use super::gltf_file::{self, GltfCamera};
use super::parse_with;
use super::obj_scene::{framing, VFOV_DEG};
use crate::error::UserError;
use crate::scene::Scene;

/// Opens `path`, a `.gltf` or `.glb` file, as a scene.
pub fn open_gltf(path: &Path) -> Result<Scene, UserError> {
    let file = path.file_name().map(|n| n.to_string_lossy().into_owned()).ok_or_else(|| UserError::in_file(path, "not a file name"))?;
    let gltf = gltf_file::read(path).map_err(UserError::new)?;
    for w in &gltf.warnings {
        eprintln!("glint: {}: {w}", path.display());
    }
    let (lo, hi) = gltf.bounds().ok_or_else(|| UserError::in_file(path, "the glTF file's scene places no triangles to show"))?;
    let (camera_at, target, light) = framing(lo, hi);
    let p = |v: DVec3| format!("({:?}, {:?}, {:?})", v.x, v.y, v.z);
    let camera = match gltf.cameras.first() {
        Some(GltfCamera { position, target, up, vfov_deg }) => {
            format!("Camera(position: {}, target: {}, up: {}, vfov_deg: {:?})", p(*position), p(*target), p(*up), *vfov_deg as f32)
        }
        None => {
            eprintln!("glint: {}: the file has no perspective camera; one on +z frames its bounds", path.display());
            format!("Camera(position: {}, target: {}, vfov_deg: {VFOV_DEG:?})", p(camera_at), p(target))
        }
    };
    let lights = if gltf.lights.is_empty() {
        eprintln!("glint: {}: the file has no point light; a default sphere light is added above and in front", path.display());
        let e = light.radiance;
        format!("SphereLight(center: {}, radius: {:?}, radiance: ({e:?}, {e:?}, {e:?}))", p(light.centre), light.radius)
    } else {
        String::new()
    };
    let text = format!("Scene(camera: {camera}, objects: [Gltf(path: {file:?})], lights: [{lights}])");
    parse_with(&text, path, vec![(path.to_path_buf(), gltf)])
}
