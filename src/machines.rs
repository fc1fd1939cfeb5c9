//! Machine profiles (`passes/machines.ron`): which graph, resolution scale
//! and frame-time target an adapter gets.

use std::path::Path;

use serde::Deserialize;

use crate::error::{ron_error, UserError};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
pub enum DeviceType {
    Cpu,
    IntegratedGpu,
    DiscreteGpu,
    VirtualGpu,
    Other,
}

impl DeviceType {
    pub fn of(t: wgpu::DeviceType) -> DeviceType {
        match t {
            wgpu::DeviceType::Cpu => DeviceType::Cpu,
            wgpu::DeviceType::IntegratedGpu => DeviceType::IntegratedGpu,
            wgpu::DeviceType::DiscreteGpu => DeviceType::DiscreteGpu,
            wgpu::DeviceType::VirtualGpu => DeviceType::VirtualGpu,
            wgpu::DeviceType::Other => DeviceType::Other,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    pub name: String,
    pub device_type: Option<DeviceType>,
    pub name_contains: Option<String>,
    /// Graph file, relative to the profiles file.
    pub graph: String,
    pub resolution_scale: f32,
    pub target_ms: f32,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Machines {
    pub profiles: Vec<Profile>,
    pub default: Profile,
}

impl Machines {
    pub fn load(path: &Path) -> Result<Machines, UserError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| UserError::in_file(path, format!("cannot read machine profiles: {e}")))?;
        ron::Options::default().from_str(&text).map_err(|e| ron_error(path, &e))
    }

    /// The first profile matching the adapter, else the default.
    pub fn pick(&self, device_type: DeviceType, adapter_name: &str) -> &Profile {
        let name = adapter_name.to_lowercase();
        self.profiles
            .iter()
            .find(|p| {
                p.device_type.is_none_or(|t| t == device_type)
                    && p.name_contains.as_ref().is_none_or(|s| name.contains(&s.to_lowercase()))
            })
            .unwrap_or(&self.default)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_profiles_parse_and_pick() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("passes/machines.ron");
        let m = Machines::load(&path).expect("machines.ron parses");
        assert_eq!(m.pick(DeviceType::Cpu, "llvmpipe (LLVM 15)").graph, "hybrid-point.ron");
        assert_eq!(m.pick(DeviceType::DiscreteGpu, "NVIDIA H100").graph, "hybrid.ron");
        for p in m.profiles.iter().chain([&m.default]) {
            assert!(Path::new(env!("CARGO_MANIFEST_DIR")).join("passes").join(&p.graph).is_file(), "{} names a missing graph", p.name);
        }
        assert_eq!(m.pick(DeviceType::Other, "x").name, "default");
    }
}
