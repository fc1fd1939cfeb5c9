//! Screenshots: the window as an sRGB PNG (copied from the surface texture
//! in the frame's own encoder) and the graph output as a linear EXR.

use std::path::Path;

use crate::error::UserError;
use crate::gpu::readback::{map_buffer, ImageF32};
use crate::gpu::Gpu;
use crate::session::Session;
use crate::viewer::present::Rect;

/// A copy of the window recorded into a frame, waiting to be read.
pub struct Capture {
    buffer: wgpu::Buffer,
    width: u32,
    height: u32,
    row: u32,
}

/// Records a copy of `texture` (the surface's) into a readback buffer;
/// None when the surface was not made copyable.
pub fn record(device: &wgpu::Device, enc: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) -> Option<Capture> {
    if !texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
        return None;
    }
    let (width, height) = (texture.width(), texture.height());
    let row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("screenshot"),
        size: u64::from(row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    enc.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(height) },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    Some(Capture { buffer, width, height, row })
}

/// Writes the window to `png` and the graph output to the same name with
/// `.exr`; returns the line to print (with the viewport rectangle, so a
/// script can crop the render out of the window).
pub fn save(gpu: &Gpu, c: Capture, format: wgpu::TextureFormat, png: &Path, session: &Session, viewport: Rect) -> Result<String, UserError> {
    let bytes = map_buffer(&gpu.device, &c.buffer)?;
    let bgra = matches!(format, wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb);
    let mut rgb = Vec::with_capacity((c.width * c.height * 3) as usize);
    for y in 0..c.height {
        for x in 0..c.width {
            let at = (y * c.row + x * 4) as usize;
            let p = &bytes[at..at + 4];
            if bgra {
                rgb.extend_from_slice(&[p[2], p[1], p[0]]);
            } else {
                rgb.extend_from_slice(&p[..3]);
            }
        }
    }
    let image = image::RgbImage::from_raw(c.width, c.height, rgb).ok_or_else(|| UserError::in_file(png, "screenshot size mismatch"))?;
    image.save(png).map_err(|e| UserError::in_file(png, format!("cannot write the screenshot: {e}")))?;
    let exr = png.with_extension("exr");
    let output: ImageF32 = session.read_output()?;
    crate::image_io::save(&output, &exr)?;
    Ok(format!(
        "screenshot {} (window {}x{}), {} (graph output, linear); viewport {},{} {}x{}",
        png.display(),
        c.width,
        c.height,
        exr.display(),
        viewport.x,
        viewport.y,
        viewport.w,
        viewport.h
    ))
}
