//! The inner solves of the fixed points on the threshold (Coulomb's and
//! Norton–Hoff's, course notes §4.3): each Tresca problem by the semi-smooth
//! Newton method of [`super`], from the previous forces, with the checks
//! that end a fixed point early (a load friction cannot hold, inner solves
//! failing in a row).

use super::*;
use crate::friction::holding::friction_overload;

/// The Tresca problems of a fixed point on the threshold (course notes §4.3):
/// the semi-smooth Newton method from the previous forces, counting the
/// Newton iterations of all solves.
pub(super) struct Newton<'a> {
    pub(super) problem: &'a DelassusProblem,
    pub(super) layout: &'a FrictionLayout,
    pub(super) opts: &'a FrictionOptions,
    pub(super) iterations: usize,
    pub(super) dim: usize,
    /// Whether the forces the next thresholds come from are those of a
    /// converged solve (of this step's Tresca problem, or of the previous
    /// step): their normal forces are then in equilibrium.
    pub(super) trusted: bool,
    /// The factor on the projection parameters ρ = 1/W_ii of the solves.
    pub(super) rho_scale: f64,
    /// The inner solves that failed in a row, and why the last one did.
    pub(super) failures: usize,
    pub(super) last_failure: Option<StopReason>,
}

/// Inner solves failed in a row after which the fixed point's next ones
/// are not tried: its last forces are returned with the last failure, and
/// the fixed point stops on it. (A push past what friction holds, 101 % of
/// μ N on the assembly, ran its inner solves, each to its stall, for more
/// than 100 s; those that fail under stale thresholds settle at the next.)
const INNER_FAILURES_IN_A_ROW: usize = 3;

impl Newton<'_> {
    /// The iterate of the forces `forces` (no solve): their gaps (rigid-mode
    /// amplitudes zero) and statuses.
    pub(super) fn iterate(&self, forces: Vec<f64>) -> InnerSolve {
        let mut x = forces.clone();
        x.resize(forces.len() + self.problem.g_mat.ncols(), 0.0);
        let gaps = Inner::new(self.problem, self.layout, &[]).gaps(&x);
        InnerSolve {
            statuses: statuses(self.layout, &forces, &gaps, self.opts, self.dim),
            forces,
            gaps,
            converged: false,
            reason: StopReason::Pending,
        }
    }
}

impl TrescaSolver for Newton<'_> {
    type Thresholds = Vec<[f64; 2]>;

    /// Coulomb thresholds from forces in equilibrium (`trusted`) that cannot
    /// hold a floating body end the fixed point: the start returned, not
    /// converged, with the overload as its reason
    /// ([`crate::friction::holding`]).
    fn solve(&mut self, thr: &Vec<[f64; 2]>, start: &[f64]) -> Result<InnerSolve, ContactError> {
        if self.trusted && !self.layout.has_norton_hoff() {
            let overload = friction_overload(self.problem, self.layout, start, thr);
            if let Some(reason) = overload {
                return Ok(InnerSolve {
                    reason,
                    ..self.iterate(start.to_vec())
                });
            }
        }
        if self.failures >= INNER_FAILURES_IN_A_ROW {
            if let Some(reason) = self.last_failure.clone() {
                return Ok(InnerSolve {
                    reason,
                    ..self.iterate(start.to_vec())
                });
            }
        }
        let (solve, iterations) = solve_inner(self, thr, start, false)?;
        self.iterations += iterations;
        self.trusted = solve.converged;
        if solve.converged {
            self.failures = 0;
        } else {
            self.failures += 1;
            self.last_failure = Some(solve.reason.clone());
        }
        Ok(solve)
    }
}
