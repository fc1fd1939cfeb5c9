//! Ray robustness on the GPU path: rays made of NaN, infinities, zeros and
//! tiny values end as misses (or as valid hits for the finite ones) and the
//! traversal terminates.

mod common;

use common::*;

#[test]
fn special_value_rays_end_as_misses_on_the_gpu() {
    let Some(gpu) = gpu() else { return };
    // moving-lights goes through the BVH; cornell (13 primitives) is flat.
    for scene in ["moving-lights.ron", "cornell.ron"] {
        check_special_rays(gpu, scene);
    }
}

fn check_special_rays(gpu: &glint::gpu::Gpu, scene: &str) {
    let img = render(gpu, load_scene(scene), &repo().join("tests/graphs/ray-tests.ron"), (512, 512), 1, None);
    let special = [0.0f32, -0.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1.0, -1.0, 1e-30];
    let mut finite_hits = 0;
    for (k, px) in img.data.iter().enumerate() {
        let v = |shift: usize| special[(k >> shift) & 7];
        let o = [v(0), v(3), v(6)];
        let d = [v(9), v(12), v(15)];
        assert_ne!(px[3], 2.0, "ray {k} o={o:?} d={d:?}: trace_primary or trace_pair disagrees with trace_closest and trace_any");
        assert_eq!(px[3], 1.0, "ray {k} did not finish");
        let finite = o.iter().chain(d.iter()).all(|x| x.is_finite());
        // Only rays with an origin inside the box region and a real
        // direction can hit; anything with NaN or infinity must miss.
        if !finite {
            assert_eq!((px[0], px[1]), (0.0, 0.0), "non-finite ray {k} o={o:?} d={d:?} reported a hit");
        } else if px[0] == 1.0 {
            assert!(px[2].is_finite() && px[2] > 0.0, "ray {k} hit at t={}", px[2]);
            assert_eq!(px[1], 1.0, "ray {k}: closest hit but no any-hit");
            finite_hits += 1;
        }
    }
    // Axis rays from inside the Cornell box hit the walls.
    assert!(finite_hits > 0);
}

/// The GPU traversal finds exactly what testing every primitive finds:
/// the bench-rays graph's primary hits (point and distance) and its shadow
/// and diffuse results, with and without the BVH (BRUTE_FORCE), bit for
/// bit, on a random triangle soup with spheres in it, on the soup alone
/// (one mesh: traversal may start at its BLAS, ONE_MESH, or go through
/// the TLAS; both are checked) and on a scene file.
#[test]
fn gpu_bvh_matches_brute_force_bit_for_bit() {
    let Some(gpu) = gpu() else { return };
    let dir = scratch("bvh-vs-brute");
    let obj = dir.join("soup.obj");
    std::fs::write(&obj, random_soup(3000, 7)).expect("write soup");
    let room = dir.join("room.obj");
    std::fs::write(&room, random_room(2000, 5)).expect("write room");
    let soup_with = |spheres: &str| soup_scene(&obj, spheres);
    let spheres = r#"Sphere(center: (0.2, 0.1, 0.3), radius: 0.25, material: "grey"),
                     Sphere(center: (-0.4, -0.3, -0.2), radius: 0.3, material: "grey")"#;
    let size = (96, 96);
    let cases = [
        ("soup", Some(soup_with(spheres)), Traversal::Engine),
        ("cornell, flat: primary rays by the written-out sweep", Some(std::fs::read_to_string(repo().join("scenes/cornell.ron")).expect("read cornell")), Traversal::Engine),
        ("soup alone, from its BLAS", Some(soup_with("")), Traversal::OneMesh(true)),
        ("soup alone, through the TLAS", Some(soup_with("")), Traversal::OneMesh(false)),
        // Its camera inside the soup's box: primary rays start from the
        // camera's entries (src/bvh/entry.rs).
        ("a room of small triangles, camera inside it", Some(soup_scene_at(&room, "", INSIDE)), Traversal::OneMesh(true)),
        ("moving-lights", None, Traversal::Engine),
    ];
    for (name, text, traversal) in cases {
        let scene = || text.as_deref().map_or_else(|| load_scene("moving-lights.ron"), scene_from);
        for output in ["bench_hit", "bench_out", "bench_query"] {
            let bvh = bench_rays(gpu, scene(), size, output, traversal);
            let brute = bench_rays(gpu, scene(), size, output, Traversal::BruteForce);
            let differ = bvh.data.iter().zip(&brute.data).filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits)).count();
            assert_eq!(differ, 0, "{name}: {differ} pixels of {output} differ between the BVH and brute force");
            if output == "bench_hit" {
                let hits = bvh.data.iter().filter(|p| p[3] > 0.0).count();
                assert!(hits > bvh.data.len() / 10, "{name}: only {hits} primary hits; the test would prove little");
            }
        }
    }
}

/// The bench's `query` pass (the hit records alone) traces the same rays
/// as its `primary` pass: the same distances, bit for bit, and the same
/// misses; and its record names the primitive hit: the triangle's point
/// at the record's barycentrics (the triangles as the GPU holds them, in
/// BVH leaf order) is primary's hit point, and a sphere's surface holds
/// it. Through the BVH (one mesh and a scene with spheres) and on a flat
/// scene.
#[test]
fn the_query_pass_finds_what_the_primary_pass_finds() {
    let Some(gpu) = gpu() else { return };
    let dir = scratch("query-vs-primary");
    let obj = dir.join("soup.obj");
    std::fs::write(&obj, random_soup(2000, 11)).expect("write soup");
    let soup = soup_scene(&obj, "");
    let options = glint::graph::CompileOptions { also_compute: vec!["bench_query".into()], keep: vec!["bench_hit".into()], ..Default::default() };
    for name in ["soup", "moving-lights", "cornell"] {
        let scene = if name == "soup" { scene_from(&soup) } else { load_scene(&format!("{name}.ron")) };
        let compiled = compile(&scene, &repo().join("passes/bench-rays.ron"), &options);
        let mut s = session(gpu, scene, &compiled, (64, 48), 1);
        s.frame(0.0);
        let read = |r: &str| s.read_resource(r).unwrap_or_else(|| panic!("{name}: no {r}")).unwrap_or_else(|e| panic!("{e}"));
        let (hit, query) = (read("bench_hit"), read("bench_query"));
        let data = &s.scene.buffers.data;
        let (mut triangles, mut spheres) = (0, 0);
        for (k, (h, q)) in hit.data.iter().zip(&query.data).enumerate() {
            assert_eq!(h[3].to_bits(), q[0].to_bits(), "{name}: pixel {k}: primary's distance {} against the query's {}", h[3], q[0]);
            if q[0] <= 0.0 {
                assert_eq!(*q, [-1.0, 0.0, 0.0, 0.0], "{name}: pixel {k}: a miss");
                continue;
            }
            let p = glam::Vec3::new(h[0], h[1], h[2]);
            let tol = 1e-5 * (1.0 + p.abs().max_element());
            assert_eq!(q[3].fract(), 0.0, "{name}: pixel {k}: primitive {}", q[3]);
            if q[3] >= 0.0 {
                let t = data.triangles.get(q[3] as usize).unwrap_or_else(|| panic!("{name}: pixel {k}: triangle {} of {}", q[3], data.triangles.len()));
                let (u, v) = (q[1], q[2]);
                let at = (1.0 - u - v) * glam::Vec3::from(t.p0) + u * glam::Vec3::from(t.p1) + v * glam::Vec3::from(t.p2);
                assert!(at.distance(p) <= tol, "{name}: pixel {k}: triangle {} at ({u}, {v}) is {at}, primary hit {p}", q[3]);
                triangles += 1;
            } else {
                let i = (-1.0 - q[3]) as usize;
                let sp = data.spheres.get(i).unwrap_or_else(|| panic!("{name}: pixel {k}: sphere {i} of {}", data.spheres.len()));
                let off = p.distance(glam::Vec3::from(sp.center)) - sp.radius;
                assert!(off.abs() <= tol * (1.0 + sp.radius), "{name}: pixel {k}: sphere {i}'s surface is {off} from primary's hit {p}");
                spheres += 1;
            }
        }
        assert!(triangles + spheres > hit.data.len() / 10, "{name}: only {triangles} + {spheres} hits; the test would prove little");
        if name == "moving-lights" {
            assert!(triangles > 0 && spheres > 0, "{name}: {triangles} triangle and {spheres} sphere hits; both kinds should be checked");
        }
    }
}

/// How the bench-rays graph traces: as the engine specialises it for the
/// scene, with ONE_MESH set either way, or testing every primitive.
#[derive(Clone, Copy)]
enum Traversal {
    Engine,
    OneMesh(bool),
    BruteForce,
}

fn bench_rays(gpu: &glint::gpu::Gpu, scene: glint::scene::Scene, size: (u32, u32), output: &str, traversal: Traversal) -> glint::gpu::readback::ImageF32 {
    let options = glint::graph::CompileOptions { output: Some(output.to_string()), ..Default::default() };
    let mut compiled = compile(&scene, &repo().join("passes/bench-rays.ron"), &options);
    let constant = match traversal {
        Traversal::Engine => None,
        Traversal::OneMesh(on) => Some(("ONE_MESH", f64::from(u8::from(on)))),
        Traversal::BruteForce => Some(("BRUTE_FORCE", 1.0)),
    };
    for pass in &mut compiled.schedule.passes {
        pass.constants.extend(constant.map(|(k, v)| (k.to_string(), v)));
    }
    render_compiled(gpu, scene, &compiled, size, 1)
}

/// A scene of the OBJ `obj` in grey, seen from (0.3, 0.2, 3), with the
/// objects `more` (RON, may be empty) beside it.
fn soup_scene(obj: &std::path::Path, more: &str) -> String {
    soup_scene_at(obj, more, "position: (0.3, 0.2, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 45.0")
}

/// A camera inside `random_soup`'s box, looking across it.
const INSIDE: &str = "position: (0.1, 0.05, 0.2), target: (1.0, -0.2, -0.6), vfov_deg: 60.0";

/// `soup_scene` seen from `camera` (its position and target in RON).
fn soup_scene_at(obj: &std::path::Path, more: &str, camera: &str) -> String {
    format!(
        r#"Scene(
            camera: Camera({camera}),
            materials: {{ "grey": Material(albedo: (0.5, 0.5, 0.5)) }},
            objects: [ Mesh(path: "{}", material: "grey"), {more} ],
        )"#,
        obj.display()
    )
}

/// `n` random triangles (some long and thin) in [-1, 1]^3 as OBJ text.
fn random_soup(n: usize, seed: u64) -> String {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    };
    let mut text = String::new();
    for i in 0..n {
        let c = [next(), next(), next()];
        let size = if i % 7 == 0 { 0.8 } else { 0.08 };
        for _ in 0..3 {
            text += &format!("v {} {} {}\n", c[0] + size * next(), c[1] + size * next(), c[2] + size * next());
        }
        text += &format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
    }
    text
}

/// The camera inside the room has entries, so the case above tests them.
#[test]
fn a_camera_inside_the_room_has_entries() {
    let dir = scratch("room-entries");
    let obj = dir.join("room.obj");
    std::fs::write(&obj, random_room(2000, 5)).expect("write room");
    let scene = scene_from(&soup_scene_at(&obj, "", INSIDE));
    let mut data = scene.pack();
    glint::bvh::scene::SceneBvh::default().update(&mut data);
    let camera = glam::Vec3::new(0.1, 0.05, 0.2);
    let cut = glint::bvh::entry::camera_cut(&data.bvh, data.instances[0].index, camera).expect("the camera inside the room has a cut");
    assert!(cut.len() >= 4, "{} entries", cut.len());
}

/// The six walls of the box [-2, 2]^3 as two triangles each, and `n`
/// small random triangles inside it (clutter), as OBJ text.
fn random_room(n: usize, seed: u64) -> String {
    let mut text = String::new();
    for i in 0..8 {
        let c = |bit: usize| if i & bit == 0 { -2.0 } else { 2.0 };
        text += &format!("v {} {} {}\n", c(1), c(2), c(4));
    }
    for [a, b, c, d] in [[1, 2, 4, 3], [5, 6, 8, 7], [1, 2, 6, 5], [3, 4, 8, 7], [1, 3, 7, 5], [2, 4, 8, 6]] {
        text += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
    }
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    };
    for i in 0..n {
        let c = [1.8 * next(), 1.8 * next(), 1.8 * next()];
        for _ in 0..3 {
            text += &format!("v {} {} {}\n", c[0] + 0.06 * next(), c[1] + 0.06 * next(), c[2] + 0.06 * next());
        }
        text += &format!("f {} {} {}\n", 9 + 3 * i, 10 + 3 * i, 11 + 3 * i);
    }
    text
}
