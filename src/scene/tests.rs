//! Scene tests without a GPU: the shipped scenes, features, packing,
//! animation, and every error path (file and line in the message, no panic).

use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::bvh::Aabb;

use super::*;

fn shipped(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    match load(&path) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    }
}

/// A scene with two materials; `objects` starts on line 8, `lights` on line 11
/// (when `objects` is one line).
fn scene(objects: &str, lights: &str) -> String {
    format!(
        r#"Scene(
    camera: Camera(position: (0.0, 0.0, 3.4), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),
    materials: {{
        "white": Material(albedo: (0.7, 0.7, 0.7)),
        "red": Material(albedo: (0.6, 0.1, 0.1)),
    }},
    objects: [
{objects}
    ],
    lights: [
{lights}
    ],
)
"#
    )
}

const SPHERE: &str = r#"        Sphere(center: (0.0, 0.0, 0.0), radius: 0.5, material: "white"),"#;
const LIGHT: &str =
    r#"        SphereLight(center: (0.0, 0.8, 0.0), radius: 0.1, radiance: (1.0, 1.0, 1.0)),"#;

/// Parses `text` as `/nowhere/bad.ron`; the error's Display must name the
/// file and `line`, and contain `needle`.
fn expect_err(text: &str, line: usize, needle: &str) -> String {
    expect_err_at(text, Path::new("/nowhere/bad.ron"), line, needle)
}

fn expect_err_at(text: &str, path: &Path, line: usize, needle: &str) -> String {
    let msg = match parse(text, path) {
        Ok(_) => panic!("expected an error containing {needle:?}"),
        Err(e) => e.to_string(),
    };
    let at = format!("{}:{line}:", path.display());
    assert!(msg.starts_with(&at), "{msg:?} should start with {at:?}");
    assert!(msg.contains(needle), "{msg:?} should contain {needle:?}");
    msg
}

/// A fresh folder under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("glint-scene-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn shipped_scenes_load_with_their_features() {
    let f = shipped("cornell.ron").features;
    assert!(f.spheres && f.meshes && f.area_lights && f.specular);
    assert!(!f.point_lights && !f.emissive && !f.motion);

    let f = shipped("cornell-diffuse.ron").features;
    assert!(f.spheres && f.meshes && f.area_lights);
    assert!(!f.specular && !f.point_lights && !f.emissive && !f.motion);

    let f = shipped("cornell-point.ron").features;
    assert!(f.point_lights && f.specular && f.spheres && f.meshes);
    assert!(!f.area_lights && !f.emissive && !f.motion);

    let f = shipped("moving-lights.ron").features;
    assert!(f.motion && f.meshes && f.area_lights);
    assert!(!f.spheres && !f.point_lights && !f.specular && !f.emissive);
}

#[test]
fn cornell_camera_and_background() {
    let s = shipped("cornell.ron");
    assert_eq!(
        s.camera,
        Camera {
            position: glam::DVec3::new(0.0, 0.0, 3.4),
            target: glam::DVec3::ZERO,
            up: Vec3::Y,
            vfov_deg: 40.0
        }
    );
    assert_eq!(s.background, Vec3::ZERO);
    assert!(s.path.ends_with("scenes/cornell.ron"));
}

/// The box around some packed triangles.
fn triangles_box(tris: &[TriangleGpu]) -> Aabb {
    let points: Vec<Vec3> = tris.iter().flat_map(|t| [t.p0, t.p1, t.p2]).map(Vec3::from).collect();
    Aabb::of_points(&points)
}

#[test]
fn cornell_packs_quads_spheres_and_the_light() {
    let s = shipped("cornell.ron");
    assert_eq!(s.triangle_count(), 10);
    let d = s.pack();
    assert_eq!(d.triangles.len(), 10);
    // The five quads, none moving, in one MeshGpu (one BLAS).
    assert_eq!((d.meshes.len(), d.meshes[0].count), (1, 10));
    assert_eq!(d.spheres.len(), 3);
    assert_eq!(d.lights.len(), 1);
    // white, red, green, mirror, then the light's emissive material.
    assert_eq!(d.materials.len(), 5);
    assert_eq!(d.materials[3].specular, 1.0);
    assert_eq!(
        d.materials[4],
        MaterialGpu::thesis([0.0; 3], 0.0, [10.0; 3], 1.0)
    );

    // Quad i's two triangles at 2i, in object order.
    for i in 0..5 {
        let range = 2 * i..2 * i + 2;
        for (t, tn) in d.triangles[range.clone()].iter().zip(&d.normals[range]) {
            assert_eq!(t.object, i as u32);
            assert_eq!((t._pad0, tn._pad1, tn._pad2, tn._pad3), (0, 0.0, 0.0, 0.0));
            // Walls face the inside of the box.
            let centroid = (Vec3::from(t.p0) + Vec3::from(t.p1) + Vec3::from(t.p2)) / 3.0;
            let n = Vec3::from(tn.n0);
            assert!(n.dot(-centroid) > 0.0, "wall {i} faces outwards");
            let geo =
                (Vec3::from(t.p1) - Vec3::from(t.p0)).cross(Vec3::from(t.p2) - Vec3::from(t.p0));
            assert!(
                geo.normalize().dot(n) > 0.999,
                "normal disagrees with the winding"
            );
        }
    }
    let m = d.meshes[0];
    for k in 0..3 {
        assert!(m.bmin[k] >= -1.0 && m.bmax[k] <= 1.0 && m.bmin[k] <= m.bmax[k]);
    }
    // Red left wall, green right wall.
    assert_eq!(d.triangles[6].material, 1);
    assert_eq!(d.triangles[8].material, 2);

    let [white, mirror, light] = [d.spheres[0], d.spheres[1], d.spheres[2]];
    assert_eq!(
        white,
        SphereGpu {
            center: [-0.4, -0.65, -0.3],
            radius: 0.35,
            material: 0,
            light: -1,
            object: 5,
            _pad: 0
        }
    );
    assert_eq!((mirror.material, mirror.light, mirror.object), (3, -1, 6));
    assert_eq!(
        light,
        SphereGpu {
            center: [0.0, 0.75, 0.0],
            radius: 0.15,
            material: 4,
            light: 0,
            object: 7,
            _pad: 0
        }
    );
    assert_eq!(
        d.lights[0],
        LightGpu {
            position: [0.0, 0.75, 0.0],
            radius: 0.15,
            color: [10.0; 3],
            kind: LIGHT_SPHERE,
            spot: [0.0, 0.0, 0.0, 1.0],
        }
    );

    let n = d.materials.len() as u32;
    assert!(d.triangles.iter().all(|t| t.material < n));
    assert!(d.spheres.iter().all(|s| s.material < n));
    // Packing is deterministic.
    assert_eq!(d, s.pack());
}

#[test]
fn point_light_packs_without_a_sphere() {
    let d = shipped("cornell-point.ron").pack();
    assert_eq!(d.spheres.len(), 2);
    assert_eq!(d.materials.len(), 4);
    let l = d.lights[0];
    assert_eq!(
        (l.kind, l.radius, l.position),
        (LIGHT_POINT, 0.0, [0.0, 0.75, 0.0])
    );
    assert!((l.color[0] - 10.0 * std::f32::consts::PI * 0.15 * 0.15).abs() < 1e-6);
}

#[test]
fn moving_lights_has_the_knot_on_the_floor() {
    let mut s = shipped("moving-lights.ron");
    assert_eq!(s.triangle_count(), 10 + 4000);
    let d = s.pack();
    // The room's five quads and the knot, none moving, in one MeshGpu;
    // the knot's triangles after the quads'.
    assert_eq!(d.meshes.len(), 1);
    assert_eq!((d.meshes[0].first, d.meshes[0].count), (0, 10 + 4000));
    let Aabb { min: lo, max: hi } = triangles_box(&d.triangles[10..]);
    assert!((lo.y + 1.0).abs() < 2e-3, "knot bottom at {}", lo.y);
    assert!(lo.abs().max_element() < 1.0 && hi.abs().max_element() < 1.0);
    // 3 named, the MTL material of knot.obj, 3 emissive light materials.
    assert_eq!(d.materials.len(), 7);
    let kd = d.materials[3];
    assert_eq!((kd.albedo, kd.specular), ([0.8, 0.55, 0.2], 0.0));
    assert!(d.triangles[10..]
        .iter()
        .all(|t| t.material == 3 && t.object == 5));
    assert_eq!(d.normals.len(), d.triangles.len());
    assert!(d
        .normals
        .iter()
        .all(|t| (Vec3::from(t.n1).length() - 1.0).abs() < 1e-4));
    assert_eq!(d.spheres.len(), 3);
    assert_eq!(
        d.spheres.iter().map(|s| s.light).collect::<Vec<_>>(),
        [0, 1, 2]
    );

    // Three lights 120° apart on a circle of radius 0.55 around (0, 0.6, 0).
    let centre = Vec3::new(0.0, 0.6, 0.0);
    let p: Vec<Vec3> = d.lights.iter().map(|l| Vec3::from(l.position)).collect();
    assert!((p[0] - Vec3::new(0.55, 0.6, 0.0)).length() < 1e-5);
    for k in 0..3 {
        assert!(((p[k] - centre).length() - 0.55).abs() < 1e-5);
        assert!(((p[k] - p[(k + 1) % 3]).length() - 0.55 * 3f32.sqrt()).abs() < 1e-4);
    }
    assert!(s.animate(1.0));
    assert_ne!(s.pack().lights[0].position, d.lights[0].position);
}

#[test]
fn animate_moves_an_orbiting_light_and_reports_it() {
    let light = r#"        SphereLight(center: (0.0, 0.75, 0.0), radius: 0.1, radiance: (1.0, 1.0, 1.0),
            motion: Orbit(center: (0.0, 0.75, 0.0), axis: (0.0, 2.0, 0.0), radius: 0.3, period_s: 6.0)),"#;
    let mut s = parse(&scene(SPHERE, light), Path::new("orbit.ron")).unwrap();
    assert!(s.features.motion);
    let at = |s: &Scene| Vec3::from(s.pack().lights[0].position);
    let p0 = at(&s);
    // Loading leaves the scene at t = 0.
    assert!(!s.animate(0.0));
    assert!((p0 - Vec3::new(0.3, 0.75, 0.0)).length() < 1e-6);
    // A quarter period later: a quarter turn, counter-clockwise about +y.
    assert!(s.animate(1.5));
    let p1 = at(&s);
    assert!((p1 - p0).length() - 0.3 * 2f32.sqrt() < 1e-5);
    assert!((p1 - Vec3::new(0.0, 0.75, -0.3)).length() < 1e-5, "{p1}");
    // The visible sphere follows the light.
    assert_eq!(s.pack().spheres[1].center, s.pack().lights[0].position);
    assert!(!s.animate(1.5));
    assert!(!s.animate(f32::NAN));
    // A whole period later it is back.
    assert!(s.animate(6.0));
    assert!((at(&s) - p0).length() < 1e-5);

    let mut still = parse(&scene(SPHERE, LIGHT), Path::new("still.ron")).unwrap();
    assert!(!still.features.motion);
    assert!(!still.animate(3.0));
}

#[test]
fn linear_motion_moves_spheres_and_meshes() {
    let dir = TempDir::new("linear");
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let objects = r#"        Sphere(center: (0.0, 0.0, 0.0), radius: 0.5, material: "white", motion: Linear(velocity: (1.0, 0.0, 0.0))),
        Mesh(path: "tri.obj", translate: (0.0, 0.0, -1.0), motion: Some(Linear(velocity: (0.0, 0.0, 2.0)))),"#;
    let path = dir.0.join("linear.ron");
    let mut s = parse(&scene(objects, ""), &path).unwrap();
    assert!(s.animate(0.5));
    let d = s.pack();
    assert_eq!(d.spheres[0].center, [0.5, 0.0, 0.0]);
    assert_eq!(d.meshes[0].bmin, [0.0, 0.0, 0.0]);
    assert_eq!(d.meshes[0].bmax, [1.0, 1.0, 0.0]);
}

#[test]
fn objects_that_never_move_share_one_mesh_and_movers_keep_their_own() {
    let dir = TempDir::new("runs");
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    // A mover between two still objects, and one after them.
    let objects = r#"        Mesh(path: "tri.obj", translate: (0.0, 0.0, -1.0)),
        Mesh(path: "tri.obj", translate: (0.0, 0.0, -2.0), motion: Some(Linear(velocity: (1.0, 0.0, 0.0)))),
        Quad(vertices: [(0.0, 0.0, -3.0), (1.0, 0.0, -3.0), (1.0, 1.0, -3.0), (0.0, 1.0, -3.0)], material: "white"),
        Mesh(path: "tri.obj", translate: (0.0, 0.0, -4.0), motion: Some(Linear(velocity: (0.0, 1.0, 0.0)))),"#;
    let mut s = parse(&scene(objects, ""), &dir.0.join("runs.ron")).unwrap();
    let d = s.pack();
    // The still triangle and quad first, in one run; then each mover.
    let runs: Vec<(u32, u32)> = d.meshes.iter().map(|m| (m.first, m.count)).collect();
    assert_eq!(runs, vec![(0, 3), (3, 1), (4, 1)]);
    assert_eq!((d.meshes[0].bmin, d.meshes[0].bmax), ([0.0, 0.0, -3.0], [1.0, 1.0, -1.0]));
    assert_eq!(d.triangles[3].object, 1);
    assert_eq!(d.triangles[4].object, 3);
    // Motion moves its own run alone.
    assert!(s.animate(1.0));
    let moved = s.pack();
    assert_eq!(moved.meshes[0].bmin, d.meshes[0].bmin);
    assert_eq!((moved.meshes[1].bmin, moved.meshes[2].bmin), ([1.0, 0.0, -2.0], [0.0, 1.0, -4.0]));
}

#[test]
fn meshes_transform_and_take_materials() {
    let dir = TempDir::new("mesh");
    // No normals, no MTL: flat normals and the default white.
    dir.write(
        "plain.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n",
    );
    dir.write(
        "lib.mtl",
        "newmtl shiny\nKd 0.2 0.4 0.6\nKs 0.5 0.5 0.5\nNs 48\nKe 0 0 2\n",
    );
    dir.write(
        "mtl.obj",
        "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nusemtl shiny\nf 1//1 2//1 3//1\n",
    );
    let objects = r#"        Mesh(path: "plain.obj", translate: (1.0, 2.0, 3.0), scale: 2.0, rotate_deg: (0.0, 90.0, 0.0)),
        Mesh(path: "mtl.obj"),
        Mesh(path: "mtl.obj", material: "red"),
        Mesh(path: "plain.obj", translate: (0.0, -1.0, 0.0)),"#;
    let s = parse(&scene(objects, ""), &dir.0.join("m.ron")).unwrap();
    // plain.obj is loaded once; mtl.obj once per material choice.
    assert_eq!(s.meshes().len(), 3);
    assert_eq!(s.triangle_count(), 2 + 1 + 1 + 2);
    let d = s.pack();
    // white, red, default white (plain.obj), shiny (mtl.obj).
    assert_eq!(d.materials.len(), 4);
    assert_eq!(d.materials[2].albedo, [0.8; 3]);
    let shiny = d.materials[3];
    assert_eq!(
        (shiny.albedo, shiny.specular, shiny.emission),
        ([0.2, 0.4, 0.6], 0.5, [0.0, 0.0, 2.0])
    );
    assert!((shiny.roughness - 0.2).abs() < 1e-6);
    assert!(s.features.specular && s.features.emissive && s.features.meshes);

    // Rotated 90° about y: local +x goes to -z; scale 2; then translated.
    let t = d.triangles[0];
    assert!(
        (Vec3::from(t.p1) - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-5,
        "{:?}",
        t.p1
    );
    let tn = d.normals[0];
    assert!((Vec3::from(tn.n0) - Vec3::X).length() < 1e-5, "{:?}", tn.n0);
    assert_eq!(t.material, 2);
    // The first object's two triangles span z from 1 and y up to 4 (the
    // four objects, none moving, share one MeshGpu: its box spans them all).
    let Aabb { min: lo, max: hi } = triangles_box(&d.triangles[..2]);
    assert!((lo.z - 1.0).abs() < 1e-5 && (hi.y - 4.0).abs() < 1e-5, "{lo} {hi}");
    assert_eq!((d.meshes.len(), d.meshes[0].count), (1, 6));
    assert_eq!(d.triangles[2].material, 3);
    assert_eq!(d.triangles[3].material, 1);
    assert_eq!(
        (d.triangles[4].object, d.triangles[4].p0),
        (3, [0.0, -1.0, 0.0])
    );
}

#[test]
fn material_ids_follow_file_order() {
    let text = scene(SPHERE, "").replace(
        r#""white": Material(albedo: (0.7, 0.7, 0.7)),"#,
        r#""zeta": Material(albedo: (0.1, 0.1, 0.1)), "white": Material(albedo: (0.7, 0.7, 0.7)),"#,
    );
    let d = parse(&text, Path::new("order.ron")).unwrap().pack();
    assert_eq!(d.spheres[0].material, 1);
    assert_eq!(d.materials[1].albedo, [0.7; 3]);
}

#[test]
fn emissive_objects_are_a_feature_but_light_spheres_are_not() {
    let text = scene(SPHERE, LIGHT).replace(
        "(0.6, 0.1, 0.1))",
        "(0.6, 0.1, 0.1), emission: (1.0, 0.0, 0.0))",
    );
    // The emissive material is defined but unused.
    assert!(!parse(&text, Path::new("e.ron")).unwrap().features.emissive);
    let text = text.replace(r#"material: "white""#, r#"material: "red""#);
    assert!(parse(&text, Path::new("e.ron")).unwrap().features.emissive);
}

#[test]
fn minimal_scene_uses_defaults() {
    let s = parse(
        "Scene(camera: Camera(position: (0.0, 0.0, 1.0), target: (0.0, 0.0, 0.0), vfov_deg: 60))",
        Path::new("min.ron"),
    )
    .unwrap();
    assert_eq!(s.camera.up, Vec3::Y);
    assert_eq!(s.features, SceneFeatures::default());
    assert_eq!(s.pack(), SceneData::default());
    assert_eq!(s.triangle_count(), 0);
}

// ---- errors ----

#[test]
fn unknown_material_names_the_line_and_the_choices() {
    let objects = format!("{SPHERE}\n        Sphere(center: (1.0, 0.0, 0.0), radius: 0.5,\n            material: \"foo\"),");
    expect_err(
        &scene(&objects, ""),
        10,
        r#"unknown material "foo"; the scene defines: white, red"#,
    );
    let quad = r#"        Quad(vertices: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)], material: "blue"),"#;
    expect_err(
        &scene(quad, ""),
        8,
        r#"objects[0] (Quad): unknown material "blue""#,
    );
    let mesh = r#"        Mesh(path: "x.obj", material: "blue"),"#;
    expect_err(&scene(mesh, ""), 8, r#"unknown material "blue""#);
}

#[test]
fn bad_sphere_radii_are_reported() {
    for (radius, shown) in [
        ("NaN", "NaN"),
        ("-0.5", "-0.5"),
        ("0.0", "0"),
        ("inf", "inf"),
        ("-inf", "-inf"),
    ] {
        let objects = format!("{SPHERE}\n{}", SPHERE.replace("0.5", radius));
        let msg = expect_err(
            &scene(&objects, ""),
            9,
            "objects[1] (Sphere): `radius` must be a positive finite number",
        );
        assert!(msg.ends_with(&format!("got {shown}")), "{msg}");
    }
}

#[test]
fn bad_lights_are_reported() {
    let light = LIGHT.replace("radius: 0.1", "radius: NaN");
    expect_err(
        &scene(SPHERE, &format!("{LIGHT}\n{light}")),
        12,
        "lights[1] (SphereLight): `radius`",
    );
    let light = LIGHT.replace("radius: 0.1", "radius: -0.1");
    expect_err(
        &scene(SPHERE, &light),
        11,
        "lights[0] (SphereLight): `radius`",
    );
    let light = LIGHT.replace("radiance: (1.0, 1.0, 1.0)", "radiance: (1.0, -1.0, 1.0)");
    expect_err(
        &scene(SPHERE, &light),
        11,
        "`radiance` must not be negative",
    );
    let point =
        "        PointLight(position: (0.0, 0.5, 0.0),\n            intensity: (1.0, 1.0, -2.0)),";
    expect_err(
        &scene(SPHERE, point),
        12,
        "lights[0] (PointLight): `intensity` must not be negative",
    );
    let point = "        PointLight(position: (0.0, NaN, 0.0), intensity: (1.0, 1.0, 1.0)),";
    expect_err(
        &scene(SPHERE, point),
        11,
        "`position` has a NaN or infinite component",
    );
}

#[test]
fn a_zero_radius_sphere_light_points_at_point_lights() {
    let light = LIGHT.replace("radius: 0.1", "radius: 0.0");
    expect_err(&scene(SPHERE, &light), 11, "lights[0] (SphereLight): a sphere light of radius 0 has no area to emit from; for a light without size write PointLight");
}

#[test]
fn nan_in_vectors_is_reported() {
    let objects = SPHERE.replace("center: (0.0, 0.0, 0.0)", "center: (0.0, NaN, 0.0)");
    expect_err(
        &scene(&objects, ""),
        8,
        "objects[0] (Sphere): `center` has a NaN or infinite component",
    );
    let text = scene(SPHERE, "").replace("target: (0.0, 0.0, 0.0)", "target: (0.0, inf, 0.0)");
    expect_err(&text, 2, "camera: `target`");
    let text = scene(SPHERE, "").replace("(0.7, 0.7, 0.7)", "(0.7, NaN, 0.7)");
    expect_err(&text, 4, "material \"white\": `albedo`");
    let mesh = r#"        Mesh(path: "x.obj", translate: (0.0, 0.0, NaN)),"#;
    expect_err(&scene(mesh, ""), 8, "objects[0] (Mesh): `translate`");
    let mesh = r#"        Mesh(path: "x.obj", scale: 0.0),"#;
    expect_err(&scene(mesh, ""), 8, "objects[0] (Mesh): `scale`");
}

#[test]
fn bad_camera_is_reported() {
    for fov in ["0.0", "180.0", "NaN", "-10.0"] {
        let text = scene(SPHERE, "").replace("vfov_deg: 40.0", &format!("vfov_deg: {fov}"));
        expect_err(&text, 2, "camera: `vfov_deg` must be in (0, 180)");
    }
    let text = scene(SPHERE, "").replace("(0.0, 0.0, 3.4)", "(0.0, 0.0, 0.0)");
    expect_err(&text, 2, "must differ from `position`");
    let text = scene(SPHERE, "").replace("vfov_deg: 40.0", "vfov_deg: 40.0, up: (0.0, 0.0, 1.0)");
    expect_err(&text, 2, "camera: `up`");
}

#[test]
fn bad_materials_are_reported() {
    let text = scene(SPHERE, "").replace("(0.6, 0.1, 0.1))", "(0.6, 0.1, 0.1), specular: 1.5)");
    expect_err(
        &text,
        5,
        "material \"red\": `specular` must be in 0..1, got 1.5",
    );
    let text = scene(SPHERE, "").replace("(0.6, 0.1, 0.1))", "(2.0, 0.1, 0.1))");
    expect_err(
        &text,
        5,
        "material \"red\": `albedo` components must be in 0..1",
    );
    let text = scene(SPHERE, "").replace("(0.6, 0.1, 0.1))", "(0.6, 0.1, 0.1), metallic: 1.2)");
    expect_err(&text, 5, "material \"red\": `metallic` must be in 0..1, got 1.2");
    let text = scene(SPHERE, "").replace("(0.6, 0.1, 0.1))", "(0.6, 0.1, 0.1), specular: 0.5, metallic: 1.0)");
    expect_err(&text, 5, "material \"red\": a material has `specular` (the thesis material) or `metallic`");
    let text = scene(SPHERE, "").replace("\"red\"", "\"white\"");
    expect_err(&text, 5, "material \"white\" is defined twice");
    let text = scene(SPHERE, "").replace(
        "vfov_deg: 40.0),",
        "vfov_deg: 40.0),\n    background: (-1.0, 0.0, 0.0),",
    );
    expect_err(&text, 3, "scene: `background` must not be negative");
}

#[test]
fn bad_quads_are_reported() {
    let flat = r#"        Quad(vertices: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (3.0, 0.0, 0.0)], material: "white"),"#;
    expect_err(
        &scene(&format!("{SPHERE}\n{flat}"), ""),
        9,
        "objects[1] (Quad): the quad is degenerate (zero area)",
    );
    let three = r#"        Quad(vertices: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 1.0, 0.0)], material: "white"),"#;
    expect_err(
        &scene(three, ""),
        8,
        "a quad needs exactly 4 vertices, got 3",
    );
}

#[test]
fn bad_motion_is_reported() {
    let orbit = |args: &str| {
        format!(
            "{LIGHT}\n        PointLight(position: (0.0, 0.5, 0.0), intensity: (1.0, 1.0, 1.0),\n            motion: Orbit({args})),"
        )
    };
    for period in ["0.0", "-2.0", "NaN", "inf"] {
        let args = format!("center: (0.0, 0.0, 0.0), axis: (0.0, 1.0, 0.0), radius: 0.3,\n                period_s: {period}");
        expect_err(
            &scene(SPHERE, &orbit(&args)),
            14,
            "lights[1] (PointLight) Orbit: `period_s` must be a positive",
        );
    }
    let args = "center: (0.0, 0.0, 0.0), axis: (0.0, 0.0, 0.0), radius: 0.3, period_s: 1.0";
    expect_err(
        &scene(SPHERE, &orbit(args)),
        13,
        "Orbit: `axis` must not be zero",
    );
    let args = "center: (0.0, 0.0, 0.0), axis: (0.0, 1.0, 0.0), radius: -0.3, period_s: 1.0";
    expect_err(
        &scene(SPHERE, &orbit(args)),
        13,
        "Orbit: `radius` must be a finite number >= 0, got -0.3",
    );
    let objects = SPHERE.replace(
        "material",
        "motion: Linear(velocity: (NaN, 0.0, 0.0)), material",
    );
    expect_err(
        &scene(&objects, ""),
        8,
        "objects[0] (Sphere) Linear: `velocity` has a NaN",
    );
}

#[test]
fn ron_errors_have_line_and_column() {
    let objects = format!("{SPHERE}\n        Sphere(center: (1.0, 0.0, 0.0), radius: 0.5, material: \"white\", colour: 3),");
    let msg = expect_err(&scene(&objects, ""), 9, "colour");
    assert!(msg.starts_with("/nowhere/bad.ron:9:73:"), "{msg}");
    let text = scene(SPHERE, "").replace("vfov_deg", "fov");
    expect_err(&text, 2, "fov");
    let text = scene(SPHERE, "").replace("(0.7, 0.7, 0.7)),", "(0.7, 0.7 0.7)),");
    expect_err(&text, 4, "bad.ron:4:");
    let objects = "        Cube(size: 1.0),";
    expect_err(&scene(objects, ""), 8, "Cube");
    let text = scene(SPHERE, "") + "junk";
    expect_err(&text, 13, "trailing");
    expect_err("", 1, "bad.ron:1:");
}

#[test]
fn missing_files_are_reported() {
    let mesh = "        Mesh(path: \"meshes/missing.obj\",\n            scale: 2.0),";
    let msg = expect_err(
        &scene(mesh, ""),
        8,
        "objects[0] (Mesh): mesh file \"meshes/missing.obj\" not found",
    );
    assert!(msg.contains("/nowhere/meshes/missing.obj"), "{msg}");

    let missing = Path::new("/nowhere/at-all.ron");
    let msg = match load(missing) {
        Ok(_) => panic!("loaded a missing file"),
        Err(e) => e.to_string(),
    };
    assert!(
        msg.starts_with("/nowhere/at-all.ron: cannot read the scene file"),
        "{msg}"
    );
}

#[test]
fn corrupt_objs_are_reported() {
    let dir = TempDir::new("corrupt");
    let scene_path = dir.0.join("c.ron");
    let cases = [
        (
            "syntax.obj",
            "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n",
            "position parse error",
        ),
        (
            "range.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
            "out of bounds",
        ),
        ("empty.obj", "# nothing here\nv 0 0 0\n", "has no triangles"),
        (
            "flat.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
            "has no triangles",
        ),
        (
            "nan.obj",
            "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n",
            "is not finite",
        ),
        (
            "inf.obj",
            "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n",
            "is not finite",
        ),
        ("binary.obj", "\u{0}\u{1}\u{2}garbage\u{ff}\n", ""),
    ];
    for (name, text, needle) in cases {
        let obj = dir.write(name, text);
        let mesh = format!("        Mesh(path: \"{name}\"),");
        let msg = expect_err_at(&scene(&mesh, ""), &scene_path, 8, needle);
        assert!(msg.contains(&obj.display().to_string()), "{msg}");
    }
}

#[test]
fn obj_without_mtl_library_falls_back() {
    let dir = TempDir::new("nomtl");
    dir.write(
        "t.obj",
        "mtllib gone.mtl\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let s = parse(
        &scene("        Mesh(path: \"t.obj\"),", ""),
        &dir.0.join("s.ron"),
    )
    .unwrap();
    let d = s.pack();
    assert_eq!(d.materials.len(), 3);
    assert_eq!(d.triangles[0].material, 2);
    let s = parse(
        &scene("        Mesh(path: \"t.obj\", material: \"red\"),", ""),
        &dir.0.join("s.ron"),
    )
    .unwrap();
    assert_eq!(s.pack().triangles[0].material, 1);
}

#[test]
fn truncated_scenes_never_panic() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/moving-lights.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    // Every proper prefix of the closing `)` is cut off.
    let whole = text.trim_end().len();
    for end in (0..whole).filter(|&i| text.is_char_boundary(i)) {
        let err = parse(&text[..end], &path).err().map(|e| e.to_string());
        assert!(
            err.is_some_and(|e| e.contains("moving-lights.ron:")),
            "prefix of {end} bytes"
        );
    }
}

#[test]
fn multiplied_lights_are_copies_beside_the_originals() {
    let mut s = shipped("cornell.ron");
    let before = s.pack();
    assert_eq!((before.lights.len(), s.features.lights), (1, 1));
    assert_eq!(s.multiply_lights(3), 2);
    assert_eq!(s.features.lights, 3);
    let after = s.pack();
    assert_eq!(after.lights.len(), 3);
    // Sphere lights are spheres rays hit: two more, as bright, each with
    // its own light index, beside the original and not on it.
    assert_eq!(after.spheres.len(), before.spheres.len() + 2);
    let l0 = after.lights[0];
    for l in &after.lights[1..] {
        assert_eq!((l.color, l.radius, l.kind), (l0.color, l0.radius, l0.kind));
        let d = (Vec3::from(l.position) - Vec3::from(l0.position)).length();
        assert!(d > 3.9 * l0.radius && d < 4.1 * l0.radius, "{d}");
        // The light under the ceiling stays under it (copies spread across
        // the line from the box's centre, here horizontally).
        assert!((l.position[1] - l0.position[1]).abs() < 1e-5);
    }
    assert_eq!(s.multiply_lights(1), 0);
}

#[test]
fn cornell_triangles_pair_up_as_quads_in_leaf_order() {
    let s = shipped("cornell.ron");
    let mut d = s.pack();
    crate::bvh::scene::SceneBvh::default().update(&mut d);
    assert!(d.is_flat() && d.flat_pairs(), "the five walls are pairs (a, b, c), (a, c, d)");
    // A pair in the other order, or a lone triangle, is not.
    let mut swapped = d.clone();
    swapped.triangles.swap(0, 1);
    assert!(!swapped.flat_pairs());
    d.triangles.pop();
    assert!(!d.flat_pairs());
}

/// `may_enclose`: whether a sphere light can hold a shading point (its
/// from-inside sampling is compiled out otherwise).
#[test]
fn sphere_lights_that_may_hold_a_shading_point() {
    let parsed = |text: &str| parse(text, Path::new("/nowhere/x.ron")).unwrap_or_else(|e| panic!("{e}"));
    for name in ["cornell.ron", "cornell-point.ron", "thesis-env1.ron"] {
        assert!(!shipped(name).may_enclose(), "{name}");
    }
    // A light apart from the sphere, one reaching into it, one around the
    // camera (at z = 3.4).
    assert!(!parsed(&scene(SPHERE, LIGHT)).may_enclose());
    let touching = r#"        SphereLight(center: (0.0, 0.8, 0.0), radius: 0.31, radiance: (1.0, 1.0, 1.0)),"#;
    assert!(parsed(&scene(SPHERE, touching)).may_enclose());
    let around = r#"        SphereLight(center: (0.0, 0.0, 3.0), radius: 0.5, radiance: (1.0, 1.0, 1.0)),"#;
    assert!(parsed(&scene("", around)).may_enclose());
    // Point lights hold nothing; anything moving may get anywhere.
    let point = r#"        PointLight(position: (0.0, 0.0, 0.0), intensity: (1.0, 1.0, 1.0)),"#;
    assert!(!parsed(&scene(SPHERE, point)).may_enclose());
    assert!(shipped("moving-lights.ron").may_enclose());
}

#[test]
fn environments_are_checked() {
    let env = |e: &str| scene(SPHERE, "").replace("vfov_deg: 40.0),", &format!("vfov_deg: 40.0),\n    environment: {e},"));
    expect_err(&env("Environment(color: (1.0, 1.0, 1.0), path: \"sky.exr\")"), 3, "environment: give `path` (a map) or `color`, not both");
    expect_err(&env("Environment(intensity: 2.0)"), 3, "environment: give `path` (an EXR or PFM latitude-longitude map) or `color`");
    expect_err(&env("Environment(color: (1.0, -1.0, 1.0))"), 3, "environment: `color` must not be negative");
    expect_err(&env("Environment(color: (1.0, 1.0, 1.0), intensity: -2.0)"), 3, "`intensity` must be a finite number >= 0, got -2");
    expect_err(&env("Environment(color: (1.0, 1.0, 1.0), rotation_deg: inf)"), 3, "`rotation_deg` must be finite");
    expect_err(&env("Environment(path: \"nowhere.exr\")"), 3, "environment map file \"nowhere.exr\" not found");
    let both = env("Environment(color: (1.0, 1.0, 1.0))").replace("vfov_deg: 40.0),", "vfov_deg: 40.0),\n    background: (0.1, 0.1, 0.1),");
    expect_err(&both, 4, "give `background` or `environment`, not both");
    // A map that is not a map, and one holding a NaN.
    let dir = TempDir::new("glint-env");
    std::fs::write(dir.0.join("sky.png"), b"not an image").unwrap();
    let path = dir.0.join("scene.ron");
    expect_err_at(&env("Environment(path: \"sky.png\")"), &path, 3, "an environment map must be an .exr or .pfm file");
    let mut pfm = b"PF\n2 1\n-1.0\n".to_vec();
    for v in [1.0f32, 1.0, 1.0, f32::NAN, 0.0, 0.0] {
        pfm.extend(v.to_le_bytes());
    }
    std::fs::write(dir.0.join("nan.pfm"), pfm).unwrap();
    expect_err_at(&env("Environment(path: \"nan.pfm\")"), &path, 3, "\"nan.pfm\": texel (1, 0) (from the top left) is [NaN, 0, 0]: radiance must be finite");
    // An EXR map (what image_io writes), watched for hot reload.
    let mut img = crate::gpu::readback::ImageF32::new(4, 2);
    img.data[5] = [3.0, 2.0, 1.0, 1.0];
    img.data[6] = [-1e-4, 1.0, 1.0, 1.0];
    crate::image_io::save(&img, &dir.0.join("sky.exr")).unwrap();
    let s = parse(&env("Environment(path: \"sky.exr\", intensity: 2.0)"), &path).unwrap();
    let e = s.environment.as_ref().expect("loaded");
    assert_eq!((e.width, e.height, e.radiance[5]), (4, 2, glam::Vec3::new(6.0, 4.0, 2.0)));
    assert_eq!(e.radiance[6], glam::Vec3::new(0.0, 2.0, 2.0), "a small negative component is clamped");
    assert!(s.mesh_files.contains(&dir.0.join("sky.exr")), "{:?}", s.mesh_files);
    // A good one: the last light, sampled; the scene counts it as a light.
    let s = parse(&env("Environment(color: (0.5, 0.5, 0.5), intensity: 2.0, rotation_deg: 90.0)"), Path::new("/nowhere/ok.ron")).unwrap();
    let e = s.environment.as_ref().expect("loaded");
    assert_eq!(e.radiance[0], glam::Vec3::ONE);
    assert!((e.rotation - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    let data = s.pack();
    assert_eq!(data.lights.last().map(|l| l.kind), Some(crate::scene::LIGHT_ENVIRONMENT));
    assert_eq!(data.environment.len(), 32 * 16 + 8 * 16 + 4);
    assert!(!data.is_flat(), "the flat path's occluder lists need light positions");
    assert!(s.features.environment && s.features.point_lights);
}
