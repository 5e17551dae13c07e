//! The inner Tresca problems of the 2D fixed points on the threshold (course
//! notes §4.3): the friction status method, with the box QP where it cycles.

use crate::active_set::friction_status::{status_loop, Run};
use crate::delassus::DelassusProblem;
use crate::friction::fixed_point::{fixed_point, ThresholdMap, TrescaSolver};
use crate::friction::tresca_projection::tresca_box;
use crate::law::FrictionLayout;
use crate::options::FrictionOptions;
use crate::solution::friction_iterate::InnerSolve;
use crate::solution::{ContactSolution, PointStatus, StopReason};
use crate::ContactError;

/// The 2D Tresca problems of a fixed point on the threshold (course notes §4.3):
/// the status method, from the statuses of the previous inner problem.
pub(crate) struct StatusTresca<'a> {
    problem: &'a mut DelassusProblem,
    layout: &'a FrictionLayout,
    pub run: Run,
    opts: &'a FrictionOptions,
}

impl<'a> StatusTresca<'a> {
    pub fn new(
        problem: &'a mut DelassusProblem,
        layout: &'a FrictionLayout,
        initial: Vec<PointStatus>,
        opts: &'a FrictionOptions,
    ) -> Result<Self, ContactError> {
        layout.validate(problem.q.len(), 2)?;
        Ok(Self {
            problem,
            layout,
            run: Run::new(initial),
            opts,
        })
    }

    /// The solution in which every point initially closed sticks.
    pub fn stuck(&mut self) -> Result<InnerSolve, ContactError> {
        let inf = vec![f64::INFINITY; self.run.statuses.len()];
        status_loop(
            self.problem,
            self.layout,
            &mut self.run,
            inf,
            false,
            self.opts,
        )
    }

    pub fn fixed_point(
        mut self,
        start: InnerSolve,
        map: &ThresholdMap<'_, Vec<f64>>,
        method: &str,
    ) -> Result<ContactSolution, ContactError> {
        let opts = self.opts;
        let end = fixed_point(&mut self, start, map, opts)?;
        Ok(self.run.finish(end, method, self.problem.solves))
    }
}

impl TrescaSolver for StatusTresca<'_> {
    type Thresholds = Vec<f64>;

    /// The status method; where it cycles (some Tresca problems at large
    /// μ), the same problem as a convex box QP, which always has its
    /// solution.
    fn solve(&mut self, thr: &Vec<f64>, _: &[f64]) -> Result<InnerSolve, ContactError> {
        let (problem, layout, opts) = (&mut *self.problem, self.layout, self.opts);
        let out = status_loop(problem, layout, &mut self.run, thr.clone(), false, opts)?;
        if out.converged || problem.n_kernel() > 0 {
            return Ok(out);
        }
        let (sol, statuses) = tresca_box(problem, layout, thr, opts)?;
        if !sol.report.converged {
            return Ok(out);
        }
        self.run.statuses.clone_from(&statuses);
        self.run.box_fallbacks += 1;
        Ok(InnerSolve {
            gaps: crate::lcp::gaps(&problem.w, &problem.q, &sol.forces),
            forces: sol.forces,
            statuses,
            converged: true,
            reason: StopReason::TrescaBoxSolved,
        })
    }
}
