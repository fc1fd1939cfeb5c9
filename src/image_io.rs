//! Writing and reading images: EXR is linear float, PNG is sRGB-encoded and
//! clamped (no tone mapping).

use std::path::Path;

use crate::error::UserError;
use crate::gpu::readback::ImageF32;

pub fn linear_to_srgb(x: f32) -> f32 {
    let x = if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
    if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

pub fn srgb_to_linear(x: f32) -> f32 {
    if x <= 0.040_45 { x / 12.92 } else { ((x + 0.055) / 1.055).powf(2.4) }
}

/// 8-bit sRGB RGB bytes of a linear image.
pub fn to_srgb8(img: &ImageF32) -> Vec<u8> {
    img.data
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]].map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8))
        .collect()
}

/// Writes `.png` (sRGB) or `.exr` (linear RGBA f32), by extension.
pub fn save(img: &ImageF32, path: &Path) -> Result<(), UserError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| UserError::in_file(path, format!("cannot create the folder {}: {e}", dir.display())))?;
    }
    let result = match ext.as_deref() {
        Some("png") => image::RgbImage::from_raw(img.width, img.height, to_srgb8(img))
            .ok_or_else(|| UserError::in_file(path, "internal: image size mismatch"))?
            .save(path),
        Some("exr") => {
            let data: Vec<f32> = img.data.iter().flat_map(|p| [p[0], p[1], p[2], p[3]]).collect();
            image::Rgba32FImage::from_raw(img.width, img.height, data)
                .ok_or_else(|| UserError::in_file(path, "internal: image size mismatch"))?
                .save(path)
        }
        _ => return Err(UserError::in_file(path, "unknown image type: the output must end in .png or .exr")),
    };
    result.map_err(|e| UserError::in_file(path, format!("cannot write the image: {e}")))
}

/// Reads a PNG (decoded from sRGB to linear) or an EXR (linear).
pub fn load(path: &Path) -> Result<ImageF32, UserError> {
    let dynimg = image::open(path).map_err(|e| UserError::in_file(path, format!("cannot read the image: {e}")))?;
    let is_exr = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let rgba = dynimg.to_rgba32f();
    let mut img = ImageF32::new(rgba.width(), rgba.height());
    for (dst, src) in img.data.iter_mut().zip(rgba.pixels()) {
        *dst = if is_exr {
            src.0
        } else {
            [srgb_to_linear(src.0[0]), srgb_to_linear(src.0[1]), srgb_to_linear(src.0[2]), src.0[3]]
        };
    }
    Ok(img)
}
