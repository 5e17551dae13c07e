//! The rows of the nodes of curved slave faces with the frame inside the
//! integral (docs/theory/mortar.md "Curved quadratic faces"): for slave node
//! j, its normal row and its two tangential rows
//!
//! ```text
//! g_j   = ∫ Φ_j n(x)  · (u_s(x) − u_m(π(x))) dA / D_jj,
//! s_j,k = ∫ Φ_j t_k(x) · (u_s(x) − u_m(π(x))) dA / D_jj,   k = 1, 2,
//! ```
//!
//! with n(x) the contact normal at x (the slave face's, reversed) and a
//! smooth tangent frame at x made from node j's nodal frame
//! (`crate::pairing::tangent_frame` of its nodal normal n_j): t_1(x) is
//! t_1j projected on the tangent plane at x and normalised, t_2(x) =
//! n(x) × t_1(x). (t_1(x), t_2(x), n(x)) is orthonormal at every x, so the
//! tangential rows never measure a normal motion; on a flat face they are
//! the rows t_kj · (ũ_j − Σ_l (M_jl/D_jj) u_l) of the nodal frame.

use signorini_mesh::vec3::{cross, dot, norm};
use signorini_mesh::{Mesh, Surface};
use std::collections::{BTreeMap, BTreeSet};

use crate::mortar::MortarPairing;
use crate::pairing::tangent_frame;
use crate::{TermSide, VectorTerm};

/// Per term (side, node) of a slave node's rows, the integrals ∫Φ_j N n_s dA
/// (n_s the slave's outward normal), ∫Φ_j N t_1 dA and ∫Φ_j N t_2 dA.
type Integrals = BTreeMap<(TermSide, usize), [[f64; 3]; 3]>;

/// The nodes of curved slave faces, their nodal first tangents, and the
/// integrals of their rows.
pub(super) struct CurvedRows {
    nodes: BTreeSet<usize>,
    tangent: BTreeMap<usize, [f64; 3]>,
    integrals: BTreeMap<usize, Integrals>,
}

impl CurvedRows {
    /// The nodes of `curved` faces, with the frames of their nodal slave
    /// `normals` (outward; the contact normal is reversed).
    pub fn new(curved: BTreeSet<usize>, normals: &BTreeMap<usize, [f64; 3]>) -> Self {
        let tangent = (curved.iter())
            .filter_map(|&j| Some((j, tangent_frame(normals.get(&j)?.map(|v| -v)).0)))
            .collect();
        CurvedRows {
            nodes: curved,
            tangent,
            integrals: BTreeMap::new(),
        }
    }

    /// Whether a face with `nodes` has a node of a curved face.
    pub fn touches(&self, nodes: &[usize]) -> bool {
        nodes.iter().any(|k| self.nodes.contains(k))
    }

    /// Adds to slave node j's rows the weight `w_phi` = w Φ_j(x) of an
    /// integration point whose slave outward normal is `normal`, times each
    /// term's shape function.
    pub fn add(
        &mut self,
        j: usize,
        w_phi: f64,
        normal: [f64; 3],
        terms: impl Iterator<Item = (TermSide, usize, f64)>,
    ) {
        let (t1, t2) = match self.tangent.get(&j) {
            Some(&t) => point_frame(t, normal),
            None => ([0.0; 3], [0.0; 3]),
        };
        let row = self.integrals.entry(j).or_default();
        for (side, node, shape) in terms {
            let e = row.entry((side, node)).or_insert([[0.0; 3]; 3]);
            for (k, nk) in normal.iter().enumerate() {
                e[0][k] += w_phi * shape * nk;
                e[1][k] += w_phi * shape * t1[k];
                e[2][k] += w_phi * shape * t2[k];
            }
        }
    }
}

/// The tangents at a point of slave outward normal `outward` from a node's
/// first tangent `t1`: t1 projected on the tangent plane and normalised,
/// and n × t1 with n = −`outward` the contact normal.
fn point_frame(t1: [f64; 3], outward: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let n = outward.map(|v| -v);
    let along = dot(t1, n);
    let p = [0, 1, 2].map(|k| t1[k] - along * n[k]);
    let length = norm(p);
    let t = p.map(|v| v / length);
    (t, cross(n, t))
}

/// Writes the rows of the nodes of curved slave faces into their contact
/// points: g_j = (Σ_k v_jk · ũ_k − Σ_l v_jl · u_l) / D_jj with v the
/// integrals of [`CurvedRows`] along the contact normal (the slave's
/// reversed), the recombined slave displacements ũ written as u as in
/// `super::transform_slave_rows`, the initial gap the normal row applied to
/// the coordinates; the tangential rows likewise along t_1(x), t_2(x),
/// without a gap. The ties' weights stay.
pub(super) fn write_rows(
    [s_mesh, m_mesh]: [&Mesh; 2],
    surface: &Surface,
    rows: &CurvedRows,
    out: &mut MortarPairing,
) {
    let edges: BTreeMap<usize, [usize; 2]> = crate::quadratic_slave::mid_side_edges(3, surface)
        .into_iter()
        .collect();
    for p in &mut out.pairing.points {
        let (Some(v), Some(&djj)) = (
            rows.integrals.get(&p.slave_node),
            out.measure.get(&p.slave_node),
        ) else {
            continue;
        };
        if !rows.nodes.contains(&p.slave_node) {
            continue;
        }
        let normal = row(v, 0, -1.0, &edges, djj);
        p.gap0 = normal
            .iter()
            .map(|(&(side, node), c)| {
                let mesh = if side == TermSide::Slave {
                    s_mesh
                } else {
                    m_mesh
                };
                dot(*c, mesh.coords[node])
            })
            .sum();
        p.normal_row = terms(normal);
        p.tangent_rows = [1, 2].map(|k| terms(row(v, k, 1.0, &edges, djj)));
    }
}

/// Component `which` (0 normal, 1 and 2 tangents) of a node's integrals
/// `v` as a row over u: the slave terms times `slave_sign` / D_jj (the
/// recombined ũ of a mid-side node written in its own and its corners'
/// displacements), the master terms times −`slave_sign` / D_jj.
fn row(
    v: &Integrals,
    which: usize,
    slave_sign: f64,
    edges: &BTreeMap<usize, [usize; 2]>,
    djj: f64,
) -> BTreeMap<(TermSide, usize), [f64; 3]> {
    let alpha = crate::quadratic_slave::ALPHA;
    let (own, corner) = (1.0 / (1.0 - 2.0 * alpha), -alpha / (1.0 - 2.0 * alpha));
    let mut row = BTreeMap::<(TermSide, usize), [f64; 3]>::new();
    let mut add = |side, node, c: [f64; 3], s: f64| {
        let e = row.entry((side, node)).or_insert([0.0; 3]);
        for k in 0..3 {
            e[k] += s * c[k];
        }
    };
    for (&(side, node), c) in v {
        let c = c[which];
        match (side, edges.get(&node)) {
            (TermSide::Slave, Some(&[c1, c2])) => {
                add(side, node, c, slave_sign * own / djj);
                add(side, c1, c, slave_sign * corner / djj);
                add(side, c2, c, slave_sign * corner / djj);
            }
            (TermSide::Slave, None) => add(side, node, c, slave_sign / djj),
            (TermSide::Master, _) => add(side, node, c, -slave_sign / djj),
        }
    }
    row
}

fn terms(row: BTreeMap<(TermSide, usize), [f64; 3]>) -> Vec<VectorTerm> {
    row.into_iter()
        .map(|((side, node), coefficient)| VectorTerm {
            side,
            node,
            coefficient,
        })
        .collect()
}
