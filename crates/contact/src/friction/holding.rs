//! Whether friction can hold the floating bodies at all: a rigid motion of
//! a body held by its contacts alone (a column r of G, Gᵀ λ = e) that moves
//! none of its contact points along their normals (a translation or a
//! rotation in the plane of flat contacts: the normal forces, free in the
//! inner Tresca problems, do no work along it) is in equilibrium only if
//! its load e_r (less the round-off of the normal rows) is within what the tangential forces can
//! carry along it, Σ_p max over the point's admissible set of
//! (G_t1 λ_t1 + G_t2 λ_t2) = Σ_p ‖(g1 G_t1, g2 G_t2)‖ (g_i the semi-axes of
//! the point's disc or ellipse: μ_i λ_n for Coulomb). Beyond it no static
//! equilibrium exists (a body pushed past its friction under force
//! control), and no friction solver converges: this says so instead.

use crate::delassus::DelassusProblem;
use crate::law::FrictionLayout;
use crate::solution::StopReason;

/// The relative excess of the load over the capacity below which a mode is
/// not called overloaded (the normal forces are those of an iterate).
const OVERLOAD_MARGIN: f64 = 1e-3;

/// A load below this fraction of the terms of its mode's equilibrium is
/// round-off.
const ROUND_OFF: f64 = 1e-9;

/// The rigid motion most overloaded (largest load over capacity) at the
/// normal forces `forces[..m]` with the semi-axes `axes` of the points'
/// admissible sets, as [`StopReason::FrictionOverload`]; `None` when every
/// rigid motion is within what friction holds (or there is none).
pub fn friction_overload(
    problem: &DelassusProblem,
    layout: &FrictionLayout,
    forces: &[f64],
    axes: &[[f64; 2]],
) -> Option<StopReason> {
    let g = &problem.g_mat;
    let m = layout.n_points();
    let mut worst: Option<(f64, StopReason)> = None;
    for j in 0..g.ncols() {
        if !tangential_mode(g, layout, j) {
            continue;
        }
        let normal_terms = (0..m).map(|p| g[(p, j)] * forces[p].max(0.0));
        let normal: f64 = normal_terms.clone().sum();
        // the size of the terms of the mode's equilibrium: its load is
        // round-off below it (a mode held by the normal forces alone)
        let scale = normal_terms.map(f64::abs).sum::<f64>() + problem.e[j].abs();
        let load = problem.e[j] - normal;
        let capacity: f64 = (0..m)
            .map(|p| {
                let rows = &layout.tangent_rows[p];
                let reach = |i: usize| rows.get(i).map_or(0.0, |&r| axes[p][i] * g[(r, j)]);
                let c = reach(0).hypot(reach(1));
                if c.is_finite() {
                    c
                } else {
                    f64::INFINITY
                }
            })
            .sum();
        let excess = load.abs() - capacity * (1.0 + OVERLOAD_MARGIN);
        if excess > ROUND_OFF * scale
            && worst
                .as_ref()
                .is_none_or(|(r, _)| load.abs() / capacity > *r)
        {
            let reason = StopReason::FrictionOverload {
                mode: j,
                load: load.abs(),
                capacity,
            };
            worst = Some((load.abs() / capacity, reason));
        }
    }
    worst.map(|(_, r)| r)
}

/// Whether rigid mode j moves the contact points along their tangents only
/// (its normal rows of G round-off against its tangential ones).
fn tangential_mode(g: &faer::Mat<f64>, layout: &FrictionLayout, j: usize) -> bool {
    let m = layout.n_points();
    let normal: f64 = (0..m).map(|p| g[(p, j)].abs()).sum();
    let tangential: f64 = (m..g.nrows()).map(|r| g[(r, j)].abs()).sum();
    tangential > 0.0 && normal <= 1e-9 * tangential
}
