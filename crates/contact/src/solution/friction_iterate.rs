//! The iterates of a friction solve: one solve of a Tresca problem, the
//! inner problem of the fixed point on the threshold (course notes §4.3) and
//! the status method's answer (§4.5), and where a solve stopped, made into a
//! [`ContactSolution`].

use crate::solution::{ContactSolution, PointStatus, SolverReport, StopReason};

/// One solve of a Tresca problem (fixed thresholds): the forces and gaps of
/// all rows (normal rows 0..m, then the tangential rows), the statuses of
/// the m points, and whether and why it stopped.
#[derive(Debug, Clone)]
pub(crate) struct InnerSolve {
    pub forces: Vec<f64>,
    pub gaps: Vec<f64>,
    pub statuses: Vec<PointStatus>,
    pub converged: bool,
    pub reason: StopReason,
}

/// Where the fixed point stopped: its last iterate, the residual after each
/// outer iteration, whether it converged and why it stopped.
pub(crate) struct FixedPoint {
    pub last: InnerSolve,
    pub residuals: Vec<f64>,
    pub converged: bool,
    pub reason: StopReason,
}

impl FixedPoint {
    /// The solution of a friction solve by `method` that ended here, after
    /// `iterations` inner iterations in all (`cycle`: some status loop
    /// cycled); one fixed-point iteration per residual.
    pub fn solution(self, method: &str, iterations: usize, cycle: bool) -> ContactSolution {
        let report = SolverReport {
            method: method.into(),
            converged: self.converged,
            iterations,
            operator_applications: 0,
            residual_history: self.residuals,
            stop: self.reason,
        };
        let fixed_point_iterations = report.residual_history.len();
        let last = self.last;
        let mut sol = ContactSolution::with_gaps(last.forces, last.gaps, Vec::new(), report);
        sol.set_points(last.statuses);
        sol.friction.fixed_point_iterations = fixed_point_iterations;
        sol.statuses.cycle_detected_at = cycle.then_some(iterations);
        sol
    }
}
