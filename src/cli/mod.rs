//! The `glint` command line.

/// `println!` to stdout, ignoring write errors: `glint compare a b | head`
/// closes the pipe early, and that must neither panic nor stop the command
/// before it has written its files.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

/// `print!` with the same rule as `out!`.
macro_rules! out_raw {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout().lock(), $($arg)*);
    }};
}

mod bake_cmd;
mod bench_cmd;
mod bench_frames;
mod converge_cmd;
mod graph_cmd;
mod render_cmd;
mod stress;
mod thesis_cmd;
mod trade_cmd;
mod trade_motion;
mod trade_run;
mod trips;
mod view_cmd;
mod watch_cmd;

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::error::UserError;

/// The parsed command line.
#[derive(Parser, Debug)]
#[command(name = "glint", version, about = "A real-time ray tracer in WGSL compute shaders")]
pub struct Cli {
    /// The subcommand to run.
    #[command(subcommand)]
    pub command: Command,
}

/// A `glint` subcommand.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene headless to a PNG (sRGB) or EXR (linear) file.
    Render(render_cmd::RenderArgs),
    /// Speed against accuracy: every graph's error against a reference,
    /// frame by frame (trade.csv, trade.md).
    Trade(trade_cmd::TradeArgs),
    /// Bake a graph's irradiance volume alone (progress, seconds, MiB);
    /// --out saves it for `glint render --volume`.
    Bake(bake_cmd::BakeArgs),
    /// Benchmarks.
    Bench {
        /// Which benchmark.
        #[command(subcommand)]
        command: bench_cmd::BenchCommand,
    },
    /// Frame graph tools.
    Graph {
        /// Which tool.
        #[command(subcommand)]
        command: GraphCommand,
    },
    /// Compare an image with a reference: FLIP, relMSE, PSNR, block error.
    Compare {
        /// The reference image (.png, .exr or .pfm).
        reference: PathBuf,
        /// The image measured against it, of the same size.
        test: PathBuf,
        /// Block size for the block-averaged relative error (at least 1).
        #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..))]
        block: u32,
    },
    /// Open a window on a scene: panels, fly/orbit camera, hot reload.
    View(view_cmd::ViewArgs),
    /// Print this adapter, the machine profile it gets and why, and every
    /// profile of passes/machines.ron.
    Machines,
    /// Validate WGSL shaders with naga (all of shaders/ when none are named).
    Shaders {
        /// Shader files under the shader folder, e.g. lights.wgsl.
        files: Vec<String>,
        /// The shader folder (default: shaders).
        #[arg(long)]
        dir: Option<PathBuf>,
    },
}

/// A `glint graph` tool.
#[derive(Subcommand, Debug)]
pub enum GraphCommand {
    /// Compile a graph and print its schedule.
    Check(graph_cmd::CheckArgs),
}

/// A finite number of seconds (`--time`, `--dt`): NaN and infinities are
/// refused here, as the scene file refuses them.
pub fn parse_seconds(s: &str) -> Result<f32, String> {
    let v: f32 = s.trim().parse().map_err(|_| format!("`{s}` is not a number of seconds"))?;
    if !v.is_finite() || v.abs() > 1e9 {
        return Err(format!("`{s}`: give a finite number of seconds within +-1e9"));
    }
    Ok(v)
}

/// Parses `WxH` (or `WXH`) as a size in pixels, both sides at least 1.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("`{s}` is not a size; write WxH, e.g. 256x256"))?;
    let w: u32 = w.trim().parse().map_err(|_| format!("`{w}` is not a whole number of pixels"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("`{h}` is not a whole number of pixels"))?;
    if w == 0 || h == 0 {
        return Err(format!("the size {w}x{h} is empty; both sides must be at least 1"));
    }
    Ok((w, h))
}

/// An image to measure with or against: metrics of non-finite pixels are
/// NaN, and a gate written as "relmse > x fails" would pass them, so such
/// input is refused.
pub(crate) fn load_finite(path: &std::path::Path) -> Result<crate::gpu::readback::ImageF32, UserError> {
    let img = crate::image_io::load(path)?;
    if let Some((count, x, y)) = crate::metrics::non_finite(&img) {
        return Err(UserError::in_file(path, format!("{count} pixels hold NaN or infinite values (the first at x {x}, y {y}); errors are measured on finite images")));
    }
    Ok(img)
}

fn compare(reference: &std::path::Path, test: &std::path::Path, block: u32) -> Result<(), UserError> {
    let r = load_finite(reference)?;
    let t = load_finite(test)?;
    if (r.width, r.height) != (t.width, t.height) {
        return Err(UserError::in_file(test, format!("is {}x{}, the reference is {}x{}", t.width, t.height, r.width, r.height)));
    }
    let (flip, _) = crate::metrics::flip(&r, &t);
    let b = crate::metrics::block_relative_error(&r, &t, block, 0.01);
    out!("flip_mean={:.5}", flip.mean);
    out!("flip_p99={:.5}", flip.p99);
    out!("relmse={:.6}", crate::metrics::rel_mse(&r, &t));
    out!("psnr_db={:.3}", crate::metrics::psnr(&r, &t));
    out!("block{block}_rel_err_mean={:.5}", b.mean);
    out!("block{block}_rel_err_p95={:.5}", b.p95);
    out!("block{block}_rel_err_max={:.5}", b.max);
    out!("luminance_ratio={:.5}", b.luminance_ratio);
    Ok(())
}

/// Switches off Mesa's device-select Vulkan layer unless the user set it
/// up: it connects to a Wayland display just to order the adapters, and on
/// a machine without one (headless, Xvfb) libwayland prints
/// "error: XDG_RUNTIME_DIR is invalid or not set" twice, which reads like
/// glint failing. glint orders adapters itself (`WGPU_ADAPTER_NAME` picks
/// one). Called first thing in `main`, before any thread exists.
fn quiet_platform() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // SAFETY of intent: single-threaded here, before any wgpu call.
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// Runs the command line; returns the process exit code.
pub fn main() -> i32 {
    quiet_platform();
    let cli = Cli::parse();
    let result: Result<(), UserError> = match cli.command {
        Command::Render(args) => watch_cmd::run(&args),
        Command::View(args) => view_cmd::run(args),
        Command::Machines => view_cmd::machines(),
        Command::Bake(args) => bake_cmd::run(args),
        Command::Trade(args) => trade_cmd::run(args),
        Command::Bench { command } => bench_cmd::run(command),
        Command::Graph { command: GraphCommand::Check(args) } => graph_cmd::check(args),
        Command::Shaders { files, dir } => graph_cmd::check_shaders(files, dir),
        Command::Compare { reference, test, block } => compare(&reference, &test, block),
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            crate::gpu::EXIT_USER_ERROR
        }
    }
}
