//! The regularised contact law (course notes §3.6) and the status method with the
//! active constraints imposed by penalty (course notes §3.3).
//!
//! # Regularised law (course notes §3.6)
//!
//! A finite normal stiffness k_p (force per length) replaces the rigid
//! non-penetration: a penetration −g_p is allowed ("écrasement des
//! aspérités") and the force follows it one to one,
//!
//! ```text
//!   λ_p = k_p max(0, −g_p),      g = W λ + q.
//! ```
//!
//! On the set A of penetrating points λ_A = −K_A g_A = −K_A (W_AA λ_A + q_A)
//! and λ = 0 elsewhere, i.e. (I + K_A W_AA) λ_A = −K_A q_A, or, dividing by
//! K_A to get a symmetric positive definite system,
//!
//! ```text
//!   (W_AA + K_A⁻¹) λ_A = −q_A.
//! ```
//!
//! With h = (W + K⁻¹) λ + q = g + K⁻¹λ, the law is exactly LCP(W + K⁻¹, q):
//! λ_p > 0 ⇒ h_p = 0 ⇒ g_p = −λ_p/k_p < 0; λ_p = 0 ⇒ g_p = h_p ≥ 0. The
//! matrix W + K⁻¹ is positive definite even when W is singular (redundant
//! constraints), so the answer is unique. It is solved exactly by the
//! active-set (semi-smooth Newton) iteration on this piecewise-linear
//! monotone problem: solve on A, then A ← {p : g_p < 0} (a point of A leaves
//! when its force turns to a tension, a point outside enters when it
//! penetrates); converged when A repeats, which gives the exact solution of
//! the regularised law (finite termination). If an active set repeats an
//! earlier one (cycling of the all-at-once update), the iteration switches
//! to Murty's least-index rule (one status change per iteration, the
//! smallest violating index), which terminates for positive definite
//! matrices.
//!
//! The regularised solution is not the Signorini solution: with
//! κ = λ_max(W_AA⁻¹)/k, the force error is O(κ) and the penetration
//! max(−g) = max(λ_p/k_p) is O(1/k). [`penetration_warning`] flags a
//! penetration that is a sizeable fraction of the element size.
//!
//! # Status method with penalty (course notes §3.3)
//!
//! Step 1 of the status method imposes g_p = 0 on the active points "par
//! multiplicateur de Lagrange ou par pénalité". [`status_with_penalty`] is the
//! penalty variant: the penalty term ½ k Σ_A g_p² added to the energy makes
//! λ_A = −K_A g_A, the same system (W_AA + K_A⁻¹) λ_A = −q_A, with the
//! statuses of [`crate::status_method`] (release an active point whose force
//! is a tension, impose an inactive point that penetrates). It converges to
//! the solution of LCP(W + K⁻¹, q), which tends to the exact Signorini
//! solution as k → ∞ with an error O(1/k); k must be very large relative to
//! the contact stiffness 1/W_pp, but not so large that round-off in
//! W_AA + K_A⁻¹ (condition ~ k · max W_pp) dominates.

use faer::Mat;

use crate::active_set::signorini::{status_method, ActiveSetSolve, StatusOptions, StatusVariant};
use crate::lcp::regularised::{regularised_newton, solve_block};
use crate::lcp::{check_input, gaps, mean_diag, residual_from_gaps, LcpOptions};
use crate::solution::{ContactSolution, SolverReport, StopReason};
use crate::ContactError;

/// A uniform stiffness k_p = factor / mean diag(W): `factor` times the mean
/// contact stiffness of the points.
pub fn uniform_stiffness(w: &Mat<f64>, factor: f64) -> Vec<f64> {
    let d = mean_diag(w);
    vec![factor / d; w.nrows()]
}

/// Solves the regularised contact law λ = K max(0, −(Wλ + q)) of course notes §3.6
/// exactly, by the active-set Newton iteration on (W_AA + K_A⁻¹) λ_A = −q_A
/// starting from A = {p : q_p < 0} (see the module documentation).
///
/// `k`: stiffness of each point (force per length), finite and positive.
/// `report.converged`: the active set repeated (the regularised law holds to
/// `opts.tolerance`); `report.residual_history`: the natural residual of the
/// unregularised LCP(W, q) after each iteration, which does not go to zero:
/// it shows the penetration the penalty allows (O(1/k)).
/// `report.operator_applications`: block solves + products with W.
pub fn penalty(
    w: &Mat<f64>,
    q: &[f64],
    k: &[f64],
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    let c = compliance(w, q, k)?;
    let m = q.len();
    if m == 0 {
        return Ok(ContactSolution::empty("penalty"));
    }
    let mut report = SolverReport {
        method: "penalty".into(),
        ..Default::default()
    };
    let active: Vec<bool> = q.iter().map(|&v| v < 0.0).collect();
    let mut history = Vec::new();
    let out = regularised_newton(w, q, &c, active, opts, opts.max_iterations, &mut |l, g| {
        history.push(residual_from_gaps(l, g, opts))
    })?;
    report.iterations = out.iterations;
    report.operator_applications = out.operator_applications;
    report.residual_history = history;
    report.converged = out.converged;
    report.stop = if out.converged {
        StopReason::RegularisedSolved {
            active: out.active.iter().filter(|&&a| a).count(),
            iterations: out.iterations,
            cycle_at: out.cycle_at,
            penetration: max_penetration(&out.g),
        }
    } else {
        with_last_residual(out.stop, &report.residual_history)
    };
    Ok(ContactSolution::from_forces(w, q, out.lambda, report))
}

/// The status method of course notes §3.3 with the active constraints imposed by a
/// penalty of stiffness `k` (per point) instead of Lagrange multipliers:
/// on the active set, (W_AA + K_A⁻¹) λ_A = −q_A; an active point whose
/// force is a tension is released, an inactive point that penetrates is
/// imposed; loop until the statuses repeat ([`crate::status_method`], with
/// its `variant`, cycle detection and fallback, starting with every point
/// active).
///
/// The answer solves LCP(W + K⁻¹, q): it tends to the exact solution as
/// k → ∞, with a force error and a penetration O(1/k). Choose k very large
/// relative to the contact stiffness 1/W_pp (e.g. [`uniform_stiffness`]
/// with a factor 1e6–1e8). `report.residual_history` is the natural residual
/// of the exact LCP(W, q) after each status iteration, so it shows the
/// penalty's error; `report.operator_applications` counts block solves and
/// products with W.
pub fn status_with_penalty(
    w: &Mat<f64>,
    q: &[f64],
    k: &[f64],
    variant: StatusVariant,
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    let c = compliance(w, q, k)?;
    let m = q.len();
    let mut report = SolverReport {
        method: match variant {
            StatusVariant::All => "status_penalty_all".into(),
            StatusVariant::Single => "status_penalty_single".into(),
        },
        ..Default::default()
    };
    if m == 0 {
        return Ok(ContactSolution::empty(&report.method));
    }
    let mut solver = PenalisedActiveSet {
        w,
        q,
        c: &c,
        opts,
        solves: 0,
        products: 0,
        history: Vec::new(),
    };
    let out = status_method(&mut solver, &StatusOptions::from_lcp(variant, opts, None))?;
    let lambda: Vec<f64> = out.forces.iter().map(|v| v.max(0.0)).collect();
    if lambda.iter().any(|v| !v.is_finite()) {
        return Err(ContactError::Solve(
            "status method with penalty: non-finite forces".into(),
        ));
    }
    let g = gaps(w, q, &lambda);
    report.iterations = out.report.iterations;
    report.operator_applications = solver.solves + solver.products;
    report.residual_history = solver.history;
    report.converged = out.report.converged;
    report.stop = if out.report.converged {
        StopReason::ByPenalty {
            status: Box::new(out.report.stop),
            penetration: max_penetration(&g),
        }
    } else {
        with_last_residual(out.report.stop, &report.residual_history)
    };
    Ok(ContactSolution::with_gaps(lambda, g, Vec::new(), report))
}

/// A time limit at the last residual of `history` (the iterations leave
/// it to their caller); any other stop as it is.
fn with_last_residual(mut stop: StopReason, history: &[f64]) -> StopReason {
    if let (StopReason::TimeLimit { residual, .. }, Some(&last)) = (&mut stop, history.last()) {
        *residual = last;
    }
    stop
}

/// A message naming the worst point when some penetration −g_p exceeds
/// `fraction` × `element_size[p]` (the penalty is too soft for the mesh:
/// raise k, course notes §3.6); `None` otherwise. Points with a non-finite gap or a
/// non-positive element size are skipped.
pub fn penetration_warning(g: &[f64], element_size: &[f64], fraction: f64) -> Option<String> {
    debug_assert_eq!(g.len(), element_size.len());
    let mut worst: Option<(usize, f64)> = None;
    for (p, (&gp, &h)) in g.iter().zip(element_size).enumerate() {
        if !gp.is_finite() || !h.is_finite() || h <= 0.0 {
            continue;
        }
        let ratio = -gp / h;
        if ratio > fraction && worst.is_none_or(|(_, r)| ratio > r) {
            worst = Some((p, ratio));
        }
    }
    worst.map(|(p, ratio)| {
        let count = g
            .iter()
            .zip(element_size)
            .filter(|(&gp, &h)| h > 0.0 && -gp > fraction * h)
            .count();
        format!(
            "penetration {:.3e} at contact point {p} is {:.1}% of its element size {:.3e} (threshold {:.1}%, {count} point(s) above it): the penalty stiffness is too low for this mesh (course notes §3.6)",
            -g[p],
            100.0 * ratio,
            element_size[p],
            100.0 * fraction
        )
    })
}

fn max_penetration(g: &[f64]) -> f64 {
    g.iter().fold(0.0f64, |a, &v| a.max(-v))
}

/// Checks the input and returns the compliances 1/k_p.
fn compliance(w: &Mat<f64>, q: &[f64], k: &[f64]) -> Result<Vec<f64>, ContactError> {
    check_input(w, q, "penalty")?;
    if k.len() != q.len() {
        return Err(ContactError::Solve(format!(
            "penalty: {} stiffnesses for {} contact points",
            k.len(),
            q.len()
        )));
    }
    if let Some(p) = k.iter().position(|&v| !(v.is_finite() && v > 0.0)) {
        return Err(ContactError::Solve(format!(
            "penalty: the stiffness of point {p} must be finite and positive, got {}",
            k[p]
        )));
    }
    Ok(k.iter().map(|v| 1.0 / v).collect())
}

/// [`ActiveSetSolve`] with the constraints of the active set imposed by
/// penalty: (W_AA + C_A) λ_A = −q_A, C = K⁻¹; returns the true gaps Wλ + q.
struct PenalisedActiveSet<'a> {
    w: &'a Mat<f64>,
    q: &'a [f64],
    c: &'a [f64],
    opts: &'a LcpOptions,
    solves: usize,
    products: usize,
    history: Vec<f64>,
}

impl ActiveSetSolve for PenalisedActiveSet<'_> {
    fn n_points(&self) -> usize {
        self.q.len()
    }

    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        let lambda = solve_block(self.w, self.q, self.c, active)?;
        self.solves += 1;
        let g = gaps(self.w, self.q, &lambda);
        self.products += 1;
        let clamped: Vec<f64> = lambda.iter().map(|v| v.max(0.0)).collect();
        let gc = gaps(self.w, self.q, &clamped);
        self.history
            .push(residual_from_gaps(&clamped, &gc, self.opts));
        Ok((lambda, g))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::gaps;
    use crate::test_problems::*;

    fn opts() -> LcpOptions {
        lcp_options(1e-13, 200)
    }

    fn norm2(v: &[f64]) -> f64 {
        v.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    /// Relative error and penetration for k = 10^j / mean diag W, j = 0..=12.
    fn sweep(
        w: &Mat<f64>,
        q: &[f64],
        exact: &[f64],
        solve: &dyn Fn(&[f64]) -> ContactSolution,
    ) -> Vec<(f64, f64)> {
        (0..=12)
            .map(|j| {
                let k = uniform_stiffness(w, 10f64.powi(j));
                let sol = solve(&k);
                assert!(sol.report.converged, "k = 1e{j}: {}", sol.report.stop);
                assert!(sol.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
                let d: Vec<f64> = sol.forces.iter().zip(exact).map(|(a, b)| a - b).collect();
                let g = gaps(w, q, &sol.forces);
                (norm2(&d) / norm2(exact), max_penetration(&g))
            })
            .collect()
    }

    fn check_sweep(name: &str, s: &[(f64, f64)]) {
        for (j, (e, p)) in s.iter().enumerate() {
            println!("{name}: k = 1e{j:<2} / mean diag W   error {e:.3e}   penetration {p:.3e}");
        }
        // Monotone decrease over the first decades.
        for j in 0..8 {
            assert!(
                s[j + 1].0 < s[j].0,
                "{name}: error not decreasing at 1e{j}: {s:?}"
            );
        }
        assert!(s[8].0 <= 1e-6, "{name}: error {} at k = 1e8", s[8].0);
        // Penetration ∝ 1/k once the active set has settled.
        for j in 2..10 {
            let r = s[j].1 / s[j + 1].1;
            assert!(
                (9.0..=11.0).contains(&r),
                "{name}: penetration ratio {r} at 1e{j}"
            );
        }
        // The error is O(1/k) too.
        for j in 2..6 {
            let r = s[j].0 / s[j + 1].0;
            assert!(
                (8.0..=12.0).contains(&r),
                "{name}: error ratio {r} at 1e{j}"
            );
        }
    }

    /// The random mixed cases of 20 points.
    fn random_mixed_20() -> Vec<Case> {
        let mut all = cases();
        all.retain(|c| c.name.starts_with("random mixed m = 20"));
        all
    }

    #[test]
    fn penalty_converges_to_the_exact_solution_like_one_over_k() {
        for c in &random_mixed_20() {
            let o = opts();
            let s = sweep(&c.w, &c.q, &c.exact, &|k| {
                penalty(&c.w, &c.q, k, &o).unwrap()
            });
            check_sweep("penalty", &s);
        }
    }

    #[test]
    fn status_with_penalty_converges_to_the_exact_solution_like_one_over_k() {
        for c in &random_mixed_20() {
            let o = opts();
            for variant in [StatusVariant::All, StatusVariant::Single] {
                let s = sweep(&c.w, &c.q, &c.exact, &|k| {
                    status_with_penalty(&c.w, &c.q, k, variant, &o).unwrap()
                });
                check_sweep(&format!("status with penalty {variant:?}"), &s);
            }
        }
    }

    #[test]
    fn penalty_and_status_with_penalty_solve_the_same_regularised_law() {
        for (c, factor) in cases().iter().flat_map(|c| [(c, 1e3), (c, 1e8)]) {
            let k = uniform_stiffness(&c.w, factor);
            let a = penalty(&c.w, &c.q, &k, &opts()).unwrap();
            let b = status_with_penalty(&c.w, &c.q, &k, StatusVariant::All, &opts()).unwrap();
            assert!(a.report.converged && b.report.converged, "{}", c.name);
            let scale = norm_inf(&a.forces).max(1e-300);
            // Round-off grows with the condition of W_AA + K_A⁻¹ (~ factor).
            let tol = (1e-10f64).max(1e-14 * factor);
            for (x, y) in a.forces.iter().zip(&b.forces) {
                assert!((x - y).abs() <= tol * scale, "{}: {x} vs {y}", c.name);
            }
            // The law itself: λ_p = k_p max(0, −g_p).
            let g = gaps(&c.w, &c.q, &a.forces);
            for p in 0..g.len() {
                let law = k[p] * (-g[p]).max(0.0);
                assert!(
                    (a.forces[p] - law).abs() <= 10.0 * tol * scale,
                    "{}: point {p}",
                    c.name
                );
            }
            println!(
                "k = {factor:e} / mean diag W, {}: penalty {} iterations ({} solves + products); status with penalty {} iterations ({} solves + products)",
                c.name,
                a.report.iterations,
                a.report.operator_applications,
                b.report.iterations,
                b.report.operator_applications
            );
        }
    }

    #[test]
    fn penalty_is_regular_on_redundant_constraints() {
        let (w, q, l0, _) = redundant();
        let k = uniform_stiffness(&w, 1e9);
        for sol in [
            penalty(&w, &q, &k, &opts()).unwrap(),
            status_with_penalty(&w, &q, &k, StatusVariant::All, &opts()).unwrap(),
        ] {
            assert!(sol.report.converged, "{}", sol.report.stop);
            let l = &sol.forces;
            assert!(l.iter().all(|v| v.is_finite() && *v >= 0.0));
            // The pair shares the force equally (W + K⁻¹ is definite, but
            // its condition ~ k·max W_pp = 1e9 limits the split's accuracy).
            assert!((l[0] - l[1]).abs() <= 1e-5 * l[0], "{} vs {}", l[0], l[1]);
            let s = norm_inf(&l0);
            assert!(((l[0] + l[1]) - l0[0]).abs() <= 1e-6 * s);
            for i in 1..l0.len() {
                assert!((l[i + 1] - l0[i]).abs() <= 1e-6 * s);
            }
        }
    }

    #[test]
    fn penetration_warning_fires_above_the_fraction_only() {
        let h = [0.1, 0.1, 0.2, 0.1];
        // −g / h = 0, 0.04, 0.045, −
        let g = [0.0, -0.004, -0.009, 0.5];
        assert!(penetration_warning(&g, &h, 0.05).is_none());
        let msg = penetration_warning(&g, &h, 0.03).unwrap();
        assert!(msg.contains("contact point 2"), "{msg}");
        assert!(msg.contains("2 point(s)"), "{msg}");
        let msg = penetration_warning(&g, &h, 0.042).unwrap();
        assert!(
            msg.contains("contact point 2") && msg.contains("1 point(s)"),
            "{msg}"
        );
        assert!(penetration_warning(&[], &[], 0.01).is_none());
    }

    #[test]
    fn penalty_rejects_bad_input_and_handles_empty_problems() {
        let c = &cases()[0];
        let k = uniform_stiffness(&c.w, 1e3);
        let mut bad = k.clone();
        bad[1] = 0.0;
        assert!(matches!(
            penalty(&c.w, &c.q, &bad, &opts()),
            Err(ContactError::Solve(_))
        ));
        bad[1] = f64::NAN;
        assert!(matches!(
            status_with_penalty(&c.w, &c.q, &bad, StatusVariant::All, &opts()),
            Err(ContactError::Solve(_))
        ));
        let mut q = c.q.clone();
        q[0] = f64::INFINITY;
        assert!(matches!(
            penalty(&c.w, &q, &k, &opts()),
            Err(ContactError::Solve(_))
        ));
        let e = penalty(&Mat::zeros(0, 0), &[], &[], &opts()).unwrap();
        assert!(e.report.converged && e.forces.is_empty());
        let e =
            status_with_penalty(&Mat::zeros(0, 0), &[], &[], StatusVariant::All, &opts()).unwrap();
        assert!(e.report.converged && e.forces.is_empty());
        let o = LcpOptions {
            max_iterations: 1,
            ..opts()
        };
        let big = &cases()[2];
        let s = penalty(&big.w, &big.q, &uniform_stiffness(&big.w, 1e6), &o).unwrap();
        assert!(!s.report.converged && s.report.stop.to_string().contains("iteration limit"));
        assert!(s.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
}
