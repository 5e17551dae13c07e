//! Semi-smooth Newton on the Alart–Curnier equations (Alart & Curnier 1991)
//! for friction with fixed thresholds, 2D and 3D; for Coulomb on Coulomb's
//! law itself (thresholds μ λ_n of the iterate, `coulomb::solve_coulomb`), with
//! the fixed point on the threshold around the fixed-threshold method as
//! its fallback (course notes §4.1.2, §4.3).
//!
//! Unknowns: the forces λ (normal rows, then each point's one or two
//! tangential rows, [`FrictionLayout`]) and the rigid-mode amplitudes α of
//! floating bodies; gaps y = W λ + q + G α. With ρ > 0, D = diag(g1, g2) the
//! semi-axes of a point's disc / ellipse and c = ρ / max(g_i)², the
//! projection equations are
//!
//! ```text
//!   normal:      F_n = λ_n − max(0, λ_n − ρ y_n)
//!   tangential:  F_t = λ_t − D proj_B(z),   z = D⁺ λ_t − c D Δs   (B: unit disc)
//!   equilibrium: Gᵀ λ = e
//! ```
//!
//! (Δs = y_t, the slip increments; an infinite bound is stuck, Δs = 0.) A
//! semi-smooth Newton step linearises F on the current statuses, which is a
//! primal–dual active set step: an open point (λ_n − ρ y_n ≤ 0) has the
//! identity rows dλ = −λ; a closed normal row and a stuck tangential row
//! (‖z‖ ≤ 1) the W rows (zero gap); a slipping point (‖z‖ > 1) its force on
//! the boundary, i.e. with τ the unit tangent of the circle at proj(z) and
//! a = Dτ, the component of λ_t across a given and the component along a
//! coupled to the slip with the compliance (‖z‖ − aᵀD⁺τ) / (c ‖a‖²) > 0.
//! Those rows ([`NewtonSystem`]) are solved by [`crate::reduced`]: the
//! given rows substituted, the coupled ones (a symmetric block, W plus a
//! diagonal) by Cholesky, floating bodies through the k × k Schur
//! complement on G; when that fails or is near singular, the full system by
//! a fully pivoted LU. An Armijo line search on ½‖F‖² globalises it; without
//! floating bodies an accelerated projected gradient takes over when the
//! line search fails.
//!
//! As with the 2D projection method ([`crate::friction::tresca_projection`]),
//! a Tresca point that opens may still carry a tangential force up to its
//! threshold (Tresca's law does not depend on the normal force); with
//! Coulomb the threshold of an open point is zero.

use faer::prelude::Solve;
use faer::Mat;

use crate::delassus::DelassusProblem;
use crate::friction::fixed_point::{fixed_point, normal_change, ThresholdMap, TrescaSolver};
use crate::law::cone::project_ellipse;
use crate::law::FrictionLayout;
use crate::options::FrictionOptions;
use crate::solution::friction_iterate::{FixedPoint, InnerSolve};
use crate::solution::{ContactSolution, PointStatus, StopReason, ThresholdMapKind};
use crate::ContactError;
use signorini_linalg::reduced::VarEquation;

/// A unit direction over at most two force rows (`c[1] = 0` for one row).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dir {
    pub rows: [usize; 2],
    pub c: [f64; 2],
}

impl Dir {
    fn one(row: usize) -> Self {
        Self {
            rows: [row, row],
            c: [1.0, 0.0],
        }
    }

    /// cᵀ v on the direction's rows.
    pub fn dot(&self, v: &[f64]) -> f64 {
        self.c[0] * v[self.rows[0]] + self.c[1] * v[self.rows[1]]
    }
}

/// The linearised Alart–Curnier equations at an iterate, one equation per
/// force row on orthonormal directions (so that dλ = Σ given + Σ coupled):
/// `given` cᵀ dλ = v; `coupled` d cᵀ dλ + cᵀ (W dλ + G dα) = v (d ≥ 0);
/// `equilibrium` Gᵀ dλ = v_j. With `secant`, a slipping point with one
/// tangential row is linearised on the secant of the projection (see
/// [`slip_rows`]). Coulomb's law (threshold μ λ_n, [`solve_coulomb`]) adds
/// the normal force dλ_n of a slipping point to its rows: `given_normal`
/// (i, row, f) makes given equation i cᵀ dλ = v + f dλ_row, and
/// `coupled_normal` (i, row, f) adds f dλ_row to the left of coupled
/// equation i (the system is then nonsymmetric).
#[derive(Debug, Default)]
pub(crate) struct NewtonSystem {
    pub secant: bool,
    pub given: Vec<(Dir, f64)>,
    pub coupled: Vec<(Dir, f64, f64)>,
    pub equilibrium: Vec<f64>,
    pub given_normal: Vec<(usize, usize, f64)>,
    pub coupled_normal: Vec<(usize, usize, f64)>,
    /// The last factor of the reduced system, for chord steps.
    pub factor: Option<crate::reduced::NewtonFactor>,
}

impl NewtonSystem {
    /// The full (n + k) square system [rows; Gᵀ 0] of the same equations,
    /// solved by a fully pivoted LU: the fallback of the reduced solve.
    fn solve_full(&self, w: &Mat<f64>, g: &Mat<f64>) -> Option<Vec<f64>> {
        let (jac, rhs) = self.full_system(w, g);
        let dx = jac.full_piv_lu().solve(&rhs);
        let dx: Vec<f64> = (0..jac.nrows()).map(|i| dx[(i, 0)]).collect();
        dx.iter().all(|v| v.is_finite()).then_some(dx)
    }

    /// The matrix and right-hand side of the full (n + k) square system
    /// [rows; Gᵀ 0] of the equations.
    fn full_system(&self, w: &Mat<f64>, g: &Mat<f64>) -> (Mat<f64>, Mat<f64>) {
        let (n, k) = (w.nrows(), g.ncols());
        let mut jac = Mat::<f64>::zeros(n + k, n + k);
        let mut rhs = Mat::<f64>::zeros(n + k, 1);
        let mut row = 0;
        for (d, v) in &self.given {
            for l in 0..2 {
                jac[(row, d.rows[l])] += d.c[l];
            }
            rhs[(row, 0)] = *v;
            row += 1;
        }
        for &(i, r, f) in &self.given_normal {
            jac[(i, r)] -= f;
        }
        for &(i, r, f) in &self.coupled_normal {
            jac[(self.given.len() + i, r)] += f;
        }
        for (d, comp, v) in &self.coupled {
            for l in 0..2 {
                let (r, cl) = (d.rows[l], d.c[l]);
                jac[(row, r)] += comp * cl;
                for col in 0..n {
                    jac[(row, col)] += cl * w[(r, col)];
                }
                for j in 0..k {
                    jac[(row, n + j)] += cl * g[(r, j)];
                }
            }
            rhs[(row, 0)] = *v;
            row += 1;
        }
        for (j, v) in self.equilibrium.iter().enumerate() {
            for i in 0..n {
                jac[(n + j, i)] = g[(i, j)];
            }
            rhs[(n + j, 0)] = *v;
        }
        (jac, rhs)
    }
}

/// The trial z = D⁺ λ_t − c D Δs of a point's rows in the unit disc
/// (D = diag(g), D⁺ its pseudo-inverse), with c and D⁺.
fn scaled_trial(
    x: &[f64],
    y: &[f64],
    rows: &[usize],
    g: [f64; 2],
    c: f64,
) -> (f64, [f64; 2], [f64; 2]) {
    let dinv = g.map(|gi| if gi > 0.0 { 1.0 / gi } else { 0.0 });
    let mut z = [0.0; 2];
    for (i, &r) in rows.iter().enumerate() {
        z[i] = dinv[i] * x[r] - c * g[i] * y[r];
    }
    (c, dinv, z)
}

/// The Tresca problem with fixed semi-axes: its rows, thresholds and scales.
struct Inner<'a> {
    problem: &'a DelassusProblem,
    layout: &'a FrictionLayout,
    /// Semi-axes (g1, g2) per point; infinite: no bound (stuck).
    thr: &'a [[f64; 2]],
    /// Newton's projection parameters per row (1 / diagonal of W).
    rho: Vec<f64>,
    /// Coulomb's law itself: the semi-axes of a Coulomb point are μ_i λ_n
    /// of the iterate (`thr` holds the other points' bounds).
    coulomb: bool,
}

/// How a residual is scaled: `Newton` with ρ = 1/W_ii, `Check` with ρ = F/L
/// (the natural residual relative to the force and length scales).
#[derive(Clone, Copy, PartialEq)]
enum Scale {
    Newton,
    Check(f64),
}

impl<'a> Inner<'a> {
    fn new(problem: &'a DelassusProblem, layout: &'a FrictionLayout, thr: &'a [[f64; 2]]) -> Self {
        let n = problem.q.len();
        let rho = (0..n)
            .map(|i| {
                let d = problem.w[(i, i)];
                if d > 0.0 && d.is_finite() {
                    1.0 / d
                } else {
                    1.0
                }
            })
            .collect();
        Self {
            problem,
            layout,
            thr,
            rho,
            coulomb: false,
        }
    }

    /// The semi-axes of point p at x and, for Coulomb's law itself, their
    /// derivatives in λ_n (μ_i where λ_n > 0).
    fn bound(&self, p: usize, x: &[f64]) -> ([f64; 2], Option<[f64; 2]>) {
        let law = &self.layout.law[p];
        match law.coulomb_mu() {
            Some(mu) if self.coulomb => {
                let dg = if x[p] > 0.0 { mu } else { [0.0; 2] };
                (law.semi_axes(x[p]), Some(dg))
            }
            _ => (self.thr[p], None),
        }
    }

    fn n(&self) -> usize {
        self.problem.q.len()
    }

    fn k(&self) -> usize {
        self.problem.g_mat.ncols()
    }

    /// W dλ + G dα of d = (dλ, dα) (W column by column, skipping zeros).
    fn apply(&self, d: &[f64]) -> Vec<f64> {
        let (n, k) = (self.n(), self.k());
        let mut y = vec![0.0; n];
        crate::lcp::matvec(&self.problem.w, &d[..n], &mut y);
        for j in 0..k {
            let a = d[n + j];
            for (i, yi) in y.iter_mut().enumerate() {
                *yi += self.problem.g_mat[(i, j)] * a;
            }
        }
        y
    }

    /// y = W λ + q + G α.
    fn gaps(&self, x: &[f64]) -> Vec<f64> {
        let mut y = self.apply(x);
        y.iter_mut()
            .zip(&self.problem.q)
            .for_each(|(yi, qi)| *yi += qi);
        y
    }

    /// The iterate x with its gaps computed afresh.
    fn iterate(&self, x: Vec<f64>) -> Iterate {
        Iterate {
            y: self.gaps(&x),
            x,
            fresh: true,
        }
    }

    /// The Alart–Curnier residual F(x) at the iterate (x, its gaps y) (rows:
    /// the n forces, then the k equilibrium equations) and, if asked, its
    /// linearisation.
    fn residual(&self, it: &Iterate, scale: Scale, mut sys: Option<&mut NewtonSystem>) -> Vec<f64> {
        let (n, k) = (self.n(), self.k());
        let gm = &self.problem.g_mat;
        let (x, y) = (&it.x[..], &it.y[..]);
        let mut f = vec![0.0; n + k];
        if let Some(s) = sys.as_deref_mut() {
            *s = NewtonSystem {
                secant: s.secant,
                factor: s.factor.take(),
                ..NewtonSystem::default()
            };
        }
        for p in 0..self.layout.n_points() {
            let rn = match scale {
                Scale::Newton => self.rho[p],
                Scale::Check(c) => c,
            };
            if x[p] - rn * y[p] > 0.0 {
                f[p] = rn * y[p];
                if let Some(s) = sys.as_deref_mut() {
                    s.coupled.push((Dir::one(p), 0.0, -y[p]));
                }
            } else {
                f[p] = x[p];
                if let Some(s) = sys.as_deref_mut() {
                    s.given.push((Dir::one(p), -x[p]));
                }
            }
            let rows = &self.layout.tangent_rows[p];
            if !rows.is_empty() {
                let sys = sys.as_deref_mut();
                let (g, dg) = self.bound(p, x);
                let normal = dg.map(|dg| (p, dg));
                self.tangential_residual(x, y, rows, (g, normal), scale, &mut f, sys);
            }
        }
        // Equilibrium of the rigid modes: Gᵀ λ = e.
        for j in 0..k {
            f[n + j] = (0..n).map(|i| gm[(i, j)] * x[i]).sum::<f64>() - self.problem.e[j];
            if let Some(s) = sys.as_deref_mut() {
                s.equilibrium.push(-f[n + j]);
            }
        }
        f
    }

    /// The Alart–Curnier rows of one point's tangential force λ_t (one or
    /// two rows) with semi-axes `g`: stuck (Δs = 0) for an infinite bound,
    /// zero for a zero bound, else, scaled to the unit disc,
    /// ν = D⁺ λ_t, z = ν − c D Δs, F = λ_t − D proj(z) (course notes §4.1.2).
    /// `normal`: Coulomb's law itself, (normal row, ∂g/∂λ_n) (see
    /// [`slip_rows`]).
    #[allow(clippy::too_many_arguments)]
    fn tangential_residual(
        &self,
        x: &[f64],
        y: &[f64],
        rows: &[usize],
        (g, normal): ([f64; 2], Option<(usize, [f64; 2])>),
        scale: Scale,
        f: &mut [f64],
        mut sys: Option<&mut NewtonSystem>,
    ) {
        let rt = match scale {
            Scale::Newton => rows.iter().map(|&r| self.rho[r]).sum::<f64>() / rows.len() as f64,
            Scale::Check(c) => c,
        };
        let gbar = g[..rows.len()].iter().fold(0.0f64, |a, &v| a.max(v));
        let (c, dinv, z) = scaled_trial(x, y, rows, g, rt / (gbar * gbar));
        let nz = z[0].hypot(z[1]);
        // A bound so small that c = ρ/ḡ² or z overflows (μ λ_n of a
        // round-off λ_n) is a zero bound: the point carries no λ_t.
        let negligible = !(c.is_finite() && nz.is_finite());
        if gbar.is_infinite() || gbar <= 0.0 || negligible {
            for &r in rows {
                if gbar.is_infinite() {
                    // No bound: stuck, Δs = 0.
                    f[r] = rt * y[r];
                    if let Some(s) = sys.as_deref_mut() {
                        s.coupled.push((Dir::one(r), 0.0, -y[r]));
                    }
                } else {
                    f[r] = x[r];
                    if let Some(s) = sys.as_deref_mut() {
                        s.given.push((Dir::one(r), -x[r]));
                    }
                }
            }
            return;
        }
        let pz = if nz <= 1.0 { z } else { [z[0] / nz, z[1] / nz] };
        for (i, &r) in rows.iter().enumerate() {
            f[r] = x[r] - g[i] * pz[i];
        }
        let Some(sys) = sys else { return };
        if nz <= 1.0 {
            // Stuck: zero slip on the rows with a bound, zero force on the others.
            for (i, &r) in rows.iter().enumerate() {
                if g[i] > 0.0 {
                    sys.coupled.push((Dir::one(r), 0.0, -y[r]));
                } else {
                    sys.given.push((Dir::one(r), -f[r]));
                }
            }
        } else {
            let coulomb = normal.map(|(p, dg)| (p, [dg[0] * pz[0], dg[1] * pz[1]]));
            slip_rows(sys, rows, (g, dinv), pz, nz, c, f, coulomb);
        }
    }

    /// One semi-smooth Newton step from x with an Armijo line search on
    /// ½‖F‖² ([`Inner::line_search`]). The Newton system is solved reduced
    /// ([`crate::reduced::solve_newton`]), or in full when that fails; with
    /// floating bodies, when it is singular, on the secants of the slipping
    /// points; when it is still singular, or its direction fails the line
    /// search (with floating bodies or on Coulomb's law itself, where no
    /// projected gradient follows), by the least-change steps
    /// ([`least_change`]). On Coulomb's law itself, while the structure of
    /// the reduced system repeats, a chord step on the previous factor comes
    /// first, kept when it halves ‖F‖ (a factorisation saved). The gaps
    /// follow the step (y + t W dx, one product with W a direction).
    fn newton_step(&self, x: &mut Iterate, sys: &mut NewtonSystem) -> Step {
        let f = self.residual(x, Scale::Newton, Some(sys));
        let psi = merit(&f);
        let (w, g) = (&self.problem.w, &self.problem.g_mat);
        let solve = |sys: &mut NewtonSystem, chord: bool| {
            let mut factor = sys.factor.take();
            let dx = crate::reduced::solve_newton(w, g, sys, &mut factor, chord);
            sys.factor = factor;
            if chord {
                return dx;
            }
            dx.or_else(|| sys.solve_full(w, g))
        };
        if self.coulomb {
            if let Some(dx) = solve(sys, true) {
                let trial = x.moved(&dx, &self.apply(&dx), 1.0);
                if merit(&self.residual(&trial, Scale::Newton, None)) <= 0.25 * psi {
                    *x = trial;
                    return Step::Accepted;
                }
            }
        }
        let mut dx = solve(sys, false);
        if dx.is_none() && self.k() > 0 {
            // Every point that could hold a floating body slips: relinearise
            // on the secants, which keep their slip coupled to the body.
            sys.secant = true;
            self.residual(x, Scale::Newton, Some(sys));
            dx = solve(sys, false);
            sys.secant = false;
        }
        if let Some(dx) = &dx {
            if self.line_search(x, dx, psi) {
                return Step::Accepted;
            }
        }
        if dx.is_none() || self.k() > 0 || self.coulomb {
            let jac = self.difference_jacobian(x, &f);
            for weight in least_change::LEAST_CHANGE_WEIGHTS {
                let step = least_change::least_change_step(&jac, &f, weight);
                if step.is_some_and(|d| self.line_search(x, &d, psi)) {
                    return Step::Accepted;
                }
            }
        }
        dx.map_or(Step::Singular, Step::Rejected)
    }

    /// The Armijo line search on ½‖F‖² along dx from x (merit `psi`),
    /// halving the step at most 30 times: whether a step was taken.
    fn line_search(&self, x: &mut Iterate, dx: &[f64], psi: f64) -> bool {
        let wdx = self.apply(dx);
        let mut t = 1.0;
        for _ in 0..30 {
            let trial = x.moved(dx, &wdx, t);
            let ft = self.residual(&trial, Scale::Newton, None);
            if merit(&ft) <= (1.0 - 1e-4 * t) * psi {
                *x = trial;
                return true;
            }
            t *= 0.5;
        }
        false
    }

    /// The unknowns from the forces `start`, the rigid-mode amplitudes from
    /// the problem's last solve (zero without one).
    fn start(&self, start: &[f64]) -> Vec<f64> {
        let (n, k) = (self.n(), self.k());
        let mut x = vec![0.0; n + k];
        x[..n].copy_from_slice(start);
        if self.problem.alpha().len() == k {
            x[n..].copy_from_slice(self.problem.alpha());
        }
        x
    }

    /// Why the Newton method stops at `x` after `iterations` iterations, if
    /// `x` meets the tolerance (on gaps computed afresh: those that followed
    /// the steps are refreshed first), or because `x` became non-finite
    /// (a NaN residual is never met); the observer (crate::observe) hears
    /// of `x`.
    fn met(
        &self,
        x: &mut Iterate,
        opts: &FrictionOptions,
        iterations: usize,
    ) -> Option<StopReason> {
        let mut residual = self.check(x, opts);
        if residual <= opts.tolerance && !x.fresh {
            x.y = self.gaps(&x.x);
            x.fresh = true;
            residual = self.check(x, opts);
        }
        let normal = &x.x[..self.layout.n_points()];
        let lmax = crate::norms::max_abs(normal);
        let tol_f = opts.tolerance * opts.force_scale.max(lmax);
        crate::observe::iteration(crate::observe::Iteration {
            method: "newton",
            iteration: iterations,
            active: normal.iter().filter(|&&l| l > tol_f).count(),
            residual: residual / opts.tolerance.max(f64::MIN_POSITIVE),
        });
        if residual.is_nan() {
            return Some(StopReason::NonFinite {
                iteration: iterations,
            });
        }
        (residual <= opts.tolerance).then_some(StopReason::NewtonConverged {
            residual,
            iterations,
        })
    }

    /// The scaled natural residual: max over the rows of |F_check| / F.
    fn check(&self, x: &Iterate, opts: &FrictionOptions) -> f64 {
        let n = self.n();
        let fs = opts
            .force_scale
            .max(crate::norms::max_abs(&x.x[..n]))
            .max(f64::MIN_POSITIVE);
        let c = fs / opts.gap_scale.max(f64::MIN_POSITIVE);
        let f = self.residual(x, Scale::Check(c), None);
        crate::norms::max_abs(&f) / fs
    }

    /// Accelerated projected gradient (FISTA with adaptive restart) on
    /// ½ λᵀ W λ + qᵀ λ over the product of half-lines and ellipses; no
    /// floating body.
    fn projected_gradient(&self, x: &mut [f64], iterations: usize) {
        let n = self.n();
        let m = self.layout.n_points();
        let w = &self.problem.w;
        // Gershgorin bound on the largest eigenvalue of W.
        let lip = (0..n)
            .map(|i| (0..n).map(|j| w[(i, j)].abs()).sum::<f64>())
            .fold(0.0f64, f64::max)
            .max(f64::MIN_POSITIVE);
        let project = |v: &mut [f64]| {
            for p in 0..m {
                v[p] = v[p].max(0.0);
                match self.layout.tangent_rows[p][..] {
                    [a, b] => {
                        let r = project_ellipse([v[a], v[b]], self.thr[p]);
                        v[a] = r[0];
                        v[b] = r[1];
                    }
                    [a] if self.thr[p][0].is_finite() => {
                        v[a] = v[a].clamp(-self.thr[p][0], self.thr[p][0]);
                    }
                    _ => {}
                }
            }
        };
        project(x);
        let mut prev = x.to_vec();
        let mut ypt = x.to_vec();
        let mut t = 1.0f64;
        for _ in 0..iterations {
            let grad = self.gaps(&ypt);
            let mut next: Vec<f64> = (0..n).map(|i| ypt[i] - grad[i] / lip).collect();
            project(&mut next);
            // Restart when the momentum points uphill.
            let uphill: f64 = (0..n).map(|i| grad[i] * (next[i] - prev[i])).sum();
            let t_next = if uphill > 0.0 {
                1.0
            } else {
                0.5 * (1.0 + (1.0 + 4.0 * t * t).sqrt())
            };
            let beta = if uphill > 0.0 {
                0.0
            } else {
                (t - 1.0) / t_next
            };
            for i in 0..n {
                ypt[i] = next[i] + beta * (next[i] - prev[i]);
            }
            prev = next;
            t = t_next;
        }
        x[..n].copy_from_slice(&prev);
    }
}

/// The rows of a slipping point (‖z‖ > 1, u = proj(z) on the unit
/// circle): with τ ⊥ u, a = D τ, b = D⁺ τ, the linearised equations
/// dλ_t − a bᵀ dλ_t / ‖z‖ + c a aᵀ (W_t dλ + G_t dα) / ‖z‖ = −F_t give the
/// component of dλ_t across a, and along â = a/‖a‖ the coupled row with
/// the compliance (‖z‖ − aᵀb) / (c ‖a‖²) (positive: aᵀb ≤ 1 < ‖z‖). When
/// a vanishes (one bounded row, or D τ = 0) the rows are the identity.
/// With `sys.secant`, every row of the point is linearised on the
/// projection's secant slope 1/‖z‖ instead of its derivative (zero across
/// the boundary): (1 − 1/‖z‖) dλ_ti + c g_i² (W_ti dλ + G_ti dα) / ‖z‖ =
/// −F_ti, the compliance (‖z‖ − 1) / (c g_i²) (a body held by friction
/// alone, all its points slipping at an iterate, is otherwise held by
/// nothing along their slip: a singular step).
///
/// Coulomb's law itself (`coulomb` = (normal row, m), m = (∂D/∂λ_n) u, i.e.
/// μ_i u_i): with D = λ_n diag(μ), u does not depend on λ_n (z = w / λ_n)
/// and F_t = λ_t − D u gains −m dλ_n; the equations above hold with −F_t
/// replaced by −F_t + m dλ_n, all linear in F_t: the component across a
/// (isotropic: the radial one) follows the normal force, and the coupled
/// row gains a multiple of dλ_n ([`NewtonSystem`]).
#[allow(clippy::too_many_arguments)]
fn slip_rows(
    sys: &mut NewtonSystem,
    rows: &[usize],
    (g, dinv): ([f64; 2], [f64; 2]),
    u: [f64; 2],
    nz: f64,
    c: f64,
    f: &[f64],
    coulomb: Option<(usize, [f64; 2])>,
) {
    let (normal, m) = coulomb.unwrap_or((0, [0.0; 2]));
    let given = |sys: &mut NewtonSystem, d: Dir, v: f64, fm: f64| {
        if fm != 0.0 {
            sys.given_normal.push((sys.given.len(), normal, fm));
        }
        sys.given.push((d, v));
    };
    let coupled = |sys: &mut NewtonSystem, d: Dir, comp: f64, v: f64, fm: f64| {
        if fm != 0.0 {
            sys.coupled_normal.push((sys.coupled.len(), normal, fm));
        }
        sys.coupled.push((d, comp, v));
    };
    let tau = [-u[1], u[0]];
    let two = rows.len() == 2;
    let a = [g[0] * tau[0], if two { g[1] * tau[1] } else { 0.0 }];
    let b = [dinv[0] * tau[0], if two { dinv[1] * tau[1] } else { 0.0 }];
    let na = a[0].hypot(a[1]);
    if sys.secant {
        for (i, &r) in rows.iter().enumerate() {
            let cg = c * g[i] * g[i];
            if cg > 0.0 && cg.is_finite() {
                let (comp, v, fm) = ((nz - 1.0) / cg, -nz * f[r] / cg, -nz * m[i] / cg);
                coupled(sys, Dir::one(r), comp, v, fm);
            } else {
                given(sys, Dir::one(r), -f[r], m[i]);
            }
        }
        return;
    }
    if !two || na <= 1e-12 * g[0].max(g[1]) {
        for (i, &r) in rows.iter().enumerate() {
            given(sys, Dir::one(r), -f[r], m[i]);
        }
        return;
    }
    let ah = [a[0] / na, a[1] / na];
    let across = Dir {
        rows: [rows[0], rows[1]],
        c: [-ah[1], ah[0]],
    };
    let along = Dir {
        rows: across.rows,
        c: ah,
    };
    // cᵀ v, zero below its rounding (isotropic: a ⊥ u, b ⊥ â⊥ exactly,
    // and the system keeps the structure key of its chord steps).
    let on = |d: &Dir, v: [f64; 2]| {
        let p = d.c[0] * v[0] + d.c[1] * v[1];
        let bound = 8.0 * f64::EPSILON * (v[0].abs() + v[1].abs());
        if p.abs() <= bound {
            0.0
        } else {
            p
        }
    };
    let beta = -across.dot(f);
    let ab = a[0] * b[0] + a[1] * b[1];
    let bv = on(&across, b);
    let comp = (nz - ab) / (c * na * na);
    let rhs = -nz * along.dot(f) / (c * na * na) + beta * bv / (c * na);
    let kappa = on(&across, m);
    let eta = nz * on(&along, m) / (c * na * na) + kappa * bv / (c * na);
    given(sys, across, beta, kappa);
    coupled(sys, along, comp, rhs, -eta);
}

/// The merit ½‖F‖² of a residual.
fn merit(f: &[f64]) -> f64 {
    0.5 * f.iter().map(|v| v * v).sum::<f64>()
}

/// An iterate x = (λ, α) and its gaps y = W λ + q + G α, computed afresh
/// (`fresh`) or followed along the steps.
struct Iterate {
    x: Vec<f64>,
    y: Vec<f64>,
    fresh: bool,
}

impl Iterate {
    /// x + t dx, y + t W dx.
    fn moved(&self, dx: &[f64], wdx: &[f64], t: f64) -> Iterate {
        let step = |a: &[f64], d: &[f64]| a.iter().zip(d).map(|(a, d)| a + t * d).collect();
        Iterate {
            x: step(&self.x, dx),
            y: step(&self.y, wdx),
            fresh: false,
        }
    }
}

/// What a Newton step did.
enum Step {
    /// A step length decreased the merit: x moved.
    Accepted,
    /// No step length did; the Newton direction.
    Rejected(Vec<f64>),
    /// The Newton system is singular (a non-finite direction).
    Singular,
}

/// Newton iterations without a residual below [`STALL_DECREASE`] times the
/// best so far after which the method stops as stalled: where it converges
/// it does so in a few dozen (the pushed assembly: 5 to 30); where it does
/// not it cycled between statuses (a period of 75 iterations at 1.2e-2 on
/// an assembly pushed sideways) or blew up under full steps, and spent its
/// 500 iterations so, in each of the fixed point's inner solves.
const STALLED_AFTER: usize = 60;

/// The decrease of the residual that counts as progress for
/// [`STALLED_AFTER`].
const STALL_DECREASE: f64 = 0.9;

/// Semi-smooth Newton on the Alart–Curnier equations with fixed semi-axes
/// `thr`, from the forces `start`; with `coulomb`, on Coulomb's law itself
/// (the semi-axes of Coulomb points μ_i λ_n of the iterate): no projected
/// gradient (not a convex program) and a singular system is not an error
/// but a failure, for the caller's fixed point.
fn solve_inner(
    newton: &Newton,
    thr: &[[f64; 2]],
    start: &[f64],
    coulomb: bool,
) -> Result<(InnerSolve, usize), ContactError> {
    let (problem, layout, opts, dim) = (newton.problem, newton.layout, newton.opts, newton.dim);
    let mut inner = Inner::new(problem, layout, thr);
    inner.coulomb = coulomb;
    inner.rho.iter_mut().for_each(|r| *r *= newton.rho_scale);
    let (n, k) = (inner.n(), inner.k());
    let mut x = inner.iterate(inner.start(start));
    let mut sys = NewtonSystem::default();
    let mut fallbacks = 0usize;
    let mut iterations = 0;
    let mut reason = StopReason::NewtonLimit {
        limit: opts.max_iterations,
    };
    let mut best = (f64::INFINITY, 0usize);
    for it in 0..opts.max_iterations {
        if let Some(met) = inner.met(&mut x, opts, it) {
            reason = met;
            break;
        }
        let residual = inner.check(&x, opts);
        if residual < STALL_DECREASE * best.0 {
            best = (residual, it);
        } else if it - best.1 >= STALLED_AFTER {
            reason = StopReason::NewtonStalled {
                best: best.0,
                at: best.1,
                since: it - best.1,
            };
            break;
        }
        iterations = it + 1;
        let dx = match inner.newton_step(&mut x, &mut sys) {
            Step::Accepted => continue,
            Step::Rejected(dx) => Some(dx),
            Step::Singular => None,
        };
        fallbacks += 1;
        match dx {
            // Globalisation: accelerated projected gradient, then Newton again.
            _ if k == 0 && !coulomb => {
                inner.projected_gradient(&mut x.x, 200 * fallbacks);
                x = inner.iterate(x.x);
            }
            // Floating bodies: no projection on the equilibrium; take the
            // full (non-monotone) Newton step.
            Some(dx) if fallbacks <= 5 => {
                x.x.iter_mut().zip(&dx).for_each(|(xi, d)| *xi += d);
                x = inner.iterate(x.x);
            }
            Some(_) => {
                reason = StopReason::NewtonLineSearchFailed;
                break;
            }
            // Coulomb: a singular step fails; the caller's fixed point decides.
            // No finite step, not even a least-change one: a non-finite
            // entry in the system; the caller's fallback decides.
            None => {
                reason = StopReason::NonFinite { iteration: it + 1 };
                break;
            }
        }
    }
    let met = |r: &StopReason| matches!(r, StopReason::NewtonConverged { .. });
    if !met(&reason) {
        reason = inner.met(&mut x, opts, iterations).unwrap_or(reason);
    }
    let converged = met(&reason);
    let Iterate { mut x, y, fresh } = x;
    let gaps = if fresh { y } else { inner.gaps(&x) };
    x.truncate(n);
    let solve = InnerSolve {
        statuses: statuses(layout, &x, &gaps, opts, dim),
        forces: x,
        gaps,
        converged,
        reason,
    };
    Ok((solve, iterations))
}

/// Statuses: open (λ_n ≤ tol), slip (‖Δs‖ > tol, the force on the boundary
/// of the disc / ellipse; in 2D slip± by the sign of λ_t), stick otherwise
/// (in contact, and sticking if the point has friction).
fn statuses(
    layout: &FrictionLayout,
    r: &[f64],
    g: &[f64],
    opts: &FrictionOptions,
    dim: usize,
) -> Vec<PointStatus> {
    let lmax = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let tol_f = opts.tolerance * opts.force_scale.max(lmax);
    let tol_g = opts.tolerance * opts.gap_scale;
    (0..layout.n_points())
        .map(|p| {
            if r[p] <= tol_f {
                PointStatus::Open
            } else {
                let slip = layout.tangent_rows[p]
                    .iter()
                    .map(|&t| g[t] * g[t])
                    .sum::<f64>();
                if slip.sqrt() <= tol_g {
                    PointStatus::Stick
                } else if dim == 3 {
                    PointStatus::Slip
                } else if r[layout.tangent_rows[p][0]] > 0.0 {
                    PointStatus::SlipPlus
                } else {
                    PointStatus::SlipMinus
                }
            }
        })
        .collect()
}

mod coulomb;
mod least_change;
mod norton_hoff;
mod tresca_inner;
pub use coulomb::coulomb_newton;
pub(crate) use coulomb::friction_newton;
use tresca_inner::Newton;

#[cfg(test)]
mod tests;
