//! A scene's textures as the GPU holds them: every image resampled to a
//! square power-of-two side (a size class) and stacked in that class's
//! `texture_2d_array`, with its mip chain, so one sampler with hardware
//! wrapping and trilinear filtering reads any of them (lavapipe has no
//! binding arrays). Resampling and mips average in linear light; texels
//! stay sRGB (`Rgba8UnormSrgb`, decoded by the sampler). Pure: tested
//! without a GPU.

use glam::Vec4;

use super::world::TextureImage;

/// The sides of the size classes. An image goes to the smallest class at
/// least as large as its larger side (the largest class when none is:
/// it is scaled down).
pub const CLASSES: [u32; 4] = [256, 512, 1024, 2048];

/// "No texture" in a material's texture slot.
pub const NO_TEXTURE: u32 = u32::MAX;

/// Where each texture went: (class index, layer in that class), and how
/// many layers each class holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TextureLayout {
    /// Per texture, in scene order: (class index, layer).
    pub places: Vec<(usize, u32)>,
    /// Layers in each class.
    pub layers: [u32; CLASSES.len()],
}

impl TextureLayout {
    /// The slot value shaders read for texture `i`: class in the top 16
    /// bits, layer in the low 16.
    pub fn slot(&self, i: usize) -> u32 {
        self.places.get(i).map_or(NO_TEXTURE, |&(c, l)| ((c as u32) << 16) | l)
    }
}

/// The class of a `width x height` image.
pub fn class_of(width: u32, height: u32) -> usize {
    let side = width.max(height);
    CLASSES.iter().position(|&c| c >= side).unwrap_or(CLASSES.len() - 1)
}

/// Places `textures` in their classes, in order.
pub fn layout(textures: &[TextureImage]) -> TextureLayout {
    let mut layers = [0u32; CLASSES.len()];
    let places = textures
        .iter()
        .map(|t| {
            let c = class_of(t.width, t.height);
            layers[c] += 1;
            (c, layers[c] - 1)
        })
        .collect();
    TextureLayout { places, layers }
}

/// What `textures` take on the GPU, in words: "N textures, B bytes (M MiB;
/// layers per class 256: a, 512: b, ...)", or None for a scene without.
pub fn describe(textures: &[TextureImage]) -> Option<String> {
    if textures.is_empty() {
        return None;
    }
    let l = layout(textures);
    let bytes: u64 = CLASSES.iter().zip(l.layers).map(|(&side, layers)| u64::from(layers) * level_bytes(side)).sum();
    let classes: Vec<String> = CLASSES.iter().zip(l.layers).filter(|(_, n)| *n > 0).map(|(side, n)| format!("{side}: {n}")).collect();
    let n = textures.len();
    Some(format!("{n} texture{}, {bytes} bytes ({:.1} MiB; layers per size class {})", if n == 1 { "" } else { "s" }, bytes as f64 / 1048576.0, classes.join(", ")))
}

/// Bytes of one RGBA8 layer of side `side` with its mips.
fn level_bytes(side: u32) -> u64 {
    (0..mip_count(side)).map(|k| 4 * u64::from(side >> k) * u64::from(side >> k)).sum()
}

/// Mip levels of a class side (down to 1x1).
pub fn mip_count(side: u32) -> u32 {
    32 - side.leading_zeros()
}

/// `image` as `side x side` sRGB RGBA8 levels, largest first, down to 1x1.
/// A `linear` image's bytes are its values: they are averaged as they are
/// and stored sRGB-encoded, so the sampler's decoding gives them back
/// (to within a step of the sRGB curve: at most 1.2/255 near 1, less
/// below).
pub fn mip_chain(image: &TextureImage, side: u32) -> Vec<Vec<u8>> {
    let s = side as usize;
    let decode = decoder(image.linear);
    if image.width as usize == s && image.height as usize == s && image.rgba.len() >= 4 * s * s {
        // Already the class's size: level 0 is the image as it is.
        let level0 = &image.rgba[..4 * s * s];
        let mut out = vec![encode_bytes(level0, image.linear)];
        if s > 1 {
            // Level 1 straight from the bytes (level 0 is never held as f32).
            let m = s / 2;
            let texel = |x: usize, y: usize| decode(&level0[4 * (y * s + x)..4 * (y * s + x) + 4]);
            let level1: Vec<Vec4> = (0..m * m).map(|i| (i % m, i / m)).map(|(x, y)| 0.25 * (texel(2 * x, 2 * y) + texel(2 * x + 1, 2 * y) + texel(2 * x, 2 * y + 1) + texel(2 * x + 1, 2 * y + 1))).collect();
            out.push(encode(&level1));
            out.extend(mips_below(level1, m));
        }
        return out;
    }
    chain_by_resampling(image, side)
}

/// `mip_chain` for any image size: level 0 resampled in linear light.
fn chain_by_resampling(image: &TextureImage, side: u32) -> Vec<Vec<u8>> {
    let (w, h) = (image.width as usize, image.height as usize);
    let s = side as usize;
    let decode = decoder(image.linear);
    // Rows first, then columns; each source row decoded to linear light
    // only as it is resampled (a 4096^2 image whole in f32 would be 256 MiB).
    let mut rows = Vec::with_capacity(s * h);
    let mut row = Vec::with_capacity(w);
    for texels in image.rgba.chunks_exact(4 * w.max(1)).take(h) {
        row.clear();
        row.extend(texels.chunks_exact(4).map(&decode));
        rows.extend(resample(&row, s));
    }
    // (The rows there are: a short buffer cannot index past its end.)
    let h = rows.len() / s;
    let mut level = vec![Vec4::ZERO; s * s];
    let mut column = vec![Vec4::ZERO; h];
    for x in 0..s {
        for y in 0..h {
            column[y] = rows[y * s + x];
        }
        for (y, v) in resample(&column, s).into_iter().enumerate() {
            level[y * s + x] = v;
        }
    }
    let mut out = vec![encode(&level)];
    out.extend(mips_below(level, s));
    out
}

/// The encoded levels below `level` (side `n`, linear light), each the 2x2
/// box average of the one above, down to 1x1.
fn mips_below(mut level: Vec<Vec4>, mut n: usize) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    while n > 1 {
        let m = n / 2;
        let mut next = vec![Vec4::ZERO; m * m];
        for y in 0..m {
            for x in 0..m {
                let at = |dx: usize, dy: usize| level[(2 * y + dy) * n + 2 * x + dx];
                next[y * m + x] = 0.25 * (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1));
            }
        }
        out.push(encode(&next));
        level = next;
        n = m;
    }
    out
}

/// `src` resampled to `len` values: the average over each output texel's
/// footprint when shrinking, linear interpolation (clamped at the ends)
/// when growing.
fn resample(src: &[Vec4], len: usize) -> Vec<Vec4> {
    let n = src.len();
    if n == len {
        return src.to_vec();
    }
    if n > len {
        let scale = n as f64 / len as f64;
        return (0..len)
            .map(|i| {
                let (a, b) = (i as f64 * scale, (i + 1) as f64 * scale);
                let mut sum = Vec4::ZERO;
                let mut k = a.floor() as usize;
                while (k as f64) < b && k < n {
                    let cover = (b.min(k as f64 + 1.0) - a.max(k as f64)) as f32;
                    sum += src[k] * cover;
                    k += 1;
                }
                sum / (b - a) as f32
            })
            .collect();
    }
    (0..len)
        .map(|i| {
            let x = ((i as f64 + 0.5) * n as f64 / len as f64 - 0.5).clamp(0.0, (n - 1) as f64);
            let k = (x.floor() as usize).min(n - 1);
            let t = (x - k as f64) as f32;
            src[k].lerp(src[(k + 1).min(n - 1)], t)
        })
        .collect()
}

/// A texel's bytes to linear light (an sRGB image) or to its values (a
/// data image); alpha is always data.
fn decoder(linear: bool) -> impl Fn(&[u8]) -> Vec4 {
    let lut = if linear { std::array::from_fn(|i| i as f32 / 255.0) } else { srgb_to_linear_table() };
    move |p: &[u8]| Vec4::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize], f32::from(p[3]) / 255.0)
}

fn srgb_to_linear_table() -> [f32; 256] {
    let mut t = [0.0; 256];
    for (i, v) in t.iter_mut().enumerate() {
        let c = i as f32 / 255.0;
        *v = if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    }
    t
}

fn linear_to_srgb(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let c = if l <= 0.003_130_8 { 12.92 * l } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 };
    (c * 255.0 + 0.5) as u8
}

/// Cells of the encoder's table over linear 0..1.
const ENCODE_CELLS: usize = 4096;

/// `linear_to_srgb` by table, byte for byte the same (a `powf` a channel
/// was most of a large scene's load time): `start[c]` is the byte at the
/// start of cell c, `rise[k]` the least linear value whose byte is above
/// k; a value steps up from its cell's byte past the rises it has reached
/// (at most two: the curve's steepest slope is 0.8 bytes a cell).
struct SrgbEncoder {
    start: Vec<u8>,
    rise: [f32; 255],
}

impl SrgbEncoder {
    fn new() -> SrgbEncoder {
        let mut rise = [0.0f32; 255];
        for (k, r) in rise.iter_mut().enumerate() {
            // Bisection for the least l with linear_to_srgb(l) > k, down to
            // adjacent floats.
            let (mut lo, mut hi) = (0.0f32, 1.0f32);
            loop {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if linear_to_srgb(mid) as usize > k {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            // The bisection ends on adjacent floats: hi is the first above.
            *r = hi;
        }
        let start = (0..=ENCODE_CELLS).map(|c| linear_to_srgb(c as f32 / ENCODE_CELLS as f32)).collect();
        SrgbEncoder { start, rise }
    }

    fn encode(&self, l: f32) -> u8 {
        let l = if l > 0.0 { l.min(1.0) } else { 0.0 };
        let mut b = self.start[(l * ENCODE_CELLS as f32) as usize];
        while b < 255 && l >= self.rise[b as usize] {
            b += 1;
        }
        b
    }
}

fn encoder() -> &'static SrgbEncoder {
    static ENCODER: std::sync::OnceLock<SrgbEncoder> = std::sync::OnceLock::new();
    ENCODER.get_or_init(SrgbEncoder::new)
}

fn encode(level: &[Vec4]) -> Vec<u8> {
    let e = encoder();
    let mut out = Vec::with_capacity(4 * level.len());
    for v in level {
        out.extend_from_slice(&[e.encode(v.x), e.encode(v.y), e.encode(v.z), (v.w.clamp(0.0, 1.0) * 255.0 + 0.5) as u8]);
    }
    out
}

/// Level 0 of an image already its class's size: sRGB bytes stay as they
/// are; a linear image's values become sRGB bytes.
fn encode_bytes(rgba: &[u8], linear: bool) -> Vec<u8> {
    if !linear {
        return rgba.to_vec();
    }
    let e = encoder();
    let byte: [u8; 256] = std::array::from_fn(|b| e.encode(b as f32 / 255.0));
    let mut out = Vec::with_capacity(rgba.len());
    for p in rgba.chunks_exact(4) {
        out.extend_from_slice(&[byte[p[0] as usize], byte[p[1] as usize], byte[p[2] as usize], p[3]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, texel: impl Fn(u32, u32) -> [u8; 4]) -> TextureImage {
        let rgba = (0..height).flat_map(|y| (0..width).map(move |x| (x, y))).flat_map(|(x, y)| texel(x, y)).collect();
        TextureImage { width, height, rgba, linear: false }
    }

    #[test]
    fn classes_take_the_smallest_side_that_fits() {
        assert_eq!(class_of(16, 8), 0);
        assert_eq!(class_of(256, 256), 0);
        assert_eq!(class_of(300, 20), 1);
        assert_eq!(class_of(1024, 2048), 3);
        assert_eq!(class_of(8192, 8192), 3, "scaled down into the largest");
        let textures = [image(4, 4, |_, _| [0; 4]), image(600, 10, |_, _| [0; 4]), image(2, 2, |_, _| [0; 4])];
        let l = layout(&textures);
        assert_eq!(l.places, vec![(0, 0), (2, 0), (0, 1)]);
        assert_eq!(l.layers, [2, 0, 1, 0]);
        assert_eq!(l.slot(2), 1);
        assert_eq!(l.slot(1), 2 << 16);
        assert_eq!(l.slot(9), NO_TEXTURE);
        assert_eq!(mip_count(256), 9);
        // 256^2 x 4 x (1 + 1/4 + ...) = 349524 bytes a layer of 256.
        assert_eq!(level_bytes(256), 349_524);
        let said = describe(&textures).expect("textures");
        assert!(said.starts_with(&format!("3 textures, {} bytes", 2 * 349_524 + level_bytes(1024))) && said.ends_with("256: 2, 1024: 1)"), "{said}");
        assert_eq!(describe(&[]), None);
    }

    #[test]
    fn mips_average_in_linear_light() {
        // A constant image stays constant at every level and size.
        let flat = mip_chain(&image(3, 5, |_, _| [200, 100, 50, 255]), 8);
        assert_eq!(flat.len(), 4);
        for (k, level) in flat.iter().enumerate() {
            assert_eq!(level.len(), 4 * (8 >> k) * (8 >> k));
            assert!(level.chunks_exact(4).all(|p| p == [200, 100, 50, 255]), "level {k}: {:?}", &level[..4]);
        }
        // Black and white halves average to linear 0.5 (sRGB 188), not 128.
        let halves = mip_chain(&image(2, 2, |x, _| if x == 0 { [0, 0, 0, 255] } else { [255, 255, 255, 255] }), 4);
        assert_eq!(&halves[2][..4], &[188, 188, 188, 255]);
        // Shrinking a 4-texel row to 2 averages pairs.
        let row = [Vec4::ZERO, Vec4::ONE, Vec4::ONE, Vec4::ONE];
        assert_eq!(resample(&row, 2), vec![Vec4::splat(0.5), Vec4::ONE]);
    }
    #[test]
    fn the_table_encodes_every_value_as_powf_does() {
        let e = encoder();
        let mut values: Vec<f32> = (0..=1.0f32.to_bits()).step_by(1001).map(f32::from_bits).collect();
        // Each step of the curve and the floats beside it.
        for r in e.rise {
            let b = r.to_bits();
            values.extend((b.saturating_sub(3)..=b + 3).map(f32::from_bits));
        }
        values.extend([-1.0, -0.0, 1.0, 1.5, f32::INFINITY]);
        for v in values {
            assert_eq!(e.encode(v), linear_to_srgb(v), "{v:e}");
        }
        // Bytes come back: decoding then encoding is the identity.
        let lut = srgb_to_linear_table();
        assert!((0..=255u8).all(|b| e.encode(lut[b as usize]) == b));
    }

    #[test]
    fn an_image_of_its_class_size_skips_resampling_and_gets_the_same_chain() {
        let mut state = 12345u32;
        let mut byte = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 24) as u8
        };
        let mut img = image(8, 8, |_, _| [0; 4]);
        img.rgba.iter_mut().for_each(|b| *b = byte());
        for linear in [false, true] {
            img.linear = linear;
            let fast = mip_chain(&img, 8);
            assert_eq!(fast, chain_by_resampling(&img, 8), "linear {linear}");
            if !linear {
                assert_eq!(fast[0], img.rgba, "sRGB texels are kept as they are");
            }
        }
    }
}
