//! Node-to-face rows of a quadratic slave surface (the Tri6 faces of Tet10
//! cells, the Quad8 faces of Hex20 cells), by a change of basis that makes
//! every slave weight positive.
//!
//! The consistent nodal measures `∫ N_a dS` of a quadratic face are `0` at the
//! Tri6 corners and `−A/12` at the Quad8 corners (`A/3` at the mid-sides): a
//! uniform pressure loads the corners of a serendipity face in tension, and a
//! node-by-node contact row, whose force must be compressive, cannot carry
//! it (the contact patch test then fails by 30 %). Following Wohlmuth, Popp,
//! Gee and Wall (2012, "An abstract framework for a priori estimates for
//! contact problems in 3D with quadratic finite elements", Comput. Mech. 49)
//! the slave's shape functions are recombined edge by edge, with `α = 1/5`:
//!
//! ```text
//! Ñ_c = N_c + α Σ_{m on an edge at c} N_m,     Ñ_m = (1 − 2α) N_m,
//! ```
//!
//! (`Σ Ñ = Σ N = 1`). The rows are those of the recombined nodal gaps:
//! `g̃_c = g_c` at a corner and `g̃_m = (g_m − α (g_c1 + g_c2)) / (1 − 2α)` at
//! the mid-side `m` of the edge `c1`–`c2`, so that the nodal forces are
//! `f_c = λ_c − α/(1 − 2α) Σ λ_m`, `f_m = λ_m / (1 − 2α)`; and the measures
//! (pressure = force / measure) are `∫ Ñ_a dS`: on a flat face `A/20` at a
//! Quad8 corner and `2A/15` at a Tri6 corner, `A/5` at every mid-side, all
//! positive. A uniform pressure p then has `λ_a = p ∫ Ñ_a ≥ 0`: the
//! patch test passes on matching meshes. The mid-side row combines its
//! corners' gaps along its own normal (the same normal on a flat master);
//! non-penetration is asked of the recombined gaps, as mortar asks it of
//! weighted gaps.
//!
//! On a curved face the rows' directions matter: under σ = −p I the
//! consistent slave forces are `p ∫ N_a n dS` (n varying along the face),
//! and the row forces above equal them, after the recombination, iff each
//! row's normal is the direction of `v_a = ∫ Ñ_a n dS` and `λ_a = p |v_a|`.
//! [`consistent_normals`] gives these normals and measures `|v_a|` (on a flat
//! face the face's normal and `∫ Ñ_a dS`); on matching meshes each slave node
//! meets the coincident master node, so the linear field closes every gap
//! whatever its direction, and the patch test passes on curved faces too.

use crate::pairing::ContactPoint;
use signorini_mesh::vec3::unit;
use signorini_mesh::{facet_corners, Surface};
use std::collections::{BTreeMap, HashMap};

/// The recombination weight α of the corners' shape functions.
pub const ALPHA: f64 = 0.2;

/// The mid-side nodes of a 3D quadratic surface with the corners of their
/// edges, `(mid, [c1, c2])`, sorted by mid-side node; empty for a linear
/// surface.
pub fn mid_side_edges(dim: usize, surface: &Surface) -> Vec<(usize, [usize; 2])> {
    let mut out = BTreeMap::new();
    if dim != 3 {
        return Vec::new();
    }
    for f in &surface.facets {
        let m = facet_corners(3, f.nodes.len());
        if f.nodes.len() != 2 * m {
            continue;
        }
        for k in 0..m {
            out.insert(f.nodes[m + k], [f.nodes[k], f.nodes[(k + 1) % m]]);
        }
    }
    out.into_iter().collect()
}

/// The recombined integrals `∫ Ñ_a f dS` of a field from the consistent ones
/// `∫ N_a f dS`: `Ñ_c = N_c + α Σ N_m`, `Ñ_m = (1 − 2α) N_m` (see the module
/// docs).
fn recombined<const K: usize>(
    consistent: &BTreeMap<usize, [f64; K]>,
    edges: &[(usize, [usize; 2])],
) -> BTreeMap<usize, [f64; K]> {
    let mut out = consistent.clone();
    for &(m, [c1, c2]) in edges {
        let t = consistent.get(&m).copied().unwrap_or([0.0; K]);
        for c in [c1, c2] {
            let e = out.entry(c).or_insert([0.0; K]);
            for k in 0..K {
                e[k] += ALPHA * t[k];
            }
        }
        out.insert(m, t.map(|tk| (1.0 - 2.0 * ALPHA) * tk));
    }
    out
}

/// The consistent nodal normals of a quadratic slave surface and their
/// area vectors, from its nodal area vectors `∫ N_a n dS` (n the outward
/// normal, integrated on the curved faces): the recombined vector
/// `v_a = ∫ Ñ_a n dS` gives the outward normal `v_a / |v_a|`; a row along
/// the contact normal `n_c` has the pressure measure `|n_c · v_a|` (`|v_a|`
/// along the consistent normal). With these, a uniform pressure p has the
/// row forces `λ_a = p |v_a|` along `n_a` equal to its consistent nodal
/// forces `p ∫ N_a n dS` after the recombination, on a curved face as on a
/// flat one (docs/theory/elements.md "Node-to-face on quadratic faces"). On
/// a flat face `v_a = n ∫ Ñ_a dS`: the face's normal and the measure
/// `∫ Ñ_a dS`. A node with `v_a = 0` gets the zero normal.
pub fn consistent_normals(
    area_vectors: &BTreeMap<usize, [f64; 3]>,
    edges: &[(usize, [usize; 2])],
) -> ConsistentNormals {
    let v = recombined(area_vectors, edges);
    let normals = v
        .iter()
        .map(|(&a, &va)| (a, unit(va).unwrap_or([0.0; 3])))
        .collect();
    ConsistentNormals {
        normals,
        area_vectors: v,
    }
}

/// The consistent nodal normals of a quadratic surface and their measures
/// (see [`consistent_normals`]), by node.
pub struct ConsistentNormals {
    /// Each node with its outward unit normal `v_a / |v_a|`, sorted by node.
    pub normals: Vec<(usize, [f64; 3])>,
    /// Each node's recombined area vector `v_a = ∫ Ñ_a n dS`.
    pub area_vectors: BTreeMap<usize, [f64; 3]>,
}

/// Rewrites the row of every mid-side point whose two corners have a point
/// as the recombined gap `(g_m − α (g_c1 + g_c2)) / (1 − 2α)`: terms and
/// initial gap (see the module docs). Corner points keep their rows.
/// Returns the edges whose mid-side row was rewritten (those with a point at
/// all three nodes).
pub fn recombine_rows(
    points: &mut [ContactPoint],
    edges: &[(usize, [usize; 2])],
) -> Vec<(usize, [usize; 2])> {
    let at: HashMap<usize, usize> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (p.slave_node, i))
        .collect();
    let own = 1.0 / (1.0 - 2.0 * ALPHA);
    let corner = -ALPHA / (1.0 - 2.0 * ALPHA);
    let mut new_rows = Vec::new();
    for &(m, [c1, c2]) in edges {
        let (Some(&im), Some(&i1), Some(&i2)) = (at.get(&m), at.get(&c1), at.get(&c2)) else {
            continue;
        };
        let mut terms = Vec::new();
        let mut gap0 = 0.0;
        for (i, s) in [(im, own), (i1, corner), (i2, corner)] {
            gap0 += s * points[i].gap0;
            terms.extend(points[i].terms.iter().map(|t| {
                let mut t = *t;
                t.weight *= s;
                t
            }));
        }
        // one term per (side, node)
        let mut merged: Vec<crate::pairing::Term> = Vec::with_capacity(terms.len());
        for t in terms {
            match merged
                .iter_mut()
                .find(|u| u.side == t.side && u.node == t.node)
            {
                Some(u) => u.weight += t.weight,
                None => merged.push(t),
            }
        }
        new_rows.push((im, merged, gap0, (m, [c1, c2])));
    }
    let mut rewritten = Vec::with_capacity(new_rows.len());
    for (i, terms, gap0, edge) in new_rows {
        points[i].terms = terms;
        points[i].gap0 = gap0;
        rewritten.push(edge);
    }
    rewritten
}

/// The displacement of each slave node of a quadratic surface as a
/// combination of master nodes, from mortar rows written on the recombined
/// displacements (`ũ_j = Σ_l W_jl u_l`, `crate::mortar3d`): `u = Tᵀ ũ`, so a
/// corner keeps its row and a mid-side's is `(1 − 2α) W_m + α (W_c1 + W_c2)`
/// (a tie's elimination, where every slave node follows its masters).
/// `rows` maps each slave node to its master weights; a mid-side node whose
/// corners have no row is left as it is.
pub fn displacement_rows(
    rows: &BTreeMap<usize, Vec<(usize, f64)>>,
    edges: &[(usize, [usize; 2])],
) -> BTreeMap<usize, Vec<(usize, f64)>> {
    let mut out = rows.clone();
    for &(m, [c1, c2]) in edges {
        let (Some(wm), Some(w1), Some(w2)) = (rows.get(&m), rows.get(&c1), rows.get(&c2)) else {
            continue;
        };
        let mut sum: BTreeMap<usize, f64> = BTreeMap::new();
        for (w, s) in [(wm, 1.0 - 2.0 * ALPHA), (w1, ALPHA), (w2, ALPHA)] {
            for &(l, v) in w {
                *sum.entry(l).or_insert(0.0) += s * v;
            }
        }
        out.insert(m, sum.into_iter().collect());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_mesh::vec3::norm;

    /// A flat Quad8 face of area A along n (its area vectors n ∫ N_a dS:
    /// −A/12 at a corner, A/3 at a mid-side) has the consistent normal n at
    /// every node and the measures A/20 at the corners, A/5 at the
    /// mid-sides; a node whose recombined vector vanishes gets the zero
    /// normal.
    #[test]
    fn a_flat_face_has_its_normal_and_the_recombined_measures() {
        let (area, n) = (2.0, [0.6, 0.0, 0.8]);
        let edges: Vec<(usize, [usize; 2])> = (0..4).map(|k| (4 + k, [k, (k + 1) % 4])).collect();
        let along = |m: f64| n.map(|nk| nk * m * area);
        let mut v: BTreeMap<usize, [f64; 3]> = (0..4).map(|c| (c, along(-1.0 / 12.0))).collect();
        v.extend((4..8).map(|m| (m, along(1.0 / 3.0))));
        v.insert(8, [0.0; 3]);
        let ConsistentNormals {
            normals,
            area_vectors,
        } = consistent_normals(&v, &edges);
        for (a, na) in normals {
            let want = if a == 8 { [0.0; 3] } else { n };
            for k in 0..3 {
                assert!((na[k] - want[k]).abs() <= 1e-15, "node {a}: {na:?}");
            }
            let share = match a {
                0..=3 => 1.0 / 20.0,
                4..=7 => 1.0 / 5.0,
                _ => 0.0,
            };
            assert!(
                (norm(area_vectors[&a]) - share * area).abs() <= 1e-15 * area,
                "node {a}"
            );
        }
    }
}
