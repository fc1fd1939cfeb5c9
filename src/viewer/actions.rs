//! What a panel action does to the session: the same calls the tests and
//! the CLI make (`set_param`, `set_enabled`, `switch_profile`), so a click
//! in the viewer and a test do the same. An action that rebuilds the graph
//! (a graph or profile picked) comes back as a `Switch`: its rebuild can
//! run on another thread while the window keeps presenting, and `finish`
//! commits it at a frame boundary.

use crate::error::UserError;
use crate::graph::executor::Timing;
use crate::machines::{self, Profile};
use crate::session::frame_loop::{FrameLoop, FrameTarget};
use crate::session::rebuild::{Rebuild, RebuildJob};
use crate::session::{ReloadReport, Session};
use crate::viewer::panels::Action;

/// What is set when a switch's rebuild is committed.
#[derive(Debug, Clone)]
pub struct SwitchCommit {
    /// The render size it runs at.
    pub size: (u32, u32),
    /// The frame-time target it brings in ms (a profile's), or none.
    pub target_ms: Option<f64>,
    /// What it switches to, for the panel and the event line.
    pub what: String,
    /// The machine profile it selects (its number), if it is one.
    pub profile: Option<usize>,
}

/// A rebuild an action needs, and what its commit sets.
pub struct Switch {
    /// The rebuild, to run on any thread.
    pub job: RebuildJob,
    /// What `finish` sets with it.
    pub commit: SwitchCommit,
}

/// An action's first step: done already, or a rebuild still to run.
pub enum Step {
    /// Applied; the report of a rebuild that ran, if one did.
    Done(Option<ReloadReport>),
    /// A switch whose rebuild is yet to run (`finish` commits it); boxed:
    /// a rebuild job holds the whole compiled graph.
    Switch(Box<Switch>),
}

/// Applies a session-level action. `requested` is the size asked for on
/// the command line (a profile's resolution scale applies to it). Returns
/// the rebuild's report when one ran. Screenshots and opening a scene are
/// the window's, not the session's: they are ignored here.
pub fn apply(session: &mut Session, frames: &mut FrameLoop, profiles: &[Profile], requested: (u32, u32), action: &Action) -> Result<Option<ReloadReport>, UserError> {
    match start(session, frames, profiles, requested, action)? {
        Step::Done(report) => Ok(report),
        Step::Switch(s) => {
            let rebuild = s.job.run()?;
            finish(session, frames, &s.commit, rebuild).map(Some)
        }
    }
}

/// Applies what needs no rebuild at once; returns a graph or profile
/// switch as a `Switch` (nothing of the session changed yet).
pub fn start(session: &mut Session, frames: &mut FrameLoop, profiles: &[Profile], requested: (u32, u32), action: &Action) -> Result<Step, UserError> {
    match action {
        Action::SetParam { pass, name, value } => session.set_param(pass, name, value.clone()).map(|_| Step::Done(None)),
        Action::SetEnabled { pass, enabled } => session.set_enabled(pass, *enabled).map(|r| Step::Done(Some(r))),
        Action::SetGraph(path) => {
            // A graph picked by hand runs as `--graph` runs it: at the size
            // asked for, without a profile's scale, params or frame-time
            // target; graph and size in one rebuild, all of it or nothing.
            let commit = SwitchCommit { size: requested, target_ms: None, what: path.display().to_string(), profile: None };
            Ok(Step::Switch(Box::new(Switch { job: session.switch_job(path, Vec::new()), commit })))
        }
        Action::SetProfile(i) => {
            let p = profiles.get(*i).ok_or_else(|| UserError::new(format!("no machine profile number {i}")))?;
            // A bad target is refused before anything is built.
            FrameTarget::new(f64::from(p.target_ms))?;
            let commit = SwitchCommit {
                size: machines::scale_size(requested, p.resolution_scale),
                target_ms: Some(f64::from(p.target_ms)),
                what: format!("the {} profile", p.name),
                profile: Some(*i),
            };
            Ok(Step::Switch(Box::new(Switch { job: session.switch_job(&machines::profile_graph(p), machines::param_sets(p)?), commit })))
        }
        Action::SetSize { requested, scale } => {
            if !(scale.is_finite() && *scale > 0.0) {
                return Err(UserError::new(format!("resolution scale {scale}: give a number above 0")));
            }
            session.resize(machines::scale_size(*requested, *scale)).map(|r| Step::Done(Some(r)))
        }
        Action::SetTarget(ms) => {
            frames.target = ms.map(FrameTarget::new).transpose()?;
            Ok(Step::Done(None))
        }
        Action::SetSampleTarget(n) => {
            frames.sample_target = *n;
            Ok(Step::Done(None))
        }
        Action::Pause(p) => {
            frames.paused = *p;
            Ok(Step::Done(None))
        }
        Action::Profile(on) => {
            session.timing = Timing::for_adapter(&session.gpu, *on);
            frames.stats.last.clear();
            Ok(Step::Done(None))
        }
        Action::Screenshot | Action::MeasureReuse | Action::OpenScene(_) => Ok(Step::Done(None)),
    }
}

/// Commits a switch's finished rebuild at its size, with its frame-time
/// target; on failure nothing changes.
pub fn finish(session: &mut Session, frames: &mut FrameLoop, commit: &SwitchCommit, rebuild: Rebuild) -> Result<ReloadReport, UserError> {
    let target = commit.target_ms.map(FrameTarget::new).transpose()?;
    let report = session.commit_sized(rebuild, commit.size)?;
    frames.target = target;
    Ok(report)
}
