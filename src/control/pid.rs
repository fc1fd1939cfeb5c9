//! A PID controller hardened for frame-time feedback: derivative on the
//! measurement (no kick when the target steps), a low-pass on that
//! derivative, clamped output with anti-windup, and samples that cannot be
//! trusted (NaN, infinite, negative, dt <= 0) are ignored, so the output is
//! always finite and within its limits.

/// How the integral is kept from winding up while the output is clamped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AntiWindup {
    /// No protection (only for comparison: the integral winds up while the
    /// output is saturated).
    None,
    /// Back-calculation: the integral bleeds off what the clamp cut away,
    /// with time constant `tracking_s` (Åström & Hägglund).
    BackCalculation {
        /// The bleed's time constant, seconds.
        tracking_s: f64,
    },
}

/// Gains, limits and filtering of a `Pid`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PidConfig {
    /// Proportional gain.
    pub kp: f64,
    /// Integral gain (per second).
    pub ki: f64,
    /// Derivative gain (seconds).
    pub kd: f64,
    /// Lowest output.
    pub out_min: f64,
    /// Highest output.
    pub out_max: f64,
    /// Output rises when the measurement is above the setpoint (frame time
    /// too long → raise the mask threshold → less work).
    pub reverse_acting: bool,
    /// Time constant of the derivative's low-pass, seconds.
    pub derivative_filter_s: f64,
    /// Longer steps (a pause, a breakpoint) count as this long.
    pub max_dt_s: f64,
    /// How the integral is kept from winding up.
    pub anti_windup: AntiWindup,
}

impl PidConfig {
    /// Mask threshold in [0, 1] from frame time in milliseconds.
    pub fn frame_time() -> PidConfig {
        PidConfig {
            kp: 0.01,
            ki: 0.5,
            kd: 0.0002,
            out_min: 0.0,
            out_max: 1.0,
            reverse_acting: true,
            derivative_filter_s: 0.05,
            max_dt_s: 0.25,
            anti_windup: AntiWindup::BackCalculation { tracking_s: 0.1 },
        }
    }
}

/// A PID controller (see the module docs); `update` it once a frame.
#[derive(Debug, Clone)]
pub struct Pid {
    /// Its gains and limits, read at each `update`.
    pub config: PidConfig,
    integral: f64,
    last_measurement: Option<f64>,
    derivative: f64,
    output: f64,
}

fn usable(x: f64) -> bool {
    x.is_finite()
}

impl Pid {
    /// Starts at `initial` output (clamped).
    pub fn new(config: PidConfig, initial: f64) -> Pid {
        let initial = if initial.is_finite() { initial.clamp(config.out_min, config.out_max) } else { config.out_min };
        Pid { config, integral: initial, last_measurement: None, derivative: 0.0, output: initial }
    }

    /// The current output, within `[out_min, out_max]`.
    pub fn output(&self) -> f64 {
        self.output
    }

    /// The integral term (for tests and plots).
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// One step: `measurement` against `setpoint` over `dt` seconds.
    /// Untrustworthy input leaves the output where it was.
    pub fn update(&mut self, setpoint: f64, measurement: f64, dt: f64) -> f64 {
        let c = self.config;
        if !usable(setpoint) || !usable(measurement) || measurement < 0.0 || !usable(dt) || dt <= 0.0 {
            return self.output;
        }
        let dt = dt.min(c.max_dt_s);
        let sign = if c.reverse_acting { -1.0 } else { 1.0 };
        let error = sign * (setpoint - measurement);
        // Derivative on the measurement, low-passed.
        if let Some(last) = self.last_measurement {
            let raw = -sign * (measurement - last) / dt;
            let alpha = dt / (c.derivative_filter_s + dt);
            self.derivative += alpha * (raw - self.derivative);
        }
        self.last_measurement = Some(measurement);
        self.integral += c.ki * error * dt;
        let unclamped = c.kp * error + self.integral + c.kd * self.derivative;
        let clamped = unclamped.clamp(c.out_min, c.out_max);
        if let AntiWindup::BackCalculation { tracking_s } = c.anti_windup {
            self.integral += (clamped - unclamped) * (dt / tracking_s.max(dt)).min(1.0);
        }
        // Keep the state finite whatever the gains did.
        if !self.integral.is_finite() {
            self.integral = clamped;
        }
        self.output = if clamped.is_finite() { clamped } else { self.output };
        self.output
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Frame time of a renderer whose masked share is (1 - threshold):
    /// 10 ms base plus 40 ms at full mask, with one frame of lag.
    struct Plant {
        last_threshold: f64,
    }

    impl Plant {
        fn frame_ms(&mut self, threshold: f64) -> f64 {
            let ms = 10.0 + 40.0 * (1.0 - self.last_threshold);
            self.last_threshold = threshold;
            ms
        }
    }

    /// Saturate for 10,000 frames (unreachable target), then release to a
    /// reachable one. Returns (max integral seen, overshoot ratio, frames to
    /// settle within 5 % for good).
    fn saturate_then_release(config: PidConfig) -> (f64, f64, usize) {
        let mut pid = Pid::new(config, 0.5);
        let mut plant = Plant { last_threshold: 0.5 };
        let dt = 1.0 / 60.0;
        let mut u = pid.output();
        let mut max_integral: f64 = 0.0;
        for _ in 0..10_000 {
            let ms = plant.frame_ms(u);
            u = pid.update(5.0, ms, dt); // 5 ms cannot be reached: saturates at 1
            max_integral = max_integral.max(pid.integral().abs());
        }
        assert_eq!(u, 1.0);
        let target = 30.0; // reached at threshold 0.5
        let mut trace = Vec::new();
        for _ in 0..2000 {
            let ms = plant.frame_ms(u);
            u = pid.update(target, ms, dt);
            trace.push(ms);
        }
        let overshoot = trace.iter().map(|ms| (ms - target) / target).fold(0.0f64, f64::max);
        let settled = trace.iter().rposition(|ms| ((ms - target) / target).abs() > 0.05).map_or(0, |i| i + 1);
        eprintln!("anti-windup {:?}: max |integral| {max_integral:.3}, overshoot {overshoot:.3}, settled after {settled} frames", config.anti_windup);
        (max_integral, overshoot, settled)
    }

    #[test]
    fn recovers_from_long_saturation() {
        let (max_integral, overshoot, settled) = saturate_then_release(PidConfig::frame_time());
        assert!(max_integral < 2.0, "integral wound up to {max_integral}");
        assert!(overshoot < 0.2, "overshoot {overshoot}");
        assert!(settled < 120, "took {settled} frames to settle");
    }

    #[test]
    fn without_anti_windup_the_same_test_fails() {
        let config = PidConfig { anti_windup: AntiWindup::None, ..PidConfig::frame_time() };
        let (max_integral, overshoot, settled) = saturate_then_release(config);
        let passes = max_integral < 2.0 && overshoot < 0.2 && settled < 120;
        assert!(!passes, "windup went unnoticed: {max_integral} {overshoot} {settled}");
    }

    #[test]
    fn bad_samples_leave_the_output_alone() {
        let mut pid = Pid::new(PidConfig::frame_time(), 0.3);
        let before = pid.update(16.0, 20.0, 0.016);
        for (ms, dt) in [
            (f64::NAN, 0.016),
            (f64::INFINITY, 0.016),
            (f64::NEG_INFINITY, 0.016),
            (-5.0, 0.016),
            (20.0, 0.0),
            (20.0, -1.0),
            (20.0, f64::NAN),
            (20.0, f64::INFINITY),
        ] {
            assert_eq!(pid.update(16.0, ms, dt), before, "ms {ms} dt {dt}");
        }
        assert_eq!(pid.update(f64::NAN, 20.0, 0.016), before);
    }

    #[test]
    fn a_pause_of_seconds_counts_as_one_short_step() {
        let mut pid = Pid::new(PidConfig::frame_time(), 0.5);
        pid.update(16.0, 16.0, 0.016);
        let after = pid.update(16.0, 30.0, 5.0);
        let mut reference = Pid::new(PidConfig::frame_time(), 0.5);
        reference.update(16.0, 16.0, 0.016);
        assert_eq!(after, reference.update(16.0, 30.0, PidConfig::frame_time().max_dt_s));
    }

    #[test]
    fn output_always_finite_and_within_limits() {
        let config = PidConfig::frame_time();
        let mut pid = Pid::new(config, f64::NAN);
        let mut s: u32 = 12345;
        for i in 0..100_000 {
            s = s.wrapping_mul(1664525).wrapping_add(1013904223);
            let r = f64::from(s >> 8) / 16_777_216.0;
            let ms = match i % 7 {
                0 => f64::NAN,
                1 => 1e300,
                2 => -r,
                _ => r * 100.0,
            };
            let target = if i % 1000 < 500 { 16.0 } else { 33.0 };
            let dt = if i % 11 == 0 { 0.0 } else { r * 0.1 };
            let u = pid.update(target, ms, dt);
            assert!(u.is_finite() && (config.out_min..=config.out_max).contains(&u), "step {i}: {u}");
        }
    }

    #[test]
    fn setpoint_step_gives_no_derivative_kick() {
        let mut pid = Pid::new(PidConfig::frame_time(), 0.5);
        for _ in 0..10 {
            pid.update(16.0, 16.0, 0.016);
        }
        let u0 = pid.output();
        let u1 = pid.update(33.0, 16.0, 0.016);
        // Only proportional and integral respond to the new target.
        let c = PidConfig::frame_time();
        let error = 16.0 - 33.0; // reverse acting: measurement - setpoint
        let expected = (u0 + c.kp * error + c.ki * error * 0.016).clamp(0.0, 1.0);
        assert!((u1 - expected).abs() < 1e-9, "{u1} vs {expected}");
    }
}
