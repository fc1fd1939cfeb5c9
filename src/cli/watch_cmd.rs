//! `glint render --watch`: the headless hot-reload loop. After the first
//! render it waits for saves; each batch of changed files becomes rebuilds
//! (see `reload::classify`), each built aside and swapped in only when it
//! succeeded, and the outputs are rendered again. One line per event:
//! `reloaded <file>: <n> passes rebuilt in <ms> ms` ("1 pass rebuilt"), or
//! `error: <file>:<line>:<col>: <message> (keeping the last good <what>)`,
//! or, for a file left empty or replaced by something that is not a file,
//! `waiting for <file> to have content: it is empty (keeping the last good
//! state)`. An error from a file saved again while it built is not printed:
//! the next batch rebuilds from the newer content.
//! Ctrl-C (SIGINT) ends it with exit code 0.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::render_cmd::{render_frames, RenderArgs};
use crate::error::UserError;
use crate::reload::{classify, relative_to_cwd, waiting_line, watch_dirs, Sources, Watcher};
use crate::session::frame_loop::{FrameLoop, FrameStats};
use crate::session::rebuild::RebuildKind;
use crate::session::Session;

/// The file a rebuild is named by in its event line: for a scene, the
/// scene file if it changed, else the meshes or materials that did.
fn subject(kind: &RebuildKind, changed: &[PathBuf], sources: &Sources) -> String {
    let list = |files: &[&PathBuf]| files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>().join(", ");
    match kind {
        RebuildKind::Shaders(files) => list(&files.iter().collect::<Vec<_>>()),
        RebuildKind::Graph(p) | RebuildKind::SwitchGraph(p) | RebuildKind::OpenScene(p) => p.display().to_string(),
        RebuildKind::Scene(p) => {
            let meshes: Vec<&PathBuf> = changed
                .iter()
                .filter(|c| c.as_path() != p.as_path() && classify(sources, std::slice::from_ref(*c)).iter().any(|k| matches!(k, RebuildKind::Scene(_))))
                .collect();
            if changed.iter().any(|c| c == p) || meshes.is_empty() { p.display().to_string() } else { list(&meshes) }
        }
        RebuildKind::Edits => "graph edits".to_string(),
    }
}

/// `glint render ... --watch`: the render, then the watch loop.
pub fn run(args: &RenderArgs) -> Result<(), UserError> {
    let (session, frames) = super::render_cmd::run(args)?;
    if !args.watch {
        return Ok(());
    }
    watch(args, session, frames)
}

fn watch(args: &RenderArgs, mut session: Session, mut frames: FrameLoop) -> Result<(), UserError> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    ctrlc::set_handler(move || flag.store(true, Ordering::Release))
        .map_err(|e| UserError::new(format!("cannot handle Ctrl-C: {e}")))?;
    let dirs = watch_dirs(&session.sources());
    let mut watcher = Watcher::new(&dirs)?;
    let shown: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
    out!("watching {} (Ctrl-C ends)", shown.join(", "));
    while !stop.load(Ordering::Acquire) {
        let batch = watcher.changed(Duration::from_millis(200));
        for e in &batch.errors {
            eprintln!("glint: file watcher: {e}");
        }
        for (path, why) in &batch.waiting {
            out!("{} (keeping the last good state)", waiting_line(path, why));
        }
        let changed = batch.changed;
        if changed.is_empty() {
            continue;
        }
        let sources = session.sources();
        for kind in classify(&sources, &changed) {
            let what = kind.what();
            let file = subject(&kind, &changed, &sources);
            let start = Instant::now();
            let result = session.job(kind).run().and_then(|r| session.commit(r));
            match result {
                Ok(report) => {
                    // Each output is a render from the start, as a fresh
                    // `glint render` makes it (a commit that changed nothing
                    // would otherwise keep accumulating).
                    session.restart();
                    frames.time = args.time;
                    frames.stats = FrameStats::default();
                    // A failed write (a full disk, a folder gone) is reported
                    // and the watch goes on with the new state.
                    if let Err(e) = render_frames(args, &mut session, &mut frames, true) {
                        out!("{}", relative_to_cwd(&format!("error: {e} (the rebuild of {file} is in place; the output was not written)")));
                        continue;
                    }
                    let line = format!("reloaded {file}: {} in {:.0} ms", report.passes_rebuilt(), start.elapsed().as_secs_f64() * 1e3);
                    out!("{}", relative_to_cwd(&line));
                }
                // Saved again while it built (a burst of saves, or an editor
                // truncating mid-read): the next batch rebuilds from the
                // newer content, so this error is stale.
                Err(_) if watcher.superseded(&changed) => {}
                Err(e) => out!("{}", relative_to_cwd(&format!("error: {e} (keeping the last good {what})"))),
            }
        }
    }
    out!("stopped watching");
    Ok(())
}
