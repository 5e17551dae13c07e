//! The equality constraints of an FCLib global problem, eliminated with M's
//! factor (the range-space method).
//!
//! FCLib's global problem with p ≥ 1 equality constraints (`G`, n × p, and
//! `vectors/b`) is
//!
//! ```text
//! M v = H r + G λ + f,    Gᵀ v + b = 0,    u = Hᵀ v + w.
//! ```
//!
//! With x = M⁻¹ (H r + f) the velocity without the constraints, Y = M⁻¹ G
//! and C = Gᵀ M⁻¹ G (p × p, symmetric positive definite when G has full
//! column rank), the constraint gives C λ = −(Gᵀ x + b), so
//!
//! ```text
//! v = x − Y C⁻¹ (Gᵀ x + b),
//! W = Hᵀ M⁻¹ H − Z C⁻¹ Zᵀ,   Z = Hᵀ Y  (m × p),
//! q = Hᵀ v₀ + w,             v₀ = M⁻¹ f − Y C⁻¹ (Gᵀ M⁻¹ f + b),
//! ```
//!
//! the same local problem u = W r + q that the saddle-point system
//! [M −G; −Gᵀ 0] gives once v and λ are eliminated (W is Hᵀ times the
//! M-orthogonal projection of M⁻¹ onto the kernel of Gᵀ, times H). A
//! column of G that depends on the others (C singular) is refused, naming
//! it: the pivot of column k of C's Cholesky factor, squared, is the part of
//! that constraint's C_kk outside the span of the columns before it; below
//! [`DEPENDENT`] × C_kk it is a repeated or implied constraint, whose λ is
//! not determined.

use faer::linalg::solvers::{Llt, Solve};
use faer::sparse::SparseColMat;
use faer::{Mat, MatMut, MatRef, Side};
use signorini_linalg::products::subtract_product;

/// A column of G is dependent on the others when its pivot² is below this
/// fraction of its C_kk (the sine² of its angle with their span, in the
/// M⁻¹ inner product): 1e-12, far above rounding (ε ≈ 2e-16), far below
/// any constraint an exporter means to impose.
const DEPENDENT: f64 = 1e-12;

/// G, b and the factors that eliminate them (module doc).
pub(super) struct EqualityConstraints {
    g: SparseColMat<usize, f64>,
    b: Vec<f64>,
    /// Y = M⁻¹ G, n × p.
    y: Mat<f64>,
    /// The Cholesky factor of C = Gᵀ M⁻¹ G.
    c: Llt<f64>,
}

impl EqualityConstraints {
    /// Y = M⁻¹ G by `solve_m` (overwrites an n × k block with M⁻¹ times it),
    /// C and its factor; an error (for the file `shown`, matrix `name`)
    /// naming the first column of G that depends on the ones before it.
    pub(super) fn new(
        shown: &str,
        name: &str,
        g: SparseColMat<usize, f64>,
        b: Vec<f64>,
        solve_m: impl Fn(MatMut<'_, f64>),
    ) -> Result<Self, String> {
        let (n, p) = (g.nrows(), g.ncols());
        let mut y = Mat::<f64>::zeros(n, p);
        for k in 0..p {
            for (&i, &v) in g.row_idx_of_col_raw(k).iter().zip(g.val_of_col(k)) {
                y[(i, k)] = v;
            }
        }
        solve_m(y.as_mut());
        let c = transpose_times(&g, y.as_ref());
        let c = Mat::<f64>::from_fn(p, p, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
        let dependent = |k: usize| {
            format!(
                "{shown}: column {k} of {name} depends on the columns before it (G^T M^-1 G is singular): an equality constraint repeated or implied by the others leaves its multiplier undetermined; remove it"
            )
        };
        let factor = c.llt(Side::Lower).map_err(|e| {
            let k = match e {
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => index,
            };
            dependent(k)
        })?;
        let l = factor.L();
        if let Some(k) = (0..p).find(|&k| l[(k, k)] * l[(k, k)] <= DEPENDENT * c[(k, k)]) {
            return Err(dependent(k));
        }
        Ok(Self { g, b, y, c: factor })
    }

    /// The number of constraints p.
    pub(super) fn len(&self) -> usize {
        self.b.len()
    }

    /// x (a velocity without the constraints, M x = H r + f) becomes
    /// v = x − Y C⁻¹ (Gᵀ x + b), which satisfies Gᵀ v + b = 0.
    pub(super) fn project(&self, x: &mut [f64]) {
        let mut t = transpose_times(&self.g, MatRef::from_column_major_slice(x, x.len(), 1));
        for (k, bk) in self.b.iter().enumerate() {
            t[(k, 0)] += bk;
        }
        let minus_lambda = self.c.solve(&t);
        for (i, xi) in x.iter_mut().enumerate() {
            *xi -= (0..self.len())
                .map(|k| self.y[(i, k)] * minus_lambda[(k, 0)])
                .sum::<f64>();
        }
    }

    /// W (= Hᵀ M⁻¹ H on entry) becomes Hᵀ M⁻¹ H − Z C⁻¹ Zᵀ, Z = Hᵀ Y
    /// (the caller symmetrises W afterwards).
    pub(super) fn reduce_delassus(&self, h: &SparseColMat<usize, f64>, w: &mut Mat<f64>) {
        let z = transpose_times(h, self.y.as_ref());
        let c_inv_zt = self.c.solve(z.transpose());
        subtract_product(w.as_mut(), z.as_ref(), c_inv_zt.as_ref(), faer::Par::Seq);
    }
}

/// Aᵀ X for a sparse A (n × k) and a dense X (n × c): k × c.
pub(super) fn transpose_times(a: &SparseColMat<usize, f64>, x: faer::MatRef<'_, f64>) -> Mat<f64> {
    Mat::<f64>::from_fn(a.ncols(), x.ncols(), |k, c| {
        let rows = a.row_idx_of_col_raw(k).iter();
        rows.zip(a.val_of_col(k))
            .map(|(&i, &v)| v * x[(i, c)])
            .sum()
    })
}
