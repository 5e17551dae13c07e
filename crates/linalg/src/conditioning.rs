//! Condition estimates of the symmetric positive definite operators of the
//! pipeline (K_II per subdomain, S at the root, the Delassus operator W).
//!
//! κ₁(A) = ‖A‖₁ ‖A⁻¹‖₁: ‖A‖₁ (the largest absolute column sum) is computed
//! exactly, ‖A⁻¹‖₁ is estimated by the Hager–Higham estimator (Hager 1984;
//! Higham 1988, the algorithm of LAPACK's `dlacon`/`dlacn2`) from a handful
//! of solves with a factorisation that already exists: about 4 to 11 solves,
//! O(n²) each for a dense factor, against O(n³) for the factorisation. The
//! estimate is a lower bound of ‖A⁻¹‖₁, in practice within a factor 3 of it
//! (usually exact).
//!
//! The number of decimal digits a solve with A may lose is log10 κ: a double
//! carries [`F64_DIGITS`] = −log10 ε ≈ 15.65 of them.

use faer::{MatRef, Side};

/// Decimal digits of an f64, −log10(ε) ≈ 15.65.
pub const F64_DIGITS: f64 = 15.653_559_774_527_023;

/// Largest number of iterations of the estimator (LAPACK's ITMAX).
const MAX_ITERATIONS: usize = 5;

/// Estimates ‖A⁻¹‖₁ for a nonsingular *symmetric* n × n matrix A, given
/// `solve`, which overwrites its argument x by A⁻¹ x. Symmetry lets the same
/// solve serve for A⁻ᵀ (Hager's algorithm needs both). Returns a lower bound
/// of ‖A⁻¹‖₁ (0 for n = 0), usually equal to it and within a factor 3 in
/// practice; a non-finite value when a solve produced one.
pub fn inverse_norm1_estimate(n: usize, mut solve: impl FnMut(&mut [f64])) -> f64 {
    if n == 0 {
        return 0.0;
    }
    let sign = |v: f64| if v >= 0.0 { 1.0 } else { -1.0 };
    let norm1 = |x: &[f64]| x.iter().map(|v| v.abs()).sum::<f64>();
    let argmax = |x: &[f64]| {
        let mut j = 0;
        for (i, v) in x.iter().enumerate() {
            if v.abs() > x[j].abs() {
                j = i;
            }
        }
        j
    };
    let mut x = vec![1.0 / n as f64; n];
    solve(&mut x);
    if n == 1 {
        return x[0].abs();
    }
    let mut est = norm1(&x);
    if !est.is_finite() {
        return est;
    }
    let mut signs: Vec<f64> = x.iter().map(|&v| sign(v)).collect();
    let mut z = signs.clone();
    solve(&mut z);
    let mut j = argmax(&z);
    let mut iteration = 2;
    loop {
        x.iter_mut().for_each(|v| *v = 0.0);
        x[j] = 1.0;
        solve(&mut x);
        let previous = est;
        est = norm1(&x);
        if !est.is_finite() {
            return est;
        }
        let new_signs: Vec<f64> = x.iter().map(|&v| sign(v)).collect();
        // A repeated sign vector, or no growth: converged.
        if new_signs == signs || est <= previous {
            break;
        }
        signs = new_signs;
        z.copy_from_slice(&signs);
        solve(&mut z);
        let last = j;
        j = argmax(&z);
        if z[last] == z[j].abs() || iteration >= MAX_ITERATIONS {
            break;
        }
        iteration += 1;
    }
    // Higham's alternative vector guards against the cases where the
    // gradient steps are misled (x_i = ±(1 + (i−1)/(n−1)), alternating).
    for (i, v) in x.iter_mut().enumerate() {
        let s = if i % 2 == 0 { 1.0 } else { -1.0 };
        *v = s * (1.0 + i as f64 / (n - 1) as f64);
    }
    solve(&mut x);
    let alternative = 2.0 * norm1(&x) / (3.0 * n as f64);
    if alternative > est || !alternative.is_finite() {
        est = alternative;
    }
    est
}

/// ‖A‖₁, the largest absolute column sum of a dense matrix.
pub fn dense_norm1(a: MatRef<'_, f64>) -> f64 {
    (0..a.ncols())
        .map(|j| (0..a.nrows()).map(|i| a[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// κ₁ estimate of a dense symmetric matrix by a dense Cholesky factorisation:
/// `None` when the Cholesky fails (the matrix is not numerically positive
/// definite: singular or indefinite).
pub fn dense_spd_condition(a: MatRef<'_, f64>) -> Option<f64> {
    let n = a.nrows();
    if n == 0 {
        return Some(1.0);
    }
    let llt = a.llt(Side::Lower).ok()?;
    let norm = dense_norm1(a);
    let inv = inverse_norm1_estimate(n, |x| {
        llt_solve(&llt, x);
    });
    Some(norm * inv)
}

/// x ← A⁻¹ x with a dense Cholesky factor of A.
pub fn llt_solve(llt: &faer::linalg::solvers::Llt<f64>, x: &mut [f64]) {
    use faer::linalg::solvers::SolveCore;
    let n = x.len();
    let xm = faer::MatMut::from_column_major_slice_mut(x, n, 1);
    llt.solve_in_place_with_conj(faer::Conj::No, xm);
}

/// Decimal digits a solve with condition number κ may lose, log10 κ (0 for
/// κ ≤ 1; +∞ for a singular or unknown κ = +∞).
pub fn digits_lost(kappa: f64) -> f64 {
    if kappa.is_nan() {
        return f64::INFINITY;
    }
    kappa.max(1.0).log10()
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// Exact κ₁ of a small dense symmetric positive definite matrix through its
    /// explicit inverse (for tests of the estimator).
    fn exact_condition_dense(a: &Mat<f64>) -> f64 {
        let n = a.nrows();
        let llt = a.llt(Side::Lower).expect("positive definite");
        let mut inv = Mat::<f64>::identity(n, n);
        faer::linalg::solvers::SolveCore::solve_in_place_with_conj(
            &llt,
            faer::Conj::No,
            inv.as_mut(),
        );
        dense_norm1(a.as_ref()) * dense_norm1(inv.as_ref())
    }

    /// The estimate against a known ‖A⁻¹‖₁: a lower bound (up to rounding)
    /// within a factor 3.
    fn assert_close_below(est: f64, exact: f64) {
        assert!(
            est <= exact * (1.0 + 1e-8),
            "estimate {est:e} above the exact {exact:e}"
        );
        assert!(
            est >= exact / 3.0,
            "estimate {est:e} below a third of the exact {exact:e}"
        );
    }

    fn estimate_dense(a: &Mat<f64>) -> f64 {
        dense_spd_condition(a.as_ref()).expect("positive definite")
    }

    #[test]
    fn diagonal_matrix_is_estimated_exactly() {
        let d = [3.0, 1e-3, 7.0, 250.0, 0.5];
        let a = Mat::<f64>::from_fn(5, 5, |i, j| if i == j { d[i] } else { 0.0 });
        // κ₁ = max d / min d
        let exact = 250.0 / 1e-3;
        let est = estimate_dense(&a);
        assert!((est - exact).abs() <= 1e-10 * exact, "{est:e} vs {exact:e}");
        // and a 1 × 1 matrix
        let one = Mat::<f64>::from_fn(1, 1, |_, _| 4.0);
        assert!((estimate_dense(&one) - 1.0).abs() < 1e-15);
    }

    /// Hilbert matrix H_ij = 1/(i+j−1) (1-based) and its exact inverse
    /// (H⁻¹)_ij = (−1)^{i+j} (i+j−1) C(n+i−1, n−j) C(n+j−1, n−i) C(i+j−2, i−1)².
    fn hilbert(n: usize) -> (Mat<f64>, Mat<f64>) {
        fn binom(n: u64, k: u64) -> f64 {
            let mut r = 1.0f64;
            for t in 0..k {
                r = r * (n - t) as f64 / (t + 1) as f64;
            }
            r.round()
        }
        let h = Mat::<f64>::from_fn(n, n, |i, j| 1.0 / (i + j + 1) as f64);
        let nn = n as u64;
        let inv = Mat::<f64>::from_fn(n, n, |i, j| {
            let (i, j) = (i as u64 + 1, j as u64 + 1);
            let s = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
            s * (i + j - 1) as f64
                * binom(nn + i - 1, nn - j)
                * binom(nn + j - 1, nn - i)
                * binom(i + j - 2, i - 1).powi(2)
        });
        (h, inv)
    }

    #[test]
    fn hilbert_6_condition_is_within_a_factor_3() {
        let (h, hinv) = hilbert(6);
        let exact = dense_norm1(h.as_ref()) * dense_norm1(hinv.as_ref());
        // The published κ₁(H_6) ≈ 2.907e7.
        assert!((exact / 2.907_028_8e7 - 1.0).abs() < 1e-6, "{exact:e}");
        let est = estimate_dense(&h);
        assert_close_below(est, exact);
        // The explicit-inverse helper agrees with the closed form.
        let via_inverse = exact_condition_dense(&h);
        assert!((via_inverse / exact - 1.0).abs() < 1e-6, "{via_inverse:e}");
    }

    #[test]
    fn laplacian_1d_condition_matches_the_closed_form() {
        // tridiag(−1, 2, −1), n × n: ‖A‖₁ = 4 and (A⁻¹)_ij =
        // min(i,j)(n+1−max(i,j))/(n+1), whose largest column sum (the middle
        // column) gives ‖A⁻¹‖₁; κ₁ grows like n² (h⁻²).
        let mut previous = 0.0;
        for n in [10usize, 41, 200] {
            let a = Mat::<f64>::from_fn(n, n, |i, j| {
                if i == j {
                    2.0
                } else if i.abs_diff(j) == 1 {
                    -1.0
                } else {
                    0.0
                }
            });
            let inv_norm = (1..=n)
                .map(|j| {
                    (1..=n)
                        .map(|i| (i.min(j) * (n + 1 - i.max(j))) as f64 / (n + 1) as f64)
                        .sum::<f64>()
                })
                .fold(0.0, f64::max);
            let exact = 4.0 * inv_norm;
            let est = estimate_dense(&a);
            assert_close_below(est, exact);
            // κ₁ = 4·‖A⁻¹‖₁ ≈ (n+1)²/2 for odd n.
            if n % 2 == 1 {
                assert!((exact / ((n + 1) as f64).powi(2) * 2.0 - 1.0).abs() < 1e-12);
            }
            assert!(est > previous);
            previous = est;
        }
    }

    #[test]
    fn random_spd_matrices_are_estimated_within_a_factor_3() {
        // A = Mᵀ M + δ I with a deterministic pseudo-random M, for several
        // sizes and conditionings.
        let mut seed = 12345u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for (n, delta) in [(8usize, 1e-1), (20, 1e-4), (35, 1e-7), (60, 1.0)] {
            let m = Mat::<f64>::from_fn(n, n, |_, _| rnd());
            let mut a = m.transpose() * &m;
            for i in 0..n {
                a[(i, i)] += delta;
            }
            let exact = exact_condition_dense(&a);
            let est = estimate_dense(&a);
            assert_close_below(est, exact);
        }
    }

    #[test]
    fn a_singular_matrix_has_no_cholesky_estimate() {
        // rank 1: [1 1; 1 1]
        let a = Mat::<f64>::from_fn(2, 2, |_, _| 1.0);
        assert!(dense_spd_condition(a.as_ref()).is_none());
    }

    #[test]
    fn digits_lost_is_log10_kappa() {
        assert_eq!(digits_lost(1e6), 6.0);
        assert_eq!(digits_lost(0.5), 0.0);
        assert_eq!(digits_lost(f64::INFINITY), f64::INFINITY);
        assert!((F64_DIGITS + f64::EPSILON.log10()).abs() < 1e-12);
    }
}
