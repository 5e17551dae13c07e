//! Norton–Hoff friction in 3D (seed §4.1.4, eq. 19) by the fixed point on
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
//! point; the map contracts at a rate of order ρ. A slip below 1e-14
//! times the length scale is no slip: the disc then has the floor's
//! radius μ λ_n (1e-14 L)^ρ (a zero slip would give a zero disc, from
//! which a stuck point could not load), and such a point satisfies the law
//! when its force lies within it (a law steep at zero slip, ρ small, needs
//! slips far below round-off to carry a force).

use super::coulomb::Newton;
use super::*;
use crate::friction::FrictionLaw;

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
        ..*newton
    };
    let s_min = 1e-14 * opts.gap_scale.max(f64::MIN_POSITIVE);
    // (μ λ_n, ρ, ‖Δs‖ floored) of a Norton–Hoff point with tangential rows.
    let law = |r: &[f64], g: &[f64], p: usize| -> Option<(f64, f64, f64)> {
        let FrictionLaw::NortonHoff { mu, rho } = layout.law[p] else {
            return None;
        };
        let rows = &layout.tangent_rows[p];
        let slip = rows.iter().map(|&t| g[t] * g[t]).sum::<f64>().sqrt();
        (!rows.is_empty()).then_some((mu * r[p].max(0.0), rho, slip.max(s_min)))
    };
    let threshold = |r: &[f64], g: &[f64]| -> Vec<[f64; 2]> {
        (0..layout.n_points())
            .map(|p| match law(r, g, p) {
                Some((bound, rho, slip)) => [bound * slip.powf(rho); 2],
                None => layout.law[p].semi_axes(r[p]),
            })
            .collect()
    };
    let misfit = |_: &[f64], it: &InnerSolve| {
        let (r, g) = (&it.forces, &it.gaps);
        let closed = (0..it.statuses.len()).filter(|&p| it.statuses[p] != PointStatus::Open);
        closed.fold(0.0f64, |worst, p| {
            let Some((bound, rho, slip)) = law(r, g, p) else {
                return worst;
            };
            let rows = &layout.tangent_rows[p];
            let off = match slip <= s_min {
                true => {
                    let force = rows.iter().map(|&t| r[t] * r[t]).sum::<f64>().sqrt();
                    (force - bound * s_min.powf(rho)).max(0.0)
                }
                false => {
                    let scale = bound * slip.powf(rho - 1.0);
                    let off = rows.iter().map(|&t| (r[t] + scale * g[t]).powi(2));
                    off.sum::<f64>().sqrt()
                }
            };
            crate::norms::nan_max(worst, off)
        })
    };
    let map = ThresholdMap {
        threshold: &threshold,
        residual: &misfit,
        kind: ThresholdMapKind::NortonHoff,
    };
    let end = fixed_point(&mut inner, start, &map, opts)?;
    Ok(end.solution("norton_hoff_3d", inner.iterations, false))
}
