//! Projection methods on the forces (course notes §3.2, docs/theory/algorithms.md): the projected
//! gradient and the projected conjugate gradient for the frictionless
//! LCP(W, q),
//!
//! ```text
//! λ ≥ 0,   w = W λ + q ≥ 0,   λ·w = 0,
//! ```
//!
//! i.e. the bound-constrained quadratic programme
//!
//! ```text
//! min f(λ) = ½ λᵀ W λ + qᵀ λ   subject to   λ ≥ 0,
//! ```
//!
//! whose gradient is the gap, ∇f(λ) = W λ + q = w. The course notes (§3.2) project
//! the displacements onto H = {B u ≥ j}, which needs B diagonalised; on the
//! forces the bounds are simple (λ_p ≥ 0) and the projection is the clamp
//! P(λ)_p = max(λ_p, 0).
//!
//! Both methods start from λ = 0, keep λ ≥ 0 exactly, maintain the gradient
//! g = W λ + q, and stop when the natural residual of [`lcp_residual`] is at
//! most `opts.tolerance` (checked at the end with the true gaps W λ + q, so
//! round-off in the recursively updated gradient cannot fake convergence).
//!
//! The helpers at the end of this file (input checks, products with W, the
//! residual from a known gradient) are shared with [`crate::lcp::lemke`] and
//! [`crate::lcp::mprgp`].

use faer::Mat;

use crate::lcp::{
    checked_or_empty, clamp, dot, energy_of, gaps_into, lcp_residual, matvec, residual_from_gaps,
    time_limit_stop, LcpOptions,
};
use crate::solution::{ContactSolution, Measure, SolverReport, StopReason};
use crate::ContactError;

/// Armijo constant of the sufficient-decrease test on the projection arc.
const ARMIJO: f64 = 1e-4;

/// Projected gradient (course notes §3.2) on the forces.
///
/// Iteration k, with g = W λᵏ + q (the gaps) and the free part of the
/// residual r = −g restricted to the points that may move (r_p = 0 where
/// λ_p = 0 and g_p ≥ 0, the points held at the bound):
///
/// 1. exact line-search step of the seed, μᵏ = rᵀr / rᵀW r;
/// 2. λᵏ⁺¹ = P(λᵏ + μᵏ r), P the clamp onto λ ≥ 0.
///
/// When the clamp cuts the step and the energy f does not decrease enough
/// (Armijo test f(λᵏ⁺¹) ≤ f(λᵏ) + 10⁻⁴ gᵀ(λᵏ⁺¹ − λᵏ) along the projection
/// arc) μ is halved: this safeguard keeps the method convergent when the
/// exact step is longer than 2/‖W‖.
///
/// `report.iterations` counts steps, `operator_applications` the products
/// W·v (one per step, two when the clamp is active, one per backtrack).
pub fn projected_gradient(
    w: &Mat<f64>,
    q: &[f64],
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    const METHOD: &str = "projected_gradient";
    if let Some(empty) = checked_or_empty(w, q, METHOD)? {
        return Ok(empty);
    }
    let m = q.len();
    let mut s = Projection::new(w, q, opts, METHOD);
    let mut wr = vec![0.0; m];
    loop {
        let res = match s.next_step() {
            Next::Stop => break,
            Next::Again => continue,
            Next::Step(res) => res,
        };
        let r = free_residual(&s.lambda, &s.g);
        let rr = dot(&r, &r);
        if rr == 0.0 {
            s.report.stop = stagnated(s.report.iterations, res, opts.tolerance);
            break;
        }
        matvec(w, &r, &mut wr);
        s.report.operator_applications += 1;
        let curv = dot(&r, &wr);
        // Longest step before a force reaches zero.
        let feasible = max_feasible_step(&s.lambda, &r);
        let mut mu = exact_step(rr, curv, s.wscale, rr);
        if !mu.is_finite() {
            if !feasible.is_finite() {
                return Err(unbounded(METHOD));
            }
            mu = feasible;
        }
        if mu <= feasible {
            // No clamp: the exact step of the seed, gradient updated exactly.
            s.advance(mu, &r, &wr);
            s.update_energy();
        } else if !s.backtrack(mu, feasible, &r) {
            s.report.stop = StopReason::LineSearchFailed {
                iteration: s.report.iterations,
                residual: res,
            };
            break;
        }
        s.push_residual();
    }
    Ok(s.finish())
}

/// The free part of the residual of [`projected_gradient`]: r = −g, 0 at
/// the points held at the bound (λ_p = 0 and g_p ≥ 0).
fn free_residual(lambda: &[f64], g: &[f64]) -> Vec<f64> {
    (0..g.len())
        .map(|p| {
            if lambda[p] <= 0.0 && g[p] >= 0.0 {
                0.0
            } else {
                -g[p]
            }
        })
        .collect()
}

/// The exact minimiser `num / curv` along a direction d with dᵀd = `dd`
/// and curvature dᵀW d = `curv`; ∞ where the curvature is negligible
/// against ‖W‖ (the energy is flat or unbounded along d).
fn exact_step(num: f64, curv: f64, wscale: f64, dd: f64) -> f64 {
    if curv > 1e-14 * wscale * dd {
        num / curv
    } else {
        f64::INFINITY
    }
}

/// What [`Projection::next_step`] found at the head of an iteration.
enum Next {
    /// Converged or out of iterations (reported): stop.
    Stop,
    /// The recursive residual met the tolerance but the exact one did not:
    /// the gradient is exact again, look again.
    Again,
    /// Take the step counted now; the natural residual before it.
    Step(f64),
}

/// The state shared by the projection methods: the iterate λ ≥ 0, its
/// gradient g = W λ + q (updated recursively), its energy f(λ), the trial
/// point of the Armijo test and the report.
struct Projection<'a> {
    w: &'a Mat<f64>,
    q: &'a [f64],
    opts: &'a LcpOptions,
    /// max |W_ij|, the scale of negligible curvature (see `exact_step`).
    wscale: f64,
    lambda: Vec<f64>,
    g: Vec<f64>,
    energy: f64,
    trial: Vec<f64>,
    g_trial: Vec<f64>,
    report: SolverReport,
}

impl<'a> Projection<'a> {
    /// λ = 0, g = q, f = 0.
    fn new(w: &'a Mat<f64>, q: &'a [f64], opts: &'a LcpOptions, method: &str) -> Self {
        let m = q.len();
        Self {
            w,
            q,
            opts,
            wscale: w.norm_max(),
            lambda: vec![0.0; m],
            g: q.to_vec(),
            energy: 0.0,
            trial: vec![0.0; m],
            g_trial: vec![0.0; m],
            report: SolverReport {
                method: method.into(),
                ..Default::default()
            },
        }
    }

    /// The natural residual from the recursive gradient.
    fn residual(&self) -> f64 {
        residual_from_gaps(&self.lambda, &self.g, self.opts)
    }

    fn update_energy(&mut self) {
        self.energy = energy_of(&self.lambda, &self.g, self.q);
    }

    fn push_residual(&mut self) {
        let res = self.residual();
        self.report.residual_history.push(res);
    }

    /// At a recursive residual `res` ≤ tolerance: [`verify`] with the exact
    /// gaps; `true` (converged, reported) when it holds, else the iteration
    /// goes on from the exact gradient and its energy.
    fn at_tolerance(&mut self, res: f64) -> bool {
        if verify(
            self.w,
            self.q,
            &mut self.lambda,
            &mut self.g,
            self.opts,
            &mut self.report,
        ) {
            self.report.converged = true;
            self.report.stop = StopReason::ResidualMet {
                residual: self.report.residual_history.last().copied().unwrap_or(res),
                tolerance: self.opts.tolerance,
                iterations: self.report.iterations,
            };
            return true;
        }
        self.update_energy();
        false
    }

    /// The head of an iteration of the projection methods: convergence
    /// ([`Self::at_tolerance`]), then the iteration limit, then the step is
    /// counted.
    fn next_step(&mut self) -> Next {
        let res = self.residual();
        if res <= self.opts.tolerance {
            return if self.at_tolerance(res) {
                Next::Stop
            } else {
                Next::Again
            };
        }
        if self.out_of_iterations(res) {
            return Next::Stop;
        }
        self.report.iterations += 1;
        Next::Step(res)
    }

    /// `true` (reported) when the time limit or the iteration limit is
    /// reached.
    fn out_of_iterations(&mut self, res: f64) -> bool {
        if self.opts.out_of_time(self.report.iterations) {
            self.report.stop = time_limit_stop(&self.report, res);
            return true;
        }
        if self.report.iterations < self.opts.max_iterations {
            return false;
        }
        self.report.stop = StopReason::IterationLimit {
            limit: self.opts.max_iterations,
            measure: Measure::Natural,
            residual: res,
            tolerance: self.opts.tolerance,
            steps: None,
        };
        true
    }

    /// λ ← P(λ + α d), g ← g + α W d (W d in `wd`).
    fn advance(&mut self, alpha: f64, d: &[f64], wd: &[f64]) {
        for p in 0..self.lambda.len() {
            self.lambda[p] = (self.lambda[p] + alpha * d[p]).max(0.0);
            self.g[p] += alpha * wd[p];
        }
    }

    /// The clamped trial point P(λ + μ d) with its exact gaps (one
    /// product); `true` when it passes the Armijo test
    /// f(trial) ≤ f(λ) + 10⁻⁴ gᵀ(trial − λ).
    fn armijo_trial(&mut self, mu: f64, d: &[f64]) -> bool {
        let m = self.lambda.len();
        for ((t, &l), &dp) in self.trial.iter_mut().zip(&self.lambda).zip(d) {
            *t = (l + mu * dp).max(0.0);
        }
        gaps_into(self.w, self.q, &self.trial, &mut self.g_trial);
        self.report.operator_applications += 1;
        let e_trial = energy_of(&self.trial, &self.g_trial, self.q);
        let decrease: f64 = (0..m)
            .map(|p| self.g[p] * (self.trial[p] - self.lambda[p]))
            .sum();
        e_trial <= self.energy + ARMIJO * decrease
    }

    /// The trial point becomes the iterate.
    fn accept_trial(&mut self) {
        std::mem::swap(&mut self.lambda, &mut self.trial);
        std::mem::swap(&mut self.g, &mut self.g_trial);
    }

    /// Clamped step with Armijo backtracking on the projection arc: μ is
    /// halved (never below the feasible step) until the test passes;
    /// `false` when it does not within 60 halvings.
    fn backtrack(&mut self, mut mu: f64, feasible: f64, r: &[f64]) -> bool {
        for _ in 0..60 {
            if self.armijo_trial(mu, r) || mu <= feasible {
                self.accept_trial();
                self.update_energy();
                return true;
            }
            mu = (0.5 * mu).max(feasible);
        }
        false
    }

    fn finish(self) -> ContactSolution {
        ContactSolution::from_forces(self.w, self.q, clamp(self.lambda), self.report)
    }
}

/// Projected conjugate gradient (course notes §3.2 with CG in place of the gradient;
/// Polyak's method with projection, in the spirit of Moré & Toraldo).
///
/// The free set F = {p : λ_p > 0 or g_p < 0} (points that may move; its
/// complement is held at λ_p = 0 with a non-negative gap). With the free
/// gradient φ = g restricted to F:
///
/// - direction: p = −φ after a restart, else the conjugate direction
///   p = −φ + β p_old, β = φᵀφ / φ_oldᵀφ_old (Fletcher–Reeves);
/// - step: the exact minimiser α = −gᵀp / pᵀW p along p;
/// - if λ + α p ≥ 0 the CG step is taken and the gradient updated,
///   g ← g + α W p; otherwise the clamped point P(λ + α p) is taken if it
///   passes the Armijo test, else the step stops at the first bound it
///   meets (feasible step), and the CG recursion restarts;
/// - the recursion also restarts whenever F changes.
///
/// Counts as [`projected_gradient`].
pub fn projected_conjugate_gradient(
    w: &Mat<f64>,
    q: &[f64],
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    const METHOD: &str = "projected_conjugate_gradient";
    if let Some(empty) = checked_or_empty(w, q, METHOD)? {
        return Ok(empty);
    }
    let m = q.len();
    let mut s = Projection::new(w, q, opts, METHOD);
    let mut cg = Conjugate::new(m);
    let mut wd = vec![0.0; m];
    loop {
        let res = match s.next_step() {
            Next::Stop => break,
            Next::Again => {
                cg.restart = true;
                continue;
            }
            Next::Step(res) => res,
        };
        cg.update(&s.lambda, &s.g);
        let dir = &cg.dir;
        let slope = dot(&s.g, dir);
        let dd = dot(dir, dir);
        if dd == 0.0 {
            s.report.stop = stagnated(s.report.iterations, res, opts.tolerance);
            break;
        }
        matvec(w, dir, &mut wd);
        s.report.operator_applications += 1;
        let curv = dot(dir, &wd);
        let feasible = max_feasible_step(&s.lambda, dir);
        let alpha = exact_step(-slope, curv, s.wscale, dd);
        if !alpha.is_finite() && !feasible.is_finite() {
            return Err(unbounded(METHOD));
        }
        if alpha <= feasible {
            s.advance(alpha, dir, &wd);
        } else {
            // The CG step leaves λ ≥ 0: try the clamped point, else stop at the bound.
            if alpha.is_finite() && s.armijo_trial(alpha, dir) {
                s.accept_trial();
            } else {
                s.advance(feasible, dir, &wd);
                // The blocking point lands exactly on its bound.
                if let Some(b) = blocking_index(&s.lambda, dir) {
                    s.lambda[b] = 0.0;
                }
            }
            cg.restart = true;
        }
        s.update_energy();
        s.push_residual();
    }
    Ok(s.finish())
}

/// The conjugate-gradient recursion of [`projected_conjugate_gradient`]:
/// the direction, the free set and ‖φ‖² of the previous iteration, and
/// whether the next direction restarts along −φ.
struct Conjugate {
    dir: Vec<f64>,
    free_old: Vec<bool>,
    phi_norm_old: f64,
    restart: bool,
}

impl Conjugate {
    fn new(m: usize) -> Self {
        Self {
            dir: vec![0.0; m],
            free_old: Vec::new(),
            phi_norm_old: 0.0,
            restart: true,
        }
    }

    /// The next direction: p = −φ after a restart (asked, or the free set
    /// F changed), else p = −φ + β p_old with β = φᵀφ / φ_oldᵀφ_old
    /// (Fletcher–Reeves); −φ again when p is not a descent direction.
    fn update(&mut self, lambda: &[f64], g: &[f64]) {
        let m = g.len();
        let free: Vec<bool> = (0..m).map(|p| lambda[p] > 0.0 || g[p] < 0.0).collect();
        if free != self.free_old {
            self.restart = true;
        }
        let phi_norm: f64 = (0..m).filter(|&p| free[p]).map(|p| g[p] * g[p]).sum();
        let beta = if self.restart || self.phi_norm_old <= 0.0 {
            0.0
        } else {
            phi_norm / self.phi_norm_old
        };
        for p in 0..m {
            self.dir[p] = if free[p] {
                -g[p] + beta * self.dir[p]
            } else {
                0.0
            };
        }
        self.free_old = free;
        self.phi_norm_old = phi_norm;
        self.restart = false;
        if dot(g, &self.dir) >= 0.0 {
            // Not a descent direction (round-off): restart along −φ.
            for ((dp, &free), &gp) in self.dir.iter_mut().zip(&self.free_old).zip(g) {
                *dp = if free { -gp } else { 0.0 };
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Helpers shared by the LCP methods (lemke, projected_gradient, mprgp).
// ---------------------------------------------------------------------------

/// Largest α with λ + α d ≥ 0 (∞ when no component decreases).
pub(crate) fn max_feasible_step(lambda: &[f64], d: &[f64]) -> f64 {
    lambda
        .iter()
        .zip(d)
        .filter(|(_, &dp)| dp < 0.0)
        .map(|(&lp, &dp)| (lp / -dp).max(0.0))
        .fold(f64::INFINITY, f64::min)
}

/// The point that stops the step λ + α d at α = `step` (smallest index on ties).
fn blocking_index(lambda_after: &[f64], d: &[f64]) -> Option<usize> {
    (0..d.len())
        .filter(|&p| d[p] < 0.0)
        .min_by(|&a, &b| lambda_after[a].total_cmp(&lambda_after[b]).then(a.cmp(&b)))
}

/// Recomputes the gaps exactly (one product) and checks the residual with
/// [`lcp_residual`]; on failure the recursively updated gradient had
/// drifted and iterations continue from the exact one.
pub(crate) fn verify(
    w: &Mat<f64>,
    q: &[f64],
    lambda: &mut [f64],
    g: &mut [f64],
    opts: &LcpOptions,
    report: &mut SolverReport,
) -> bool {
    for v in lambda.iter_mut() {
        *v = v.max(0.0);
    }
    gaps_into(w, q, lambda, g);
    report.operator_applications += 1;
    let res = lcp_residual(w, q, lambda, opts);
    if let Some(last) = report.residual_history.last_mut() {
        *last = res;
    } else {
        report.residual_history.push(res);
    }
    res <= opts.tolerance
}

/// The stop of a projection method without a descent direction at
/// iteration `it`, natural residual `res` above the tolerance `tol`.
fn stagnated(it: usize, res: f64, tol: f64) -> StopReason {
    StopReason::Stagnation {
        iteration: it,
        measure: Measure::Natural,
        residual: res,
        tolerance: tol,
    }
}

pub(crate) fn unbounded(method: &str) -> ContactError {
    ContactError::Singular(format!(
        "{method}: W is singular along a feasible descent direction, so ½λᵀWλ + qᵀλ is unbounded below on λ ≥ 0 and the LCP has no solution (a body free to move away from its contacts?)"
    ))
}

#[cfg(test)]
pub(crate) mod test_support {
    //! Problems with known answers, shared by the tests of the LCP methods.

    use faer::Mat;

    use crate::lcp::{gaps, lcp_residual, LcpOptions};
    use crate::solution::ContactSolution;
    use crate::test_problems::status_solution;
    use crate::{ContactError, DelassusProblem};

    /// Deterministic xorshift64* generator.
    pub struct Rng(pub u64);

    impl Rng {
        pub fn new(seed: u64) -> Self {
            Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
        }
        pub fn next_u64(&mut self) -> u64 {
            let mut x = self.0;
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            self.0 = x;
            x.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }
        /// Uniform in [−1, 1).
        pub fn uniform(&mut self) -> f64 {
            (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// W = AᵀA / (2m) + ε I with A (2m × m) uniform in [−1, 1): SPD,
    /// entries O(1), condition number O(10).
    pub fn random_spd(m: usize, rng: &mut Rng) -> Mat<f64> {
        let a = Mat::<f64>::from_fn(2 * m, m, |_, _| rng.uniform());
        let mut w = a.transpose() * &a;
        for j in 0..m {
            for i in 0..m {
                w[(i, j)] /= 2.0 * m as f64;
            }
            w[(j, j)] += 0.05;
        }
        symmetrize(w)
    }

    pub fn symmetrize(mut w: Mat<f64>) -> Mat<f64> {
        let m = w.nrows();
        for j in 0..m {
            for i in j + 1..m {
                let v = 0.5 * (w[(i, j)] + w[(j, i)]);
                w[(i, j)] = v;
                w[(j, i)] = v;
            }
        }
        w
    }

    pub fn random_vec(m: usize, rng: &mut Rng) -> Vec<f64> {
        (0..m).map(|_| rng.uniform()).collect()
    }

    /// q = w* − W λ* for a complementary pair (λ*, w*): the solution is λ*.
    pub fn q_for(w: &Mat<f64>, lambda: &[f64], gap: &[f64]) -> Vec<f64> {
        let wl = gaps(w, &vec![0.0; lambda.len()], lambda);
        gap.iter().zip(&wl).map(|(g, x)| g - x).collect()
    }

    pub fn tight() -> LcpOptions {
        LcpOptions {
            tolerance: 1e-12,
            max_iterations: 100_000,
            ..Default::default()
        }
    }

    /// The status method (course notes §3.3) on (W, q): the reference answer.
    pub fn reference(w: &Mat<f64>, q: &[f64]) -> Vec<f64> {
        status_solution(w, q, 1e-14)
    }

    pub fn inf_norm(v: &[f64]) -> f64 {
        v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
    }

    /// ‖a − b‖∞ ≤ rel · max(‖b‖∞, 1).
    pub fn assert_close(a: &[f64], b: &[f64], rel: f64, what: &str) {
        assert_eq!(a.len(), b.len());
        let d = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f64, f64::max);
        let scale = inf_norm(b).max(1.0);
        assert!(
            d <= rel * scale,
            "{what}: ‖Δ‖∞ = {d:.3e} > {rel:.1e} × {scale:.3e}"
        );
    }

    /// Checks a returned solution: finite, λ ≥ 0 exactly, residual met, converged.
    pub fn check_solution(w: &Mat<f64>, q: &[f64], sol: &ContactSolution, opts: &LcpOptions) {
        assert!(
            sol.report.converged,
            "{}: {}",
            sol.report.method, sol.report.stop
        );
        assert_eq!(sol.forces.len(), q.len());
        assert!(sol.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
        let r = lcp_residual(w, q, &sol.forces, opts);
        assert!(
            r <= opts.tolerance,
            "{}: residual {r:.3e}",
            sol.report.method
        );
        assert_eq!(
            sol.report.residual_history.last(),
            Some(&r),
            "{}",
            sol.report.method
        );
    }

    pub type Method = fn(&Mat<f64>, &[f64], &LcpOptions) -> Result<ContactSolution, ContactError>;

    /// [`agrees_with_status_method`] for an iterative `method` (named `name`
    /// in the log): it iterates, each iteration one product with W at least.
    pub fn iterates_to_the_status_method(name: &str, method: Method) {
        let (it, ops) = agrees_with_status_method(method);
        eprintln!("{name}: {it} iterations, {ops} products on the m = 60 random case");
        assert!(it > 0 && ops >= it);
    }

    /// Every case of the brief against the status method; returns
    /// (iterations, products with W) on the m = 60 random problem.
    pub fn agrees_with_status_method(method: Method) -> (usize, usize) {
        let opts = tight();
        let mut rng = Rng::new(7);
        let mut iters60 = (0, 0);
        // Random SPD W, q of mixed signs.
        for m in [5, 20, 60] {
            let w = random_spd(m, &mut rng);
            let q = random_vec(m, &mut rng);
            assert!(q.iter().any(|v| *v < 0.0) && q.iter().any(|v| *v > 0.0));
            let sol = method(&w, &q, &opts).unwrap();
            check_solution(&w, &q, &sol, &opts);
            let exact = reference(&w, &q);
            assert!(exact.iter().any(|v| *v > 0.0) && exact.contains(&0.0));
            assert_close(&sol.forces, &exact, 1e-8, &format!("random m = {m}"));
            if m == 60 {
                iters60 = (sol.report.iterations, sol.report.operator_applications);
            }
        }
        let m = 20;
        let w = random_spd(m, &mut rng);
        // All contacts active: λ* > 0, w* = 0 (q ≪ 0).
        let lstar: Vec<f64> = (0..m).map(|_| 1.5 + rng.uniform()).collect();
        let q = q_for(&w, &lstar, &vec![0.0; m]);
        assert!(q.iter().all(|v| *v < 0.0));
        let sol = method(&w, &q, &opts).unwrap();
        check_solution(&w, &q, &sol, &opts);
        assert_close(&sol.forces, &lstar, 1e-8, "all active");
        assert_close(
            &sol.forces,
            &reference(&w, &q),
            1e-8,
            "all active vs status",
        );
        // None active: q > 0, λ = 0 exactly.
        let q: Vec<f64> = (0..m).map(|_| 1.5 + rng.uniform()).collect();
        let sol = method(&w, &q, &opts).unwrap();
        check_solution(&w, &q, &sol, &opts);
        assert!(
            sol.forces.iter().all(|v| *v == 0.0),
            "none active: {:?}",
            sol.forces
        );
        // Weakly active: points 3 and 11 have λ* = 0 and w* = 0.
        let mut lstar = vec![0.0; m];
        let mut wstar = vec![0.0; m];
        for p in 0..m {
            if p == 3 || p == 11 {
                continue;
            }
            if p % 2 == 0 {
                lstar[p] = 1.0 + 0.5 * rng.uniform();
            } else {
                wstar[p] = 0.5 + 0.25 * rng.uniform();
            }
        }
        let q = q_for(&w, &lstar, &wstar);
        let sol = method(&w, &q, &opts).unwrap();
        check_solution(&w, &q, &sol, &opts);
        assert_close(&sol.forces, &lstar, 1e-8, "weakly active");
        assert_close(
            &sol.forces,
            &reference(&w, &q),
            1e-8,
            "weakly active vs status",
        );
        let g = gaps(&w, &q, &sol.forces);
        assert!(g[3].abs() <= 1e-9 && g[11].abs() <= 1e-9 && sol.forces[3] <= 1e-9);
        iters60
    }

    /// Redundant constraints: two identical rows of B, so W = B S⁻¹ Bᵀ is
    /// singular. The gaps and λ_2 + λ_dup must match the problem without the
    /// duplicate (solved by the status method); each force alone is not
    /// unique. `may_fail`: an `Err` is accepted (never a NaN).
    pub fn redundant_constraints(method: Method, may_fail: bool) {
        let mut rng = Rng::new(99);
        let n = 12;
        let a = Mat::<f64>::from_fn(n, n, |_, _| rng.uniform());
        let mut s = a.transpose() * &a;
        for i in 0..n {
            s[(i, i)] += 1.0;
        }
        let s = symmetrize(s);
        let mut rows: Vec<Vec<(usize, f64)>> = (0..7)
            .map(|p| vec![(p, 1.0), ((p + 5) % n, 0.5 * rng.uniform())])
            .collect();
        let mut gap0: Vec<f64> = (0..7).map(|_| 0.01 * rng.uniform()).collect();
        let f: Vec<f64> = (0..n)
            .map(|i| if i < 7 { -1.0 } else { 0.3 * rng.uniform() })
            .collect();
        let reduced = DelassusProblem::new(&s, &rows, &gap0, &f, &Mat::zeros(n, 0)).unwrap();
        let exact = reference(&reduced.w, &reduced.q);
        assert!(exact[2] > 0.0, "the duplicated contact must carry a force");
        rows.push(rows[2].clone());
        gap0.push(gap0[2]);
        let full = DelassusProblem::new(&s, &rows, &gap0, &f, &Mat::zeros(n, 0)).unwrap();
        let opts = tight();
        match method(&full.w, &full.q, &opts) {
            Ok(sol) => {
                eprintln!(
                    "{} on redundant constraints: {} iterations, λ_2 = {:.6}, λ_dup = {:.6}, sum {:.6} (reduced problem: {:.6})",
                    sol.report.method,
                    sol.report.iterations,
                    sol.forces[2],
                    sol.forces[7],
                    sol.forces[2] + sol.forces[7],
                    exact[2]
                );
                assert!(sol.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
                check_solution(&full.w, &full.q, &sol, &opts);
                let mut merged = sol.forces[..7].to_vec();
                merged[2] += sol.forces[7];
                assert_close(
                    &merged,
                    &exact,
                    1e-8,
                    "redundant: forces with the duplicate merged",
                );
                let g = gaps(&full.w, &full.q, &sol.forces);
                let g_exact = gaps(&reduced.w, &reduced.q, &exact);
                assert_close(&g[..7], &g_exact, 1e-8, "redundant: gaps");
                assert!((g[7] - g[2]).abs() <= 1e-12);
            }
            Err(e) => {
                eprintln!("redundant constraints: error {e}");
                assert!(may_fail, "{e}");
                let msg = e.to_string();
                assert!(!msg.is_empty() && !msg.contains("NaN"), "{msg}");
            }
        }
    }

    /// Non-finite input, size mismatch, m = 0.
    pub fn edge_cases(method: Method) {
        let opts = LcpOptions::default();
        let sol = method(&Mat::zeros(0, 0), &[], &opts).unwrap();
        assert!(sol.report.converged && sol.forces.is_empty());
        let mut w = Mat::<f64>::identity(3, 3);
        assert!(matches!(
            method(&w, &[1.0, f64::NAN, -1.0], &opts),
            Err(ContactError::Solve(_))
        ));
        w[(1, 2)] = f64::INFINITY;
        assert!(matches!(
            method(&w, &[1.0, 0.0, -1.0], &opts),
            Err(ContactError::Solve(_))
        ));
        assert!(matches!(
            method(&Mat::identity(2, 2), &[1.0, 0.0, -1.0], &opts),
            Err(ContactError::Solve(_))
        ));
    }

    /// The same LCP in other units: (s W, t q) for s, t in 1e-12 … 1e12, with
    /// the force and gap scales of the options scaled alike (t/s, t), has
    /// the solution (t/s) λ to 1e-8 relatively, converges, and takes the
    /// same number of iterations as (W, q) within `slack`.
    pub fn scale_invariant(method: Method, slack: usize) {
        let mut rng = Rng::new(11);
        let m = 20;
        let w = random_spd(m, &mut rng);
        let q = random_vec(m, &mut rng);
        let base = method(&w, &q, &tight()).unwrap();
        assert!(base.report.converged, "{}", base.report.stop);
        assert!(base.forces.iter().any(|v| *v > 0.0) && base.forces.contains(&0.0));
        let scales = [1e-12, 1e-6, 1.0, 2.1e11, 1e12];
        for s in scales {
            for t in scales {
                let ws = Mat::<f64>::from_fn(m, m, |i, j| s * w[(i, j)]);
                let qs: Vec<f64> = q.iter().map(|v| t * v).collect();
                let opts = LcpOptions {
                    force_scale: t / s,
                    gap_scale: t,
                    ..tight()
                };
                let sol = method(&ws, &qs, &opts).unwrap();
                let what = format!("{} at s = {s:e}, t = {t:e}", sol.report.method);
                assert!(sol.report.converged, "{what}: {}", sol.report.stop);
                let back: Vec<f64> = sol.forces.iter().map(|v| v * s / t).collect();
                assert_close(&back, &base.forces, 1e-8, &what);
                let (a, b) = (sol.report.iterations, base.report.iterations);
                assert!(
                    a.abs_diff(b) <= slack,
                    "{what}: {a} iterations, {b} in units 1"
                );
            }
        }
    }

    /// A too small iteration budget gives Ok with converged = false.
    pub fn reports_iteration_limit(method: Method, budget: usize) {
        let mut rng = Rng::new(3);
        let w = random_spd(40, &mut rng);
        let q = random_vec(40, &mut rng);
        let opts = LcpOptions {
            tolerance: 1e-14,
            max_iterations: budget,
            ..Default::default()
        };
        let sol = method(&w, &q, &opts).unwrap();
        assert!(!sol.report.converged);
        assert!(
            sol.report.stop.to_string().contains("not converged"),
            "{}",
            sol.report.stop
        );
        assert!(sol.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;

    #[test]
    fn projected_gradient_agrees_with_the_status_method() {
        iterates_to_the_status_method("projected_gradient", projected_gradient);
    }

    #[test]
    fn projected_conjugate_gradient_agrees_with_the_status_method() {
        iterates_to_the_status_method("projected_conjugate_gradient", projected_conjugate_gradient);
    }

    #[test]
    fn projection_methods_handle_redundant_constraints() {
        redundant_constraints(projected_gradient, false);
        redundant_constraints(projected_conjugate_gradient, false);
    }

    #[test]
    fn projection_methods_do_not_depend_on_the_units() {
        scale_invariant(projected_gradient, 1);
        scale_invariant(projected_conjugate_gradient, 1);
    }

    #[test]
    fn projection_methods_edge_cases() {
        edge_cases(projected_gradient);
        edge_cases(projected_conjugate_gradient);
        reports_iteration_limit(projected_gradient, 3);
        reports_iteration_limit(projected_conjugate_gradient, 3);
    }

    #[test]
    fn projected_gradient_takes_the_exact_seed_step_without_bounds() {
        // q < 0 everywhere with W diagonal: one exact step μ = rᵀr / rᵀWr
        // per distinct eigenvalue; W = 2 I converges in one step to λ = −q/2.
        let w = Mat::<f64>::from_fn(3, 3, |i, j| if i == j { 2.0 } else { 0.0 });
        let q = [-1.0, -2.0, -4.0];
        let sol = projected_gradient(&w, &q, &tight()).unwrap();
        assert!(sol.report.converged);
        assert_eq!(sol.report.iterations, 1);
        assert_close(&sol.forces, &[0.5, 1.0, 2.0], 1e-15, "one step");
    }
}
