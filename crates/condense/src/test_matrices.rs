//! Test matrices shared by the unit tests of this crate.

use faer::sparse::{SparseColMat, Triplet};

/// A 3D grid matrix (m³ rows, 7-point stencil, varied weights): zero row
/// sums (a floating, pure Neumann block) plus a Dirichlet shift on its
/// first layer when `held` (then positive definite).
pub(crate) fn grid3(m: usize, held: bool) -> SparseColMat<usize, f64> {
    let id = |i: usize, j: usize, k: usize| i + m * (j + m * k);
    let mut t = Vec::new();
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                let a = id(i, j, k);
                let mut diag = if held && k == 0 { 1.0 } else { 0.0 };
                for (b, ok) in [
                    (a.wrapping_sub(1), i > 0),
                    (a + 1, i + 1 < m),
                    (a.wrapping_sub(m), j > 0),
                    (a + m, j + 1 < m),
                    (a.wrapping_sub(m * m), k > 0),
                    (a + m * m, k + 1 < m),
                ] {
                    if ok {
                        t.push(Triplet::new(a, b, -1.0 - 0.1 * ((a + b) % 3) as f64));
                        diag += 1.0 + 0.1 * ((a + b) % 3) as f64;
                    }
                }
                t.push(Triplet::new(a, a, diag));
            }
        }
    }
    SparseColMat::try_new_from_triplets(m * m * m, m * m * m, &t).unwrap()
}
