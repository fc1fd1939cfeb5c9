//! The engine side of `glint trade` and `glint bench thesis`: a graph
//! rendered frame after frame with each frame timed and its accumulated
//! image measured against a reference, and the path-traced reference
//! itself, cached by what it was rendered from.

use std::path::Path;
use std::time::Instant;

use crate::camera_path::CameraPath;
use crate::error::UserError;
use crate::gpu::readback::ImageF32;
use crate::gpu::Gpu;
use crate::graph::executor::Timing;
use crate::graph::CompileOptions;
use crate::scene::{Camera, Scene};
use crate::session::frame_loop::FrameTarget;
use crate::session::{check_size, Session, SessionOptions};
use crate::trade::sweep::Setting;
use crate::trade::{Curve, Sample};
use crate::{image_io, metrics};

/// A session for `graph` on `scene` with a sweep setting's edits.
pub(crate) fn session_for(gpu: &Gpu, scene: Scene, graph: &Path, size: (u32, u32), seed: u32, setting: &Setting) -> Result<Session, UserError> {
    let mut options = SessionOptions::new(size);
    options.seed = seed;
    // The first frame of each kind would otherwise carry its pipelines'
    // compile on a driver that compiles at the first dispatch (llvmpipe).
    options.warm_pipelines = true;
    options.compile = CompileOptions { no_specialise: !setting.specialise, no_cull: !setting.cull, ..CompileOptions::default() };
    options.compile.edits.set = setting.param_sets();
    options.compile.edits.skip = setting.skip.clone();
    Session::new(gpu, scene, graph, options)
}

/// One graph (and setting) being measured, a frame at a time, so several
/// can be measured in alternation (`bench thesis`: this machine's speed
/// drifts over minutes, frame-by-frame alternation cancels it).
///
/// A frame's time is GPU timestamps where they bracket the work, else the
/// wall clock around a frame that is waited for. The readback is not
/// timed. A setting's resolution scale renders smaller (or larger) and
/// upscales the image to the reference's size (bilinear) before
/// measuring; its frame-time target drives the mask threshold by the PID
/// controller on the measured frame time, as the viewer does.
pub(crate) struct Run {
    pub graph: String,
    pub setting: String,
    session: Session,
    /// Scene time and camera per frame (`trade --animate`); None: still.
    motion: Option<Motion>,
    target: Option<FrameTarget>,
    gpu_timed: bool,
    samples: Vec<Sample>,
    cum_ms: f64,
    last: Option<ImageF32>,
}

impl Run {
    pub fn new(gpu: &Gpu, scene: Scene, graph: &Path, setting: &Setting, size: (u32, u32)) -> Result<Run, UserError> {
        Run::with_seed(gpu, scene, graph, setting, size, 1)
    }

    /// `new` with the samples' random seed (`trade --seeds`).
    pub fn with_seed(gpu: &Gpu, scene: Scene, graph: &Path, setting: &Setting, size: (u32, u32), seed: u32) -> Result<Run, UserError> {
        let size = crate::machines::scale_size(size, setting.resolution_scale);
        check_size(gpu, size)?;
        let mut session = session_for(gpu, scene, graph, size, seed, setting)?;
        // One frame untimed, then a restart (the image starts over as in a
        // fresh session): CPU drivers compile a pipeline's code on its first
        // dispatch, which is not a frame's cost.
        session.frame(0.0);
        session.gpu.wait();
        session.restart();
        let gpu_timed = Timing::stamps_bracket_work(gpu);
        session.timing = if gpu_timed { Timing::Gpu } else { Timing::None };
        Ok(Run {
            graph: graph.file_stem().map_or("graph".into(), |s| s.to_string_lossy().into_owned()),
            setting: setting.name.clone(),
            session,
            motion: None,
            target: setting.target_ms.map(|t| FrameTarget::new(f64::from(t))).transpose()?,
            gpu_timed,
            samples: Vec::new(),
            cum_ms: 0.0,
            last: None,
        })
    }

    /// Animates the run: frame k (from 0) at scene time k dt, with the
    /// camera on `path` at that time.
    pub fn animate(&mut self, motion: Motion) {
        self.motion = Some(motion);
    }

    /// Renders and times one frame; with a reference, reads the image back
    /// and records its error (without one, only the time).
    pub fn step(&mut self, reference: Option<&ImageF32>) -> Result<(), UserError> {
        let mut time = 0.0;
        if let Some(m) = &self.motion {
            time = self.samples.len() as f32 * m.dt;
            self.session.scene.scene.camera = m.camera_at(time);
        }
        let start = Instant::now();
        self.session.frame(time);
        self.session.gpu.wait();
        let wall = start.elapsed().as_secs_f64() * 1e3;
        let ms = if self.gpu_timed { self.session.finish().last().map_or(wall, |t| t.total()) } else { wall };
        self.cum_ms += ms;
        if let Some(t) = &mut self.target {
            self.session.mask_threshold = t.pid.update(t.target_ms, ms, ms / 1e3) as f32;
        }
        let (mut flip, mut relmse, mut psnr) = (f64::NAN, f64::NAN, f64::NAN);
        if let Some(reference) = reference {
            let mut img = self.session.read_output()?;
            if (img.width, img.height) != (reference.width, reference.height) {
                img = image_io::resize_bilinear(&img, reference.width, reference.height);
            }
            flip = f64::from(metrics::flip(reference, &img).0.mean);
            relmse = metrics::rel_mse(reference, &img);
            psnr = metrics::psnr(reference, &img);
            self.last = Some(img);
        }
        self.samples.push(Sample {
            graph: self.graph.clone(),
            setting: self.setting.clone(),
            frame: self.samples.len() as u32 + 1,
            ms,
            cum_ms: self.cum_ms,
            flip,
            relmse,
            psnr,
        });
        Ok(())
    }

    /// The accumulated image now, as rendered (not rescaled).
    pub fn read(&self) -> Result<ImageF32, UserError> {
        self.session.read_output()
    }

    /// The frame times so far, in order.
    pub fn frame_ms(&self) -> Vec<f64> {
        self.samples.iter().map(|s| s.ms).collect()
    }

    /// The curve, and the last image measured (None without a reference).
    pub fn finish(self) -> (Curve, Option<ImageF32>) {
        (Curve { graph: self.graph, setting: self.setting, samples: self.samples }, self.last)
    }
}

/// Scene time and camera of an animated run, frame by frame.
#[derive(Debug, Clone)]
pub(crate) struct Motion {
    pub dt: f32,
    pub path: Option<CameraPath>,
    /// The scene's own camera, where the path starts.
    pub base: Camera,
}

impl Motion {
    pub fn camera_at(&self, time: f32) -> Camera {
        self.path.as_ref().map_or(self.base, |p| p.at(&self.base, time))
    }
}

/// Runs in alternation, a frame each in turn, for `frames` frames: this
/// machine's speed drifts over minutes, and graphs measured one after
/// another would carry that drift into their ratio. Each frame starts
/// with the next run, so that none always follows the same one.
pub(crate) fn step_together(runs: &mut [Run], frames: u32, reference: Option<&ImageF32>, what: &str) -> Result<(), UserError> {
    let bar = indicatif::ProgressBar::new(u64::from(frames));
    bar.set_style(indicatif::ProgressStyle::with_template(&format!("{what} {{bar:30}} {{pos}}/{{len}}")).unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()));
    let n = runs.len();
    for f in 1..=frames {
        for k in 0..n {
            runs[(f as usize + k) % n].step(reference)?;
        }
        bar.set_position(u64::from(f));
    }
    bar.finish_and_clear();
    Ok(())
}

/// What a cached reference was rendered from.
#[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct ReferenceKey {
    scene_hash: u64,
    size: (u32, u32),
    frames: u32,
    engine: String,
    /// The graph that rendered it, the scene time and the camera
    /// (position, target) it was held at.
    graph: String,
    time: f32,
    camera: [f64; 6],
}

/// Where a reference is cached and what renders it.
pub(crate) struct ReferenceSpec<'a> {
    pub scene: &'a Path,
    pub size: (u32, u32),
    pub frames: u32,
    /// `<stem>.exr` and `<stem>.ron` (its key) in `dir`.
    pub dir: &'a Path,
    pub stem: &'a str,
    /// The path tracer's graph (or `--reference-graph`).
    pub pathtracer: &'a Path,
    /// Scene time, and the camera (None: the scene's), held still.
    pub time: f32,
    pub camera: Option<Camera>,
}

/// The path tracer's converged image, from the cache when its key (scene
/// hash, size, frames, engine version) matches, else rendered (with a
/// progress bar) and cached; a stale cache is rendered again, never used.
pub(crate) fn cached_reference(gpu: &Gpu, spec: &ReferenceSpec) -> Result<ImageF32, UserError> {
    if spec.frames < 2 {
        return Err(UserError::new("the reference needs at least 2 frames"));
    }
    let mut scene = crate::scene::load(spec.scene)?;
    if let Some(camera) = spec.camera {
        scene.camera = camera;
    }
    let (p, t) = (scene.camera.position, scene.camera.target);
    let key = ReferenceKey {
        scene_hash: scene.content_hash(),
        size: spec.size,
        frames: spec.frames,
        engine: format!("glint {}", env!("CARGO_PKG_VERSION")),
        graph: spec.pathtracer.display().to_string(),
        time: spec.time,
        camera: [p.x, p.y, p.z, t.x, t.y, t.z],
    };
    let image_path = spec.dir.join(format!("{}.exr", spec.stem));
    let key_path = spec.dir.join(format!("{}.ron", spec.stem));
    let cached = std::fs::read_to_string(&key_path).ok().and_then(|t| ron::from_str::<ReferenceKey>(&t).ok());
    if cached.as_ref() == Some(&key) {
        if let Ok(img) = image_io::load(&image_path) {
            out!("reference: cached {} ({} samples per pixel)", image_path.display(), key.frames);
            return Ok(img);
        }
    } else if cached.is_some() {
        out!("reference: the cached one is stale (scene, graph, size, frames or engine changed); rendering again");
    }
    let mut session = session_for(gpu, scene, spec.pathtracer, spec.size, 7, &Setting::plain())?;
    let bar = indicatif::ProgressBar::new(u64::from(spec.frames));
    bar.set_style(indicatif::ProgressStyle::with_template("reference {bar:40} {pos}/{len} frames (eta {eta})").unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()));
    let mut half = None;
    for f in 1..=spec.frames {
        session.frame(spec.time);
        if f == spec.frames / 2 {
            half = Some(session.read_output()?);
        }
        bar.set_position(u64::from(f));
    }
    bar.finish_and_clear();
    let img = session.read_output()?;
    if let Some(h) = half {
        let (flip, _) = metrics::flip(&img, &h);
        out!(
            "reference: {} on {}, {} samples per pixel; at half of them it was FLIP {:.4} from the final image (how converged it is)",
            spec.pathtracer.display(),
            spec.scene.display(),
            spec.frames,
            flip.mean
        );
    }
    image_io::save(&img, &image_path)?;
    let text = ron::to_string(&key).map_err(|e| UserError::new(e.to_string()))?;
    std::fs::write(&key_path, text).map_err(|e| UserError::in_file(&key_path, e.to_string()))?;
    Ok(img)
}

/// A setting's name as part of a file name.
pub(crate) fn file_safe(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect()
}

/// The path tracer's graph beside the first graph named (passes/ as
/// shipped): the default reference graph.
pub(crate) fn pathtracer_beside(graphs: &[std::path::PathBuf]) -> std::path::PathBuf {
    graphs.first().and_then(|g| g.parent()).map_or(std::path::PathBuf::from("passes/pathtrace.ron"), |p| p.join("pathtrace.ron"))
}
