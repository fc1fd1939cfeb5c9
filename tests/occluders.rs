//! Shadow rays on flat scenes test only the triangles that can shadow
//! their light at all (src/scene/origins.rs): every graph's image with
//! those lists must equal, bit for bit, its image with every triangle
//! tested, on the Cornell box (where no wall can shadow the light) and on
//! a scene with two lights and a card that shadows.

mod common;

use common::*;

/// A floor, a card standing on it, a sphere behind the card, a sphere
/// light and a point light.
const CARD: &str = r#"Scene(
    camera: Camera(position: (0.0, 1.2, 4.0), target: (0.0, 0.4, 0.0), vfov_deg: 45.0),
    materials: { "white": Material(albedo: (0.7, 0.7, 0.7)), "mirror": Material(albedo: (0.9, 0.9, 0.9), specular: 1.0) },
    objects: [
        Quad(vertices: [(-2.0, 0.0, -2.0), (-2.0, 0.0, 2.0), (2.0, 0.0, 2.0), (2.0, 0.0, -2.0)], material: "white"),
        Quad(vertices: [(-0.5, 0.0, 0.0), (0.5, 0.0, 0.0), (0.5, 1.0, 0.0), (-0.5, 1.0, 0.0)], material: "white"),
        Sphere(center: (0.3, 0.3, -0.8), radius: 0.3, material: "mirror"),
    ],
    lights: [
        SphereLight(center: (0.4, 1.6, 1.2), radius: 0.15, radiance: (10.0, 10.0, 10.0)),
        PointLight(position: (-1.0, 1.5, 0.8), intensity: (3.0, 3.0, 3.0)),
    ],
)"#;

fn render(scene: glint::scene::Scene, graph: &str, cull: bool) -> glint::gpu::readback::ImageF32 {
    let Some(gpu) = gpu() else { unreachable!() };
    let compiled = compile(&scene, &repo().join("passes").join(graph), &Default::default());
    let mut s = session(gpu, scene, &compiled, (64, 48), 7);
    s.scene.buffers.cull_occluders = cull;
    for _ in 0..3 {
        s.frame(0.0);
    }
    s.read_output().unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn occluder_lists_leave_every_image_as_it_was() {
    if gpu().is_none() {
        return;
    }
    for (name, text) in [("cornell", std::fs::read_to_string(repo().join("scenes/cornell.ron")).expect("read cornell")), ("card", CARD.to_string())] {
        for graph in ["hybrid-point.ron", "hybrid.ron", "pathtrace.ron", "direct.ron", "hybrid-gi.ron", "irradiance.ron"] {
            let culled = render(scene_from(&text), graph, true);
            let all = render(scene_from(&text), graph, false);
            let lit = all.data.iter().filter(|p| p[0] > 0.0).count();
            assert!(lit > all.data.len() / 4, "{name} {graph}: {lit} lit pixels");
            let differ = culled.data.iter().zip(&all.data).filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits)).count();
            assert_eq!(differ, 0, "{name} {graph}: {differ} pixels differ with the occluder lists");
        }
    }
}

/// The path tracer's shortcuts on flat scenes leave its image as it was,
/// bit for bit, against the override forced off: bounce rays test a quad's
/// two triangles together (`FLAT_PAIRS`, set by the engine for the Cornell
/// box and the card scene), and shadow rays toward the last light leave
/// out that light's own sphere (`FLAT_LAST_LIGHT_SPHERE`; 32 is none).
#[test]
fn flat_shortcuts_leave_the_path_tracers_image_as_it_was() {
    let Some(gpu) = gpu() else { return };
    let text = std::fs::read_to_string(repo().join("passes/pathtrace.ron")).expect("read pathtrace.ron");
    let cornell = std::fs::read_to_string(repo().join("scenes/cornell.ron")).expect("read cornell");
    let dir = scratch("pairs");
    for (constant, off) in [("FLAT_PAIRS", 0), ("FLAT_LAST_LIGHT_SPHERE", 32)] {
        let forced = text.replace("constants: { FIRST_HIT: 0 }", &format!("constants: {{ FIRST_HIT: 0, {constant}: {off} }}"));
        assert_ne!(forced, text);
        let off_graph = dir.join(format!("pathtrace-{constant}.ron"));
        std::fs::write(&off_graph, forced).expect("write the graph");
        for (name, scene_text) in [("cornell", cornell.as_str()), ("card", CARD)] {
            let mut images = Vec::new();
            for graph in [repo().join("passes/pathtrace.ron"), off_graph.clone()] {
                let scene = scene_from(scene_text);
                let compiled = compile(&scene, &graph, &Default::default());
                images.push(render_compiled(gpu, scene, &compiled, (64, 48), 3));
            }
            let differ = images[0].data.iter().zip(&images[1].data).filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits)).count();
            assert_eq!(differ, 0, "{name}: {differ} pixels differ with {constant} forced to {off}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
