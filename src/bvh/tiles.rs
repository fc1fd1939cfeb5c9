//! Where the camera rays of each screen tile enter a BLAS (after the
//! multi-level ray tracing of Reshetov, Soupikov and Hurley 2005). Camera
//! rays through neighbouring pixels walk almost the same nodes: inside
//! Sponza, of a primary ray's 52 node trips from the root, 47 are trips
//! every ray of its 16 x 16 pixel tile takes. Once a frame the engine
//! works out, per tile, a cut of the tree below those nodes (`tile_cut`),
//! and a camera ray through the tile starts from it: it tests the cut's
//! boxes and pushes those it hits, as it does the camera's entries
//! (`super::entry`), and goes on from there.
//!
//! The cut differs from the camera's in one way: it leaves out the
//! subtrees whose boxes lie wholly outside the tile's frustum (widened by
//! `FRUSTUM_MARGIN_PX` pixels), which no ray through the tile can reach.
//! So a tile's entries serve the camera rays through that tile's pixels
//! (any sub-pixel offset) and nothing else. Every other leaf lies under
//! exactly one entry, so those rays hit what they hit from the root; the
//! Rust mirror (`Geometry::closest_from`) checks this against brute force.

use glam::Vec3;

use super::entry::{distance2, entry_texels, holds};
use super::ray::{hit_box, Ray, STACK};
use super::{BvhNode, BLAS_MAX_DEPTH};

/// Pixels on a side of the smallest tile (2^4 = 16).
pub const MIN_TILE_LOG2: u32 = 4;
/// Tiles the table holds: larger images take larger tiles (32 x 32 from
/// 1920 x 1080 on, 64 x 64 from 4K), so its size is fixed per scene.
pub const MAX_TILES: usize = 4096;
/// Entries a tile holds at most. Inside Sponza at 1280 x 720 a tile's cut
/// has 12.6 on average.
pub const MAX_TILE_ENTRIES: usize = 15;
/// Texels per tile in the table: a header, then two per entry.
pub const TILE_TEXELS: usize = 32;
const _: () = assert!(2 * MAX_TILE_ENTRIES < TILE_TEXELS);
// An entry pushed j-th sits on j others, its subtree at most
// BLAS_MAX_DEPTH levels deep: the stack always holds it.
const _: () = assert!(MAX_TILE_ENTRIES + BLAS_MAX_DEPTH as usize <= STACK);
/// How far beyond its pixels a tile's frustum reaches: rounding in the
/// directions and planes never drops a subtree a ray through the tile
/// can reach.
pub const FRUSTUM_MARGIN_PX: f32 = 1.0;

/// The tile size for an image: the smallest power of two from
/// 2^MIN_TILE_LOG2 whose tiles fit MAX_TILES.
pub fn tile_log2(size: (u32, u32)) -> u32 {
    let mut log2 = MIN_TILE_LOG2;
    while tile_grid(size, log2).0 as usize * tile_grid(size, log2).1 as usize > MAX_TILES && log2 < 16 {
        log2 += 1;
    }
    log2
}

/// Tiles across and down.
pub fn tile_grid(size: (u32, u32), log2: u32) -> (u32, u32) {
    let side = 1u32 << log2;
    (size.0.div_ceil(side), size.1.div_ceil(side))
}

/// Sample rays a side of a tile (`TileFrustum::worth_expanding`).
pub const EXPAND_GRID: usize = 3;
/// Of the EXPAND_GRID^2 sample rays, how many must enter a node for the
/// cut to go below it: a third. Expanding a node adds one entry, which
/// every ray of the tile tests (two texels and one box, a fraction of a
/// trip), and saves each ray that enters the node the trip that would
/// test its children; a cut below partly covered nodes also leaves out
/// more of what the frustum misses. On the 1M-triangle knot (`glint
/// bench rays --trips`, 1280 x 720) the busiest lane of 8 took 11.31 BLAS
/// trips a ray where only nodes every ray enters were expanded; with
/// 2, 3 or 4 of 3 x 3 samples 9.39, 9.24 or 9.54; with 13, 8, 3 or 1 of
/// 5 x 5, 9.72, 9.32, 9.47 or 9.81 (and the table took twice the time).
pub const EXPAND_MIN_HITS: usize = 3;

/// The rays through one tile: from `origin` along the directions within
/// the four corner directions (a convex cone), bounded by four planes
/// through the origin.
#[derive(Debug, Clone)]
pub struct TileFrustum {
    /// The camera position all the rays start from.
    pub origin: Vec3,
    /// Rays through the centres of an EXPAND_GRID x EXPAND_GRID grid of
    /// the tile's pixels (`worth_expanding`), made once per tile, not
    /// per box tested (inside Sponza making rays per box took a fifth of
    /// the table's time, by `perf`).
    pub samples: [Ray; EXPAND_GRID * EXPAND_GRID],
    /// Inward normals of the side planes, through the corners widened by
    /// FRUSTUM_MARGIN_PX (`may_hit`).
    normals: [Vec3; 4],
}

impl TileFrustum {
    /// The frustum of the pixels in [x0, x1] x [y0, y1] (continuous pixel
    /// coordinates; `dir` maps them to a ray direction, as `camera_dir`),
    /// its side planes widened by FRUSTUM_MARGIN_PX. Which nodes are
    /// expanded (`worth_expanding`, by sample rays within the tile's own
    /// pixels) changes no hit.
    pub fn new(origin: Vec3, (x0, y0): (f32, f32), (x1, y1): (f32, f32), dir: impl Fn(f32, f32) -> Vec3) -> TileFrustum {
        let at = |i: usize, lo: f32, hi: f32| lo + (i as f32 + 0.5) / EXPAND_GRID as f32 * (hi - lo);
        let samples = std::array::from_fn(|k| {
            let (i, j) = (k % EXPAND_GRID, k / EXPAND_GRID);
            Ray::new(origin, dir(at(i, x0, x1), at(j, y0, y1)))
        });
        let m = FRUSTUM_MARGIN_PX;
        let (x0, y0, x1, y1) = (x0 - m, y0 - m, x1 + m, y1 + m);
        let wide = [dir(x0, y0), dir(x1, y0), dir(x1, y1), dir(x0, y1)];
        let centre = wide.iter().copied().sum::<Vec3>();
        let normals = std::array::from_fn(|i| {
            let n = wide[i].cross(wide[(i + 1) % 4]);
            if n.dot(centre) < 0.0 { -n } else { n }
        });
        TileFrustum { origin, samples, normals }
    }

    /// False only where no ray of the frustum can reach the box: the box
    /// lies wholly outside one side plane.
    pub fn may_hit(&self, n: &BvhNode) -> bool {
        let (lo, hi) = (Vec3::from(n.bmin) - self.origin, Vec3::from(n.bmax) - self.origin);
        self.normals.iter().all(|&nrm| {
            // The box corner farthest along the normal.
            let far = Vec3::select(nrm.cmpgt(Vec3::ZERO), hi, lo);
            nrm.dot(far) >= 0.0
        })
    }

    /// Whether the cut goes below this node: it holds the camera, or at
    /// least EXPAND_MIN_HITS of the sample rays enter its box.
    pub fn worth_expanding(&self, n: &BvhNode) -> bool {
        if holds(n, self.origin) {
            return true;
        }
        let (lo, hi) = (Vec3::from(n.bmin), Vec3::from(n.bmax));
        let mut hits = 0;
        for (k, r) in self.samples.iter().enumerate() {
            if hits + (self.samples.len() - k) < EXPAND_MIN_HITS {
                return false;
            }
            hits += usize::from(hit_box(r, lo, hi, f32::MAX).is_some());
            if hits >= EXPAND_MIN_HITS {
                return true;
            }
        }
        false
    }
}

/// The cut of the BLAS at `root` for the rays of `frustum`, in push order
/// (the last is popped first): at most MAX_TILE_ENTRIES entries, or None
/// where a node index lies outside `nodes` (`tile_table` then gives the
/// tile the root as its one entry). Nodes enough of the frustum's rays
/// enter (`worth_expanding`) are expanded while the cut fits, children
/// taken as `camera_cut` takes them (the one holding the camera first,
/// else the nearer); subtrees
/// outside the frustum are left out. Empty where the frustum misses the
/// root's box.
pub fn tile_cut(nodes: &[BvhNode], root: u32, frustum: &TileFrustum) -> Option<Vec<u32>> {
    let mut cut: Vec<u32> = Vec::new();
    let mut todo = vec![root];
    while let Some(i) = todo.pop() {
        let n = nodes.get(i as usize)?;
        if !frustum.may_hit(n) {
            continue;
        }
        let expand = !n.is_leaf() && cut.len() + todo.len() + 2 <= MAX_TILE_ENTRIES && frustum.worth_expanding(n);
        if !expand {
            cut.push(i);
            if cut.len() > MAX_TILE_ENTRIES {
                return None;
            }
            continue;
        }
        let (a, b) = (n.left_first, n.left_first + 1);
        let (na, nb) = (nodes.get(a as usize)?, nodes.get(b as usize)?);
        let o = frustum.origin;
        let b_first = match (holds(na, o), holds(nb, o)) {
            (true, _) => false,
            (false, true) => true,
            (false, false) => distance2(nb, o) < distance2(na, o),
        };
        let (first, second) = if b_first { (b, a) } else { (a, b) };
        todo.push(second);
        todo.push(first);
    }
    cut.reverse();
    Some(cut)
}

/// The camera as `camera_dir` in shaders/shared/frame.wgsl sees it: what
/// maps a pixel to its ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelCamera {
    /// The camera position.
    pub origin: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit right vector.
    pub right: Vec3,
    /// Unit up vector, orthogonal to `forward` and `right`.
    pub up: Vec3,
    /// tan(vertical field of view / 2).
    pub tan_half_fov: f32,
    /// width / height
    pub aspect: f32,
    /// The image size in pixels (width, height).
    pub size: (u32, u32),
}

impl PixelCamera {
    /// The direction through continuous pixel coordinates (x, y) (pixel
    /// (i, j) spans [i, i + 1) x [j, j + 1)), normalised.
    pub fn dir(&self, x: f32, y: f32) -> Vec3 {
        let sx = (2.0 * x / self.size.0 as f32 - 1.0) * self.aspect * self.tan_half_fov;
        let sy = (1.0 - 2.0 * y / self.size.1 as f32) * self.tan_half_fov;
        (self.forward + sx * self.right + sy * self.up).normalize()
    }

    /// The frustum of tile (tx, ty) of side 2^log2 pixels.
    pub fn tile_frustum(&self, log2: u32, (tx, ty): (u32, u32)) -> TileFrustum {
        let side = (1u32 << log2) as f32;
        let (x0, y0) = (tx as f32 * side, ty as f32 * side);
        TileFrustum::new(self.origin, (x0, y0), (x0 + side, y0 + side), |x, y| self.dir(x, y))
    }
}

/// The table the shaders read (`scene_tiles`): tile t (row-major, `tiles_x`
/// across) at texels t * TILE_TEXELS: a header (entry count), then its
/// entries as `camera_entries` lays them out, in push order. A tile whose
/// cut was refused has the root as its one entry; a tile whose frustum
/// misses the BLAS has none.
#[derive(Debug, Clone, PartialEq)]
pub struct TileTable {
    /// The tile side, log2 of pixels.
    pub log2: u32,
    /// Tiles per row.
    pub tiles_x: u32,
    /// The table's texels, as uploaded.
    pub texels: Vec<[u32; 4]>,
}

/// The tile table of the BLAS at `root` for `camera`; None where the image
/// needs more than MAX_TILES tiles (the shaders then start at the root).
pub fn tile_table(nodes: &[BvhNode], root: u32, camera: &PixelCamera) -> Option<TileTable> {
    let log2 = tile_log2(camera.size);
    let (tiles_x, tiles_y) = tile_grid(camera.size, log2);
    if tiles_x as usize * tiles_y as usize > MAX_TILES || nodes.get(root as usize).is_none() {
        return None;
    }
    let mut texels = vec![[0u32; 4]; MAX_TILES * TILE_TEXELS];
    for ty in 0..tiles_y {
        for tx in 0..tiles_x {
            let cut = tile_cut(nodes, root, &camera.tile_frustum(log2, (tx, ty))).unwrap_or_else(|| vec![root]);
            let at = (ty * tiles_x + tx) as usize * TILE_TEXELS;
            texels[at][0] = cut.len() as u32;
            for (e, &i) in cut.iter().enumerate() {
                let [lo, hi] = entry_texels(nodes, i);
                texels[at + 1 + 2 * e] = lo;
                texels[at + 2 + 2 * e] = hi;
            }
        }
    }
    Some(TileTable { log2, tiles_x, texels })
}

#[cfg(test)]
mod tests;
