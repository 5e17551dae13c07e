//! What every contact algorithm on the condensed problem shares: the LCP in
//! the contact forces (DESIGN.md §3), λ ≥ 0, w = W λ + q ≥ 0, λ·w = 0, with
//! W the Delassus operator (symmetric positive definite, or semi-definite
//! with redundant constraints) and q the gaps of the unconstrained solution;
//! the stopping test; and the report each method gives.

use faer::Mat;
use serde::Serialize;

/// Options of an iterative or pivoting LCP method.
#[derive(Debug, Clone)]
pub struct LcpOptions {
    /// Relative tolerance of the natural residual (see [`lcp_residual`]).
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Force scale: forces are compared with tolerance × max(force_scale, ‖λ‖∞).
    pub force_scale: f64,
    /// Length scale: gaps are compared with tolerance × max(gap_scale, ‖w‖∞ of the active points).
    pub gap_scale: f64,
    /// Penalty or augmentation stiffness where the method has one (relative
    /// to the mean diagonal of W⁻¹, i.e. a multiple of the contact stiffness);
    /// `None` chooses a default.
    pub stiffness: Option<f64>,
}

impl Default for LcpOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 500,
            force_scale: 1.0,
            gap_scale: 1.0,
            stiffness: None,
        }
    }
}

/// What a method says about its run (`report.json` → `solver`).
#[derive(Debug, Clone, Default, Serialize)]
pub struct SolverReport {
    pub method: String,
    pub converged: bool,
    pub iterations: usize,
    /// Products with W (or solves with a block of W, each counted once).
    pub operator_applications: usize,
    /// The natural residual after each iteration (see [`lcp_residual`]).
    pub residual_history: Vec<f64>,
    pub stopping_reason: String,
}

/// A solution of the LCP and how it was found.
#[derive(Debug, Clone)]
pub struct LcpSolution {
    pub lambda: Vec<f64>,
    pub report: SolverReport,
}

/// w = W λ + q.
pub fn gaps(w: &Mat<f64>, q: &[f64], lambda: &[f64]) -> Vec<f64> {
    let m = q.len();
    (0..m)
        .map(|i| q[i] + (0..m).map(|j| w[(i, j)] * lambda[j]).sum::<f64>())
        .collect()
}

/// The scaled natural residual of the LCP, max over points of
/// |min(λ_p / F, w_p / L)| with F = max(force_scale, ‖λ‖∞) and
/// L = max(gap_scale, ‖w‖∞ over points with w > 0 … all points): zero exactly
/// at a solution, and comparable with the tolerance whatever the units.
pub fn lcp_residual(w: &Mat<f64>, q: &[f64], lambda: &[f64], opts: &LcpOptions) -> f64 {
    let g = gaps(w, q, lambda);
    let f = opts
        .force_scale
        .max(lambda.iter().fold(0.0f64, |a, v| a.max(v.abs())))
        .max(f64::MIN_POSITIVE);
    let l = opts.gap_scale.max(f64::MIN_POSITIVE);
    lambda
        .iter()
        .zip(&g)
        .map(|(&lp, &gp)| (lp / f).min(gp / l).abs())
        .fold(0.0, f64::max)
}
