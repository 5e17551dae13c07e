//! The augmented Lagrangian method (course notes §3.4: "méthode mixte entre pénalité
//! et multiplicateur de Lagrange"), in the contact forces.
//!
//! In the displacements, the augmented Lagrangian of the contact problem
//! with penalty r and multiplier λ_k is minimised in u, then the multiplier
//! is updated: λ_{k+1} = max(0, λ_k − r g(u_{k+1})). With the displacements
//! eliminated (S u = F' + Bᵀλ, g = Wλ + q, docs/theory/contact-problem.md) the inner
//! minimisation and the update become one piecewise-linear equation in the
//! forces:
//!
//! ```text
//!   λ_{k+1} = max(0, λ_k − r (W λ_{k+1} + q)),
//! ```
//!
//! i.e. λ_{k+1} solves LCP(W + I/r, q − λ_k/r): a penalty problem (course notes §3.6
//! with k = r, see [`crate::lcp::penalty`]) whose penetration is corrected by the
//! previous multiplier. It is the proximal-point iteration on the dual
//! energy, λ_{k+1} = argmin_{λ≥0} ½λᵀWλ + qᵀλ + ‖λ − λ_k‖²/(2r): it
//! converges for every r > 0, even with W singular (redundant constraints),
//! and once the contact zone has settled the error contracts by
//! 1/(1 + r μ_min(W_AA)) per outer iteration. Unlike pure penalty, the limit
//! is the exact Signorini solution; unlike Uzawa, a larger r costs nothing in
//! stability.
//!
//! Each inner problem is solved exactly by the active-set (semi-smooth
//! Newton) iteration of [`crate::lcp::penalty`] on the symmetric positive definite
//! blocks W_AA + I/r, warm-started with the previous active set, so it
//! usually takes one or two Newton steps.
//!
//! Penalty: r = s / mean diag(W), s = `opts.stiffness` (default 100: a
//! hundred times the mean contact stiffness, a few outer iterations for
//! moderately conditioned W; larger s needs fewer outer iterations, and as
//! s → ∞ one outer iteration is the status method).

use faer::Mat;

use crate::lcp::regularised::regularised_newton;
use crate::lcp::{dual_start, mean_diag, residual_from_gaps, DualStart, LcpOptions};
use crate::solution::{ContactSolution, DualDetail, StopReason};
use crate::ContactError;

/// The augmentation factor used when `opts.stiffness` is `None`.
pub const DEFAULT_AUGMENTATION: f64 = 100.0;

/// Solves LCP(W, q) by the augmented Lagrangian method from λ_0 = 0 (see the
/// module documentation).
///
/// `report.iterations` counts the outer (multiplier) iterations and
/// `report.residual_history` the natural residual ([`crate::lcp_residual`])
/// after each; `report.operator_applications` counts the inner block solves
/// and products with W; the stopping reason gives the number of inner
/// Newton steps.
pub fn augmented_lagrangian(
    w: &Mat<f64>,
    q: &[f64],
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    let m = q.len();
    let mut run = match dual_start(w, q, opts, "augmented_lagrangian")? {
        DualStart::Done(solution) => return Ok(*solution),
        DualStart::Iterate(run) => run,
    };
    let mut lambda = vec![0.0; m];
    let s = opts.stiffness.unwrap_or(DEFAULT_AUGMENTATION);
    let d = mean_diag(w);
    if !(s.is_finite() && s > 0.0) {
        return Err(ContactError::Solve(format!(
            "augmented Lagrangian: the augmentation factor must be finite and positive, got {s}"
        )));
    }
    if d.is_nan() || d <= 0.0 {
        return Err(ContactError::Solve(
            "augmented Lagrangian: the Delassus operator has a non-positive mean diagonal".into(),
        ));
    }
    let r = s / d;
    let c = vec![1.0 / r; m];
    let mut active: Vec<bool> = q.iter().map(|&v| v < 0.0).collect();
    let mut newton_steps = 0usize;
    let mut cycles = 0usize;
    while run.next(opts) {
        // Inner problem: LCP(W + I/r, q − λ_k/r).
        let q_inner: Vec<f64> = (0..m).map(|p| q[p] - lambda[p] / r).collect();
        let inner = regularised_newton(
            w,
            &q_inner,
            &c,
            active,
            opts,
            opts.max_iterations,
            &mut |_, _| {},
        )?;
        newton_steps += inner.iterations;
        run.report.operator_applications += inner.operator_applications;
        if inner.cycle_at.is_some() {
            cycles += 1;
        }
        if matches!(inner.stop, StopReason::TimeLimit { .. }) {
            // The inner solve ran out of time: the last outer iterate.
            run.time_limit_reached();
            break;
        }
        if !inner.converged {
            run.report.stop = StopReason::InnerFailed {
                outer: run.report.iterations,
                inner: Box::new(inner.stop),
            };
            return Ok(ContactSolution::from_forces(w, q, lambda, run.report));
        }
        // True gaps g = Wλ + q = (Wλ + q̃) + λ_k/r, no extra product.
        let g: Vec<f64> = (0..m).map(|p| inner.g[p] + lambda[p] / r).collect();
        lambda = inner.lambda;
        active = inner.active;
        let res = residual_from_gaps(&lambda, &g, opts);
        if !res.is_finite() {
            return Err(ContactError::Solve(format!(
                "augmented Lagrangian: non-finite residual at outer iteration {}",
                run.report.iterations
            )));
        }
        if run.converged_at(res, opts) {
            break;
        }
    }
    let detail = DualDetail::Augmented {
        newton_steps,
        factor: s,
        cycles,
    };
    Ok(run.finish((w, q), lambda, detail, opts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_problems::*;

    fn opts() -> LcpOptions {
        lcp_options(1e-13, 500)
    }

    #[test]
    fn augmented_lagrangian_agrees_with_the_status_method() {
        for stiffness in [None, Some(1.0), Some(1e4)] {
            for c in cases() {
                let o = LcpOptions {
                    stiffness,
                    ..opts()
                };
                let sol = augmented_lagrangian(&c.w, &c.q, &o).unwrap();
                assert_solves_case(&c, &sol, &format!("{} ({stiffness:?})", c.name));
                println!(
                    "augmented Lagrangian {} (stiffness {stiffness:?}): {} outer iterations, {} solves + products; {}",
                    c.name,
                    sol.report.iterations,
                    sol.report.operator_applications,
                    sol.report.stop
                );
            }
        }
    }

    #[test]
    fn few_outer_iterations_with_the_default_augmentation() {
        for c in cases() {
            let sol = augmented_lagrangian(&c.w, &c.q, &opts()).unwrap();
            assert!(
                sol.report.iterations <= 20,
                "{}: {}",
                c.name,
                sol.report.iterations
            );
        }
    }

    #[test]
    fn augmented_lagrangian_on_redundant_constraints_gives_the_gaps_and_the_total_force() {
        let (w, q, l0, g0) = redundant();
        let sol = augmented_lagrangian(&w, &q, &opts()).unwrap();
        assert_solves_redundant(&w, &q, &l0, &g0, &sol);
    }

    #[test]
    fn augmented_lagrangian_reports_the_limit_and_rejects_bad_input() {
        let c = &cases()[2];
        let o = LcpOptions {
            max_iterations: 1,
            stiffness: Some(0.1),
            ..opts()
        };
        let sol = augmented_lagrangian(&c.w, &c.q, &o).unwrap();
        assert!(!sol.report.converged);
        assert!(
            sol.report.stop.to_string().contains("limit 1")
                || sol.report.stop.to_string().contains("not solved"),
            "{}",
            sol.report.stop
        );
        assert!(sol.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
        let mut q = c.q.clone();
        q[0] = f64::NAN;
        assert!(matches!(
            augmented_lagrangian(&c.w, &q, &opts()),
            Err(ContactError::Solve(_))
        ));
        let bad = LcpOptions {
            stiffness: Some(-1.0),
            ..opts()
        };
        assert!(matches!(
            augmented_lagrangian(&c.w, &c.q, &bad),
            Err(ContactError::Solve(_))
        ));
        let e = augmented_lagrangian(&Mat::zeros(0, 0), &[], &opts()).unwrap();
        assert!(e.report.converged && e.forces.is_empty());
    }
}
