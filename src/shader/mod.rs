//! Shaders: WGSL loading with `#import`, naga validation with errors mapped
//! to the original files, and reflection into `ShaderInfo`.

pub mod budget;
pub mod hints;
pub mod reflect;
pub mod source;
pub mod specialise;
pub mod validation_words;

#[cfg(test)]
mod validation_tests;

use std::path::Path;

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

use crate::error::UserError;
use crate::format::TexFormat;
pub use reflect::*;
pub use source::ShaderSource;

/// A parsed, validated and reflected shader.
#[derive(Debug, Clone)]
pub struct Shader {
    /// The expanded source, with its map back to the original files.
    pub source: ShaderSource,
    /// naga's IR of it.
    pub module: naga::Module,
    /// What naga's validator found out (expression types, global uses).
    pub module_info: ModuleInfo,
    /// The reflection the frame graph works on.
    pub info: ShaderInfo,
}

/// Loads `dir/name`, expands imports, parses, validates and reflects it.
pub fn load(dir: &Path, name: &str) -> Result<Shader, UserError> {
    let source = source::load(dir, name)?;
    from_source(source)
}

/// Parses, validates and reflects already-expanded source.
pub fn from_source(source: ShaderSource) -> Result<Shader, UserError> {
    let module = naga::front::wgsl::parse_str(&source.text).map_err(|e| {
        let loc = e
            .labels()
            .next()
            .map(|(span, _)| source.span_location(span))
            .or_else(|| e.location(&source.text).map(|l| source.original(l.line_number as usize, l.line_position as usize)))
            .unwrap_or_else(|| source.original(0, 0));
        let mut msg = format!("WGSL error: {}", e.message());
        for (_, label) in e.labels().filter(|(_, l)| !l.is_empty()) {
            msg.push_str(&format!("; {label}"));
        }
        for note in e.notes() {
            msg.push_str(&format!("; note: {note}"));
        }
        UserError::at(loc, msg)
    })?;
    let module_info = Validator::new(ValidationFlags::all(), capabilities())
        .validate(&module)
        .map_err(|e| {
            let worded = validation_words::word(&module, &source.text, &e);
            UserError::at(source.span_location(worded.span), format!("WGSL validation error: {}", worded.message))
        })?;
    budget::check(&source, &module)?;
    let info = reflect_module(&source, &module, &module_info)?;
    Ok(Shader { source, module, module_info, info })
}

/// The capabilities our passes may use (all are available on lavapipe).
pub fn capabilities() -> Capabilities {
    Capabilities::SUBGROUP | Capabilities::SHADER_INT64
}

fn reflect_module(src: &ShaderSource, module: &naga::Module, info: &ModuleInfo) -> Result<ShaderInfo, UserError> {
    let mut entry_points = Vec::new();
    for (index, ep) in module.entry_points.iter().enumerate() {
        if ep.stage != naga::ShaderStage::Compute {
            continue;
        }
        let uses = info.get_entry_point(index);
        let mut bindings = Vec::new();
        for (handle, var) in module.global_variables.iter() {
            let Some(binding) = &var.binding else { continue };
            if uses[handle].is_empty() {
                continue;
            }
            let location = src.span_location(module.global_variables.get_span(handle));
            let name = var.name.clone().unwrap_or_default();
            let kind = binding_kind(module, var).map_err(|m| {
                UserError::at(location.clone(), format!("binding `{name}`: {m}"))
            })?;
            bindings.push(BindingInfo { name, group: binding.group, binding: binding.binding, kind, location });
        }
        entry_points.push(EntryInfo { name: ep.name.clone(), workgroup_size: ep.workgroup_size, bindings });
    }
    let overrides = module
        .overrides
        .iter()
        .filter_map(|(_, o)| {
            let name = o.name.clone()?;
            let scalar = scalar_of(&module.types[o.ty].inner)?;
            Some(OverrideInfo { name, scalar, has_default: o.init.is_some() })
        })
        .collect();
    let params = params_layout(src, module)?;
    Ok(ShaderInfo { name: src.name.clone(), entry_points, overrides, params })
}

fn binding_kind(module: &naga::Module, var: &naga::GlobalVariable) -> Result<BindingKind, String> {
    use naga::{AddressSpace, ImageClass, ImageDimension, TypeInner};
    let ty = &module.types[var.ty];
    match var.space {
        AddressSpace::Uniform => Ok(BindingKind::Uniform {
            type_name: ty.name.clone().unwrap_or_else(|| "?".into()),
            size: ty.inner.size(module.to_ctx()),
        }),
        AddressSpace::Storage { access } => Ok(BindingKind::Storage {
            read_only: !access.contains(naga::StorageAccess::STORE),
        }),
        AddressSpace::Handle => match &ty.inner {
            TypeInner::Image { dim: ImageDimension::D2, arrayed: false, class } => match class {
                ImageClass::Sampled { kind, multi: false } => Ok(BindingKind::SampledTexture {
                    sample: match kind {
                        naga::ScalarKind::Uint => SampleType::Uint,
                        naga::ScalarKind::Sint => SampleType::Sint,
                        _ => SampleType::Float,
                    },
                }),
                ImageClass::Storage { format, access } => {
                    let format = tex_format(*format)
                        .ok_or_else(|| format!("storage format {format:?} is not supported by glint graphs"))?;
                    let read = access.contains(naga::StorageAccess::LOAD);
                    let write = access.contains(naga::StorageAccess::STORE);
                    let access = match (read, write) {
                        (true, true) => StorageAccess::ReadWrite,
                        (true, false) => StorageAccess::Read,
                        _ => StorageAccess::Write,
                    };
                    Ok(BindingKind::StorageTexture { format, access })
                }
                _ => Err("only texture_2d<T> and texture_storage_2d are supported".into()),
            },
            TypeInner::Image { dim: ImageDimension::D2, arrayed: true, class: ImageClass::Sampled { kind: naga::ScalarKind::Float, multi: false } } => {
                Ok(BindingKind::SampledTextureArray)
            }
            TypeInner::Sampler { comparison: false } => Ok(BindingKind::Sampler),
            _ => Err("only 2D textures are supported (texture_2d_array<f32> and sampler for the engine's scene textures alone)".into()),
        },
        other => Err(format!("address space {other:?} cannot be bound")),
    }
}

/// The graph texture format of a storage texture format; None for the
/// formats glint graphs do not support.
pub fn tex_format(f: naga::StorageFormat) -> Option<TexFormat> {
    use naga::StorageFormat as S;
    Some(match f {
        S::R32Float => TexFormat::R32Float,
        S::Rg32Float => TexFormat::Rg32Float,
        S::Rgba32Float => TexFormat::Rgba32Float,
        S::Rgba16Float => TexFormat::Rgba16Float,
        S::R32Uint => TexFormat::R32Uint,
        S::Rg32Uint => TexFormat::Rg32Uint,
        S::Rgba32Uint => TexFormat::Rgba32Uint,
        S::Rgba8Unorm => TexFormat::Rgba8Unorm,
        _ => return None,
    })
}

fn scalar_of(inner: &naga::TypeInner) -> Option<ScalarType> {
    let s = match inner {
        naga::TypeInner::Scalar(s) => s,
        naga::TypeInner::Vector { scalar, .. } => scalar,
        _ => return None,
    };
    if s.width != 4 && s.kind != naga::ScalarKind::Bool {
        return None;
    }
    Some(match s.kind {
        naga::ScalarKind::Float => ScalarType::F32,
        naga::ScalarKind::Uint => ScalarType::U32,
        naga::ScalarKind::Sint => ScalarType::I32,
        naga::ScalarKind::Bool => ScalarType::Bool,
        _ => return None,
    })
}

fn params_layout(src: &ShaderSource, module: &naga::Module) -> Result<Option<ParamsLayout>, UserError> {
    let Some((handle, var)) = module
        .global_variables
        .iter()
        .find(|(_, v)| v.name.as_deref() == Some("params") && v.binding.is_some())
    else {
        return Ok(None);
    };
    let location = src.span_location(module.global_variables.get_span(handle));
    let ty = &module.types[var.ty];
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        return Err(UserError::at(location, "`params` must be a var<uniform> of a struct type"));
    };
    if var.space != naga::AddressSpace::Uniform {
        return Err(UserError::at(location, "`params` must be declared var<uniform>"));
    }
    let hints = hints::params_hints(&src.text);
    let mut out = Vec::new();
    for m in members {
        let inner = &module.types[m.ty].inner;
        let components = match inner {
            naga::TypeInner::Scalar(_) => 1,
            naga::TypeInner::Vector { size, .. } => *size as u32,
            _ => 0,
        };
        let scalar = scalar_of(inner).filter(|s| *s != ScalarType::Bool && components > 0).ok_or_else(|| {
            UserError::at(
                location.clone(),
                format!("params member `{}` must be f32, u32, i32 or a vector of them", m.name.as_deref().unwrap_or("?")),
            )
        })?;
        let name = m.name.clone().unwrap_or_default();
        let limit = hints.get(&name).filter(|h| h.limit).and_then(|h| h.range);
        out.push(ParamMember { name, offset: m.offset, scalar, components, limit });
    }
    Ok(Some(ParamsLayout { size: *span, members: out }))
}
