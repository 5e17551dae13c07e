//! Contact points of a contact pair (seed §2.4 and §3.1.2).
//!
//! Each slave node is a contact point. Its normal n (unit, from master to
//! slave) follows the rule of seed Fig. 3: the master's normal, the slave's
//! (reversed), their average, or the direction joining the two points at rest.
//! Its initial gap is g0 = n · (x_slave − x_master) with x_master the closest
//! point of the master (seed eq. 10, j = g0). The row of B is
//! n·(u_slave − Σ N_i u_i) with N_i the master's shape functions at that point
//! (seed §3.1.2, Fig. 6: ½(u_A + u_B) at a mid-segment projection).

use signorini_mesh::{Mesh, Surface};

use crate::ContactError;

/// Rule that chooses the contact normal (seed §2.4, Fig. 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalRule {
    Master,
    Slave,
    Average,
    Points,
}

/// The master side of a contact pair.
pub enum MasterGeometry<'a> {
    /// A deformable body's surface.
    Surface {
        mesh: &'a Mesh,
        surface: &'a Surface,
    },
    /// A rigid plane (2D: a line) through `point` with unit normal `normal`
    /// pointing towards the slave.
    Plane { point: [f64; 3], normal: [f64; 3] },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermSide {
    Slave,
    Master,
}

/// One term of a row of B: `weight` times n · u(node) of the given side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    pub side: TermSide,
    pub node: usize,
    pub weight: f64,
}

/// A contact point: a slave node and the row of B that gives its gap.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPoint {
    pub slave_node: usize,
    pub x: [f64; 3],
    /// Unit normal, from master to slave.
    pub normal: [f64; 3],
    /// Unit tangent (2D: the normal turned by −90°).
    pub tangent: [f64; 3],
    /// Initial gap g0 (negative: initial overlap).
    pub gap0: f64,
    /// g = g0 + Σ_terms weight · n · u(node).
    pub terms: Vec<Term>,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let l = norm(a);
    (l > 0.0 && l.is_finite()).then(|| [a[0] / l, a[1] / l, a[2] / l])
}

/// Outward unit normal at each node of a surface (2D): the length-weighted
/// average of the normals of the facets around it.
pub fn nodal_normals(mesh: &Mesh, surface: &Surface) -> Vec<(usize, [f64; 3])> {
    let mut acc: std::collections::BTreeMap<usize, [f64; 3]> = Default::default();
    for f in &surface.facets {
        let (n, len) = mesh.facet_normal_2d(f);
        for &v in &f.nodes {
            let e = acc.entry(v).or_insert([0.0; 3]);
            e[0] += n[0] * len;
            e[1] += n[1] * len;
        }
    }
    acc.into_iter()
        .map(|(v, n)| (v, unit(n).unwrap_or([0.0, 0.0, 0.0])))
        .collect()
}

/// Closest point of the master segments to x: (facet index, parameter ξ in
/// [0, 1] from node 0 to node 1, distance, unclamped ξ).
fn closest_segment(mesh: &Mesh, surface: &Surface, x: [f64; 3]) -> Option<(usize, f64, f64, f64)> {
    let mut best: Option<(usize, f64, f64, f64)> = None;
    for (k, f) in surface.facets.iter().enumerate() {
        let a = mesh.coords[f.nodes[0]];
        let b = mesh.coords[f.nodes[1]];
        let ab = sub(b, a);
        let l2 = dot(ab, ab);
        let xi_raw = if l2 > 0.0 {
            dot(sub(x, a), ab) / l2
        } else {
            0.0
        };
        let xi = xi_raw.clamp(0.0, 1.0);
        let p = [a[0] + xi * ab[0], a[1] + xi * ab[1], a[2] + xi * ab[2]];
        let d = norm(sub(x, p));
        if best.is_none_or(|bst| d < bst.2) {
            best = Some((k, xi, d, xi_raw));
        }
    }
    best
}

fn tangent_2d(n: [f64; 3]) -> [f64; 3] {
    [n[1], -n[0], 0.0]
}

fn choose_normal(
    rule: NormalRule,
    n_master: [f64; 3],
    n_slave_out: [f64; 3],
    x_slave: [f64; 3],
    x_master: [f64; 3],
    length_scale: f64,
) -> [f64; 3] {
    match rule {
        NormalRule::Master => n_master,
        NormalRule::Slave => [-n_slave_out[0], -n_slave_out[1], -n_slave_out[2]],
        NormalRule::Average => unit(sub(n_master, n_slave_out)).unwrap_or(n_master),
        NormalRule::Points => {
            let d = sub(x_slave, x_master);
            if norm(d) <= 1e-9 * length_scale {
                n_master
            } else {
                let mut n = unit(d).unwrap_or(n_master);
                // An initial overlap reverses x_s − x_m: keep n from master to slave.
                if dot(n, n_master) < 0.0 {
                    n = [-n[0], -n[1], -n[2]];
                }
                n
            }
        }
    }
}

/// Node-to-segment contact points (seed §3.1.2, Fig. 6): each slave node is
/// projected on the closest master segment (or on the rigid plane). Slave
/// nodes whose projection falls outside the master surface (beyond a
/// relative tolerance of the segment length) are not contact points.
pub fn node_to_segment(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
    rule: NormalRule,
) -> Result<Vec<ContactPoint>, ContactError> {
    let slave_normals = nodal_normals(slave_mesh, slave_surface);
    let scale = slave_mesh.size();
    let mut out = Vec::with_capacity(slave_normals.len());
    for (s, n_s) in slave_normals {
        let x = slave_mesh.coords[s];
        match master {
            MasterGeometry::Plane { point, normal } => {
                let d = dot(sub(x, *point), *normal);
                let xm = [
                    x[0] - d * normal[0],
                    x[1] - d * normal[1],
                    x[2] - d * normal[2],
                ];
                let n = choose_normal(rule, *normal, n_s, x, xm, scale);
                out.push(ContactPoint {
                    slave_node: s,
                    x,
                    normal: n,
                    tangent: tangent_2d(n),
                    gap0: dot(n, sub(x, xm)),
                    terms: vec![Term {
                        side: TermSide::Slave,
                        node: s,
                        weight: 1.0,
                    }],
                });
            }
            MasterGeometry::Surface { mesh, surface } => {
                let Some((k, xi, _d, xi_raw)) = closest_segment(mesh, surface, x) else {
                    return Err(ContactError::Geometry(
                        "the master surface has no facet".into(),
                    ));
                };
                let tol = 1e-6;
                if xi_raw < -tol || xi_raw > 1.0 + tol {
                    // Projection outside the master: no contact point here.
                    continue;
                }
                let f = &surface.facets[k];
                let (nm2, _) = mesh.facet_normal_2d(f);
                let n_master = [nm2[0], nm2[1], 0.0];
                let a = mesh.coords[f.nodes[0]];
                let b = mesh.coords[f.nodes[1]];
                let xm = [
                    a[0] + xi * (b[0] - a[0]),
                    a[1] + xi * (b[1] - a[1]),
                    a[2] + xi * (b[2] - a[2]),
                ];
                let n = choose_normal(rule, n_master, n_s, x, xm, scale);
                let mut terms = vec![Term {
                    side: TermSide::Slave,
                    node: s,
                    weight: 1.0,
                }];
                for (node, w) in [(f.nodes[0], 1.0 - xi), (f.nodes[1], xi)] {
                    if w != 0.0 {
                        terms.push(Term {
                            side: TermSide::Master,
                            node,
                            weight: -w,
                        });
                    }
                }
                out.push(ContactPoint {
                    slave_node: s,
                    x,
                    normal: n,
                    tangent: tangent_2d(n),
                    gap0: dot(n, sub(x, xm)),
                    terms,
                });
            }
        }
    }
    Ok(out)
}

/// Node-to-node contact points for matching meshes (seed §3.1.2, Fig. 4):
/// each slave node faces the nearest master node; the pair must coincide
/// within a relative tolerance of the slave's element size unless a gap
/// separates them along the normal.
pub fn node_to_node(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
    rule: NormalRule,
) -> Result<Vec<ContactPoint>, ContactError> {
    let (mesh, surface) = match master {
        MasterGeometry::Plane { .. } => {
            // Against a rigid plane, node-to-node and node-to-segment coincide.
            return node_to_segment(slave_mesh, slave_surface, master, rule);
        }
        MasterGeometry::Surface { mesh, surface } => (*mesh, *surface),
    };
    let slave_normals = nodal_normals(slave_mesh, slave_surface);
    let master_normals = nodal_normals(mesh, surface);
    let scale = slave_mesh.size();
    let mut out = Vec::with_capacity(slave_normals.len());
    for (s, n_s) in slave_normals {
        let x = slave_mesh.coords[s];
        let Some(&(m, n_m)) = master_normals.iter().min_by(|a, b| {
            norm(sub(mesh.coords[a.0], x)).total_cmp(&norm(sub(mesh.coords[b.0], x)))
        }) else {
            return Err(ContactError::Geometry(
                "the master surface has no node".into(),
            ));
        };
        let xm = mesh.coords[m];
        let d = sub(x, xm);
        let n = choose_normal(rule, n_m, n_s, x, xm, scale);
        // The facing node must lie along the normal: a tangential offset
        // means the meshes do not match.
        let tangential = norm([
            d[0] - dot(d, n) * n[0],
            d[1] - dot(d, n) * n[1],
            d[2] - dot(d, n) * n[2],
        ]);
        if tangential > 1e-6 * scale.max(f64::MIN_POSITIVE) {
            return Err(ContactError::Geometry(format!(
                "node_to_node needs matching meshes: slave node {s} at ({:.6}, {:.6}) has no master node facing it (nearest is {:.3e} off the normal); use discretization = \"node_to_segment\"",
                x[0], x[1], tangential
            )));
        }
        out.push(ContactPoint {
            slave_node: s,
            x,
            normal: n,
            tangent: tangent_2d(n),
            gap0: dot(n, d),
            terms: vec![
                Term {
                    side: TermSide::Slave,
                    node: s,
                    weight: 1.0,
                },
                Term {
                    side: TermSide::Master,
                    node: m,
                    weight: -1.0,
                },
            ],
        });
    }
    Ok(out)
}
