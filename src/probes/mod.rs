//! Irradiance probes (issue 13), the pure half: how a direction maps to a
//! texel of a probe's maps, and how a position maps to the probes around
//! it. The WGSL the bake and shading passes use mirrors these functions;
//! they are tested here without a GPU.
//!
//! - `mapping`: the thesis's hemisphere maps (Shirley and Chiu's
//!   concentric square-to-disk map lifted to the hemisphere with equal
//!   area, so every bucket of an S x S map covers the same solid angle)
//!   and DDGI's octahedral map of the sphere.
//! - `grid`: a regular grid of probes over the scene's bounds and the
//!   trilinear weights of the eight probes of a point's cell.

pub mod grid;
pub mod mapping;
pub mod volume_file;
pub use grid::ProbeGrid;
