//! The in-motion figures of `glint trade --animate` (pure): per graph, the
//! mean and 95th percentile FLIP of the compared frames, each against a
//! reference of its own instant, and the flicker.

use std::fmt::Write;

use super::Curve;

/// One graph's figures in motion.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionRow {
    /// The graph's label (with its setting).
    pub label: String,
    /// Mean FLIP of the compared frames.
    pub mean: f64,
    /// 95th percentile FLIP of the compared frames (nearest rank).
    pub p95: f64,
    /// Mean FLIP between consecutive frames less the references' own (only
    /// when every frame is compared).
    pub flicker: Option<f64>,
}

impl MotionRow {
    /// The figures of `curve` (NaN where no frame has a finite FLIP).
    pub fn new(label: String, curve: &Curve, flicker: Option<f64>) -> MotionRow {
        let mut flips: Vec<f64> = curve.samples.iter().map(|s| s.flip).filter(|f| f.is_finite()).collect();
        flips.sort_by(f64::total_cmp);
        let mean = if flips.is_empty() { f64::NAN } else { flips.iter().sum::<f64>() / flips.len() as f64 };
        MotionRow { label, mean, p95: percentile(&flips, 0.95), flicker }
    }
}

/// The `q` quantile of sorted values (nearest rank); NaN when empty.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

/// trade.md's in-motion section.
pub fn motion_markdown(rows: &[MotionRow]) -> String {
    let mut o = String::from("\n## In motion (each compared frame against its own instant)\n\n| graph | FLIP mean | FLIP p95 | flicker |\n|---|---|---|---|\n");
    for r in rows {
        let flicker = r.flicker.map_or("- (needs --reference-every 1)".into(), |f| format!("{f:.4}"));
        let _ = writeln!(o, "| {} | {:.4} | {:.4} | {flicker} |", r.label, r.mean, r.p95);
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trade::Sample;

    fn curve(flips: &[f64]) -> Curve {
        let samples = flips
            .iter()
            .enumerate()
            .map(|(i, &flip)| Sample { graph: "g".into(), setting: String::new(), frame: i as u32 + 1, ms: 1.0, cum_ms: i as f64 + 1.0, flip, relmse: 0.0, psnr: 0.0 })
            .collect();
        Curve { graph: "g".into(), setting: String::new(), samples }
    }

    #[test]
    fn mean_and_p95_of_the_compared_frames() {
        let flips: Vec<f64> = (1..=20).map(|i| i as f64 / 100.0).collect();
        let row = MotionRow::new("g".into(), &curve(&flips), Some(0.01));
        assert!((row.mean - 0.105).abs() < 1e-12);
        assert_eq!(row.p95, 0.19);
        let md = motion_markdown(&[row]);
        assert!(md.contains("| g | 0.1050 | 0.1900 | 0.0100 |"), "{md}");
    }

    #[test]
    fn no_frames_give_nan_not_a_panic() {
        let row = MotionRow::new("g".into(), &curve(&[]), None);
        assert!(row.mean.is_nan() && row.p95.is_nan());
        assert!(motion_markdown(&[row]).contains("needs --reference-every 1"));
    }
}
