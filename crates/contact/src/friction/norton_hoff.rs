//! Norton–Hoff friction in 2D (course notes §4.1.4, eq. 19) by the fixed point
//! on its slip-dependent threshold, each inner problem a Tresca problem
//! solved by the status method.

use crate::delassus::DelassusProblem;
use crate::friction::fixed_point::ThresholdMap;
use crate::friction::status_tresca::StatusTresca;
use crate::law::norton_hoff::NortonHoffLaw;
use crate::law::FrictionLayout;
use crate::options::FrictionOptions;
use crate::solution::friction_iterate::InnerSolve;
use crate::solution::{ContactSolution, PointStatus, ThresholdMapKind};
use crate::ContactError;

/// Norton–Hoff friction (course notes §4.1.4, eq. 19) at the points whose law is
/// [`FrictionLaw::NortonHoff`] (the others stuck): λ_t = −μ λ_n |Δs|^(ρ−1) Δs, 0 < ρ < 1, i.e. a slip
/// with the tangential force of magnitude g = μ λ_n |Δs|^ρ opposing it (the
/// slip measured in the scene's length unit; Coulomb as ρ → 0). Solved as a
/// fixed point on that slip-dependent threshold, each inner problem a Tresca
/// problem (as §4.3 does for Coulomb); the map g → μ λ_n |Δs(g)|^ρ contracts
/// at a rate of order ρ. Started from the all-stick solution; it stops when
/// the law's misfit ([`NortonHoffLaw::misfit`]) vanishes at every point in
/// contact.
pub fn norton_hoff(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    initial: Vec<PointStatus>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    let mut solver = StatusTresca::new(problem, layout, initial, opts)?;
    let start = solver.stuck()?;
    let law = NortonHoffLaw::new(layout, opts);
    let threshold = |r: &[f64], g: &[f64]| law.thresholds(r, g, |radius| radius, |_| f64::INFINITY);
    let misfit = |_: &[f64], it: &InnerSolve| law.misfit(&it.forces, &it.gaps, &it.statuses);
    let map = ThresholdMap {
        threshold: &threshold,
        residual: &misfit,
        kind: ThresholdMapKind::NortonHoff,
    };
    solver.fixed_point(start, &map, "norton_hoff")
}
