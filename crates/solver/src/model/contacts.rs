//! The contact points of every pair of a scene: the pairing of a slave
//! surface with its master, each point's normal and tangential rows over
//! the bodies' DOFs, its gap and friction law; the points whose gap the
//! supports fix, and the constraints that repeat another.

use signorini_geometry::mortar::mortar_pairing;
use signorini_geometry::mortar3d::mortar3d_pairing;
use signorini_geometry::pairing::{
    contact_element_pairing, nodal_normals, node_to_node_pairing, node_to_segment_pairing,
    node_to_segment_pairing_with, GivenNormals, Pairing,
};
use signorini_geometry::quadratic_slave::{consistent_normals, mid_side_edges, recombine_rows};
use signorini_geometry::{ContactPoint, GeometryError, MasterGeometry, NormalRule, TermSide};
use signorini_mesh::vec3::dot;
use signorini_mesh::{Mesh, Surface};
use signorini_scene as scene;
use std::collections::BTreeMap;

use super::held_tangents::{
    dot_parts, held_at_both_bodies, least_eigenpair, part, HeldTangents, Row, NEGLIGIBLE,
};
use super::{input, point3, BodyModel, PointModel, PrescribedSlip, Zone};
use crate::error::SolveError;
use signorini_contact::friction::FrictionLaw;

/// The contact points of a scene: the contact unknowns, the points whose gap
/// the supports fix, and the points outside the candidate zone.
pub struct ContactSet {
    pub points: Vec<PointModel>,
    pub fixed: Vec<FixedPoint>,
    /// Points whose initial gap is beyond their contact's zone: not
    /// unknowns, checked after the solve (see `zone`).
    pub excluded: Vec<PointModel>,
}

/// Builds the contact points of every pair, and marks the DOFs of contact
/// surfaces as interface DOFs of their bodies: every node of both surfaces,
/// or, for a contact that `zone` restricts, the nodes of its contact
/// unknowns' rows only. Adds to `notes` a note per pair that left slave
/// nodes out (no master point along their normal).
pub fn build_contacts(
    sc: &scene::Scene,
    bodies: &mut [BodyModel],
    zone: &Zone,
    notes: &mut Vec<String>,
) -> Result<ContactSet, SolveError> {
    let mut set = ContactSet {
        points: Vec::new(),
        fixed: Vec::new(),
        excluded: Vec::new(),
    };
    let mut interface_nodes: Vec<Vec<usize>> = vec![Vec::new(); bodies.len()];
    for ci in 0..sc.contact.len() {
        if sc.contact[ci].law == scene::Law::Tied {
            continue; // eliminated, not contact points (`super::ties`)
        }
        let restricted = zone.restricts(ci);
        let surfaces = (!restricted).then_some(&mut interface_nodes[..]);
        let pair = contact_pair(sc, bodies, ci, notes, surfaces)?;
        for p in pair.points {
            let corners = pair.recombined.get(&p.slave_node).copied();
            match point_model(sc, bodies, &pair.sides, ci, &pair.tributary, p, corners) {
                PairPoint::Unknown(point) if zone.includes(ci, point.gap0) => {
                    if restricted {
                        let p = &point.point;
                        let terms = p.terms.iter().map(|t| (t.side, t.node));
                        let vector = p.normal_row.iter().map(|t| (t.side, t.node));
                        for (side, node) in terms.chain(vector) {
                            let b = match side {
                                TermSide::Slave => pair.sides.slave,
                                TermSide::Master => pair.sides.master.unwrap_or(usize::MAX),
                            };
                            if let Some(nodes) = interface_nodes.get_mut(b) {
                                nodes.push(node);
                            }
                        }
                    }
                    set.points.push(*point)
                }
                PairPoint::Unknown(point) => set.excluded.push(*point),
                PairPoint::Fixed(f) => set.fixed.push(f),
            }
        }
    }
    for (b, nodes) in interface_nodes.into_iter().enumerate() {
        for n in nodes {
            bodies[b].contact_node[n] = true;
        }
    }
    Ok(set)
}

/// The contact points of one pair with the slave's tributary measure per
/// node, and the bodies their rows act on.
struct ContactPair {
    points: Vec<ContactPoint>,
    tributary: std::collections::BTreeMap<usize, f64>,
    /// The mid-side slave nodes whose rows were recombined, with the
    /// positions of their edge's corners (`PointModel::recombined_corners`).
    recombined: std::collections::BTreeMap<usize, [[f64; 3]; 2]>,
    sides: PairSides,
}

/// The body models of a pair's slave and (deformable) master.
struct PairSides {
    slave: usize,
    master: Option<usize>,
}

/// Refuses what the contact solver does not support yet: mortar in an
/// axisymmetric model or with a normal rule it does not use, Norton–Hoff
/// friction in 3D, and mortar or contact
/// elements against a rigid master (from the scene alone: `plan` asks it
/// before anything is built, so that `check` refuses it too).
pub(crate) fn check_contact_supported(
    sc: &scene::Scene,
    c: &scene::Contact,
    entry: &str,
) -> Result<(), SolveError> {
    if c.discretization == scene::Discretization::Mortar && sc.model == scene::Model::Axisymmetric {
        return Err(input(format!(
            "{entry}.discretization: \"mortar\" is not supported with model = \"axisymmetric\" yet (supported: node_to_node, node_to_segment)"
        )));
    }
    if c.discretization == scene::Discretization::Mortar && c.normal != scene::NormalRule::Master {
        return Err(input(format!(
            "{entry}.normal: \"{}\" is not used by mortar, whose normal is the slave's averaged nodal normal (reversed); leave the key out (its default \"master\"), or use node_to_segment for the rules master, slave, average, points",
            c.normal.as_str()
        )));
    }
    let rigid_master = sc.body(&c.master.body).is_some_and(|b| b.rigid.is_some());
    if rigid_master && c.discretization == scene::Discretization::Mortar {
        let (shape, instead) = if sc.dimension == 3 {
            ("sphere", "node_to_face")
        } else {
            ("circle", "node_to_segment")
        };
        return Err(input(format!(
            "{entry}: mortar needs a deformable master surface (a rigid plane or {shape}: use {instead})"
        )));
    }
    if rigid_master && c.discretization == scene::Discretization::ContactElements {
        return Err(input(format!(
            "{entry}: contact elements join two deformable bodies: the master must be a deformable body with a surface"
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
/// and marks both surfaces' nodes as interface nodes (when given
/// `interface_nodes`).
fn contact_pair(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    ci: usize,
    notes: &mut Vec<String>,
    interface_nodes: Option<&mut [Vec<usize>]>,
) -> Result<ContactPair, SolveError> {
    let (chosen, note) = super::slave_choice::chosen_sides(
        &sc.contact[ci],
        |name| bodies.iter().find(|b| b.name == name),
        |b, s| b.mesh.surface(s).ok(),
    );
    notes.extend(note);
    let c = &chosen;
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
    // Node-to-face on a quadratic slave: the recombined rows, normals and
    // measures (geometry's quadratic_slave).
    let edges = match c.discretization {
        scene::Discretization::NodeToSegment => mid_side_edges(sc.dimension as usize, s_surf),
        _ => Vec::new(),
    };
    // Mortar rows come with their own measure D_jj (contact::mortar, mortar3d).
    let (pairing, measure) = match c.discretization {
        scene::Discretization::NodeToNode => {
            (node_to_node_pairing(s_mesh, s_surf, &master, rule), None)
        }
        scene::Discretization::ContactElements => {
            (contact_element_pairing(s_mesh, s_surf, &master, rule), None)
        }
        scene::Discretization::Mortar => match if sc.dimension == 3 {
            mortar3d_pairing(s_mesh, s_surf, &master)
        } else {
            mortar_pairing(s_mesh, s_surf, &master)
        } {
            Ok(m) => (Ok(m.pairing), Some(m.measure)),
            Err(e) => (Err(e), None),
        },
        _ => node_to_face(s_mesh, s_surf, &master, rule, &edges),
    };
    let mut pairing = pairing.map_err(|e| input(format!("{entry}: {e}")))?;
    let corner_at: std::collections::HashMap<usize, [f64; 3]> =
        pairing.points.iter().map(|p| (p.slave_node, p.x)).collect();
    let recombined = recombine_rows(&mut pairing.points, &edges)
        .into_iter()
        .map(|(m, [c1, c2])| (m, [corner_at[&c1], corner_at[&c2]]))
        .collect();
    let dropped = pairing.dropped.note().map(|n| format!("{entry}: {n}"));
    if pairing.points.is_empty() {
        return Err(input(format!(
            "{entry}: no node of slave surface \"{}\" faces the master; check the geometry{}",
            c.slave.surface.as_deref().unwrap_or_default(),
            dropped.map_or(String::new(), |n| format!(" ({n})"))
        )));
    }
    notes.extend(dropped);
    let tributary = measure.unwrap_or_else(|| {
        signorini_fem::tributary_measure(s_mesh, s_surf, bodies[si].material.model)
            .into_iter()
            .collect()
    });
    if let Some(interface_nodes) = interface_nodes {
        interface_nodes[si].extend(s_surf.nodes());
        if let (Some(mi), MasterGeometry::Surface { surface, .. }) = (mi, &master) {
            interface_nodes[mi].extend(surface.nodes());
        }
    }
    Ok(ContactPair {
        points: pairing.points,
        tributary,
        recombined,
        sides: PairSides {
            slave: si,
            master: mi,
        },
    })
}

/// Node-to-face (node-to-segment in 2D) contact points. On a quadratic 3D
/// slave surface (`edges`, its mid-sides, not empty) the slave normals are
/// its consistent ones (geometry's `quadratic_slave::consistent_normals`)
/// and each point's measure is |n · v_a|, v_a = ∫ Ñ_a n dS, n the point's
/// normal (|v_a| along the consistent normal; on a flat face ∫ Ñ_a dS);
/// otherwise the nodal normals, and the measures are left to the caller.
/// On a quadratic 3D master surface the master's normal is interpolated from
/// its own consistent nodal normals.
fn node_to_face(
    s_mesh: &Mesh,
    s_surf: &Surface,
    master: &MasterGeometry<'_>,
    rule: NormalRule,
    edges: &[(usize, [usize; 2])],
) -> (Result<Pairing, GeometryError>, Option<BTreeMap<usize, f64>>) {
    let consistent = |mesh: &Mesh, surface: &Surface, edges: &[(usize, [usize; 2])]| {
        let area_vectors = signorini_fem::nodal_area_vectors(mesh, surface)
            .into_iter()
            .collect();
        consistent_normals(&area_vectors, edges)
    };
    let master_normals = match master {
        MasterGeometry::Surface { mesh, surface } => {
            let m_edges = mid_side_edges(mesh.dim, surface);
            (!m_edges.is_empty()).then(|| consistent(mesh, surface, &m_edges).normals)
        }
        _ => None,
    };
    if edges.is_empty() && master_normals.is_none() {
        return (node_to_segment_pairing(s_mesh, s_surf, master, rule), None);
    }
    let (slave, measures) = if edges.is_empty() {
        (nodal_normals(s_mesh, s_surf), None)
    } else {
        let c = consistent(s_mesh, s_surf, edges);
        (c.normals, Some(c.area_vectors))
    };
    let normals = GivenNormals {
        slave,
        master: master_normals.map(|n| n.into_iter().collect()),
    };
    let pairing = node_to_segment_pairing_with(s_mesh, normals, master, rule);
    // the measure of a row along n: |n · v_a|, the pressure whose consistent
    // load along n is the row's force
    let measures = measures.map(|v| {
        (pairing.iter().flat_map(|p| &p.points))
            .map(|p| (p.slave_node, dot(p.normal, v[&p.slave_node]).abs()))
            .collect()
    });
    (pairing, measures)
}

/// The row of a contact point along `direction` (its normal or a tangent):
/// Σ weight × direction over the terms' DOFs, slave and master.
fn row_along(p: &ContactPoint, sides: &PairSides, dim: usize, direction: [f64; 3]) -> Row {
    let terms = (p.terms.iter()).map(|t| (t.side, t.node, direction.map(|dk| t.weight * dk)));
    row_of(terms, sides, dim)
}

/// The normal row of a contact point: along its normal, or its own
/// coefficients where the normal varies along the row (`normal_row`, mortar
/// on curved faces).
fn normal_row(p: &ContactPoint, sides: &PairSides, dim: usize) -> Row {
    if p.normal_row.is_empty() {
        return row_along(p, sides, dim, p.normal);
    }
    let terms = (p.normal_row.iter()).map(|t| (t.side, t.node, t.coefficient));
    row_of(terms, sides, dim)
}

/// Tangential row `k` (0: along `tangent`, 1: `tangent2`) of a contact
/// point: along the tangent, or its own coefficients where the frame turns
/// along the row (`tangent_rows`, mortar on curved faces).
fn tangent_row(p: &ContactPoint, sides: &PairSides, dim: usize, k: usize) -> Row {
    if p.tangent_rows[k].is_empty() {
        return row_along(p, sides, dim, [p.tangent, p.tangent2][k]);
    }
    let terms = (p.tangent_rows[k].iter()).map(|t| (t.side, t.node, t.coefficient));
    row_of(terms, sides, dim)
}

/// The row Σ coefficient · u(node) over the terms' DOFs, slave and master.
fn row_of(
    terms: impl Iterator<Item = (TermSide, usize, [f64; 3])>,
    sides: &PairSides,
    dim: usize,
) -> Row {
    let mut row = Vec::new();
    for (side, node, coefficient) in terms {
        let b = match side {
            TermSide::Slave => sides.slave,
            TermSide::Master => sides
                .master
                .expect("a master term needs a deformable master"),
        };
        for (k, &coef) in coefficient.iter().enumerate().take(dim) {
            if coef != 0.0 {
                row.push((b, node * dim + k, coef));
            }
        }
    }
    row
}

/// The friction law of a contact at one of its points, and the slip
/// stiffness of a regularised law (course notes §4.1.3): a Tresca threshold and a
/// slip stiffness scale with the point's tributary measure.
pub(crate) fn point_friction(
    friction: &scene::Friction,
    tributary: f64,
) -> (FrictionLaw, Option<f64>) {
    match friction {
        scene::Friction::None => (FrictionLaw::None, None),
        scene::Friction::NortonHoff { coefficient, rho } => (
            FrictionLaw::NortonHoff {
                mu: *coefficient,
                rho: *rho,
            },
            None,
        ),
        scene::Friction::Tresca(g) => (FrictionLaw::Tresca(g * tributary), None),
        scene::Friction::Coulomb {
            coefficient,
            slip_stiffness,
            ..
        } => {
            let mu = coefficient.first().copied().unwrap_or(0.0);
            let mu2 = coefficient.get(1).copied().unwrap_or(mu);
            let law = FrictionLaw::Coulomb { mu: [mu, mu2] };
            (law, slip_stiffness.map(|k| k * tributary))
        }
    }
}

/// A contact point of a pair: an unknown of the contact problem, or one
/// whose gap the supports fix.
enum PairPoint {
    Unknown(Box<PointModel>),
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
    recombined_corners: Option<[[f64; 3]; 2]>,
) -> PairPoint {
    let c = &sc.contact[ci];
    let dim = sc.dimension as usize;
    let row = normal_row(&p, sides, dim);
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
    let (friction, slip_stiffness) = point_friction(&c.friction, tributary);
    let trow = (friction != FrictionLaw::None).then(|| tangent_row(&p, sides, dim, 0));
    let trow2 = (friction != FrictionLaw::None && dim == 3).then(|| tangent_row(&p, sides, dim, 1));
    let rows = free_tangential_rows(bodies, sides.slave, &mut p, trow, trow2, friction);
    PairPoint::Unknown(Box::new(PointModel {
        trow: rows.t1,
        trow2: rows.t2,
        friction: rows.friction,
        prescribed_slip: rows.prescribed,
        slip_stiffness,
        contact: ci,
        tributary,
        point: p,
        row,
        gap0,
        slave_body: sides.slave,
        recombined_corners,
    }))
}

/// The tangential rows of a contact point: those that carry a friction
/// unknown, its friction law (turned with the frame in 3D), and the rows
/// dropped because a support prescribes the slip along them.
struct TangentialRows {
    t1: Option<Row>,
    t2: Option<Row>,
    friction: FrictionLaw,
    prescribed: Option<PrescribedSlip>,
}

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
/// cone's coefficient in that direction (course notes §4.1.2). The dropped rows of a
/// point with no tangential unknown left are kept as its prescribed slip: a
/// support that drags it makes it slide (course notes §4, Coulomb's law).
///
/// A row that keeps free master DOFs (mortar: master nodes off the plane)
/// is dropped, or its direction turned out, in the same way when supports
/// hold its direction at both bodies (`held_tangents`): its friction force
/// is zero, with no prescribed slip.
fn free_tangential_rows(
    bodies: &[BodyModel],
    slave_body: usize,
    p: &mut ContactPoint,
    t1: Option<Row>,
    t2: Option<Row>,
    friction: FrictionLaw,
) -> TangentialRows {
    let rows = |t1, t2, prescribed| TangentialRows {
        t1,
        t2,
        friction,
        prescribed,
    };
    let free = |r: &Row| part(r, |b, d| !bodies[b].prescribed[d]);
    let norm2 = |r: &Row| r.iter().map(|e| e.2 * e.2).sum::<f64>();
    let (Some(r1), Some(r2)) = (&t1, &t2) else {
        // 2D: one tangent.
        return match t1 {
            Some(r) if free(&r).is_empty() => {
                rows(None, None, Some(PrescribedSlip { t1: r, t2: None }))
            }
            Some(r)
                if held_at_both_bodies(bodies, slave_body, p, &r, None) == HeldTangents::All =>
            {
                rows(None, None, None)
            }
            keep => rows(keep, None, None),
        };
    };
    let (f1, f2) = (free(r1), free(r2));
    let (a, b, c) = (
        dot_parts(&f1, &f1),
        dot_parts(&f1, &f2),
        dot_parts(&f2, &f2),
    );
    let scale = norm2(r1) + norm2(r2);
    let (lmin, prescribed_direction) = least_eigenpair(a, b, c);
    if a + c <= 1e-24 * scale {
        let (r1, r2) = (r1.clone(), r2.clone());
        return rows(
            None,
            None,
            Some(PrescribedSlip {
                t1: r1,
                t2: Some(r2),
            }),
        );
    }
    if lmin <= NEGLIGIBLE * scale {
        return turned_frame(p, r1, r2, prescribed_direction, friction);
    }
    match held_at_both_bodies(bodies, slave_body, p, r1, Some(r2)) {
        HeldTangents::None => rows(t1, t2, None),
        HeldTangents::Direction(held) => turned_frame(p, r1, r2, held, friction),
        HeldTangents::All => rows(None, None, None),
    }
}

/// Turns the tangential frame of a point about its normal so that t2 is the
/// direction cs t1 + sn t2 (`held`, whose friction force is zero) and keeps
/// the row along the new t1, with the elliptic cone's coefficient in that
/// direction (course notes §4.1.2).
fn turned_frame(
    p: &mut ContactPoint,
    r1: &Row,
    r2: &Row,
    [cs, sn]: [f64; 2],
    friction: FrictionLaw,
) -> TangentialRows {
    // New frame: t1' = −sn t1 + cs t2 (kept), t2' = −(cs t1 + sn t2).
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
        FrictionLaw::Coulomb { mu: [mu, mu2] } if mu > 0.0 && mu2 > 0.0 => {
            FrictionLaw::coulomb(1.0 / ((-sn / mu).powi(2) + (cs / mu2).powi(2)).sqrt())
        }
        other => other,
    };
    TangentialRows {
        t1: Some(kept),
        t2: None,
        friction,
        prescribed: None,
    }
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
    let dup = signorini_geometry::redundancy::duplicate_constraints(&rows, 1e-9 * size);
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
