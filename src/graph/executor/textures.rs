//! The executor's textures as the rest of the engine sees them: the output
//! and any resource's final version after a frame (or during one, for a
//! frame hook), and the persistent resources a volume is saved from and
//! loaded into.

use crate::error::UserError;
use crate::format::TexFormat;
use crate::gpu::readback::{read_texture, ImageF32};
use crate::gpu::Gpu;

use super::{Executor, FrameHook};

impl Executor {
    /// The persistent resources (name, format, size) of this schedule.
    pub fn persistent_resources(&self) -> Vec<(String, TexFormat, (u32, u32))> {
        let mut out: Vec<(String, TexFormat, (u32, u32))> = Vec::new();
        for v in &self.schedule.versions {
            let i = v.texture.resolve(0);
            if self.schedule.textures.get(i).is_some_and(|t| t.persistent) && !out.iter().any(|o| o.0 == v.resource) {
                let t = &self.textures[i].texture;
                out.push((v.resource.clone(), self.schedule.textures[i].format, (t.width(), t.height())));
            }
        }
        out
    }

    /// Overwrites a persistent Rgba32Float resource with `texels` (row by
    /// row, its exact size).
    pub fn write_persistent(&self, gpu: &Gpu, resource: &str, texels: &[[f32; 4]]) -> Result<(), UserError> {
        let Some((_, format, (w, h))) = self.persistent_resources().into_iter().find(|r| r.0 == resource) else {
            return Err(UserError::new(format!("graph `{}` has no persistent resource `{resource}`", self.schedule.name)));
        };
        if format != TexFormat::Rgba32Float || texels.len() != (w as usize) * (h as usize) {
            return Err(UserError::new(format!("`{resource}` is {format:?} {w}x{h}; {} RGBA f32 texels do not fill it", texels.len())));
        }
        let Some((texture, _)) = self.resource_texture(resource) else {
            return Err(UserError::new(format!("`{resource}` has no texture")));
        };
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
            bytemuck::cast_slice(texels),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(w * 16), rows_per_image: Some(h) },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(UserError::new(format!("{} refused writing `{resource}`: {e}", gpu.describe()))),
            None => Ok(()),
        }
    }

    /// Reads a persistent resource back (what its last write left).
    pub fn read_persistent(&self, gpu: &Gpu, resource: &str) -> Option<Result<ImageF32, UserError>> {
        self.persistent_resources().iter().find(|r| r.0 == resource)?;
        let (texture, format) = self.resource_texture(resource)?;
        Some(read_texture(&gpu.device, &gpu.queue, texture, format))
    }

    /// Calls a frame hook with this frame's texture (before the parity flips).
    pub(super) fn run_hook(&self, enc: &mut wgpu::CommandEncoder, hook: &mut FrameHook<'_>) {
        let shown = hook.resource.and_then(|r| self.final_texture(r, self.parity));
        let output = (self.output_at(self.parity), self.schedule.output_format);
        let (texture, format) = shown.unwrap_or(output);
        (hook.record)(enc, texture, format);
    }

    /// The parity the last frame used (`run_frame` already flipped it).
    pub(super) fn last_parity(&self) -> u8 {
        if self.schedule.flips_parity { self.parity ^ 1 } else { self.parity }
    }

    /// The texture holding the output of the last frame.
    pub fn output_texture(&self) -> &wgpu::Texture {
        self.output_at(self.last_parity())
    }

    /// The output texture of the frame of `parity`.
    fn output_at(&self, parity: u8) -> &wgpu::Texture {
        &self.textures[self.schedule.output.resolve(parity)].texture
    }

    /// The size of the output texture (a graph resource may have its own
    /// size, not the render's).
    pub fn output_size(&self) -> (u32, u32) {
        let t = self.output_texture();
        (t.width(), t.height())
    }

    /// Reads the last frame's output back to the CPU (waits for the GPU).
    pub fn read_output(&self, gpu: &Gpu) -> Result<ImageF32, UserError> {
        read_texture(&gpu.device, &gpu.queue, self.output_texture(), self.schedule.output_format)
    }

    /// The final version of a kept resource (see Schedule::kept) after the
    /// last frame; None when the resource was not kept.
    pub fn read_resource(&self, gpu: &Gpu, resource: &str) -> Option<Result<ImageF32, UserError>> {
        if !self.schedule.kept.iter().any(|r| r == resource) {
            return None;
        }
        let (texture, format) = self.resource_texture(resource)?;
        Some(read_texture(&gpu.device, &gpu.queue, texture, format))
    }

    /// The texture and format of a resource's final version after the last
    /// frame (for viewers: pooled transients may since hold another
    /// resource; kept and history ones do not).
    pub fn resource_texture(&self, resource: &str) -> Option<(&wgpu::Texture, TexFormat)> {
        self.final_texture(resource, self.last_parity())
    }

    /// A resource's final version in the frame of `parity`.
    fn final_texture(&self, resource: &str, parity: u8) -> Option<(&wgpu::Texture, TexFormat)> {
        let v = self.schedule.versions.iter().filter(|v| v.resource == resource).max_by_key(|v| v.version)?;
        let index = v.texture.resolve(parity);
        let format = self.schedule.textures.get(index)?.format;
        Some((&self.textures.get(index)?.texture, format))
    }
}
