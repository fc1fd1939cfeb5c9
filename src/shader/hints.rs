//! How a pass's params are shown and bounded: read from `// ui:` annotations on
//! the members of the shader's `Params` struct (naga drops comments, so the
//! source text is read). The convention, documented in docs/viewer.md
//! ("Params in the UI"):
//!
//! ```wgsl
//! struct Params {
//!     samples: u32,      // ui: 1..64 "samples per light"
//!     sigma: f32,        // ui: 0.1..16 log
//!     reuse: u32,        // ui: bool "screen-space reuse"
//!     tint: vec3f,       // ui: color
//! }
//! ```
//!
//! `MIN..MAX` gives a slider (`log` makes it logarithmic), `bool` a
//! checkbox for a u32, `color` a colour picker for a vec3f; a quoted string
//! is the label. A member without an annotation gets a drag value.
//! `limit` makes the range binding: values outside it are refused by
//! compile and `set_param` (loop counts: a driver bounds the loop
//! iterations of one invocation, lavapipe at 65535 in all).

use std::collections::BTreeMap;

/// One member's `// ui:` annotation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Hint {
    /// `MIN..MAX`: a slider's range.
    pub range: Option<(f64, f64)>,
    /// `log`: the slider is logarithmic.
    pub log: bool,
    /// `bool`: a u32 shown as a checkbox.
    pub checkbox: bool,
    /// `color`: a vec3f shown as a colour picker.
    pub color: bool,
    /// The range is enforced, not just the slider's.
    pub limit: bool,
    /// A quoted string: the label shown instead of the member's name.
    pub label: Option<String>,
}

/// Parses one annotation (the text after `ui:`). None when it says nothing
/// this convention knows.
pub fn parse_hint(text: &str) -> Option<Hint> {
    let mut hint = Hint::default();
    let mut rest = text.trim().to_string();
    if let (Some(a), Some(b)) = (rest.find('"'), rest.rfind('"')) {
        if b > a {
            hint.label = Some(rest[a + 1..b].to_string());
            rest.replace_range(a..=b, "");
        }
    }
    let mut known = hint.label.is_some();
    for word in rest.split_whitespace() {
        match word {
            "log" => hint.log = true,
            "bool" => hint.checkbox = true,
            "color" | "colour" => hint.color = true,
            "limit" => hint.limit = true,
            w => {
                let (lo, hi) = w.split_once("..")?;
                let (lo, hi): (f64, f64) = (lo.parse().ok()?, hi.parse().ok()?);
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return None;
                }
                hint.range = Some((lo, hi));
            }
        }
        known = true;
    }
    known.then_some(hint)
}

/// The hints of every member of `struct Params` in a shader's (expanded)
/// source, by member name.
pub fn params_hints(source: &str) -> BTreeMap<String, Hint> {
    let mut hints = BTreeMap::new();
    let mut inside = false;
    for line in source.lines() {
        let t = line.trim();
        if !inside {
            inside = t.starts_with("struct Params") && t.ends_with('{');
            continue;
        }
        if t.starts_with('}') {
            break;
        }
        let Some((code, comment)) = t.split_once("//") else { continue };
        let Some(annotation) = comment.trim().strip_prefix("ui:") else { continue };
        let Some((name, _)) = code.split_once(':') else { continue };
        if let Some(h) = parse_hint(annotation) {
            hints.insert(name.trim().to_string(), h);
        }
    }
    hints
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_convention() {
        let src = "struct Other {\n  x: f32, // ui: 0..1\n}\nstruct Params {\n    samples: u32,      // ui: 1..64 \"samples per light\"\n    sigma: f32, // ui: 0.1..16 log\n    reuse: u32, // ui: bool\n    tint: vec3f, // ui: color \"tint\"\n    plain: f32,\n    odd: f32, // ui: 3..1\n    note: f32, // not a hint\n}\n";
        let h = params_hints(src);
        assert_eq!(h.len(), 4, "{h:?}");
        assert_eq!(h["samples"], Hint { range: Some((1.0, 64.0)), label: Some("samples per light".into()), ..Hint::default() });
        assert_eq!(h["sigma"], Hint { range: Some((0.1, 16.0)), log: true, ..Hint::default() });
        assert!(h["reuse"].checkbox);
        assert!(h["tint"].color && h["tint"].label.as_deref() == Some("tint"));
        assert!(!h.contains_key("odd") && !h.contains_key("plain") && !h.contains_key("x"));
        let limited = parse_hint("1..64 limit \"samples\"").unwrap();
        assert!(limited.limit && limited.range == Some((1.0, 64.0)));
    }
}
