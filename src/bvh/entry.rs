//! Where the camera's rays enter a BLAS. Every primary ray starts at the
//! camera, so it enters every node whose box holds the camera at t = 0,
//! and a traversal from the root spends its first trips on those nodes,
//! the same ones for every ray: inside Sponza 17 of the 49.4 node trips a
//! primary ray takes. Once a frame the engine works out the cut of the
//! tree just below them (`camera_cut`): the children of those nodes that do
//! not hold the camera, and any leaf that does. A camera ray then starts
//! with the entries whose boxes it hits on its stack instead of at the
//! root (`traverse_camera` in shaders/shared/intersect.wgsl), the entries
//! read from a uniform (`scene_entries`). The entries cost their own box
//! tests: about a tenth of a Sponza primary ray's time for its 18
//! (docs/acceleration.md, "Where camera rays enter").
//!
//! Any cut of the tree gives the same hits as the root does: every leaf
//! lies under exactly one entry, and an entry's box holds its subtree's.
//! Which nodes are expanded only decides how many trips are saved. The
//! Rust mirror (`Geometry::closest_from`) checks this against brute force.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::{BvhNode, BLAS_MAX_DEPTH};
use crate::bvh::ray::STACK;

/// Entries the uniform holds; a cut with more is not used (the rays start
/// at the root). Sponza's camera needs 18.
pub const MAX_CAMERA_ENTRIES: usize = 32;

/// `struct CameraEntries` in shaders/shared/bvh.wgsl: the count in
/// `count[0]`, then per entry two texels as a BLAS node has them, (bmin,
/// node reference) and (bmax, node index), the reference packed as the
/// traversal packs it (`node_ref`: first child or triangle, and the leaf's
/// triangle count in the top three bits). Pushed in this order (the
/// reverse of the order a traversal from the root reaches them: see
/// `camera_cut`), so the last is popped first.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct CameraEntriesGpu {
    /// The entry count in `count[0]`; the rest zero.
    pub count: [u32; 4],
    /// Per entry, its two texels; the first `count[0]` are used.
    pub entries: [[[u32; 4]; 2]; MAX_CAMERA_ENTRIES],
}

impl Default for CameraEntriesGpu {
    fn default() -> Self {
        Self::zeroed()
    }
}

/// The top three bits of a packed node reference hold the leaf's count
/// (`REF_COUNT_SHIFT` in shaders/shared/bvh.wgsl).
pub const REF_COUNT_SHIFT: u32 = 29;

pub(crate) fn holds(n: &BvhNode, p: Vec3) -> bool {
    (0..3).all(|k| n.bmin[k] <= p[k] && p[k] <= n.bmax[k])
}

/// Squared distance from `p` to the node's box (0 inside).
pub(crate) fn distance2(n: &BvhNode, p: Vec3) -> f32 {
    let lo = Vec3::from(n.bmin) - p;
    let hi = p - Vec3::from(n.bmax);
    lo.max(hi).max(Vec3::ZERO).length_squared()
}

/// The cut of the BLAS at `root` (node indices into `nodes`, interior
/// nodes index their children there) just below the nodes whose boxes
/// hold `camera`, or None where starting there saves nothing (the root's
/// box does not hold the camera, or the root is a leaf) or where the cut
/// has more than `MAX_CAMERA_ENTRIES` entries or could overflow the
/// traversal stack: an entry pushed j-th sits on j others while its
/// subtree, at most BLAS_MAX_DEPTH minus its depth levels deep, pushes one
/// a level.
///
/// In push order: the last is popped first. A traversal from the root
/// pops them in the order it would have reached them: at a node holding
/// the camera, the child that holds it first (the first child if both
/// do: both are entered at t = 0), then the other; where neither child
/// holds it, the nearer to the camera first.
pub fn camera_cut(nodes: &[BvhNode], root: u32, camera: Vec3) -> Option<Vec<u32>> {
    let root_node = nodes.get(root as usize)?;
    if root_node.is_leaf() || !holds(root_node, camera) {
        return None;
    }
    // Depth first, the child to be popped first taken first.
    let mut popped: Vec<(u32, u32)> = Vec::new();
    let mut todo = vec![(root, 0u32)];
    while let Some((i, depth)) = todo.pop() {
        let n = nodes.get(i as usize)?;
        if n.is_leaf() || !holds(n, camera) {
            popped.push((i, depth));
            if popped.len() > MAX_CAMERA_ENTRIES {
                return None;
            }
            continue;
        }
        let (a, b) = (n.left_first, n.left_first + 1);
        let (na, nb) = (nodes.get(a as usize)?, nodes.get(b as usize)?);
        let b_first = match (holds(na, camera), holds(nb, camera)) {
            (true, _) => false,
            (false, true) => true,
            (false, false) => distance2(nb, camera) < distance2(na, camera),
        };
        let (first, second) = if b_first { (b, a) } else { (a, b) };
        todo.push((second, depth + 1));
        todo.push((first, depth + 1));
    }
    popped.reverse();
    let fits = popped.iter().enumerate().all(|(j, &(_, depth))| j + (BLAS_MAX_DEPTH.saturating_sub(depth) as usize) < STACK);
    fits.then(|| popped.into_iter().map(|(i, _)| i).collect())
}

/// The uniform for a cut (`camera_cut`); no cut, no entries.
pub fn camera_entries(nodes: &[BvhNode], cut: Option<&[u32]>) -> CameraEntriesGpu {
    let mut gpu = CameraEntriesGpu::zeroed();
    let Some(cut) = cut else { return gpu };
    for (slot, &i) in gpu.entries.iter_mut().zip(cut) {
        *slot = entry_texels(nodes, i);
    }
    gpu.count[0] = cut.len().min(MAX_CAMERA_ENTRIES) as u32;
    gpu
}

/// Node `i` as an entry: (bmin, node reference) and (bmax, node index),
/// the reference packed as the traversal packs it.
pub fn entry_texels(nodes: &[BvhNode], i: u32) -> [[u32; 4]; 2] {
    let n = &nodes[i as usize];
    let node_ref = n.left_first | (n.count << REF_COUNT_SHIFT);
    let [x, y, z] = n.bmin.map(f32::to_bits);
    let [u, v, w] = n.bmax.map(f32::to_bits);
    [[x, y, z, node_ref], [u, v, w, i]]
}

#[cfg(test)]
pub(crate) mod tests;
