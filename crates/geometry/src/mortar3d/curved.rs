//! Mortar integrals on a curved quadratic slave face, taken on the curved
//! faces themselves (docs/theory/mortar.md "Curved quadratic faces"; Popp,
//! Wohlmuth, Gee, Wall, SISC 34 (2012) §4, whose integration cells are flat:
//! here the cells are the slave face's reference domain).
//!
//! A Tri6 or Quad8 slave face x_s(ξ) is curved when a mid-side node lies off
//! the chord of its side (beyond [`CURVED`] of the side's length). Its
//! integrals are taken in its reference coordinates ξ:
//! 1. each master face that faces it has its corners carried to the slave's
//!    reference plane by the closest point on the slave face (Gauss–Newton
//!    on x_s(ξ), [`FaceMap::closest`]), and the slave's reference polygon
//!    (triangle or square) is clipped by theirs (Sutherland–Hodgman);
//! 2. the clip polygon is cut into triangles and integrated with the rule of
//!    the flat path; at each point ξ the slave face gives x_s(ξ), its shape
//!    functions and the area vector a = ∂x_s/∂ξ₁ × ∂x_s/∂ξ₂ (n dA = a dξ,
//!    dA = |a| dξ), and x_s(ξ) is projected on the master face along n by
//!    Newton's method on x_m(η) = x_s + g n ([`FaceMap::along`]), where the
//!    master's shape functions are evaluated.
//!
//! The row of slave node j then carries the normal inside the integral,
//!
//! ```text
//! g_j = ∫ Φ_j n(x) · (u_s(x) − u_m(π(x))) dA
//!     = Σ_k (∫ Φ_j Ñ_k n dA) · ũ_k − Σ_l (∫ Φ_j N_l∘π n dA) · u_l,
//! ```
//!
//! instead of n_j · (D_jj ũ_j − Σ_l M_jl u_l) with the nodal normal n_j
//! (`super::curved_rows`). When the two discretised surfaces coincide
//! (π(x) = x), a field u = ε x makes every integrand vanish pointwise, and
//! with λ_j = p the slave and master forces are p ∫Ñ_k n dA and p ∫N_l n dA
//! (Σ_j Φ_j = 1): the consistent nodal forces of σ = −p I on the curved
//! surface. The patch test is exact when the rule integrates Ñ_k a and
//! N_l∘π a exactly.

use signorini_mesh::vec3::{cross, dot, norm, sub};
use signorini_mesh::{facet_corners, Facet, Mesh};

use super::cells::{self, FaceShape, MAX_FACE_NODES};
use super::clipping::{clip, counter_clockwise, polygon_rule, signed_area, Point2};
use super::{FacePoint, MasterCells, CLIP_TOL, SLIVER};
use crate::closest::QUAD_CORNERS;

/// A quadratic face is curved when a mid-side node lies off the chord of its
/// side by more than this fraction of the side's length.
const CURVED: f64 = 1e-9;

/// Newton's iterations stop when the step is below this fraction of the
/// reference domain.
const STEP_TOL: f64 = 1e-14;
const MAX_ITERATIONS: usize = 50;
/// The largest last step of a closest-point search that is accepted after
/// [`MAX_ITERATIONS`] (a point off a curved face converges linearly).
const LOOSE_TOL: f64 = 1e-8;

/// Whether face `f` of `mesh` is quadratic with a mid-side node off the
/// chord of its side (see the module documentation).
pub(super) fn is_curved(mesh: &Mesh, f: &Facet) -> bool {
    if !cells::is_quadratic(f) {
        return false;
    }
    let corners = facet_corners(3, f.nodes.len());
    (0..corners).any(|k| {
        let a = mesh.coords[f.nodes[k]];
        let b = mesh.coords[f.nodes[(k + 1) % corners]];
        let m = mesh.coords[f.nodes[corners + k]];
        let side = sub(b, a);
        let off = norm(cross(side, sub(m, a))) / norm(side);
        off > CURVED * norm(side)
    })
}

/// A face's map x(ξ) from its reference coordinates (Tri3, Quad4, Tri6,
/// Quad8, node order of the mesh's faces).
pub(super) struct FaceMap {
    x: Vec<[f64; 3]>,
}

impl FaceMap {
    pub fn new(mesh: &Mesh, nodes: &[usize]) -> Self {
        FaceMap {
            x: nodes.iter().map(|&k| mesh.coords[k]).collect(),
        }
    }

    fn triangle(&self) -> bool {
        facet_corners(3, self.x.len()) == 3
    }

    /// The reference domain, counter-clockwise.
    pub fn reference_polygon(&self) -> Vec<Point2> {
        if self.triangle() {
            vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
        } else {
            QUAD_CORNERS.to_vec()
        }
    }

    /// Shape functions, the point and its two tangents ∂x/∂ξ₁, ∂x/∂ξ₂ at ξ.
    pub fn at(&self, xi: Point2) -> (FaceShape, [f64; 3], [[f64; 3]; 2]) {
        let (n, dn) = shape_gradient(self.x.len(), xi);
        let (mut p, mut t) = ([0.0; 3], [[0.0; 3]; 2]);
        for (a, y) in self.x.iter().enumerate() {
            for k in 0..3 {
                p[k] += n[a] * y[k];
                t[0][k] += dn[0][a] * y[k];
                t[1][k] += dn[1][a] * y[k];
            }
        }
        (n, p, t)
    }

    fn start(&self) -> Point2 {
        if self.triangle() {
            [1.0 / 3.0, 1.0 / 3.0]
        } else {
            [0.0, 0.0]
        }
    }

    /// The reference coordinates of the point of the (extended) face
    /// closest to y: Gauss–Newton on |x(ξ) − y|² (quadratic convergence for
    /// a point on the face, linear off it: a last step below [`LOOSE_TOL`]
    /// is accepted), `None` without convergence.
    pub fn closest(&self, y: [f64; 3]) -> Option<Point2> {
        let mut xi = self.start();
        let mut last = f64::INFINITY;
        for _ in 0..MAX_ITERATIONS {
            let (_, p, [t1, t2]) = self.at(xi);
            let r = sub(y, p);
            let (a11, a12, a22) = (dot(t1, t1), dot(t1, t2), dot(t2, t2));
            let (b1, b2) = (dot(t1, r), dot(t2, r));
            let det = a11 * a22 - a12 * a12;
            if det.abs() <= 1e-300 {
                return None;
            }
            let step = [(a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det];
            xi = [xi[0] + step[0], xi[1] + step[1]];
            last = step[0].abs().max(step[1].abs());
            if last <= STEP_TOL {
                return Some(xi);
            }
        }
        (last <= LOOSE_TOL).then_some(xi)
    }

    /// Where the line y + g n meets the (extended) face: its reference
    /// coordinates and g, by Newton's method on x(ξ) − y − g n = 0 from the
    /// point closest to y; `None` without convergence.
    pub fn along(&self, y: [f64; 3], n: [f64; 3]) -> Option<(Point2, f64)> {
        let mut xi = self.closest(y).unwrap_or_else(|| self.start());
        let mut g = 0.0;
        for _ in 0..MAX_ITERATIONS {
            let (_, p, [t1, t2]) = self.at(xi);
            let r = [0, 1, 2].map(|k| y[k] + g * n[k] - p[k]);
            // [t1 t2 −n] (dξ₁, dξ₂, dg) = r, by Cramer's rule.
            let m = [t1, t2, n.map(|v| -v)];
            let det = dot(m[0], cross(m[1], m[2]));
            if det.abs() <= 1e-300 {
                return None;
            }
            let d = [
                dot(r, cross(m[1], m[2])) / det,
                dot(m[0], cross(r, m[2])) / det,
                dot(m[0], cross(m[1], r)) / det,
            ];
            xi = [xi[0] + d[0], xi[1] + d[1]];
            g += d[2];
            if d[0].abs().max(d[1].abs()) <= STEP_TOL {
                return Some((xi, g));
            }
        }
        None
    }
}

/// Shape functions of a face with `nodes` nodes at ξ and their derivatives
/// along ξ₁ and ξ₂: Tri3 (1 − ξ₁ − ξ₂, ξ₁, ξ₂), bilinear Quad4 on [−1, 1]²,
/// and the Tri6 and Quad8 of [`cells::quadratic_shape`].
pub(super) fn shape_gradient(nodes: usize, xi: Point2) -> (FaceShape, [FaceShape; 2]) {
    let [x, y] = xi;
    let (mut n, mut d) = ([0.0; MAX_FACE_NODES], [[0.0; MAX_FACE_NODES]; 2]);
    match nodes {
        3 | 6 => {
            let l = [1.0 - x - y, x, y];
            let dl = [[-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]];
            for i in 0..3 {
                let j = (i + 1) % 3;
                if nodes == 3 {
                    n[i] = l[i];
                    d[0][i] = dl[0][i];
                    d[1][i] = dl[1][i];
                    continue;
                }
                n[i] = l[i] * (2.0 * l[i] - 1.0);
                n[3 + i] = 4.0 * l[i] * l[j];
                for (e, dle) in d.iter_mut().zip(dl) {
                    e[i] = (4.0 * l[i] - 1.0) * dle[i];
                    e[3 + i] = 4.0 * (dle[i] * l[j] + l[i] * dle[j]);
                }
            }
        }
        _ => {
            for (a, c) in QUAD_CORNERS.iter().enumerate() {
                let (fx, fy) = (1.0 + c[0] * x, 1.0 + c[1] * y);
                if nodes == 4 {
                    n[a] = 0.25 * fx * fy;
                    d[0][a] = 0.25 * c[0] * fy;
                    d[1][a] = 0.25 * c[1] * fx;
                    continue;
                }
                n[a] = 0.25 * fx * fy * (c[0] * x + c[1] * y - 1.0);
                d[0][a] = 0.25 * c[0] * fy * (2.0 * c[0] * x + c[1] * y);
                d[1][a] = 0.25 * c[1] * fx * (c[0] * x + 2.0 * c[1] * y);
            }
            if nodes == 8 {
                n[4] = 0.5 * (1.0 - x * x) * (1.0 - y);
                n[5] = 0.5 * (1.0 + x) * (1.0 - y * y);
                n[6] = 0.5 * (1.0 - x * x) * (1.0 + y);
                n[7] = 0.5 * (1.0 - x) * (1.0 - y * y);
                d[0][4..8].copy_from_slice(&[
                    -x * (1.0 - y),
                    0.5 * (1.0 - y * y),
                    -x * (1.0 + y),
                    -0.5 * (1.0 - y * y),
                ]);
                d[1][4..8].copy_from_slice(&[
                    -0.5 * (1.0 - x * x),
                    -(1.0 + x) * y,
                    0.5 * (1.0 - x * x),
                    -(1.0 - x) * y,
                ]);
            }
        }
    }
    (n, d)
}

/// The integration points of curved slave face `f` over the master faces
/// that face it (steps 1–2 of the module documentation), with the slave's
/// recombined shape functions, the weight |a| dξ and the unit outward normal
/// a/|a|.
pub(super) fn face_points(
    s_mesh: &Mesh,
    f: &Facet,
    masters: &MasterCells<'_>,
    rule: &[(f64, f64, f64)],
) -> Vec<FacePoint> {
    let face = FaceMap::new(s_mesh, &f.nodes);
    let (outward, _) = s_mesh.facet_normal(f);
    let reference = face.reference_polygon();
    let ref_area = signed_area(&reference);
    let (_, centre, [t1, t2]) = face.at(face.start());
    let sign = if dot(cross(t1, t2), outward) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let corners = facet_corners(3, f.nodes.len());
    let diameter = (0..corners)
        .flat_map(|a| (0..corners).map(move |b| (a, b)))
        .map(|(a, b)| norm(sub(face.x[a], face.x[b])))
        .fold(0.0, f64::max);
    let from = [0, 1, 2].map(|k| centre[k] - diameter * outward[k]);
    let to = [0, 1, 2].map(|k| centre[k] + masters.reach * outward[k]);
    let mut out = Vec::new();
    for k in masters.index.crossed(from, to, diameter) {
        let mf = &masters.surface.facets[k];
        if dot(masters.mesh.facet_normal(mf).0, outward) >= 0.0 {
            continue; // the master face must face the slave
        }
        let master = FaceMap::new(masters.mesh, &mf.nodes);
        let m_corners = facet_corners(3, mf.nodes.len());
        let Some(polygon) = (0..m_corners)
            .map(|c| face.closest(master.x[c]))
            .collect::<Option<Vec<_>>>()
        else {
            continue;
        };
        let poly = clip(&counter_clockwise(polygon), &reference, CLIP_TOL);
        if poly.len() < 3 || signed_area(&poly) <= SLIVER * ref_area {
            continue;
        }
        let points = polygon_rule(&poly, rule);
        let mut kept = Vec::with_capacity(points.len());
        for (xi, w) in points {
            let (ns, x, [t1, t2]) = face.at(xi);
            let a = cross(t1, t2).map(|v| sign * v);
            let jac = norm(a);
            let normal = a.map(|v| v / jac);
            let Some((eta, g)) = master.along(x, normal) else {
                continue;
            };
            if !(-diameter..=masters.reach).contains(&g) {
                continue;
            }
            kept.push(FacePoint {
                w: w * jac,
                ns: cells::recombined(f.nodes.len(), ns),
                master: k,
                nm: shape_gradient(mf.nodes.len(), eta).0,
                normal,
            });
        }
        out.extend(kept);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_gradients_are_the_derivatives_of_the_shape_functions() {
        let h = 1e-6;
        for nodes in [3, 4, 6, 8] {
            let xi = [0.23, -0.17 + if nodes % 3 == 0 { 0.4 } else { 0.0 }];
            let (n, d) = shape_gradient(nodes, xi);
            let sum: f64 = n[..nodes].iter().sum();
            assert!((sum - 1.0).abs() < 1e-14, "{nodes}: Σ N = {sum}");
            if nodes > 4 {
                assert_eq!(n, cells::quadratic_shape(nodes, xi));
            }
            for (dir, dd) in d.iter().enumerate() {
                let mut plus = xi;
                let mut minus = xi;
                plus[dir] += h;
                minus[dir] -= h;
                let (np, nm) = (
                    shape_gradient(nodes, plus).0,
                    shape_gradient(nodes, minus).0,
                );
                for a in 0..nodes {
                    let fd = (np[a] - nm[a]) / (2.0 * h);
                    assert!(
                        (fd - dd[a]).abs() < 1e-8,
                        "{nodes} node {a} dir {dir}: {fd} vs {}",
                        dd[a]
                    );
                }
            }
        }
    }
}
