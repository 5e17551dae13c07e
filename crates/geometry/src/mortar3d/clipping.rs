//! The geometry of 3D mortar integration (Puso & Laursen 2004, §3; Popp,
//! Gitterle, Gee, Wall, IJNME 83 (2010), §4.2): the auxiliary plane of a
//! slave face, the clipping of two convex polygons in it (Sutherland &
//! Hodgman 1974), and a Gauss rule on the clipped polygon cut into triangles
//! about its centroid.

use signorini_mesh::vec3::{dot, sub};

/// A point of the auxiliary plane in its in-plane coordinates.
pub(super) type Point2 = [f64; 2];

/// The auxiliary plane through `origin` with unit normal `normal`, and an
/// orthonormal in-plane basis (`e1`, `e2`) with e1 × e2 = normal.
pub(super) struct AuxPlane {
    origin: [f64; 3],
    normal: [f64; 3],
    e1: [f64; 3],
    e2: [f64; 3],
}

impl AuxPlane {
    pub fn new(origin: [f64; 3], normal: [f64; 3]) -> Self {
        let (e1, e2) = crate::pairing::tangent_frame(normal);
        AuxPlane {
            origin,
            normal,
            e1,
            e2,
        }
    }

    /// In-plane coordinates of the projection of x along the normal.
    pub fn coords(&self, x: [f64; 3]) -> Point2 {
        let d = sub(x, self.origin);
        [dot(d, self.e1), dot(d, self.e2)]
    }

    /// The point of the plane with in-plane coordinates p.
    pub fn point(&self, p: Point2) -> [f64; 3] {
        [0, 1, 2].map(|k| self.origin[k] + p[0] * self.e1[k] + p[1] * self.e2[k])
    }

    pub fn normal(&self) -> [f64; 3] {
        self.normal
    }
}

/// Signed area of a polygon (positive counter-clockwise).
pub(super) fn signed_area(poly: &[Point2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        * 0.5
}

/// The polygon counter-clockwise (reversed if it was clockwise).
pub(super) fn counter_clockwise(mut poly: Vec<Point2>) -> Vec<Point2> {
    if signed_area(&poly) < 0.0 {
        poly.reverse();
    }
    poly
}

fn cross2(o: Point2, a: Point2, b: Point2) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Sutherland–Hodgman: the part of polygon `subject` inside the convex
/// polygon `clipper` (both counter-clockwise). Each side of the clipper cuts
/// the current polygon by its half plane; a vertex within `tol` (a length)
/// of a side counts as inside, so that shared edges of the two meshes do
/// not leave slivers from rounding.
pub(super) fn clip(subject: &[Point2], clipper: &[Point2], tol: f64) -> Vec<Point2> {
    let mut out = subject.to_vec();
    let m = clipper.len();
    for k in 0..m {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clipper[k], clipper[(k + 1) % m]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if len == 0.0 {
            continue;
        }
        // Signed distance of p to the line a–b, positive inside.
        let side = |p: Point2| cross2(a, b, p) / len;
        let input = std::mem::take(&mut out);
        let n = input.len();
        for i in 0..n {
            let (p, q) = (input[i], input[(i + 1) % n]);
            let (sp, sq) = (side(p), side(q));
            let (p_in, q_in) = (sp >= -tol, sq >= -tol);
            if p_in {
                out.push(p);
            }
            if p_in != q_in && (sp - sq).abs() > 0.0 {
                // Where p–q crosses the side's line. When p and q lie on
                // either side of the tolerance band but on the same side of
                // the line (both within ~tol of it: nodes off a common line
                // by rounding), that crossing is beyond p–q, possibly far:
                // it is put on the segment's end instead.
                let mut t = sp / (sp - sq);
                if !(-1e-9..=1.0 + 1e-9).contains(&t) {
                    t = t.clamp(0.0, 1.0);
                }
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
    }
    out
}

/// The 7-point Gauss rule of degree 5 on a triangle (Radon 1948; Stroud
/// T2:5-1): barycentric coordinates (the third is 1 − a − b) and weights
/// that sum to 1 (to be multiplied by the area).
pub(super) const TRIANGLE_RULE: [(f64, f64, f64); 7] = [
    (1.0 / 3.0, 1.0 / 3.0, 0.225),
    (A1, A1, W1),
    (A1, 1.0 - 2.0 * A1, W1),
    (1.0 - 2.0 * A1, A1, W1),
    (A2, A2, W2),
    (A2, 1.0 - 2.0 * A2, W2),
    (1.0 - 2.0 * A2, A2, W2),
];
// (6 − √15)/21, (6 + √15)/21 and (155 ∓ √15)/1200.
const A1: f64 = 0.101_286_507_323_456_34;
const A2: f64 = 0.470_142_064_105_115_1;
const W1: f64 = 0.125_939_180_544_827_15;
const W2: f64 = 0.132_394_152_788_506_2;

/// The collapsed ("conical product", Stroud 1971 §2.7) 4 × 4 Gauss rule
/// on a triangle, as [`TRIANGLE_RULE`]: the square [0, 1]² mapped onto the
/// triangle by (u, v) ↦ (u, (1 − u) v), of Jacobian 1 − u; the 4-point
/// Gauss–Legendre rule in u and v integrates every polynomial of total
/// degree 6 exactly (degree ≤ 7 in u with the Jacobian, ≤ 6 in v): the
/// products of the quadratic faces' shape functions (Tri6, Quad8) and their
/// dual basis.
pub(super) fn collapsed_rule() -> Vec<(f64, f64, f64)> {
    let mut out = Vec::with_capacity(16);
    for &(u, wu) in &crate::mortar::GAUSS {
        for &(v, wv) in &crate::mortar::GAUSS {
            out.push((u, (1.0 - u) * v, 2.0 * wu * wv * (1.0 - u)));
        }
    }
    out
}

/// Gauss points (in-plane coordinates) and weights (areas) of a convex
/// polygon: the triangles from its centroid to each side, each with the
/// triangle `rule` (barycentric coordinates of two vertices and weights that
/// sum to 1): [`TRIANGLE_RULE`] (degree 5, exact for the products of linear
/// or bilinear shape functions on flat parallelogram faces) or
/// [`collapsed_rule`] (degree 6, quadratic faces).
pub(super) fn polygon_rule(poly: &[Point2], rule: &[(f64, f64, f64)]) -> Vec<(Point2, f64)> {
    let n = poly.len();
    let mut c = [0.0; 2];
    for p in poly {
        c[0] += p[0] / n as f64;
        c[1] += p[1] / n as f64;
    }
    let mut out = Vec::with_capacity(rule.len() * n);
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        let area = 0.5 * cross2(c, a, b);
        if area <= 0.0 {
            continue;
        }
        for &(la, lb, w) in rule {
            let lc = 1.0 - la - lb;
            let p = [
                la * a[0] + lb * b[0] + lc * c[0],
                la * a[1] + lb * b[1] + lc * c[1],
            ];
            out.push((p, w * area));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_mesh::vec3::{cross, norm};

    fn face_normal(x: &[[f64; 3]]) -> [f64; 3] {
        let c = cross(sub(x[1], x[0]), sub(x[2], x[0]));
        let l = norm(c);
        [c[0] / l, c[1] / l, c[2] / l]
    }

    #[test]
    fn the_triangle_rules_integrate_degrees_5_and_6_exactly() {
        // ∫ x^i y^j over the unit right triangle = i! j! / (i + j + 2)!.
        let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
        let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        for (rule, degree) in [
            (polygon_rule(&tri, &TRIANGLE_RULE), 5u32),
            (polygon_rule(&tri, &collapsed_rule()), 6),
        ] {
            for i in 0..=degree {
                for j in 0..=(degree - i) {
                    let got: f64 = rule
                        .iter()
                        .map(|(p, w)| w * p[0].powi(i as i32) * p[1].powi(j as i32))
                        .sum();
                    let want = fact(i) * fact(j) / fact(i + j + 2);
                    assert!((got - want).abs() < 1e-15, "x^{i} y^{j}: {got} vs {want}");
                }
            }
        }
    }

    #[test]
    fn clipping_two_squares_gives_their_intersection() {
        let sq =
            |x0: f64, y0: f64, s: f64| vec![[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]];
        let c = clip(&sq(0.0, 0.0, 1.0), &sq(0.5, 0.25, 1.0), 1e-14);
        assert!((signed_area(&c) - 0.375).abs() < 1e-15, "{c:?}");
        // A triangle inside: unchanged; disjoint: empty.
        let t = vec![[0.1, 0.1], [0.4, 0.1], [0.1, 0.4]];
        assert!((signed_area(&clip(&t, &sq(0.0, 0.0, 1.0), 1e-14)) - 0.045).abs() < 1e-15);
        assert!(clip(&t, &sq(2.0, 2.0, 1.0), 1e-14).len() < 3);
        // Shared edge: no sliver.
        let c = clip(&sq(0.0, 0.0, 1.0), &sq(1.0, 0.0, 1.0), 1e-14);
        assert!(signed_area(&c).abs() < 1e-15);
    }

    #[test]
    fn vertices_within_the_tolerance_of_a_side_stay_on_the_subject() {
        // p is outside the side y = 0 by more than tol, q inside the band
        // but below the line: p–q crosses y = 0 beyond q (x = 0.35).
        let tol = 1e-14;
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let t = [[0.2, -1.5e-14], [0.3, -0.5e-14], [0.25, 0.5]];
        let c = clip(&t, &sq, tol);
        assert!(c.iter().all(|p| p[0] <= 0.3 + 1e-12), "{c:?}");
        assert!((signed_area(&c) - signed_area(&t)).abs() < 1e-14);
    }

    #[test]
    fn the_auxiliary_plane_round_trips_its_points() {
        let n = face_normal(&[[0.0, 0.0, 1.0], [1.0, 0.0, 1.5], [0.0, 1.0, 1.0]]);
        let plane = AuxPlane::new([0.2, 0.3, 1.1], n);
        let x = plane.point([0.7, -0.4]);
        let p = plane.coords(x);
        assert!((p[0] - 0.7).abs() < 1e-15 && (p[1] + 0.4).abs() < 1e-15);
        assert!(dot(sub(x, [0.2, 0.3, 1.1]), plane.normal()).abs() < 1e-15);
    }
}
