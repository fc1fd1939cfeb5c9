//! Writing and reading images: EXR is linear float, PNG is sRGB-encoded and
//! clamped (no tone mapping).

use std::path::Path;

use crate::error::UserError;
use crate::gpu::readback::ImageF32;

/// The sRGB encoding of a linear value, clamped to [0, 1] first (NaN and
/// infinities give 0).
pub fn linear_to_srgb(x: f32) -> f32 {
    let x = if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
    if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

/// The linear value of an sRGB-encoded one in [0, 1].
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

/// Resamples to `w`x`h` with bilinear filtering over texel centres (a
/// machine profile's lower render resolution, shown at the size asked for).
pub fn resize_bilinear(img: &ImageF32, w: u32, h: u32) -> ImageF32 {
    let mut out = ImageF32::new(w, h);
    if img.width == 0 || img.height == 0 {
        return out;
    }
    let sx = img.width as f32 / w as f32;
    let sy = img.height as f32 / h as f32;
    for y in 0..h {
        let fy = ((y as f32 + 0.5) * sy - 0.5).clamp(0.0, (img.height - 1) as f32);
        let (y0, ty) = (fy.floor() as u32, fy.fract());
        let y1 = (y0 + 1).min(img.height - 1);
        for x in 0..w {
            let fx = ((x as f32 + 0.5) * sx - 0.5).clamp(0.0, (img.width - 1) as f32);
            let (x0, tx) = (fx.floor() as u32, fx.fract());
            let x1 = (x0 + 1).min(img.width - 1);
            let (a, b, c, d) = (img.get(x0, y0), img.get(x1, y0), img.get(x0, y1), img.get(x1, y1));
            let mut p = [0.0; 4];
            for k in 0..4 {
                let top = a[k] + (b[k] - a[k]) * tx;
                let bottom = c[k] + (d[k] - c[k]) * tx;
                p[k] = top + (bottom - top) * ty;
            }
            out.data[(y * w + x) as usize] = p;
        }
    }
    out
}

/// Writes a PFM (linear RGB f32, bottom row first, little-endian).
fn save_pfm(img: &ImageF32, path: &Path) -> std::io::Result<()> {
    write_pfm(img, path, 3)
}

/// Writes the first channel alone as a greyscale PFM (`Pf`), e.g. a hit
/// distance image for tools without an EXR reader.
pub fn save_pfm_grey(img: &ImageF32, path: &Path) -> Result<(), UserError> {
    write_pfm(img, path, 1).map_err(|e| UserError::in_file(path, format!("cannot write the PFM: {e}")))
}

fn write_pfm(img: &ImageF32, path: &Path, channels: usize) -> std::io::Result<()> {
    let tag = if channels == 1 { "Pf" } else { "PF" };
    let mut bytes = format!("{tag}\n{} {}\n-1.0\n", img.width, img.height).into_bytes();
    for y in (0..img.height).rev() {
        for x in 0..img.width {
            for c in &img.get(x, y)[..channels] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    std::fs::write(path, bytes)
}

/// Reads a colour PFM (`PF`), either byte order.
fn load_pfm(path: &Path) -> Result<ImageF32, UserError> {
    let bad = |m: &str| UserError::in_file(path, format!("not a colour PFM: {m}"));
    let bytes = crate::error::read_user_file(path, "image")?;
    // Three whitespace-separated header tokens after "PF", then one byte.
    let mut fields = Vec::new();
    let mut at = 0;
    while fields.len() < 4 {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        if start == at {
            return Err(bad("short header"));
        }
        fields.push(String::from_utf8_lossy(&bytes[start..at]).into_owned());
    }
    at += 1;
    if fields[0] != "PF" {
        return Err(bad("it does not start with PF"));
    }
    let w: u32 = fields[1].parse().map_err(|_| bad(&format!("bad width `{}`", fields[1])))?;
    let h: u32 = fields[2].parse().map_err(|_| bad(&format!("bad height `{}`", fields[2])))?;
    let scale: f32 = fields[3].parse().map_err(|_| bad(&format!("bad scale `{}`", fields[3])))?;
    if w == 0 || h == 0 {
        return Err(bad(&format!("the header says {w}x{h}: an empty image")));
    }
    if !(scale.is_finite() && scale != 0.0) {
        return Err(bad(&format!("the scale `{}` must be a finite non-zero number (its sign is the byte order)", fields[3])));
    }
    // Every size from the header in checked arithmetic: a header that says
    // 2147483648 x 2147483648 must not wrap into a small buffer.
    let need = u64::from(w).checked_mul(u64::from(h)).and_then(|n| n.checked_mul(12));
    let have = (bytes.len() - at.min(bytes.len())) as u64;
    let Some(need) = need.filter(|&n| n <= have) else {
        return Err(bad(&format!("the header says {w}x{h} pixels ({} bytes of data) but the file holds {have} bytes after it", need.map_or_else(|| "more than 2^64".to_string(), |n| n.to_string()))));
    };
    let data = &bytes[at..at + need as usize];
    let (wu, hu) = (w as usize, h as usize);
    let mut img = ImageF32::new(w, h);
    for (i, px) in data.chunks_exact(12).enumerate() {
        let f = |k: usize| {
            let b = [px[4 * k], px[4 * k + 1], px[4 * k + 2], px[4 * k + 3]];
            if scale < 0.0 { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) }
        };
        let (x, y) = (i % wu, hu - 1 - i / wu);
        img.data[y * wu + x] = [f(0), f(1), f(2), 1.0];
    }
    Ok(img)
}

fn extension(path: &Path) -> Option<String> {
    path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase)
}

/// Writes `.png` (sRGB), `.exr` (linear RGBA f32) or `.pfm` (linear RGB
/// f32), by extension.
pub fn save(img: &ImageF32, path: &Path) -> Result<(), UserError> {
    let ext = extension(path);
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
        Some("pfm") => return save_pfm(img, path).map_err(|e| UserError::in_file(path, format!("cannot write the image: {e}"))),
        _ => return Err(UserError::in_file(path, "unknown image type: the output must end in .png, .exr or .pfm")),
    };
    result.map_err(|e| UserError::in_file(path, format!("cannot write the image: {e}")))
}

/// Reads a PNG (decoded from sRGB to linear), an EXR or a PFM (linear).
pub fn load(path: &Path) -> Result<ImageF32, UserError> {
    if extension(path).as_deref() == Some("pfm") {
        return load_pfm(path);
    }
    let dynimg = image::open(path).map_err(|e| UserError::in_file(path, format!("cannot read the image: {e}")))?;
    let is_exr = extension(path).as_deref() == Some("exr");
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pfm_and_exr_round_trip() {
        let mut img = ImageF32::new(3, 2);
        for (i, p) in img.data.iter_mut().enumerate() {
            *p = [i as f32, 0.5 * i as f32, 100.0 + i as f32, 1.0];
        }
        let dir = std::env::temp_dir().join(format!("glint-io-{}", std::process::id()));
        for name in ["a.pfm", "a.exr"] {
            let path = dir.join(name);
            save(&img, &path).unwrap();
            assert_eq!(load(&path).unwrap(), img, "{name}");
        }
        assert!(load(&dir.join("missing.pfm")).is_err());
        std::fs::write(dir.join("bad.pfm"), "PF\n3 2\n-1.0\nshort").unwrap();
        assert!(load(&dir.join("bad.pfm")).unwrap_err().to_string().contains("holds 5 bytes"));
        // Sizes that wrap 32- or 64-bit arithmetic, an empty image, a bad scale.
        for (header, says) in [
            ("PF\n2147483648 2147483648\n-1.0\n", "2147483648x2147483648 pixels (more than 2^64"),
            ("PF\n4294967295 4294967295\n-1.0\n", "4294967295x4294967295"),
            ("PF\n0 5\n-1.0\n", "an empty image"),
            ("PF\n1 1\nNaN\n", "finite non-zero"),
            ("PF\n1 1\n0\n", "finite non-zero"),
            ("PF\n-1 1\n-1.0\n", "bad width `-1`"),
        ] {
            std::fs::write(dir.join("huge.pfm"), header).unwrap();
            let e = load(&dir.join("huge.pfm")).unwrap_err().to_string();
            assert!(e.contains(says) && e.contains("huge.pfm"), "{header:?}: {e}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn srgb_round_trip() {
        for x in [0.0, 0.001, 0.2, 0.5, 1.0] {
            assert!((srgb_to_linear(linear_to_srgb(x)) - x).abs() < 1e-5);
        }
    }
}
