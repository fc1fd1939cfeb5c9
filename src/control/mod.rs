//! Frame-time feedback (thesis 4.2.2): a PID controller that turns the
//! measured frame time into the noise-mask threshold.

pub mod pid;

pub use pid::{AntiWindup, Pid, PidConfig};
