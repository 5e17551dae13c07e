//! The dense Cholesky factorisation of the root's SPD blocks (W_AA of the
//! status method, course notes §3.3; the symmetric part of the friction blocks,
//! §4.5), right-looking and recursive: with A split at about n/2,
//!
//! ```text
//!   L₁₁ L₁₁ᵀ = A₁₁,   L₂₁ = A₂₁ L₁₁⁻ᵀ,   L₂₂ L₂₂ᵀ = A₂₂ − L₂₁ L₂₁ᵀ
//! ```
//!
//! so that half of the n³/3 flops are one large triangular update and most
//! of the rest large triangular solves, both at the matrix-product rate;
//! blocks of at most [`BASE`] rows go to faer's blocked factorisation.
//! Measured on this project's 2-core machine at n = 1,650: 27–29 GFlop/s on
//! one core and 36–44 on two, against 16–20 and 24–30 for faer's
//! left-looking `cholesky_in_place` on the whole block.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::triangular::{matmul, BlockStructure};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, Par};

/// The order up to which a block goes to faer's factorisation, on one
/// thread.
const BASE: usize = 256;

/// The order below which the whole factorisation runs on one thread.
/// Measured on this project's 2-core machine (best of seven, a dense SPD
/// block): two threads took 2.3× the one thread's time at n = 400 and
/// 1.3× at 800 when every block was shared, 1.3× and 1.06× with the leaves
/// on one thread; from n = 1,100 sharing the products gains (0.95× at
/// 1,100, 0.72× at 2,000).
const SHARED_FROM: usize = 4 * BASE;

/// Overwrites the lower triangle of `a` (SPD; its strictly upper triangle is
/// not read) with L, L Lᵀ = A. `Err(i)`: the pivot of row i is not
/// positive (A is not positive definite); `a` is then partly overwritten.
pub fn cholesky(a: MatMut<'_, f64>, par: Par) -> Result<(), usize> {
    let par = if a.nrows() < SHARED_FROM {
        Par::Seq
    } else {
        par
    };
    factor(a, par)
}

/// [`cholesky`] on the threads `par`, the leaves on one.
fn factor(mut a: MatMut<'_, f64>, par: Par) -> Result<(), usize> {
    let n = a.nrows();
    if n <= BASE {
        let par = Par::Seq;
        let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(n, par, Default::default()));
        let stack = MemStack::new(&mut mem);
        return cholesky_in_place(a, Default::default(), par, stack, Default::default())
            .map(|_| ())
            .map_err(
                |faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }| index,
            );
    }
    // A multiple of 32 rows first, for the blocks of the products.
    let h = (n / 2).div_ceil(32) * 32;
    let (mut a11, _, mut a21, mut a22) = a.rb_mut().split_at_mut(h, h);
    factor(a11.rb_mut(), par)?;
    // L₂₁ᵀ = L₁₁⁻¹ A₂₁ᵀ.
    solve_lower_triangular_in_place(a11.rb(), a21.rb_mut().transpose_mut(), par);
    matmul(
        a22.rb_mut(),
        BlockStructure::TriangularLower,
        Accum::Add,
        a21.rb(),
        BlockStructure::Rectangular,
        a21.rb().transpose(),
        BlockStructure::Rectangular,
        -1.0,
        par,
    );
    factor(a22, par).map_err(|i| i + h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::{Mat, Side};

    #[test]
    fn equals_faer_llt_below_and_above_the_base_and_reports_the_failing_row() {
        for n in [1, 5, BASE, BASE + 1, 3 * BASE + 17] {
            let b = Mat::<f64>::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 101) as f64 / 101.0 - 0.5);
            let a = &b * b.transpose() + Mat::<f64>::identity(n, n);
            let mut c = a.clone();
            for j in 0..n {
                for i in 0..j {
                    c[(i, j)] = f64::NAN;
                }
            }
            cholesky(c.as_mut(), Par::Seq).unwrap();
            let l = a.llt(Side::Lower).unwrap();
            let l = l.L();
            for j in 0..n {
                for i in j..n {
                    assert!((c[(i, j)] - l[(i, j)]).abs() <= 1e-12 * l[(j, j)].abs().max(1.0));
                }
            }
        }
        let n = 2 * BASE + 3;
        let mut a = Mat::<f64>::identity(n, n);
        a[(BASE + 7, BASE + 7)] = -1.0;
        assert_eq!(cholesky(a.as_mut(), Par::Seq), Err(BASE + 7));
    }

    /// From [`SHARED_FROM`] rows on two threads: the factor equals the one
    /// thread's to rounding, and a failing row deep in the second half is
    /// reported at its own index.
    #[test]
    fn two_threads_give_the_one_threads_factor_and_failing_row() {
        let n = SHARED_FROM + 37;
        let b = Mat::<f64>::from_fn(n, n, |i, j| ((i * 11 + j * 5) % 97) as f64 / 97.0 - 0.5);
        let a = &b * b.transpose() + Mat::<f64>::identity(n, n);
        let (mut one, mut two) = (a.clone(), a.clone());
        cholesky(one.as_mut(), Par::Seq).unwrap();
        cholesky(two.as_mut(), Par::rayon(2)).unwrap();
        for j in 0..n {
            for i in j..n {
                assert!((one[(i, j)] - two[(i, j)]).abs() <= 1e-12 * one[(j, j)].abs().max(1.0));
            }
        }
        let mut a = Mat::<f64>::identity(n, n);
        a[(n - 5, n - 5)] = -1.0;
        assert_eq!(cholesky(a.as_mut(), Par::rayon(2)), Err(n - 5));
    }
}
