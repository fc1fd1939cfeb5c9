//! A hundred shader reloads in a row do not grow the live wgpu objects:
//! what a swap replaces is released once the GPU is done with it
//! (docs/ARCHITECTURE.md, "Reload protocol", step 4). Alone in its own test
//! binary, since wgpu's counts are per process and other tests create
//! objects concurrently.

mod common;

use glint::session::{Session, SessionOptions};

#[test]
fn a_hundred_reloads_do_not_grow_live_gpu_objects() {
    let Some(gpu) = common::gpu() else { return };
    let ws = common::workspace("reload-leak");
    let scene = glint::scene::load(&ws.join("scenes/cornell.ron")).unwrap_or_else(|e| panic!("{e}"));
    let mut s = Session::new(gpu, scene, &ws.join("passes/hybrid.ron"), SessionOptions::new((32, 32))).unwrap_or_else(|e| panic!("{e}"));
    // accumulate.wgsl: a cheap pipeline to rebuild, and a pass with history
    // textures (taken over by each new executor) and a params buffer.
    let shader = ws.join("shaders/accumulate.wgsl");
    let original = std::fs::read_to_string(&shader).expect("read accumulate.wgsl");
    let variant = |i: u32| format!("{original}\n// edit {}\n", i % 2);
    let reload = |s: &mut Session, i: u32| {
        std::fs::write(&shader, variant(i)).expect("write accumulate.wgsl");
        let report = s.reload_shaders(std::slice::from_ref(&shader)).unwrap_or_else(|e| panic!("reload {i}: {e}"));
        assert_eq!(report.rebuilt, vec!["accumulate".to_string()], "reload {i}");
        s.frame(0.0);
    };
    s.frame(0.0);
    // One reload first: whatever a first rebuild creates once is counted in.
    reload(&mut s, 1);
    s.release_all();
    assert_eq!(s.retired_count(), 0);
    let Some(start) = gpu.live_objects() else {
        eprintln!("skipping the live-object check: this wgpu backend gives no registry report");
        return;
    };
    assert!(start.compute_pipelines > 0 && start.textures > 0, "the report counts nothing: {start:?}");
    for i in 0..100 {
        reload(&mut s, i);
    }
    s.release_all();
    assert_eq!(s.retired_count(), 0);
    let end = gpu.live_objects().expect("registry report");
    eprintln!("live wgpu objects after 1 reload: {} ({start:?}); after 101: {} ({end:?})", start.total(), end.total());
    assert_eq!(end, start, "live wgpu objects after 100 reloads (left) against after one (right): totals {} vs {}", end.total(), start.total());
}
