//! What a panel action does to the session: the same calls the tests and
//! the CLI make (`set_param`, `set_enabled`, `set_graph`,
//! `switch_profile`), so a click in the viewer and a test do the same.

use crate::error::UserError;
use crate::graph::executor::Timing;
use crate::machines::{self, Profile};
use crate::session::frame_loop::{FrameLoop, FrameTarget};
use crate::session::{ReloadReport, Session};
use crate::viewer::panels::Action;

/// Applies a session-level action. `requested` is the size asked for on
/// the command line (a profile's resolution scale applies to it). Returns
/// the rebuild's report when one ran. Screenshots are the window's, not
/// the session's: they are ignored here.
pub fn apply(session: &mut Session, frames: &mut FrameLoop, profiles: &[Profile], requested: (u32, u32), action: &Action) -> Result<Option<ReloadReport>, UserError> {
    match action {
        Action::SetParam { pass, name, value } => session.set_param(pass, name, value.clone()).map(|_| None),
        Action::SetEnabled { pass, enabled } => session.set_enabled(pass, *enabled).map(Some),
        Action::SetGraph(path) => {
            // A graph picked by hand runs as `--graph` runs it: at the size
            // asked for, without a profile's scale, params or frame-time
            // target; graph and size in one rebuild, all of it or nothing.
            let report = session.switch_profile(path, Vec::new(), requested)?;
            frames.target = None;
            Ok(Some(report))
        }
        Action::SetProfile(i) => {
            let p = profiles.get(*i).ok_or_else(|| UserError::new(format!("no machine profile number {i}")))?;
            let report = session.switch_profile(&machines::profile_graph(p), machines::param_sets(p)?, machines::scale_size(requested, p.resolution_scale))?;
            frames.target = Some(FrameTarget::new(f64::from(p.target_ms))?);
            Ok(Some(report))
        }
        Action::Pause(p) => {
            frames.paused = *p;
            Ok(None)
        }
        Action::Profile(on) => {
            session.timing = Timing::for_adapter(&session.gpu, *on);
            frames.stats.last.clear();
            Ok(None)
        }
        Action::Screenshot | Action::MeasureReuse => Ok(None),
    }
}
