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
