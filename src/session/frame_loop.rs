//! The one frame loop every front end uses: scene time (fixed steps for
//! headless renders, the wall clock in the viewer, pausable), the camera
//! path, the PID controller on the measured frame time, and the timing
//! statistics by pass name.

use std::collections::BTreeMap;
use std::time::Instant;

use crate::camera_path::CameraPath;
use crate::control::{Pid, PidConfig};
use crate::error::UserError;
use crate::graph::executor::{FrameHook, PassTimings, Timing};
use crate::metrics::median;
use crate::scene::Camera;
use crate::session::{Session, DEFAULT_MASK_THRESHOLD};

/// How scene time advances from frame to frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clock {
    /// By a fixed step (headless renders: reproducible).
    Fixed {
        /// Scene seconds per frame (0: time stands still).
        dt: f32,
    },
    /// By the wall-clock time between frames (the viewer).
    Real,
}

/// A frame-time target driving the noise-mask threshold.
pub struct FrameTarget {
    /// The frame time to hold, milliseconds (finite, positive).
    pub target_ms: f64,
    /// Sets `Session::mask_threshold` from the measured frame time.
    pub pid: Pid,
}

impl FrameTarget {
    /// A target of `target_ms` milliseconds, the PID starting at
    /// `DEFAULT_MASK_THRESHOLD`; an error unless finite and positive.
    pub fn new(target_ms: f64) -> Result<FrameTarget, UserError> {
        if !(target_ms.is_finite() && target_ms > 0.0) {
            return Err(UserError::new(format!("frame-time target {target_ms} ms: give a positive number of milliseconds")));
        }
        Ok(FrameTarget { target_ms, pid: Pid::new(PidConfig::frame_time(), f64::from(DEFAULT_MASK_THRESHOLD)) })
    }
}

/// Per-frame figures, kept for reports and the viewer's plots.
#[derive(Debug, Clone, Default)]
pub struct FrameStats {
    /// Wall milliseconds of each frame (recording and submission, and the
    /// wait when the timing mode waits).
    pub frame_ms: Vec<f64>,
    /// Milliseconds per pass, by name, in the order first seen.
    pub pass_ms: Vec<(String, Vec<f64>)>,
    /// The last frame's timings that arrived, by pass name.
    pub last: BTreeMap<String, f64>,
    /// The mask threshold after each frame.
    pub thresholds: Vec<f32>,
}

impl FrameStats {
    fn record(&mut self, t: &PassTimings) {
        self.last.clear();
        for (name, ms) in &t.passes {
            self.last.insert(name.clone(), *ms);
            match self.pass_ms.iter_mut().find(|(n, _)| n == name) {
                Some((_, v)) => v.push(*ms),
                None => self.pass_ms.push((name.clone(), vec![*ms])),
            }
        }
    }

    /// Median of every pass that was timed, in first-seen order.
    pub fn pass_medians(&self) -> Vec<(String, f64)> {
        self.pass_ms.iter().map(|(n, v)| (n.clone(), median(v))).collect()
    }
}

/// What one step did.
#[derive(Debug, Clone)]
pub struct FrameReport {
    /// Scene time of the frame, seconds.
    pub time: f32,
    /// Wall milliseconds of the step (0 when it rendered nothing).
    pub wall_ms: f64,
    /// Timings that arrived during this step (possibly of earlier frames).
    pub timings: Vec<PassTimings>,
}

/// Drives a `Session` frame after frame (`step`): scene time, the camera
/// path, the frame-time target, the sample target and the statistics.
pub struct FrameLoop {
    /// Scene time of the next frame, seconds.
    pub time: f32,
    /// How `time` advances.
    pub clock: Clock,
    /// While paused, scene time stands still (the camera still moves).
    pub paused: bool,
    /// Moves the camera by scene time (None: it stays where it is put).
    pub camera_path: Option<CameraPath>,
    /// The camera the path starts from.
    pub base_camera: Camera,
    /// Drives the noise-mask threshold (None: the threshold stays as set).
    pub target: Option<FrameTarget>,
    /// Every step's figures so far.
    pub stats: FrameStats,
    /// The last step's wall time was longer than scene time may advance
    /// in one frame (MAX_STEP_S): animations run slower than the clock.
    pub slowed: bool,
    /// Frames to accumulate, after which a still image renders no more
    /// (None: render every step).
    pub sample_target: Option<u32>,
    /// The last step rendered nothing: the sample target was reached.
    pub converged: bool,
    last_step: Option<Instant>,
}

/// The most scene time one frame of the real clock advances: a stall (a
/// window drag, a breakpoint, a multi-second frame) is not a jump.
pub const MAX_STEP_S: f32 = 0.25;

impl FrameLoop {
    /// Starts at scene time `time` seconds: not paused, no camera path,
    /// frame-time target or sample target.
    pub fn new(time: f32, clock: Clock, base_camera: Camera) -> FrameLoop {
        FrameLoop {
            time,
            clock,
            paused: false,
            camera_path: None,
            base_camera,
            target: None,
            stats: FrameStats::default(),
            slowed: false,
            sample_target: None,
            converged: false,
            last_step: None,
        }
    }

    /// Renders one frame: camera from the path, the frame, the PID update
    /// from the measured time, statistics; then advances the clock.
    pub fn step(&mut self, session: &mut Session) -> FrameReport {
        self.step_with(session, None)
    }

    /// `step`, with `hook` recorded after the frame's passes (see
    /// `Session::frame_with`); not called when the step renders nothing.
    pub fn step_with(&mut self, session: &mut Session, hook: Option<FrameHook<'_>>) -> FrameReport {
        let now = Instant::now();
        self.converged = self.camera_path.is_none() && self.sample_target.is_some_and(|n| session.accumulated() >= n) && session.still();
        if self.converged {
            self.last_step = Some(now);
            return FrameReport { time: self.time, wall_ms: 0.0, timings: Vec::new() };
        }
        if self.clock == Clock::Real && !self.paused {
            if let Some(last) = self.last_step {
                let wall = now.duration_since(last).as_secs_f32();
                self.slowed = wall > MAX_STEP_S;
                self.time += wall.min(MAX_STEP_S);
            }
        }
        self.last_step = Some(now);
        if let Some(path) = &self.camera_path {
            session.scene.scene.camera = path.at(&self.base_camera, self.time);
        }
        let time = self.time;
        if self.sample_target.is_some_and(|n| session.accumulated().saturating_add(1) >= n) {
            // The last frame before the loop stops at its target: shown
            // in full, as it stays on screen.
            session.show_next_in_full();
        }
        let timings = session.frame_with(time, hook);
        let wall_ms = now.elapsed().as_secs_f64() * 1e3;
        self.stats.frame_ms.push(wall_ms);
        for t in &timings {
            self.stats.record(t);
        }
        if let Some(target) = &mut self.target {
            // GPU time where timestamps bracket the work (it arrives a
            // frame or two late), else wall time.
            let measured = match session.timing {
                Timing::Gpu => timings.last().map(PassTimings::total),
                _ => Some(wall_ms),
            };
            if let Some(ms) = measured {
                session.mask_threshold = target.pid.update(target.target_ms, ms, wall_ms / 1e3) as f32;
            }
        }
        self.stats.thresholds.push(session.mask_threshold);
        if let Clock::Fixed { dt } = self.clock {
            if !self.paused {
                self.time += dt;
            }
        }
        FrameReport { time, wall_ms, timings }
    }

    /// Waits for the frames in flight and records their timings.
    pub fn finish(&mut self, session: &mut Session) {
        for t in session.finish() {
            self.stats.record(&t);
        }
    }
}
