//! One graph rendered with several random seeds (`glint trade --seeds N`).
//! A frame's error is a random variable: at one sample a pixel, the FLIP
//! of one seed's first frame on thesis-env3 ranges over about ±5% of the
//! mean (docs/realtime.md, "One seed is one draw"). The curve `trade.csv`
//! and the tables then hold the mean over the seeds, frame by frame, and
//! `trade.md` adds each curve's spread.

use std::fmt::Write;

use super::{Curve, Sample};

/// The seeds' curves averaged frame by frame (milliseconds, FLIP, relMSE
/// and PSNR; the cumulative time summed from the mean frame times), over
/// the frames every run has. None without runs.
pub fn mean_over_seeds(runs: &[Curve]) -> Option<Curve> {
    let first = runs.first()?;
    let frames = runs.iter().map(|c| c.samples.len()).min()?;
    let n = runs.len() as f64;
    let mean = |k: usize, f: fn(&Sample) -> f64| runs.iter().map(|c| f(&c.samples[k])).sum::<f64>() / n;
    let mut cum_ms = 0.0;
    let samples = (0..frames)
        .map(|k| {
            let ms = mean(k, |s| s.ms);
            cum_ms += ms;
            Sample {
                graph: first.graph.clone(),
                setting: first.setting.clone(),
                frame: first.samples[k].frame,
                ms,
                cum_ms,
                flip: mean(k, |s| s.flip),
                relmse: mean(k, |s| s.relmse),
                psnr: mean(k, |s| s.psnr),
            }
        })
        .collect();
    Some(Curve { graph: first.graph.clone(), setting: first.setting.clone(), samples })
}

/// FLIP at one frame over the seeds: the least, the mean, the greatest,
/// and how many seeds' FLIP is at or below `limit`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// The least FLIP.
    pub min: f64,
    /// The mean FLIP.
    pub mean: f64,
    /// The greatest FLIP.
    pub max: f64,
    /// How many seeds' FLIP is at or below the limit.
    pub at_or_below: usize,
}

/// The spread of frame `index` (0-based) over the runs that have it.
pub fn spread(runs: &[Curve], index: usize, limit: f64) -> Option<Spread> {
    let flips: Vec<f64> = runs.iter().filter_map(|c| c.samples.get(index)).map(|s| s.flip).collect();
    if flips.is_empty() {
        return None;
    }
    Some(Spread {
        min: flips.iter().copied().fold(f64::INFINITY, f64::min),
        mean: flips.iter().sum::<f64>() / flips.len() as f64,
        max: flips.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        at_or_below: flips.iter().filter(|&&f| f <= limit).count(),
    })
}

/// `trade.md`'s section on the seeds: per curve (its label and its runs,
/// one per seed), FLIP at the first and the last frame, mean (least -
/// greatest), and how many seeds' first frame is at or below 0.10.
pub fn markdown(curves: &[(String, Vec<Curve>)]) -> String {
    let mut o = String::from("\n## Over the seeds (FLIP mean, least - greatest)\n\n| graph | seeds | first frame | first frame at or below 0.10 | last frame |\n|---|---|---|---|---|\n");
    let cell = |s: Option<Spread>| s.map_or("-".into(), |s| format!("{:.4} ({:.4} - {:.4})", s.mean, s.min, s.max));
    for (label, runs) in curves {
        let frames = runs.iter().map(|c| c.samples.len()).min().unwrap_or(0);
        let first = spread(runs, 0, 0.1);
        let below = first.map_or("-".into(), |s| format!("{} of {}", s.at_or_below, runs.len()));
        let last = frames.checked_sub(1).and_then(|k| spread(runs, k, 0.1));
        let _ = writeln!(o, "| {label} | {} | {} | {below} | {} (frame {frames}) |", runs.len(), cell(first), cell(last));
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(points: &[(f64, f64)]) -> Curve {
        crate::trade::tests::curve("g", points)
    }

    #[test]
    fn the_mean_curve_averages_frame_by_frame_over_the_frames_all_have() {
        let runs = [curve(&[(10.0, 0.1), (20.0, 0.05), (5.0, 0.01)]), curve(&[(30.0, 0.3), (40.0, 0.07)])];
        let m = mean_over_seeds(&runs).unwrap();
        assert_eq!(m.samples.len(), 2, "frame 3 is one seed's only");
        let got: Vec<(u32, f64, f64, f64)> = m.samples.iter().map(|s| (s.frame, s.ms, s.cum_ms, s.flip)).collect();
        assert_eq!(got, vec![(1, 20.0, 20.0, 0.2), (2, 30.0, 50.0, 0.060000000000000005)]);
        assert!((m.samples[0].relmse - 0.05).abs() < 1e-12 && (m.samples[1].psnr - 20.0).abs() < 1e-12);
        assert!(mean_over_seeds(&[]).is_none());
        // One seed is its own mean.
        assert_eq!(mean_over_seeds(&runs[..1]).unwrap(), runs[0]);
    }

    #[test]
    fn the_spread_counts_the_seeds_under_a_limit() {
        let runs = [curve(&[(1.0, 0.09)]), curve(&[(1.0, 0.12)]), curve(&[(1.0, 0.1)])];
        let s = spread(&runs, 0, 0.1).unwrap();
        assert_eq!((s.min, s.max, s.at_or_below), (0.09, 0.12, 2));
        assert!((s.mean - 0.31 / 3.0).abs() < 1e-12);
        assert!(spread(&runs, 1, 0.1).is_none());
        let md = markdown(&[("realtime".into(), runs.to_vec())]);
        assert!(md.contains("| realtime | 3 | 0.1033 (0.0900 - 0.1200) | 2 of 3 | 0.1033 (0.0900 - 0.1200) (frame 1) |"), "{md}");
    }
}
