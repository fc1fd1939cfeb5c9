//! Accumulation at the extremes, on the GPU (the CPU mirror's tests are in
//! src/mean.rs): a million samples keep the running mean within 1e-6
//! relative of the exact mean, and NaN, +-Inf, 1e30 and negative radiance
//! never reach the history or the output (checked by bits).

mod common;

use common::*;
use glint::graph::desc::ParamValue;
use glint::graph::edit::{GraphEdits, ParamSet};
use glint::graph::CompileOptions;
use glint::mean::test_sequence;

/// Whether an f32's exponent bits are all ones (NaN or Inf).
fn non_finite(x: f32) -> bool {
    x.to_bits() & 0x7f80_0000 == 0x7f80_0000
}

#[test]
fn a_million_samples_on_the_gpu_stay_within_1e_6() {
    let Some(gpu) = gpu() else { return };
    let compiled = compile(&load_scene("cornell.ron"), &repo().join("tests/graphs/mean-test.ron"), &CompileOptions::default());
    let mut s = session(gpu, load_scene("cornell.ron"), &compiled, (4, 1), 1);
    let (steps, frames) = (50_000u32, 20u32);
    for _ in 0..frames {
        s.frame(0.0);
    }
    let got = s.read_output().unwrap_or_else(|e| panic!("{e}"));
    let n = steps * frames;
    let mut worst = 0.0f64;
    for p in 0..4u32 {
        let mut exact = [0.0f64; 3];
        for k in 0..n {
            for (e, x) in exact.iter_mut().zip(test_sequence(p, k)) {
                *e += f64::from(x);
            }
        }
        for (e, g) in exact.iter().zip(got.data[p as usize]) {
            let mean = e / f64::from(n);
            worst = worst.max(((f64::from(g) - mean) / mean).abs());
        }
    }
    eprintln!("GPU: {n} samples, worst relative error of the mean {worst:.2e}");
    assert!(worst <= 1e-6, "the accumulated mean drifted by {worst} after {n} samples");
}

fn render_bad(frames: u32, clamp_max: f64) -> (Vec<[f32; 4]>, Vec<[f32; 4]>, u32) {
    let gpu = gpu().expect("checked by the caller");
    let set = vec![ParamSet { pass: "accumulate".into(), param: "clamp_max".into(), value: ParamValue::Float(clamp_max) }];
    let options = CompileOptions { edits: GraphEdits { set, ..Default::default() }, keep: vec!["accum_geo".into()], ..Default::default() };
    let scene = load_scene("cornell.ron");
    let compiled = compile(&scene, &repo().join("tests/graphs/nonfinite.ron"), &options);
    let size = (12, 6);
    let mut s = session(gpu, scene, &compiled, size, 1);
    for _ in 0..frames {
        s.frame(0.0);
    }
    let out = s.read_output().unwrap_or_else(|e| panic!("{e}")).data;
    let geo = s.read_resource("accum_geo").expect("kept").unwrap_or_else(|e| panic!("{e}")).data;
    (out, geo, size.0)
}

#[test]
fn non_finite_samples_never_reach_history_or_output() {
    if gpu().is_none() {
        return;
    }
    let frames = 6;
    let (out, geo, width) = render_bad(frames, 0.0);
    for (i, (o, g)) in out.iter().zip(&geo).enumerate() {
        assert!(!o.iter().chain(g.iter()).any(|x| non_finite(*x)), "pixel {i}: {o:?} / {g:?} holds NaN or Inf");
    }
    // What each column should hold after 6 frames (see test_nonfinite.wgsl).
    for (i, (o, g)) in out.iter().zip(&geo).enumerate() {
        let col = i as u32 % width % 6;
        let (mean, count) = match col {
            0 => (1.0, 3.0),      // NaN on frames 0, 2, 4: three 1.0s kept
            1 => (0.0, 0.0),      // +Inf every frame: nothing accumulated
            2 => (2.0, 3.0),      // -Inf on odd frames: three 2.0s
            3 => ((1e30 + 5.0) / 6.0, 6.0),
            4 => (0.0, 5.0),      // negative: counted as 0; the NaN frame is dropped
            _ => (0.5, 6.0),
        };
        assert_eq!(g[3], count, "pixel {i} (column {col}): sample count");
        let tol = if col == 3 { 1e24 } else { 1e-6 };
        assert!((f64::from(o[0]) - mean).abs() <= tol, "pixel {i} (column {col}): mean {} != {mean}", o[0]);
    }
    // The firefly clamp holds 1e30 to clamp_max (and leaves the rest).
    let (out, _, width) = render_bad(frames, 4.0);
    for (i, o) in out.iter().enumerate() {
        let col = i as u32 % width % 6;
        let want = if col == 3 { (4.0 + 5.0) / 6.0 } else { f64::from(o[0]) };
        assert!((f64::from(o[0]) - want).abs() <= 1e-6 && o[0] <= 4.0, "pixel {i} (column {col}): clamped mean {}", o[0]);
    }
}
