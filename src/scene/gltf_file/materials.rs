//! glTF metallic-roughness materials (docs/scenes.md, "glTF"; the BRDF is
//! src/brdf.rs): base colour, metallic and roughness factors as they are,
//! emission = emissive factor x emissive strength. Base colour, emissive,
//! metallic-roughness and normal textures are read (textures.rs); occlusion
//! textures are not (rays find occlusion), which the loader says once.

use super::super::gpu_types::MaterialGpu;

/// The glTF default material (no `material` on a primitive): white,
/// metallic 1, roughness 1, as the spec's defaults give.
pub(crate) const DEFAULT: MaterialGpu = MaterialGpu::metal_rough([1.0; 3], 1.0, 1.0, [0.0; 3]);

/// Material `m` in glint's terms; values outside glTF's ranges are errors.
pub(crate) fn convert(m: &gltf::Material) -> Result<MaterialGpu, String> {
    let at = format!("materials[{}]", m.index().unwrap_or(0));
    let pbr = m.pbr_metallic_roughness();
    let unit = |field: &str, x: f32| -> Result<f32, String> {
        if (0.0..=1.0).contains(&x) {
            Ok(x)
        } else {
            Err(format!("{at}.{field}: {x} is outside 0..1"))
        }
    };
    let base = pbr.base_color_factor();
    let mut albedo = [0.0; 3];
    for (k, a) in albedo.iter_mut().enumerate() {
        *a = unit("pbrMetallicRoughness.baseColorFactor", base[k])?;
    }
    let metallic = unit("pbrMetallicRoughness.metallicFactor", pbr.metallic_factor())?;
    let roughness = unit("pbrMetallicRoughness.roughnessFactor", pbr.roughness_factor())?;
    let strength = m.emissive_strength().unwrap_or(1.0);
    if !(strength.is_finite() && strength >= 0.0) {
        return Err(format!("{at}.extensions.KHR_materials_emissive_strength.emissiveStrength: {strength} is not a finite value >= 0"));
    }
    let mut emission = [0.0; 3];
    for (k, e) in emission.iter_mut().enumerate() {
        *e = unit("emissiveFactor", m.emissive_factor()[k])? * strength;
    }
    Ok(MaterialGpu::metal_rough(albedo, metallic, roughness, emission))
}

/// What the conversion leaves out for the materials of `doc`, one line each
/// (empty when nothing is left out).
pub(crate) fn left_out(doc: &gltf::Document) -> Vec<String> {
    let mut textured = 0;
    let mut blend = 0;
    for m in doc.materials() {
        textured += usize::from(m.occlusion_texture().is_some());
        blend += usize::from(m.alpha_mode() == gltf::material::AlphaMode::Blend);
    }
    let mut out = Vec::new();
    if textured > 0 {
        out.push(format!("{textured} material(s) have occlusion textures, which glint does not read (rays find the occlusion themselves)"));
    }
    if blend > 0 {
        out.push(format!("{blend} material(s) use alphaMode BLEND, which glint renders as MASK at alpha 0.5"));
    }
    out
}
