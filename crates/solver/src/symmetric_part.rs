//! The Newton direction of the whole-system friction method
//! ([`crate::direct_newton`]) by a symmetric LDLᵀ and GMRES instead of a
//! sparse LU of its nonsymmetric Jacobian J.
//!
//! Each point's equations are on orthonormal directions c_j of its force
//! rows, dλ = Σ_j c_j α_j: a given row is α_j − f α_n = v, a coupled row
//! d_j α_j + Σ_l c_jᵀ Ĉ c_l α_l + c_jᵀ B du + f α_n = v (Ĉ the rows'
//! compliance with the matrix's shift, f Coulomb's terms on the normal
//! force α_n), and the equilibrium rows are K du − Σ_j B̃_jᵀ α_j = v with
//! B̃_j = c_jᵀ B. Without Coulomb's terms the Jacobian, M, is block
//! triangular in the α: a given α is its right-hand side, and the kept
//! unknowns (u, the coupled α) solve, with their rows scaled by s (the
//! mean |diag K|, as [`crate::kkt`]) and α = −s ω,
//!
//! ```text
//!   [ K     s B̃ᵀ  ] [u]   [ r_u + B̃_eᵀ α_e          ]
//!   [ s B̃   −s² D ] [ω] = [ s (r_c − D_ke α_e)       ]
//! ```
//!
//! with D = diag(d) + (c_jᵀ Ĉ c_l) ≥ 0: symmetric and quasi-definite once
//! −δ is added on the contact diagonal (and γ on K's when a body floats),
//! factorised by the sparse LDLᵀ of [`crate::kkt`] (Vanderbei 1995) whose
//! pattern holds every row of every point whatever its status (a given
//! unknown is decoupled, −s on its diagonal): one ordering and symbolic
//! factor per run, a numerical factor per Newton iteration. J x = b is
//! then solved by GMRES ([`crate::gmres`]) preconditioned by M⁻¹:
//! J M⁻¹ = I + (J − M) M⁻¹, J − M being μ times the normal–tangential
//! coupling of the slipping points and the regularisation, so a few
//! Krylov steps reach the exact Newton direction. The Krylov residual
//! weighs the coupled rows by s, so that every row is a force.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::{Pair, SparseColMat};
use faer::{Conj, MatMut};

use crate::fixed_pattern::FixedPattern;
use crate::gmres::gmres;
use crate::kkt::{
    ldlt_scratch, numeric_ldlt, row_scale, ACCEPTED_BACKWARD_ERROR, TARGET_BACKWARD_ERROR,
};
use signorini_condense::ordering::{order_and_analyse, OrderedSymbolic, OrderingChoice};
use signorini_contact::friction::Dir;
use signorini_linalg::sparse::SparseRow;

/// GMRES stops at this residual relative to the right-hand side (2-norm,
/// rows weighed as forces)...
pub(crate) const KRYLOV_TOLERANCE: f64 = 1e-12;
/// ... or fails after this many steps (the caller then takes the LU).
pub(crate) const MAX_KRYLOV_STEPS: usize = 30;
/// GMRES runs at most this many times, each on the residual of the last
/// (restarted), until the solve's backward error is a few roundings
/// ([`TARGET_BACKWARD_ERROR`], as the LU's refinement); the direction is
/// accepted at [`ACCEPTED_BACKWARD_ERROR`], as the LU's.
const RESTARTS: usize = 4;

/// The contact rows grouped by point, as the whole system holds them.
pub(crate) struct Points<'a> {
    pub rows: &'a [SparseRow],
    /// The rows of each point: its normal row, then its tangential rows.
    pub point_rows: &'a [Vec<usize>],
    /// The point of each row.
    pub owner: &'a [usize],
}

/// A Newton system's equations in the unknowns α (module doc): for each
/// contact row s of J (the slot of one equation), its direction over its
/// point's rows (in the order of `point_rows`), whether it is given, and
/// its d (zero for a given row).
pub(crate) struct Rotation {
    dir: Vec<[f64; 3]>,
    given: Vec<bool>,
    d: Vec<f64>,
}

impl Rotation {
    /// The rotation of `equations` (slot, direction, given, d).
    pub(crate) fn new(
        points: &Points,
        equations: impl Iterator<Item = (usize, Dir, bool, f64)>,
    ) -> Self {
        let m = points.rows.len();
        let mut rot = Self {
            dir: vec![[0.0; 3]; m],
            given: vec![true; m],
            d: vec![0.0; m],
        };
        for (slot, dir, given, d) in equations {
            let pr = &points.point_rows[points.owner[slot]];
            for l in 0..2 {
                if let Some(at) = pr.iter().position(|&r| r == dir.rows[l]) {
                    rot.dir[slot][at] += dir.c[l];
                }
            }
            rot.given[slot] = given;
            rot.d[slot] = d;
        }
        rot
    }
}

/// The symmetric part's pattern, ordering and symbolic LDLᵀ (computed
/// once per run), each point's rows on its DOFs, the storage of its values,
/// factor and scratch (allocated once), and the counts.
pub(crate) struct SymmetricPart {
    row_scale: f64,
    delta: f64,
    gamma: f64,
    /// Each point's DOFs (the union of its rows'), and its rows'
    /// coefficients on them, row after row.
    dofs: Vec<Vec<usize>>,
    coefs: Vec<Vec<f64>>,
    matrix: FixedPattern,
    /// The matrix's values in the order of its pairs.
    values: Vec<f64>,
    ordered: OrderedSymbolic,
    l_values: Vec<f64>,
    scratch: MemBuffer,
    /// Numerical LDLᵀ factorisations, and Krylov steps over all solves.
    pub(crate) factorisations: usize,
    pub(crate) krylov_steps: usize,
}

impl SymmetricPart {
    /// The symmetric part of stiffness `k` (both triangles) and `points`;
    /// `floating` when K is singular.
    pub(crate) fn new(
        k: &SparseColMat<usize, f64>,
        points: &Points,
        floating: bool,
    ) -> Result<Self, String> {
        let (n, m) = (k.nrows(), points.rows.len());
        let (mut dofs, mut coefs) = (Vec::new(), Vec::new());
        for pr in points.point_rows {
            let mut d: Vec<usize> = pr
                .iter()
                .flat_map(|&r| points.rows[r].iter().map(|&(i, _)| i))
                .collect();
            d.sort_unstable();
            d.dedup();
            let mut c = vec![0.0; pr.len() * d.len()];
            for (li, &r) in pr.iter().enumerate() {
                for &(i, v) in &points.rows[r] {
                    let t = d.binary_search(&i).unwrap_or(0);
                    c[li * d.len() + t] += v;
                }
            }
            dofs.push(d);
            coefs.push(c);
        }
        let mut pairs: Vec<Pair<usize, usize>> = Vec::new();
        for j in 0..n {
            pairs.extend(k.row_idx_of_col_raw(j).iter().map(|&i| Pair::new(i, j)));
        }
        for (pr, d) in points.point_rows.iter().zip(&dofs) {
            for &s in pr {
                for &i in d {
                    pairs.push(Pair::new(i, n + s));
                    pairs.push(Pair::new(n + s, i));
                }
            }
        }
        for pr in points.point_rows {
            for &s in pr {
                pairs.extend(pr.iter().map(|&r| Pair::new(n + s, n + r)));
            }
        }
        if floating {
            pairs.extend((0..n).map(|i| Pair::new(i, i)));
        }
        let mut matrix = FixedPattern::new(n + m, n + m, &pairs)
            .map_err(|e| format!("symmetric part pattern: {e}"))?;
        let ones = matrix.set(&vec![1.0; pairs.len()]);
        let ordered = order_and_analyse(ones.as_ref(), n + m, OrderingChoice::Auto)
            .map_err(|e| format!("symmetric part ordering: {e}"))?;
        let s = row_scale(k);
        let sqrt_eps = f64::EPSILON.sqrt();
        let scratch = ldlt_scratch(&ordered.symbolic, faer::get_global_parallelism());
        Ok(Self {
            row_scale: s,
            delta: sqrt_eps * s,
            gamma: if floating { sqrt_eps * s } else { 0.0 },
            dofs,
            coefs,
            matrix,
            values: Vec::with_capacity(pairs.len()),
            l_values: vec![0.0; ordered.symbolic.len_val()],
            ordered,
            scratch,
            factorisations: 0,
            krylov_steps: 0,
        })
    }

    /// The ordering and size of the LDLᵀ factor.
    pub(crate) fn ordered(&self) -> &OrderedSymbolic {
        &self.ordered
    }

    /// The values of the scaled, regularised M_kk (module doc) in the
    /// order of the pattern's pairs, into `v`; `chat` the rows' Ĉ.
    fn values(
        &self,
        k: &SparseColMat<usize, f64>,
        points: &Points,
        (rot, chat): (&Rotation, &[f64]),
        v: &mut Vec<f64>,
    ) {
        let s = self.row_scale;
        v.clear();
        v.extend_from_slice(k.val());
        for (p, pr) in points.point_rows.iter().enumerate() {
            let nd = self.dofs[p].len();
            for &slot in pr {
                for t in 0..nd {
                    let b = if rot.given[slot] {
                        0.0
                    } else {
                        (0..pr.len())
                            .map(|li| rot.dir[slot][li] * self.coefs[p][li * nd + t])
                            .sum::<f64>()
                    };
                    v.push(s * b);
                    v.push(s * b);
                }
            }
        }
        for pr in points.point_rows {
            for &a in pr {
                for &b in pr {
                    v.push(if rot.given[a] || rot.given[b] {
                        if a == b {
                            -s
                        } else {
                            0.0
                        }
                    } else {
                        let cross = point_compliance(rot, pr, chat, a, b);
                        let d = if a == b { rot.d[a] } else { 0.0 };
                        let reg = if a == b { self.delta } else { 0.0 };
                        -s * s * (d + cross) - reg
                    });
                }
            }
        }
        if self.gamma > 0.0 {
            v.extend(std::iter::repeat_n(self.gamma, k.nrows()));
        }
    }

    /// Solves J x = b (`j` the whole Jacobian, unknowns (u, λ), rows: the
    /// equilibrium, then the contact equations by slot) by GMRES
    /// preconditioned by M⁻¹ (module doc): with `forcing` η, to the
    /// weighted relative residual η (an inexact Newton direction,
    /// [`crate::direct_forcing`]), else (or when that is not reached) to
    /// the LU's backward error; `None` when the LDLᵀ fails or GMRES reaches
    /// neither.
    pub(crate) fn solve(
        &mut self,
        k: &SparseColMat<usize, f64>,
        points: &Points,
        (rot, chat): (&Rotation, &[f64]),
        (j, b): (&SparseColMat<usize, f64>, &[f64]),
        forcing: Option<f64>,
    ) -> Option<Vec<f64>> {
        let n = k.nrows();
        let mut values = std::mem::take(&mut self.values);
        self.values(k, points, (rot, chat), &mut values);
        let a = self.matrix.set(&values);
        self.values = values;
        self.factorisations += 1;
        let s = self.row_scale;
        let weight: Vec<f64> = (0..b.len())
            .map(|i| if i >= n && !rot.given[i - n] { s } else { 1.0 })
            .collect();
        let par = faer::get_global_parallelism();
        let symbolic = &self.ordered.symbolic;
        let stack = MemStack::new(&mut self.scratch);
        let ldlt = numeric_ldlt(symbolic, &mut self.l_values, a.as_ref(), par, stack)?;
        let block = Block {
            n,
            s,
            points,
            rot,
            chat,
            dofs: &self.dofs,
            coefs: &self.coefs,
        };
        let mut precondition = |v: &[f64]| -> Vec<f64> {
            let r: Vec<f64> = v.iter().zip(&weight).map(|(x, w)| x / w).collect();
            block.solve(&r, |y| {
                let ym = MatMut::from_column_major_slice_mut(y, r.len(), 1);
                ldlt.solve_in_place_with_conj(Conj::No, ym, par, stack);
            })
        };
        let weighted = Weighted { j, weight: &weight };
        let (x, steps) = weighted.krylov(&mut precondition, b, forcing);
        self.krylov_steps += steps;
        x
    }
}

/// J with its rows weighed (module doc).
struct Weighted<'w> {
    j: &'w SparseColMat<usize, f64>,
    weight: &'w [f64],
}

impl Weighted<'_> {
    /// w ⊙ J x.
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = product(self.j, x);
        y.iter_mut().zip(self.weight).for_each(|(v, w)| *v *= w);
        y
    }

    /// x solving J x = b by GMRES preconditioned by `precondition`: with
    /// `forcing` η, one cycle to the weighted relative residual η; else,
    /// or when that cycle fails, restarted cycles to the LU's backward
    /// error. The x (`None` when neither is reached) and the Krylov steps.
    fn krylov(
        &self,
        precondition: &mut impl FnMut(&[f64]) -> Vec<f64>,
        b: &[f64],
        forcing: Option<f64>,
    ) -> (Option<Vec<f64>>, usize) {
        let (j, weight) = (self.j, self.weight);
        let apply = |x: &[f64]| self.apply(x);
        let mut x = vec![0.0; b.len()];
        let mut steps_taken = 0;
        let (mut berr, mut r) = weighted_backward_error(j, weight, &x, b);
        if let Some(eta) = forcing {
            let out = gmres(apply, &mut *precondition, &r, eta, MAX_KRYLOV_STEPS);
            if let Some((d, steps)) = out {
                if d.iter().all(|v| v.is_finite()) {
                    return (Some(d), steps);
                }
            }
            steps_taken += MAX_KRYLOV_STEPS;
        }
        for _ in 0..RESTARTS {
            if berr <= TARGET_BACKWARD_ERROR {
                break;
            }
            let out = gmres(
                apply,
                &mut *precondition,
                &r,
                KRYLOV_TOLERANCE,
                MAX_KRYLOV_STEPS,
            );
            let Some((d, steps)) = out else { break };
            steps_taken += steps;
            let candidate: Vec<f64> = x.iter().zip(&d).map(|(a, b)| a + b).collect();
            let (e, rr) = weighted_backward_error(j, weight, &candidate, b);
            // Stop when a cycle does not help (also when e is NaN).
            if e.partial_cmp(&berr) != Some(std::cmp::Ordering::Less) {
                break;
            }
            (x, berr, r) = (candidate, e, rr);
        }
        let accepted = berr <= ACCEPTED_BACKWARD_ERROR;
        (accepted.then_some(x), steps_taken)
    }
}

/// The normwise backward error ‖w ⊙ (b − J x)‖∞ / (‖w ⊙ |J||x|‖∞ +
/// ‖w ⊙ b‖∞) of x (rows weighed by `w`, module doc), and the weighted
/// residual w ⊙ (b − J x).
fn weighted_backward_error(
    j: &SparseColMat<usize, f64>,
    w: &[f64],
    x: &[f64],
    b: &[f64],
) -> (f64, Vec<f64>) {
    let mut jx = vec![0.0; j.nrows()];
    let mut size = vec![0.0; j.nrows()];
    for (c, &xc) in x.iter().enumerate() {
        for (&i, &v) in j.row_idx_of_col_raw(c).iter().zip(j.val_of_col(c)) {
            jx[i] += v * xc;
            size[i] += (v * xc).abs();
        }
    }
    let r: Vec<f64> = (0..b.len()).map(|i| w[i] * (b[i] - jx[i])).collect();
    let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |a, x| a.max(x.abs()));
    let scale = max(&mut (0..b.len()).map(|i| w[i] * size[i]))
        + max(&mut (0..b.len()).map(|i| w[i] * b[i]));
    let err = max(&mut r.iter().copied());
    (if scale > 0.0 { err / scale } else { err }, r)
}

/// c_aᵀ Ĉ c_b over point rows `pr`.
fn point_compliance(rot: &Rotation, pr: &[usize], chat: &[f64], a: usize, b: usize) -> f64 {
    pr.iter()
        .enumerate()
        .map(|(li, &r)| rot.dir[a][li] * chat[r] * rot.dir[b][li])
        .sum()
}

/// What M⁻¹ reads (module doc).
struct Block<'b> {
    n: usize,
    s: f64,
    points: &'b Points<'b>,
    rot: &'b Rotation,
    chat: &'b [f64],
    dofs: &'b [Vec<usize>],
    coefs: &'b [Vec<f64>],
}

impl Block<'_> {
    /// x = M⁻¹ r (rows of J in, unknowns (u, λ) out), the kept block
    /// solved in place by `solve_kept` (the LDLᵀ of M_kk).
    fn solve(&self, r: &[f64], mut solve_kept: impl FnMut(&mut [f64])) -> Vec<f64> {
        let (n, s, rot) = (self.n, self.s, self.rot);
        let mut alpha = vec![0.0; r.len() - n];
        let mut y = r.to_vec();
        for (p, pr) in self.points.point_rows.iter().enumerate() {
            let nd = self.dofs[p].len();
            for &e in pr.iter().filter(|&&e| rot.given[e]) {
                alpha[e] = r[n + e];
                y[n + e] = 0.0;
                for li in 0..pr.len() {
                    let c = rot.dir[e][li] * alpha[e];
                    for (t, &i) in self.dofs[p].iter().enumerate() {
                        y[i] += c * self.coefs[p][li * nd + t];
                    }
                }
            }
            for &a in pr.iter().filter(|&&a| !rot.given[a]) {
                let coupling: f64 = pr
                    .iter()
                    .filter(|&&e| rot.given[e])
                    .map(|&e| point_compliance(rot, pr, self.chat, a, e) * alpha[e])
                    .sum();
                y[n + a] = s * (r[n + a] - coupling);
            }
        }
        solve_kept(&mut y);
        let mut x = y[..n].to_vec();
        x.resize(r.len(), 0.0);
        for pr in self.points.point_rows {
            for &a in pr.iter().filter(|&&a| !rot.given[a]) {
                alpha[a] = -s * y[n + a];
            }
            for (li, &row) in pr.iter().enumerate() {
                x[n + row] = pr.iter().map(|&a| rot.dir[a][li] * alpha[a]).sum();
            }
        }
        x
    }
}

/// y = A x for a sparse A (column storage).
fn product(a: &SparseColMat<usize, f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.nrows()];
    for (c, &xc) in x.iter().enumerate() {
        for (&i, &v) in a.row_idx_of_col_raw(c).iter().zip(a.val_of_col(c)) {
            y[i] += v * xc;
        }
    }
    y
}
