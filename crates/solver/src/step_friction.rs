//! The friction law of each contact point at a load step: `[[steps]]`
//! `friction = { <contact> = { coulomb = mu } }` (or `{ tresca = g }`) sets
//! the contact's coefficient from that step on
//! (docs/reference/scene-format.md, "Friction that changes with the step").
//! The law's kind, its slip stiffness and the tangential rows do not change;
//! the slip history carries over, so a point that stuck under μ₁ slips at
//! the first step whose μ₂ |λ_n| is below its tangential force.

use crate::model::{point_friction, PointModel};
use signorini_contact::friction::FrictionLaw;
use signorini_scene as scene;

/// Every point's friction law at load step `si` (0-based), or `None` when
/// no step of the scene changes a friction law (each point keeps its own).
pub(crate) fn step_laws(
    sc: &scene::Scene,
    points: &[PointModel],
    si: usize,
) -> Option<Vec<FrictionLaw>> {
    if sc.steps.iter().all(|s| s.friction.is_empty()) {
        return None;
    }
    let frictions = sc.step_frictions();
    let at = frictions.get(si).or(frictions.last())?;
    Some(
        points
            .iter()
            .map(|p| point_friction(&at[p.contact], p.tributary).0)
            .collect(),
    )
}
