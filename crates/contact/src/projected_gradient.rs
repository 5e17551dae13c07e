//! Projection methods on the forces (seed §3.2, DESIGN.md §4): the projected
//! gradient and the projected conjugate gradient for the frictionless
//! LCP(W, q),
//!
//! ```text
//! λ ≥ 0,   w = W λ + q ≥ 0,   λ·w = 0,
//! ```
//!
//! i.e. the bound-constrained quadratic programme
//!
//! ```text
//! min f(λ) = ½ λᵀ W λ + qᵀ λ   subject to   λ ≥ 0,
//! ```
//!
//! whose gradient is the gap, ∇f(λ) = W λ + q = w. The seed (§3.2) projects
//! the displacements onto H = {B u ≥ j}, which needs B diagonalised; on the
//! forces the bounds are simple (λ_p ≥ 0) and the projection is the clamp
//! P(λ)_p = max(λ_p, 0).
//!
//! Both methods start from λ = 0, keep λ ≥ 0 exactly, maintain the gradient
//! g = W λ + q, and stop when the natural residual of [`lcp_residual`] is at
//! most `opts.tolerance` (checked at the end with the true gaps W λ + q, so
//! round-off in the recursively updated gradient cannot fake convergence).
//!
//! The helpers at the end of this file (input checks, products with W, the
//! residual from a known gradient) are shared with [`crate::lemke`] and
//! [`crate::mprgp`].

use faer::Mat;

use crate::lcp::{
    check_input, dot, empty_solution, energy_of, gaps_into, lcp_residual, matvec,
    residual_from_gaps, LcpOptions, LcpSolution, SolverReport,
};
use crate::ContactError;

/// Armijo constant of the sufficient-decrease test on the projection arc.
const ARMIJO: f64 = 1e-4;

/// Projected gradient (seed §3.2) on the forces.
///
/// Iteration k, with g = W λᵏ + q (the gaps) and the free part of the
/// residual r = −g restricted to the points that may move (r_p = 0 where
/// λ_p = 0 and g_p ≥ 0, the points held at the bound):
///
/// 1. exact line-search step of the seed, μᵏ = rᵀr / rᵀW r;
/// 2. λᵏ⁺¹ = P(λᵏ + μᵏ r), P the clamp onto λ ≥ 0.
///
/// When the clamp cuts the step and the energy f does not decrease enough
/// (Armijo test f(λᵏ⁺¹) ≤ f(λᵏ) + 10⁻⁴ gᵀ(λᵏ⁺¹ − λᵏ) along the projection
/// arc) μ is halved: this safeguard keeps the method convergent when the
/// exact step is longer than 2/‖W‖.
///
/// `report.iterations` counts steps, `operator_applications` the products
/// W·v (one per step, two when the clamp is active, one per backtrack).
pub fn projected_gradient(
    w: &Mat<f64>,
    q: &[f64],
    opts: &LcpOptions,
) -> Result<LcpSolution, ContactError> {
    const METHOD: &str = "projected_gradient";
    check_input(w, q, METHOD)?;
    let m = q.len();
    if m == 0 {
        return Ok(empty_solution(METHOD));
    }
    let wscale = w.norm_max();
    let mut report = SolverReport {
        method: METHOD.into(),
        ..Default::default()
    };
    let mut lambda = vec![0.0; m];
    let mut g = q.to_vec();
    let mut energy = 0.0;
    let mut wr = vec![0.0; m];
    let mut trial = vec![0.0; m];
    let mut g_trial = vec![0.0; m];
    loop {
        let res = residual_from_gaps(&lambda, &g, opts);
        if res <= opts.tolerance {
            if verify(w, q, &mut lambda, &mut g, opts, &mut report) {
                report.converged = true;
                report.stopping_reason = format!(
                    "natural residual {:.3e} ≤ tolerance {:.3e} after {} iterations",
                    report.residual_history.last().copied().unwrap_or(res),
                    opts.tolerance,
                    report.iterations
                );
                break;
            }
            energy = energy_of(&lambda, &g, q);
            continue;
        }
        if report.iterations >= opts.max_iterations {
            report.stopping_reason = iteration_limit(opts.max_iterations, res, opts.tolerance);
            break;
        }
        report.iterations += 1;
        // Free part of the residual.
        let r: Vec<f64> = (0..m)
            .map(|p| {
                if lambda[p] <= 0.0 && g[p] >= 0.0 {
                    0.0
                } else {
                    -g[p]
                }
            })
            .collect();
        let rr = dot(&r, &r);
        if rr == 0.0 {
            report.stopping_reason = stagnated(report.iterations, res, opts.tolerance);
            break;
        }
        matvec(w, &r, &mut wr);
        report.operator_applications += 1;
        let curv = dot(&r, &wr);
        // Longest step before a force reaches zero.
        let feasible = max_feasible_step(&lambda, &r);
        let mut mu = if curv > 1e-14 * wscale * rr {
            rr / curv
        } else {
            f64::INFINITY
        };
        if !mu.is_finite() {
            if !feasible.is_finite() {
                return Err(unbounded(METHOD));
            }
            mu = feasible;
        }
        if mu <= feasible {
            // No clamp: the exact step of the seed, gradient updated exactly.
            for p in 0..m {
                lambda[p] = (lambda[p] + mu * r[p]).max(0.0);
                g[p] += mu * wr[p];
            }
            energy = energy_of(&lambda, &g, q);
        } else {
            // Clamped step with Armijo backtracking on the projection arc.
            let mut accepted = false;
            for _ in 0..60 {
                for p in 0..m {
                    trial[p] = (lambda[p] + mu * r[p]).max(0.0);
                }
                gaps_into(w, q, &trial, &mut g_trial);
                report.operator_applications += 1;
                let e_trial = energy_of(&trial, &g_trial, q);
                let decrease: f64 = (0..m).map(|p| g[p] * (trial[p] - lambda[p])).sum();
                if e_trial <= energy + ARMIJO * decrease || mu <= feasible {
                    accepted = true;
                    break;
                }
                mu = (0.5 * mu).max(feasible);
            }
            if !accepted {
                report.stopping_reason = format!(
                    "line search failed at iteration {} (natural residual {:.3e})",
                    report.iterations, res
                );
                break;
            }
            std::mem::swap(&mut lambda, &mut trial);
            std::mem::swap(&mut g, &mut g_trial);
            energy = energy_of(&lambda, &g, q);
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

/// Projected conjugate gradient (seed §3.2 with CG in place of the gradient;
/// Polyak's method with projection, in the spirit of Moré & Toraldo).
///
/// The free set F = {p : λ_p > 0 or g_p < 0} (points that may move; its
/// complement is held at λ_p = 0 with a non-negative gap). With the free
/// gradient φ = g restricted to F:
///
/// - direction: p = −φ after a restart, else the conjugate direction
///   p = −φ + β p_old, β = φᵀφ / φ_oldᵀφ_old (Fletcher–Reeves);
/// - step: the exact minimiser α = −gᵀp / pᵀW p along p;
/// - if λ + α p ≥ 0 the CG step is taken and the gradient updated,
///   g ← g + α W p; otherwise the clamped point P(λ + α p) is taken if it
///   passes the Armijo test, else the step stops at the first bound it
///   meets (feasible step), and the CG recursion restarts;
/// - the recursion also restarts whenever F changes.
///
/// Counts as [`projected_gradient`].
pub fn projected_conjugate_gradient(
    w: &Mat<f64>,
    q: &[f64],
    opts: &LcpOptions,
) -> Result<LcpSolution, ContactError> {
    const METHOD: &str = "projected_conjugate_gradient";
    check_input(w, q, METHOD)?;
    let m = q.len();
    if m == 0 {
        return Ok(empty_solution(METHOD));
    }
    let wscale = w.norm_max();
    let mut report = SolverReport {
        method: METHOD.into(),
        ..Default::default()
    };
    let mut lambda = vec![0.0; m];
    let mut g = q.to_vec();
    let mut energy = 0.0;
    let mut dir = vec![0.0; m];
    let mut wd = vec![0.0; m];
    let mut trial = vec![0.0; m];
    let mut g_trial = vec![0.0; m];
    let mut free_old: Vec<bool> = Vec::new();
    let mut phi_norm_old = 0.0;
    let mut restart = true;
    loop {
        let res = residual_from_gaps(&lambda, &g, opts);
        if res <= opts.tolerance {
            if verify(w, q, &mut lambda, &mut g, opts, &mut report) {
                report.converged = true;
                report.stopping_reason = format!(
                    "natural residual {:.3e} ≤ tolerance {:.3e} after {} iterations",
                    report.residual_history.last().copied().unwrap_or(res),
                    opts.tolerance,
                    report.iterations
                );
                break;
            }
            energy = energy_of(&lambda, &g, q);
            restart = true;
            continue;
        }
        if report.iterations >= opts.max_iterations {
            report.stopping_reason = iteration_limit(opts.max_iterations, res, opts.tolerance);
            break;
        }
        report.iterations += 1;
        let free: Vec<bool> = (0..m).map(|p| lambda[p] > 0.0 || g[p] < 0.0).collect();
        if free != free_old {
            restart = true;
        }
        let phi_norm: f64 = (0..m).filter(|&p| free[p]).map(|p| g[p] * g[p]).sum();
        let beta = if restart || phi_norm_old <= 0.0 {
            0.0
        } else {
            phi_norm / phi_norm_old
        };
        for p in 0..m {
            dir[p] = if free[p] { -g[p] + beta * dir[p] } else { 0.0 };
        }
        free_old = free;
        phi_norm_old = phi_norm;
        restart = false;
        let slope = dot(&g, &dir);
        if slope >= 0.0 {
            // Not a descent direction (round-off): restart along −φ.
            for p in 0..m {
                dir[p] = if free_old[p] { -g[p] } else { 0.0 };
            }
        }
        let slope = dot(&g, &dir);
        let dd = dot(&dir, &dir);
        if dd == 0.0 {
            report.stopping_reason = stagnated(report.iterations, res, opts.tolerance);
            break;
        }
        matvec(w, &dir, &mut wd);
        report.operator_applications += 1;
        let curv = dot(&dir, &wd);
        let feasible = max_feasible_step(&lambda, &dir);
        let alpha = if curv > 1e-14 * wscale * dd {
            -slope / curv
        } else {
            f64::INFINITY
        };
        if !alpha.is_finite() && !feasible.is_finite() {
            return Err(unbounded(METHOD));
        }
        if alpha <= feasible {
            for p in 0..m {
                lambda[p] = (lambda[p] + alpha * dir[p]).max(0.0);
                g[p] += alpha * wd[p];
            }
            energy = energy_of(&lambda, &g, q);
        } else {
            // The CG step leaves λ ≥ 0: try the clamped point, else stop at the bound.
            let mut accepted = false;
            if alpha.is_finite() {
                for p in 0..m {
                    trial[p] = (lambda[p] + alpha * dir[p]).max(0.0);
                }
                gaps_into(w, q, &trial, &mut g_trial);
                report.operator_applications += 1;
                let e_trial = energy_of(&trial, &g_trial, q);
                let decrease: f64 = (0..m).map(|p| g[p] * (trial[p] - lambda[p])).sum();
                if e_trial <= energy + ARMIJO * decrease {
                    std::mem::swap(&mut lambda, &mut trial);
                    std::mem::swap(&mut g, &mut g_trial);
                    accepted = true;
                }
            }
            if !accepted {
                for p in 0..m {
                    lambda[p] = (lambda[p] + feasible * dir[p]).max(0.0);
                    g[p] += feasible * wd[p];
                }
                // The blocking point lands exactly on its bound.
                if let Some(b) = blocking_index(&lambda, &dir) {
                    lambda[b] = 0.0;
                }
            }
            energy = energy_of(&lambda, &g, q);
            restart = true;
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

// ---------------------------------------------------------------------------
// Helpers shared by the LCP methods (lemke, projected_gradient, mprgp).
// ---------------------------------------------------------------------------

/// Largest α with λ + α d ≥ 0 (∞ when no component decreases).
pub(crate) fn max_feasible_step(lambda: &[f64], d: &[f64]) -> f64 {
    lambda
        .iter()
        .zip(d)
        .filter(|(_, &dp)| dp < 0.0)
        .map(|(&lp, &dp)| (lp / -dp).max(0.0))
        .fold(f64::INFINITY, f64::min)
}

/// The point that stops the step λ + α d at α = `step` (smallest index on ties).
fn blocking_index(lambda_after: &[f64], d: &[f64]) -> Option<usize> {
    (0..d.len())
        .filter(|&p| d[p] < 0.0)
        .min_by(|&a, &b| lambda_after[a].total_cmp(&lambda_after[b]).then(a.cmp(&b)))
}

/// max(λ, 0) entry by entry (removes −0.0 and round-off below zero).
pub(crate) fn clamp(mut lambda: Vec<f64>) -> Vec<f64> {
    for v in &mut lambda {
        *v = if *v > 0.0 { *v } else { 0.0 };
    }
    lambda
}

/// Recomputes the gaps exactly (one product) and checks the residual with
/// [`lcp_residual`]; on failure the recursively updated gradient had
/// drifted and iterations continue from the exact one.
pub(crate) fn verify(
    w: &Mat<f64>,
    q: &[f64],
    lambda: &mut [f64],
    g: &mut [f64],
    opts: &LcpOptions,
    report: &mut SolverReport,
) -> bool {
    for v in lambda.iter_mut() {
        *v = v.max(0.0);
    }
    gaps_into(w, q, lambda, g);
    report.operator_applications += 1;
    let res = lcp_residual(w, q, lambda, opts);
    if let Some(last) = report.residual_history.last_mut() {
        *last = res;
    } else {
        report.residual_history.push(res);
    }
    res <= opts.tolerance
}

pub(crate) fn iteration_limit(max: usize, res: f64, tol: f64) -> String {
    format!(
        "iteration limit {max} reached with natural residual {res:.3e} above tolerance {tol:.3e} (not converged)"
    )
}

pub(crate) fn stagnated(it: usize, res: f64, tol: f64) -> String {
    format!(
        "stagnation at iteration {it}: no descent direction left at natural residual {res:.3e} above tolerance {tol:.3e} (round-off floor; not converged)"
    )
}

pub(crate) fn unbounded(method: &str) -> ContactError {
    ContactError::Singular(format!(
        "{method}: W is singular along a feasible descent direction, so ½λᵀWλ + qᵀλ is unbounded below on λ ≥ 0 and the LCP has no solution (a body free to move away from its contacts?)"
    ))
}

#[cfg(test)]
pub(crate) mod test_support {
    //! Problems with known answers, shared by the tests of the LCP methods.

    use faer::Mat;

    use crate::lcp::{gaps, lcp_residual, LcpOptions, LcpSolution};
    use crate::status::{status_method, StatusOptions, StatusVariant};
    use crate::{ContactError, DelassusProblem};

    /// Deterministic xorshift64* generator.
    pub struct Rng(pub u64);

    impl Rng {
        pub fn new(seed: u64) -> Self {
            Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
        }
        pub fn next_u64(&mut self) -> u64 {
            let mut x = self.0;
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            self.0 = x;
            x.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }
        /// Uniform in [−1, 1).
        pub fn uniform(&mut self) -> f64 {
            (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// W = AᵀA / (2m) + ε I with A (2m × m) uniform in [−1, 1): SPD,
    /// entries O(1), condition number O(10).
    pub fn random_spd(m: usize, rng: &mut Rng) -> Mat<f64> {
        let a = Mat::<f64>::from_fn(2 * m, m, |_, _| rng.uniform());
        let mut w = a.transpose() * &a;
        for j in 0..m {
            for i in 0..m {
                w[(i, j)] /= 2.0 * m as f64;
            }
            w[(j, j)] += 0.05;
        }
        symmetrize(w)
    }

    pub fn symmetrize(mut w: Mat<f64>) -> Mat<f64> {
        let m = w.nrows();
        for j in 0..m {
            for i in j + 1..m {
                let v = 0.5 * (w[(i, j)] + w[(j, i)]);
                w[(i, j)] = v;
                w[(j, i)] = v;
            }
        }
        w
    }

    pub fn random_vec(m: usize, rng: &mut Rng) -> Vec<f64> {
        (0..m).map(|_| rng.uniform()).collect()
    }

    /// q = w* − W λ* for a complementary pair (λ*, w*): the solution is λ*.
    pub fn q_for(w: &Mat<f64>, lambda: &[f64], gap: &[f64]) -> Vec<f64> {
        let wl = gaps(w, &vec![0.0; lambda.len()], lambda);
        gap.iter().zip(&wl).map(|(g, x)| g - x).collect()
    }

    pub fn tight() -> LcpOptions {
        LcpOptions {
            tolerance: 1e-12,
            max_iterations: 100_000,
            ..Default::default()
        }
    }

    /// The status method (seed §3.3) on (W, q): the reference answer.
    pub fn reference(w: &Mat<f64>, q: &[f64]) -> Vec<f64> {
        let m = q.len();
        let mut p = DelassusProblem::new(
            &Mat::<f64>::identity(m, m),
            &(0..m).map(|i| vec![(i, 1.0)]).collect::<Vec<_>>(),
            &vec![0.0; m],
            &vec![0.0; m],
            &Mat::zeros(m, 0),
        )
        .unwrap();
        p.w = w.clone();
        p.q = q.to_vec();
        let out = status_method(
            &mut p,
            &StatusOptions {
                variant: StatusVariant::All,
                max_iterations: 10 * m + 10,
                tolerance: 1e-14,
                force_scale: 1.0,
                gap_scale: 1.0,
                initial_active: None,
            },
        )
        .unwrap();
        assert!(out.converged, "status method: {}", out.stopping_reason);
        out.lambda
    }

    pub fn inf_norm(v: &[f64]) -> f64 {
        v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
    }

    /// ‖a − b‖∞ ≤ rel · max(‖b‖∞, 1).
    pub fn assert_close(a: &[f64], b: &[f64], rel: f64, what: &str) {
        assert_eq!(a.len(), b.len());
        let d = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f64, f64::max);
        let scale = inf_norm(b).max(1.0);
        assert!(
            d <= rel * scale,
            "{what}: ‖Δ‖∞ = {d:.3e} > {rel:.1e} × {scale:.3e}"
        );
    }

    /// Checks a returned solution: finite, λ ≥ 0 exactly, residual met, converged.
    pub fn check_solution(w: &Mat<f64>, q: &[f64], sol: &LcpSolution, opts: &LcpOptions) {
        assert!(
            sol.report.converged,
            "{}: {}",
            sol.report.method, sol.report.stopping_reason
        );
        assert_eq!(sol.lambda.len(), q.len());
        assert!(sol.lambda.iter().all(|v| v.is_finite() && *v >= 0.0));
        let r = lcp_residual(w, q, &sol.lambda, opts);
        assert!(
            r <= opts.tolerance,
            "{}: residual {r:.3e}",
            sol.report.method
        );
        assert_eq!(
            sol.report.residual_history.last(),
            Some(&r),
            "{}",
            sol.report.method
        );
    }

    pub type Method = fn(&Mat<f64>, &[f64], &LcpOptions) -> Result<LcpSolution, ContactError>;

    /// Every case of the brief against the status method; returns
    /// (iterations, products with W) on the m = 60 random problem.
    pub fn agrees_with_status_method(method: Method) -> (usize, usize) {
        let opts = tight();
        let mut rng = Rng::new(7);
        let mut iters60 = (0, 0);
        // Random SPD W, q of mixed signs.
        for m in [5, 20, 60] {
            let w = random_spd(m, &mut rng);
            let q = random_vec(m, &mut rng);
            assert!(q.iter().any(|v| *v < 0.0) && q.iter().any(|v| *v > 0.0));
            let sol = method(&w, &q, &opts).unwrap();
            check_solution(&w, &q, &sol, &opts);
            let exact = reference(&w, &q);
            assert!(exact.iter().any(|v| *v > 0.0) && exact.contains(&0.0));
            assert_close(&sol.lambda, &exact, 1e-8, &format!("random m = {m}"));
            if m == 60 {
                iters60 = (sol.report.iterations, sol.report.operator_applications);
            }
        }
        let m = 20;
        let w = random_spd(m, &mut rng);
        // All contacts active: λ* > 0, w* = 0 (q ≪ 0).
        let lstar: Vec<f64> = (0..m).map(|_| 1.5 + rng.uniform()).collect();
        let q = q_for(&w, &lstar, &vec![0.0; m]);
        assert!(q.iter().all(|v| *v < 0.0));
        let sol = method(&w, &q, &opts).unwrap();
        check_solution(&w, &q, &sol, &opts);
        assert_close(&sol.lambda, &lstar, 1e-8, "all active");
        assert_close(
            &sol.lambda,
            &reference(&w, &q),
            1e-8,
            "all active vs status",
        );
        // None active: q > 0, λ = 0 exactly.
        let q: Vec<f64> = (0..m).map(|_| 1.5 + rng.uniform()).collect();
        let sol = method(&w, &q, &opts).unwrap();
        check_solution(&w, &q, &sol, &opts);
        assert!(
            sol.lambda.iter().all(|v| *v == 0.0),
            "none active: {:?}",
            sol.lambda
        );
        // Weakly active: points 3 and 11 have λ* = 0 and w* = 0.
        let mut lstar = vec![0.0; m];
        let mut wstar = vec![0.0; m];
        for p in 0..m {
            if p == 3 || p == 11 {
                continue;
            }
            if p % 2 == 0 {
                lstar[p] = 1.0 + 0.5 * rng.uniform();
            } else {
                wstar[p] = 0.5 + 0.25 * rng.uniform();
            }
        }
        let q = q_for(&w, &lstar, &wstar);
        let sol = method(&w, &q, &opts).unwrap();
        check_solution(&w, &q, &sol, &opts);
        assert_close(&sol.lambda, &lstar, 1e-8, "weakly active");
        assert_close(
            &sol.lambda,
            &reference(&w, &q),
            1e-8,
            "weakly active vs status",
        );
        let g = gaps(&w, &q, &sol.lambda);
        assert!(g[3].abs() <= 1e-9 && g[11].abs() <= 1e-9 && sol.lambda[3] <= 1e-9);
        iters60
    }

    /// Redundant constraints: two identical rows of B, so W = B S⁻¹ Bᵀ is
    /// singular. The gaps and λ_2 + λ_dup must match the problem without the
    /// duplicate (solved by the status method); each force alone is not
    /// unique. `may_fail`: an `Err` is accepted (never a NaN).
    pub fn redundant_constraints(method: Method, may_fail: bool) {
        let mut rng = Rng::new(99);
        let n = 12;
        let a = Mat::<f64>::from_fn(n, n, |_, _| rng.uniform());
        let mut s = a.transpose() * &a;
        for i in 0..n {
            s[(i, i)] += 1.0;
        }
        let s = symmetrize(s);
        let mut rows: Vec<Vec<(usize, f64)>> = (0..7)
            .map(|p| vec![(p, 1.0), ((p + 5) % n, 0.5 * rng.uniform())])
            .collect();
        let mut gap0: Vec<f64> = (0..7).map(|_| 0.01 * rng.uniform()).collect();
        let f: Vec<f64> = (0..n)
            .map(|i| if i < 7 { -1.0 } else { 0.3 * rng.uniform() })
            .collect();
        let reduced = DelassusProblem::new(&s, &rows, &gap0, &f, &Mat::zeros(n, 0)).unwrap();
        let exact = reference(&reduced.w, &reduced.q);
        assert!(exact[2] > 0.0, "the duplicated contact must carry a force");
        rows.push(rows[2].clone());
        gap0.push(gap0[2]);
        let full = DelassusProblem::new(&s, &rows, &gap0, &f, &Mat::zeros(n, 0)).unwrap();
        let opts = tight();
        match method(&full.w, &full.q, &opts) {
            Ok(sol) => {
                eprintln!(
                    "{} on redundant constraints: {} iterations, λ_2 = {:.6}, λ_dup = {:.6}, sum {:.6} (reduced problem: {:.6})",
                    sol.report.method,
                    sol.report.iterations,
                    sol.lambda[2],
                    sol.lambda[7],
                    sol.lambda[2] + sol.lambda[7],
                    exact[2]
                );
                assert!(sol.lambda.iter().all(|v| v.is_finite() && *v >= 0.0));
                check_solution(&full.w, &full.q, &sol, &opts);
                let mut merged = sol.lambda[..7].to_vec();
                merged[2] += sol.lambda[7];
                assert_close(
                    &merged,
                    &exact,
                    1e-8,
                    "redundant: forces with the duplicate merged",
                );
                let g = gaps(&full.w, &full.q, &sol.lambda);
                let g_exact = gaps(&reduced.w, &reduced.q, &exact);
                assert_close(&g[..7], &g_exact, 1e-8, "redundant: gaps");
                assert!((g[7] - g[2]).abs() <= 1e-12);
            }
            Err(e) => {
                eprintln!("redundant constraints: error {e}");
                assert!(may_fail, "{e}");
                let msg = e.to_string();
                assert!(!msg.is_empty() && !msg.contains("NaN"), "{msg}");
            }
        }
    }

    /// Non-finite input, size mismatch, m = 0.
    pub fn edge_cases(method: Method) {
        let opts = LcpOptions::default();
        let sol = method(&Mat::zeros(0, 0), &[], &opts).unwrap();
        assert!(sol.report.converged && sol.lambda.is_empty());
        let mut w = Mat::<f64>::identity(3, 3);
        assert!(matches!(
            method(&w, &[1.0, f64::NAN, -1.0], &opts),
            Err(ContactError::Solve(_))
        ));
        w[(1, 2)] = f64::INFINITY;
        assert!(matches!(
            method(&w, &[1.0, 0.0, -1.0], &opts),
            Err(ContactError::Solve(_))
        ));
        assert!(matches!(
            method(&Mat::identity(2, 2), &[1.0, 0.0, -1.0], &opts),
            Err(ContactError::Solve(_))
        ));
    }

    /// A too small iteration budget gives Ok with converged = false.
    pub fn reports_iteration_limit(method: Method, budget: usize) {
        let mut rng = Rng::new(3);
        let w = random_spd(40, &mut rng);
        let q = random_vec(40, &mut rng);
        let opts = LcpOptions {
            tolerance: 1e-14,
            max_iterations: budget,
            ..Default::default()
        };
        let sol = method(&w, &q, &opts).unwrap();
        assert!(!sol.report.converged);
        assert!(
            sol.report.stopping_reason.contains("not converged"),
            "{}",
            sol.report.stopping_reason
        );
        assert!(sol.lambda.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;

    #[test]
    fn projected_gradient_agrees_with_the_status_method() {
        let (it, ops) = agrees_with_status_method(projected_gradient);
        eprintln!("projected_gradient: {it} iterations, {ops} products on the m = 60 random case");
        assert!(it > 0 && ops >= it);
    }

    #[test]
    fn projected_conjugate_gradient_agrees_with_the_status_method() {
        let (it, ops) = agrees_with_status_method(projected_conjugate_gradient);
        eprintln!(
            "projected_conjugate_gradient: {it} iterations, {ops} products on the m = 60 random case"
        );
        assert!(it > 0 && ops >= it);
    }

    #[test]
    fn projection_methods_handle_redundant_constraints() {
        redundant_constraints(projected_gradient, false);
        redundant_constraints(projected_conjugate_gradient, false);
    }

    #[test]
    fn projection_methods_edge_cases() {
        edge_cases(projected_gradient);
        edge_cases(projected_conjugate_gradient);
        reports_iteration_limit(projected_gradient, 3);
        reports_iteration_limit(projected_conjugate_gradient, 3);
    }

    #[test]
    fn projected_gradient_takes_the_exact_seed_step_without_bounds() {
        // q < 0 everywhere with W diagonal: one exact step μ = rᵀr / rᵀWr
        // per distinct eigenvalue; W = 2 I converges in one step to λ = −q/2.
        let w = Mat::<f64>::from_fn(3, 3, |i, j| if i == j { 2.0 } else { 0.0 });
        let q = [-1.0, -2.0, -4.0];
        let sol = projected_gradient(&w, &q, &tight()).unwrap();
        assert!(sol.report.converged);
        assert_eq!(sol.report.iterations, 1);
        assert_close(&sol.lambda, &[0.5, 1.0, 2.0], 1e-15, "one step");
    }
}
