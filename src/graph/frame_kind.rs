//! Per-frame specialisations: override constants the engine sets each
//! frame from what kind of frame it is.
//!
//! A CPU driver runs both sides of a branch under lane masks, so a branch
//! that no pixel takes this frame (reprojecting a camera that did not
//! move, testing gradients of a scene that did not change) still costs its
//! arithmetic. A shader that declares one of these bool overrides (default
//! false: the generic shader, right for any frame) gets a pipeline per
//! kind of frame it can tell apart, and the executor records the one that
//! fits the frame (`CachedPipeline::for_frame`). Each flag set must leave
//! the shader's results exactly as the generic shader computes them in
//! such a frame: it only removes code whose branch the frame's uniform
//! already decides.

/// Set in frames whose camera is bit for bit last frame's (a pixel's
/// history is then its own texel).
pub const CAMERA_STILL: &str = "CAMERA_STILL";
/// Set in frames whose scene did not change since last frame, or that
/// have no last frame (`frame.epoch_frames > 0 || frame.history_frames
/// == 0`: nothing moved since the history was made).
pub const SCENE_STILL: &str = "SCENE_STILL";
/// Set in frames without history (`frame.history_frames == 0`: a first
/// frame, or the first after a reset).
pub const NO_HISTORY: &str = "NO_HISTORY";

/// Set in frames in which none of the graph's passes that thin their
/// still frames (`ThinWhenStill`) runs (`Executor::thins`), always still
/// ones: a pass that feeds only them may leave out what they alone read
/// (THIN_STORES, shaders/realtime/path.wgsl).
pub const THINNED: &str = "THINNED";

/// Every per-frame constant; a graph cannot set them.
pub const FRAME_CONSTANTS: [&str; 4] = [CAMERA_STILL, SCENE_STILL, NO_HISTORY, THINNED];

/// What a frame is, as the per-frame constants say it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrameKind {
    /// The camera is bit for bit last frame's.
    pub camera_still: bool,
    /// The scene did not change since last frame (or there is none).
    pub scene_still: bool,
    /// The frame has no history.
    pub no_history: bool,
    /// The graph's thinning passes all skip the frame (a still frame with
    /// history).
    pub thinned: bool,
}

/// Which of FRAME_CONSTANTS a shader declares, in that order.
pub type Declared = [bool; 4];

impl FrameKind {
    /// The generic kind: no flag set.
    pub const GENERIC: FrameKind = FrameKind { camera_still: false, scene_still: false, no_history: false, thinned: false };

    fn flags(self) -> [bool; 4] {
        [self.camera_still, self.scene_still, self.no_history, self.thinned]
    }

    fn from_flags(f: [bool; 4]) -> FrameKind {
        FrameKind { camera_still: f[0], scene_still: f[1], no_history: f[2], thinned: f[3] }
    }

    /// The flags a shader declaring `declared` tells apart in this frame:
    /// those it does not declare dropped, and where it declares
    /// NO_HISTORY a frame without history sets only that (it needs no
    /// other: nothing is reprojected or tested against a history).
    pub fn seen_by(self, declared: Declared) -> FrameKind {
        if self.no_history && declared[2] {
            return FrameKind { no_history: true, ..Self::GENERIC };
        }
        let f = self.flags();
        // THINNED only in a still frame (where the engine sets it): one
        // pipeline more, not one per camera and scene flag.
        let thinned = f[3] && declared[3] && f[0] && f[1];
        FrameKind::from_flags([f[0] && declared[0], f[1] && declared[1], false, thinned])
    }

    /// The kinds a shader declaring `declared` gets a pipeline for besides
    /// the generic one: every combination of its camera and scene flags,
    /// a still frame that is THINNED, and NO_HISTORY alone.
    pub fn variants(declared: Declared) -> Vec<FrameKind> {
        let mut out = Vec::new();
        for camera_still in [false, true] {
            for scene_still in [false, true] {
                for thinned in [false, true] {
                    let k = FrameKind { camera_still, scene_still, no_history: false, thinned }.seen_by(declared);
                    if k != Self::GENERIC && !out.contains(&k) {
                        out.push(k);
                    }
                }
            }
        }
        if declared[2] {
            out.push(FrameKind { no_history: true, ..Self::GENERIC });
        }
        out
    }

    /// The flags set, as pipeline constants (the others keep their
    /// default, false).
    pub fn constants(self) -> Vec<(&'static str, f64)> {
        FRAME_CONSTANTS.iter().zip(self.flags()).filter(|(_, on)| *on).map(|(k, _)| (*k, 1.0)).collect()
    }
}

/// Which per-frame constants a shader with these override names declares.
pub fn declared<'a>(overrides: impl IntoIterator<Item = &'a str> + Clone) -> Declared {
    FRAME_CONSTANTS.map(|c| overrides.clone().into_iter().any(|o| o == c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shader_gets_a_pipeline_per_kind_of_frame_it_tells_apart() {
        assert!(FrameKind::variants([false; 4]).is_empty());
        let camera = FrameKind { camera_still: true, ..FrameKind::GENERIC };
        assert_eq!(FrameKind::variants([true, false, false, false]), vec![camera]);
        // Camera and scene: three besides the generic one; with
        // NO_HISTORY, a fourth; with THINNED, a fifth (still frames only).
        assert_eq!(FrameKind::variants([true, true, false, false]).len(), 3);
        let all = FrameKind::variants([true, true, true, false]);
        assert_eq!(all.len(), 4);
        assert!(all.contains(&FrameKind { no_history: true, ..FrameKind::GENERIC }));
        let thin = FrameKind::variants([true, true, true, true]);
        assert_eq!(thin.len(), 5);
        assert!(thin.contains(&FrameKind { camera_still: true, scene_still: true, thinned: true, ..FrameKind::GENERIC }));
        // A shader that tells apart only THINNED: one pipeline more.
        assert_eq!(FrameKind::variants([false, false, false, true]), vec![FrameKind { thinned: true, ..FrameKind::GENERIC }]);
    }

    #[test]
    fn a_frame_is_seen_only_through_the_flags_a_shader_declares() {
        let first = FrameKind { camera_still: true, scene_still: true, no_history: true, thinned: false };
        // A shader that knows NO_HISTORY needs nothing else there...
        assert_eq!(first.seen_by([true, true, true, true]), FrameKind { no_history: true, ..FrameKind::GENERIC });
        // ...one that does not still takes its still-camera pipeline.
        assert_eq!(first.seen_by([true, false, false, false]), FrameKind { camera_still: true, ..FrameKind::GENERIC });
        assert_eq!(first.seen_by([false; 4]), FrameKind::GENERIC);
        // A thinned frame is a still one; a shader that knows only THINNED
        // sees only that.
        let thinned = FrameKind { camera_still: true, scene_still: true, no_history: false, thinned: true };
        assert_eq!(thinned.seen_by([false, false, false, true]), FrameKind { thinned: true, ..FrameKind::GENERIC });
        assert_eq!(thinned.seen_by([true, true, true, false]), FrameKind { thinned: false, ..thinned });
        // Whatever the frame, what a shader sees is one of its pipelines.
        let bits = |f: u8| [f & 1 != 0, f & 2 != 0, f & 4 != 0, f & 8 != 0];
        for f in 0..16u8 {
            let kind = FrameKind::from_flags(bits(f));
            for d in 0..16u8 {
                let declared = bits(d);
                let seen = kind.seen_by(declared);
                assert!(seen == FrameKind::GENERIC || FrameKind::variants(declared).contains(&seen), "{kind:?} seen by {declared:?}");
            }
        }
    }

    #[test]
    fn the_constants_are_the_flags_set() {
        assert!(FrameKind::GENERIC.constants().is_empty());
        assert_eq!(FrameKind { scene_still: true, no_history: true, ..FrameKind::GENERIC }.constants(), vec![(SCENE_STILL, 1.0), (NO_HISTORY, 1.0)]);
        assert_eq!(FrameKind { thinned: true, ..FrameKind::GENERIC }.constants(), vec![(THINNED, 1.0)]);
        assert_eq!(declared(["STEP", "NO_HISTORY"]), [false, false, true, false]);
    }
}
