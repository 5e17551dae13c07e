//! The interface stiffness S = Σ_i S_i on Γ (seed §1.4, §8.3) and the
//! factor of it the Delassus operator applies.
//!
//! One subdomain's Schur complement S_i is dense on its own interface DOFs;
//! with several subdomains, S is a sparse matrix of dense blocks: two Γ DOFs
//! are coupled only when one subdomain holds both (glue DOFs are shared by
//! two to four subdomains). [`InterfaceStiffness::from_blocks`] assembles it
//! in compressed columns without the dense n_Γ × n_Γ matrix, and
//! [`SchurFactor`] factorises it by a supernodal sparse Cholesky (ordering by
//! `signorini_condense::ordering`, AMD or nested dissection, the cheaper)
//! unless its symbolic factor shows that a dense Cholesky costs less
//! ([`SPARSE_FLOP_RATIO`]).
//!
//! Floating bodies make S singular with a known kernel R (orthonormal, the
//! rigid modes on Γ). The dense factor keeps the seed's regularisation
//! S + ρRRᵀ (its inverse is a generalised inverse of S). The sparse factor
//! cannot add the dense RRᵀ: it uses the generalised inverse of FETI's
//! "fixing DOFs" (Farhat & Roux; Brzobohatý et al.): k DOFs J chosen so
//! that R_J is well conditioned (column-pivoted QR of Rᵀ), S̃ = S with the
//! rows and columns of J replaced by the identity (scaled), and
//! S⁺ = S̃⁻¹ Z, Z zeroing the entries on J. S̃ is positive definite when the
//! kernel of S is exactly span R, and S S⁺ S = S. Any generalised inverse
//! gives the same forces and displacements: the equilibrium constraint
//! Gᵀλ = e and the rigid amplitudes α absorb the difference.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Mat, MatMut, MatRef, Par, Side};
use signorini_condense::ordering::{
    order_and_analyse_with_last, FactorStats, Ordering, OrderingChoice,
};

use crate::delassus::SparseRow;
use crate::ContactError;

/// The sparse factor is kept when it needs at most this fraction of the
/// flops of the dense Cholesky (n³/3): a dense factorisation runs at a few
/// times the flop rate of the supernodal one on the same matrix.
pub const SPARSE_FLOP_RATIO: f64 = 0.5;

/// The interface stiffness S on Γ, symmetric positive semi-definite.
pub enum InterfaceStiffness {
    Dense(Mat<f64>),
    /// Both triangles stored, rows sorted in each column.
    Sparse(SparseColMat<usize, f64>),
}

/// How the interface stiffness was factorised, for the report.
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceFactorStats {
    /// "dense" or "sparse".
    pub storage: &'static str,
    /// Stored entries of S (both triangles).
    pub matrix_nnz: usize,
    /// The sparse factor's statistics (also when the dense one was kept).
    pub sparse: Option<FactorStats>,
    /// Bytes of the factor kept.
    pub factor_bytes: usize,
    /// The fixing DOFs of the floating bodies' rigid modes (sparse factor).
    pub fixing_dofs: usize,
}

impl InterfaceStiffness {
    /// Σ_i of the dense blocks `schur` (column-major, nb × nb) on the Γ DOFs
    /// `gamma` (block index → Γ index), in compressed columns: the pattern
    /// is the union of the blocks' cliques.
    pub fn from_blocks(n: usize, blocks: &[(&[usize], &[f64])]) -> Self {
        let (holders, patterns, pattern_of) = column_patterns(n, blocks);
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        for &p in &pattern_of {
            col_ptr.push(col_ptr[col_ptr.len() - 1] + patterns[p].len());
        }
        let mut row_idx = Vec::with_capacity(col_ptr[n]);
        let mut values = vec![0.0; col_ptr[n]];
        let mut position = vec![usize::MAX; n];
        for (c, held) in holders.iter().enumerate() {
            let pattern = &patterns[pattern_of[c]];
            row_idx.extend_from_slice(pattern);
            for (k, &r) in pattern.iter().enumerate() {
                position[r] = k;
            }
            let column = &mut values[col_ptr[c]..col_ptr[c + 1]];
            for &(b, j) in held {
                let (gamma, schur) = blocks[b];
                let nb = gamma.len();
                for (&g, &v) in gamma.iter().zip(&schur[nb * j..nb * (j + 1)]) {
                    column[position[g]] += v;
                }
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        InterfaceStiffness::Sparse(SparseColMat::new(symbolic, values))
    }

    pub fn nrows(&self) -> usize {
        match self {
            InterfaceStiffness::Dense(s) => s.nrows(),
            InterfaceStiffness::Sparse(s) => s.nrows(),
        }
    }

    /// The diagonal of S.
    pub fn diagonal(&self) -> Vec<f64> {
        match self {
            InterfaceStiffness::Dense(s) => (0..s.nrows()).map(|i| s[(i, i)]).collect(),
            InterfaceStiffness::Sparse(s) => sparse_diagonal(s),
        }
    }

    /// S X for a dense X.
    pub fn mul(&self, x: &Mat<f64>) -> Mat<f64> {
        match self {
            InterfaceStiffness::Dense(s) => s * x,
            InterfaceStiffness::Sparse(s) => s * x,
        }
    }
}

fn sparse_diagonal(s: &SparseColMat<usize, f64>) -> Vec<f64> {
    (0..s.ncols())
        .map(|j| {
            let rows = s.row_idx_of_col_raw(j);
            rows.binary_search(&j).map_or(0.0, |p| s.val_of_col(j)[p])
        })
        .collect()
}

fn sparse_norm1(s: &SparseColMat<usize, f64>) -> f64 {
    (0..s.ncols())
        .map(|j| s.val_of_col(j).iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// The holders of each column, the distinct row patterns and each column's
/// pattern (see [`column_patterns`]).
type ColumnPatterns = (Vec<Vec<(usize, usize)>>, Vec<Vec<usize>>, Vec<usize>);

/// Which blocks hold each Γ DOF ((block, its index there), blocks in
/// order), and the row pattern of each column: the sorted union of its
/// holders' Γ DOFs, made once per distinct set of holders (the DOFs of one
/// face, edge or corner of the decomposition share it) and referred to by
/// index. Sorting each column's rows instead took seconds for the 8-part
/// sphere (14,298 columns, 7.7e7 entries).
fn column_patterns(n: usize, blocks: &[(&[usize], &[f64])]) -> ColumnPatterns {
    let mut holders: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (b, (gamma, _)) in blocks.iter().enumerate() {
        for (j, &g) in gamma.iter().enumerate() {
            holders[g].push((b, j));
        }
    }
    let mut index: std::collections::HashMap<Vec<usize>, usize> = Default::default();
    let mut patterns: Vec<Vec<usize>> = Vec::new();
    let mut pattern_of = Vec::with_capacity(n);
    for held in &holders {
        let set: Vec<usize> = held.iter().map(|&(b, _)| b).collect();
        let p = *index.entry(set).or_insert_with_key(|set| {
            let mut rows: Vec<usize> = set
                .iter()
                .flat_map(|&b| blocks[b].0.iter().copied())
                .collect();
            rows.sort_unstable();
            rows.dedup();
            patterns.push(rows);
            patterns.len() - 1
        });
        pattern_of.push(p);
    }
    (holders, patterns, pattern_of)
}

/// The factor of S that applies a generalised inverse S⁺ (module doc).
pub struct SchurFactor {
    kind: FactorKind,
    n: usize,
    stats: InterfaceFactorStats,
    /// ‖·‖₁ of the matrix factorised (S, S + ρRRᵀ or S̃), for κ estimates.
    norm1: f64,
}

enum FactorKind {
    /// L L^T = P (S + ρRRᵀ) Pᵀ, the lower triangle of `l`; factor row k is
    /// the Γ DOF `order[k]`, the contact DOFs last in `contact`'s order.
    Dense {
        l: Mat<f64>,
        order: Vec<usize>,
        contact: Vec<usize>,
    },
    Sparse {
        symbolic: Box<SymbolicCholesky<usize>>,
        l_values: Vec<f64>,
        fixed: Vec<usize>,
        /// The contact DOFs, sorted: eliminated last, in this order (the
        /// trailing rows of the factor).
        contact: Vec<usize>,
    },
}

fn not_definite() -> ContactError {
    ContactError::Singular(
        "the interface stiffness S is not positive definite beyond the rigid modes of the floating bodies: a body is free to move in a way its supports do not prevent".into(),
    )
}

impl SchurFactor {
    /// Factorises S, with `r` the orthonormal kernel (n × k, k = 0 without
    /// floating bodies) and `contact` the Γ DOFs the contact rows touch (a
    /// sparse S is factorised with them last, so that W needs only the
    /// trailing block of the factor, [`Self::delassus`]).
    pub fn new(
        s: &InterfaceStiffness,
        r: &Mat<f64>,
        contact: &[usize],
    ) -> Result<Self, ContactError> {
        let mut contact = contact.to_vec();
        contact.sort_unstable();
        contact.dedup();
        match s {
            InterfaceStiffness::Dense(s) => Self::dense(s, r, contact, None),
            InterfaceStiffness::Sparse(s) => Self::sparse(s, r, contact),
        }
    }

    /// Dense Cholesky of P (S + ρRRᵀ) Pᵀ with the contact DOFs last (ρ the
    /// mean |diagonal|: any ρ > 0 gives the same answer, this one keeps the
    /// matrix well scaled), in place on its lower triangle
    /// (`recursive_cholesky`).
    fn dense(
        s: &Mat<f64>,
        r: &Mat<f64>,
        contact: Vec<usize>,
        sparse: Option<(FactorStats, usize)>,
    ) -> Result<Self, ContactError> {
        let n = s.nrows();
        let order = contact_last(n, &contact);
        let mut l = Mat::<f64>::from_fn(
            n,
            n,
            |i, j| {
                if i >= j {
                    s[(order[i], order[j])]
                } else {
                    0.0
                }
            },
        );
        if r.ncols() > 0 {
            let rho = regularisation_scale(&(0..n).map(|i| s[(i, i)]).collect::<Vec<_>>());
            let r_p = Mat::<f64>::from_fn(n, r.ncols(), |i, j| r[(order[i], j)]);
            faer::linalg::matmul::triangular::matmul(
                l.as_mut(),
                faer::linalg::matmul::triangular::BlockStructure::TriangularLower,
                faer::Accum::Add,
                r_p.as_ref(),
                faer::linalg::matmul::triangular::BlockStructure::Rectangular,
                r_p.transpose(),
                faer::linalg::matmul::triangular::BlockStructure::Rectangular,
                rho,
                Par::Seq,
            );
        }
        let norm1 = lower_symmetric_norm1(&l);
        crate::recursive_cholesky::cholesky(l.as_mut(), faer::get_global_parallelism())
            .map_err(|_| not_definite())?;
        let stats = InterfaceFactorStats {
            storage: "dense",
            matrix_nnz: sparse.map_or(n * n, |(_, nnz)| nnz),
            sparse: sparse.map(|(st, _)| st),
            factor_bytes: 8 * n * n,
            fixing_dofs: 0,
        };
        Ok(Self {
            kind: FactorKind::Dense { l, order, contact },
            n,
            stats,
            norm1,
        })
    }

    /// Sparse Cholesky of P S̃ Pᵀ (S with the fixing DOFs of the kernel
    /// replaced by the identity, the contact DOFs last), or the dense factor
    /// when that costs fewer flops.
    fn sparse(
        s: &SparseColMat<usize, f64>,
        r: &Mat<f64>,
        contact: Vec<usize>,
    ) -> Result<Self, ContactError> {
        let n = s.nrows();
        let fixed = fixing_dofs(r);
        let s_fixed = if fixed.is_empty() {
            std::borrow::Cow::Borrowed(s)
        } else {
            let scale = regularisation_scale(&sparse_diagonal(s));
            std::borrow::Cow::Owned(with_fixed_dofs(s, &fixed, scale))
        };
        let s_fixed: &SparseColMat<usize, f64> = &s_fixed;
        let choice = OrderingChoice::Only(Ordering::BlockMinimumDegree);
        let ordered = order_and_analyse_with_last(s_fixed.as_ref(), &contact, choice)
            .map_err(|e| ContactError::Solve(format!("interface ordering: {e}")))?;
        let dense_flops = (n as f64).powi(3) / 3.0;
        if ordered.stats.flops > SPARSE_FLOP_RATIO * dense_flops {
            let dense = s.to_dense();
            return Self::dense(&dense, r, contact, Some((ordered.stats, s.compute_nnz())));
        }
        let symbolic = Box::new(ordered.symbolic);
        let mut l_values = vec![0.0f64; symbolic.len_val()];
        let par = faer::get_global_parallelism();
        let mut mem =
            MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut l_values,
                s_fixed.as_ref(),
                Side::Lower,
                LltRegularization::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|_| not_definite())?;
        let stats = InterfaceFactorStats {
            storage: "sparse",
            matrix_nnz: s.compute_nnz(),
            sparse: Some(ordered.stats),
            factor_bytes: 8 * l_values.len(),
            fixing_dofs: fixed.len(),
        };
        Ok(Self {
            kind: FactorKind::Sparse {
                symbolic,
                l_values,
                fixed,
                contact,
            },
            n,
            stats,
            norm1: sparse_norm1(s_fixed),
        })
    }

    pub fn stats(&self) -> &InterfaceFactorStats {
        &self.stats
    }

    /// x ← S⁺ x, column by column.
    pub fn solve_in_place(&self, mut x: MatMut<'_, f64>) {
        match &self.kind {
            FactorKind::Dense { l, order, .. } => dense_solve(l, order, x),
            FactorKind::Sparse {
                symbolic,
                l_values,
                fixed,
                ..
            } => {
                for j in 0..x.ncols() {
                    for &i in fixed {
                        x[(i, j)] = 0.0;
                    }
                }
                let par = faer::get_global_parallelism();
                let mut mem =
                    MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(x.ncols(), par));
                LltRef::new(symbolic, l_values).solve_in_place_with_conj(
                    Conj::No,
                    x.as_mut(),
                    par,
                    MemStack::new(&mut mem),
                );
                for j in 0..x.ncols() {
                    for &i in fixed {
                        x[(i, j)] = 0.0;
                    }
                }
            }
        }
    }

    /// W = B S⁺ Bᵀ (m × m, symmetric) for the contact rows `b`. The
    /// contact DOFs C are eliminated last: P S̃ Pᵀ = L Lᵀ (S̃ = S + ρRRᵀ
    /// dense, S with its fixing DOFs replaced by the identity sparse) and B
    /// touches only C, so L⁻¹ P Z Bᵀ = [0; L_CC⁻¹ B_C] and W = Yᵀ Y with
    /// Y = L_CC⁻¹ B_C: one dense triangular solve with the trailing block of
    /// the factor instead of m solves with all of it.
    pub fn delassus(&self, b: &[SparseRow]) -> Result<Mat<f64>, ContactError> {
        let n = self.n;
        let trailing;
        let (l_cc, fixed, contact): (MatRef<'_, f64>, &[usize], &[usize]) = match &self.kind {
            FactorKind::Sparse {
                symbolic,
                l_values,
                fixed,
                contact,
            } => {
                let nc = contact.len();
                trailing = signorini_condense::trailing_block(symbolic, l_values, n - nc, nc)
                    .map_err(|e| ContactError::Solve(format!("interface factor: {e}")))?;
                (trailing.as_ref(), fixed, contact)
            }
            FactorKind::Dense { l, contact, .. } => {
                let nc = contact.len();
                (l.as_ref().submatrix(n - nc, n - nc, nc, nc), &[], contact)
            }
        };
        let (nc, m) = (contact.len(), b.len());
        let mut y = Mat::<f64>::zeros(nc, m);
        for (p, row) in b.iter().enumerate() {
            for &(i, c) in row {
                if let (Err(_), Ok(k)) = (fixed.binary_search(&i), contact.binary_search(&i)) {
                    y[(k, p)] += c;
                }
            }
        }
        let par = faer::get_global_parallelism();
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(l_cc, y.as_mut(), par);
        let mut w = Mat::<f64>::zeros(m, m);
        use faer::linalg::matmul::triangular::{matmul, BlockStructure};
        matmul(
            w.as_mut(),
            BlockStructure::TriangularLower,
            faer::Accum::Replace,
            y.transpose(),
            BlockStructure::Rectangular,
            y.as_ref(),
            BlockStructure::Rectangular,
            1.0,
            par,
        );
        for j in 0..m {
            for i in j + 1..m {
                w[(j, i)] = w[(i, j)];
            }
        }
        Ok(w)
    }

    /// S⁺ applied to one vector.
    pub fn solve(&self, v: &[f64]) -> Vec<f64> {
        let mut x = Mat::<f64>::from_fn(self.n, 1, |i, _| v[i]);
        self.solve_in_place(x.as_mut());
        (0..self.n).map(|i| x[(i, 0)]).collect()
    }

    /// κ₁ of the matrix factorised by the Hager–Higham estimator (a dozen
    /// solves with the factor). With fixing DOFs, the solve is that of S̃
    /// itself (its rows on J are the scaled identity).
    pub fn condition(&self) -> f64 {
        use signorini_condense::conditioning::inverse_norm1_estimate;
        let inv = inverse_norm1_estimate(self.n, |x| {
            let xm = faer::MatMut::from_column_major_slice_mut(x, self.n, 1);
            match &self.kind {
                FactorKind::Dense { l, order, .. } => dense_solve(l, order, xm),
                FactorKind::Sparse {
                    symbolic, l_values, ..
                } => {
                    let par = Par::Seq;
                    let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
                    LltRef::new(symbolic, l_values).solve_in_place_with_conj(
                        Conj::No,
                        xm,
                        par,
                        MemStack::new(&mut mem),
                    );
                }
            }
        });
        self.norm1 * inv
    }
}

/// The factor's numbering of the n Γ DOFs: the others in their order, then
/// the contact DOFs `contact` (sorted) in theirs.
fn contact_last(n: usize, contact: &[usize]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n)
        .filter(|i| contact.binary_search(i).is_err())
        .collect();
    order.extend_from_slice(contact);
    order
}

/// x ← A⁻¹ x for L Lᵀ = P A Pᵀ, `order` the permutation P (factor row k is
/// row `order[k]` of A).
fn dense_solve(l: &Mat<f64>, order: &[usize], mut x: MatMut<'_, f64>) {
    let mut y = Mat::<f64>::from_fn(order.len(), x.ncols(), |k, j| x[(order[k], j)]);
    let par = faer::get_global_parallelism();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), y.as_mut(), par);
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(l.transpose(), y.as_mut(), par);
    for (k, &i) in order.iter().enumerate() {
        for j in 0..x.ncols() {
            x[(i, j)] = y[(k, j)];
        }
    }
}

/// ‖A‖₁ of the symmetric A whose lower triangle is that of `a`.
fn lower_symmetric_norm1(a: &Mat<f64>) -> f64 {
    let n = a.nrows();
    let mut sums = vec![0.0f64; n];
    for j in 0..n {
        for i in j..n {
            let v = a[(i, j)].abs();
            sums[j] += v;
            if i != j {
                sums[i] += v;
            }
        }
    }
    sums.into_iter().fold(0.0, f64::max)
}

/// ρ for S + ρRRᵀ and the scale of the identity on fixing DOFs: the mean
/// |diagonal| of S (1 for an empty or zero S).
fn regularisation_scale(diagonal: &[f64]) -> f64 {
    let n = diagonal.len().max(1) as f64;
    let mean = diagonal.iter().map(|d| d.abs()).sum::<f64>() / n;
    if mean > 0.0 {
        mean
    } else {
        1.0
    }
}

/// k rows J of the orthonormal R (n × k) with R_J well conditioned: the
/// pivots of a column-pivoted QR of Rᵀ (greedily the row farthest from the
/// span of the rows already chosen). Sorted.
pub fn fixing_dofs(r: &Mat<f64>) -> Vec<usize> {
    let (n, k) = (r.nrows(), r.ncols());
    let mut rows: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..k).map(|j| r[(i, j)]).collect())
        .collect();
    let mut chosen = Vec::with_capacity(k);
    for _ in 0..k {
        let norm2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
        let Some(p) = (0..n)
            .filter(|i| !chosen.contains(i))
            .max_by(|&a, &b| norm2(&rows[a]).total_cmp(&norm2(&rows[b])))
        else {
            break;
        };
        let norm = norm2(&rows[p]).sqrt();
        if norm == 0.0 {
            break;
        }
        let q: Vec<f64> = rows[p].iter().map(|x| x / norm).collect();
        for row in rows.iter_mut() {
            let d: f64 = row.iter().zip(&q).map(|(a, b)| a * b).sum();
            for (a, b) in row.iter_mut().zip(&q) {
                *a -= d * b;
            }
        }
        chosen.push(p);
    }
    chosen.sort_unstable();
    chosen
}

/// S with the rows and columns of `fixed` zeroed and `scale` on their
/// diagonal (same pattern).
fn with_fixed_dofs(
    s: &SparseColMat<usize, f64>,
    fixed: &[usize],
    scale: f64,
) -> SparseColMat<usize, f64> {
    let mut out = s.clone();
    let mut is_fixed = vec![false; s.nrows()];
    for &i in fixed {
        is_fixed[i] = true;
    }
    for j in 0..s.ncols() {
        let rows = s.row_idx_of_col_raw(j).to_vec();
        let vals = out.val_of_col_mut(j);
        for (v, &i) in vals.iter_mut().zip(&rows) {
            if is_fixed[i] || is_fixed[j] {
                *v = if i == j { scale } else { 0.0 };
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Laplacian of the complete graph on `k` vertices, column-major:
    /// positive semi-definite, kernel the constants.
    fn clique_laplacian(k: usize, scale: f64) -> Vec<f64> {
        (0..k * k)
            .map(|e| {
                let (i, j) = (e % k, e / k);
                scale * if i == j { k as f64 - 1.0 } else { -1.0 }
            })
            .collect()
    }

    /// `parts` cliques of `own + 2 glue` DOFs in a ring (each shares `glue`
    /// DOFs with the next), plus `spring` on the diagonal.
    /// The dense factor with the contact DOFs last gives the W and the
    /// solves of the plain formulas B (S + ρRRᵀ)⁻¹ Bᵀ, held (the sparse
    /// factor's W too) and floating (the kernel of a ring without springs:
    /// the constants).
    #[test]
    fn dense_factor_with_contact_last_gives_the_plain_delassus_operator() {
        let rows: Vec<SparseRow> =
            vec![vec![(3, 1.0)], vec![(17, 0.6), (40, -0.8)], vec![(40, 2.0)]];
        for spring in [0.5, 0.0] {
            let (n, s, dense) = ring(8, 12, 3, spring);
            let r = if spring > 0.0 {
                Mat::<f64>::zeros(n, 0)
            } else {
                Mat::<f64>::from_fn(n, 1, |_, _| 1.0 / (n as f64).sqrt())
            };
            let factor =
                SchurFactor::new(&InterfaceStiffness::Dense(dense.clone()), &r, &[40, 3, 17])
                    .unwrap();
            let rho = regularisation_scale(&(0..n).map(|i| dense[(i, i)]).collect::<Vec<_>>());
            let reg = if r.ncols() > 0 {
                &dense + rho * &r * r.transpose()
            } else {
                dense.clone()
            };
            let llt = reg.llt(Side::Lower).unwrap();
            let bt = Mat::<f64>::from_fn(n, rows.len(), |i, p| {
                rows[p].iter().filter(|e| e.0 == i).map(|e| e.1).sum()
            });
            let mut x = bt.clone();
            faer::linalg::solvers::SolveCore::solve_in_place_with_conj(&llt, Conj::No, x.as_mut());
            let plain = bt.transpose() * &x;
            let w = factor.delassus(&rows).unwrap();
            let scale = plain.norm_max();
            assert!((&w - &plain).norm_max() <= 1e-12 * scale, "{w:?} {plain:?}");
            let solved = factor.solve(&(0..n).map(|i| bt[(i, 1)]).collect::<Vec<_>>());
            let err = (0..n)
                .map(|i| (solved[i] - x[(i, 1)]).abs())
                .fold(0.0, f64::max);
            assert!(err <= 1e-12 * x.norm_max(), "{err}");
            if spring > 0.0 {
                let sparse = SchurFactor::new(&s, &r, &[3, 17, 40]).unwrap();
                assert_eq!(sparse.stats().storage, "sparse");
                assert!((&sparse.delassus(&rows).unwrap() - &plain).norm_max() <= 1e-12 * scale);
            }
        }
    }

    fn ring(
        parts: usize,
        own: usize,
        glue: usize,
        spring: f64,
    ) -> (usize, InterfaceStiffness, Mat<f64>) {
        let per = own + glue;
        let n = parts * per;
        let mut gammas = Vec::new();
        let mut values = Vec::new();
        for p in 0..parts {
            let next = (p + 1) % parts;
            let g: Vec<usize> = (0..per)
                .map(|i| per * p + i)
                .chain((0..glue).map(|i| per * next + own + i))
                .collect();
            let mut v = clique_laplacian(g.len(), 1.0 + p as f64);
            for i in 0..g.len() {
                v[i + g.len() * i] += spring;
            }
            gammas.push(g);
            values.push(v);
        }
        let blocks: Vec<(&[usize], &[f64])> = gammas
            .iter()
            .zip(&values)
            .map(|(g, v)| (g.as_slice(), v.as_slice()))
            .collect();
        let s = InterfaceStiffness::from_blocks(n, &blocks);
        let mut dense = Mat::<f64>::zeros(n, n);
        for (g, v) in gammas.iter().zip(&values) {
            let nb = g.len();
            for j in 0..nb {
                for i in 0..nb {
                    dense[(g[i], g[j])] += v[i + nb * j];
                }
            }
        }
        (n, s, dense)
    }

    #[test]
    fn blocks_assemble_to_the_dense_sum() {
        let (n, s, dense) = ring(6, 4, 2, 0.5);
        let InterfaceStiffness::Sparse(sp) = &s else {
            panic!("from_blocks is sparse")
        };
        assert_eq!(sp.to_dense(), dense);
        // each DOF couples with its own clique or two: far from n² entries
        assert!(
            sp.compute_nnz() < n * n / 2,
            "{} of {}",
            sp.compute_nnz(),
            n * n
        );
        assert_eq!(
            s.diagonal(),
            (0..n).map(|i| dense[(i, i)]).collect::<Vec<_>>()
        );
    }

    #[test]
    fn sparse_factor_solves_like_the_dense_one_and_a_dense_block_stays_dense() {
        let (n, s, dense) = ring(8, 12, 3, 0.5);
        let r = Mat::<f64>::zeros(n, 0);
        let sparse = SchurFactor::new(&s, &r, &[3, 17, 40]).unwrap();
        assert_eq!(sparse.stats().storage, "sparse", "{:?}", sparse.stats());
        let full = SchurFactor::new(&InterfaceStiffness::Dense(dense.clone()), &r, &[]).unwrap();
        let f: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 - 5.0).collect();
        let (a, b) = (sparse.solve(&f), full.solve(&f));
        let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(a
            .iter()
            .zip(&b)
            .all(|(x, y)| (x - y).abs() <= 1e-12 * scale));
        // One block holding every DOF: its sparse factor is dense, kept dense.
        let k = 30;
        let g: Vec<usize> = (0..k).collect();
        let mut v = clique_laplacian(k, 1.0);
        for i in 0..k {
            v[i + k * i] += 1.0;
        }
        let one = InterfaceStiffness::from_blocks(k, &[(&g, &v)]);
        let f = SchurFactor::new(&one, &Mat::zeros(k, 0), &[]).unwrap();
        assert_eq!(f.stats().storage, "dense");
        assert!(f.stats().sparse.is_some(), "the sparse cost was measured");
    }

    #[test]
    fn fixing_dofs_give_a_generalised_inverse_of_a_floating_interface() {
        // No spring: S is singular with the constants as kernel.
        let (n, s, dense) = ring(8, 12, 3, 0.0);
        let norm = (n as f64).sqrt();
        let r = Mat::<f64>::from_fn(n, 1, |_, _| 1.0 / norm);
        let factor = SchurFactor::new(&s, &r, &[0, 5, 77]).unwrap();
        assert_eq!(factor.stats().storage, "sparse");
        assert_eq!(factor.stats().fixing_dofs, 1);
        // S S⁺ S = S: x = S⁺ S, then S x
        let mut x = dense.clone();
        factor.solve_in_place(x.as_mut());
        let sss = &dense * &x;
        let err = (&sss - &dense).norm_max();
        assert!(err <= 1e-10 * dense.norm_max(), "‖S S⁺ S − S‖ = {err:e}");
        // A balanced load: S (S⁺ f) = f
        let mut f: Vec<f64> = (0..n).map(|i| (i % 5) as f64).collect();
        let mean = f.iter().sum::<f64>() / n as f64;
        f.iter_mut().for_each(|v| *v -= mean);
        let u = factor.solve(&f);
        let su = &dense * Mat::<f64>::from_fn(n, 1, |i, _| u[i]);
        assert!((0..n).all(|i| (su[(i, 0)] - f[i]).abs() <= 1e-10));
    }

    #[test]
    fn fixing_dofs_of_a_planar_rigid_body_pick_well_separated_rows() {
        // Rigid modes of 4 points of a square (2 DOFs each): the chosen rows
        // make R_J invertible.
        let pts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let mut kernel = Mat::<f64>::zeros(8, 3);
        for (p, x) in pts.iter().enumerate() {
            kernel[(2 * p, 0)] = 1.0;
            kernel[(2 * p + 1, 1)] = 1.0;
            kernel[(2 * p, 2)] = -x[1];
            kernel[(2 * p + 1, 2)] = x[0];
        }
        let q = kernel.qr().compute_thin_Q();
        let j = fixing_dofs(&q);
        assert_eq!(j.len(), 3);
        let rj = Mat::<f64>::from_fn(3, 3, |a, b| q[(j[a], b)]);
        let det = rj.determinant();
        assert!(det.abs() > 0.1, "R_J = {rj:?}");
    }
}
