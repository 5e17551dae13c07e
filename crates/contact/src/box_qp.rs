//! MPRGP for simple bounds (Z. Dostál, *Optimal Quadratic Programming
//! Algorithms*, Springer 2009, ch. 8), for the box-constrained quadratic
//! programme of Tresca friction (normal forces λ_n ≥ 0, tangential forces
//! −g ≤ λ_t ≤ g with the Tresca threshold g):
//!
//! ```text
//! min f(x) = ½ xᵀ A x + bᵀ x   subject to   l ≤ x ≤ u,     g = ∇f = A x + b,
//! ```
//!
//! with l_i ∈ [−∞, ∞), u_i ∈ (−∞, ∞], l_i ≤ u_i (l_i = u_i fixes x_i). With
//! the free set F = {i : l_i < x_i < u_i} and P the projection onto the box:
//!
//! - free gradient         φ_i = g_i on F, 0 elsewhere;
//! - chopped gradient      β_i = min(g_i, 0) where x_i = l_i < u_i,
//!   max(g_i, 0) where x_i = u_i > l_i, 0 elsewhere (the components at a
//!   bound whose descent direction points into the box);
//! - reduced free gradient φ̃ = (x − P(x − ᾱ φ)) / ᾱ, i.e.
//!   φ̃_i = min((x_i − l_i)/ᾱ, φ_i) for φ_i > 0 and max((x_i − u_i)/ᾱ, φ_i)
//!   for φ_i < 0 on F, 0 elsewhere;
//! - projected gradient    gᴾ = φ + β (zero exactly at the solution).
//!
//! x is *proportional* when ‖β‖² ≤ Γ² φ̃ᵀφ (Γ = 1). Each iteration is one of
//!
//! - **CG step** (proportional, α_cg = gᵀp / pᵀAp ≤ α_f, the longest step with
//!   l ≤ x − α p ≤ u): x ← x − α_cg p, g ← g − α_cg A p, p ← φ − γ p with
//!   γ = φᵀA p / pᵀA p;
//! - **expansion step** (proportional, α_cg > α_f): the feasible half step
//!   x½ = x − α_f p, then x ← P(x½ − ᾱ φ(x½)) with the fixed step
//!   ᾱ = 1.9/‖A‖ (‖A‖ by power iterations, enlarged by 1 %), g ← A x + b,
//!   p ← φ;
//! - **proportioning step** (not proportional): x ← x − α β with the exact
//!   minimiser α = gᵀβ / βᵀAβ along the chopped gradient, cut at the
//!   opposite bound when it would cross it, p ← φ.
//!
//! The start is P(0). Stopping: [`box_residual`] ≤ `opts.tolerance`, checked
//! with the exact gradient. On convergence the iterate is *polished*: the
//! variables at a bound are fixed, A_FF x_F = −b_F − A_FB x_B is solved
//! (Cholesky, else full-pivoting LU) and the result is kept only if it stays
//! in the box and its residual is no larger.
//!
//! A may be positive semi-definite (redundant constraints); when f is
//! unbounded below along a feasible direction (zero curvature, no bound in
//! the way) the method returns [`ContactError::Singular`]. With l = 0 and
//! u = +∞ the problem is LCP(A, b) and the residual is [`crate::lcp_residual`].

use faer::Mat;

use crate::lcp::{
    dot, gaps, matvec, spectral_norm_estimate, LcpOptions, LcpSolution, SolverReport,
};
use crate::ContactError;

const METHOD: &str = "mprgp_box";

/// Γ of the proportioning test ‖β‖² ≤ Γ² φ̃ᵀφ.
const GAMMA: f64 = 1.0;

/// ᾱ = STEP_FACTOR / ‖A‖, inside (0, 2/‖A‖].
const STEP_FACTOR: f64 = 1.9;

/// Curvatures pᵀAp ≤ FLAT · ‖A‖ · pᵀp count as zero.
const FLAT: f64 = 1e-14;

/// MPRGP on min ½ xᵀ A x + bᵀ x subject to l ≤ x ≤ u (see the module
/// documentation). `lower[i]` may be −∞, `upper[i]` may be +∞; `lower[i] =
/// upper[i]` fixes x_i.
///
/// The solution is returned in `LcpSolution::lambda`. `report.iterations`
/// counts CG, expansion and proportioning steps; `operator_applications` the
/// products A·v (power iterations for ‖A‖ included) and the polishing solve;
/// `residual_history` holds [`box_residual`] after each step, its last entry
/// being the residual of the returned x.
///
/// Errors: [`ContactError::Solve`] for inconsistent sizes, a non-finite
/// entry of A or b, a NaN bound, l_i = +∞, u_i = −∞ or l_i > u_i (the message
/// names the index); [`ContactError::Singular`] when the objective is
/// unbounded below on the box. Reaching `opts.max_iterations` is not an
/// error: `report.converged` is then false and the stopping reason says so.
pub fn mprgp_box(
    a: &Mat<f64>,
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
    opts: &LcpOptions,
) -> Result<LcpSolution, ContactError> {
    check_box_input(a, b, lower, upper)?;
    let n = b.len();
    let mut report = SolverReport {
        method: METHOD.into(),
        ..Default::default()
    };
    if n == 0 {
        report.converged = true;
        report.stopping_reason = "no unknown".into();
        return Ok(LcpSolution {
            lambda: Vec::new(),
            report,
        });
    }
    let mut x: Vec<f64> = (0..n).map(|i| project(0.0, lower[i], upper[i])).collect();
    let mut g = gaps(a, b, &x);
    report.operator_applications += 1;
    let res0 = scaled_residual(&x, &g, lower, upper, opts);
    if res0 <= opts.tolerance {
        let (res, polished) = polish(a, b, lower, upper, &mut x, res0, opts, &mut report);
        report.residual_history.push(res);
        report.converged = true;
        report.stopping_reason = format!(
            "the projection of 0 onto the box solves the problem: residual {res:.3e} ≤ tolerance {:.3e}{polished}",
            opts.tolerance
        );
        return Ok(LcpSolution { lambda: x, report });
    }
    if a.norm_max() == 0.0 {
        return solve_linear(b, lower, upper, x, opts, report);
    }
    let (norm_a, power_products) = spectral_norm_estimate(a);
    report.operator_applications += power_products;
    let abar = STEP_FACTOR / norm_a;
    let mut p = free_gradient(&x, &g, lower, upper);
    let mut ap = vec![0.0; n];
    let (mut n_cg, mut n_exp, mut n_prop) = (0usize, 0usize, 0usize);
    loop {
        let res = scaled_residual(&x, &g, lower, upper, opts);
        if res <= opts.tolerance {
            // Check with the exact gradient (the recursive one may drift).
            g = gaps(a, b, &x);
            report.operator_applications += 1;
            let exact = scaled_residual(&x, &g, lower, upper, opts);
            if exact <= opts.tolerance {
                let (res, polished) = polish(a, b, lower, upper, &mut x, exact, opts, &mut report);
                set_last(&mut report, res);
                report.converged = true;
                report.stopping_reason = format!(
                    "projected-gradient residual {res:.3e} ≤ tolerance {:.3e} after {} iterations ({n_cg} CG, {n_exp} expansion, {n_prop} proportioning steps; ᾱ = 1.9/‖A‖, ‖A‖ ≈ {norm_a:.6e}){polished}",
                    opts.tolerance, report.iterations
                );
                break;
            }
            // The exact residual is above the tolerance: continue from the
            // exact gradient (the next test sees `exact`).
            set_last(&mut report, exact);
            p = free_gradient(&x, &g, lower, upper);
            continue;
        }
        if report.iterations >= opts.max_iterations {
            report.stopping_reason = format!(
                "iteration limit {} reached with projected-gradient residual {res:.3e} above tolerance {:.3e} (not converged; {n_cg} CG, {n_exp} expansion, {n_prop} proportioning steps)",
                opts.max_iterations, opts.tolerance
            );
            break;
        }
        report.iterations += 1;
        let phi = free_gradient(&x, &g, lower, upper);
        let beta = chopped_gradient(&x, &g, lower, upper);
        let beta_sq = dot(&beta, &beta);
        let phi_tilde_phi: f64 = (0..n)
            .filter(|&i| phi[i] != 0.0)
            .map(|i| reduced(phi[i], x[i], lower[i], upper[i], abar) * phi[i])
            .sum();
        if beta_sq <= GAMMA * GAMMA * phi_tilde_phi {
            if dot(&g, &p) <= 0.0 {
                // p lost the descent property (round-off): restart along φ.
                p.clone_from(&phi);
                if dot(&p, &p) == 0.0 {
                    report.stopping_reason = format!(
                        "stagnation at iteration {}: no descent direction left at residual {res:.3e} above tolerance {:.3e} (round-off floor; not converged)",
                        report.iterations, opts.tolerance
                    );
                    break;
                }
            }
            matvec(a, &p, &mut ap);
            report.operator_applications += 1;
            let curv = dot(&p, &ap);
            let flat = curv <= FLAT * norm_a * dot(&p, &p);
            let (alpha_f, block) = feasible_step(&x, &p, lower, upper);
            if flat && block.is_none() {
                return Err(unbounded());
            }
            let alpha_cg = if flat {
                f64::INFINITY
            } else {
                dot(&g, &p) / curv
            };
            if alpha_cg <= alpha_f {
                // CG step.
                n_cg += 1;
                for i in 0..n {
                    x[i] = project(x[i] - alpha_cg * p[i], lower[i], upper[i]);
                    g[i] -= alpha_cg * ap[i];
                }
                let phi = free_gradient(&x, &g, lower, upper);
                let gamma = dot(&phi, &ap) / curv;
                for i in 0..n {
                    p[i] = phi[i] - gamma * p[i];
                }
            } else {
                // Expansion step: feasible half step, then fixed-step projection.
                n_exp += 1;
                for i in 0..n {
                    x[i] = project(x[i] - alpha_f * p[i], lower[i], upper[i]);
                    g[i] -= alpha_f * ap[i];
                }
                if let Some(k) = block {
                    // The blocking variable lands exactly on its bound.
                    x[k] = if p[k] > 0.0 { lower[k] } else { upper[k] };
                }
                let phi = free_gradient(&x, &g, lower, upper);
                for i in 0..n {
                    x[i] = project(x[i] - abar * phi[i], lower[i], upper[i]);
                }
                matvec(a, &x, &mut g);
                for (gi, bi) in g.iter_mut().zip(b) {
                    *gi += bi;
                }
                report.operator_applications += 1;
                p = free_gradient(&x, &g, lower, upper);
            }
        } else {
            // Proportioning step along −β (into the box), cut at the
            // opposite bound.
            n_prop += 1;
            matvec(a, &beta, &mut ap);
            report.operator_applications += 1;
            let curv = dot(&beta, &ap);
            let flat = curv <= FLAT * norm_a * beta_sq;
            let (alpha_f, block) = feasible_step(&x, &beta, lower, upper);
            if flat && block.is_none() {
                return Err(unbounded());
            }
            let alpha_cg = if flat { f64::INFINITY } else { beta_sq / curv };
            let alpha = alpha_cg.min(alpha_f);
            for i in 0..n {
                x[i] = project(x[i] - alpha * beta[i], lower[i], upper[i]);
                g[i] -= alpha * ap[i];
            }
            if alpha_cg >= alpha_f {
                if let Some(k) = block {
                    x[k] = if beta[k] > 0.0 { lower[k] } else { upper[k] };
                }
            }
            p = free_gradient(&x, &g, lower, upper);
        }
        if !x.iter().chain(&g).all(|v| v.is_finite()) {
            // Runaway iterates (curvature just above the flatness threshold
            // along an unbounded direction): never return a NaN.
            return Err(unbounded());
        }
        report
            .residual_history
            .push(scaled_residual(&x, &g, lower, upper, opts));
    }
    Ok(LcpSolution { lambda: x, report })
}

/// The projected-gradient residual of the box QP at x,
///
/// ```text
/// max_i | min((x_i − l_i)/F, max((x_i − u_i)/F, g_i/L)) |,   g = A x + b,
/// ```
///
/// i.e. |x − P_[l,u](x − g)| with the forces scaled by F = max(force_scale,
/// ‖x‖∞) and the gradients by L = gap_scale (as [`crate::lcp_residual`],
/// which it equals bit for bit when l = 0 and u = +∞). Zero exactly when x
/// solves the QP; positive at any other x, in particular outside the box.
/// Non-finite data give +∞.
///
/// # Panics
/// When the sizes of A, b, x, l and u disagree.
pub fn box_residual(
    a: &Mat<f64>,
    b: &[f64],
    x: &[f64],
    lower: &[f64],
    upper: &[f64],
    opts: &LcpOptions,
) -> f64 {
    let n = b.len();
    assert!(
        a.nrows() == n && a.ncols() == n && x.len() == n && lower.len() == n && upper.len() == n,
        "box_residual: A is {}×{}, b, x, l, u have {n}, {}, {}, {} entries",
        a.nrows(),
        a.ncols(),
        x.len(),
        lower.len(),
        upper.len()
    );
    let g = gaps(a, b, x);
    scaled_residual(x, &g, lower, upper, opts)
}

/// [`box_residual`] from a known gradient g = A x + b.
fn scaled_residual(x: &[f64], g: &[f64], lower: &[f64], upper: &[f64], opts: &LcpOptions) -> f64 {
    let f = opts
        .force_scale
        .max(x.iter().fold(0.0f64, |m, v| m.max(v.abs())))
        .max(f64::MIN_POSITIVE);
    let l = opts.gap_scale.max(f64::MIN_POSITIVE);
    let mut worst = 0.0f64;
    for i in 0..x.len() {
        let r = ((x[i] - lower[i]) / f)
            .min(((x[i] - upper[i]) / f).max(g[i] / l))
            .abs();
        if !r.is_finite() || !x[i].is_finite() || !g[i].is_finite() {
            return f64::INFINITY;
        }
        worst = worst.max(r);
    }
    worst
}

/// P_[l,u](v).
fn project(v: f64, l: f64, u: f64) -> f64 {
    v.max(l).min(u)
}

fn is_free(x: f64, l: f64, u: f64) -> bool {
    l < x && x < u
}

/// φ(x): g on the free set, 0 elsewhere.
fn free_gradient(x: &[f64], g: &[f64], lower: &[f64], upper: &[f64]) -> Vec<f64> {
    (0..x.len())
        .map(|i| {
            if is_free(x[i], lower[i], upper[i]) {
                g[i]
            } else {
                0.0
            }
        })
        .collect()
}

/// β(x): the components of g at a bound whose descent direction −g points
/// into the box, 0 elsewhere (and 0 for the fixed variables l = u).
fn chopped_gradient(x: &[f64], g: &[f64], lower: &[f64], upper: &[f64]) -> Vec<f64> {
    (0..x.len())
        .map(|i| {
            if lower[i] == upper[i] {
                0.0
            } else if x[i] == lower[i] {
                g[i].min(0.0)
            } else if x[i] == upper[i] {
                g[i].max(0.0)
            } else {
                0.0
            }
        })
        .collect()
}

/// φ̃_i = (x_i − P(x_i − ᾱ φ_i)) / ᾱ for a free variable.
fn reduced(phi: f64, x: f64, l: f64, u: f64, abar: f64) -> f64 {
    if phi > 0.0 {
        ((x - l) / abar).min(phi)
    } else {
        ((x - u) / abar).max(phi)
    }
}

/// α_f = max{α : l ≤ x − α d ≤ u} and the variable that blocks it (smallest
/// index on ties); (∞, None) when no bound is in the way.
fn feasible_step(x: &[f64], d: &[f64], lower: &[f64], upper: &[f64]) -> (f64, Option<usize>) {
    let mut best = (f64::INFINITY, None);
    for i in 0..x.len() {
        let step = if d[i] > 0.0 {
            (x[i] - lower[i]) / d[i]
        } else if d[i] < 0.0 {
            (upper[i] - x[i]) / -d[i]
        } else {
            continue;
        };
        if step.is_finite() && step.max(0.0) < best.0 {
            best = (step.max(0.0), Some(i));
        }
    }
    best
}

/// Active-set polishing of a converged iterate (see the module
/// documentation). Replaces x when the polished point is in the box with a
/// residual ≤ `res`; returns the residual of the kept x and a note for the
/// stopping reason.
#[allow(clippy::too_many_arguments)]
fn polish(
    a: &Mat<f64>,
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
    x: &mut [f64],
    res: f64,
    opts: &LcpOptions,
    report: &mut SolverReport,
) -> (f64, &'static str) {
    use faer::prelude::Solve;
    let n = x.len();
    let free: Vec<usize> = (0..n)
        .filter(|&i| is_free(x[i], lower[i], upper[i]))
        .collect();
    if free.is_empty() || res == 0.0 {
        return (res, "");
    }
    let mut fixed = vec![true; n];
    for &i in &free {
        fixed[i] = false;
    }
    let nf = free.len();
    let aff = Mat::<f64>::from_fn(nf, nf, |r, c| a[(free[r], free[c])]);
    let rhs = Mat::<f64>::from_fn(nf, 1, |r, _| {
        let i = free[r];
        -(b[i]
            + (0..n)
                .filter(|&j| fixed[j])
                .map(|j| a[(i, j)] * x[j])
                .sum::<f64>())
    });
    let sol = match aff.llt(faer::Side::Lower) {
        Ok(llt) => llt.solve(&rhs),
        Err(_) => aff.full_piv_lu().solve(&rhs),
    };
    report.operator_applications += 2; // the block solve and the residual
    let mut y = x.to_vec();
    for (k, &i) in free.iter().enumerate() {
        let v = sol[(k, 0)];
        if !v.is_finite() || v < lower[i] || v > upper[i] {
            return (res, "; polishing rejected (left the box)");
        }
        y[i] = v;
    }
    let res_y = box_residual(a, b, &y, lower, upper, opts);
    if res_y <= res {
        x.copy_from_slice(&y);
        (res_y, "; polished on the active set")
    } else {
        (res, "; polishing rejected (larger residual)")
    }
}

/// A = 0: f(x) = bᵀx is minimised variable by variable at the bound that
/// b_i points away from (x_i unchanged where b_i = 0); unbounded when that
/// bound is infinite.
fn solve_linear(
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
    mut x: Vec<f64>,
    opts: &LcpOptions,
    mut report: SolverReport,
) -> Result<LcpSolution, ContactError> {
    for i in 0..b.len() {
        if b[i] > 0.0 {
            x[i] = lower[i];
        } else if b[i] < 0.0 {
            x[i] = upper[i];
        }
        if !x[i].is_finite() {
            return Err(unbounded());
        }
    }
    let res = scaled_residual(&x, b, lower, upper, opts);
    report.residual_history.push(res);
    report.converged = res <= opts.tolerance;
    report.stopping_reason =
        format!("A = 0: the linear objective is minimised at the bounds, residual {res:.3e}");
    Ok(LcpSolution { lambda: x, report })
}

fn set_last(report: &mut SolverReport, res: f64) {
    if let Some(last) = report.residual_history.last_mut() {
        *last = res;
    } else {
        report.residual_history.push(res);
    }
}

fn unbounded() -> ContactError {
    ContactError::Singular(format!(
        "{METHOD}: A is singular along a feasible descent direction with no bound in the way, so ½xᵀAx + bᵀx is unbounded below on the box (a body free to slide or move away from its contacts?)"
    ))
}

/// Rejects inconsistent sizes, non-finite entries of A or b, NaN bounds,
/// l_i = +∞, u_i = −∞ and l_i > u_i, naming the index.
fn check_box_input(
    a: &Mat<f64>,
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
) -> Result<(), ContactError> {
    let n = b.len();
    if a.nrows() != n || a.ncols() != n || lower.len() != n || upper.len() != n {
        return Err(ContactError::Solve(format!(
            "{METHOD}: A is {}×{} but b, l, u have {n}, {}, {} entries",
            a.nrows(),
            a.ncols(),
            lower.len(),
            upper.len()
        )));
    }
    if let Some(i) = b.iter().position(|v| !v.is_finite()) {
        return Err(ContactError::Solve(format!(
            "{METHOD}: b[{i}] = {} is not finite",
            b[i]
        )));
    }
    for j in 0..n {
        if let Some(i) = a.col_as_slice(j).iter().position(|v| !v.is_finite()) {
            return Err(ContactError::Solve(format!(
                "{METHOD}: A[({i}, {j})] = {} is not finite",
                a[(i, j)]
            )));
        }
    }
    for i in 0..n {
        let (l, u) = (lower[i], upper[i]);
        if l.is_nan() || l == f64::INFINITY {
            return Err(ContactError::Solve(format!(
                "{METHOD}: lower bound l[{i}] = {l} is not a valid bound (NaN or +∞)"
            )));
        }
        if u.is_nan() || u == f64::NEG_INFINITY {
            return Err(ContactError::Solve(format!(
                "{METHOD}: upper bound u[{i}] = {u} is not a valid bound (NaN or −∞)"
            )));
        }
        if l > u {
            return Err(ContactError::Solve(format!(
                "{METHOD}: empty box at index {i}: l[{i}] = {l} > u[{i}] = {u}"
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::lcp_residual;
    use crate::mprgp::mprgp;
    use crate::projected_gradient::test_support::{
        agrees_with_status_method, assert_close, edge_cases, inf_norm, random_spd, random_vec,
        redundant_constraints, reports_iteration_limit, tight, Rng,
    };

    const INF: f64 = f64::INFINITY;

    /// mprgp_box with l = 0, u = +∞: an LCP method.
    fn as_lcp(w: &Mat<f64>, q: &[f64], opts: &LcpOptions) -> Result<LcpSolution, ContactError> {
        let m = q.len();
        mprgp_box(w, q, &vec![0.0; m], &vec![INF; m], opts)
    }

    /// Every x with each variable at its lower bound, free or at its upper
    /// bound (3ⁿ combinations; infinite bounds skipped), the free part from
    /// A_FF x_F = −b_F − A_FB x_B. Returns the KKT points and the others.
    fn brute_force(
        a: &Mat<f64>,
        b: &[f64],
        l: &[f64],
        u: &[f64],
    ) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        use faer::prelude::Solve;
        let n = b.len();
        let (mut kkt, mut others) = (Vec::new(), Vec::new());
        'combo: for c in 0..3usize.pow(n as u32) {
            let status: Vec<usize> = (0..n).map(|i| (c / 3usize.pow(i as u32)) % 3).collect();
            let mut x = vec![0.0; n];
            for i in 0..n {
                x[i] = match status[i] {
                    0 => l[i],
                    2 => u[i],
                    _ => 0.0,
                };
                if !x[i].is_finite() {
                    continue 'combo;
                }
            }
            let free: Vec<usize> = (0..n).filter(|&i| status[i] == 1).collect();
            if !free.is_empty() {
                let nf = free.len();
                let aff = Mat::<f64>::from_fn(nf, nf, |r, s| a[(free[r], free[s])]);
                let rhs = Mat::<f64>::from_fn(nf, 1, |r, _| {
                    let i = free[r];
                    -(b[i]
                        + (0..n)
                            .filter(|&j| status[j] != 1)
                            .map(|j| a[(i, j)] * x[j])
                            .sum::<f64>())
                });
                let sol = aff.llt(faer::Side::Lower).unwrap().solve(&rhs);
                for (k, &i) in free.iter().enumerate() {
                    x[i] = sol[(k, 0)];
                }
            }
            let g = gaps(a, b, &x);
            let tol = 1e-12;
            let ok = (0..n).all(|i| {
                x[i] >= l[i] - tol
                    && x[i] <= u[i] + tol
                    && match status[i] {
                        0 => g[i] >= -tol || l[i] == u[i],
                        2 => g[i] <= tol || l[i] == u[i],
                        _ => true,
                    }
            });
            if ok {
                kkt.push(x);
            } else {
                others.push(x);
            }
        }
        (kkt, others)
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    /// A Tresca-like problem: x = [λ_n; λ_t], l = [0; −g], u = [∞; g].
    fn tresca(m: usize, seed: u64) -> (Mat<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut rng = Rng::new(seed);
        let a = random_spd(2 * m, &mut rng);
        let b: Vec<f64> = random_vec(2 * m, &mut rng)
            .iter()
            .map(|v| 2.0 * v)
            .collect();
        let g: Vec<f64> = (0..m).map(|_| 0.05 + 0.5 * rng.uniform().abs()).collect();
        let mut l = vec![0.0; m];
        l.extend(g.iter().map(|v| -v));
        let mut u = vec![INF; m];
        u.extend(g.iter().copied());
        (a, b, l, u)
    }

    #[test]
    fn box_qp_equals_mprgp_on_the_lcp() {
        let opts = tight();
        let mut rng = Rng::new(11);
        for m in [5, 20, 60] {
            let w = random_spd(m, &mut rng);
            let q = random_vec(m, &mut rng);
            let reference = mprgp(&w, &q, &opts).unwrap();
            let sol = as_lcp(&w, &q, &opts).unwrap();
            assert!(sol.report.converged, "{}", sol.report.stopping_reason);
            assert!(sol.lambda.iter().all(|v| v.is_finite() && *v >= 0.0));
            let r = lcp_residual(&w, &q, &sol.lambda, &opts);
            assert_eq!(sol.report.residual_history.last(), Some(&r));
            assert!(r <= 1e-12, "m = {m}: residual {r:.3e}");
            let d = max_diff(&sol.lambda, &reference.lambda);
            eprintln!(
                "m = {m}: mprgp_box {} iterations / {} products, mprgp {} / {}; ‖Δλ‖∞ = {d:.2e}, residual {r:.2e}; {}",
                sol.report.iterations,
                sol.report.operator_applications,
                reference.report.iterations,
                reference.report.operator_applications,
                sol.report.stopping_reason
            );
            assert!(
                d <= 1e-8 * inf_norm(&reference.lambda).max(1.0),
                "m = {m}: {d:.3e}"
            );
            assert!(sol.lambda.contains(&0.0) && sol.lambda.iter().any(|v| *v > 0.0));
        }
    }

    #[test]
    fn box_qp_passes_the_lcp_test_suite() {
        let (it, ops) = agrees_with_status_method(as_lcp);
        eprintln!("mprgp_box as LCP: {it} iterations, {ops} products on the m = 60 random case");
        assert!(it > 0 && ops >= it);
        redundant_constraints(as_lcp, false);
        edge_cases(as_lcp);
        reports_iteration_limit(as_lcp, 3);
    }

    #[test]
    fn box_qp_tresca_matches_brute_force() {
        let opts = tight();
        let m = 3;
        // Which status each block reached over the seeds:
        // [normal at 0, normal free, tangent at −g, tangent free, tangent at +g].
        let mut seen = [0usize; 5];
        for seed in 0..40u64 {
            let (a, b, l, u) = tresca(m, seed);
            let (kkt, others) = brute_force(&a, &b, &l, &u);
            assert!(!kkt.is_empty(), "seed {seed}: no KKT point");
            for k in &kkt[1..] {
                assert!(
                    max_diff(k, &kkt[0]) <= 1e-10,
                    "seed {seed}: KKT points differ"
                );
            }
            assert!(kkt.len() + others.len() <= 729 && kkt.len() + others.len() == 216);
            let exact = &kkt[0];
            let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
            assert!(
                sol.report.converged,
                "seed {seed}: {}",
                sol.report.stopping_reason
            );
            let x = &sol.lambda;
            assert!((0..2 * m).all(|i| x[i] >= l[i] && x[i] <= u[i]));
            let d = max_diff(x, exact);
            assert!(d <= 1e-10, "seed {seed}: ‖x − x_bf‖∞ = {d:.3e}");
            for i in 0..m {
                seen[if x[i] == 0.0 { 0 } else { 1 }] += 1;
                let t = m + i;
                seen[if x[t] == l[t] {
                    2
                } else if x[t] == u[t] {
                    4
                } else {
                    3
                }] += 1;
            }
        }
        eprintln!("Tresca statuses over 40 seeds [n=0, n free, t=−g, t free, t=+g]: {seen:?}");
        assert!(seen.iter().all(|&c| c > 0), "{seen:?}");
    }

    #[test]
    fn box_qp_with_fixed_and_two_sided_bounds_matches_brute_force() {
        let opts = tight();
        let (a, b, mut l, mut u) = tresca(3, 77);
        // Fix one tangential variable, bound a normal one from above, free one
        // variable on both sides.
        l[4] = 0.1;
        u[4] = 0.1;
        u[1] = 0.05;
        l[5] = -INF;
        u[5] = INF;
        let (kkt, _) = brute_force(&a, &b, &l, &u);
        let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
        assert!(sol.report.converged, "{}", sol.report.stopping_reason);
        assert_eq!(sol.lambda[4], 0.1);
        let d = max_diff(&sol.lambda, &kkt[0]);
        assert!(d <= 1e-10, "‖x − x_bf‖∞ = {d:.3e}");
    }

    #[test]
    fn box_qp_all_fixed_returns_the_bounds() {
        let mut rng = Rng::new(5);
        let a = random_spd(7, &mut rng);
        let b = random_vec(7, &mut rng);
        let l = random_vec(7, &mut rng);
        let sol = mprgp_box(&a, &b, &l, &l, &tight()).unwrap();
        assert!(sol.report.converged, "{}", sol.report.stopping_reason);
        assert_eq!(sol.lambda, l);
        assert_eq!(sol.report.iterations, 0);
        assert_eq!(sol.report.residual_history, vec![0.0]);
        assert_eq!(box_residual(&a, &b, &l, &l, &l, &tight()), 0.0);
    }

    #[test]
    fn box_qp_unbounded_semidefinite_is_singular() {
        let opts = tight();
        // A = [[1, −1], [−1, 1]] (null vector (1, 1)), b = (−1, −1):
        // f(t, t) = −2t → −∞ on x ≥ 0.
        let a = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { 1.0 } else { -1.0 });
        let b = [-1.0, -1.0];
        let r = mprgp_box(&a, &b, &[0.0, 0.0], &[INF, INF], &opts);
        assert!(matches!(r, Err(ContactError::Singular(_))), "{r:?}");
        assert!(!format!("{:?}", r.unwrap_err()).contains("NaN"));
        // Tresca-like: the tangential pair unbounded on both sides.
        let r = mprgp_box(&a, &[0.5, 0.5], &[-INF, -INF], &[INF, INF], &opts);
        assert!(matches!(r, Err(ContactError::Singular(_))), "{r:?}");
        // A = 0 with b pointing to an infinite bound.
        let r = mprgp_box(
            &Mat::zeros(2, 2),
            &[-1.0, 1.0],
            &[0.0, 0.0],
            &[INF, 3.0],
            &opts,
        );
        assert!(matches!(r, Err(ContactError::Singular(_))), "{r:?}");
        // The same A = 0 with finite bounds: x = (l_0, u_1).
        let sol = mprgp_box(
            &Mat::zeros(2, 2),
            &[1.0, -1.0],
            &[0.0, 0.0],
            &[2.0, 3.0],
            &opts,
        )
        .unwrap();
        assert!(sol.report.converged);
        assert_eq!(sol.lambda, vec![0.0, 3.0]);
        // Semi-definite but bounded by u_1 = 5: x = (6, 5).
        let sol = mprgp_box(&a, &b, &[0.0, 0.0], &[INF, 5.0], &opts).unwrap();
        assert!(sol.report.converged, "{}", sol.report.stopping_reason);
        assert_close(&sol.lambda, &[6.0, 5.0], 1e-12, "bounded semi-definite");
        assert_eq!(
            box_residual(&a, &b, &[6.0, 5.0], &[0.0, 0.0], &[INF, 5.0], &opts),
            0.0
        );
    }

    #[test]
    fn box_residual_is_zero_exactly_at_the_solution() {
        let opts = tight();
        // Exactly representable: x* = (1, 0.5, −0.25), x_0 and x_2 free,
        // x_1 at its upper bound with g_1 = −1.
        let a = Mat::<f64>::from_fn(3, 3, |i, j| {
            [[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]][i][j]
        });
        let b = [-4.5, -3.25, 0.0];
        let (l, u) = ([0.0, -0.5, -1.0], [INF, 0.5, 1.0]);
        let xs = [1.0, 0.5, -0.25];
        assert_eq!(box_residual(&a, &b, &xs, &l, &u, &opts), 0.0);
        let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
        assert!(sol.report.converged);
        assert_close(&sol.lambda, &xs, 1e-14, "exact case");
        // Perturbations: free variable moved, bound variable moved inward,
        // a point outside the box.
        for (i, dx, expected) in [(0, 1e-3, 4e-3), (1, -1e-3, 1e-3), (2, -1.0, 1.8)] {
            let mut y = xs;
            y[i] += dx;
            let r = box_residual(&a, &b, &y, &l, &u, &opts);
            assert!(
                (r - expected).abs() <= 1e-12,
                "x_{i} + {dx}: residual {r:e}, expected {expected:e}"
            );
        }
        // Random Tresca problem: round-off zero at the brute-force solution,
        // positive at every other candidate of the enumeration.
        let (a, b, l, u) = tresca(3, 3);
        let (kkt, others) = brute_force(&a, &b, &l, &u);
        let r = box_residual(&a, &b, &kkt[0], &l, &u, &opts);
        assert!(r <= 1e-15, "at the solution: {r:e}");
        let rmin = others
            .iter()
            .filter(|x| max_diff(x, &kkt[0]) > 1e-12)
            .map(|x| box_residual(&a, &b, x, &l, &u, &opts))
            .fold(INF, f64::min);
        eprintln!("box_residual at the solution {r:.2e}, smallest elsewhere {rmin:.3e}");
        assert!(rmin > 1e-6, "{rmin:e}");
        // Non-finite data.
        assert_eq!(box_residual(&a, &b, &[f64::NAN; 6], &l, &u, &opts), INF);
    }

    #[test]
    fn box_qp_converges_on_many_tresca_and_semidefinite_problems() {
        let opts = tight();
        let mut worst_iterations = 0;
        for seed in 0..200u64 {
            let m = 1 + (seed as usize) % 15;
            let (a, b, l, u) = tresca(m, 1000 + seed);
            let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
            assert!(
                sol.report.converged,
                "seed {seed}: {}",
                sol.report.stopping_reason
            );
            assert!((0..2 * m).all(|i| sol.lambda[i] >= l[i] && sol.lambda[i] <= u[i]));
            let r = box_residual(&a, &b, &sol.lambda, &l, &u, &opts);
            assert!(r <= 1e-12, "seed {seed}: residual {r:e}");
            assert_eq!(sol.report.residual_history.last(), Some(&r));
            worst_iterations = worst_iterations.max(sol.report.iterations);
            // Rank-deficient A = C Cᵀ (C is 2m × m) in the finite box [−1, 1]:
            // bounded, so it must converge.
            let mut rng = Rng::new(seed);
            let c = Mat::<f64>::from_fn(2 * m, m, |_, _| rng.uniform());
            let s = &c * c.transpose();
            let s = Mat::<f64>::from_fn(2 * m, 2 * m, |i, j| 0.5 * (s[(i, j)] + s[(j, i)]));
            let (lo, hi) = (vec![-1.0; 2 * m], vec![1.0; 2 * m]);
            let sol = mprgp_box(&s, &b, &lo, &hi, &opts).unwrap();
            assert!(
                sol.report.converged,
                "semi-definite seed {seed}: {}",
                sol.report.stopping_reason
            );
            let r = box_residual(&s, &b, &sol.lambda, &lo, &hi, &opts);
            assert!(r <= 1e-12, "semi-definite seed {seed}: residual {r:e}");
        }
        eprintln!("Tresca m ≤ 15, 200 seeds: at most {worst_iterations} iterations");
    }

    #[test]
    fn box_qp_rejects_bad_input_and_reports_the_limit() {
        let opts = LcpOptions::default();
        let a = Mat::<f64>::identity(3, 3);
        let b = [1.0, -1.0, 0.5];
        for (l, u, idx) in [
            ([0.0, 2.0, 0.0], [1.0, 1.0, 1.0], "[1]"),
            ([0.0, 0.0, f64::NAN], [1.0, 1.0, 1.0], "[2]"),
            ([INF, 0.0, 0.0], [INF, 1.0, 1.0], "[0]"),
            ([0.0, 0.0, 0.0], [1.0, -INF, 1.0], "[1]"),
        ] {
            match mprgp_box(&a, &b, &l, &u, &opts) {
                Err(ContactError::Solve(msg)) => assert!(msg.contains(idx), "{msg}"),
                other => panic!("{other:?}"),
            }
        }
        match mprgp_box(&a, &[1.0, f64::INFINITY, 0.0], &[0.0; 3], &[1.0; 3], &opts) {
            Err(ContactError::Solve(msg)) => assert!(msg.contains("b[1]"), "{msg}"),
            other => panic!("{other:?}"),
        }
        // Iteration limit on a Tresca problem: Ok, not converged, in the box.
        let (a, b, l, u) = tresca(20, 9);
        let sol = mprgp_box(
            &a,
            &b,
            &l,
            &u,
            &LcpOptions {
                tolerance: 1e-14,
                max_iterations: 2,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(!sol.report.converged);
        assert!(sol.report.stopping_reason.contains("not converged"));
        assert_eq!(sol.report.iterations, 2);
        assert!((0..40).all(|i| sol.lambda[i] >= l[i] && sol.lambda[i] <= u[i]));
        // Larger Tresca problem: converges to the tolerance.
        let sol = mprgp_box(&a, &b, &l, &u, &tight()).unwrap();
        assert!(sol.report.converged, "{}", sol.report.stopping_reason);
        assert!(box_residual(&a, &b, &sol.lambda, &l, &u, &tight()) <= 1e-12);
        eprintln!("Tresca m = 20: {}", sol.report.stopping_reason);
    }
}
