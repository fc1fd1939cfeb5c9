//! Binned SAH builder (Wald 2007): at each node the primitives' centroids
//! are binned along the widest centroid axis (a strided sample of the
//! primitives for large nodes), the
//! cheapest plane by the surface area heuristic is taken, and a node
//! becomes a leaf when splitting costs more than intersecting its
//! primitives (at most `MAX_LEAF` of them). The partition that follows sees
//! every primitive and gathers the exact child bounds on the way.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A, Vec4};

use super::Aabb;

/// Leaves hold at most this many primitives. The shader packs a BLAS
/// node's count into the top three bits of a u32 (REF_COUNT_SHIFT in
/// shaders/shared/bvh.wgsl), so this must stay below 8.
pub const MAX_LEAF: usize = 4;
const _: () = assert!(MAX_LEAF < 8);
/// Nodes this small become leaves without evaluating the SAH: splitting a
/// handful of triangles saves little traversal (measured on a 1M-triangle
/// knot: same Mrays/s) and costs a third of the build time and half the nodes.
const MIN_SPLIT: usize = MAX_LEAF + 1;
const BINS: usize = 12;
/// Nodes of up to this many primitives are split at their centroid median
/// into two leaves without binning (on a 1M-triangle knot: build -12%,
/// traversal steps per primary ray +1.2%).
const MEDIAN_SPLIT_MAX: usize = 2 * MAX_LEAF;
/// Cost of one traversal step relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// `struct BvhNode` in shaders/shared/bvh.wgsl (32 bytes). Interior nodes
/// have `count == 0` and children at `left_first` and `left_first + 1`;
/// leaves hold primitives `left_first .. left_first + count`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub bmin: [f32; 3],
    pub left_first: u32,
    pub bmax: [f32; 3],
    pub count: u32,
}

impl BvhNode {
    pub fn bounds(&self) -> Aabb {
        Aabb { min: Vec3::from(self.bmin), max: Vec3::from(self.bmax) }
    }
    fn set_bounds(&mut self, b: &Aabb) {
        self.bmin = b.min.to_array();
        self.bmax = b.max.to_array();
    }
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A BVH over primitives `0..n`: `order[i]` is the primitive stored at
/// position i (leaves index into `order`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    pub order: Vec<u32>,
}

/// A primitive during the build: its box and its index, kept contiguous
/// and partitioned in place so each level streams through one array. The
/// index rides in the w lanes as two 12-bit halves stored as small whole
/// floats (exact, never denormal: min/max over them stays fast).
#[derive(Clone, Copy)]
struct Prim {
    min: Vec4,
    max: Vec4,
}

impl Prim {
    fn new(b: &Aabb, id: u32) -> Prim {
        Prim { min: b.min.extend((id >> 12) as f32), max: b.max.extend((id & 0xfff) as f32) }
    }
    #[inline]
    fn lo(&self) -> Vec3A {
        Vec3A::from_vec4(self.min)
    }
    #[inline]
    fn hi(&self) -> Vec3A {
        Vec3A::from_vec4(self.max)
    }
    #[inline]
    fn centroid(&self) -> Vec3A {
        (self.lo() + self.hi()) * 0.5
    }
    fn id(&self) -> u32 {
        ((self.min.w as u32) << 12) | self.max.w as u32
    }
}

/// SIMD box used inside the builder.
#[derive(Clone, Copy)]
struct Box3 {
    min: Vec3A,
    max: Vec3A,
}

impl Box3 {
    const EMPTY: Box3 = Box3 { min: Vec3A::splat(f32::INFINITY), max: Vec3A::splat(f32::NEG_INFINITY) };
    #[inline]
    fn grow(&mut self, min: Vec3A, max: Vec3A) {
        self.min = self.min.min(min);
        self.max = self.max.max(max);
    }
    #[inline]
    fn union(&mut self, o: &Box3) {
        self.grow(o.min, o.max);
    }
    #[inline]
    fn half_area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
    fn to_aabb(self) -> Aabb {
        Aabb { min: self.min.into(), max: self.max.into() }
    }
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Box3,
    count: u32,
}

const EMPTY_BIN: Bin = Bin { bounds: Box3::EMPTY, count: 0 };

struct Task {
    node: usize,
    start: usize,
    end: usize,
    centroids: Box3,
    depth: u32,
}

/// Default depth bound of a BLAS. The shader's traversal stacks grow by
/// at most one entry per level: the BLAS stack has 64 entries, the TLAS
/// stack 16 (`TLAS_MAX_DEPTH`).
pub const BLAS_MAX_DEPTH: u32 = 44;
pub const TLAS_MAX_DEPTH: u32 = 16;

/// Levels a balanced subtree over `count` primitives needs below its root.
fn balanced_levels(count: usize) -> u32 {
    count.div_ceil(MAX_LEAF).max(1).next_power_of_two().trailing_zeros()
}

/// Nodes with more primitives than this choose their plane from an evenly
/// strided sample of about this many (the SAH cost curve of a large node is
/// smooth; the exact partition and child bounds still see every primitive).
const SAMPLE_ABOVE: usize = 4096;

/// Builds a BVH over primitives given their bounds (binned by box centre),
/// at most `BLAS_MAX_DEPTH` levels deep.
pub fn build(bounds: &[Aabb]) -> Bvh {
    build_with_depth(bounds, BLAS_MAX_DEPTH)
}

/// `build` with a depth bound (see `BvhBuilder::build`).
pub fn build_with_depth(bounds: &[Aabb], max_depth: u32) -> Bvh {
    BvhBuilder::default().build(bounds, max_depth)
}

/// Builds BVHs, keeping its working array (32 bytes a primitive) from one
/// build to the next: memory a process has not touched yet costs a page
/// fault per 4 KiB, about 15% of a 1M-triangle build on this machine.
#[derive(Default)]
pub struct BvhBuilder {
    prims: Vec<Prim>,
}

impl BvhBuilder {
    /// A subtree that could not otherwise stay within `max_depth` levels
    /// (the SAH happily peels off one primitive per level on graded input)
    /// is split at its centroid median from there on, which halves it each
    /// level. Best effort when even that cannot fit.
    pub fn build(&mut self, bounds: &[Aabb], max_depth: u32) -> Bvh {
        self.prims.clear();
        self.prims.extend(bounds.iter().enumerate().map(|(i, b)| Prim::new(b, i as u32)));
        build_prims(&mut self.prims, max_depth)
    }
}

fn build_prims(prims: &mut [Prim], max_depth: u32) -> Bvh {
    let n = prims.len();
    let mut nodes = Vec::with_capacity((2 * n / MAX_LEAF).max(1) + 1);
    let (mut root_bounds, mut root_centroids) = (Box3::EMPTY, Box3::EMPTY);
    for p in prims.iter() {
        root_bounds.grow(p.lo(), p.hi());
        let c = p.centroid();
        root_centroids.grow(c, c);
    }
    let mut root = BvhNode::zeroed();
    root.set_bounds(&root_bounds.to_aabb());
    root.count = n as u32;
    nodes.push(root);
    if n == 0 {
        return Bvh { nodes, order: Vec::new() };
    }
    let mut stack = vec![Task { node: 0, start: 0, end: n, centroids: root_centroids, depth: 1 }];
    let mut bins = [EMPTY_BIN; BINS];
    while let Some(task) = stack.pop() {
        let count = task.end - task.start;
        let node_area = nodes[task.node].bounds().half_area();
        let too_deep = task.depth + balanced_levels(count) >= max_depth;
        let median = count > MAX_LEAF && (count <= MEDIAN_SPLIT_MAX || too_deep);
        let split = if count >= MIN_SPLIT && !median { best_split(&prims[task.start..task.end], &task.centroids, &mut bins) } else { None };
        let split = match split {
            Some(s) if node_area > 0.0 && TRAVERSAL_COST + s.cost / node_area < count as f32 => Some(s),
            Some(s) if count > MAX_LEAF => Some(s),
            _ if count > MAX_LEAF => Some(Split::middle()),
            _ => None,
        };
        let Some(split) = split else {
            nodes[task.node].left_first = task.start as u32;
            nodes[task.node].count = count as u32;
            continue;
        };
        // Partition by the chosen bin (child bounds gathered on the way); a
        // degenerate result (all on one side, possible with NaN centroids)
        // falls back to the middle.
        let range = task.start..task.end;
        let mut sides = None;
        if let Some((axis, scale, bin)) = split.plane {
            let cmin = task.centroids.min[axis];
            // bin_of(c) < bin as a float compare (the same for every
            // centroid, NaN included: bin_of puts NaN in bin 0), with the
            // axis fixed per loop.
            let threshold = bin as f32;
            let below = |x: f32| {
                let v = (x - cmin) * scale;
                v < threshold || v.is_nan()
            };
            let slice = &mut prims[range.clone()];
            let (m, s) = match axis {
                0 => partition(slice, |c| below(c.x)),
                1 => partition(slice, |c| below(c.y)),
                _ => partition(slice, |c| below(c.z)),
            };
            if m > 0 && m < count {
                sides = Some((task.start + m, s));
            }
        }
        let (mid, [lb, lc, rb, rc]) = match sides {
            Some(s) => s,
            None => {
                let mid = task.start + count / 2;
                if median {
                    let e = task.centroids.max - task.centroids.min;
                    let axis = if e.x >= e.y && e.x >= e.z { 0 } else if e.y >= e.z { 1 } else { 2 };
                    prims[range.clone()].select_nth_unstable_by(count / 2, |a, b| a.centroid()[axis].total_cmp(&b.centroid()[axis]));
                }
                let (l, r) = (side_bounds(&prims[task.start..mid]), side_bounds(&prims[mid..task.end]));
                (mid, [l.0, l.1, r.0, r.1])
            }
        };
        let left = nodes.len();
        let mut l = BvhNode::zeroed();
        l.set_bounds(&lb.to_aabb());
        let mut r = BvhNode::zeroed();
        r.set_bounds(&rb.to_aabb());
        nodes.push(l);
        nodes.push(r);
        nodes[task.node].left_first = left as u32;
        nodes[task.node].count = 0;
        let depth = task.depth + 1;
        stack.push(Task { node: left + 1, start: mid, end: task.end, centroids: rc, depth });
        stack.push(Task { node: left, start: task.start, end: mid, centroids: lc, depth });
    }
    Bvh { nodes, order: prims.iter().map(Prim::id).collect() }
}

/// Bounds and centroid bounds of a run of primitives.
fn side_bounds(prims: &[Prim]) -> (Box3, Box3) {
    let (mut b, mut c) = (Box3::EMPTY, Box3::EMPTY);
    for p in prims {
        b.grow(p.lo(), p.hi());
        let cc = p.centroid();
        c.grow(cc, cc);
    }
    (b, c)
}

struct Split {
    cost: f32,
    /// (axis, bin scale, first bin of the right side); None: split in the middle.
    plane: Option<(usize, f32, usize)>,
}

impl Split {
    fn middle() -> Split {
        Split { cost: f32::INFINITY, plane: None }
    }
}

#[inline]
fn bin_of(c: f32, cmin: f32, scale: f32) -> usize {
    let b = ((c - cmin) * scale) as isize; // NaN -> 0
    b.clamp(0, BINS as isize - 1) as usize
}

fn best_split(prims: &[Prim], cb: &Box3, bins: &mut [Bin; BINS]) -> Option<Split> {
    // Fewer bins for small nodes: their fixed cost (clearing and sweeping
    // bins) dominates the build, and a handful of primitives needs few planes.
    let nb = match prims.len() {
        0..16 => 4,
        16..64 => 8,
        _ => BINS,
    };
    // Binned along the widest centroid axis only: the SAH plane is almost
    // always there, and binning one axis instead of three is cheaper (on a
    // 1M-triangle knot, three axes for nodes up to 256 primitives took 20%
    // longer to build for 2% fewer traversal steps per primary ray).
    let extent = cb.max - cb.min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z { 0 } else if extent.y >= extent.z { 1 } else { 2 };
    if !(extent[axis] > 0.0 && extent[axis].is_finite()) {
        return None;
    }
    let scale = nb as f32 * (1.0 - 1e-6) / extent[axis];
    // Clear only the bins this node uses (the scratch is reused across nodes).
    bins[..nb].fill(EMPTY_BIN);
    let stride = prims.len().div_ceil(SAMPLE_ABOVE).max(1);
    bin_one_axis(prims, stride, axis, cb.min[axis], scale, bins);
    // Right-to-left sweep: areas and counts of the right sides.
    let mut right_area = [0.0f32; BINS];
    let mut right_count = [0u32; BINS];
    let mut acc = Box3::EMPTY;
    let mut n = 0;
    for i in (1..nb).rev() {
        acc.union(&bins[i].bounds);
        n += bins[i].count;
        right_area[i] = acc.half_area();
        right_count[i] = n;
    }
    let mut best: Option<Split> = None;
    let mut left = Box3::EMPTY;
    let mut nl = 0;
    for i in 1..nb {
        left.union(&bins[i - 1].bounds);
        nl += bins[i - 1].count;
        if nl == 0 || right_count[i] == 0 {
            continue;
        }
        // Counts of a sample stand for `stride` primitives each.
        let cost = (left.half_area() * nl as f32 + right_area[i] * right_count[i] as f32) * stride as f32;
        if best.as_ref().is_none_or(|b| cost < b.cost) {
            best = Some(Split { cost, plane: Some((axis, scale, i)) });
        }
    }
    best
}

/// Bins every `stride`-th primitive along `axis`.
fn bin_one_axis(prims: &[Prim], stride: usize, axis: usize, cmin: f32, scale: f32, bins: &mut [Bin; BINS]) {
    for p in prims.iter().step_by(stride) {
        let c = (p.min[axis] + p.max[axis]) * 0.5;
        let bin = &mut bins[bin_of(c, cmin, scale)];
        bin.bounds.grow(p.lo(), p.hi());
        bin.count += 1;
    }
}

/// Branch-free in-place partition of `prims` by a
/// test on the centroid; returns how many went left and the left bounds,
/// left centroid bounds, right bounds and right centroid bounds.
#[inline(always)]
fn partition(prims: &mut [Prim], left: impl Fn(Vec3A) -> bool) -> (usize, [Box3; 4]) {
    // sides[0]: right, sides[1]: left (indexed by the test's result).
    let mut bounds = [Box3::EMPTY; 2];
    let mut centroids = [Box3::EMPTY; 2];
    let mut j = 0;
    for i in 0..prims.len() {
        let p = prims[i];
        let c = p.centroid();
        let l = left(c) as usize;
        bounds[l].grow(p.lo(), p.hi());
        centroids[l].grow(c, c);
        // Lomuto without a branch: [0, j) went left, [j, i] right.
        prims.swap(i, j);
        j += l;
    }
    (j, [bounds[1], centroids[1], bounds[0], centroids[0]])
}

/// Recomputes node bounds bottom-up after primitives moved (same topology).
/// `bounds[i]` is the bound of primitive i (original numbering).
pub fn refit(bvh: &mut Bvh, bounds: &[Aabb]) {
    for i in (0..bvh.nodes.len()).rev() {
        let node = bvh.nodes[i];
        let mut b = Aabb::EMPTY;
        if node.is_leaf() {
            for k in node.left_first..node.left_first + node.count {
                b.union(&bounds[bvh.order[k as usize] as usize]);
            }
        } else if node.left_first != 0 {
            b = bvh.nodes[node.left_first as usize].bounds();
            b.union(&bvh.nodes[node.left_first as usize + 1].bounds());
        }
        bvh.nodes[i].set_bounds(&b);
    }
}

#[cfg(test)]
mod tests {
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
}
