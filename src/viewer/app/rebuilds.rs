//! What the viewer does with rebuilds: a scene opened (dropped, or picked
//! in the panel), a graph or profile switch built off this thread
//! (`background`), a panel action, a finished hot reload, and the error
//! overlay when one fails.

use std::path::PathBuf;
use std::time::Instant;

use super::Viewer;
use crate::session::rebuild::{RebuildJob, RebuildKind};
use crate::stats::{ReuseShare, REFLECT_REUSE};
use crate::viewer::actions::{self, Step, Switch};
use crate::viewer::background::{After, Pending};
use crate::viewer::camera::CameraControl;
use crate::viewer::panels::Action;
use crate::viewer::reloader::Reloader;

impl Viewer {
    /// Opens another scene file (dropped on the window): its camera, its
    /// lights; the graph stays. It loads off this thread; a file that
    /// fails to load leaves the running scene as it was, with the error in
    /// the overlay.
    pub(super) fn open_scene(&mut self, path: PathBuf) {
        if !crate::scene::opens(&path) {
            let hint = "the viewer opens a .ron scene file, an .obj mesh or a .gltf/.glb file (docs/scenes.md)";
            self.show_error(format!("{}: not a scene file: {hint}", path.display()));
            return;
        }
        let job = self.session.job(RebuildKind::OpenScene(path.clone()));
        self.start_pending(job, path.display().to_string(), After::OpenScene(path));
    }

    pub(super) fn start_pending(&mut self, job: RebuildJob, what: String, after: After) {
        // The same switch asked for again while it builds (a second click,
        // an Enter and a click) is not built twice.
        if self.pending.as_ref().is_some_and(|p| p.what == what) {
            return;
        }
        // A newer switch supersedes one still building (its result is dropped).
        match Pending::start(job, what, after) {
            Ok(p) => self.pending = Some(p),
            Err(e) => self.show_error(e.to_string()),
        }
    }

    /// Commits a switch whose rebuild finished, at this frame boundary.
    pub(super) fn poll_pending(&mut self) {
        let Some(result) = self.pending.as_ref().and_then(Pending::poll) else { return };
        let Some(pending) = self.pending.take() else { return };
        let ms = pending.started.elapsed().as_secs_f64() * 1e3;
        match pending.after {
            After::Switch(commit) => match result.and_then(|r| actions::finish(&mut self.session, &mut self.frames, &commit, r)) {
                Ok(report) => {
                    self.panel.active_profile = commit.profile;
                    self.panel.scale = commit.profile.and_then(|i| self.panel.profiles.get(i)).map_or(1.0, |p| p.resolution_scale);
                    self.overlay = None;
                    let gap = self.presents.longest_gap_since(pending.started, Instant::now());
                    let line = format!("switched to {}: {} in {ms:.0} ms (longest gap between frames {gap:.0} ms)", commit.what, report.passes_rebuilt());
                    let line = crate::reload::relative_to_cwd(&line);
                    self.announce = Some((line.clone(), self.session.generation));
                    self.last_reload = Some(line);
                    self.refresh_reloader();
                }
                Err(e) => self.show_error(format!("{e} (keeping the running graph)")),
            },
            After::OpenScene(path) => match result.and_then(|r| self.session.commit(r)) {
                Ok(report) => {
                    self.frames.base_camera = self.session.scene.scene.camera;
                    self.control = CameraControl::for_scene(&self.frames.base_camera, self.session.scene.scene.bounds());
                    self.window.set_title(&format!("glint: {} ({})", path.display(), self.gpu.info.name));
                    self.scene_path = path;
                    self.overlay = None;
                    self.last_reload = Some(format!("opened {} ({} in {ms:.0} ms)", self.scene_path.display(), report.passes_rebuilt()));
                    println!("opened {}", self.scene_path.display());
                    let shown = crate::reload::relative_to_cwd(&self.scene_path.display().to_string());
                    self.notice = Some((format!("opened {shown}: its camera and lights, the graph as it was"), Instant::now()));
                    self.refresh_reloader();
                }
                Err(e) => self.show_error(format!("{e} (keeping the scene shown)")),
            },
        }
    }

    /// Applies a panel or key action through the session's calls.
    pub(super) fn apply(&mut self, action: Action) {
        match &action {
            Action::Screenshot => self.screenshot_requested = true,
            Action::OpenScene(path) => {
                self.open_scene(path.clone());
                return;
            }
            Action::MeasureReuse => {
                self.panel.reuse = Some(match self.session.read_resource(REFLECT_REUSE) {
                    Some(Ok(img)) => {
                        let s = ReuseShare::of(&img);
                        format!("{:.1}% of {} specular pixels reused", s.share() * 100.0, s.specular)
                    }
                    Some(Err(e)) => e.to_string(),
                    None => "no reuse record in this graph".into(),
                });
            }
            _ => {}
        }
        match actions::start(&mut self.session, &mut self.frames, &self.panel.profiles, self.options.size, &action) {
            Ok(Step::Switch(s)) => {
                let Switch { job, commit } = *s;
                let what = commit.what.clone();
                self.start_pending(job, what, After::Switch(commit));
            }
            Ok(Step::Done(Some(report))) => {
                if let Action::SetSize { requested, .. } = action {
                    self.options.size = requested;
                    self.panel.requested = requested;
                }
                self.overlay = None;
                self.last_reload = Some(format!("{} in {:.0} ms", report.passes_rebuilt(), report.ms));
                self.refresh_reloader();
            }
            Ok(Step::Done(None)) => {
                if matches!(action, Action::SetParam { .. }) {
                    self.refresh_reloader();
                }
            }
            Err(e) => self.show_error(e.to_string()),
        }
    }

    pub(super) fn show_error(&mut self, message: String) {
        let message = crate::reload::relative_to_cwd(&message);
        if self.overlay.as_deref() != Some(message.as_str()) {
            eprintln!("error: {message}");
        }
        self.overlay = Some(message);
    }

    /// Commits a rebuild the reload thread finished, at this frame
    /// boundary.
    pub(super) fn poll_reload(&mut self) {
        let Some(finished) = self.reloader.as_ref().and_then(Reloader::finished) else { return };
        match finished.result.and_then(|r| self.session.commit(r)) {
            Ok(report) => {
                let line = format!(
                    "reloaded {}: {} in {:.0} ms ({} frames presented meanwhile, longest gap between frames {:.0} ms, frame time {:.0} ms)",
                    finished.what,
                    report.passes_rebuilt(),
                    finished.started.elapsed().as_secs_f64() * 1e3,
                    finished.frames,
                    self.presents.longest_gap_since(finished.started, Instant::now()),
                    self.presents.frame_ms_before(finished.started)
                );
                let line = crate::reload::relative_to_cwd(&line);
                self.announce = Some((line.clone(), self.session.generation));
                self.last_reload = Some(line);
                self.overlay = None;
            }
            Err(e) => self.show_error(format!("{e} (keeping the last good {})", finished.kind)),
        }
        self.refresh_reloader();
    }

    pub(super) fn refresh_reloader(&self) {
        if let Some(r) = &self.reloader {
            r.refresh(&self.session);
        }
    }
}
