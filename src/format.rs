//! Texture formats: plain data shared by the shader reflection, the frame
//! graph and GPU readback (no layer above this one is imported here).

use serde::Deserialize;

/// Texture formats a graph may declare: the storage-capable WGSL formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
pub enum TexFormat {
    R32Float,
    Rg32Float,
    Rgba32Float,
    Rgba16Float,
    R32Uint,
    Rg32Uint,
    Rgba32Uint,
    Rgba8Unorm,
}

impl TexFormat {
    pub fn bytes_per_pixel(self) -> u64 {
        match self {
            TexFormat::R32Float | TexFormat::R32Uint | TexFormat::Rgba8Unorm => 4,
            TexFormat::Rg32Float | TexFormat::Rg32Uint | TexFormat::Rgba16Float => 8,
            TexFormat::Rgba32Float | TexFormat::Rgba32Uint => 16,
        }
    }

    /// The WGSL spelling (`rgba32float`), as in `texture_storage_2d<rgba32float, write>`.
    pub fn wgsl_name(self) -> &'static str {
        match self {
            TexFormat::R32Float => "r32float",
            TexFormat::Rg32Float => "rg32float",
            TexFormat::Rgba32Float => "rgba32float",
            TexFormat::Rgba16Float => "rgba16float",
            TexFormat::R32Uint => "r32uint",
            TexFormat::Rg32Uint => "rg32uint",
            TexFormat::Rgba32Uint => "rgba32uint",
            TexFormat::Rgba8Unorm => "rgba8unorm",
        }
    }

    /// Whether a sampled binding reads this format as `texture_2d<u32>`.
    pub fn is_uint(self) -> bool {
        matches!(self, TexFormat::R32Uint | TexFormat::Rg32Uint | TexFormat::Rgba32Uint)
    }
}
