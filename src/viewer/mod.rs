//! `glint view`: a winit window with the graph output through a present
//! pass, egui panels (schedule, params, resources, frame time, graphs and
//! machine profiles, stats, an error overlay), fly and orbit cameras, and
//! hot reload built off the presenting thread (docs/ARCHITECTURE.md).

pub mod actions;
mod app;
mod background;
mod mirror;
pub mod camera;
pub mod keys;
pub mod panels;
pub mod present;
pub mod presents;
mod reloader;
mod screenshot;
mod window;

use std::path::PathBuf;

use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::WindowId;

use crate::error::UserError;
use crate::scene::Scene;
use app::Viewer;

/// Wakes the window's event loop from another thread (a rebuild or a
/// scene frame finished), so the window need not poll for it.
pub(crate) type Waker = std::sync::Arc<dyn Fn() + Send + Sync>;

/// What `glint view` opens and how (the `glint view` arguments).
#[derive(Debug, Clone)]
pub struct ViewOptions {
    /// The scene file (RON, OBJ or glTF).
    pub scene: PathBuf,
    /// The scene's glTF camera to start from (`--camera`).
    pub camera: Option<usize>,
    /// Frame graph to run (None: the machine profile's, from
    /// passes/machines.ron for this adapter).
    pub graph: Option<PathBuf>,
    /// Render size (before a machine profile's resolution scale).
    pub size: (u32, u32),
    /// Random seed of every pass's samples (the frame uniform's `seed`).
    pub seed: u32,
    /// Render this many frames, write the screenshot and exit.
    pub frames: Option<u32>,
    /// Where the screenshot after `frames` goes (PNG; the graph output is
    /// written beside it as a linear EXR).
    pub screenshot: Option<PathBuf>,
    /// Where F12 writes its screenshots (None: the working folder).
    pub screenshot_dir: Option<PathBuf>,
    /// Frames a still image accumulates before it stops rendering.
    pub sample_target: Option<u32>,
}

struct App {
    options: ViewOptions,
    wake: Waker,
    scene: Option<Scene>,
    viewer: Option<Viewer>,
    result: Result<(), UserError>,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some(scene) = self.scene.take() else { return };
        match Viewer::new(event_loop, self.options.clone(), scene, self.wake.clone()) {
            Ok(v) => {
                v.window.request_redraw();
                self.viewer = Some(v);
            }
            Err(e) => {
                self.result = Err(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(v) = &mut self.viewer else { return };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => {
                v.redraw();
                if let Some(e) = v.failure.take() {
                    self.result = Err(e);
                }
                if v.done {
                    event_loop.exit();
                }
            }
            other => {
                v.on_event(&other);
                if v.done {
                    event_loop.exit();
                }
            }
        }
    }

    /// A waker's call: something finished off the window's thread.
    fn user_event(&mut self, _event_loop: &ActiveEventLoop, _event: ()) {
        if let Some(v) = &self.viewer {
            v.window.request_redraw();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        // Render continuously: accumulation and moving lights need frames.
        // While a scene frame runs, the window redraws at a steady rate.
        let Some(v) = &self.viewer else { return };
        match v.next_redraw() {
            Some(at) if at > std::time::Instant::now() => event_loop.set_control_flow(ControlFlow::WaitUntil(at)),
            _ => {
                event_loop.set_control_flow(ControlFlow::Poll);
                v.window.request_redraw();
            }
        }
    }
}

/// Opens the window and runs until it is closed (or, with `frames`, until
/// the screenshot is written). Start-up errors (scene, graph, shaders, no
/// display) are returned before or instead of a window.
pub fn run(options: ViewOptions) -> Result<(), UserError> {
    let mut scene = crate::scene::load(&options.scene)?;
    if let Some(n) = options.camera {
        scene.use_camera(n)?;
    }
    if options.frames == Some(0) {
        return Err(UserError::new("--frames 0 shows nothing; give at least 1"));
    }
    let event_loop = EventLoop::new().map_err(|e| {
        UserError::new(format!(
            "cannot open a window: {e}. `glint view` needs a display (X11 or Wayland); on a machine without one, run it under `xvfb-run -a`"
        ))
    })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let proxy = event_loop.create_proxy();
    let wake: Waker = std::sync::Arc::new(move || {
        // The loop is gone at exit: nothing to wake.
        let _ = proxy.send_event(());
    });
    let mut app = App { options, wake, scene: Some(scene), viewer: None, result: Ok(()) };
    event_loop.run_app(&mut app).map_err(|e| UserError::new(format!("the window's event loop failed: {e}")))?;
    if let Some(v) = &app.viewer {
        println!("{}", v.summary());
    }
    app.result
}
