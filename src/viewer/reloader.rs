//! The viewer's reload thread: it owns the file watcher, and as soon as a
//! batch of saves arrives it runs the rebuilds (naga, compile, pipelines)
//! there, from a template of the session's state, while the window keeps
//! presenting. Finished rebuilds wait in a channel for the frame boundary
//! where the viewer commits them. A rebuild also updates the template, so a
//! second save does not start from state the first one replaced.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::error::UserError;
use crate::reload::{classify, waiting_line, watch_dirs, Sources, Watcher};
use crate::session::rebuild::{Rebuild, RebuildJob, RebuildKind};
use crate::session::Session;

/// A rebuild the reload thread finished.
pub struct Finished {
    /// The files it was for, for the event line.
    pub what: String,
    /// "shader", "graph" or "scene": what the last good one of is kept.
    pub kind: &'static str,
    pub started: Instant,
    /// Frames the window presented while it ran.
    pub frames: u64,
    pub result: Result<Rebuild, UserError>,
}

struct Shared {
    template: RebuildJob,
    sources: Sources,
    /// What is being rebuilt now (for the panel).
    running: Option<String>,
}

pub struct Reloader {
    shared: Arc<Mutex<Shared>>,
    results: Receiver<Finished>,
    presented: Arc<AtomicU64>,
}

fn describe(kind: &RebuildKind) -> String {
    match kind {
        RebuildKind::Shaders(f) => f.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", "),
        RebuildKind::Graph(p) | RebuildKind::SwitchGraph(p) | RebuildKind::Scene(p) | RebuildKind::OpenScene(p) => p.display().to_string(),
        RebuildKind::Edits => "graph edits".into(),
    }
}

impl Reloader {
    /// Starts watching the session's files; returns the folders watched.
    /// `wake` is called whenever a result is waiting.
    pub fn start(session: &Session, wake: crate::viewer::Waker) -> Result<(Reloader, Vec<std::path::PathBuf>), UserError> {
        let sources = session.sources();
        let dirs = watch_dirs(&sources);
        let mut watcher = Watcher::new(&dirs)?;
        let shared = Arc::new(Mutex::new(Shared { template: session.job(RebuildKind::Edits), sources, running: None }));
        let presented = Arc::new(AtomicU64::new(0));
        let (tx, results) = channel();
        let (thread_shared, thread_presented) = (Arc::clone(&shared), Arc::clone(&presented));
        std::thread::Builder::new()
            .name("glint reload".into())
            .spawn(move || loop {
                let batch = watcher.changed(Duration::from_millis(200));
                for e in &batch.errors {
                    eprintln!("glint: file watcher: {e}");
                }
                for (path, why) in batch.waiting {
                    let result = Err(UserError::new(waiting_line(&path, &why)));
                    let what = path.display().to_string();
                    let waited = Finished { what, kind: "state", started: Instant::now(), frames: 0, result };
                    if tx.send(waited).is_err() {
                        return;
                    }
                    wake();
                }
                let changed = batch.changed;
                if changed.is_empty() {
                    // The viewer is gone when nobody listens any more.
                    if Arc::strong_count(&thread_shared) == 1 {
                        return;
                    }
                    continue;
                }
                let kinds = match thread_shared.lock() {
                    Ok(s) => classify(&s.sources, &changed),
                    Err(_) => return,
                };
                for kind in kinds {
                    let what = describe(&kind);
                    let Ok(mut s) = thread_shared.lock() else { return };
                    let job = s.template.clone().with_kind(kind);
                    s.running = Some(what.clone());
                    drop(s);
                    let kind_word = job.kind().what();
                    let (started, frames0) = (Instant::now(), thread_presented.load(Ordering::Acquire));
                    let result = job.run();
                    let Ok(mut s) = thread_shared.lock() else { return };
                    if let Ok(r) = &result {
                        s.template.absorb(r);
                    }
                    s.running = None;
                    drop(s);
                    // Saved again while it built: the next batch rebuilds
                    // from the newer content, so this error is stale.
                    if result.is_err() && watcher.superseded(&changed) {
                        continue;
                    }
                    let frames = thread_presented.load(Ordering::Acquire) - frames0;
                    if tx.send(Finished { what, kind: kind_word, started, frames, result }).is_err() {
                        return;
                    }
                    wake();
                }
            })
            .map_err(|e| UserError::new(format!("cannot start the reload thread: {e}")))?;
        Ok((Reloader { shared, results, presented }, dirs))
    }

    /// After the session changed (a commit, a param, a pass switched):
    /// the next rebuild starts from its state.
    pub fn refresh(&self, session: &Session) {
        if let Ok(mut s) = self.shared.lock() {
            s.template = session.job(RebuildKind::Edits);
            s.sources = session.sources();
        }
    }

    /// A finished rebuild, if one is waiting.
    pub fn finished(&self) -> Option<Finished> {
        match self.results.try_recv() {
            Ok(f) => Some(f),
            Err(TryRecvError::Empty) | Err(TryRecvError::Disconnected) => None,
        }
    }

    /// What is being rebuilt now.
    pub fn running(&self) -> Option<String> {
        self.shared.lock().ok().and_then(|s| s.running.clone())
    }

    /// Counts a presented frame (for "frames presented meanwhile").
    pub fn presented(&self) {
        self.presented.fetch_add(1, Ordering::AcqRel);
    }
}
