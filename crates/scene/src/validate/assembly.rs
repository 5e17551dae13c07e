//! The checks of an assembly's entries: where a `[[boundary]]` entry acts
//! (`surface`, `point` or `nodes`), a tied contact, and the friction a load
//! step changes.

use super::{invalid, known, validate_friction, vector, Result};
use crate::types::{Boundary, Contact, Friction, Law, Scene};

/// Where boundary entry `e` acts: exactly one of `surface`, `point`,
/// `nodes`, none blank; a traction acts on a surface.
pub(super) fn validate_place(e: &str, bc: &Boundary, dim: usize) -> Result {
    let given = [bc.surface.is_some(), bc.point.is_some(), bc.nodes.is_some()]
        .iter()
        .filter(|x| **x)
        .count();
    if given != 1 {
        let what = if given == 0 {
            "give"
        } else {
            "give only one of"
        };
        return Err(invalid(
            e,
            format!("{what} `surface` (a surface of the body), `point` (the body's node at that point) or `nodes` (a physical group of the body's Gmsh file)"),
        ));
    }
    for (key, name) in [("surface", &bc.surface), ("nodes", &bc.nodes)] {
        if name.as_ref().is_some_and(|s| s.trim().is_empty()) {
            return Err(invalid(format!("{e}.{key}"), "must not be empty"));
        }
    }
    if let Some(p) = &bc.point {
        vector(&format!("{e}.point"), p, dim)?;
    }
    if bc.traction.is_some() && bc.surface.is_none() {
        return Err(invalid(
            format!("{e}.traction"),
            "a traction acts on a surface; give `surface`, or a total `force` on a point or node set",
        ));
    }
    Ok(())
}

/// A tied contact `e`: a deformable master, no friction (the tie holds every
/// direction), a gap from the coordinates.
pub(super) fn validate_tie(scene: &Scene, e: &str, c: &Contact) -> Result {
    if c.law != Law::Tied {
        return Ok(());
    }
    if scene.body(&c.master.body).is_some_and(|b| b.is_rigid()) {
        return Err(invalid(
            format!("{e}.master.body"),
            format!(
                "body \"{}\" is rigid; a tie joins two deformable surfaces (fix the surface with a [[boundary]] displacement instead)",
                c.master.body
            ),
        ));
    }
    if c.friction != Friction::None {
        return Err(invalid(
            format!("{e}.friction"),
            "a tied contact holds every direction; leave friction out (\"none\")",
        ));
    }
    Ok(())
}

/// `steps[i].friction`: each names a contact with friction, and gives a law
/// of the same kind (Tresca for Tresca; isotropic Coulomb with one coefficient,
/// its slip stiffness and roughness left out (kept) or the contact's own; one
/// coefficient: an elliptic cone keeps its own), valid like the contact's own.
pub(super) fn validate_step_friction(scene: &Scene) -> Result {
    let dim = scene.dimension as usize;
    let names: Vec<&str> = scene.contact.iter().map(|c| c.name.as_str()).collect();
    for (i, step) in scene.steps.iter().enumerate() {
        for (name, f) in &step.friction {
            let e = format!("steps[{i}].friction.{name}");
            let Some(c) = scene.contact.iter().find(|c| &c.name == name) else {
                return Err(invalid(
                    e,
                    format!(
                        "\"{name}\" is not the name of a [[contact]] entry; {}",
                        known(&names, "contact names", "[[contact]]")
                    ),
                ));
            };
            if !same_kind(&c.friction, f) {
                return Err(invalid(
                    e,
                    "a step changes the coefficient of the contact's friction law, not its kind: give { tresca = <threshold> } for a Tresca contact, { coulomb = <mu> } for an isotropic Coulomb one (one coefficient; slip_stiffness and roughness left out, kept from the contact, or equal to the contact's); a contact without friction has none to change",
                ));
            }
            validate_friction(&e, f, dim)?;
        }
    }
    Ok(())
}

/// Whether a step's `step` value of a key leaves the contact's `own`
/// unchanged: left out (kept) or given the same.
fn kept(own: &Option<f64>, step: &Option<f64>) -> bool {
    step.is_none() || step == own
}

/// Whether `step` changes the coefficient of `own` alone.
fn same_kind(own: &Friction, step: &Friction) -> bool {
    match (own, step) {
        (Friction::Tresca(_), Friction::Tresca(_)) => true,
        (
            Friction::Coulomb {
                coefficient: a,
                slip_stiffness: ka,
                roughness: qa,
            },
            Friction::Coulomb {
                coefficient: b,
                slip_stiffness: kb,
                roughness: qb,
            },
        ) => a.len() == 1 && b.len() == 1 && kept(ka, kb) && kept(qa, qb),
        _ => false,
    }
}
