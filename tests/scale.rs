//! Any scale (issue 12, part 2, as far as it goes): the Cornell box scaled
//! by 1e-5 .. 1e5 (positions and radii scaled, radiance unchanged, point
//! intensities times s^2) renders the image of the unscaled box, in every
//! shipped graph, with the same seed. What made small scenes fail was the
//! absolute near-origin offset of `offset_ray`; it is now relative to the
//! scene (`frame.offset_scale`, src/bvh/offset.rs).

mod common;

use common::*;
use glint::metrics;

/// The scene text with every position, vertex, centre and radius times
/// `s`, and point-light intensities times s^2.
fn scaled(text: &str, s: f64) -> String {
    let scale_numbers = |seg: &str, k: f64| -> String {
        let mut out = String::new();
        let mut num = String::new();
        let flush = |num: &mut String, out: &mut String| {
            if !num.is_empty() {
                let v: f64 = num.parse().unwrap_or_else(|_| panic!("`{num}` is not a number"));
                out.push_str(&format!("{:e}", v * k));
                num.clear();
            }
        };
        for c in seg.chars() {
            if c.is_ascii_digit() || c == '.' || c == '-' || c == 'e' {
                num.push(c);
            } else {
                flush(&mut num, &mut out);
                out.push(c);
            }
        }
        flush(&mut num, &mut out);
        out
    };
    let mut lines = Vec::new();
    for line in text.lines() {
        let mut line = line.to_string();
        if line.trim_start().starts_with("//") {
            lines.push(line);
            continue;
        }
        for (key, close, k) in [("position: (", ')', s), ("target: (", ')', s), ("vertices: [", ']', s), ("center: (", ')', s), ("intensity: (", ')', s * s)] {
            if let Some(i) = line.find(key) {
                let start = i + key.len();
                let end = start + line[start..].find(close).expect("closing bracket");
                line = format!("{}{}{}", &line[..start], scale_numbers(&line[start..end], k), &line[end..]);
            }
        }
        if let Some(i) = line.find("radius: ") {
            let start = i + "radius: ".len();
            let end = start + line[start..].find([',', ')']).expect("radius value end");
            line = format!("{}{}{}", &line[..start], scale_numbers(&line[start..end], s), &line[end..]);
        }
        lines.push(line);
    }
    lines.join("\n")
}

#[test]
fn any_scale_renders_the_same_image() {
    let Some(gpu) = gpu() else { return };
    let size = (64, 64);
    let mut worst = 0.0f32;
    for scene in ["cornell.ron", "cornell-point.ron"] {
        let text = std::fs::read_to_string(repo().join("scenes").join(scene)).expect("read scene");
        for graph in ["direct.ron", "hybrid-point.ron", "hybrid.ron", "pathtrace.ron"] {
            let path = repo().join("passes").join(graph);
            let reference = render(gpu, scene_from(&text), &path, size, 8, None);
            for s in [1e-5, 1e-3, 1e3, 1e5] {
                let image = render(gpu, scene_from(&scaled(&text, s)), &path, size, 8, None);
                let (flip, _) = metrics::flip(&reference, &image);
                eprintln!("{scene} {graph} scaled by {s:e}: FLIP mean {:.5}", flip.mean);
                worst = worst.max(flip.mean);
                assert!(flip.mean <= 0.01, "{scene} with {graph} scaled by {s:e}: FLIP mean {} against the unscaled box", flip.mean);
            }
        }
    }
    eprintln!("worst FLIP mean over scales 1e-5..1e5: {worst:.5}");
}

#[test]
fn scaling_the_text_scales_the_scene() {
    let text = "Scene(camera: Camera(position: (0.0, 1.5, -2.0), target: (0.0, 0.0, 0.0)),\n  Sphere(center: (1.0, 2.0, 3.0), radius: 0.5, material: \"m\"),\n  PointLight(position: (0.0, 1.0, 0.0), intensity: (2.0, 2.0, 2.0)),\n  // radius: 7.0\n)";
    let t = scaled(text, 10.0);
    assert!(t.contains("position: (0e0, 1.5e1, -2e1)"), "{t}");
    assert!(t.contains("center: (1e1, 2e1, 3e1), radius: 5e0,"), "{t}");
    assert!(t.contains("intensity: (2e2, 2e2, 2e2)"), "{t}");
    assert!(t.contains("// radius: 7.0"), "{t}");
}
