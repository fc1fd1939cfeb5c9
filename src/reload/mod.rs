//! Hot reload: watching the files a session is made of and turning saves
//! into rebuilds (docs/ARCHITECTURE.md, "Reload protocol").
//!
//! notify watches folders recursively (editors that save by renaming over
//! the file, vim and JetBrains among them, replace it); notify-debouncer-full
//! folds the events of one save, or a burst of saves, into one batch after
//! about 50 ms of quiet. A file whose content hash has not changed since
//! the last batch is skipped (touches, saves of the same text, editors'
//! backup files). `classify` says which rebuild a changed file calls for.

pub mod classify;

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::Duration;

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

/// A debounced, content-filtered file watcher.
pub struct Watcher {
    _debouncer: Debouncer<notify_debouncer_full::notify::RecommendedWatcher, RecommendedCache>,
    events: Receiver<DebounceEventResult>,
    hashes: HashMap<PathBuf, Option<u64>>,
}

fn content_hash(path: &Path) -> Option<u64> {
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
        Ok(Watcher { _debouncer: debouncer, events, hashes })
    }

    /// The files whose content changed, from the batches that arrived
    /// within `timeout` (empty when none did). Watcher errors are returned
    /// as messages beside the files.
    pub fn changed(&mut self, timeout: Duration) -> (Vec<PathBuf>, Vec<String>) {
        let mut paths: Vec<PathBuf> = Vec::new();
        let mut errors = Vec::new();
        let mut take = |r: DebounceEventResult, paths: &mut Vec<PathBuf>| match r {
            Ok(events) => {
                for e in events {
                    paths.extend(e.event.paths.iter().cloned());
                }
            }
            Err(es) => errors.extend(es.into_iter().map(|e| e.to_string())),
        };
        match self.events.recv_timeout(timeout) {
            Ok(r) => take(r, &mut paths),
            Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => return (vec![], errors),
        }
        while let Ok(r) = self.events.try_recv() {
            take(r, &mut paths);
        }
        paths.sort();
        paths.dedup();
        let mut changed = Vec::new();
        for p in paths {
            if p.is_dir() {
                continue;
            }
            let now = content_hash(&p);
            // A file gone for now (mid-rename), unreadable, or empty (the
            // moment between an editor's truncate and its write) waits for
            // the event that brings its content.
            if now.is_none() || std::fs::metadata(&p).is_ok_and(|m| m.len() == 0) {
                continue;
            }
            if self.hashes.get(&p) != Some(&now) {
                self.hashes.insert(p.clone(), now);
                changed.push(p);
            }
        }
        (changed, errors)
    }
}
