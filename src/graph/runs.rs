//! Which passes run in a frame and how many times (`RunMode`), and the
//! `run` uniform each dispatch sees. Pure: the executor asks `plan` for a
//! frame's dispatches and writes the records it returns.

use bytemuck::{Pod, Zeroable};

use crate::graph::desc::RunMode;

/// `struct Run` in `shaders/shared/run.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct RunGpu {
    /// Dispatches of this pass since the graph was built or restarted.
    pub iteration: u32,
    /// Dispatches since the scene last changed (0: the first after a
    /// change, where a progressive pass starts over).
    pub since_change: u32,
    /// This dispatch's index within the frame.
    pub index: u32,
    /// Dispatches of this pass this frame.
    pub count: u32,
}

/// Bytes of one `RunGpu` record.
pub const RUN_BYTES: u64 = std::mem::size_of::<RunGpu>() as u64;

/// One pass's counters across frames.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RunState {
    /// Dispatches since the graph was built or restarted.
    pub iteration: u32,
    /// Dispatches since the scene last changed.
    pub since_change: u32,
    /// The scene epoch the pass last ran with; None before its first run.
    pub last_epoch: Option<u32>,
}

impl RunState {
    /// This frame's dispatches of a pass running `mode` with the scene at
    /// `epoch`, and the state after them; `inputs_ran`: a pass writing one
    /// of its inputs ran earlier this frame; `has_history`: the frame has a
    /// last frame to compare with; `still`: frames the image has stood
    /// still before this one (None: a frame shown in full, where every
    /// pass that thins its frames runs).
    pub fn plan(self, mode: RunMode, epoch: u32, inputs_ran: bool, has_history: bool, still: Option<u32>) -> (Vec<RunGpu>, RunState) {
        let changed = self.last_epoch != Some(epoch);
        let since = if changed { 0 } else { self.since_change };
        let count = match mode {
            RunMode::EveryFrame => 1,
            RunMode::Once => u32::from(self.last_epoch.is_none()),
            RunMode::OnSceneChange => u32::from(changed),
            RunMode::OnSceneChangeWithHistory if !has_history => {
                // Nothing to compare with; the scene as it is now is what
                // the next frame's change is measured from.
                return (Vec::new(), RunState { last_epoch: Some(epoch), ..self });
            }
            RunMode::OnSceneChangeWithHistory => u32::from(changed),
            RunMode::OnInputChange => u32::from(self.last_epoch.is_none() || inputs_ran),
            RunMode::ThinWhenStill { .. } => u32::from(mode.thin_runs(still) == Some(true)),
            RunMode::Progressive { per_frame, until: None } => per_frame,
            RunMode::Progressive { per_frame, until: Some(u) } => per_frame.min(u.saturating_sub(since)),
        };
        if count == 0 {
            return (Vec::new(), self);
        }
        let records = (0..count)
            .map(|k| RunGpu { iteration: self.iteration.wrapping_add(k), since_change: since.saturating_add(k), index: k, count })
            .collect();
        let next = RunState { iteration: self.iteration.wrapping_add(count), since_change: since.saturating_add(count), last_epoch: Some(epoch) };
        (records, next)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(mode: RunMode, epochs: &[u32]) -> Vec<Vec<(u32, u32)>> {
        let mut st = RunState::default();
        epochs
            .iter()
            .map(|&e| {
                let (records, next) = st.plan(mode, e, false, true, Some(0));
                st = next;
                records.iter().map(|r| (r.iteration, r.since_change)).collect()
            })
            .collect()
    }

    #[test]
    fn every_frame_runs_once_a_frame() {
        assert_eq!(run(RunMode::EveryFrame, &[0, 0, 1]), vec![vec![(0, 0)], vec![(1, 1)], vec![(2, 0)]]);
    }

    #[test]
    fn once_runs_in_the_first_frame_only() {
        assert_eq!(run(RunMode::Once, &[0, 0, 5, 6]), vec![vec![(0, 0)], vec![], vec![], vec![]]);
    }

    #[test]
    fn on_scene_change_runs_when_the_epoch_moves() {
        let got = run(RunMode::OnSceneChange, &[0, 0, 1, 1, 1, 2]);
        assert_eq!(got.iter().map(Vec::len).collect::<Vec<_>>(), vec![1, 0, 1, 0, 0, 1]);
        assert_eq!(got[2], vec![(1, 0)]);
    }

    #[test]
    fn with_history_skips_frames_without_one_and_tracks_the_epoch() {
        let mut st = RunState::default();
        let mut counts = Vec::new();
        // (epoch, has_history): a start, still frames, a change, a reset
        // with a change, then a still frame after it.
        for (epoch, history) in [(0, false), (0, true), (1, true), (1, true), (2, false), (2, true)] {
            let (records, next) = st.plan(RunMode::OnSceneChangeWithHistory, epoch, false, history, Some(0));
            st = next;
            counts.push(records.len());
        }
        assert_eq!(counts, vec![0, 0, 1, 0, 0, 0]);
        // Kept across a rebuild with history: the first frame runs.
        let (records, _) = RunState::default().plan(RunMode::OnSceneChangeWithHistory, 5, false, true, Some(0));
        assert_eq!(records.len(), 1);
    }

    #[test]
    fn on_input_change_runs_after_its_inputs_changed() {
        let mut st = RunState::default();
        let mut counts = Vec::new();
        for inputs_ran in [false, false, true, false, true] {
            let (records, next) = st.plan(RunMode::OnInputChange, 0, inputs_ran, true, Some(0));
            st = next;
            counts.push(records.len());
        }
        assert_eq!(counts, vec![1, 0, 1, 0, 1]);
    }

    #[test]
    fn progressive_counts_to_until_and_restarts_on_change() {
        let mode = RunMode::Progressive { per_frame: 3, until: Some(7) };
        let got = run(mode, &[0, 0, 0, 0, 1, 1]);
        let since: Vec<Vec<u32>> = got.iter().map(|f| f.iter().map(|r| r.1).collect()).collect();
        assert_eq!(since, vec![vec![0, 1, 2], vec![3, 4, 5], vec![6], vec![], vec![0, 1, 2], vec![3, 4, 5]]);
        // The iteration keeps counting across the change.
        assert_eq!(got[4][0].0, 7);
        let forever = run(RunMode::Progressive { per_frame: 2, until: None }, &[0, 0, 0]);
        assert_eq!(forever.iter().map(Vec::len).collect::<Vec<_>>(), vec![2, 2, 2]);
    }

    #[test]
    fn records_number_the_dispatches_of_a_frame() {
        let (records, _) = RunState::default().plan(RunMode::Progressive { per_frame: 4, until: None }, 0, false, true, Some(0));
        assert_eq!(records.iter().map(|r| (r.index, r.count)).collect::<Vec<_>>(), vec![(0, 4), (1, 4), (2, 4), (3, 4)]);
    }

    #[test]
    fn thin_when_still_runs_every_frame_then_one_in_every() {
        let mode = RunMode::ThinWhenStill { after: 4, every: 3 };
        let counts: Vec<usize> = (0..12).map(|s| RunState::default().plan(mode, 0, false, true, Some(s)).0.len()).collect();
        assert_eq!(counts, vec![1, 1, 1, 1, 0, 0, 1, 0, 0, 1, 0, 0]);
        // A frame shown in full runs it whatever the count.
        assert_eq!(RunState::default().plan(mode, 0, false, true, None).0.len(), 1);
        // `every: 0` is refused by the compiler; here it counts as 1.
        let zero = RunMode::ThinWhenStill { after: 0, every: 0 };
        assert_eq!(RunState::default().plan(zero, 0, false, true, Some(7)).0.len(), 1);
    }
}
