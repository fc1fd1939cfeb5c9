//! The scene's two-level BVH in one node array: the TLAS first (root at 0),
//! then one BLAS per `MeshGpu` over its world-space triangles (every object
//! that never moves shares one: `Scene::pack_at`). TLAS leaves carry
//! `TLAS_LEAF` in `count` and index `instances`; a mesh instance points at
//! its BLAS root, a sphere instance at the sphere.
//!
//! BLASes are cached between frames: a mesh whose triangles did not change
//! keeps its tree, one whose vertices moved is refitted, and the TLAS (a few
//! boxes) is rebuilt whenever anything moved.

use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::{build_with_depth, refit, Aabb, Bvh, BvhBuilder, BvhNode, BLAS_MAX_DEPTH, TLAS_MAX_DEPTH};
use crate::scene::{SceneData, TriangleGpu, TriangleNormalsGpu, TriangleUvGpu};

/// Flag in a TLAS node's `count`: a TLAS leaf (its primitives index `instances`).
pub const TLAS_LEAF: u32 = 0x8000_0000;
/// `InstanceGpu::kind` of a sphere.
pub const INSTANCE_SPHERE: u32 = 0;
/// `InstanceGpu::kind` of a mesh (its BLAS).
pub const INSTANCE_MESH: u32 = 1;

/// `struct Instance` in shaders/shared/bvh.wgsl (16 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct InstanceGpu {
    /// `INSTANCE_SPHERE` or `INSTANCE_MESH`.
    pub kind: u32,
    /// Sphere index, or the node index of the mesh's BLAS root.
    pub index: u32,
    /// Padding; zero.
    pub _pad: [u32; 2],
}

/// What one `SceneBvh::update` built and how long it took.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BuildStats {
    /// Triangles in the scene.
    pub triangles: usize,
    /// Triangles in BLASes built (not reused or refitted) this update.
    pub built_triangles: usize,
    /// Time in the SAH builder alone for those BLASes.
    pub build_ms: f64,
    /// The whole BLAS stage: bounds, builds, refits, reordering.
    pub blas_ms: f64,
    /// Time building the TLAS, in milliseconds.
    pub tlas_ms: f64,
}

impl BuildStats {
    /// Millions of triangles built per second by the SAH builder.
    pub fn mtri_per_s(&self) -> f64 {
        if self.build_ms <= 0.0 { 0.0 } else { self.built_triangles as f64 / (self.build_ms * 1e3) }
    }
}

/// One mesh's BLAS and the (world-space, unordered) triangles it was built for.
struct CachedBlas {
    input: Vec<TriangleGpu>,
    normals: Vec<TriangleNormalsGpu>,
    uvs: Vec<TriangleUvGpu>,
    bvh: Bvh,
}

/// The scene's two-level BVH, with the BLASes cached between updates.
#[derive(Default)]
pub struct SceneBvh {
    cache: Vec<Option<CachedBlas>>,
    builder: BvhBuilder,
}

/// The bounding box of a triangle, what the BLAS builder bins.
pub fn tri_bounds(t: &TriangleGpu) -> Aabb {
    Aabb::of_points(&[Vec3::from(t.p0), Vec3::from(t.p1), Vec3::from(t.p2)])
}

impl SceneBvh {
    /// Fills `data.bvh` and `data.instances` and reorders each mesh's
    /// triangles into BLAS leaf order.
    pub fn update(&mut self, data: &mut SceneData) -> BuildStats {
        let mut stats = BuildStats { triangles: data.triangles.len(), ..Default::default() };
        let blas_start = Instant::now();
        self.cache.resize_with(data.meshes.len(), || None);
        for (m, mesh) in data.meshes.iter().enumerate() {
            let range = mesh.first as usize..(mesh.first + mesh.count) as usize;
            let input = &data.triangles[range.clone()];
            let normals = data.normals.get(range.clone()).unwrap_or(&[]);
            let uvs = data.uvs.get(range.clone()).unwrap_or(&[]);
            let entry = &mut self.cache[m];
            match entry {
                Some(c) if c.input == input && c.normals == normals && c.uvs == uvs => {}
                Some(c) if c.input.len() == input.len() => {
                    let bounds: Vec<Aabb> = input.iter().map(tri_bounds).collect();
                    refit(&mut c.bvh, &bounds);
                    c.input.copy_from_slice(input);
                    c.normals = normals.to_vec();
                    c.uvs = uvs.to_vec();
                }
                _ => {
                    let bounds: Vec<Aabb> = input.iter().map(tri_bounds).collect();
                    let start = Instant::now();
                    let bvh = self.builder.build(&bounds, BLAS_MAX_DEPTH);
                    stats.build_ms += start.elapsed().as_secs_f64() * 1e3;
                    stats.built_triangles += input.len();
                    *entry = Some(CachedBlas { input: input.to_vec(), normals: normals.to_vec(), uvs: uvs.to_vec(), bvh });
                }
            }
            let Some(c) = entry.as_ref() else { continue };
            // Triangles (and their normals and uvs) in leaf order.
            for (k, &p) in c.bvh.order.iter().enumerate() {
                data.triangles[range.start + k] = c.input[p as usize];
                if let (Some(dst), Some(src)) = (data.normals.get_mut(range.start + k), c.normals.get(p as usize)) {
                    *dst = *src;
                }
                if let (Some(dst), Some(src)) = (data.uvs.get_mut(range.start + k), c.uvs.get(p as usize)) {
                    *dst = *src;
                }
            }
        }
        stats.blas_ms = blas_start.elapsed().as_secs_f64() * 1e3;
        // Borrowed, not cloned: this runs every frame something moves.
        let blas_nodes: Vec<&[BvhNode]> =
            self.cache.iter().map(|c| c.as_ref().map_or(&[][..], |c| c.bvh.nodes.as_slice())).collect();

        // TLAS over meshes and spheres.
        let tlas_start = Instant::now();
        let mut inst_bounds = Vec::new();
        let mut inst = Vec::new();
        for (m, nodes) in blas_nodes.iter().enumerate() {
            if data.meshes[m].count > 0 {
                inst_bounds.push(nodes.first().map(BvhNode::bounds).unwrap_or(Aabb::EMPTY));
                inst.push((INSTANCE_MESH, m));
            }
        }
        // Spheres tested apart (`SceneData::spheres_apart`) are not instances.
        let spheres = if data.spheres_apart() { &[][..] } else { &data.spheres[..] };
        for (i, s) in spheres.iter().enumerate() {
            let c = Vec3::from(s.center);
            inst_bounds.push(Aabb { min: c - Vec3::splat(s.radius), max: c + Vec3::splat(s.radius) });
            inst.push((INSTANCE_SPHERE, i));
        }
        let mut tlas = build_with_depth(&inst_bounds, TLAS_MAX_DEPTH);
        // The TLAS always takes as many slots as any tree over these
        // instances can need (2n - 1: every leaf holds one or more), the
        // unused ones empty leaves nothing points to. Its node count changes
        // as things move; this way the node array, the BLAS roots after the
        // TLAS and the uploaded textures keep their sizes and places.
        let slots = 2 * inst_bounds.len().max(1) - 1;
        debug_assert!(tlas.nodes.len() <= slots);
        tlas.nodes.resize(slots, BvhNode { bmin: [0.0; 3], left_first: 0, bmax: [0.0; 3], count: TLAS_LEAF });
        // BLAS m starts after the TLAS and the BLASes before it.
        let mut roots = Vec::with_capacity(blas_nodes.len());
        let mut next = tlas.nodes.len() as u32;
        for b in &blas_nodes {
            roots.push(next);
            next += b.len() as u32;
        }
        data.instances = tlas
            .order
            .iter()
            .map(|&p| {
                let (kind, i) = inst[p as usize];
                let index = if kind == INSTANCE_MESH { roots[i] } else { i as u32 };
                InstanceGpu { kind, index, _pad: [0; 2] }
            })
            .collect();
        let mut nodes: Vec<BvhNode> = tlas.nodes;
        for n in &mut nodes {
            if n.count > 0 {
                n.count |= TLAS_LEAF;
            }
        }
        if data.instances.is_empty() {
            nodes[0].count = TLAS_LEAF; // an empty scene: a leaf with nothing
        }
        stats.tlas_ms = tlas_start.elapsed().as_secs_f64() * 1e3;
        for (m, blas) in blas_nodes.iter().enumerate() {
            let (base, first_tri) = (roots[m], data.meshes[m].first);
            nodes.extend(blas.iter().map(|n| {
                let mut n = *n;
                n.left_first += if n.count > 0 { first_tri } else { base };
                n
            }));
        }
        data.bvh = nodes;
        stats
    }
}
