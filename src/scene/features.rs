//! Scene features: what a scene contains, used to cull passes (`requires`)
//! and to specialise shaders.

use serde::{Deserialize, Serialize};

/// A capability a pass can require of the scene (`requires: [...]` in a graph).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Feature {
    /// Quads or OBJ meshes.
    Meshes,
    /// Sphere objects (sphere lights do not count).
    Spheres,
    /// Point lights.
    PointLights,
    /// Sphere (area) lights.
    AreaLights,
    /// Any light at all (point or area).
    Lights,
    /// A material with a specular lobe that some object uses.
    Specular,
    /// An emissive material that some object uses (sphere lights' own do not count).
    Emissive,
    /// Anything that moves.
    Motion,
    /// The graph's `probes.mode` is `Thesis` (a property of the graph, not
    /// of the scene: compile decides it, `SceneFeatures::has` says no).
    ThesisProbes,
    /// The graph's `probes.mode` is `Ddgi`.
    DdgiProbes,
}

impl Feature {
    /// The scene features (not the graph's probe modes), for printing.
    pub const ALL: [Feature; 8] = [
        Feature::Meshes,
        Feature::Spheres,
        Feature::PointLights,
        Feature::AreaLights,
        Feature::Lights,
        Feature::Specular,
        Feature::Emissive,
        Feature::Motion,
    ];
}

/// What a loaded scene contains.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SceneFeatures {
    /// Has quads or OBJ meshes.
    pub meshes: bool,
    /// Has sphere objects (sphere lights do not count).
    pub spheres: bool,
    /// Has point lights.
    pub point_lights: bool,
    /// Has sphere lights.
    pub area_lights: bool,
    /// Some object's material has a specular lobe.
    pub specular: bool,
    /// Some object's material emits.
    pub emissive: bool,
    /// Something moves.
    pub motion: bool,
    /// Some surface samples a texture or has vertex colours (both multiply
    /// the material through its texture factors).
    pub textures: bool,
    /// Some triangle has vertex colours other than white.
    pub vertex_colors: bool,
    /// Some normal-mapped triangle has vertex tangents.
    pub vertex_tangents: bool,
    /// Which texture size classes (`texture_classes::CLASSES`) hold images.
    pub texture_classes: [bool; 4],
    /// Some texture has a uv transform other than the identity.
    pub texture_transforms: bool,
    /// Some point light has a cone.
    pub spot_lights: bool,
    /// Some light is directional (`point_lights` is set too: the passes
    /// that shade point lights shade them).
    pub directional_lights: bool,
    /// Some material is alpha-tested (alphaMode MASK).
    pub alpha_mask: bool,
    /// The scene has an environment light (`point_lights` is set too).
    pub environment: bool,
    /// Some triangle's material is single-sided (glTF's `doubleSided:
    /// false`): traversal tests the side a ray meets it from.
    pub single_sided: bool,
    /// Some object's material is glTF's metallic-roughness (src/brdf.rs).
    pub metal_rough: bool,
    /// Some object's material is a coat: a specular share between 0 and
    /// 1 over a diffuse base, not metallic-roughness.
    pub coats: bool,
    /// How many lights (point and sphere); `u32::MAX` in `all()`.
    pub lights: u32,
    /// Rays test every primitive instead of walking a BVH (at most
    /// FLAT_LIMIT of them: `Scene::is_flat`), so a trace loops over at most
    /// that many primitives; false in `all()`. `Scene::compile_features`
    /// sets it from the scene as it is when a graph is compiled for it.
    pub flat: bool,
    /// A sphere light may hold a surface or the camera inside it (one
    /// reaches an object's bounds or the camera, or something moves), so
    /// light sampling needs its from-inside case. `Scene::compile_features`
    /// sets it; true in `all()`.
    pub enclosing_lights: bool,
}

impl SceneFeatures {
    /// Every feature present: used when a graph is checked without a scene.
    pub fn all() -> Self {
        SceneFeatures {
            meshes: true,
            spheres: true,
            point_lights: true,
            area_lights: true,
            specular: true,
            emissive: true,
            motion: true,
            textures: true,
            vertex_colors: true,
            vertex_tangents: true,
            texture_classes: [true; 4],
            texture_transforms: true,
            spot_lights: true,
            directional_lights: true,
            alpha_mask: true,
            environment: true,
            single_sided: true,
            metal_rough: true,
            coats: true,
            lights: u32::MAX,
            flat: false,
            enclosing_lights: true,
        }
    }

    /// Whether the scene has `f` (never for the probe modes).
    pub fn has(&self, f: Feature) -> bool {
        match f {
            Feature::Meshes => self.meshes,
            Feature::Spheres => self.spheres,
            Feature::PointLights => self.point_lights,
            Feature::AreaLights => self.area_lights,
            Feature::Lights => self.point_lights || self.area_lights,
            Feature::Specular => self.specular,
            Feature::Emissive => self.emissive,
            Feature::Motion => self.motion,
            Feature::ThesisProbes | Feature::DdgiProbes => false,
        }
    }

    /// Names of the features present, for printing.
    pub fn names(&self) -> Vec<String> {
        Feature::ALL
            .iter()
            .filter(|f| self.has(**f))
            .map(|f| format!("{f:?}"))
            .collect()
    }
}
