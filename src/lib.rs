//! glint: a real-time ray tracer built from WGSL compute passes.
//!
//! Data flow (docs/ARCHITECTURE.md): a RON scene is loaded into an hecs
//! world, a RON frame graph is compiled (pure, no GPU) against shader
//! reflections and scene features into a `Schedule`, and the executor
//! records one command encoder per frame from it. A `session::Session`
//! owns all of it, rebuilds aside and swaps on success; every front end
//! (the CLI, the viewer, the tests) renders through it.

#![warn(missing_docs)]

pub mod batches;
pub mod blue_noise;
pub mod brdf;
pub mod bvh;
pub mod camera_path;
#[cfg(test)]
mod chi2;
pub mod cli;
pub mod control;
pub mod error;
pub mod format;
pub mod gpu;
pub mod graph;
pub mod image_io;
pub mod machines;
pub mod mean;
pub mod metrics;
pub mod probes;
pub mod reload;
pub mod sampling;
pub mod scene;
pub mod session;
pub mod shader;
pub mod stats;
pub mod trade;
pub mod viewer;
