//! The comparison of a run with its analytic reference (docs/theory/validation-cases.md):
//! the nodal pressures and forces handed to `signorini_report::reference`.

use crate::error::SolveError;
use crate::model::PointModel;
use crate::pressure::nodal_pressures;
use crate::root::point_force;
use crate::step::FrictionStep;
use signorini_contact::friction::PointStatus;
use signorini_report::{reference, StepReport};
use signorini_scene as scene;

pub(crate) fn contact_modulus(sc: &scene::Scene, body: &str) -> f64 {
    // 1/E* contribution of one body: (1 − ν²)/E in plane strain, 1/E in plane stress, 0 if rigid.
    let Some(b) = sc.body(body) else { return 0.0 };
    let Some(m) = b.material.as_deref().and_then(|n| sc.material(n)) else {
        return 0.0;
    };
    match sc.model {
        scene::Model::PlaneStress => 1.0 / m.young,
        _ => (1.0 - m.poisson * m.poisson) / m.young,
    }
}

/// The comparison of the final contact forces with the scene's analytic
/// reference (Hertz cylinder or sphere, flat punch, uniform pressure,
/// Cattaneo–Mindlin, sliding block); refuses a reference the scene's model
/// does not fit.
pub(crate) fn compare_reference(
    sc: &scene::Scene,
    r: &scene::Reference,
    points: &[PointModel],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
    steps: &[StepReport],
) -> Result<signorini_report::ReferenceReport, SolveError> {
    let Some(pmax) = (0..points.len()).max_by(|&a, &b| lambda[a].total_cmp(&lambda[b])) else {
        return Err(SolveError::Input(
            "reference: the scene has no contact point to compare".into(),
        ));
    };
    let direction = tangential_direction(points, friction, points[pmax].point.tangent);
    let mut nodes = reference_nodes(sc, points, lambda, friction, pmax, direction);
    check_reference(sc)?;
    let copies = r.symmetry.map_or(1.0, |s| s.copies());
    if copies != 1.0 {
        // each point stands for itself and its mirror images
        for n in &mut nodes {
            n.force *= copies;
            n.tributary *= copies;
        }
    }
    let first = sc
        .contact
        .first()
        .ok_or_else(|| SolveError::Input("reference: needs a [[contact]]".into()))?;
    let e_star =
        || 1.0 / (contact_modulus(sc, &first.slave.body) + contact_modulus(sc, &first.master.body));
    let radius = || {
        r.effective_radius().ok_or_else(|| {
            SolveError::Input(format!(
                "reference.radius: {} needs the radius",
                r.kind.as_str()
            ))
        })
    };
    let mu = || reference_mu(r, first, &points[pmax].point, direction);
    match r.kind {
        scene::ReferenceKind::HertzCylinder => {
            Ok(reference::hertz_cylinder(&nodes, e_star(), radius()?))
        }
        scene::ReferenceKind::HertzSphere => {
            let mut rep = reference::hertz_sphere(&nodes, e_star(), radius()?);
            if let Some(s) = r.symmetry {
                rep.notes.push(format!("symmetry = \"{}\": the load is {copies} times the computed resultant (the whole contact), radii are measured from reference.center", s.as_str()));
            }
            Ok(rep)
        }
        scene::ReferenceKind::UniformPressure => {
            Ok(reference::uniform_pressure(&nodes, r.pressure, None))
        }
        scene::ReferenceKind::CattaneoMindlin => Ok(reference::cattaneo_mindlin(
            &nodes,
            contact_shape(sc),
            e_star(),
            radius()?,
            mu()?,
            &tangential_history(steps, direction),
        )),
        scene::ReferenceKind::SlidingBlock => Ok(reference::sliding_block(&nodes, mu()?, None)),
        scene::ReferenceKind::FlatPunch => Ok(reference::flat_punch(
            &nodes,
            contact_shape(sc),
            r.half_width,
        )),
    }
}

/// The tangential load of the steps before the last, along the final one
/// (`direction`): the load history of the Cattaneo–Mindlin reference.
fn tangential_history(steps: &[StepReport], direction: [f64; 3]) -> Vec<f64> {
    steps[..steps.len().saturating_sub(1)]
        .iter()
        .map(|st| {
            (0..3)
                .map(|k| st.tangential_resultant[k] * direction[k])
                .sum()
        })
        .collect()
}

/// Refuses, before anything is solved, a reference the scene cannot be
/// compared with: no contact, a kind of another model (a cylinder's in an
/// axisymmetric or 3D model, a sphere's in a plane one, Cattaneo–Mindlin
/// about an axis), or without the radius or μ it needs (found by a fourth
/// robustness sweep: these were refused once the run had solved, and
/// `signorini check` called such scenes valid).
pub(crate) fn check_reference(sc: &scene::Scene) -> Result<(), SolveError> {
    let Some(r) = &sc.reference else {
        return Ok(());
    };
    let refuse = |m: &str| Err(SolveError::Input(m.to_string()));
    let Some(first) = sc.contact.first() else {
        return refuse("reference: needs a [[contact]]");
    };
    let plane = sc.dimension == 2 && sc.model != scene::Model::Axisymmetric;
    use scene::ReferenceKind as K;
    match r.kind {
        K::HertzCylinder if !plane => return refuse("reference.kind: \"hertz_cylinder\" is a plane strain / plane stress reference; for a sphere (3D or axisymmetric) use \"hertz_sphere\""),
        K::HertzSphere if plane => return refuse("reference.kind: \"hertz_sphere\" needs model = \"axisymmetric\" or dimension = 3; in plane strain use \"hertz_cylinder\""),
        K::CattaneoMindlin if sc.model == scene::Model::Axisymmetric => return refuse("reference.kind: \"cattaneo_mindlin\" needs a tangential load across the contact, which an axisymmetric model cannot carry; use plane strain / plane stress (cylinders) or dimension = 3 (spheres)"),
        _ => {}
    }
    let needs_radius = matches!(
        r.kind,
        K::HertzCylinder | K::HertzSphere | K::CattaneoMindlin
    );
    if needs_radius && r.effective_radius().is_none() {
        return Err(SolveError::Input(format!(
            "reference.radius: {} needs the radius",
            r.kind.as_str()
        )));
    }
    let coulomb = matches!(&first.friction, scene::Friction::Coulomb { coefficient, .. } if matches!(coefficient.len(), 1 | 2));
    if matches!(r.kind, K::CattaneoMindlin | K::SlidingBlock) && r.friction.is_none() && !coulomb {
        return Err(SolveError::Input(format!(
            "reference.friction: {} needs μ (or a Coulomb contact)",
            r.kind.as_str()
        )));
    }
    Ok(())
}

/// The shape of a contact the references see: a strip across the plane
/// models, a circle about the axis (axisymmetric) or in 3D.
fn contact_shape(sc: &scene::Scene) -> reference::PunchShape {
    match (sc.dimension, sc.model) {
        (2, m) if m != scene::Model::Axisymmetric => reference::PunchShape::Strip,
        _ => reference::PunchShape::Circle,
    }
}

/// The direction of the total tangential force of the contact points, or
/// `t` (the tangent of the most loaded point) where there is none.
fn tangential_direction(
    points: &[PointModel],
    friction: Option<&FrictionStep>,
    t: [f64; 3],
) -> [f64; 3] {
    let mut total_t = [0.0; 3];
    for (pi, p) in points.iter().enumerate() {
        let v = point_force(p, pi, 0.0, friction);
        (0..3).for_each(|k| total_t[k] += v[k]);
    }
    let norm_t = (total_t[0].powi(2) + total_t[1].powi(2) + total_t[2].powi(2)).sqrt();
    if norm_t > 0.0 {
        total_t.map(|x| x / norm_t)
    } else {
        t
    }
}

/// Each contact point as the reference sees it: its coordinate across the
/// contact, normal force, tributary measure, pressure, tangential force
/// (along t in 2D; in 3D its component along `direction`, that of the total
/// tangential force) and whether it sticks.
fn reference_nodes(
    sc: &scene::Scene,
    points: &[PointModel],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
    pmax: usize,
    direction: [f64; 3],
) -> Vec<reference::NodalPressure> {
    let coordinate = contact_coordinate(sc, points, lambda, pmax);
    let pressure = nodal_pressures(points, lambda);
    points
        .iter()
        .zip(lambda)
        .enumerate()
        .map(|(pi, (p, &l))| reference::NodalPressure {
            s: coordinate(p.point.x),
            force: l.max(0.0),
            tributary: p.tributary,
            pressure: pressure[pi].max(0.0),
            tangential: if sc.dimension == 3 {
                let v = point_force(&points[pi], pi, 0.0, friction);
                v[0] * direction[0] + v[1] * direction[1] + v[2] * direction[2]
            } else {
                friction.map_or(0.0, |f| f.tangential[pi])
            },
            // a point whose slip a support prescribes has no friction
            // unknown: held, its status is `contact`; dragged, `slip` (as in
            // contact.csv)
            stick: p.trow.is_some()
                && friction.is_some_and(|f| f.statuses[pi] == PointStatus::Stick),
            recombined: p.recombined_corners.map(|[c1, c2]| reference::Recombined {
                corners: [coordinate(c1), coordinate(c2)],
                alpha: signorini_geometry::quadratic_slave::ALPHA,
            }),
        })
        .collect()
}

/// The coordinate across the contact of a point at x: along the tangent of
/// the most loaded point `pmax` in 2D; the radius in an axisymmetric model;
/// in 3D the distance within the contact plane from `reference.center`, or
/// else from the force-weighted centre.
fn contact_coordinate<'a>(
    sc: &'a scene::Scene,
    points: &[PointModel],
    lambda: &[f64],
    pmax: usize,
) -> impl Fn([f64; 3]) -> f64 + 'a {
    let t = points[pmax].point.tangent;
    let n0 = points[pmax].point.normal;
    let total: f64 = lambda.iter().map(|l| l.max(0.0)).sum();
    let mut centre = [0.0; 3];
    for (p, &l) in points.iter().zip(lambda) {
        for (c, x) in centre.iter_mut().zip(p.point.x) {
            *c += l.max(0.0) * x / total.max(f64::MIN_POSITIVE);
        }
    }
    if let Some(c) = sc.reference.as_ref().and_then(|r| r.center.as_deref()) {
        centre = crate::model::point3(c);
    }
    move |x: [f64; 3]| -> f64 {
        match sc.model {
            scene::Model::Axisymmetric => x[0],
            scene::Model::Solid => {
                let d = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
                let dn = d[0] * n0[0] + d[1] * n0[1] + d[2] * n0[2];
                ((d[0] - dn * n0[0]).powi(2)
                    + (d[1] - dn * n0[1]).powi(2)
                    + (d[2] - dn * n0[2]).powi(2))
                .sqrt()
            }
            _ => x[0] * t[0] + x[1] * t[1],
        }
    }
}

/// The friction coefficient of a reference: its own μ, else that of the
/// first contact's Coulomb law in the direction of the tangential force —
/// μ, or on an elliptic cone (3D, μ₁ along t1, μ₂ along t2)
/// 1/‖(d₁/μ₁, d₂/μ₂)‖ with the tangents of the most loaded point `p`.
fn reference_mu(
    r: &scene::Reference,
    first: &scene::Contact,
    p: &signorini_geometry::ContactPoint,
    direction: [f64; 3],
) -> Result<f64, SolveError> {
    let directional = |c: &[f64]| -> Option<f64> {
        match c {
            [mu] => Some(*mu),
            [mu1, mu2] => {
                let d1: f64 = (0..3).map(|k| direction[k] * p.tangent[k]).sum();
                let d2: f64 = (0..3).map(|k| direction[k] * p.tangent2[k]).sum();
                Some(1.0 / ((d1 / mu1).powi(2) + (d2 / mu2).powi(2)).sqrt())
            }
            _ => None,
        }
    };
    r.friction
        .or(match &first.friction {
            scene::Friction::Coulomb { coefficient, .. } => directional(coefficient),
            _ => None,
        })
        .ok_or_else(|| {
            SolveError::Input(format!(
                "reference.friction: {} needs μ (or a Coulomb contact)",
                r.kind.as_str()
            ))
        })
}
