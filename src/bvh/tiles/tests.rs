//! The screen tiles' cuts: camera rays through every pixel of a tile, at
//! any sub-pixel offset, hit what brute force hits from the tile's cut, bit
//! for bit; the cuts leave out what the tile cannot see; the table's layout.

use glam::Vec3;

use super::*;
use crate::bvh::entry::tests::{entries_above_leaves, room, root, Rng};
use crate::bvh::ray::{Geometry, Ray};
use crate::scene::SceneData;

fn camera(origin: Vec3, target: Vec3, vfov_deg: f32, size: (u32, u32)) -> PixelCamera {
    let forward = (target - origin).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    PixelCamera {
        origin,
        forward,
        right,
        up: right.cross(forward),
        tan_half_fov: (vfov_deg.to_radians() * 0.5).tan(),
        aspect: size.0 as f32 / size.1 as f32,
        size,
    }
}

fn geometry(data: &SceneData) -> Geometry<'_> {
    Geometry { spheres: &data.spheres, triangles: &data.triangles, nodes: &data.bvh, instances: &data.instances }
}

/// Leaves under no entry: those the tile's frustum cannot reach (some
/// node above them, or they, lie outside it). Panics where a leaf lies
/// under two entries.
fn leaves_left_out(nodes: &[BvhNode], root: u32, cut: &[u32]) -> usize {
    let leaves = entries_above_leaves(nodes, root, cut);
    for &(i, n) in &leaves {
        assert!(n <= 1, "leaf {i} lies under {n} entries");
    }
    leaves.iter().filter(|&&(_, n)| n == 0).count()
}

#[test]
fn tiles_grow_with_the_image_to_fit_the_table() {
    assert_eq!(tile_log2((1280, 720)), 4);
    assert_eq!(tile_grid((1280, 720), 4), (80, 45));
    assert_eq!(tile_log2((1920, 1080)), 5);
    assert_eq!(tile_log2((3840, 2160)), 6);
    assert_eq!(tile_grid((3840, 2160), 6), (60, 34));
    assert_eq!(tile_log2((64, 48)), MIN_TILE_LOG2);
    assert_eq!(tile_grid((17, 16), 4), (2, 1));
    assert_eq!(tile_grid((0, 0), 4), (0, 0));
}

/// Every pixel of a 96 x 64 image (6 x 4 tiles), at its corner, centre and
/// far corner and at a random offset, from cameras inside the room, on its
/// walls and floor, in a corner and outside it.
#[test]
fn pixel_rays_from_their_tiles_cut_hit_what_brute_force_hits() {
    let data = room(3000);
    let g = geometry(&data);
    let size = (96, 64);
    let views = [
        (Vec3::new(0.3, 3.9, 0.1), Vec3::new(10.0, 3.9, 0.1), 60.0),
        (Vec3::new(-8.0, 1.0, -4.0), Vec3::new(9.0, 6.0, 5.0), 90.0),
        (Vec3::new(1.0, 0.0, 1.0), Vec3::new(1.0, 8.0, 1.0), 70.0),
        (Vec3::new(10.0, 4.0, 2.0), Vec3::new(-10.0, 4.0, 2.0), 45.0),
        (Vec3::new(-10.0, 0.0, -6.0), Vec3::new(0.0, 4.0, 0.0), 30.0),
        (Vec3::new(0.0, 4.0, 40.0), Vec3::new(0.0, 4.0, 0.0), 40.0),
        // Looking away from the room: every tile misses it.
        (Vec3::new(0.0, 4.0, 40.0), Vec3::new(0.0, 4.0, 80.0), 40.0),
    ];
    let mut rng = Rng(777);
    let (mut hits, mut rays, mut left_out, mut expanded) = (0, 0, 0, 0);
    for (origin, target, fov) in views {
        let cam = camera(origin, target, fov, size);
        let log2 = tile_log2(size);
        let (tx_n, ty_n) = tile_grid(size, log2);
        for ty in 0..ty_n {
            for tx in 0..tx_n {
                let cut = tile_cut(&data.bvh, root(&data), &cam.tile_frustum(log2, (tx, ty))).expect("a cut within the budget");
                left_out += usize::from(leaves_left_out(&data.bvh, root(&data), &cut) > 0);
                expanded += usize::from(cut.len() > 1);
                for y in ty << log2..(ty + 1) << log2 {
                    for x in tx << log2..(tx + 1) << log2 {
                        for (jx, jy) in [(0.0, 0.0), (0.5, 0.5), (0.99999, 0.99999), (rng.unit(), rng.unit())] {
                            let r = Ray::new(origin, cam.dir(x as f32 + jx, y as f32 + jy));
                            let want = g.closest_brute(&r, f32::INFINITY);
                            assert_eq!(g.closest_from(&r, f32::INFINITY, &cut), want, "camera {origin}, pixel ({x}, {y}) + ({jx}, {jy})");
                            hits += usize::from(want.is_some());
                            rays += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(hits > rays / 2, "{hits} of {rays} rays hit");
    // The tiles really leave subtrees out, and go below the root.
    assert!(left_out > 100, "{left_out} of 168 tiles left something out");
    assert!(expanded > 80, "{expanded} of 168 tiles have more than one entry");
}

#[test]
fn a_frustum_keeps_the_boxes_its_rays_reach_and_drops_the_rest() {
    let cam = camera(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), 90.0, (64, 64));
    // The tile at the top left sees up and to the left.
    let f = cam.tile_frustum(4, (0, 0));
    let node = |lo: [f32; 3], hi: [f32; 3]| BvhNode { bmin: lo, left_first: 0, bmax: hi, count: 1 };
    assert!(f.may_hit(&node([-6.0, 4.0, -6.0], [-4.0, 6.0, -4.0])));
    assert!(!f.may_hit(&node([4.0, -6.0, -6.0], [6.0, -4.0, -4.0])));
    // Behind the camera.
    assert!(!f.may_hit(&node([-6.0, 4.0, 4.0], [-4.0, 6.0, 6.0])));
    // A box around the camera is entered by every ray.
    assert!(f.worth_expanding(&node([-1.0; 3], [1.0; 3])));
    assert!(!f.worth_expanding(&node([-6.0, 4.0, -6.0], [-5.9, 4.1, -5.9])));
}

#[test]
fn a_node_is_expanded_when_a_third_of_the_tiles_rays_enter_it() {
    // The tile at the top left of a 90 degree view down -z spans x in
    // [-1, -0.5] and y in [0.5, 1] at z = -1. Its 3 x 3 sample rays cross
    // z = -1 in columns at x = -0.917, -0.75, -0.583 and rows at y = 0.917,
    // 0.75, 0.583; the boxes below end at z = -1.1.
    let cam = camera(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), 90.0, (64, 64));
    let f = cam.tile_frustum(4, (0, 0));
    let node = |x1: f32, y0: f32| BvhNode { bmin: [-1.5, y0, -1.1], left_first: 0, bmax: [x1, 2.0, -0.9], count: 1 };
    // The left column: 3 of 9.
    assert!(f.worth_expanding(&node(-0.95, 0.0)));
    // Its top ray alone, in the frustum all the same.
    assert!(!f.worth_expanding(&node(-0.95, 0.95)));
    assert!(f.may_hit(&node(-0.95, 0.95)));
    // None.
    assert!(!f.worth_expanding(&node(-1.2, 0.0)));
}

#[test]
fn the_table_holds_each_tiles_entries_in_push_order() {
    let data = room(1000);
    let cam = camera(Vec3::new(0.3, 3.9, 0.1), Vec3::new(10.0, 3.9, 0.1), 60.0, (100, 40));
    let table = tile_table(&data.bvh, root(&data), &cam).expect("7 x 3 tiles fit");
    assert_eq!((table.log2, table.tiles_x), (4, 7));
    assert_eq!(table.texels.len(), MAX_TILES * TILE_TEXELS);
    for ty in 0..3 {
        for tx in 0..7 {
            let cut = tile_cut(&data.bvh, root(&data), &cam.tile_frustum(4, (tx, ty))).unwrap();
            let at = (ty * 7 + tx) as usize * TILE_TEXELS;
            assert_eq!(table.texels[at][0] as usize, cut.len());
            for (e, &i) in cut.iter().enumerate() {
                let n = &data.bvh[i as usize];
                assert_eq!(table.texels[at + 1 + 2 * e][3], n.left_first | (n.count << crate::bvh::entry::REF_COUNT_SHIFT));
                assert_eq!(table.texels[at + 2 + 2 * e], [n.bmax[0].to_bits(), n.bmax[1].to_bits(), n.bmax[2].to_bits(), i]);
            }
        }
    }
    // Past the last tile, nothing.
    assert!(table.texels[21 * TILE_TEXELS..].iter().all(|t| *t == [0; 4]));
    // An image that would need more tiles than the table holds has none.
    let huge = camera(Vec3::ZERO, Vec3::X, 60.0, (4_000_000_000, 4_000_000_000));
    assert_eq!(tile_table(&data.bvh, root(&data), &huge), None);
}

#[test]
fn the_shaders_read_the_table_as_it_is_laid_out() {
    let wgsl = include_str!("../../../shaders/shared/bvh.wgsl");
    for (name, value) in [("MAX_TILES", MAX_TILES), ("TILE_TEXELS", TILE_TEXELS), ("MAX_TILE_ENTRIES", MAX_TILE_ENTRIES)] {
        assert!(wgsl.contains(&format!("const {name}: u32 = {value}u;")), "bvh.wgsl declares {name} = {value}");
    }
}
