//! Copies a texture back to the CPU as linear RGBA f32.

use crate::error::UserError;
use crate::format::TexFormat;

/// An RGBA f32 image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageF32 {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, RGBA.
    pub data: Vec<[f32; 4]>,
}

impl ImageF32 {
    /// A black, transparent image.
    pub fn new(width: u32, height: u32) -> Self {
        ImageF32 { width, height, data: vec![[0.0; 4]; (width * height) as usize] }
    }
    /// The pixel at column `x`, row `y` (panics outside the image).
    pub fn get(&self, x: u32, y: u32) -> [f32; 4] {
        self.data[(y * self.width + x) as usize]
    }
}

fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = (h >> 10) & 0x1f;
    let mant = f32::from(h & 0x3ff);
    match exp {
        0 => sign * mant * 2f32.powi(-24),
        31 => if mant == 0.0 { sign * f32::INFINITY } else { f32::NAN },
        e => sign * (1.0 + mant / 1024.0) * 2f32.powi(i32::from(e) - 15),
    }
}

/// Reads a whole 2D texture. Uint formats come back as their integer values.
pub fn read_texture(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture, format: TexFormat) -> Result<ImageF32, UserError> {
    let (w, h) = (texture.width(), texture.height());
    let bpp = format.bytes_per_pixel() as u32;
    let row = (w * bpp).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(row) * u64::from(h),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(h) },
        },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    queue.submit([enc.finish()]);
    let bytes = map_buffer(device, &buffer)?;
    let mut img = ImageF32::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let at = (y * row + x * bpp) as usize;
            let px = &bytes[at..at + bpp as usize];
            let word = |i: usize| u32::from_le_bytes([px[4 * i], px[4 * i + 1], px[4 * i + 2], px[4 * i + 3]]);
            let half = |i: usize| f16_to_f32(u16::from_le_bytes([px[2 * i], px[2 * i + 1]]));
            let v = match format {
                TexFormat::R32Float => [f32::from_bits(word(0)), 0.0, 0.0, 1.0],
                TexFormat::Rg32Float => [f32::from_bits(word(0)), f32::from_bits(word(1)), 0.0, 1.0],
                TexFormat::Rgba32Float => [0, 1, 2, 3].map(|i| f32::from_bits(word(i))),
                TexFormat::Rgba16Float => [0, 1, 2, 3].map(half),
                TexFormat::R32Uint => [word(0) as f32, 0.0, 0.0, 1.0],
                TexFormat::Rg32Uint => [word(0) as f32, word(1) as f32, 0.0, 1.0],
                TexFormat::Rgba32Uint => [0, 1, 2, 3].map(|i| word(i) as f32),
                TexFormat::Rgba8Unorm => [0, 1, 2, 3].map(|i| f32::from(px[i]) / 255.0),
            };
            img.data[(y * w + x) as usize] = v;
        }
    }
    Ok(img)
}

/// Maps a MAP_READ buffer and copies its bytes out.
pub fn map_buffer(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>, UserError> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    let timeout = super::gpu_timeout();
    if let Err(wgpu::PollError::Timeout) = device.poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(timeout) }) {
        return Err(UserError::new(format!(
            "the GPU did not finish its work within {} s (GLINT_GPU_TIMEOUT_S sets the limit); a pass may loop for too long: render smaller or with fewer samples",
            timeout.as_secs_f64()
        )));
    }
    match rx.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(UserError::new(format!("GPU readback failed: {e}"))),
        Err(_) => return Err(UserError::new("GPU readback never completed")),
    }
    let bytes = buffer
        .get_mapped_range(..)
        .map_err(|e| UserError::new(format!("GPU readback failed: {e}")))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    #[test]
    fn half_floats() {
        assert_eq!(super::f16_to_f32(0x3c00), 1.0);
        assert_eq!(super::f16_to_f32(0xc000), -2.0);
        assert_eq!(super::f16_to_f32(0x0000), 0.0);
        assert!(super::f16_to_f32(0x7c00).is_infinite());
    }
}
