//! A glTF material's textures: which image each slot samples, with its
//! sampler's wrap modes and its `KHR_texture_transform`, and the images
//! themselves decoded to RGBA8 (PNG and JPEG, from a file beside the glTF,
//! a data URI or a buffer view).

use std::path::{Path, PathBuf};

use super::buffers;
use crate::scene::world::TextureImage;

/// How a texture coordinate outside 0..1 reads the image (glTF sampler).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Wrap {
    Repeat,
    Clamp,
    Mirror,
}

/// One texture slot of a material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TextureRef {
    /// The glTF image index.
    pub image: usize,
    /// (s, t) wrap modes.
    pub wrap: [Wrap; 2],
    /// uv' = (row 0 . (u, v, 1), row 1 . (u, v, 1)): KHR_texture_transform
    /// (the identity without it).
    pub transform: [[f32; 3]; 2],
}

/// The texture slots glint reads: base colour and emission (sRGB),
/// metallic-roughness and normals (linear; the normal texture's scale).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct MaterialTextures {
    pub base_color: Option<TextureRef>,
    pub emissive: Option<TextureRef>,
    pub metallic_roughness: Option<TextureRef>,
    pub normal: Option<(TextureRef, f32)>,
    /// alphaMode MASK (and BLEND, as MASK at 0.5): (alphaCutoff, the base
    /// colour factor's alpha).
    pub alpha_mask: Option<(f32, f32)>,
}


/// The slots of material `m` (`at`: its glTF path).
pub(crate) fn material_textures(m: &gltf::Material, at: &str) -> Result<MaterialTextures, String> {
    let pbr = m.pbr_metallic_roughness();
    let factor = pbr.base_color_factor()[3];
    let alpha_mask = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => None,
        gltf::material::AlphaMode::Mask => {
            let cutoff = m.alpha_cutoff().unwrap_or(0.5);
            if !(cutoff.is_finite() && cutoff >= 0.0) {
                return Err(format!("{at}.alphaCutoff: {cutoff} is not a finite value >= 0"));
            }
            Some((cutoff, factor))
        }
        gltf::material::AlphaMode::Blend => Some((0.5, factor)),
    };
    let normal = match m.normal_texture() {
        Some(t) => {
            let scale = t.scale();
            if !scale.is_finite() {
                return Err(format!("{at}.normalTexture.scale: {scale} is not finite"));
            }
            // (gltf 1.4 does not hand a normal texture's KHR_texture_transform
            // over: it is read untransformed.)
            Some((texture_ref(&t.texture(), t.tex_coord(), None, &format!("{at}.normalTexture"))?, scale))
        }
        None => None,
    };
    let info = |t: gltf::texture::Info, at: String| texture_ref(&t.texture(), t.tex_coord(), t.texture_transform(), &at);
    Ok(MaterialTextures {
        alpha_mask,
        base_color: pbr.base_color_texture().map(|t| info(t, format!("{at}.pbrMetallicRoughness.baseColorTexture"))).transpose()?,
        emissive: m.emissive_texture().map(|t| info(t, format!("{at}.emissiveTexture"))).transpose()?,
        metallic_roughness: pbr.metallic_roughness_texture().map(|t| info(t, format!("{at}.pbrMetallicRoughness.metallicRoughnessTexture"))).transpose()?,
        normal,
    })
}

fn texture_ref(texture: &gltf::Texture, tex_coord: u32, transform_ext: Option<gltf::texture::TextureTransform>, at: &str) -> Result<TextureRef, String> {
    let mut tex_coord = tex_coord;
    let mut transform = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    if let Some(t) = transform_ext {
        let ([ox, oy], r, [sx, sy]) = (t.offset(), t.rotation(), t.scale());
        if ![ox, oy, r, sx, sy].iter().all(|x| x.is_finite()) {
            return Err(format!("{at}.extensions.KHR_texture_transform: a value is not finite"));
        }
        // translation x rotation x scale. The rotation turns the image
        // clockwise as it appears (v points down): the extension's example
        // (offset (0, 1), a quarter turn, scale 0.5) then reads the lower
        // left quadrant, and the TextureTransformTest sample model's arrow
        // meets its green marker.
        let (s, c) = r.sin_cos();
        transform = [[c * sx, s * sy, ox], [-s * sx, c * sy, oy]];
        tex_coord = t.tex_coord().unwrap_or(tex_coord);
    }
    if tex_coord != 0 {
        return Err(format!("{at}.texCoord: {tex_coord}; glint reads TEXCOORD_0 only so far"));
    }
    let wrap = |m: gltf::texture::WrappingMode| match m {
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
    };
    let sampler = texture.sampler();
    Ok(TextureRef { image: texture.source().index(), wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())], transform })
}

/// Decodes images `wanted` of `doc`, in that order, with the file each
/// names (if any): a batch at a time on every core (decoding JPEGs was half
/// of a Sponza-class scene's load on one); the first error in that order.
pub(crate) fn decode_all(doc: &gltf::Document, wanted: &[usize], buffers: &[Vec<u8>], dir: &Path) -> Result<Vec<(TextureImage, Option<PathBuf>)>, String> {
    let mut out = Vec::with_capacity(wanted.len());
    crate::batches::in_batches(wanted, |&i| decode(doc, i, buffers, dir), |_, d| out.push(d));
    out.into_iter().collect()
}

/// Decodes image `index` of `doc`, with the file it names (if any).
fn decode(doc: &gltf::Document, index: usize, buffers: &[Vec<u8>], dir: &Path) -> Result<(TextureImage, Option<PathBuf>), String> {
    let at = format!("images[{index}]");
    let image = doc.images().nth(index).ok_or_else(|| format!("{at}: missing"))?;
    let mut file = None;
    let bytes: Vec<u8> = match image.source() {
        gltf::image::Source::View { view, .. } => {
            let buffer = buffers.get(view.buffer().index()).map_or(&[][..], Vec::as_slice);
            let range = view.offset()..view.offset().saturating_add(view.length());
            buffer.get(range).ok_or_else(|| format!("{at}.bufferView: bufferViews[{}] runs past its buffer", view.index()))?.to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => match buffers::data_uri(uri) {
            Some(decoded) => decoded.map_err(|e| format!("{at}.uri: a data URI that is not valid base64: {e}"))?,
            None => {
                let path = buffers::local_file(uri, dir).map_err(|e| format!("{at}.uri: {e}"))?;
                let bytes = std::fs::read(&path).map_err(|e| format!("{at}.uri: cannot read \"{uri}\" (looked for {}): {e}", path.display()))?;
                file = Some(path);
                bytes
            }
        },
    };
    Ok((TextureImage::decode(&bytes).map_err(|e| format!("{at}: {e}"))?, file))
}
