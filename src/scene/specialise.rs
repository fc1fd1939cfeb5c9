//! Shader specialisation: what a scene lacks, as pipeline override
//! constants that compile the code for it out of every shader.
//!
//! The constants are declared in `shaders/shared/scene.wgsl`, with
//! defaults that are right for any scene (the generic shader). A pass gets
//! the ones its shader declares, unless its graph sets them itself. CPU
//! drivers run every path of a shader under a SIMD mask, taken or not, so
//! code a scene cannot reach still costs time there; on a GPU it costs
//! registers. Compile decides them (`Schedule::specialisations`), and
//! `glint graph check --scene` prints them with their reasons;
//! `--no-specialise` leaves every shader generic.

use super::features::SceneFeatures;

/// One override constant set away from its generic default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Specialisation {
    /// The override's name in the shaders.
    pub constant: &'static str,
    /// The value set.
    pub value: bool,
    /// Why, in words, for `graph check`.
    pub reason: &'static str,
}

impl Specialisation {
    /// The value as a pipeline constant.
    pub fn as_constant(&self) -> (&'static str, f64) {
        (self.constant, f64::from(u8::from(self.value)))
    }
}

/// Whether rays can hit spheres (sphere objects or sphere lights).
pub const SCENE_SPHERES: &str = "SCENE_SPHERES";
/// Whether rays can hit triangles (meshes and quads).
pub const SCENE_MESHES: &str = "SCENE_MESHES";
/// Whether the scene has point lights.
pub const SCENE_POINT_LIGHTS: &str = "SCENE_POINT_LIGHTS";
/// Whether the scene has sphere lights.
pub const SCENE_AREA_LIGHTS: &str = "SCENE_AREA_LIGHTS";
/// Whether any surface is specular (reflects: reflection depth above 0).
pub const SCENE_SPECULAR: &str = "SCENE_SPECULAR";
/// Exactly one light: the light loops become straight code.
pub const SCENE_ONE_LIGHT: &str = "SCENE_ONE_LIGHT";
/// Whether a sphere light may hold a shading point inside it.
pub const SCENE_INSIDE_LIGHTS: &str = "SCENE_INSIDE_LIGHTS";
/// Whether some surface samples a texture (shared/textures.wgsl).
pub const SCENE_TEXTURES: &str = "SCENE_TEXTURES";
/// Whether some point light has a cone (shared/scene.wgsl, spot_factor).
pub const SCENE_SPOT_LIGHTS: &str = "SCENE_SPOT_LIGHTS";
/// Whether some light is directional (shared/scene.wgsl, load_light).
pub const SCENE_DIRECTIONAL_LIGHTS: &str = "SCENE_DIRECTIONAL_LIGHTS";
/// Whether some material is alpha-tested (shared/textures.wgsl, alpha_passes).
pub const SCENE_ALPHA_MASK: &str = "SCENE_ALPHA_MASK";

/// Whether some material is a coat, a specular share between 0 and 1
/// (shared/path.wgsl, SPLIT_LOBES).
pub const SCENE_COATS: &str = "SCENE_COATS";

/// Whether some material is glTF's metallic-roughness (shared/brdf.wgsl).
pub const SCENE_METALLIC_ROUGHNESS: &str = "SCENE_METALLIC_ROUGHNESS";

/// Whether each texture size class (256, 512, 1024, 2048) holds images
/// (shared/textures.wgsl, sample_slot): a class without any is never
/// sampled, and its reads are compiled out (CPU drivers run each class's
/// read under a lane mask for every texel a shader samples).
pub const SCENE_TEXTURE_CLASSES: [&str; 4] = ["SCENE_TEXTURES_256", "SCENE_TEXTURES_512", "SCENE_TEXTURES_1024", "SCENE_TEXTURES_2048"];

/// Whether some texture has a uv transform other than the identity
/// (shared/textures.wgsl, sample_material).
pub const SCENE_TEXTURE_TRANSFORMS: &str = "SCENE_TEXTURE_TRANSFORMS";

/// Whether some triangle has vertex colours (shared/textures.wgsl,
/// texture_factors).
pub const SCENE_VERTEX_COLORS: &str = "SCENE_VERTEX_COLORS";

/// Whether some normal-mapped triangle has vertex tangents (the file's or
/// MikkTSpace's; shared/textures.wgsl, bent_normal).
pub const SCENE_VERTEX_TANGENTS: &str = "SCENE_VERTEX_TANGENTS";

/// Whether the lights are in clusters (shared/light_choice.wgsl): a
/// scene of at most `light_clusters::CLUSTERED_ABOVE` lights weighs each.
pub const SCENE_LIGHT_CLUSTERS: &str = "SCENE_LIGHT_CLUSTERS";

/// Whether the scene has an environment light (shared/environment.wgsl):
/// without one a miss sees `background` and nothing samples it.
pub const SCENE_ENVIRONMENT: &str = "SCENE_ENVIRONMENT";

/// Whether some material is single-sided (shared/scene.wgsl,
/// `face_passes`): without one, traversal never asks which side a ray meets.
pub const SCENE_SINGLE_SIDED: &str = "SCENE_SINGLE_SIDED";

/// Every constant this module may set, with its generic default.
pub const GENERIC: [(&str, bool); 23] = [
    (SCENE_SPHERES, true),
    (SCENE_MESHES, true),
    (SCENE_POINT_LIGHTS, true),
    (SCENE_AREA_LIGHTS, true),
    (SCENE_SPECULAR, true),
    (SCENE_COATS, true),
    (SCENE_ONE_LIGHT, false),
    (SCENE_LIGHT_CLUSTERS, true),
    (SCENE_INSIDE_LIGHTS, true),
    (SCENE_TEXTURES, true),
    (SCENE_SPOT_LIGHTS, true),
    (SCENE_ALPHA_MASK, true),
    (SCENE_DIRECTIONAL_LIGHTS, true),
    (SCENE_METALLIC_ROUGHNESS, true),
    (SCENE_ENVIRONMENT, true),
    (SCENE_SINGLE_SIDED, true),
    (SCENE_TEXTURE_CLASSES[0], true),
    (SCENE_TEXTURE_CLASSES[1], true),
    (SCENE_TEXTURE_CLASSES[2], true),
    (SCENE_TEXTURE_CLASSES[3], true),
    (SCENE_TEXTURE_TRANSFORMS, true),
    (SCENE_VERTEX_COLORS, true),
    (SCENE_VERTEX_TANGENTS, true),
];

/// The specialisations for a scene with `f`: only the constants that
/// differ from the generic default, in `GENERIC`'s order.
pub fn specialisations(f: &SceneFeatures) -> Vec<Specialisation> {
    let mut out = Vec::new();
    let mut off = |constant, reason| out.push(Specialisation { constant, value: false, reason });
    if !f.spheres && !f.area_lights {
        off(SCENE_SPHERES, "no spheres or sphere lights: sphere tests compiled out");
    }
    if !f.meshes {
        off(SCENE_MESHES, "no meshes or quads: triangle tests and mesh traversal compiled out");
    }
    if !f.point_lights {
        off(SCENE_POINT_LIGHTS, "no point lights: point-light shading compiled out");
    }
    if !f.area_lights {
        off(SCENE_AREA_LIGHTS, "no sphere lights: area-light sampling compiled out");
    }
    if !f.specular {
        off(SCENE_SPECULAR, "no specular material: reflection depth 0, mirror bounces compiled out");
    }
    if !f.coats {
        off(SCENE_COATS, "no coat (a specular share between 0 and 1): a coat's two lobes compiled out");
    }
    if f.lights == 1 {
        out.push(Specialisation { constant: SCENE_ONE_LIGHT, value: true, reason: "one light: no light loop" });
    }
    if !super::light_clusters::clustered(f.lights as usize) {
        out.push(Specialisation { constant: SCENE_LIGHT_CLUSTERS, value: false, reason: "few lights: each weighed at every choice, no clusters" });
    }
    if !f.enclosing_lights {
        out.push(Specialisation {
            constant: SCENE_INSIDE_LIGHTS,
            value: false,
            reason: "no sphere light reaches a surface or the camera: sampling from inside one compiled out",
        });
    }
    if !f.textures {
        out.push(Specialisation { constant: SCENE_TEXTURES, value: false, reason: "no textures: texture sampling compiled out" });
    }
    if !f.spot_lights {
        out.push(Specialisation { constant: SCENE_SPOT_LIGHTS, value: false, reason: "no spot lights: cones compiled out" });
    }
    if !f.alpha_mask {
        out.push(Specialisation { constant: SCENE_ALPHA_MASK, value: false, reason: "no alpha-tested material: the alpha test compiled out of traversal" });
    }
    if !f.directional_lights {
        out.push(Specialisation { constant: SCENE_DIRECTIONAL_LIGHTS, value: false, reason: "no directional lights: their sampling compiled out" });
    }
    if !f.metal_rough {
        out.push(Specialisation { constant: SCENE_METALLIC_ROUGHNESS, value: false, reason: "no metallic-roughness material: its BRDF compiled out" });
    }
    if !f.environment {
        out.push(Specialisation { constant: SCENE_ENVIRONMENT, value: false, reason: "no environment light: its map and sampling compiled out" });
    }
    if !f.single_sided {
        out.push(Specialisation { constant: SCENE_SINGLE_SIDED, value: false, reason: "no single-sided material: traversal tests no face's side" });
    }
    if f.textures {
        for (constant, present) in SCENE_TEXTURE_CLASSES.into_iter().zip(f.texture_classes) {
            if !present {
                out.push(Specialisation { constant, value: false, reason: "no texture of this size class: its reads compiled out" });
            }
        }
        if !f.texture_transforms {
            out.push(Specialisation { constant: SCENE_TEXTURE_TRANSFORMS, value: false, reason: "no texture transform: uvs read as they are" });
        }
        if !f.vertex_colors {
            out.push(Specialisation { constant: SCENE_VERTEX_COLORS, value: false, reason: "no vertex colours: none read" });
        }
        if !f.vertex_tangents {
            out.push(Specialisation { constant: SCENE_VERTEX_TANGENTS, value: false, reason: "no vertex tangents: normal textures bent in each triangle's uv frame" });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(f: &SceneFeatures) -> Vec<(&'static str, bool)> {
        specialisations(f).iter().map(|s| (s.constant, s.value)).collect()
    }

    #[test]
    fn a_scene_with_everything_is_generic() {
        assert!(specialisations(&SceneFeatures::all()).is_empty());
        let mut f = SceneFeatures::all();
        f.lights = 65;
        assert!(specialisations(&f).is_empty(), "65 lights: in clusters");
        f.lights = 64;
        assert_eq!(names(&f), [(SCENE_LIGHT_CLUSTERS, false)]);
    }

    #[test]
    fn what_a_scene_lacks_is_compiled_out() {
        // The Cornell box with a point light and no mirror.
        let f = SceneFeatures { meshes: true, spheres: true, point_lights: true, lights: 1, ..Default::default() };
        assert_eq!(names(&f), [(SCENE_AREA_LIGHTS, false), (SCENE_SPECULAR, false), (SCENE_COATS, false), (SCENE_ONE_LIGHT, true), (SCENE_LIGHT_CLUSTERS, false), (SCENE_INSIDE_LIGHTS, false), (SCENE_TEXTURES, false), (SCENE_SPOT_LIGHTS, false), (SCENE_ALPHA_MASK, false), (SCENE_DIRECTIONAL_LIGHTS, false), (SCENE_METALLIC_ROUGHNESS, false), (SCENE_ENVIRONMENT, false), (SCENE_SINGLE_SIDED, false)]);
        // A sphere light is a sphere rays can hit.
        let f = SceneFeatures { meshes: true, area_lights: true, specular: true, lights: 3, ..Default::default() };
        assert_eq!(names(&f), [(SCENE_POINT_LIGHTS, false), (SCENE_COATS, false), (SCENE_LIGHT_CLUSTERS, false), (SCENE_INSIDE_LIGHTS, false), (SCENE_TEXTURES, false), (SCENE_SPOT_LIGHTS, false), (SCENE_ALPHA_MASK, false), (SCENE_DIRECTIONAL_LIGHTS, false), (SCENE_METALLIC_ROUGHNESS, false), (SCENE_ENVIRONMENT, false), (SCENE_SINGLE_SIDED, false)]);
        // One that may hold a surface or the camera keeps sampling from inside.
        let f = SceneFeatures { meshes: true, area_lights: true, specular: true, lights: 3, enclosing_lights: true, ..Default::default() };
        assert_eq!(names(&f), [(SCENE_POINT_LIGHTS, false), (SCENE_COATS, false), (SCENE_LIGHT_CLUSTERS, false), (SCENE_TEXTURES, false), (SCENE_SPOT_LIGHTS, false), (SCENE_ALPHA_MASK, false), (SCENE_DIRECTIONAL_LIGHTS, false), (SCENE_METALLIC_ROUGHNESS, false), (SCENE_ENVIRONMENT, false), (SCENE_SINGLE_SIDED, false)]);
        // Only spheres and a point light: no triangles.
        let f = SceneFeatures { spheres: true, point_lights: true, specular: true, lights: 2, ..Default::default() };
        assert_eq!(names(&f), [(SCENE_MESHES, false), (SCENE_AREA_LIGHTS, false), (SCENE_COATS, false), (SCENE_LIGHT_CLUSTERS, false), (SCENE_INSIDE_LIGHTS, false), (SCENE_TEXTURES, false), (SCENE_SPOT_LIGHTS, false), (SCENE_ALPHA_MASK, false), (SCENE_DIRECTIONAL_LIGHTS, false), (SCENE_METALLIC_ROUGHNESS, false), (SCENE_ENVIRONMENT, false), (SCENE_SINGLE_SIDED, false)]);
    }

    #[test]
    fn an_empty_scene_has_every_specialisation_but_one_light() {
        // (Its size classes go with the textures: no texture is read at all.)
        let got = names(&SceneFeatures::default());
        let want: Vec<_> = GENERIC
            .iter()
            .filter(|(c, _)| {
                *c != SCENE_ONE_LIGHT && !SCENE_TEXTURE_CLASSES.contains(c) && ![SCENE_TEXTURE_TRANSFORMS, SCENE_VERTEX_COLORS, SCENE_VERTEX_TANGENTS].contains(c)
            })
            .map(|(c, v)| (*c, !v))
            .collect();
        assert_eq!(got, want);
    }

    #[test]
    fn a_textured_scene_keeps_the_reads_of_its_size_classes_only() {
        let mut f = SceneFeatures::all();
        f.texture_classes = [false, true, false, false];
        f.texture_transforms = false;
        f.vertex_tangents = false;
        let off: Vec<_> = specialisations(&f).iter().map(|s| (s.constant, s.value)).collect();
        assert_eq!(off, [("SCENE_TEXTURES_256", false), ("SCENE_TEXTURES_1024", false), ("SCENE_TEXTURES_2048", false), (SCENE_TEXTURE_TRANSFORMS, false), (SCENE_VERTEX_TANGENTS, false)]);
    }

    #[test]
    fn every_specialisation_flips_a_generic_default() {
        let f = SceneFeatures { lights: 1, ..Default::default() };
        for s in specialisations(&f) {
            let generic = GENERIC.iter().find(|(c, _)| *c == s.constant).map(|(_, v)| *v);
            assert_eq!(generic, Some(!s.value), "{}", s.constant);
            assert!(!s.reason.is_empty());
        }
    }
}
