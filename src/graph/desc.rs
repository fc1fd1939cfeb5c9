//! The RON schema of a frame graph (README, "The frame graph"). A graph file knows
//! nothing about wgpu: resources, passes and the output.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::error::{ron_error, UserError};
pub use crate::format::TexFormat;
use crate::scene::Feature;

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameGraph {
    pub name: String,
    #[serde(default)]
    pub resources: BTreeMap<String, ResourceDesc>,
    pub passes: Vec<PassDesc>,
    pub output: String,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
pub enum ResourceDesc {
    Texture(TextureDesc),
}

/// `Texture(format: .., size: .., history: ..)` (RON's unwrapped newtype).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDesc {
    pub format: TexFormat,
    #[serde(default)]
    pub size: SizeDesc,
    /// Survives across frames (read at version 0 = last frame's result).
    #[serde(default)]
    pub history: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Default)]
pub enum SizeDesc {
    /// The render size.
    #[default]
    Screen,
    /// The render size times a factor (at least 1x1).
    Scaled(f32),
    Fixed(u32, u32),
}

impl SizeDesc {
    pub fn resolve(self, screen: (u32, u32)) -> (u32, u32) {
        match self {
            SizeDesc::Screen => screen,
            SizeDesc::Scaled(s) => (
                ((screen.0 as f32 * s).round() as u32).max(1),
                ((screen.1 as f32 * s).round() as u32).max(1),
            ),
            SizeDesc::Fixed(w, h) => (w.max(1), h.max(1)),
        }
    }
}

/// A value for one member of a pass's `params` uniform.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum ParamValue {
    Bool(bool),
    Int(i64),
    Float(f64),
    Vector(Vec<f64>),
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
#[serde(rename = "Pass")]
pub struct PassDesc {
    pub name: String,
    /// File name under `shaders/`.
    pub shader: String,
    /// Compute entry point; the shader's only one when omitted.
    #[serde(default)]
    pub entry: Option<String>,
    /// Members of the shader's `params` uniform, by name.
    #[serde(default, deserialize_with = "named_map")]
    pub params: BTreeMap<String, ParamValue>,
    /// WGSL `override` constants, by name.
    #[serde(default, deserialize_with = "named_map")]
    pub constants: BTreeMap<String, f64>,
    /// Scene features this pass needs; culled when the scene lacks one.
    #[serde(default)]
    pub requires: Vec<Feature>,
    /// Shader variable name -> graph resource name, for names that differ.
    #[serde(default, deserialize_with = "named_map")]
    pub bind: BTreeMap<String, String>,
}

/// A map key written bare (`{ samples: 1 }`, as the shipped graphs write them) or quoted
/// (`{ "src": "lit" }`). Untagged enums go through serde's buffered content,
/// for which RON hands bare identifiers over as strings.
#[derive(Deserialize, PartialEq, Eq, PartialOrd, Ord)]
#[serde(untagged)]
enum Name {
    Name(String),
}

fn named_map<'de, D, V>(d: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: serde::Deserializer<'de>,
    V: Deserialize<'de>,
{
    let map: BTreeMap<Name, V> = BTreeMap::deserialize(d)?;
    Ok(map.into_iter().map(|(Name::Name(k), v)| (k, v)).collect())
}

impl FrameGraph {
    pub fn parse(text: &str, path: &Path) -> Result<FrameGraph, UserError> {
        // A UTF-8 byte order mark is not RON; editors may write one.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let graph: FrameGraph = ron::Options::default()
            .with_default_extension(
                ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES | ron::extensions::Extensions::IMPLICIT_SOME,
            )
            .from_str(text)
            .map_err(|e| ron_error(path, &e))?;
        graph.check_sizes(text, path)?;
        Ok(graph)
    }

    /// Texture sizes RON accepts but no texture has: a scale that is not a
    /// positive finite number (NaN, inf, 0, negative) or that makes a side
    /// of a 16384-pixel screen overflow, and fixed sides of 0.
    fn check_sizes(&self, text: &str, path: &Path) -> Result<(), UserError> {
        for (name, r) in &self.resources {
            let ResourceDesc::Texture(t) = r;
            let bad = match t.size {
                SizeDesc::Scaled(s) if !(s.is_finite() && s > 0.0 && s <= 16.0) => {
                    Some(format!("`Scaled({s})`: the scale must be a finite number in (0, 16]"))
                }
                SizeDesc::Fixed(w, h) if w == 0 || h == 0 => Some(format!("`Fixed({w}, {h})` is empty: both sides must be at least 1")),
                _ => None,
            };
            if let Some(message) = bad {
                let line = crate::error::line_of(text, &format!("\"{name}\"")).unwrap_or(0);
                return Err(UserError::at(crate::error::Location::at(path, line, 0), format!("resource `{name}`: {message}")));
            }
        }
        Ok(())
    }

    pub fn load(path: &Path) -> Result<FrameGraph, UserError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| UserError::in_file(path, format!("cannot read the graph file: {e}")))?;
        Self::parse(&text, path)
    }
}
