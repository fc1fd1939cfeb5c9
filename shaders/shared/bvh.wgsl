// The scene's two-level BVH (mirrors src/bvh/build.rs and src/bvh/scene.rs).
// One node array: the TLAS from index 0, then one BLAS per mesh.
// Interior: count == 0, children at left_first and left_first + 1.
// BLAS leaf: triangles left_first .. left_first + count.
// TLAS leaf: count has TLAS_LEAF set; instances left_first .. + (count & ~TLAS_LEAF).
#import scene

const TLAS_LEAF: u32 = 0x80000000u;
const INSTANCE_SPHERE: u32 = 0u;
const INSTANCE_MESH: u32 = 1u;

struct BvhNode {
    bmin: vec3f,
    left_first: u32,
    bmax: vec3f,
    count: u32,
}

struct Instance {
    kind: u32,
    // Sphere index, or the node index of the mesh's BLAS root.
    index: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(1) @binding(6) var<storage, read> scene_bvh: array<BvhNode>;
@group(1) @binding(7) var<storage, read> scene_instances: array<Instance>;
