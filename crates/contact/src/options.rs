//! The options of the contact solvers that more than one method reads (the
//! LCP methods' own are [`crate::lcp::LcpOptions`]).

use serde::Serialize;

/// How many statuses change per iteration of the status method.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StatusVariant {
    /// Every violated status changes at each iteration.
    #[default]
    All,
    /// Only the most violated status changes (the variant with the proof).
    Single,
}

/// The options of a friction solver.
#[derive(Debug, Clone)]
pub struct FrictionOptions {
    pub max_iterations: usize,
    pub max_fixed_point: usize,
    pub tolerance: f64,
    pub force_scale: f64,
    pub gap_scale: f64,
    /// The wall-clock time at which a solve stops, converged or not
    /// (`None`: no time limit).
    pub deadline: Option<std::time::Instant>,
}

/// The default wall-clock budget of a friction solve of `rows` rows, in
/// seconds: 10 s, plus 2e-9 s × rows³ (about six dense factorisations of
/// W at 1 GFlop/s for every second past the first ten: 11 s at 858 rows,
/// 460 s at 6 075), so that a large problem is not cut short and a small
/// one that does not converge ends soon.
pub fn default_time_limit(rows: usize) -> f64 {
    10.0 + 2e-9 * (rows as f64).powi(3)
}
