//! Mortar contact in 2D (segment-to-segment; linear or quadratic slave and
//! master edges) with dual Lagrange multipliers.
//!
//! References: B. Wohlmuth, "A mortar finite element method using dual
//! spaces for the Lagrange multiplier", SINUM 38 (2000); A. Popp, M. Gee,
//! W. Wall, "A finite deformation mortar contact formulation using a
//! primal–dual active set strategy", IJNME 79 (2009), §3–4; the project's
//! docs/theory/mortar.md.
//!
//! The multiplier λ_j of slave node j is a pressure with shape function Φ_j.
//! Over the part Γ_c of the slave surface that projects onto the master:
//!
//! ```text
//! D_jk = ∫_Γc Φ_j N_k^s dγ,    M_jl = ∫_Γc Φ_j (N_l^m ∘ π) dγ,
//! g̃_j  = n_jᵀ ( D_jj x_j − Σ_l M_jl x_l ) + n_jᵀ ( D_jj u_j − Σ_l M_jl u_l ),
//! ```
//!
//! with π the projection of a slave point onto the master along the slave
//! normal interpolated between the nodes, n(ξ) = Σ N_k(ξ) n_k, and n_j the
//! contact normal at node j (the slave's averaged nodal normal, reversed: from
//! master to slave). The dual basis is biorthogonal to the slave's shape
//! functions on Γ_c, ∫_Γc Φ_j N_k = δ_jk ∫_Γc N_k, so D is diagonal. On a
//! fully projected 2-node segment Φ_1 = 2N_1 − N_2, Φ_2 = 2N_2 − N_1; in
//! general (a partly projected edge, a 3-node edge) the coefficients come
//! from the covered part only, A_e = D_e M_e⁻¹ (D_e = diag ∫N, M_e = ∫N Nᵀ
//! over the covered part; the "boundary modification" of Popp et al.), which
//! keeps D_jj = ∫_Γc N_j > 0 (on a quadratic edge ∫N = 1/6, 1/6, 2/3 of its
//! length: every node has a positive measure, see [`edge`]).
//!
//! Edges: 2 nodes `[c0, c1]` or 3 `[c0, c1, mid]` (the facets of Quad8 and
//! Tri6 cells), with their shape functions on ξ ∈ [0, 1]; the geometry is
//! the edge's own, x(ξ) = Σ N_k(ξ) x_k (curved for a quadratic edge whose
//! mid-side node is off the chord), dγ = |x'(ξ)| dξ, and the normal field is
//! interpolated with the same shape functions.
//!
//! Overlap (Popp et al. §4.1): the master end points are projected onto each
//! slave edge along n(ξ) (a quadratic equation in ξ on a 2-node edge, Newton
//! on a 3-node one); the overlap is an interval of ξ (kept when the master
//! lies in front of the slave within the search distance, or behind it by
//! less than the slave edge's length), integrated with a 4-point Gauss rule,
//! at each point of which the slave point is projected onto the master edge
//! along n(ξ) (closed form on a straight edge, Newton on a quadratic one). On
//! flat interfaces the integrands are polynomials of degree ≤ 2 (linear
//! edges) or ≤ 4 (quadratic edges with centred mid-side nodes): exact.
//!
//! Each slave node gives one [`ContactPoint`] whose row is the weighted gap
//! divided by D_jj: n_j·(u_j − Σ_l (M_jl/D_jj) u_l), gap0 = g̃0_j/D_jj. Its
//! multiplier is then the nodal force D_jj λ_j and its measure (tributary,
//! see [`MortarPairing::measure`]) is D_jj, so force / measure = λ_j, the
//! pressure, and Σ_j D_jj λ_j is the resultant. Scaling a row of the LCP by
//! a positive constant does not change its solution: the rows behave as
//! node-to-segment rows downstream (condensation, Delassus operator, every
//! algorithm, tangential rows t_j with the same weights for friction).
//! Σ_l M_jl = D_jj (the master shape functions sum to 1), so the master
//! weights sum to −1: a rigid translation leaves every gap unchanged.

use signorini_mesh::vec3::{dot, norm, sub};
use signorini_mesh::{Mesh, Surface};
use std::collections::BTreeMap;

use crate::error::GeometryError;
use crate::pairing::{
    nodal_normals, search_distance, ContactPoint, Dropped, MasterGeometry, Pairing, Term,
};
use edge::{Edge, SlaveEdge};

/// Gauss–Legendre points and weights on [0, 1] (4 points: exact to degree 7).
pub(crate) const GAUSS: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// Relative length (of a slave segment's parameter range) below which an
/// overlap or a covered part is ignored: a sliver from round-off at a
/// shared end point, or a covered part too short for its dual basis
/// (M_e ≈ rank one).
const SLIVER: f64 = 1e-8;

/// Mortar contact points and the slave nodes' mortar measures D_jj.
#[derive(Debug, Clone, PartialEq)]
pub struct MortarPairing {
    pub pairing: Pairing,
    /// D_jj = ∫_Γc N_j per contact point's slave node: the measure that
    /// turns its multiplier (a force) into the pressure λ_j.
    pub measure: BTreeMap<usize, f64>,
}

/// One overlap of a slave edge with a master edge: the slave parameter
/// interval [lo, hi] ⊂ [0, 1] and the master edge.
struct Overlap {
    lo: f64,
    hi: f64,
    master: Edge,
}

/// The Gauss points (ξ, weight in ξ) of an overlap.
fn gauss_points(o: &Overlap) -> impl Iterator<Item = (f64, f64)> + '_ {
    GAUSS
        .iter()
        .map(move |&(t, w)| (o.lo + t * (o.hi - o.lo), w * (o.hi - o.lo)))
}

/// What the mortar pairing of one dimension accepts, and the messages that
/// say what is wrong otherwise.
pub(crate) struct MortarInput<'s> {
    /// The dimension of both meshes.
    pub dim: usize,
    /// The node counts of the facets of both surfaces.
    pub facet_nodes: &'s [usize],
    /// What to use instead against a rigid master.
    pub rigid_hint: &'s str,
    pub wrong_dimension: &'s str,
    pub wrong_facets: &'s str,
}

/// The master's mesh and surface when the pair is one `input` accepts: a
/// deformable master, meshes of its dimension, facets of its node counts.
pub(crate) fn mortar_master<'a>(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'a>,
    input: &MortarInput<'_>,
) -> Result<(&'a Mesh, &'a Surface), GeometryError> {
    let MasterGeometry::Surface { mesh, surface } = master else {
        return Err(GeometryError(format!(
            "mortar needs a deformable master surface ({})",
            input.rigid_hint
        )));
    };
    if slave_mesh.dim != input.dim || mesh.dim != input.dim {
        return Err(GeometryError(input.wrong_dimension.into()));
    }
    let accepted =
        |s: &Surface| (s.facets.iter()).all(|f| input.facet_nodes.contains(&f.nodes.len()));
    if !accepted(slave_surface) || !accepted(surface) {
        return Err(GeometryError(input.wrong_facets.into()));
    }
    Ok((mesh, surface))
}

/// The 2D mortar pairing of a slave surface of linear or quadratic edges
/// with a deformable master surface of linear or quadratic edges (see the
/// module documentation). Slave nodes whose edges do not project onto the
/// master (within the [`search_distance`]) are not contact points; they are
/// counted as `off_surface` in [`Dropped`].
pub fn mortar_pairing(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
) -> Result<MortarPairing, GeometryError> {
    let input = MortarInput {
        dim: 2,
        facet_nodes: &[2, 3],
        rigid_hint: "a rigid plane or circle: use node_to_segment",
        wrong_dimension:
            "mortar_pairing needs two 2D meshes (in 3D see mortar3d::mortar3d_pairing)",
        wrong_facets:
            "mortar needs edges of 2 nodes (linear) or 3 (quadratic: corner, corner, mid-side)",
    };
    let (m_mesh, m_surf) = mortar_master(slave_mesh, slave_surface, master, &input)?;
    let reach = search_distance(slave_mesh, master);
    let normals: BTreeMap<usize, [f64; 3]> = nodal_normals(slave_mesh, slave_surface)
        .into_iter()
        .collect();
    let masters: Vec<(Edge, [f64; 2])> = m_surf
        .facets
        .iter()
        .map(|f| (Edge::of(m_mesh, f), m_mesh.facet_normal_2d(f).0))
        .collect();
    let mut d = BTreeMap::<usize, f64>::new();
    let mut m = BTreeMap::<usize, BTreeMap<usize, f64>>::new();
    for f in &slave_surface.facets {
        let edge = Edge::of(slave_mesh, f);
        let seg = SlaveEdge {
            edge,
            n: edge
                .nodes
                .map(|k| normals.get(&k).copied().unwrap_or([0.0; 3])),
        };
        let overlaps = segment_overlaps(&seg, &masters, reach);
        integrate_segment(&seg, &overlaps, &mut d, &mut m);
    }
    Ok(mortar_points(slave_mesh, &normals, &d, &m, m_mesh, reach))
}

/// The overlaps of a slave edge with the master edges (with their outward
/// chord normals) that face it within `reach` along the slave normal (a
/// master point behind the slave, an initial overlap, by less than the
/// edge's length).
fn segment_overlaps(seg: &SlaveEdge, masters: &[(Edge, [f64; 2])], reach: f64) -> Vec<Overlap> {
    let mut out = Vec::new();
    let outward = seg.normal(0.5);
    for &(master, nm) in masters {
        // The master edge must face the slave.
        if nm[0] * outward[0] + nm[1] * outward[1] >= 0.0 {
            continue;
        }
        let (Some(a), Some(b)) = (seg.parameter_of(master.x[0]), seg.parameter_of(master.x[1]))
        else {
            continue;
        };
        let (lo, hi) = (a.min(b).max(0.0), a.max(b).min(1.0));
        if hi - lo <= SLIVER {
            continue;
        }
        let mid = 0.5 * (lo + hi);
        let (x, n) = (seg.point(mid), seg.normal(mid));
        // In front of the slave within the search distance, or behind it
        // (an initial overlap) by less than the edge's length: not a
        // master edge on the far side of the slave body.
        // The overlap's middle must project inside the master edge: the
        // end points' parameters can straddle the slave edge without
        // facing it (two normal lines nearly parallel to the master).
        let near = master.parameter_along(x, n).is_some_and(|eta| {
            let along = dot(sub(master.point(eta), x), n) / norm(n);
            (-SLIVER..=1.0 + SLIVER).contains(&eta) && along <= reach && along >= -seg.edge.chord()
        });
        if near {
            out.push(Overlap { lo, hi, master });
        }
    }
    out
}

/// The relative pivot of M_e (to its diagonal entry) below which the
/// covered part of a slave edge is too short for its dual basis. A 2-node
/// edge's pivots are at least 1/4 of their diagonal whatever the covered
/// part; a 3-node edge's smallest falls as (covered fraction)², so covered
/// parts below about 1e-5 of a quadratic edge are ignored.
const PIVOT_FLOOR: f64 = 1e-10;

/// The dual basis coefficients A_e = D_e M_e⁻¹ on the covered part of a
/// slave edge (Φ_j = Σ_k A_jk N_k), or None when it is too short.
fn dual_coefficients(seg: &SlaveEdge, overlaps: &[Overlap]) -> Option<[[f64; 3]; 3]> {
    let p = seg.edge.count;
    let (mut me, mut de, mut covered) = ([[0.0; 3]; 3], [0.0; 3], 0.0);
    for o in overlaps {
        covered += o.hi - o.lo;
        for (xi, w) in gauss_points(o) {
            let (nn, w) = (seg.edge.shape(xi), w * seg.jacobian(xi));
            for a in 0..p {
                de[a] += w * nn[a];
                for b in 0..p {
                    me[a][b] += w * nn[a] * nn[b];
                }
            }
        }
    }
    if covered <= SLIVER {
        return None;
    }
    let inv = inverse_spd(me, p)?;
    Some([0, 1, 2].map(|a| [0, 1, 2].map(|b| de[a] * inv[a][b])))
}

/// The inverse of the symmetric positive definite leading p × p block of m
/// (Gauss–Jordan), None when a pivot falls below [`PIVOT_FLOOR`] times its
/// diagonal entry.
fn inverse_spd(mut m: [[f64; 3]; 3], p: usize) -> Option<[[f64; 3]; 3]> {
    let mut inv = [[0.0; 3]; 3];
    (0..p).for_each(|k| inv[k][k] = 1.0);
    let diagonal = [0, 1, 2].map(|k| m[k][k]);
    for k in 0..p {
        let pivot = m[k][k];
        // Also false for a NaN pivot.
        let sound = pivot > PIVOT_FLOOR * diagonal[k] && diagonal[k] > 0.0;
        if !sound {
            return None;
        }
        for j in 0..p {
            m[k][j] /= pivot;
            inv[k][j] /= pivot;
        }
        for a in (0..p).filter(|&a| a != k) {
            let f = m[a][k];
            for j in 0..p {
                m[a][j] -= f * m[k][j];
                inv[a][j] -= f * inv[k][j];
            }
        }
    }
    Some(inv)
}

/// Adds a slave edge's contributions to D (diagonal) and M.
fn integrate_segment(
    seg: &SlaveEdge,
    overlaps: &[Overlap],
    d: &mut BTreeMap<usize, f64>,
    m: &mut BTreeMap<usize, BTreeMap<usize, f64>>,
) {
    let Some(a) = dual_coefficients(seg, overlaps) else {
        return;
    };
    for o in overlaps {
        for (xi, w) in gauss_points(o) {
            let w = w * seg.jacobian(xi);
            let (x, n) = (seg.point(xi), seg.normal(xi));
            let Some(eta) = o.master.parameter_along(x, n) else {
                continue;
            };
            let ns = seg.edge.shape(xi);
            let nm = o.master.shape(eta.clamp(0.0, 1.0));
            for (aj, &sj) in a.iter().zip(seg.edge.nodes()) {
                let phi = aj[0] * ns[0] + aj[1] * ns[1] + aj[2] * ns[2];
                // Lumped row: Σ_k ∫Φ_j N_k = ∫Φ_j = D_jj by biorthogonality.
                *d.entry(sj).or_insert(0.0) += w * phi;
                let row = m.entry(sj).or_default();
                for (&ml, nml) in o.master.nodes().iter().zip(nm) {
                    *row.entry(ml).or_insert(0.0) += w * phi * nml;
                }
            }
        }
    }
}

/// The contact points from D and M: one per slave node with D_jj > 0.
pub(crate) fn mortar_points(
    slave_mesh: &Mesh,
    normals: &BTreeMap<usize, [f64; 3]>,
    d: &BTreeMap<usize, f64>,
    m: &BTreeMap<usize, BTreeMap<usize, f64>>,
    m_mesh: &Mesh,
    reach: f64,
) -> MortarPairing {
    let largest = d.values().fold(0.0f64, |a, &v| a.max(v));
    let mut out = MortarPairing {
        pairing: Pairing {
            points: Vec::new(),
            dropped: Dropped::within(reach),
        },
        measure: BTreeMap::new(),
    };
    for (&s, n_out) in normals {
        let djj = d.get(&s).copied().unwrap_or(0.0);
        if djj <= 1e-9 * largest || largest <= 0.0 {
            out.pairing.dropped.off_surface += 1;
            continue;
        }
        let n = [-n_out[0], -n_out[1], -n_out[2]];
        let x = slave_mesh.coords[s];
        let mut terms = vec![Term::slave(s)];
        let mut xm = [0.0; 3];
        for (&l, &mjl) in m.get(&s).into_iter().flatten() {
            let w = mjl / djj;
            let y = m_mesh.coords[l];
            for k in 0..3 {
                xm[k] += w * y[k];
            }
            terms.push(Term::master(l, w));
        }
        let three_d = slave_mesh.dim == 3;
        (out.pairing.points).push(ContactPoint::new(s, (x, xm), n, terms, three_d));
        out.measure.insert(s, djj);
    }
    out
}

mod edge;
#[cfg(test)]
pub(crate) mod tests;
