//! Machine profiles (`passes/machines.ron`): which graph, resolution scale,
//! frame-time target and param overrides an adapter gets. `--graph`
//! overrides the profile; `glint machines` says which profile applies and
//! why; the viewer switches profiles at run time.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::{ron_error, UserError};
use crate::gpu::Gpu;
use crate::graph::desc::ParamValue;
use crate::graph::edit::ParamSet;

/// An adapter's kind, as a profile matches it (`wgpu::DeviceType` in RON).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
pub enum DeviceType {
    /// A software rasteriser (lavapipe, llvmpipe).
    Cpu,
    /// A GPU sharing memory with the CPU.
    IntegratedGpu,
    /// A GPU with its own memory.
    DiscreteGpu,
    /// A virtualised GPU.
    VirtualGpu,
    /// Anything else.
    Other,
}

impl DeviceType {
    /// The profile kind of a wgpu device type.
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

/// One machine profile: which adapters it matches and what they run.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    /// Shown in messages and the viewer's profile list.
    pub name: String,
    /// Matches only adapters of this kind (any when omitted).
    pub device_type: Option<DeviceType>,
    /// Matches only adapters whose name contains this, ignoring case (any when omitted).
    pub name_contains: Option<String>,
    /// Graph file, relative to the profiles file.
    pub graph: String,
    /// The render size is the requested size times this (the viewer and
    /// `render` upscale the result to the requested size).
    pub resolution_scale: f32,
    /// Frame-time target in milliseconds, which the PID steers toward.
    pub target_ms: f32,
    /// Param overrides, `"pass.param": value`, applied as `--set` would
    /// (a `--set` on the command line wins).
    #[serde(default)]
    pub params: BTreeMap<String, ParamValue>,
    /// Where the profiles file is (to resolve `graph`); set on load.
    #[serde(skip)]
    pub dir: PathBuf,
}

/// A profiles file: the profiles in order, first match wins.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Machines {
    /// Tried in order.
    pub profiles: Vec<Profile>,
    /// Taken when no profile matches.
    pub default: Profile,
}

impl Machines {
    /// Load and check a profiles file (scales in (0, 4], positive targets, `pass.param` keys).
    pub fn load(path: &Path) -> Result<Machines, UserError> {
        let text = crate::error::read_user_text(path, "machine profiles")?;
        let mut m: Machines = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
            .from_str(&text)
            .map_err(|e| ron_error(path, &e))?;
        let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        for p in m.profiles.iter_mut().chain([&mut m.default]) {
            p.dir = dir.clone();
            if !(p.resolution_scale.is_finite() && p.resolution_scale > 0.0 && p.resolution_scale <= 4.0) {
                return Err(UserError::in_file(path, format!("profile `{}`: resolution_scale {} must be in (0, 4]", p.name, p.resolution_scale)));
            }
            if !(p.target_ms.is_finite() && p.target_ms > 0.0) {
                return Err(UserError::in_file(path, format!("profile `{}`: target_ms {} must be a positive number", p.name, p.target_ms)));
            }
            param_sets(p).map_err(|e| UserError::in_file(path, e.message))?;
        }
        Ok(m)
    }

    /// The first profile matching the adapter, else the default.
    pub fn pick(&self, device_type: DeviceType, adapter_name: &str) -> &Profile {
        self.pick_index(device_type, adapter_name).map_or(&self.default, |i| &self.profiles[i])
    }

    /// The index of the first matching profile (None: the default).
    pub fn pick_index(&self, device_type: DeviceType, adapter_name: &str) -> Option<usize> {
        let name = adapter_name.to_lowercase();
        self.profiles.iter().position(|p| {
            p.device_type.is_none_or(|t| t == device_type) && p.name_contains.as_ref().is_none_or(|s| name.contains(&s.to_lowercase()))
        })
    }

    /// Why profile `i` matched, in words.
    pub fn rule(&self, i: Option<usize>) -> String {
        let Some(p) = i.and_then(|i| self.profiles.get(i)) else { return "no profile matched: the default".into() };
        let mut why = Vec::new();
        if let Some(t) = p.device_type {
            why.push(format!("device type {t:?}"));
        }
        if let Some(s) = &p.name_contains {
            why.push(format!("name contains \"{s}\""));
        }
        if why.is_empty() { "matches any adapter".into() } else { format!("the first profile whose {} matches", why.join(" and ")) }
    }

    /// The shipped profiles file: `passes/machines.ron` under the current
    /// folder, else the one this crate was built from.
    pub fn default_path() -> PathBuf {
        let here = Path::new("passes/machines.ron");
        if here.is_file() { here.to_path_buf() } else { Path::new(env!("CARGO_MANIFEST_DIR")).join("passes/machines.ron") }
    }
}

/// A profile's graph file.
pub fn profile_graph(p: &Profile) -> PathBuf {
    p.dir.join(&p.graph)
}

/// A profile's param overrides as `--set`s.
pub fn param_sets(p: &Profile) -> Result<Vec<ParamSet>, UserError> {
    p.params
        .iter()
        .map(|(k, v)| {
            let (pass, param) = k.split_once('.').filter(|(a, b)| !a.is_empty() && !b.is_empty()).ok_or_else(|| {
                UserError::new(format!("profile `{}`: param key `{k}` must be written \"pass.param\"", p.name))
            })?;
            Ok(ParamSet { pass: pass.to_string(), param: param.to_string(), value: v.clone() })
        })
        .collect()
}

/// `size` times a resolution scale, at least 1x1.
pub fn scale_size(size: (u32, u32), scale: f32) -> (u32, u32) {
    let s = |x: u32| ((x as f32 * scale).round() as u32).max(1);
    (s(size.0), s(size.1))
}

/// What a front end runs: the graph, and from the machine profile (unless
/// `--graph` was given) the frame-time target, param overrides and
/// resolution scale; plus the graphs and profiles a viewer may offer.
#[derive(Debug, Clone)]
pub struct Choice {
    /// The graph file to run.
    pub graph: PathBuf,
    /// Frame-time target in milliseconds (None with `--graph`).
    pub target_ms: Option<f64>,
    /// Param overrides from the profile, as `--set`s.
    pub params: Vec<ParamSet>,
    /// The render size is the requested size times this (1 with `--graph`).
    pub resolution_scale: f32,
    /// Every profile, the default last.
    pub profiles: Vec<Profile>,
    /// The profile the adapter matched (index into `profiles`), if any.
    pub matched: Option<usize>,
    /// Every graph file beside the profiles file.
    pub graphs: Vec<PathBuf>,
}

impl Choice {
    /// `size` at the resolution scale, at least 1x1.
    pub fn scaled(&self, size: (u32, u32)) -> (u32, u32) {
        scale_size(size, self.resolution_scale)
    }
}

/// `passes/bench-*.ron`: the benchmarks' graphs (`glint bench rays`),
/// whose outputs are ray records, not images: not offered for viewing.
fn is_benchmark(p: &Path) -> bool {
    p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with("bench-"))
}

/// Picks the graph for this adapter (see `Choice`).
pub fn choose(gpu: &Gpu, graph: Option<&Path>) -> Result<Choice, UserError> {
    let path = Machines::default_path();
    let m = Machines::load(&path)?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut graphs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|rd| rd.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|e| e == "ron") && p != &path && !is_benchmark(p)).collect())
        .unwrap_or_default();
    graphs.sort();
    let mut profiles = m.profiles.clone();
    profiles.push(m.default.clone());
    let index = m.pick_index(DeviceType::of(gpu.info.device_type), &gpu.info.name);
    let matched = Some(index.unwrap_or(profiles.len() - 1));
    if let Some(g) = graph {
        return Ok(Choice { graph: g.to_path_buf(), target_ms: None, params: vec![], resolution_scale: 1.0, profiles, matched, graphs });
    }
    let p = m.pick(DeviceType::of(gpu.info.device_type), &gpu.info.name);
    eprintln!("glint: machine profile `{}`: {} (target {} ms, resolution scale {})", p.name, p.graph, p.target_ms, p.resolution_scale);
    Ok(Choice {
        graph: profile_graph(p),
        target_ms: Some(f64::from(p.target_ms)),
        params: param_sets(p)?,
        resolution_scale: p.resolution_scale,
        profiles,
        matched,
        graphs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_profiles_parse_and_pick() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("passes/machines.ron");
        let m = Machines::load(&path).expect("machines.ron parses");
        let cpu = m.pick(DeviceType::Cpu, "llvmpipe (LLVM 15)");
        assert_eq!((cpu.name.as_str(), cpu.graph.as_str(), cpu.resolution_scale), ("cpu (lavapipe, llvmpipe)", "realtime.ron", 0.5));
        let gpu = m.pick(DeviceType::DiscreteGpu, "NVIDIA H100");
        assert_eq!((gpu.name.as_str(), gpu.graph.as_str(), gpu.resolution_scale), ("discrete gpu", "realtime.ron", 1.0));
        for p in m.profiles.iter().chain([&m.default]) {
            assert!(Path::new(env!("CARGO_MANIFEST_DIR")).join("passes").join(&p.graph).is_file(), "{} names a missing graph", p.name);
        }
        assert_eq!(m.pick(DeviceType::Other, "x").name, "default");
    }
}
