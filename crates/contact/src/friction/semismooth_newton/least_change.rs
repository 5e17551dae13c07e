//! The least-change (Levenberg–Marquardt) step of the semi-smooth Newton
//! method of [`super`], where its system is singular or its direction fails
//! the line search.
//!
//! A Newton system is singular where, at the iterate's statuses, some rigid
//! motion of a floating body is held by no row coupled to the gaps: every
//! point that could hold it open, slipping along that motion, or with a
//! vanishing normal force (a Coulomb point whose bound μ λ_n is zero has
//! given rows λ_t = 0). And a Newton direction of one set of statuses may
//! not decrease the merit ½‖F‖² once the statuses change along it. With J
//! the Jacobian of F itself by differences (a column per unknown: F is
//! piecewise smooth, and a difference across a kink gives the slope of the
//! secant), the step that changes the unknowns least among those that best
//! satisfy J dx = −F,
//!
//! ```text
//!   min ‖J dx + F‖² + δ ‖dx‖²,   (JᵀJ + δ I) dx = −JᵀF,
//! ```
//!
//! exists for every δ > 0; it tends to the Newton step (the minimum-norm one
//! where J is singular) as δ → 0 and to the steepest descent of the merit,
//! −JᵀF / δ, as δ grows, so that the line search on the merit accepts one
//! of them wherever the merit is not stationary.

use faer::prelude::Solve;
use faer::{Mat, Side};

use super::{Inner, Iterate, Scale};

/// The weights δ tried, relative to the mean of diag(JᵀJ): nearly the
/// Newton step first, then steps closer and closer to steepest descent.
pub(super) const LEAST_CHANGE_WEIGHTS: [f64; 4] = [1e-8, 1e-4, 1e-1, 1e1];

/// The relative size of the differences (of max(|x_i|, the unknowns' scale)).
const DIFFERENCE: f64 = 1e-7;

impl Inner<'_> {
    /// J, the Jacobian of F (Newton's scaling) at x by forward differences,
    /// column i from x + h e_i (its gaps moved by h W e_i, or h G e_j for a
    /// rigid-mode amplitude): O(n) per column.
    pub(super) fn difference_jacobian(&self, x: &Iterate, f: &[f64]) -> Mat<f64> {
        let (n, k) = (self.n(), self.k());
        let (w, g) = (&self.problem.w, &self.problem.g_mat);
        let scale = crate::norms::max_abs(&x.x[..n]).max(f64::MIN_POSITIVE);
        let mut jac = Mat::<f64>::zeros(n + k, n + k);
        let mut trial = Iterate {
            x: x.x.clone(),
            y: x.y.clone(),
            fresh: false,
        };
        for col in 0..n + k {
            let h = DIFFERENCE * x.x[col].abs().max(if col < n { scale } else { 1.0 });
            trial.x[col] += h;
            for i in 0..n {
                trial.y[i] += h * if col < n {
                    w[(i, col)]
                } else {
                    g[(i, col - n)]
                };
            }
            let ft = self.residual(&trial, Scale::Newton, None);
            for (row, (a, b)) in ft.iter().zip(f).enumerate() {
                jac[(row, col)] = (a - b) / h;
            }
            trial.x[col] = x.x[col];
            trial.y.copy_from_slice(&x.y);
        }
        jac
    }
}

/// The least-change step dx = (dλ, dα) of J dx = −F with weight
/// δ = `weight` × mean diag(JᵀJ) (see the module); `None` when it is not
/// finite.
pub(super) fn least_change_step(jac: &Mat<f64>, f: &[f64], weight: f64) -> Option<Vec<f64>> {
    let size = jac.ncols();
    let mut normal = jac.transpose() * jac;
    let rhs = Mat::<f64>::from_fn(size, 1, |i, _| {
        -(0..f.len()).map(|r| jac[(r, i)] * f[r]).sum::<f64>()
    });
    let mean = (0..size).map(|i| normal[(i, i)]).sum::<f64>() / size.max(1) as f64;
    let delta = weight * mean.max(f64::MIN_POSITIVE);
    for i in 0..size {
        normal[(i, i)] += delta;
    }
    let dx = normal.llt(Side::Lower).ok()?.solve(&rhs);
    let dx: Vec<f64> = (0..size).map(|i| dx[(i, 0)]).collect();
    dx.iter().all(|v| v.is_finite()).then_some(dx)
}
