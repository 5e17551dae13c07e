//! From a scene to the discrete model: one [`BodyModel`] per deformable body
//! (mesh, stiffness, DOF classes, loads per boundary entry, rigid-body kernel)
//! and (in `contacts`) the contact points with their rows over the bodies' DOFs.

use faer::{Mat, Side};
use signorini_contact::friction::{FrictionLaw, PointStatus};
use signorini_fem::{Elasticity, Formulation as FemFormulation, Model as FemModel};
use signorini_geometry::ContactPoint;
use signorini_mesh::generators::{
    box_mesh, half_disk, hemisphere_of_kind, quarter_disk, rectangle, BoxSide, HalfBall,
    HemisphereSector, RectSide,
};
use signorini_mesh::{CellKind, Mesh, MeshError};
use signorini_scene as scene;

use crate::error::SolveError;

mod contacts;
mod held_tangents;
mod slave_choice;
mod ties;
mod zone;
pub use contacts::{build_contacts, eliminate_redundant, ContactSet, FixedPoint};
pub(crate) use contacts::{check_contact_supported, point_friction};
pub use ties::{build_ties, TiedDof, Ties};
pub use zone::{check_excluded, zone_notes, Widening, Zone, MAX_WIDENINGS};

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
    /// The boundary entry (index in `scene.boundary`) that prescribes each
    /// DOF, whose reaction it counts in (the last entry that names it);
    /// `None` for a free DOF and for the axis of an axisymmetric model.
    pub support_of: Vec<Option<usize>>,
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
    /// threshold as a force (g × tributary length), or μ (in 3D, along t1
    /// and t2: the elliptic cone of course notes §4.1.2).
    pub friction: FrictionLaw,
    /// The elastic slip stiffness (force per unit slip) of a regularised
    /// Coulomb law (course notes §4.1.3).
    pub slip_stiffness: Option<f64>,
    /// The tangential rows dropped because a support prescribes every DOF
    /// of them (`model::contacts::free_tangential_rows`): the slip there is
    /// known, and a non-zero slip increment makes the point slide (course notes §4,
    /// Coulomb's law), its force evaluated at the end of the step.
    pub prescribed_slip: Option<PrescribedSlip>,
    /// On a quadratic slave face whose rows are recombined
    /// (`signorini_geometry::quadratic_slave`), the positions of the two
    /// corners of this mid-side point's edge: its force is then not that of
    /// its own shape function, which the pressure moments of the analytic
    /// references undo (`compare`). `None` elsewhere.
    pub recombined_corners: Option<[[f64; 3]; 2]>,
}

/// The tangential rows of a contact point whose slip a support prescribes:
/// the tangent t1 in 2D; t1 and t2 in 3D (both rows without a free DOF).
pub struct PrescribedSlip {
    pub t1: Vec<(usize, usize, f64)>,
    pub t2: Option<Vec<(usize, usize, f64)>>,
}

impl PointModel {
    /// Whether the point's friction status (stick, slip) is reported: it has
    /// a friction unknown, or a support drags it and it slides.
    pub fn reports_friction(&self, status: PointStatus) -> bool {
        self.trow.is_some() || (self.prescribed_slip.is_some() && status.is_slip())
    }
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

fn hemisphere_sector(s: scene::Sector) -> HemisphereSector {
    match s {
        scene::Sector::Whole => HemisphereSector::Whole,
        scene::Sector::Quarter => HemisphereSector::Quarter,
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
        scene::Element::Hex20 => CellKind::Hex20,
        scene::Element::Tet10 => CellKind::Tet10,
    }
}

/// The mesh of a rectangle or a box generator: `mesher` on the block, with
/// `grading = { towards, ratio }` as the generator's side (`from_name`) and
/// ratio, or an error listing the valid `names`.
fn block_mesh<const D: usize, S>(
    block: &scene::Block<D>,
    (from_name, names): (impl Fn(&str) -> Option<S>, &str),
    entry: &str,
    mesher: BlockMesher<D, S>,
) -> Result<Result<Mesh, MeshError>, SolveError> {
    let grading = block
        .grading
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
        .transpose()?;
    let kind = cell_kind(block.element);
    Ok(mesher(
        block.origin,
        block.size,
        block.divisions,
        kind,
        grading,
    ))
}

/// [`rectangle`] or [`box_mesh`]: origin, size, divisions, cell kind and
/// grading side and ratio.
type BlockMesher<const D: usize, S> =
    fn([f64; D], [f64; D], [usize; D], CellKind, Option<(S, f64)>) -> Result<Mesh, MeshError>;

/// The first `dim` coordinates of `x` as `(x, y[, z])` for a message, each
/// a few characters whatever its size.
fn point_text(x: &[f64; 3], dim: usize) -> String {
    let parts: Vec<String> = x[..dim]
        .iter()
        .map(|v| scene::Shown(*v).to_string())
        .collect();
    format!("({})", parts.join(", "))
}

/// A point given with `dimension` components, as `[x, y, z]` (z = 0 in 2D).
pub fn point3(v: &[f64]) -> [f64; 3] {
    [
        v[0],
        v.get(1).copied().unwrap_or(0.0),
        v.get(2).copied().unwrap_or(0.0),
    ]
}

/// Every surface a boundary condition or a contact names must be one of
/// its body's mesh (`files`: those read from Gmsh files; generators name
/// theirs), refused as `run` refuses it.
pub fn check_surface_names(
    sc: &scene::Scene,
    files: &std::collections::BTreeMap<String, Vec<String>>,
) -> Result<(), SolveError> {
    let dim = sc.dimension as usize;
    let known = |body: &str| -> Option<Vec<String>> {
        files.get(body).cloned().or_else(|| {
            let b = sc.body(body)?;
            let mut names: Vec<String> = crate::memory::generator_surfaces(b, dim)?
                .iter()
                .map(|n| n.to_string())
                .collect();
            names.sort();
            Some(names)
        })
    };
    let named = sc
        .boundary
        .iter()
        .enumerate()
        .map(|(i, b)| (format!("boundary[{i}].surface"), &b.body, &b.surface))
        .chain(sc.contact.iter().enumerate().flat_map(|(i, c)| {
            [
                (
                    format!("contact[{i}].slave.surface"),
                    &c.slave.body,
                    &c.slave.surface,
                ),
                (
                    format!("contact[{i}].master.surface"),
                    &c.master.body,
                    &c.master.surface,
                ),
            ]
        }));
    for (entry, body, surface) in named {
        let (Some(surface), Some(names)) = (surface, known(body)) else {
            continue;
        };
        if !names.contains(surface) {
            return Err(SolveError::Input(format!(
                "{entry}: body \"{body}\": {}",
                signorini_mesh::MeshError::UnknownSurface {
                    name: surface.clone(),
                    known: names.join(", "),
                }
            )));
        }
    }
    Ok(())
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
        scene::MeshSpec::Generator(G::Rectangle(block)) => {
            let sides = (RectSide::from_name, "bottom, top, left, right");
            block_mesh(block, sides, entry, rectangle)?
        }
        scene::MeshSpec::Generator(G::HalfDisk(d)) => {
            let ball = HalfBall::new(d.center, d.radius, d.divisions, d.pole, d.grading);
            half_disk(&ball, cell_kind(d.element))
        }
        scene::MeshSpec::Generator(G::Box(block)) => {
            let sides = (BoxSide::from_name, "xmin, xmax, ymin, ymax, zmin, zmax");
            block_mesh(block, sides, entry, box_mesh)?
        }
        scene::MeshSpec::Generator(G::Hemisphere(h)) => {
            let ball = HalfBall::new(h.center, h.radius, h.divisions, h.pole, h.grading);
            hemisphere_of_kind(&ball, cell_kind(h.element), hemisphere_sector(h.sector))
        }
        scene::MeshSpec::Generator(G::QuarterDisk(d)) => quarter_disk(
            d.center,
            d.radius,
            d.divisions,
            d.grading,
            cell_kind(d.element),
        ),
        scene::MeshSpec::File { file, volume } => {
            let key = if volume.is_some() { "volume" } else { "file" };
            return finish(
                signorini_mesh::gmsh::read_msh_volume(file, dim, volume.as_deref())
                    .map_err(|e| input(format!("{entry}.mesh.{key}: {e}")))?,
            );
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
                "{entry}.point: body \"{body}\" has no node at {}; the nearest is {}, {d:e} away",
                point_text(&x, mesh.dim),
                point_text(&c, mesh.dim)
            )));
        }
        Ok(vec![n])
    } else if let Some(set) = &b.nodes {
        node_set(mesh, set, entry, body)
    } else {
        Err(input(format!("{entry}: give a surface, a point or nodes")))
    }
}

/// The nodes of the physical group `set` of a body's Gmsh file: a node set
/// (points, curves in 3D) or a surface; an error listing both otherwise.
fn node_set(mesh: &Mesh, set: &str, entry: &str, body: &str) -> Result<Vec<usize>, SolveError> {
    if let Some(nodes) = mesh.node_sets.get(set) {
        return Ok(nodes.clone());
    }
    if let Some(surface) = mesh.surfaces.get(set) {
        return Ok(surface.nodes());
    }
    let mut known: Vec<String> = mesh
        .node_sets
        .keys()
        .chain(mesh.surfaces.keys())
        .map(|n| format!("\"{n}\""))
        .collect();
    known.sort();
    Err(input(format!(
        "{entry}.nodes: body \"{body}\" has no physical group \"{set}\" of points, curves or surfaces (its groups: {})",
        if known.is_empty() { "none".to_string() } else { known.join(", ") }
    )))
}

/// Builds every deformable body with its DOF classes and loads.
pub fn build_bodies(sc: &scene::Scene) -> Result<Vec<BodyModel>, SolveError> {
    let model = fem_model(sc.model)?;
    let mut out = Vec::new();
    for (bi, body) in sc.bodies.iter().enumerate() {
        if body.is_deformable() {
            out.push(build_body(sc, bi, model)?);
        }
    }
    if out.is_empty() {
        return Err(input("bodies: the scene has no deformable body"));
    }
    Ok(out)
}

/// One deformable body: its mesh and material, checked, its prescribed and
/// free DOFs, its loads and the rigid motions its supports leave free.
fn build_body(sc: &scene::Scene, bi: usize, model: FemModel) -> Result<BodyModel, SolveError> {
    let body = &sc.bodies[bi];
    let entry = format!("bodies[{bi}]");
    let mesh = build_mesh(body, &entry, sc.dimension as usize)?;
    let material = body_material(sc, body, &entry, &mesh, model)?;
    let n_dof = mesh.n_nodes() * mesh.dim;
    let mut supports = Supports {
        prescribed: vec![false; n_dof],
        set_by: vec![None; n_dof],
    };
    let mut loads = Vec::new();
    for (li, b) in sc.boundary.iter().enumerate() {
        if b.body == body.name {
            loads.push(boundary_load(
                sc,
                li,
                &mesh,
                &body.name,
                model,
                &mut supports,
            )?);
        }
    }
    if model == FemModel::Axisymmetric {
        fix_axis(&mesh, &body.name, &mut supports)?;
    }
    let prescribed = supports.prescribed;
    let support_of = supports
        .set_by
        .iter()
        .map(|s| s.map(|(li, _)| li))
        .collect();
    let free: Vec<usize> = (0..n_dof).filter(|&d| !prescribed[d]).collect();
    let mut free_index = vec![usize::MAX; n_dof];
    for (i, &d) in free.iter().enumerate() {
        free_index[d] = i;
    }
    let kernel = free_rigid_modes(&mesh, model, &prescribed);
    let n_cells = mesh.cells.len();
    let n_nodes = mesh.n_nodes();
    Ok(BodyModel {
        scene_index: bi,
        name: body.name.clone(),
        mesh,
        material,
        n_dof,
        prescribed,
        support_of,
        free,
        free_index,
        loads,
        kernel,
        contact_node: vec![false; n_nodes],
        parts: vec![0; n_cells],
        n_parts: 1,
    })
}

/// The elasticity of a body: its material with its formulation, the
/// material, mesh and formulation checked for the model.
fn body_material(
    sc: &scene::Scene,
    body: &scene::Body,
    entry: &str,
    mesh: &Mesh,
    model: FemModel,
) -> Result<Elasticity, SolveError> {
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
    signorini_fem::check_mesh(mesh, model).map_err(|e| input(format!("{entry}.mesh: {e}")))?;
    signorini_fem::check_formulation(mesh, &material).map_err(|e| {
        input(format!(
            "{entry}.formulation \"{}\": {e}",
            body.formulation.as_str()
        ))
    })?;
    Ok(material)
}

/// The prescribed DOFs of a body so far, and for each the boundary entry
/// that set it and its value.
struct Supports {
    prescribed: Vec<bool>,
    set_by: Vec<Option<(usize, f64)>>,
}

/// The load of boundary entry `li` on a body: a prescribed displacement
/// (recorded in `supports`, refused where another entry imposes another
/// value or scale), or a force from a traction or a force.
fn boundary_load(
    sc: &scene::Scene,
    li: usize,
    mesh: &Mesh,
    body: &str,
    model: FemModel,
    supports: &mut Supports,
) -> Result<BodyLoad, SolveError> {
    let b = &sc.boundary[li];
    let lentry = format!("boundary[{li}]");
    let nodes = boundary_nodes(b, &lentry, mesh, body)?;
    let n_dof = mesh.n_nodes() * mesh.dim;
    let mut force = vec![0.0; n_dof];
    let mut displacement = vec![0.0; n_dof];
    if let Some(d) = &b.displacement {
        displacement = prescribe(sc, li, d, &nodes, mesh, body, supports)?;
    } else if let Some(t) = &b.traction {
        let surf_name = b.surface.as_deref().ok_or_else(|| {
            input(format!("{lentry}.traction: a traction acts on a surface; give `surface` (or use `force` on a point)"))
        })?;
        let surf = mesh
            .surface(surf_name)
            .map_err(|e| input(format!("{lentry}.surface: {e}")))?;
        force = signorini_fem::traction_load(mesh, surf, t, model);
    } else if let Some(f) = &b.force {
        if let Some(surf_name) = &b.surface {
            let surf = mesh
                .surface(surf_name)
                .map_err(|e| input(format!("{lentry}.surface: {e}")))?;
            let len = signorini_fem::surface_measure(mesh, surf, model);
            let t: Vec<f64> = f.iter().map(|v| v / len).collect();
            force = signorini_fem::traction_load(mesh, surf, &t, model);
        } else {
            // a total force shared equally by the nodes (one for a point)
            let share = 1.0 / nodes.len() as f64;
            for &n in &nodes {
                for (c, v) in f.iter().enumerate().take(mesh.dim) {
                    force[n * mesh.dim + c] += v * share;
                }
            }
        }
    }
    Ok(BodyLoad {
        boundary: li,
        force,
        displacement,
    })
}

/// Prescribes the given components of a displacement entry on its nodes;
/// refuses a DOF that another entry already imposes with another value or
/// scale (unless both hold it at zero). Returns the entry's displacement
/// at scale 1 on every DOF.
fn prescribe(
    sc: &scene::Scene,
    li: usize,
    d: &scene::Displacement,
    nodes: &[usize],
    mesh: &Mesh,
    body: &str,
    supports: &mut Supports,
) -> Result<Vec<f64>, SolveError> {
    let b = &sc.boundary[li];
    let dim = mesh.dim;
    let mut displacement = vec![0.0; mesh.n_nodes() * dim];
    for (c, v) in d.components().iter().enumerate().take(dim) {
        let Some(v) = v else { continue };
        for &n in nodes {
            let dof = n * dim + c;
            if let Some((other, ov)) = supports.set_by[dof] {
                if ov != *v || sc.boundary[other].name != b.name {
                    let x = mesh.coords[n];
                    if !(ov == 0.0 && *v == 0.0) {
                        return Err(input(format!(
                            "boundary[{li}].displacement: boundary[{other}] already imposes component {} at node {} of body \"{}\" with another value or scale",
                            ["x", "y", "z"][c], point_text(&x, dim), body
                        )));
                    }
                }
            }
            supports.set_by[dof] = Some((li, *v));
            supports.prescribed[dof] = true;
            displacement[dof] = *v;
        }
    }
    Ok(displacement)
}

/// In an axisymmetric model the radial displacement on the axis (r = 0) is
/// zero by symmetry: prescribes it, and refuses an entry that imposes
/// another value there.
fn fix_axis(mesh: &Mesh, body: &str, supports: &mut Supports) -> Result<(), SolveError> {
    let dim = mesh.dim;
    let tol = 1e-9 * mesh.size();
    for (n, x) in mesh.coords.iter().enumerate() {
        if x[0].abs() <= tol {
            if let Some((other, v)) = supports.set_by[n * dim] {
                if v != 0.0 {
                    return Err(input(format!(
                        "boundary[{other}].displacement: imposes x = {} at node {} on the axis of body \"{}\"; in an axisymmetric model the radial displacement on the axis is zero",
                        scene::Shown(v), point_text(x, dim), body
                    )));
                }
            }
            supports.prescribed[n * dim] = true;
        }
    }
    Ok(())
}

/// The rigid motions r with r = 0 on every prescribed DOF, part by part of
/// the mesh (`Mesh::node_components`): a body of k disconnected parts has k
/// sets of rigid modes, each free unless the supports of its own part hold
/// it. Each is zero outside its part.
fn free_rigid_modes(mesh: &Mesh, model: FemModel, prescribed: &[bool]) -> Vec<Vec<f64>> {
    let modes = signorini_fem::rigid_body_modes(mesh, model);
    let (part, n_parts) = mesh.node_components();
    let dim = mesh.dim;
    let mut kernel = Vec::new();
    for p in 0..n_parts {
        let dofs: Vec<usize> = (0..prescribed.len())
            .filter(|&d| part[d / dim] == p)
            .collect();
        kernel.extend(free_modes_of_part(&modes, &dofs, prescribed));
    }
    kernel
}

/// The rigid motions of one part (its DOFs `dofs`) that vanish on its
/// prescribed DOFs: the body's modes restricted to the part and
/// orthonormalised there (thin QR), then the null space of their prescribed
/// rows C by a symmetric eigen decomposition of CᵀC, a rank test scaled by
/// the part's number of DOFs. Full-length vectors, zero off the part.
fn free_modes_of_part(modes: &[Vec<f64>], dofs: &[usize], prescribed: &[bool]) -> Vec<Vec<f64>> {
    let n = dofs.len();
    let restricted = Mat::<f64>::from_fn(n, modes.len(), |i, j| modes[j][dofs[i]]);
    let q = restricted.qr().compute_thin_Q();
    let k = q.ncols();
    let mut ctc = Mat::<f64>::zeros(k, k);
    for i in (0..n).filter(|&i| prescribed[dofs[i]]) {
        for a in 0..k {
            for b in 0..k {
                ctc[(a, b)] += q[(i, a)] * q[(i, b)];
            }
        }
    }
    let Ok(eig) = ctc.self_adjoint_eigen(Side::Lower) else {
        return Vec::new();
    };
    let threshold = 1e-8 / n as f64;
    let mut kernel = Vec::new();
    for j in (0..k).filter(|&j| eig.S()[j] <= threshold) {
        let mut r = vec![0.0; prescribed.len()];
        for (i, &d) in dofs.iter().enumerate() {
            if !prescribed[d] {
                r[d] = (0..k).map(|a| eig.U()[(a, j)] * q[(i, a)]).sum();
            }
        }
        kernel.push(r);
    }
    kernel
}

/// g_p = g0_p + Σ coef u over the full DOFs.
pub(crate) fn gaps_of(points: &[PointModel], u_full: &[Vec<f64>]) -> Vec<f64> {
    points
        .iter()
        .map(|p| p.gap0 + p.row.iter().map(|&(b, d, c)| c * u_full[b][d]).sum::<f64>())
        .collect()
}
