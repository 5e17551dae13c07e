//! The fixed point on the slip threshold (course notes §4.3), one driver for 2D and
//! 3D friction.
//!
//! With the thresholds g fixed, friction is a Tresca problem (a convex
//! program on the condensed problem, course notes §4.1.1). Coulomb's law makes the
//! threshold depend on the normal force, g = μ λ_n (§4.1.2): the fixed point
//!
//! g⁽ᵏ⁺¹⁾ ← μ λ_n(g⁽ᵏ⁾)
//!
//! solves one Tresca problem per outer iteration, with the thresholds of the
//! previous forces, until the normal forces no longer change. Norton–Hoff
//! friction (§4.1.4, eq. 19) is the same iteration with another threshold
//! map, g ← μ λ_n |Δs|^ρ, stopped on the misfit of its law. The driver
//! [`fixed_point`] is therefore generic over
//! - the inner Tresca solver ([`TrescaSolver`]): the 2D status method
//!   (`friction::status_tresca::StatusTresca`) or the 3D semi-smooth Newton method
//!   (`friction3d::Newton`), each counting its own iterations;
//! - the threshold map and the residual ([`ThresholdMap`]): Coulomb's
//!   g ← μ λ_n with the change of the normal forces ([`normal_change`]),
//!   or Norton–Hoff's map with its misfit.

use crate::options::{FrictionOptions, Stall, StallWatch};
use crate::solution::friction_iterate::{FixedPoint, InnerSolve};
use crate::solution::{StopReason, ThresholdMapKind};
use crate::ContactError;

/// A solver of the Tresca problem with given thresholds (course notes §4.1.1), the
/// inner problem of the fixed point.
pub(crate) trait TrescaSolver {
    /// The thresholds of the points (2D: a force per point; 3D: the
    /// semi-axes of each point's disc / ellipse).
    type Thresholds;

    /// Solves the Tresca problem with `thresholds`, from the forces `start`
    /// (the previous iterate; a solver may carry its own start instead,
    /// e.g. the statuses of the status method).
    fn solve(
        &mut self,
        thresholds: &Self::Thresholds,
        start: &[f64],
    ) -> Result<InnerSolve, ContactError>;
}

/// The thresholds from the forces and gaps of an iterate.
pub(crate) type ThresholdFn<'a, T> = &'a dyn Fn(&[f64], &[f64]) -> T;
/// How far an iterate is from the law, as a force (the driver divides it by
/// the force scale), from the previous forces and the iterate.
pub(crate) type ResidualFn<'a> = &'a dyn Fn(&[f64], &InnerSolve) -> f64;

/// A friction law solved as a fixed point on its threshold.
pub(crate) struct ThresholdMap<'a, T> {
    pub threshold: ThresholdFn<'a, T>,
    pub residual: ResidualFn<'a>,
    /// Which map: the stop reasons name it.
    pub kind: ThresholdMapKind,
}

/// Coulomb's residual (course notes §4.3): max |Δλ_n| over the m points between the
/// previous forces and the iterate.
pub(crate) fn normal_change(previous: &[f64], next: &InnerSolve) -> f64 {
    (0..next.statuses.len()).fold(0.0f64, |a, p| {
        crate::norms::nan_max(a, (next.forces[p] - previous[p]).abs())
    })
}

/// Outer iterations without a new smallest residual after which the fixed
/// point stops as stalled: where it converges its residual keeps falling;
/// where the normal forces are not unique (a pile of rigid bodies, W of
/// rank 380 in 480 rows) it wandered between 1e-6 and 5e-3 for hundreds of
/// iterations (and, on a larger pile, broke down after 1 600).
const STALLED_AFTER: usize = 100;

/// The fixed point on the threshold (course notes §4.3) from the iterate `start`:
/// each outer iteration solves the Tresca problem with the thresholds
/// `map.threshold` of the previous forces and gaps, until `map.residual`
/// relative to the force scale max(force_scale, ‖λ‖∞) meets the tolerance.
/// An inner problem that fails under stale thresholds usually settles once
/// they are updated, so the iteration goes on unless it was the last chance
/// or the thresholds no longer move; it then stops with "inner Tresca
/// problem: <its reason>".
pub(crate) fn fixed_point<S: TrescaSolver>(
    solver: &mut S,
    start: InnerSolve,
    map: &ThresholdMap<'_, S::Thresholds>,
    opts: &FrictionOptions,
) -> Result<FixedPoint, ContactError> {
    let mut last = start;
    let mut residuals = Vec::new();
    let mut watch = StallWatch::new(1.0, STALLED_AFTER, None);
    let stop = |last, residuals, converged, reason| FixedPoint {
        last,
        residuals,
        converged,
        reason,
    };
    for outer in 0..opts.max_fixed_point {
        if crate::options::deadline_passed(opts.deadline) {
            let residual = residuals.last().copied().unwrap_or(f64::INFINITY);
            let reason = StopReason::TimeLimit {
                iterations: outer,
                residual,
            };
            return Ok(stop(last, residuals, false, reason));
        }
        let thr = (map.threshold)(&last.forces, &last.gaps);
        let next = solver.solve(&thr, &last.forces)?;
        let fscale = opts
            .force_scale
            .max(crate::norms::max_abs(&next.forces))
            .max(f64::MIN_POSITIVE);
        let res = (map.residual)(&last.forces, &next) / fscale;
        residuals.push(res);
        last = next;
        if res.is_nan() {
            let reason = StopReason::NonFinite {
                iteration: outer + 1,
            };
            return Ok(stop(last, residuals, false, reason));
        }
        if let Some(Stall { best, at, since }) = watch.stalled(res, outer + 1) {
            let reason = StopReason::FixedPointStalled {
                map: map.kind,
                best,
                at,
                since,
            };
            return Ok(stop(last, residuals, false, reason));
        }
        if !last.converged && outer + 1 < opts.max_fixed_point && res > opts.tolerance {
            continue;
        }
        if !last.converged {
            let reason = StopReason::InnerTresca(Box::new(last.reason.clone()));
            return Ok(stop(last, residuals, false, reason));
        }
        if res <= opts.tolerance {
            let reason = StopReason::FixedPointReached {
                map: map.kind,
                iterations: outer + 1,
            };
            return Ok(stop(last, residuals, true, reason));
        }
    }
    let reason = StopReason::FixedPointLimit {
        map: map.kind,
        limit: opts.max_fixed_point,
    };
    Ok(stop(last, residuals, false, reason))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solution::PointStatus;

    /// An inner solver whose normal force follows `forces(k)` at its k-th solve.
    struct Scripted<F: Fn(usize) -> f64> {
        forces: F,
        calls: usize,
    }

    impl<F: Fn(usize) -> f64> TrescaSolver for Scripted<F> {
        type Thresholds = ();
        fn solve(&mut self, _: &(), _: &[f64]) -> Result<InnerSolve, ContactError> {
            self.calls += 1;
            Ok(InnerSolve {
                forces: vec![(self.forces)(self.calls)],
                gaps: vec![0.0],
                statuses: vec![PointStatus::Stick],
                converged: true,
                reason: StopReason::Pending,
            })
        }
    }

    fn run<F: Fn(usize) -> f64>(forces: F) -> (FixedPoint, usize) {
        let opts = FrictionOptions {
            max_iterations: 10_000,
            max_fixed_point: 10_000,
            tolerance: 1e-10,
            force_scale: 1.0,
            gap_scale: 1.0,
            deadline: None,
        };
        let map = ThresholdMap {
            threshold: &|_, _| (),
            residual: &normal_change,
            kind: ThresholdMapKind::Coulomb,
        };
        let mut solver = Scripted { forces, calls: 0 };
        let start = solver.solve(&(), &[]).unwrap();
        let end = fixed_point(&mut solver, start, &map, &opts).unwrap();
        (end, solver.calls - 1)
    }

    /// Forces that wander without approaching a limit stop the fixed point
    /// as stalled, STALLED_AFTER iterations after its best residual, not at
    /// the limit of 10 000; forces that converge slowly (halving each
    /// time) are followed to the tolerance; a NaN stops it at once.
    #[test]
    fn a_wandering_fixed_point_stalls_a_converging_one_does_not() {
        let (end, outer) = run(|k| 1.0 + 0.5 * ((k * 7919) % 13) as f64 / 13.0);
        assert!(!end.converged);
        assert!(
            matches!(end.reason, StopReason::FixedPointStalled { since, .. } if since == STALLED_AFTER),
            "{:?}",
            end.reason
        );
        assert!(outer <= STALLED_AFTER + 20, "{outer}");
        let (end, outer) = run(|k| 1.0 + 0.5f64.powi(k as i32));
        assert!(
            end.converged && outer > 30,
            "{:?} after {outer}",
            end.reason
        );
        let (end, outer) = run(|k| if k < 5 { k as f64 } else { f64::NAN });
        assert!(!end.converged && outer == 4, "{outer}");
        assert!(
            matches!(end.reason, StopReason::NonFinite { iteration: 4 }),
            "{:?}",
            end.reason
        );
    }
}
