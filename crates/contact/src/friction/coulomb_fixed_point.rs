//! Coulomb in 2D by the fixed point on the threshold g ← μ λ_n (course notes
//! §4.3), each inner problem a Tresca problem solved by the status method.

use crate::active_set::friction_status::thresholds_from;
use crate::delassus::DelassusProblem;
use crate::friction::fixed_point::{normal_change, ThresholdMap};
use crate::friction::status_tresca::StatusTresca;
use crate::law::FrictionLayout;
use crate::options::FrictionOptions;
use crate::solution::friction_iterate::InnerSolve;
use crate::solution::{ContactSolution, PointStatus, StopReason, ThresholdMapKind};
use crate::ContactError;

/// Coulomb by fixed point on the threshold g ← μ λ_n (course notes §4.3), stopping
/// when the normal forces no longer change. Without `start` (the previous
/// step's forces), the first threshold comes from the solution in which
/// every point initially closed sticks.
pub fn coulomb_fixed_point(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    initial: Vec<PointStatus>,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    let mut solver = StatusTresca::new(problem, layout, initial, opts)?;
    let start = match start {
        Some(f) => InnerSolve {
            forces: f.to_vec(),
            gaps: vec![0.0; f.len()],
            statuses: solver.run.statuses.clone(),
            converged: false,
            reason: StopReason::Pending,
        },
        None => solver.stuck()?,
    };
    let map = ThresholdMap {
        threshold: &|r, _| thresholds_from(layout, r),
        residual: &normal_change,
        kind: ThresholdMapKind::Coulomb,
    };
    solver.fixed_point(start, &map, "coulomb_fixed_point")
}
