//! `glint bench frames`: two frame graphs on one scene, frame by frame in
//! turn in one process, and the median of the per-frame time ratios. Two
//! separate `glint render` runs on a machine whose speed swings within
//! minutes differ by 15-50%; frames taken in turn see the same machine.
//! The usual pair is one graph and the same graph in another checkout (a
//! copy with a shader edited): each graph takes its shaders from beside it.

use std::path::PathBuf;

use clap::Args;

use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::executor::Timing;
use crate::metrics::{median, paired_ratios};
use crate::session::frame_loop::{Clock, FrameLoop};
use crate::session::{check_size, Session, SessionOptions};

#[derive(Args, Debug)]
pub struct FramesArgs {
    pub scene: PathBuf,
    /// The graph timed (its shaders: the `shaders` folder beside its own).
    #[arg(long)]
    pub graph: PathBuf,
    /// The graph it is timed against, in turn.
    #[arg(long)]
    pub vs: PathBuf,
    #[arg(long, default_value = "1280x720", value_parser = super::parse_size)]
    pub size: (u32, u32),
    /// Frames timed of each graph, after one untimed.
    #[arg(long, default_value_t = 16)]
    pub frames: u32,
    /// Submit each pass alone and compare the passes too (by name).
    #[arg(long)]
    pub profile: bool,
    /// Start both images over before every timed frame: times each
    /// graph's first frame (pipelines already compiled), as a viewer sees
    /// it after a camera cut.
    #[arg(long)]
    pub first_frames: bool,
}

/// One of the two graphs: its session, its frames, and each frame's wall
/// milliseconds until the device finished it.
struct Side {
    session: Session,
    frames: FrameLoop,
    frame_ms: Vec<f64>,
}

impl Side {
    fn new(gpu: &Gpu, args: &FramesArgs, graph: &std::path::Path) -> Result<Side, UserError> {
        let scene = crate::scene::load(&args.scene)?;
        let camera = scene.camera;
        let options = SessionOptions { warm_pipelines: true, ..SessionOptions::new(args.size) };
        let mut session = Session::new(gpu, scene, graph, options)?;
        session.timing = Timing::for_adapter(gpu, args.profile);
        // The same scene times on both sides, as `glint render` steps them.
        let frames = FrameLoop::new(0.0, Clock::Fixed { dt: 1.0 / 60.0 }, camera);
        Ok(Side { session, frames, frame_ms: Vec::new() })
    }

    /// One frame, waited for: frames in flight would otherwise overlap
    /// the other side's.
    fn step(&mut self, restart: bool) -> Result<(), UserError> {
        if restart {
            self.session.restart();
        }
        let start = std::time::Instant::now();
        self.frames.step(&mut self.session);
        if !self.session.gpu.wait() {
            return Err(UserError::new("the GPU did not finish a frame in time"));
        }
        self.frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
        Ok(())
    }
}

pub fn run(args: FramesArgs) -> Result<(), UserError> {
    let gpu = Gpu::new()?;
    check_size(&gpu, args.size)?;
    let mut a = Side::new(&gpu, &args, &args.graph)?;
    let mut b = Side::new(&gpu, &args, &args.vs)?;
    // Untimed: pipeline compilation and first touch.
    for side in [&mut a, &mut b] {
        side.step(false)?;
        side.frames.stats = Default::default();
        side.frame_ms.clear();
    }
    for k in 0..args.frames.max(1) {
        // Each side first on every other frame, so neither always follows.
        let (first, second) = if k % 2 == 0 { (&mut a, &mut b) } else { (&mut b, &mut a) };
        first.step(args.first_frames)?;
        second.step(args.first_frames)?;
    }
    out!("adapter={}", gpu.describe());
    out!("graph={} vs={}{}", args.graph.display(), args.vs.display(), if args.first_frames { " (first frames)" } else { "" });
    print_ratio("frame", &a.frame_ms, &b.frame_ms);
    for (name, ms) in &a.frames.stats.pass_ms {
        if let Some((_, other)) = b.frames.stats.pass_ms.iter().find(|(n, _)| n == name) {
            print_ratio(name, ms, other);
        }
    }
    Ok(())
}

/// Both sides' medians and the median of the per-frame ratios.
fn print_ratio(name: &str, a: &[f64], b: &[f64]) {
    if let Some((ratio, lo, hi)) = paired_ratios(a, b) {
        out!("{name}_ms={:.3} vs {:.3}; {name}_over_vs={ratio:.3} (frames {lo:.3}-{hi:.3})", median(a), median(b));
    }
}
