//! The scene's textures on the GPU: one `texture_2d_array` per size class
//! (`texture_classes`), sRGB with full mip chains, and the sampler that
//! reads them (trilinear, repeat; clamp and mirror are done on the uv in
//! `shaders/shared/textures.wgsl`). A class with no texture binds a 1x1
//! placeholder, so every shader binds the same four.

use super::texture_classes::{self, CLASSES};
use super::world::TextureImage;

/// The four class arrays and the sampler.
pub struct TextureArrays {
    /// By class (256, 512, 1024, 2048).
    pub views: Vec<wgpu::TextureView>,
    /// Trilinear, repeat.
    pub sampler: wgpu::Sampler,
    /// Bytes of texels uploaded (mips included).
    pub bytes: u64,
}

impl TextureArrays {
    /// Resamples `textures` into their classes and uploads them; an error
    /// when a class needs more layers than the adapter allows.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, textures: &[TextureImage]) -> Result<TextureArrays, String> {
        let layout = texture_classes::layout(textures);
        let max_layers = device.limits().max_texture_array_layers;
        let mut views = Vec::with_capacity(CLASSES.len());
        let mut bytes = 0u64;
        for (c, &side) in CLASSES.iter().enumerate() {
            let layers = layout.layers[c];
            if layers > max_layers {
                return Err(format!("{layers} textures of side {side}: the adapter allows {max_layers} in one texture array"));
            }
            let (size, mips) = if layers == 0 { (1, 1) } else { (side, texture_classes::mip_count(side)) };
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some(&format!("scene_images_{side}")),
                size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: layers.max(1) },
                mip_level_count: mips,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8UnormSrgb,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            let members: Vec<(&TextureImage, u32)> = textures.iter().zip(&layout.places).filter(|(_, p)| p.0 == c).map(|(t, p)| (t, p.1)).collect();
            for_each_mip_chain(&members, side, |layer, chain| {
                for (level, texels) in chain.iter().enumerate() {
                    let s = side >> level;
                    bytes += texels.len() as u64;
                    queue.write_texture(
                        wgpu::TexelCopyTextureInfo {
                            texture: &texture,
                            mip_level: level as u32,
                            origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
                            aspect: wgpu::TextureAspect::All,
                        },
                        texels,
                        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * s), rows_per_image: Some(s) },
                        wgpu::Extent3d { width: s, height: s, depth_or_array_layers: 1 },
                    );
                }
            });
            views.push(texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }));
        }
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("scene_sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        Ok(TextureArrays { views, sampler, bytes })
    }
}

/// Hands `upload` the mip chain of each of `members` (image, layer) at
/// class side `side`, with its layer, in order: worked out on every core
/// (each is independent of the others), a batch uploaded before the next
/// is made.
fn for_each_mip_chain(members: &[(&TextureImage, u32)], side: u32, mut upload: impl FnMut(u32, &[Vec<u8>])) {
    crate::batches::in_batches(members, |&(t, _)| texture_classes::mip_chain(t, side), |&(_, layer), chain| upload(layer, &chain));
}
