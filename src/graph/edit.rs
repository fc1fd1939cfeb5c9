//! Edits applied to a parsed graph before it is compiled, so a user (or a
//! benchmark) can try a variant without writing another RON file:
//! `--set pass.param=value` overrides a param, `--skip pass` removes a pass
//! (whatever then feeds nothing is culled as unreachable), `--stop-after
//! pass` drops every pass after it in file order (to view a pass's own
//! output of a resource that later passes overwrite).

use crate::graph::desc::{FrameGraph, ParamValue, ProbeMode, MAX_PROBE_LEVEL};

/// One `pass.param=value` override.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamSet {
    /// The pass's name (`probes` for the graph's probe grid).
    pub pass: String,
    /// The param (a member of the pass's `params`, or `mode`, `level`, `padding`
    /// of the probes).
    pub param: String,
    /// The value to set.
    pub value: ParamValue,
}

impl std::str::FromStr for ParamSet {
    type Err = String;

    /// `pass.param=value`: value is `true`/`false`, an integer, a float or
    /// comma-separated floats (a vector).
    fn from_str(s: &str) -> Result<Self, String> {
        let (lhs, value) = s.split_once('=').ok_or_else(|| format!("`{s}`: expected pass.param=value"))?;
        let (pass, param) = lhs.split_once('.').ok_or_else(|| format!("`{s}`: expected pass.param=value"))?;
        if pass.is_empty() || param.is_empty() {
            return Err(format!("`{s}`: expected pass.param=value"));
        }
        let (pass, param, value) = (pass.trim(), param.trim(), value.trim());
        // The probe mode is a name: thesis is 0, ddgi 1.
        let value = match (pass, param, value.to_ascii_lowercase().as_str()) {
            (PROBES, "mode", "thesis") => ParamValue::Int(0),
            (PROBES, "mode", "ddgi") => ParamValue::Int(1),
            (PROBES, "mode", _) => return Err(format!("`{s}`: the probe mode is `thesis` or `ddgi`")),
            _ => parse_value(value)?,
        };
        Ok(ParamSet { pass: pass.to_string(), param: param.to_string(), value })
    }
}

fn parse_value(v: &str) -> Result<ParamValue, String> {
    match v {
        "true" => return Ok(ParamValue::Bool(true)),
        "false" => return Ok(ParamValue::Bool(false)),
        _ => {}
    }
    if let Ok(i) = v.parse::<i64>() {
        return Ok(ParamValue::Int(i));
    }
    if v.contains(',') {
        let parts: Result<Vec<f64>, _> = v.split(',').map(|p| p.trim().parse::<f64>()).collect();
        return parts.map(ParamValue::Vector).map_err(|_| format!("`{v}` is not a number list"));
    }
    match v.parse::<f64>() {
        Ok(f) if f.is_finite() => Ok(ParamValue::Float(f)),
        _ => Err(format!("`{v}` is not a finite number, a bool or a number list")),
    }
}

/// The edits of `CompileOptions`; empty by default.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GraphEdits {
    /// `--set`: param overrides, in order.
    pub set: Vec<ParamSet>,
    /// `--skip`: passes to remove.
    pub skip: Vec<String>,
    /// `--stop-after`: the last pass kept, in file order.
    pub stop_after: Option<String>,
}

impl GraphEdits {
    /// Whether there is nothing to apply.
    pub fn is_empty(&self) -> bool {
        self.set.is_empty() && self.skip.is_empty() && self.stop_after.is_none()
    }

    /// Applies the edits to a copy of `desc`. Unknown passes are errors
    /// naming the passes that exist; unknown params are caught by compile
    /// (it checks params against the shader's uniform).
    pub fn apply(&self, desc: &FrameGraph) -> Result<FrameGraph, String> {
        let mut g = desc.clone();
        let known = || pass_list(desc);
        for s in self.set.iter().filter(|s| s.pass == PROBES) {
            set_probes(&mut g, s)?;
        }
        for s in self.set.iter().filter(|s| s.pass != PROBES) {
            let pass = g
                .passes
                .iter_mut()
                .find(|p| p.name == s.pass)
                .ok_or_else(|| format!("--set {}.{}: no pass `{}`; passes: {}", s.pass, s.param, s.pass, known()))?;
            pass.params.insert(s.param.clone(), s.value.clone());
        }
        if let Some(last) = &self.stop_after {
            let i = g
                .passes
                .iter()
                .position(|p| &p.name == last)
                .ok_or_else(|| format!("--stop-after {last}: no such pass; passes: {}", known()))?;
            g.passes.truncate(i + 1);
        }
        for name in &self.skip {
            if !desc.passes.iter().any(|p| &p.name == name) {
                return Err(format!("--skip {name}: no such pass; passes: {}", known()));
            }
            g.passes.retain(|p| &p.name != name);
        }
        Ok(g)
    }
}

/// `--set probes.X=V` edits the graph's probe grid, not a pass.
const PROBES: &str = "probes";

fn set_probes(g: &mut FrameGraph, s: &ParamSet) -> Result<(), String> {
    let what = format!("--set probes.{}", s.param);
    let Some(p) = &mut g.probes else {
        return Err(format!("{what}: graph `{}` has no `probes` grid", g.name));
    };
    let bad = || format!("{what}: `{:?}` is not a valid value", s.value);
    match (s.param.as_str(), &s.value) {
        ("mode", ParamValue::Int(0)) => p.mode = ProbeMode::Thesis,
        ("mode", ParamValue::Int(1)) => p.mode = ProbeMode::Ddgi,
        ("level", ParamValue::Int(l)) if (1..=i64::from(MAX_PROBE_LEVEL)).contains(l) => p.level = *l as u32,
        ("level", _) => return Err(format!("{what}: the level is an integer in 1..={MAX_PROBE_LEVEL}")),
        ("padding", ParamValue::Float(f)) if (0.0..0.5).contains(f) => p.padding = *f as f32,
        ("padding", ParamValue::Int(0)) => p.padding = 0.0,
        ("padding", _) => return Err(format!("{what}: the padding is a fraction in [0, 0.5)")),
        ("mode", _) => return Err(bad()),
        (other, _) => return Err(format!("--set probes.{other}: the probe grid has mode, level and padding")),
    }
    Ok(())
}

fn pass_list(desc: &FrameGraph) -> String {
    desc.passes.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_param_sets() {
        let s: ParamSet = "accumulate.mode=0".parse().unwrap();
        assert_eq!((s.pass.as_str(), s.param.as_str(), s.value), ("accumulate", "mode", ParamValue::Int(0)));
        let s: ParamSet = "blur_h.sigma=2.5".parse().unwrap();
        assert_eq!(s.value, ParamValue::Float(2.5));
        let s: ParamSet = "p.v=1,2,3".parse().unwrap();
        assert_eq!(s.value, ParamValue::Vector(vec![1.0, 2.0, 3.0]));
        let s: ParamSet = "p.b=true".parse().unwrap();
        assert_eq!(s.value, ParamValue::Bool(true));
        for bad in ["mode=1", "accumulate.mode", ".x=1", "a.=1", "a.b=nan", "a.b=inf", "a.b=x", "a.b=1,y"] {
            assert!(bad.parse::<ParamSet>().is_err(), "{bad} should not parse");
        }
    }
}
