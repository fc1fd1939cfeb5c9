//! glint: a real-time ray tracer built from WGSL compute passes.
//!
//! Data flow (DESIGN.md section 2): a RON scene is loaded into an hecs world,
//! a RON frame graph is compiled (pure, no GPU) against shader reflections and
//! scene features into a `Schedule`, and the executor records one command
//! encoder per frame from it.

pub mod bvh;
pub mod camera_path;
pub mod cli;
pub mod control;
pub mod error;
pub mod gpu;
pub mod graph;
pub mod image_io;
pub mod machines;
pub mod metrics;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shader;
pub mod stats;
