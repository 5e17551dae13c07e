//! LCP(W + diag(c), q), c > 0, the regularised problem that the penalty
//! methods and the augmented Lagrangian method solve exactly: the solve on
//! an active set and the active-set (semi-smooth Newton) iteration.

use std::collections::HashSet;

use faer::Mat;

use crate::lcp::{gaps, LcpOptions};
use crate::solution::StopReason;
use crate::ContactError;

/// λ with (W_AA + C_A) λ_A = −q_A and λ = 0 off A.
pub(crate) fn solve_block(
    w: &Mat<f64>,
    q: &[f64],
    c: &[f64],
    active: &[usize],
) -> Result<Vec<f64>, ContactError> {
    let m = q.len();
    let na = active.len();
    let mut lambda = vec![0.0; m];
    if na == 0 {
        return Ok(lambda);
    }
    let a = Mat::<f64>::from_fn(na, na, |i, j| {
        w[(active[i], active[j])] + if i == j { c[active[i]] } else { 0.0 }
    });
    let rhs = Mat::<f64>::from_fn(na, 1, |i, _| -q[active[i]]);
    // A singular block leaves NaN forces, refused below.
    let sol = signorini_linalg::pivot_policy::solve_symmetric_checked(&a, &rhs, "W_AA + K_A⁻¹")
        .unwrap_or_else(|_| Mat::from_fn(na, 1, |_, _| f64::NAN));
    for (i, &p) in active.iter().enumerate() {
        lambda[p] = sol[(i, 0)];
    }
    if lambda.iter().any(|v| !v.is_finite()) {
        return Err(ContactError::Solve(format!(
            "the regularised system W_AA + K_A⁻¹ ({na} active points) is singular: W is not positive semi-definite"
        )));
    }
    Ok(lambda)
}

/// What [`regularised_newton`] found.
pub(crate) struct NewtonOutcome {
    pub converged: bool,
    /// Why the iteration stopped when it did not converge.
    pub stop: StopReason,
    /// λ ≥ 0.
    pub lambda: Vec<f64>,
    /// g = Wλ + q (the true gaps, without the regularisation).
    pub g: Vec<f64>,
    pub active: Vec<bool>,
    /// The first iteration whose next active set repeated an earlier one.
    pub cycle_at: Option<usize>,
    pub iterations: usize,
    /// Block solves and products W·λ: one of each an iteration.
    pub operator_applications: usize,
}

/// Exact solution of LCP(W + diag(c), q), c > 0, by the active-set (semi-
/// smooth Newton, primal-dual active set) iteration from the active set
/// `active`: solve (W_AA + C_A) λ_A = −q_A, λ = 0 off A; h = (W + C)λ + q;
/// A keeps the points with λ_p ≥ −tol_f and gains those with h_p < −tol_g;
/// stop when A repeats. A repeated earlier set switches to Murty's
/// least-index single change. `observe(λ, g)` is called after each
/// iteration with λ clamped to ≥ 0 and g = Wλ + q. At the deadline of
/// `opts` it stops with the last iterate ([`StopReason::TimeLimit`], its
/// residual left to the caller: NaN).
pub(crate) fn regularised_newton(
    w: &Mat<f64>,
    q: &[f64],
    c: &[f64],
    mut active: Vec<bool>,
    opts: &LcpOptions,
    max_iterations: usize,
    observe: &mut dyn FnMut(&[f64], &[f64]),
) -> Result<NewtonOutcome, ContactError> {
    let m = q.len();
    let mut seen: HashSet<Vec<bool>> = HashSet::new();
    let mut single = false;
    let mut out = NewtonOutcome {
        converged: false,
        stop: StopReason::Pending,
        lambda: vec![0.0; m],
        g: q.to_vec(),
        active: active.clone(),
        cycle_at: None,
        iterations: 0,
        operator_applications: 0,
    };
    while out.iterations < max_iterations {
        if opts.out_of_time(out.iterations) {
            out.stop = StopReason::TimeLimit {
                iterations: out.iterations,
                residual: f64::NAN,
            };
            return Ok(out);
        }
        out.iterations += 1;
        seen.insert(active.clone());
        let set: Vec<usize> = (0..m).filter(|&p| active[p]).collect();
        let lambda = solve_block(w, q, c, &set)?;
        let g = gaps(w, q, &lambda);
        out.operator_applications += 2;
        let lmax = lambda.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let h: Vec<f64> = (0..m).map(|p| g[p] + c[p] * lambda[p]).collect();
        let hmax = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let tol_f = opts.tolerance * opts.force_scale.max(lmax);
        let tol_g = opts.tolerance * opts.gap_scale.max(hmax);
        let violating: Vec<usize> = (0..m)
            .filter(|&p| {
                if active[p] {
                    lambda[p] < -tol_f
                } else {
                    h[p] < -tol_g
                }
            })
            .collect();
        out.lambda = lambda.iter().map(|v| v.max(0.0)).collect();
        out.g = if violating.is_empty() && lambda.iter().all(|&v| v >= 0.0) {
            g
        } else {
            gaps(w, q, &out.lambda)
        };
        out.active = active.clone();
        observe(&out.lambda, &out.g);
        if violating.is_empty() {
            out.converged = true;
            return Ok(out);
        }
        let mut next = active.clone();
        if single {
            next[violating[0]] = !next[violating[0]];
        } else {
            for &p in &violating {
                next[p] = !next[p];
            }
        }
        if seen.contains(&next) {
            if single {
                out.stop = StopReason::NewtonCycling {
                    iteration: out.iterations,
                    tolerance: opts.tolerance,
                };
                return Ok(out);
            }
            out.cycle_at.get_or_insert(out.iterations);
            single = true;
            seen.clear();
            next = active.clone();
            next[violating[0]] = !next[violating[0]];
        }
        active = next;
    }
    out.stop = StopReason::ActiveSetLimit {
        limit: max_iterations,
    };
    Ok(out)
}
