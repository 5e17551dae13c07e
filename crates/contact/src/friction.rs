//! Friction on the condensed problem (course notes §4): each frictional contact
//! point has a normal force λ_n (row of B) and a tangential force λ_t (row of
//! T); the "gap" of a tangential row is the slip increment Δs of the slave
//! relative to the master along t since the previous load step (course notes §4.4:
//! the conditions hold on the totals, the slip on the increments).
//!
//! Laws, with the threshold g (Tresca, §4.1.1) or μ λ_n (Coulomb, §4.1.2):
//! stick |λ_t| < g and Δs = 0; slip |λ_t| = g and the slip opposes the
//! force, λ_t Δs ≤ 0. With g fixed this is the box-constrained problem
//! min ½ rᵀ W r + qᵀ r over λ_n ≥ 0, −g ≤ λ_t ≤ g (Tresca's energy theorem).
//!
//! The solvers, one file each:
//! - the friction status method (§4.5) and the Tresca problem by statuses:
//!   [`crate::active_set::friction_status`];
//! - [`tresca_projection()`]: Tresca as a box QP by MPRGP;
//! - [`coulomb_fixed_point()`]: the fixed point g ← μ λ_n (§4.3), each inner
//!   problem a Tresca problem (`status_tresca`); started from the previous
//!   step, or from the solution with every contact point stuck (so that a
//!   body held by friction alone can start: §4.3 notes that g = 0 cannot);
//! - [`contact_zone`]: any of the Coulomb methods on the points that can
//!   touch, the others checked open;
//! - [`norton_hoff()`]: Norton–Hoff's law by the fixed point on its threshold;
//! - [`coulomb_newton`]: the semi-smooth Newton method on the Alart–Curnier
//!   equations (`semismooth_newton`, shared with 3D); [`friction3d`] for 3D.
//!
//! Regularised Coulomb (§4.1.3, elastic slip k_e) is the same problem with
//! the compliance 1/k_e added to the tangential diagonal of W
//! ([`crate::DelassusProblem::add_compliance`]); with roughness (course notes §6,
//! linear kinematic hardening of the slip) the rough rows' unknown becomes
//! the slider force ([`kinematic_hardening`]).

pub mod contact_zone;
pub mod coulomb_fixed_point;
pub mod driver;
pub(crate) mod fixed_point;
pub mod friction3d;
pub mod holding;
pub mod kinematic_hardening;
pub mod norton_hoff;
pub mod nsgs;
pub(crate) mod semismooth_newton;
pub(crate) mod status_tresca;
pub mod tresca_projection;
pub use crate::law::{FrictionLaw, FrictionLayout};
pub use crate::options::FrictionOptions;
pub use crate::solution::PointStatus;
pub use coulomb_fixed_point::coulomb_fixed_point;
pub use norton_hoff::norton_hoff;
pub use semismooth_newton::coulomb::RETRY_RHO_SCALE;
pub use semismooth_newton::coulomb_newton;
pub use semismooth_newton::{
    merit, statuses, AlartCurnier, Dir, NewtonSystem, Scale, STALLED_AFTER, STALL_DECREASE,
};
pub use tresca_projection::tresca_projection;
