//! The elimination of tied DOFs from the interface problem (docs/theory/
//! mortar.md, "Ties"). Every DOF of a tie's surfaces is on Γ; a slave DOF is
//! a combination of master DOFs, u_s = Σ c u_m (`model::ties`), so
//! u_Γ = T v with v the kept Γ DOFs (every Γ DOF but the tied slave ones)
//! and T = [I; C] up to ordering. The root solves on v: S_v = Tᵀ S T
//! (assembled from the subdomains' Tᵢᵀ Sᵢ Tᵢ), F_v = Tᵀ F', B_v = B T, and
//! hands u_Γ = T v back; nothing below the root sees the tie. The tie's
//! multipliers (the bond's forces) are eliminated with it: T spans exactly
//! the displacements the ties allow, so T v is the solution of the problem
//! with the equality constraints u_s − C u_m = 0.

use crate::error::SolveError;
use crate::model::Ties;
use crate::subdomain::CondensedData;
use faer::sparse::{SparseColMat, Triplet};
use std::collections::{BTreeMap, HashMap};

/// T as the expansion of every Γ DOF over the kept ones.
#[derive(Debug, Clone)]
pub(crate) struct TieReduction {
    /// Per Γ DOF: its combination of kept DOFs (one entry of weight 1 for
    /// a kept DOF).
    of_gamma: Vec<Vec<(usize, f64)>>,
    /// Per Γ DOF: its index among the kept DOFs (`usize::MAX` for a tied one).
    kept: Vec<usize>,
    /// The number of kept DOFs.
    pub n_kept: usize,
}

impl TieReduction {
    /// T from the tied DOFs and a numbering of the bodies' DOFs (Γ on the
    /// condensed path, the free DOFs on the direct path; `usize::MAX` off
    /// it) of size `n_gamma`; `None` without a tie.
    pub(crate) fn new(ties: &Ties, gamma_of: &[Vec<usize>], n_gamma: usize) -> Option<Self> {
        if ties.dofs.is_empty() {
            return None;
        }
        let mut tied: BTreeMap<usize, Vec<(usize, f64)>> = BTreeMap::new();
        for d in &ties.dofs {
            let g = gamma_of[d.slave.0][d.slave.1];
            if g == usize::MAX {
                continue;
            }
            let masters = d
                .masters
                .iter()
                .map(|&(b, dof, c)| (gamma_of[b][dof], c))
                .filter(|&(g, _)| g != usize::MAX)
                .collect();
            tied.insert(g, masters);
        }
        let mut kept = vec![usize::MAX; n_gamma];
        let mut n_kept = 0;
        for (g, k) in kept.iter_mut().enumerate() {
            if !tied.contains_key(&g) {
                *k = n_kept;
                n_kept += 1;
            }
        }
        let of_gamma = (0..n_gamma)
            .map(|g| match tied.get(&g) {
                None => vec![(kept[g], 1.0)],
                Some(masters) => masters
                    .iter()
                    .filter(|&&(m, _)| kept[m] != usize::MAX)
                    .map(|&(m, c)| (kept[m], c))
                    .collect(),
            })
            .collect();
        Some(TieReduction {
            of_gamma,
            kept,
            n_kept,
        })
    }

    /// The kept index of Γ DOF `g`, `None` for a tied slave DOF.
    pub(crate) fn kept(&self, g: usize) -> Option<usize> {
        Some(self.kept[g]).filter(|&k| k != usize::MAX)
    }

    /// A row over Γ times T: a row over the kept DOFs.
    pub(crate) fn row(&self, row: &[(usize, f64)]) -> Vec<(usize, f64)> {
        let mut out: BTreeMap<usize, f64> = BTreeMap::new();
        for &(g, c) in row {
            for &(k, t) in &self.of_gamma[g] {
                *out.entry(k).or_default() += c * t;
            }
        }
        out.into_iter().filter(|&(_, c)| c != 0.0).collect()
    }

    /// u_Γ = T v.
    pub(crate) fn expand(&self, v: &[f64]) -> Vec<f64> {
        self.of_gamma
            .iter()
            .map(|e| e.iter().map(|&(k, t)| t * v[k]).sum())
            .collect()
    }

    /// Tᵀ r: a residual over Γ as the kept DOFs see it (the tied slave
    /// DOFs' residuals carried to their masters, as the tie's forces do).
    pub(crate) fn fold(&self, r: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n_kept];
        for (e, &v) in self.of_gamma.iter().zip(r) {
            for &(k, t) in e {
                out[k] += t * v;
            }
        }
        out
    }

    /// Each subdomain's data on the kept DOFs: Tᵢᵀ Sᵢ Tᵢ and Tᵢᵀ F'ᵢ, its
    /// Γ indices the kept DOFs its own reach through T.
    pub(crate) fn reduce(&self, data: &mut [CondensedData]) {
        for d in data {
            let nb = d.gamma.len();
            let mut local: BTreeMap<usize, usize> = BTreeMap::new();
            for &g in &d.gamma {
                for &(k, _) in &self.of_gamma[g] {
                    local.insert(k, 0);
                }
            }
            for (i, slot) in local.values_mut().enumerate() {
                *slot = i;
            }
            let nk = local.len();
            // Tᵢ by rows: local Γ DOF → (new local index, weight)
            let t: Vec<Vec<(usize, f64)>> = d
                .gamma
                .iter()
                .map(|&g| {
                    self.of_gamma[g]
                        .iter()
                        .map(|&(k, w)| (local[&k], w))
                        .collect()
                })
                .collect();
            let mut st = vec![0.0; nb * nk]; // Sᵢ Tᵢ, column-major nb × nk
            for (j, tj) in t.iter().enumerate() {
                for &(c, w) in tj {
                    for i in 0..nb {
                        st[i + nb * c] += d.schur[i + nb * j] * w;
                    }
                }
            }
            let mut s = vec![0.0; nk * nk];
            for c in 0..nk {
                for (i, ti) in t.iter().enumerate() {
                    for &(r, w) in ti {
                        s[r + nk * c] += w * st[i + nb * c];
                    }
                }
            }
            for f in &mut d.fprime {
                let mut out = vec![0.0; nk];
                for (i, ti) in t.iter().enumerate() {
                    for &(r, w) in ti {
                        out[r] += w * f[i];
                    }
                }
                *f = out;
            }
            d.schur = s;
            d.gamma = local.into_keys().collect();
        }
    }

    /// Tᵀ K T of a sparse matrix over the numbering (the direct path's
    /// stiffness on the free DOFs).
    pub(crate) fn reduce_matrix(
        &self,
        k: &SparseColMat<usize, f64>,
    ) -> Result<SparseColMat<usize, f64>, SolveError> {
        let mut sum: HashMap<(usize, usize), f64> = HashMap::new();
        for j in 0..k.ncols() {
            for (&i, &v) in k.row_idx_of_col_raw(j).iter().zip(k.val_of_col(j)) {
                for &(a, ta) in &self.of_gamma[i] {
                    for &(b, tb) in &self.of_gamma[j] {
                        *sum.entry((a, b)).or_default() += ta * tb * v;
                    }
                }
            }
        }
        let mut triplets: Vec<Triplet<usize, usize, f64>> = sum
            .into_iter()
            .map(|((a, b), v)| Triplet::new(a, b, v))
            .collect();
        triplets.sort_unstable_by_key(|t| (t.col, t.row));
        SparseColMat::try_new_from_triplets(self.n_kept, self.n_kept, &triplets)
            .map_err(|e| SolveError::Internal(format!("the tied stiffness: {e:?}")))
    }
}
