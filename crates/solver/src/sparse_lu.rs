//! A sparse LU of a square matrix whose pattern is fixed over a run and
//! whose values change: the column ordering (COLAMD) and the symbolic
//! factor are computed once, each new set of values is factorised
//! numerically with partial pivoting into the storage of the previous
//! factor (no new allocation of the factor's size at each factorisation),
//! and each solve is refined against the exact matrix
//! ([`crate::kkt::refine`]) to a backward error of a few roundings. The
//! whole-system Newton method of friction on the direct path factorises its
//! nonsymmetric Jacobian so ([`crate::direct_newton`]).
//!
//! The factor's size is reported by its bound: the entries of the Cholesky
//! factor of (AP)ᵀ(AP), P the column ordering, which holds the pattern of L
//! and of Uᵀ whatever the row pivots (George & Ng 1987), the structure
//! faer's supernodal LU is laid out on.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu, SymbolicLu};
use faer::sparse::linalg::qr::{
    col_etree, col_etree_scratch, column_counts_aat_scratch, column_counts_ata, postorder,
    postorder_scratch,
};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, Mat, Par};

use crate::kkt::refine;

/// The pattern of a square sparse matrix with its symbolic LU factor, the
/// storage of its numerical factor, and the counts of the numerical
/// factorisations done on it.
pub(crate) struct SparseLu {
    pattern: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    /// Scratch of a numerical factorisation and of a solve.
    scratch: MemBuffer,
    par: Par,
    /// Entries of the Cholesky factor of (AP)ᵀ(AP) (module doc).
    pub(crate) factor_bound: usize,
    /// Numerical factorisations, and refinement steps over all solves.
    pub(crate) factorisations: usize,
    pub(crate) refinement_steps: usize,
}

impl SparseLu {
    /// The symbolic LU of the n × n pattern `pairs` (repeated pairs are
    /// summed by [`SparseLu::matrix`]).
    pub(crate) fn new(n: usize, pairs: &[Pair<usize, usize>]) -> Result<Self, String> {
        let (pattern, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, pairs)
            .map_err(|e| format!("sparse LU pattern: {e:?}"))?;
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default())
            .map_err(|e| format!("symbolic sparse LU: {e:?}"))?;
        let par = faer::get_global_parallelism();
        let scratch = MemBuffer::try_new(StackReq::any_of(&[
            symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ]))
        .map_err(|e| format!("sparse LU scratch: {e:?}"))?;
        let factor_bound = factor_bound(pattern.as_ref(), &symbolic)?;
        Ok(Self {
            pattern,
            argsort,
            symbolic,
            numeric: NumericLu::new(),
            scratch,
            par,
            factor_bound,
            factorisations: 0,
            refinement_steps: 0,
        })
    }

    /// The matrix of `values`, one per pair in the order of the pattern's
    /// pairs.
    pub(crate) fn matrix(&self, values: &[f64]) -> Result<SparseColMat<usize, f64>, String> {
        SparseColMat::new_from_argsort(self.pattern.clone(), &self.argsort, values)
            .map_err(|e| format!("sparse LU values: {e:?}"))
    }

    /// Solves A x = b for the matrix of `values`: one numerical LU on the
    /// symbolic factor, the solve refined against A; `None` when the
    /// factorisation fails (a zero pivot) or the refined solve does not
    /// reach [`crate::kkt::ACCEPTED_BACKWARD_ERROR`].
    pub(crate) fn solve(&mut self, values: &[f64], b: &[f64]) -> Option<Vec<f64>> {
        let a = self.matrix(values).ok()?;
        self.factorisations += 1;
        let par = self.par;
        let stack = MemStack::new(&mut self.scratch);
        let lu = (self.symbolic)
            .factorize_numeric_lu(
                &mut self.numeric,
                a.as_ref(),
                par,
                stack,
                Default::default(),
            )
            .ok()?;
        let n = b.len();
        let scratch = &mut self.scratch;
        let solve = |rhs: &[f64]| {
            let mut x = Mat::<f64>::from_fn(n, 1, |i, _| rhs[i]);
            lu.solve_in_place_with_conj(Conj::No, x.as_mut(), par, MemStack::new(scratch));
            (0..n).map(|i| x[(i, 0)]).collect::<Vec<f64>>()
        };
        let (x, steps) = refine(&a, solve, b)?;
        self.refinement_steps += steps;
        Some(x)
    }
}

/// The entries of the Cholesky factor of (AP)ᵀ(AP), P the symbolic
/// factor's column ordering (module doc).
fn factor_bound(
    a: SymbolicSparseColMatRef<'_, usize>,
    symbolic: &SymbolicLu<usize>,
) -> Result<usize, String> {
    let n = a.ncols();
    let at = (a.transpose().to_col_major()).map_err(|e| format!("sparse LU bound: {e:?}"))?;
    let mut mem = MemBuffer::try_new(StackReq::any_of(&[
        col_etree_scratch::<usize>(n, n),
        postorder_scratch::<usize>(n),
        column_counts_aat_scratch::<usize>(n, n),
    ]))
    .map_err(|e| format!("sparse LU bound: {e:?}"))?;
    let stack = MemStack::new(&mut mem);
    let perm = symbolic.col_perm();
    let mut etree = vec![0usize; n];
    let etree = col_etree(a, Some(perm), &mut etree, stack);
    let mut post = vec![0usize; n];
    postorder(&mut post, etree, stack);
    let (mut counts, mut min_col) = (vec![0usize; n], vec![0usize; n]);
    column_counts_ata(
        &mut counts,
        &mut min_col,
        at.as_ref(),
        Some(perm),
        etree,
        &post,
        stack,
    );
    Ok(counts.iter().sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A nonsymmetric matrix with a zero diagonal entry (partial pivoting
    /// needed), factorised twice on one symbolic factor: A x = b to a few
    /// roundings relative to ‖b‖, for both sets of values.
    #[test]
    fn one_symbolic_factor_solves_two_nonsymmetric_matrices() {
        let entries = [(0, 0), (1, 0), (0, 1), (2, 1), (1, 2), (2, 2), (0, 2)];
        let pairs: Vec<Pair<usize, usize>> =
            entries.iter().map(|&(i, j)| Pair::new(i, j)).collect();
        let mut lu = SparseLu::new(3, &pairs).expect("pattern");
        for values in [
            [4.0, 1.0, 2.0, -1.0, 3.0, 0.0, 1.0],
            [0.0, 2.0, 5.0, 1.0, -2.0, 3.0, 0.5],
        ] {
            let b = [1.0, -2.0, 3.0];
            let x = lu.solve(&values, &b).expect("nonsingular");
            let mut ax = [0.0; 3];
            for (&(i, j), v) in entries.iter().zip(values) {
                ax[i] += v * x[j];
            }
            let err = ax
                .iter()
                .zip(&b)
                .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
            assert!(err <= 8.0 * f64::EPSILON * 3.0, "{err:e}");
        }
        assert_eq!(lu.factorisations, 2);
        // Row 0 holds every column: AᵀA is full, its Cholesky factor has
        // the 3 · 4 / 2 entries of a full triangle.
        assert_eq!(lu.factor_bound, 6);
    }
}
