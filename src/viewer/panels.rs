//! The viewer's egui panels. They read the session and return `Action`s;
//! the viewer applies them through the same session calls the tests use
//! (`set_param`, `set_enabled`, `set_graph`...), so a click and a test do
//! the same thing.

use std::collections::BTreeMap;
use std::path::PathBuf;

use egui::{Color32, RichText, Ui};

use crate::graph::desc::ParamValue;
use crate::graph::executor::Timing;
use crate::graph::schedule::CullReason;
use crate::machines::Profile;
use crate::scene::Feature;
use crate::session::frame_loop::FrameLoop;
use crate::session::Session;
use crate::shader::{ParamMember, ScalarType};
use crate::viewer::present::Channel;
use crate::shader::hints::{params_hints, Hint};

/// What the user asked for this frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Set one param of a pass (`Session::set_param`): applies from the
    /// next frame without a recompile and restarts accumulation.
    SetParam {
        /// The scheduled pass, by name.
        pass: String,
        /// The member of the pass's param struct.
        name: String,
        /// Its new value, checked against the reflected layout.
        value: ParamValue,
    },
    /// Switch a pass on or off, as `--skip` does (whatever then feeds
    /// nothing is culled).
    SetEnabled {
        /// The pass, by name in the graph.
        pass: String,
        /// false: skipped.
        enabled: bool,
    },
    /// Switch to this graph file, as `--graph` runs it: at the requested
    /// size, without a profile's scale, params or frame-time target.
    SetGraph(PathBuf),
    /// Switch to this machine profile (an index into
    /// `PanelState::profiles`): its graph, scale, params and target.
    SetProfile(usize),
    /// Render at `requested` times `scale` (a profile's resolution scale,
    /// or one set by hand).
    SetSize {
        /// Render size before the scale, in pixels.
        requested: (u32, u32),
        /// The resolution scale; finite and above 0.
        scale: f32,
    },
    /// The frame-time target the noise mask's PID steers to (None: off).
    SetTarget(Option<f64>),
    /// Frames to accumulate before a still image stops rendering (None:
    /// never stop).
    SetSampleTarget(Option<u32>),
    /// Stop (true) or resume scene time; the camera still moves.
    Pause(bool),
    /// Per-pass wall times on CPU adapters (submits passes one by one).
    Profile(bool),
    /// Open another scene file (its camera and lights; the graph stays).
    OpenScene(PathBuf),
    /// Read back the reflection-reuse record once (it waits for the frame).
    MeasureReuse,
    /// Write a screenshot: a PNG of the window, an EXR of the render.
    Screenshot,
}

/// Panel state that lives across frames.
#[derive(Debug, Clone)]
pub struct PanelState {
    /// The resource shown in the viewport (None: the graph's output).
    pub resource: Option<String>,
    /// Viewport exposure in stops (the panel offers -10 to 10): the
    /// texels are scaled by 2^exposure.
    pub exposure: f32,
    /// Which channels of the resource the viewport shows.
    pub channel: Channel,
    /// Graph files offered in the selector.
    pub graphs: Vec<PathBuf>,
    /// Machine profiles offered in the selector.
    pub profiles: Vec<Profile>,
    /// The profile the adapter matched (an index into `profiles`).
    pub matched_profile: Option<usize>,
    /// The profile running (None: a graph picked by hand).
    pub active_profile: Option<usize>,
    /// The last reflection-reuse measurement, in words.
    pub reuse: Option<String>,
    /// The render size asked for, before the resolution scale (pixels).
    pub requested: (u32, u32),
    /// The resolution scale applied to `requested` (the slider offers
    /// 0.25 to 2).
    pub scale: f32,
    /// The frame-time target being edited (ms), shown while off too.
    target_ms: f64,
    /// The sample target being edited, shown while off too.
    sample_target: u32,
    /// The path typed into the scene section's "open" field.
    open_path: String,
    /// Hints per shader file, read once per session generation.
    hints: BTreeMap<String, BTreeMap<String, Hint>>,
    hints_generation: u64,
}

impl PanelState {
    /// The start-up state: the graph's output at exposure 0 in RGB, with
    /// `matched_profile` running.
    pub fn new(graphs: Vec<PathBuf>, profiles: Vec<Profile>, matched_profile: Option<usize>, requested: (u32, u32), scale: f32) -> PanelState {
        PanelState {
            resource: None,
            exposure: 0.0,
            channel: Channel::Rgb,
            graphs,
            profiles,
            matched_profile,
            active_profile: matched_profile,
            reuse: None,
            requested,
            scale,
            target_ms: 100.0,
            sample_target: 1024,
            open_path: String::new(),
            hints: BTreeMap::new(),
            hints_generation: 0,
        }
    }

    /// A shader's `// ui:` hints, parsed once until the session's graph or
    /// shaders change (a commit bumps its generation).
    fn hints_for(&mut self, session: &Session, shader: &str) -> &BTreeMap<String, Hint> {
        if self.hints_generation != session.generation {
            self.hints.clear();
            self.hints_generation = session.generation;
        }
        self.hints.entry(shader.to_string()).or_insert_with(|| {
            session.graph.shaders.get(shader).map(|s| params_hints(&s.source.text)).unwrap_or_default()
        })
    }
}

/// Everything the panels show besides the session.
pub struct PanelInput<'a> {
    /// The frame loop: accumulation, scene time, targets, pass times.
    pub frames: &'a FrameLoop,
    /// Frames per second over the recent presents (None before two).
    pub fps: Option<f64>,
    /// Milliseconds between presented frames, by frame index.
    pub frame_plot: &'a [egui_plot::PlotPoint],
    /// The fly speed, scene units per second.
    pub fly_speed: f32,
    /// What is being rebuilt off the presenting thread now, if anything.
    pub rebuilding: Option<&'a str>,
    /// The last reload, switch or scene opened, in words (None: none yet).
    pub last_reload: Option<&'a str>,
    /// The scene file shown.
    pub scene: &'a std::path::Path,
}

/// Draws the side panel's sections into `ui`; returns what the user asked
/// for this frame, in order.
pub fn draw(ui: &mut Ui, session: &Session, input: &PanelInput, state: &mut PanelState) -> Vec<Action> {
    let mut actions = Vec::new();
    egui::ScrollArea::vertical().show(ui, |ui| {
        stats(ui, session, input, state, &mut actions);
        scene(ui, session, input, state, &mut actions);
        graphs(ui, session, state, &mut actions);
        size(ui, input, state, &mut actions);
        schedule(ui, session, input, &mut actions);
        params(ui, session, state, &mut actions);
        resources(ui, session, state);
        frame_time(ui, input);
    });
    actions
}

/// What converges: the accumulation (towards a sample target, after which
/// a still image stops rendering) and a bake's progressive passes.
fn progress(ui: &mut Ui, session: &Session, input: &PanelInput, state: &mut PanelState, actions: &mut Vec<Action>) {
    let n = session.accumulated();
    ui.horizontal(|ui| {
        let mut on = input.frames.sample_target.is_some();
        if let Some(t) = input.frames.sample_target {
            state.sample_target = t;
        }
        let toggled = ui.checkbox(&mut on, "stop at").on_hover_text("a still image stops rendering once it has this many frames").changed();
        let edit = ui.add(egui::DragValue::new(&mut state.sample_target).range(1..=1_000_000).suffix(" frames"));
        if toggled || edit.lost_focus() || edit.drag_stopped() {
            actions.push(Action::SetSampleTarget(on.then_some(state.sample_target)));
        }
    });
    match input.frames.sample_target {
        Some(t) => {
            let text = if input.frames.converged { format!("{n} / {t} frames: done, rendering stopped") } else { format!("{n} / {t} frames accumulated") };
            ui.add(egui::ProgressBar::new((n as f32 / t as f32).min(1.0)).text(text));
        }
        None => {
            ui.label(format!("frames accumulated: {n}"));
        }
    }
    if let Some((done, total)) = session.executor.bake_progress() {
        let text = if done >= total { format!("volume baked: {total} iterations") } else { format!("baking the volume: {done} / {total} iterations") };
        ui.add(egui::ProgressBar::new(done as f32 / total.max(1) as f32).text(text));
    }
}

fn stats(ui: &mut Ui, session: &Session, input: &PanelInput, state: &mut PanelState, actions: &mut Vec<Action>) {
    let sched = &session.graph.schedule;
    ui.heading("glint");
    let fps = match input.fps {
        Some(f) if f >= 10.0 => format!("{f:.0} FPS ({:.0} ms)", 1e3 / f),
        Some(f) => format!("{f:.2} FPS ({:.0} ms)", 1e3 / f),
        None => "FPS: after two frames".to_string(),
    };
    ui.label(format!("{fps}, {}x{}, graph `{}`", session.size.0, session.size.1, sched.name));
    progress(ui, session, input, state, actions);
    let time = if input.frames.paused {
        " (paused)"
    } else if input.frames.slowed {
        " (slowed: a frame advances it at most 0.25 s)"
    } else {
        ""
    };
    ui.add(egui::Label::new(format!("scene time {:.2} s{time}", input.frames.time)).wrap());
    if sched.passes.iter().any(|p| p.name == "reflections") {
        ui.horizontal(|ui| {
            if ui.button("reflection reuse").on_hover_text("reads the reuse record back once (waits for the frame)").clicked() {
                actions.push(Action::MeasureReuse);
            }
            ui.label(state.reuse.as_deref().unwrap_or("not measured"));
        });
    }
    // Always one line, so the widgets below do not move when it changes.
    let status = match (input.rebuilding, input.last_reload) {
        (Some(what), _) => RichText::new(format!("rebuilding {what}...")).color(Color32::YELLOW),
        (None, Some(r)) => RichText::new(r).weak(),
        (None, None) => RichText::new("no reload yet").weak(),
    };
    ui.add(egui::Label::new(status).truncate()).on_hover_text(input.last_reload.unwrap_or(""));
    ui.horizontal(|ui| {
        let paused = input.frames.paused;
        if ui.button(if paused { "resume (P)" } else { "pause (P)" }).clicked() {
            actions.push(Action::Pause(!paused));
        }
        if ui.button("screenshot (F12)").clicked() {
            actions.push(Action::Screenshot);
        }
    });
    if session.timing != Timing::Gpu {
        let mut on = session.timing == Timing::WallPerPass;
        if ui.checkbox(&mut on, "per-pass wall time (slower: passes submitted one by one)").changed() {
            actions.push(Action::Profile(on));
        }
    }
    ui.add(egui::Label::new(RichText::new(format!("fly {:.3} units/s: WASD, Q/E, wheel = speed; right-drag looks, left-drag orbits; F1: every key", input.fly_speed)).weak()).wrap());
}

/// The scene files beside the one shown, and a field to open any other.
fn scene(ui: &mut Ui, session: &Session, input: &PanelInput, state: &mut PanelState, actions: &mut Vec<Action>) {
    egui::CollapsingHeader::new("scene").default_open(false).show(ui, |ui| {
        if let Some(t) = crate::scene::texture_classes::describe(session.scene.scene.textures()) {
            ui.add(egui::Label::new(t).wrap());
        }
        if let Some(e) = &session.scene.scene.environment {
            ui.add(egui::Label::new(format!("environment map: {}", e.describe())).wrap());
        }
        let name = |p: &std::path::Path| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        egui::ComboBox::from_id_salt("scene").selected_text(name(input.scene)).show_ui(ui, |ui| {
            // Only while the list is open: it reads the folder.
            let folder = input.scene.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
            let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
                .map(|d| d.filter_map(Result::ok).map(|e| e.path()).filter(|p| crate::scene::opens(p)).collect())
                .unwrap_or_default();
            files.sort();
            for f in files {
                let is = name(&f) == name(input.scene);
                if ui.selectable_label(is, name(&f)).clicked() && !is {
                    actions.push(Action::OpenScene(f));
                }
            }
        });
        ui.horizontal(|ui| {
            let field = ui.add(egui::TextEdit::singleline(&mut state.open_path).hint_text("path/to/scene.ron").desired_width(200.0));
            let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if (ui.button("open").clicked() || enter) && !state.open_path.trim().is_empty() {
                actions.push(Action::OpenScene(PathBuf::from(state.open_path.trim())));
            }
        });
        ui.add(egui::Label::new(RichText::new("or drop a .ron scene, an .obj or a .gltf/.glb on the window").weak()).wrap());
    });
}

fn graphs(ui: &mut Ui, session: &Session, state: &mut PanelState, actions: &mut Vec<Action>) {
    egui::CollapsingHeader::new("graph").default_open(true).show(ui, |ui| {
        let name = |p: &PathBuf| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        egui::ComboBox::from_id_salt("graph").selected_text(name(&session.graph.path)).show_ui(ui, |ui| {
            // Only while the list is open: it touches the file system.
            let running = std::fs::canonicalize(&session.graph.path).unwrap_or_else(|_| session.graph.path.clone());
            for g in &state.graphs {
                let is = std::fs::canonicalize(g).is_ok_and(|c| c == running);
                if ui.selectable_label(is, name(g)).clicked() && !is {
                    actions.push(Action::SetGraph(g.clone()));
                }
            }
        });
        if !state.profiles.is_empty() {
            let label = |i: Option<usize>| i.and_then(|i| state.profiles.get(i)).map_or("(none)".to_string(), |p| p.name.clone());
            egui::ComboBox::from_id_salt("profile").selected_text(format!("profile: {}", label(state.active_profile))).show_ui(ui, |ui| {
                for (i, p) in state.profiles.iter().enumerate() {
                    let mark = if Some(i) == state.matched_profile { " (this adapter)" } else { "" };
                    if ui.selectable_label(state.active_profile == Some(i), format!("{}{mark}: {}", p.name, p.graph)).clicked() {
                        actions.push(Action::SetProfile(i));
                    }
                }
            });
        }
    });
}

/// Sizes offered for the render, before the resolution scale.
const SIZES: [(u32, u32); 6] = [(160, 90), (320, 180), (640, 360), (960, 540), (1280, 720), (1920, 1080)];

/// Render size, resolution scale and the frame-time target.
fn size(ui: &mut Ui, input: &PanelInput, state: &mut PanelState, actions: &mut Vec<Action>) {
    egui::CollapsingHeader::new("size and target").default_open(false).show(ui, |ui| {
        let (w, h) = state.requested;
        egui::ComboBox::from_id_salt("size").selected_text(format!("size {w}x{h}")).show_ui(ui, |ui| {
            for s in SIZES {
                if ui.selectable_label(s == state.requested, format!("{}x{}", s.0, s.1)).clicked() && s != state.requested {
                    actions.push(Action::SetSize { requested: s, scale: state.scale });
                }
            }
        });
        // Applied when the slider is let go: each change rebuilds textures.
        let scale = ui.add(egui::Slider::new(&mut state.scale, 0.25..=2.0).step_by(0.05).text("resolution scale"));
        if scale.drag_stopped() || (scale.changed() && !scale.dragged()) {
            actions.push(Action::SetSize { requested: state.requested, scale: state.scale });
        }
        let mut on = input.frames.target.is_some();
        if let Some(t) = &input.frames.target {
            state.target_ms = t.target_ms;
        }
        ui.horizontal(|ui| {
            let toggled = ui.checkbox(&mut on, "frame-time target").changed();
            let slider = ui.add_enabled(on, egui::Slider::new(&mut state.target_ms, 5.0..=2000.0).logarithmic(true).suffix(" ms"));
            if toggled || slider.drag_stopped() || (slider.changed() && !slider.dragged()) {
                actions.push(Action::SetTarget(on.then_some(state.target_ms)));
            }
        });
        ui.add(egui::Label::new(RichText::new("the noise mask's PID refines fewer pixels to meet it (graphs with a threshold pass)").weak()).wrap());
    });
}

fn schedule(ui: &mut Ui, session: &Session, input: &PanelInput, actions: &mut Vec<Action>) {
    egui::CollapsingHeader::new("schedule").default_open(true).show(ui, |ui| {
        let sched = &session.graph.schedule;
        for pass in &session.graph.desc.passes {
            let name = &pass.name;
            let disabled = session.disabled().iter().any(|d| d == name);
            let culled = sched.culled.iter().find(|c| &c.name == name);
            ui.horizontal(|ui| {
                let mut on = !disabled;
                if ui.checkbox(&mut on, "").changed() {
                    actions.push(Action::SetEnabled { pass: name.clone(), enabled: on });
                }
                match (disabled, culled) {
                    (true, _) => {
                        ui.label(RichText::new(format!("{name}: off")).weak());
                    }
                    (false, Some(c)) => {
                        let why = match &c.reason {
                            CullReason::Requires(fs) => cull_reason(fs),
                            CullReason::Unreachable => "culled: feeds nothing".to_string(),
                        };
                        ui.add(egui::Label::new(RichText::new(format!("{name}: {why}")).color(Color32::GRAY)).wrap());
                    }
                    (false, None) => {
                        let last = &input.frames.stats.last;
                        ui.label(match last.get(name.as_str()) {
                            Some(ms) => format!("{name}: {ms:.2} ms"),
                            // Other passes were timed: this one did not run.
                            None if !last.is_empty() => {
                                let run = session.executor.schedule.passes.iter().find(|p| &p.name == name).map(|p| p.run.describe()).unwrap_or_default();
                                format!("{name}: did not run (runs {run})")
                            }
                            None => format!("{name}: (not timed)"),
                        });
                    }
                }
            });
        }
    });
}

fn params(ui: &mut Ui, session: &Session, state: &mut PanelState, actions: &mut Vec<Action>) {
    egui::CollapsingHeader::new("params").default_open(false).show(ui, |ui| {
        // The later dispatches of a split sample loop (`NAME#k`) are the
        // engine's: their params follow the first pass's.
        for sp in session.executor.schedule.passes.iter().filter(|sp| !sp.name.contains('#')) {
            let Some(p) = &sp.params else { continue };
            let hints = state.hints_for(session, &sp.shader);
            ui.label(RichText::new(&sp.name).strong());
            for m in &p.layout.members {
                let Some(value) = p.values.get(&m.name) else { continue };
                // `X_done` is set by the engine when it splits `X`.
                if m.name.strip_suffix("_done").is_some_and(|x| p.values.contains_key(x)) {
                    continue;
                }
                // A split count shows the total over its dispatches.
                let total;
                let value = match session.split_total(&sp.name, &m.name) {
                    Some(n) => {
                        total = ParamValue::Int(n);
                        &total
                    }
                    None => value,
                };
                if let Some(v) = param_widget(ui, m, value, hints.get(&m.name)) {
                    actions.push(Action::SetParam { pass: sp.name.clone(), name: m.name.clone(), value: v });
                }
            }
        }
    });
}

/// Why a pass that needs `features` was culled. The probe modes are the
/// graph's (`probes.mode`), not the scene's.
fn cull_reason(features: &[Feature]) -> String {
    let (probes, scene): (Vec<&Feature>, Vec<&Feature>) = features.iter().partition(|f| matches!(f, Feature::ThesisProbes | Feature::DdgiProbes));
    match (probes.first(), scene.is_empty()) {
        (Some(Feature::ThesisProbes), true) => "culled: the graph's probes mode is not Thesis".into(),
        (Some(_), true) => "culled: the graph's probes mode is not Ddgi".into(),
        _ => {
            let words: Vec<&str> = scene.iter().map(|f| feature_words(f)).collect();
            format!("culled: the scene has no {}", words.join(" and no "))
        }
    }
}

/// A scene feature as the panel says it.
fn feature_words(f: &Feature) -> &'static str {
    match f {
        Feature::Meshes => "quads or meshes",
        Feature::Spheres => "spheres",
        Feature::PointLights => "point lights",
        Feature::AreaLights => "sphere lights",
        Feature::Lights => "lights",
        Feature::Specular => "specular material",
        Feature::Emissive => "emissive material",
        Feature::Motion => "motion",
        Feature::ThesisProbes | Feature::DdgiProbes => "probes",
    }
}

/// One widget for a param member; the new value when the user changed it.
fn param_widget(ui: &mut Ui, m: &ParamMember, value: &ParamValue, hint: Option<&Hint>) -> Option<ParamValue> {
    let label = hint.and_then(|h| h.label.clone()).unwrap_or_else(|| m.name.clone());
    let scalars: Vec<f64> = match value {
        ParamValue::Vector(v) => v.clone(),
        ParamValue::Int(i) => vec![*i as f64],
        ParamValue::Float(f) => vec![*f],
        ParamValue::Bool(b) => vec![f64::from(u8::from(*b))],
    };
    let int = m.scalar != ScalarType::F32;
    let mut out = None;
    let wrapped = |ui: &mut Ui| ui.add(egui::Label::new(label.as_str()).wrap());
    let own_label = (m.components == 1 && hint.is_some_and(|h| h.checkbox)) || (m.components == 3 && hint.is_some_and(|h| h.color));
    if !own_label {
        // Above its widgets, wrapped: a long label beside a slider was
        // clipped at the panel's edge.
        wrapped(ui);
    }
    ui.horizontal_wrapped(|ui| {
        if m.components == 3 && hint.is_some_and(|h| h.color) {
            let mut rgb = [scalars[0] as f32, scalars[1] as f32, scalars[2] as f32];
            if ui.color_edit_button_rgb(&mut rgb).changed() {
                out = Some(ParamValue::Vector(rgb.iter().map(|&c| f64::from(c)).collect()));
            }
            wrapped(ui);
            return;
        }
        if m.components == 1 && hint.is_some_and(|h| h.checkbox) {
            let mut on = scalars[0] != 0.0;
            if ui.checkbox(&mut on, label.as_str()).changed() {
                out = Some(ParamValue::Int(i64::from(on)));
            }
            return;
        }
        let mut v = scalars.clone();
        let mut changed = false;
        for x in v.iter_mut() {
            let r = match hint.and_then(|h| h.range) {
                Some((lo, hi)) => ui.add(egui::Slider::new(x, lo..=hi).logarithmic(hint.is_some_and(|h| h.log)).integer_if(int)),
                None => ui.add(egui::DragValue::new(x).speed(if int { 1.0 } else { 0.01 }).range(if m.scalar == ScalarType::U32 { 0.0 } else { f64::MIN }..=f64::MAX)),
            };
            changed |= r.changed();
        }
        if changed {
            out = Some(match (v.len(), int) {
                (1, true) => ParamValue::Int(v[0].round() as i64),
                (1, false) => ParamValue::Float(v[0]),
                _ => ParamValue::Vector(if int { v.iter().map(|x| x.round()).collect() } else { v }),
            });
        }
    });
    out
}

trait IntegerIf {
    fn integer_if(self, int: bool) -> Self;
}

impl IntegerIf for egui::Slider<'_> {
    fn integer_if(self, int: bool) -> Self {
        if int { self.integer() } else { self }
    }
}

fn resources(ui: &mut Ui, session: &Session, state: &mut PanelState) {
    egui::CollapsingHeader::new("resources").default_open(false).show(ui, |ui| {
        let sched = &session.executor.schedule;
        let mut names: Vec<&str> = sched.versions.iter().map(|v| v.resource.as_str()).collect();
        names.sort();
        names.dedup();
        let shown = state.resource.clone().unwrap_or_else(|| format!("{} (output)", sched.output_resource));
        // Resource names in monospace: the proportional font's underscore
        // sits below the combo box's clip rect (`reflect_reuse` read as
        // `reflect reuse`).
        egui::ComboBox::from_id_salt("resource").selected_text(RichText::new(shown).monospace()).show_ui(ui, |ui| {
            if ui.selectable_label(state.resource.is_none(), "output").clicked() {
                state.resource = None;
            }
            for n in names {
                if ui.selectable_label(state.resource.as_deref() == Some(n), RichText::new(n).monospace()).clicked() {
                    state.resource = Some(n.to_string());
                }
            }
        });
        ui.add(egui::Slider::new(&mut state.exposure, -10.0..=10.0).text("exposure (stops)"));
        ui.horizontal(|ui| {
            for c in Channel::ALL {
                ui.selectable_value(&mut state.channel, c, c.label());
            }
        });
        ui.label(RichText::new("transient textures are pooled: a resource may show what a later pass wrote into its texture").weak());
    });
}

fn frame_time(ui: &mut Ui, input: &PanelInput) {
    egui::CollapsingHeader::new("frame time").default_open(true).show(ui, |ui| {
        let width = ui.available_width();
        ui.label("milliseconds between presented frames");
        egui_plot::Plot::new("frame_ms").width(width).height(110.0).include_y(0.0).allow_zoom(false).allow_drag(false).allow_scroll(false).show(ui, |p| {
            p.line(egui_plot::Line::new("frame ms", egui_plot::PlotPoints::Borrowed(input.frame_plot)));
        });
        if input.frames.target.is_some() {
            let thresholds = &input.frames.stats.thresholds;
            let start = thresholds.len().saturating_sub(300);
            let th: Vec<[f64; 2]> = thresholds[start..].iter().enumerate().map(|(i, t)| [(start + i) as f64, f64::from(*t)]).collect();
            ui.add(egui::Label::new("noise-mask threshold (0-1) the PID sets for the frame-time target: pixels noisier than it are refined").wrap());
            egui_plot::Plot::new("threshold").width(width).height(80.0).include_y(0.0).include_y(1.0).allow_zoom(false).allow_drag(false).allow_scroll(false).show(ui, |p| {
                p.line(egui_plot::Line::new("mask threshold", th));
            });
        }
    });
}

/// The help overlay (F1 or `?`): every key and mouse binding.
pub fn help(ctx: &egui::Context, open: &mut bool) {
    egui::Window::new("keys and mouse (F1 or ? closes)").open(open).collapsible(false).resizable(false).show(ctx, |ui| {
        egui::Grid::new("bindings").striped(true).show(ui, |ui| {
            for (key, what) in crate::viewer::keys::BINDINGS {
                ui.label(RichText::new(*key).monospace());
                ui.label(*what);
                ui.end_row();
            }
        });
    });
}
