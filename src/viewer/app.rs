//! The viewer's window and frame: winit events, the camera, the session's
//! frame, hot reload off the presenting thread, the present pass and egui.


mod rebuilds;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, ModifiersState, PhysicalKey};
use winit::window::Window;

use crate::error::UserError;
use crate::gpu::Gpu;
use crate::graph::executor::{FrameHook, Timing};
use crate::session::frame_loop::{Clock, FrameLoop, FrameTarget};
use crate::session::{Session, SessionOptions};
use crate::stats::REFLECT_REUSE;
use crate::viewer::background::Pending;
use crate::viewer::camera::{self, CameraControl};
use crate::viewer::keys::{self, KeyCommand, Viewpoints};
use crate::viewer::panels::{self, PanelInput, PanelState};
use crate::viewer::mirror::Mirror;
use crate::viewer::present::{Present, Rect};
use crate::viewer::presents::Presents;
use crate::viewer::reloader::Reloader;
use crate::viewer::screenshot;
use crate::viewer::window::{self, pick_format, PANEL_WIDTH};
use crate::viewer::ViewOptions;

/// Milliseconds between window frames while a scene frame is running.
const UI_WHILE_RENDERING_MS: u64 = 40;

/// Seconds a notice stays over the image.
const NOTICE_S: f32 = 6.0;

/// Scene seconds per frame in a scripted run (`--frames`).
pub const SCRIPTED_DT: f32 = 1.0 / 30.0;

#[derive(Default)]
struct Mouse {
    left: bool,
    right: bool,
    last: Option<(f64, f64)>,
}

pub struct Viewer {
    pub window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The window's device: the surface, egui and the present pass.
    ui: Gpu,
    /// The scene's device (the session's), another on the same adapter.
    gpu: Gpu,
    pub session: Session,
    /// The scene's latest finished image, on the window's device.
    mirror: Mirror,
    /// The session generation of the frame in flight and of the image
    /// shown (a reload line waits for an image of the new state).
    flight_generation: u64,
    shown_generation: u64,
    /// When the window last presented.
    last_ui: Instant,
    /// Window frames presented, and the longest time between two after
    /// the first scene image (milliseconds).
    ui_frames: u64,
    ui_longest_gap_ms: f64,
    frames: FrameLoop,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    present: Present,
    control: CameraControl,
    mouse: Mouse,
    reloader: Option<Reloader>,
    /// A graph, profile or scene switch being built off this thread.
    pending: Option<Pending>,
    /// The error of the last failed rebuild, shown until a good one.
    overlay: Option<String>,
    /// A short message over the image (the camera line, a viewpoint
    /// saved), shown for NOTICE_S from when it was set.
    notice: Option<(String, Instant)>,
    last_reload: Option<String>,
    panel: PanelState,
    options: ViewOptions,
    /// When frames reached the screen: the FPS, the frame-time plot and
    /// the gaps a rebuild left.
    presents: Presents,
    last_frame: Instant,
    modifiers: ModifiersState,
    help: bool,
    viewpoints: Viewpoints,
    /// The scene file shown (viewpoints are kept per file).
    scene_path: PathBuf,
    /// Why a scripted run failed (an unwritable screenshot): the exit code.
    pub failure: Option<UserError>,
    screenshot_requested: bool,
    /// The screenshots F12 wrote this run (none is overwritten).
    screenshots: Vec<PathBuf>,
    /// A reload line printed once the first frame with the new state has
    /// been presented (what "save to new image" latency is measured to),
    /// with the session generation that state has.
    announce: Option<(String, u64)>,
    /// The viewport rectangle of the last frame (physical pixels).
    viewport: Rect,
    /// The area beside the panel, in egui points, as the last frame laid it out.
    central: egui::Rect,
    pub done: bool,
}

impl Viewer {
    pub fn new(event_loop: &ActiveEventLoop, options: ViewOptions, scene: crate::scene::Scene, wake: crate::viewer::Waker) -> Result<Viewer, UserError> {
        let window = Arc::new(event_loop.create_window(window::attributes(&options)).map_err(|e| UserError::new(format!("cannot open a window: {e}")))?);
        let descriptor = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(event_loop.owned_display_handle()));
        let instance = wgpu::Instance::new(descriptor);
        let surface = instance
            .create_surface(Arc::clone(&window))
            .map_err(|e| UserError::new(format!("cannot draw into the window: {e}")))?;
        let ui = Gpu::for_surface(instance, &surface)?;
        let gpu = ui.second_device()?;
        window.set_title(&format!("glint: {} ({})", options.scene.display(), gpu.info.name));
        let caps = surface.get_capabilities(&ui.adapter);
        let format = pick_format(&caps).ok_or_else(|| UserError::new(format!("{} offers no 8-bit surface format for the window", gpu.describe())))?;
        let size = window.inner_size();
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        if caps.usages.contains(wgpu::TextureUsages::COPY_SRC) {
            usage |= wgpu::TextureUsages::COPY_SRC;
        }
        let config = wgpu::SurfaceConfiguration {
            usage,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoNoVsync,
            desired_maximum_frame_latency: 1,
            alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
        };
        surface.configure(&ui.device, &config);

        let choice = crate::machines::choose(&gpu, options.graph.as_deref())?;
        let mut session_options = SessionOptions::new(options.size);
        session_options.seed = options.seed;
        session_options.warm_pipelines = true;
        session_options.compile.edits.set = choice.params.clone();
        session_options.compile.keep = vec![REFLECT_REUSE.to_string()];
        session_options.size = choice.scaled(options.size);
        let base_camera = scene.camera;
        let mut session = Session::new(&gpu, scene, &choice.graph, session_options)?;
        session.timing = Timing::for_adapter(&gpu, false);
        // A scripted run (--frames) steps scene time like `glint render
        // --dt` does, so its frames are reproducible; live, the wall clock.
        let clock = if options.frames.is_some() { Clock::Fixed { dt: SCRIPTED_DT } } else { Clock::Real };
        let mut frames = FrameLoop::new(0.0, clock, base_camera);
        frames.target = choice.target_ms.map(FrameTarget::new).transpose()?;
        frames.sample_target = options.sample_target;
        let control = CameraControl::for_scene(&base_camera, session.scene.scene.bounds());

        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(ui.max_texture_side() as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(&ui.device, format, egui_wgpu::RendererOptions::default());
        let present = Present::new(&ui.device, format)?;
        // A scripted run (--frames) renders and exits: nothing to watch.
        let mirror = Mirror::new(&gpu, wake.clone())?;
        let reloader = match Reloader::start(&session, wake) {
            _ if options.frames.is_some() => None,
            Ok((r, dirs)) => {
                let shown: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
                println!("watching {} for changes", shown.join(", "));
                Some(r)
            }
            Err(e) => {
                eprintln!("glint: hot reload is off: {e}");
                None
            }
        };
        let mut panel = PanelState::new(choice.graphs.clone(), choice.profiles.clone(), choice.matched, options.size, choice.resolution_scale);
        if options.graph.is_some() {
            panel.active_profile = None;
        }
        Ok(Viewer {
            window,
            surface,
            config,
            ui,
            gpu,
            session,
            frames,
            egui_ctx,
            egui_state,
            egui_renderer,
            present,
            control,
            mouse: Mouse::default(),
            reloader,
            pending: None,
            overlay: None,
            notice: None,
            last_reload: None,
            panel,
            scene_path: options.scene.clone(),
            options,
            presents: Presents::default(),
            last_frame: Instant::now(),
            modifiers: ModifiersState::empty(),
            help: false,
            viewpoints: Viewpoints::default(),
            failure: None,
            screenshot_requested: false,
            screenshots: Vec::new(),
            announce: None,
            mirror,
            flight_generation: 0,
            shown_generation: 0,
            last_ui: Instant::now(),
            ui_frames: 0,
            ui_longest_gap_ms: 0.0,
            viewport: Rect { x: 0.0, y: 0.0, w: 0.0, h: 0.0 },
            central: egui::Rect::NOTHING,
            done: false,
        })
    }

    pub fn on_event(&mut self, event: &WindowEvent) {
        let response = self.egui_state.on_window_event(&self.window, event);
        match event {
            WindowEvent::Resized(size) => {
                self.config.width = size.width.max(1);
                self.config.height = size.height.max(1);
                self.surface.configure(&self.ui.device, &self.config);
            }
            WindowEvent::ModifiersChanged(m) => self.modifiers = m.state(),
            WindowEvent::KeyboardInput { event, .. } if !response.consumed => {
                let down = event.state == ElementState::Pressed;
                let PhysicalKey::Code(code) = event.physical_key else { return };
                let keys = &mut self.control.keys;
                match code {
                    KeyCode::KeyW => keys.forward = down,
                    KeyCode::KeyS => keys.back = down,
                    KeyCode::KeyA => keys.left = down,
                    KeyCode::KeyD => keys.right = down,
                    KeyCode::KeyE => keys.up = down,
                    KeyCode::KeyQ => keys.down = down,
                    _ => {}
                }
                if down && !event.repeat {
                    if let Some(c) = keys::command(code, event.text.as_deref(), self.modifiers.control_key()) {
                        self.key_command(c);
                    }
                }
            }
            WindowEvent::DroppedFile(path) => self.open_scene(path.clone()),
            WindowEvent::MouseInput { state, button, .. } => {
                let down = *state == ElementState::Pressed;
                if down && self.pointer_over_ui() {
                    return;
                }
                match button {
                    MouseButton::Left => self.mouse.left = down,
                    MouseButton::Right => self.mouse.right = down,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let (x, y) = (position.x, position.y);
                if let Some((lx, ly)) = self.mouse.last {
                    let (dx, dy) = ((x - lx) as f32, (y - ly) as f32);
                    let cam = &mut self.session.scene.scene.camera;
                    if self.mouse.right {
                        camera::look(cam, dx, dy);
                    } else if self.mouse.left {
                        camera::orbit(cam, dx, dy);
                    }
                }
                self.mouse.last = Some((x, y));
            }
            WindowEvent::MouseWheel { delta, .. } if !self.pointer_over_ui() => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.control.wheel(notches);
            }
            _ => {}
        }
    }

    /// Whether a button pressed now is the panels' (or a window's or a
    /// popup's over the image), from where the cursor is now. egui's own
    /// answer is as of the last frame, whose pointer may have been outside
    /// the window: with a slow frame, or no keyboard focus, a press that
    /// arrived with its motion was taken for the panel's and the drag lost.
    fn pointer_over_ui(&self) -> bool {
        let Some((x, y)) = self.mouse.last else { return true };
        let ppp = self.egui_ctx.pixels_per_point();
        let pos = egui::pos2(x as f32 / ppp, y as f32 / ppp);
        let over_layer = self.egui_ctx.layer_id_at(pos).is_some_and(|l| l.order != egui::Order::Background);
        !self.central.contains(pos) || over_layer || self.egui_ctx.egui_is_using_pointer()
    }

    fn key_command(&mut self, c: KeyCommand) {
        let camera = &mut self.session.scene.scene.camera;
        match c {
            KeyCommand::Quit => self.done = true,
            KeyCommand::ToggleHelp => self.help = !self.help,
            KeyCommand::ResetCamera => *camera = self.frames.base_camera,
            KeyCommand::CopyCamera => {
                let line = keys::camera_line(camera);
                println!("{line}");
                self.egui_ctx.copy_text(line.clone());
                self.notice = Some((format!("{line}\n(copied: paste it into the scene file's `camera:`)"), Instant::now()));
            }
            KeyCommand::SaveView(n) => {
                self.viewpoints.save(&self.scene_path, n, *camera);
                self.notice = Some((format!("viewpoint {n} saved: {n} returns to it"), Instant::now()));
            }
            KeyCommand::RecallView(n) => match self.viewpoints.get(&self.scene_path, n) {
                Some(c) => *camera = c,
                None => self.notice = Some((format!("no viewpoint {n} for this scene: Ctrl+{n} saves one"), Instant::now())),
            },
            KeyCommand::Pause => self.frames.paused = !self.frames.paused,
            KeyCommand::Screenshot => self.screenshot_requested = true,
        }
    }

    /// One frame: reload, camera, render, UI, present.
    pub fn redraw(&mut self) {
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f32();
        self.last_frame = now;
        self.poll_reload();
        self.poll_pending();
        self.control.fly(&mut self.session.scene.scene.camera, dt.min(0.25));
        // The scene: take in an image that arrived, then start the next
        // frame unless one is running. A scripted run waits for each
        // frame, so its Nth present shows the Nth frame.
        let scripted = self.options.frames.is_some();
        let mut arrived = self.take_scene_image(false);
        // While a saved file's rebuild compiles, no new scene frame starts:
        // on a CPU driver the frame and the compiler share the cores, and
        // the save reaches the image sooner with the compiler alone (the
        // window goes on presenting; the image holds meanwhile).
        let reloading = self.reloader.as_ref().and_then(Reloader::running);
        let compiling = reloading.is_some();
        if !self.mirror.busy() && !compiling {
            if self.last_scripted_frame() {
                // A scripted run's last frame is its screenshot: in full.
                self.session.show_next_in_full();
            }
            let (mirror, device) = (&mut self.mirror, &self.gpu.device);
            let mut record = |enc: &mut wgpu::CommandEncoder, texture: &wgpu::Texture, format| mirror.record(device, enc, texture, format);
            let hook = FrameHook { resource: self.panel.resource.as_deref(), record: &mut record };
            self.frames.step_with(&mut self.session, Some(hook));
            self.mirror.submitted();
            if self.mirror.busy() {
                self.flight_generation = self.session.generation;
                if scripted {
                    arrived |= self.take_scene_image(true);
                }
            }
        }
        for gpu in [&self.gpu, &self.ui] {
            if let Some(e) = gpu.uncaptured.lock().ok().and_then(|mut l| l.pop()) {
                self.overlay = Some(format!("GPU error: {e}"));
                eprintln!("error: GPU error: {e}");
            }
        }

        let raw = self.egui_state.take_egui_input(&self.window);
        let mut actions = Vec::new();
        let mut central = egui::Rect::NOTHING;
        let switching = self.pending.as_ref().map(|p| p.what.clone());
        let rebuilding = switching.or(reloading);
        let frame_plot = self.presents.plot();
        let input = PanelInput {
            frames: &self.frames,
            fps: self.presents.fps(Instant::now()),
            frame_plot: &frame_plot,
            fly_speed: self.control.speed,
            rebuilding: rebuilding.as_deref(),
            last_reload: self.last_reload.as_deref(),
            scene: &self.scene_path,
        };
        if self.notice.as_ref().is_some_and(|(_, at)| at.elapsed().as_secs_f32() > NOTICE_S) {
            self.notice = None;
        }
        let notice = self.notice.as_ref().map(|(n, _)| n.as_str());
        let (session, panel, overlay, help) = (&self.session, &mut self.panel, &self.overlay, &mut self.help);
        let output = self.egui_ctx.run_ui(raw, |ui| {
            egui::Panel::left("panels").resizable(false).exact_size(PANEL_WIDTH).show(ui, |ui| {
                actions = panels::draw(ui, session, &input, panel);
            });
            egui::CentralPanel::default().frame(egui::Frame::NONE).show(ui, |ui| {
                central = ui.max_rect();
                if let Some(e) = overlay {
                    egui::Frame::new().fill(egui::Color32::from_black_alpha(200)).inner_margin(8.0).show(ui, |ui| {
                        ui.label(egui::RichText::new(e).color(egui::Color32::from_rgb(255, 120, 100)).monospace());
                    });
                }
                if let Some(n) = notice {
                    egui::Frame::new().fill(egui::Color32::from_black_alpha(200)).inner_margin(8.0).show(ui, |ui| {
                        ui.label(egui::RichText::new(n).color(egui::Color32::from_rgb(200, 230, 255)).monospace());
                    });
                }
            });
            panels::help(ui.ctx(), help);
        });
        self.central = central;
        self.egui_state.handle_platform_output(&self.window, output.platform_output);
        let kept_before = self.panel.resource.clone();
        for a in actions {
            self.apply(a);
        }
        if self.panel.resource != kept_before {
            let keep = self.panel.resource.iter().cloned().chain([REFLECT_REUSE.to_string()]).collect();
            match self.session.set_kept(keep) {
                Ok(_) => self.refresh_reloader(),
                Err(e) => self.show_error(e.to_string()),
            }
        }
        let ppp = output.pixels_per_point;
        let jobs = self.egui_ctx.tessellate(output.shapes, ppp);
        self.viewport = viewport_rect(central, ppp, self.session.size);
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.ui.device, &self.config);
                return;
            }
            _ => return,
        };
        let target = frame.texture.create_view(&Default::default());
        let device = &self.ui.device;
        let queue = &self.ui.queue;
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("present") });
        if let Some((texture, format)) = self.mirror.shown() {
            self.present.draw(device, queue, &mut enc, &target, texture, format, self.viewport, self.panel.exposure, self.panel.channel);
        }
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                self.egui_renderer.update_texture(device, queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor { size_in_pixels: [self.config.width, self.config.height], pixels_per_point: ppp };
        let extra = self.egui_renderer.update_buffers(device, queue, &mut enc, &jobs, &screen);
        {
            let pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.egui_renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        let capture = self.wants_screenshot().then(|| screenshot::record(device, &mut enc, &frame.texture));
        queue.submit(extra.into_iter().chain([enc.finish()]));
        self.window.pre_present_notify();
        queue.present(frame);
        for id in &output.textures_delta.free {
            self.egui_renderer.free_texture(id);
        }
        let now = Instant::now();
        if self.presents.count() > 0 {
            self.ui_longest_gap_ms = self.ui_longest_gap_ms.max(now.duration_since(self.last_ui).as_secs_f64() * 1e3);
        }
        self.last_ui = now;
        self.ui_frames += 1;
        if arrived {
            // The FPS, the plot and the gaps count the scene's frames.
            self.presents.push(self.last_ui);
            if scripted && self.presents.count() == 1 {
                // A scripted run's first frame: what a test times the rest from.
                println!("first frame presented");
            }
            if let Some(r) = &self.reloader {
                r.presented();
            }
        }
        if self.announce.as_ref().is_some_and(|(_, g)| self.shown_generation >= *g) {
            // The first frame rendered after the swap was just presented.
            use std::io::Write as _;
            let mut out = std::io::stdout().lock();
            let _ = writeln!(out, "{}", self.announce.take().map(|(l, _)| l).unwrap_or_default());
            let _ = out.flush();
        }
        if let Some(capture) = capture {
            self.save_screenshot(capture);
        }
    }

    /// Takes in the scene's image if it arrived (with `wait`, waits for
    /// it): true when a new one is shown.
    fn take_scene_image(&mut self, wait: bool) -> bool {
        match self.mirror.poll(&self.gpu, &self.ui, wait) {
            Ok(true) => {
                self.shown_generation = self.flight_generation;
                true
            }
            Ok(false) => false,
            Err(e) => {
                self.show_error(e.to_string());
                false
            }
        }
    }

    /// When the window should next redraw: now (None) while scene frames
    /// keep coming; while one is running or a saved file's rebuild
    /// compiles, at a steady rate that keeps the panel live without taking
    /// the cores the frame or the compiler need (the reload thread wakes
    /// the loop the moment its rebuild is done).
    pub fn next_redraw(&self) -> Option<Instant> {
        let waiting = self.mirror.busy() || self.reloader.as_ref().is_some_and(|r| r.running().is_some());
        (waiting && self.options.frames.is_none()).then(|| self.last_ui + std::time::Duration::from_millis(UI_WHILE_RENDERING_MS))
    }

    /// What the window and the scene presented, for the line printed at
    /// exit: how live the panel stayed while the scene's frames ran.
    pub fn summary(&self) -> String {
        format!(
            "window: {} frames, longest gap {:.0} ms; scene: {} frames, median {:.0} ms",
            self.ui_frames,
            self.ui_longest_gap_ms,
            self.presents.count(),
            self.presents.median_ms(30)
        )
    }

    fn wants_screenshot(&self) -> bool {
        self.screenshot_requested || self.last_scripted_frame()
    }

    /// Whether the next present is a scripted run's last (`--frames N`).
    fn last_scripted_frame(&self) -> bool {
        self.options.frames.is_some_and(|n| self.presents.count() + 1 >= u64::from(n))
    }

    fn save_screenshot(&mut self, capture: Option<screenshot::Capture>) {
        self.screenshot_requested = false;
        let presented = self.presents.count();
        let last = self.options.frames.is_some_and(|n| presented >= u64::from(n));
        if last {
            // What the panel showed at the end, for a test to check
            // against the times it saw.
            let fps = self.presents.fps(Instant::now()).unwrap_or(0.0);
            // The plot's mean over every interval since the first frame, which a
            // busy machine's stalls move as much as they move the wall clock.
            let intervals = usize::try_from(presented.saturating_sub(1)).unwrap_or(usize::MAX);
            println!("last frame presented: {presented} frames, {fps:.2} FPS shown, frame-time plot mean {:.1} ms, last {:.1} ms", self.presents.mean_ms(intervals), self.presents.last_ms().unwrap_or(0.0));
        }
        let png = match (&self.options.screenshot, last) {
            (Some(p), true) => p.clone(),
            _ => {
                // N: the scene frames shown; a second shot of the same frame gets a suffix.
                let dir = self.options.screenshot_dir.clone().unwrap_or_default();
                let name = |k: u32| if k == 0 { format!("glint-screenshot-{presented}.png") } else { format!("glint-screenshot-{presented}-{k}.png") };
                let k = (0..).find(|k| !self.screenshots.contains(&dir.join(name(*k)))).unwrap_or(0);
                let png = dir.join(name(k));
                self.screenshots.push(png.clone());
                png
            }
        };
        let result = match capture {
            Some(c) => screenshot::save(&self.ui, c, self.config.format, &png, &self.session, self.viewport),
            None => Err(UserError::new("this surface cannot be copied from (no COPY_SRC); no screenshot")),
        };
        match result {
            Ok(line) => println!("{line}"),
            Err(e) if last => self.failure = Some(e),
            Err(e) => self.show_error(e.to_string()),
        }
        if last {
            self.done = true;
        }
    }
}

/// Where the render goes in the central area: at 1:1, centred, when it
/// fits; else scaled down to fit, keeping its aspect.
fn viewport_rect(central: egui::Rect, ppp: f32, size: (u32, u32)) -> Rect {
    if !central.is_finite() || central.width() <= 0.0 {
        return Rect { x: 0.0, y: 0.0, w: 0.0, h: 0.0 };
    }
    let (cx, cy) = ((central.min.x * ppp).round(), (central.min.y * ppp).round());
    let (cw, ch) = ((central.width() * ppp).floor(), (central.height() * ppp).floor());
    let (w, h) = (size.0 as f32, size.1 as f32);
    let s = (cw / w).min(ch / h).min(1.0);
    let (vw, vh) = ((w * s).floor(), (h * s).floor());
    Rect { x: cx + ((cw - vw) / 2.0).floor(), y: cy + ((ch - vh) / 2.0).floor(), w: vw, h: vh }
}
