//! The camera's cut of a BLAS: what it holds, and that camera rays started
//! from it hit what brute force hits, bit for bit, from inside a room full
//! of clutter, from outside it, and with the camera on a box's face.

use bytemuck::Zeroable;
use glam::Vec3;

use super::*;
use crate::bvh::ray::{Geometry, Ray};
use crate::bvh::scene::SceneBvh;
use crate::bvh::Aabb;
use crate::scene::{MeshGpu, SceneData, TriangleGpu};

/// xorshift32, enough for scattering triangles.
pub(crate) struct Rng(pub u32);

impl Rng {
    pub fn unit(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        (self.0 >> 8) as f32 / (1u32 << 24) as f32
    }
    pub fn in_box(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        lo + (hi - lo) * Vec3::new(self.unit(), self.unit(), self.unit())
    }
}

fn tri(a: Vec3, b: Vec3, c: Vec3) -> TriangleGpu {
    TriangleGpu { p0: a.to_array(), p1: b.to_array(), p2: c.to_array(), ..TriangleGpu::zeroed() }
}

/// One mesh: the six walls of a 20 x 8 x 12 room as two triangles each,
/// and `clutter` small triangles scattered inside it.
pub(crate) fn room(clutter: usize) -> SceneData {
    let (lo, hi) = (Vec3::new(-10.0, 0.0, -6.0), Vec3::new(10.0, 8.0, 6.0));
    let corner = |i: usize| Vec3::new(if i & 1 == 0 { lo.x } else { hi.x }, if i & 2 == 0 { lo.y } else { hi.y }, if i & 4 == 0 { lo.z } else { hi.z });
    let mut tris = Vec::new();
    for [a, b, c, d] in [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]] {
        tris.push(tri(corner(a), corner(b), corner(c)));
        tris.push(tri(corner(a), corner(c), corner(d)));
    }
    let mut rng = Rng(0x9e37_79b9);
    for _ in 0..clutter {
        let c = rng.in_box(lo, hi);
        let s = 0.05 + 0.6 * rng.unit();
        let mut p = || c + (rng.in_box(Vec3::splat(-1.0), Vec3::ONE)) * s;
        tris.push(tri(p(), p(), p()));
    }
    let mut b = Aabb::EMPTY;
    for t in &tris {
        for p in [t.p0, t.p1, t.p2] {
            b.grow(Vec3::from(p));
        }
    }
    let mut data = SceneData::default();
    data.meshes.push(MeshGpu { bmin: b.min.to_array(), first: 0, bmax: b.max.to_array(), count: tris.len() as u32 });
    data.triangles = tris;
    SceneBvh::default().update(&mut data);
    data
}

pub(crate) fn root(data: &SceneData) -> u32 {
    assert_eq!(data.instances.len(), 1);
    data.instances[0].index
}

/// How many entries of `cut` each leaf under `root` lies under, by leaf.
pub(crate) fn entries_above_leaves(nodes: &[BvhNode], root: u32, cut: &[u32]) -> Vec<(u32, u32)> {
    let mut under = vec![0u32; nodes.len()];
    for &e in cut {
        let mut todo = vec![e];
        while let Some(i) = todo.pop() {
            let n = &nodes[i as usize];
            if n.is_leaf() {
                under[i as usize] += 1;
            } else {
                todo.extend([n.left_first, n.left_first + 1]);
            }
        }
    }
    let mut leaves = Vec::new();
    let mut todo = vec![root];
    while let Some(i) = todo.pop() {
        let n = &nodes[i as usize];
        if n.is_leaf() {
            leaves.push((i, under[i as usize]));
        } else {
            todo.extend([n.left_first, n.left_first + 1]);
        }
    }
    leaves
}

/// Every leaf under the root lies under exactly one entry.
fn assert_partition(nodes: &[BvhNode], root: u32, cut: &[u32]) {
    for (i, n) in entries_above_leaves(nodes, root, cut) {
        assert_eq!(n, 1, "leaf {i} lies under {n} entries");
    }
}

#[test]
fn the_cut_lies_just_below_the_nodes_that_hold_the_camera() {
    let data = room(3000);
    let camera = Vec3::new(0.3, 3.9, 0.1);
    let cut = camera_cut(&data.bvh, root(&data), camera).expect("a camera inside the room has a cut");
    assert!(cut.len() > 2, "{} entries", cut.len());
    assert_partition(&data.bvh, root(&data), &cut);
    let holds = |n: &BvhNode| (0..3).all(|k| n.bmin[k] <= camera[k] && camera[k] <= n.bmax[k]);
    for &i in &cut {
        let n = &data.bvh[i as usize];
        assert!(n.is_leaf() || !holds(n), "entry {i} holds the camera and is not a leaf");
    }
    // The uniform carries each entry's box and packed reference.
    let gpu = camera_entries(&data.bvh, Some(&cut));
    assert_eq!(gpu.count[0] as usize, cut.len());
    for (slot, &i) in gpu.entries.iter().zip(&cut) {
        let n = &data.bvh[i as usize];
        assert_eq!(slot[0][3] & ((1 << REF_COUNT_SHIFT) - 1), n.left_first);
        assert_eq!(slot[0][3] >> REF_COUNT_SHIFT, n.count);
        assert_eq!(f32::from_bits(slot[1][0]), n.bmax[0]);
        assert_eq!(slot[1][3], i);
    }
    assert_eq!(gpu.entries[cut.len()], [[0; 4]; 2]);
}

/// Pushed in the order a traversal from the root reaches them, reversed:
/// at a node holding the camera its child holding it first, then the
/// other; where neither child holds it, the nearer first.
#[test]
fn entries_are_popped_in_the_order_a_traversal_from_the_root_reaches_them() {
    let node = |lo: f32, hi: f32, left_first: u32, count: u32| BvhNode { bmin: [lo; 3], left_first, bmax: [hi; 3], count };
    // Root 0 holds the camera at the origin; its children: 1 holds it, 2
    // does not. Node 1's children 3 (far) and 4 (near) do not hold it.
    let nodes = [node(-10.0, 10.0, 1, 0), node(-5.0, 5.0, 3, 0), node(6.0, 10.0, 0, 1), node(3.0, 5.0, 1, 1), node(1.0, 2.0, 2, 1)];
    assert_eq!(camera_cut(&nodes, 0, Vec3::ZERO), Some(vec![2, 3, 4]));
    // Both children of the root hold it: the first one's subtree first.
    let nodes = [node(-10.0, 10.0, 1, 0), node(-5.0, 5.0, 3, 0), node(-1.0, 1.0, 0, 1), node(3.0, 5.0, 1, 1), node(1.0, 2.0, 2, 1)];
    assert_eq!(camera_cut(&nodes, 0, Vec3::ZERO), Some(vec![2, 3, 4]));
    // Only the second child holds it: it goes first.
    let nodes = [node(-10.0, 10.0, 1, 0), node(6.0, 10.0, 0, 1), node(-5.0, 5.0, 3, 0), node(3.0, 5.0, 1, 1), node(1.0, 2.0, 2, 1)];
    assert_eq!(camera_cut(&nodes, 0, Vec3::ZERO), Some(vec![1, 3, 4]));
}

#[test]
fn no_cut_from_outside_the_root_box_nor_from_a_nan_camera() {
    let data = room(500);
    for camera in [Vec3::new(0.0, 4.0, 40.0), Vec3::new(f32::NAN, 4.0, 0.0), Vec3::new(0.0, 8.5, 0.0)] {
        assert_eq!(camera_cut(&data.bvh, root(&data), camera), None, "{camera}");
    }
    assert_eq!(camera_entries(&data.bvh, None).count[0], 0);
}

#[test]
fn camera_rays_from_the_cut_hit_what_brute_force_hits() {
    let data = room(3000);
    let g = Geometry { spheres: &data.spheres, triangles: &data.triangles, nodes: &data.bvh, instances: &data.instances };
    let mut rng = Rng(12345);
    let mut cameras = vec![
        Vec3::new(0.3, 3.9, 0.1),
        // On the floor's plane and on a wall's: boxes the camera touches.
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(10.0, 4.0, 2.0),
        // A corner of the room.
        Vec3::new(-10.0, 0.0, -6.0),
    ];
    cameras.extend((0..6).map(|_| rng.in_box(Vec3::new(-9.5, 0.5, -5.5), Vec3::new(9.5, 7.5, 5.5))));
    let (mut hits, mut cuts) = (0, 0);
    for camera in cameras {
        // A camera on a wall lies in many boxes that touch it: its cut
        // may be too big to use, and its rays then start at the root.
        let cut = camera_cut(&data.bvh, root(&data), camera).unwrap_or_else(|| vec![root(&data)]);
        cuts += usize::from(cut.len() > 1);
        assert_partition(&data.bvh, root(&data), &cut);
        for k in 0..400 {
            // Unit directions, some along an axis (parallel to slabs).
            let d = match k % 40 {
                0 => Vec3::X,
                1 => -Vec3::Y,
                2 => Vec3::Z,
                _ => (rng.in_box(Vec3::splat(-1.0), Vec3::ONE)).normalize_or(Vec3::X),
            };
            let r = Ray::new(camera, d);
            let want = g.closest_brute(&r, f32::INFINITY);
            let got = g.closest_from(&r, f32::INFINITY, &cut);
            assert_eq!(got, want, "camera {camera}, direction {d}");
            assert_eq!(g.closest(&r, f32::INFINITY), want);
            hits += usize::from(want.is_some());
        }
    }
    // Rays from the cameras on the walls that leave the room miss.
    assert!(hits > 3000, "{hits} of 4000 rays hit the room");
    assert!(cuts >= 8, "only {cuts} of 10 cameras have a cut");
}

/// A complete binary tree `levels` deep in heap order (node i's children
/// at 2i + 1 and 2i + 2), whose nodes above depth `holding` hold the
/// camera at the origin and the rest lie beside it.
fn heap_tree(levels: u32, holding: u32) -> Vec<BvhNode> {
    let count = (1usize << levels) - 1;
    (0..count)
        .map(|i| {
            let depth = usize::BITS - 1 - (i + 1).leading_zeros();
            let (bmin, bmax) = if depth < holding { ([-1.0; 3], [1.0; 3]) } else { ([2.0; 3], [3.0; 3]) };
            let leaf = depth + 1 == levels;
            BvhNode { bmin, left_first: if leaf { i as u32 } else { 2 * i as u32 + 1 }, bmax, count: u32::from(leaf) }
        })
        .collect()
}

#[test]
fn a_cut_that_could_overflow_the_stack_or_the_uniform_is_not_used() {
    // 16 entries at depth 4: entry j sits on j others under a subtree at
    // most 40 levels deep, j + 40 < 64.
    let cut = camera_cut(&heap_tree(7, 4), 0, Vec3::ZERO).expect("16 entries fit");
    assert_eq!(cut.len(), 16);
    assert_partition(&heap_tree(7, 4), 0, &cut);
    // 32 entries at depth 5: the 25th and later could overflow the stack.
    assert_eq!(camera_cut(&heap_tree(7, 5), 0, Vec3::ZERO), None);
    // 64 at depth 6 (the leaves): more than the uniform holds.
    assert_eq!(camera_cut(&heap_tree(7, 7), 0, Vec3::ZERO), None);
    // Only the root holds the camera: its two children.
    assert_eq!(camera_cut(&heap_tree(7, 1), 0, Vec3::ZERO).map(|c| c.len()), Some(2));
}
