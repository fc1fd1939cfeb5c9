//! Sweep files for `glint trade --sweep`: settings each graph is rendered
//! with, one curve per graph and setting (docs/trade.md, "Sweeps"):
//!
//! ```ron
//! Sweep(settings: [
//!     (name: "shipped"),
//!     (name: "2 light samples", params: { "lights_area.samples": 2 }),
//!     (name: "half size", resolution_scale: 0.5),
//!     (name: "PID at 40 ms", target_ms: 40.0),
//!     (name: "generic shaders", specialise: false),
//! ])
//! ```
//!
//! `params` are `--set`s and `skip` is `--skip` (a list of passes);
//! `resolution_scale` renders at that share of the
//! size and upscales (bilinear) before the error is measured;
//! `target_ms` drives the noise mask's threshold with the PID controller
//! on the measured frame time; `specialise: false` is `--no-specialise`
//! and `cull: false` is `--no-cull`.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::error::{ron_error, UserError};
use crate::graph::desc::ParamValue;
use crate::graph::edit::ParamSet;

/// A sweep file: the settings each graph is rendered with.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename = "Sweep", deny_unknown_fields)]
pub struct Sweep {
    /// At least one; names unique.
    pub settings: Vec<Setting>,
}

/// One setting of a sweep (see the module docs).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Setting {
    /// Labels the curve; unique within the sweep.
    pub name: String,
    /// Param overrides, `"pass.param": value` (`--set`).
    #[serde(default)]
    pub params: BTreeMap<String, ParamValue>,
    /// Passes removed (`--skip`); what then feeds nothing is culled.
    #[serde(default)]
    pub skip: Vec<String>,
    /// Render at this share of the size, in (0, 4] (1 when omitted).
    #[serde(default = "one")]
    pub resolution_scale: f32,
    /// Frame-time target in milliseconds for the PID (none when omitted).
    #[serde(default)]
    pub target_ms: Option<f32>,
    /// False: `--no-specialise` (true when omitted).
    #[serde(default = "yes")]
    pub specialise: bool,
    /// False: `--no-cull` (true when omitted).
    #[serde(default = "yes")]
    pub cull: bool,
}

fn one() -> f32 {
    1.0
}

fn yes() -> bool {
    true
}

impl Setting {
    /// The setting of a run without a sweep.
    pub fn plain() -> Setting {
        Setting { name: String::new(), params: BTreeMap::new(), skip: Vec::new(), resolution_scale: 1.0, target_ms: None, specialise: true, cull: true }
    }

    /// `params` as `--set`s.
    pub fn param_sets(&self) -> Vec<ParamSet> {
        self.params
            .iter()
            .filter_map(|(k, v)| k.split_once('.').map(|(pass, param)| ParamSet { pass: pass.into(), param: param.into(), value: v.clone() }))
            .collect()
    }

    /// The passes its params and skips name, which a graph must have for
    /// the setting to apply to it.
    pub fn passes(&self) -> Vec<&str> {
        self.params.keys().filter_map(|k| k.split_once('.').map(|(p, _)| p)).chain(self.skip.iter().map(String::as_str)).collect()
    }
}

impl Sweep {
    /// Read and check a sweep file.
    pub fn load(path: &Path) -> Result<Sweep, UserError> {
        let text = crate::error::read_user_text(path, "sweep")?;
        Sweep::parse(&text, path)
    }

    /// Parse and check sweep text; `path` is for messages.
    pub fn parse(text: &str, path: &Path) -> Result<Sweep, UserError> {
        let sweep: Sweep = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
            .from_str(text)
            .map_err(|e| ron_error(path, &e))?;
        sweep.check().map_err(|m| UserError::in_file(path, m))?;
        Ok(sweep)
    }

    fn check(&self) -> Result<(), String> {
        if self.settings.is_empty() {
            return Err("the sweep has no settings; give at least one".into());
        }
        for (i, s) in self.settings.iter().enumerate() {
            let at = format!("settings[{i}] (`{}`)", s.name);
            if s.name.trim().is_empty() {
                return Err(format!("settings[{i}]: the name is empty"));
            }
            if self.settings[..i].iter().any(|o| o.name == s.name) {
                return Err(format!("{at}: the name is used twice (it labels the curve)"));
            }
            if !(s.resolution_scale.is_finite() && s.resolution_scale > 0.0 && s.resolution_scale <= 4.0) {
                return Err(format!("{at}: resolution_scale {} must be in (0, 4]", s.resolution_scale));
            }
            if let Some(t) = s.target_ms {
                if !(t.is_finite() && t > 0.0) {
                    return Err(format!("{at}: target_ms {t} must be a positive number of milliseconds"));
                }
            }
            for k in s.params.keys() {
                if !k.split_once('.').is_some_and(|(p, q)| !p.is_empty() && !q.is_empty()) {
                    return Err(format!("{at}: param key `{k}` must be written \"pass.param\""));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Sweep, String> {
        Sweep::parse(text, Path::new("s.ron")).map_err(|e| e.to_string())
    }

    #[test]
    fn settings_parse_with_defaults() {
        let s = parse(
            r#"Sweep(settings: [
                (name: "shipped"),
                (name: "two", params: { "lights_area.samples": 2, "accumulate.clamp_max": 8.0 }, skip: ["refine"]),
                (name: "half", resolution_scale: 0.5, target_ms: 40.0, specialise: false, cull: false),
            ])"#,
        )
        .unwrap();
        assert_eq!(s.settings.len(), 3);
        assert_eq!(s.settings[0].resolution_scale, 1.0);
        assert!(s.settings[0].specialise && s.settings[0].target_ms.is_none());
        let sets = s.settings[1].param_sets();
        assert_eq!(sets.len(), 2);
        assert_eq!((sets[1].pass.as_str(), sets[1].param.as_str()), ("lights_area", "samples"));
        assert_eq!(s.settings[1].passes(), ["accumulate", "lights_area", "refine"]);
        assert_eq!(s.settings[1].skip, ["refine"]);
        assert_eq!((s.settings[2].resolution_scale, s.settings[2].target_ms, s.settings[2].specialise), (0.5, Some(40.0), false));
        assert!(s.settings[0].cull && !s.settings[2].cull);
    }

    #[test]
    fn bad_sweeps_name_the_problem() {
        let e = parse("Sweep(settings: [])").unwrap_err();
        assert!(e.contains("s.ron") && e.contains("no settings"), "{e}");
        let e = parse(r#"Sweep(settings: [(name: "a"), (name: "a")])"#).unwrap_err();
        assert!(e.contains("used twice"), "{e}");
        let e = parse(r#"Sweep(settings: [(name: "a", resolution_scale: 0.0)])"#).unwrap_err();
        assert!(e.contains("resolution_scale"), "{e}");
        let e = parse(r#"Sweep(settings: [(name: "a", target_ms: -1.0)])"#).unwrap_err();
        assert!(e.contains("target_ms"), "{e}");
        let e = parse(r#"Sweep(settings: [(name: "a", params: { "samples": 2 })])"#).unwrap_err();
        assert!(e.contains("pass.param"), "{e}");
        // A misspelt field: RON's error, with the line.
        let e = parse("Sweep(settings: [\n(name: \"a\", scale: 2.0)])").unwrap_err();
        assert!(e.contains("s.ron:2"), "{e}");
    }
}
