//! Products with a dense column-major matrix W (the Delassus operator, m × m):
//! y = W x with the rows shared between the cores, and the affine map
//! W x + q; the update C −= A B of block eliminations.

use std::ops::Range;

use faer::{Accum, Mat, MatMut, MatRef, Par};

/// C −= A B (faer's product, accumulated into C): the Schur-complement
/// update of a block elimination.
pub fn subtract_product(c: MatMut<'_, f64>, a: MatRef<'_, f64>, b: MatRef<'_, f64>, par: Par) {
    faer::linalg::matmul::matmul(c, Accum::Add, a, b, -1.0, par);
}

/// y = W x (W column-major, m × m), the rows shared between the cores.
pub fn matvec(w: &Mat<f64>, x: &[f64], y: &mut [f64]) {
    y.iter_mut().for_each(|v| *v = 0.0);
    let nonzero: Vec<usize> = (0..x.len()).filter(|&j| x[j] != 0.0).collect();
    let rows = 0..y.len();
    add_columns_shared(w, &nonzero, x, std::slice::from_ref(&rows), y);
}

/// [`add_columns`] on every row of `y` (from row 0), the rows shared
/// between the cores: each takes the part of `runs` in its own rows.
pub fn add_columns_shared(
    w: &Mat<f64>,
    cols: &[usize],
    x: &[f64],
    runs: &[Range<usize>],
    y: &mut [f64],
) {
    let rows: usize = runs.iter().map(|r| r.len()).sum();
    let work = (cols.len() * rows) as f64;
    crate::threads::for_each_chunk(y, 1, work, |first, chunk| {
        let end = first + chunk.len();
        let mine: Vec<Range<usize>> = runs
            .iter()
            .map(|r| r.start.max(first)..r.end.min(end))
            .filter(|r| !r.is_empty())
            .collect();
        add_columns(w, cols, x, &mine, chunk, first);
    });
}

/// y = W x + q, into `y`.
pub fn affine_into(w: &Mat<f64>, x: &[f64], q: &[f64], y: &mut [f64]) {
    matvec(w, x, y);
    for (yi, qi) in y.iter_mut().zip(q) {
        *yi += qi;
    }
}

/// W x + q.
pub fn affine(w: &Mat<f64>, x: &[f64], q: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; q.len()];
    affine_into(w, x, q, &mut y);
    y
}

/// y_i += Σ_{j ∈ cols} W_ij x_j for i in `runs`, four columns at a time
/// (y is loaded and stored once per four columns: the sweep is bound by the
/// reading of W); `y` holds the rows from `offset` on.
pub fn add_columns(
    w: &Mat<f64>,
    cols: &[usize],
    x: &[f64],
    runs: &[Range<usize>],
    y: &mut [f64],
    offset: usize,
) {
    let at = |r: &Range<usize>| r.start - offset..r.end - offset;
    let mut quads = cols.chunks_exact(4);
    for c in &mut quads {
        let [c0, c1, c2, c3] = [0, 1, 2, 3].map(|k| w.col_as_slice(c[k]));
        let [x0, x1, x2, x3] = [0, 1, 2, 3].map(|k| x[c[k]]);
        for r in runs {
            let y = y[at(r)].iter_mut().zip(&c0[r.clone()]).zip(&c1[r.clone()]);
            for (((yi, a0), a1), (a2, a3)) in y.zip(c2[r.clone()].iter().zip(&c3[r.clone()])) {
                *yi += a0 * x0 + a1 * x1 + a2 * x2 + a3 * x3;
            }
        }
    }
    for &j in quads.remainder() {
        let (col, xj) = (w.col_as_slice(j), x[j]);
        for r in runs {
            for (yi, wij) in y[at(r)].iter_mut().zip(&col[r.clone()]) {
                *yi += wij * xj;
            }
        }
    }
}
