//! A scene file moved and scaled as text, as a user would edit it: every
//! position (camera, vertices, centres, mesh translations, point lights,
//! orbit centres) becomes `p * scale + offset`, radii, orbit radii, mesh
//! scales and velocities are times `scale`, point-light intensities times
//! `scale^2` (so the irradiance they give at scaled distances is the same),
//! radiance and colours unchanged. Numbers are written back in shortest
//! round-trip form, so the file says exactly the f64 that was computed.
//! Used by tests/place_scale.rs and examples/place_scale.rs.

/// How a field's numbers change.
#[derive(Clone, Copy)]
enum Kind {
    /// Positions: scaled, then the offset added by component (x, y, z, x, ...).
    Point,
    /// Times a factor, no offset.
    Times(f64),
}

/// `text` with every field the scene format knows moved by `offset` and
/// scaled by `scale` about the origin.
pub fn transformed(text: &str, scale: f64, offset: [f64; 3]) -> String {
    // (key, the character that ends its value, kind); a scalar's value
    // also ends at `)`.
    let fields: [(&str, char, Kind); 9] = [
        ("position: (", ')', Kind::Point),
        ("target: (", ')', Kind::Point),
        ("vertices: [", ']', Kind::Point),
        ("center: (", ')', Kind::Point),
        ("translate: (", ')', Kind::Point),
        ("velocity: (", ')', Kind::Times(scale)),
        ("intensity: (", ')', Kind::Times(scale * scale)),
        ("radius: ", ',', Kind::Times(scale)),
        ("scale: ", ',', Kind::Times(scale)),
    ];
    let mut lines = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("//") {
            lines.push(line.to_string());
            continue;
        }
        let mut out = String::new();
        let mut rest = line;
        // Fields in the order they appear on the line (a line may hold a
        // centre and a radius, or an orbit inside a light).
        loop {
            let next = fields
                .iter()
                .filter_map(|&(key, close, kind)| rest.find(key).map(|i| (i, key, close, kind)))
                .min_by_key(|f| f.0);
            let Some((i, key, close, kind)) = next else { break };
            let start = i + key.len();
            let scalar = close == ',';
            let end = start + rest[start..].find(|c| c == close || (scalar && c == ')')).expect("field end");
            out.push_str(&rest[..start]);
            out.push_str(&numbers(&rest[start..end], kind, scale, offset));
            rest = &rest[end..];
        }
        out.push_str(rest);
        lines.push(out);
    }
    lines.join("\n")
}

/// The numbers of one field's text, transformed; everything else kept.
fn numbers(seg: &str, kind: Kind, scale: f64, offset: [f64; 3]) -> String {
    let mut out = String::new();
    let mut num = String::new();
    let mut index = 0;
    let mut flush = |num: &mut String, out: &mut String| {
        if num.is_empty() {
            return;
        }
        let v: f64 = num.parse().unwrap_or_else(|_| panic!("`{num}` is not a number"));
        let v = match kind {
            Kind::Point => v * scale + offset[index % 3],
            Kind::Times(k) => v * k,
        };
        index += 1;
        out.push_str(&format!("{v:e}"));
        num.clear();
    };
    for c in seg.chars() {
        if c.is_ascii_digit() || c == '.' || c == '-' || c == 'e' || c == '+' {
            num.push(c);
        } else {
            flush(&mut num, &mut out);
            out.push(c);
        }
    }
    flush(&mut num, &mut out);
    out
}
