//! Norton–Hoff friction in 3D (course notes §4.1.4, eq. 19) by the fixed point on
//! its slip-dependent threshold, each inner Tresca problem by the
//! semi-smooth Newton method of [`super`].
//!
//! In the tangent plane the law is isotropic: the tangential force of a
//! point in contact is
//!
//! ```text
//! λ_t = −μ λ_n ‖Δs‖^(ρ−1) Δs,   0 < ρ < 1,
//! ```
//!
//! a force of magnitude g = μ λ_n ‖Δs‖^ρ opposing the slip increment Δs
//! (the two tangential gaps; with one tangential row, the other tangent
//! held by a support, its one component), in the scene's length unit;
//! Coulomb as ρ → 0. As in 2D ([`crate::friction::norton_hoff`]), the fixed
//! point solves the Tresca problem whose disc has the radius g of the
//! previous iterate's forces and slips, g ← μ λ_n ‖Δs‖^ρ, from the solution
//! with every closed point stuck, and stops when the law's misfit
//! ‖λ_t + μ λ_n ‖Δs‖^(ρ−1) Δs‖ is within the tolerance at every closed
//! point; the map contracts at a rate of order ρ. The law, its threshold,
//! its misfit and its floor of slip are the 2D ones
//! ([`crate::law::norton_hoff::NortonHoffLaw`]).

use super::tresca_inner::Newton;
use super::*;
use crate::law::norton_hoff::NortonHoffLaw;

/// The inner Tresca problems of Norton–Hoff's fixed point are solved this
/// many times tighter than the law's tolerance: the misfit is read from
/// their forces and slips, so it cannot fall below their own residual (at
/// the same tolerance the fixed point stalled at 1.02 times it).
const INNER_TIGHTER: f64 = 1e-2;

/// The fixed point of Norton–Hoff's law (module doc) from `start` (the
/// solution with the closed points stuck), Newton's inner solves counted
/// in its iterations.
pub(super) fn norton_hoff_fixed_point(
    newton: &mut Newton,
    start: InnerSolve,
) -> Result<ContactSolution, ContactError> {
    let (layout, opts) = (newton.layout, newton.opts);
    let inner_opts = FrictionOptions {
        tolerance: (opts.tolerance * INNER_TIGHTER).max(64.0 * f64::EPSILON),
        ..opts.clone()
    };
    let mut inner = Newton {
        opts: &inner_opts,
        last_failure: None,
        ..*newton
    };
    let law = NortonHoffLaw::new(layout, opts);
    let threshold = |r: &[f64], g: &[f64]| {
        law.thresholds(
            r,
            g,
            |radius| [radius; 2],
            |p| layout.law[p].semi_axes(r[p]),
        )
    };
    let misfit = |_: &[f64], it: &InnerSolve| law.misfit(&it.forces, &it.gaps, &it.statuses);
    let map = ThresholdMap {
        threshold: &threshold,
        residual: &misfit,
        kind: ThresholdMapKind::NortonHoff,
    };
    let end = fixed_point(&mut inner, start, &map, opts)?;
    Ok(end.solution("norton_hoff_3d", inner.iterations, false))
}
