//! A symmetric matrix stored as one triangle: LMGC90 writes the M of its
//! finite-element global problems so, and some writers W. A square matrix
//! whose strictly lower part is empty while its strictly upper part is not
//! (or the other way round) is read as the symmetric matrix of that
//! triangle, completed by symmetry; `signorini local` says so in its JSON
//! line (`stored_triangle`). A matrix with entries in both triangles is
//! taken as written (symmetric or not).

use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

/// The triangle a symmetric matrix was stored as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Triangle {
    Upper,
    Lower,
}

impl Triangle {
    /// Its name in the JSON line.
    pub fn name(self) -> &'static str {
        match self {
            Triangle::Upper => "upper",
            Triangle::Lower => "lower",
        }
    }
}

/// The triangle the nonzero entries (row, column) lie in, when one strictly
/// triangular part has some and the other none.
fn stored_triangle(nonzero: impl IntoIterator<Item = (usize, usize)>) -> Option<Triangle> {
    let (mut upper, mut lower) = (false, false);
    for (i, j) in nonzero {
        upper |= i < j;
        lower |= i > j;
    }
    match (upper, lower) {
        (true, false) => Some(Triangle::Upper),
        (false, true) => Some(Triangle::Lower),
        _ => None,
    }
}

/// Completes a dense square matrix stored as one triangle by symmetry;
/// which triangle it was, if it was one.
pub(crate) fn complete_dense(w: &mut Mat<f64>) -> Option<Triangle> {
    let n = w.nrows();
    let nonzero: Vec<(usize, usize)> = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .filter(|&(i, j)| w[(i, j)] != 0.0)
        .collect();
    let triangle = stored_triangle(nonzero)?;
    for j in 0..n {
        for i in j + 1..n {
            let v = w[(i, j)] + w[(j, i)];
            w[(i, j)] = v;
            w[(j, i)] = v;
        }
    }
    Some(triangle)
}

/// Completes a sparse square matrix stored as one triangle by symmetry
/// (the same matrix when it is not one), and which triangle it was.
pub(crate) fn complete_sparse(
    a: SparseColMat<usize, f64>,
) -> (SparseColMat<usize, f64>, Option<Triangle>) {
    let mut triplets = Vec::new();
    for j in 0..a.ncols() {
        let rows = a.row_idx_of_col_raw(j).iter();
        for (&i, &v) in rows.zip(a.val_of_col(j)) {
            if v != 0.0 {
                triplets.push(Triplet::new(i, j, v));
            }
        }
    }
    let Some(triangle) = stored_triangle(triplets.iter().map(|t| (t.row, t.col))) else {
        return (a, None);
    };
    let mirrored: Vec<_> = triplets
        .iter()
        .filter(|t| t.row != t.col)
        .map(|t| Triplet::new(t.col, t.row, t.val))
        .collect();
    triplets.extend(mirrored);
    match SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &triplets) {
        Ok(full) => (full, Some(triangle)),
        Err(_) => (a, None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Upper, lower, both and neither: only a matrix with exactly one
    /// strictly triangular part is completed, to the symmetric matrix.
    #[test]
    fn one_triangle_is_completed_two_or_none_are_kept() {
        let full = Mat::<f64>::from_fn(3, 3, |i, j| 1.0 + (i + j) as f64 + (i == j) as u8 as f64);
        let upper: fn(usize, usize) -> bool = |i, j| i <= j;
        let lower: fn(usize, usize) -> bool = |i, j| i >= j;
        for (keep, expected) in [
            (upper, Some(Triangle::Upper)),
            (lower, Some(Triangle::Lower)),
        ] {
            let mut w =
                Mat::<f64>::from_fn(3, 3, |i, j| if keep(i, j) { full[(i, j)] } else { 0.0 });
            assert_eq!(complete_dense(&mut w), expected);
            assert_eq!(w, full);
            let triplets: Vec<_> = (0..3)
                .flat_map(|j| (0..3).map(move |i| (i, j)))
                .filter(|&(i, j)| keep(i, j))
                .map(|(i, j)| Triplet::new(i, j, full[(i, j)]))
                .collect();
            let a = SparseColMat::try_new_from_triplets(3, 3, &triplets).unwrap();
            let (b, t) = complete_sparse(a);
            assert_eq!(t, expected);
            assert_eq!(b.to_dense(), full);
        }
        let mut w = full.clone();
        w[(0, 1)] += 1e-3;
        assert_eq!(complete_dense(&mut w), None);
        assert_eq!(w[(0, 1)], full[(0, 1)] + 1e-3);
        let mut d = Mat::<f64>::identity(3, 3);
        assert_eq!(complete_dense(&mut d), None);
    }
}
