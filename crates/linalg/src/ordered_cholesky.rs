//! Solves and products with a dense Cholesky factor of a matrix whose rows
//! were permuted, some eliminated last (the interface stiffness with its
//! contact DOFs last): the generalised inverse it applies and W = B A⁻¹ Bᵀ
//! from its trailing block alone.

use faer::linalg::matmul::triangular::{matmul, BlockStructure};
use faer::{Mat, MatMut, MatRef, Par};

use crate::sparse::SparseRow;

/// The lower triangle of W += YᵀY, Y = L_CC⁻¹ B_C (the trailing block
/// `l_cc` of a factor on the Γ DOFs `dofs`, sorted; entries of B on the
/// `fixed` DOFs, sorted, dropped: S⁺ = S̃⁻¹ Z).
pub fn add_trailing_delassus(
    w: &mut Mat<f64>,
    l_cc: MatRef<'_, f64>,
    dofs: &[usize],
    fixed: &[usize],
    b: &[SparseRow],
    par: Par,
) {
    let mut y = Mat::<f64>::zeros(dofs.len(), b.len());
    for (p, row) in b.iter().enumerate() {
        for &(i, c) in row {
            if let (Err(_), Ok(k)) = (fixed.binary_search(&i), dofs.binary_search(&i)) {
                y[(k, p)] += c;
            }
        }
    }
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l_cc, y.as_mut(), par);
    matmul(
        w.as_mut(),
        BlockStructure::TriangularLower,
        faer::Accum::Add,
        y.transpose(),
        BlockStructure::Rectangular,
        y.as_ref(),
        BlockStructure::Rectangular,
        1.0,
        par,
    );
}

/// x_P ← (L Lᵀ)⁻¹ x_P on the rows P = `order` of x (factor row k is row
/// `order[k]` of x; the other rows are left alone): with P every row,
/// x ← A⁻¹ x for L Lᵀ = P A Pᵀ.
pub fn dense_solve(l: &Mat<f64>, order: &[usize], mut x: MatMut<'_, f64>, par: Par) {
    let mut y = Mat::<f64>::from_fn(order.len(), x.ncols(), |k, j| x[(order[k], j)]);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), y.as_mut(), par);
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(l.transpose(), y.as_mut(), par);
    for (k, &i) in order.iter().enumerate() {
        for j in 0..x.ncols() {
            x[(i, j)] = y[(k, j)];
        }
    }
}
