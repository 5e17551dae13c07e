//! Tied contacts (`law = "tied"`): two surfaces bonded, the displacement
//! continuous in every direction, by the mortar equality constraints of
//! docs/theory/mortar.md. With the dual basis D is diagonal, so each slave
//! node's displacement is a combination of the master nodes' (the rows of
//! the 2D and 3D mortar pairings, `signorini_geometry::mortar`, `mortar3d`):
//!
//! ```text
//! u_j = Σ_l (M_jl / D_jj) u_l      (every component, each slave node j)
//! ```
//!
//! which the solver eliminates: a slave DOF is not an unknown of the
//! interface problem (`crate::ties`). On coincident nodes M = D and the tie
//! joins the nodes. Both surfaces' nodes are interface DOFs.

use signorini_geometry::mortar::mortar_pairing;
use signorini_geometry::mortar3d::mortar3d_pairing;
use signorini_geometry::quadratic_slave::{displacement_rows, mid_side_edges};
use signorini_geometry::{MasterGeometry, TermSide};
use signorini_scene as scene;
use std::collections::BTreeMap;

use super::{input, point_text, BodyModel};
use crate::error::SolveError;

/// One eliminated DOF: slave (body model, DOF) = Σ coef · master DOF.
#[derive(Debug, Clone)]
pub struct TiedDof {
    /// The tie (index in `scene.contact`).
    pub contact: usize,
    pub slave: (usize, usize),
    pub masters: Vec<(usize, usize, f64)>,
}

/// The tied DOFs of every tie of a scene, and the nodes of each body that
/// ties hold (interface nodes, never rotated into a contact frame).
#[derive(Debug, Clone, Default)]
pub struct Ties {
    pub dofs: Vec<TiedDof>,
    pub tied_node: Vec<Vec<bool>>,
}

/// The ties of the scene over the body models: each tied contact's slave
/// DOFs as combinations of its master's. Refused (naming the contact): a
/// slave node tied twice or a master node that another tie eliminates, a
/// slave node that does not face the master or lies away from it, a master
/// DOF prescribed to a non-zero value. A body whose supports leave it free
/// takes the supports of the body it is tied to (its rigid modes are held).
pub fn build_ties(sc: &scene::Scene, bodies: &mut [BodyModel]) -> Result<Ties, SolveError> {
    let mut ties = Ties {
        dofs: Vec::new(),
        tied_node: bodies
            .iter()
            .map(|b| vec![false; b.mesh.n_nodes()])
            .collect(),
    };
    let mut slave_of: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    let mut groups: Vec<usize> = (0..bodies.len()).collect();
    for (ci, c) in sc.contact.iter().enumerate() {
        if c.law != scene::Law::Tied {
            continue;
        }
        let entry = format!("contact \"{}\"", c.name);
        let (si, mi, rows) = tie_rows(sc, bodies, c, &entry)?;
        for (j, masters) in rows {
            if let Some(other) = slave_of.insert((si, j), ci) {
                return Err(overlap(&entry, sc, other, bodies, si, j));
            }
            ties.tied_node[si][j] = true;
            for &(l, _) in &masters {
                ties.tied_node[mi][l] = true;
            }
            let tied = (ci, si, j);
            eliminate(&mut ties.dofs, bodies, tied, mi, &masters, &entry)?;
        }
        join(&mut groups, si, mi);
    }
    for d in &ties.dofs {
        for &(b, dof, _) in &d.masters {
            if slave_of.contains_key(&(b, dof / bodies[b].mesh.dim)) {
                let ci = slave_of[&(b, dof / bodies[b].mesh.dim)];
                return Err(input(format!(
                    "contact \"{}\": a node of its slave surface is a master node of another tie (a chain of ties); make that surface the master of both",
                    sc.contact[ci].name
                )));
            }
        }
    }
    hold_tied_groups(bodies, &groups)?;
    Ok(ties)
}

impl Ties {
    /// The force of each tie's master on its slave (index in
    /// `scene.contact`, resultant): the sum over its slave DOFs of the
    /// residual K u − f − Bᵀλ there, `residual(body, DOF)`, which the tie
    /// balances. A slave DOF a support prescribes counts in its reaction.
    pub fn forces(
        &self,
        dim: usize,
        mut residual: impl FnMut(usize, usize) -> f64,
    ) -> Vec<(usize, Vec<f64>)> {
        let mut out: BTreeMap<usize, Vec<f64>> = BTreeMap::new();
        for d in &self.dofs {
            let (b, dof) = d.slave;
            out.entry(d.contact).or_insert_with(|| vec![0.0; dim])[dof % dim] += residual(b, dof);
        }
        out.into_iter().collect()
    }
}

/// The slave and master body models of a tie and, per slave node, its
/// master nodes with their weights M_jl / D_jj.
type TieRows = (usize, usize, Vec<(usize, Vec<(usize, f64)>)>);

fn tie_rows(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    c: &scene::Contact,
    entry: &str,
) -> Result<TieRows, SolveError> {
    let body = |name: &str, side: &str| {
        bodies.iter().position(|b| b.name == name).ok_or_else(|| {
            input(format!(
                "{entry}.{side}.body: \"{name}\" is not a deformable body"
            ))
        })
    };
    let (si, mi) = (
        body(&c.slave.body, "slave")?,
        body(&c.master.body, "master")?,
    );
    let surface = |b: usize, s: &scene::ContactSide, side: &str| {
        let name = s.surface.as_deref().unwrap_or_default();
        bodies[b]
            .mesh
            .surface(name)
            .map_err(|e| input(format!("{entry}.{side}.surface: body \"{}\": {e}", s.body)))
    };
    let (s_mesh, m_mesh) = (&bodies[si].mesh, &bodies[mi].mesh);
    let s_surf = surface(si, &c.slave, "slave")?;
    let master = MasterGeometry::Surface {
        mesh: m_mesh,
        surface: surface(mi, &c.master, "master")?,
    };
    let pairing = if sc.dimension == 3 {
        mortar3d_pairing(s_mesh, s_surf, &master)
    } else {
        mortar_pairing(s_mesh, s_surf, &master)
    }
    .map_err(|e| input(format!("{entry}: {e}")))?
    .pairing;
    let paired: std::collections::BTreeSet<usize> =
        pairing.points.iter().map(|p| p.slave_node).collect();
    if let Some(&j) = s_surf.nodes().iter().find(|n| !paired.contains(n)) {
        return Err(input(format!(
            "{entry}: slave node {} of surface \"{}\" does not face the master surface \"{}\": a tie bonds two surfaces that lie on each other; make the smaller surface the slave",
            point_text(&s_mesh.coords[j], s_mesh.dim),
            c.slave.surface.as_deref().unwrap_or_default(),
            c.master.surface.as_deref().unwrap_or_default()
        )));
    }
    let tolerance = 1e-6 * s_mesh.size().max(m_mesh.size());
    let mut rows = BTreeMap::new();
    for p in &pairing.points {
        let x = p.x;
        if p.gap0.abs() > tolerance {
            return Err(input(format!(
                "{entry}: slave node {} lies {:e} away from the master surface (more than {tolerance:e}): a tie bonds surfaces that touch; move the meshes together",
                point_text(&x, s_mesh.dim),
                p.gap0.abs()
            )));
        }
        let masters = p
            .terms
            .iter()
            .filter(|t| t.side == TermSide::Master)
            .map(|t| (t.node, -t.weight))
            .collect();
        rows.insert(p.slave_node, masters);
    }
    // A quadratic slave's mortar rows are those of its recombined
    // displacements: the nodes' own follow from them.
    let edges = mid_side_edges(s_mesh.dim, s_surf);
    let rows = displacement_rows(&rows, &edges);
    Ok((si, mi, rows.into_iter().collect()))
}

/// The tied DOFs of slave node `j` of body `si` (tie `ci`): each free component a
/// combination of the master's free DOFs (a master DOF held at zero drops
/// out; one prescribed to another value is refused).
fn eliminate(
    dofs: &mut Vec<TiedDof>,
    bodies: &[BodyModel],
    (ci, si, j): (usize, usize, usize),
    mi: usize,
    masters: &[(usize, f64)],
    entry: &str,
) -> Result<(), SolveError> {
    let dim = bodies[si].mesh.dim;
    for k in 0..dim {
        let d = j * dim + k;
        if bodies[si].prescribed[d] {
            continue;
        }
        let mut combination = Vec::new();
        for &(l, w) in masters {
            let md = l * dim + k;
            if bodies[mi].prescribed[md] {
                if bodies[mi].loads.iter().any(|ld| ld.displacement[md] != 0.0) {
                    return Err(input(format!(
                        "{entry}: master node {} is given a non-zero displacement; tie the surfaces where the supports hold them at zero, or prescribe the slave side",
                        point_text(&bodies[mi].mesh.coords[l], dim)
                    )));
                }
                continue;
            }
            combination.push((mi, md, w));
        }
        dofs.push(TiedDof {
            contact: ci,
            slave: (si, d),
            masters: combination,
        });
    }
    Ok(())
}

/// The error of a slave node that two ties eliminate.
fn overlap(
    entry: &str,
    sc: &scene::Scene,
    other: usize,
    bodies: &[BodyModel],
    b: usize,
    j: usize,
) -> SolveError {
    input(format!(
        "{entry}: its slave surface overlaps that of contact \"{}\": node {} of body \"{}\" would be tied twice; tie each part of a surface once",
        sc.contact[other].name,
        point_text(&bodies[b].mesh.coords[j], bodies[b].mesh.dim),
        bodies[b].name
    ))
}

/// Joins the groups of bodies `a` and `b` (union by the smaller index).
fn join(groups: &mut [usize], a: usize, b: usize) {
    let (ga, gb) = (groups[a], groups[b]);
    let (keep, drop) = (ga.min(gb), ga.max(gb));
    for g in groups.iter_mut() {
        if *g == drop {
            *g = keep;
        }
    }
}

/// The bodies of a tied group move together: when one of them is held by
/// its supports (no free rigid motion), so are the others (their rigid
/// modes are cleared). A group none of whose bodies is held is refused.
fn hold_tied_groups(bodies: &mut [BodyModel], groups: &[usize]) -> Result<(), SolveError> {
    for g in 0..bodies.len() {
        let members: Vec<usize> = (0..bodies.len()).filter(|&b| groups[b] == g).collect();
        if members.len() < 2 {
            continue;
        }
        if members.iter().any(|&b| bodies[b].kernel.is_empty()) {
            for &b in &members {
                bodies[b].kernel.clear();
            }
        } else {
            let names: Vec<String> = members
                .iter()
                .map(|&b| format!("\"{}\"", bodies[b].name))
                .collect();
            return Err(input(format!(
                "bodies[{}]: the tied bodies {} are all free to move: hold one of them by its supports (tied bodies held by contact alone are not supported)",
                bodies[members[0]].scene_index,
                names.join(", ")
            )));
        }
    }
    Ok(())
}
