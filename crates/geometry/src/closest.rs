//! Closest points on the primitives of a master surface: a straight segment,
//! a triangle, a bilinear quadrilateral. Each returns the master's shape
//! functions at the closest point (they sum to 1) and, for the "outside the
//! master" test, which sides of the primitive the point lies beyond.

use signorini_mesh::vec3::{cross, dot, norm, sub, unit};

/// Relative tolerance of the "beyond this side" tests: 10⁻⁶ of the
/// primitive's parameter range (segment ξ ∈ [0, 1], triangle barycentric
/// coordinates, quadrilateral: 10⁻⁶ of √area), as the 2D code has always used.
pub(super) const BEYOND_TOL: f64 = 1e-6;

/// Closest point of a primitive to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Closest {
    /// The closest point.
    pub x: [f64; 3],
    /// Euclidean distance from the query point to `x`.
    pub dist: f64,
    /// Shape functions of the primitive's nodes at `x` (unused entries 0).
    pub weights: [f64; 4],
    /// Side k of the primitive (segment: end node k; triangle and quad: the
    /// side from node k to node k+1) has the query point beyond it, by more
    /// than [`BEYOND_TOL`].
    pub beyond: [bool; 4],
    /// Segments only: the unclamped parameter of the projection on the
    /// segment's line (0 at node 0, 1 at node 1).
    pub xi_raw: f64,
    /// Quadrilaterals only: the parametric coordinates (ξ, η) ∈ [−1, 1]² of
    /// `x`.
    pub xi_eta: [f64; 2],
}

/// Closest point of the segment a–b to x. The arithmetic is the one the 2D
/// node-to-segment has always used (its results must stay bit-for-bit).
pub(super) fn segment(x: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Closest {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    let xi_raw = if l2 > 0.0 {
        dot(sub(x, a), ab) / l2
    } else {
        0.0
    };
    let xi = xi_raw.clamp(0.0, 1.0);
    let p = [a[0] + xi * ab[0], a[1] + xi * ab[1], a[2] + xi * ab[2]];
    let dist = norm(sub(x, p));
    Closest {
        x: p,
        dist,
        weights: [1.0 - xi, xi, 0.0, 0.0],
        beyond: [
            xi_raw < -BEYOND_TOL,
            xi_raw > 1.0 + BEYOND_TOL,
            false,
            false,
        ],
        xi_raw,
        xi_eta: [0.0; 2],
    }
}

/// Exact closest point of the triangle a–b–c to x (Ericson, Real-Time
/// Collision Detection §5.1.5: the Voronoi regions of the vertices, then of
/// the edges, then the interior). `weights` are the barycentric coordinates
/// (linear shape functions) of the closest point; `beyond[k]` tells whether x
/// projected on the triangle's plane lies beyond edge k (a–b, b–c, c–a), from
/// the unclamped barycentric coordinates. A degenerate (zero-area) triangle
/// is taken as its three edges.
pub(super) fn triangle(x: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Closest {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let nrm = cross(ab, ac);
    let n2 = dot(nrm, nrm);
    let longest = dot(ab, ab).max(dot(ac, ac)).max(dot(sub(c, b), sub(c, b)));
    if n2.is_nan() || n2 <= (1e-14 * longest).powi(2) {
        return degenerate_polygon(x, &[a, b, c]);
    }
    let w = ericson(x, a, b, c, ab, ac);
    let p = [
        w[0] * a[0] + w[1] * b[0] + w[2] * c[0],
        w[0] * a[1] + w[1] * b[1] + w[2] * c[1],
        w[0] * a[2] + w[1] * b[2] + w[2] * c[2],
    ];
    // Unclamped barycentric coordinates of the projection on the plane.
    let ax = sub(x, a);
    let (d00, d01, d11) = (dot(ab, ab), dot(ab, ac), dot(ac, ac));
    let (d20, d21) = (dot(ax, ab), dot(ax, ac));
    let den = d00 * d11 - d01 * d01;
    let lb = (d11 * d20 - d01 * d21) / den;
    let lc = (d00 * d21 - d01 * d20) / den;
    let la = 1.0 - lb - lc;
    Closest {
        x: p,
        dist: norm(sub(x, p)),
        weights: [w[0], w[1], w[2], 0.0],
        // Edge a–b is opposite c, b–c opposite a, c–a opposite b.
        beyond: [lc < -BEYOND_TOL, la < -BEYOND_TOL, lb < -BEYOND_TOL, false],
        xi_raw: 0.0,
        xi_eta: [0.0; 2],
    }
}

/// Barycentric weights of the closest point of a non-degenerate triangle.
fn ericson(
    p: [f64; 3],
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    ab: [f64; 3],
    ac: [f64; 3],
) -> [f64; 3] {
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return [1.0 - v, v, 0.0];
    }
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return [1.0 - w, 0.0, w];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - w, w];
    }
    let den = 1.0 / (va + vb + vc);
    let v = vb * den;
    let w = vc * den;
    [1.0 - v - w, v, w]
}

/// Closest point on the sides of a polygon (a degenerate face).
fn degenerate_polygon(x: [f64; 3], p: &[[f64; 3]]) -> Closest {
    let m = p.len();
    let mut best: Option<Closest> = None;
    for k in 0..m {
        let s = segment(x, p[k], p[(k + 1) % m]);
        if best.is_none_or(|b| s.dist < b.dist) {
            let mut weights = [0.0; 4];
            weights[k] = s.weights[0];
            weights[(k + 1) % m] += s.weights[1];
            best = Some(Closest {
                weights,
                beyond: [false; 4],
                xi_raw: 0.0,
                ..s
            });
        }
    }
    best.expect("a polygon has sides")
}

/// Reference coordinates of the bilinear quadrilateral's corners.
pub(super) const QUAD_CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// Bilinear shape functions at (ξ, η) and their derivatives (also used by
/// `ray`).
pub(super) fn bilinear(xi: f64, eta: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let mut n = [0.0; 4];
    let mut dxi = [0.0; 4];
    let mut deta = [0.0; 4];
    for (k, [a, b]) in QUAD_CORNERS.into_iter().enumerate() {
        n[k] = 0.25 * (1.0 + a * xi) * (1.0 + b * eta);
        dxi[k] = 0.25 * a * (1.0 + b * eta);
        deta[k] = 0.25 * b * (1.0 + a * xi);
    }
    (n, dxi, deta)
}

/// The point Σ w_k p_k.
pub(super) fn combine(w: [f64; 4], p: &[[f64; 3]; 4]) -> [f64; 3] {
    let mut x = [0.0; 3];
    for (wk, pk) in w.iter().zip(p) {
        for d in 0..3 {
            x[d] += wk * pk[d];
        }
    }
    x
}

/// Closest point of the bilinear quadrilateral p0–p1–p2–p3 (x(ξ, η) =
/// Σ N_k(ξ, η) p_k on [−1, 1]²) to x.
///
/// Method: Gauss–Newton from the centre on the stationarity conditions
/// (x(ξ, η) − x)·∂x/∂ξ = (x(ξ, η) − x)·∂x/∂η = 0 (for a planar quad this is
/// Newton's method on the inverse bilinear map, quadratically convergent).
/// If it converges inside [−1, 1]² (up to 10⁻⁹; within 10⁻¹² of a side it is
/// put on it), that interior
/// point is a candidate. The four sides of a bilinear quad are straight
/// segments, on which the closest points are exact; the result is the nearest
/// of the candidates, so a point beyond the quad, or one where the iteration
/// fails (far outside a strongly warped quad), gets its exact closest point
/// on the boundary. `weights` are the bilinear shape functions at the result
/// (on a side they reduce to the linear ones of that side). `beyond[k]` tells
/// whether x lies beyond side k (p_k → p_{k+1}) in the quad's mean plane
/// (normal ½ (p2 − p0) × (p3 − p1)), by more than 10⁻⁶ √area; it is only set
/// when the closest point is on the boundary.
pub(super) fn quad(x: [f64; 3], p: &[[f64; 3]; 4]) -> Closest {
    let diag = cross(sub(p[2], p[0]), sub(p[3], p[1]));
    let area = 0.5 * norm(diag);
    let longest = (0..4)
        .map(|k| norm(sub(p[(k + 1) % 4], p[k])))
        .fold(0.0, f64::max);
    if area.is_nan() || area <= 1e-14 * longest * longest {
        return degenerate_polygon(x, p);
    }
    let mut best: Option<Closest> = None;
    if let Some([xi, eta]) = quad_newton(x, p) {
        let (w, _, _) = bilinear(xi, eta);
        let q = combine(w, p);
        best = Some(Closest {
            x: q,
            dist: norm(sub(x, q)),
            weights: w,
            beyond: [false; 4],
            xi_raw: 0.0,
            xi_eta: [xi, eta],
        });
    }
    let mut on_side = None;
    for k in 0..4 {
        let s = segment(x, p[k], p[(k + 1) % 4]);
        if best.is_none_or(|b| s.dist < b.dist) {
            let t = s.weights[1];
            let mut weights = [0.0; 4];
            weights[k] = s.weights[0];
            weights[(k + 1) % 4] = t;
            let [a0, b0] = QUAD_CORNERS[k];
            let [a1, b1] = QUAD_CORNERS[(k + 1) % 4];
            best = Some(Closest {
                x: s.x,
                dist: s.dist,
                weights,
                beyond: [false; 4],
                xi_raw: 0.0,
                xi_eta: [a0 + t * (a1 - a0), b0 + t * (b1 - b0)],
            });
            on_side = Some(k);
        }
    }
    let mut best = best.expect("a quad has sides");
    if on_side.is_some() {
        let n = unit(diag).expect("a non-degenerate quad has a normal");
        let tol = BEYOND_TOL * area.sqrt();
        for k in 0..4 {
            if let Some(m) = unit(cross(sub(p[(k + 1) % 4], p[k]), n)) {
                best.beyond[k] = dot(sub(x, p[k]), m) > tol;
            }
        }
    }
    best
}

/// Gauss–Newton for the stationary point of |x(ξ, η) − x|² from (0, 0);
/// `Some` only if it converged inside [−1, 1]² (clamped there).
fn quad_newton(x: [f64; 3], p: &[[f64; 3]; 4]) -> Option<[f64; 2]> {
    let (mut xi, mut eta) = (0.0f64, 0.0f64);
    for _ in 0..60 {
        let (w, dxi, deta) = bilinear(xi, eta);
        let r = sub(combine(w, p), x);
        let gx = combine(dxi, p);
        let ge = combine(deta, p);
        let (a11, a12, a22) = (dot(gx, gx), dot(gx, ge), dot(ge, ge));
        let (b1, b2) = (-dot(gx, r), -dot(ge, r));
        let det = a11 * a22 - a12 * a12;
        if det.is_nan() || det <= 1e-300 {
            return None;
        }
        let dx = (b1 * a22 - b2 * a12) / det;
        let de = (a11 * b2 - a12 * b1) / det;
        xi += dx;
        eta += de;
        if !(xi.abs() < 10.0 && eta.abs() < 10.0) {
            return None;
        }
        if dx.abs() + de.abs() < 1e-13 {
            let inside = |v: f64| v.abs() <= 1.0 + 1e-9;
            // On a side up to rounding: exactly on it (no 1e-17 weights).
            let snap = |v: f64| {
                if (v.abs() - 1.0).abs() <= 1e-12 {
                    v.signum()
                } else {
                    v
                }
            };
            return (inside(xi) && inside(eta)).then(|| [snap(xi), snap(eta)]);
        }
    }
    None
}

/// Unit normal of a bilinear quad at (ξ, η): ∂x/∂ξ × ∂x/∂η (the right-hand
/// normal of the node order), or `None` where the map degenerates.
pub(super) fn quad_normal(p: &[[f64; 3]; 4], xi_eta: [f64; 2]) -> Option<[f64; 3]> {
    let (_, dxi, deta) = bilinear(xi_eta[0], xi_eta[1]);
    unit(cross(combine(dxi, p), combine(deta, p)))
}

/// The planar trapezoid (0,0) (4,0) (3,2) (1,2) in z = 0 of the tests: its
/// bilinear map x(ξ, η) is not affine.
#[cfg(test)]
pub(crate) const TRAPEZOID: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [4.0, 0.0, 0.0],
    [3.0, 2.0, 0.0],
    [1.0, 2.0, 0.0],
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_regions() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]);
        // Interior, above the plane.
        let r = triangle([0.5, 0.5, 0.3], a, b, c);
        assert!((r.dist - 0.3).abs() < 1e-15);
        for (w, e) in r.weights.iter().zip([0.5, 0.25, 0.25, 0.0]) {
            assert!((w - e).abs() < 1e-15);
        }
        assert_eq!(r.beyond, [false; 4]);
        // Vertex region of a.
        let r = triangle([-1.0, -1.0, 1.0], a, b, c);
        assert_eq!(r.weights, [1.0, 0.0, 0.0, 0.0]);
        assert!((r.dist - 3f64.sqrt()).abs() < 1e-15);
        assert_eq!(r.beyond, [true, false, true, false]);
        // Edge b–c region: closest point (1.5, 0.5, 0).
        let r = triangle([2.0, 1.0, 0.0], a, b, c);
        assert!((r.weights[1] - 0.75).abs() < 1e-15 && (r.weights[2] - 0.25).abs() < 1e-15);
        assert!((r.dist - 0.5f64.sqrt()).abs() < 1e-15);
        assert_eq!(r.beyond, [false, true, false, false]);
        // Degenerate triangle: its sides.
        let r = triangle([1.0, 1.0, 0.0], a, b, [1.0, 0.0, 0.0]);
        assert!((r.dist - 1.0).abs() < 1e-15);
        assert!((r.weights.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn quad_inverse_map_on_a_trapezoid_and_its_sides() {
        // Planar trapezoid in z = 1: x(ξ, η) is not affine.
        let p = TRAPEZOID.map(|c| [c[0], c[1], 1.0]);
        let (xi, eta) = (0.3, -0.4);
        let (w, _, _) = bilinear(xi, eta);
        let q = combine(w, &p);
        let r = quad([q[0], q[1], 1.75], &p);
        assert!((r.dist - 0.75).abs() < 1e-14);
        for k in 0..4 {
            assert!((r.weights[k] - w[k]).abs() < 1e-13, "{:?} {w:?}", r.weights);
        }
        assert!((r.xi_eta[0] - xi).abs() < 1e-13 && (r.xi_eta[1] - eta).abs() < 1e-13);
        // Beyond side 0 (y < 0): closest point on p0–p1 at x = 1.
        let r = quad([1.0, -0.5, 1.0], &p);
        assert!((r.dist - 0.5).abs() < 1e-15);
        assert!((r.weights[0] - 0.75).abs() < 1e-15 && (r.weights[1] - 0.25).abs() < 1e-15);
        assert_eq!(r.beyond, [true, false, false, false]);
        assert!((r.xi_eta[0] + 0.5).abs() < 1e-15 && (r.xi_eta[1] + 1.0).abs() < 1e-15);
    }

    #[test]
    fn warped_quad_closest_point_is_stationary() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.2],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.2],
        ];
        let x = [0.4, 0.7, 0.5];
        let r = quad(x, &p);
        // x − x(ξ, η) is normal to the surface there.
        let n = quad_normal(&p, r.xi_eta).unwrap();
        let d = sub(x, r.x);
        let c = cross(d, n);
        assert!(norm(c) < 1e-12 * norm(d), "{c:?}");
        assert!((r.weights.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        // No point of a fine sampling of the patch is closer.
        for i in 0..=50 {
            for j in 0..=50 {
                let (w, _, _) = bilinear(-1.0 + i as f64 / 25.0, -1.0 + j as f64 / 25.0);
                assert!(norm(sub(x, combine(w, &p))) >= r.dist - 1e-14);
            }
        }
    }
}
