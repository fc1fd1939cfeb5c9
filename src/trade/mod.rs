//! The speed/accuracy trade, measured (`glint trade`): per graph (or sweep
//! setting) and frame, the frame's milliseconds, the cumulative
//! milliseconds and the error of the accumulated image against a
//! reference. Pure: the curves, the CSV, error at fixed time budgets, time
//! to reach a FLIP, the efficiency 1/(relMSE x time) and the Pareto front
//! of error against cumulative time. `cli/trade_cmd.rs` renders and
//! measures; this module only reads the numbers.

use std::fmt::Write;

pub mod motion;
pub mod plot;
pub mod seeds;
pub mod sweep;

/// One frame of one curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// The graph file's stem.
    pub graph: String,
    /// The sweep setting ("" without a sweep).
    pub setting: String,
    /// 1-based frame number.
    pub frame: u32,
    /// The frame's milliseconds.
    pub ms: f64,
    /// Milliseconds of every frame up to and including this one.
    pub cum_ms: f64,
    /// FLIP mean of the accumulated image against the reference.
    pub flip: f64,
    /// Relative MSE of the accumulated image.
    pub relmse: f64,
    /// PSNR of the accumulated image, dB.
    pub psnr: f64,
}

/// The samples of one graph and setting, in frame order.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The graph file's stem.
    pub graph: String,
    /// The sweep setting ("" without a sweep).
    pub setting: String,
    /// One per frame, in order.
    pub samples: Vec<Sample>,
}

impl Curve {
    /// The graph, with the setting in brackets when there is one.
    pub fn label(&self) -> String {
        if self.setting.is_empty() { self.graph.clone() } else { format!("{} [{}]", self.graph, self.setting) }
    }

    /// The last sample within `budget_ms` of cumulative time; the first
    /// frame when even that took longer (the error a user sees first).
    pub fn at_budget(&self, budget_ms: f64) -> Option<&Sample> {
        self.samples.iter().take_while(|s| s.cum_ms <= budget_ms).last()
    }

    /// Cumulative milliseconds until the FLIP mean is at or below `flip`.
    pub fn time_to(&self, flip: f64) -> Option<f64> {
        self.samples.iter().find(|s| s.flip <= flip).map(|s| s.cum_ms)
    }

    /// 1 / (relMSE x seconds) at the last frame: higher is better.
    pub fn efficiency(&self) -> Option<f64> {
        let last = self.samples.last()?;
        let t = last.cum_ms / 1e3;
        (last.relmse > 0.0 && t > 0.0).then(|| 1.0 / (last.relmse * t))
    }
}

/// How much sooner one graph reaches an error than another (the thesis's
/// "convergence speed-up", made exact): the FLIP mean `fast` settles at
/// (the best it reached, plus `SETTLE_MARGIN`, so a level it holds rather
/// than one lucky frame's), and the cumulative times the two first reach it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedUp {
    /// The FLIP mean both are timed to.
    pub flip: f64,
    /// Cumulative milliseconds until `fast` first reaches it.
    pub fast_ms: f64,
    /// None: `slow` never got there in its frames (then `slow_total_ms`
    /// bounds the speed-up from below).
    pub slow_ms: Option<f64>,
    /// `slow`'s cumulative milliseconds over all its frames.
    pub slow_total_ms: f64,
}

/// The share above its best FLIP at which a curve counts as settled.
pub const SETTLE_MARGIN: f64 = 0.1;

impl SpeedUp {
    /// slow_ms / fast_ms; below 1 where `slow` is in fact faster.
    pub fn ratio(&self) -> Option<f64> {
        self.slow_ms.map(|s| s / self.fast_ms)
    }

    /// The ratio in words: "12.3x", or "> 40x" when `slow` never got there.
    pub fn describe(&self) -> String {
        match self.ratio() {
            Some(r) => format!("{r:.2}x"),
            None => format!("> {:.1}x", self.slow_total_ms / self.fast_ms),
        }
    }
}

/// The speed-up of `fast` over `slow` at the FLIP `fast` settles at; None
/// when `fast` has no finite error.
pub fn speed_up(fast: &Curve, slow: &Curve) -> Option<SpeedUp> {
    let best = fast.samples.iter().map(|s| s.flip).filter(|f| f.is_finite()).fold(f64::INFINITY, f64::min);
    if !best.is_finite() {
        return None;
    }
    let flip = best * (1.0 + SETTLE_MARGIN);
    Some(SpeedUp { flip, fast_ms: fast.time_to(flip)?, slow_ms: slow.time_to(flip), slow_total_ms: slow.samples.last().map_or(0.0, |s| s.cum_ms) })
}

/// The CSV `trade.csv` holds: one row per curve and frame.
pub fn csv(curves: &[Curve]) -> String {
    let mut o = String::from("graph,setting,frame,ms,cum_ms,flip,relmse,psnr\n");
    for c in curves {
        for s in &c.samples {
            let _ = writeln!(o, "{},{},{},{:.4},{:.4},{:.6},{:.6},{:.4}", quote(&s.graph), quote(&s.setting), s.frame, s.ms, s.cum_ms, s.flip, s.relmse, s.psnr);
        }
    }
    o
}

/// A CSV field: quoted when it holds a comma or a quote.
fn quote(s: &str) -> String {
    if s.contains(',') || s.contains('"') { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

/// The samples no other sample beats in both cumulative time and FLIP
/// (lower is better in both), over every curve, in time order: the best
/// error reachable at each time by some graph.
pub fn pareto(curves: &[Curve]) -> Vec<&Sample> {
    let mut all: Vec<&Sample> = curves.iter().flat_map(|c| &c.samples).collect();
    all.sort_by(|a, b| a.cum_ms.total_cmp(&b.cum_ms).then(a.flip.total_cmp(&b.flip)));
    let mut front: Vec<&Sample> = Vec::new();
    for s in all {
        if front.last().is_none_or(|f| s.flip < f.flip) {
            front.push(s);
        }
    }
    front
}

/// Budgets of `trade.md`: cumulative milliseconds.
pub const BUDGETS_MS: [f64; 4] = [16.7, 100.0, 1000.0, 10000.0];
/// FLIP targets of `trade.md`.
pub const FLIP_TARGETS: [f64; 3] = [0.1, 0.05, 0.02];

/// `trade.md`: error at the first frame and at fixed budgets, time to the
/// FLIP targets, efficiency, and the Pareto front.
pub fn markdown(title: &str, how: &str, curves: &[Curve]) -> String {
    let mut o = format!("# {title}\n\n{how}\n\n## FLIP mean at a time budget (cumulative)\n\n| graph | first frame |");
    for b in BUDGETS_MS {
        let _ = write!(o, " {} |", budget_name(b));
    }
    let _ = writeln!(o, "\n|---|---|{}", "---|".repeat(BUDGETS_MS.len()));
    for c in curves {
        let first = c.samples.first().map_or("-".into(), |s| format!("{:.3} ({:.1} ms)", s.flip, s.cum_ms));
        let _ = write!(o, "| {} | {first} |", c.label());
        for b in BUDGETS_MS {
            let v = c.at_budget(b).map_or("-".into(), |s| format!("{:.3} ({})", s.flip, frames_text(s.frame)));
            let _ = write!(o, " {v} |");
        }
        o.push('\n');
    }
    let _ = write!(o, "\n## Time to reach a FLIP mean\n\n| graph |");
    for f in FLIP_TARGETS {
        let _ = write!(o, " {f} |");
    }
    let _ = writeln!(o, " efficiency 1/(relMSE x s) |\n|---|{}---|", "---|".repeat(FLIP_TARGETS.len()));
    for c in curves {
        let _ = write!(o, "| {} |", c.label());
        for f in FLIP_TARGETS {
            let v = c.time_to(f).map_or("not reached".into(), |t| format!("{t:.1} ms"));
            let _ = write!(o, " {v} |");
        }
        let e = c.efficiency().map_or("-".into(), |e| format!("{e:.3}"));
        let _ = writeln!(o, " {e} |");
    }
    let _ = writeln!(o, "\n## Pareto front (the best FLIP reached by any graph by each time)\n\n| cumulative ms | FLIP | graph | frame |\n|---|---|---|---|");
    let front = pareto(curves);
    // Long fronts are thinned to a readable table (every point is in the CSV).
    let step = front.len().div_ceil(24).max(1);
    for (i, s) in front.iter().enumerate() {
        if i % step == 0 || i + 1 == front.len() {
            let label = if s.setting.is_empty() { s.graph.clone() } else { format!("{} [{}]", s.graph, s.setting) };
            let _ = writeln!(o, "| {:.1} | {:.4} | {label} | {} |", s.cum_ms, s.flip, s.frame);
        }
    }
    o
}

/// "1 frame", "5 frames".
pub fn frames_text(n: u32) -> String {
    if n == 1 { "1 frame".into() } else { format!("{n} frames") }
}

fn budget_name(ms: f64) -> String {
    if ms >= 1000.0 { format!("{} s", ms / 1000.0) } else { format!("{ms} ms") }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A curve of (ms, FLIP) frames (relMSE FLIP², PSNR 20).
    pub(super) fn curve(graph: &str, points: &[(f64, f64)]) -> Curve {
        let mut cum = 0.0;
        let samples = points
            .iter()
            .enumerate()
            .map(|(i, &(ms, flip))| {
                cum += ms;
                Sample { graph: graph.into(), setting: String::new(), frame: i as u32 + 1, ms, cum_ms: cum, flip, relmse: flip * flip, psnr: 20.0 }
            })
            .collect();
        Curve { graph: graph.into(), setting: String::new(), samples }
    }

    #[test]
    fn speed_up_is_the_ratio_of_times_to_the_level_the_fast_curve_settles_at() {
        // Settles at 0.1 (best 0.1, plus 10%: 0.11), reached at 20 ms.
        let fast = curve("hybrid", &[(10.0, 0.3), (10.0, 0.105), (10.0, 0.1)]);
        let slow = curve("pt", &[(5.0, 0.5), (5.0, 0.3), (90.0, 0.2), (100.0, 0.11)]);
        let s = speed_up(&fast, &slow).unwrap();
        assert!((s.flip - 0.11).abs() < 1e-12);
        assert_eq!((s.fast_ms, s.slow_ms), (20.0, Some(200.0)));
        assert_eq!(s.describe(), "10.00x");
        // A slow curve that never gets there bounds the speed-up from below.
        let never = curve("pt", &[(50.0, 0.5), (50.0, 0.4)]);
        let s = speed_up(&fast, &never).unwrap();
        assert_eq!((s.ratio(), s.describe()), (None, "> 5.0x".to_string()));
        // A "slow" curve that is faster gives a ratio below 1.
        let quick = curve("pt", &[(2.0, 0.05)]);
        assert_eq!(speed_up(&fast, &quick).unwrap().ratio(), Some(0.1));
        // No finite error: no speed-up.
        assert!(speed_up(&curve("x", &[(1.0, f64::NAN)]), &slow).is_none());
    }

    #[test]
    fn budgets_and_targets_read_the_curve() {
        let c = curve("a", &[(10.0, 0.3), (10.0, 0.2), (10.0, 0.08), (100.0, 0.04)]);
        assert_eq!(c.at_budget(16.7).map(|s| s.frame), Some(1));
        assert_eq!(c.at_budget(100.0).map(|s| s.frame), Some(3));
        assert_eq!(c.at_budget(5.0), None);
        assert_eq!(c.time_to(0.1), Some(30.0));
        assert_eq!(c.time_to(0.05), Some(130.0));
        assert_eq!(c.time_to(0.01), None);
        let e = c.efficiency().unwrap();
        assert!((e - 1.0 / (0.04 * 0.04 * 0.13)).abs() < 1e-9, "{e}");
    }

    #[test]
    fn the_pareto_front_keeps_only_unbeaten_points() {
        let fast = curve("fast", &[(1.0, 0.5), (1.0, 0.4), (1.0, 0.35)]);
        let slow = curve("slow", &[(10.0, 0.2), (10.0, 0.1)]);
        let front: Vec<(String, u32)> = pareto(&[fast, slow]).iter().map(|s| (s.graph.clone(), s.frame)).collect();
        assert_eq!(front, vec![("fast".into(), 1), ("fast".into(), 2), ("fast".into(), 3), ("slow".into(), 1), ("slow".into(), 2)]);
        // A curve beaten everywhere is not on it.
        let worse = curve("worse", &[(5.0, 0.9), (5.0, 0.8)]);
        let better = curve("better", &[(1.0, 0.3), (1.0, 0.2)]);
        assert!(pareto(&[worse, better]).iter().all(|s| s.graph == "better"));
    }

    #[test]
    fn csv_has_a_header_and_a_row_per_frame() {
        let mut c = curve("hybrid", &[(1.0, 0.5), (2.0, 0.25)]);
        c.samples[1].setting = "refine.samples=4,8".into();
        let text = csv(&[c]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "graph,setting,frame,ms,cum_ms,flip,relmse,psnr");
        assert_eq!(lines.len(), 3);
        assert!(lines[1].starts_with("hybrid,,1,1.0000,1.0000,0.500000,"), "{}", lines[1]);
        assert!(lines[2].starts_with("hybrid,\"refine.samples=4,8\",2,"), "{}", lines[2]);
    }

    #[test]
    fn markdown_names_every_graph_and_section() {
        let md = markdown("t", "how", &[curve("a", &[(10.0, 0.3), (10.0, 0.04)]), curve("b", &[(50.0, 0.2)])]);
        for want in ["| a |", "| b |", "first frame", "16.7 ms", "10 s", "Time to reach", "Pareto front", "not reached"] {
            assert!(md.contains(want), "`{want}` missing:\n{md}");
        }
    }
}
