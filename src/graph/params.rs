//! Packing a pass's `params` uniform from values by member name, against the
//! layout naga reflected from the shader. The compiler packs the graph
//! file's values (and `--set`) with it; the session packs a live
//! `set_param` with the same function, so both give the same errors and
//! the same bytes.

use std::collections::BTreeMap;

use crate::graph::desc::ParamValue;
use crate::shader::{ParamMember, ParamsLayout, ScalarType};

/// Why a set of values does not fit a `params` layout.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ParamError {
    /// A member of the struct has no value.
    Missing(String),
    /// A value names no member of the struct.
    Unknown(String),
    /// A value has the wrong number of components or does not fit the type.
    Bad(String),
}

impl ParamError {
    /// The message, whatever the kind.
    pub fn message(&self) -> &str {
        match self {
            ParamError::Missing(m) | ParamError::Unknown(m) | ParamError::Bad(m) => m,
        }
    }
}

/// A pass's params: the reflected layout, the values by name (graph file,
/// edits and live changes) and the packed bytes the uniform buffer holds.
#[derive(Debug, Clone, PartialEq)]
pub struct PassParams {
    /// The shader file (for messages).
    pub shader: String,
    /// The reflected layout of the `params` struct.
    pub layout: ParamsLayout,
    /// Every member's value, by name.
    pub values: BTreeMap<String, ParamValue>,
    /// The packed bytes of the uniform.
    pub bytes: Vec<u8>,
}

impl PassParams {
    /// Packs `values` into `layout`; every member needs a value.
    pub fn new(shader: &str, layout: &ParamsLayout, values: BTreeMap<String, ParamValue>) -> Result<PassParams, ParamError> {
        let bytes = pack(shader, layout, &values)?;
        Ok(PassParams { shader: shader.to_string(), layout: layout.clone(), values, bytes })
    }

    /// Checks and applies one value; on error nothing changes.
    pub fn set(&mut self, name: &str, value: ParamValue) -> Result<(), ParamError> {
        let mut values = self.values.clone();
        values.insert(name.to_string(), value);
        self.bytes = pack(&self.shader, &self.layout, &values)?;
        self.values = values;
        Ok(())
    }

    /// The layout of member `name`, if the struct has one.
    pub fn member(&self, name: &str) -> Option<&ParamMember> {
        self.layout.members.iter().find(|m| m.name == name)
    }
}

fn names<'a>(it: impl Iterator<Item = &'a String>) -> String {
    let v: Vec<&str> = it.map(String::as_str).collect();
    if v.is_empty() { "(none)".into() } else { v.join(", ") }
}

/// The uniform's bytes for `values`, checked member by member.
pub fn pack(shader: &str, layout: &ParamsLayout, values: &BTreeMap<String, ParamValue>) -> Result<Vec<u8>, ParamError> {
    for k in values.keys() {
        if !layout.members.iter().any(|m| &m.name == k) {
            return Err(ParamError::Unknown(format!(
                "unknown param `{k}`; {shader} takes: {}",
                names(layout.members.iter().map(|m| &m.name))
            )));
        }
    }
    let mut bytes = vec![0u8; layout.size as usize];
    for m in &layout.members {
        let value = values.get(&m.name).ok_or_else(|| {
            ParamError::Missing(format!("param `{}` is missing ({shader} needs every member of `params`)", m.name))
        })?;
        for (c, word) in encode(m, value)?.iter().enumerate() {
            let at = m.offset as usize + 4 * c;
            bytes[at..at + 4].copy_from_slice(word);
        }
    }
    Ok(bytes)
}

/// One member's value as little-endian words, one per component.
pub fn encode(m: &ParamMember, value: &ParamValue) -> Result<Vec<[u8; 4]>, ParamError> {
    let scalars: Vec<f64> = match value {
        ParamValue::Vector(v) => v.clone(),
        ParamValue::Int(i) => vec![*i as f64],
        ParamValue::Float(f) => vec![*f],
        ParamValue::Bool(b) => vec![f64::from(u8::from(*b))],
    };
    let is_int_literal = !matches!(value, ParamValue::Float(_));
    if scalars.len() != m.components as usize {
        return Err(ParamError::Bad(format!("param `{}` needs {} value(s), got {}", m.name, m.components, scalars.len())));
    }
    if let Some((lo, hi)) = m.limit {
        if let Some(x) = scalars.iter().find(|x| !(lo..=hi).contains(*x)) {
            return Err(ParamError::Bad(format!(
                "param `{}` = {x} is outside its limit {lo}..{hi} (a loop count: one invocation may only do so much; accumulate frames for more)",
                m.name
            )));
        }
    }
    scalars
        .iter()
        .map(|&x| match m.scalar {
            ScalarType::F32 if x.is_finite() => Ok((x as f32).to_le_bytes()),
            ScalarType::U32 if is_int_literal && x.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&x) => Ok((x as u32).to_le_bytes()),
            ScalarType::I32 if is_int_literal && x.fract() == 0.0 && (i32::MIN as f64..=i32::MAX as f64).contains(&x) => {
                Ok((x as i32).to_le_bytes())
            }
            _ => Err(ParamError::Bad(format!(
                "param `{}` is {:?} in the shader; {x} does not fit (write an integer for u32/i32)",
                m.name, m.scalar
            ))),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout() -> ParamsLayout {
        ParamsLayout {
            size: 32,
            members: vec![
                ParamMember { name: "gain".into(), offset: 0, scalar: ScalarType::F32, components: 1, limit: None },
                ParamMember { name: "count".into(), offset: 4, scalar: ScalarType::U32, components: 1, limit: None },
                ParamMember { name: "tint".into(), offset: 16, scalar: ScalarType::F32, components: 3, limit: None },
            ],
        }
    }

    fn values(list: &[(&str, ParamValue)]) -> BTreeMap<String, ParamValue> {
        list.iter().map(|(k, v)| (k.to_string(), v.clone())).collect()
    }

    #[test]
    fn packs_at_the_reflected_offsets() {
        let v = values(&[
            ("gain", ParamValue::Float(0.5)),
            ("count", ParamValue::Int(7)),
            ("tint", ParamValue::Vector(vec![1.0, 2.0, 3.0])),
        ]);
        let b = pack("s.wgsl", &layout(), &v).unwrap();
        assert_eq!(b.len(), 32);
        assert_eq!(&b[0..4], &0.5f32.to_le_bytes());
        assert_eq!(&b[4..8], &7u32.to_le_bytes());
        assert_eq!(&b[8..16], &[0; 8]);
        assert_eq!(&b[16..20], &1f32.to_le_bytes());
        assert_eq!(&b[24..28], &3f32.to_le_bytes());
    }

    #[test]
    fn set_checks_and_keeps_the_old_value_on_error() {
        let v = values(&[
            ("gain", ParamValue::Float(0.5)),
            ("count", ParamValue::Int(7)),
            ("tint", ParamValue::Vector(vec![1.0, 2.0, 3.0])),
        ]);
        let mut p = PassParams::new("s.wgsl", &layout(), v).unwrap();
        let before = p.clone();
        assert!(matches!(p.set("count", ParamValue::Float(1.5)), Err(ParamError::Bad(_))));
        assert!(matches!(p.set("count", ParamValue::Int(-1)), Err(ParamError::Bad(_))));
        assert!(matches!(p.set("tint", ParamValue::Float(1.0)), Err(ParamError::Bad(_))));
        assert!(matches!(p.set("nope", ParamValue::Int(1)), Err(ParamError::Unknown(m)) if m.contains("gain, count, tint")));
        assert_eq!(p, before);
        p.set("count", ParamValue::Int(9)).unwrap();
        assert_eq!(&p.bytes[4..8], &9u32.to_le_bytes());
        assert_eq!(p.values["count"], ParamValue::Int(9));
    }

    #[test]
    fn missing_member_is_an_error() {
        let v = values(&[("gain", ParamValue::Float(0.5))]);
        assert!(matches!(pack("s.wgsl", &layout(), &v), Err(ParamError::Missing(m)) if m.contains("`count`")));
    }

    #[test]
    fn limited_members_refuse_values_outside_their_range() {
        let m = ParamMember { name: "samples".into(), offset: 0, scalar: ScalarType::U32, components: 1, limit: Some((1.0, 64.0)) };
        assert!(encode(&m, &ParamValue::Int(64)).is_ok());
        for bad in [0, 65, 4_000_000_000] {
            let e = encode(&m, &ParamValue::Int(bad)).unwrap_err();
            assert!(e.message().contains("outside its limit 1..64"), "{}", e.message());
        }
    }
}
