//! Watertight on the GPU path (issue 12, part 7), at Embree's own test
//! location: a sphere tessellated 500x500 (shared vertices, 499,000
//! triangles) of radius 2 centred at (148376, 1234, -223423), and 1e6 rays
//! in random directions from its centre. Every ray must hit it: closest
//! hit and any hit, 0 misses (Embree's `verify` allows 0.002%).
//!
//! Traced twice: as glint renders (the world rebased on the camera, so the
//! sphere sits near the GPU's origin), and with the origin pinned at the
//! world origin, where the vertices are f32 world coordinates 1/64 apart
//! (Embree's setting): the watertight triangle test alone has to close the
//! mesh there. The same for a flat icosahedron, whose camera rays and
//! shadow rays from a light at the centre take shared/origins.wgsl.

mod common;

use common::*;
use glam::DVec3;
use std::fmt::Write;

const CENTRE: [f64; 3] = [148376.0, 1234.0, -223423.0];
const RADIUS: f64 = 2.0;
const N: usize = 500;

/// A UV sphere as OBJ text: `N - 1` rings of `N` shared vertices plus the
/// poles, computed in f64 and written as the f32 they round to.
fn sphere_obj() -> String {
    use std::f64::consts::{PI, TAU};
    let c = DVec3::from_array(CENTRE);
    let mut out = String::new();
    let mut vertex = |p: DVec3| {
        let p = p.as_vec3();
        let _ = writeln!(out, "v {:?} {:?} {:?}", p.x, p.y, p.z);
    };
    vertex(c + DVec3::new(0.0, RADIUS, 0.0));
    for i in 1..N {
        let th = PI * i as f64 / N as f64;
        for j in 0..N {
            let ph = TAU * j as f64 / N as f64;
            vertex(c + RADIUS * DVec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()));
        }
    }
    vertex(c - DVec3::new(0.0, RADIUS, 0.0));
    // OBJ indices count from 1.
    let south = 2 + (N - 1) * N;
    let ring = |i: usize, j: usize| 2 + (i - 1) * N + j % N;
    for j in 0..N {
        let _ = writeln!(out, "f 1 {} {}", ring(1, j + 1), ring(1, j));
        for i in 1..N - 1 {
            let _ = writeln!(out, "f {} {} {}", ring(i, j), ring(i, j + 1), ring(i + 1, j + 1));
            let _ = writeln!(out, "f {} {} {}", ring(i, j), ring(i + 1, j + 1), ring(i + 1, j));
        }
        let _ = writeln!(out, "f {south} {} {}", ring(N - 1, j), ring(N - 1, j + 1));
    }
    out
}

/// An icosahedron of radius `RADIUS` about `CENTRE` (20 triangles: a flat
/// scene, traced without a BVH), its vertices the f32 they round to.
fn icosahedron_obj() -> String {
    let c = DVec3::from_array(CENTRE);
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut out = String::new();
    let corners = [(-1.0, g, 0.0), (1.0, g, 0.0), (-1.0, -g, 0.0), (1.0, -g, 0.0), (0.0, -1.0, g), (0.0, 1.0, g), (0.0, -1.0, -g), (0.0, 1.0, -g), (g, 0.0, -1.0), (g, 0.0, 1.0), (-g, 0.0, -1.0), (-g, 0.0, 1.0)];
    for (x, y, z) in corners {
        let p = (c + DVec3::new(x, y, z).normalize() * RADIUS).as_vec3();
        let _ = writeln!(out, "v {:?} {:?} {:?}", p.x, p.y, p.z);
    }
    let faces = [
        [1, 12, 6], [1, 6, 2], [1, 2, 8], [1, 8, 11], [1, 11, 12], [2, 6, 10], [6, 12, 5], [12, 11, 3], [11, 8, 7], [8, 2, 9],
        [4, 10, 5], [4, 5, 3], [4, 3, 7], [4, 7, 9], [4, 9, 10], [5, 10, 6], [3, 5, 12], [7, 3, 11], [9, 7, 8], [10, 9, 2],
    ];
    for [a, b, c] in faces {
        let _ = writeln!(out, "f {a} {b} {c}");
    }
    out
}

/// Traces 1e6 rays from the centre of the closed mesh `obj` (with a point
/// light there too), rebased and pinned: every ray must hit it within
/// `inradius`..1.01 radii, and on a flat scene the origin-table paths must agree (test_watertight.wgsl).
fn every_ray_from_inside_hits(name: &str, obj: &str, min_triangles: usize, inradius: f32) {
    let Some(gpu) = gpu() else { return };
    let dir = scratch(name);
    let path = dir.join("mesh.obj");
    std::fs::write(&path, obj).expect("write the mesh");
    let [x, y, z] = CENTRE;
    let text = format!(
        "Scene(camera: Camera(position: ({x:e}, {y:e}, {z:e}), target: ({x:e}, {y:e}, {:e}), vfov_deg: 60.0),\n\
         materials: {{ \"grey\": Material(albedo: (0.5, 0.5, 0.5)) }},\n\
         objects: [ Mesh(path: {:?}, material: \"grey\") ],\n\
         lights: [ PointLight(position: ({x:e}, {y:e}, {z:e}), intensity: (1.0, 1.0, 1.0)) ])",
        z + 1.0,
        path.display().to_string()
    );
    let graph = repo().join("tests/graphs/watertight.ron");
    for pinned in [false, true] {
        let scene = glint::scene::parse(&text, &dir.join("watertight.ron")).unwrap_or_else(|e| panic!("{e}"));
        // Rounded to f32 at 1/64 spacing, the UV sphere's triangles near
        // the poles collapse and the loader drops them; the rest still
        // closes it.
        let triangles = scene.triangle_count();
        assert!(triangles >= min_triangles, "{triangles} triangles");
        let compiled = compile(&scene, &graph, &Default::default());
        let mut s = session(gpu, scene, &compiled, (64, 64), 1);
        // The shadow rays start outside the closed mesh, where no ray the
        // engine traces can reach: every face must be tested, not only the
        // faces that can shadow a reachable point (src/scene/origins.rs).
        s.scene.buffers.cull_occluders = false;
        if pinned {
            s.scene.pin_origin(&gpu.queue, DVec3::ZERO);
        }
        s.frame(0.0);
        let img = s.read_output().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(img.data.len(), 1_000_000);
        let closest = img.data.iter().filter(|p| p[0] != 1.0).count();
        let any = img.data.iter().filter(|p| p[1] != 1.0).count();
        let far = img.data.iter().filter(|p| p[0] == 1.0 && !(p[2] > inradius * RADIUS as f32 && p[2] < 1.01 * RADIUS as f32)).count();
        let flag = |bit: u32| img.data.iter().filter(|p| (p[3] as u32 - 1) & bit != 0).count();
        let (camera, shadow) = (flag(2), flag(4));
        let origin = if pinned { "pinned at the world origin" } else { "rebased on the camera" };
        eprintln!("{name}, origin {origin}: {triangles} triangles, 1e6 rays, {closest} closest misses, {any} any misses, {far} hits off the mesh, {camera} camera rays that differ, {shadow} shadow rays from the light not blocked");
        assert_eq!((closest, any, far, camera, shadow), (0, 0, 0, 0, 0), "origin {origin}: cracks in {name}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_far_tessellated_sphere_is_watertight_on_the_gpu() {
    every_ray_from_inside_hits("watertight", &sphere_obj(), N * N, 0.99);
}

/// A flat scene: the camera's rays and the shadow rays toward the light
/// go through the triangle planes of scene_origins (shared/origins.wgsl).
#[test]
fn a_far_flat_icosahedron_is_watertight_from_the_camera_and_the_light() {
    every_ray_from_inside_hits("watertight-flat", &icosahedron_obj(), 20, 0.79);
}
