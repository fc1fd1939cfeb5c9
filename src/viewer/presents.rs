//! When the viewer's frames reached the screen, and what the panel says
//! about it: frames per second and the frame-time plot come from the wall
//! time between presents (what a user sees), not from the CPU's recording
//! time, which on a CPU adapter is a small part of the frame. Pure (unit
//! tested without a window).

use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// The frames per second shown cover at most this much recent time...
const FPS_WINDOW: Duration = Duration::from_secs(2);
/// ...and at most this many frames.
const FPS_FRAMES: usize = 60;
/// Intervals kept for the plot and the reload reports.
const KEPT: usize = 300;

/// The times the viewer's frames were presented (the last 300), and the
/// rates and intervals the panel shows from them.
#[derive(Debug, Default)]
pub struct Presents {
    /// When each of the last frames was presented.
    times: VecDeque<Instant>,
    /// Milliseconds between consecutive presents, oldest first, with the
    /// index of the frame each one ended.
    intervals: VecDeque<(u64, f64)>,
    count: u64,
}

impl Presents {
    /// Records a frame presented at `t`.
    pub fn push(&mut self, t: Instant) {
        if let Some(&last) = self.times.back() {
            self.intervals.push_back((self.count, t.saturating_duration_since(last).as_secs_f64() * 1e3));
            if self.intervals.len() > KEPT {
                self.intervals.pop_front();
            }
        }
        self.times.push_back(t);
        if self.times.len() > KEPT {
            self.times.pop_front();
        }
        self.count += 1;
    }

    /// Frames presented so far.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Frames per second over the recent frames (up to two seconds or 60
    /// frames), counting the time since the last present once it is longer
    /// than the frames were, so a stalled frame shows as a falling rate;
    /// None before two frames.
    pub fn fps(&self, now: Instant) -> Option<f64> {
        let last = *self.times.back()?;
        let first = self
            .times
            .iter()
            .rev()
            .take(FPS_FRAMES)
            .take_while(|&&t| last.saturating_duration_since(t) <= FPS_WINDOW)
            .last()
            .copied()
            .filter(|&t| t < last)
            .or_else(|| self.times.iter().rev().nth(1).copied())?;
        let frames = self.times.iter().filter(|&&t| t > first && t <= last).count() as f64;
        let span = last.saturating_duration_since(first).as_secs_f64();
        let waiting = now.saturating_duration_since(last).as_secs_f64();
        let per_frame = span / frames;
        if per_frame.is_nan() || per_frame <= 0.0 {
            return None;
        }
        // A frame still rendering for longer than the recent ones counts.
        let span = if waiting > per_frame { span + waiting - per_frame } else { span };
        Some(frames / span)
    }

    /// The plot's points: (frame index, milliseconds since the frame before).
    pub fn plot(&self) -> Vec<egui_plot::PlotPoint> {
        self.intervals.iter().map(|&(i, ms)| egui_plot::PlotPoint::new(i as f64, ms)).collect()
    }

    /// The last interval in milliseconds.
    pub fn last_ms(&self) -> Option<f64> {
        self.intervals.back().map(|&(_, ms)| ms)
    }

    /// The mean of the last `n` intervals, milliseconds (0 with none).
    pub fn mean_ms(&self, n: usize) -> f64 {
        let v: Vec<f64> = self.intervals.iter().rev().take(n).map(|&(_, ms)| ms).collect();
        if v.is_empty() { 0.0 } else { v.iter().sum::<f64>() / v.len() as f64 }
    }

    /// The median of the last `n` intervals, milliseconds.
    pub fn median_ms(&self, n: usize) -> f64 {
        let v: Vec<f64> = self.intervals.iter().rev().take(n).map(|&(_, ms)| ms).collect();
        crate::metrics::median(&v)
    }

    /// The longest time between two presents from `start` to `now` (the
    /// gap from the last present to now included), milliseconds.
    pub fn longest_gap_since(&self, start: Instant, now: Instant) -> f64 {
        let mut last = start;
        let mut gap = 0.0f64;
        for &t in self.times.iter().filter(|&&t| t > start) {
            gap = gap.max(t.saturating_duration_since(last).as_secs_f64());
            last = t;
        }
        gap.max(now.saturating_duration_since(last).as_secs_f64()) * 1e3
    }

    /// The median time between the (up to 30) presents before `before`,
    /// milliseconds.
    pub fn frame_ms_before(&self, before: Instant) -> f64 {
        let times: Vec<&Instant> = self.times.iter().filter(|&&t| t <= before).collect();
        let gaps: Vec<f64> = times.windows(2).map(|w| w[1].saturating_duration_since(*w[0]).as_secs_f64() * 1e3).collect();
        let start = gaps.len().saturating_sub(30);
        crate::metrics::median(&gaps[start..])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t0: Instant, ms: u64) -> Instant {
        t0 + Duration::from_millis(ms)
    }

    #[test]
    fn no_rate_before_two_frames() {
        let t0 = Instant::now();
        let mut p = Presents::default();
        assert_eq!(p.fps(t0), None);
        p.push(t0);
        assert_eq!(p.fps(at(t0, 5)), None);
        assert_eq!(p.last_ms(), None);
    }

    #[test]
    fn a_near_zero_first_interval_does_not_inflate_the_rate() {
        // The bug this replaces: an average seeded by a first interval of
        // almost nothing read 700-1000 FPS while frames took a second.
        let t0 = Instant::now();
        let mut p = Presents::default();
        p.push(t0);
        p.push(at(t0, 1));
        for k in 1..=5 {
            p.push(at(t0, 1 + 1000 * k));
        }
        let fps = p.fps(at(t0, 5001)).expect("a rate");
        assert!((fps - 1.0).abs() < 0.01, "{fps}");
    }

    #[test]
    fn steady_frames_give_their_rate_and_plot() {
        let t0 = Instant::now();
        let mut p = Presents::default();
        for k in 0..100 {
            p.push(at(t0, 50 * k));
        }
        let fps = p.fps(at(t0, 4950)).expect("a rate");
        assert!((fps - 20.0).abs() < 0.01, "{fps}");
        assert_eq!(p.last_ms(), Some(50.0));
        assert_eq!(p.median_ms(10), 50.0);
        let plot = p.plot();
        assert_eq!(plot.len(), 99);
        assert_eq!((plot[0].x, plot[0].y), (1.0, 50.0));
    }

    #[test]
    fn a_stall_moves_the_mean_but_not_the_median() {
        let t0 = Instant::now();
        let mut p = Presents::default();
        // Nine 20 ms frames and one 200 ms stall.
        for (k, ms) in [0, 20, 40, 60, 80, 280, 300, 320, 340, 360, 380].into_iter().enumerate() {
            assert_eq!(p.count(), k as u64);
            p.push(at(t0, ms));
        }
        assert_eq!(p.median_ms(10), 20.0);
        assert!((p.mean_ms(10) - 38.0).abs() < 1e-9, "{}", p.mean_ms(10));
        assert_eq!(Presents::default().mean_ms(5), 0.0);
    }

    #[test]
    fn a_frame_still_rendering_lowers_the_rate() {
        let t0 = Instant::now();
        let mut p = Presents::default();
        for k in 0..10 {
            p.push(at(t0, 100 * k));
        }
        let steady = p.fps(at(t0, 900)).expect("a rate");
        let stalled = p.fps(at(t0, 900 + 3000)).expect("a rate");
        assert!((steady - 10.0).abs() < 0.01, "{steady}");
        assert!(stalled < 3.5, "{stalled}");
    }

    #[test]
    fn gaps_and_recent_frame_time() {
        let t0 = Instant::now();
        let mut p = Presents::default();
        for ms in [0, 100, 200, 700, 800] {
            p.push(at(t0, ms));
        }
        assert_eq!(p.longest_gap_since(at(t0, 150), at(t0, 850)), 500.0);
        assert_eq!(p.frame_ms_before(at(t0, 250)), 100.0);
    }
}
