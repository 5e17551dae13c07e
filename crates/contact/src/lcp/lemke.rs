//! Lemke's complementary pivoting (course notes §3.4: "méthode directe de pivotage
//! où les conditions unilatérales sont prises en compte pendant la
//! factorisation"; docs/theory/algorithms.md) for the frictionless LCP(W, q),
//!
//! ```text
//! λ ≥ 0,   w = W λ + q ≥ 0,   λ·w = 0.
//! ```
//!
//! An artificial variable z0 ≥ 0 with the covering vector d = 1 gives the
//! augmented system
//!
//! ```text
//! w − W λ − d z0 = q,     w, λ, z0 ≥ 0,   λ·w = 0,
//! ```
//!
//! solved in a dense tableau [I | −W | −d | q] (the first m columns hold B⁻¹,
//! the inverse of the current basis). Start: the basis is w (λ = 0); if
//! q ≥ 0 that is the answer. Otherwise z0 enters at the row of the most
//! negative q_i (all w ≥ 0 then), and each later pivot brings in the
//! complement of the variable that just left (w_i ↔ λ_i), the leaving row
//! chosen by the minimum-ratio test, until z0 leaves: the basis then is
//! complementary and feasible, a solution. If the entering column has no
//! positive entry the path ends on a ray: for W positive semi-definite
//! (copositive-plus) this proves that the LCP has no solution.
//!
//! The pivoting runs on the problem scaled to unit diagonal and ‖q‖∞ = 1
//! (W̃ = D W D, q̃ = D q / β, D_ii = W_ii^(−1/2)), and λ = β D λ̃ is scaled
//! back: the tableau then mixes no units (on W as assembled, the columns of
//! B⁻¹ hold compliances, stiffnesses and pure numbers side by side, and a
//! tolerance relative to the largest entry of a column zeroed the pivots of
//! a stiff material), and the same scene in any units pivots the same way.
//!
//! The ratio test is lexicographic (ties in rhsᵢ/colᵢ broken by the rows of
//! B⁻¹ divided by colᵢ, then by the smallest basic-variable index), with a
//! relative pivot tolerance, which prevents cycling on degenerate problems
//! (weakly active points: λ_p = w_p = 0).
//!
//! Polish: the pivoting accumulates round-off, so on the active set of the
//! final basis A = {p : λ_p basic and > 0} the forces are recomputed from
//! W_AA λ_A = −q_A (faer Cholesky, full-pivoting LU as fallback); the polished
//! forces are kept if their natural residual is not worse.

use faer::Mat;

use crate::lcp::clamp;
use crate::lcp::{checked_or_empty, lcp_residual, time_limit_stop, LcpOptions};
use crate::solution::{ContactSolution, SolverReport, StopReason};
use crate::ContactError;

/// Relative pivot tolerance: column entries below `PIVOT_TOL` × the largest
/// entry of the column are treated as zero.
const PIVOT_TOL: f64 = 1e-11;

/// Relative tolerance for ties in the ratio test.
const TIE_TOL: f64 = 1e-12;

/// Entries of a column below `ZERO_TOL` × the largest |W̃_ij| of its original
/// column (1 for a gap column) are zero: relative to the scaled problem
/// ([`Scaling`], unit diagonal and ‖q̃‖∞ = 1), whose entries are O(1)
/// whatever the units of W and q.
const ZERO_TOL: f64 = 1e-14;

/// Lemke's method with covering vector d = 1 (see the module documentation).
///
/// `report.iterations` and `report.operator_applications` are the number of
/// pivots (each pivot touches the whole tableau, O(m²)); at most
/// `opts.max_iterations.max(10 m)` pivots are made (reaching the cap is
/// `Ok` with `converged = false`). `residual_history` holds one entry, the
/// natural residual of the returned forces. Ray termination is
/// [`ContactError::Singular`].
pub fn lemke(w: &Mat<f64>, q: &[f64], opts: &LcpOptions) -> Result<ContactSolution, ContactError> {
    const METHOD: &str = "lemke";
    if let Some(empty) = checked_or_empty(w, q, METHOD)? {
        return Ok(empty);
    }
    let m = q.len();
    let mut report = SolverReport {
        method: METHOD.into(),
        ..Default::default()
    };
    if q.iter().all(|&v| v >= 0.0) {
        let lambda = vec![0.0; m];
        report
            .residual_history
            .push(lcp_residual(w, q, &lambda, opts));
        report.converged = true;
        report.stop = StopReason::NoPivot;
        return Ok(ContactSolution::from_forces(w, q, lambda, report));
    }
    let max_pivots = opts.max_iterations.max(10 * m);
    let scaling = Scaling::new(w, q);
    let (scaled, solved, pivots) = pivot_path(&scaling.w, &scaling.q, max_pivots, opts)?;
    report.iterations = pivots;
    report.operator_applications = pivots;
    let mut lambda = scaling.forces(&scaled);
    let mut polished = false;
    if solved {
        let active: Vec<usize> = (0..m).filter(|&p| lambda[p] > 0.0).collect();
        if let Some(candidate) = polish(w, q, &active) {
            let r_piv = lcp_residual(w, q, &lambda, opts);
            let r_pol = lcp_residual(w, q, &candidate, opts);
            if r_pol <= r_piv {
                lambda = candidate;
                polished = true;
            }
        }
    }
    let lambda = clamp(lambda);
    let res = lcp_residual(w, q, &lambda, opts);
    report.residual_history.push(res);
    let tolerance = opts.tolerance;
    report.converged = solved && res <= tolerance;
    report.stop = if !solved && pivots < max_pivots {
        time_limit_stop(&report, res)
    } else if !solved {
        StopReason::PivotLimit {
            limit: max_pivots,
            residual: res,
        }
    } else if report.converged {
        StopReason::Pivoted {
            pivots,
            residual: res,
            tolerance,
            polished,
        }
    } else {
        StopReason::PivotedAboveTolerance {
            pivots,
            residual: res,
            tolerance,
        }
    };
    Ok(ContactSolution::from_forces(w, q, lambda, report))
}

/// The points with a force in the solution of LCP(W, q) by [`lemke`], with
/// the equilibrium Gᵀλ = e of floating bodies when G has columns (SMALBE
/// with Lemke's method inside, [`crate::lcp::smalbe`]): the way out of a cycle
/// of the status method, whose next iteration solves on this set and checks
/// it. `None` when the method did not converge.
pub(crate) fn pivoted_active_set(
    w: &Mat<f64>,
    q: &[f64],
    (g, e): (&Mat<f64>, &[f64]),
    opts: &LcpOptions,
) -> Result<Option<Vec<usize>>, ContactError> {
    let sol = if g.ncols() == 0 {
        lemke(w, q, opts)?
    } else {
        crate::lcp::smalbe::smalbe(w, q, g, e, opts, |wi, qi, _, o| lemke(wi, qi, o))?
    };
    if !sol.report.converged {
        return Ok(None);
    }
    let largest = sol.forces.iter().fold(0.0f64, |a, f| a.max(f.abs()));
    let zero = opts.tolerance * opts.force_scale.max(largest);
    Ok(Some(
        (0..q.len()).filter(|&p| sol.forces[p] > zero).collect(),
    ))
}

/// The complementary pivoting path on the scaled LCP(W, q) from z0 entering
/// at the most negative q_i, at most `max_pivots` pivots and until the
/// deadline of `opts`: the forces of the final basis, whether z0 left it (a
/// solution), and the pivots made. A ray is [`ContactError::Singular`].
fn pivot_path(
    w: &Mat<f64>,
    q: &[f64],
    max_pivots: usize,
    opts: &LcpOptions,
) -> Result<(Vec<f64>, bool, usize), ContactError> {
    let m = q.len();
    let mut tab = Tableau::new(w, q);
    let z0 = 2 * m;
    // First pivot: z0 enters at the lexicographic minimum of the rows
    // (q_i, e_i), i.e. the most negative q_i (ties: the largest index, which
    // keeps every row lexicographically positive).
    let qmin = q.iter().copied().fold(f64::INFINITY, f64::min);
    let r = (0..m)
        .rev()
        .find(|&i| q[i] <= qmin + TIE_TOL * qmin.abs())
        .unwrap_or(0);
    let mut leaving = tab.pivot(r, z0);
    let mut pivots = 1;
    while pivots < max_pivots && leaving != z0 && !opts.out_of_time(pivots) {
        // The complement of the variable that left enters.
        let entering = if leaving < m {
            leaving + m
        } else {
            leaving - m
        };
        let Some(row) = tab.ratio_test(entering) else {
            return Err(ContactError::Singular(format!(
                "Lemke's method ended on a ray after {pivots} pivots: {} (point {}) can grow without bound, so LCP(W, q) has no solution for this q — W is singular or not positive semi-definite (redundant or inconsistent contact constraints, or a body free to move away from its contacts)",
                if entering < m { "the gap w" } else { "the force λ" },
                entering % m
            )));
        };
        leaving = tab.pivot(row, entering);
        pivots += 1;
    }
    let mut lambda = vec![0.0; m];
    for (i, &b) in tab.basis.iter().enumerate() {
        if (m..2 * m).contains(&b) {
            lambda[b - m] = tab.rhs(i).max(0.0);
        }
    }
    Ok((lambda, leaving == z0, pivots))
}

/// The LCP(W, q) in units of the problem: W̃ = D W D with unit diagonal
/// (D_ii = W_ii^(−1/2)) and q̃ = D q / β with ‖q̃‖∞ = 1 (β = ‖D q‖∞); its
/// solution λ̃ gives λ = β D λ̃ (w̃ = D w / β: the positive scalings keep
/// λ ≥ 0, w ≥ 0, λ·w = 0). Replacing W by s W and q by t q leaves W̃ and q̃
/// unchanged, hence the pivot sequence and the tolerances of the tableau,
/// which can then be relative to 1. A point with W_ii ≤ 0 (no compliance of
/// its own) is scaled by the largest diagonal entry.
struct Scaling {
    d: Vec<f64>,
    beta: f64,
    w: Mat<f64>,
    q: Vec<f64>,
}

impl Scaling {
    fn new(w: &Mat<f64>, q: &[f64]) -> Self {
        let m = q.len();
        let dmax = (0..m).map(|i| w[(i, i)]).fold(0.0, f64::max);
        let d: Vec<f64> = (0..m)
            .map(|i| {
                let wii = if w[(i, i)] > 0.0 { w[(i, i)] } else { dmax };
                if wii > 0.0 {
                    1.0 / wii.sqrt()
                } else {
                    1.0
                }
            })
            .collect();
        let dq: Vec<f64> = q.iter().zip(&d).map(|(qi, di)| qi * di).collect();
        let qmax = dq.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let beta = if qmax > 0.0 { qmax } else { 1.0 };
        Self {
            w: Mat::from_fn(m, m, |i, j| d[i] * w[(i, j)] * d[j]),
            q: dq.iter().map(|v| v / beta).collect(),
            d,
            beta,
        }
    }

    /// λ = β D λ̃.
    fn forces(&self, scaled: &[f64]) -> Vec<f64> {
        scaled
            .iter()
            .zip(&self.d)
            .map(|(l, di)| self.beta * di * l)
            .collect()
    }
}

/// λ_A = −W_AA⁻¹ q_A on `active`, 0 elsewhere; `None` if the solve fails or
/// is not finite.
fn polish(w: &Mat<f64>, q: &[f64], active: &[usize]) -> Option<Vec<f64>> {
    let m = q.len();
    let na = active.len();
    let mut lambda = vec![0.0; m];
    if na == 0 {
        return Some(lambda);
    }
    let a = Mat::<f64>::from_fn(na, na, |i, j| w[(active[i], active[j])]);
    let rhs = Mat::<f64>::from_fn(na, 1, |i, _| -q[active[i]]);
    let x = signorini_linalg::pivot_policy::solve_symmetric_checked(&a, &rhs, "W_AA").ok()?;
    for (i, &p) in active.iter().enumerate() {
        if !x[(i, 0)].is_finite() {
            return None;
        }
        lambda[p] = x[(i, 0)].max(0.0);
    }
    Some(lambda)
}

/// Dense tableau [B⁻¹ | −B⁻¹W | −B⁻¹d | B⁻¹q], row-major; variables
/// 0..m are w, m..2m are λ, 2m is z0.
struct Tableau {
    m: usize,
    ncols: usize,
    t: Vec<f64>,
    basis: Vec<usize>,
    /// Scale of each original column (for the zero test of [`ZERO_TOL`]).
    col_scale: Vec<f64>,
}

impl Tableau {
    fn new(w: &Mat<f64>, q: &[f64]) -> Self {
        let m = q.len();
        let ncols = 2 * m + 2;
        let mut t = vec![0.0; m * ncols];
        for i in 0..m {
            let row = &mut t[i * ncols..(i + 1) * ncols];
            row[i] = 1.0;
            for j in 0..m {
                row[m + j] = -w[(i, j)];
            }
            row[2 * m] = -1.0;
            row[2 * m + 1] = q[i];
        }
        let mut col_scale = vec![1.0; 2 * m + 1];
        for j in 0..m {
            col_scale[m + j] = (0..m).map(|i| w[(i, j)].abs()).fold(0.0, f64::max);
        }
        Self {
            m,
            ncols,
            t,
            basis: (0..m).collect(),
            col_scale,
        }
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.t[i * self.ncols + j]
    }

    fn rhs(&self, i: usize) -> f64 {
        self.at(i, self.ncols - 1)
    }

    /// Gauss–Jordan pivot on (r, c); returns the variable that left.
    fn pivot(&mut self, r: usize, c: usize) -> usize {
        let nc = self.ncols;
        let piv = self.t[r * nc + c];
        for v in &mut self.t[r * nc..(r + 1) * nc] {
            *v /= piv;
        }
        self.t[r * nc + c] = 1.0;
        let (before, rest) = self.t.split_at_mut(r * nc);
        let (prow, after) = rest.split_at_mut(nc);
        for row in before
            .chunks_exact_mut(nc)
            .chain(after.chunks_exact_mut(nc))
        {
            let f = row[c];
            if f != 0.0 {
                for (x, p) in row.iter_mut().zip(prow.iter()) {
                    *x -= f * p;
                }
                row[c] = 0.0;
            }
        }
        std::mem::replace(&mut self.basis[r], c)
    }

    /// Lexicographic minimum-ratio test for the entering column c; `None` on
    /// a ray (no positive entry).
    fn ratio_test(&self, c: usize) -> Option<usize> {
        let m = self.m;
        let col_max = (0..m).map(|i| self.at(i, c).abs()).fold(0.0, f64::max);
        let tol = (PIVOT_TOL * col_max).max(ZERO_TOL * self.col_scale[c]);
        let rows: Vec<usize> = (0..m)
            .filter(|&i| self.at(i, c) > tol && self.at(i, c) > 0.0)
            .collect();
        if rows.is_empty() {
            return None;
        }
        let ratio = |i: usize, k: Option<usize>| -> f64 {
            let num = match k {
                None => self.rhs(i).max(0.0),
                Some(k) => self.at(i, k),
            };
            num / self.at(i, c)
        };
        // Keep the rows that tie for the minimum of rhs/col, then of each
        // column of B⁻¹ in turn.
        let mut ties = rows;
        for k in std::iter::once(None).chain((0..m).map(Some)) {
            if ties.len() == 1 {
                break;
            }
            let vals: Vec<f64> = ties.iter().map(|&i| ratio(i, k)).collect();
            let min = vals.iter().copied().fold(f64::INFINITY, f64::min);
            let spread = vals.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let keep: Vec<usize> = ties
                .iter()
                .zip(&vals)
                .filter(|(_, &v)| v <= min + TIE_TOL * spread.max(f64::MIN_POSITIVE))
                .map(|(&i, _)| i)
                .collect();
            ties = keep;
            if k.is_none() {
                // z0 leaving ends the path: prefer it among the ties.
                if let Some(&i) = ties.iter().find(|&&i| self.basis[i] == 2 * m) {
                    return Some(i);
                }
            }
        }
        ties.into_iter().min_by_key(|&i| self.basis[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::projected_gradient::test_support::*;

    #[test]
    fn lemke_agrees_with_the_status_method() {
        let (it, ops) = agrees_with_status_method(lemke);
        eprintln!("lemke: {it} pivots on the m = 60 random case");
        assert!(it > 0 && ops == it);
    }

    #[test]
    fn lemke_on_redundant_constraints_is_right_or_a_clear_error() {
        redundant_constraints(lemke, true);
    }

    #[test]
    fn lemke_pivots_the_same_way_in_any_units() {
        // Exactly the same pivots: the tableau is that of the scaled problem.
        scale_invariant(lemke, 0);
    }

    #[test]
    fn lemke_edge_cases() {
        edge_cases(lemke);
    }

    #[test]
    fn lemke_reports_a_ray_when_there_is_no_solution() {
        // W = 0, q_0 < 0: no force closes the gap.
        let w = Mat::<f64>::zeros(2, 2);
        let err = lemke(&w, &[-1.0, 1.0], &LcpOptions::default()).unwrap_err();
        assert!(matches!(err, ContactError::Singular(_)));
        assert!(err.to_string().contains("ray"), "{err}");
    }

    #[test]
    fn lemke_two_by_two_by_hand() {
        // W = [2 1; 1 2], q = (−1, 1): λ = (1/2, 0), w = (0, 3/2); two pivots
        // (z0 in, then λ_0 in and z0 out).
        let w = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { 2.0 } else { 1.0 });
        let sol = lemke(&w, &[-1.0, 1.0], &tight()).unwrap();
        assert!(sol.report.converged);
        assert_eq!(sol.report.iterations, 2);
        assert_eq!(sol.forces, vec![0.5, 0.0]);
    }
}
