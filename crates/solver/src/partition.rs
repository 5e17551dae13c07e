//! The model and partition stages: the bodies and contact points built from
//! the scene (every rank builds the same, deterministically: METIS runs with
//! a fixed seed), the METIS parts of each body, and the numbering of the
//! interface Γ.

use crate::contact_frames::ContactFrames;
use crate::error::SolveError;
use crate::model::{BodyModel, FixedPoint, PointModel};
use crate::subdomain::SubdomainSpec;
use crate::{memory, model, subdomain};
use signorini_scene as scene;

/// What the model and partition stages build, on every rank alike.
pub(crate) struct ModelData {
    pub bodies: Vec<BodyModel>,
    pub points: Vec<PointModel>,
    pub fixed: Vec<FixedPoint>,
    /// The points outside their contact's candidate zone (`zone`): not
    /// contact unknowns, checked after the solve.
    pub excluded: Vec<PointModel>,
    pub zone: model::Zone,
    /// Γ index of every body DOF (usize::MAX off Γ), and the size of Γ.
    /// On a node rotated into its contact frame ([`ContactFrames`]) the DOF
    /// of component 0 is the normal component, the others are off Γ.
    pub gamma_of: Vec<Vec<usize>>,
    /// The contact nodes condensed on their normal component only.
    pub frames: ContactFrames,
    pub n_gamma: usize,
    /// Owner part of every body node.
    pub owner_part: Vec<Vec<usize>>,
    pub specs: Vec<SubdomainSpec>,
    /// The scale of each load entry of each body at each step.
    pub scales: Vec<Vec<Vec<f64>>>,
    /// The tied DOFs (`law = "tied"`) and their elimination from Γ
    /// (`crate::ties`); `None` without a tie.
    pub ties: Option<crate::ties::TieReduction>,
    /// The tied DOFs themselves (the direct path eliminates them from its
    /// free DOFs).
    pub tied: model::Ties,
    /// What each contact of the scene keeps as unknowns (the memory
    /// estimate once the candidate zones are known).
    pub kept: Vec<memory::KeptContact>,
}

/// What each of the `contacts` keeps as unknowns: its contact points and
/// the DOFs of a deformable master their rows hold.
fn kept_contacts(points_of: &[PointModel], contacts: usize) -> Vec<memory::KeptContact> {
    let mut master: Vec<std::collections::HashSet<(usize, usize)>> =
        vec![Default::default(); contacts];
    let mut points = vec![0.0; contacts];
    for p in points_of {
        points[p.contact] += 1.0;
        let rows = [Some(&p.row), p.trow.as_ref(), p.trow2.as_ref()];
        for &(body, dof, _) in rows.into_iter().flatten().flatten() {
            if body != p.slave_body {
                master[p.contact].insert((body, dof));
            }
        }
    }
    points
        .into_iter()
        .zip(master)
        .map(|(points, m)| memory::KeptContact {
            points,
            master_dofs: m.len() as f64,
        })
        .collect()
}

/// Builds the bodies and the contact points (the candidates of `zone`, by
/// default the scene's), drops redundant constraints, partitions the bodies
/// over `ranks` (1 on the direct path) and numbers Γ; notes what a user
/// should know in `messages`.
pub(crate) fn model_stage(
    sc: &scene::Scene,
    ranks: usize,
    zone: Option<&model::Zone>,
    messages: &mut Vec<String>,
) -> Result<ModelData, SolveError> {
    let mut bodies = model::build_bodies(sc)?;
    let ties = model::build_ties(sc, &mut bodies)?;
    let scales = all_scales(sc, &bodies);
    let zone = zone
        .cloned()
        .unwrap_or_else(|| model::Zone::of_scene(sc, &bodies, &scales));
    let model::ContactSet {
        mut points,
        fixed,
        excluded,
    } = model::build_contacts(sc, &mut bodies, &zone, messages)?;
    messages.extend(model::eliminate_redundant(sc, &mut points));
    messages.extend(model::zone_notes(sc, &zone, &points, &excluded));
    if !fixed.is_empty() {
        messages.push(format!(
            "{} slave node(s) have every normal DOF prescribed: their gap is known and they are not contact unknowns",
            fixed.len()
        ));
    }
    for b in &bodies {
        if let Some(u) = crate::checks::unjoined(&b.mesh) {
            messages.push(format!("body \"{}\": {u}", b.name));
        }
        if !b.kernel.is_empty() {
            messages.push(format!(
                "body \"{}\" is held by contact in {} rigid motion(s): solved with the equilibrium of its rigid modes as a constraint (no artificial spring)",
                b.name,
                b.kernel.len()
            ));
        }
    }
    let (gamma_of, n_gamma, owner_part, frames) =
        interface_numbering(sc, &mut bodies, &points, &ties.tied_node, ranks)?;
    let reduction = crate::ties::TieReduction::new(&ties, &gamma_of, n_gamma);
    if frames.count() > 0 {
        messages.push(format!(
            "{} contact node(s) constrained along their normal only are condensed on that component alone (one interface DOF each)",
            frames.count()
        ));
    }
    let specs = subdomain::subdomain_specs(&bodies);
    let kept = kept_contacts(&points, sc.contact.len());
    Ok(ModelData {
        bodies,
        points,
        fixed,
        excluded,
        zone,
        gamma_of,
        frames,
        n_gamma,
        owner_part,
        specs,
        scales,
        kept,
        ties: reduction,
        tied: ties,
    })
}

/// The scale of each load entry of each body at each step.
pub(crate) fn all_scales(sc: &scene::Scene, bodies: &[BodyModel]) -> Vec<Vec<Vec<f64>>> {
    sc.step_scales()
        .iter()
        .map(|st| bodies.iter().map(|b| b.scales(sc, st)).collect())
        .collect()
}

/// How many METIS parts each body gets: its `subdomains` count, and for
/// `"auto"` bodies the ranks left over, shared in proportion to their cells.
pub(crate) fn parts_per_body(sc: &scene::Scene, bodies: &[BodyModel], ranks: usize) -> Vec<usize> {
    let fixed: usize = bodies
        .iter()
        .map(|b| match sc.bodies[b.scene_index].subdomains {
            scene::Subdomains::Count(n) => n,
            scene::Subdomains::Auto => 0,
        })
        .sum();
    let auto: Vec<usize> = (0..bodies.len())
        .filter(|&i| sc.bodies[bodies[i].scene_index].subdomains == scene::Subdomains::Auto)
        .collect();
    let spare = ranks.saturating_sub(fixed).max(auto.len());
    let cells: usize = auto.iter().map(|&i| bodies[i].mesh.cells.len()).sum();
    let mut out: Vec<usize> = bodies
        .iter()
        .map(|b| match sc.bodies[b.scene_index].subdomains {
            scene::Subdomains::Count(n) => n,
            scene::Subdomains::Auto => 1,
        })
        .collect();
    let mut given = 0;
    for (k, &i) in auto.iter().enumerate() {
        let share = if k + 1 == auto.len() {
            spare.saturating_sub(given)
        } else {
            ((spare as f64 * bodies[i].mesh.cells.len() as f64 / cells.max(1) as f64).round()
                as usize)
                .max(1)
        };
        // No more parts than cells: the ranks left over idle.
        out[i] = share.clamp(1, bodies[i].mesh.cells.len().max(1));
        given += out[i];
    }
    out
}

/// Partitions the bodies and numbers the interface Γ: the free DOFs of the
/// nodes on contact surfaces or shared between parts, body by body, a node
/// rotated into its contact frame by its normal component only. Returns
/// (Γ index of every body DOF, size of Γ, owner part of every node, frames).
pub(crate) fn interface_numbering(
    sc: &scene::Scene,
    bodies: &mut [BodyModel],
    points: &[PointModel],
    tied_node: &[Vec<bool>],
    ranks: usize,
) -> Result<InterfaceNumbering, SolveError> {
    let counts = parts_per_body(sc, bodies, ranks);
    let mut owner = Vec::new();
    let mut shared_all = Vec::new();
    for (b, &k) in bodies.iter_mut().zip(&counts) {
        if k > 1 {
            b.parts = signorini_mesh::partition::partition_cells(&b.mesh, k).map_err(|e| {
                SolveError::Input(format!("bodies[{}].subdomains: {e}", b.scene_index))
            })?;
        }
        b.n_parts = k;
        let mut shared = vec![false; b.mesh.n_nodes()];
        for s in signorini_mesh::partition::shared_nodes(&b.mesh, &b.parts) {
            shared[s] = true;
        }
        // tied nodes are on Γ in every component (`crate::ties`)
        let tied = tied_node.get(shared_all.len()).map_or(&[][..], |t| &t[..]);
        for (s, &t) in shared.iter_mut().zip(tied) {
            *s |= t;
        }
        let mut own = vec![usize::MAX; b.mesh.n_nodes()];
        for (c, cell) in b.mesh.cells.iter().enumerate() {
            for &v in &cell.nodes {
                own[v] = own[v].min(b.parts[c]);
            }
        }
        shared_all.push(shared);
        owner.push(own);
    }
    let frames = ContactFrames::decide(bodies, points, &shared_all);
    let mut gamma_of = Vec::new();
    let mut n = 0;
    for (bi, b) in bodies.iter().enumerate() {
        let dim = b.mesh.dim;
        let mut g = vec![usize::MAX; b.n_dof];
        for (d, gd) in g.iter_mut().enumerate() {
            let node = d / dim;
            let on_gamma = shared_all[bi][node] || b.contact_node[node];
            let rotated_tangent = d % dim != 0 && frames.normal(bi, node).is_some();
            if !b.prescribed[d] && on_gamma && !rotated_tangent {
                *gd = n;
                n += 1;
            }
        }
        gamma_of.push(g);
    }
    Ok((gamma_of, n, owner, frames))
}

/// Γ index of every body DOF, size of Γ, owner part of every body node.
pub(crate) type InterfaceNumbering = (Vec<Vec<usize>>, usize, Vec<Vec<usize>>, ContactFrames);
