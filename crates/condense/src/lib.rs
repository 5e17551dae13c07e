//! Static condensation of one subdomain on its interface (course notes §8.2).
//!
//! The subdomain's DOFs are split into interior DOFs I and interface DOFs B
//! (every DOF on a contact surface, or shared with another subdomain). With
//!
//! ```text
//! [K_II K_IB] [u_I]   [F_I]
//! [K_BI K_BB] [u_B] = [F_B + r_B]
//! ```
//!
//! eliminating u_I = K_II⁻¹ (F_I − K_IB u_B) leaves the condensed problem
//! S u_B = F'_B + r_B with the Schur complement S = K_BB − K_BI K_II⁻¹ K_IB and
//! the condensed load F' = F_B − K_BI K_II⁻¹ F_I.
//!
//! [`Condensed::new`] computes S by a partial factorisation (docs/architecture.md, "Libraries",
//! "method C"): the whole subdomain matrix is factorised by a supernodal
//! Cholesky with the interior ordered first (by the cheaper of AMD and nested
//! dissection on K_II, [`ordering`]) and the interface last, stopped once the
//! interface block holds S (`partial_factorisation`: S is read there, without
//! factorising it). Where the interface is split over several supernodes, K_BB
//! is shifted by c·I and the whole matrix factorised; then
//! L_BB L_BBᵀ = S + c·I exactly, so S is read from the trailing dense block
//! (the shift keeps that factorisation valid for a floating subdomain, whose S
//! is singular). The same factor gives F' and the interior
//! //! recovery. [`schur_complement_reference`] is the plain multi-RHS formula,
//! kept as the reference in tests. [`Condensed::interior_condition_estimate`]
//! estimates κ₁(K_II) from the same factor (`signorini_linalg::conditioning`).
//!
//! The condense crate owns the static condensation of one subdomain and the
//! interface stiffness S = Σ_i S_i with its factor ([`interface`]); it must not
//! know contact, the scene format or MPI.

pub mod interface;
pub mod ordering;
mod partial_factorisation;
#[cfg(test)]
mod test_matrices;

pub use ordering::{FactorStats, Ordering, OrderingChoice};

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::{SparseColMat, SparseColMatRef, Triplet};
use faer::{Accum, Conj, Mat, Par, Side};

#[derive(Debug, thiserror::Error)]
pub enum CondenseError {
    #[error("the interior stiffness K_II is not positive definite ({0}): the subdomain has a free rigid-body motion that its interface does not hold, or a degenerate element")]
    NotPositiveDefinite(String),
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
    #[error("interface DOF {0} out of range or repeated")]
    BadInterface(usize),
}

/// Rows `rows` and columns `cols` of a sparse matrix, as a new sparse matrix
/// (row i of the result is row `rows[i]`).
pub fn submatrix(
    k: SparseColMatRef<'_, usize, f64>,
    rows: &[usize],
    cols: &[usize],
) -> SparseColMat<usize, f64> {
    let mut row_map = vec![usize::MAX; k.nrows()];
    for (i, &r) in rows.iter().enumerate() {
        row_map[r] = i;
    }
    let mut t = Vec::new();
    for (j, &c) in cols.iter().enumerate() {
        let idx = k.row_idx_of_col_raw(c);
        let val = k.val_of_col(c);
        for (&r, &v) in idx.iter().zip(val) {
            if row_map[r] != usize::MAX {
                t.push(Triplet::new(row_map[r], j, v));
            }
        }
    }
    SparseColMat::try_new_from_triplets(rows.len(), cols.len(), &t)
        .expect("indices are in range by construction")
}

/// Sparse matrix times vector, y = K x.
pub fn spmv(k: SparseColMatRef<'_, usize, f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; k.nrows()];
    for_each_term(k, x, |r, t| y[r] += t);
    y
}

/// Calls `f(r, K[r][j] x[j])` for every stored entry of K whose `x[j]` is
/// not zero, column by column.
fn for_each_term(k: SparseColMatRef<'_, usize, f64>, x: &[f64], mut f: impl FnMut(usize, f64)) {
    for (j, &xj) in x.iter().enumerate().take(k.ncols()) {
        if xj == 0.0 {
            continue;
        }
        for (&r, &v) in k.row_idx_of_col_raw(j).iter().zip(k.val_of_col(j)) {
            f(r, v * xj);
        }
    }
}

/// (K x, |K| |x|) in one pass: the product and, entry by entry, the size
/// of the terms summed in it, the scale of its round-off (a componentwise
/// backward-error scale, Oettli–Prager). Where internal forces cancel (an
/// interior node, a stiff body next to a soft one) K x is small but |K||x|
/// is not.
pub fn spmv_with_magnitude(k: SparseColMatRef<'_, usize, f64>, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut y = vec![0.0; k.nrows()];
    let mut size = vec![0.0; k.nrows()];
    for_each_term(k, x, |r, t| {
        y[r] += t;
        size[r] += t.abs();
    });
    (y, size)
}

/// Which of the n DOFs are on the interface; refused when an interface DOF
/// is out of range or repeated.
fn interface_mask(n: usize, interface: &[usize]) -> Result<Vec<bool>, CondenseError> {
    let mut is_b = vec![false; n];
    for &b in interface {
        if b >= n || is_b[b] {
            return Err(CondenseError::BadInterface(b));
        }
        is_b[b] = true;
    }
    Ok(is_b)
}

/// ‖K_II‖₁, the largest absolute column sum of the interior block.
fn interior_norm1(k: SparseColMatRef<'_, usize, f64>, is_b: &[bool], interior: &[usize]) -> f64 {
    interior
        .iter()
        .map(|&col| {
            k.row_idx_of_col_raw(col)
                .iter()
                .zip(k.val_of_col(col))
                .filter(|(&r, _)| !is_b[r])
                .map(|(_, v)| v.abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// Shift c on the interface diagonal: c ~ max diag(K_BB) (1 when it is 0).
fn interface_shift(k: SparseColMatRef<'_, usize, f64>, interface: &[usize]) -> f64 {
    let mut c = 0.0f64;
    for &b in interface {
        for (&r, &v) in k.row_idx_of_col_raw(b).iter().zip(k.val_of_col(b)) {
            if r == b {
                c = c.max(v.abs());
            }
        }
    }
    if c == 0.0 {
        c = 1.0;
    }
    c
}

/// The lower triangle of K renumbered: interior first (natural), interface
/// last, with every interface diagonal entry stored (so that it can be
/// shifted in place); the factorisation reads the lower triangle alone, and
/// the ordering mirrors it. Built column by column straight into CSC (each
/// column's rows renumbered and sorted), not through triplets: a sixth of
/// the memory the triplets and a full copy took, and no global sort.
fn interface_last(
    k: SparseColMatRef<'_, usize, f64>,
    interior: &[usize],
    interface: &[usize],
) -> Result<SparseColMat<usize, f64>, CondenseError> {
    let n = k.nrows();
    let ni = interior.len();
    let order: Vec<usize> = interior.iter().chain(interface).copied().collect();
    let mut new_index = vec![0usize; n];
    for (i, &d) in order.iter().enumerate() {
        new_index[d] = i;
    }
    let capacity = k.compute_nnz() + interface.len();
    let (mut col_ptr, mut row_idx, mut values) = (
        Vec::with_capacity(n + 1),
        Vec::with_capacity(capacity),
        Vec::with_capacity(capacity),
    );
    col_ptr.push(0);
    let mut column: Vec<(usize, f64)> = Vec::new();
    for (j, &c) in order.iter().enumerate() {
        column.clear();
        let rows = k.row_idx_of_col_raw(c).iter().map(|&r| new_index[r]);
        let lower = rows.zip(k.val_of_col(c).iter().copied());
        column.extend(lower.filter(|&(r, _)| r >= j));
        if j >= ni && !column.iter().any(|&(r, _)| r == j) {
            column.push((j, 0.0));
        }
        column.sort_unstable_by_key(|&(r, _)| r);
        for w in column.chunk_by(|a, b| a.0 == b.0) {
            row_idx.push(w[0].0);
            values.push(w.iter().map(|e| e.1).sum::<f64>());
        }
        col_ptr.push(row_idx.len());
    }
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    Ok(SparseColMat::new(symbolic, values))
}

/// The values of the supernodal Cholesky factor `symbolic` of the shifted,
/// renumbered matrix `ks` (interface rows ni..n last).
fn factorise_interface_last(
    ks: SparseColMatRef<'_, usize, f64>,
    symbolic: &SymbolicCholesky<usize>,
    par: Par,
) -> Result<Vec<f64>, CondenseError> {
    let mut l_values = vec![0.0f64; symbolic.len_val()];
    partial_factorisation::factorise(ks, symbolic, &mut l_values, par)
        .map_err(|e| CondenseError::NotPositiveDefinite(format!("{e:?}")))?;
    Ok(l_values)
}

/// The factor's values, S, and whether the factorisation stopped at the
/// interface ([`partial_factorisation`], when the interface is in the last
/// supernode) rather than factorising K + c·I_BB whole (S = L_BB L_BBᵀ − c·I).
fn factor_and_schur(
    k: SparseColMatRef<'_, usize, f64>,
    ks: SparseColMat<usize, f64>,
    interface: &[usize],
    symbolic: &SymbolicCholesky<usize>,
    par: Par,
) -> Result<(Vec<f64>, Mat<f64>, bool), CondenseError> {
    let ni = ks.nrows() - interface.len();
    use partial_factorisation::Stopped;
    let mut ks = match partial_factorisation::schur_by_stopped_factorisation(ks, symbolic, ni, par)?
    {
        Stopped::Done(l_values, schur) => return Ok((l_values, schur, true)),
        Stopped::NotApplicable(ks) => ks,
    };
    let c = interface_shift(k, interface);
    for j in ni..ks.nrows() {
        let at = partial_factorisation::diagonal_position(ks.as_ref(), j);
        ks.val_mut()[at.expect("every interface diagonal entry is stored")] += c;
    }
    let l_values = factorise_interface_last(ks.as_ref(), symbolic, par)?;
    drop(ks);
    let l_bb = trailing_block(symbolic, &l_values, ni, interface.len())?;
    // L_BB stays in the factor (`for_each_trailing_entry`): no dense copy.
    Ok((l_values, schur_from_trailing_block(&l_bb, c, par), false))
}

/// Calls `f(i, j, L[ni + i][ni + j])` for every stored entry (i ≥ j) of the
/// trailing nb × nb block L_BB of the supernodal factor (lower triangular),
/// read from the supernodes that reach past the interior.
fn for_each_trailing_entry(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &[f64],
    ni: usize,
    mut f: impl FnMut(usize, usize, f64),
) -> Result<(), CondenseError> {
    let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
        return Err(CondenseError::Factorisation(
            "expected a supernodal factor".into(),
        ));
    };
    let l = SupernodalLltRef::<usize, f64>::new(sn, l_values);
    for s in 0..sn.n_supernodes() {
        let snode = l.supernode(s);
        let (start, ncols) = (snode.start(), snode.val().ncols());
        if start + ncols <= ni {
            continue;
        }
        let rows: Vec<usize> = (start..start + ncols)
            .chain(snode.pattern().iter().copied())
            .collect();
        for jj in 0..ncols {
            let j = start + jj;
            if j < ni {
                continue;
            }
            for (ii, &i) in rows.iter().enumerate() {
                if i >= ni && i >= j {
                    f(i - ni, j - ni, snode.val()[(ii, jj)]);
                }
            }
        }
    }
    Ok(())
}

/// The trailing nb × nb block L_BB of the supernodal factor (lower
/// triangular), as a dense matrix.
pub fn trailing_block(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &[f64],
    ni: usize,
    nb: usize,
) -> Result<Mat<f64>, CondenseError> {
    let mut l_bb = Mat::<f64>::zeros(nb, nb);
    for_each_trailing_entry(symbolic, l_values, ni, |i, j, v| l_bb[(i, j)] = v)?;
    Ok(l_bb)
}

/// S = L_BB L_BBᵀ − c·I (L_BB L_BBᵀ = S + c·I exactly), symmetrised.
fn schur_from_trailing_block(l_bb: &Mat<f64>, c: f64, par: Par) -> Mat<f64> {
    let nb = l_bb.nrows();
    use faer::linalg::matmul::triangular::{matmul, BlockStructure};
    let mut schur = Mat::<f64>::from_fn(nb, nb, |i, j| if i == j { -c } else { 0.0 });
    // The lower triangle only, from triangular factors: nb³/3 flops, not 2 nb³.
    matmul(
        schur.as_mut(),
        BlockStructure::TriangularLower,
        Accum::Add,
        l_bb.as_ref(),
        BlockStructure::TriangularLower,
        l_bb.transpose(),
        BlockStructure::TriangularUpper,
        1.0,
        par,
    );
    for j in 0..nb {
        for i in j + 1..nb {
            schur[(j, i)] = schur[(i, j)];
        }
    }
    schur
}

/// A condensed subdomain: the factor of its stiffness with the interface last,
/// its Schur complement S, and what is needed to condense loads and recover the
/// interior.
pub struct Condensed {
    n: usize,
    interior: Vec<usize>,
    interface: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    /// Fill-reducing permutation of the renumbered DOFs (interior first):
    /// factor row i is renumbered DOF `perm_fwd[i]`.
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
    l_values: Vec<f64>,
    /// Schur complement on the interface (dense, symmetric), in `interface` order.
    pub schur: Mat<f64>,
    /// ‖K_II‖₁, the largest absolute column sum of the interior block.
    k_ii_norm1: f64,
    /// The factor's ordering, size and flops.
    stats: FactorStats,
    /// Every ordering tried (the kept one first).
    candidates: Vec<FactorStats>,
    par: Par,
}

impl Condensed {
    /// Factorises K (the subdomain stiffness on its free DOFs, both triangles
    /// stored) with the DOFs `interface` ordered last and forms
    /// S = K_BB − K_BI K_II⁻¹ K_IB (docs/architecture.md, "Libraries"), the interior
    /// ordered by the cheaper of AMD and nested dissection ([`ordering`]).
    pub fn new(
        k: SparseColMatRef<'_, usize, f64>,
        interface: &[usize],
        par: Par,
    ) -> Result<Self, CondenseError> {
        Self::with_ordering(k, interface, OrderingChoice::Auto, par)
    }

    /// [`Condensed::new`] with the interior ordered by `choice`.
    pub fn with_ordering(
        k: SparseColMatRef<'_, usize, f64>,
        interface: &[usize],
        choice: OrderingChoice,
        par: Par,
    ) -> Result<Self, CondenseError> {
        let n = k.nrows();
        let is_b = interface_mask(n, interface)?;
        let interior: Vec<usize> = (0..n).filter(|&i| !is_b[i]).collect();
        let ni = interior.len();
        let k_ii_norm1 = interior_norm1(k, &is_b, &interior);
        let ks = interface_last(k, &interior, interface)?;
        let ordered = ordering::order_and_analyse(ks.as_ref(), ni, choice)?;
        let (l_values, schur, stopped) =
            factor_and_schur(k, ks, interface, &ordered.symbolic, par)?;
        let mut ordered = ordered;
        if stopped {
            // The interface block's own factorisation (Σ c², c = 1..nb) is not done.
            let nb = interface.len() as f64;
            let skipped = nb * (nb + 1.0) * (2.0 * nb + 1.0) / 6.0;
            ordered.stats.flops -= skipped;
            ordered
                .candidates
                .iter_mut()
                .for_each(|c| c.flops -= skipped);
        }
        Ok(Self {
            n,
            interior,
            interface: interface.to_vec(),
            symbolic: ordered.symbolic,
            perm_fwd: ordered.fwd,
            perm_inv: ordered.inv,
            l_values,
            schur,
            k_ii_norm1,
            stats: ordered.stats,
            candidates: ordered.candidates,
            par,
        })
    }

    /// Estimated 1-norm condition number κ₁(K_II) = ‖K_II‖₁ ‖K_II⁻¹‖₁ of the
    /// interior stiffness (the unshifted K_II: the shift only touches K_BB),
    /// ‖K_II⁻¹‖₁ by the Hager–Higham estimator with solves by the leading
    /// block L_II of the factor (a handful of sparse triangular solve pairs,
    /// far cheaper than the factorisation). `None` without interior DOFs.
    pub fn interior_condition_estimate(&self) -> Option<f64> {
        let ni = self.interior.len();
        if ni == 0 {
            return None;
        }
        let mut mem = self.scratch();
        let l = self.lref();
        let mut z = Mat::<f64>::zeros(self.n, 1);
        // The estimate works in the factor's (permuted) numbering: κ₁ is
        // invariant under a symmetric permutation. Single right-hand sides
        // are solved sequentially (threads cost more than they save there).
        let inv = signorini_linalg::conditioning::inverse_norm1_estimate(ni, |x| {
            for i in 0..self.n {
                z[(i, 0)] = if i < ni { x[i] } else { 0.0 };
            }
            // L = [L_II 0; L_BI L_BB]: with the interface part cut after the
            // forward solve, the backward solve gives L_IIᵀ⁻¹ L_II⁻¹ x = K_II⁻¹ x.
            l.l_solve_with_conj(Conj::No, z.as_mut(), Par::Seq, MemStack::new(&mut mem));
            for i in ni..self.n {
                z[(i, 0)] = 0.0;
            }
            l.l_transpose_solve_with_conj(Conj::No, z.as_mut(), Par::Seq, MemStack::new(&mut mem));
            for (i, xi) in x.iter_mut().enumerate() {
                *xi = z[(i, 0)];
            }
        });
        Some(self.k_ii_norm1 * inv)
    }

    pub fn n_interior(&self) -> usize {
        self.interior.len()
    }
    pub fn n_interface(&self) -> usize {
        self.interface.len()
    }
    pub fn interface(&self) -> &[usize] {
        &self.interface
    }

    fn lref(&self) -> SupernodalLltRef<'_, usize, f64> {
        let SymbolicCholeskyRaw::Supernodal(sn) = self.symbolic.raw() else {
            unreachable!("checked in new()")
        };
        SupernodalLltRef::new(sn, &self.l_values)
    }

    fn scratch(&self) -> MemBuffer {
        MemBuffer::new(StackReq::any_of(&[
            self.symbolic.solve_in_place_scratch::<f64>(1, self.par),
            StackReq::new::<f64>(self.n * 2),
        ]))
    }

    /// Condensed load F' = F_B − K_BI K_II⁻¹ F_I for a load F on all DOFs of
    /// the subdomain (in the subdomain's numbering). Computed as
    /// F' = L_BB (L⁻¹ P F)_B, since L_BI = K_BI L_IIᵀ⁻¹.
    pub fn condensed_load(&self, f: &[f64]) -> Vec<f64> {
        let ni = self.interior.len();
        let nb = self.interface.len();
        let renumbered: Vec<usize> = self
            .interior
            .iter()
            .chain(&self.interface)
            .copied()
            .collect();
        let y_at = |i: usize| f[renumbered[self.perm_fwd[i]]];
        let mut y = Mat::<f64>::from_fn(self.n, 1, |i, _| y_at(i));
        let mut mem = self.scratch();
        self.lref()
            .l_solve_with_conj(Conj::No, y.as_mut(), self.par, MemStack::new(&mut mem));
        let mut out = vec![0.0; nb];
        for_each_trailing_entry(&self.symbolic, &self.l_values, ni, |i, j, v| {
            out[i] += v * y[(ni + j, 0)];
        })
        .expect("supernodal, checked in new()");
        out
    }

    /// Moves the Schur complement out (leaving `schur` empty, 0 × 0): the
    /// caller that sends it keeps one dense copy instead of two.
    pub fn take_schur(&mut self) -> Mat<f64> {
        std::mem::replace(&mut self.schur, Mat::new())
    }

    /// Interior recovery: given the load F on all DOFs and the interface
    /// displacement u_B, returns the whole displacement of the subdomain
    /// (u_I = K_II⁻¹ (F_I − K_IB u_B)).
    pub fn recover(&self, k: SparseColMatRef<'_, usize, f64>, f: &[f64], u_b: &[f64]) -> Vec<f64> {
        let ni = self.interior.len();
        let mut u = vec![0.0; self.n];
        for (j, &d) in self.interface.iter().enumerate() {
            u[d] = u_b[j];
        }
        // r = F − K u_B (restricted to the interior)
        let ku = spmv(k, &u);
        let mut z = Mat::<f64>::zeros(self.n, 1);
        for i in 0..ni {
            let d = self.interior[self.perm_fwd[i]];
            z[(i, 0)] = f[d] - ku[d];
        }
        let mut mem = self.scratch();
        let l = self.lref();
        l.l_solve_with_conj(Conj::No, z.as_mut(), self.par, MemStack::new(&mut mem));
        for i in ni..self.n {
            z[(i, 0)] = 0.0;
        }
        l.l_transpose_solve_with_conj(Conj::No, z.as_mut(), self.par, MemStack::new(&mut mem));
        for (i, &d) in self.interior.iter().enumerate() {
            u[d] = z[(self.perm_inv[i], 0)];
        }
        u
    }

    /// Bytes held by the factor and the dense Schur complement.
    pub fn memory_bytes(&self) -> usize {
        8 * (self.l_values.len() + self.interface.len().pow(2))
    }

    /// The factor's ordering, size and flops.
    pub fn factor_stats(&self) -> FactorStats {
        self.stats
    }

    /// Every ordering compared for this factor, the kept one first.
    pub fn ordering_candidates(&self) -> &[FactorStats] {
        &self.candidates
    }
}

/// The plain formula S = K_BB − K_BI K_II⁻¹ K_IB and F' = F_B − K_BI K_II⁻¹ F_I
/// by a sparse Cholesky of K_II and multi-right-hand-side solves (docs/architecture.md, "Libraries",
/// "method A"): the reference against which [`Condensed`] is tested.
pub fn schur_complement_reference(
    k: SparseColMatRef<'_, usize, f64>,
    interface: &[usize],
    f: &[f64],
) -> Result<(Mat<f64>, Vec<f64>), CondenseError> {
    use faer::prelude::Solve;
    let n = k.nrows();
    let mut is_b = vec![false; n];
    for &b in interface {
        is_b[b] = true;
    }
    let interior: Vec<usize> = (0..n).filter(|&i| !is_b[i]).collect();
    let kii = submatrix(k, &interior, &interior);
    let kib = submatrix(k, &interior, interface);
    let kbb = submatrix(k, interface, interface).to_dense();
    let llt = kii
        .sp_cholesky(Side::Lower)
        .map_err(|e| CondenseError::NotPositiveDefinite(format!("{e:?}")))?;
    let mut x = kib.to_dense();
    llt.solve_in_place(x.as_mut());
    let s = &kbb
        - kib
            .transpose()
            .to_col_major()
            .map_err(|e| CondenseError::Factorisation(format!("{e:?}")))?
            * &x;
    let mut fi = Mat::<f64>::from_fn(interior.len(), 1, |i, _| f[interior[i]]);
    llt.solve_in_place(fi.as_mut());
    let kfi = kib
        .transpose()
        .to_col_major()
        .map_err(|e| CondenseError::Factorisation(format!("{e:?}")))?
        * &fi;
    let fp = interface
        .iter()
        .enumerate()
        .map(|(j, &b)| f[b] - kfi[(j, 0)])
        .collect();
    Ok((s, fp))
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_linalg::conditioning::dense_norm1;

    /// [`grid`] with its interface: the top row of nodes and two more.
    fn grid_with_top_interface(
        nx: usize,
        ny: usize,
        shift: f64,
        more: [usize; 2],
    ) -> (SparseColMat<usize, f64>, Vec<usize>) {
        let interface = (0..nx).map(|i| i + nx * (ny - 1)).chain(more).collect();
        (grid(nx, ny, shift), interface)
    }

    /// 2D grid Laplacian-like SPD matrix (5-point stencil) with an optional
    /// Dirichlet shift on the first row: floating when `shift` is 0.
    fn grid(nx: usize, ny: usize, shift: f64) -> SparseColMat<usize, f64> {
        let id = |i: usize, j: usize| i + nx * j;
        let mut t = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let mut push = |a: usize, b: usize, w: f64| {
                    t.push(Triplet::new(a, a, w));
                    t.push(Triplet::new(b, b, w));
                    t.push(Triplet::new(a, b, -w));
                    t.push(Triplet::new(b, a, -w));
                };
                if i + 1 < nx {
                    push(id(i, j), id(i + 1, j), 1.0 + 0.1 * (i as f64));
                }
                if j + 1 < ny {
                    push(id(i, j), id(i, j + 1), 2.0 + 0.05 * (j as f64));
                }
            }
        }
        if shift > 0.0 {
            for i in 0..nx {
                t.push(Triplet::new(id(i, 0), id(i, 0), shift));
            }
        }
        SparseColMat::try_new_from_triplets(nx * ny, nx * ny, &t).unwrap()
    }

    /// S and F' of [`Condensed::new`] equal the multi-right-hand-side
    /// formula's to rounding (relative to ‖S‖ and ‖F'‖).
    fn assert_matches_the_reference(
        k: SparseColMatRef<'_, usize, f64>,
        interface: &[usize],
        f: &[f64],
    ) {
        let c = Condensed::new(k, interface, Par::Seq).unwrap();
        let (s_ref, fp_ref) = schur_complement_reference(k, interface, f).unwrap();
        assert!(max_abs_diff(&c.schur, &s_ref) <= 1e-12 * s_ref.norm_max());
        let fp = c.condensed_load(f);
        let f_scale = fp_ref.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in fp.iter().zip(&fp_ref) {
            assert!((a - b).abs() <= 1e-12 * f_scale, "F' {a} vs {b}");
        }
    }

    fn max_abs_diff(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
        let mut m = 0.0f64;
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                m = m.max((a[(i, j)] - b[(i, j)]).abs());
            }
        }
        m
    }

    /// Two grids that share nothing: the interface block of the factor is
    /// two supernodes, so S comes from the shifted whole factorisation;
    /// S, F' and the recovery equal the plain formula's as on one grid.
    #[test]
    fn an_interface_split_over_supernodes_is_condensed_by_the_shifted_factor() {
        let (nx, ny) = (6, 5);
        let one = grid(nx, ny, 2.0);
        let n1 = nx * ny;
        let mut t = Vec::new();
        for part in 0..2 {
            for j in 0..n1 {
                for (&i, &v) in one.row_idx_of_col_raw(j).iter().zip(one.val_of_col(j)) {
                    t.push(Triplet::new(
                        i + part * n1,
                        j + part * n1,
                        v * (1.0 + part as f64),
                    ));
                }
            }
        }
        let k = SparseColMat::try_new_from_triplets(2 * n1, 2 * n1, &t).unwrap();
        let top: Vec<usize> = (0..nx).map(|i| i + nx * (ny - 1)).collect();
        let interface: Vec<usize> = top
            .iter()
            .chain(&top)
            .enumerate()
            .map(|(p, &i)| i + n1 * (p / nx))
            .collect();
        let ni = 2 * n1 - interface.len();
        let mut is_b = vec![false; 2 * n1];
        interface.iter().for_each(|&b| is_b[b] = true);
        let interior: Vec<usize> = (0..2 * n1).filter(|&i| !is_b[i]).collect();
        let ks = interface_last(k.as_ref(), &interior, &interface).unwrap();
        let ordered = ordering::order_and_analyse(ks.as_ref(), ni, OrderingChoice::Auto).unwrap();
        let stopped = partial_factorisation::schur_by_stopped_factorisation(
            ks,
            &ordered.symbolic,
            ni,
            Par::Seq,
        )
        .unwrap();
        assert!(
            matches!(stopped, partial_factorisation::Stopped::NotApplicable(_)),
            "two independent blocks are two supernodes"
        );
        let f: Vec<f64> = (0..2 * n1).map(|i| ((i * 5) % 7) as f64 - 3.0).collect();
        assert_matches_the_reference(k.as_ref(), &interface, &f);
    }

    #[test]
    fn partial_factorisation_equals_multi_rhs_schur_complement() {
        let (nx, ny) = (12, 9);
        let (k, interface) = grid_with_top_interface(nx, ny, 3.0, [5, 40]);
        let n = nx * ny;
        let f: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 - 5.0).collect();
        assert_matches_the_reference(k.as_ref(), &interface, &f);
    }

    #[test]
    fn recovery_solves_the_whole_system() {
        use faer::prelude::Solve;
        let (nx, ny) = (10, 7);
        let k = grid(nx, ny, 2.0);
        let n = nx * ny;
        let interface: Vec<usize> = (0..nx).collect();
        let f: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        // Solve the whole system directly, then check that condensation + recovery agree.
        let llt = k.sp_cholesky(Side::Lower).unwrap();
        let mut u = Mat::<f64>::from_fn(n, 1, |i, _| f[i]);
        llt.solve_in_place(u.as_mut());
        let c = Condensed::new(k.as_ref(), &interface, Par::Seq).unwrap();
        let fp = c.condensed_load(&f);
        let s_llt = c.schur.llt(Side::Lower).unwrap();
        let mut ub = Mat::<f64>::from_fn(interface.len(), 1, |i, _| fp[i]);
        s_llt.solve_in_place(ub.as_mut());
        let ub: Vec<f64> = (0..interface.len()).map(|i| ub[(i, 0)]).collect();
        let full = c.recover(k.as_ref(), &f, &ub);
        let scale = (0..n).fold(0.0f64, |m, i| m.max(u[(i, 0)].abs()));
        for i in 0..n {
            assert!((full[i] - u[(i, 0)]).abs() <= 1e-11 * scale, "dof {i}");
        }
    }

    #[test]
    fn interior_condition_estimate_matches_the_dense_inverse() {
        let (nx, ny) = (11, 8);
        let (k, interface) = grid_with_top_interface(nx, ny, 0.5, [3, 30]);
        let n = nx * ny;
        let c = Condensed::new(k.as_ref(), &interface, Par::Seq).unwrap();
        let est = c.interior_condition_estimate().unwrap();
        let interior: Vec<usize> = (0..n).filter(|i| !interface.contains(i)).collect();
        let kii = submatrix(k.as_ref(), &interior, &interior).to_dense();
        let llt = kii.llt(Side::Lower).unwrap();
        let mut inv = Mat::<f64>::identity(interior.len(), interior.len());
        faer::linalg::solvers::SolveCore::solve_in_place_with_conj(&llt, Conj::No, inv.as_mut());
        let exact = dense_norm1(kii.as_ref()) * dense_norm1(inv.as_ref());
        assert!(exact > 10.0, "{exact}");
        assert!(
            est <= exact * (1.0 + 1e-10) && est >= exact / 3.0,
            "{est:e} vs {exact:e}"
        );
        // No interior: no estimate.
        let all: Vec<usize> = (0..n).collect();
        let c = Condensed::new(k.as_ref(), &all, Par::Seq).unwrap();
        assert!(c.interior_condition_estimate().is_none());
    }

    #[test]
    fn floating_subdomain_gives_singular_schur_complement_with_constant_kernel() {
        let (nx, ny) = (8, 6);
        let k = grid(nx, ny, 0.0);
        let interface: Vec<usize> = (0..nx).collect();
        let c = Condensed::new(k.as_ref(), &interface, Par::Seq).unwrap();
        let scale = c.schur.norm_max();
        for i in 0..nx {
            let row: f64 = (0..nx).map(|j| c.schur[(i, j)]).sum();
            assert!(row.abs() <= 1e-12 * scale, "S·1 = {row}");
        }
    }
}
