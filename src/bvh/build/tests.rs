//! The builder's own tests (the BVH against brute force lives in
//! src/bvh/tests.rs).

use super::*;

fn random_boxes(n: usize, seed: u32) -> (Vec<Aabb>, Vec<Vec3>) {
    let mut s = seed;
    let mut r = move || {
        s = s.wrapping_mul(1664525).wrapping_add(1013904223);
        (s >> 8) as f32 / 16777216.0
    };
    let mut bounds = Vec::new();
    let mut cs = Vec::new();
    for _ in 0..n {
        let c = Vec3::new(r(), r(), r()) * 10.0;
        let h = Vec3::new(r(), r(), r()) * 0.2;
        bounds.push(Aabb { min: c - h, max: c + h });
        cs.push(c);
    }
    (bounds, cs)
}

fn check(bvh: &Bvh, bounds: &[Aabb]) {
    let mut seen = vec![false; bounds.len()];
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        let node = bvh.nodes[i];
        let nb = node.bounds();
        if node.is_leaf() {
            assert!(node.count as usize <= MAX_LEAF.max(1) || bounds.len() <= MAX_LEAF);
            for k in node.left_first..node.left_first + node.count {
                let p = bvh.order[k as usize] as usize;
                assert!(!seen[p], "primitive {p} twice");
                seen[p] = true;
                let b = bounds[p];
                assert!(nb.min.cmple(b.min).all() && nb.max.cmpge(b.max).all(), "leaf does not contain its primitive");
            }
        } else {
            for c in [node.left_first as usize, node.left_first as usize + 1] {
                let cb = bvh.nodes[c].bounds();
                assert!(nb.min.cmple(cb.min).all() && nb.max.cmpge(cb.max).all(), "child outside parent");
                stack.push(c);
            }
        }
    }
    assert!(seen.iter().all(|s| *s), "a primitive is missing");
}

#[test]
fn builds_valid_trees() {
    // 20000: the top nodes choose their plane from a sample.
    for n in [0, 1, 2, 3, 5, 17, 100, 5000, 20000] {
        let (b, _) = random_boxes(n, n as u32 + 7);
        let bvh = build(&b);
        if n > 0 {
            check(&bvh, &b);
        }
    }
}

#[test]
fn primitive_ids_ride_in_the_w_lanes_exactly() {
    let b = Aabb { min: Vec3::splat(-1.0), max: Vec3::ONE };
    for id in [0, 1, 4095, 4096, 4097, (1 << 24) + 7, u32::MAX - 1, u32::MAX] {
        let p = Prim::new(&b, id);
        assert_eq!(p.id(), id);
        assert!(p.min.w.is_normal() || p.min.w == 0.0);
        assert_eq!((p.lo(), p.hi()), (Vec3A::splat(-1.0), Vec3A::ONE));
    }
}

#[test]
fn identical_centroids_still_split_into_small_leaves() {
    let b = vec![Aabb { min: Vec3::ZERO, max: Vec3::ONE }; 100];
    let bvh = build(&b);
    check(&bvh, &b);
    assert!(bvh.nodes.iter().all(|n| n.count as usize <= MAX_LEAF));
}

fn prim_at(x: f32) -> Prim {
    Prim::new(&Aabb { min: Vec3::new(x, 0.0, 0.0), max: Vec3::new(x, 1.0, 1.0) }, 0)
}

#[test]
fn rank_sort_matches_a_stable_sort_with_ties_and_specials() {
    let specials = [0.0, -0.0, 1.0, -1.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, -f32::NAN, 1e-30, 3.0];
    let mut s = 12345u32;
    for trial in 0..400 {
        let n = 1 + trial % SMALL_MAX;
        let mut prims: Vec<Prim> = (0..n)
            .map(|i| {
                s = s.wrapping_mul(1664525).wrapping_add(1013904223);
                let p = prim_at(specials[(s >> 24) as usize % specials.len()]);
                // Distinguish equal keys by their ids.
                Prim::new(&Aabb { min: p.lo().into(), max: p.hi().into() }, i as u32)
            })
            .collect();
        let mut expected = prims.clone();
        expected.sort_by_key(|p| centroid_key(p, 0));
        sort_by_rank(&mut prims, 0);
        let ids = |v: &[Prim]| v.iter().map(Prim::id).collect::<Vec<_>>();
        assert_eq!(ids(&prims), ids(&expected), "n = {n}");
    }
}

#[test]
fn sah_sweep_takes_the_cheapest_plane() {
    for n in 2..=SMALL_MAX {
        let (b, _) = random_boxes(n, n as u32);
        let mut prims: Vec<Prim> = b.iter().enumerate().map(|(i, b)| Prim::new(b, i as u32)).collect();
        sort_by_rank(&mut prims, 0);
        let area = |v: &[Prim]| {
            let mut bx = Box3::EMPTY;
            v.iter().for_each(|p| bx.grow(p.lo(), p.hi()));
            bx.half_area() * v.len() as f32
        };
        let costs: Vec<f32> = (1..n).map(|i| area(&prims[..i]) + area(&prims[i..])).collect();
        let best = sah_sweep(&prims);
        let min = costs.iter().cloned().fold(f32::INFINITY, f32::min);
        assert!((costs[best - 1] - min).abs() <= min * 1e-5, "n = {n}: split {best} costs {} > {min}", costs[best - 1]);
    }
}

#[test]
fn small_subtrees_split_sorted_runs_and_bound_their_children() {
    // Primitives in reverse order along x: every small subtree has to
    // sort them; the leaves must hold runs contiguous in x.
    let b: Vec<Aabb> = (0..SMALL_MAX).rev().map(|i| Aabb { min: Vec3::new(i as f32, 0.0, 0.0), max: Vec3::new(i as f32 + 0.5, 0.1, 0.1) }).collect();
    let bvh = build(&b);
    check(&bvh, &b);
    for node in bvh.nodes.iter().filter(|n| n.is_leaf()) {
        let xs: Vec<f32> = (node.left_first..node.left_first + node.count).map(|k| b[bvh.order[k as usize] as usize].min.x).collect();
        assert!(xs.windows(2).all(|w| w[1] == w[0] + 1.0), "leaf not a sorted run: {xs:?}");
    }
}

#[test]
fn the_partition_test_agrees_with_the_bins_for_every_kind_of_float() {
    // The children's bounds are the union of their bins, so the
    // partition must put exactly the bins below the plane on the left.
    let mut s = 99u32;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s
    };
    let specials = [0.0, -0.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, f32::MAX, f32::MIN_POSITIVE, 1e-40];
    for _ in 0..20000 {
        let cmin = f32::from_bits(next() >> 2) * if next() % 2 == 0 { 1.0 } else { -1.0 };
        let extent = (f32::from_bits(next() >> 2)).max(1e-30);
        let scale = BINS as f32 * (1.0 - 1e-6) / extent;
        // Near a bin boundary, then a few ulps either side of it.
        let near = cmin + (next() % (BINS as u32 + 1)) as f32 / scale;
        let c = match next() % 4 {
            0 => specials[next() as usize % specials.len()],
            1 => f32::from_bits(next()),
            2 => near,
            _ => f32::from_bits(near.to_bits().wrapping_add(next() % 5).wrapping_sub(2)),
        };
        for first_right in 1..BINS {
            assert_eq!(below_plane(c, cmin, scale, first_right), bin_of(c, cmin, scale) < first_right, "c = {c:e}, cmin = {cmin:e}, scale = {scale:e}, bin {first_right}");
        }
    }
}

#[test]
fn refit_follows_moved_primitives() {
    let (mut b, _) = random_boxes(300, 3);
    let mut bvh = build(&b);
    for bb in &mut b {
        bb.min += Vec3::new(5.0, 0.0, 0.0);
        bb.max += Vec3::new(5.0, 0.0, 0.0);
    }
    refit(&mut bvh, &b);
    check(&bvh, &b);
}

fn unit_box_at(x: f32) -> Aabb {
    Aabb { min: Vec3::new(x, 0.0, 0.0), max: Vec3::new(x + 1.0, 1.0, 1.0) }
}

#[test]
fn a_leaf_ends_where_splitting_stops_paying() {
    // Two pairs of unit boxes far apart: most rays that enter the node's
    // box enter neither pair, so the split pays; within a pair it does not.
    let far = [0.0, 1.0, 100.0, 101.0].map(unit_box_at);
    let bvh = build(&far);
    check(&bvh, &far);
    let leaves: Vec<u32> = bvh.nodes.iter().filter(|n| n.is_leaf()).map(|n| n.count).collect();
    assert_eq!(leaves, [2, 2]);
    // Overlapping boxes: a ray that enters one mostly enters them all.
    let near = [0.0, 0.1, 0.2, 0.3].map(unit_box_at);
    let bvh = build(&near);
    assert_eq!((bvh.nodes.len(), bvh.nodes[0].count), (1, 4));
    let nan = Box3 { min: Vec3A::splat(f32::NAN), max: Vec3A::splat(f32::NAN) };
    assert!(!split_pays(&nan, 2, &nan, 2));
}

#[test]
fn meshes_too_big_for_the_cache_take_leaves_of_a_fixed_size() {
    assert!(SmallBuild::for_mesh(66_453, BLAS_MAX_DEPTH).sah_leaves);
    let big = SmallBuild::for_mesh(1_000_000, BLAS_MAX_DEPTH);
    assert!(!big.sah_leaves);
    assert_eq!(big.leaf, small::LARGE_MESH_LEAF);
    // Four boxes in a row split at the median into leaves of two, whether
    // or not the SAH would split them (the near pairs above it would not).
    for xs in [[0.0, 1.0, 100.0, 101.0], [0.0, 0.1, 0.2, 0.3]] {
        let mut prims: Vec<Prim> = xs.map(unit_box_at).iter().enumerate().map(|(i, b)| Prim::new(b, i as u32)).collect();
        let mut nodes = vec![BvhNode::zeroed()];
        build_small(&mut prims, 0, 0, 1, big, &mut nodes, None);
        assert_eq!(nodes.len(), 3, "{xs:?}");
        assert_eq!((nodes[0].count, nodes[1].count, nodes[2].count), (0, 2, 2), "{xs:?}");
    }
    // At the depth bound, four stay one leaf.
    let mut prims: Vec<Prim> = [0.0, 1.0, 2.0, 3.0].map(unit_box_at).iter().enumerate().map(|(i, b)| Prim::new(b, i as u32)).collect();
    let mut nodes = vec![BvhNode::zeroed()];
    build_small(&mut prims, 0, 0, BLAS_MAX_DEPTH - 1, big, &mut nodes, None);
    assert_eq!((nodes.len(), nodes[0].count), (1, 4));
}
