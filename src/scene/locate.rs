//! Where things are in a scene file. serde gives positions only for syntax
//! errors, so semantic errors (a bad radius in the third object) find their
//! line in a loose outline of the RON text: where every value, struct field,
//! map entry and list item starts. The outline is built after RON accepted
//! the text, and the scanner is lenient: on anything unexpected it moves on,
//! it never fails.

use std::path::Path;

use crate::error::{Location, UserError};

/// One step of a path into the document.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Step<'a> {
    /// A named struct field (or a map entry with that key).
    Field(&'a str),
    /// The n-th item of a list (or the n-th entry of a map).
    Item(usize),
}

#[derive(Debug, Default)]
struct Node {
    start: usize,
    fields: Vec<(String, Node)>,
    items: Vec<Node>,
}

impl Node {
    fn leaf(start: usize) -> Self {
        Node {
            start,
            ..Node::default()
        }
    }

    /// The deepest node along `path` (stops at the first step that misses).
    fn find(&self, path: &[Step]) -> &Node {
        let Some((step, rest)) = path.split_first() else {
            return self;
        };
        let next = match *step {
            Step::Field(name) => self.fields.iter().find(|(k, _)| k == name).map(|(_, n)| n),
            Step::Item(i) => self
                .items
                .get(i)
                .or_else(|| self.fields.get(i).map(|(_, n)| n)),
        };
        next.map_or(self, |n| n.find(rest))
    }
}

/// The outline of one RON document.
pub(crate) struct Outline<'a> {
    text: &'a str,
    root: Node,
}

impl<'a> Outline<'a> {
    pub(crate) fn new(text: &'a str) -> Self {
        let mut s = Scanner {
            b: text.as_bytes(),
            pos: 0,
        };
        let root = s.value(0);
        Outline { text, root }
    }

    /// 1-based line of the deepest value found along `path`; 0 if even the
    /// root is missing (empty text).
    pub(crate) fn line(&self, path: &[Step]) -> usize {
        let at = self.root.find(path).start.min(self.text.len());
        self.text.as_bytes()[..at]
            .iter()
            .filter(|&&c| c == b'\n')
            .count()
            + 1
    }
}

/// Builds `UserError`s located in one scene file.
pub(crate) struct Locator<'a> {
    pub(crate) path: &'a Path,
    outline: Outline<'a>,
}

impl<'a> Locator<'a> {
    pub(crate) fn new(path: &'a Path, text: &'a str) -> Self {
        Locator {
            path,
            outline: Outline::new(text),
        }
    }

    pub(crate) fn line(&self, at: &[Step]) -> usize {
        self.outline.line(at)
    }

    pub(crate) fn err(&self, at: &[Step], message: impl Into<String>) -> UserError {
        UserError::at(Location::at(self.path, self.line(at), 0), message)
    }
}

/// Deep nesting is not a real scene; stop descending rather than overflow.
const MAX_DEPTH: usize = 64;

struct Scanner<'t> {
    b: &'t [u8],
    pos: usize,
}

impl Scanner<'_> {
    fn peek(&self) -> Option<u8> {
        self.b.get(self.pos).copied()
    }

    fn peek_at(&self, k: usize) -> Option<u8> {
        self.b.get(self.pos + k).copied()
    }

    /// Skips whitespace, comments (`//`, nested `/* */`) and `#![...]` attributes.
    fn skip_ws(&mut self) {
        while let Some(c) = self.peek() {
            if c.is_ascii_whitespace() {
                self.pos += 1;
            } else if c == b'/' && self.peek_at(1) == Some(b'/') {
                while self.peek().is_some_and(|c| c != b'\n') {
                    self.pos += 1;
                }
            } else if c == b'/' && self.peek_at(1) == Some(b'*') {
                self.pos += 2;
                let mut depth = 1;
                while depth > 0 && self.pos < self.b.len() {
                    if self.peek() == Some(b'/') && self.peek_at(1) == Some(b'*') {
                        depth += 1;
                        self.pos += 2;
                    } else if self.peek() == Some(b'*') && self.peek_at(1) == Some(b'/') {
                        depth -= 1;
                        self.pos += 2;
                    } else {
                        self.pos += 1;
                    }
                }
            } else if c == b'#' && self.peek_at(1) == Some(b'!') {
                while self.peek().is_some_and(|c| c != b']') {
                    self.pos += 1;
                }
                self.pos += 1;
            } else {
                break;
            }
        }
    }

    fn value(&mut self, depth: usize) -> Node {
        self.skip_ws();
        let start = self.pos;
        match self.peek() {
            None => Node::leaf(start),
            Some(open @ (b'(' | b'[' | b'{')) if depth < MAX_DEPTH => {
                self.group(start, open, depth)
            }
            Some(b'"') => {
                self.quoted(b'"');
                Node::leaf(start)
            }
            Some(b'\'') => {
                self.quoted(b'\'');
                Node::leaf(start)
            }
            Some(b'r') if matches!(self.peek_at(1), Some(b'"' | b'#')) => {
                self.raw_string();
                Node::leaf(start)
            }
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                while self
                    .peek()
                    .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_')
                {
                    self.pos += 1;
                }
                let after = self.pos;
                self.skip_ws();
                match self.peek() {
                    // `Name(...)`: the node starts at the name.
                    Some(open @ b'(') if depth < MAX_DEPTH => self.group(start, open, depth),
                    _ => {
                        self.pos = after;
                        Node::leaf(start)
                    }
                }
            }
            Some(_) => {
                // Numbers and anything else: up to the next delimiter.
                self.pos += 1;
                while self
                    .peek()
                    .is_some_and(|c| !c.is_ascii_whitespace() && !b",:()[]{}".contains(&c))
                {
                    self.pos += 1;
                }
                Node::leaf(start)
            }
        }
    }

    /// `(...)`, `[...]` or `{...}` starting at the current position.
    fn group(&mut self, start: usize, open: u8, depth: usize) -> Node {
        let close = match open {
            b'(' => b')',
            b'[' => b']',
            _ => b'}',
        };
        self.pos += 1;
        let mut node = Node::leaf(start);
        loop {
            self.skip_ws();
            let before = self.pos;
            match self.peek() {
                None => break,
                Some(c) if c == close => {
                    self.pos += 1;
                    break;
                }
                Some(b',') => {
                    self.pos += 1;
                    continue;
                }
                // A stray closer of another kind: leave it to the caller.
                Some(b')' | b']' | b'}') => break,
                Some(_) => {}
            }
            let first = self.value(depth + 1);
            self.skip_ws();
            if self.peek() == Some(b':') {
                self.pos += 1;
                let key = self.key_text(first.start);
                let value = self.value(depth + 1);
                node.fields.push((key, value));
            } else {
                node.items.push(first);
            }
            if self.pos == before {
                self.pos += 1; // never loop without progress
            }
        }
        node
    }

    /// The text of a key: an identifier or a quoted string (without quotes).
    fn key_text(&self, start: usize) -> String {
        let rest = &self.b[start..];
        let bytes: &[u8] = if rest.first() == Some(&b'"') {
            let end = rest[1..]
                .iter()
                .position(|&c| c == b'"')
                .unwrap_or(rest.len() - 1);
            &rest[1..1 + end]
        } else {
            let end = rest
                .iter()
                .position(|&c| !(c.is_ascii_alphanumeric() || c == b'_'))
                .unwrap_or(rest.len());
            &rest[..end]
        };
        String::from_utf8_lossy(bytes).into_owned()
    }

    fn quoted(&mut self, q: u8) {
        self.pos += 1;
        while let Some(c) = self.peek() {
            self.pos += 1;
            if c == b'\\' {
                self.pos += 1;
            } else if c == q {
                break;
            }
        }
    }

    /// `r"..."`, `r#"..."#`, ...
    fn raw_string(&mut self) {
        self.pos += 1;
        let mut hashes = 0;
        while self.peek() == Some(b'#') {
            hashes += 1;
            self.pos += 1;
        }
        if self.peek() != Some(b'"') {
            return;
        }
        self.pos += 1;
        while self.pos < self.b.len() {
            if self.peek() == Some(b'"') && (1..=hashes).all(|k| self.peek_at(k) == Some(b'#')) {
                self.pos += 1 + hashes;
                return;
            }
            self.pos += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"#![enable(implicit_some)]
// a comment with objects: [
Scene(
    camera: Camera(position: (0.0, 0.0, 3.4),
        vfov_deg: 40.0),
    materials: {
        "white": Material(albedo: (1.0, 1.0, 1.0)),
        "red": /* ( */ Material(albedo: (1.0, 0.0, 0.0)),
    },
    objects: [
        Sphere(center: (0.0, 0.0, 0.0), radius: 1.0, material: "white"),
        Sphere(
            center: (0.0, 0.0, 0.0),
            radius: NaN,
            material: "red",
        ),
    ],
)
"#;

    #[test]
    fn finds_fields_items_and_entries() {
        let o = Outline::new(TEXT);
        assert_eq!(o.line(&[]), 3);
        assert_eq!(o.line(&[Step::Field("camera"), Step::Field("vfov_deg")]), 5);
        assert_eq!(o.line(&[Step::Field("materials"), Step::Item(1)]), 8);
        assert_eq!(o.line(&[Step::Field("materials"), Step::Field("red")]), 8);
        assert_eq!(
            o.line(&[
                Step::Field("objects"),
                Step::Item(0),
                Step::Field("material")
            ]),
            11
        );
        assert_eq!(o.line(&[Step::Field("objects"), Step::Item(1)]), 12);
        assert_eq!(
            o.line(&[Step::Field("objects"), Step::Item(1), Step::Field("radius")]),
            14
        );
        // A missing step falls back to the deepest node found.
        assert_eq!(
            o.line(&[Step::Field("objects"), Step::Item(1), Step::Field("motion")]),
            12
        );
        assert_eq!(o.line(&[Step::Field("lights"), Step::Item(0)]), 3);
    }

    #[test]
    fn never_panics_on_junk() {
        for t in [
            "",
            "(",
            ")",
            "[}",
            "Scene(a: ",
            "\"unterminated",
            "r#\"x",
            "/* open",
            "#!",
            "a:b:c",
            "((((",
            "'",
        ] {
            let o = Outline::new(t);
            let _ = o.line(&[Step::Field("a"), Step::Item(3)]);
        }
        let deep = "(".repeat(10_000);
        let _ = Outline::new(&deep).line(&[Step::Item(0)]);
    }
}
