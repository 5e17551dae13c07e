//! MPRGP, modified proportioning with reduced gradient projection
//! (Z. Dostál, *Optimal Quadratic Programming Algorithms*, Springer 2009,
//! ch. 8 — minimisation with simple bounds; Dostál & Schöberl, Comput. Optim.
//! Appl. 30, 2005), on the box-constrained quadratic programme
//!
//! ```text
//! min f(x) = ½ xᵀ W x + qᵀ x   subject to   l ≤ x ≤ u,     g = ∇f = W x + q,
//! ```
//!
//! with l_i ∈ [−∞, ∞), u_i ∈ (−∞, ∞], l_i ≤ u_i (l_i = u_i fixes x_i) and W
//! symmetric positive semi-definite. The projection methods of the course notes
//! (§3.2) work on the forces because their bounds are simple there; two
//! problems of the contact solver have this form:
//!
//! - the frictionless LCP(W, q) of docs/theory/contact-problem.md is the box (0, ∞): x = λ the
//!   contact forces, g = w the gaps ([`crate::lcp::mprgp`], the LCP method);
//! - Tresca friction, normal forces λ_n ≥ 0 and tangential forces
//!   −s ≤ λ_t ≤ s with the Tresca threshold s ([`mprgp_box`], called by
//!   [`crate::friction::tresca_projection`]).
//!
//! With the free set F = {i : l_i < x_i < u_i} and P the projection onto the
//! box:
//!
//! - free gradient         φ_i = g_i on F, 0 elsewhere;
//! - chopped gradient      β_i = min(g_i, 0) where x_i = l_i < u_i,
//!   max(g_i, 0) where x_i = u_i > l_i, 0 elsewhere (the components at a
//!   bound whose descent direction points into the box);
//! - reduced free gradient φ̃ = (x − P(x − ᾱ φ)) / ᾱ, i.e.
//!   φ̃_i = min((x_i − l_i)/ᾱ, φ_i) for φ_i > 0 and max((x_i − u_i)/ᾱ, φ_i)
//!   for φ_i < 0 on F, 0 elsewhere;
//! - projected gradient    gᴾ = φ + β (zero exactly at the solution).
//!
//! x is *proportional* when ‖β‖² ≤ Γ² φ̃ᵀφ (Γ = 1). Each iteration is one of
//!
//! - **CG step** (proportional, α_cg = gᵀp / pᵀWp ≤ α_f, the longest step with
//!   l ≤ x − α p ≤ u): x ← x − α_cg p, g ← g − α_cg W p, p ← φ − γ p with
//!   γ = φᵀW p / pᵀW p (CG on the free set);
//! - **expansion step** (proportional, α_cg > α_f): the feasible half step
//!   x½ = x − α_f p, then x ← P(x½ − ᾱ φ(x½)) with the fixed step
//!   ᾱ = 1.9/‖W‖ ∈ (0, 2/‖W‖] (‖W‖ by power iterations, enlarged by 1 %),
//!   g ← W x + q, p ← φ;
//! - **proportioning step** (not proportional): x ← x − α β with the exact
//!   minimiser α = gᵀβ / βᵀWβ = βᵀβ / βᵀWβ along the chopped gradient, cut
//!   at the opposite bound when it would cross it (for λ ≥ 0 it releases the
//!   points at zero force with a negative gap), p ← φ.
//!
//! For W SPD MPRGP converges R-linearly, at a rate given by the spectrum of W
//! only (Dostál 2009, Thm 8.1), and identifies the active set in a finite
//! number of steps.
//!
//! The start is the projection of the warm start x0 (of 0 without one); if
//! it already meets the tolerance no iteration is made. Stopping: the
//! projected-gradient residual [`box_residual`] ≤ `opts.tolerance`, checked
//! with the exact gradient (for λ ≥ 0 it is the natural residual
//! [`crate::lcp_residual`], bit for bit). The general box iterate is then
//! *polished*: the variables at a bound are fixed, W_FF x_F = −q_F − W_FB x_B
//! is solved (Cholesky, else full-pivoting LU) and the result is kept only if
//! it stays in the box and its residual is no larger. The LCP entry points
//! leave polishing to their callers ([`crate::registry`], [`crate::lcp::smalbe`]).
//!
//! W may be positive semi-definite (redundant constraints); when f is
//! unbounded below along a feasible direction (zero curvature, no bound in
//! the way) the method returns [`ContactError::Singular`].

use faer::Mat;

use crate::lcp::{
    check_finite, dot, gaps, gaps_into, matvec, spectral_norm_estimate, time_limit_stop, LcpOptions,
};
use crate::solution::{BoxPolish, ContactSolution, Measure, MprgpSteps, SolverReport, StopReason};
use crate::ContactError;

/// Γ of the proportioning test ‖β‖² ≤ Γ² φ̃ᵀφ.
const GAMMA: f64 = 1.0;

/// ᾱ = STEP_FACTOR / ‖W‖, inside (0, 2/‖W‖].
const STEP_FACTOR: f64 = 1.9;

/// Curvatures pᵀWp ≤ FLAT · ‖W‖ · pᵀp count as zero.
const FLAT: f64 = 1e-14;

/// How an entry point names the method and its residual in the report, and
/// whether a converged iterate is polished.
#[derive(Clone, Copy)]
pub(crate) struct Flavour {
    pub method: &'static str,
    pub residual: Measure,
    pub polish: bool,
}

/// A general box (Tresca friction).
const BOX: Flavour = Flavour {
    method: "mprgp_box",
    residual: Measure::ProjectedGradient,
    polish: true,
};

/// MPRGP on min ½ xᵀ A x + bᵀ x subject to l ≤ x ≤ u (see the module
/// documentation), from the projection of 0 onto the box. `lower[i]` may be
/// −∞, `upper[i]` may be +∞; `lower[i] = upper[i]` fixes x_i.
///
/// The solution is returned in `ContactSolution::forces` (its `gaps` are
/// the gradient A x + b). `report.iterations`
/// counts CG, expansion and proportioning steps; `operator_applications` the
/// products A·v (power iterations for ‖A‖ included) and the polishing solve;
/// `residual_history` holds [`box_residual`] after each step, its last entry
/// being the residual of the returned x.
///
/// Errors: [`ContactError::Solve`] for inconsistent sizes, a non-finite
/// entry of A or b, a NaN bound, l_i = +∞, u_i = −∞ or l_i > u_i (the message
/// names the index); [`ContactError::Singular`] when the objective is
/// unbounded below on the box. Reaching `opts.max_iterations` is not an
/// error: `report.converged` is then false and the stopping reason says so.
pub fn mprgp_box(
    a: &Mat<f64>,
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    mprgp_box_from(a, b, lower, upper, &vec![0.0; b.len()], opts)
}

/// [`mprgp_box`] from a warm start x0, projected onto the box. An x0 of the
/// wrong length or with a non-finite entry is an error.
pub fn mprgp_box_from(
    a: &Mat<f64>,
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
    x0: &[f64],
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    check_box_input(a, b, lower, upper)?;
    check_start(x0, b.len(), BOX.method)?;
    if b.is_empty() {
        return Ok(ContactSolution::empty(BOX.method));
    }
    minimise(a, b, (lower, upper), x0, opts, BOX)
}

/// MPRGP from x0 on the box (`lower`, `upper`) of checked data, the report
/// and polishing as `flavour` says.
pub(crate) fn minimise(
    a: &Mat<f64>,
    b: &[f64],
    (lower, upper): (&[f64], &[f64]),
    x0: &[f64],
    opts: &LcpOptions,
    flavour: Flavour,
) -> Result<ContactSolution, ContactError> {
    Mprgp::new(a, b, Bounds { lower, upper }, x0, opts, flavour).solve()
}

/// The projected-gradient residual of the box QP at x,
///
/// ```text
/// max_i | min((x_i − l_i)/F, max((x_i − u_i)/F, g_i/L)) |,   g = A x + b,
/// ```
///
/// i.e. |x − P(x − g)| (P the projection onto the box) with the forces
/// scaled by F = max(force_scale, ‖x‖∞) and the gradients by L = gap_scale
/// (as [`crate::lcp_residual`], which it equals bit for bit when l = 0 and
/// u = +∞). Zero exactly when x solves the QP; positive at any other x, in
/// particular outside the box. Non-finite data give +∞.
///
/// # Panics
/// When the sizes of A, b, x, l and u disagree.
pub fn box_residual(
    a: &Mat<f64>,
    b: &[f64],
    x: &[f64],
    lower: &[f64],
    upper: &[f64],
    opts: &LcpOptions,
) -> f64 {
    let n = b.len();
    assert!(
        a.nrows() == n && a.ncols() == n && x.len() == n && lower.len() == n && upper.len() == n,
        "box_residual: A is {}×{}, b, x, l, u have {n}, {}, {}, {} entries",
        a.nrows(),
        a.ncols(),
        x.len(),
        lower.len(),
        upper.len()
    );
    let g = gaps(a, b, x);
    Bounds { lower, upper }.residual(x, &g, opts)
}

/// The box l ≤ x ≤ u.
#[derive(Clone, Copy)]
struct Bounds<'a> {
    lower: &'a [f64],
    upper: &'a [f64],
}

impl Bounds<'_> {
    /// The projection of v onto the interval of variable i.
    fn project(&self, i: usize, v: f64) -> f64 {
        v.max(self.lower[i]).min(self.upper[i])
    }

    fn is_free(&self, i: usize, x: f64) -> bool {
        self.lower[i] < x && x < self.upper[i]
    }

    /// The bound that a step x − α d reaches on variable i (d_i ≠ 0).
    fn reached(&self, i: usize, d: f64) -> f64 {
        if d > 0.0 {
            self.lower[i]
        } else {
            self.upper[i]
        }
    }

    /// [`box_residual`] from a known gradient g = W x + q.
    fn residual(&self, x: &[f64], g: &[f64], opts: &LcpOptions) -> f64 {
        let f = opts
            .force_scale
            .max(x.iter().fold(0.0f64, |m, v| m.max(v.abs())))
            .max(f64::MIN_POSITIVE);
        let l = opts.gap_scale.max(f64::MIN_POSITIVE);
        let mut worst = 0.0f64;
        for i in 0..x.len() {
            let r = ((x[i] - self.lower[i]) / f)
                .min(((x[i] - self.upper[i]) / f).max(g[i] / l))
                .abs();
            if !r.is_finite() || !x[i].is_finite() || !g[i].is_finite() {
                return f64::INFINITY;
            }
            worst = worst.max(r);
        }
        worst
    }

    /// φ(x): g on the free set, 0 elsewhere.
    fn free_gradient(&self, x: &[f64], g: &[f64]) -> Vec<f64> {
        (0..x.len())
            .map(|i| if self.is_free(i, x[i]) { g[i] } else { 0.0 })
            .collect()
    }

    /// β(x): the components of g at a bound whose descent direction −g points
    /// into the box, 0 elsewhere (and 0 for the fixed variables l = u).
    fn chopped_gradient(&self, x: &[f64], g: &[f64]) -> Vec<f64> {
        let (lower, upper) = (self.lower, self.upper);
        (0..x.len())
            .map(|i| {
                if lower[i] == upper[i] {
                    0.0
                } else if x[i] == lower[i] {
                    g[i].min(0.0)
                } else if x[i] == upper[i] {
                    g[i].max(0.0)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// φ̃ᵀφ with φ̃_i = (x_i − P(x_i − ᾱ φ_i)) / ᾱ on the free set.
    fn reduced_dot(&self, x: &[f64], phi: &[f64], abar: f64) -> f64 {
        (0..x.len())
            .filter(|&i| phi[i] != 0.0)
            .map(|i| {
                let reduced = if phi[i] > 0.0 {
                    ((x[i] - self.lower[i]) / abar).min(phi[i])
                } else {
                    ((x[i] - self.upper[i]) / abar).max(phi[i])
                };
                reduced * phi[i]
            })
            .sum()
    }

    /// α_f = max{α : l ≤ x − α d ≤ u} and the variable that blocks it
    /// (smallest index on ties); (∞, None) when no bound is in the way.
    fn feasible_step(&self, x: &[f64], d: &[f64]) -> (f64, Option<usize>) {
        let mut best = (f64::INFINITY, None);
        for i in 0..x.len() {
            let step = if d[i] > 0.0 {
                (x[i] - self.lower[i]) / d[i]
            } else if d[i] < 0.0 {
                (self.upper[i] - x[i]) / -d[i]
            } else {
                continue;
            };
            if step.is_finite() && step.max(0.0) < best.0 {
                best = (step.max(0.0), Some(i));
            }
        }
        best
    }
}

/// What one iteration did.
enum Step {
    Taken,
    /// No descent direction left (round-off floor).
    Stagnated,
}

/// The state of one MPRGP run.
struct Mprgp<'a> {
    w: &'a Mat<f64>,
    q: &'a [f64],
    bounds: Bounds<'a>,
    opts: &'a LcpOptions,
    flavour: Flavour,
    /// The iterate and its gradient g = W x + q (updated recursively).
    x: Vec<f64>,
    g: Vec<f64>,
    /// The search direction and W p.
    p: Vec<f64>,
    wp: Vec<f64>,
    /// ‖W‖ and the fixed step ᾱ = 1.9/‖W‖.
    norm_w: f64,
    abar: f64,
    steps: MprgpSteps,
    report: SolverReport,
}

impl<'a> Mprgp<'a> {
    /// x = P(x0), g = W x + q (a product only when x ≠ 0).
    fn new(
        w: &'a Mat<f64>,
        q: &'a [f64],
        bounds: Bounds<'a>,
        x0: &[f64],
        opts: &'a LcpOptions,
        flavour: Flavour,
    ) -> Self {
        let x: Vec<f64> = (0..q.len()).map(|i| bounds.project(i, x0[i])).collect();
        let g = gaps(w, q, &x);
        let report = SolverReport {
            method: flavour.method.into(),
            operator_applications: usize::from(x.iter().any(|&v| v != 0.0)),
            ..Default::default()
        };
        Self {
            w,
            q,
            bounds,
            opts,
            flavour,
            x,
            g,
            p: Vec::new(),
            wp: vec![0.0; q.len()],
            norm_w: 0.0,
            abar: 0.0,
            steps: MprgpSteps::default(),
            report,
        }
    }

    fn residual(&self) -> f64 {
        self.bounds.residual(&self.x, &self.g, self.opts)
    }

    fn free_gradient(&self) -> Vec<f64> {
        self.bounds.free_gradient(&self.x, &self.g)
    }

    /// Iterates until the tolerance, the iteration limit or stagnation.
    fn solve(mut self) -> Result<ContactSolution, ContactError> {
        let res0 = self.residual();
        if res0 <= self.opts.tolerance {
            return Ok(self.solved_at_start(res0));
        }
        if self.w.norm_max() == 0.0 {
            return self.solve_linear();
        }
        let (norm_w, power_products) = spectral_norm_estimate(self.w);
        self.report.operator_applications += power_products;
        self.norm_w = norm_w;
        self.abar = STEP_FACTOR / norm_w;
        self.p = self.free_gradient();
        loop {
            let res = self.residual();
            if res <= self.opts.tolerance {
                if self.converged_on_exact_gradient() {
                    break;
                }
                continue;
            }
            if self.report.iterations >= self.opts.max_iterations {
                self.report.stop = StopReason::IterationLimit {
                    limit: self.opts.max_iterations,
                    measure: self.flavour.residual,
                    residual: res,
                    tolerance: self.opts.tolerance,
                    steps: Some(self.steps),
                };
                break;
            }
            if self.opts.out_of_time(self.report.iterations) {
                self.report.stop = time_limit_stop(&self.report, res);
                break;
            }
            self.report.iterations += 1;
            if let Step::Stagnated = self.step()? {
                self.report.stop = StopReason::Stagnation {
                    iteration: self.report.iterations,
                    measure: self.flavour.residual,
                    residual: res,
                    tolerance: self.opts.tolerance,
                };
                break;
            }
            if !self.x.iter().chain(&self.g).all(|v| v.is_finite()) {
                // Runaway iterates (curvature just above the flatness
                // threshold along an unbounded direction): never return a NaN.
                return Err(self.unbounded());
            }
            let res = self.residual();
            self.report.residual_history.push(res);
        }
        Ok(self.finish())
    }

    /// The start meets the tolerance: no iteration (and no ‖W‖).
    fn solved_at_start(mut self, res0: f64) -> ContactSolution {
        let (res, polish) = self.polish_if_asked(res0);
        self.report.residual_history.push(res);
        self.report.converged = true;
        self.report.stop = StopReason::StartMeetsTolerance {
            measure: self.flavour.residual,
            residual: res,
            tolerance: self.opts.tolerance,
            polish,
        };
        self.finish()
    }

    /// The answer: the iterate with its exact gradient W x + q as gaps.
    fn finish(self) -> ContactSolution {
        ContactSolution::from_forces(self.w, self.q, self.x, self.report)
    }

    /// At a recursive residual ≤ tolerance: recomputes g exactly (the
    /// recursive one may drift) and, if the residual still meets the
    /// tolerance, polishes and reports convergence; otherwise iterations go
    /// on from the exact gradient.
    fn converged_on_exact_gradient(&mut self) -> bool {
        gaps_into(self.w, self.q, &self.x, &mut self.g);
        self.report.operator_applications += 1;
        let exact = self.residual();
        if exact > self.opts.tolerance {
            set_last(&mut self.report, exact);
            self.p = self.free_gradient();
            return false;
        }
        let (res, polish) = self.polish_if_asked(exact);
        set_last(&mut self.report, res);
        self.report.converged = true;
        self.report.stop = StopReason::MprgpConverged {
            measure: self.flavour.residual,
            residual: res,
            tolerance: self.opts.tolerance,
            iterations: self.report.iterations,
            steps: self.steps,
            norm_w: self.norm_w,
            polish,
        };
        true
    }

    /// One CG, expansion or proportioning step.
    fn step(&mut self) -> Result<Step, ContactError> {
        let phi = self.free_gradient();
        let beta = self.bounds.chopped_gradient(&self.x, &self.g);
        let beta_sq = dot(&beta, &beta);
        if beta_sq <= GAMMA * GAMMA * self.bounds.reduced_dot(&self.x, &phi, self.abar) {
            self.proportional_step(phi)
        } else {
            self.proportioning_step(&beta, beta_sq)?;
            Ok(Step::Taken)
        }
    }

    /// x is proportional: a CG step if it stays in the box, else an
    /// expansion step.
    fn proportional_step(&mut self, phi: Vec<f64>) -> Result<Step, ContactError> {
        if dot(&self.g, &self.p) <= 0.0 {
            // p lost the descent property (round-off): restart along φ.
            self.p = phi;
            if dot(&self.p, &self.p) == 0.0 {
                return Ok(Step::Stagnated);
            }
        }
        matvec(self.w, &self.p, &mut self.wp);
        self.report.operator_applications += 1;
        let curv = dot(&self.p, &self.wp);
        let flat = curv <= FLAT * self.norm_w * dot(&self.p, &self.p);
        let (alpha_f, block) = self.bounds.feasible_step(&self.x, &self.p);
        if flat && block.is_none() {
            return Err(self.unbounded());
        }
        let alpha_cg = if flat {
            f64::INFINITY
        } else {
            dot(&self.g, &self.p) / curv
        };
        if alpha_cg <= alpha_f {
            self.cg_step(alpha_cg, curv);
        } else {
            self.expansion_step(alpha_f, block);
        }
        Ok(Step::Taken)
    }

    fn cg_step(&mut self, alpha: f64, curv: f64) {
        self.steps.cg += 1;
        let p = std::mem::take(&mut self.p);
        self.advance(alpha, &p, None);
        let phi = self.free_gradient();
        let gamma = dot(&phi, &self.wp) / curv;
        self.p = phi.iter().zip(&p).map(|(f, d)| f - gamma * d).collect();
    }

    /// The feasible half step to the blocking bound, then the fixed-step
    /// projection x ← P(x − ᾱ φ).
    fn expansion_step(&mut self, alpha_f: f64, block: Option<usize>) {
        self.steps.expansion += 1;
        let p = std::mem::take(&mut self.p);
        self.advance(alpha_f, &p, block);
        let phi = self.free_gradient();
        for (i, f) in phi.iter().enumerate() {
            self.x[i] = self.bounds.project(i, self.x[i] - self.abar * f);
        }
        gaps_into(self.w, self.q, &self.x, &mut self.g);
        self.report.operator_applications += 1;
        self.p = self.free_gradient();
    }

    /// Exact minimisation along −β (into the box), cut at the opposite bound.
    fn proportioning_step(&mut self, beta: &[f64], beta_sq: f64) -> Result<(), ContactError> {
        self.steps.proportioning += 1;
        matvec(self.w, beta, &mut self.wp);
        self.report.operator_applications += 1;
        let curv = dot(beta, &self.wp);
        let flat = curv <= FLAT * self.norm_w * beta_sq;
        let (alpha_f, block) = self.bounds.feasible_step(&self.x, beta);
        if flat && block.is_none() {
            return Err(self.unbounded());
        }
        let alpha_cg = if flat { f64::INFINITY } else { beta_sq / curv };
        let cut = alpha_cg >= alpha_f;
        self.advance(alpha_cg.min(alpha_f), beta, block.filter(|_| cut));
        self.p = self.free_gradient();
        Ok(())
    }

    /// x ← P(x − α d), g ← g − α W d (W d in `wp`); the blocking variable,
    /// if any, lands exactly on its bound.
    fn advance(&mut self, alpha: f64, d: &[f64], block: Option<usize>) {
        for (i, (&di, &wdi)) in d.iter().zip(&self.wp).enumerate() {
            self.x[i] = self.bounds.project(i, self.x[i] - alpha * di);
            self.g[i] -= alpha * wdi;
        }
        if let Some(k) = block {
            self.x[k] = self.bounds.reached(k, d[k]);
        }
    }

    /// W = 0: f(x) = qᵀx is minimised variable by variable at the bound that
    /// q_i points away from (x_i unchanged where q_i = 0); unbounded when
    /// that bound is infinite.
    fn solve_linear(mut self) -> Result<ContactSolution, ContactError> {
        for i in 0..self.q.len() {
            if self.q[i] != 0.0 {
                self.x[i] = self.bounds.reached(i, self.q[i]);
            }
            if !self.x[i].is_finite() {
                return Err(self.unbounded());
            }
        }
        let res = self.bounds.residual(&self.x, self.q, self.opts);
        self.report.residual_history.push(res);
        self.report.converged = res <= self.opts.tolerance;
        self.report.stop = StopReason::LinearObjective { residual: res };
        Ok(self.finish())
    }

    fn polish_if_asked(&mut self, res: f64) -> (f64, BoxPolish) {
        if self.flavour.polish {
            self.polish(res)
        } else {
            (res, BoxPolish::NotTried)
        }
    }

    /// Active-set polishing of a converged iterate (see the module
    /// documentation). Replaces x when the polished point is in the box with
    /// a residual ≤ `res`; returns the residual of the kept x and a note for
    /// the stopping reason.
    fn polish(&mut self, res: f64) -> (f64, BoxPolish) {
        let (w, q, n) = (self.w, self.q, self.x.len());
        let free: Vec<usize> = (0..n)
            .filter(|&i| self.bounds.is_free(i, self.x[i]))
            .collect();
        if free.is_empty() || res == 0.0 {
            return (res, BoxPolish::NotTried);
        }
        let mut fixed = vec![true; n];
        for &i in &free {
            fixed[i] = false;
        }
        let nf = free.len();
        let wff = Mat::<f64>::from_fn(nf, nf, |r, c| w[(free[r], free[c])]);
        let rhs = Mat::<f64>::from_fn(nf, 1, |r, _| {
            let i = free[r];
            let bound_part: f64 = (0..n)
                .filter(|&j| fixed[j])
                .map(|j| w[(i, j)] * self.x[j])
                .sum();
            -(q[i] + bound_part)
        });
        // A singular block leaves NaN, refused below as leaving the box.
        let sol = signorini_linalg::pivot_policy::solve_symmetric_checked(&wff, &rhs, "W_FF")
            .unwrap_or_else(|_| Mat::from_fn(nf, 1, |_, _| f64::NAN));
        self.report.operator_applications += 2; // the block solve and the residual
        let mut y = self.x.clone();
        for (k, &i) in free.iter().enumerate() {
            let v = sol[(k, 0)];
            if !v.is_finite() || v < self.bounds.lower[i] || v > self.bounds.upper[i] {
                return (res, BoxPolish::LeftTheBox);
            }
            y[i] = v;
        }
        let gy = gaps(w, q, &y);
        let res_y = self.bounds.residual(&y, &gy, self.opts);
        if res_y <= res {
            self.x = y;
            self.g = gy;
            (res_y, BoxPolish::Polished)
        } else {
            (res, BoxPolish::LargerResidual)
        }
    }

    fn unbounded(&self) -> ContactError {
        ContactError::Singular(format!(
            "{}: W is singular along a feasible descent direction with no bound in the way, so ½xᵀWx + qᵀx is unbounded below on the bounds (with λ ≥ 0 alone the LCP has no solution; a body free to slide or move away from its contacts?)",
            self.flavour.method
        ))
    }
}

fn set_last(report: &mut SolverReport, res: f64) {
    if let Some(last) = report.residual_history.last_mut() {
        *last = res;
    } else {
        report.residual_history.push(res);
    }
}

/// Rejects a warm start of the wrong length or with a non-finite entry.
pub(crate) fn check_start(x0: &[f64], n: usize, method: &str) -> Result<(), ContactError> {
    if x0.len() != n {
        return Err(ContactError::Solve(format!(
            "{method}: the warm start has {} entries for {n} unknowns",
            x0.len()
        )));
    }
    if let Some(i) = x0.iter().position(|v| !v.is_finite()) {
        return Err(ContactError::Solve(format!(
            "{method}: warm start x0[{i}] = {} is not finite",
            x0[i]
        )));
    }
    Ok(())
}

/// Rejects inconsistent sizes, non-finite entries of A or b, NaN bounds,
/// l_i = +∞, u_i = −∞ and l_i > u_i, naming the index.
fn check_box_input(
    a: &Mat<f64>,
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
) -> Result<(), ContactError> {
    let method = BOX.method;
    let n = b.len();
    if a.nrows() != n || a.ncols() != n || lower.len() != n || upper.len() != n {
        return Err(ContactError::Solve(format!(
            "{method}: A is {}×{} but b, l, u have {n}, {}, {} entries",
            a.nrows(),
            a.ncols(),
            lower.len(),
            upper.len()
        )));
    }
    check_finite(method, ("A", a), ("b", b))?;
    for i in 0..n {
        let (l, u) = (lower[i], upper[i]);
        if l.is_nan() || l == f64::INFINITY {
            return Err(ContactError::Solve(format!(
                "{method}: lower bound l[{i}] = {l} is not a valid bound (NaN or +∞)"
            )));
        }
        if u.is_nan() || u == f64::NEG_INFINITY {
            return Err(ContactError::Solve(format!(
                "{method}: upper bound u[{i}] = {u} is not a valid bound (NaN or −∞)"
            )));
        }
        if l > u {
            return Err(ContactError::Solve(format!(
                "{method}: empty box at index {i}: l[{i}] = {l} > u[{i}] = {u}"
            )));
        }
    }
    Ok(())
}
