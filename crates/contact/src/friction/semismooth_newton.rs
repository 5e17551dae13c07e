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
use crate::options::{FrictionOptions, StallWatch};
use crate::solution::friction_iterate::{FixedPoint, InnerSolve};
use crate::solution::{ContactSolution, PointStatus, StopReason, ThresholdMapKind};
use crate::ContactError;
pub use alart_curnier::{AlartCurnier, Dir, NewtonSystem, Scale};
use signorini_linalg::reduced::VarEquation;

impl NewtonSystem {
    /// The full (n + k) square system [rows; Gᵀ 0] of the same equations,
    /// solved by a fully pivoted LU: the fallback of the reduced solve.
    /// When that LU is singular (W rank deficient: rigid bodies with more
    /// contact rows than degrees of freedom), the system regularised by
    /// 1e-6 max |J| on its diagonal (a Levenberg–Marquardt step, for the
    /// line search to judge).
    fn solve_full(&self, w: &Mat<f64>, g: &Mat<f64>) -> Option<Vec<f64>> {
        let (mut jac, rhs) = self.full_system(w, g);
        let solve = |jac: &Mat<f64>| {
            let dx = jac.full_piv_lu().solve(&rhs);
            let dx: Vec<f64> = (0..jac.nrows()).map(|i| dx[(i, 0)]).collect();
            dx.iter().all(|v| v.is_finite()).then_some(dx)
        };
        solve(&jac).or_else(|| {
            let shift = 1e-6 * jac.norm_max();
            (0..jac.nrows()).for_each(|i| jac[(i, i)] += shift);
            solve(&jac)
        })
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

/// The Tresca problem with fixed semi-axes: the condensed problem and the
/// Alart–Curnier equations of its points (ρ = 1 / diagonal of W).
struct Inner<'a> {
    problem: &'a DelassusProblem,
    law: AlartCurnier<'a>,
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
            law: AlartCurnier {
                layout,
                thr,
                rho,
                coulomb: false,
            },
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
        let x = &it.x[..];
        let mut f = vec![0.0; n + k];
        self.law
            .residual(x, &it.y, scale, &mut f, sys.as_deref_mut());
        // Equilibrium of the rigid modes: Gᵀ λ = e.
        for j in 0..k {
            f[n + j] = (0..n).map(|i| gm[(i, j)] * x[i]).sum::<f64>() - self.problem.e[j];
            if let Some(s) = sys.as_deref_mut() {
                s.equilibrium.push(-f[n + j]);
            }
        }
        f
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
        if self.law.coulomb {
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
        if dx.is_none() || self.k() > 0 || self.law.coulomb {
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
        let normal = &x.x[..self.law.layout.n_points()];
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
        let m = self.law.layout.n_points();
        let w = &self.problem.w;
        // Gershgorin bound on the largest eigenvalue of W.
        let lip = (0..n)
            .map(|i| (0..n).map(|j| w[(i, j)].abs()).sum::<f64>())
            .fold(0.0f64, f64::max)
            .max(f64::MIN_POSITIVE);
        let project = |v: &mut [f64]| {
            for p in 0..m {
                v[p] = v[p].max(0.0);
                match self.law.layout.tangent_rows[p][..] {
                    [a, b] => {
                        let r = project_ellipse([v[a], v[b]], self.law.thr[p]);
                        v[a] = r[0];
                        v[b] = r[1];
                    }
                    [a] if self.law.thr[p][0].is_finite() => {
                        v[a] = v[a].clamp(-self.law.thr[p][0], self.law.thr[p][0]);
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

/// The merit ½‖F‖² of a residual.
pub fn merit(f: &[f64]) -> f64 {
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
pub const STALLED_AFTER: usize = 60;

/// The decrease of the residual that counts as progress for
/// [`STALLED_AFTER`].
pub const STALL_DECREASE: f64 = 0.9;

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
    inner.law.coulomb = coulomb;
    inner
        .law
        .rho
        .iter_mut()
        .for_each(|r| *r *= newton.rho_scale);
    let (n, k) = (inner.n(), inner.k());
    let mut x = inner.iterate(inner.start(start));
    let mut sys = NewtonSystem::default();
    let mut fallbacks = 0usize;
    let mut iterations = 0;
    let mut reason = StopReason::NewtonLimit {
        limit: opts.max_iterations,
    };
    let mut watch = StallWatch::new(STALL_DECREASE, STALLED_AFTER, opts.deadline);
    for it in 0..opts.max_iterations {
        if let Some(met) = inner.met(&mut x, opts, it) {
            reason = met;
            break;
        }
        let residual = inner.check(&x, opts);
        if watch.time_up() {
            reason = StopReason::TimeLimit {
                iterations: it,
                residual,
            };
            break;
        }
        if let Some(stall) = watch.stalled(residual, it) {
            reason = StopReason::newton_stalled(stall);
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
pub fn statuses(
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

pub mod alart_curnier;
pub(crate) mod coulomb;
mod least_change;
mod norton_hoff;
mod tresca_inner;
pub use coulomb::coulomb_newton;
pub(crate) use coulomb::friction_newton;
use tresca_inner::Newton;

#[cfg(test)]
mod tests;
