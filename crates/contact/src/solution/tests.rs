//! The words of every [`StopReason`] against the `format!` each method
//! wrote before the reasons became data (copied verbatim), so that
//! `report.json`'s `stopping_reason` texts do not change.

use super::*;

const RES: f64 = 1.234_567e-7;
const TOL: f64 = 1e-10;

fn steps() -> MprgpSteps {
    MprgpSteps {
        cg: 12,
        expansion: 3,
        proportioning: 4,
    }
}

fn same(stop: StopReason, old: String) {
    assert_eq!(stop.to_string(), old);
}

#[test]
fn the_reasons_of_the_projection_methods_and_lemke_read_as_before() {
    let (res, tol) = (RES, TOL);
    same(StopReason::NoContactPoint, "no contact point".into());
    same(StopReason::Pending, String::new());
    same(
        StopReason::ZeroForces { residual: res },
        format!("λ = 0 already satisfies the tolerance (natural residual {res:.3e}): no point in contact"),
    );
    same(
        StopReason::ResidualMet {
            residual: res,
            tolerance: tol,
            iterations: 7,
        },
        format!(
            "natural residual {:.3e} ≤ tolerance {:.3e} after {} iterations",
            res, tol, 7
        ),
    );
    same(
        StopReason::IterationLimit { limit: 9, measure: Measure::Natural, residual: res, tolerance: tol, steps: None },
        format!("iteration limit {} reached with natural residual {res:.3e} above tolerance {tol:.3e} (not converged)", 9),
    );
    same(
        StopReason::Stagnation { iteration: 4, measure: Measure::Natural, residual: res, tolerance: tol },
        format!("stagnation at iteration {}: no descent direction left at natural residual {res:.3e} above tolerance {tol:.3e} (round-off floor; not converged)", 4),
    );
    same(
        StopReason::LineSearchFailed {
            iteration: 5,
            residual: res,
        },
        format!(
            "line search failed at iteration {} (natural residual {:.3e})",
            5, res
        ),
    );
    same(
        StopReason::NoPivot,
        "q ≥ 0: λ = 0 solves the LCP (no pivot)".into(),
    );
    same(
        StopReason::PivotLimit { limit: 30, residual: res },
        format!("pivot limit {} reached before z0 left the basis (natural residual {res:.3e}; not converged)", 30),
    );
    for polished in [false, true] {
        same(
            StopReason::Pivoted { pivots: 6, residual: res, tolerance: tol, polished },
            format!(
                "z0 left the basis after {} pivots; natural residual {res:.3e} ≤ tolerance {:.3e}{}",
                6,
                tol,
                if polished { " after polishing on the active set" } else { "" }
            ),
        );
    }
    same(
        StopReason::PivotedAboveTolerance { pivots: 6, residual: res, tolerance: tol },
        format!("z0 left the basis after {} pivots but the natural residual {res:.3e} is above tolerance {:.3e} (round-off on an ill-conditioned W; not converged)", 6, tol),
    );
}

#[test]
fn the_reasons_of_mprgp_read_as_before() {
    let (res, tol, norm_w) = (RES, TOL, 3.25);
    for (measure, name) in [
        (Measure::Natural, "natural residual"),
        (Measure::ProjectedGradient, "projected-gradient residual"),
    ] {
        same(
            StopReason::IterationLimit { limit: 9, measure, residual: res, tolerance: tol, steps: Some(steps()) },
            format!(
                "iteration limit {} reached with {} {res:.3e} above tolerance {:.3e} (not converged; {})",
                9, name, tol, "12 CG, 3 expansion, 4 proportioning steps"
            ),
        );
        same(
            StopReason::Stagnation { iteration: 4, measure, residual: res, tolerance: tol },
            format!("stagnation at iteration {}: no descent direction left at {} {res:.3e} above tolerance {:.3e} (round-off floor; not converged)", 4, name, tol),
        );
        for (polish, polished) in [
            (BoxPolish::NotTried, ""),
            (BoxPolish::Polished, "; polished on the active set"),
            (BoxPolish::LeftTheBox, "; polishing rejected (left the box)"),
            (
                BoxPolish::LargerResidual,
                "; polishing rejected (larger residual)",
            ),
        ] {
            same(
                StopReason::StartMeetsTolerance { measure, residual: res, tolerance: tol, polish },
                format!("the start projected onto the box meets the tolerance: {} {res:.3e} ≤ tolerance {:.3e}{polished}", name, tol),
            );
            same(
                StopReason::MprgpConverged { measure, residual: res, tolerance: tol, iterations: 19, steps: steps(), norm_w, polish },
                format!(
                    "{} {res:.3e} ≤ tolerance {:.3e} after {} iterations ({}; ᾱ = 1.9/‖W‖, ‖W‖ ≈ {:.6e}){polished}",
                    name, tol, 19, "12 CG, 3 expansion, 4 proportioning steps", norm_w
                ),
            );
        }
    }
    same(
        StopReason::LinearObjective { residual: res },
        format!("W = 0: the linear objective is minimised at the bounds, residual {res:.3e}"),
    );
}

#[test]
fn the_reasons_of_the_dual_methods_read_as_before() {
    let (res, tol) = (RES, TOL);
    let uzawa = |step, halvings| DualDetail::Uzawa { step, halvings };
    for (step, origin) in [
        (
            UzawaStep::Given { factor: 0.5 },
            format!("{} / mean diag W", 0.5),
        ),
        (
            UzawaStep::PowerIteration { norm: 2.5 },
            format!("1.9 / ‖W‖₂ (power iteration: ‖W‖₂ ≈ {:.6e})", 2.5),
        ),
        (UzawaStep::ZeroOperator, "1 (W = 0)".to_string()),
    ] {
        for (halvings, halved) in [
            (0, String::new()),
            (
                3,
                ", halved 3 times because the dual energy increased".to_string(),
            ),
        ] {
            let detail = format!("ρ = {origin}{halved}");
            same(
                StopReason::DualConverged {
                    residual: res,
                    tolerance: tol,
                    iterations: 8,
                    detail: uzawa(step, halvings),
                },
                format!(
                    "natural residual {res:.3e} ≤ tolerance {:.1e} after {} {} ({detail})",
                    tol, 8, "iterations"
                ),
            );
            same(
                StopReason::DualLimit { limit: 5, residual: res, tolerance: tol, detail: uzawa(step, halvings) },
                format!(
                    "iteration limit {} reached: natural residual {:.3e} > tolerance {:.1e} ({detail}); {}",
                    5, res, tol, "Uzawa converges slowly when W is ill-conditioned"
                ),
            );
        }
    }
    for (cycles, note) in [
        (0, String::new()),
        (
            2,
            "; 2 inner problems cycled and switched to one status change per step".to_string(),
        ),
    ] {
        let (newton_steps, s) = (14, 100.0);
        let al = DualDetail::Augmented {
            newton_steps,
            factor: s,
            cycles,
        };
        let detail = format!(
            "{newton_steps} inner Newton steps, r = {s} / mean diag W{}",
            note
        );
        same(
            StopReason::DualConverged {
                residual: res,
                tolerance: tol,
                iterations: 3,
                detail: al.clone(),
            },
            format!(
                "natural residual {res:.3e} ≤ tolerance {:.1e} after {} {} ({detail})",
                tol, 3, "outer iterations"
            ),
        );
        same(
            StopReason::DualLimit { limit: 5, residual: res, tolerance: tol, detail: al },
            format!(
                "iteration limit {} reached: natural residual {:.3e} > tolerance {:.1e} ({detail}); {}",
                5, res, tol, "a larger augmentation (stiffness option) converges in fewer outer iterations"
            ),
        );
    }
    let inner = StopReason::ActiveSetLimit { limit: 5 };
    same(
        StopReason::InnerFailed {
            outer: 2,
            inner: Box::new(inner.clone()),
        },
        format!(
            "inner problem of outer iteration {} not solved: {}",
            2, "iteration limit 5 reached with the active set still changing"
        ),
    );
}

#[test]
fn the_reasons_of_the_status_and_penalty_methods_read_as_before() {
    let iterations = 4;
    same(
        StopReason::StatusesRepeated { iterations },
        format!("statuses repeated after {iterations} iterations"),
    );
    same(
        StopReason::Cycling { iteration: iterations },
        format!("cycling: the active set of iteration {iterations} repeats an earlier one even with one status change per iteration (the contact zone is probably meshed too coarsely, course notes §3.3)"),
    );
    same(
        StopReason::StatusLimit { limit: 50 },
        format!(
            "iteration limit {} reached with statuses still changing",
            50
        ),
    );
    let pen = 2.5e-9;
    for (cycle_at, note) in [
        (None, String::new()),
        (Some(3), format!(" (an active set repeated at iteration {}: switched to one status change per iteration, least index first)", 3)),
    ] {
        same(
            StopReason::RegularisedSolved { active: 6, iterations: 5, cycle_at, penetration: pen },
            format!(
                "regularised law solved exactly: the active set ({} points) repeated after {} iterations{}; max penetration {pen:.3e} (O(1/k), course notes §3.6)",
                6, 5, note
            ),
        );
    }
    same(
        StopReason::NewtonCycling { iteration: 7, tolerance: TOL },
        format!("cycling: the active set of iteration {} repeats an earlier one even with one status change per iteration (round-off at the tolerance {:.1e}?)", 7, TOL),
    );
    let max_iterations = 11;
    same(
        StopReason::ActiveSetLimit {
            limit: max_iterations,
        },
        format!("iteration limit {max_iterations} reached with the active set still changing"),
    );
    same(
        StopReason::ByPenalty {
            status: Box::new(StopReason::StatusesRepeated { iterations }),
            penetration: pen,
        },
        format!(
            "{} (constraints imposed by penalty); max penetration {:.3e} (O(1/k))",
            "statuses repeated after 4 iterations", pen
        ),
    );
}

#[test]
fn the_reasons_of_smalbe_and_polishing_read_as_before() {
    let (natural, feas, tol, rho) = (RES, 2.0 * RES, TOL, 12.5);
    let inner = StopReason::ResidualMet {
        residual: RES,
        tolerance: TOL,
        iterations: 3,
    };
    let last_reason = inner.to_string();
    let progress = SmalbeProgress {
        outer: 2,
        inner_iterations: 30,
        rho,
    };
    let progress_text = format!(
        "after {} outer iterations ({} inner iterations; ρ = {rho:.3e})",
        2, 30
    );
    let last_inner = Box::new(inner.clone());
    same(
        StopReason::Smalbe(SmalbeStop::Met { natural, feasibility: feas, tolerance: tol, progress, last_inner: last_inner.clone() }),
        format!("SMALBE: natural residual {natural:.3e} and equilibrium residual {feas:.3e} ≤ tolerance {:.3e} {progress_text}; last inner: {last_reason}", tol),
    );
    same(
        StopReason::Smalbe(SmalbeStop::Settled { progress, tolerance: tol, last_inner: last_inner.clone() }),
        format!("SMALBE: the active set settled {progress_text}; one saddle-point solve on it meets the tolerance {:.3e}; last inner: {last_reason}", tol),
    );
    same(
        StopReason::Smalbe(SmalbeStop::InnerFailed {
            outer: 3,
            inner: last_inner.clone(),
        }),
        format!(
            "SMALBE outer iteration {}: the inner solver did not converge: {}",
            3, last_reason
        ),
    );
    const MAX_OUTER: usize = 60;
    same(
        StopReason::Smalbe(SmalbeStop::Exhausted { outer: MAX_OUTER, tolerance: tol, natural, feasibility: feas, rho, last_inner }),
        format!("SMALBE: {MAX_OUTER} outer iterations without meeting the tolerance {:.3e} (natural residual {natural:.3e}, equilibrium residual {feas:.3e}, ρ = {rho:.3e}); last inner: {last_reason}", tol),
    );
    let mut report = SolverReport {
        stop: inner,
        ..Default::default()
    };
    report.record_polish(1e-16, PolishSolve::ActiveSet);
    assert_eq!(
        report.stop.to_string(),
        format!("{last_reason}; polished by one solve on the identified active set")
    );
    report.record_polish(1e-16, PolishSolve::SaddlePoint);
    assert!(report
        .stop
        .to_string()
        .ends_with("; polished by one saddle-point solve on the identified active set"));
    assert_eq!(report.operator_applications, 2);
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["stopping_reason"], report.stop.to_string());
    assert!(json.get("stop").is_none());
}

#[test]
fn the_reasons_of_the_friction_status_method_and_the_fixed_point_read_as_before() {
    let (solves, max_iterations, boxed) = (7usize, 50usize, 2usize);
    same(
        StopReason::FrictionStatusesRepeated { solves },
        format!("statuses repeated after {} status solves", solves),
    );
    same(
        StopReason::FrictionCycling,
        "cycling even with one status change per iteration".into(),
    );
    same(
        StopReason::StatusLimit {
            limit: max_iterations,
        },
        format!(
            "iteration limit {} reached with statuses still changing",
            max_iterations
        ),
    );
    same(
        StopReason::TrescaBoxSolved,
        "solved by MPRGP on the Tresca box".into(),
    );
    let inner = StopReason::FrictionCycling;
    let inner_text = inner.to_string();
    same(
        StopReason::InnerTresca(Box::new(inner.clone())),
        format!("inner Tresca problem: {}", inner_text),
    );
    for (map, name) in [
        (ThresholdMapKind::Coulomb, "fixed point on the threshold"),
        (ThresholdMapKind::NortonHoff, "Norton-Hoff fixed point"),
    ] {
        let reached = StopReason::FixedPointReached { map, iterations: 4 };
        let reached_text = format!("{} reached after {} iterations", name, 3 + 1);
        same(reached.clone(), reached_text.clone());
        same(
            StopReason::FixedPointLimit {
                map,
                limit: max_iterations,
            },
            format!("{} not reached in {} iterations", name, max_iterations),
        );
        same(
            StopReason::BoxFallbacks {
                before: Box::new(reached),
                count: boxed,
            },
            format!(
                "{} ({} inner Tresca problem(s) solved by MPRGP on the box after the status method cycled)",
                reached_text, boxed
            ),
        );
    }
}

#[test]
fn the_reasons_of_the_semismooth_newton_method_read_as_before() {
    let (res, it, max_iterations) = (RES, 9usize, 100usize);
    let converged = StopReason::NewtonConverged {
        residual: res,
        iterations: it,
    };
    let converged_text = format!("natural residual {res:.2e} after {it} Newton iterations");
    same(converged.clone(), converged_text.clone());
    same(
        StopReason::NewtonLimit {
            limit: max_iterations,
        },
        format!("iteration limit {} reached", max_iterations),
    );
    same(
        StopReason::NewtonStalled {
            best: 1.2e-2,
            at: 143,
            since: 60,
        },
        "stalled: no iterate came closer than the residual 1.20e-2 (iteration 143) in the 60 iterations since".into(),
    );
    same(
        StopReason::NewtonLineSearchFailed,
        "the Newton line search failed repeatedly (floating bodies: no fallback)".into(),
    );
    same(
        StopReason::Tresca(Box::new(converged)),
        format!("Tresca: {}", converged_text),
    );
}
