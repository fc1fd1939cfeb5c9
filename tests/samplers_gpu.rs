//! The WGSL samplers draw the samples their Rust mirror draws (which the
//! chi-square tests in src/chi2.rs prove): the same random stream, the same
//! cosine-hemisphere, sphere-light-cone and glossy-lobe directions, and the
//! metallic-roughness BRDF's samples, values and pdfs (src/brdf.rs), for
//! the same seeds.

mod common;

use common::*;
use glam::Vec3;
use glint::brdf::{self, MetalRough};
use glint::graph::CompileOptions;
use glint::sampling::{sample_cone, sample_cosine, sample_glossy, Rng};

#[test]
fn wgsl_samplers_draw_what_the_mirror_draws() {
    let Some(gpu) = gpu() else { return };
    let scene = load_scene("cornell.ron");
    let compiled = compile(&scene, &repo().join("tests/graphs/samplers.ron"), &CompileOptions::default());
    let seed = 1;
    let mut s = session(gpu, scene, &compiled, (1024, 7), seed);
    s.frame(0.0);
    let img = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    let normal = Vec3::new(0.267_261_24, 0.534_522_5, 0.801_783_7);
    let axis = Vec3::new(-0.2, 0.5, 0.84).normalize();
    let one_minus_cos = 0.001_250_782_3f32;
    let mirror = Vec3::new(0.6, -0.1, 0.793_725_4).normalize();
    let view = Vec3::new(0.8, 0.1, 0.591_608);
    let m = MetalRough { base: Vec3::new(0.9, 0.6, 0.3), metallic: 0.5, roughness: 0.4 };
    let mut worst = [0.0f32; 7];
    for x in 0..img.width {
        let draw = |row: u32| Rng::new((x, row), 0, 0xc41, seed).next2();
        let u = draw(2);
        let got = img.get(x, 2);
        // The stream is integer arithmetic: exactly the same numbers.
        assert_eq!((got[0], got[1]), (u.x, u.y), "x {x}: the random stream differs");
        let want = [(0, sample_cosine(normal, draw(0))), (1, sample_cone(axis, one_minus_cos, draw(1))), (3, sample_glossy(mirror, normal, 0.35, draw(3)))];
        for &(row, w) in &want {
            let g = img.get(x, row as u32);
            let err = (Vec3::new(g[0], g[1], g[2]) - w).abs().max_element();
            worst[row] = worst[row].max(err);
        }
        let mut rng = Rng::new((x, 4), 0, 0xc41, seed);
        let u_lobe = rng.next_f32();
        let l = brdf::sample(&m, normal, view, u_lobe, rng.next2());
        let g = img.get(x, 4);
        worst[4] = worst[4].max((Vec3::new(g[0], g[1], g[2]) - l).abs().max_element());
        // Values and pdfs relative to their size (a sharp lobe's pdf is large).
        let (f, p) = (brdf::eval(&m, normal, view, l), brdf::pdf(&m, normal, view, l));
        let g = img.get(x, 5);
        let rel = |a: f32, b: f32| (a - b).abs() / b.abs().max(1.0);
        worst[5] = worst[5].max(rel(g[0], f.x).max(rel(g[1], f.y)).max(rel(g[2], f.z)).max(rel(g[3], p)));
        // The specular lobe alone (the hybrid graphs' glossy reflections).
        let s = brdf::sample_specular(&m, normal, view, rng.next2());
        let w = brdf::luminance(brdf::specular_weight(&m, normal, view, s));
        let g = img.get(x, 6);
        worst[6] = worst[6].max((Vec3::new(g[0], g[1], g[2]) - s).abs().max_element().max(rel(g[3], w)));
    }
    eprintln!("largest component difference, GPU against mirror: cosine {:.1e}, cone {:.1e}, glossy {:.1e}, metallic-roughness sample {:.1e}, value and pdf {:.1e}, specular lobe {:.1e}", worst[0], worst[1], worst[3], worst[4], worst[5], worst[6]);
    // sin, cos and sqrt may differ by an ulp or two between the driver and Rust.
    // (The BRDF's values and pdfs, relative, through a few more of them.)
    assert!(worst[..5].iter().all(|&w| w < 1e-5) && worst[5] < 1e-4 && worst[6] < 1e-4, "the WGSL samplers differ from the mirror: {worst:?}");
}
