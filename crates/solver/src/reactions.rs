//! What a step's supports and contacts carry (docs/reference/scene-format.md,
//! "steps.csv" and the report's steps): the reaction of every
//! prescribed-displacement boundary entry, and the sums of every contact
//! pair.
//!
//! The reaction of an entry is the force its support exerts on the body,
//! R = K u − f − Bᵀλ summed over the DOFs the entry prescribes: K u − f
//! comes from whoever holds the stiffness (each subdomain on its own DOFs,
//! summed here; the whole stiffness on the direct path), and the contact
//! forces on those DOFs (a contact row that reaches a prescribed DOF) are
//! taken out here. A body in equilibrium then has Σ R + Σ f + its contact
//! force = 0: the reaction of a face that presses a body onto another is
//! minus the contact force it transmits.

use signorini_report::{Reaction, StepContact};
use signorini_scene as scene;

use crate::model::{BodyModel, PointModel};
use crate::root::{net_force, point_force};
use crate::step::{contact_row_forces, FrictionStep};

/// The reaction of every prescribed-displacement entry of the scene at one
/// step, from `support` (K u − f on prescribed DOFs, as (body, DOF, value),
/// repeated entries summed) and the step's contact forces.
pub(crate) fn step_reactions(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    support: &[(usize, usize, f64)],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
) -> Vec<Reaction> {
    let dim = sc.dimension as usize;
    let entries: Vec<usize> = (0..sc.boundary.len())
        .filter(|&li| sc.boundary[li].displacement.is_some())
        .collect();
    let mut slot = vec![usize::MAX; sc.boundary.len()];
    for (k, &li) in entries.iter().enumerate() {
        slot[li] = k;
    }
    let about: Vec<[f64; 3]> = entries.iter().map(|&li| moment_point(sc, li)).collect();
    let mut force = vec![[0.0f64; 3]; entries.len()];
    let mut moment = vec![[0.0f64; 3]; entries.len()];
    let contact = contact_on_supports(bodies, points, lambda, friction);
    let nodal = support.iter().copied().chain(contact);
    for (b, d, v) in nodal {
        let Some(li) = bodies[b].support_of[d] else {
            continue; // the axis of an axisymmetric model
        };
        let k = slot[li];
        let x = bodies[b].mesh.coords[d / dim];
        let r = [0, 1, 2].map(|j| x[j] - about[k][j]);
        let mut f = [0.0; 3];
        f[d % dim] = v;
        for j in 0..3 {
            force[k][j] += f[j];
            moment[k][j] += r[(j + 1) % 3] * f[(j + 2) % 3] - r[(j + 2) % 3] * f[(j + 1) % 3];
        }
    }
    let axisymmetric = sc.model == scene::Model::Axisymmetric;
    (entries.iter().enumerate())
        .map(|(k, &li)| {
            let entry = &sc.boundary[li];
            let moment = match dim {
                2 => vec![moment[k][2]],
                _ => moment[k].to_vec(),
            };
            Reaction {
                boundary: entry.name.clone().unwrap_or(format!("boundary[{li}]")),
                body: entry.body.clone(),
                force: net_force(sc.model, force[k][..dim].to_vec()),
                moment: (!axisymmetric).then_some(moment),
                moment_about: (!axisymmetric).then(|| about[k][..dim].to_vec()),
            }
        })
        .collect()
}

/// The point of entry `li`'s moment: its `moment_about`, else the origin.
fn moment_point(sc: &scene::Scene, li: usize) -> [f64; 3] {
    sc.boundary[li]
        .moment_about
        .as_deref()
        .map_or([0.0; 3], crate::model::point3)
}

/// Minus the contact forces on prescribed DOFs, as (body, DOF, value): the
/// normal rows times λ_n, and the tangential rows (those with a friction
/// unknown, and those a support drags) times the tangential forces.
fn contact_on_supports<'a>(
    bodies: &'a [BodyModel],
    points: &'a [PointModel],
    lambda: &'a [f64],
    friction: Option<&'a FrictionStep>,
) -> impl Iterator<Item = (usize, usize, f64)> + 'a {
    contact_row_forces(points, lambda, friction)
        .filter(|&(b, d, _)| bodies[b].prescribed[d])
        .map(|(b, d, f)| (b, d, -f))
}

/// Every contact pair's sums at one step: the normal and tangential forces
/// of its points and its resultant force on the slaves.
pub(crate) fn step_contacts(
    sc: &scene::Scene,
    points: &[PointModel],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
) -> Vec<StepContact> {
    let dim = sc.dimension as usize;
    let mut contacts: Vec<StepContact> = (sc.contact.iter())
        .map(|c| StepContact {
            name: c.name.clone(),
            normal_force: 0.0,
            tangential_force: 0.0,
            tangential_force_2: (dim == 3).then_some(0.0),
            force: vec![0.0; dim],
        })
        .collect();
    for (pi, p) in points.iter().enumerate() {
        let c = &mut contacts[p.contact];
        c.normal_force += lambda[pi];
        if let Some(f) = friction {
            c.tangential_force += f.tangential[pi];
            if let Some(t2) = c.tangential_force_2.as_mut() {
                *t2 += f.tangential2[pi];
            }
        }
        let force = point_force(p, pi, lambda[pi], friction);
        for (total, fk) in c.force.iter_mut().zip(force) {
            *total += fk;
        }
    }
    for c in &mut contacts {
        c.force = net_force(sc.model, std::mem::take(&mut c.force));
    }
    contacts
}
