//! Irradiance probes, the Rust side of the irradiance volume
//! (docs/global-illumination.md): how a direction maps to a texel of a probe's
//! maps, how a position maps to the probes around it, and the volume file.
//! shaders/shared/probes.wgsl mirrors the maps and the grid; they are
//! tested here without a GPU and against the shaders in
//! tests/probes_gpu.rs.
//!
//! - `mapping`: the thesis's hemisphere maps (Shirley and Chiu's
//!   concentric square-to-disk map lifted to the hemisphere with equal
//!   area, so every bucket of an S x S map covers the same solid angle)
//!   and DDGI's octahedral map of the sphere.
//! - `grid`: a regular grid of probes over the scene's bounds and the
//!   trilinear weights of the eight probes of a point's cell.
//! - `volume_file`: a baked volume on disk, with a header naming its scene
//!   and grid so a stale one is refused.

pub mod grid;
pub mod mapping;
pub mod volume_file;
pub use grid::ProbeGrid;
