//! Uzawa's algorithm on the dual problem: the method of Lagrange multipliers
//! of course notes §3.4 ("le problème unilatéral est reporté sur les efforts par
//! dualisation").
//!
//! Eliminating the displacements (S u = F' + Bᵀλ, docs/theory/contact-problem.md) leaves the
//! dual problem in the contact forces alone,
//!
//! ```text
//!   min_{λ ≥ 0}  J(λ) = ½ λᵀ W λ + qᵀ λ,     ∇J(λ) = W λ + q = g(λ),
//! ```
//!
//! whose optimality conditions are LCP(W, q): λ ≥ 0, g = Wλ + q ≥ 0, λ·g = 0.
//! Uzawa's iteration is the projected gradient ascent on the multipliers of
//! the Lagrangian (descent on J):
//!
//! ```text
//!   λ ← max(0, λ − ρ (W λ + q)),
//! ```
//!
//! i.e. a point that penetrates (g_p < 0) gains force, a point that opens
//! (g_p > 0) loses it, down to zero. It converges for 0 < ρ < 2/λ_max(W)
//! (J decreases at every step), linearly with a rate 1 − ρ λ_min(W) on the
//! contact zone: robust and cheap per iteration (one product with W), but
//! slow when W is ill-conditioned (fine meshes).
//!
//! Step: ρ = 1.9/‖W‖₂ with ‖W‖₂ = λ_max(W) estimated by power iteration,
//! unless `opts.stiffness = Some(s)` gives ρ = s / mean diag(W) (a multiple of
//! the contact stiffness 1/W_pp; ρ ≥ 2/λ_max diverges). Safeguard: if J
//! increases, which proves ρ ≥ 2/λ_max(W), ρ is halved and the step is
//! repeated from the last iterate.

use faer::Mat;

use crate::lcp::{
    dual_start, energy_of, gaps, mean_diag, power_iteration, residual_from_gaps, DualStart,
    LcpOptions,
};
use crate::solution::{ContactSolution, DualDetail, UzawaStep};
use crate::ContactError;

/// Solves LCP(W, q) by Uzawa's iteration λ ← max(0, λ − ρ(Wλ + q)) from
/// λ = 0 (see the module documentation).
///
/// `report.iterations` counts the Uzawa steps, `report.operator_applications`
/// every product with W (power iteration included), `report.residual_history`
/// the natural residual ([`crate::lcp_residual`]) after each step.
pub fn uzawa(w: &Mat<f64>, q: &[f64], opts: &LcpOptions) -> Result<ContactSolution, ContactError> {
    let m = q.len();
    let mut run = match dual_start(w, q, opts, "uzawa")? {
        DualStart::Done(solution) => return Ok(*solution),
        DualStart::Iterate(run) => run,
    };
    let mut lambda = vec![0.0; m];
    let mut g = q.to_vec();
    let d = mean_diag(w);
    let (mut rho, rho_origin) = match opts.stiffness {
        Some(s) if s.is_finite() && s > 0.0 && d > 0.0 => (s / d, UzawaStep::Given { factor: s }),
        Some(s) if !(s.is_finite() && s > 0.0) => {
            return Err(ContactError::Solve(format!(
                "Uzawa: the step factor (stiffness option) must be finite and positive, got {s}"
            )))
        }
        _ => {
            let (lmax, products) = power_iteration(w, 200, 1e-8);
            run.report.operator_applications += products;
            if lmax > 0.0 {
                (1.9 / lmax, UzawaStep::PowerIteration { norm: lmax })
            } else {
                (1.0, UzawaStep::ZeroOperator)
            }
        }
    };
    let mut energy = 0.0; // J(0)
    let mut halvings = 0usize;
    let mut next = vec![0.0; m];
    while run.next(opts) {
        for p in 0..m {
            next[p] = (lambda[p] - rho * g[p]).max(0.0);
        }
        let g_next = gaps(w, q, &next);
        run.report.operator_applications += 1;
        if next.iter().chain(&g_next).any(|v| !v.is_finite()) {
            return Err(ContactError::Solve(format!(
                "Uzawa: non-finite iterate at step {} (ρ = {rho:.3e})",
                run.report.iterations
            )));
        }
        let e_next = energy_of(&next, &g_next, q);
        if e_next - energy > 1e-12 * (energy.abs() + e_next.abs()) && halvings < 60 {
            // J increased: ρ ≥ 2/λ_max(W). Halve and redo the step.
            rho *= 0.5;
            halvings += 1;
            run.report
                .residual_history
                .push(residual_from_gaps(&lambda, &g, opts));
            continue;
        }
        std::mem::swap(&mut lambda, &mut next);
        g = g_next;
        energy = e_next;
        if run.converged_at(residual_from_gaps(&lambda, &g, opts), opts) {
            break;
        }
    }
    let detail = DualDetail::Uzawa {
        step: rho_origin,
        halvings,
    };
    Ok(run.finish((w, q), lambda, detail, opts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::gaps;
    use crate::lcp_residual;
    use crate::test_problems::*;

    fn opts() -> LcpOptions {
        lcp_options(1e-13, 100_000)
    }

    #[test]
    fn uzawa_agrees_with_the_status_method() {
        for c in cases() {
            let sol = uzawa(&c.w, &c.q, &opts()).unwrap();
            assert_solves_case(&c, &sol, &c.name);
            println!(
                "uzawa {}: {} iterations, {} products",
                c.name, sol.report.iterations, sol.report.operator_applications
            );
        }
    }

    #[test]
    fn uzawa_does_not_depend_on_the_units() {
        crate::lcp::projected_gradient::test_support::scale_invariant(uzawa, 1);
    }

    #[test]
    fn the_residual_without_a_product_is_lcp_residual() {
        let c = &cases()[1];
        let o = opts();
        let g = gaps(&c.w, &c.q, &c.exact);
        let lam: Vec<f64> = c.exact.iter().map(|v| v * 1.1).collect();
        let g2 = gaps(&c.w, &c.q, &lam);
        assert_eq!(
            residual_from_gaps(&c.exact, &g, &o),
            lcp_residual(&c.w, &c.q, &c.exact, &o)
        );
        assert_eq!(
            residual_from_gaps(&lam, &g2, &o),
            lcp_residual(&c.w, &c.q, &lam, &o)
        );
    }

    #[test]
    fn uzawa_on_redundant_constraints_gives_the_gaps_and_the_total_force() {
        let (w, q, l0, g0) = redundant();
        let sol = uzawa(&w, &q, &opts()).unwrap();
        assert_solves_redundant(&w, &q, &l0, &g0, &sol);
    }

    #[test]
    fn uzawa_reports_the_iteration_limit_and_rejects_non_finite_input() {
        let c = &cases()[2];
        let o = LcpOptions {
            max_iterations: 5,
            ..opts()
        };
        let sol = uzawa(&c.w, &c.q, &o).unwrap();
        assert!(!sol.report.converged);
        assert!(sol.report.stop.to_string().contains("iteration limit 5"));
        assert_eq!(sol.report.iterations, 5);
        assert!(sol.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
        let mut q = c.q.clone();
        q[3] = f64::NAN;
        assert!(matches!(uzawa(&c.w, &q, &o), Err(ContactError::Solve(_))));
        let mut w = c.w.clone();
        w[(1, 2)] = f64::INFINITY;
        assert!(matches!(uzawa(&w, &c.q, &o), Err(ContactError::Solve(_))));
        let e = uzawa(&Mat::zeros(0, 0), &[], &o).unwrap();
        assert!(e.report.converged && e.forces.is_empty());
    }

    #[test]
    fn a_too_large_step_is_halved_instead_of_diverging() {
        let c = &cases()[1];
        let o = LcpOptions {
            stiffness: Some(50.0),
            ..opts()
        };
        let sol = uzawa(&c.w, &c.q, &o).unwrap();
        assert!(sol.report.converged, "{}", sol.report.stop);
        assert!(sol.report.stop.to_string().contains("halved"));
        assert!(rel_err(&sol.forces, &c.exact) <= 1e-8);
    }

    #[test]
    fn power_iteration_finds_the_largest_eigenvalue() {
        let w = Mat::<f64>::from_fn(3, 3, |i, j| if i == j { [1.0, 5.0, 2.0][i] } else { 0.0 });
        let (l, _) = power_iteration(&w, 200, 1e-8);
        assert!((l - 5.0).abs() <= 1e-6 * 5.0);
    }
}
