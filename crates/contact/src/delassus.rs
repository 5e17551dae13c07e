//! The condensed contact problem in the forces alone (docs/theory/contact-problem.md).
//!
//! On the interface Γ: S u = F' + Bᵀ λ, g = g0 + B u. With S factorised once,
//! the Delassus operator W = B S⁻¹ Bᵀ and q = g0 + B S⁻¹ F' give g = W λ + q,
//! and the frictionless problem is LCP(W, q): λ ≥ 0, g ≥ 0, λ·g = 0.
//!
//! Floating bodies (no Dirichlet condition on some rigid motion) make S
//! singular with a known kernel R (the rigid modes of the body, restricted to
//! Γ). As in FETI, u = S⁺(F' + Bᵀλ) + R α and the equilibrium of the rigid
//! modes Rᵀ(F' + Bᵀλ) = 0 becomes the equality constraint Gᵀ λ = e with
//! G = B R and e = −Rᵀ F'; then g = W λ + q + G α. S⁺ is the inverse of
//! S + ρ R Rᵀ (R orthonormal), a generalised inverse of S on its range: no
//! artificial spring enters the answer.

use std::sync::Arc;

use faer::prelude::SolveLstsq;
use faer::Mat;

use crate::active_set::signorini::ActiveSetSolve;
use crate::ContactError;
use signorini_linalg::active_factor::{solve_on_active_set, ActiveFactor};
use signorini_linalg::capacitance::{solve_status_system, StatusFactor};
use signorini_linalg::pivot_policy::{is_rank_deficient, solve_checked, solve_symmetric_checked};
use signorini_linalg::reduced::VarEquation;
use signorini_linalg::sparse::SparseRow;
use signorini_linalg::GeneralisedInverse;

/// The Delassus operator of a run, W = B S⁺ Bᵀ (course notes §3.1.3), with what
/// every load step needs of it: the Cholesky factor of S (S + ρRRᵀ with
/// floating bodies), X = S⁺ Bᵀ, the orthonormal kernel R and G = B R. S, B
/// and R do not change over the steps: it is built once per run (one
/// factorisation and m solves), and each step's [`DelassusProblem`] needs
/// only one more solve, u0 = S⁺ F', for its right-hand side q = g0 + B u0
/// and e = −Rᵀ F' ([`DelassusOperator::problem`]).
pub struct DelassusOperator {
    n: usize,
    schur: Arc<dyn GeneralisedInverse>,
    b: Arc<Vec<SparseRow>>,
    r: Arc<Mat<f64>>,
    w: Mat<f64>,
    g_mat: Mat<f64>,
    s_condition: Option<f64>,
}

pub struct DelassusProblem {
    n: usize,
    /// The factor of S and the rows B, shared with the operator (for the
    /// displacement u = S⁺(F' + Bᵀλ) + Rα; none for a problem given by W).
    schur: Option<Arc<dyn GeneralisedInverse>>,
    b: Arc<Vec<SparseRow>>,
    /// u0 = S⁺ F'.
    u0: Vec<f64>,
    /// Orthonormal kernel basis (n × k), shared with the operator.
    r: Arc<Mat<f64>>,
    pub w: Mat<f64>,
    pub q: Vec<f64>,
    /// G = B R (m × k).
    pub g_mat: Mat<f64>,
    /// e = −Rᵀ F'.
    pub e: Vec<f64>,
    last_alpha: Vec<f64>,
    /// Number of linear solves with W blocks (for the report).
    pub solves: usize,
    /// The Cholesky factor of the last active block (no floating body),
    /// carried to the next status iteration, and by
    /// [`Self::take_factor`] / [`Self::with_factor`] to the next load step
    /// (W is the same). Changing `w` must drop it ([`Self::add_compliance`]).
    factor: Option<ActiveFactor>,
}

impl DelassusOperator {
    /// The operator of the factor `schur` of the interface stiffness S
    /// (a generalised inverse S⁺: S + ρRRᵀ or the fixing DOFs' with
    /// floating bodies), the contact rows `b` (over interface DOFs), the
    /// orthonormal kernel `r` (n × k, k = 0 without floating bodies), W =
    /// B S⁺ Bᵀ formed with that factor, and the condition estimate of the
    /// matrix factorised if made. The condensation builds them
    /// (`signorini_condense::interface::InterfaceOperator`).
    pub fn from_factor(
        schur: Arc<dyn GeneralisedInverse>,
        b: &[SparseRow],
        r: Mat<f64>,
        w: Mat<f64>,
        s_condition: Option<f64>,
    ) -> Self {
        let (n, k) = (r.nrows(), r.ncols());
        let g_mat = Mat::<f64>::from_fn(b.len(), k, |p, j| {
            b[p].iter().map(|&(i, c)| c * r[(i, j)]).sum()
        });
        Self {
            n,
            schur,
            b: Arc::new(b.to_vec()),
            r: Arc::new(r),
            w,
            g_mat,
            s_condition,
        }
    }

    /// Builds W (and G for floating bodies) from the dense interface
    /// stiffness `s`, the contact rows `b` (over interface DOFs) and the
    /// kernel `kernel` (n × k, k = 0 without floating bodies), by the
    /// condensation's factor (for tests).
    #[cfg(test)]
    pub fn new(s: &Mat<f64>, b: &[SparseRow], kernel: &Mat<f64>) -> Result<Self, ContactError> {
        use signorini_condense::interface::{InterfaceOperator, InterfaceStiffness};
        let op = InterfaceOperator::new(InterfaceStiffness::Dense(s.clone()), b, kernel, false)?;
        Ok(Self::from_factor(
            Arc::new(op.factor),
            b,
            op.r,
            op.w,
            op.s_condition,
        ))
    }

    /// The estimated κ₁ of S (S + ρRRᵀ with floating bodies) when the
    /// factor's builder made it, else `None`.
    pub fn s_condition(&self) -> Option<f64> {
        self.s_condition
    }

    /// W = B S⁺ Bᵀ.
    pub fn w(&self) -> &Mat<f64> {
        &self.w
    }

    /// The number of rigid modes of the floating bodies.
    pub fn n_kernel(&self) -> usize {
        self.r.ncols()
    }

    /// The problem of one load step: q = g0 + B S⁺ F' and e = −Rᵀ F' for the
    /// initial gaps `gap0` and the condensed load `f` (one solve with the
    /// factor of S).
    pub fn problem(&self, gap0: &[f64], f: &[f64]) -> DelassusProblem {
        let (n, k) = (self.n, self.n_kernel());
        let u0 = self.schur.solve(f);
        let q: Vec<f64> = self
            .b
            .iter()
            .zip(gap0)
            .map(|(row, g0)| g0 + row.iter().map(|&(i, c)| c * u0[i]).sum::<f64>())
            .collect();
        let e: Vec<f64> = (0..k)
            .map(|j| -(0..n).map(|i| self.r[(i, j)] * f[i]).sum::<f64>())
            .collect();
        DelassusProblem {
            n,
            schur: Some(Arc::clone(&self.schur)),
            b: Arc::clone(&self.b),
            u0,
            r: Arc::clone(&self.r),
            w: self.w.clone(),
            q,
            g_mat: self.g_mat.clone(),
            e,
            last_alpha: vec![0.0; k],
            solves: 0,
            factor: None,
        }
    }
}

impl DelassusProblem {
    /// The problem of one step built from scratch: [`DelassusOperator::new`]
    /// then [`DelassusOperator::problem`] (for a single solve in tests; a
    /// run builds the operator once).
    #[cfg(test)]
    pub fn new(
        s: &Mat<f64>,
        b: &[SparseRow],
        gap0: &[f64],
        f: &[f64],
        kernel: &Mat<f64>,
    ) -> Result<Self, ContactError> {
        Ok(DelassusOperator::new(s, b, kernel)?.problem(gap0, f))
    }

    /// A problem given directly by its Delassus operator W and gaps q (for
    /// stand-alone local problems): no interface displacement behind it.
    pub fn from_operator(w: Mat<f64>, q: Vec<f64>) -> Self {
        let m = q.len();
        Self {
            n: 0,
            schur: None,
            b: Arc::new(Vec::new()),
            u0: Vec::new(),
            r: Arc::new(Mat::zeros(0, 0)),
            g_mat: Mat::zeros(m, 0),
            e: Vec::new(),
            w,
            q,
            last_alpha: Vec::new(),
            solves: 0,
            factor: None,
        }
    }

    pub fn n_kernel(&self) -> usize {
        self.r.ncols()
    }

    /// The factor of the last active block, for the next load step's
    /// problem of the same operator ([`Self::with_factor`]).
    pub fn take_factor(&mut self) -> Option<ActiveFactor> {
        self.factor.take()
    }

    /// Starts from the factor of an earlier problem of the same operator
    /// (same W): the status method then updates it instead of factorising.
    pub fn with_factor(mut self, factor: Option<ActiveFactor>) -> Self {
        self.factor = factor.filter(|f| f.rows().iter().all(|&r| r < self.q.len()));
        self
    }

    /// Interface displacement u = S⁺(F' + Bᵀλ) + R α for forces λ (and the α
    /// of the last solve).
    pub fn displacement(&self, lambda: &[f64]) -> Vec<f64> {
        let mut u = self.u0.clone();
        if let Some(schur) = &self.schur {
            let mut bt_lambda = vec![0.0; self.n];
            for (row, &l) in self.b.iter().zip(lambda) {
                for &(i, c) in row {
                    bt_lambda[i] += c * l;
                }
            }
            for (ui, d) in u.iter_mut().zip(schur.solve(&bt_lambda)) {
                *ui += d;
            }
        }
        for (j, &a) in self.last_alpha.iter().enumerate() {
            for (i, ui) in u.iter_mut().enumerate().take(self.n) {
                *ui += self.r[(i, j)] * a;
            }
        }
        u
    }

    /// Adds a compliance to the diagonal of W (per row): the elastic slip of
    /// a regularised friction law (course notes §4.1.3), 1/k_e on tangential rows.
    pub fn add_compliance(&mut self, diag: &[f64]) {
        self.factor = None;
        for (i, &c) in diag.iter().enumerate() {
            self.w[(i, i)] += c;
        }
    }

    /// Solves for the forces r with one equation per force (a zero gap, a
    /// given value, or a multiple of another force: a slipping point's
    /// tangential force ±μ λ_n) and, for floating bodies, the equilibrium of
    /// their rigid modes Gᵀ r = e. Returns (r, W r + q + G α).
    pub fn solve_equations(
        &mut self,
        eqs: &[VarEquation],
    ) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        self.solves += 1;
        if let Some((r, alpha)) =
            signorini_linalg::reduced::solve_reduced(&self.w, &self.q, &self.g_mat, &self.e, eqs)
        {
            let g = crate::lcp::constrained_gaps(&self.w, &self.q, &self.g_mat, &r, &alpha);
            self.last_alpha = alpha;
            return Ok((r, g));
        }
        let m = self.q.len();
        let k = self.r.ncols();
        let dim = m + k;
        let mut a = Mat::<f64>::zeros(dim, dim);
        let mut rhs = Mat::<f64>::zeros(dim, 1);
        for (i, eq) in eqs.iter().enumerate() {
            match *eq {
                VarEquation::Gap => {
                    for j in 0..m {
                        a[(i, j)] = self.w[(i, j)];
                    }
                    for j in 0..k {
                        a[(i, m + j)] = self.g_mat[(i, j)];
                    }
                    rhs[(i, 0)] = -self.q[i];
                }
                VarEquation::Value(c) => {
                    a[(i, i)] = 1.0;
                    rhs[(i, 0)] = c;
                }
                VarEquation::Ratio { of, factor } => {
                    a[(i, i)] = 1.0;
                    a[(i, of)] = -factor;
                }
            }
        }
        for j in 0..k {
            for i in 0..m {
                a[(m + j, i)] = self.g_mat[(i, j)];
            }
            rhs[(m + j, 0)] = self.e[j];
        }
        let sol = solve_checked(&a, &rhs, "the contact and friction statuses do not hold a floating body, or the constraints are redundant")?;
        let r: Vec<f64> = (0..m).map(|i| sol[(i, 0)]).collect();
        let alpha: Vec<f64> = (0..k).map(|j| sol[(m + j, 0)]).collect();
        let g = crate::lcp::constrained_gaps(&self.w, &self.q, &self.g_mat, &r, &alpha);
        self.last_alpha = alpha;
        Ok((r, g))
    }

    /// As [`Self::solve_equations`], with the factor of an earlier status
    /// iteration's system carried in `factor` and updated by the
    /// capacitance formula when few equations changed
    /// ([`signorini_linalg::capacitance`]; without floating bodies).
    pub(crate) fn solve_equations_updating(
        &mut self,
        eqs: &[VarEquation],
        factor: &mut Option<StatusFactor>,
    ) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        if self.r.ncols() == 0 {
            if let Some(out) = solve_status_system(factor, &self.w, &self.q, eqs) {
                self.solves += 1;
                return Ok(out);
            }
        }
        self.solve_equations(eqs)
    }

    /// The orthonormal basis R (n × k) of the floating bodies' modes.
    pub(crate) fn kernel_basis(&self) -> &Mat<f64> {
        &self.r
    }

    /// Replaces the modes' basis (n × k') by combinations of it, α reset to
    /// zero: a transformed problem that eliminated some modes, or its
    /// return to all of them before [`Self::displacement`].
    pub(crate) fn set_kernel_basis(&mut self, r: Mat<f64>) {
        self.last_alpha = vec![0.0; r.ncols()];
        self.r = Arc::new(r);
        self.factor = None;
    }

    /// The rigid-mode amplitudes α of the last solve.
    pub fn alpha(&self) -> &[f64] {
        &self.last_alpha
    }

    /// Sets α from a solver that found it itself (the multiplier of the
    /// equality in [`crate::lcp::smalbe`]), for [`Self::displacement`].
    pub fn set_alpha(&mut self, alpha: &[f64]) {
        assert_eq!(alpha.len(), self.r.ncols());
        self.last_alpha = alpha.to_vec();
    }

    /// Sets α from the gaps y = W λ + q + G α of the forces λ that a solver
    /// computed with its own α (the semi-smooth Newton method, whose
    /// unknowns hold it): the least-squares solution of G α = y − W λ − q,
    /// exact when G has full column rank, so that [`Self::displacement`]
    /// gives back the gaps the solver met its tolerance on. Whether α was
    /// set (not when it comes out non-finite: α is then left as it was).
    pub fn set_alpha_from_gaps(&mut self, lambda: &[f64], gaps: &[f64]) -> bool {
        let k = self.g_mat.ncols();
        if k == 0 || gaps.len() != self.q.len() {
            return k == 0;
        }
        let elastic = crate::lcp::gaps(&self.w, &self.q, lambda);
        let rigid = Mat::<f64>::from_fn(gaps.len(), 1, |i, _| gaps[i] - elastic[i]);
        let alpha = self.g_mat.qr().solve_lstsq(&rigid);
        let alpha: Vec<f64> = (0..k).map(|j| alpha[(j, 0)]).collect();
        let finite = alpha.iter().all(|a| a.is_finite());
        if finite {
            self.last_alpha = alpha;
        }
        finite
    }
}

impl ActiveSetSolve for DelassusProblem {
    fn n_points(&self) -> usize {
        self.q.len()
    }

    /// Lemke's method on LCP(W, q), with the equilibrium of the floating
    /// bodies' rigid modes when there are any.
    fn pivoted_active_set(
        &mut self,
        opts: &crate::lcp::LcpOptions,
    ) -> Result<Option<Vec<usize>>, ContactError> {
        crate::lcp::lemke::pivoted_active_set(&self.w, &self.q, (&self.g_mat, &self.e), opts)
    }

    /// Solves W_AA λ_A = −q_A (no floating body) or the saddle-point system
    /// [W_AA G_A; G_Aᵀ 0][λ_A; α] = [−q_A; e].
    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        self.solves += 1;
        let m = self.q.len();
        let k = self.r.ncols();
        let na = active.len();
        if k == 0 {
            if let Some(lambda) = solve_on_active_set(&mut self.factor, &self.w, &self.q, active) {
                let g = crate::lcp::gaps(&self.w, &self.q, &lambda);
                return Ok((lambda, g));
            }
        }
        let mut eqs = vec![VarEquation::Value(0.0); m];
        for &p in active {
            eqs[p] = VarEquation::Gap;
        }
        if let Some((lambda, alpha)) =
            signorini_linalg::reduced::solve_reduced(&self.w, &self.q, &self.g_mat, &self.e, &eqs)
        {
            let g = crate::lcp::constrained_gaps(&self.w, &self.q, &self.g_mat, &lambda, &alpha);
            self.last_alpha = alpha;
            return Ok((lambda, g));
        }
        let mut lambda = vec![0.0; m];
        let mut alpha = vec![0.0; k];
        if na + k > 0 {
            let (a, rhs) =
                crate::lcp::saddle_point_system(&self.w, &self.q, &self.g_mat, &self.e, active);
            let sol = if k == 0 {
                solve_symmetric_checked(&a, &rhs, "W_AA (redundant contact constraints?)")?
            } else {
                solve_checked(&a, &rhs, "the active contacts do not hold a floating body").map_err(
                    |e| {
                        // Tell redundant constraints (W_AA itself singular)
                        // from contacts that cannot hold a rigid motion.
                        let waa = a.submatrix(0, 0, na, na).to_owned();
                        if is_rank_deficient(&waa) {
                            ContactError::Singular(
                                "W_AA is singular: the active contact constraints are linearly dependent (redundant constraints)".into(),
                            )
                        } else {
                            e.into()
                        }
                    },
                )?
            };
            for (ii, &p) in active.iter().enumerate() {
                lambda[p] = sol[(ii, 0)];
            }
            for j in 0..k {
                alpha[j] = sol[(na + j, 0)];
            }
        }
        let g = crate::lcp::constrained_gaps(&self.w, &self.q, &self.g_mat, &lambda, &alpha);
        self.last_alpha = alpha;
        Ok((lambda, g))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One operator serves every load: each step's problem equals the one
    /// built from scratch for that load (W, q, G, e and the displacement).
    #[test]
    fn one_operator_gives_each_steps_problem() {
        let n = 4;
        let s = Mat::<f64>::from_fn(n, n, |i, j| {
            if i == j {
                4.0 + i as f64
            } else if i.abs_diff(j) == 1 {
                -1.0
            } else {
                0.0
            }
        });
        let rows: Vec<SparseRow> = vec![vec![(0, 1.0)], vec![(2, 1.0), (3, -0.5)]];
        let kernel = Mat::<f64>::zeros(n, 0);
        let op = DelassusOperator::new(&s, &rows, &kernel).unwrap();
        for (gap0, f) in [
            ([0.1, 0.0], [1.0, -2.0, 0.5, 0.0]),
            ([0.0, 0.3], [0.0, 0.0, -3.0, 1.0]),
        ] {
            let a = op.problem(&gap0, &f);
            let b = DelassusProblem::new(&s, &rows, &gap0, &f, &kernel).unwrap();
            let scale = a.w.norm_max();
            assert!((&a.w - &b.w).norm_max() <= 1e-14 * scale);
            for (x, y) in a.q.iter().zip(&b.q) {
                assert!((x - y).abs() <= 1e-14 * (1.0 + y.abs()), "{x} {y}");
            }
            let (ua, ub) = (a.displacement(&[1.0, 2.0]), b.displacement(&[1.0, 2.0]));
            for (x, y) in ua.iter().zip(&ub) {
                assert!((x - y).abs() <= 1e-14 * (1.0 + y.abs()));
            }
        }
    }
}
