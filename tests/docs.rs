//! The documentation as files: the README stays a user's page (under 300
//! lines) and every relative link in it and in docs/ leads to a file that
//! exists (and, with an anchor, to a heading there). No GPU.

use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The markdown files checked: README.md and docs/*.md.
fn pages() -> Vec<PathBuf> {
    let mut v = vec![repo().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(repo().join("docs"))
        .expect("docs/")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    v.extend(docs);
    v
}

/// Link targets of `[text](target)` and `![alt](target)`, outside code.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut fenced = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            out.push((n + 1, after[..end].to_string()));
            rest = &after[end..];
        }
    }
    out
}

/// GitHub's anchor for a heading: lower case, spaces to dashes, most
/// punctuation dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(text: &str) -> Vec<String> {
    text.lines().filter(|l| l.starts_with('#')).map(|l| slug(l.trim_start_matches('#'))).collect()
}

fn resolve(page: &Path, target: &str) -> Result<(), String> {
    if target.contains("://") || target.starts_with("mailto:") {
        return Ok(());
    }
    let (file, anchor) = target.split_once('#').map_or((target, None), |(f, a)| (f, Some(a)));
    let path = if file.is_empty() { page.to_path_buf() } else { page.parent().expect("a folder").join(file) };
    if !path.exists() {
        return Err(format!("{} does not exist", path.display()));
    }
    if let (Some(a), true) = (anchor, path.extension().is_some_and(|e| e == "md")) {
        let text = std::fs::read_to_string(&path).map_err(|e| e.to_string())?;
        if !anchors(&text).iter().any(|h| h == a) {
            return Err(format!("no heading #{a} in {}", path.display()));
        }
    }
    Ok(())
}

#[test]
fn the_readme_is_a_users_page() {
    let text = std::fs::read_to_string(repo().join("README.md")).expect("README.md");
    let lines = text.lines().count();
    assert!(lines < 300, "README.md has {lines} lines; engineering notes go in docs/");
}

#[test]
fn every_relative_link_resolves() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("a page");
        for (line, target) in links(&text) {
            checked += 1;
            if let Err(e) = resolve(&page, &target) {
                broken.push(format!("{}:{line}: ({target}): {e}", page.strip_prefix(repo()).unwrap_or(&page).display()));
            }
        }
    }
    assert!(checked > 20, "only {checked} links found: is the link pattern right?");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_checker_finds_a_broken_link() {
    let page = repo().join("README.md");
    assert!(resolve(&page, "docs/no-such-page.md").is_err());
    assert!(resolve(&page, "docs/usage.md#no-such-heading").is_err());
    assert!(resolve(&page, "docs/usage.md").is_ok());
    assert_eq!(slug(" Speed against accuracy"), "speed-against-accuracy");
    assert_eq!(links("see [a](b.md) and ![c](d/e.png)"), vec![(1, "b.md".to_string()), (1, "d/e.png".to_string())]);
}
