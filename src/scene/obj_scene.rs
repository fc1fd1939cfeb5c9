//! An OBJ file opened as a scene (`glint view model.obj`, `glint render
//! model.obj`, an OBJ dropped on the viewer): the mesh with its MTL
//! materials (white where it has none), a camera on +z framing its bounds
//! and a small sphere light above and in front of it. Said once on stderr,
//! since a scene file chooses all three.

use std::path::Path;

use glam::DVec3;

use crate::error::UserError;
use crate::scene::{parse, Scene};

/// The field of view of the framing camera, degrees.
pub(crate) const VFOV_DEG: f64 = 40.0;

/// The scene text for `file` (the OBJ's name, beside the scene's "file")
/// with this camera and, if given, a sphere light (centre, radius,
/// radiance).
fn scene_text(file: &str, position: DVec3, target: DVec3, light: Option<Light>) -> String {
    let p = |v: DVec3| format!("({:?}, {:?}, {:?})", v.x, v.y, v.z);
    let lights = light.map_or(String::new(), |l| {
        let e = l.radiance;
        format!("SphereLight(center: {}, radius: {:?}, radiance: ({e:?}, {e:?}, {e:?}))", p(l.centre), l.radius)
    });
    format!(
        "Scene(camera: Camera(position: {}, target: {}, vfov_deg: {VFOV_DEG:?}), objects: [Mesh(path: {file:?})], lights: [{lights}])",
        p(position),
        p(target)
    )
}

/// The default light: a sphere light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Light {
    pub centre: DVec3,
    pub radius: f64,
    /// Radiance, the same in every channel.
    pub radiance: f64,
}

/// Where the framing camera and the default light go for bounds `lo..hi`
/// (camera position, target, light): the camera on +z (a little above) at
/// the distance where the bounding sphere fills the field of view; a small
/// sphere light above, right and in front at three radii, bright enough for
/// an irradiance of about 2 at the centre (pi L a^2 / d^2).
pub(crate) fn framing(lo: DVec3, hi: DVec3) -> (DVec3, DVec3, Light) {
    let centre = 0.5 * (lo + hi);
    let r = (0.5 * (hi - lo).length()).max(1e-6);
    let distance = r / (0.5 * VFOV_DEG).to_radians().sin();
    let camera = centre + DVec3::new(0.0, 0.25, 1.0).normalize() * distance;
    let (d, a) = (3.0 * r, 0.05 * r);
    let light = Light { centre: centre + DVec3::new(1.0, 2.0, 2.0) * r, radius: a, radiance: 2.0 * d * d / (std::f64::consts::PI * a * a) };
    (camera, centre, light)
}

/// Opens `path`, an OBJ file, as a scene.
pub fn open_obj(path: &Path) -> Result<Scene, UserError> {
    let file = path.file_name().map(|n| n.to_string_lossy().into_owned()).ok_or_else(|| UserError::in_file(path, "not a file name"))?;
    // First without a light, for the bounds.
    let probe = parse(&scene_text(&file, DVec3::Z, DVec3::ZERO, None), path)?;
    let (lo, hi) = probe.bounds().ok_or_else(|| UserError::in_file(path, "the OBJ has no triangles to show"))?;
    let (camera, target, light) = framing(lo, hi);
    let scene = parse(&scene_text(&file, camera, target, Some(light)), path)?;
    eprintln!(
        "glint: {}: an OBJ opened as a scene: its MTL materials (white where none), a camera framing it and a default sphere light; a scene file chooses them (docs/scenes.md)",
        path.display()
    );
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_frames_the_bounds_and_the_light_reaches_the_centre() {
        let (lo, hi) = (DVec3::new(-1.0, 0.0, -2.0), DVec3::new(3.0, 2.0, 0.0));
        let (camera, target, light) = framing(lo, hi);
        let r = 0.5 * (hi - lo).length();
        assert_eq!(target, DVec3::new(1.0, 1.0, -1.0));
        // The bounding sphere just fits the vertical field of view.
        let half = (r / (camera - target).length()).asin().to_degrees();
        assert!((half - 0.5 * VFOV_DEG).abs() < 1e-9, "half angle {half}");
        assert!(camera.z > target.z && camera.y > target.y, "in front and a little above");
        let irradiance = std::f64::consts::PI * light.radiance * light.radius * light.radius / (light.centre - target).length_squared();
        assert!((irradiance - 2.0).abs() < 1e-9);
    }

    #[test]
    fn an_obj_opens_as_a_scene() {
        let dir = std::env::temp_dir().join(format!("glint-obj-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let obj = dir.join("tri \"quoted\".obj");
        std::fs::write(&obj, "v 0 0 0\nv 4 0 0\nv 0 2 0\nf 1 2 3\n").expect("write");
        let scene = open_obj(&obj).unwrap_or_else(|e| panic!("{e}"));
        // Framed on the triangle's bounds, (0, 0, 0) to (4, 2, 0).
        assert_eq!(scene.camera.target, DVec3::new(2.0, 1.0, 0.0));
        assert!(scene.compile_features().area_lights, "a default light");
        let empty = dir.join("empty.obj");
        std::fs::write(&empty, "# nothing\n").expect("write");
        let Err(e) = open_obj(&empty) else { panic!("an empty OBJ opened") };
        let e = e.to_string();
        assert!(e.contains("empty.obj"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn an_mtl_map_kd_is_a_base_colour_texture() {
        let dir = std::env::temp_dir().join(format!("glint-obj-texture-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let img = image::RgbaImage::from_raw(1, 1, vec![10, 20, 30, 255]).expect("image");
        img.save(dir.join("wood.png")).expect("png");
        std::fs::write(dir.join("m.mtl"), "newmtl wood\nKd 1 1 1\nmap_Kd -s 1 1 1 wood.png\nnewmtl plain\nKd 0.5 0.5 0.5\n").expect("write");
        std::fs::write(dir.join("m.obj"), "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 0.25\nusemtl wood\nf 1/1 2/2 3/3\n").expect("write");
        let scene = open_obj(&dir.join("m.obj")).unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.compile_features().textures);
        assert_eq!(scene.textures().len(), 1);
        assert_eq!(scene.textures()[0].rgba, vec![10, 20, 30, 255]);
        let slots = scene.material_textures();
        let wood = slots.iter().position(|m| m.base_color.is_some()).expect("a textured material");
        assert!(slots.iter().filter(|m| m.base_color.is_some()).count() == 1, "only wood has a map_Kd");
        let tri = scene.meshes()[0].triangles[0];
        assert_eq!(tri.material as usize, wood);
        // OBJ's v points up; glTF's (and glint's) down from the top.
        assert_eq!(tri.uv, [glam::Vec2::new(0.0, 1.0), glam::Vec2::new(1.0, 1.0), glam::Vec2::new(0.0, 0.75)]);
        // A map that is not there names the material and the file.
        std::fs::remove_file(dir.join("wood.png")).expect("remove");
        let e = open_obj(&dir.join("m.obj")).map(|_| ()).expect_err("a missing map_Kd loaded").to_string();
        assert!(e.contains("material \"wood\"") && e.contains("wood.png"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn an_mtl_normal_map_is_a_linear_normal_texture_with_its_scale() {
        let dir = std::env::temp_dir().join(format!("glint-obj-normal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let img = image::RgbaImage::from_raw(1, 1, vec![200, 128, 230, 255]).expect("image");
        img.save(dir.join("n.png")).expect("png");
        // map_Bump with -bm, `norm`, and the same file as a colour map:
        // the colour use and the data use are two textures, each read once.
        let mtl = "newmtl a\nKd 1 1 1\nmap_Bump -bm 0.5 n.png\nnewmtl b\nKd 1 1 1\nnorm n.png\nnewmtl c\nKd 1 1 1\nmap_Kd n.png\n";
        std::fs::write(dir.join("m.mtl"), mtl).expect("write");
        let faces = "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 2/2 3/3\nusemtl c\nf 1/1 2/2 3/3\n";
        std::fs::write(dir.join("m.obj"), format!("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n{faces}")).expect("write");
        let scene = open_obj(&dir.join("m.obj")).unwrap_or_else(|e| panic!("{e}"));
        let textures = scene.textures();
        assert_eq!(textures.len(), 2, "one linear copy for the normal maps, one sRGB for the colour map");
        let slots = scene.material_textures();
        let normals: Vec<_> = slots.iter().filter_map(|m| m.normal).collect();
        assert_eq!(normals.len(), 2);
        assert_eq!(normals[0].0.texture, normals[1].0.texture, "both normal maps share their texture");
        assert!(textures[normals[0].0.texture].linear);
        assert_eq!((normals[0].1, normals[1].1), (0.5, 1.0));
        let colour = slots.iter().find_map(|m| m.base_color).expect("c's colour map");
        assert!(!textures[colour.texture].linear);
        // A -bm that is not a number is an error naming it.
        std::fs::write(dir.join("m.mtl"), mtl.replace("-bm 0.5", "-bm strong")).expect("write");
        let e = open_obj(&dir.join("m.obj")).map(|_| ()).expect_err("-bm strong loaded").to_string();
        assert!(e.contains("-bm") && e.contains("m.obj"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
