//! From a scene to the discrete model: one [`BodyModel`] per deformable body
//! (mesh, stiffness, DOF classes, loads per boundary entry, rigid-body kernel)
//! and the contact points with their rows over the bodies' DOFs.

use faer::{Mat, Side};
use signorini_contact::geometry::{node_to_node_pairing, node_to_segment_pairing};
use signorini_contact::{ContactPoint, MasterGeometry, NormalRule, TermSide};
use signorini_fem::{Elasticity, Formulation as FemFormulation, Model as FemModel};
use signorini_mesh::generators::{
    box_mesh, half_disk, hemisphere, quarter_disk, rectangle, BoxSide, RectSide,
};
use signorini_mesh::{CellKind, Mesh};
use signorini_scene as scene;

use crate::SolveError;

fn input(msg: impl Into<String>) -> SolveError {
    SolveError::Input(msg.into())
}

/// A load entry acting on one body, linear in its scale.
pub struct BodyLoad {
    /// Index in `scene.boundary`.
    pub boundary: usize,
    /// External force at scale 1 on every DOF (zero for displacement entries).
    pub force: Vec<f64>,
    /// Prescribed displacement at scale 1 on every DOF (zero elsewhere).
    pub displacement: Vec<f64>,
}

pub struct BodyModel {
    pub scene_index: usize,
    pub name: String,
    pub mesh: Mesh,
    pub material: Elasticity,
    pub n_dof: usize,
    pub prescribed: Vec<bool>,
    /// Free DOFs (full indices), in order.
    pub free: Vec<usize>,
    /// Full DOF → position in `free` (usize::MAX for a prescribed DOF).
    pub free_index: Vec<usize>,
    pub loads: Vec<BodyLoad>,
    /// Rigid motions that the supports leave free (each of length `n_dof`,
    /// zero on prescribed DOFs); empty for a supported body.
    pub kernel: Vec<Vec<f64>>,
    /// Nodes on a contact surface of this body.
    pub contact_node: Vec<bool>,
    /// METIS part of every cell (all zero for one subdomain).
    pub parts: Vec<usize>,
    pub n_parts: usize,
}

impl BodyModel {
    /// Scale of every load entry at a step.
    pub fn scales(
        &self,
        scene: &scene::Scene,
        step: &std::collections::BTreeMap<String, f64>,
    ) -> Vec<f64> {
        self.loads
            .iter()
            .map(|l| {
                scene.boundary[l.boundary]
                    .name
                    .as_ref()
                    .and_then(|n| step.get(n).copied())
                    .unwrap_or(1.0)
            })
            .collect()
    }

    /// Σ s_b v_b for the chosen vector of each load (length `n_dof`).
    pub fn combine(&self, scales: &[f64], pick: impl Fn(&BodyLoad) -> &Vec<f64>) -> Vec<f64> {
        let mut out = vec![0.0; self.n_dof];
        for (l, &s) in self.loads.iter().zip(scales) {
            if s != 0.0 {
                for (o, v) in out.iter_mut().zip(pick(l)) {
                    *o += s * v;
                }
            }
        }
        out
    }
}

/// A contact point with its row over the bodies' full DOFs.
pub struct PointModel {
    pub contact: usize,
    pub point: ContactPoint,
    /// (body model index, full DOF, coefficient): g = g0 + Σ coef u.
    pub row: Vec<(usize, usize, f64)>,
    pub gap0: f64,
    pub slave_body: usize,
    pub tributary: f64,
    /// The tangential row (slip of the slave relative to the master along
    /// the tangent t), for points of a contact with friction.
    pub trow: Option<Vec<(usize, usize, f64)>>,
    /// In 3D, the row along the second tangent t2 (n, t1, t2 right-handed).
    pub trow2: Option<Vec<(usize, usize, f64)>>,
    /// The friction law of the point's contact, per point: the Tresca
    /// threshold as a force (g × tributary length), or μ.
    pub friction: PointFriction,
}

/// The friction law at one contact point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointFriction {
    None,
    /// Threshold force.
    Tresca(f64),
    /// Coefficient, and the elastic slip stiffness (force per unit slip) of a
    /// regularised law (seed §4.1.3).
    Coulomb {
        mu: f64,
        /// The coefficient along the second tangent t2 (3D anisotropic
        /// friction, the elliptic cone of seed §4.1.2); equal to `mu` when
        /// one coefficient is given.
        mu2: f64,
        slip_stiffness: Option<f64>,
    },
    /// Norton–Hoff (seed §4.1.4): λ_t = −μ λ_n |Δs|^(ρ−1) Δs.
    NortonHoff {
        mu: f64,
        rho: f64,
    },
}

pub fn fem_model(model: scene::Model) -> Result<FemModel, SolveError> {
    Ok(match model {
        scene::Model::PlaneStrain => FemModel::PlaneStrain,
        scene::Model::PlaneStress => FemModel::PlaneStress,
        scene::Model::Axisymmetric => FemModel::Axisymmetric,
        scene::Model::Solid => FemModel::Solid,
    })
}

/// The element formulation of a body (`bodies.formulation`).
pub fn fem_formulation(f: scene::Formulation) -> FemFormulation {
    match f {
        scene::Formulation::Displacement => FemFormulation::Displacement,
        scene::Formulation::BBar => FemFormulation::BBar,
    }
}

fn cell_kind(e: scene::Element) -> CellKind {
    match e {
        scene::Element::Quad4 => CellKind::Quad4,
        scene::Element::Tri3 => CellKind::Tri3,
        scene::Element::Quad8 => CellKind::Quad8,
        scene::Element::Tri6 => CellKind::Tri6,
        scene::Element::Hex8 => CellKind::Hex8,
        scene::Element::Tet4 => CellKind::Tet4,
    }
}

/// `grading = { towards, ratio }` as the generator's side (`from_name`) and
/// ratio, or an error listing the valid `names`.
fn grading_side<S>(
    grading: &Option<scene::Grading>,
    from_name: impl Fn(&str) -> Option<S>,
    names: &str,
    entry: &str,
) -> Result<Option<(S, f64)>, SolveError> {
    grading
        .as_ref()
        .map(|g| {
            from_name(&g.towards)
                .map(|side| (side, g.ratio))
                .ok_or_else(|| {
                    input(format!(
                        "{entry}.mesh.grading.towards: \"{}\" is not one of {names}",
                        g.towards
                    ))
                })
        })
        .transpose()
}

/// A point given with `dimension` components, as `[x, y, z]` (z = 0 in 2D).
pub fn point3(v: &[f64]) -> [f64; 3] {
    [
        v[0],
        v.get(1).copied().unwrap_or(0.0),
        v.get(2).copied().unwrap_or(0.0),
    ]
}

/// The mesh of a deformable body: a generator's, or a Gmsh file's (its
/// physical groups of dimension d−1 are the surfaces).
pub fn build_mesh(body: &scene::Body, entry: &str, dim: usize) -> Result<Mesh, SolveError> {
    let Some(spec) = &body.mesh else {
        return Err(input(format!("{entry}.mesh: missing")));
    };
    let finish = |mesh: Mesh| {
        if mesh.dim != dim {
            return Err(input(format!(
                "{entry}.mesh: a {}D mesh in a scene of dimension {dim}",
                mesh.dim
            )));
        }
        Ok(mesh)
    };
    use scene::Generator as G;
    let mesh = match spec {
        scene::MeshSpec::Generator(G::Rectangle {
            origin,
            size,
            divisions,
            element,
            grading,
        }) => {
            let g = grading_side(
                grading,
                RectSide::from_name,
                "bottom, top, left, right",
                entry,
            )?;
            rectangle(*origin, *size, *divisions, cell_kind(*element), g)
        }
        scene::MeshSpec::Generator(G::HalfDisk {
            center,
            radius,
            divisions,
            pole,
            grading,
            element,
        }) => half_disk(
            *center,
            *radius,
            *divisions,
            *pole,
            *grading,
            cell_kind(*element),
        ),
        scene::MeshSpec::Generator(G::Box {
            origin,
            size,
            divisions,
            element,
            grading,
        }) => {
            let g = grading_side(
                grading,
                BoxSide::from_name,
                "xmin, xmax, ymin, ymax, zmin, zmax",
                entry,
            )?;
            box_mesh(*origin, *size, *divisions, cell_kind(*element), g)
        }
        scene::MeshSpec::Generator(G::Hemisphere {
            center,
            radius,
            divisions,
            pole,
            grading,
        }) => hemisphere(*center, *radius, *divisions, *pole, *grading),
        scene::MeshSpec::Generator(G::QuarterDisk {
            center,
            radius,
            divisions,
            grading,
            element,
        }) => quarter_disk(*center, *radius, *divisions, *grading, cell_kind(*element)),
        scene::MeshSpec::File { file } => {
            return finish(
                signorini_mesh::gmsh::read_msh(file, dim)
                    .map_err(|e| input(format!("{entry}.mesh.file: {e}")))?,
            )
        }
    };
    finish(mesh.map_err(|e| input(format!("{entry}.mesh: {e}")))?)
}

/// Nodes a boundary entry acts on.
fn boundary_nodes(
    b: &scene::Boundary,
    entry: &str,
    mesh: &Mesh,
    body: &str,
) -> Result<Vec<usize>, SolveError> {
    if let Some(s) = &b.surface {
        let surf = mesh
            .surface(s)
            .map_err(|e| input(format!("{entry}.surface: body \"{body}\": {e}")))?;
        let nodes = surf.nodes();
        if nodes.is_empty() {
            return Err(input(format!(
                "{entry}.surface: surface \"{s}\" of body \"{body}\" has no nodes"
            )));
        }
        Ok(nodes)
    } else if let Some(p) = &b.point {
        let x = point3(p);
        let (n, d) = mesh
            .nearest_node(x)
            .ok_or_else(|| input(format!("{entry}.point: body \"{body}\" has no nodes")))?;
        if d > 1e-6 * mesh.size() {
            let c = mesh.coords[n];
            return Err(input(format!(
                "{entry}.point: body \"{body}\" has no node at ({}, {}); the nearest is ({}, {}), {d:e} away",
                x[0], x[1], c[0], c[1]
            )));
        }
        Ok(vec![n])
    } else {
        Err(input(format!("{entry}: give a surface or a point")))
    }
}

/// Builds every deformable body with its DOF classes and loads.
pub fn build_bodies(sc: &scene::Scene) -> Result<Vec<BodyModel>, SolveError> {
    let model = fem_model(sc.model)?;
    let scene_dim = sc.dimension as usize;
    let mut out = Vec::new();
    for (bi, body) in sc.bodies.iter().enumerate() {
        if !body.is_deformable() {
            continue;
        }
        let entry = format!("bodies[{bi}]");
        let mesh = build_mesh(body, &entry, scene_dim)?;
        let mat_name = body.material.as_deref().unwrap_or_default();
        let mat = sc.material(mat_name).ok_or_else(|| {
            input(format!(
                "{entry}.material: no material named \"{mat_name}\""
            ))
        })?;
        // The body's formulation travels with its material, so every path
        // that assembles or recovers stresses from `material` (condensed
        // subdomains, direct path, MPI ranks) uses it.
        let material = Elasticity::new(mat.young, mat.poisson, model)
            .with_formulation(fem_formulation(body.formulation));
        signorini_fem::check_material(mat.young, mat.poisson)
            .map_err(|e| input(format!("{entry}.material \"{mat_name}\": {e}")))?;
        signorini_fem::check_mesh(&mesh, model).map_err(|e| input(format!("{entry}.mesh: {e}")))?;
        signorini_fem::check_formulation(&mesh, &material).map_err(|e| {
            input(format!(
                "{entry}.formulation \"{}\": {e}",
                body.formulation.as_str()
            ))
        })?;
        let dim = mesh.dim;
        let n_dof = mesh.n_nodes() * dim;
        // Prescribed DOFs and their values per entry.
        let mut prescribed = vec![false; n_dof];
        let mut set_by: Vec<Option<(usize, f64)>> = vec![None; n_dof];
        let mut raw_loads: Vec<(usize, Vec<f64>, Vec<f64>)> = Vec::new();
        for (li, b) in sc.boundary.iter().enumerate() {
            if b.body != body.name {
                continue;
            }
            let lentry = format!("boundary[{li}]");
            let nodes = boundary_nodes(b, &lentry, &mesh, &body.name)?;
            let mut force = vec![0.0; n_dof];
            let mut disp = vec![0.0; n_dof];
            if let Some(d) = &b.displacement {
                for (c, v) in d.components().iter().enumerate().take(dim) {
                    let Some(v) = v else { continue };
                    for &n in &nodes {
                        let dof = n * dim + c;
                        if let Some((other, ov)) = set_by[dof] {
                            if ov != *v || sc.boundary[other].name != b.name {
                                let x = mesh.coords[n];
                                if !(ov == 0.0 && *v == 0.0) {
                                    return Err(input(format!(
                                        "{lentry}.displacement: boundary[{other}] already imposes component {} at node ({}, {}) of body \"{}\" with another value or scale",
                                        ["x", "y", "z"][c], x[0], x[1], body.name
                                    )));
                                }
                            }
                        }
                        set_by[dof] = Some((li, *v));
                        prescribed[dof] = true;
                        disp[dof] = *v;
                    }
                }
            } else if let Some(t) = &b.traction {
                let surf_name = b.surface.as_deref().ok_or_else(|| {
                    input(format!("{lentry}.traction: a traction acts on a surface; give `surface` (or use `force` on a point)"))
                })?;
                let surf = mesh
                    .surface(surf_name)
                    .map_err(|e| input(format!("{lentry}.surface: {e}")))?;
                force = signorini_fem::traction_load(&mesh, surf, t, model);
            } else if let Some(f) = &b.force {
                if let Some(surf_name) = &b.surface {
                    let surf = mesh
                        .surface(surf_name)
                        .map_err(|e| input(format!("{lentry}.surface: {e}")))?;
                    let len = signorini_fem::surface_measure(&mesh, surf, model);
                    let t: Vec<f64> = f.iter().map(|v| v / len).collect();
                    force = signorini_fem::traction_load(&mesh, surf, &t, model);
                } else {
                    for (c, v) in f.iter().enumerate().take(dim) {
                        force[nodes[0] * dim + c] += v;
                    }
                }
            }
            raw_loads.push((li, force, disp));
        }
        if model == FemModel::Axisymmetric {
            // On the axis (r = 0) the radial displacement is zero by symmetry.
            let tol = 1e-9 * mesh.size();
            for (n, x) in mesh.coords.iter().enumerate() {
                if x[0].abs() <= tol {
                    if let Some((other, v)) = set_by[n * dim] {
                        if v != 0.0 {
                            return Err(input(format!(
                                "boundary[{other}].displacement: imposes x = {v} at node ({}, {}) on the axis of body \"{}\"; in an axisymmetric model the radial displacement on the axis is zero",
                                x[0], x[1], body.name
                            )));
                        }
                    }
                    prescribed[n * dim] = true;
                }
            }
        }
        let free: Vec<usize> = (0..n_dof).filter(|&d| !prescribed[d]).collect();
        let mut free_index = vec![usize::MAX; n_dof];
        for (i, &d) in free.iter().enumerate() {
            free_index[d] = i;
        }
        let loads = raw_loads
            .into_iter()
            .map(|(li, force, disp)| BodyLoad {
                boundary: li,
                force,
                displacement: disp,
            })
            .collect();
        let kernel = free_rigid_modes(&mesh, model, &prescribed);
        let n_cells = mesh.cells.len();
        let n_nodes = mesh.n_nodes();
        out.push(BodyModel {
            scene_index: bi,
            name: body.name.clone(),
            mesh,
            material,
            n_dof,
            prescribed,
            free,
            free_index,
            loads,
            kernel,
            contact_node: vec![false; n_nodes],
            parts: vec![0; n_cells],
            n_parts: 1,
        });
    }
    if out.is_empty() {
        return Err(input("bodies: the scene has no deformable body"));
    }
    Ok(out)
}

/// The rigid motions r with r = 0 on every prescribed DOF: the null space of
/// the prescribed rows of the (normalised) rigid-body modes, by a symmetric
/// eigen decomposition of CᵀC, a rank test scaled by the number of DOFs.
fn free_rigid_modes(mesh: &Mesh, model: FemModel, prescribed: &[bool]) -> Vec<Vec<f64>> {
    let mut modes = signorini_fem::rigid_body_modes(mesh, model);
    for m in modes.iter_mut() {
        let n = m.iter().map(|v| v * v).sum::<f64>().sqrt();
        m.iter_mut().for_each(|v| *v /= n);
    }
    let k = modes.len();
    let n_dof = prescribed.len();
    let mut ctc = Mat::<f64>::zeros(k, k);
    for d in (0..n_dof).filter(|&d| prescribed[d]) {
        for i in 0..k {
            for j in 0..k {
                ctc[(i, j)] += modes[i][d] * modes[j][d];
            }
        }
    }
    let Ok(eig) = ctc.self_adjoint_eigen(Side::Lower) else {
        return Vec::new();
    };
    let threshold = 1e-8 / n_dof as f64;
    let mut kernel = Vec::new();
    for j in 0..k {
        if eig.S()[j] <= threshold {
            let v: Vec<f64> = (0..k).map(|i| eig.U()[(i, j)]).collect();
            let r: Vec<f64> = (0..n_dof)
                .map(|d| {
                    if prescribed[d] {
                        0.0
                    } else {
                        (0..k).map(|i| v[i] * modes[i][d]).sum()
                    }
                })
                .collect();
            kernel.push(r);
        }
    }
    kernel
}

/// Builds the contact points of every pair, and marks the DOFs of contact
/// surfaces as interface DOFs of their bodies. Adds to `notes` a note per
/// pair that left slave nodes out (no master point along their normal).
pub fn build_contacts(
    sc: &scene::Scene,
    bodies: &mut [BodyModel],
    notes: &mut Vec<String>,
) -> Result<(Vec<PointModel>, Vec<FixedPoint>), SolveError> {
    let mut points = Vec::new();
    let mut fixed = Vec::new();
    let mut interface_nodes: Vec<Vec<usize>> = vec![Vec::new(); bodies.len()];
    for ci in 0..sc.contact.len() {
        let pair = contact_pair(sc, bodies, ci, notes, &mut interface_nodes)?;
        for p in pair.points {
            match point_model(sc, bodies, &pair.sides, ci, &pair.tributary, p) {
                PairPoint::Unknown(point) => points.push(point),
                PairPoint::Fixed(f) => fixed.push(f),
            }
        }
    }
    for (b, nodes) in interface_nodes.into_iter().enumerate() {
        for n in nodes {
            bodies[b].contact_node[n] = true;
        }
    }
    Ok((points, fixed))
}

/// The contact points of one pair with the slave's tributary measure per
/// node, and the bodies their rows act on.
struct ContactPair {
    points: Vec<ContactPoint>,
    tributary: std::collections::BTreeMap<usize, f64>,
    sides: PairSides,
}

/// The body models of a pair's slave and (deformable) master.
struct PairSides {
    slave: usize,
    master: Option<usize>,
}

/// Refuses what the contact solver does not support yet: a discretisation
/// other than node-to-node or node-to-segment, Norton–Hoff friction in 3D.
fn check_contact_supported(
    sc: &scene::Scene,
    c: &scene::Contact,
    entry: &str,
) -> Result<(), SolveError> {
    match c.discretization {
        scene::Discretization::NodeToNode | scene::Discretization::NodeToSegment => {}
        other => {
            return Err(input(format!(
                "{entry}.discretization: \"{}\" is not supported yet (supported: node_to_node, node_to_segment)",
                other.as_str()
            )))
        }
    }
    if sc.dimension == 3 && matches!(c.friction, scene::Friction::NortonHoff { .. }) {
        return Err(input(format!(
            "{entry}.friction: Norton-Hoff friction is not supported in 3D yet (supported in 3D: tresca, coulomb with one or two coefficients, slip_stiffness)"
        )));
    }
    Ok(())
}

/// The named contact surface of a body (`side` is "slave" or "master"),
/// refused when it is unknown or has no nodes.
fn contact_surface<'a>(
    bodies: &'a [BodyModel],
    b: usize,
    s: &scene::ContactSide,
    side: &str,
    entry: &str,
) -> Result<&'a signorini_mesh::Surface, SolveError> {
    let name = s.surface.as_deref().unwrap_or_default();
    let surface = bodies[b]
        .mesh
        .surface(name)
        .map_err(|e| input(format!("{entry}.{side}.surface: body \"{}\": {e}", s.body)))?;
    if surface.facets.is_empty() {
        return Err(input(format!(
            "{entry}.{side}.surface: surface \"{name}\" has no nodes"
        )));
    }
    Ok(surface)
}

/// The scene's normal rule as the contact crate's.
fn normal_rule(rule: scene::NormalRule) -> NormalRule {
    match rule {
        scene::NormalRule::Master => NormalRule::Master,
        scene::NormalRule::Slave => NormalRule::Slave,
        scene::NormalRule::Average => NormalRule::Average,
        scene::NormalRule::Points => NormalRule::Points,
    }
}

/// The master geometry of a pair: a deformable body's surface, or a rigid
/// plane (unit normal) or circle/sphere.
fn master_geometry<'a>(
    sc: &scene::Scene,
    bodies: &'a [BodyModel],
    c: &scene::Contact,
    mi: Option<usize>,
    entry: &str,
) -> Result<MasterGeometry<'a>, SolveError> {
    let master_scene = sc.body(&c.master.body).ok_or_else(|| {
        input(format!(
            "{entry}.master.body: no body named \"{}\"",
            c.master.body
        ))
    })?;
    if let Some(mi) = mi {
        return Ok(MasterGeometry::Surface {
            mesh: &bodies[mi].mesh,
            surface: contact_surface(bodies, mi, &c.master, "master", entry)?,
        });
    }
    Ok(match &master_scene.rigid {
        Some(scene::RigidShape::Plane { point, normal }) => {
            let n = point3(normal);
            let nn = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            MasterGeometry::Plane {
                point: point3(point),
                normal: [n[0] / nn, n[1] / nn, n[2] / nn],
            }
        }
        Some(scene::RigidShape::Circle { center, radius })
        | Some(scene::RigidShape::Sphere { center, radius }) => MasterGeometry::Sphere {
            center: point3(center),
            radius: *radius,
        },
        None => {
            return Err(input(format!(
                "{entry}.master: body \"{}\" is neither deformable nor rigid",
                c.master.body
            )))
        }
    })
}

/// Pairs the slave surface of contact `ci` with its master: the contact
/// points, the slave's tributary measures; notes the slave nodes left out
/// and marks both surfaces' nodes as interface nodes.
fn contact_pair(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    ci: usize,
    notes: &mut Vec<String>,
    interface_nodes: &mut [Vec<usize>],
) -> Result<ContactPair, SolveError> {
    let c = &sc.contact[ci];
    let entry = format!("contact \"{}\"", c.name);
    check_contact_supported(sc, c, &entry)?;
    let body_model = |name: &str| bodies.iter().position(|b| b.name == name);
    let si = body_model(&c.slave.body).ok_or_else(|| {
        input(format!(
            "{entry}.slave.body: \"{}\" is not a deformable body",
            c.slave.body
        ))
    })?;
    let s_mesh = &bodies[si].mesh;
    let s_surf = contact_surface(bodies, si, &c.slave, "slave", &entry)?;
    let rule = normal_rule(c.normal);
    let mi = body_model(&c.master.body);
    let master = master_geometry(sc, bodies, c, mi, &entry)?;
    let pairing = match c.discretization {
        scene::Discretization::NodeToNode => node_to_node_pairing(s_mesh, s_surf, &master, rule),
        _ => node_to_segment_pairing(s_mesh, s_surf, &master, rule),
    }
    .map_err(|e| input(format!("{entry}: {e}")))?;
    let dropped = pairing.dropped.note().map(|n| format!("{entry}: {n}"));
    if pairing.points.is_empty() {
        return Err(input(format!(
            "{entry}: no node of slave surface \"{}\" faces the master; check the geometry{}",
            c.slave.surface.as_deref().unwrap_or_default(),
            dropped.map_or(String::new(), |n| format!(" ({n})"))
        )));
    }
    notes.extend(dropped);
    let tributary = signorini_fem::tributary_measure(s_mesh, s_surf, bodies[si].material.model)
        .into_iter()
        .collect();
    interface_nodes[si].extend(s_surf.nodes());
    if let (Some(mi), MasterGeometry::Surface { surface, .. }) = (mi, &master) {
        interface_nodes[mi].extend(surface.nodes());
    }
    Ok(ContactPair {
        points: pairing.points,
        tributary,
        sides: PairSides {
            slave: si,
            master: mi,
        },
    })
}

/// The row of a contact point along `direction` (its normal or a tangent):
/// Σ weight × direction over the terms' DOFs, slave and master.
fn row_along(p: &ContactPoint, sides: &PairSides, dim: usize, direction: [f64; 3]) -> Row {
    let mut row = Vec::new();
    for term in &p.terms {
        let b = match term.side {
            TermSide::Slave => sides.slave,
            TermSide::Master => sides
                .master
                .expect("a master term needs a deformable master"),
        };
        for (k, dk) in direction.iter().enumerate().take(dim) {
            let coef = term.weight * dk;
            if coef != 0.0 {
                row.push((b, term.node * dim + k, coef));
            }
        }
    }
    row
}

/// The friction law of a contact at one of its points: a Tresca threshold
/// and a slip stiffness scale with the point's tributary measure.
fn point_friction(friction: &scene::Friction, tributary: f64) -> PointFriction {
    match friction {
        scene::Friction::None => PointFriction::None,
        scene::Friction::NortonHoff { coefficient, rho } => PointFriction::NortonHoff {
            mu: *coefficient,
            rho: *rho,
        },
        scene::Friction::Tresca(g) => PointFriction::Tresca(g * tributary),
        scene::Friction::Coulomb {
            coefficient,
            slip_stiffness,
        } => PointFriction::Coulomb {
            mu: coefficient.first().copied().unwrap_or(0.0),
            mu2: coefficient
                .get(1)
                .or(coefficient.first())
                .copied()
                .unwrap_or(0.0),
            slip_stiffness: slip_stiffness.map(|k| k * tributary),
        },
    }
}

/// A contact point of a pair: an unknown of the contact problem, or one
/// whose gap the supports fix.
enum PairPoint {
    Unknown(PointModel),
    Fixed(FixedPoint),
}

/// The model of one contact point: its normal row, gap and friction law
/// with the tangential rows that carry a friction unknown; or, when its
/// normal DOFs are all prescribed, the point as a [`FixedPoint`] (its gap is
/// known: it is not an unknown of the contact problem).
fn point_model(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    sides: &PairSides,
    ci: usize,
    tributaries: &std::collections::BTreeMap<usize, f64>,
    mut p: ContactPoint,
) -> PairPoint {
    let c = &sc.contact[ci];
    let dim = sc.dimension as usize;
    let row = row_along(&p, sides, dim, p.normal);
    if row.iter().all(|&(b, d, _)| bodies[b].prescribed[d]) {
        return PairPoint::Fixed(FixedPoint {
            contact: ci,
            node: p.slave_node,
            row,
            gap0: p.gap0,
        });
    }
    let gap0 = match c.gap {
        scene::Gap::Geometric => p.gap0,
        scene::Gap::Uniform(j) => j,
    };
    let tributary = tributaries.get(&p.slave_node).copied().unwrap_or(0.0);
    let friction = point_friction(&c.friction, tributary);
    let trow = (friction != PointFriction::None).then(|| row_along(&p, sides, dim, p.tangent));
    let trow2 = (friction != PointFriction::None && dim == 3)
        .then(|| row_along(&p, sides, dim, p.tangent2));
    let (trow, trow2, friction) = free_tangential_rows(bodies, &mut p, trow, trow2, friction);
    PairPoint::Unknown(PointModel {
        trow,
        trow2,
        friction,
        contact: ci,
        tributary,
        point: p,
        row,
        gap0,
        slave_body: sides.slave,
    })
}

/// A row of B as (body, DOF, coefficient) entries.
type Row = Vec<(usize, usize, f64)>;

/// The tangential rows of a contact point that carry a friction unknown.
///
/// A support that prescribes the slave's (and master's) motion along a
/// tangent — a symmetry plane or a guide meeting the contact surface, the
/// axis r = 0 of an axisymmetric model — makes the slip along it known: the
/// tangential force there is a support reaction, not a friction unknown, and
/// its row has no free DOF (a zero row of the condensed B, a singular W), as
/// the normal row of a [`FixedPoint`]. In 2D such a row is dropped. In 3D the
/// free parts f1, f2 of the two rows are compared (Gram matrix): both zero,
/// both are dropped; dependent (a node on one symmetry plane), the frame
/// (t1, t2) is turned about n so that t2 is the prescribed direction, and
/// only t1, along which the node may slip, keeps a row, with the elliptic
/// cone's coefficient in that direction (seed §4.1.2).
fn free_tangential_rows(
    bodies: &[BodyModel],
    p: &mut ContactPoint,
    t1: Option<Row>,
    t2: Option<Row>,
    friction: PointFriction,
) -> (Option<Row>, Option<Row>, PointFriction) {
    let free = |r: &Row| -> std::collections::BTreeMap<(usize, usize), f64> {
        let mut m = std::collections::BTreeMap::new();
        for &(b, d, c) in r.iter().filter(|&&(b, d, _)| !bodies[b].prescribed[d]) {
            *m.entry((b, d)).or_insert(0.0) += c;
        }
        m
    };
    let dot = |a: &std::collections::BTreeMap<(usize, usize), f64>,
               b: &std::collections::BTreeMap<(usize, usize), f64>| {
        a.iter()
            .map(|(k, v)| v * b.get(k).copied().unwrap_or(0.0))
            .sum::<f64>()
    };
    let norm2 = |r: &Row| r.iter().map(|e| e.2 * e.2).sum::<f64>();
    let (Some(r1), Some(r2)) = (&t1, &t2) else {
        // 2D: one tangent.
        let keep = t1.filter(|r| !free(r).is_empty());
        return (keep, None, friction);
    };
    let (f1, f2) = (free(r1), free(r2));
    let (a, b, c) = (dot(&f1, &f1), dot(&f1, &f2), dot(&f2, &f2));
    let scale = norm2(r1) + norm2(r2);
    let lmin = 0.5 * (a + c - ((a - c).powi(2) + 4.0 * b * b).sqrt());
    if a + c <= 1e-24 * scale {
        return (None, None, friction);
    }
    if lmin > 1e-10 * scale {
        return (t1, t2, friction);
    }
    // (cs, sn): the combination cs t1 + sn t2 with no free DOF.
    let (v1, v2) = if (a - lmin).abs() >= (c - lmin).abs() {
        (-b, a - lmin)
    } else {
        (c - lmin, -b)
    };
    let nv = v1.hypot(v2);
    let (cs, sn) = (v1 / nv, v2 / nv);
    // New frame: t1' = −sn t1 + cs t2 (free), t2' = −(cs t1 + sn t2).
    let combine = |x: f64, y: f64, u: &Row, v: &Row| -> Row {
        u.iter()
            .map(|&(bb, d, k)| (bb, d, x * k))
            .chain(v.iter().map(|&(bb, d, k)| (bb, d, y * k)))
            .filter(|e| e.2 != 0.0)
            .collect()
    };
    let kept = combine(-sn, cs, r1, r2);
    let (o1, o2) = (p.tangent, p.tangent2);
    p.tangent = [0, 1, 2].map(|k| -sn * o1[k] + cs * o2[k]);
    p.tangent2 = [0, 1, 2].map(|k| -(cs * o1[k] + sn * o2[k]));
    let friction = match friction {
        PointFriction::Coulomb {
            mu,
            mu2,
            slip_stiffness,
        } if mu > 0.0 && mu2 > 0.0 => {
            let m = 1.0 / ((-sn / mu).powi(2) + (cs / mu2).powi(2)).sqrt();
            PointFriction::Coulomb {
                mu: m,
                mu2: m,
                slip_stiffness,
            }
        }
        other => other,
    };
    (Some(kept), None, friction)
}

/// A slave node whose normal motion is fully prescribed: its gap follows
/// from the prescribed displacements and must not be negative.
pub struct FixedPoint {
    pub contact: usize,
    pub node: usize,
    pub row: Vec<(usize, usize, f64)>,
    pub gap0: f64,
}

/// Finds contact constraints that repeat another (contact::redundancy: the
/// same slave node against the same master with a parallel row, e.g. a
/// surface in two contacts or two-pass node-to-node contact), drops the
/// less restrictive of each pair, and reports what it did; also reports
/// slave nodes shared by two contacts whose constraints differ (a corner
/// against two obstacles), which are kept. Returns the messages.
pub fn eliminate_redundant(sc: &scene::Scene, points: &mut Vec<PointModel>) -> Vec<String> {
    let mut messages = Vec::new();
    let size = points.iter().fold(0.0f64, |a, p| a.max(p.tributary));
    // (body, DOF) keys: a row of B and its initial gap per point.
    type Keyed = (Vec<((usize, usize), f64)>, f64);
    let rows: Vec<Keyed> = points
        .iter()
        .map(|p| (p.row.iter().map(|&(b, d, c)| ((b, d), c)).collect(), p.gap0))
        .collect();
    let dup = signorini_contact::redundancy::duplicate_constraints(&rows, 1e-9 * size);
    // (dropped contact, kept contact) → count
    let mut dropped: std::collections::BTreeMap<(usize, usize), usize> = Default::default();
    for (i, d) in dup.iter().enumerate() {
        if let Some(j) = d {
            *dropped
                .entry((points[i].contact, points[*j].contact))
                .or_default() += 1;
        }
    }
    for ((ci, cj), n) in &dropped {
        messages.push(if ci == cj {
            format!(
                "contact \"{}\": {n} constraint(s) repeat another of the same contact: dropped (redundant constraints)",
                sc.contact[*ci].name
            )
        } else {
            format!(
                "contact \"{}\": {n} constraint(s) repeat those of contact \"{}\" (same nodes, parallel rows): dropped as redundant, the problem is unchanged",
                sc.contact[*ci].name, sc.contact[*cj].name
            )
        });
    }
    let mut i = 0;
    points.retain(|_| {
        let keep = dup[i].is_none();
        i += 1;
        keep
    });
    // Slave nodes in two contacts with different constraints: reported.
    let mut by_node: std::collections::BTreeMap<(usize, usize), Vec<usize>> = Default::default();
    for p in points.iter() {
        by_node
            .entry((p.slave_body, p.point.slave_node))
            .or_default()
            .push(p.contact);
    }
    let mut shared: std::collections::BTreeMap<(usize, usize), usize> = Default::default();
    for cs in by_node.values() {
        for a in 0..cs.len() {
            for b in a + 1..cs.len() {
                if cs[a] != cs[b] {
                    *shared
                        .entry((cs[a].min(cs[b]), cs[a].max(cs[b])))
                        .or_default() += 1;
                }
            }
        }
    }
    for ((a, b), n) in shared {
        messages.push(format!(
            "{n} slave node(s) belong to both contact \"{}\" and contact \"{}\" with different normals: each keeps its constraint",
            sc.contact[a].name, sc.contact[b].name
        ));
    }
    messages
}
