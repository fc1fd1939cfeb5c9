//! The viewer: its panel actions go through the session calls the tests
//! use (checked headless), and under Xvfb on lavapipe a scripted run's
//! window shows what `glint render` renders for the same frames.

mod common;
mod xdnd;

use std::path::Path;
use std::process::Command;

use common::*;
use glint::graph::desc::ParamValue;
use glint::graph::edit::{GraphEdits, ParamSet};
use glint::graph::CompileOptions;
use glint::image_io;
use glint::machines::{self, Machines};
use glint::metrics;
use glint::session::frame_loop::{Clock, FrameLoop};
use glint::session::{Session, SessionOptions};
use glint::viewer::actions;
use glint::viewer::panels::Action;

const SIZE: (u32, u32) = (48, 48);

fn session_with(gpu: &glint::gpu::Gpu, graph: &str, edits: GraphEdits) -> Session {
    let options = SessionOptions { compile: CompileOptions { edits, ..Default::default() }, ..SessionOptions::new(SIZE) };
    Session::new(gpu, load_scene("cornell.ron"), &repo().join("passes").join(graph), options).unwrap_or_else(|e| panic!("{e}"))
}

fn frames(s: &mut Session, n: u32) -> Vec<u32> {
    for _ in 0..n {
        s.frame(0.0);
    }
    s.read_output().unwrap_or_else(|e| panic!("{e}")).data.iter().flat_map(|p| p.map(f32::to_bits)).collect()
}

#[test]
fn panel_actions_equal_command_line_edits() {
    let Some(gpu) = gpu() else { return };
    let mut clock = FrameLoop::new(0.0, Clock::Fixed { dt: 0.0 }, load_scene("cornell.ron").camera);

    // A param slider equals --set.
    let set = ParamSet { pass: "gbuffer".into(), param: "jitter".into(), value: ParamValue::Int(0) };
    let mut with_set = session_with(gpu, "hybrid-point.ron", GraphEdits { set: vec![set], ..Default::default() });
    let want = frames(&mut with_set, 3);
    let mut live = session_with(gpu, "hybrid-point.ron", GraphEdits::default());
    let before = frames(&mut live, 2);
    let action = Action::SetParam { pass: "gbuffer".into(), name: "jitter".into(), value: ParamValue::Int(0) };
    assert_eq!(actions::apply(&mut live, &mut clock, &[], SIZE, &action).map_err(|e| e.to_string()), Ok(None));
    let got = frames(&mut live, 3);
    assert_ne!(before, want, "the param should change the image");
    assert!(got == want, "set_param differs from --set");

    // A pass's checkbox equals --skip.
    let mut skipped = session_with(gpu, "hybrid-point.ron", GraphEdits { skip: vec!["reflections".into()], ..Default::default() });
    let want = frames(&mut skipped, 2);
    let mut live = session_with(gpu, "hybrid-point.ron", GraphEdits::default());
    frames(&mut live, 1);
    let off = Action::SetEnabled { pass: "reflections".into(), enabled: false };
    actions::apply(&mut live, &mut clock, &[], SIZE, &off).unwrap_or_else(|e| panic!("{e}"));
    assert!(!live.graph.schedule.passes.iter().any(|p| p.name == "reflections"));
    assert!(frames(&mut live, 2) == want, "switching a pass off differs from --skip");
    let on = Action::SetEnabled { pass: "reflections".into(), enabled: true };
    actions::apply(&mut live, &mut clock, &[], SIZE, &on).unwrap_or_else(|e| panic!("{e}"));
    assert!(live.graph.schedule.passes.iter().any(|p| p.name == "reflections"));

    // A bad value is the error --set gives, and changes nothing.
    let bad = Action::SetParam { pass: "gbuffer".into(), name: "jitter".into(), value: ParamValue::Float(0.5) };
    let e = actions::apply(&mut live, &mut clock, &[], SIZE, &bad).unwrap_err();
    assert!(e.to_string().contains("param `jitter` is U32"), "{e}");
    assert_eq!(live.param("gbuffer", "jitter"), Some(&ParamValue::Int(1)));

    // A machine profile: its graph, scaled size and target, in one rebuild.
    let m = Machines::load(&repo().join("passes/machines.ron")).unwrap_or_else(|e| panic!("{e}"));
    let cpu = m.profiles.iter().position(|p| p.name.starts_with("cpu")).expect("a cpu profile");
    actions::apply(&mut live, &mut clock, &m.profiles, (64, 64), &Action::SetProfile(cpu)).unwrap_or_else(|e| panic!("{e}"));
    let p = &m.profiles[cpu];
    assert!(live.graph.path.ends_with(&p.graph));
    assert_eq!(live.size, machines::scale_size((64, 64), p.resolution_scale));
    assert_eq!(clock.target.as_ref().map(|t| t.target_ms), Some(f64::from(p.target_ms)));
    frames(&mut live, 1);
}

/// `x,y WxH` from the viewer's screenshot line.
fn viewport(line: &str) -> (u32, u32, u32, u32) {
    let rest = line.split("viewport ").nth(1).unwrap_or_else(|| panic!("no viewport in `{line}`"));
    let (xy, wh) = rest.trim().split_once(' ').expect("x,y WxH");
    let (x, y) = xy.split_once(',').expect("x,y");
    let (w, h) = wh.split_once('x').expect("WxH");
    let n = |s: &str| s.trim().parse::<f32>().unwrap_or_else(|_| panic!("`{s}`")) as u32;
    (n(x), n(y), n(w), n(h))
}

/// Whether `xvfb-run` and a GPU adapter are here for a window test (CI
/// must have both: tools/test installs them).
fn can_run_xvfb() -> bool {
    if Command::new("xvfb-run").arg("--help").output().is_err() {
        assert!(std::env::var("CI").map_or(true, |v| v != "true"), "CI needs xvfb-run (tools/test installs it)");
        eprintln!("skipping: no xvfb-run");
        return false;
    }
    gpu().is_some()
}

#[test]
fn window_shows_what_render_renders() {
    let _window = one_window_at_a_time();
    if !can_run_xvfb() {
        return;
    }
    let dir = scratch("viewer");
    let shot = dir.join("view.png");
    let glint = env!("CARGO_BIN_EXE_glint");
    let (w, h) = (96, 64);
    let size = format!("{w}x{h}");
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24", glint, "view", "scenes/moving-lights.ron", "--graph", "passes/hybrid.ron", "--size", &size, "--frames", "30", "--screenshot"])
        .arg(&shot)
        .current_dir(repo())
        .env("WGPU_BACKEND", "vulkan")
        .output()
        .expect("run xvfb-run");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "glint view failed: {stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    let line = stdout.lines().find(|l| l.starts_with("screenshot")).unwrap_or_else(|| panic!("no screenshot line: {stdout}"));
    let (x, y, vw, vh) = viewport(line);
    assert_eq!((vw, vh), (w, h), "the render is shown at 1:1");
    let window = image::open(&shot).unwrap_or_else(|e| panic!("{e}")).to_rgb8();
    let crop = image::imageops::crop_imm(&window, x, y, w, h).to_image();
    let cropped = dir.join("viewport.png");
    crop.save(&cropped).expect("save crop");

    // The same 30 frames, headless: scene time 0, 1/30, ... as the viewer's
    // scripted clock steps it.
    let rendered = dir.join("render.png");
    let status = Command::new(glint)
        .args(["render", "scenes/moving-lights.ron", "--graph", "passes/hybrid.ron", "--size", &size, "--frames", "30", "--dt", "0.033333335", "--out"])
        .arg(&rendered)
        .current_dir(repo())
        .env("WGPU_BACKEND", "vulkan")
        .output()
        .expect("run glint render");
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let a = image_io::load(&rendered).unwrap_or_else(|e| panic!("{e}"));
    let b = image_io::load(&cropped).unwrap_or_else(|e| panic!("{e}"));
    let (flip, _) = metrics::flip(&a, &b);
    eprintln!("viewer viewport against glint render: FLIP mean {:.5}, p99 {:.5}", flip.mean, flip.p99);
    assert!(flip.mean <= 0.01, "the window shows another image: FLIP mean {}", flip.mean);
    // The EXR beside the screenshot is the graph output itself.
    assert!(Path::new(&shot.with_extension("exr")).is_file());
}

/// The window tests run one at a time: they time frames, and a path-traced
/// window beside them would take the cores their frames need.
fn one_window_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    static WINDOW: std::sync::Mutex<()> = std::sync::Mutex::new(());
    WINDOW.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A script for `under_xvfb`: starts `glint view ARGS`, waits for its
/// window (`$wid`) and then `settle` seconds, runs `body`, presses Esc and
/// prints `exit N` with the viewer's exit code.
fn viewer_script(args: &str, settle: u32, body: &str) -> String {
    format!(
        r#"
        "$GLINT" view {args} &
        pid=$!
        for i in $(seq 120); do wid=$(xdotool search --name "glint:" 2>/dev/null | head -1); [ -n "$wid" ] && break; sleep 0.5; done
        sleep {settle}
        {body}
        xdotool windowfocus "$wid"; sleep 0.3
        xdotool key Escape
        wait $pid
        echo "exit $?"
    "#
    )
}

/// Runs `script` (bash, with `$GLINT` the binary) under Xvfb with xdotool;
/// None where either is missing outside CI.
fn under_xvfb(script: &str) -> Option<std::process::Output> {
    let has = |tool: &str, arg: &str| Command::new(tool).arg(arg).output().is_ok();
    if !has("xvfb-run", "--help") || !has("xdotool", "version") {
        assert!(std::env::var("CI").map_or(true, |v| v != "true"), "CI needs xvfb-run and xdotool (tools/test installs them)");
        eprintln!("skipping: no xvfb-run or xdotool");
        return None;
    }
    gpu()?;
    Some(
        Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24", "bash", "-c", script])
            .current_dir(repo())
            .env("WGPU_BACKEND", "vulkan")
            .env("GLINT", env!("CARGO_BIN_EXE_glint"))
            .output()
            .expect("run xvfb-run"),
    )
}

#[test]
fn keys_and_mouse_reach_the_viewer_without_a_window_manager() {
    let _window = one_window_at_a_time();
    // No window manager: the window gets keyboard focus only when given it,
    // and the mouse events arrive between frames. The window is the panel
    // (340 points) and the 160x120 image beside it.
    let script = viewer_script(
        "scenes/cornell.ron --graph passes/hybrid.ron --size 160x120",
        3,
        r#"
        xdotool windowfocus "$wid"; sleep 0.3
        xdotool key c; sleep 1
        xdotool mousemove --window "$wid" 400 100 sleep 0.3 mousedown 3 sleep 0.3 mousemove --window "$wid" 430 120 sleep 0.3 mousemove --window "$wid" 460 140 sleep 0.3 mouseup 3
        sleep 1
        xdotool key c; sleep 1
        "#,
    );
    let Some(out) = under_xvfb(&script) else { return };
    let stdout = String::from_utf8_lossy(&out.stdout);
    let cameras: Vec<&str> = stdout.lines().filter(|l| l.starts_with("camera: Camera(")).collect();
    assert_eq!(cameras.len(), 2, "C prints the camera: {stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert_ne!(cameras[0], cameras[1], "a right-drag over the image turns the camera");
    assert!(stdout.lines().any(|l| l == "exit 0"), "Esc quits with exit 0: {stdout}");
}

#[test]
fn the_fps_and_frame_plot_show_what_the_frames_took() {
    let _window = one_window_at_a_time();
    // The test's own clock: from the first frame's line to the last's.
    let Some(_) = under_xvfb("true") else { return };
    let glint = env!("CARGO_BIN_EXE_glint");
    let mut child = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24", glint, "view", "scenes/cornell.ron", "--graph", "passes/pathtrace.ron", "--size", "96x64", "--frames", "40", "--screenshot"])
        .arg(scratch("viewer-fps").join("shot.png"))
        .current_dir(repo())
        .env("WGPU_BACKEND", "vulkan")
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("run xvfb-run");
    use std::io::BufRead as _;
    let lines = std::io::BufReader::new(child.stdout.take().expect("stdout"));
    let (mut first, mut last) = (None, None);
    for line in lines.lines().map_while(Result::ok) {
        if line == "first frame presented" {
            first = Some(std::time::Instant::now());
        } else if line.starts_with("last frame presented") {
            last = Some((std::time::Instant::now(), line));
        }
    }
    assert!(child.wait().expect("wait").success());
    let (first, (end, line)) = (first.expect("a first-frame line"), last.expect("a last-frame line"));
    let measured_ms = end.duration_since(first).as_secs_f64() * 1e3 / 39.0;
    let figure = |key: &str| -> f64 {
        let before = line.split(key).next().unwrap_or_else(|| panic!("no `{key}` in `{line}`"));
        before.trim_end().rsplit([' ', ',']).next().and_then(|s| s.parse().ok()).unwrap_or_else(|| panic!("no figure before `{key}` in `{line}`"))
    };
    let fps = figure(" FPS shown");
    let plot_ms = figure(" ms, last");
    eprintln!("{line}; measured {measured_ms:.1} ms a frame");
    assert!((fps * measured_ms / 1e3 - 1.0).abs() <= 0.2, "FPS shown {fps} against {:.2} measured", 1e3 / measured_ms);
    assert!((plot_ms / measured_ms - 1.0).abs() <= 0.2, "the plot's frame time {plot_ms} ms against {measured_ms:.1} ms measured");
}

#[test]
fn a_screenshot_that_cannot_be_written_fails_the_run() {
    let _window = one_window_at_a_time();
    let Some(_) = under_xvfb("true") else { return };
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24", env!("CARGO_BIN_EXE_glint"), "view", "scenes/cornell.ron", "--graph", "passes/hybrid.ron"])
        .args(["--size", "64x48", "--frames", "2", "--screenshot", "/nonexistent-folder/shot.png"])
        .current_dir(repo())
        .env("WGPU_BACKEND", "vulkan")
        .output()
        .expect("run xvfb-run");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "exit code; stderr: {stderr}");
    assert!(stderr.contains("nonexistent-folder"), "{stderr}");
    assert!(!String::from_utf8_lossy(&out.stdout).contains("watching"), "a scripted run watches nothing");
}

/// Not a test of its own: `a_dropped_scene_file_opens` runs the test binary
/// again with this one alone, under its Xvfb, as the drag-and-drop source.
#[test]
#[ignore = "run by a_dropped_scene_file_opens"]
fn drop_source() {
    let (Ok(window), Ok(file)) = (std::env::var("GLINT_DROP_WINDOW"), std::env::var("GLINT_DROP_FILE")) else { return };
    let window: u32 = window.trim().parse().expect("a window id");
    // Over the image, right of the 340-point panel.
    xdnd::drop_file(window, 400, 60, Path::new(&file)).unwrap_or_else(|e| panic!("drop: {e}"));
    println!("dropped {file}");
}

#[test]
fn a_dropped_scene_file_opens() {
    let _window = one_window_at_a_time();
    let dropped = repo().join("scenes/cornell-point.ron");
    let body = format!(
        r#"
        GLINT_DROP_WINDOW="$wid" GLINT_DROP_FILE="{}" "{}" --exact drop_source --ignored --nocapture --test-threads 1
        sleep 3
        echo "title: $(xdotool getwindowname "$wid")"
        "#,
        dropped.display(),
        std::env::current_exe().expect("the test binary").display()
    );
    let script = viewer_script("scenes/cornell.ron --graph passes/hybrid.ron --size 160x120", 3, &body);
    let Some(out) = under_xvfb(&script) else { return };
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains(&format!("dropped {}", dropped.display())), "the drop went through: {stdout}\n{stderr}");
    assert!(stdout.lines().any(|l| l.starts_with("opened ") && l.ends_with("cornell-point.ron")), "the viewer opened the dropped scene: {stdout}\n{stderr}");
    assert!(stdout.lines().any(|l| l.starts_with("title: glint: ") && l.contains("cornell-point.ron")), "the title names it: {stdout}");
    assert!(stdout.lines().any(|l| l == "exit 0"), "Esc quits with exit 0: {stdout}");
}

#[test]
fn the_panel_stays_live_while_a_frame_renders() {
    let _window = one_window_at_a_time();
    // Path-traced frames of thesis-env2 take a second or more on lavapipe;
    // the window's own frames go on between them.
    let script = viewer_script("scenes/thesis-env2.ron --graph passes/pathtrace.ron --size 480x270", 8, "");
    let Some(out) = under_xvfb(&script) else { return };
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout.lines().find(|l| l.starts_with("window: ")).unwrap_or_else(|| panic!("no summary line: {stdout}\n{}", String::from_utf8_lossy(&out.stderr)));
    let figure = |key: &str| -> f64 {
        let after = line.split(key).nth(1).unwrap_or_else(|| panic!("no `{key}` in `{line}`"));
        after.trim_start().split([' ', ',', ';']).next().and_then(|s| s.parse().ok()).unwrap_or_else(|| panic!("no figure after `{key}` in `{line}`"))
    };
    let (window_gap, scene_frames, scene_ms) = (figure("longest gap"), figure("scene:"), figure("median"));
    eprintln!("{line}");
    assert!(scene_frames >= 2.0, "the scene presented frames: {line}");
    if scene_ms < 600.0 {
        eprintln!("scene frames of {scene_ms} ms are too fast here to show a slow frame");
        return;
    }
    assert!(window_gap < 0.5 * scene_ms, "the window waited for the scene's frames: {line}");
    assert!(stdout.lines().any(|l| l == "exit 0"), "Esc quits with exit 0: {stdout}");
}

/// A render size beyond the adapter is refused as `render` refuses it
/// (exit 2), not a panic in the windowing library (issue 40: winit
/// panicked on a 100000-pixel window).
#[test]
fn a_size_no_adapter_renders_is_refused() {
    let _window = one_window_at_a_time();
    if !can_run_xvfb() {
        return;
    }
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24", env!("CARGO_BIN_EXE_glint"), "view", "scenes/cornell.ron"])
        .args(["--size", "100000x100000", "--frames", "1", "--screenshot"])
        .arg(scratch("viewer-huge").join("never.png"))
        .current_dir(repo())
        .env("WGPU_BACKEND", "vulkan")
        .output()
        .expect("run xvfb-run");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    // (The size named is after the machine profile's resolution scale.)
    assert!(stderr.contains("is beyond this adapter's limit") && !stderr.contains("panicked"), "{stderr}");
}
