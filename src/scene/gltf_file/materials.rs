//! glTF metallic-roughness materials (docs/scenes.md, "glTF"; the BRDF is
//! src/brdf.rs): base colour, metallic and roughness factors as they are,
//! emission = emissive factor x emissive strength. Base colour, emissive,
//! metallic-roughness and normal textures are read (textures.rs); occlusion
//! textures are not (rays find occlusion), which the loader says once.

use super::super::gpu_types::{MaterialGpu, MATERIAL_SINGLE_SIDED};

/// The glTF default material (no `material` on a primitive): white,
/// metallic 1, roughness 1, single-sided, as the spec's defaults give.
pub(crate) const DEFAULT: MaterialGpu = MaterialGpu { flags: MATERIAL_SINGLE_SIDED, ..MaterialGpu::metal_rough([1.0; 3], 1.0, 1.0, [0.0; 3]) };

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
    let flags = if m.double_sided() { 0 } else { MATERIAL_SINGLE_SIDED };
    Ok(MaterialGpu { flags, ..MaterialGpu::metal_rough(albedo, metallic, roughness, emission) })
}

/// What the conversion leaves out for the materials and primitives of
/// `doc`, one line each (empty when nothing is left out).
pub(crate) fn left_out(doc: &gltf::Document) -> Vec<String> {
    use gltf::Semantic;
    let (mut occlusion, mut blend, mut second_uvs) = (0, 0, 0);
    for m in doc.materials() {
        occlusion += usize::from(m.occlusion_texture().is_some());
        blend += usize::from(m.alpha_mode() == gltf::material::AlphaMode::Blend);
        let pbr = m.pbr_metallic_roughness();
        let sets = [
            pbr.base_color_texture().map(|t| t.tex_coord()),
            pbr.metallic_roughness_texture().map(|t| t.tex_coord()),
            m.emissive_texture().map(|t| t.tex_coord()),
            m.normal_texture().map(|t| t.tex_coord()),
        ];
        second_uvs += usize::from(sets.iter().flatten().any(|&set| set != 0));
    }
    let (mut colour_alpha, mut morphs) = (0, 0);
    for prim in doc.meshes().flat_map(|m| m.primitives().collect::<Vec<_>>()) {
        let alpha_tested = prim.material().alpha_mode() != gltf::material::AlphaMode::Opaque;
        colour_alpha += usize::from(alpha_tested && prim.get(&Semantic::Colors(0)).is_some_and(|a| a.dimensions() == gltf::accessor::Dimensions::Vec4));
        morphs += usize::from(prim.morph_targets().next().is_some());
    }
    let mut out = Vec::new();
    let mut say = |n: usize, what: &str| {
        if n > 0 {
            out.push(format!("{n} {what}"));
        }
    };
    say(occlusion, "material(s) have occlusion textures, which glint does not read (rays find the occlusion themselves)");
    say(blend, "material(s) use alphaMode BLEND, which glint renders as MASK at alpha 0.5");
    say(second_uvs, "material(s) read a texture through TEXCOORD_1 or later, which glint reads through TEXCOORD_0");
    say(colour_alpha, "alpha-tested primitive(s) have vertex colours with alpha (COLOR_0), whose alpha glint does not apply");
    say(morphs, "primitive(s) have morph targets, which glint does not apply (the base shape is shown)");
    out
}
