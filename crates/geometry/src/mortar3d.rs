//! Mortar contact in 3D (segment-based integration over clipped polygons;
//! linear slave and master faces, 3-node triangles and 4-node
//! quadrilaterals, and quadratic ones, Tri6 and Quad8) with dual Lagrange
//! multipliers: the 3D counterpart of [`crate::mortar`].
//!
//! References: M. Puso, T. Laursen, "A mortar segment-to-segment contact
//! method for large deformation solid mechanics", CMAME 193 (2004) §3;
//! A. Popp, M. Gitterle, M. Gee, W. Wall, "A dual mortar approach for 3D
//! finite deformation contact with consistent linearization", IJNME 83
//! (2010) §3–4; A. Popp, B. Wohlmuth, M. Gee, W. Wall, "Dual quadratic
//! mortar finite element methods for 3D finite deformation contact", SISC 34
//! (2012) §3–4; B. Wohlmuth, SINUM 38 (2000); the project's notes
//! docs/theory/mortar.md.
//!
//! The operators are those of the 2D module, over the slave surface Γ_c
//! that faces the master:
//!
//! ```text
//! D_jk = ∫_Γc Φ_j Ñ_k^s dγ = δ_jk ∫_Γc Ñ_j dγ,   M_jl = ∫_Γc Φ_j (N_l^m ∘ π) dγ,
//! ```
//!
//! with dual shape functions Φ = A_e Ñ on each slave face, A_e = D_e M_e⁻¹
//! (D_e = diag ∫Ñ, M_e = ∫Ñ Ñᵀ over the face's covered part: on a fully
//! covered triangle Φ_i = 3N_i − N_j − N_k; partly covered faces get the
//! "boundary modification" of Popp et al. as in 2D). On a linear face Ñ = N;
//! on a quadratic one Ñ = T N is the slave basis recombined edge by edge
//! (Popp et al. 2012 §3.2, `crate::quadratic_slave`, α = 1/5), because the
//! standard Tri6 and Quad8 functions have ∫N = 0 and < 0 at the corners, which
//! would leave D_jj zero or negative there: with Ñ every D_jj is positive
//! (A/20 at a flat Quad8's corners, 2A/15 at a Tri6's, A/5 at the
//! mid-sides). The weighted gaps are then those of the recombined slave
//! displacements ũ = T⁻ᵀ u ([`transform_slave_rows`]).
//!
//! Integration (Puso–Laursen; Popp et al. 2010 §4.2), per slave cell and per
//! master cell that faces it (candidates from the R*-tree of the master's
//! face boxes along the slave cell's normal, `geometry::FacetSearch`); a
//! linear face is one cell, a quadratic face is cut into flat cells through
//! its mid-side nodes ([`cells`]):
//! 1. the auxiliary plane through the slave cell's centre with its unit
//!    normal n0 (a quadrilateral's from its diagonals, as
//!    `Mesh::facet_normal`);
//! 2. both cells projected onto it along n0, the slave polygon clipped by
//!    the (convex) master polygon (Sutherland–Hodgman, [`clipping::clip`]);
//!    the pair is kept when the master lies in front of the slave at the
//!    clip polygon's centroid within the search distance, or behind it (an
//!    initial overlap) by less than the slave cell's diameter;
//! 3. the clip polygon cut into triangles about its centroid, each with a
//!    7-point Gauss rule of degree 5 (linear faces) or the 16-point rule of
//!    degree 6 (when a face of either surface is quadratic); each point is
//!    mapped back to the slave and master cells along n0 (barycentric
//!    coordinates on triangles, the inverse bilinear map by Newton's method
//!    on quadrilaterals, `geometry::meet_face`), and from the cells to the
//!    faces' reference coordinates, where the shape functions are evaluated.
//!
//! The measure is the auxiliary planes' area, the slave face's own on a flat
//! face. On flat faces with affine maps (triangles, parallelograms, and
//! their quadratic versions with centred mid-side nodes) the integrands are
//! polynomials of degree ≤ 4 (linear) or ≤ 6 (quadratic): exact, so
//! Σ_l M_jl = D_jj to round-off (a rigid translation keeps every weighted
//! gap) and a uniform pressure crosses non-matching meshes exactly (the
//! patch test). A curved quadratic slave face (a mid-side node off its
//! side's chord) is integrated on the curved faces instead, in its reference
//! coordinates ([`curved`]).
//!
//! Each slave node becomes one [`crate::ContactPoint`] exactly as in 2D
//! (`mortar::mortar_points`): the row n_j·(ũ_j − Σ_l (M_jl/D_jj) u_l) with
//! n_j the reversed averaged nodal normal, measure D_jj, and the tangential
//! rows along the frame of `geometry::tangent_frame(n_j)` with the same
//! weights: friction in 3D works on the weighted slips t·(D ũ_s − M u_m)/D_jj.
//! The nodes of curved slave faces take the normal row with the normal inside
//! the integral instead, and the tangential rows with a frame turning with
//! the surface inside it ([`curved_rows`], `ContactPoint::normal_row` and
//! `ContactPoint::tangent_rows`).

mod cells;
mod clipping;
mod curved;
mod curved_rows;

use signorini_mesh::vec3::{dot, norm, sub};
use signorini_mesh::{Facet, Mesh, Surface};
use std::collections::{BTreeMap, BTreeSet};

use crate::error::GeometryError;
use crate::mortar::{mortar_master, mortar_points, MortarInput, MortarPairing};
use crate::pairing::{meet_face, nodal_normals, search_distance, FacetSearch, MasterGeometry};
use crate::TermSide;
use cells::{Cell, FaceShape, MAX_FACE_NODES};
use clipping::{
    clip, collapsed_rule, counter_clockwise, polygon_rule, signed_area, AuxPlane, Point2,
    TRIANGLE_RULE,
};
use curved_rows::CurvedRows;

/// Relative area (of a slave face) below which a clipped overlap is ignored:
/// a sliver from rounding along a shared edge.
const SLIVER: f64 = 1e-8;

/// Relative tolerance of the clipping's inside test (of the slave face's
/// diameter): vertices of the two meshes on a common line stay inside.
const CLIP_TOL: f64 = 1e-12;

/// An integration point of a slave face: its weight (an area), the slave
/// face's (recombined) shape functions there, the master face and its shape
/// functions, and the slave face's unit outward normal there.
struct FacePoint {
    w: f64,
    ns: FaceShape,
    master: usize,
    nm: FaceShape,
    normal: [f64; 3],
}

/// A slave integration cell (a linear face, or a piece of a quadratic one):
/// its nodes, corners, auxiliary plane and size.
struct SlaveFace<'a> {
    nodes: &'a [usize],
    plane: AuxPlane,
    polygon: Vec<Point2>,
    area: f64,
    diameter: f64,
}

impl<'a> SlaveFace<'a> {
    /// `None` for a degenerate (zero-area) cell.
    fn new(mesh: &Mesh, nodes: &'a [usize], cell: usize) -> Option<Self> {
        let x: Vec<[f64; 3]> = nodes.iter().map(|&k| mesh.coords[k]).collect();
        let (n0, _) = mesh.facet_normal(&Facet {
            nodes: nodes.to_vec(),
            cell,
        });
        let mut centre = [0.0; 3];
        for p in &x {
            for k in 0..3 {
                centre[k] += p[k] / x.len() as f64;
            }
        }
        let diameter = x
            .iter()
            .flat_map(|a| x.iter().map(move |b| norm(sub(*a, *b))))
            .fold(0.0, f64::max);
        let plane = AuxPlane::new(centre, n0);
        let polygon = counter_clockwise(x.iter().map(|&p| plane.coords(p)).collect());
        let area = signed_area(&polygon);
        (norm(n0) > 0.5 && area > 0.0).then_some(SlaveFace {
            nodes,
            plane,
            polygon,
            area,
            diameter,
        })
    }
}

/// The master side of the integration: the mesh, surface, integration cells
/// of every face, the R*-tree of the faces and the search distance.
struct MasterCells<'a> {
    mesh: &'a Mesh,
    surface: &'a Surface,
    cells: Vec<Vec<Cell>>,
    index: FacetSearch<'a>,
    reach: f64,
}

/// The 3D mortar pairing of a slave surface of linear or quadratic faces
/// with a deformable master surface of linear or quadratic faces (see the
/// module documentation). Slave nodes none of whose faces overlap the
/// master are not contact points; they are counted as `off_surface` in
/// [`crate::pairing::Dropped`].
pub fn mortar3d_pairing(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
) -> Result<MortarPairing, GeometryError> {
    let input = MortarInput {
        dim: 3,
        facet_nodes: &[3, 4, 6, 8],
        rigid_hint: "a rigid plane or sphere: use node_to_face",
        wrong_dimension: "mortar3d_pairing needs two 3D meshes (in 2D see mortar::mortar_pairing)",
        wrong_facets: "mortar in 3D needs faces of 3 or 4 nodes (linear) or 6 or 8 (quadratic: corners, then mid-sides)",
    };
    let (m_mesh, m_surf) = mortar_master(slave_mesh, slave_surface, master, &input)?;
    let masters = MasterCells {
        mesh: m_mesh,
        surface: m_surf,
        cells: m_surf.facets.iter().map(cells::cells).collect(),
        index: FacetSearch::new(m_mesh, m_surf)?,
        reach: search_distance(slave_mesh, master),
    };
    // Products of quadratic shape functions need the rule of degree 6; the
    // linear faces keep the rule of degree 5.
    let quadratic = (slave_surface.facets.iter())
        .chain(&m_surf.facets)
        .any(cells::is_quadratic);
    let rule = if quadratic {
        collapsed_rule()
    } else {
        TRIANGLE_RULE.to_vec()
    };
    let normals: BTreeMap<usize, [f64; 3]> = nodal_normals(slave_mesh, slave_surface)
        .into_iter()
        .collect();
    let mut d = BTreeMap::<usize, f64>::new();
    let mut m = BTreeMap::<usize, BTreeMap<usize, f64>>::new();
    // The nodes of curved slave faces take rows with the normal inside the
    // integral (`curved`), over every face they belong to.
    let curved_nodes: BTreeSet<usize> = (slave_surface.facets.iter())
        .filter(|f| curved::is_curved(slave_mesh, f))
        .flat_map(|f| f.nodes.iter().copied())
        .collect();
    let mut vectors = CurvedRows::new(curved_nodes, &normals);
    for f in &slave_surface.facets {
        let vector = vectors.touches(&f.nodes).then_some(&mut vectors);
        if curved::is_curved(slave_mesh, f) {
            let points = curved::face_points(slave_mesh, f, &masters, &rule);
            let area = slave_mesh.facet_normal(f).1;
            integrate_face(&f.nodes, area, &points, m_surf, (&mut d, &mut m), vector);
            continue;
        }
        let (mut points, mut area) = (Vec::new(), 0.0);
        for cell in cells::cells(f) {
            let Some(face) = SlaveFace::new(slave_mesh, &cell.nodes, f.cell) else {
                continue;
            };
            area += face.area;
            for mut p in face_points(slave_mesh, &face, &masters, &rule) {
                p.ns =
                    cells::recombined(f.nodes.len(), cell.face_shape(first4(p.ns), f.nodes.len()));
                points.push(p);
            }
        }
        integrate_face(&f.nodes, area, &points, m_surf, (&mut d, &mut m), vector);
    }
    let mut out = mortar_points(slave_mesh, &normals, &d, &m, m_mesh, masters.reach);
    transform_slave_rows(slave_mesh, slave_surface, &mut out);
    let meshes = [slave_mesh, m_mesh];
    curved_rows::write_rows(meshes, slave_surface, &vectors, &mut out);
    Ok(out)
}

fn first4(n: FaceShape) -> [f64; 4] {
    [n[0], n[1], n[2], n[3]]
}

/// The integration points of a slave cell over its overlaps with the
/// master cells that face it (steps 1–3 of the module documentation): the
/// slave cell's own weights in `ns` (the caller turns them into the face's
/// shape functions), the master face's shape functions in `nm`.
fn face_points(
    s_mesh: &Mesh,
    face: &SlaveFace<'_>,
    masters: &MasterCells<'_>,
    rule: &[(f64, f64, f64)],
) -> Vec<FacePoint> {
    let (m_mesh, m_surf) = (masters.mesh, masters.surface);
    let n0 = face.plane.normal();
    let origin = face.plane.point([0.0, 0.0]);
    let from = [0, 1, 2].map(|k| origin[k] - face.diameter * n0[k]);
    let to = [0, 1, 2].map(|k| origin[k] + masters.reach * n0[k]);
    let mut out = Vec::new();
    for k in masters.index.crossed(from, to, face.diameter) {
        let mf = &m_surf.facets[k];
        for cell in &masters.cells[k] {
            let Some(poly) = overlap(face, m_mesh, &cell.nodes, mf.cell) else {
                continue;
            };
            // In front within the search distance, or behind by less than
            // the face's diameter, at the clip polygon's centroid.
            let c = poly.iter().fold([0.0; 2], |a, p| {
                [
                    a[0] + p[0] / poly.len() as f64,
                    a[1] + p[1] / poly.len() as f64,
                ]
            });
            let xc = face.plane.point(c);
            let (Some((_, gs)), Some((_, gm))) = (
                meet_face(s_mesh, face.nodes, xc, n0),
                meet_face(m_mesh, &cell.nodes, xc, n0),
            ) else {
                continue;
            };
            let gap = gs - gm;
            if !(-face.diameter..=masters.reach).contains(&gap) {
                continue;
            }
            for (p, w) in polygon_rule(&poly, rule) {
                let x = face.plane.point(p);
                if let (Some((ns, _)), Some((nm, _))) = (
                    meet_face(s_mesh, face.nodes, x, n0),
                    meet_face(m_mesh, &cell.nodes, x, n0),
                ) {
                    let mut own = [0.0; MAX_FACE_NODES];
                    own[..4].copy_from_slice(&ns);
                    out.push(FacePoint {
                        w,
                        ns: own,
                        master: k,
                        nm: cell.face_shape(nm, mf.nodes.len()),
                        normal: n0,
                    });
                }
            }
        }
    }
    out
}

/// The clip polygon of a slave cell and the master cell with `nodes` (of
/// cell `cell`) in the slave cell's plane, when the master cell faces the
/// slave and the overlap is more than a sliver.
fn overlap(
    face: &SlaveFace<'_>,
    m_mesh: &Mesh,
    nodes: &[usize],
    cell: usize,
) -> Option<Vec<Point2>> {
    let (nm, _) = m_mesh.facet_normal(&Facet {
        nodes: nodes.to_vec(),
        cell,
    });
    // The master face must face the slave.
    if dot(nm, face.plane.normal()) >= 0.0 {
        return None;
    }
    let master_polygon = counter_clockwise(
        nodes
            .iter()
            .map(|&v| face.plane.coords(m_mesh.coords[v]))
            .collect(),
    );
    let poly = clip(&face.polygon, &master_polygon, CLIP_TOL * face.diameter);
    (poly.len() >= 3 && signed_area(&poly) > SLIVER * face.area).then_some(poly)
}

/// Dual basis coefficients: row j holds Φ_j = Σ_k A_jk Ñ_k.
type DualCoefficients = [[f64; MAX_FACE_NODES]; MAX_FACE_NODES];

/// The dual basis coefficients A_e = D_e M_e⁻¹ of a slave face with `n`
/// nodes over its covered part (the integration points), or `None` when the
/// covered part is too small for them (M_e nearly singular).
fn dual_coefficients(points: &[FacePoint], n: usize, area: f64) -> Option<DualCoefficients> {
    const N: usize = MAX_FACE_NODES;
    let (mut me, mut de) = ([[0.0; N]; N], [0.0; N]);
    for p in points {
        for (a, row) in me.iter_mut().enumerate().take(n) {
            de[a] += p.w * p.ns[a];
            for (b, mab) in row.iter_mut().enumerate().take(n) {
                *mab += p.w * p.ns[a] * p.ns[b];
            }
        }
    }
    let covered: f64 = de[..n].iter().sum();
    if covered <= SLIVER * area {
        return None;
    }
    // Cholesky M_e = L Lᵀ; a pivot below 10⁻⁹ of the covered area (a fully
    // covered triangle's least eigenvalue is area/12) means a sliver.
    let mut l = [[0.0; N]; N];
    for j in 0..n {
        let s = me[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if s <= 1e-9 * covered {
            return None;
        }
        l[j][j] = s.sqrt();
        for i in j + 1..n {
            let t = me[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            l[i][j] = t / l[j][j];
        }
    }
    // A = D_e M_e⁻¹: row a solves M_e x = D_aa e_a (M_e is symmetric).
    let mut a = [[0.0; N]; N];
    for (r, row) in a.iter_mut().enumerate().take(n) {
        let mut y = [0.0; N];
        for i in 0..n {
            let rhs = if i == r { de[r] } else { 0.0 };
            y[i] = (rhs - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
        }
        for i in (0..n).rev() {
            row[i] = (y[i] - (i + 1..n).map(|k| l[k][i] * row[k]).sum::<f64>()) / l[i][i];
        }
    }
    Some(a)
}

/// D (diagonal, per slave node) and M (per slave node, per master node).
type MortarSums<'a> = (
    &'a mut BTreeMap<usize, f64>,
    &'a mut BTreeMap<usize, BTreeMap<usize, f64>>,
);

/// Adds the contributions of a slave face (its `nodes`, the `area` of its
/// cells) to D (diagonal) and M, and to the rows with the normal inside the
/// integral when `vectors` is given.
fn integrate_face(
    nodes: &[usize],
    area: f64,
    points: &[FacePoint],
    m_surf: &Surface,
    (d, m): MortarSums<'_>,
    mut vectors: Option<&mut CurvedRows>,
) {
    let n = nodes.len();
    let Some(a) = dual_coefficients(points, n, area) else {
        return;
    };
    for p in points {
        let master = &m_surf.facets[p.master].nodes;
        for (aj, &sj) in a.iter().zip(nodes) {
            let phi: f64 = (0..n).map(|k| aj[k] * p.ns[k]).sum();
            // Lumped row: Σ_k ∫Φ_j Ñ_k = ∫Φ_j = D_jj by biorthogonality.
            *d.entry(sj).or_insert(0.0) += p.w * phi;
            let row = m.entry(sj).or_default();
            for (&ml, nml) in master.iter().zip(p.nm) {
                *row.entry(ml).or_insert(0.0) += p.w * phi * nml;
            }
            if let Some(v) = vectors.as_deref_mut() {
                let slave = (nodes.iter().zip(p.ns)).map(|(&k, s)| (TermSide::Slave, k, s));
                let master = (master.iter().zip(p.nm)).map(|(&l, s)| (TermSide::Master, l, s));
                v.add(sj, p.w * phi, p.normal, slave.chain(master));
            }
        }
    }
}

/// On a quadratic slave surface the weighted gaps are those of the
/// recombined displacements ũ = T⁻ᵀ u (u_h = Σ N_k u_k = Σ Ñ_k ũ_k): a
/// corner's ũ_c = u_c, a mid-side's ũ_m = (u_m − α (u_c1 + u_c2)) / (1 − 2α).
/// Rewrites each mid-side row's slave term and initial gap accordingly (the
/// master terms M_jl / D_jj stay); corner rows and linear surfaces are left
/// as they are.
fn transform_slave_rows(mesh: &Mesh, surface: &Surface, out: &mut MortarPairing) {
    let edges: BTreeMap<usize, [usize; 2]> = crate::quadratic_slave::mid_side_edges(3, surface)
        .into_iter()
        .collect();
    if edges.is_empty() {
        return;
    }
    let alpha = crate::quadratic_slave::ALPHA;
    let (own, corner) = (1.0 / (1.0 - 2.0 * alpha), -alpha / (1.0 - 2.0 * alpha));
    for p in &mut out.pairing.points {
        let Some(&[c1, c2]) = edges.get(&p.slave_node) else {
            continue;
        };
        let (x1, x2) = (mesh.coords[c1], mesh.coords[c2]);
        // n · (x̃_m − x_m), x̃_m = own x_m + corner (x_c1 + x_c2).
        let shift: f64 = (0..3)
            .map(|k| p.normal[k] * ((own - 1.0) * p.x[k] + corner * (x1[k] + x2[k])))
            .sum();
        p.gap0 += shift;
        for t in &mut p.terms {
            if t.side == crate::TermSide::Slave {
                t.weight *= own;
            }
        }
        p.terms.insert(1, slave_term(c1, corner));
        p.terms.insert(2, slave_term(c2, corner));
    }
}

fn slave_term(node: usize, weight: f64) -> crate::Term {
    crate::Term {
        side: crate::TermSide::Slave,
        node,
        weight,
    }
}

#[cfg(test)]
mod tests;
