//! Acceleration (docs/acceleration.md): binned-SAH BVHs over triangles (BLAS)
//! built on the CPU, a TLAS over instances (meshes, spheres, light spheres),
//! the flattened GPU layout, and a Rust mirror of the WGSL ray math and
//! traversal for exhaustive CPU tests.

pub mod aabb;
pub mod build;
pub mod entry;
pub mod offset;
pub mod origin;
pub mod ray;
pub mod scene;
pub mod tiles;
#[cfg(test)]
mod tests;

pub use aabb::Aabb;
pub use build::{build, build_with_depth, refit, Bvh, BvhBuilder, BvhNode, BLAS_MAX_DEPTH, MAX_LEAF, TLAS_MAX_DEPTH};
