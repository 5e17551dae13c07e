//! The friction status method on the condensed problem, 2D (course notes
//! §4.5, and the Tresca problems of §4.3): each frictional contact point has a
//! normal force λ_n (row of B) and a tangential force λ_t (row of T); the
//! "gap" of a tangential row is the slip increment Δs of the slave relative
//! to the master along t since the previous load step (course notes §4.4: the
//! conditions hold on the totals, the slip on the increments).
//!
//! Laws, with the threshold g (Tresca, §4.1.1) or μ λ_n (Coulomb, §4.1.2):
//! stick |λ_t| < g and Δs = 0; slip |λ_t| = g and the slip opposes the
//! force, λ_t Δs ≤ 0. The statuses open, stick, slip+, slip− each impose
//! one equation per force variable, solved over the [`crate::active_set`]
//! driver, with the rigid modes of floating bodies:
//!
//! - [`tresca_status`]: the Tresca problem (fixed thresholds);
//! - [`coulomb_status`]: the status method applied to friction (§4.5), slip
//!   statuses imposing λ_t = ±μ λ_n directly; the course notes warn that it
//!   converges badly, and the report counts its iterations;
//! - `status_loop`: one status loop with given thresholds, the inner
//!   problem of the 2D fixed points (`crate::friction::status_tresca`).

use crate::active_set::{drive, scaled_tolerances, Change, Fallback, Regular, StatusRule, Stop};
use crate::delassus::DelassusProblem;
use crate::law::{FrictionLaw, FrictionLayout};
use crate::options::FrictionOptions;
use crate::solution::friction_iterate::{FixedPoint, InnerSolve};
use crate::solution::{ContactSolution, PointStatus, StopReason};
use crate::ContactError;
use signorini_linalg::capacitance::StatusFactor;
use signorini_linalg::reduced::VarEquation;

fn equations(
    layout: &FrictionLayout,
    statuses: &[PointStatus],
    threshold: &[f64],
    coulomb_ratio: bool,
) -> Vec<VarEquation> {
    let m = statuses.len();
    let n_rows = m + layout.tangent_rows.iter().flatten().count();
    let mut eqs = vec![VarEquation::Gap; n_rows];
    for (p, &st) in statuses.iter().enumerate() {
        eqs[p] = if st == PointStatus::Open {
            VarEquation::Value(0.0)
        } else {
            VarEquation::Gap
        };
        if let Some(t) = layout.tangent_row(p) {
            // Stuck while its shadow is closed, the point's slip is already
            // held by the shadow's gap: the two rows are one constraint, the
            // split of the force between them is free, and the friction
            // force is taken as zero (inside any cone) so that the system
            // stays regular.
            let held = layout
                .shadow
                .get(p)
                .copied()
                .flatten()
                .is_some_and(|q| statuses[q] != PointStatus::Open);
            eqs[t] = match st {
                PointStatus::Open => VarEquation::Value(0.0),
                PointStatus::Stick | PointStatus::Slip if held => VarEquation::Value(0.0),
                // Slip (3D) does not occur in 2D: no direction, treated as stick.
                PointStatus::Stick | PointStatus::Slip => VarEquation::Gap,
                PointStatus::SlipPlus | PointStatus::SlipMinus => {
                    let sign = if st == PointStatus::SlipPlus {
                        1.0
                    } else {
                        -1.0
                    };
                    match (coulomb_ratio, layout.law[p]) {
                        (true, FrictionLaw::Coulomb { mu }) => VarEquation::Ratio {
                            of: p,
                            factor: sign * mu[0],
                        },
                        _ => VarEquation::Value(sign * threshold[p]),
                    }
                }
            };
        }
    }
    eqs
}

/// The status of a point closing from open, with the gaps `g` it had while
/// open: it slips on in the direction it was moving (the force opposing
/// it), or sticks if it was not moving or its threshold is infinite.
fn closing_status(
    layout: &FrictionLayout,
    p: usize,
    g: &[f64],
    finite: bool,
    tol_g: f64,
) -> PointStatus {
    match layout.tangent_row(p).map(|t| g[t]) {
        Some(s) if finite && s > tol_g => PointStatus::SlipMinus,
        Some(s) if finite && s < -tol_g => PointStatus::SlipPlus,
        _ => PointStatus::Stick,
    }
}

/// The statuses of a cold start (no earlier solution) for the 2D status
/// methods: each point of `closed` that sticks is given the status of a
/// point closing from open ([`closing_status`]) with the gaps of zero
/// forces, q. From every closed point sticking, the first status system has
/// all their tangents as unknowns, a (2|A|)² factorisation, and in a
/// partial-slip problem its answer makes most of them slip; predicted so,
/// the first system is solved on the normals and the sticking tangents.
/// Points whose slip is held by a shadow ([`FrictionLayout::shadow`]) keep
/// sticking.
pub fn predicted_statuses(
    layout: &FrictionLayout,
    q: &[f64],
    closed: Vec<PointStatus>,
    opts: &FrictionOptions,
) -> Vec<PointStatus> {
    let (_, tol_g) = scaled_tolerances(opts.tolerance, 0.0, opts.gap_scale, &[], q);
    let finite = |p: usize| layout.law[p].semi_axes(1.0)[0].is_finite();
    let shadowed = |p: usize| layout.shadow.get(p).copied().flatten().is_some();
    let statuses = closed.into_iter().enumerate();
    statuses
        .map(|(p, st)| match st {
            PointStatus::Stick if !shadowed(p) => closing_status(layout, p, q, finite(p), tol_g),
            other => other,
        })
        .collect()
}

/// One status update; returns the changes as (point, new status, violation).
fn updates(
    layout: &FrictionLayout,
    statuses: &[PointStatus],
    r: &[f64],
    g: &[f64],
    threshold: &[f64],
    tol_f: f64,
    tol_g: f64,
) -> Vec<(usize, PointStatus, f64)> {
    let mut out = Vec::new();
    for (p, &st) in statuses.iter().enumerate() {
        let (ln, gn) = (r[p], g[p]);
        match st {
            PointStatus::Open => {
                if gn < -tol_g {
                    let next = closing_status(layout, p, g, threshold[p].is_finite(), tol_g);
                    out.push((p, next, -gn / tol_g));
                }
                continue;
            }
            _ if ln < -tol_f => {
                out.push((p, PointStatus::Open, -ln / tol_f));
                continue;
            }
            _ => {}
        }
        let Some(t) = layout.tangent_row(p) else {
            continue;
        };
        let (lt, s) = (r[t], g[t]);
        let bound = threshold[p].max(0.0);
        match st {
            PointStatus::Stick if lt > bound + tol_f => {
                out.push((p, PointStatus::SlipPlus, (lt - bound) / tol_f))
            }
            PointStatus::Stick if lt < -bound - tol_f => {
                out.push((p, PointStatus::SlipMinus, (-bound - lt) / tol_f))
            }
            // A slip in the direction of the force is not a slip: stick. With a
            // zero threshold the force is zero and any slip direction dissipates
            // nothing: the point keeps slipping.
            PointStatus::SlipPlus if s > tol_g && bound > tol_f => {
                out.push((p, PointStatus::Stick, s / tol_g))
            }
            PointStatus::SlipMinus if s < -tol_g && bound > tol_f => {
                out.push((p, PointStatus::Stick, -s / tol_g))
            }
            _ => {}
        }
    }
    out
}

/// The status rule of friction (course notes §4.5, and the Tresca problems of
/// §4.3) over the [`crate::active_set`] driver: statuses open, stick, slip±,
/// one equation per force variable ([`equations`]), the changes of
/// [`updates`].
struct FrictionRule<'a> {
    problem: &'a mut DelassusProblem,
    layout: &'a FrictionLayout,
    /// Thresholds (Tresca values, or μ λ_n of the previous fixed-point
    /// iterate; with `coulomb_ratio`, μ λ_n of the last solve).
    thr: Vec<f64>,
    coulomb_ratio: bool,
    opts: &'a FrictionOptions,
    /// The factor of an earlier status system, updated from one iteration
    /// to the next ([`signorini_linalg::capacitance`]).
    factor: &'a mut Option<StatusFactor>,
}

impl StatusRule for FrictionRule<'_> {
    type Status = PointStatus;
    type Solution = (Vec<f64>, Vec<f64>);

    fn solve(&mut self, statuses: &[PointStatus]) -> Result<Self::Solution, ContactError> {
        let eqs = equations(self.layout, statuses, &self.thr, self.coulomb_ratio);
        self.problem.solve_equations_updating(&eqs, self.factor)
    }

    fn violations(
        &mut self,
        _: usize,
        statuses: &[PointStatus],
        (r, g): &Self::Solution,
    ) -> Result<Vec<Change<PointStatus>>, ContactError> {
        if self.coulomb_ratio {
            self.thr = thresholds_from(self.layout, r);
        }
        let o = self.opts;
        let (tol_f, tol_g) = scaled_tolerances(o.tolerance, o.force_scale, o.gap_scale, r, g);
        Ok(updates(
            self.layout,
            statuses,
            r,
            g,
            &self.thr,
            tol_f,
            tol_g,
        ))
    }

    /// Nothing holds a friction-held body: go back to the last regular
    /// statuses and make their most loaded contact point not yet tried stick
    /// (one stick point holds the tangential motion).
    fn singular(
        &mut self,
        _: usize,
        _: &[PointStatus],
        last: &mut Option<Regular<PointStatus, Self::Solution>>,
    ) -> Option<Fallback<PointStatus>> {
        let regular = last.as_mut()?;
        let (prev, prev_r) = (&regular.statuses, &regular.solution.0);
        let p = (0..prev.len())
            .filter(|&p| {
                prev[p] != PointStatus::Open
                    && self.layout.tangent_row(p).is_some()
                    && !regular.tried.contains(&p)
            })
            .max_by(|&a, &b| prev_r[a].total_cmp(&prev_r[b]))?;
        regular.tried.push(p);
        let mut next = prev.clone();
        next[p] = PointStatus::Stick;
        Some(Fallback::OneChange(next))
    }

    fn in_contact(&self, statuses: &[PointStatus]) -> usize {
        statuses.iter().filter(|&&s| s != PointStatus::Open).count()
    }

    fn out_of_time(&self) -> bool {
        crate::options::deadline_passed(self.opts.deadline)
    }
}

/// The natural residual of the friction law at (r, g), forces relative to
/// max(force scale, ‖r‖∞).
fn law_residual(layout: &FrictionLayout, r: &[f64], g: &[f64], opts: &FrictionOptions) -> f64 {
    let force = opts.force_scale.max(crate::norms::max_abs(r));
    crate::law::natural_residual(layout, r, g, force, opts.gap_scale)
}

/// Status iterations with the thresholds `thr` (Tresca values, or μ λ_n of
/// the previous fixed-point iterate); with `coulomb_ratio`, slipping Coulomb
/// points use λ_t = ±μ λ_n instead (§4.5).
pub(crate) fn status_loop(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    run: &mut Run,
    thr: Vec<f64>,
    coulomb_ratio: bool,
    opts: &FrictionOptions,
) -> Result<InnerSolve, ContactError> {
    let mut rule = FrictionRule {
        problem,
        layout,
        thr,
        coulomb_ratio,
        opts,
        factor: &mut run.factor,
    };
    let initial = std::mem::take(&mut run.statuses);
    let out = drive(&mut rule, initial, false, opts.max_iterations)?;
    let out_of_time = out.stop == Stop::Limit && rule.out_of_time();
    run.statuses = out.statuses;
    run.iterations += out.iterations;
    run.cycle |= out.cycle_at.is_some();
    let reason = match out.stop {
        Stop::Converged => StopReason::FrictionStatusesRepeated {
            solves: run.iterations,
        },
        Stop::Cycling => StopReason::FrictionCycling,
        Stop::Limit if out_of_time => StopReason::TimeLimit {
            iterations: run.iterations,
            residual: f64::NAN,
        },
        Stop::Limit => StopReason::StatusLimit {
            limit: opts.max_iterations,
        },
    };
    let (forces, gaps) = out.solution.unwrap_or_default();
    let reason = match reason {
        StopReason::TimeLimit { iterations, .. } => StopReason::TimeLimit {
            iterations,
            residual: law_residual(layout, &forces, &gaps, opts),
        },
        other => other,
    };
    Ok(InnerSolve {
        forces,
        gaps,
        statuses: run.statuses.clone(),
        converged: out.stop == Stop::Converged,
        reason,
    })
}

/// The threshold of each point (2D: the first semi-axis of its law) with
/// the normal forces `r`.
pub(crate) fn thresholds_from(layout: &FrictionLayout, r: &[f64]) -> Vec<f64> {
    let laws = layout.law.iter().enumerate();
    laws.map(|(p, law)| law.semi_axes(r[p])[0]).collect()
}

/// What a friction solve carries from status loop to status loop.
pub(crate) struct Run {
    pub statuses: Vec<PointStatus>,
    /// Status solves so far.
    pub iterations: usize,
    cycle: bool,
    /// Inner Tresca problems solved by the box QP after the status method
    /// cycled.
    pub box_fallbacks: usize,
    /// The factor of the last status system (W does not change in a run).
    factor: Option<StatusFactor>,
}

impl Run {
    pub fn new(statuses: Vec<PointStatus>) -> Self {
        Self {
            statuses,
            iterations: 0,
            cycle: false,
            box_fallbacks: 0,
            factor: None,
        }
    }

    /// The solution by `method` that ended at `end` after this run, with
    /// the `solves` of the problem so far.
    pub fn finish(self, mut end: FixedPoint, method: &str, solves: usize) -> ContactSolution {
        if self.box_fallbacks > 0 {
            end.reason = StopReason::BoxFallbacks {
                before: Box::new(end.reason),
                count: self.box_fallbacks,
            };
        }
        let mut sol = end.solution(method, self.iterations, self.cycle);
        sol.report.operator_applications = solves;
        sol
    }
}

/// One status loop with thresholds that do not depend on the forces (or,
/// with `coulomb_ratio`, with λ_t = ±μ λ_n imposed at slipping points).
fn fixed_thresholds(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    initial: Vec<PointStatus>,
    coulomb_ratio: bool,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    layout.validate(problem.q.len(), 2)?;
    let mut run = Run::new(initial);
    let thresholds = thresholds_from(layout, &vec![0.0; layout.n_points()]);
    let last = status_loop(problem, layout, &mut run, thresholds, coulomb_ratio, opts)?;
    let end = FixedPoint {
        converged: last.converged,
        reason: last.reason.clone(),
        residuals: Vec::new(),
        last,
    };
    let method = if coulomb_ratio {
        "friction_status"
    } else {
        "tresca_status"
    };
    Ok(run.finish(end, method, problem.solves))
}

/// The Tresca problem (fixed thresholds) by the status method.
pub fn tresca_status(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    initial: Vec<PointStatus>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    fixed_thresholds(problem, layout, initial, false, opts)
}

/// The status method applied to friction (course notes §4.5): slipping Coulomb
/// points impose λ_t = ±μ λ_n in the same linear system as the contact
/// conditions; statuses change until they repeat.
pub fn coulomb_status(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    initial: Vec<PointStatus>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    fixed_thresholds(problem, layout, initial, true, opts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::coulomb_fixed_point;
    use faer::Mat;

    /// One elastic point pressed on a plane (normal stiffness kn) and pulled
    /// tangentially (stiffness kt): the forces follow by hand.
    fn one_point(fn_: f64, ft: f64) -> DelassusProblem {
        // DOFs (x, y) with S = diag(kt, kn); rows: normal = u_y, tangent = u_x.
        let s = Mat::<f64>::from_fn(2, 2, |i, j| {
            if i != j {
                0.0
            } else if i == 0 {
                2.0
            } else {
                5.0
            }
        });
        let rows = vec![vec![(1, 1.0)], vec![(0, 1.0)]];
        DelassusProblem::new(&s, &rows, &[0.0, 0.0], &[ft, -fn_], &Mat::zeros(2, 0)).unwrap()
    }

    fn layout(t: FrictionLaw) -> FrictionLayout {
        FrictionLayout {
            tangent_rows: vec![vec![1]],
            law: vec![t],
            shadow: vec![None],
        }
    }

    fn opts() -> FrictionOptions {
        FrictionOptions {
            max_iterations: 50,
            max_fixed_point: 50,
            tolerance: 1e-12,
            force_scale: 1.0,
            gap_scale: 1.0,
            deadline: None,
        }
    }

    /// One point from stick by the Coulomb fixed point (`solve` = 0), the
    /// Coulomb status method (1) with `l`, or the Tresca status method
    /// with the threshold 1.5 (otherwise).
    fn solve_one(solve: usize, p: &mut DelassusProblem, l: &FrictionLayout) -> ContactSolution {
        match solve {
            0 => coulomb_fixed_point(p, l, vec![PointStatus::Stick], None, &opts()).unwrap(),
            1 => coulomb_status(p, l, vec![PointStatus::Stick], &opts()).unwrap(),
            _ => tresca_status(
                p,
                &layout(FrictionLaw::Tresca(1.5)),
                vec![PointStatus::Stick],
                &opts(),
            )
            .unwrap(),
        }
    }

    #[test]
    fn a_point_sticks_below_the_threshold_and_slips_at_it() {
        // Pressed by N = 3, pulled by Q = 1: μ = 0.5 → μN = 1.5 > Q: sticks, λ_t = −Q.
        for solve in [0, 1, 2] {
            let mut p = one_point(3.0, 1.0);
            let l = layout(FrictionLaw::coulomb(0.5));
            let out = solve_one(solve, &mut p, &l);
            assert!(out.report.converged, "{}", out.report.stop);
            assert_eq!(out.friction.points, vec![PointStatus::Stick]);
            assert!(
                (out.forces[0] - 3.0).abs() < 1e-12 && (out.forces[1] + 1.0).abs() < 1e-12,
                "{:?}",
                out.forces
            );
            // Pulled by Q = 2 > μN = 1.5: slips, λ_t = −1.5, slip Q − μN over kt = 0.25 in +x.
            let mut p = one_point(3.0, 2.0);
            let out = solve_one(solve, &mut p, &l);
            assert!(out.report.converged);
            assert_eq!(out.friction.points, vec![PointStatus::SlipMinus]);
            assert!((out.forces[1] + 1.5).abs() < 1e-12, "{:?}", out.forces);
            assert!((out.gaps[1] - 0.25).abs() < 1e-12, "slip {}", out.gaps[1]);
            // The friction force opposes the slip.
            assert!(out.forces[1] * out.gaps[1] < 0.0);
        }
    }

    #[test]
    fn zero_friction_equals_the_frictionless_answer() {
        let mut p = one_point(3.0, 0.0);
        let out = solve_one(0, &mut p, &layout(FrictionLaw::coulomb(0.0)));
        assert!(out.report.converged);
        assert!((out.forces[0] - 3.0).abs() < 1e-12 && out.forces[1].abs() < 1e-12);
    }

    #[test]
    fn a_point_pulled_away_opens() {
        let mut p = one_point(-3.0, 1.0);
        let out = solve_one(0, &mut p, &layout(FrictionLaw::coulomb(0.5)));
        assert!(out.report.converged);
        assert_eq!(out.friction.points, vec![PointStatus::Open]);
        assert_eq!(out.forces, vec![0.0, 0.0]);
    }
    /// A partial-slip problem (30 points, a diagonally dominant W, pulled
    /// tangentially by q_t of both signs): started from the slip predicted
    /// by q ([`predicted_statuses`]) instead of every point sticking, the
    /// status method reaches the same forces and statuses.
    #[test]
    fn the_predicted_start_reaches_the_answer_of_the_stuck_start() {
        let m = 30;
        let mut rng = crate::test_problems::XorShift(7);
        let mut w = crate::test_problems::random_spd(2 * m, &mut rng);
        for v in w.as_mut().col_iter_mut().flat_map(|c| c.iter_mut()) {
            *v *= 0.01;
        }
        for i in 0..2 * m {
            w[(i, i)] += 1.0;
        }
        let q: Vec<f64> = (0..2 * m)
            .map(|i| match i < m {
                true if i % 7 == 3 => 0.2,
                true => -1.0 - 0.5 * (i as f64).sin(),
                false => 0.8 * (1.7 * i as f64).cos(),
            })
            .collect();
        let layout = FrictionLayout {
            tangent_rows: (0..m).map(|p| vec![m + p]).collect(),
            law: vec![FrictionLaw::coulomb(0.3); m],
            shadow: vec![None; m],
        };
        let closed: Vec<PointStatus> = (0..m)
            .map(|p| match q[p] <= 0.0 {
                true => PointStatus::Stick,
                false => PointStatus::Open,
            })
            .collect();
        let predicted = predicted_statuses(&layout, &q, closed.clone(), &opts());
        assert!(predicted.iter().filter(|s| s.is_slip()).count() >= m / 2);
        let solve = |start: Vec<PointStatus>| {
            let mut p = crate::test_problems::lcp_problem(&w, &q);
            coulomb_status(&mut p, &layout, start, &opts()).unwrap()
        };
        let (stuck, slipping) = (solve(closed), solve(predicted));
        assert!(stuck.report.converged && slipping.report.converged);
        assert_eq!(stuck.friction.points, slipping.friction.points);
        let n = stuck.forces.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in stuck.forces.iter().zip(&slipping.forces) {
            assert!((a - b).abs() <= 1e-10 * n, "{a} against {b}");
        }
        let slips = stuck.friction.points.iter().filter(|s| s.is_slip());
        let sticks = stuck
            .friction
            .points
            .iter()
            .filter(|&&s| s == PointStatus::Stick);
        assert!(slips.count() > 0 && sticks.count() > 0, "partial slip");
    }
}
