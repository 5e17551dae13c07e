//! The interface stiffness S = Σ_i S_i on Γ (course notes §8.3; docs/architecture.md, "Libraries") and the
//! factor of it the Delassus operator applies.
//!
//! One subdomain's Schur complement S_i is dense on its own interface DOFs:
//! one subdomain gives a dense S, factorised by a dense Cholesky with the
//! contact DOFs last. With several, S is a sparse matrix of dense blocks
//! (two Γ DOFs are coupled only when one subdomain holds both), never
//! assembled: [`InterfaceStiffness::Blocks`] keeps the blocks and
//! `interface::tree` factorises S over a tree of the subdomains, the
//! contact DOFs last too, so that W = B S⁺ Bᵀ = YᵀY needs only the
//! trailing block L_CC of either factor.
//!
//! Floating bodies make S singular with a known kernel R (orthonormal, the
//! rigid modes on Γ). The dense factor keeps the regularisation
//! S + ρRRᵀ (its inverse is a generalised inverse of S). The tree factor
//! cannot add the dense RRᵀ: it uses the generalised inverse of FETI's
//! "fixing DOFs" (Farhat & Roux; Brzobohatý et al.): k DOFs J chosen so
//! that R_J is well conditioned (column-pivoted QR of Rᵀ), S̃ = S with the
//! rows and columns of J replaced by the identity (scaled), and
//! S⁺ = S̃⁻¹ Z, Z zeroing the entries on J. S̃ is positive definite when the
//! kernel of S is exactly span R, and S S⁺ S = S. Any generalised inverse
//! gives the same forces and displacements: the equilibrium constraint
//! Gᵀλ = e and the rigid amplitudes α absorb the difference.

use faer::{Mat, MatMut, MatRef, Par};

use signorini_linalg::ordered_cholesky::{add_trailing_delassus, dense_solve};
use signorini_linalg::sparse::SparseRow;
use signorini_linalg::LinalgError;

mod tree;
pub use tree::SchurBlock;
use tree::TreeFactor;

/// The interface stiffness S on Γ, symmetric positive semi-definite.
pub enum InterfaceStiffness {
    Dense(Mat<f64>),
    /// The subdomains' dense blocks S_i on n Γ DOFs, never assembled
    /// (factorised over a tree of subdomains, `tree`).
    Blocks {
        n: usize,
        blocks: Vec<SchurBlock>,
    },
}

/// How the interface stiffness was factorised, for the report.
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceFactorStats {
    /// "dense" (one subdomain) or "tree" (several, `tree`).
    pub storage: &'static str,
    /// Entries of S stored: n_Γ² dense, Σ_i n_i² in the subdomains' blocks.
    pub matrix_nnz: usize,
    /// The tree factor's flops and entries.
    pub tree: Option<(f64, usize)>,
    /// Bytes of the factor.
    pub factor_bytes: usize,
    /// The fixing DOFs of the floating bodies' rigid modes (tree factor).
    pub fixing_dofs: usize,
}

impl InterfaceStiffness {
    pub fn nrows(&self) -> usize {
        match self {
            InterfaceStiffness::Dense(s) => s.nrows(),
            InterfaceStiffness::Blocks { n, .. } => *n,
        }
    }

    /// The diagonal of S.
    pub fn diagonal(&self) -> Vec<f64> {
        match self {
            InterfaceStiffness::Dense(s) => (0..s.nrows()).map(|i| s[(i, i)]).collect(),
            InterfaceStiffness::Blocks { n, blocks } => blocks_diagonal(*n, blocks),
        }
    }

    /// S X for a dense X.
    pub fn mul(&self, x: &Mat<f64>) -> Mat<f64> {
        match self {
            InterfaceStiffness::Dense(s) => s * x,
            InterfaceStiffness::Blocks { n, blocks } => blocks_mul(*n, blocks, x.as_ref()),
        }
    }
}

/// The diagonal of Σ_i S_i.
fn blocks_diagonal(n: usize, blocks: &[SchurBlock]) -> Vec<f64> {
    let mut d = vec![0.0; n];
    for b in blocks {
        let nb = b.gamma.len();
        for (i, &g) in b.gamma.iter().enumerate() {
            d[g] += b.values[i + nb * i];
        }
    }
    d
}

/// ‖S̃‖₁ of S̃ = Σ_i S_i with the rows and columns of `fixed` (sorted)
/// replaced by `scale`·I: each column added up in a dense accumulator from
/// the blocks holding it (Σ_i n_i² additions, no assembled S).
fn blocks_norm1(n: usize, blocks: &[SchurBlock], fixed: &[usize], scale: f64) -> f64 {
    let mut holders: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (b, block) in blocks.iter().enumerate() {
        block
            .gamma
            .iter()
            .enumerate()
            .for_each(|(j, &g)| holders[g].push((b, j)));
    }
    let is_fixed = |i: &usize| fixed.binary_search(i).is_ok();
    let mut acc = vec![0.0f64; n];
    let mut norm = if fixed.is_empty() { 0.0 } else { scale.abs() };
    for (_, held) in holders.iter().enumerate().filter(|(c, _)| !is_fixed(c)) {
        let column = |&(b, j): &(usize, usize)| {
            let nb = blocks[b].gamma.len();
            blocks[b]
                .gamma
                .iter()
                .zip(&blocks[b].values[nb * j..nb * (j + 1)])
        };
        for (&g, &v) in held.iter().flat_map(column) {
            acc[g] += v;
        }
        let mut sum = 0.0;
        for (&g, _) in held.iter().flat_map(column) {
            if !is_fixed(&g) {
                sum += acc[g].abs();
            }
            acc[g] = 0.0;
        }
        norm = f64::max(norm, sum);
    }
    norm
}

/// (Σ_i S_i) X, block by block.
fn blocks_mul(n: usize, blocks: &[SchurBlock], x: MatRef<'_, f64>) -> Mat<f64> {
    let mut y = Mat::<f64>::zeros(n, x.ncols());
    for b in blocks {
        let nb = b.gamma.len();
        let s = MatRef::from_column_major_slice(&b.values, nb, nb);
        let xb = Mat::<f64>::from_fn(nb, x.ncols(), |i, j| x[(b.gamma[i], j)]);
        let yb = s * &xb;
        for j in 0..x.ncols() {
            for (i, &g) in b.gamma.iter().enumerate() {
                y[(g, j)] += yb[(i, j)];
            }
        }
    }
    y
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
    /// Over the tree of subdomains, with the fixing DOFs `fixed` (sorted).
    Tree { tree: TreeFactor, fixed: Vec<usize> },
    /// L L^T = P (S + ρRRᵀ) Pᵀ, the lower triangle of `l`; factor row k is
    /// the Γ DOF `order[k]`, the contact DOFs last in `contact`'s order.
    Dense {
        l: Mat<f64>,
        order: Vec<usize>,
        contact: Vec<usize>,
    },
}

/// S (plus the kernel term) has a pivot that is not positive at Γ DOF
/// `dof`: a body is free to move beyond the rigid modes it was given.
fn not_definite(dof: usize) -> LinalgError {
    LinalgError::NotPositiveDefinite { index: dof }
}

impl SchurFactor {
    /// Factorises S, with `r` the orthonormal kernel (n × k, k = 0 without
    /// floating bodies) and `contact` the Γ DOFs the contact rows touch
    /// (eliminated last by either factor, so that W needs only the trailing
    /// block of the factor, [`Self::delassus`]).
    pub fn new(
        s: InterfaceStiffness,
        r: &Mat<f64>,
        contact: &[usize],
    ) -> Result<Self, LinalgError> {
        let mut contact = contact.to_vec();
        contact.sort_unstable();
        contact.dedup();
        match s {
            InterfaceStiffness::Dense(s) => Self::dense(&s, r, contact),
            InterfaceStiffness::Blocks { n, blocks } => Self::tree(n, blocks, r, contact),
        }
    }

    /// Dense Cholesky of P (S + ρRRᵀ) Pᵀ with the contact DOFs last (ρ the
    /// mean |diagonal|: any ρ > 0 gives the same answer, this one keeps the
    /// matrix well scaled), in place on its lower triangle
    /// (`recursive_cholesky`).
    fn dense(s: &Mat<f64>, r: &Mat<f64>, contact: Vec<usize>) -> Result<Self, LinalgError> {
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
        signorini_linalg::recursive_cholesky::cholesky(l.as_mut(), faer::get_global_parallelism())
            .map_err(|i| not_definite(order[i]))?;
        let stats = InterfaceFactorStats {
            storage: "dense",
            matrix_nnz: n * n,
            tree: None,
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

    /// The factor of S̃ (S with the fixing DOFs of the kernel replaced by
    /// the identity) over the tree of subdomains, the contact DOFs last.
    fn tree(
        n: usize,
        blocks: Vec<SchurBlock>,
        r: &Mat<f64>,
        contact: Vec<usize>,
    ) -> Result<Self, LinalgError> {
        let fixed = fixing_dofs(r);
        let scale = regularisation_scale(&blocks_diagonal(n, &blocks));
        let norm1 = blocks_norm1(n, &blocks, &fixed, scale);
        let matrix_nnz = blocks.iter().map(|b| b.gamma.len().pow(2)).sum();
        let tree =
            TreeFactor::new(n, blocks, &contact, &fixed, scale).map_err(|e| not_definite(e.dof))?;
        let stats = InterfaceFactorStats {
            storage: "tree",
            matrix_nnz,
            tree: Some((tree.flops, tree.bytes / 8)),
            factor_bytes: tree.bytes,
            fixing_dofs: fixed.len(),
        };
        Ok(Self {
            kind: FactorKind::Tree { tree, fixed },
            n,
            stats,
            norm1,
        })
    }

    pub fn stats(&self) -> &InterfaceFactorStats {
        &self.stats
    }

    /// x ← S⁺ x, column by column.
    pub fn solve_in_place(&self, mut x: MatMut<'_, f64>) {
        match &self.kind {
            FactorKind::Dense { l, order, .. } => {
                dense_solve(l, order, x, faer::get_global_parallelism())
            }
            FactorKind::Tree { tree, fixed } => {
                zero_rows(&mut x, fixed);
                tree.solve_in_place(x.as_mut(), faer::get_global_parallelism());
                zero_rows(&mut x, fixed);
            }
        }
    }

    /// W = B S⁺ Bᵀ (m × m, symmetric) for the contact rows `b`. The
    /// contact DOFs C are eliminated last: P S̃ Pᵀ = L Lᵀ (S̃ = S + ρRRᵀ
    /// dense, S with its fixing DOFs replaced by the identity over the tree)
    /// and B touches only C, so L⁻¹ P Z Bᵀ = [0; L_CC⁻¹ B_C] and W = Yᵀ Y
    /// with Y = L_CC⁻¹ B_C: one dense triangular solve with the trailing
    /// block of the factor instead of m solves with all of it.
    pub fn delassus(&self, b: &[SparseRow]) -> Result<Mat<f64>, LinalgError> {
        let m = b.len();
        let mut w = Mat::<f64>::zeros(m, m);
        let par = faer::get_global_parallelism();
        match &self.kind {
            FactorKind::Dense { l, contact, .. } => {
                let (n, nc) = (self.n, contact.len());
                let l_cc = l.as_ref().submatrix(n - nc, n - nc, nc, nc);
                add_trailing_delassus(&mut w, l_cc, contact, &[], b, par);
            }
            FactorKind::Tree { tree, fixed } => tree.add_delassus(&mut w, b, fixed, par),
        }
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
        use signorini_linalg::conditioning::inverse_norm1_estimate;
        let inv = inverse_norm1_estimate(self.n, |x| {
            let xm = faer::MatMut::from_column_major_slice_mut(x, self.n, 1);
            match &self.kind {
                FactorKind::Dense { l, order, .. } => dense_solve(l, order, xm, Par::Seq),
                FactorKind::Tree { tree, .. } => tree.solve_in_place(xm, Par::Seq),
            }
        });
        self.norm1 * inv
    }
}

impl signorini_linalg::GeneralisedInverse for SchurFactor {
    fn solve(&self, v: &[f64]) -> Vec<f64> {
        SchurFactor::solve(self, v)
    }
}

/// What the Delassus operator W = B S⁺ Bᵀ is made of: the factor of S,
/// the orthonormal kernel R, W itself and, when asked for, κ₁ of the
/// matrix factorised.
pub struct InterfaceOperator {
    pub factor: SchurFactor,
    /// The rigid modes of the floating bodies on Γ, orthonormal (n × k).
    pub r: Mat<f64>,
    pub w: Mat<f64>,
    pub s_condition: Option<f64>,
}

impl InterfaceOperator {
    /// Factorises S with the kernel `kernel` (n × k, k = 0 without floating
    /// bodies; checked to be S's) and the contact DOFs of the rows `b` last,
    /// and forms W; estimates the condition of the matrix factorised when
    /// `estimate_condition` (a dozen O(n²) solves beside the factorisation).
    pub fn new(
        s: InterfaceStiffness,
        b: &[SparseRow],
        kernel: &Mat<f64>,
        estimate_condition: bool,
    ) -> Result<Self, LinalgError> {
        let n = s.nrows();
        let r = if kernel.ncols() > 0 {
            orthonormalize(kernel)?
        } else {
            Mat::zeros(n, 0)
        };
        if r.ncols() > 0 {
            check_kernel(&s, &r)?;
        }
        let mut contact: Vec<usize> = b.iter().flatten().map(|&(i, _)| i).collect();
        contact.sort_unstable();
        contact.dedup();
        let factor = SchurFactor::new(s, &r, &contact)?;
        let s_condition = estimate_condition.then(|| factor.condition());
        let w = factor.delassus(b)?;
        Ok(Self {
            factor,
            r,
            w,
            s_condition,
        })
    }
}

/// The columns of `r` made orthonormal (twice-repeated Gram–Schmidt);
/// rejects columns that are linearly dependent.
fn orthonormalize(r: &Mat<f64>) -> Result<Mat<f64>, LinalgError> {
    let (n, k) = (r.nrows(), r.ncols());
    let mut q = r.clone();
    for j in 0..k {
        for _pass in 0..2 {
            for i in 0..j {
                let d: f64 = (0..n).map(|t| q[(t, i)] * q[(t, j)]).sum();
                for t in 0..n {
                    q[(t, j)] -= d * q[(t, i)];
                }
            }
        }
        let nn: f64 = (0..n).map(|t| q[(t, j)].powi(2)).sum::<f64>().sqrt();
        let orig: f64 = (0..n).map(|t| r[(t, j)].powi(2)).sum::<f64>().sqrt();
        if nn <= 1e-10 * orig.max(f64::MIN_POSITIVE) {
            return Err(LinalgError::Singular(
                "the rigid modes of the floating bodies are linearly dependent on the interface"
                    .into(),
            ));
        }
        for t in 0..n {
            q[(t, j)] /= nn;
        }
    }
    Ok(q)
}

/// The kernel comes from the supports (the rigid modes they leave free, by a
/// rank test); checks that it is S's: ‖S r‖ must be round-off next to the
/// stiffness (r orthonormal).
fn check_kernel(s: &InterfaceStiffness, r: &Mat<f64>) -> Result<(), LinalgError> {
    let n = s.nrows();
    let smax = s.diagonal().iter().fold(0.0f64, |a, d| a.max(d.abs()));
    let worst = s.mul(r).norm_max();
    if worst.is_nan() || worst > 1e-8 * smax * (n as f64).sqrt() {
        return Err(LinalgError::NotKernel {
            residual: worst,
            scale: smax,
        });
    }
    Ok(())
}

/// Zeroes the rows `rows` of x.
fn zero_rows(x: &mut MatMut<'_, f64>, rows: &[usize]) {
    for j in 0..x.ncols() {
        for &i in rows {
            x[(i, j)] = 0.0;
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use faer::{Conj, Side};

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

    /// A ring of `parts` subdomains, each holding `own` DOFs and `glue`
    /// DOFs of the next (a clique Laplacian, plus `spring` on the diagonal:
    /// 0 leaves the constants as kernel): n, the blocks, the dense sum.
    fn ring(
        parts: usize,
        own: usize,
        glue: usize,
        spring: f64,
    ) -> (usize, InterfaceStiffness, Mat<f64>) {
        let per = own + glue;
        let n = parts * per;
        let blocks: Vec<SchurBlock> = (0..parts)
            .map(|p| {
                let next = (p + 1) % parts;
                let gamma: Vec<usize> = (0..per)
                    .map(|i| per * p + i)
                    .chain((0..glue).map(|i| per * next + own + i))
                    .collect();
                let mut values = clique_laplacian(gamma.len(), 1.0 + p as f64);
                for i in 0..gamma.len() {
                    values[i + gamma.len() * i] += spring;
                }
                SchurBlock { gamma, values }
            })
            .collect();
        let mut dense = Mat::<f64>::zeros(n, n);
        for b in &blocks {
            let nb = b.gamma.len();
            for j in 0..nb {
                for i in 0..nb {
                    dense[(b.gamma[i], b.gamma[j])] += b.values[i + nb * j];
                }
            }
        }
        (n, InterfaceStiffness::Blocks { n, blocks }, dense)
    }

    fn constants(n: usize) -> Mat<f64> {
        Mat::<f64>::from_fn(n, 1, |_, _| 1.0 / (n as f64).sqrt())
    }

    fn rows() -> Vec<SparseRow> {
        vec![vec![(3, 1.0)], vec![(17, 0.6), (40, -0.8)], vec![(40, 2.0)]]
    }

    /// Bᵀ as a dense n × m matrix.
    fn b_transpose(n: usize, rows: &[SparseRow]) -> Mat<f64> {
        Mat::<f64>::from_fn(n, rows.len(), |i, p| {
            rows[p].iter().filter(|e| e.0 == i).map(|e| e.1).sum()
        })
    }

    /// (S + ρRRᵀ)⁻¹ X by faer's Cholesky, ρ as the factor takes it.
    fn plain_solve(dense: &Mat<f64>, r: &Mat<f64>, x: &Mat<f64>) -> Mat<f64> {
        let n = dense.nrows();
        let rho = regularisation_scale(&(0..n).map(|i| dense[(i, i)]).collect::<Vec<_>>());
        let reg = dense + rho * r * r.transpose();
        let llt = reg.llt(Side::Lower).unwrap();
        let mut y = x.clone();
        faer::linalg::solvers::SolveCore::solve_in_place_with_conj(&llt, Conj::No, y.as_mut());
        y
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    /// The blocks multiply, give their diagonal and ‖S̃‖₁ as the dense sum
    /// does.
    #[test]
    fn blocks_act_as_their_dense_sum() {
        let (n, s, dense) = ring(6, 4, 2, 0.5);
        let x = Mat::<f64>::from_fn(n, 2, |i, j| (i + 3 * j) as f64 - 7.0);
        assert!((s.mul(&x) - &dense * &x).norm_max() <= 1e-12 * (&dense * &x).norm_max());
        assert_eq!(
            s.diagonal(),
            (0..n).map(|i| dense[(i, i)]).collect::<Vec<_>>()
        );
        let InterfaceStiffness::Blocks { blocks, .. } = &s else {
            unreachable!()
        };
        let want = signorini_linalg::conditioning::dense_norm1(dense.as_ref());
        assert!((blocks_norm1(n, blocks, &[], 1.0) - want).abs() <= 1e-12 * want);
        // A fixing DOF: its column is scale·e_j, its row leaves the others.
        let mut fixed = dense.clone();
        for k in 0..n {
            fixed[(5, k)] = 0.0;
            fixed[(k, 5)] = 0.0;
        }
        fixed[(5, 5)] = 100.0;
        let want = signorini_linalg::conditioning::dense_norm1(fixed.as_ref());
        assert!((blocks_norm1(n, blocks, &[5], 100.0) - want).abs() <= 1e-12 * want);
    }

    /// One subdomain's dense S and several subdomains' blocks over the tree
    /// (an odd number: a group passes a level alone) give the W and the
    /// solves of the plain formulas B (S + ρRRᵀ)⁻¹ Bᵀ, and the same κ.
    #[test]
    fn dense_and_tree_factors_give_the_plain_delassus_operator_when_held() {
        let rows = rows();
        for parts in [8, 7, 3] {
            let (n, blocks, dense) = ring(parts, 12, 3, 0.5);
            let r = Mat::<f64>::zeros(n, 0);
            let bt = b_transpose(n, &rows);
            let x = plain_solve(&dense, &r, &bt);
            let plain = bt.transpose() * &x;
            let one = SchurFactor::new(InterfaceStiffness::Dense(dense.clone()), &r, &[40, 3, 17])
                .unwrap();
            let tree = SchurFactor::new(blocks, &r, &[40, 3, 17]).unwrap();
            assert_eq!(
                (one.stats().storage, tree.stats().storage),
                ("dense", "tree")
            );
            for f in [&one, &tree] {
                let w = f.delassus(&rows).unwrap();
                assert!(
                    (&w - &plain).norm_max() <= 1e-12 * plain.norm_max(),
                    "{parts}: {w:?} {plain:?}"
                );
                let v: Vec<f64> = (0..n).map(|i| bt[(i, 1)]).collect();
                let want: Vec<f64> = (0..n).map(|i| x[(i, 1)]).collect();
                assert!(max_diff(&f.solve(&v), &want) <= 1e-12 * x.norm_max());
            }
            let (k1, k2) = (one.condition(), tree.condition());
            assert!((k1 - k2).abs() <= 1e-6 * k1, "{k1} {k2}");
        }
    }

    /// Floating (no spring: the constants are the kernel): the dense factor
    /// of S + ρRRᵀ gives the plain W; the tree's fixing DOFs give another
    /// generalised inverse: S S⁺ S = S, S (S⁺ f) = f for a balanced f, and
    /// its W is B S⁺ Bᵀ.
    #[test]
    fn factors_of_a_floating_interface_are_generalised_inverses() {
        let rows = rows();
        for parts in [8, 5] {
            let (n, blocks, dense) = ring(parts, 12, 3, 0.0);
            let r = constants(n);
            let bt = b_transpose(n, &rows);
            let one = SchurFactor::new(InterfaceStiffness::Dense(dense.clone()), &r, &[3, 17, 40])
                .unwrap();
            let plain = bt.transpose() * plain_solve(&dense, &r, &bt);
            assert!((one.delassus(&rows).unwrap() - &plain).norm_max() <= 1e-12 * plain.norm_max());
            let tree = SchurFactor::new(blocks, &r, &[3, 17, 40]).unwrap();
            assert_eq!(tree.stats().fixing_dofs, 1);
            for f in [&one, &tree] {
                let mut x = dense.clone();
                f.solve_in_place(x.as_mut());
                let err = (&dense * &x - &dense).norm_max();
                assert!(err <= 1e-10 * dense.norm_max(), "‖S S⁺ S − S‖ = {err:e}");
                let mut load: Vec<f64> = (0..n).map(|i| (i % 5) as f64).collect();
                let mean = load.iter().sum::<f64>() / n as f64;
                load.iter_mut().for_each(|v| *v -= mean);
                let u = f.solve(&load);
                let su = &dense * Mat::<f64>::from_fn(n, 1, |i, _| u[i]);
                assert!((0..n).all(|i| (su[(i, 0)] - load[i]).abs() <= 1e-10));
            }
            let mut x = bt.clone();
            tree.solve_in_place(x.as_mut());
            let w = bt.transpose() * &x;
            let wt = tree.delassus(&rows).unwrap();
            assert!((&wt - &w).norm_max() <= 1e-12 * w.norm_max());
        }
    }

    /// Two bodies (rings sharing no DOF, one floating): the tree stops at
    /// one group per body; S S⁺ S = S and W = B S⁺ Bᵀ.
    #[test]
    fn tree_factor_of_separate_bodies() {
        let (n1, a, d1) = ring(4, 6, 2, 0.5);
        let (n2, b, d2) = ring(3, 5, 2, 0.0);
        let (
            InterfaceStiffness::Blocks { blocks: a, .. },
            InterfaceStiffness::Blocks { blocks: b, .. },
        ) = (a, b)
        else {
            unreachable!()
        };
        let mut blocks = a;
        blocks.extend(b.into_iter().map(|mut blk| {
            blk.gamma.iter_mut().for_each(|g| *g += n1);
            blk
        }));
        let n = n1 + n2;
        let mut dense = Mat::<f64>::zeros(n, n);
        dense.as_mut().submatrix_mut(0, 0, n1, n1).copy_from(&d1);
        dense.as_mut().submatrix_mut(n1, n1, n2, n2).copy_from(&d2);
        let s = InterfaceStiffness::Blocks { n, blocks };
        let r = Mat::<f64>::from_fn(n, 1, |i, _| {
            if i >= n1 {
                1.0 / (n2 as f64).sqrt()
            } else {
                0.0
            }
        });
        let contact = [1, 9, 20, n1 + 2, n1 + 12];
        let rows: Vec<SparseRow> = contact
            .iter()
            .map(|&i| vec![(i, 1.0)])
            .chain([vec![(1, 0.5), (n1 + 2, -0.5)]])
            .collect();
        let f = SchurFactor::new(s, &r, &contact).unwrap();
        let mut x = dense.clone();
        f.solve_in_place(x.as_mut());
        assert!((&dense * &x - &dense).norm_max() <= 1e-10 * dense.norm_max());
        let bt = b_transpose(n, &rows);
        let mut y = bt.clone();
        f.solve_in_place(y.as_mut());
        let w = bt.transpose() * &y;
        assert!((f.delassus(&rows).unwrap() - &w).norm_max() <= 1e-12 * w.norm_max());
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
