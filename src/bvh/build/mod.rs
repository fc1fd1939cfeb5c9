//! Binned SAH builder (Wald 2007): at each node the primitives' centroids
//! are binned along the widest centroid axis (a strided sample of the
//! primitives for large nodes) and the cheapest plane by the surface area
//! heuristic is taken; the partition that follows sees every primitive.
//! Subtrees of up to SMALL_MAX primitives are built by sorting instead (see
//! `small.rs`, which also decides where leaves of up to `MAX_LEAF`
//! primitives end).

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A, Vec4};

use super::Aabb;

mod small;
use small::{build_small, SmallBuild, SMALL_MAX};
#[cfg(test)]
use small::{sah_sweep, sort_by_rank, split_pays};

/// Leaves hold at most this many primitives. The shader packs a BLAS
/// node's count into the top three bits of a u32 (REF_COUNT_SHIFT in
/// shaders/shared/bvh.wgsl), so this must stay below 8.
pub const MAX_LEAF: usize = 4;
const _: () = assert!(MAX_LEAF < 8);
const BINS: usize = 12;

/// `struct BvhNode` in shaders/shared/bvh.wgsl (32 bytes). Interior nodes
/// have `count == 0` and children at `left_first` and `left_first + 1`;
/// leaves hold primitives `left_first .. left_first + count`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    /// Box minimum corner.
    pub bmin: [f32; 3],
    /// Index of the first child (interior) or first primitive position (leaf).
    pub left_first: u32,
    /// Box maximum corner.
    pub bmax: [f32; 3],
    /// Primitives in a leaf; 0 for an interior node.
    pub count: u32,
}

impl BvhNode {
    /// The node's box.
    pub fn bounds(&self) -> Aabb {
        Aabb { min: Vec3::from(self.bmin), max: Vec3::from(self.bmax) }
    }
    fn set_bounds(&mut self, b: &Aabb) {
        self.bmin = b.min.to_array();
        self.bmax = b.max.to_array();
    }
    /// Whether it holds primitives (`count > 0`).
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A BVH over primitives `0..n`: `order[i]` is the primitive stored at
/// position i (leaves index into `order`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    /// The nodes; the root is node 0.
    pub nodes: Vec<BvhNode>,
    /// The primitive at each leaf position.
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
    /// Bounds of `lo + hi` (twice the centroids) of the bin's primitives.
    centroid_sums: Box3,
    count: u32,
}

const EMPTY_BIN: Bin = Bin { bounds: Box3::EMPTY, centroid_sums: Box3::EMPTY, count: 0 };

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
/// Default depth bound of the TLAS (its shader stack has 16 entries).
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
    let policy = SmallBuild::for_mesh(n, max_depth);
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
    let mut bins = [[EMPTY_BIN; BINS]; 2];
    while let Some(task) = stack.pop() {
        let count = task.end - task.start;
        if count <= SMALL_MAX {
            build_small(&mut prims[task.start..task.end], task.start, task.node, task.depth, policy, &mut nodes, None);
            continue;
        }
        // More than SMALL_MAX primitives: always split, at the SAH plane, at
        // the centroid median when the depth bound is near, or in the middle
        // when no plane separates the centroids.
        let median = task.depth + balanced_levels(count) >= max_depth;
        let split = if median { None } else { best_split(&prims[task.start..task.end], &task.centroids, &mut bins) };
        let split = split.unwrap_or_else(Split::middle);
        // Partition by the chosen bin; a degenerate result (all on one side,
        // possible with NaN centroids) falls back to the middle.
        let range = task.start..task.end;
        let mut sides = None;
        let mut exact_sides = None;
        if let Some((axis, scale, bin)) = split.plane {
            let cmin = task.centroids.min[axis];
            let below = |x: f32| below_plane(x, cmin, scale, bin);
            let m = match axis {
                0 => partition::<0>(&mut prims[range.clone()], below),
                1 => partition::<1>(&mut prims[range.clone()], below),
                _ => partition::<2>(&mut prims[range.clone()], below),
            };
            if m > 0 && m < count {
                sides = Some(task.start + m);
                exact_sides = split.sides;
            }
        }
        let mid = sides.unwrap_or_else(|| {
            if median {
                let e = task.centroids.max - task.centroids.min;
                let axis = if e.x >= e.y && e.x >= e.z { 0 } else if e.y >= e.z { 1 } else { 2 };
                split_at_median(&mut prims[range.clone()], axis);
            }
            task.start + count / 2
        });
        // The sides' bounds come with the split when every primitive was
        // binned (the partition puts exactly the bins below the plane left).
        let [lb, lc, rb, rc] = exact_sides.unwrap_or_else(|| {
            let ((lb, lc), (rb, rc)) = (side_bounds(&prims[task.start..mid]), side_bounds(&prims[mid..task.end]));
            [lb, lc, rb, rc]
        });
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

/// The key `f32::total_cmp` orders by, of a primitive's centroid along
/// `axis` (doubled: the order is the same).
#[inline]
fn centroid_key(p: &Prim, axis: usize) -> i32 {
    let bits = (p.min[axis] + p.max[axis]).to_bits() as i32;
    bits ^ (((bits >> 31) as u32) >> 1) as i32
}

/// Puts the lower half of `prims` by centroid along `axis` first.
fn split_at_median(prims: &mut [Prim], axis: usize) {
    let n = prims.len();
    prims.select_nth_unstable_by_key(n / 2, |p| centroid_key(p, axis));
}

/// Bounds and centroid bounds of a run of primitives. Two accumulators
/// halve the min/max dependency chains; the centroid bounds are taken over
/// `lo + hi` and halved once at the end, which is exact (halving is exact
/// and monotonic, so it commutes with min and max).
// The four passes over a node's primitives (side_bounds, best_split,
// bin_one_axis, partition) stay out of line: inlined into build_prims, the
// 1M-triangle build took 254 instead of 178 ms (register pressure).
#[inline(never)]
fn side_bounds(prims: &[Prim]) -> (Box3, Box3) {
    let mut acc = [(Box3::EMPTY, Box3::EMPTY); 2];
    let pairs = prims.chunks_exact(2);
    let rest = pairs.remainder();
    for pair in pairs {
        for (p, (b, c)) in pair.iter().zip(acc.iter_mut()) {
            let (lo, hi) = (p.lo(), p.hi());
            b.grow(lo, hi);
            let s = lo + hi;
            c.grow(s, s);
        }
    }
    for p in rest {
        let (lo, hi) = (p.lo(), p.hi());
        acc[0].0.grow(lo, hi);
        let s = lo + hi;
        acc[0].1.grow(s, s);
    }
    let [(mut b, mut c), (b1, c1)] = acc;
    b.union(&b1);
    c.union(&c1);
    c.min *= 0.5;
    c.max *= 0.5;
    (b, c)
}

struct Split {
    cost: f32,
    /// (axis, bin scale, first bin of the right side); None: split in the middle.
    plane: Option<(usize, f32, usize)>,
    /// When every primitive was binned: the bounds and centroid bounds of
    /// the left and right sides, the union of their bins.
    sides: Option<[Box3; 4]>,
}

impl Split {
    fn middle() -> Split {
        Split { cost: f32::INFINITY, plane: None, sides: None }
    }
}

/// `bin_of(c, ..) < first_right` as one float compare: the same for every
/// centroid, NaN included (bin_of puts NaN in bin 0).
#[inline(always)]
fn below_plane(c: f32, cmin: f32, scale: f32, first_right: usize) -> bool {
    let v = (c - cmin) * scale;
    v < first_right as f32 || v.is_nan()
}

#[inline]
fn bin_of(c: f32, cmin: f32, scale: f32) -> usize {
    let b = ((c - cmin) * scale) as i32; // NaN -> 0
    b.clamp(0, BINS as i32 - 1) as usize
}

#[inline(never)]
fn best_split(prims: &[Prim], cb: &Box3, bin_sets: &mut [[Bin; BINS]; 2]) -> Option<Split> {
    // Fewer bins for small nodes: their fixed cost (clearing and sweeping
    // bins) dominates the build, and a handful of primitives needs few planes.
    let nb = if prims.len() < 64 { 8 } else { BINS };
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
    for set in bin_sets.iter_mut() {
        set[..nb].fill(EMPTY_BIN);
    }
    let stride = prims.len().div_ceil(SAMPLE_ABOVE).max(1);
    let cmin = cb.min[axis];
    match axis {
        0 => bin_one_axis::<0>(prims, stride, cmin, scale, bin_sets, nb),
        1 => bin_one_axis::<1>(prims, stride, cmin, scale, bin_sets, nb),
        _ => bin_one_axis::<2>(prims, stride, cmin, scale, bin_sets, nb),
    }
    let bins = &bin_sets[0];
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
            best = Some(Split { cost, plane: Some((axis, scale, i)), sides: None });
        }
    }
    if let Some(Split { plane: Some((_, _, first_right)), sides, .. }) = &mut best {
        if stride == 1 {
            let side = |bins: &[Bin]| {
                let (mut b, mut c) = (Box3::EMPTY, Box3::EMPTY);
                for bin in bins {
                    b.union(&bin.bounds);
                    c.union(&bin.centroid_sums);
                }
                (c.min, c.max) = (c.min * 0.5, c.max * 0.5);
                (b, c)
            };
            let ((lb, lc), (rb, rc)) = (side(&bins[..*first_right]), side(&bins[*first_right..nb]));
            *sides = Some([lb, lc, rb, rc]);
        }
    }
    best
}

/// Bins every `stride`-th primitive along `AXIS`. Consecutive primitives
/// alternate between two sets of bins, merged at the end: neighbours in a
/// mesh mostly fall in the same bin, and with one set each update waited
/// for the store of the one before.
#[inline(never)]
fn bin_one_axis<const AXIS: usize>(prims: &[Prim], stride: usize, cmin: f32, scale: f32, bin_sets: &mut [[Bin; BINS]; 2], nb: usize) {
    #[inline(always)]
    fn add<const AXIS: usize>(bins: &mut [Bin; BINS], p: &Prim, cmin: f32, scale: f32) {
        let (lo, hi) = (p.lo(), p.hi());
        let sum = lo + hi;
        let bin = &mut bins[bin_of(sum[AXIS] * 0.5, cmin, scale)];
        bin.bounds.grow(lo, hi);
        bin.centroid_sums.grow(sum, sum);
        bin.count += 1;
    }
    let [bins, other] = bin_sets;
    if stride == 1 {
        let pairs = prims.chunks_exact(2);
        if let [p] = pairs.remainder() {
            add::<AXIS>(bins, p, cmin, scale);
        }
        for pair in pairs {
            add::<AXIS>(bins, &pair[0], cmin, scale);
            add::<AXIS>(other, &pair[1], cmin, scale);
        }
    } else {
        for (k, p) in prims.iter().step_by(stride).enumerate() {
            add::<AXIS>(if k % 2 == 0 { &mut *bins } else { &mut *other }, p, cmin, scale);
        }
    }
    for (b, o) in bins[..nb].iter_mut().zip(other[..nb].iter()) {
        b.bounds.union(&o.bounds);
        b.centroid_sums.union(&o.centroid_sums);
        b.count += o.count;
    }
}

/// Branch-free in-place partition (Lomuto) of `prims` by a test on one
/// centroid coordinate; returns how many went left. The child bounds are
/// gathered afterwards by `side_bounds`, in registers: gathering them here
/// meant indexing the four boxes by the test's result, a store and reload
/// per primitive that held the loop to the store-forwarding latency.
#[inline(never)]
fn partition<const AXIS: usize>(prims: &mut [Prim], left: impl Fn(f32) -> bool) -> usize {
    let mut j = 0;
    for i in 0..prims.len() {
        let l = left((prims[i].min[AXIS] + prims[i].max[AXIS]) * 0.5) as usize;
        // [0, j) went left, [j, i] right. A whole-element swap: copying the
        // element out by value let the compiler split it into scalars, and
        // the next vector load of the same element missed store forwarding.
        prims.swap(i, j);
        j += l;
    }
    j
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
mod tests;
