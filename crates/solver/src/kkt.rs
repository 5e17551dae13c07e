//! The direct path: the contact problem on the whole sparse stiffness,
//! refactorised at each status iteration as course notes §3.3 describes ("il faut
//! procéder à une factorisation de la matrice de raideur globale à chaque
//! itération"). For checking the condensed path and for benchmarking it.
//!
//! For an active set A it solves the saddle-point system
//! [K B_Aᵀ; B_A 0] [u; −λ_A] = [F; −g0_A], with the constraint rows scaled by
//! s = the mean of |diag K| ([K s B_Aᵀ; s B_A 0] [u; −λ_A / s] = [F; −s g0_A])
//! so that the pivots of both blocks have the same magnitude whatever the
//! units (without it, E = 210e9 against unit rows loses seven digits).
//!
//! The matrix is symmetric indefinite. It is factorised by a sparse LDLᵀ of
//! the quasi-definite neighbour M̃ = [K + γI, s Bᵀ; s B, −δI] (Vanderbei 1995:
//! a quasi-definite matrix has an LDLᵀ factorisation in every symmetric
//! ordering, so the fill-reducing ordering is free), with δ = √ε s on the
//! active constraint rows and γ = √ε s on K only when a body floats (K
//! singular). Iterative refinement against the exact matrix removes the
//! regularisation: each step multiplies the error by about ‖M̃⁻¹(M̃ − M)‖ ≈
//! √ε κ, so two or three steps reach the exact solution to rounding. A solve
//! whose backward error stays above [`ACCEPTED_BACKWARD_ERROR`] is redone by
//! sparse LU (counted in `lu_fallbacks`).
//!
//! The pattern holds every contact row, active or not (an inactive row p
//! has its B entries zero and −s on its diagonal: it gives λ_p = 0), so the
//! ordering and the symbolic factor are computed once per run, by the rule
//! of condensation (the cheaper in flops of AMD and nested dissection,
//! `signorini_condense::ordering`), and only the numerical LDLᵀ is redone at
//! each status iteration.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::prelude::Solve;
use faer::sparse::linalg::cholesky::{LdltRef, SymbolicCholesky};
use faer::sparse::{Argsort, Pair, SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Mat, MatMut};

use signorini_condense::ordering::{order_and_analyse, OrderedSymbolic, OrderingChoice};
use signorini_condense::spmv_with_magnitude;
use signorini_contact::ActiveSetSolve;
use signorini_contact::ContactError;
use signorini_linalg::conditioning::inverse_norm1_estimate;
use signorini_linalg::sparse::SparseRow;

/// Largest normwise backward error ‖b − M x‖∞ / (‖|M||x|‖∞ + ‖b‖∞) accepted
/// from the refined LDLᵀ solve: a thousand roundings (a backward-stable
/// solve gives a few; the margin covers long rows summed in the residual).
pub const ACCEPTED_BACKWARD_ERROR: f64 = 1e3 * f64::EPSILON;
/// Refinement stops at this backward error (a few roundings)...
pub(crate) const TARGET_BACKWARD_ERROR: f64 = 4.0 * f64::EPSILON;
/// ... or after this many steps.
const MAX_REFINEMENT_STEPS: usize = 20;

/// Counts of the KKT solves of a run (report.json `factorisation`).
#[derive(Debug, Clone, Copy, Default)]
pub struct KktCounts {
    pub factorisations: usize,
    pub refinement_steps: usize,
    pub lu_fallbacks: usize,
}

/// The KKT matrix of a run: its pattern with every contact row, its
/// ordering and symbolic LDLᵀ factor (computed once), and the counts of
/// its numerical factorisations.
pub struct KktSystem<'a> {
    k: &'a SparseColMat<usize, f64>,
    rows: &'a [SparseRow],
    /// The scale s of the constraint rows (mean |diag K|).
    row_scale: f64,
    /// Regularisation of the active constraint rows' diagonal.
    delta: f64,
    /// Regularisation of K's diagonal (0 unless a body floats).
    gamma: f64,
    pattern: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    ordered: OrderedSymbolic,
    l_values: Vec<f64>,
    pub counts: KktCounts,
}

impl<'a> KktSystem<'a> {
    /// The KKT system of stiffness `k` (both triangles stored) and the
    /// contact `rows` (on K's DOFs); `floating` when K is singular.
    pub fn new(
        k: &'a SparseColMat<usize, f64>,
        rows: &'a [SparseRow],
        floating: bool,
    ) -> Result<Self, ContactError> {
        let (n, m) = (k.nrows(), rows.len());
        let row_scale = row_scale(k);
        let sqrt_eps = f64::EPSILON.sqrt();
        let pairs = kkt_pairs(k, rows, floating);
        let (pattern, argsort) = SymbolicSparseColMat::try_new_from_indices(n + m, n + m, &pairs)
            .map_err(|e| ContactError::Solve(format!("KKT pattern: {e:?}")))?;
        let ones =
            SparseColMat::new_from_argsort(pattern.clone(), &argsort, &vec![1.0; pairs.len()])
                .map_err(|e| ContactError::Solve(format!("KKT pattern: {e:?}")))?;
        let ordered = order_and_analyse(ones.as_ref(), n + m, OrderingChoice::Auto)
            .map_err(|e| ContactError::Solve(format!("KKT ordering: {e}")))?;
        Ok(Self {
            k,
            rows,
            row_scale,
            delta: sqrt_eps * row_scale,
            gamma: if floating { sqrt_eps * row_scale } else { 0.0 },
            pattern,
            argsort,
            l_values: vec![0.0; ordered.symbolic.len_val()],
            ordered,
            counts: KktCounts::default(),
        })
    }

    /// κ₁(K) = ‖K‖₁ ‖K⁻¹‖₁ of the stiffness alone (K positive definite:
    /// no floating body), ‖K⁻¹‖₁ by the Hager–Higham estimator on one LDLᵀ
    /// of the KKT matrix with every contact row inactive, blockdiag(K, −sI),
    /// whose leading block's inverse is K⁻¹: the run's ordering and symbolic
    /// factor serve, no second ordering. `None` when the factorisation fails
    /// or the estimate is not finite.
    pub fn stiffness_condition(&mut self) -> Option<f64> {
        let (n, m) = (self.k.nrows(), self.rows.len());
        if n == 0 || self.gamma > 0.0 {
            return None;
        }
        let a = self.matrix(&vec![false; m], false).ok()?;
        let par = faer::get_global_parallelism();
        let symbolic = &self.ordered.symbolic;
        let mut mem = ldlt_scratch(symbolic, par);
        let stack = MemStack::new(&mut mem);
        let ldlt = numeric_ldlt(symbolic, &mut self.l_values, a.as_ref(), par, stack)?;
        let mut y = vec![0.0; n + m];
        let inverse = inverse_norm1_estimate(n, |x| {
            y[..n].copy_from_slice(x);
            y[n..].fill(0.0);
            let ym = MatMut::from_column_major_slice_mut(&mut y, n + m, 1);
            ldlt.solve_in_place_with_conj(Conj::No, ym, par, stack);
            x.copy_from_slice(&y[..n]);
        });
        let norm = (0..n)
            .map(|j| self.k.val_of_col(j).iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        Some(norm * inverse).filter(|kappa| kappa.is_finite())
    }

    /// The ordering and size of the LDLᵀ factor.
    pub fn ordered(&self) -> &OrderedSymbolic {
        &self.ordered
    }

    /// The KKT matrix for the active set `is_active`: exact
    /// (`regularised == false`) or M̃ (module doc), in the order of
    /// [`kkt_pairs`].
    fn matrix(
        &self,
        is_active: &[bool],
        regularised: bool,
    ) -> Result<SparseColMat<usize, f64>, ContactError> {
        let n = self.k.nrows();
        let s = self.row_scale;
        let mut v: Vec<f64> = self.k.val().to_vec();
        for (p, row) in self.rows.iter().enumerate() {
            for &(_, c) in row {
                let b = if is_active[p] { s * c } else { 0.0 };
                v.push(b);
                v.push(b);
            }
        }
        for &a in is_active {
            v.push(match (a, regularised) {
                (false, _) => -s,
                (true, false) => 0.0,
                (true, true) => -self.delta,
            });
        }
        if self.gamma > 0.0 {
            let g = if regularised { self.gamma } else { 0.0 };
            v.extend(std::iter::repeat_n(g, n));
        }
        SparseColMat::new_from_argsort(self.pattern.clone(), &self.argsort, &v)
            .map_err(|e| ContactError::Solve(format!("KKT values: {e:?}")))
    }

    /// Solves M x = b for the active set: LDLᵀ of M̃ and iterative
    /// refinement, or sparse LU when that does not reach
    /// [`ACCEPTED_BACKWARD_ERROR`].
    fn solve(&mut self, is_active: &[bool], b: &[f64]) -> Result<Vec<f64>, ContactError> {
        let exact = self.matrix(is_active, false)?;
        let regularised = self.matrix(is_active, true)?;
        self.counts.factorisations += 1;
        let par = faer::get_global_parallelism();
        let symbolic = &self.ordered.symbolic;
        let mut mem = ldlt_scratch(symbolic, par);
        let stack = MemStack::new(&mut mem);
        let factor = numeric_ldlt(
            symbolic,
            &mut self.l_values,
            regularised.as_ref(),
            par,
            stack,
        );
        let refined = match factor {
            Some(ldlt) => {
                let n = b.len();
                let solve = |rhs: &[f64]| {
                    let mut x = rhs.to_vec();
                    let xm = MatMut::from_column_major_slice_mut(&mut x, n, 1);
                    ldlt.solve_in_place_with_conj(Conj::No, xm, par, stack);
                    x
                };
                refine(&exact, solve, b)
            }
            None => None,
        };
        if let Some((x, steps)) = refined {
            self.counts.refinement_steps += steps;
            return Ok(x);
        }
        self.counts.lu_fallbacks += 1;
        solve_by_lu(&exact, b)
    }
}

/// The scale s of the constraint rows: the mean of |diag K| (1 when that
/// is not positive and finite).
pub(crate) fn row_scale(k: &SparseColMat<usize, f64>) -> f64 {
    let n = k.nrows();
    let mut diag = 0.0;
    for j in 0..n {
        for (&i, &v) in k.row_idx_of_col_raw(j).iter().zip(k.val_of_col(j)) {
            if i == j {
                diag += v.abs();
            }
        }
    }
    let mean = diag / n.max(1) as f64;
    if mean.is_finite() && mean > 0.0 {
        mean
    } else {
        1.0
    }
}

/// The report.json `factorisation` of an LDLᵀ of ordering `ordered`
/// (`kind`), with its counts.
pub(crate) fn ldlt_factorisation(
    ordered: &OrderedSymbolic,
    kind: &str,
    counts: KktCounts,
) -> signorini_report::Factorisation {
    let stats = ordered.stats;
    signorini_report::Factorisation {
        kind: kind.into(),
        ordering: stats.ordering.as_str().into(),
        factor_nnz: stats.nnz as u64,
        factor_bytes: 8 * stats.values as u64,
        flops: stats.flops,
        candidates: ordered
            .candidates
            .iter()
            .map(|c| signorini_report::OrderingCandidate {
                ordering: c.ordering.as_str().into(),
                factor_nnz: c.nnz as u64,
                flops: c.flops,
            })
            .collect(),
        factorisations: Some(counts.factorisations),
        refinement_steps: Some(counts.refinement_steps),
        lu_fallbacks: Some(counts.lu_fallbacks),
        interface: None,
    }
}

/// The numerical LDLᵀ of `a` (its lower triangle) on `symbolic`, into
/// `l_values`, with faer's default (no) regularisation; `None` when it
/// breaks down.
pub(crate) fn numeric_ldlt<'a>(
    symbolic: &'a SymbolicCholesky<usize>,
    l_values: &'a mut [f64],
    a: SparseColMatRef<'_, usize, f64>,
    par: faer::Par,
    stack: &mut MemStack,
) -> Option<LdltRef<'a, usize, f64>> {
    symbolic
        .factorize_numeric_ldlt::<f64>(
            l_values,
            a,
            faer::Side::Lower,
            LdltRegularization::default(),
            par,
            stack,
            Default::default(),
        )
        .ok()
}

/// Scratch memory for one numerical LDLᵀ of `symbolic` and its solves.
pub(crate) fn ldlt_scratch(symbolic: &SymbolicCholesky<usize>, par: faer::Par) -> MemBuffer {
    MemBuffer::new(StackReq::any_of(&[
        symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
        symbolic.solve_in_place_scratch::<f64>(1, par),
    ]))
}

/// The (row, column) pairs of the KKT pattern, in the order of
/// `KktSystem::matrix`'s values: K's entries column by column; each contact
/// row's entries (i, n+p) and (n+p, i); the m constraint diagonals; when
/// `floating`, K's n diagonals again (for γ).
fn kkt_pairs(
    k: &SparseColMat<usize, f64>,
    rows: &[SparseRow],
    floating: bool,
) -> Vec<Pair<usize, usize>> {
    let n = k.nrows();
    let mut pairs = Vec::with_capacity(k.compute_nnz() + 2 * rows.len() * 8);
    for j in 0..n {
        pairs.extend(k.row_idx_of_col_raw(j).iter().map(|&i| Pair::new(i, j)));
    }
    for (p, row) in rows.iter().enumerate() {
        for &(i, _) in row {
            pairs.push(Pair::new(i, n + p));
            pairs.push(Pair::new(n + p, i));
        }
    }
    pairs.extend((0..rows.len()).map(|p| Pair::new(n + p, n + p)));
    if floating {
        pairs.extend((0..n).map(|i| Pair::new(i, i)));
    }
    pairs
}

/// Normwise backward error of x for M x = b, and the residual b − M x.
fn backward_error(m: &SparseColMat<usize, f64>, x: &[f64], b: &[f64]) -> (f64, Vec<f64>) {
    let (mx, size) = spmv_with_magnitude(m.as_ref(), x);
    let r: Vec<f64> = b.iter().zip(&mx).map(|(bi, mi)| bi - mi).collect();
    let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |a, x| a.max(x.abs()));
    let scale = max(&mut size.iter().copied()) + max(&mut b.iter().copied());
    let err = max(&mut r.iter().copied());
    (if scale > 0.0 { err / scale } else { err }, r)
}

/// x = M̃⁻¹ b refined against M, M̃⁻¹ applied by `solve`; `None` when the
/// backward error does not reach [`ACCEPTED_BACKWARD_ERROR`]. Returns x and
/// the refinement steps.
pub(crate) fn refine(
    exact: &SparseColMat<usize, f64>,
    mut solve: impl FnMut(&[f64]) -> Vec<f64>,
    b: &[f64],
) -> Option<(Vec<f64>, usize)> {
    let mut x = solve(b);
    let (mut berr, mut r) = backward_error(exact, &x, b);
    let mut steps = 0;
    while berr.is_finite() && berr > TARGET_BACKWARD_ERROR && steps < MAX_REFINEMENT_STEPS {
        let d = solve(&r);
        let candidate: Vec<f64> = x.iter().zip(&d).map(|(a, b)| a + b).collect();
        let (e, rr) = backward_error(exact, &candidate, b);
        steps += 1;
        // Stop when a step does not help (also when e is NaN).
        if e.partial_cmp(&berr) != Some(std::cmp::Ordering::Less) {
            break;
        }
        (x, berr, r) = (candidate, e, rr);
    }
    (berr <= ACCEPTED_BACKWARD_ERROR).then_some((x, steps))
}

/// M x = b by sparse LU (the fallback).
fn solve_by_lu(m: &SparseColMat<usize, f64>, b: &[f64]) -> Result<Vec<f64>, ContactError> {
    let lu = m.sp_lu().map_err(|e| {
        ContactError::Singular(format!("sparse LU of the constrained stiffness: {e:?}"))
    })?;
    let rhs = Mat::<f64>::from_fn(b.len(), 1, |i, _| b[i]);
    let x = lu.solve(&rhs);
    Ok((0..b.len()).map(|i| x[(i, 0)]).collect())
}

/// One load step's status problem on the KKT system.
pub struct DirectProblem<'s, 'a> {
    pub system: &'s mut KktSystem<'a>,
    pub f: &'s [f64],
    pub gap0: &'s [f64],
    /// Displacement of the last solve.
    pub u: Vec<f64>,
    pub factorisations: usize,
}

impl<'s, 'a> DirectProblem<'s, 'a> {
    pub fn new(system: &'s mut KktSystem<'a>, f: &'s [f64], gap0: &'s [f64]) -> Self {
        let n = system.k.nrows();
        Self {
            system,
            f,
            gap0,
            u: vec![0.0; n],
            factorisations: 0,
        }
    }
}

impl ActiveSetSolve for DirectProblem<'_, '_> {
    fn n_points(&self) -> usize {
        self.system.rows.len()
    }

    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        let n = self.system.k.nrows();
        let rows = self.system.rows;
        let s = self.system.row_scale;
        let mut is_active = vec![false; rows.len()];
        for &p in active {
            is_active[p] = true;
        }
        let mut b = self.f.to_vec();
        b.extend((0..rows.len()).map(|p| if is_active[p] { -s * self.gap0[p] } else { 0.0 }));
        let x = self.system.solve(&is_active, &b)?;
        self.factorisations += 1;
        if !x.iter().all(|v| v.is_finite()) {
            return Err(ContactError::Singular(
                "the constrained stiffness is singular: a body is free to move in a way that neither its supports nor its active contacts prevent".into(),
            ));
        }
        self.u = x[..n].to_vec();
        let lambda = (0..rows.len())
            .map(|p| if is_active[p] { -s * x[n + p] } else { 0.0 })
            .collect();
        let g = rows
            .iter()
            .zip(self.gap0)
            .map(|(row, g0)| g0 + row.iter().map(|&(i, c)| c * self.u[i]).sum::<f64>())
            .collect();
        Ok((lambda, g))
    }
}
