//! The flat integration cells of a mortar face and the face's shape
//! functions at their points (Popp, Wohlmuth, Gee, Wall, "Dual quadratic
//! mortar finite element methods for 3D finite deformation contact", SISC 34
//! (2012) §4.1: a quadratic face is integrated over linear "integration
//! cells" spanned by its nodes).
//!
//! A linear face (3-node triangle, 4-node quadrilateral) is its own cell. A
//! quadratic face (Tri6 of a Tet10, Quad8 of a Hex20) is cut through its
//! mid-side nodes into the pieces node-to-face projects on
//! (`search::quadratic_face_pieces`): a triangle at each corner and the inner
//! triangle (Tri6) or quadrilateral (Quad8) of the mid-side nodes. Each cell
//! vertex is a face node with known reference coordinates, so a point of a
//! cell (its linear or bilinear weights w_k) has the reference coordinates
//! ξ = Σ w_k ξ_k, where the face's quadratic shape functions are evaluated.
//! On a flat face with centred mid-side nodes the cells tile the face and
//! every map is affine: the integrals over the cells are those over the face.
//!
//! On the slave side the shape functions are recombined edge by edge
//! (`crate::quadratic_slave`, α = 1/5) before the dual basis is built on them,
//! so that every ∫Ñ_j, hence every D_jj, is positive.

use signorini_mesh::{facet_corners, Facet};

use crate::closest::QUAD_CORNERS;
use crate::quadratic_slave::ALPHA;

/// The most nodes of a face (Quad8).
pub(super) const MAX_FACE_NODES: usize = 8;

/// Shape function values of a face at a point, in the face's node order.
pub(super) type FaceShape = [f64; MAX_FACE_NODES];

/// A flat piece of a face: its mesh nodes (3 or 4) and, on a quadratic face,
/// their reference coordinates on the face.
pub(super) struct Cell {
    pub nodes: Vec<usize>,
    reference: Option<Vec<[f64; 2]>>,
}

/// Whether a face has mid-side nodes (6 or 8 nodes).
pub(super) fn is_quadratic(f: &Facet) -> bool {
    f.nodes.len() > 4
}

/// The integration cells of face `f` (see the module documentation).
pub(super) fn cells(f: &Facet) -> Vec<Cell> {
    if !is_quadratic(f) {
        return vec![Cell {
            nodes: f.nodes.clone(),
            reference: None,
        }];
    }
    let corners = facet_corners(3, f.nodes.len());
    crate::search::quadratic_face_pieces(0, f, corners, [false; 4])
        .into_iter()
        .map(|piece| {
            let nodes = piece.nodes[..piece.len()].to_vec();
            let reference = nodes
                .iter()
                .map(|v| {
                    let local = f.nodes.iter().position(|u| u == v).unwrap_or(0);
                    reference_node(corners, local)
                })
                .collect();
            Cell {
                nodes,
                reference: Some(reference),
            }
        })
        .collect()
}

/// Reference coordinates of node `local` of a quadratic face with `corners`
/// corners: Tri6 corners (0, 0), (1, 0), (0, 1); Quad8 corners (±1, ±1)
/// counter-clockwise from (−1, −1); the mid-side of side k → k+1 halfway.
fn reference_node(corners: usize, local: usize) -> [f64; 2] {
    let corner = |k: usize| match corners {
        3 => [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]][k % 3],
        _ => QUAD_CORNERS[k % 4],
    };
    if local < corners {
        return corner(local);
    }
    let s = local - corners;
    let (a, b) = (corner(s), corner(s + 1));
    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
}

impl Cell {
    /// The face's shape functions at the cell point of weights `w` (the
    /// cell's linear or bilinear shape functions there).
    pub fn face_shape(&self, w: [f64; 4], face_nodes: usize) -> FaceShape {
        let mut out = [0.0; MAX_FACE_NODES];
        let Some(reference) = &self.reference else {
            out[..4].copy_from_slice(&w);
            return out;
        };
        let mut xi = [0.0; 2];
        for (wk, r) in w.iter().zip(reference) {
            xi[0] += wk * r[0];
            xi[1] += wk * r[1];
        }
        quadratic_shape(face_nodes, xi)
    }
}

/// The Tri6 (`nodes` = 6: corners L_i (2 L_i − 1), mid-sides 4 L_i L_j) or
/// serendipity Quad8 (corners ¼ (1 + ξ_a ξ)(1 + η_a η)(ξ_a ξ + η_a η − 1),
/// mid-sides ½ (1 − ξ²)(1 + η_a η) and its rotation) shape functions at ξ,
/// in the node order of the face (the mid-side of side k → k+1 after the
/// corners), as the solid elements' faces (`signorini_fem`).
pub(super) fn quadratic_shape(nodes: usize, [x, y]: [f64; 2]) -> FaceShape {
    let mut n = [0.0; MAX_FACE_NODES];
    if nodes == 6 {
        let l = [1.0 - x - y, x, y];
        for i in 0..3 {
            n[i] = l[i] * (2.0 * l[i] - 1.0);
            n[3 + i] = 4.0 * l[i] * l[(i + 1) % 3];
        }
        return n;
    }
    for (a, c) in QUAD_CORNERS.iter().enumerate() {
        let (fx, fy) = (1.0 + c[0] * x, 1.0 + c[1] * y);
        n[a] = 0.25 * fx * fy * (c[0] * x + c[1] * y - 1.0);
    }
    n[4] = 0.5 * (1.0 - x * x) * (1.0 - y);
    n[5] = 0.5 * (1.0 + x) * (1.0 - y * y);
    n[6] = 0.5 * (1.0 - x * x) * (1.0 + y);
    n[7] = 0.5 * (1.0 - x) * (1.0 - y * y);
    n
}

/// The recombined slave shape functions Ñ = T N of a quadratic face with
/// `nodes` nodes (`crate::quadratic_slave`): Ñ_c = N_c + α Σ N_m over the
/// mid-sides of the sides at corner c, Ñ_m = (1 − 2α) N_m. A linear face's
/// are its own.
pub(super) fn recombined(nodes: usize, n: FaceShape) -> FaceShape {
    if nodes <= 4 {
        return n;
    }
    let corners = facet_corners(3, nodes);
    let mut out = n;
    for s in 0..corners {
        let m = corners + s;
        out[s] += ALPHA * n[m];
        out[(s + 1) % corners] += ALPHA * n[m];
        out[m] = (1.0 - 2.0 * ALPHA) * n[m];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_shapes_interpolate_their_nodes_and_sum_to_one() {
        for (nodes, corners) in [(6, 3), (8, 4)] {
            for a in 0..nodes {
                let n = quadratic_shape(nodes, reference_node(corners, a));
                for (b, &v) in n.iter().enumerate().take(nodes) {
                    let want = if a == b { 1.0 } else { 0.0 };
                    assert!((v - want).abs() < 1e-15, "{nodes}: N_{b}(x_{a}) = {v}");
                }
            }
            let n = recombined(nodes, quadratic_shape(nodes, [0.3, 0.2]));
            let sum: f64 = n[..nodes].iter().sum();
            assert!((sum - 1.0).abs() < 1e-15, "Σ Ñ = {sum}");
        }
    }
}
