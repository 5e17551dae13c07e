//! Checks of a body held by contact alone before its solve: its load must be
//! one its contacts can balance (they only push), and, on a flat frictional
//! contact under force control, within what friction can hold.

use crate::error::SolveError;
use crate::model::{BodyModel, PointModel};
use faer::Mat;
use signorini_contact::equilibrium::nnls;
use signorini_contact::friction::FrictionLaw;
use signorini_scene as scene;

/// The fraction of the local element size (tributary length) beyond which a
/// penalty penetration is warned about.
pub const PENETRATION_WARNING_FRACTION: f64 = 0.01;

/// ‖v‖∞ (0 for an empty v, NaN when some vᵢ is NaN).
pub(crate) fn inf_norm(v: &[f64]) -> f64 {
    signorini_contact::norms::max_abs(v)
}

/// A body held by contact needs compressive contact forces that balance the
/// load on its free rigid motions: Gᵀλ = e with λ ≥ 0, G = B R, e = −Rᵀ F
/// (see [`signorini_contact::equilibrium`]). Otherwise it cannot be in
/// equilibrium: bad input, exit 1, with the unbalanced resultant. `e[bi]` is
/// computed by the caller from its own load representation (the condensed
/// load on Γ or the load on the free DOFs: both give the same work on R).
/// That the contacts can hold every free rigid motion at all does not
/// depend on the load: [`check_held_by_contacts`] checked it once, before
/// the solve.
pub(crate) fn check_floating_equilibrium(
    bodies: &[BodyModel],
    points: &[PointModel],
    e_of: &[Vec<f64>],
    resultant: &[Vec<f64>],
    step: usize,
) -> Result<(), SolveError> {
    let friction = points.iter().any(|p| p.trow.is_some());
    for (bi, b) in bodies.iter().enumerate() {
        if b.kernel.is_empty() {
            continue;
        }
        let gt = contact_on_rigid_modes(bi, b, points).gt;
        let e = &e_of[bi];
        let fr = &resultant[bi];
        let fmax = inf_norm(e).max(inf_norm(fr));
        // Compressive normal forces alone must balance the load unless
        // friction can help (then the friction solve itself decides).
        let res = if friction { 0.0 } else { nnls(&gt, e).1 };
        if friction {
            check_friction_capacity(b, points, bi, fr, step)?;
        }
        if res > 1e-8 * fmax.max(f64::MIN_POSITIVE) {
            return Err(SolveError::Input(format!(
                "bodies[{}]: body \"{}\" cannot be in equilibrium at step {}: it has no support against {} rigid motion(s), and its external load (resultant {}) cannot be balanced by its contacts, which can only push along their normals; add a [[boundary]] displacement that holds it, or change the load",
                b.scene_index,
                b.name,
                step + 1,
                b.kernel.len(),
                fmt_vector(fr)
            )));
        }
    }
    Ok(())
}

/// Every rigid motion left free by a body's supports must be one its
/// contacts can hold, whatever the load: checked once the contact points
/// are known, before anything is factorised (on the condensed path a body
/// that no contact touches would otherwise end in a singular K_II).
pub(crate) fn check_held_by_contacts(
    bodies: &[BodyModel],
    points: &[PointModel],
) -> Result<(), SolveError> {
    for (bi, b) in bodies.iter().enumerate() {
        if !b.kernel.is_empty() {
            check_held(b, &contact_on_rigid_modes(bi, b, points))?;
        }
    }
    Ok(())
}

/// NSGS solves Coulomb's law point by point: on the condensed path,
/// `solver.friction = "nsgs"` with a Tresca or Norton–Hoff contact, or with
/// a body held by contact alone (whose equilibrium couples all its points),
/// is refused (exit 1, nothing written) naming the contact or the body and
/// what solves it, instead of failing inside the solve.
pub(crate) fn check_nsgs(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
) -> Result<(), SolveError> {
    let frictional = points.iter().any(|p| p.trow.is_some());
    if !frictional || sc.solver.friction != scene::FrictionSolver::Nsgs {
        return Ok(());
    }
    let other_law = sc.contact.iter().find(|c| {
        matches!(
            c.friction,
            scene::Friction::Tresca(_) | scene::Friction::NortonHoff { .. }
        )
    });
    if let Some(c) = other_law {
        return Err(SolveError::Input(format!(
            "solver.friction = \"nsgs\": contact \"{}\" has Tresca or Norton–Hoff friction, and NSGS solves Coulomb's law only; use friction = \"newton\" or \"fixed_point\" (the default)",
            c.name
        )));
    }
    match bodies.iter().find(|b| !b.kernel.is_empty()) {
        Some(b) => Err(SolveError::Input(format!(
            "solver.friction = \"nsgs\": body \"{}\" is held by its contacts alone, whose equilibrium couples all its contact points, which NSGS solves one by one; use friction = \"newton\" or \"fixed_point\" (the default), path = \"direct\", or a support that holds the body",
            b.name
        ))),
        None => Ok(()),
    }
}

/// Gᵀ of a body: the work of each contact force (normal columns 0..m, then
/// the tangential ones when some point has friction) on each of its free
/// rigid modes; and the matrix Gᵀ would be if every force pointed along
/// the motion of its node (Σ |c| ‖r_j(node)‖ per entry): the absolute scale
/// of its rank test.
fn contact_on_rigid_modes(bi: usize, b: &BodyModel, points: &[PointModel]) -> HoldingWork {
    let friction = points.iter().any(|p| p.trow.is_some());
    let m = points.len();
    let dim = b.mesh.dim;
    let mut gt = Mat::<f64>::zeros(b.kernel.len(), m * if friction { 3 } else { 1 });
    let mut aligned = gt.clone();
    for (pi, p) in points.iter().enumerate() {
        // Tangential forces hold rigid motions too (bounded by friction).
        let rows = [Some(&p.row), p.trow.as_ref(), p.trow2.as_ref()];
        for (block, row) in rows.into_iter().enumerate() {
            for &(pb, d, c) in row.into_iter().flatten() {
                if pb == bi {
                    let node = d - d % dim..d - d % dim + dim;
                    for (j, r) in b.kernel.iter().enumerate() {
                        gt[(j, block * m + pi)] += c * r[d];
                        let motion = r[node.clone()].iter().map(|v| v * v).sum::<f64>();
                        aligned[(j, block * m + pi)] += c.abs() * motion.sqrt();
                    }
                }
            }
        }
    }
    HoldingWork { gt, aligned }
}

/// Gᵀ of a body and its aligned counterpart (see [`contact_on_rigid_modes`]).
struct HoldingWork {
    gt: Mat<f64>,
    aligned: Mat<f64>,
}

impl HoldingWork {
    /// The same with the first `cols` columns only (the normal forces).
    fn normal(&self, cols: usize) -> Self {
        Self {
            gt: self.gt.subcols(0, cols).to_owned(),
            aligned: self.aligned.subcols(0, cols).to_owned(),
        }
    }
}

/// Refuses a body with rigid motions that no contact can hold.
fn check_held(b: &BodyModel, work: &HoldingWork) -> Result<(), SolveError> {
    let unheld = unheld_modes(work)?;
    if unheld > 0 {
        return Err(SolveError::Input(format!(
            "bodies[{}]: body \"{}\" is free to move: {unheld} of its rigid motions are prevented neither by a support nor by its contacts (frictionless contact only holds along the normals); add a [[boundary]] displacement that pins it (e.g. a point with x = 0){}",
            b.scene_index,
            b.name,
            unjoined(&b.mesh)
                .map(|u| format!(". But first: {u}"))
                .unwrap_or_default()
        )));
    }
    Ok(())
}

/// What to say of a body whose mesh has distinct nodes at the same place:
/// its cells on either side are not joined, so its parts move apart (a pin
/// would not make them one solid); `None` when it has none.
pub(crate) fn unjoined(mesh: &signorini_mesh::Mesh) -> Option<String> {
    let pairs = mesh.coincident_nodes();
    let &(a, b) = pairs.first()?;
    let x = mesh.coords[a];
    let at = match mesh.dim {
        3 => format!("({}, {}, {})", x[0], x[1], x[2]),
        _ => format!("({}, {})", x[0], x[1]),
    };
    Some(format!(
        "its mesh has {} pair(s) of distinct nodes at the same place (the first: nodes {a} and {b} at {at}), so the cells on either side are not joined and its parts move apart; if they are one solid, merge those nodes (Gmsh: Coherence Mesh, or fragment the geometry before meshing), or make each part its own body with a contact between them",
        pairs.len()
    ))
}

/// The rigid motions that the forces of Gᵀ's columns cannot hold: the
/// dimension of its null space, by a rank test of G Gᵀ scaled by the
/// largest of its eigenvalues and of what forces along the motions would
/// give (‖aligned‖²_F). Relative to its own eigenvalues alone, a single free
/// motion that the contacts only touch by round-off (a plane whose normal
/// is across the motion: Gᵀ ~ 1e-17) passed as held, and its equilibrium
/// was solved with forces of 1e18.
fn unheld_modes(work: &HoldingWork) -> Result<usize, SolveError> {
    let gt = &work.gt;
    let k = gt.nrows();
    let ggt = gt * gt.transpose();
    let eig = ggt
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|e| SolveError::Internal(format!("eigen decomposition of G Gᵀ: {e:?}")))?;
    let emax = (0..k).fold(0.0f64, |a, j| a.max(eig.S()[j]));
    let scale = emax.max(work.aligned.squared_norm_l2());
    Ok((0..k)
        .filter(|&j| eig.S()[j] <= 1e-12 * scale || scale == 0.0)
        .count())
}

/// The bodies whose supports leave rigid motions that only friction holds
/// (their normal contact forces alone cannot), with how many: a load
/// along them beyond what friction carries has no static equilibrium.
pub(crate) fn held_by_friction(
    bodies: &[BodyModel],
    points: &[PointModel],
) -> Vec<(String, usize)> {
    let m = points.len();
    bodies
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.kernel.is_empty())
        .filter_map(|(bi, b)| {
            let work = contact_on_rigid_modes(bi, b, points);
            let by_normal = unheld_modes(&work.normal(m)).ok()?;
            let by_all = unheld_modes(&work).ok()?;
            (by_normal > by_all).then(|| (b.name.clone(), by_normal - by_all))
        })
        .collect()
}

/// A floating body whose every contact is frictional and flat (every
/// contact point of the body, as slave or as master, with the same normal
/// seen from the body), free to translate along that normal and along the
/// tangential part R_t of its load resultant R, needs ‖R_t‖ ≤ μ |R·n|
/// (docs/theory/validation-cases.md §5: under force control a body pushed past its friction
/// has no static equilibrium). Exit 1 with the numbers otherwise, instead of
/// a failing friction solve. When any contact of the body is frictionless,
/// or pushes along another direction, that contact may carry the rest: the
/// solver decides.
pub(crate) fn check_friction_capacity(
    b: &BodyModel,
    points: &[PointModel],
    bi: usize,
    resultant: &[f64],
    step: usize,
) -> Result<(), SolveError> {
    // Every contact point acting on the body, with its normal turned
    // towards the body (the point's normal points from master to slave).
    let own: Vec<(&PointModel, [f64; 3])> = points
        .iter()
        .filter_map(|p| {
            let sign = if p.slave_body == bi {
                1.0
            } else if p.row.iter().any(|&(pb, _, _)| pb == bi) {
                -1.0
            } else {
                return None;
            };
            Some((p, p.point.normal.map(|x| sign * x)))
        })
        .collect();
    let Some(&(_, n)) = own.first() else {
        return Ok(());
    };
    let flat = own
        .iter()
        .all(|(_, m)| (0..3).all(|k| (m[k] - n[k]).abs() <= 1e-9));
    let mu = own.iter().try_fold(0.0f64, |m, (p, _)| match p.friction {
        FrictionLaw::Coulomb { mu: [mu, mu2] } if p.trow.is_some() => Some(m.max(mu).max(mu2)),
        _ => None,
    });
    let (true, Some(mu)) = (flat, mu) else {
        return Ok(());
    };
    let dim = b.mesh.dim;
    let r: Vec<f64> = (0..3)
        .map(|k| resultant.get(k).copied().unwrap_or(0.0))
        .collect();
    let rn: f64 = (0..3).map(|k| r[k] * n[k]).sum();
    let rt: Vec<f64> = (0..3).map(|k| r[k] - rn * n[k]).collect();
    let rt_norm = rt.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = rn.abs().max(rt_norm).max(f64::MIN_POSITIVE);
    // The translations along R_t and along n must be free (no prescribed DOF
    // along them): otherwise a support carries part of the load, and the
    // normal force is not known from the load alone.
    let free_along = (0..b.n_dof)
        .filter(|&d| b.prescribed[d])
        .all(|d| rt[d % dim].abs() <= 1e-12 * scale && n[d % dim].abs() <= 1e-12);
    if free_along && rt_norm > mu * (-rn).max(0.0) * (1.0 + 1e-9) + 1e-12 * scale {
        return Err(SolveError::Input(format!(
            "bodies[{}]: body \"{}\" cannot be in equilibrium at step {}: the tangential part of its load, {rt_norm:e}, exceeds what friction can hold, μ|N| = {:e} (μ = {mu}, normal load {:e}); a body pushed past its friction under force control has no static equilibrium: impose a tangential displacement instead, or add a support",
            b.scene_index,
            b.name,
            step + 1,
            mu * (-rn).max(0.0),
            -rn
        )));
    }
    Ok(())
}

/// `(a, b, c)` with every component in `{:e}`.
pub(crate) fn fmt_vector(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
    format!("({})", parts.join(", "))
}

/// The failure of a step whose load friction cannot hold
/// ([`signorini_contact::StopReason::FrictionOverload`]): the floating body
/// of rigid mode `mode` (the columns of G: the bodies' kernels in body
/// order), the frictional contacts that act on it, what their friction can
/// hold, the sum of μ λ_n of their points at the normal forces `lambda`,
/// and its tangential load, that sum times the ratio of the mode's load to
/// its capacity (for a translation, its force along it).
pub(crate) fn friction_overload_message(
    sc: &scene::Scene,
    (bodies, points): (&[BodyModel], &[PointModel]),
    (step, method): (usize, &str),
    lambda: &[f64],
    (mode, load, capacity): (usize, f64, f64),
) -> String {
    let mut first = 0;
    let found = bodies.iter().position(|b| {
        first += b.kernel.len();
        mode < first
    });
    let Some(bi) = found else {
        let reason = signorini_contact::StopReason::FrictionOverload {
            mode,
            load,
            capacity,
        };
        return format!("step {}: {method} stopped: {reason}", step + 1);
    };
    let mut contacts: Vec<&str> = Vec::new();
    let mut holds = 0.0;
    // the laws of the step (a step may change a coefficient)
    let laws = crate::step_friction::step_laws(sc, points, step);
    let on_body = |p: &&PointModel| p.slave_body == bi || p.row.iter().any(|&(pb, _, _)| pb == bi);
    for (pi, p) in points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.trow.is_some() && on_body(p))
    {
        let name = sc.contact[p.contact].name.as_str();
        if !contacts.contains(&name) {
            contacts.push(name);
        }
        let law = laws.as_ref().map_or(p.friction, |l| l[pi]);
        holds += law.semi_axes(lambda[pi])[0];
    }
    format!(
        "step {}: {method} stopped: the load friction cannot hold: body \"{}\" is held by its contacts alone along a rigid motion its supports leave free, and its tangential load along it, {:.4e}, exceeds what the friction of its contact points can hold, the sum of μ λ_n over contact(s) \"{}\", {holds:.4e}: no static equilibrium exists; impose that motion (a displacement) instead of a force, or keep the load below μ N",
        step + 1,
        bodies[bi].name,
        holds * load / capacity.max(f64::MIN_POSITIVE),
        contacts.join("\", \"")
    )
}
