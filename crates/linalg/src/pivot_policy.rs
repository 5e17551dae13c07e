//! One policy for a singular or redundant active block: every solve of the
//! status iterations (W_AA, the reduced block with slipping rows, the small
//! Schur complement of the floating bodies, the saddle-point system with
//! the rigid modes) trusts a factorisation by the same pivot test, written
//! here once.
//!
//! The test is scale-free: a pivot is measured against the largest pivot of
//! its factorisation, and a Cholesky pivot L_ii² first against the diagonal
//! entry A_ii it comes from (L_ii² / A_ii is the squared sine of the angle,
//! in the metric of A, between row i and the rows before it; these are the
//! pivots of D A D with unit diagonal, D = diag(A)^(-1/2)). A factorisation
//! whose smallest pivot is at most [`pivot_floor`]`(n)` = 1e3 · n · ε times
//! its largest is near singular (dependent, redundant constraints, or a
//! floating body the statuses do not hold). A fast path that meets such a
//! pivot steps aside; the last word is the rank test of [`solve_checked`], a
//! full-pivoting LU (rank revealing) on the matrix scaled to unit row
//! maxima, with the same floor, which names the rank deficiency.

use faer::prelude::Solve;
use faer::{Mat, Side};

use crate::LinalgError;

/// The relative pivot floor of a factorisation of order n: 1e3 · n · ε.
pub fn pivot_floor(n: usize) -> f64 {
    1e3 * n as f64 * f64::EPSILON
}

/// The pivots at or below [`pivot_floor`]`(n)` times the largest (NaN and
/// infinite pivots count as such), with the ratio of the smallest to the
/// largest; `None` when every pivot is safe.
pub fn deficient_pivots(pivots: impl Iterator<Item = f64>, n: usize) -> Option<(usize, f64)> {
    let pivots: Vec<f64> = pivots.map(f64::abs).collect();
    let hi = pivots.iter().fold(0.0f64, |m, &p| m.max(p));
    let lo = pivots.iter().fold(f64::INFINITY, |m, &p| m.min(p));
    let floor = pivot_floor(n) * hi;
    let bad = |p: f64| !p.is_finite() || !hi.is_finite() || p <= floor;
    let count = pivots.iter().filter(|&&p| bad(p)).count();
    (count > 0).then(|| (count, lo / hi.max(f64::MIN_POSITIVE)))
}

/// Whether every pivot of a factorisation of order `n` is safe
/// ([`deficient_pivots`] finds none).
pub fn pivots_are_safe(pivots: impl Iterator<Item = f64>, n: usize) -> bool {
    deficient_pivots(pivots, n).is_none()
}

/// Whether the pivots of a Cholesky factor L (its diagonal `l_diag`, some
/// or all of the rows) of a matrix of order `n` with diagonal `a_diag` are
/// safe: the pivots L_ii² / A_ii of the matrix scaled to unit diagonal,
/// whose largest is its first, 1, so that rows appended to a factor are
/// judged alone. NaN fails.
pub fn cholesky_pivots_are_safe(
    l_diag: impl Iterator<Item = f64>,
    a_diag: impl Iterator<Item = f64>,
    n: usize,
) -> bool {
    let floor = pivot_floor(n);
    l_diag.zip(a_diag).all(|(l, a)| l * l > floor * a)
}

/// The Cholesky factor of a symmetric `a` whose pivots are safe; `None` when
/// it is not positive definite or near singular.
pub fn safe_cholesky(a: &Mat<f64>) -> Option<faer::linalg::solvers::Llt<f64>> {
    let n = a.nrows();
    let llt = a.llt(Side::Lower).ok()?;
    let l = llt.L();
    cholesky_pivots_are_safe((0..n).map(|i| l[(i, i)]), (0..n).map(|i| a[(i, i)]), n).then_some(llt)
}

/// Solves a symmetric system by a Cholesky factor with safe pivots, else by
/// [`solve_checked`] (which rejects a singular matrix naming `what`).
pub fn solve_symmetric_checked(
    a: &Mat<f64>,
    rhs: &Mat<f64>,
    what: &str,
) -> Result<Mat<f64>, LinalgError> {
    match safe_cholesky(a) {
        Some(llt) => Ok(llt.solve(rhs)),
        None => solve_checked(a, rhs, what),
    }
}

/// Dense solve by full-pivoting LU, rejecting a (numerically) singular
/// matrix with the rank test of this policy, never returning the huge or NaN
/// "solution" of a singular system: the matrix is first scaled
/// symmetrically to unit row maxima (D A D, D_i = 1/sqrt(max_j |a_ij|), so
/// that the compliance block W and the dimensionless rigid-mode block G
/// compare in any units), then its pivots must be safe (full pivoting
/// orders them by decreasing size). A backward-error test alone cannot see
/// singularity: LU is backward stable on singular matrices too.
pub fn solve_checked(a: &Mat<f64>, rhs: &Mat<f64>, what: &str) -> Result<Mat<f64>, LinalgError> {
    let n = a.nrows();
    let (lu, d) = scaled_lu(a);
    if let Some((deficiency, ratio)) = rank_deficiency(&lu) {
        return Err(LinalgError::Singular(format!(
            "{what} (rank deficient by {deficiency} of {n}: smallest pivot {ratio:.1e} of the largest)"
        )));
    }
    let srhs = Mat::<f64>::from_fn(n, rhs.ncols(), |i, j| d[i] * rhs[(i, j)]);
    let y = lu.solve(&srhs);
    let x = Mat::<f64>::from_fn(n, rhs.ncols(), |i, j| d[i] * y[(i, j)]);
    if !x.norm_max().is_finite() {
        return Err(LinalgError::Singular(what.to_string()));
    }
    Ok(x)
}

/// Whether `a` is singular by the rank test of [`solve_checked`].
pub fn is_rank_deficient(a: &Mat<f64>) -> bool {
    a.nrows() > 0 && rank_deficiency(&scaled_lu(a).0).is_some()
}

/// The full-pivoting LU of D A D, D_i = 1/sqrt(max_j |a_ij|) (see
/// [`solve_checked`]), and D.
fn scaled_lu(a: &Mat<f64>) -> (faer::linalg::solvers::FullPivLu<f64>, Vec<f64>) {
    let n = a.nrows();
    let d: Vec<f64> = (0..n)
        .map(|i| {
            let m = (0..n).fold(0.0f64, |m, j| m.max(a[(i, j)].abs()));
            if m > 0.0 && m.is_finite() {
                1.0 / m.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    let scaled = Mat::<f64>::from_fn(n, n, |i, j| d[i] * a[(i, j)] * d[j]);
    (scaled.full_piv_lu(), d)
}

/// The rank test of [`solve_checked`] on the pivots of U.
fn rank_deficiency(lu: &faer::linalg::solvers::FullPivLu<f64>) -> Option<(usize, f64)> {
    let u = lu.U();
    let n = u.nrows();
    deficient_pivots((0..n).map(|i| u[(i, i)]), n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// W of two points on one row (dependent) and of two independent ones:
    /// every chain of the policy refuses the first and solves the second.
    #[test]
    fn one_test_refuses_a_dependent_row_in_every_factorisation() {
        let dependent = Mat::<f64>::from_fn(3, 3, |i, j| {
            let v = [[2.0, 1.0, 3.0], [1.0, 2.0, 3.0], [3.0, 3.0, 6.0]];
            v[i][j]
        });
        let regular = Mat::<f64>::from_fn(3, 3, |i, j| if i == j { 4.0 } else { 1.0 });
        let rhs = Mat::<f64>::from_fn(3, 1, |i, _| 1.0 + i as f64);
        assert!(safe_cholesky(&dependent).is_none());
        assert!(is_rank_deficient(&dependent));
        let lu = dependent.partial_piv_lu();
        assert!(!pivots_are_safe((0..3).map(|i| lu.U()[(i, i)]), 3));
        let err = solve_symmetric_checked(&dependent, &rhs, "W_AA").unwrap_err();
        assert!(
            err.to_string().contains("rank deficient by 1 of 3"),
            "{err}"
        );
        let x = solve_symmetric_checked(&regular, &rhs, "W_AA").unwrap();
        let r = &regular * &x - &rhs;
        assert!(r.norm_max() <= 1e3 * f64::EPSILON * 6.0 * x.norm_max());
        assert!(!is_rank_deficient(&regular));
    }

    /// The floor is relative: the same matrix in any units passes or fails
    /// alike, and a pivot below 1e3 n ε of the largest fails.
    #[test]
    fn the_floor_is_relative_to_the_largest_pivot() {
        for scale in [1e-9, 1.0, 1e9] {
            let p = [2.0 * scale, scale, 1e-13 * scale];
            assert_eq!(deficient_pivots(p.into_iter(), 3).map(|d| d.0), Some(1));
            let p = [2.0 * scale, scale, 1e-11 * scale];
            assert!(pivots_are_safe(p.into_iter(), 3));
        }
        assert!(!pivots_are_safe([1.0, f64::NAN].into_iter(), 2));
    }
}
