//! The status (active set) method, course notes §3.3.
//!
//! 1. impose g_p = 0 on the points of the active set A (by Lagrange
//!    multipliers), 2. solve, 3. check the statuses: a point of A whose force
//!    λ_p is a tension (λ_p < 0) is released; a point outside A that
//!    penetrates (g_p < 0) is imposed. Loop on 2–3 until the statuses repeat.
//!
//! The course notes prove convergence only when one status changes per iteration
//! ([`StatusVariant::Single`]); changing all at once ([`StatusVariant::All`])
//! is faster in practice but may flip-flop at the edge of a coarse contact
//! zone, or on a stiff body pressed into a soft one (a Delassus operator
//! far from diagonal dominance). Cycling is detected (an active set seen
//! before) and reported; the `All` variant then leaves the cycle once by
//! the active set of complementary pivoting (Lemke's method, which cannot
//! cycle; [`ActiveSetSolve::pivoted_active_set`]) and goes on from it, and
//! falls back to `Single` when there is no such solve or it cycles again. The loop itself (iterations,
//! seen-set, fallbacks, stopping reasons) is the driver of
//! [`crate::active_set`]; this module is its rule for normal contact.
//!
//! The linear solve of step 2 is abstracted by [`ActiveSetSolve`]: the
//! condensed path solves with the Delassus operator on the forces
//! ([`crate::DelassusProblem`]), the direct path refactorises the whole
//! sparse stiffness with the active constraints ([`crate::direct`]).

use crate::active_set::{drive, scaled_tolerances, Change, Fallback, Regular, StatusRule, Stop};
pub use crate::options::StatusVariant;
use crate::solution::{ContactSolution, SolverReport, StatusTrace, StopReason};
use crate::ContactError;

/// Solves the equality-constrained problem for a given active set.
pub trait ActiveSetSolve {
    /// Number of contact points.
    fn n_points(&self) -> usize;
    /// With g_p = 0 imposed for p in `active` (sorted) and λ_p = 0 elsewhere,
    /// returns (λ, g) for every point.
    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError>;

    /// The active set (sorted) of the solution found by complementary
    /// pivoting (Lemke's method), which cannot cycle: the status method's
    /// way out of a cycle. `None` when the problem has no such solve (the
    /// status method then changes one status per iteration).
    fn pivoted_active_set(
        &mut self,
        _opts: &crate::lcp::LcpOptions,
    ) -> Result<Option<Vec<usize>>, ContactError> {
        Ok(None)
    }
}

#[derive(Debug, Clone)]
pub struct StatusOptions {
    pub variant: StatusVariant,
    pub max_iterations: usize,
    /// Relative tolerance.
    pub tolerance: f64,
    /// Force scale: tensions below tolerance × max(force_scale, ‖λ‖∞) are zero.
    pub force_scale: f64,
    /// Length scale: penetrations below tolerance × max(gap_scale, ‖g‖∞) are zero.
    pub gap_scale: f64,
    /// Initial active set (sorted); `None` starts with every point active.
    /// If the initial set cannot hold a floating body (singular system), the
    /// method restarts from every point active.
    pub initial_active: Option<Vec<usize>>,
    /// The wall-clock time at which the method stops, converged or not
    /// (`None`: no time limit): it then answers the last solve's forces,
    /// not converged ([`StopReason::TimeLimit`]).
    pub deadline: Option<std::time::Instant>,
}

impl StatusOptions {
    /// The status method with `variant` on an LCP solved with `opts`: the
    /// same iteration limit, tolerance, scales and deadline.
    pub(crate) fn from_lcp(
        variant: StatusVariant,
        opts: &crate::lcp::LcpOptions,
        initial_active: Option<Vec<usize>>,
    ) -> Self {
        Self {
            variant,
            max_iterations: opts.max_iterations,
            tolerance: opts.tolerance,
            force_scale: opts.force_scale,
            gap_scale: opts.gap_scale,
            initial_active,
            deadline: opts.deadline,
        }
    }
}

/// The rule of course notes §3.3 over the [`crate::active_set`] driver: a point's
/// status is whether it is active (g_p = 0 imposed); an active point in
/// tension is released, an inactive point that penetrates is imposed.
struct Signorini<'a> {
    problem: &'a mut dyn ActiveSetSolve,
    opts: &'a StatusOptions,
    /// Size of the active set at each iteration.
    history: Vec<usize>,
}

impl StatusRule for Signorini<'_> {
    type Status = bool;
    type Solution = (Vec<f64>, Vec<f64>);

    fn solve(&mut self, active: &[bool]) -> Result<Self::Solution, ContactError> {
        let set = active_points(active);
        self.history.push(set.len());
        self.problem.solve_active(&set)
    }

    fn violations(
        &mut self,
        iteration: usize,
        active: &[bool],
        (lambda, gap): &Self::Solution,
    ) -> Result<Vec<Change<bool>>, ContactError> {
        if lambda.iter().chain(gap).any(|v| !v.is_finite()) {
            return Err(ContactError::Singular(format!(
                "non-finite forces or gaps at status iteration {iteration} with {} active points",
                active_points(active).len()
            )));
        }
        let o = self.opts;
        let (tol_f, tol_g) =
            scaled_tolerances(o.tolerance, o.force_scale, o.gap_scale, lambda, gap);
        // Violations, scaled to compare forces with gaps; listed from the
        // last point so that among equal violations the last point changes
        // first.
        let mut changes = Vec::new();
        for p in (0..active.len()).rev() {
            if active[p] && lambda[p] < -tol_f {
                changes.push((p, false, -lambda[p] / tol_f.max(f64::MIN_POSITIVE)));
            } else if !active[p] && gap[p] < -tol_g {
                changes.push((p, true, -gap[p] / tol_g.max(f64::MIN_POSITIVE)));
            }
        }
        Ok(changes)
    }

    /// A singular first solve (the initial set cannot hold a floating body)
    /// starts again from every point active. Later, when a release makes the
    /// system singular (a floating body no longer held), the method goes
    /// back to the last regular set and only imposes the penetrating points
    /// it left out, once.
    fn singular(
        &mut self,
        iteration: usize,
        active: &[bool],
        last: &mut Option<Regular<bool, Self::Solution>>,
    ) -> Option<Fallback<bool>> {
        match last.take() {
            None if iteration == 1 && active.contains(&false) => {
                Some(Fallback::Restart(vec![true; active.len()]))
            }
            Some(regular) => {
                let mut next = regular.statuses;
                let mut penetrating = regular.changes.iter().filter(|c| c.1).peekable();
                penetrating.peek()?;
                for &(p, _, _) in penetrating {
                    next[p] = true;
                }
                Some(Fallback::OneChange(next))
            }
            None => None,
        }
    }

    /// Lemke's method on the problem's LCP, when it has one: its active set
    /// is the solution's up to round-off, which the next iteration checks.
    fn leave_cycle(&mut self, active: &[bool]) -> Result<Option<Vec<bool>>, ContactError> {
        let o = self.opts;
        let lcp = crate::lcp::LcpOptions {
            tolerance: o.tolerance,
            max_iterations: o.max_iterations,
            force_scale: o.force_scale,
            gap_scale: o.gap_scale,
            stiffness: None,
            deadline: o.deadline,
        };
        let Some(set) = self.problem.pivoted_active_set(&lcp)? else {
            return Ok(None);
        };
        let mut next = vec![false; active.len()];
        for p in set {
            next[p] = true;
        }
        Ok(Some(next))
    }

    fn in_contact(&self, active: &[bool]) -> usize {
        active.iter().filter(|&&a| a).count()
    }

    fn out_of_time(&self) -> bool {
        crate::options::deadline_passed(self.opts.deadline)
    }
}

fn active_points(active: &[bool]) -> Vec<usize> {
    (0..active.len()).filter(|&p| active[p]).collect()
}

/// Runs the status method of course notes §3.3 on `problem`. The answer's
/// `active` is the last active set, its report counts one operator
/// application per iteration (one linear solve) and has no residual
/// history; `method` is "status".
pub fn status_method(
    problem: &mut dyn ActiveSetSolve,
    opts: &StatusOptions,
) -> Result<ContactSolution, ContactError> {
    let m = problem.n_points();
    let mut initial = vec![opts.initial_active.is_none(); m];
    for &p in opts.initial_active.iter().flatten() {
        initial[p] = true;
    }
    let mut rule = Signorini {
        problem,
        opts,
        history: Vec::new(),
    };
    let single = opts.variant == StatusVariant::Single;
    let out = drive(&mut rule, initial, single, opts.max_iterations)?;
    let iterations = out.iterations;
    let out_of_time = out.stop == Stop::Limit && rule.out_of_time();
    let stop = match out.stop {
        Stop::Limit if out_of_time => StopReason::TimeLimit {
            iterations,
            residual: f64::NAN,
        },
        Stop::Converged => StopReason::StatusesRepeated { iterations },
        Stop::Cycling => StopReason::Cycling {
            iteration: iterations,
        },
        Stop::Limit => StopReason::StatusLimit {
            limit: opts.max_iterations,
        },
    };
    let (forces, gaps) = out.solution.unwrap_or((vec![0.0; m], vec![0.0; m]));
    Ok(ContactSolution {
        forces,
        gaps,
        alpha: Vec::new(),
        active: active_points(&out.statuses),
        report: SolverReport {
            method: "status".into(),
            converged: out.stop == Stop::Converged,
            iterations,
            operator_applications: iterations,
            residual_history: Vec::new(),
            stop,
        },
        statuses: StatusTrace {
            active_history: rule.history,
            cycle_detected_at: out.cycle_at,
            cycle_left_by_pivoting_at: out.left_cycle_at,
            variant_used: if out.one_change {
                StatusVariant::Single
            } else {
                StatusVariant::All
            },
        },
        friction: Default::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_problems::lcp_problem;
    use crate::DelassusProblem;
    use faer::Mat;

    fn opts(variant: StatusVariant) -> StatusOptions {
        StatusOptions {
            variant,
            max_iterations: 50,
            tolerance: 1e-12,
            force_scale: 1.0,
            gap_scale: 1.0,
            initial_active: None,
            deadline: None,
        }
    }

    /// Exhaustive LCP solution over all 2^m active sets (small m).
    fn brute_force(w: &Mat<f64>, q: &[f64]) -> Vec<f64> {
        let m = q.len();
        for mask in 0..(1usize << m) {
            let act: Vec<usize> = (0..m).filter(|&i| mask >> i & 1 == 1).collect();
            let mut p = lcp_problem(w, q);
            let (l, g) = p.solve_active(&act).unwrap();
            if l.iter().all(|&v| v >= -1e-12) && g.iter().all(|&v| v >= -1e-12) {
                return l;
            }
        }
        panic!("no solution")
    }

    /// A deadline already passed stops the method after its first solve
    /// (a point in tension left to release), not converged, on the time
    /// limit; without it the same problem converges at the second.
    #[test]
    fn a_passed_deadline_stops_after_the_first_solve() {
        let w = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { 2.0 } else { 1.0 });
        let q = [-1.0, 1.0];
        let free = status_method(&mut lcp_problem(&w, &q), &opts(StatusVariant::All)).unwrap();
        assert!(
            free.report.converged && free.report.iterations == 2,
            "{}",
            free.report.stop
        );
        let late = StatusOptions {
            deadline: Some(std::time::Instant::now()),
            ..opts(StatusVariant::All)
        };
        let out = status_method(&mut lcp_problem(&w, &q), &late).unwrap();
        crate::test_problems::assert_stopped_by_the_time_limit_after_one_iteration(&out.report);
    }

    #[test]
    fn status_method_solves_small_lcps_like_enumeration() {
        // Delassus operator of three springs coupled through S, with mixed gaps.
        let s = Mat::<f64>::from_fn(3, 3, |i, j| if i == j { 4.0 } else { -1.0 });
        let rows: Vec<Vec<(usize, f64)>> = (0..3).map(|i| vec![(i, 1.0)]).collect();
        for (gap0, f) in [
            ([0.0, 0.1, -0.2], [-1.0, -1.0, -1.0]),
            ([0.5, 0.5, 0.5], [-1.0, 0.2, -3.0]),
            ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        ] {
            for variant in [StatusVariant::All, StatusVariant::Single] {
                let mut p = DelassusProblem::new(&s, &rows, &gap0, &f, &Mat::zeros(3, 0)).unwrap();
                let out = status_method(&mut p, &opts(variant)).unwrap();
                assert!(out.report.converged, "{}", out.report.stop);
                let exact = brute_force(&p.w, &p.q);
                for (a, b) in out.forces.iter().zip(&exact) {
                    assert!(
                        (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                        "{variant:?}: {a} vs {b}"
                    );
                }
                for (l, g) in out.forces.iter().zip(&out.gaps) {
                    assert!(*l >= 0.0 && *g >= -1e-12 && (l * g).abs() <= 1e-12);
                }
            }
        }
    }

    /// A symmetric positive definite W on which every violated status
    /// changing at once cycles from every point active: the fourth
    /// iteration's next active set is one already solved.
    fn cycling_lcp() -> (Mat<f64>, Vec<f64>) {
        let v = [[13.0, 13.0, -7.0], [13.0, 14.0, -5.0], [-7.0, -5.0, 9.0]];
        (Mat::from_fn(3, 3, |i, j| v[i][j]), vec![-3.0, -1.0, 4.0])
    }

    /// The LCP of [`cycling_lcp`] without a pivoting solve.
    struct NoPivoting<'a>(crate::registry::DenseLcp<'a>);

    impl ActiveSetSolve for NoPivoting<'_> {
        fn n_points(&self) -> usize {
            self.0.n_points()
        }
        fn solve_active(&mut self, a: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
            self.0.solve_active(a)
        }
    }

    #[test]
    fn a_cycle_of_the_statuses_is_left_by_complementary_pivoting() {
        let (w, q) = cycling_lcp();
        let exact = brute_force(&w, &q);
        let scale = exact.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let check = |out: &ContactSolution| {
            assert!(out.report.converged, "{}", out.report.stop);
            for (a, b) in out.forces.iter().zip(&exact) {
                assert!((a - b).abs() <= 1e-12 * scale, "{a} vs {b}");
            }
        };
        // With Lemke's method: one cycle, left at once, every status
        // changing at each iteration to the end.
        let mut lcp = crate::registry::DenseLcp::new(&w, &q);
        let out = status_method(&mut lcp, &opts(StatusVariant::All)).unwrap();
        check(&out);
        assert_eq!(out.statuses.cycle_detected_at, Some(4));
        assert_eq!(out.statuses.cycle_left_by_pivoting_at, Some(4));
        assert_eq!(out.statuses.variant_used, StatusVariant::All);
        assert_eq!(out.report.iterations, 5);
        // Without it: the same cycle, then one change per iteration.
        let mut lcp = NoPivoting(crate::registry::DenseLcp::new(&w, &q));
        let out = status_method(&mut lcp, &opts(StatusVariant::All)).unwrap();
        check(&out);
        assert_eq!(out.statuses.cycle_detected_at, Some(4));
        assert_eq!(out.statuses.cycle_left_by_pivoting_at, None);
        assert_eq!(out.statuses.variant_used, StatusVariant::Single);
    }

    #[test]
    fn a_floating_point_mass_is_held_by_the_equilibrium_of_its_rigid_mode() {
        // One DOF, S = 0 (free translation), pushed down by f = -2 onto a
        // contact row g = u: the contact force must balance it exactly.
        let s = Mat::<f64>::zeros(1, 1);
        let kernel = Mat::<f64>::from_fn(1, 1, |_, _| 1.0);
        let mut p = DelassusProblem::new(&s, &[vec![(0, 1.0)]], &[0.0], &[-2.0], &kernel).unwrap();
        let out = status_method(&mut p, &opts(StatusVariant::All)).unwrap();
        assert!(out.report.converged);
        assert!((out.forces[0] - 2.0).abs() <= 1e-12);
        assert!(p.displacement(&out.forces)[0].abs() <= 1e-12);
    }
}
