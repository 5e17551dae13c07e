//! MPRGP, modified proportioning with reduced gradient projection
//! (Z. Dostál, *Optimal Quadratic Programming Algorithms*, Springer 2009,
//! ch. 8 — bound-constrained minimisation; Dostál & Schöberl, Comput. Optim.
//! Appl. 30, 2005), for the frictionless LCP(W, q) of DESIGN.md §3 written
//! as the bound-constrained quadratic programme on the forces (seed §3.2:
//! the projection methods, whose bounds are simple on the forces),
//!
//! ```text
//! min f(λ) = ½ λᵀ W λ + qᵀ λ   subject to   λ ≥ 0,     g = ∇f = W λ + q = w.
//! ```
//!
//! With the free set F = {p : λ_p > 0} and the active set A = {p : λ_p = 0}:
//!
//! - free gradient       φ_p = g_p on F, 0 on A;
//! - chopped gradient    β_p = min(g_p, 0) on A, 0 on F;
//! - reduced free gradient φ̃_p = min(λ_p / ᾱ, φ_p) on F, 0 on A;
//! - projected gradient  gᴾ = φ + β (zero exactly at the LCP solution).
//!
//! λ is *proportional* when ‖β‖² ≤ Γ² φ̃ᵀφ (Γ = 1). Each iteration is one of
//!
//! - **CG step** (proportional, the CG step α_cg = gᵀp / pᵀWp stays feasible,
//!   α_cg ≤ α_f = max{α : λ − α p ≥ 0}): λ ← λ − α_cg p, g ← g − α_cg W p,
//!   p ← φ − γ p with γ = φᵀW p / pᵀW p (CG on the free set);
//! - **expansion step** (proportional, α_cg > α_f): a feasible half step
//!   λ½ = λ − α_f p, then the fixed-step projection
//!   λ ← P(λ½ − ᾱ φ(λ½)) with ᾱ ∈ (0, 2/‖W‖] (here ᾱ = 1.9/‖W‖, ‖W‖ by
//!   power iterations), g ← W λ + q, p ← φ;
//! - **proportioning step** (not proportional): exact minimisation along the
//!   chopped gradient, λ ← λ − α β with α = gᵀβ / βᵀWβ, which releases the
//!   points of A with a negative gap, p ← φ.
//!
//! For W SPD MPRGP converges R-linearly, at a rate given by the spectrum of W
//! only (Dostál 2009, Thm 8.1), and identifies the active set in a finite
//! number of steps. Stopping as the other LCP methods: natural residual
//! [`crate::lcp::lcp_residual`] ≤ `opts.tolerance`, checked with the true gaps.

use faer::Mat;

use crate::lcp::{
    check_input, dot, empty_solution, gaps, gaps_into, matvec, residual_from_gaps,
    spectral_norm_estimate, LcpOptions, LcpSolution, SolverReport,
};
use crate::projected_gradient::{clamp, iteration_limit, stagnated, unbounded, verify};
use crate::ContactError;

/// Γ of the proportioning test ‖β‖² ≤ Γ² φ̃ᵀφ.
const GAMMA: f64 = 1.0;

/// ᾱ = STEP_FACTOR / ‖W‖, inside (0, 2/‖W‖].
const STEP_FACTOR: f64 = 1.9;

/// Dostál's MPRGP on LCP(W, q) (see the module documentation).
///
/// `report.iterations` counts CG, expansion and proportioning steps;
/// `operator_applications` the products W·v (power iterations for ‖W‖
/// included; one per CG or proportioning step, two per expansion step).
/// `stopping_reason` also gives the number of steps of each kind.
pub fn mprgp(w: &Mat<f64>, q: &[f64], opts: &LcpOptions) -> Result<LcpSolution, ContactError> {
    mprgp_from(w, q, &vec![0.0; q.len()], opts)
}

/// [`mprgp`] from a warm start λ0 (its negative entries are set to zero):
/// the inner solver of [`crate::smalbe`], whose successive problems differ
/// little.
pub fn mprgp_from(
    w: &Mat<f64>,
    q: &[f64],
    lambda0: &[f64],
    opts: &LcpOptions,
) -> Result<LcpSolution, ContactError> {
    const METHOD: &str = "mprgp";
    check_input(w, q, METHOD)?;
    let m = q.len();
    if m == 0 {
        return Ok(empty_solution(METHOD));
    }
    let mut report = SolverReport {
        method: METHOD.into(),
        ..Default::default()
    };
    let mut lambda: Vec<f64> = lambda0.iter().map(|&l| l.max(0.0)).collect();
    let mut g = gaps(w, q, &lambda);
    if lambda.iter().all(|&l| l == 0.0) && q.iter().all(|&v| v >= 0.0) {
        // λ = 0 solves the LCP: no need for ‖W‖.
        verify(w, q, &mut lambda, &mut g, opts, &mut report);
        report.converged = true;
        report.stopping_reason = "q ≥ 0: λ = 0 solves the LCP (no contact force)".into();
        return Ok(LcpSolution { lambda, report });
    }
    let wscale = w.norm_max();
    let (norm_w, power_products) = spectral_norm_estimate(w);
    report.operator_applications += power_products;
    if norm_w <= 0.0 {
        // W = 0 and some q_p < 0: no force closes that gap.
        return Err(unbounded(METHOD));
    }
    let abar = STEP_FACTOR / norm_w;
    let mut p = free_gradient(&lambda, &g);
    let mut wp = vec![0.0; m];
    let (mut n_cg, mut n_exp, mut n_prop) = (0usize, 0usize, 0usize);
    loop {
        let res = residual_from_gaps(&lambda, &g, opts);
        if res <= opts.tolerance {
            if verify(w, q, &mut lambda, &mut g, opts, &mut report) {
                report.converged = true;
                report.stopping_reason = format!(
                    "natural residual {:.3e} ≤ tolerance {:.3e} after {} iterations ({n_cg} CG, {n_exp} expansion, {n_prop} proportioning steps; ᾱ = 1.9/‖W‖, ‖W‖ ≈ {norm_w:.6e})",
                    report.residual_history.last().copied().unwrap_or(res),
                    opts.tolerance,
                    report.iterations
                );
                break;
            }
            // The recursive gradient had drifted: restart from the exact one.
            p = free_gradient(&lambda, &g);
            continue;
        }
        if report.iterations >= opts.max_iterations {
            report.stopping_reason = format!(
                "{} ({n_cg} CG, {n_exp} expansion, {n_prop} proportioning steps)",
                iteration_limit(opts.max_iterations, res, opts.tolerance)
            );
            break;
        }
        report.iterations += 1;
        let phi = free_gradient(&lambda, &g);
        let beta = chopped_gradient(&lambda, &g);
        let beta_sq = dot(&beta, &beta);
        // φ̃ᵀφ with φ̃_p = min(λ_p/ᾱ, φ_p) on the free set.
        let phi_tilde_phi: f64 = (0..m)
            .filter(|&i| lambda[i] > 0.0)
            .map(|i| (lambda[i] / abar).min(phi[i]) * phi[i])
            .sum();
        if beta_sq <= GAMMA * GAMMA * phi_tilde_phi {
            let pp = dot(&p, &p);
            if pp == 0.0 {
                // φ ≠ 0 is proportional but p lost it (cannot happen in exact
                // arithmetic): restart along φ.
                p = phi.clone();
                if dot(&p, &p) == 0.0 {
                    report.stopping_reason = stagnated(report.iterations, res, opts.tolerance);
                    break;
                }
            }
            matvec(w, &p, &mut wp);
            report.operator_applications += 1;
            let curv = dot(&p, &wp);
            let alpha_f = feasible_step(&lambda, &p);
            let alpha_cg = if curv > 1e-14 * wscale * dot(&p, &p) {
                dot(&g, &p) / curv
            } else {
                f64::INFINITY
            };
            if alpha_cg <= alpha_f {
                // CG step.
                n_cg += 1;
                for i in 0..m {
                    lambda[i] = (lambda[i] - alpha_cg * p[i]).max(0.0);
                    g[i] -= alpha_cg * wp[i];
                }
                let phi = free_gradient(&lambda, &g);
                let gamma = dot(&phi, &wp) / curv;
                for i in 0..m {
                    p[i] = phi[i] - gamma * p[i];
                }
            } else {
                // Expansion step: feasible half step, then fixed-step projection.
                n_exp += 1;
                if alpha_f.is_finite() {
                    for i in 0..m {
                        lambda[i] = (lambda[i] - alpha_f * p[i]).max(0.0);
                        g[i] -= alpha_f * wp[i];
                    }
                    // The blocking point lands exactly on its bound.
                    if let Some(b) = blocking(&lambda, &p) {
                        lambda[b] = 0.0;
                    }
                }
                let phi = free_gradient(&lambda, &g);
                for i in 0..m {
                    lambda[i] = (lambda[i] - abar * phi[i]).max(0.0);
                }
                gaps_into(w, q, &lambda, &mut g);
                report.operator_applications += 1;
                p = free_gradient(&lambda, &g);
            }
        } else {
            // Proportioning step along the chopped gradient (β ≤ 0: λ − αβ ≥ 0).
            n_prop += 1;
            matvec(w, &beta, &mut wp);
            report.operator_applications += 1;
            let curv = dot(&beta, &wp);
            if curv <= 1e-14 * wscale * beta_sq {
                return Err(unbounded(METHOD));
            }
            let alpha = dot(&g, &beta) / curv;
            for i in 0..m {
                lambda[i] = (lambda[i] - alpha * beta[i]).max(0.0);
                g[i] -= alpha * wp[i];
            }
            p = free_gradient(&lambda, &g);
        }
        report
            .residual_history
            .push(residual_from_gaps(&lambda, &g, opts));
    }
    Ok(LcpSolution {
        lambda: clamp(lambda),
        report,
    })
}

/// φ(λ): g on the free set {λ_p > 0}, 0 elsewhere.
fn free_gradient(lambda: &[f64], g: &[f64]) -> Vec<f64> {
    lambda
        .iter()
        .zip(g)
        .map(|(&l, &gi)| if l > 0.0 { gi } else { 0.0 })
        .collect()
}

/// β(λ): min(g, 0) on the active set {λ_p = 0}, 0 elsewhere.
fn chopped_gradient(lambda: &[f64], g: &[f64]) -> Vec<f64> {
    lambda
        .iter()
        .zip(g)
        .map(|(&l, &gi)| if l > 0.0 { 0.0 } else { gi.min(0.0) })
        .collect()
}

/// α_f = max{α : λ − α p ≥ 0} (∞ when no component of p is positive).
fn feasible_step(lambda: &[f64], p: &[f64]) -> f64 {
    lambda
        .iter()
        .zip(p)
        .filter(|(_, &pi)| pi > 0.0)
        .map(|(&l, &pi)| (l / pi).max(0.0))
        .fold(f64::INFINITY, f64::min)
}

/// After the half step λ − α_f p, the point that blocked it (smallest λ among
/// the decreasing ones, smallest index on ties).
fn blocking(lambda: &[f64], p: &[f64]) -> Option<usize> {
    (0..p.len())
        .filter(|&i| p[i] > 0.0)
        .min_by(|&a, &b| lambda[a].total_cmp(&lambda[b]).then(a.cmp(&b)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::lcp_residual;
    use crate::lemke::lemke;
    use crate::projected_gradient::projected_conjugate_gradient;
    use crate::projected_gradient::test_support::{
        agrees_with_status_method, edge_cases, inf_norm, random_spd, random_vec,
        redundant_constraints, reports_iteration_limit, tight, Rng,
    };
    use proptest::prelude::*;

    #[test]
    fn mprgp_agrees_with_the_status_method() {
        let (it, ops) = agrees_with_status_method(mprgp);
        eprintln!("mprgp: {it} iterations, {ops} products on the m = 60 random case");
        assert!(it > 0 && ops >= it);
    }

    #[test]
    fn mprgp_handles_redundant_constraints() {
        redundant_constraints(mprgp, false);
    }

    #[test]
    fn mprgp_edge_cases() {
        edge_cases(mprgp);
        reports_iteration_limit(mprgp, 3);
    }

    #[test]
    fn norm_estimate_is_close_to_the_largest_eigenvalue() {
        // Diagonal W: ‖W‖ = 5 exactly.
        let w = Mat::<f64>::from_fn(
            4,
            4,
            |i, j| if i == j { [1.0, 5.0, 2.0, 4.0][i] } else { 0.0 },
        );
        let (est, n) = spectral_norm_estimate(&w);
        assert!(n > 0 && (5.0 * 0.99..=5.0 * 1.02).contains(&est), "{est}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Random SPD W and q: projected CG, MPRGP and Lemke all solve the
        /// LCP and agree with each other.
        #[test]
        fn pcg_mprgp_and_lemke_agree(m in 1usize..30, seed in any::<u64>()) {
            let mut rng = Rng::new(seed);
            let w = random_spd(m, &mut rng);
            let q = random_vec(m, &mut rng);
            let opts = tight();
            let a = projected_conjugate_gradient(&w, &q, &opts).unwrap();
            let b = mprgp(&w, &q, &opts).unwrap();
            let c = lemke(&w, &q, &opts).unwrap();
            for s in [&a, &b, &c] {
                prop_assert!(s.report.converged, "{}: {}", s.report.method, s.report.stopping_reason);
                prop_assert!(s.lambda.iter().all(|v| v.is_finite() && *v >= 0.0));
                let r = lcp_residual(&w, &q, &s.lambda, &opts);
                prop_assert!(r <= 1e-8, "{}: residual {r:e}", s.report.method);
            }
            let scale = inf_norm(&c.lambda).max(1.0);
            for s in [&a, &b] {
                let d = s.lambda.iter().zip(&c.lambda).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
                prop_assert!(d <= 1e-7 * scale, "{} vs lemke: {d:e}", s.report.method);
            }
        }
    }
}
