//! Hot reload (docs/ARCHITECTURE.md, "The session" and "Reload protocol"):
//! through the `Session` API (which pipelines a shared import rebuilds, a
//! broken shader keeping the last good image, graph and scene edits keeping
//! what was set live, live changes equal to the command line's) and through
//! `glint render --watch` (each kind of save picked up once, a burst ending
//! on its last content, a broken save reported and the output kept, Ctrl-C
//! exiting 0), and pipelines built through a cache kept across runs.
//! Every test works in a scratch copy of shaders/, passes/ and scenes/.
//! That reloads release what they replace is checked in
//! tests/reload_leak.rs, alone in its process.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use glint::gpu::readback::ImageF32;
use glint::gpu::Gpu;
use glint::graph::desc::ParamValue;
use glint::graph::edit::{GraphEdits, ParamSet};
use glint::graph::CompileOptions;
use glint::session::rebuild::RebuildKind;
use glint::session::{Session, SessionOptions};

const SIZE: (u32, u32) = (32, 32);

/// The line of shaders/lights.wgsl the tests edit (without its `;`).
const RADIANCE: &str = "    let radiance = finite_or_zero(diffuse / PI * irradiance + highlight)";

// -- helpers -----------------------------------------------------------------

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Saves as editors that write a temporary file and rename it over the old
/// one do: the watcher never sees a half-written file.
fn save_atomic(path: &Path, text: &str) {
    let tmp = path.with_extension("saving");
    write(&tmp, text);
    std::fs::rename(&tmp, path).expect("rename over the file");
}

fn write(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

/// `text` with the first `from` after `anchor` replaced by `to`.
fn edit_after(text: &str, anchor: &str, from: &str, to: &str) -> String {
    let at = text.find(anchor).unwrap_or_else(|| panic!("`{anchor}` not found"));
    let rel = text[at..].find(from).unwrap_or_else(|| panic!("`{from}` not found after `{anchor}`"));
    let i = at + rel;
    format!("{}{to}{}", &text[..i], &text[i + from.len()..])
}

/// The original shaders/lights.wgsl and the 1-based line of `RADIANCE`.
fn lights_original(ws: &Path) -> (String, usize) {
    let text = read(&ws.join("shaders/lights.wgsl"));
    let line = text.lines().position(|l| l == format!("{RADIANCE};")).unwrap_or_else(|| panic!("lights.wgsl has no line `{RADIANCE};`"));
    (text, line + 1)
}

/// lights.wgsl with its radiance scaled by `scale` (a WGSL float literal).
fn lights_scaled(original: &str, scale: &str) -> String {
    original.replacen(&format!("{RADIANCE};"), &format!("{RADIANCE} * {scale};"), 1)
}

/// lights.wgsl with a type error (a vec3f into an f32) on the radiance line.
fn lights_broken(original: &str) -> String {
    original.replacen(&format!("{RADIANCE};"), "    let radiance: f32 = finite_or_zero(diffuse / PI * irradiance + highlight);", 1)
}

fn open(gpu: &Gpu, ws: &Path, scene: &str, graph: &str, compile: CompileOptions) -> Session {
    let scene = glint::scene::load(&ws.join("scenes").join(scene)).unwrap_or_else(|e| panic!("{e}"));
    let options = SessionOptions { compile, ..SessionOptions::new(SIZE) };
    Session::new(gpu, scene, &ws.join("passes").join(graph), options).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders `n` frames and reads the output.
fn frames(s: &mut Session, n: u32) -> ImageF32 {
    for _ in 0..n {
        s.frame(0.0);
    }
    s.read_output().unwrap_or_else(|e| panic!("{e}"))
}

fn bits(img: &ImageF32) -> Vec<u32> {
    img.data.iter().flat_map(|p| p.map(f32::to_bits)).collect()
}

fn same(a: &ImageF32, b: &ImageF32) -> bool {
    (a.width, a.height) == (b.width, b.height) && bits(a) == bits(b)
}

fn differing(a: &ImageF32, b: &ImageF32) -> usize {
    a.data.iter().zip(&b.data).filter(|(x, y)| x.map(f32::to_bits) != y.map(f32::to_bits)).count()
}

fn sets(list: &[(&str, &str, ParamValue)]) -> CompileOptions {
    let set = list.iter().map(|(p, n, v)| ParamSet { pass: p.to_string(), param: n.to_string(), value: v.clone() }).collect();
    CompileOptions { edits: GraphEdits { set, ..Default::default() }, ..Default::default() }
}

// -- through the Session API -------------------------------------------------

#[test]
fn shared_import_edit_rebuilds_exactly_the_passes_that_import_it() {
    let Some(gpu) = common::gpu() else { return };
    let ws = common::workspace("reload-import");
    let mut s = open(gpu, &ws, "cornell.ron", "hybrid.ron", CompileOptions::default());
    let rng = ws.join("shaders/shared/rng.wgsl");
    // Expected independently of the session: load each scheduled pass's
    // shader afresh and look for rng.wgsl in its import closure.
    let expected: Vec<String> = s
        .graph
        .schedule
        .passes
        .iter()
        .filter(|p| {
            let shader = glint::shader::load(&ws.join("shaders"), &p.shader).unwrap_or_else(|e| panic!("{e}"));
            shader.source.files.iter().any(|f| std::fs::canonicalize(f).ok().as_deref() == Some(rng.as_path()))
        })
        .map(|p| p.name.clone())
        .collect();
    let all: Vec<String> = s.graph.schedule.passes.iter().map(|p| p.name.clone()).collect();
    assert!(
        expected.iter().any(|p| p == "gbuffer") && expected.iter().any(|p| p == "lights_area") && !expected.iter().any(|p| p == "accumulate"),
        "rng.wgsl should be imported by some passes and not others: {expected:?} of {all:?}"
    );
    let before = frames(&mut s, 2);

    let mut text = read(&rng);
    text.push_str("\n// an edit that changes the text but no pixel\n");
    write(&rng, &text);
    let report = s.reload_shaders(std::slice::from_ref(&rng)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.kind, RebuildKind::Shaders(vec![rng.clone()]));
    assert_eq!(report.rebuilt, expected, "passes rebuilt for an edit of rng.wgsl (scheduled: {all:?})");
    // The swap restarted the frame state: the same frames as before the edit.
    assert!(same(&frames(&mut s, 2), &before), "a comment-only edit changed the image");

    let kept = s.accumulated();
    let again = s.reload_shaders(std::slice::from_ref(&rng)).unwrap_or_else(|e| panic!("{e}"));
    assert!(again.rebuilt.is_empty(), "a reload without a change rebuilt {:?}", again.rebuilt);
    assert_eq!(s.accumulated(), kept, "a reload that changed nothing keeps the history");
    s.restart();
    assert!(same(&frames(&mut s, 2), &before));
}

#[test]
fn broken_shader_names_file_and_line_and_keeps_the_last_good_image() {
    let Some(gpu) = common::gpu() else { return };
    let ws = common::workspace("reload-broken");
    let lights = ws.join("shaders/lights.wgsl");
    let (original, line) = lights_original(&ws);
    let mut s = open(gpu, &ws, "cornell.ron", "hybrid.ron", CompileOptions::default());
    let before = frames(&mut s, 2);

    write(&lights, &lights_broken(&original));
    let err = s.reload_shaders(std::slice::from_ref(&lights)).expect_err("a type error must fail the reload").to_string();
    let at = format!("{}:{line}:", lights.display());
    assert!(err.starts_with(&at), "expected the error to start with `{at}`: {err}");
    s.restart();
    assert!(same(&frames(&mut s, 2), &before), "after a failed reload the session no longer renders the last good image");

    write(&lights, &lights_scaled(&original, "0.5"));
    let report = s.reload_shaders(std::slice::from_ref(&lights)).unwrap_or_else(|e| panic!("the fixed shader did not reload: {e}"));
    assert_eq!(report.rebuilt, vec!["lights_area".to_string()]);
    let fixed = frames(&mut s, 2);
    assert!(differing(&fixed, &before) > 0, "the fix (radiance halved) did not change the image");
    let fresh = frames(&mut open(gpu, &ws, "cornell.ron", "hybrid.ron", CompileOptions::default()), 2);
    assert!(same(&fixed, &fresh), "after the fix: {} pixels differ from a fresh render of the fixed shader", differing(&fixed, &fresh));
}

#[test]
fn graph_edit_keeps_params_set_live() {
    let Some(gpu) = common::gpu() else { return };
    let ws = common::workspace("reload-graph");
    let graph = ws.join("passes/hybrid.ron");
    let mut s = open(gpu, &ws, "cornell.ron", "hybrid.ron", CompileOptions::default());
    s.set_param("accumulate", "max_history", ParamValue::Int(1)).unwrap_or_else(|e| panic!("{e}"));

    // Another pass's param, in the graph file.
    let text = edit_after(&read(&graph), "name: \"lights_area\"", "samples: 1,", "samples: 3,");
    write(&graph, &text);
    let report = s.reload_graph(&graph).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.kind, RebuildKind::Graph(graph.clone()));
    assert_eq!(s.param("accumulate", "max_history"), Some(&ParamValue::Int(1)), "the live param was dropped by the graph edit");
    assert_eq!(s.param("lights_area", "samples"), Some(&ParamValue::Int(3)), "the graph edit did not apply");
    assert_eq!(s.param("accumulate", "mode"), Some(&ParamValue::Int(1)));
    assert_eq!(s.param("lights_point", "samples"), None, "lights_point is culled on cornell");

    // And on the GPU: the image of a fresh `--set` render of the edited graph.
    let live = frames(&mut s, 3);
    let with_set = frames(&mut open(gpu, &ws, "cornell.ron", "hybrid.ron", sets(&[("accumulate", "max_history", ParamValue::Int(1))])), 3);
    assert!(same(&live, &with_set), "{} pixels differ from a fresh render with --set", differing(&live, &with_set));
    let without = frames(&mut open(gpu, &ws, "cornell.ron", "hybrid.ron", CompileOptions::default()), 3);
    assert!(differing(&live, &without) > 0, "max_history=1 does not change the image, so this test proves nothing");
}

#[test]
fn scene_edit_keeps_the_camera() {
    let Some(gpu) = common::gpu() else { return };
    let ws = common::workspace("reload-scene");
    let path = ws.join("scenes/cornell.ron");
    let mut s = open(gpu, &ws, "cornell.ron", "hybrid.ron", CompileOptions::default());
    let original = s.scene.scene.camera;
    s.scene.scene.camera.position = glam::DVec3::new(0.35, 0.25, 3.0);
    let moved = s.scene.scene.camera;
    assert_ne!(moved, original);
    let before = frames(&mut s, 2);

    let text = read(&path);
    let red = "\"red\":    Material(albedo: (0.63, 0.065, 0.05))";
    assert!(text.contains(red), "cornell.ron has no `{red}`");
    write(&path, &text.replacen(red, "\"red\":    Material(albedo: (0.05, 0.065, 0.63))", 1));
    let report = s.reload_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.kind, RebuildKind::Scene(path.clone()));
    assert_eq!(s.scene.scene.camera, moved, "the scene reload moved the camera");
    let after = frames(&mut s, 2);
    assert!(differing(&after, &before) > 0, "the red wall turned blue but the image did not change");

    let mut scene = glint::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.camera = moved;
    let mut fresh = Session::new(gpu, scene, &ws.join("passes/hybrid.ron"), SessionOptions::new(SIZE)).unwrap_or_else(|e| panic!("{e}"));
    let fresh = frames(&mut fresh, 2);
    assert!(same(&after, &fresh), "{} pixels differ from a fresh render of the edited scene from the moved camera", differing(&after, &fresh));
}

#[test]
fn set_param_and_set_enabled_equal_set_and_skip() {
    const N: u32 = 2;
    let Some(gpu) = common::gpu() else { return };
    let ws = common::workspace("reload-live");

    // set_param == --set
    let samples = ("lights_area", "samples", ParamValue::Int(4));
    let cli = frames(&mut open(gpu, &ws, "cornell.ron", "hybrid.ron", sets(std::slice::from_ref(&samples))), N);
    let mut live = open(gpu, &ws, "cornell.ron", "hybrid.ron", CompileOptions::default());
    let default = frames(&mut live, N);
    assert!(differing(&cli, &default) > 0, "--set lights_area.samples=4 does not change the image, so this test proves nothing");
    live.set_param(samples.0, samples.1, samples.2.clone()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(live.param(samples.0, samples.1), Some(&samples.2));
    let after = frames(&mut live, N);
    assert!(same(&after, &cli), "set_param: {} pixels differ from --set", differing(&after, &cli));

    // set_enabled(false) == --skip
    let skip = CompileOptions { edits: GraphEdits { skip: vec!["reflections".into()], ..Default::default() }, ..Default::default() };
    let cli = frames(&mut open(gpu, &ws, "cornell.ron", "hybrid-point.ron", skip), N);
    let mut live = open(gpu, &ws, "cornell.ron", "hybrid-point.ron", CompileOptions::default());
    let default = frames(&mut live, N);
    assert!(differing(&cli, &default) > 0, "--skip reflections does not change the image of the mirror sphere");
    live.set_enabled("reflections", false).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(live.disabled(), ["reflections".to_string()]);
    assert!(!live.graph.schedule.passes.iter().any(|p| p.name == "reflections"));
    let after = frames(&mut live, N);
    assert!(same(&after, &cli), "set_enabled(false): {} pixels differ from --skip", differing(&after, &cli));
    // And back on: the default image again.
    live.set_enabled("reflections", true).unwrap_or_else(|e| panic!("{e}"));
    assert!(live.disabled().is_empty());
    let back = frames(&mut live, N);
    assert!(same(&back, &default), "set_enabled(true): {} pixels differ from the default render", differing(&back, &default));
}

// -- through `glint render --watch` ------------------------------------------

/// Generous: each reload re-renders on a CPU adapter while other tests run.
const LINE_TIMEOUT: Duration = Duration::from_secs(20);
/// A `glint render --watch` child with its stdout read line by line.
struct Watch {
    child: Child,
    lines: Receiver<String>,
    stdout: Vec<String>,
    stderr: Arc<Mutex<String>>,
    barriers: u32,
}

impl Watch {
    fn start(dir: &Path, args: &[&str]) -> Watch {
        let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
            .args(args)
            .current_dir(dir)
            .env("WGPU_BACKEND", std::env::var("WGPU_BACKEND").unwrap_or_else(|_| "vulkan".into()))
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start glint");
        let (tx, lines) = channel();
        let out = child.stdout.take().expect("stdout");
        std::thread::spawn(move || {
            for line in BufReader::new(out).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let stderr = Arc::new(Mutex::new(String::new()));
        let sink = Arc::clone(&stderr);
        let mut err = child.stderr.take().expect("stderr");
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = err.read(&mut buf) {
                if n == 0 {
                    break;
                }
                sink.lock().unwrap().push_str(&String::from_utf8_lossy(&buf[..n]));
            }
        });
        Watch { child, lines, stdout: Vec::new(), stderr, barriers: 0 }
    }

    fn output(&self) -> String {
        format!("stdout:\n{}\nstderr:\n{}", self.stdout.join("\n"), self.stderr.lock().unwrap())
    }

    /// The next stdout line within `timeout`.
    fn next(&mut self, timeout: Duration) -> Option<String> {
        match self.lines.recv_timeout(timeout) {
            Ok(line) => {
                self.stdout.push(line.clone());
                Some(line)
            }
            Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => None,
        }
    }

    /// Waits for a line starting with `prefix`; the lines before it must
    /// not be events (`reloaded`, `error:`).
    fn expect(&mut self, prefix: &str, timeout: Duration) -> String {
        let end = Instant::now() + timeout;
        loop {
            let left = end.saturating_duration_since(Instant::now());
            let Some(line) = self.next(left) else {
                panic!("no line starting `{prefix}` within {timeout:?}\n{}", self.output());
            };
            if line.starts_with(prefix) {
                return line;
            }
            assert!(!is_event(&line), "unexpected `{line}` while waiting for `{prefix}`\n{}", self.output());
        }
    }

    /// The lines that arrive until `quiet` passes without one.
    fn until_quiet(&mut self, quiet: Duration) -> Vec<String> {
        let mut lines = Vec::new();
        while let Some(line) = self.next(quiet) {
            lines.push(line);
        }
        lines
    }

    /// A barrier: saves a `.wgsl` file that no shader imports and waits
    /// for its reload (0 passes rebuilt). The watcher handles batches in
    /// order, so by then every event of the saves before it has been
    /// printed: returns those event lines (not counting the barrier's own,
    /// unless its batch also held other files).
    fn barrier(&mut self, ws: &Path) -> Vec<String> {
        self.barriers += 1;
        save_atomic(&ws.join("shaders").join(BARRIER), &format!("// barrier {}\n", self.barriers));
        let end = Instant::now() + LINE_TIMEOUT;
        let mut events = Vec::new();
        loop {
            let left = end.saturating_duration_since(Instant::now());
            let Some(line) = self.next(left) else {
                panic!("the barrier save was not picked up within {LINE_TIMEOUT:?}\n{}", self.output());
            };
            if let Some(subject) = line.strip_prefix("reloaded ").and_then(|l| l.split(": ").next()) {
                if subject.split(", ").any(|f| f.ends_with(BARRIER)) {
                    if subject.split(", ").any(|f| !f.ends_with(BARRIER)) {
                        events.push(line);
                    }
                    return events;
                }
            }
            if is_event(&line) {
                events.push(line);
            }
        }
    }
}

/// The file `Watch::barrier` saves.
const BARRIER: &str = "zz_barrier.wgsl";

impl Drop for Watch {
    fn drop(&mut self) {
        // A failed test must not leave the watcher running (a no-op once it
        // has been waited for).
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn is_event(line: &str) -> bool {
    line.starts_with("reloaded ") || line.starts_with("error: ") || line.starts_with("waiting for ")
}

fn load_png(path: &Path) -> ImageF32 {
    glint::image_io::load(path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn watch_picks_up_each_save_once_and_keeps_the_last_good_shader() {
    if common::gpu().is_none() {
        return;
    }
    let ws = common::workspace("reload-watch");
    let lights = ws.join("shaders/lights.wgsl");
    let (original, line) = lights_original(&ws);
    // How the watcher may name the file: relative to its current folder
    // (the workspace) or absolute.
    let names = ["shaders/lights.wgsl".to_string(), lights.display().to_string()];
    let out = ws.join("out.png");
    let render = ["render", "scenes/cornell.ron", "--graph", "passes/hybrid.ron", "--size", "32x32", "--frames", "1"];
    let mut args = render.to_vec();
    args.extend(["--out", "out.png", "--watch"]);
    let mut w = Watch::start(&ws, &args);
    w.expect("watching ", Duration::from_secs(90));
    let first = load_png(&out);

    // Save by renaming a temporary file over the shader (vim, JetBrains).
    let tmp = ws.join("shaders/lights.wgsl.saving");
    write(&tmp, &lights_scaled(&original, "0.9"));
    std::fs::rename(&tmp, &lights).expect("rename over lights.wgsl");
    let reloaded = w.expect("reloaded ", LINE_TIMEOUT);
    assert!(names.iter().any(|n| reloaded.starts_with(&format!("reloaded {n}: 1 pass rebuilt"))), "{reloaded}");
    let extra = w.barrier(&ws);
    assert!(extra.is_empty(), "a rename-over save was picked up more than once: {extra:?}\n{}", w.output());
    assert!(differing(&load_png(&out), &first) > 0, "the output did not change after the reload");

    // Save by truncating and writing in place (the file is empty for a
    // moment: the watcher waits for content; a pause after the truncate
    // makes that moment long enough to be seen).
    {
        let text = lights_scaled(&original, "0.8");
        let mut f = std::fs::OpenOptions::new().write(true).truncate(true).open(&lights).expect("open lights.wgsl");
        f.flush().expect("flush lights.wgsl");
        std::thread::sleep(Duration::from_millis(250));
        f.write_all(text.as_bytes()).expect("write lights.wgsl");
    }
    let reloaded = w.expect("reloaded ", LINE_TIMEOUT);
    assert!(names.iter().any(|n| reloaded.starts_with(&format!("reloaded {n}: 1 pass rebuilt"))), "{reloaded}");
    let extra = w.barrier(&ws);
    assert!(extra.is_empty(), "a truncate-then-write save was picked up more than once: {extra:?}\n{}", w.output());
    let before_burst = load_png(&out);

    // A save that changes nothing (same text) is skipped.
    save_atomic(&lights, &lights_scaled(&original, "0.8"));
    let extra = w.barrier(&ws);
    assert!(extra.is_empty(), "a save of the same text was not skipped: {extra:?}\n{}", w.output());

    // A burst of 20 saves in under 100 ms ends on the last content (it may
    // take more than one reload if the machine stalls mid-burst).
    let start = Instant::now();
    for i in 0..20 {
        write(&lights, &lights_scaled(&original, &format!("{:.2}", 0.3 + 0.05 * f64::from(i))));
        std::thread::sleep(Duration::from_millis(3));
    }
    let burst_ms = start.elapsed().as_millis();
    w.expect("reloaded ", LINE_TIMEOUT);
    let more = w.barrier(&ws);
    assert!(more.iter().all(|l| l.starts_with("reloaded ") && l.contains("lights.wgsl")), "the burst gave: {more:?}\n{}", w.output());
    let status = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(render)
        .args(["--out", "fresh.png"])
        .current_dir(&ws)
        .env("WGPU_BACKEND", std::env::var("WGPU_BACKEND").unwrap_or_else(|_| "vulkan".into()))
        .stdout(Stdio::null())
        .output()
        .expect("run glint render");
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let fresh = load_png(&ws.join("fresh.png"));
    let last_good = load_png(&out);
    assert!(differing(&last_good, &before_burst) > 0, "the output did not change after the burst ({burst_ms} ms)");
    assert!(
        same(&last_good, &fresh),
        "after a burst of 20 saves in {burst_ms} ms ({} reloads) the output is not a fresh render of the last content ({} pixels differ)\n{}",
        more.len() + 1,
        differing(&last_good, &fresh),
        w.output()
    );

    // A file left empty, then replaced by a link to a device: each wait is
    // said once, nothing is rebuilt, and content brings the reload.
    write(&lights, "");
    let waiting = w.expect("waiting for ", LINE_TIMEOUT);
    assert!(waiting.ends_with("to have content: it is empty (keeping the last good state)"), "{waiting}");
    assert!(names.iter().any(|n| waiting.starts_with(&format!("waiting for {n} "))), "{waiting}");
    #[cfg(unix)]
    {
        let link = ws.join("shaders/lights.wgsl.link");
        std::os::unix::fs::symlink("/dev/zero", &link).expect("symlink to /dev/zero");
        std::fs::rename(&link, &lights).expect("rename the link over lights.wgsl");
        let waiting = w.expect("waiting for ", LINE_TIMEOUT);
        assert!(waiting.contains("it is not a regular file"), "{waiting}");
        std::fs::remove_file(&lights).expect("remove the link");
    }
    save_atomic(&lights, &lights_scaled(&original, "0.30"));
    let reloaded = w.expect("reloaded ", LINE_TIMEOUT);
    assert!(reloaded.contains("lights.wgsl: 1 pass rebuilt"), "{reloaded}");
    assert!(w.barrier(&ws).is_empty(), "{}", w.output());
    let last_good = load_png(&out);

    // A broken save: one error line naming file and line; the output stays.
    let png_bytes = std::fs::read(&out).expect("read out.png");
    let png_time = std::fs::metadata(&out).and_then(|m| m.modified()).expect("out.png mtime");
    save_atomic(&lights, &lights_broken(&original));
    let error = w.expect("error: ", LINE_TIMEOUT);
    let at: Vec<String> = names.iter().map(|n| format!("error: {n}:{line}:")).collect();
    assert!(at.iter().any(|a| error.starts_with(a)), "expected one of {at:?}: {error}");
    assert!(error.ends_with("(keeping the last good shader)"), "{error}");
    assert_eq!(std::fs::read(&out).expect("read out.png"), png_bytes, "a broken save rewrote the output");
    assert_eq!(std::fs::metadata(&out).and_then(|m| m.modified()).expect("out.png mtime"), png_time, "a broken save rewrote the output");
    let extra = w.barrier(&ws);
    assert!(extra.is_empty(), "a broken save was reported more than once: {extra:?}\n{}", w.output());
    // The barrier's reload re-rendered with the last good lights shader.
    assert!(same(&load_png(&out), &last_good), "after a broken save the session no longer renders the last good shader");

    // Ctrl-C ends it with exit code 0.
    let pid = w.child.id().to_string();
    let kill = Command::new("kill").args(["-INT", &pid]).status().expect("run kill");
    assert!(kill.success());
    let end = Instant::now() + LINE_TIMEOUT;
    let status = loop {
        if let Some(status) = w.child.try_wait().expect("wait for glint") {
            break status;
        }
        assert!(Instant::now() < end, "glint did not exit within {LINE_TIMEOUT:?} of SIGINT\n{}", w.output());
        std::thread::sleep(Duration::from_millis(50));
    };
    let rest = w.until_quiet(Duration::from_millis(500));
    assert_eq!(status.code(), Some(0), "exit status after SIGINT: {status}\n{}", w.output());
    assert!(rest.iter().any(|l| l == "stopped watching"), "{rest:?}\n{}", w.output());
}

#[test]
fn pipelines_are_built_through_a_cache_kept_across_runs_and_a_damaged_one_is_set_aside() {
    let Some(gpu) = common::gpu() else { return };
    use glint::gpu::pipeline_cache::DiskPipelineCache;
    use glint::graph::pipelines::PipelineCache;
    let dir = common::scratch("pipeline-cache");
    let Some(disk) = DiskPipelineCache::open(&gpu.device, &gpu.info, &dir) else {
        eprintln!("{}: no pipeline cache on this adapter", gpu.info.name);
        return;
    };
    let scene = common::load_scene("cornell.ron");
    let graph = common::compile(&scene, &common::repo().join("passes/realtime.ron"), &CompileOptions::default());
    let build = |disk: &DiskPipelineCache| PipelineCache::default().build(&gpu.device, Some(disk), &graph, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(!build(&disk).built.is_empty());
    // Saved once pipelines were built, under the adapter's key.
    let saved = std::fs::read(disk.file()).unwrap_or_else(|e| panic!("no cache file at {}: {e}", disk.file().display()));
    assert!(!saved.is_empty(), "an empty cache file");
    // The next run starts from it; a damaged file starts an empty cache.
    let again = DiskPipelineCache::open(&gpu.device, &gpu.info, &dir).unwrap_or_else(|| panic!("the cache did not open again"));
    build(&again);
    std::fs::write(disk.file(), b"not a pipeline cache").unwrap_or_else(|e| panic!("{e}"));
    let damaged = DiskPipelineCache::open(&gpu.device, &gpu.info, &dir).unwrap_or_else(|| panic!("a damaged file kept the cache from opening"));
    build(&damaged);
    damaged.save();
    assert!(gpu.uncaptured.lock().map(|u| u.is_empty()).unwrap_or(true), "GPU errors: {:?}", gpu.uncaptured.lock().map(|u| u.clone()));
}
