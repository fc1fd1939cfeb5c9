use super::*;
use crate::scene::{SphereGpu, TriangleGpu};

fn triangle(p0: [f32; 3], p1: [f32; 3], p2: [f32; 3]) -> TriangleGpu {
    TriangleGpu { p0, material: 0, p1, object: 0, p2, _pad0: 0 }
}

/// A quad as two triangles (a, b, c) and (a, c, d).
fn quad(a: [f32; 3], b: [f32; 3], c: [f32; 3], d: [f32; 3]) -> [TriangleGpu; 2] {
    [triangle(a, b, c), triangle(a, c, d)]
}

fn sphere(center: [f32; 3], radius: f32) -> SphereGpu {
    SphereGpu { center, radius, material: 0, light: -1, object: 0, _pad: 0 }
}

fn light(position: [f32; 3], radius: f32) -> LightGpu {
    LightGpu { position, radius, color: [1.0; 3], kind: 1, spot: [0.0, 0.0, 0.0, 1.0] }
}

fn view(camera: [f32; 3]) -> Viewpoints {
    Viewpoints { camera: camera.into(), probes: None, pixels: None }
}

/// The occluder list of light `i` in `table`.
fn occluders(table: &[[u32; 4]], i: usize) -> Vec<u32> {
    let at = ORIGIN_ROWS * ORIGIN_ROW_TEXELS + i * OCCLUDER_ROW_TEXELS;
    (0..table[at][0] as usize).map(|j| table[at + 1 + j][0]).collect()
}

/// The Cornell box's five walls (open at +z) and two spheres.
fn cornell() -> SceneData {
    let mut triangles = Vec::new();
    triangles.extend(quad([-1.0, -1.0, -1.0], [-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [1.0, -1.0, -1.0]));
    triangles.extend(quad([-1.0, 1.0, -1.0], [1.0, 1.0, -1.0], [1.0, 1.0, 1.0], [-1.0, 1.0, 1.0]));
    triangles.extend(quad([-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [1.0, 1.0, -1.0], [-1.0, 1.0, -1.0]));
    triangles.extend(quad([-1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, 1.0, 1.0], [-1.0, -1.0, 1.0]));
    triangles.extend(quad([1.0, -1.0, -1.0], [1.0, -1.0, 1.0], [1.0, 1.0, 1.0], [1.0, 1.0, -1.0]));
    let spheres = vec![sphere([-0.4, -0.65, -0.3], 0.35), sphere([0.45, -0.65, 0.25], 0.35), sphere([0.0, 0.75, 0.0], 0.15)];
    SceneData { triangles, spheres, lights: vec![light([0.0, 0.75, 0.0], 0.15)], ..Default::default() }
}

#[test]
fn rows_hold_each_triangle_seen_from_the_camera_and_light_0() {
    let data = cornell();
    let camera = [0.5, 0.0, 4.0];
    let table = origin_table(&data, &view(camera), true);
    assert_eq!(table.len(), ORIGIN_TABLE_TEXELS);
    let t = &data.triangles[1];
    let from = |o: [f32; 3]| origin_edges(t.p0.into(), t.p1.into(), t.p2.into(), o.into()).map(|e| e.map(f32::to_bits));
    assert_eq!(table[3..6], from(camera));
    let l = data.lights[0].position;
    assert_eq!(table[ORIGIN_ROW_TEXELS + 3..ORIGIN_ROW_TEXELS + 6], from(l));
    // Unused slots stay zero: their edge functions are 0, det 0, a miss.
    assert_eq!(table[3 * data.triangles.len()], [0; 4]);
    // The shaders' layout.
    let wgsl = include_str!("../../../shaders/shared/scene.wgsl");
    for (name, value) in [
        ("ORIGIN_ROW_TEXELS", ORIGIN_ROW_TEXELS),
        ("ORIGIN_ROWS", ORIGIN_ROWS),
        ("ORIGIN_LIGHT", ORIGIN_LIGHT),
        ("OCCLUDER_LIGHTS", OCCLUDER_LIGHTS),
        ("OCCLUDER_ROW_TEXELS", OCCLUDER_ROW_TEXELS),
    ] {
        assert!(wgsl.contains(&format!("const {name}: u32 = {value}u;")), "scene.wgsl's {name} is {value}");
    }
}

#[test]
fn a_room_around_its_light_shadows_nothing_from_it() {
    let data = cornell();
    // Seen from in front of the open side: no wall can block the light.
    let table = origin_table(&data, &view([0.0, 0.0, 3.4]), true);
    assert_eq!(occluders(&table, 0), Vec::<u32>::new());
    // A camera behind the back wall sees its back, which the wall shadows.
    let table = origin_table(&data, &view([0.0, 0.0, -3.0]), true);
    assert_eq!(occluders(&table, 0), vec![4, 5]);
    // So does a probe box that reaches through the floor.
    let probes = Viewpoints { camera: Vec3::new(0.0, 0.0, 3.4), probes: Some((Vec3::splat(-0.8), Vec3::new(0.8, -1.2, 0.8))), pixels: None };
    assert_eq!(occluders(&origin_table(&data, &probes, true), 0), vec![0, 1]);
    // Without culling, every triangle.
    let all = origin_table(&data, &view([0.0, 0.0, 3.4]), false);
    assert_eq!(occluders(&all, 0), (0..10).collect::<Vec<u32>>());
}

#[test]
fn only_planes_with_something_behind_them_shadow() {
    let floor = quad([-2.0, 0.0, -2.0], [-2.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0]);
    let card = quad([-0.5, 0.5, 0.0], [0.5, 0.5, 0.0], [0.5, 1.5, 0.0], [-0.5, 1.5, 0.0]);
    let mut triangles = floor.to_vec();
    triangles.extend(card);
    let data = SceneData {
        triangles,
        spheres: vec![sphere([0.0, 0.5, -1.0], 0.4)],
        lights: vec![light([0.0, 2.0, 2.0], 0.1), light([0.0, 0.0, 3.0], 0.5)],
        ..Default::default()
    };
    let table = origin_table(&data, &view([0.0, 1.0, 5.0]), true);
    // Light 0 is above the floor with everything else: the floor shadows
    // nothing; the card has the sphere behind it.
    assert_eq!(occluders(&table, 0), vec![2, 3]);
    // Light 1 straddles the floor's plane: the floor may shadow.
    assert_eq!(occluders(&table, 1), vec![0, 1, 2, 3]);
    // A camera under the floor sees its underside.
    assert_eq!(occluders(&origin_table(&data, &view([0.0, -1.0, 5.0]), true), 0), vec![0, 1, 2, 3]);
    // A collapsed triangle blocks nothing.
    let p = [0.3, 0.3, 0.3];
    let dot = SceneData { triangles: vec![triangle(p, p, p)], lights: vec![light([0.0; 3], 0.0)], ..Default::default() };
    assert_eq!(occluders(&origin_table(&dot, &view([1.0; 3]), true), 0), Vec::<u32>::new());
}

#[test]
fn scenes_beyond_the_flat_limit_and_lights_past_the_table_have_no_rows() {
    let t = triangle([-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [0.0, 1.0, -1.0]);
    let big = SceneData { triangles: vec![t], spheres: vec![sphere([0.0; 3], 1.0); FLAT_LIMIT], lights: vec![light([0.0; 3], 0.1)], ..Default::default() };
    assert!(origin_table(&big, &view([0.0; 3]), true).iter().all(|t| *t == [0; 4]));
    let dark = SceneData { triangles: vec![t], ..Default::default() };
    let table = origin_table(&dark, &view([0.0, 0.0, 3.0]), true);
    assert_ne!(table[0], [0; 4]);
    assert!(table[ORIGIN_ROW_TEXELS..].iter().all(|t| *t == [0; 4]));
    let many = SceneData { triangles: vec![t], lights: vec![light([0.0, 0.0, 2.0], 0.1); OCCLUDER_LIGHTS + 2], ..Default::default() };
    let table = origin_table(&many, &view([0.0, 0.0, 3.0]), false);
    assert_eq!(occluders(&table, OCCLUDER_LIGHTS - 1), vec![0]);
}
