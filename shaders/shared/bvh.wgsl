// The scene's two-level BVH (mirrors src/bvh/build/mod.rs and src/bvh/scene.rs).
// One node array: the TLAS from index 0, then one BLAS per mesh.
// Interior: count == 0, children at left_first and left_first + 1.
// BLAS leaf: triangles left_first .. left_first + count.
// TLAS leaf: count has TLAS_LEAF set; instances left_first .. + (count & ~TLAS_LEAF).
#import scene

const TLAS_LEAF: u32 = 0x80000000u;
const INSTANCE_SPHERE: u32 = 0u;
const INSTANCE_MESH: u32 = 1u;

// (bmin, left_first) and (bmax, count), the u32s as float bits: two
// texels of scene_geometry per node, after the triangles (see scene.wgsl).
struct BvhNode {
    lo: vec4f,
    hi: vec4f,
}

fn node_first(n: BvhNode) -> u32 {
    return bitcast<u32>(n.lo.w);
}

fn node_count(n: BvhNode) -> u32 {
    return bitcast<u32>(n.hi.w);
}

// v = (kind, index, _, _): index is the sphere, or the node of the mesh's
// BLAS root. One texel.
struct Instance {
    v: vec4u,
}

@group(1) @binding(7) var scene_instances: texture_storage_2d<rgba32uint, read>;

// Where the camera's rays enter the BLAS of a one-mesh scene (mirrors
// src/bvh/entry.rs): `count.x` entries of two texels, (bmin, node_ref)
// and (bmax, node index), pushed in order (the last is popped first, as
// a traversal from the root would reach it first). None (count 0)
// where the camera is outside the mesh's box or the scene is not one mesh.
// `count.y` and `count.z`: the tile table's tile size (log2; 0: no
// table) and tiles across; `count.w`: the BLAS root as a node_ref (where a
// one-mesh scene's rays start).
const MAX_CAMERA_ENTRIES: u32 = 32u;
struct CameraEntries {
    count: vec4u,
    entries: array<vec4u, 64>,
}
@group(1) @binding(11) var<uniform> scene_entries: CameraEntries;

// Where the camera rays through each screen tile enter that BLAS (mirrors
// src/bvh/tiles.rs): tile t (row-major) at texel t * TILE_TEXELS, its
// entry count, then its entries as above. They serve only camera rays
// through the tile's own pixels: subtrees outside its frustum are left out.
const MAX_TILES: u32 = 4096u;
const TILE_TEXELS: u32 = 32u;
const MAX_TILE_ENTRIES: u32 = 15u;
@group(1) @binding(12) var scene_tiles: texture_storage_2d<rgba32uint, read>;

// The texel of node 0 in scene_geometry.
fn node_texel_base() -> u32 {
    return 3u * frame.n_triangles;
}

fn load_node(i: u32) -> BvhNode {
    let t = node_texel_base() + 2u * i;
    return BvhNode(bitcast<vec4f>(scene_texel(scene_geometry, t)), bitcast<vec4f>(scene_texel(scene_geometry, t + 1u)));
}

fn load_instance(i: u32) -> Instance {
    return Instance(scene_texel(scene_instances, i));
}

// A BLAS node as one u32: first child / first triangle in the low bits,
// the leaf's triangle count (0: interior) in the top three (BLAS leaves
// hold at most MAX_LEAF = 4; a binding holds far fewer than 2^29 nodes).
const REF_COUNT_SHIFT: u32 = 29u;
const REF_FIRST: u32 = 0x1fffffffu;

fn node_ref(n: BvhNode) -> u32 {
    return node_first(n) | (node_count(n) << REF_COUNT_SHIFT);
}
