//! An OBJ's MTL normal map (`map_Bump`, `norm`) on the GPU: a white
//! Lambertian card facing the camera under a sun, alone against a black
//! sky, so the path tracer's image is albedo / pi x E cos(n, l) with the
//! normal the map gives, and nothing else.

mod common;

use common::*;
use glam::Vec3;

/// A card filling a 32x32 view (camera at z = 2), `vt` u along +x and v
/// up (OBJ's), white and matte, with `map` (an MTL line, or none) reading
/// a 1x1 image `texel`, under a sun travelling along `sun`.
fn card_scene(dir: &std::path::Path, name: &str, map: Option<&str>, texel: [u8; 4], sun: Vec3) -> std::path::PathBuf {
    image::RgbaImage::from_raw(1, 1, texel.to_vec()).expect("image").save(dir.join(format!("{name}.png"))).expect("png");
    let map = map.map(|m| format!("{m} {name}.png\n")).unwrap_or_default();
    std::fs::write(dir.join(format!("{name}.mtl")), format!("newmtl card\nKd 1 1 1\n{map}")).expect("write");
    let obj = format!(
        "mtllib {name}.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl card\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n"
    );
    std::fs::write(dir.join(format!("{name}.obj")), obj).expect("write");
    let scene = dir.join(format!("{name}.ron"));
    let vfov = 2.0 * 0.5f64.atan().to_degrees();
    std::fs::write(
        &scene,
        format!(
            "Scene(camera: Camera(position: (0.0, 0.0, 2.0), target: (0.0, 0.0, 0.0), vfov_deg: {vfov}), objects: [Mesh(path: \"{name}.obj\")], lights: [DirectionalLight(direction: ({}, {}, {}), irradiance: (1.0, 1.0, 1.0))])",
            sun.x, sun.y, sun.z
        ),
    )
    .expect("write");
    scene
}

#[test]
fn an_mtl_normal_map_bends_the_shading_normal_its_way() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("obj-normal-map");
    let decode = |t: [u8; 4]| Vec3::new(t[0] as f32, t[1] as f32, t[2] as f32) / 255.0 * 2.0 - Vec3::ONE;
    // A flat texel changes nothing. (8-bit 128 is 0.004, not 0: under a
    // sun 45 degrees off the card that tilt alone brightens it 0.4%, so
    // this sun stands head-on.)
    let flat = [128, 128, 255, 255];
    let head_on = Vec3::NEG_Z;
    let plain = path_traced_32(&card_scene(&dir, "plain", None, flat, head_on));
    let (flat_flip, _) = glint::metrics::flip(&plain, &path_traced_32(&card_scene(&dir, "flat", Some("map_Bump"), flat, head_on)));
    eprintln!("a flat normal map against none: FLIP {:.4}", flat_flip.mean);
    assert!(flat_flip.mean <= 0.01, "a flat normal map changed the image: FLIP {}", flat_flip.mean);
    // A texel bent toward +x in the image bends the normal toward world +x
    // (u runs along x), one bent toward the image's top toward +y (OBJ's v
    // runs up, and its images' first row is v = 1): through map_Bump, and
    // through `norm` with -bm halving the bend.
    let (right, up) = ([218, 128, 218, 255], [128, 218, 218, 255]);
    for (name, map, texel, world, scale) in [("right", "map_Bump", right, Vec3::X, 1.0), ("up", "norm", up, Vec3::Y, 1.0), ("half", "map_Bump -bm 0.5", right, Vec3::X, 0.5)] {
        let c = decode(texel);
        let n = (world * c.x.max(c.y) * scale + Vec3::Z * c.z).normalize();
        // The sun stands 45 degrees off the card toward the bend.
        let toward_sun = (world + Vec3::Z).normalize();
        let img = path_traced_32(&card_scene(&dir, name, Some(map), texel, -toward_sun));
        let want = n.dot(toward_sun).max(0.0) / std::f32::consts::PI;
        let got = centre_32(&img);
        eprintln!("normal map {name} ({map}): {:.4} (want {want:.4}; unbent {:.4})", got.x, Vec3::Z.dot(toward_sun) / std::f32::consts::PI);
        assert!((got - Vec3::splat(want)).abs().max_element() <= 0.03 * want + 1e-3, "normal map {name}: {got}, want {want}");
    }
}
