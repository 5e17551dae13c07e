//! The Schur complement read from a Cholesky factorisation stopped at the
//! interface (docs/architecture.md, "Libraries": the Schur complement read from a partial factorisation, without its last step).
//!
//! With the interior I ordered first and the interface B last, a left-looking
//! supernodal Cholesky of K first factorises every interior supernode, then
//! gathers into the trailing block their updates, K_BB − L_BI L_BIᵀ = S,
//! and only then factorises that block. When the whole interface is in the
//! last supernode, the gathered block holds S: the factorisation of S (nb³/3
//! flops) and forming S back from it (L_BB L_BBᵀ, 2·nb³ more by a full
//! product) are work thrown away — for a body in 8 parts, most of its
//! condensation. Here the first pivot of the last supernode is made
//! negative on purpose, K_jj − M with M = 2 K_jj (the pivot is K_jj less a
//! positive update, so it becomes ≤ −K_jj < 0): the factorisation stops at
//! the first column of that supernode, after gathering its updates and
//! before its dense Cholesky writes anything; K_jj is restored by adding M
//! back (a rounding of ε·M, the size of the rounding already there). The
//! few interior columns a relaxed supernode may hold are finished by hand
//! ([`finish_last_supernode`]) and the interface block is set to the
//! identity, so that the factor is that of [K_II K_IB; K_BI K_BI K_II⁻¹ K_IB + I]:
//! its L_II and L_BI are those of K, (L⁻¹ P F)_B = F_B − L_BI L_II⁻¹ F_I = F'
//! and the interior solves are unchanged ([`crate::Condensed`]).
//!
//! This relies on how faer 0.24's supernodal Cholesky stops (it reports the
//! first non-positive pivot of a supernode after gathering the supernode's
//! updates, before writing it); the tests check S against the plain formula,
//! and [`schur_by_stopped_factorisation`] returns `None` (the caller then
//! shifts and factorises the whole matrix) when the interface is split over
//! several supernodes.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::{SparseColMat, SparseColMatRef};
use faer::{Mat, MatMut, Par, Side};

use crate::CondenseError;
use signorini_linalg::products::subtract_product;

/// What [`schur_by_stopped_factorisation`] gives back.
pub(crate) enum Stopped {
    /// The factor's values (with L_BB = I) and the dense S.
    Done(Vec<f64>, Mat<f64>),
    /// The interface is split over several supernodes: the matrix, unchanged.
    NotApplicable(SparseColMat<usize, f64>),
}

/// The last supernode of the factor when it holds the whole interface:
/// its first column `begin` (≤ ni: relaxed supernodes may take a few
/// interior columns in) and its range in `l_values` (a square block:
/// nothing is below the last supernode). `None` when the interface is split
/// over several supernodes.
fn interface_supernode(
    symbolic: &SymbolicCholesky<usize>,
    ni: usize,
) -> Option<(usize, std::ops::Range<usize>)> {
    let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
        return None;
    };
    let last = sn.n_supernodes().checked_sub(1)?;
    let n = symbolic.nrows();
    let (begin, end) = (sn.supernode_begin()[last], sn.supernode_end()[last]);
    let ptr = sn.col_ptr_for_val();
    let (v0, v1) = (ptr[last], ptr[last + 1]);
    let w = n - begin;
    (ni < n && begin <= ni && end == n && v1 - v0 == w * w).then_some((begin, v0..v1))
}

/// The index in `ks.val()` of the diagonal entry of column `j`.
pub(crate) fn diagonal_position(ks: SparseColMatRef<'_, usize, f64>, j: usize) -> Option<usize> {
    let rows = ks.row_idx_of_col_raw(j);
    let start = ks.col_ptr()[j];
    rows.iter().position(|&r| r == j).map(|p| start + p)
}

/// Factorises `ks` (interior first, interface ni..n last, symbolic factor
/// `symbolic` in which the interface rows keep their place) up to its last
/// supernode and returns the factor's values (with L_BB = I) and the dense
/// Schur complement S; `ks` is freed as soon as it is factorised. When the
/// interface is not in one trailing supernode, `ks` comes back unchanged.
///
/// The last supernode starts at `begin`; its r = ni − begin interior
/// columns R are finished here: the gathered block X is the Schur
/// complement of K on R ∪ B, so L_RR L_RRᵀ = X_RR, L_BR = X_BR L_RR⁻ᵀ and
/// S = X_BB − L_BR L_BRᵀ (r·nb² flops, r a few columns).
pub(crate) fn schur_by_stopped_factorisation(
    mut ks: SparseColMat<usize, f64>,
    symbolic: &SymbolicCholesky<usize>,
    ni: usize,
    par: Par,
) -> Result<Stopped, CondenseError> {
    let Some((begin, range)) = interface_supernode(symbolic, ni) else {
        return Ok(Stopped::NotApplicable(ks));
    };
    let first = symbolic.perm().map_or(begin, |p| p.arrays().0[begin]);
    let Some(at) = diagonal_position(ks.as_ref(), first) else {
        return Ok(Stopped::NotApplicable(ks));
    };
    let d0 = ks.val()[at];
    let m = 2.0 * d0.abs().max(f64::MIN_POSITIVE);
    ks.val_mut()[at] -= m;
    let mut l_values = vec![0.0f64; symbolic.len_val()];
    let outcome = factorise(ks.as_ref(), symbolic, &mut l_values, par);
    let w = ks.nrows() - begin;
    drop(ks);
    match outcome {
        Err(LltError::NonPositivePivot { index }) if index == begin => {}
        Err(e) => return Err(CondenseError::NotPositiveDefinite(format!("{e:?}"))),
        Ok(_) => {
            return Err(CondenseError::Factorisation(
                "the factorisation did not stop at the interface".into(),
            ))
        }
    }
    let block = MatMut::from_column_major_slice_mut(&mut l_values[range], w, w);
    let schur = finish_last_supernode(block, ni - begin, m, par)?;
    Ok(Stopped::Done(l_values, schur))
}

/// The numerical supernodal Cholesky of `ks` into `l_values`.
pub(crate) fn factorise(
    ks: SparseColMatRef<'_, usize, f64>,
    symbolic: &SymbolicCholesky<usize>,
    l_values: &mut [f64],
    par: Par,
) -> Result<(), LltError> {
    let req = symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default());
    let mut mem = MemBuffer::new(req);
    symbolic
        .factorize_numeric_llt::<f64>(
            l_values,
            ks,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map(|_| ())
}

/// The last supernode X (w × w, its lower triangle the gathered Schur
/// complement of K on R ∪ B less `m` on its first diagonal entry, the r
/// interior columns R first) becomes [L_RR 0; L_BR I]; returns
/// S = X_BB − L_BR L_BRᵀ (symmetric). Only S is a dense copy of nb² values.
fn finish_last_supernode(
    mut x: MatMut<'_, f64>,
    r: usize,
    m: f64,
    par: Par,
) -> Result<Mat<f64>, CondenseError> {
    let w = x.nrows();
    let nb = w - r;
    x[(0, 0)] += m;
    let mut schur = Mat::<f64>::from_fn(nb, nb, |i, j| x[(r + i.max(j), r + i.min(j))]);
    if r > 0 {
        let x_rr = Mat::<f64>::from_fn(r, r, |i, j| x[(i.max(j), i.min(j))]);
        let llt = x_rr.llt(Side::Lower).map_err(|e| {
            CondenseError::NotPositiveDefinite(format!("last interior columns: {e:?}"))
        })?;
        let l_rr = llt.L();
        // L_BRᵀ = L_RR⁻¹ X_RB.
        let mut l_br_t = x.as_ref().get(r.., ..r).transpose().to_owned();
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(l_rr, l_br_t.as_mut(), par);
        subtract_product(schur.as_mut(), l_br_t.transpose(), l_br_t.as_ref(), par);
        for j in 0..r {
            for i in j..r {
                x[(i, j)] = l_rr[(i, j)];
            }
            for i in 0..nb {
                x[(r + i, j)] = l_br_t[(j, i)];
            }
        }
    }
    for j in 0..nb {
        for i in j..nb {
            x[(r + i, r + j)] = if i == j { 1.0 } else { 0.0 };
            let v = 0.5 * (schur[(i, j)] + schur[(j, i)]);
            schur[(i, j)] = v;
            schur[(j, i)] = v;
        }
    }
    Ok(schur)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ordering::{order_and_analyse, OrderingChoice};
    use crate::test_matrices::grid3;

    /// The stopped factorisation gives S of the plain formula to rounding
    /// (relative to ‖K‖), held or floating, and leaves the matrix unchanged;
    /// the factor it leaves solves the interior as the whole factor does.
    #[test]
    fn the_stopped_factorisation_gives_the_schur_complement() {
        let m = 8;
        for held in [true, false] {
            let k = grid3(m, held);
            let n = k.nrows();
            let nb = m * m;
            let ni = n - nb;
            let interface: Vec<usize> = (ni..n).collect();
            let f: Vec<f64> = (0..n).map(|i| ((i * 7) % 5) as f64 - 2.0).collect();
            // Floating or not, K_II is definite (the interface holds the
            // grid): the plain formula applies.
            let (reference, fp_ref) =
                crate::schur_complement_reference(k.as_ref(), &interface, &f).unwrap();
            let ordered = order_and_analyse(k.as_ref(), ni, OrderingChoice::Auto).unwrap();
            let stopped =
                schur_by_stopped_factorisation(k.clone(), &ordered.symbolic, ni, Par::Seq).unwrap();
            let Stopped::Done(_, schur) = stopped else {
                panic!("the interface of a grid is one supernode");
            };
            let (begin, _) = interface_supernode(&ordered.symbolic, ni).unwrap();
            assert!(
                begin < ni,
                "the relaxed supernode holds interior columns too"
            );
            let k_norm = k.val().iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for j in 0..nb {
                for i in 0..nb {
                    let d = (schur[(i, j)] - reference[(i, j)]).abs();
                    assert!(d <= 1e-12 * k_norm, "held {held}: S[{i},{j}] off by {d:e}");
                }
            }
            // The factor left behind (its finished interior columns and
            // L_BB = I) condenses loads and recovers the interior exactly.
            let c = crate::Condensed::new(k.as_ref(), &interface, Par::Seq).unwrap();
            let f_norm = f.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (a, b) in c.condensed_load(&f).iter().zip(&fp_ref) {
                assert!((a - b).abs() <= 1e-12 * f_norm * k_norm, "F' {a} vs {b}");
            }
            let u_b: Vec<f64> = (0..nb).map(|j| (j as f64 * 0.3).sin()).collect();
            let u = c.recover(k.as_ref(), &f, &u_b);
            let ku = crate::spmv(k.as_ref(), &u);
            for i in 0..ni {
                assert!(
                    (ku[i] - f[i]).abs() <= 1e-10 * f_norm,
                    "interior equilibrium at {i}"
                );
            }
        }
    }
}
