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
}
