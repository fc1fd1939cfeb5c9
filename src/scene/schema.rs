//! The RON scene format (docs/scenes.md), exactly as written in the
//! file. Validation and the conversion into an hecs world live in
//! `validate.rs` and `load.rs`.

use std::fmt;
use std::marker::PhantomData;

use serde::de::{MapAccess, Visitor};
use serde::{Deserialize, Deserializer};

pub(crate) type V3 = [f32; 3];
/// A position (or a displacement between positions), parsed as f64 so a
/// scene far from the origin keeps its precision until it is rebased on the
/// camera (`SceneGpu`).
pub(crate) type P3 = [f64; 3];

#[derive(Debug, Deserialize)]
#[serde(rename = "Scene", deny_unknown_fields)]
pub(crate) struct SceneDesc {
    pub camera: CameraDesc,
    #[serde(default)]
    pub background: V3,
    #[serde(default)]
    pub environment: Option<EnvironmentDesc>,
    #[serde(default)]
    pub materials: OrderedMap<MaterialDesc>,
    #[serde(default)]
    pub objects: Vec<ObjectDesc>,
    #[serde(default)]
    pub lights: Vec<LightDesc>,
}

#[derive(Debug, Deserialize)]
#[serde(rename = "Camera", deny_unknown_fields)]
pub(crate) struct CameraDesc {
    pub position: P3,
    pub target: P3,
    #[serde(default = "up_y")]
    pub up: V3,
    pub vfov_deg: f32,
}

fn up_y() -> V3 {
    [0.0, 1.0, 0.0]
}

fn one() -> f32 {
    1.0
}

/// An environment light: a latitude-longitude map (`path`, EXR or PFM) or
/// one `color`, times `intensity`, turned `rotation_deg` about +y.
#[derive(Debug, Deserialize)]
#[serde(rename = "Environment", deny_unknown_fields)]
pub(crate) struct EnvironmentDesc {
    #[serde(default)]
    pub path: Option<String>,
    #[serde(default)]
    pub color: Option<V3>,
    #[serde(default = "one")]
    pub intensity: f32,
    #[serde(default)]
    pub rotation_deg: f32,
}

#[derive(Debug, Deserialize)]
#[serde(rename = "Material", deny_unknown_fields)]
pub(crate) struct MaterialDesc {
    pub albedo: V3,
    #[serde(default)]
    pub specular: f32,
    /// Given: glTF's metallic-roughness material (albedo its base colour,
    /// roughness its perceptual roughness), with no specular share.
    #[serde(default)]
    pub metallic: Option<f32>,
    #[serde(default)]
    pub roughness: f32,
    #[serde(default)]
    pub emission: V3,
}

// The renames name the enums as a user would in messages ("in enum `Object`").
#[derive(Debug, Deserialize)]
#[serde(rename = "Object", deny_unknown_fields)]
pub(crate) enum ObjectDesc {
    Quad {
        vertices: Vec<P3>,
        material: String,
    },
    Sphere {
        center: P3,
        radius: f32,
        material: String,
        #[serde(default)]
        motion: Option<MotionDesc>,
    },
    Mesh {
        path: String,
        #[serde(default)]
        translate: P3,
        #[serde(default = "one")]
        scale: f32,
        #[serde(default)]
        rotate_deg: V3,
        #[serde(default)]
        material: Option<String>,
        #[serde(default)]
        motion: Option<MotionDesc>,
    },
    /// A glTF 2.0 file's default scene (meshes, materials, point lights),
    /// placed as a whole: world = translate + rotate(scale x glTF world).
    Gltf {
        path: String,
        #[serde(default)]
        translate: P3,
        #[serde(default = "one")]
        scale: f32,
        #[serde(default)]
        rotate_deg: V3,
    },
}

impl ObjectDesc {
    pub(crate) fn kind(&self) -> &'static str {
        match self {
            ObjectDesc::Quad { .. } => "Quad",
            ObjectDesc::Sphere { .. } => "Sphere",
            ObjectDesc::Mesh { .. } => "Mesh",
            ObjectDesc::Gltf { .. } => "Gltf",
        }
    }

    pub(crate) fn motion(&self) -> Option<&MotionDesc> {
        match self {
            ObjectDesc::Quad { .. } | ObjectDesc::Gltf { .. } => None,
            ObjectDesc::Sphere { motion, .. } | ObjectDesc::Mesh { motion, .. } => motion.as_ref(),
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(rename = "Light", deny_unknown_fields)]
// The variants are the names scene files write.
#[allow(clippy::enum_variant_names)]
pub(crate) enum LightDesc {
    SphereLight {
        center: P3,
        radius: f32,
        radiance: V3,
        #[serde(default)]
        motion: Option<MotionDesc>,
    },
    PointLight {
        position: P3,
        intensity: V3,
        #[serde(default)]
        motion: Option<MotionDesc>,
    },
    /// A point light with a cone: full intensity within `inner_deg` of
    /// `direction`, none beyond `outer_deg` (glTF's smooth step between).
    SpotLight {
        position: P3,
        direction: V3,
        intensity: V3,
        #[serde(default)]
        inner_deg: f32,
        #[serde(default = "outer_deg")]
        outer_deg: f32,
        #[serde(default)]
        motion: Option<MotionDesc>,
    },
    /// Light from infinitely far away (a sun), travelling along
    /// `direction`: irradiance E on a surface facing it.
    DirectionalLight {
        direction: V3,
        irradiance: V3,
    },
}

fn outer_deg() -> f32 {
    45.0
}

impl LightDesc {
    pub(crate) fn kind(&self) -> &'static str {
        match self {
            LightDesc::SphereLight { .. } => "SphereLight",
            LightDesc::PointLight { .. } => "PointLight",
            LightDesc::SpotLight { .. } => "SpotLight",
            LightDesc::DirectionalLight { .. } => "DirectionalLight",
        }
    }

    pub(crate) fn motion(&self) -> Option<&MotionDesc> {
        match self {
            LightDesc::SphereLight { motion, .. } | LightDesc::PointLight { motion, .. } | LightDesc::SpotLight { motion, .. } => {
                motion.as_ref()
            }
            LightDesc::DirectionalLight { .. } => None,
        }
    }
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename = "Motion", deny_unknown_fields)]
pub(crate) enum MotionDesc {
    Orbit {
        center: P3,
        axis: V3,
        radius: f32,
        period_s: f32,
        #[serde(default)]
        phase_deg: f32,
    },
    Linear {
        velocity: P3,
    },
}

/// A RON map kept in file order (serde maps would sort or hash it), so that
/// material ids follow the order the materials are written in.
#[derive(Debug)]
pub(crate) struct OrderedMap<V>(pub Vec<(String, V)>);

impl<V> Default for OrderedMap<V> {
    fn default() -> Self {
        OrderedMap(Vec::new())
    }
}

impl<'de, V: Deserialize<'de>> Deserialize<'de> for OrderedMap<V> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit<V>(PhantomData<V>);

        impl<'de, V: Deserialize<'de>> Visitor<'de> for Visit<V> {
            type Value = OrderedMap<V>;

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a map of names to values")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut out = Vec::with_capacity(map.size_hint().unwrap_or(0).min(1024));
                while let Some(entry) = map.next_entry::<String, V>()? {
                    out.push(entry);
                }
                Ok(OrderedMap(out))
            }
        }

        d.deserialize_map(Visit(PhantomData))
    }
}
