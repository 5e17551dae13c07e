//! Mortar contact in 2D (segment-to-segment, linear slave and master edges)
//! with dual Lagrange multipliers.
//!
//! References: B. Wohlmuth, "A mortar finite element method using dual
//! spaces for the Lagrange multiplier", SINUM 38 (2000); A. Popp, M. Gee,
//! W. Wall, "A finite deformation mortar contact formulation using a
//! primal–dual active set strategy", IJNME 79 (2009), §3–4; the project's
//! notes `shared/notes/mortar.md`.
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
//! fully projected 2-node segment Φ_1 = 2N_1 − N_2, Φ_2 = 2N_2 − N_1; on a
//! partly projected one the coefficients come from the covered part only,
//! A_e = D_e M_e⁻¹ (D_e = diag ∫N, M_e = ∫N Nᵀ over the covered part; the
//! "boundary modification" of Popp et al.), which keeps D_jj = ∫_Γc N_j > 0.
//!
//! Overlap (Popp et al. §4.1): the master end points are projected onto each
//! slave segment along n(ξ) (a quadratic equation in ξ); the overlap is an
//! interval of ξ (kept when the master lies in front of the slave within the
//! search distance, or behind it by less than the slave segment's length),
//! integrated with a 4-point Gauss rule, at each point of which
//! the slave point is projected onto the master segment along n(ξ). On flat
//! interfaces the integrands are polynomials of degree ≤ 2: exact.
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

use crate::geometry::{
    nodal_normals, search_distance, tangents, ContactPoint, Dropped, MasterGeometry, Pairing, Term,
    TermSide,
};
use crate::ContactError;

/// Gauss–Legendre points and weights on [0, 1] (4 points: exact to degree 7).
const GAUSS: [(f64, f64); 4] = [
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

/// One overlap of a slave segment with a master segment: the slave
/// parameter interval [lo, hi] ⊂ [0, 1] and the master nodes (c, d).
struct Overlap {
    lo: f64,
    hi: f64,
    master: [usize; 2],
}

/// A 2-node slave segment: its nodes, end points and outward nodal normals.
struct SlaveSegment {
    nodes: [usize; 2],
    x: [[f64; 3]; 2],
    n: [[f64; 3]; 2],
}

impl SlaveSegment {
    fn point(&self, xi: f64) -> [f64; 3] {
        lerp(self.x[0], self.x[1], xi)
    }

    fn normal(&self, xi: f64) -> [f64; 3] {
        lerp(self.n[0], self.n[1], xi)
    }

    fn length(&self) -> f64 {
        norm(sub(self.x[1], self.x[0]))
    }

    /// The slave parameter ξ whose interpolated normal line passes through
    /// y: cross(x(ξ) − y, n(ξ)) = 0, a quadratic in ξ; the root nearest the
    /// segment's middle.
    fn parameter_of(&self, y: [f64; 3]) -> Option<f64> {
        let r = sub(self.x[0], y);
        let e = sub(self.x[1], self.x[0]);
        let dn = sub(self.n[1], self.n[0]);
        let (c0, c1, c2) = (
            cross2(r, self.n[0]),
            cross2(r, dn) + cross2(e, self.n[0]),
            cross2(e, dn),
        );
        let scale = c1.abs().max(c0.abs()).max(f64::MIN_POSITIVE);
        if c2.abs() <= 1e-12 * scale {
            return (c1.abs() > 0.0).then(|| -c0 / c1);
        }
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
        let roots = [q / c2, if q != 0.0 { c0 / q } else { q / c2 }];
        roots
            .into_iter()
            .min_by(|a, b| (a - 0.5).abs().total_cmp(&(b - 0.5).abs()))
    }
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
}

fn cross2(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The parameter η ∈ ℝ of the point of the line c–d met by the line
/// through x along n (None when they are parallel).
fn line_parameter(c: [f64; 3], d: [f64; 3], x: [f64; 3], n: [f64; 3]) -> Option<f64> {
    let f = sub(d, c);
    let den = cross2(f, n);
    (den.abs() > 1e-14 * norm(f) * norm(n)).then(|| -cross2(sub(c, x), n) / den)
}

/// The 2D mortar pairing of a slave surface of linear edges with a
/// deformable master surface of linear edges (see the module
/// documentation). Slave nodes whose segments do not project onto the
/// master (within the [`search_distance`]) are not contact points; they are
/// counted as `off_surface` in [`Dropped`].
pub fn mortar_pairing(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
) -> Result<MortarPairing, ContactError> {
    let MasterGeometry::Surface {
        mesh: m_mesh,
        surface: m_surf,
    } = master
    else {
        return Err(ContactError::Geometry(
            "mortar needs a deformable master surface (a rigid plane or circle: use node_to_segment)"
                .into(),
        ));
    };
    if slave_mesh.dim != 2 || m_mesh.dim != 2 {
        return Err(ContactError::Geometry(
            "mortar is implemented in 2D only (in 3D use node_to_face)".into(),
        ));
    }
    let linear = |s: &Surface| s.facets.iter().all(|f| f.nodes.len() == 2);
    if !linear(slave_surface) || !linear(m_surf) {
        return Err(ContactError::Geometry(
            "mortar is implemented for linear (2-node) edges only, not quadratic ones (use node_to_segment)"
                .into(),
        ));
    }
    let reach = search_distance(slave_mesh, master);
    let normals: BTreeMap<usize, [f64; 3]> = nodal_normals(slave_mesh, slave_surface)
        .into_iter()
        .collect();
    let mut d = BTreeMap::<usize, f64>::new();
    let mut m = BTreeMap::<usize, BTreeMap<usize, f64>>::new();
    for f in &slave_surface.facets {
        let nodes = [f.nodes[0], f.nodes[1]];
        let seg = SlaveSegment {
            nodes,
            x: nodes.map(|k| slave_mesh.coords[k]),
            n: nodes.map(|k| normals.get(&k).copied().unwrap_or([0.0; 3])),
        };
        let overlaps = segment_overlaps(&seg, m_mesh, m_surf, reach);
        integrate_segment(&seg, &overlaps, m_mesh, &mut d, &mut m);
    }
    Ok(mortar_points(slave_mesh, &normals, &d, &m, m_mesh, reach))
}

/// The overlaps of a slave segment with the master segments that face it
/// within `reach` along the slave normal (a master point behind the slave,
/// an initial overlap, by less than the segment's length).
fn segment_overlaps(
    seg: &SlaveSegment,
    m_mesh: &Mesh,
    m_surf: &Surface,
    reach: f64,
) -> Vec<Overlap> {
    let mut out = Vec::new();
    let outward = seg.normal(0.5);
    for f in &m_surf.facets {
        let (c, dn) = (f.nodes[0], f.nodes[1]);
        let (yc, yd) = (m_mesh.coords[c], m_mesh.coords[dn]);
        let (nm, _) = m_mesh.facet_normal_2d(f);
        // The master segment must face the slave.
        if nm[0] * outward[0] + nm[1] * outward[1] >= 0.0 {
            continue;
        }
        let (Some(a), Some(b)) = (seg.parameter_of(yc), seg.parameter_of(yd)) else {
            continue;
        };
        let (lo, hi) = (a.min(b).max(0.0), a.max(b).min(1.0));
        if hi - lo <= SLIVER {
            continue;
        }
        let mid = 0.5 * (lo + hi);
        let (x, n) = (seg.point(mid), seg.normal(mid));
        // In front of the slave within the search distance, or behind it
        // (an initial overlap) by less than the segment's length: not a
        // master facet on the far side of the slave body.
        // The overlap's middle must project inside the master segment: the
        // end points' parameters can straddle the slave segment without
        // facing it (two normal lines nearly parallel to the master).
        let near = line_parameter(yc, yd, x, n).is_some_and(|eta| {
            let along = dot(sub(lerp(yc, yd, eta), x), n) / norm(n);
            (-SLIVER..=1.0 + SLIVER).contains(&eta) && along <= reach && along >= -seg.length()
        });
        if near {
            out.push(Overlap {
                lo,
                hi,
                master: [c, dn],
            });
        }
    }
    out
}

/// The dual basis coefficients A_e = D_e M_e⁻¹ on the covered part of a
/// slave segment (per unit length), or None when it is too short.
fn dual_coefficients(overlaps: &[Overlap]) -> Option<[[f64; 2]; 2]> {
    let (mut me, mut de) = ([[0.0; 2]; 2], [0.0; 2]);
    for o in overlaps {
        for &(t, w) in &GAUSS {
            let xi = o.lo + t * (o.hi - o.lo);
            let nn = [1.0 - xi, xi];
            let w = w * (o.hi - o.lo);
            for a in 0..2 {
                de[a] += w * nn[a];
                for b in 0..2 {
                    me[a][b] += w * nn[a] * nn[b];
                }
            }
        }
    }
    let covered = de[0] + de[1];
    if covered <= SLIVER {
        return None;
    }
    let det = me[0][0] * me[1][1] - me[0][1] * me[1][0];
    // det ≈ covered⁴/12 for a short covered part.
    if det <= 1e-3 * covered.powi(4) * SLIVER {
        return None;
    }
    let inv = [
        [me[1][1] / det, -me[0][1] / det],
        [-me[1][0] / det, me[0][0] / det],
    ];
    Some([0, 1].map(|a| [0, 1].map(|b| de[a] * inv[a][b])))
}

/// Adds a slave segment's contributions to D (diagonal) and M.
fn integrate_segment(
    seg: &SlaveSegment,
    overlaps: &[Overlap],
    m_mesh: &Mesh,
    d: &mut BTreeMap<usize, f64>,
    m: &mut BTreeMap<usize, BTreeMap<usize, f64>>,
) {
    let Some(a) = dual_coefficients(overlaps) else {
        return;
    };
    let len = seg.length();
    for o in overlaps {
        let (yc, yd) = (m_mesh.coords[o.master[0]], m_mesh.coords[o.master[1]]);
        for &(t, w) in &GAUSS {
            let xi = o.lo + t * (o.hi - o.lo);
            let w = w * (o.hi - o.lo) * len;
            let (x, n) = (seg.point(xi), seg.normal(xi));
            let Some(eta) = line_parameter(yc, yd, x, n) else {
                continue;
            };
            let eta = eta.clamp(0.0, 1.0);
            let ns = [1.0 - xi, xi];
            let nm = [1.0 - eta, eta];
            for (aj, &sj) in a.iter().zip(&seg.nodes) {
                let phi = aj[0] * ns[0] + aj[1] * ns[1];
                // Lumped row: Σ_k ∫Φ_j N_k = ∫Φ_j = D_jj by biorthogonality.
                *d.entry(sj).or_insert(0.0) += w * phi;
                let row = m.entry(sj).or_default();
                for (&ml, nml) in o.master.iter().zip(nm) {
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
            dropped: Dropped {
                search_distance: reach,
                ..Dropped::default()
            },
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
        let mut terms = vec![Term {
            side: TermSide::Slave,
            node: s,
            weight: 1.0,
        }];
        let mut xm = [0.0; 3];
        for (&l, &mjl) in m.get(&s).into_iter().flatten() {
            let w = mjl / djj;
            let y = m_mesh.coords[l];
            for k in 0..3 {
                xm[k] += w * y[k];
            }
            terms.push(Term {
                side: TermSide::Master,
                node: l,
                weight: -w,
            });
        }
        let (tangent, tangent2) = tangents(slave_mesh.dim == 3, n);
        out.pairing.points.push(ContactPoint {
            slave_node: s,
            x,
            normal: n,
            tangent,
            tangent2,
            gap0: dot(n, sub(x, xm)),
            terms,
        });
        out.measure.insert(s, djj);
    }
    out
}

#[cfg(test)]
mod tests;
