//! A dense LU factorisation P K = L U grown by bordering, for the
//! capacitance matrices of the friction status method
//! (the contact crate's `friction::capacitance`): from one status iteration to the next, the set of
//! rows whose equation differs from the base system's mostly grows, so the
//! capacitance matrix gains rows and columns and keeps the old ones.
//!
//! With K₁₁ = P₁ᵀ L₁₁ U₁₁ already factorised and the border (K₁₂, K₂₁, K₂₂)
//! of a rows and columns appended (block LU, Golub & Van Loan §3.2.11):
//!
//! ```text
//!   X = L₁₁⁻¹ P₁ K₁₂,   Y = K₂₁ U₁₁⁻¹,   S = K₂₂ − Y X = P₂ᵀ L₂ U₂,
//!   [P₁ 0; 0 P₂] K = [L₁₁ 0; P₂ Y L₂] [U₁₁ X; 0 U₂]
//! ```
//!
//! which costs about 2 r² a flops against ⅔ (r + a)³ for a new
//! factorisation. The pivoting is partial within each block only: the
//! caller checks its answer by a residual (as it does for any update) and
//! factorises afresh when the check fails.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
    solve_upper_triangular_in_place,
};
use faer::{Accum, Mat, MatRef, Par};

/// P K = L U of a square K (L unit lower, U upper; row i of P K is row
/// `perm[i]` of K).
#[derive(Debug, Clone)]
pub struct GrowingLu {
    l: Mat<f64>,
    u: Mat<f64>,
    perm: Vec<usize>,
}

impl GrowingLu {
    /// The LU factorisation of `k` with partial pivoting.
    pub fn new(k: MatRef<'_, f64>) -> Self {
        let lu = k.partial_piv_lu();
        Self {
            l: lu.L().to_owned(),
            u: lu.U().to_owned(),
            perm: lu.P().arrays().0.to_vec(),
        }
    }

    pub fn dim(&self) -> usize {
        self.perm.len()
    }

    /// The diagonal of U (the pivots).
    pub fn pivots(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.dim()).map(|i| self.u[(i, i)])
    }

    /// Appends the border of K: K₁₂ (old rows, new columns), K₂₁ (new rows,
    /// old columns) and K₂₂.
    pub fn extend(&mut self, k12: MatRef<'_, f64>, k21: MatRef<'_, f64>, k22: MatRef<'_, f64>) {
        let (r, a) = (self.dim(), k22.nrows());
        // X = L⁻¹ P K₁₂ and Yᵀ = U⁻ᵀ K₂₁ᵀ.
        let mut x = Mat::<f64>::from_fn(r, a, |i, j| k12[(self.perm[i], j)]);
        solve_unit_lower_triangular_in_place(self.l.as_ref(), x.as_mut(), Par::Seq);
        let mut yt = k21.transpose().to_owned();
        solve_lower_triangular_in_place(self.u.transpose(), yt.as_mut(), Par::Seq);
        let mut s = k22.to_owned();
        matmul(
            s.as_mut(),
            Accum::Add,
            yt.transpose(),
            x.as_ref(),
            -1.0,
            Par::Seq,
        );
        let lu2 = s.partial_piv_lu();
        let perm2 = lu2.P().arrays().0;
        let n = r + a;
        let mut l = Mat::<f64>::zeros(n, n);
        let mut u = Mat::<f64>::zeros(n, n);
        l.as_mut().submatrix_mut(0, 0, r, r).copy_from(&self.l);
        u.as_mut().submatrix_mut(0, 0, r, r).copy_from(&self.u);
        u.as_mut().submatrix_mut(0, r, r, a).copy_from(&x);
        l.as_mut().submatrix_mut(r, r, a, a).copy_from(lu2.L());
        u.as_mut().submatrix_mut(r, r, a, a).copy_from(lu2.U());
        for (i, &p) in perm2.iter().enumerate() {
            for j in 0..r {
                l[(r + i, j)] = yt[(j, p)];
            }
        }
        self.perm.extend(perm2.iter().map(|&p| r + p));
        self.l = l;
        self.u = u;
    }

    /// K⁻¹ b.
    pub fn solve(&self, b: MatRef<'_, f64>) -> Mat<f64> {
        let mut x = Mat::<f64>::from_fn(b.nrows(), b.ncols(), |i, j| b[(self.perm[i], j)]);
        solve_unit_lower_triangular_in_place(self.l.as_ref(), x.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.u.as_ref(), x.as_mut(), Par::Seq);
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::prelude::Solve;

    /// A nonsymmetric, well-conditioned n × n matrix.
    fn matrix(n: usize) -> Mat<f64> {
        Mat::<f64>::from_fn(n, n, |i, j| {
            let v = ((i * 31 + j * 17) % 13) as f64 / 13.0 - 0.5;
            if i == j {
                v + 3.0 + (i % 3) as f64
            } else {
                v
            }
        })
    }

    /// Grown by two borders, the factor solves K x = b as a new
    /// factorisation of the whole K does.
    #[test]
    fn a_grown_factor_solves_like_a_new_one() {
        let k = matrix(30);
        let mut lu = GrowingLu::new(k.as_ref().submatrix(0, 0, 12, 12));
        for (r, a) in [(12, 10), (22, 8)] {
            let (old, new) = (0..r, r..r + a);
            let block = |rows: std::ops::Range<usize>, cols: std::ops::Range<usize>| {
                k.as_ref()
                    .submatrix(rows.start, cols.start, rows.len(), cols.len())
            };
            lu.extend(
                block(old.clone(), new.clone()),
                block(new.clone(), old),
                block(new.clone(), new),
            );
        }
        assert_eq!(lu.dim(), 30);
        let b = Mat::<f64>::from_fn(30, 2, |i, j| ((i * 5 + j * 11) % 7) as f64 - 3.0);
        let x = lu.solve(b.as_ref());
        let y = k.partial_piv_lu().solve(&b);
        assert!((&x - &y).norm_max() <= 1e-13 * y.norm_max());
        assert!((&k * &x - &b).norm_max() <= 1e-13 * b.norm_max() * k.norm_max());
    }
}
