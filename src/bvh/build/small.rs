//! Subtrees of up to SMALL_MAX primitives, built by sorting instead of
//! binning, and where a BLAS's leaves end.

use bytemuck::Zeroable;
use glam::Vec4;

use super::{balanced_levels, centroid_key, Box3, BvhNode, Prim, MAX_LEAF};

/// Subtrees of up to this many primitives are built by `build_small`
/// (32 rather than 16: the same build time within this machine's noise,
/// SAH cost 69.36 -> 69.28 on the 1M knot).
pub(super) const SMALL_MAX: usize = 32;

/// BVHs over up to this many primitives (a mesh's BLAS, or the TLAS by
/// its count of instances) end their leaves where the SAH
/// says a split stops paying (`split_pays`), with the SAH plane at every
/// level: inside Sponza (66k triangles) the busiest lane of 8 took 22.7
/// BLAS trips a primary ray instead of 25.5, with 1.24x the nodes, and
/// 0.88-0.89x the time. Larger meshes keep every node of up to MAX_LEAF
/// primitives a leaf and split up to 2 x MAX_LEAF at the median: their
/// data outgrows the CPU's caches, and the 1M-triangle knot, whose trips
/// fell 4.5% with 1.24x the nodes, took 1.05-1.10x the time (each node
/// trip a cache line from far away, a leaf's next triangle the next one).
const SAH_LEAVES_MAX_PRIMS: usize = 1 << 18;

/// What visiting a node costs against testing one triangle, for
/// `split_pays`: one loop trip each in the shader, but a node's child pair
/// is a new cache line where a leaf's triangles are contiguous. 1.0 gave
/// Sponza the same time with 1.23x the nodes of 2.0.
const NODE_COST: f32 = 2.0;

/// In meshes over SAH_LEAVES_MAX_PRIMS, the leaves' size: nodes of up
/// to this many primitives are leaves, larger ones split. Two rather than
/// MAX_LEAF: a leaf costs each ray that reaches it a trip per triangle,
/// and a node of four split in two leaves of two costs a node trip and
/// the triangles of the leaves the ray enters, often one. On the
/// 1M-triangle knot (`glint bench rays --trips`, 1280 x 720) the busiest
/// lane of 8 took 8.45 BLAS trips a ray against 9.24, with 1.85x the
/// nodes (1.11M against 601k) and the same build time; query and
/// primary 0.93x the time (10 alternated rounds).
pub(super) const LARGE_MESH_LEAF: usize = 2;

/// The smallest runs `sort_by_rank` sorts in an array of their own. In
/// meshes over SAH_LEAVES_MAX_PRIMS, nodes of up to 2 x `SmallBuild::leaf`
/// primitives are split at their centroid median into two leaves without
/// an SAH search (on a 1M-triangle knot with leaves of 4: build -12%,
/// traversal steps per primary ray +1.2%).
const MEDIAN_SPLIT_MAX: usize = 2 * MAX_LEAF;

/// How `build_small` ends a BVH's subtrees: chosen once per build, from
/// its primitive count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SmallBuild {
    pub max_depth: u32,
    /// Leaves where the SAH says (else every node of up to `leaf`).
    pub sah_leaves: bool,
    /// Without SAH leaves, the primitives a leaf holds at most (MAX_LEAF
    /// near the depth bound).
    pub leaf: usize,
}

impl SmallBuild {
    pub(super) fn for_mesh(prims: usize, max_depth: u32) -> SmallBuild {
        let sah_leaves = prims <= SAH_LEAVES_MAX_PRIMS;
        SmallBuild { max_depth, sah_leaves, leaf: if sah_leaves { MAX_LEAF } else { LARGE_MESH_LEAF } }
    }
}

/// Builds the subtree under `node` (its bounds already set) over `prims`,
/// at most SMALL_MAX of them, which start at position `first`. Each level
/// sorts the primitives along the widest centroid axis by rank, without
/// branches, and takes the exact SAH plane of that order (the centroid
/// median up to 2 x MAX_LEAF primitives where `policy` has no SAH leaves,
/// or when the depth bound is near). Where `policy` has SAH leaves, a node
/// of up to MAX_LEAF primitives is a leaf unless the split pays; else a
/// node of up to `policy.leaf` is one (of up to MAX_LEAF at the depth
/// bound).
/// Through the general path, with its bins, partition and task per node,
/// the nodes under 16 primitives took 30% of a 1M-triangle build, mostly
/// fixed costs and mispredicted branches.
pub(super) fn build_small(prims: &mut [Prim], first: usize, node: usize, depth: u32, policy: SmallBuild, nodes: &mut Vec<BvhNode>, sorted_along: Option<usize>) {
    let n = prims.len();
    let make_leaf = |nodes: &mut Vec<BvhNode>| {
        nodes[node].left_first = first as u32;
        nodes[node].count = n as u32;
    };
    if n <= MAX_LEAF && ((!policy.sah_leaves && n <= policy.leaf) || n < 2 || depth + 1 >= policy.max_depth) {
        make_leaf(nodes);
        return;
    }
    let mut centroids = Box3::EMPTY;
    for p in prims.iter() {
        let s = p.lo() + p.hi();
        centroids.grow(s, s);
    }
    let e = centroids.max - centroids.min;
    let axis = if e.x >= e.y && e.x >= e.z { 0 } else if e.y >= e.z { 1 } else { 2 };
    // A run of primitives sorted along this axis is already in order (and
    // in the same order for ties: the sort is stable), so it is sorted
    // again only when the axis changes.
    if sorted_along != Some(axis) {
        sort_by_rank(prims, axis);
    }
    let median = depth + balanced_levels(n) >= policy.max_depth || (!policy.sah_leaves && n <= 2 * policy.leaf);
    let mid = if median { n / 2 } else { sah_sweep(prims) };
    let bounds = |side: &[Prim]| {
        let mut b = Box3::EMPTY;
        for p in side {
            b.grow(p.lo(), p.hi());
        }
        b
    };
    let (lb, rb) = (bounds(&prims[..mid]), bounds(&prims[mid..]));
    if policy.sah_leaves && n <= MAX_LEAF && !split_pays(&lb, mid, &rb, n - mid) {
        make_leaf(nodes);
        return;
    }
    let left = nodes.len();
    for b in [lb, rb] {
        let mut child = BvhNode::zeroed();
        child.set_bounds(&b.to_aabb());
        nodes.push(child);
    }
    nodes[node].left_first = left as u32;
    nodes[node].count = 0;
    let (l, r) = prims.split_at_mut(mid);
    build_small(l, first, left, depth + 1, policy, nodes, Some(axis));
    build_small(r, first + mid, left + 1, depth + 1, policy, nodes, Some(axis));
}

/// Whether splitting a leaf into sides of `nl` and `nr` primitives with
/// these bounds lowers its SAH cost: a ray that enters the node then
/// visits it (NODE_COST) and tests each side's primitives only if it
/// enters that side, against testing all of them. A NaN area keeps the
/// leaf.
pub(super) fn split_pays(left: &Box3, nl: usize, right: &Box3, nr: usize) -> bool {
    let mut all = *left;
    all.union(right);
    let a = all.half_area();
    let split = NODE_COST * a + left.half_area() * nl as f32 + right.half_area() * nr as f32;
    split < (nl + nr) as f32 * a
}

/// Sorts up to SMALL_MAX primitives by centroid along `axis` (ties by
/// position): each goes to its rank, counted without branches.
pub(super) fn sort_by_rank(prims: &mut [Prim], axis: usize) {
    let n = prims.len();
    if n <= MEDIAN_SPLIT_MAX {
        sort_by_rank_in::<MEDIAN_SPLIT_MAX>(prims, axis);
    } else if n <= 16 {
        sort_by_rank_in::<16>(prims, axis);
    } else {
        sort_by_rank_in::<SMALL_MAX>(prims, axis);
    }
}

/// `sort_by_rank` for up to N primitives.
#[inline(always)]
fn sort_by_rank_in<const N: usize>(prims: &mut [Prim], axis: usize) {
    let n = prims.len();
    // Padding keys sort after every real one (ties go by position), so
    // they never count towards a real rank.
    let mut keys = [i32::MAX; N];
    for (k, p) in keys.iter_mut().zip(prims.iter()) {
        *k = centroid_key(p, axis);
    }
    // rank[i] = #{j : key j < key i, or equal and j < i}, for all i at
    // once (the fixed-size inner loop is vectorised).
    let mut rank = [0i32; N];
    for (j, &kj) in keys.iter().enumerate().take(n) {
        for (i, (r, &ki)) in rank.iter_mut().zip(keys.iter()).enumerate() {
            *r += ((ki > kj) | ((ki == kj) & (i > j))) as i32;
        }
    }
    let mut sorted = [Prim { min: Vec4::ZERO, max: Vec4::ZERO }; N];
    for (p, &r) in prims.iter().zip(rank.iter()) {
        sorted[r as usize] = *p;
    }
    prims.copy_from_slice(&sorted[..n]);
}

/// The SAH-cheapest split of sorted primitives: how many go left.
pub(super) fn sah_sweep(prims: &[Prim]) -> usize {
    let n = prims.len();
    let mut right_area = [0.0f32; SMALL_MAX];
    let mut acc = Box3::EMPTY;
    for i in (1..n).rev() {
        acc.grow(prims[i].lo(), prims[i].hi());
        right_area[i] = acc.half_area();
    }
    let (mut best, mut best_cost) = (n / 2, f32::INFINITY);
    let mut left = Box3::EMPTY;
    for i in 1..n {
        left.grow(prims[i - 1].lo(), prims[i - 1].hi());
        let cost = left.half_area() * i as f32 + right_area[i] * (n - i) as f32;
        if cost < best_cost {
            (best, best_cost) = (i, cost);
        }
    }
    best
}
