//! User-facing errors: every problem with user input (graph, scene, shader,
//! OBJ, command-line values) becomes one of these, printed as one paragraph
//! that names the file, the line where there is one, and what to fix.

use std::fmt;
use std::path::{Path, PathBuf};

/// A position in a user's file. `line` and `col` are 1-based; 0 means unknown.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file, as the user named it.
    pub file: PathBuf,
    /// 1-based line; 0 if unknown.
    pub line: usize,
    /// 1-based column; 0 if unknown.
    pub col: usize,
}

impl Location {
    /// The file alone, line and column unknown.
    pub fn file(file: impl Into<PathBuf>) -> Self {
        Location { file: file.into(), line: 0, col: 0 }
    }
    /// A line and column (1-based; 0 for unknown) in `file`.
    pub fn at(file: impl Into<PathBuf>, line: usize, col: usize) -> Self {
        Location { file: file.into(), line, col }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if self.line > 0 {
            write!(f, ":{}", self.line)?;
            if self.col > 0 {
                write!(f, ":{}", self.col)?;
            }
        }
        Ok(())
    }
}

/// An error caused by user input. `Display` gives `file:line:col: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UserError {
    /// Where the problem is, when it is in a file.
    pub location: Option<Location>,
    /// What is wrong and what to do about it.
    pub message: String,
}

impl UserError {
    /// An error with no location (a command-line value, say).
    pub fn new(message: impl Into<String>) -> Self {
        UserError { location: None, message: message.into() }
    }
    /// An error at `location`.
    pub fn at(location: Location, message: impl Into<String>) -> Self {
        UserError { location: Some(location), message: message.into() }
    }
    /// An error in `file`, line unknown.
    pub fn in_file(file: &Path, message: impl Into<String>) -> Self {
        UserError::at(Location::file(file), message)
    }
}

impl fmt::Display for UserError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(loc) => write!(f, "{loc}: {}", self.message),
            None => write!(f, "{}", self.message),
        }
    }
}

impl std::error::Error for UserError {}

/// `text` with every `//` comment replaced by spaces (string contents kept,
/// so byte offsets and lines are unchanged): what a locator searches.
pub fn blank_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let mut in_string = false;
        let mut cut = None;
        let bytes = line.as_bytes();
        for i in 0..bytes.len() {
            match bytes[i] {
                b'"' if i == 0 || bytes[i - 1] != b'\\' => in_string = !in_string,
                b'/' if !in_string && bytes.get(i + 1) == Some(&b'/') => {
                    cut = Some(i);
                    break;
                }
                _ => {}
            }
        }
        match cut {
            Some(i) => {
                out.push_str(&line[..i]);
                out.extend(line[i..].chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
            }
            None => out.push_str(line),
        }
    }
    out
}

/// The 1-based line of the first occurrence of `needle` in `text`, if any.
/// RON gives positions only for syntax errors; semantic errors (an unknown
/// material, a bad radius) find their line by looking for the offending text.
pub fn line_of(text: &str, needle: &str) -> Option<usize> {
    text.find(needle).map(|at| text[..at].matches('\n').count() + 1)
}

/// The 1-based line of the `n`-th (0-based) occurrence of `needle` at or
/// after byte `from`.
pub fn line_of_nth(text: &str, needle: &str, n: usize, from: usize) -> Option<usize> {
    let mut start = from.min(text.len());
    for _ in 0..n {
        let at = text[start..].find(needle)?;
        start += at + needle.len();
    }
    let at = start + text[start..].find(needle)?;
    Some(text[..at].matches('\n').count() + 1)
}

/// A number for a message: as written below 1e6 (`0.5`, `4096`), else
/// in exponent form with at most four significant digits (`1e30`,
/// `9.999e16`: an f32's exact value says nothing more), as are nonzero
/// magnitudes below 1e-3.
pub fn figure(x: f64) -> String {
    if !x.is_finite() || x == 0.0 || (1e-3..1e6).contains(&x.abs()) {
        return format!("{x}");
    }
    let s = format!("{x:.3e}");
    match s.split_once('e') {
        Some((m, e)) => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
        None => s,
    }
}

/// A user's file, whole: only a regular file is read (a device such as
/// /dev/zero would be read forever, a pipe would wait for a writer). The
/// error names the file and says what it was to be (`what`: "scene file").
pub fn read_user_file(path: &Path, what: &str) -> Result<Vec<u8>, UserError> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(UserError::in_file(path, format!("is a folder; give the {what}"))),
        Ok(m) if !m.is_file() => {
            return Err(UserError::in_file(path, format!("is not a regular file (a device or a pipe); give the {what} as a file")));
        }
        _ => {}
    }
    std::fs::read(path).map_err(|e| UserError::in_file(path, format!("cannot read the {what}: {e}")))
}

/// `read_user_file` as UTF-8 text.
pub fn read_user_text(path: &Path, what: &str) -> Result<String, UserError> {
    String::from_utf8(read_user_file(path, what)?).map_err(|_| UserError::in_file(path, format!("cannot read the {what}: it is not UTF-8 text")))
}

/// Converts a RON parse error into a `UserError` at its position.
pub fn ron_error(file: &Path, err: &ron::error::SpannedError) -> UserError {
    // ron's own advice here is for a program's author (raise the limit,
    // add a crate); the user's file is what nests too deep.
    let message = match &err.code {
        ron::Error::ExceededRecursionLimit => {
            "brackets nested too deep here (over 128 levels); glint's graph and scene files nest a few levels at most".to_string()
        }
        code => code.to_string(),
    };
    UserError::at(Location::at(file, err.span.start.line, err.span.start.col), message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_are_short() {
        assert_eq!(figure(0.5), "0.5");
        assert_eq!(figure(4096.0), "4096");
        assert_eq!(figure(0.0), "0");
        assert_eq!(figure(1e30), "1e30");
        assert_eq!(figure(9.999999843067494e16), "1e17");
        assert_eq!(figure(-2.5e-5), "-2.5e-5");
        assert_eq!(figure(f64::NAN), "NaN");
    }

    #[test]
    fn lines_are_one_based() {
        let t = "a\nbb\nccc bb\n";
        assert_eq!(line_of(t, "a"), Some(1));
        assert_eq!(line_of(t, "bb"), Some(2));
        assert_eq!(line_of_nth(t, "bb", 1, 0), Some(3));
        assert_eq!(line_of_nth(t, "bb", 2, 0), None);
        assert_eq!(line_of(t, "zz"), None);
    }
}
