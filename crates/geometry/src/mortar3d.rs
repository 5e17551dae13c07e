//! Mortar contact in 3D (segment-based integration over clipped polygons,
//! linear slave and master faces: 3-node triangles, 4-node quadrilaterals)
//! with dual Lagrange multipliers: the 3D counterpart of [`crate::mortar`].
//!
//! References: M. Puso, T. Laursen, "A mortar segment-to-segment contact
//! method for large deformation solid mechanics", CMAME 193 (2004) §3;
//! A. Popp, M. Gitterle, M. Gee, W. Wall, "A dual mortar approach for 3D
//! finite deformation contact with consistent linearization", IJNME 83
//! (2010) §3–4; B. Wohlmuth, SINUM 38 (2000); the project's notes
//! docs/theory/mortar.md.
//!
//! The operators are those of the 2D module, over the slave surface Γ_c
//! that faces the master:
//!
//! ```text
//! D_jk = ∫_Γc Φ_j N_k^s dγ = δ_jk ∫_Γc N_j dγ,   M_jl = ∫_Γc Φ_j (N_l^m ∘ π) dγ,
//! ```
//!
//! with dual shape functions Φ = A_e N on each slave face, A_e = D_e M_e⁻¹
//! (D_e = diag ∫N, M_e = ∫N Nᵀ over the face's covered part: on a fully
//! covered triangle Φ_i = 3N_i − N_j − N_k; partly covered faces get the
//! "boundary modification" of Popp et al. as in 2D).
//!
//! Integration (Puso–Laursen; Popp et al. 2010 §4.2), per slave face and per
//! master face that faces it (candidates from the R*-tree of the master's
//! face boxes along the slave face's normal, `geometry::FacetSearch`):
//! 1. the auxiliary plane through the slave face's centre with its unit
//!    normal n0 (a quadrilateral's from its diagonals, as
//!    `Mesh::facet_normal`);
//! 2. both faces projected onto it along n0, the slave polygon clipped by
//!    the (convex) master polygon (Sutherland–Hodgman, [`clipping::clip`]);
//!    the pair is kept when the master lies in front of the slave at the
//!    clip polygon's centroid within the search distance, or behind it (an
//!    initial overlap) by less than the slave face's diameter;
//! 3. the clip polygon cut into triangles about its centroid, each with a
//!    7-point Gauss rule of degree 5; each point is mapped back to the slave
//!    and master faces along n0 (barycentric coordinates on triangles, the
//!    inverse bilinear map by Newton's method on quadrilaterals,
//!    `geometry::meet_face`), where the shape functions are evaluated.
//!
//! The measure is the auxiliary plane's area, the slave face's own on a flat
//! face. On flat faces with affine maps (triangles, parallelograms) the
//! integrands are polynomials of degree ≤ 4: exact, so Σ_l M_jl = D_jj to
//! round-off (a rigid translation keeps every weighted gap) and a uniform
//! pressure crosses non-matching meshes exactly (the patch test).
//!
//! Each slave node becomes one [`crate::ContactPoint`] exactly as in 2D
//! (`mortar::mortar_points`): the row n_j·(u_j − Σ_l (M_jl/D_jj) u_l) with
//! n_j the reversed averaged nodal normal, measure D_jj, and the tangential
//! rows along the frame of `geometry::tangent_frame(n_j)` with the same
//! weights: friction in 3D works on the weighted slips t·(D u_s − M u_m)/D_jj.

mod clipping;

use signorini_mesh::vec3::{dot, norm, sub};
use signorini_mesh::{Mesh, Surface};
use std::collections::BTreeMap;

use crate::error::GeometryError;
use crate::mortar::{mortar_master, mortar_points, MortarInput, MortarPairing};
use crate::pairing::{meet_face, nodal_normals, search_distance, FacetSearch, MasterGeometry};
use clipping::{clip, counter_clockwise, polygon_rule, signed_area, AuxPlane, Point2};

/// Relative area (of a slave face) below which a clipped overlap is ignored:
/// a sliver from rounding along a shared edge.
const SLIVER: f64 = 1e-8;

/// Relative tolerance of the clipping's inside test (of the slave face's
/// diameter): vertices of the two meshes on a common line stay inside.
const CLIP_TOL: f64 = 1e-12;

/// An integration point of a slave face: its weight (an area), the slave
/// face's shape functions there, the master face and its shape functions.
struct FacePoint {
    w: f64,
    ns: [f64; 4],
    master: usize,
    nm: [f64; 4],
}

/// A slave face: its nodes, corners, auxiliary plane and size.
struct SlaveFace<'a> {
    nodes: &'a [usize],
    plane: AuxPlane,
    polygon: Vec<Point2>,
    area: f64,
    diameter: f64,
}

impl<'a> SlaveFace<'a> {
    /// `None` for a degenerate (zero-area) face.
    fn new(mesh: &Mesh, f: &'a signorini_mesh::Facet) -> Option<Self> {
        let x: Vec<[f64; 3]> = f.nodes.iter().map(|&k| mesh.coords[k]).collect();
        let (n0, _) = mesh.facet_normal(f);
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
            nodes: &f.nodes,
            plane,
            polygon,
            area,
            diameter,
        })
    }
}

/// The 3D mortar pairing of a slave surface of linear faces with a
/// deformable master surface of linear faces (see the module
/// documentation). Slave nodes none of whose faces overlap the master are
/// not contact points; they are counted as `off_surface` in
/// [`crate::pairing::Dropped`].
pub fn mortar3d_pairing(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
) -> Result<MortarPairing, GeometryError> {
    let input = MortarInput {
        dim: 3,
        facet_nodes: [3, 4],
        rigid_hint: "a rigid plane or sphere: use node_to_face",
        wrong_dimension: "mortar3d_pairing needs two 3D meshes (in 2D see mortar::mortar_pairing)",
        wrong_facets: "mortar in 3D is implemented for linear faces only (3-node triangles, 4-node quadrilaterals), not quadratic ones (use node_to_face)",
    };
    let (m_mesh, m_surf) = mortar_master(slave_mesh, slave_surface, master, &input)?;
    let index = FacetSearch::new(m_mesh, m_surf)?;
    let reach = search_distance(slave_mesh, master);
    let normals: BTreeMap<usize, [f64; 3]> = nodal_normals(slave_mesh, slave_surface)
        .into_iter()
        .collect();
    let mut d = BTreeMap::<usize, f64>::new();
    let mut m = BTreeMap::<usize, BTreeMap<usize, f64>>::new();
    for f in &slave_surface.facets {
        let Some(face) = SlaveFace::new(slave_mesh, f) else {
            continue;
        };
        let points = face_points(slave_mesh, &face, (m_mesh, m_surf), &index, reach);
        integrate_face(&face, &points, m_surf, &mut d, &mut m);
    }
    Ok(mortar_points(slave_mesh, &normals, &d, &m, m_mesh, reach))
}

/// The integration points of a slave face over its overlaps with the
/// master faces that face it (steps 1–3 of the module documentation).
fn face_points(
    s_mesh: &Mesh,
    face: &SlaveFace<'_>,
    (m_mesh, m_surf): (&Mesh, &Surface),
    index: &FacetSearch<'_>,
    reach: f64,
) -> Vec<FacePoint> {
    let n0 = face.plane.normal();
    let origin = face.plane.point([0.0, 0.0]);
    let from = [0, 1, 2].map(|k| origin[k] - face.diameter * n0[k]);
    let to = [0, 1, 2].map(|k| origin[k] + reach * n0[k]);
    let mut out = Vec::new();
    for k in index.crossed(from, to, face.diameter) {
        let mf = &m_surf.facets[k];
        let (nm, _) = m_mesh.facet_normal(mf);
        // The master face must face the slave.
        if dot(nm, n0) >= 0.0 {
            continue;
        }
        let master_polygon = counter_clockwise(
            mf.nodes
                .iter()
                .map(|&v| face.plane.coords(m_mesh.coords[v]))
                .collect(),
        );
        let poly = clip(&face.polygon, &master_polygon, CLIP_TOL * face.diameter);
        if poly.len() < 3 || signed_area(&poly) <= SLIVER * face.area {
            continue;
        }
        // In front within the search distance, or behind by less than the
        // face's diameter, at the clip polygon's centroid.
        let c = poly.iter().fold([0.0; 2], |a, p| {
            [
                a[0] + p[0] / poly.len() as f64,
                a[1] + p[1] / poly.len() as f64,
            ]
        });
        let xc = face.plane.point(c);
        let (Some((_, gs)), Some((_, gm))) = (
            meet_face(s_mesh, face.nodes, xc, n0),
            meet_face(m_mesh, &mf.nodes, xc, n0),
        ) else {
            continue;
        };
        let gap = gs - gm;
        if !(-face.diameter..=reach).contains(&gap) {
            continue;
        }
        for (p, w) in polygon_rule(&poly) {
            let x = face.plane.point(p);
            if let (Some((ns, _)), Some((nm, _))) = (
                meet_face(s_mesh, face.nodes, x, n0),
                meet_face(m_mesh, &mf.nodes, x, n0),
            ) {
                out.push(FacePoint {
                    w,
                    ns,
                    master: k,
                    nm,
                });
            }
        }
    }
    out
}

/// The dual basis coefficients A_e = D_e M_e⁻¹ of a slave face with `n`
/// nodes over its covered part (the integration points), or `None` when the
/// covered part is too small for them (M_e nearly singular).
fn dual_coefficients(points: &[FacePoint], n: usize, area: f64) -> Option<[[f64; 4]; 4]> {
    let (mut me, mut de) = ([[0.0; 4]; 4], [0.0; 4]);
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
    let mut l = [[0.0; 4]; 4];
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
    let mut a = [[0.0; 4]; 4];
    for (r, row) in a.iter_mut().enumerate().take(n) {
        let mut y = [0.0; 4];
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

/// Adds a slave face's contributions to D (diagonal) and M.
fn integrate_face(
    face: &SlaveFace<'_>,
    points: &[FacePoint],
    m_surf: &Surface,
    d: &mut BTreeMap<usize, f64>,
    m: &mut BTreeMap<usize, BTreeMap<usize, f64>>,
) {
    let n = face.nodes.len();
    let Some(a) = dual_coefficients(points, n, face.area) else {
        return;
    };
    for p in points {
        let master = &m_surf.facets[p.master].nodes;
        for (aj, &sj) in a.iter().zip(face.nodes) {
            let phi: f64 = (0..n).map(|k| aj[k] * p.ns[k]).sum();
            // Lumped row: Σ_k ∫Φ_j N_k = ∫Φ_j = D_jj by biorthogonality.
            *d.entry(sj).or_insert(0.0) += p.w * phi;
            let row = m.entry(sj).or_default();
            for (&ml, nml) in master.iter().zip(p.nm) {
                *row.entry(ml).or_insert(0.0) += p.w * phi * nml;
            }
        }
    }
}

#[cfg(test)]
mod tests;
