//! What the frame graph needs to know of a shader, as plain data: bindings
//! (name, slot, kind, access), the `params` uniform layout, `override`
//! constants and the workgroup size. `graph::compile` works on this alone,
//! so it can be unit-tested without naga or a GPU.

use crate::error::Location;
use crate::format::TexFormat;

#[derive(Debug, Clone, PartialEq)]
pub struct ShaderInfo {
    /// File name under `shaders/`.
    pub name: String,
    pub entry_points: Vec<EntryInfo>,
    pub overrides: Vec<OverrideInfo>,
    /// Layout of the uniform named `params`, if the shader declares one.
    pub params: Option<ParamsLayout>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct EntryInfo {
    pub name: String,
    pub workgroup_size: [u32; 3],
    /// Only the bindings this entry point uses.
    pub bindings: Vec<BindingInfo>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct BindingInfo {
    pub name: String,
    pub group: u32,
    pub binding: u32,
    pub kind: BindingKind,
    /// Where the variable is declared (original file and line).
    pub location: Location,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleType {
    Float,
    Uint,
    Sint,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StorageAccess {
    Read,
    Write,
    ReadWrite,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BindingKind {
    /// `texture_2d<T>`: read with textureLoad.
    SampledTexture { sample: SampleType },
    /// `texture_storage_2d<format, access>`.
    StorageTexture { format: TexFormat, access: StorageAccess },
    /// `var<uniform>` of `size` bytes (type name for messages).
    Uniform { type_name: String, size: u32 },
    /// `var<storage, read>` (read_only) or `read_write`.
    Storage { read_only: bool },
}

impl BindingKind {
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
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScalarType {
    F32,
    U32,
    I32,
    Bool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ParamMember {
    pub name: String,
    pub offset: u32,
    pub scalar: ScalarType,
    /// 1 for a scalar, 2..4 for a vector.
    pub components: u32,
    /// The range values must keep to (`// ui: MIN..MAX limit`), with the
    /// source line that declares it.
    pub limit: Option<(f64, f64)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ParamsLayout {
    pub size: u32,
    pub members: Vec<ParamMember>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct OverrideInfo {
    pub name: String,
    pub scalar: ScalarType,
    pub has_default: bool,
}
