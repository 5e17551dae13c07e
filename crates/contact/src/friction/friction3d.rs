//! Friction in 3D on the condensed problem (course notes §4.1.1, §4.1.2, §4.3): each
//! frictional contact point has a normal force λ_n and a tangential force
//! λ_t = (λ_t1, λ_t2) in its tangent plane; the "gaps" of the two tangential
//! rows are the components (Δs1, Δs2) of the slip increment of the slave
//! relative to the master since the previous load step.
//!
//! Layout of the rows (forces and gaps, [`FrictionLayout`], shared with
//! 2D): rows 0..m are the normal rows of the m contact points (gap
//! g = g0 + B u ≥ 0, λ_n ≥ 0 compressive, λ_n g = 0); each frictional point p
//! has two further rows `tangent_rows[p] = [t1, t2]` (any rows ≥ m, each used
//! once), or one, `[t1]`, where a support prescribes the slip along the other
//! tangent (a node on a symmetry plane: the tangential force along t2 is then
//! a support reaction, not a friction unknown, and the admissible set is the
//! segment |λ_t1| ≤ g1). Sign convention: the tangential force opposes the
//! slip.
//!
//! Laws ([`crate::friction::FrictionLaw`]; threshold g for Tresca, μ λ_n for Coulomb; anisotropic Coulomb with
//! the elliptic section (λ_t1/μ1)² + (λ_t2/μ2)² ≤ λ_n², i.e. the semi-axes
//! g_i = μ_i λ_n):
//! - stick: λ_t inside the disc / ellipse and Δs = 0;
//! - slip: λ_t on its boundary and Δs = −γ ∇φ(λ_t), γ ≥ 0, with
//!   φ(λ_t) = (λ_t1/g1)² + (λ_t2/g2)² (maximum dissipation; isotropic:
//!   λ_t = −g Δs/‖Δs‖).
//!
//! With the thresholds fixed this is the convex program
//! min ½ rᵀ W r + qᵀ r over λ_n ≥ 0, λ_t in the disc / ellipse (plus the
//! equilibrium Gᵀ r = e of floating bodies). It is solved by the semi-smooth
//! Newton method on the Alart–Curnier projection equations
//! ([`crate::friction::semismooth_newton`], shared with 2D: unknowns the forces and
//! the rigid-mode amplitudes α, each step on the reduced system of its
//! statuses, an Armijo line search on ½‖F‖² and, without floating bodies,
//! an accelerated projected-gradient fallback). Coulomb is solved by the
//! same Newton method on Coulomb's law itself (the semi-axes μ_i λ_n of the
//! iterate, no outer fixed point), falling back to the fixed point on the
//! thresholds g ← μ λ_n (§4.3) when it does not converge.
//!
//! As with the 2D projection method ([`crate::friction::tresca_projection`]),
//! a Tresca point that opens may still carry a tangential force up to its
//! threshold (Tresca's law does not depend on the normal force); with
//! Coulomb the threshold of an open point is zero.

use crate::delassus::DelassusProblem;
use crate::law::FrictionLayout;
use crate::options::FrictionOptions;
use crate::ContactError;
use crate::ContactSolution;

/// Friction in 3D: Tresca (and frictionless) points in one convex solve,
/// Coulomb by the semi-smooth Newton method on Coulomb's law itself (no
/// outer fixed point), and where that does not converge by the fixed point
/// on the thresholds g ← μ λ_n (course notes §4.3, [`coulomb_3d_fixed_point`]);
/// see [`crate::friction::semismooth_newton::friction_newton`] for the start, the
/// stops and the rigid-mode amplitudes of floating bodies.
pub fn friction_3d(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    crate::friction::semismooth_newton::friction_newton(problem, layout, start, opts, 3, true)
}

/// Friction in 3D with Coulomb by the fixed point on the thresholds
/// g ← μ λ_n alone (course notes §4.3), each inner Tresca problem by the
/// semi-smooth Newton method: the reference of [`friction_3d`]'s direct
/// method, and its fallback.
pub fn coulomb_3d_fixed_point(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    crate::friction::semismooth_newton::friction_newton(problem, layout, start, opts, 3, false)
}

#[cfg(test)]
mod tests;
