//! The WGSL samplers draw the samples their Rust mirror draws (which the
//! chi-square tests in src/chi2.rs prove): the same random stream, the same
//! cosine-hemisphere, sphere-light-cone and glossy-lobe directions, for
//! the same seeds.

mod common;

use common::*;
use glam::Vec3;
use glint::graph::CompileOptions;
use glint::sampling::{sample_cone, sample_cosine, sample_glossy, Rng};

#[test]
fn wgsl_samplers_draw_what_the_mirror_draws() {
    let Some(gpu) = gpu() else { return };
    let scene = load_scene("cornell.ron");
    let compiled = compile(&scene, &repo().join("tests/graphs/samplers.ron"), &CompileOptions::default());
    let seed = 1;
    let mut s = session(gpu, scene, &compiled, (1024, 4), seed);
    s.frame(0.0);
    let img = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    let normal = Vec3::new(0.267_261_24, 0.534_522_5, 0.801_783_7);
    let axis = Vec3::new(-0.2, 0.5, 0.84).normalize();
    let one_minus_cos = 0.001_250_782_3f32;
    let mirror = Vec3::new(0.6, -0.1, 0.793_725_4).normalize();
    let mut worst = [0.0f32; 4];
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
    }
    eprintln!("largest component difference, GPU against mirror: cosine {:.1e}, cone {:.1e}, glossy {:.1e}", worst[0], worst[1], worst[3]);
    // sin, cos and sqrt may differ by an ulp or two between the driver and Rust.
    assert!(worst.iter().all(|&w| w < 1e-5), "the WGSL samplers differ from the mirror: {worst:?}");
}
