//! A dense square block factorised in its own storage, for the reduced
//! systems of friction (course notes §4.5 status iterations, §4.1.2 Newton steps):
//! their leading n₁ × n₁ block A₁₁ (the unknowns whose columns carry only W
//! and compliances) is symmetric positive definite, the trailing n₂ rows and
//! columns (the normal forces of slipping points, whose columns also carry
//! f W_·t) are not. The factorisation
//!
//! ```text
//!   A₁₁ = L Lᵀ,   X = A₁₁⁻¹ A₁₂,   S = A₂₂ − A₂₁ X = P⁻¹ L₂ U₂
//! ```
//!
//! (⅓ n₁³ + 2 n₁² n₂ + 2 n₁ n₂² + ⅔ n₂³ flops) overwrites the n × n buffer
//! as [L \ X; A₂₁ \ L₂U₂]; only the lower triangle of A₁₁ is read. n₁ = n is
//! a plain Cholesky, n₁ = 0 a plain LU. The buffer comes back with
//! [`BorderedFactor::into_buffer`], so that the next block of a Newton
//! iteration reuses its pages instead of faulting in fresh ones (about 10 %
//! of a 3D Coulomb solve with 2,000 points). [`crate::reduced::BlockFactor`]
//! puts the unknowns of a block in this order and back.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::linalg::lu::partial_pivoting as lu;
use faer::perm::PermRef;
use faer::reborrow::{Reborrow, ReborrowMut};
#[cfg(test)]
use faer::Mat;
use faer::{Conj, MatMut, MatRef};

use crate::pivot_policy::pivots_are_safe;
use crate::products::subtract_product;

/// Why a block was not factorised; the buffer is given back either way.
pub enum FactorFailure {
    /// A₁₁ is not positive definite (a Cholesky pivot ≤ 0).
    NotPositive(Vec<f64>),
    /// A pivot (L_ii² of A₁₁, U_ii of S) is below 1e3 · n · ε times the
    /// largest ([`pivots_are_safe`]).
    NearSingular(Vec<f64>),
}

/// The factor of an n × n block with an SPD leading n₁ × n₁ block.
pub struct BorderedFactor {
    buf: Vec<f64>,
    n: usize,
    n1: usize,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
}

/// The n × n column-major view of the first n² entries of `buf`.
fn view(buf: &mut [f64], n: usize) -> MatMut<'_, f64> {
    MatMut::from_column_major_slice_mut(&mut buf[..n * n], n, n)
}

impl BorderedFactor {
    /// Factorises the n × n block stored column-major in `buf` (at least n²
    /// entries), its first `n1` unknowns the SPD block.
    pub fn new(mut buf: Vec<f64>, n: usize, n1: usize) -> Result<Self, FactorFailure> {
        let par = faer::get_global_parallelism();
        let n2 = n - n1;
        let mut perm = vec![0usize; n2];
        let mut perm_inv = vec![0usize; n2];
        let mut mem = MemBuffer::new(lu::factor::lu_in_place_scratch::<usize, f64>(
            n2,
            n2,
            par,
            Default::default(),
        ));
        let mut a = view(&mut buf, n);
        let (mut a11, mut a12, a21, mut a22) = a.rb_mut().split_at_mut(n1, n1);
        if crate::recursive_cholesky::cholesky(a11.rb_mut(), par).is_err() {
            return Err(FactorFailure::NotPositive(buf));
        }
        llt::solve::solve_in_place_with_conj(
            a11.rb(),
            Conj::No,
            a12.rb_mut(),
            par,
            MemStack::new(&mut mem),
        );
        subtract_product(a22.rb_mut(), a21.rb(), a12.rb(), par);
        lu::factor::lu_in_place(
            a22.rb_mut(),
            &mut perm,
            &mut perm_inv,
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        let pivots = (0..n1).map(|i| a11[(i, i)] * a11[(i, i)]);
        if !pivots_are_safe(pivots.chain((0..n2).map(|i| a22[(i, i)])), n) {
            return Err(FactorFailure::NearSingular(buf));
        }
        Ok(Self {
            buf,
            n,
            n1,
            perm,
            perm_inv,
        })
    }

    /// Whether the block has both an SPD part and a bordered part.
    pub fn is_bordered(&self) -> bool {
        self.n1 > 0 && self.n1 < self.n
    }

    /// Solves A x = rhs in place: y₁ = A₁₁⁻¹ b₁, x₂ = S⁻¹ (b₂ − A₂₁ y₁),
    /// x₁ = y₁ − X x₂.
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        let par = faer::get_global_parallelism();
        let (n, n1) = (self.n, self.n1);
        let a = MatRef::from_column_major_slice(&self.buf[..n * n], n, n);
        let (l, x, a21, lu2) = a.split_at(n1, n1);
        let mut mem = MemBuffer::new(lu::solve::solve_in_place_scratch::<usize, f64>(
            n - n1,
            rhs.ncols(),
            par,
        ));
        let (mut b1, mut b2) = rhs.split_at_row_mut(n1);
        llt::solve::solve_in_place_with_conj(
            l,
            Conj::No,
            b1.rb_mut(),
            par,
            MemStack::new(&mut mem),
        );
        subtract_product(b2.rb_mut(), a21, b1.rb(), par);
        // Safety of the permutation: `perm` and `perm_inv` come from
        // `lu_in_place` on this block and are inverse to each other.
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n - n1);
        lu::solve::solve_in_place_with_conj(
            lu2,
            lu2,
            perm,
            Conj::No,
            b2.rb_mut(),
            par,
            MemStack::new(&mut mem),
        );
        subtract_product(b1.rb_mut(), x, b2.rb(), par);
    }

    /// x = A⁻¹ rhs.
    #[cfg(test)]
    pub fn solve(&self, rhs: &Mat<f64>) -> Mat<f64> {
        let mut x = rhs.clone();
        self.solve_in_place(x.as_mut());
        x
    }

    /// The storage, for the next block.
    pub fn into_buffer(self) -> Vec<f64> {
        self.buf
    }
}

/// `buf` with room for an n × n block (its old pages kept); its entries are
/// left as they were.
pub fn block_buffer(mut buf: Vec<f64>, n: usize) -> Vec<f64> {
    buf.resize(n * n, 0.0);
    buf
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An SPD leading block bordered by nonsymmetric columns.
    fn block(n: usize, n1: usize) -> Mat<f64> {
        let b = Mat::<f64>::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 11) as f64 / 11.0 - 0.4);
        let mut a = &b * b.transpose() + Mat::<f64>::identity(n, n) * (n as f64);
        for j in n1..n {
            for i in 0..n {
                a[(i, j)] += ((i + 3 * j) % 5) as f64 * 0.3;
            }
        }
        a
    }

    fn residual(a: &Mat<f64>, x: &Mat<f64>, b: &Mat<f64>) -> f64 {
        (a * x - b).norm_max() / b.norm_max()
    }

    #[test]
    fn solves_bordered_cholesky_and_lu_blocks() {
        let n = 40;
        for n1 in [0, 1, 17, 39, 40] {
            let a = block(n, n1);
            let mut buf = vec![f64::NAN; n * n];
            for j in 0..n {
                // Only the lower triangle of A₁₁ may be read.
                let top = if j < n1 { j } else { 0 };
                for i in top..n {
                    buf[i + j * n] = a[(i, j)];
                }
            }
            let Ok(f) = BorderedFactor::new(buf, n, n1) else {
                panic!("n1 = {n1}: not factorised");
            };
            assert_eq!(f.is_bordered(), n1 > 0 && n1 < n);
            let b = Mat::<f64>::from_fn(n, 3, |i, j| (i as f64 - 5.0 * j as f64).sin());
            let x = f.solve(&b);
            assert!(residual(&a, &x, &b) < 1e-12, "n1 = {n1}");
        }
    }

    #[test]
    fn refuses_indefinite_and_singular_blocks_and_gives_the_buffer_back() {
        let n = 6;
        let mut a = block(n, 6);
        a[(2, 2)] = -1.0;
        let buf: Vec<f64> = (0..n * n).map(|k| a[(k % n, k / n)]).collect();
        assert!(matches!(
            BorderedFactor::new(buf, n, n),
            Err(FactorFailure::NotPositive(b)) if b.len() == n * n
        ));
        let mut s = block(n, 3);
        for i in 0..n {
            s[(i, 5)] = s[(i, 4)];
        }
        let buf: Vec<f64> = (0..n * n).map(|k| s[(k % n, k / n)]).collect();
        assert!(matches!(
            BorderedFactor::new(buf, n, 3),
            Err(FactorFailure::NearSingular(_))
        ));
    }
}
