//! WGSL loading with `#import` and a line map back to the original files.
//!
//! `#import name` on a line of its own pulls in `shaders/shared/name.wgsl`
//! (once per shader, however often it is imported, so shared files may
//! import each other). The expanded text keeps, for each of its lines, the
//! file and line it came from, so naga's errors point at what the user edits.

use std::path::{Path, PathBuf};

use crate::error::{Location, UserError};

/// A shader after `#import` expansion.
#[derive(Debug, Clone)]
pub struct ShaderSource {
    /// The pass shader's file name, relative to the shader directory.
    pub name: String,
    /// The expanded text naga parses: the shader with its imports inlined
    /// (each `#import` line kept, commented out).
    pub text: String,
    /// For each line of `text` (0-based): (index into `files`, 1-based line).
    line_map: Vec<(usize, usize)>,
    /// Every file the text came from: the shader first, then its imports.
    pub files: Vec<PathBuf>,
}

impl ShaderSource {
    /// The original file and line of a 1-based line of the expanded text.
    pub fn original(&self, expanded_line: usize, col: usize) -> Location {
        if expanded_line == 0 {
            return Location::file(&self.files[0]); // naga gave no position
        }
        match self.line_map.get(expanded_line - 1) {
            Some(&(file, line)) => Location::at(&self.files[file], line, col),
            // Past the end (naga places an unexpected end of file after the
            // last newline): the pass file's last line, which is always the
            // last mapped one, since imports are inlined where they appear.
            None => match self.line_map.last() {
                Some(&(file, line)) => Location::at(&self.files[file], line, 0),
                None => Location::file(&self.files[0]),
            },
        }
    }

    /// The original location of a byte span of the expanded text.
    pub fn span_location(&self, span: naga::Span) -> Location {
        if !span.is_defined() {
            return Location::file(&self.files[0]);
        }
        let loc = span.location(&self.text);
        self.original(loc.line_number as usize, loc.line_position as usize)
    }
}

const IMPORT: &str = "#import";

/// Whether a shader name is a relative path that stays inside the shader
/// folder (no root, no `..`, not empty).
pub fn is_inside(name: &str) -> bool {
    !name.is_empty() && Path::new(name).components().all(|c| matches!(c, std::path::Component::Normal(_)))
}

/// The pass shaders under `dir`, as a graph names them, sorted: the
/// `.wgsl` files in it and in its folders one level down (`realtime/x.wgsl`),
/// except `shared/`, which holds imported modules, not passes.
pub fn pass_shaders(dir: &Path) -> std::io::Result<Vec<String>> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let Ok(name) = entry.file_name().into_string() else { continue };
        if entry.file_type()?.is_dir() {
            if name == "shared" {
                continue;
            }
            for inner in std::fs::read_dir(entry.path())? {
                let Ok(inner) = inner?.file_name().into_string() else { continue };
                if inner.ends_with(".wgsl") {
                    files.push(format!("{name}/{inner}"));
                }
            }
        } else if name.ends_with(".wgsl") {
            files.push(name);
        }
    }
    files.sort();
    Ok(files)
}

/// Loads `dir/name` and expands its imports from `dir/shared/`. `name`
/// must stay inside `dir`: a relative path without `..` (a graph must not
/// read `/etc/passwd` as a shader).
pub fn load(dir: &Path, name: &str) -> Result<ShaderSource, UserError> {
    if !is_inside(name) {
        return Err(UserError::new(format!(
            "shader `{name}`: a shader is named by its path inside the shader folder {} (no absolute paths, no `..`)",
            dir.display()
        )));
    }
    let mut src = ShaderSource {
        name: name.to_string(),
        text: String::new(),
        line_map: Vec::new(),
        files: Vec::new(),
    };
    expand(&dir.join(name), dir, None, &mut src)?;
    Ok(src)
}

/// Expands from in-memory text (tests, hot reload of an unsaved buffer).
pub fn expand_text(text: &str, file: &Path, dir: &Path) -> Result<ShaderSource, UserError> {
    let mut src = ShaderSource {
        name: file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
        text: String::new(),
        line_map: Vec::new(),
        files: vec![file.to_path_buf()],
    };
    expand_lines(text, 0, dir, &mut src)?;
    Ok(src)
}

fn expand(path: &Path, dir: &Path, from: Option<Location>, src: &mut ShaderSource) -> Result<(), UserError> {
    if src.files.iter().any(|f| f == path) {
        return Ok(());
    }
    check_resolved_inside(path, dir, from.as_ref())?;
    let text = crate::error::read_user_text(path, "shader").map_err(|e| match &from {
        Some(loc) => UserError::at(loc.clone(), format!("cannot import {}: {}", path.display(), e.message)),
        None => e,
    })?;
    if text.trim().is_empty() {
        let what = if from.is_some() { "the imported shader" } else { "the shader" };
        return Err(UserError::in_file(path, format!("{what} is empty")));
    }
    src.files.push(path.to_path_buf());
    let index = src.files.len() - 1;
    expand_lines(&text, index, dir, src)
}

/// A name inside the shader folder may still be a link that leads out of
/// it (`shaders/x.wgsl -> /etc/passwd`): the file is resolved before it is
/// read, and one outside the folder is refused without reading it. A file
/// that does not resolve is left to the read, which says it is missing.
fn check_resolved_inside(path: &Path, dir: &Path, from: Option<&Location>) -> Result<(), UserError> {
    let (Ok(real), Ok(root)) = (std::fs::canonicalize(path), std::fs::canonicalize(dir)) else { return Ok(()) };
    if real.starts_with(&root) {
        return Ok(());
    }
    let rest = format!("leads to {}, outside the shader folder {}: shaders and their imports must be inside it (links included)", real.display(), root.display());
    Err(match from {
        Some(loc) => UserError::at(loc.clone(), format!("{} {rest}", path.display())),
        None => UserError::in_file(path, format!("the shader {rest}")),
    })
}

fn expand_lines(text: &str, file: usize, dir: &Path, src: &mut ShaderSource) -> Result<(), UserError> {
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        if let Some(rest) = trimmed.strip_prefix(IMPORT) {
            let here = Location::at(&src.files[file], i + 1, 1);
            let name = rest.trim().trim_matches('"');
            let valid = !name.is_empty()
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            if !valid {
                return Err(UserError::at(
                    here,
                    format!("bad import `{trimmed}`: write `#import name` to include shaders/shared/name.wgsl"),
                ));
            }
            let path = dir.join("shared").join(format!("{name}.wgsl"));
            expand(&path, dir, Some(here), src)?;
            // Keep the import line itself (commented) so line counts stay simple.
            src.text.push_str("// ");
        }
        src.text.push_str(line);
        src.text.push('\n');
        src.line_map.push((file, i + 1));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imports_map_lines_back() {
        let dir = std::env::temp_dir().join(format!("glint-src-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("shared")).unwrap();
        std::fs::write(dir.join("shared/a.wgsl"), "// a1\n#import b\nconst A = 1;\n").unwrap();
        std::fs::write(dir.join("shared/b.wgsl"), "const B = 2;\n").unwrap();
        std::fs::write(dir.join("p.wgsl"), "#import a\n#import b\nconst P = 3;\n").unwrap();
        let s = load(&dir, "p.wgsl").unwrap();
        assert_eq!(s.files.len(), 3);
        // b is included once, inside a.
        assert_eq!(s.text.matches("const B").count(), 1);
        let line = s.text.lines().position(|l| l.starts_with("const P")).unwrap() + 1;
        let loc = s.original(line, 1);
        assert!(loc.file.ends_with("p.wgsl"));
        assert_eq!(loc.line, 3);
        let line = s.text.lines().position(|l| l.starts_with("const B")).unwrap() + 1;
        assert!(s.original(line, 1).file.ends_with("b.wgsl"));
        // An error past the end of the text lands on the pass file's last line.
        let end = s.original(s.text.lines().count() + 1, 1);
        assert!(end.file.ends_with("p.wgsl") && end.line == 3, "{end}");
        let err = expand_text("#import nothere\n", &dir.join("q.wgsl"), &dir).unwrap_err();
        assert!(err.to_string().contains("q.wgsl:1"), "{err}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
