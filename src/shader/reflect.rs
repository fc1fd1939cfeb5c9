//! What the frame graph needs to know of a shader, as plain data: bindings
//! (name, slot, kind, access), the `params` uniform layout, `override`
//! constants and the workgroup size. `graph::compile` works on this alone,
//! so it can be unit-tested without naga or a GPU.

use crate::error::Location;
use crate::format::TexFormat;

/// What the frame graph knows of one shader.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaderInfo {
    /// File name under `shaders/`.
    pub name: String,
    /// The compute entry points (other stages are left out).
    pub entry_points: Vec<EntryInfo>,
    /// The named `override` constants of a scalar type.
    pub overrides: Vec<OverrideInfo>,
    /// Layout of the uniform named `params`, if the shader declares one.
    pub params: Option<ParamsLayout>,
}

/// A compute entry point.
#[derive(Debug, Clone, PartialEq)]
pub struct EntryInfo {
    /// The function's name (`main`).
    pub name: String,
    /// `@workgroup_size(x, y, z)`, unset dimensions as 1.
    pub workgroup_size: [u32; 3],
    /// Only the bindings this entry point uses.
    pub bindings: Vec<BindingInfo>,
}

/// A resource an entry point uses: a global with `@group` and `@binding`.
#[derive(Debug, Clone, PartialEq)]
pub struct BindingInfo {
    /// The global's name, which a graph's resources are matched by.
    pub name: String,
    /// `@group(n)`.
    pub group: u32,
    /// `@binding(n)`.
    pub binding: u32,
    /// What kind of resource it is, and how it may be accessed.
    pub kind: BindingKind,
    /// Where the variable is declared (original file and line).
    pub location: Location,
}

/// The texel type a `texture_2d<T>` is read as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleType {
    /// `texture_2d<f32>`.
    Float,
    /// `texture_2d<u32>`.
    Uint,
    /// `texture_2d<i32>`.
    Sint,
}

/// The access mode of a `texture_storage_2d`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StorageAccess {
    /// `read`: textureLoad only.
    Read,
    /// `write`: textureStore only.
    Write,
    /// `read_write`: both.
    ReadWrite,
}

/// The kinds of resource a glint shader may bind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BindingKind {
    /// `texture_2d<T>`: read with textureLoad.
    SampledTexture {
        /// The texel type `T`.
        sample: SampleType,
    },
    /// `texture_storage_2d<format, access>`.
    StorageTexture {
        /// The texel format.
        format: TexFormat,
        /// `read`, `write` or `read_write`.
        access: StorageAccess,
    },
    /// `var<uniform>` of `size` bytes (type name for messages).
    Uniform {
        /// The struct's name, for messages (`?` when unnamed).
        type_name: String,
        /// Its size in bytes.
        size: u32,
    },
    /// `var<storage, read>` (read_only) or `read_write`.
    Storage {
        /// Whether it is declared `read`.
        read_only: bool,
    },
    /// `texture_2d_array<f32>`, sampled with a filtering sampler (only
    /// engine resources: the scene's texture size classes).
    SampledTextureArray,
    /// `sampler` (filtering; only the engine's `scene_sampler`).
    Sampler,
}

impl BindingKind {
    /// The binding's type as WGSL declares it (`texture_storage_2d<rgba32float, write>`).
    pub fn describe(&self) -> String {
        match self {
            BindingKind::SampledTexture { sample } => format!("texture_2d<{}>", match sample {
                SampleType::Float => "f32",
                SampleType::Uint => "u32",
                SampleType::Sint => "i32",
            }),
            BindingKind::StorageTexture { format, access } => format!(
                "texture_storage_2d<{}, {}>",
                format.wgsl_name(),
                match access {
                    StorageAccess::Read => "read",
                    StorageAccess::Write => "write",
                    StorageAccess::ReadWrite => "read_write",
                }
            ),
            BindingKind::Uniform { type_name, .. } => format!("var<uniform> of type {type_name}"),
            BindingKind::Storage { read_only: true } => "var<storage, read>".into(),
            BindingKind::Storage { read_only: false } => "var<storage, read_write>".into(),
            BindingKind::SampledTextureArray => "texture_2d_array<f32>".into(),
            BindingKind::Sampler => "sampler".into(),
        }
    }
}

/// A 32-bit scalar type (or `bool`), of a param or an override.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScalarType {
    /// `f32`.
    F32,
    /// `u32`.
    U32,
    /// `i32`.
    I32,
    /// `bool` (overrides only; params may not be bool).
    Bool,
}

/// One member of the `params` uniform struct.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamMember {
    /// The member's name, which graphs and the viewer set it by.
    pub name: String,
    /// Its byte offset in the struct.
    pub offset: u32,
    /// Its scalar type (a vector's component type).
    pub scalar: ScalarType,
    /// 1 for a scalar, 2..4 for a vector.
    pub components: u32,
    /// The range values must keep to (`// ui: MIN..MAX limit`), with the
    /// source line that declares it.
    pub limit: Option<(f64, f64)>,
}

/// The layout of a shader's `params` uniform.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamsLayout {
    /// The struct's size in bytes.
    pub size: u32,
    /// Its members, in declaration order.
    pub members: Vec<ParamMember>,
}

/// A named `override` constant.
#[derive(Debug, Clone, PartialEq)]
pub struct OverrideInfo {
    /// Its name, which a graph sets it by.
    pub name: String,
    /// Its type.
    pub scalar: ScalarType,
    /// Whether the shader gives it a default (`override x = 1u;`).
    pub has_default: bool,
}
