//! A sparse LU of a square matrix whose pattern is fixed over a run and
//! whose values change: the column ordering (COLAMD) and the symbolic
//! factor are computed once (at the first factorisation: a run whose
//! solves all succeed otherwise never holds them), each new set of values is factorised
//! numerically with partial pivoting, and each solve is refined against
//! the exact matrix ([`crate::kkt::refine`]) to a backward error of a few
//! roundings. The whole-system Newton method of friction on the direct
//! path factorises its nonsymmetric Jacobian so ([`crate::direct_newton`]).

use faer::prelude::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{Pair, SparseColMat};
use faer::Mat;

use crate::fixed_pattern::FixedPattern;
use crate::kkt::refine;

/// The pattern of a square sparse matrix with its symbolic LU factor, and
/// the counts of the numerical factorisations done on it.
pub(crate) struct SparseLu {
    matrix: FixedPattern,
    symbolic: Option<SymbolicLu<usize>>,
    /// Numerical factorisations, and refinement steps over all solves.
    pub(crate) factorisations: usize,
    pub(crate) refinement_steps: usize,
}

impl SparseLu {
    /// The symbolic LU of the n × n pattern `pairs` (repeated pairs are
    /// summed by [`SparseLu::set`]).
    pub(crate) fn new(n: usize, pairs: &[Pair<usize, usize>]) -> Result<Self, String> {
        let matrix =
            FixedPattern::new(n, n, pairs).map_err(|e| format!("sparse LU pattern: {e}"))?;
        Ok(Self {
            matrix,
            symbolic: None,
            factorisations: 0,
            refinement_steps: 0,
        })
    }

    /// The matrix A of `values`, one per pair in the order of the
    /// pattern's pairs, set in place.
    pub(crate) fn set(&mut self, values: &[f64]) -> &SparseColMat<usize, f64> {
        self.matrix.set(values)
    }

    /// Solves A x = b for the matrix last [`SparseLu::set`]: one numerical
    /// LU on the symbolic factor, the solve refined against A; `None` when
    /// the factorisation (or the symbolic one) fails (a zero pivot) or the
    /// refined solve does not reach [`crate::kkt::ACCEPTED_BACKWARD_ERROR`].
    pub(crate) fn solve(&mut self, b: &[f64]) -> Option<Vec<f64>> {
        let a = self.matrix.matrix();
        if self.symbolic.is_none() {
            self.symbolic = Some(SymbolicLu::try_new(a.symbolic()).ok()?);
        }
        let symbolic = self.symbolic.clone()?;
        self.factorisations += 1;
        let lu = Lu::try_new_with_symbolic(symbolic, a.as_ref()).ok()?;
        let n = b.len();
        let solve = |rhs: &[f64]| {
            let x = lu.solve(Mat::<f64>::from_fn(n, 1, |i, _| rhs[i]));
            (0..n).map(|i| x[(i, 0)]).collect::<Vec<f64>>()
        };
        let (x, steps) = refine(a, solve, b)?;
        self.refinement_steps += steps;
        Some(x)
    }
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
            lu.set(&values);
            let x = lu.solve(&b).expect("nonsingular");
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
    }
}
