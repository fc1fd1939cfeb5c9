//! Texture formats: plain data shared by the shader reflection, the frame
//! graph and GPU readback (no layer above this one is imported here).

use serde::Deserialize;

/// Texture formats a graph may declare: the storage-capable WGSL formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
pub enum TexFormat {
    /// One 32-bit float channel.
    R32Float,
    /// Two 32-bit float channels.
    Rg32Float,
    /// Four 32-bit float channels.
    Rgba32Float,
    /// Four 16-bit float channels.
    Rgba16Float,
    /// One 32-bit unsigned integer channel.
    R32Uint,
    /// Two 32-bit unsigned integer channels.
    Rg32Uint,
    /// Four 32-bit unsigned integer channels.
    Rgba32Uint,
    /// Four 8-bit unsigned normalised channels.
    Rgba8Unorm,
}

impl TexFormat {
    /// Bytes one texel takes.
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
