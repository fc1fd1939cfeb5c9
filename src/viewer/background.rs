//! Switches built off the presenting thread: a graph or machine profile
//! picked in the panel, a scene file dropped on the window. Their rebuild
//! (shaders through naga, the pipelines, a scene's BVH) runs on a thread
//! of its own while the window keeps presenting the running graph; the
//! viewer commits it at the first frame boundary after it finished, so a
//! switch never freezes the window for longer than the commit.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::Instant;

use crate::error::UserError;
use crate::session::rebuild::{Rebuild, RebuildJob};
use crate::viewer::actions::SwitchCommit;

/// What the viewer does with a finished rebuild.
pub enum After {
    /// A graph or profile switch: commit at its size and target.
    Switch(SwitchCommit),
    /// Another scene file: commit, then take its camera and title.
    OpenScene(PathBuf),
}

/// A switch being rebuilt.
pub struct Pending {
    /// What it is for, for the panel ("switching to ...").
    pub what: String,
    /// When it started (the event line's time is to the commit).
    pub started: Instant,
    /// What to do once it is built.
    pub after: After,
    result: Receiver<Result<Rebuild, UserError>>,
}

impl Pending {
    /// Starts `job` on its own thread.
    pub fn start(job: RebuildJob, what: String, after: After) -> Result<Pending, UserError> {
        Ok(Pending { what, started: Instant::now(), after, result: job.spawn()? })
    }

    /// The rebuild's result once it has finished (a thread that died
    /// without one is an error, not a wait forever).
    pub fn poll(&self) -> Option<Result<Rebuild, UserError>> {
        match self.result.try_recv() {
            Ok(r) => Some(r),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(UserError::new(format!("the rebuild for {} stopped without a result", self.what)))),
        }
    }
}
