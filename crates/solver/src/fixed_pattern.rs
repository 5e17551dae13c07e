//! A sparse matrix whose pattern is fixed over a run and whose values are
//! set anew at each Newton iteration, in place: the matrix and the
//! position of each (row, column) pair in its values are computed once, so
//! that setting the values allocates nothing (a new matrix at each
//! iteration was tens of megabytes of fresh pages on the 100 × 100 pad,
//! a third of its run time in page faults).

use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};

/// A sparse matrix of fixed pattern (module doc).
pub(crate) struct FixedPattern {
    matrix: SparseColMat<usize, f64>,
    /// The position in the matrix's values of each pair, in the order of
    /// the pairs it was built from.
    slot: Vec<usize>,
}

impl FixedPattern {
    /// The nrows × ncols matrix of pattern `pairs` (a repeated pair is one
    /// entry, its values summed), its values zero.
    pub(crate) fn new(
        nrows: usize,
        ncols: usize,
        pairs: &[Pair<usize, usize>],
    ) -> Result<Self, String> {
        let (pattern, _) = SymbolicSparseColMat::try_new_from_indices(nrows, ncols, pairs)
            .map_err(|e| format!("{e:?}"))?;
        let mut slot = Vec::with_capacity(pairs.len());
        for p in pairs {
            let start = pattern.col_ptr()[p.col];
            let rows = pattern.row_idx_of_col_raw(p.col);
            let at = rows
                .binary_search(&p.row)
                .map_err(|_| format!("({}, {}) not in the pattern", p.row, p.col))?;
            slot.push(start + at);
        }
        let nnz = pattern.row_idx().len();
        let matrix = SparseColMat::new(pattern, vec![0.0; nnz]);
        Ok(Self { matrix, slot })
    }

    /// The matrix with `values` (one per pair, in the pairs' order), set in
    /// place.
    pub(crate) fn set(&mut self, values: &[f64]) -> &SparseColMat<usize, f64> {
        debug_assert_eq!(values.len(), self.slot.len());
        let val = self.matrix.val_mut();
        val.fill(0.0);
        for (&at, &v) in self.slot.iter().zip(values) {
            val[at] += v;
        }
        &self.matrix
    }

    /// The matrix with the values last set.
    pub(crate) fn matrix(&self) -> &SparseColMat<usize, f64> {
        &self.matrix
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs out of order with one repeated: the matrix sums the repeated
    /// pair and places each value at its (row, column), for two sets of
    /// values on the one pattern.
    #[test]
    fn sets_values_in_place() {
        let entries = [(2, 1), (0, 0), (1, 1), (2, 1), (0, 2)];
        let pairs: Vec<Pair<usize, usize>> =
            entries.iter().map(|&(i, j)| Pair::new(i, j)).collect();
        let mut m = FixedPattern::new(3, 3, &pairs).expect("pattern");
        assert_eq!(m.matrix().val().len(), 4);
        for values in [[1.0, 2.0, 3.0, 4.0, 5.0], [-1.0, 0.5, 0.0, 0.25, 8.0]] {
            let a = m.set(&values).to_dense();
            assert_eq!(a[(2, 1)], values[0] + values[3]);
            assert_eq!(a[(0, 0)], values[1]);
            assert_eq!(a[(1, 1)], values[2]);
            assert_eq!(a[(0, 2)], values[4]);
            assert_eq!(a[(1, 0)], 0.0);
        }
    }
}
