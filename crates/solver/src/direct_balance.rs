//! The balance of the rigid motions of the bodies held by contact alone on
//! the direct path. The whole system factorises K + γI when a body floats
//! (`crate::kkt`, `crate::direct_newton`), so a load that the contacts
//! cannot balance (a tall block on friction alone pushed sideways at its
//! top: it tips) is still "solved": the body moves ever farther, its
//! contacts open but one, and γ u carries the rest of the load. The
//! equilibrium residual K u − f − Bᵀλ, scaled by |K||u|, does not see it.
//! A body's rigid motions r (the columns of its kernel) must satisfy
//! rᵀ (f + Bᵀλ) = 0 (docs/theory/validation-cases.md §5): this measures it
//! against the magnitude Σ |r_d| (|f_d| + |(Bᵀλ)_d|) of the forces along r,
//! at least the step's force scale.

use crate::model::{BodyModel, PointModel};
use crate::step::{contact_row_forces, FrictionStep};

/// Each body's contact force Bᵀλ on its DOFs: every point's normal row
/// times its normal force `lambda`, and with `friction` its tangential rows
/// times its tangential forces ([`contact_row_forces`]).
pub(crate) fn contact_forces(
    bodies: &[BodyModel],
    points: &[PointModel],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
) -> Vec<Vec<f64>> {
    let mut contact_force: Vec<Vec<f64>> = bodies.iter().map(|b| vec![0.0; b.n_dof]).collect();
    for (b, d, f) in contact_row_forces(points, lambda, friction) {
        contact_force[b][d] += f;
    }
    contact_force
}

/// The largest relative imbalance |rᵀ (f + Bᵀλ)| / max(Σ |r_d| (|f_d| +
/// |(Bᵀλ)_d|), F max |r_d|) over the rigid motions r of the bodies held by
/// contact alone (module doc), over their free DOFs; `f` each body's load
/// on its free DOFs (f − K u_p, in its free order), `contact` each body's
/// [`contact_forces`], `force_scale` F the step's force scale (a step that
/// unloads a body leaves forces of rounding size, measured against F, not
/// against themselves). 0 when no body floats.
pub(crate) fn rigid_motion_imbalance(
    bodies: &[BodyModel],
    f: &[&[f64]],
    contact: &[Vec<f64>],
    force_scale: f64,
) -> f64 {
    let mut worst = 0.0f64;
    for (bi, b) in bodies.iter().enumerate() {
        for r in &b.kernel {
            let (mut sum, mut size, mut largest) = (0.0, 0.0, 0.0f64);
            for (i, &d) in b.free.iter().enumerate() {
                let force = f[bi][i] + contact[bi][d];
                sum += r[d] * force;
                size += r[d].abs() * (f[bi][i].abs() + contact[bi][d].abs());
                largest = largest.max(r[d].abs());
            }
            let size = size.max(force_scale * largest);
            if size > 0.0 {
                worst = worst.max(sum.abs() / size);
            }
        }
    }
    worst
}
