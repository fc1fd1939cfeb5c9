//! Hot reload: watching the files a session is made of and turning saves
//! into rebuilds (docs/ARCHITECTURE.md, "Reload protocol").
//!
//! notify watches folders recursively (editors that save by renaming over
//! the file, vim and JetBrains among them, replace it); notify-debouncer-full
//! folds the events of one save, or a burst of saves, into one batch after
//! about 50 ms of quiet. A file whose content hash has not changed since
//! the last batch is skipped (touches, saves of the same text, editors'
//! backup files). A file that is empty, unreadable or not a regular file
//! (a link to a device) is not read: it waits for the save that brings
//! content, and if none comes within `WAIT_NOTE` the batch says so once.
//! `classify` says which rebuild a changed file calls for.

pub mod classify;

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

use notify_debouncer_full::notify::RecursiveMode;
use notify_debouncer_full::{new_debouncer, DebounceEventResult, Debouncer, RecommendedCache};

use crate::error::UserError;
pub use classify::{classify, watch_dirs, Sources};

/// `text` with the current folder's absolute path taken out of the paths
/// in it: the watcher reports absolute paths, a user reads
/// `shaders/lights.wgsl:67:49` better.
pub fn relative_to_cwd(text: &str) -> String {
    let Ok(cwd) = std::env::current_dir() else { return text.to_string() };
    let mut out = text.to_string();
    for dir in [std::fs::canonicalize(&cwd).unwrap_or_else(|_| cwd.clone()), cwd] {
        let prefix = format!("{}{}", dir.display(), std::path::MAIN_SEPARATOR);
        out = out.replace(&prefix, "");
    }
    out
}

/// Quiet time that ends a batch of events.
pub const DEBOUNCE: Duration = Duration::from_millis(50);

/// How long a changed file may stay empty or unreadable (an editor's
/// truncate-then-write takes milliseconds) before the watcher says what it
/// is waiting for.
pub const WAIT_NOTE: Duration = Duration::from_secs(1);

/// A debounced, content-filtered file watcher.
pub struct Watcher {
    _debouncer: Debouncer<notify_debouncer_full::notify::RecommendedWatcher, RecommendedCache>,
    events: Receiver<DebounceEventResult>,
    hashes: HashMap<PathBuf, Option<u64>>,
    /// Changed files without content yet: since when, and the reason
    /// last reported (a new reason is reported again).
    pending: HashMap<PathBuf, (Instant, Option<String>)>,
}

/// What one call of `Watcher::changed` found.
#[derive(Debug, Default)]
pub struct Batch {
    /// Files whose content changed.
    pub changed: Vec<PathBuf>,
    /// Errors of the watcher itself.
    pub errors: Vec<String>,
    /// Files that have had no content for `WAIT_NOTE`, each with what is
    /// wrong with it (reported once per wait).
    pub waiting: Vec<(PathBuf, String)>,
}

/// Why `path` cannot be read as a source now, if it cannot.
fn no_content(path: &Path) -> Option<String> {
    match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Some("does not exist (or links to nothing)".into()),
        Err(e) => Some(format!("cannot be read ({e})")),
        Ok(m) if !m.is_file() => Some("is not a regular file (a folder, or a link to a device or pipe)".into()),
        Ok(m) if m.len() == 0 => Some("is empty".into()),
        Ok(_) => None,
    }
}

/// The hash of a regular file's bytes (None for anything else: a link to
/// `/dev/zero` must not be read).
fn content_hash(path: &Path) -> Option<u64> {
    if !std::fs::metadata(path).ok()?.is_file() {
        return None;
    }
    let bytes = std::fs::read(path).ok()?;
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytes.hash(&mut h);
    Some(h.finish())
}

/// Every file under `dir` (recursively), for the first content hashes.
fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            files_under(&p, out);
        } else {
            out.push(p);
        }
    }
}

impl Watcher {
    /// Watches `dirs` recursively. The files in them now are hashed, so the
    /// first save that changes nothing is skipped too.
    pub fn new(dirs: &[PathBuf]) -> Result<Watcher, UserError> {
        let (tx, events) = channel();
        let mut debouncer =
            new_debouncer(DEBOUNCE, None, tx).map_err(|e| UserError::new(format!("cannot watch files for changes: {e}")))?;
        let mut hashes = HashMap::new();
        for dir in dirs {
            debouncer
                .watch(dir, RecursiveMode::Recursive)
                .map_err(|e| UserError::in_file(dir, format!("cannot watch this folder for changes: {e}")))?;
            let mut files = Vec::new();
            files_under(dir, &mut files);
            for f in files {
                hashes.insert(f.clone(), content_hash(&f));
            }
        }
        Ok(Watcher { _debouncer: debouncer, events, hashes, pending: HashMap::new() })
    }

    /// The files whose content changed, from the batches that arrived
    /// within `timeout` (none when none did), the watcher's own errors, and
    /// the files that have waited `WAIT_NOTE` for content.
    pub fn changed(&mut self, timeout: Duration) -> Batch {
        let mut batch = Batch::default();
        let mut paths: Vec<PathBuf> = Vec::new();
        let take = |r: DebounceEventResult, paths: &mut Vec<PathBuf>, errors: &mut Vec<String>| match r {
            Ok(events) => {
                for e in events {
                    paths.extend(e.event.paths.iter().cloned());
                }
            }
            Err(es) => errors.extend(es.into_iter().map(|e| e.to_string())),
        };
        if let Ok(r) = self.events.recv_timeout(timeout) {
            take(r, &mut paths, &mut batch.errors);
            while let Ok(r) = self.events.try_recv() {
                take(r, &mut paths, &mut batch.errors);
            }
        }
        paths.sort();
        paths.dedup();
        for p in paths {
            if p.is_dir() {
                continue;
            }
            // A file gone for now (mid-rename), unreadable, empty (the
            // moment between an editor's truncate and its write) or not a
            // file waits for the event that brings its content.
            if let Some(why) = no_content(&p) {
                let wait = self.pending.entry(p).or_insert((Instant::now(), None));
                if wait.1.as_ref().is_some_and(|said| *said != why) {
                    *wait = (Instant::now(), None);
                }
                continue;
            }
            self.pending.remove(&p);
            let now = content_hash(&p);
            if self.hashes.get(&p) != Some(&now) {
                self.hashes.insert(p.clone(), now);
                batch.changed.push(p);
            }
        }
        self.note_waits(&mut batch.waiting);
        batch
    }

    /// Reports, once, each file that has been without content too long
    /// (and forgets those that got it or went away for good).
    fn note_waits(&mut self, waiting: &mut Vec<(PathBuf, String)>) {
        let mut settled = Vec::new();
        for (path, (since, reported)) in &mut self.pending {
            // A file deleted for good (an editor's swap file) is no wait.
            if std::fs::symlink_metadata(path).is_err() {
                settled.push(path.clone());
                continue;
            }
            match no_content(path) {
                None => settled.push(path.clone()),
                Some(why) if reported.as_ref() != Some(&why) && since.elapsed() >= WAIT_NOTE => {
                    *reported = Some(why.clone());
                    waiting.push((path.clone(), why));
                }
                Some(_) => {}
            }
        }
        for p in settled {
            self.pending.remove(&p);
        }
        waiting.sort();
    }

    /// Whether any of `files` changed again after this watcher read it: a
    /// rebuild from it may have read a newer or half-written file, and the
    /// next batch rebuilds anyway, so its error is not worth reporting.
    pub fn superseded(&self, files: &[PathBuf]) -> bool {
        files.iter().any(|f| no_content(f).is_some() || self.hashes.get(f) != Some(&content_hash(f)))
    }
}

/// The line that says what a file's wait is for.
pub fn waiting_line(path: &Path, why: &str) -> String {
    relative_to_cwd(&format!("waiting for {} to have content: it {why}", path.display()))
}
