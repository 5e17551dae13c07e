//! Where the line through a slave node along a contact normal meets a
//! primitive of the master surface (course notes §2.4, Fig. 3: with the slave's or
//! the average normal, the master point paired with a slave node is the one
//! its normal points at, not the closest one).
//!
//! The line is x_m = x − g n (n unit, from master to slave), so that the
//! parameter g of the meeting point is the initial gap n · (x − x_m) (course notes
//! eq. 10, j = g0): positive when the master is ahead of the slave node along
//! −n, negative for an initial overlap. Each function returns `None` when the
//! line is parallel to the primitive or meets its plane outside it by more
//! than [`BEYOND_TOL`] of its parameter range; a meeting point within that
//! tolerance outside is put on the primitive's boundary (the weights are
//! clamped, so they stay in [0, 1] and sum to 1).

use crate::closest::{bilinear, combine, Closest, BEYOND_TOL, QUAD_CORNERS};
use signorini_mesh::vec3::{cross, dot, norm, sub};

/// `Closest` of a meeting point: `dist` is |g|, nothing is "beyond".
fn hit(x: [f64; 3], g: f64, weights: [f64; 4], xi_raw: f64, xi_eta: [f64; 2]) -> Closest {
    Closest {
        x,
        dist: g.abs(),
        weights,
        beyond: [false; 4],
        xi_raw,
        xi_eta,
    }
}

/// The solution of [c0 c1 c2] y = r by Cramer's rule, or `None` when the
/// determinant is below `tiny` times |c0| |c1| |c2| (the columns are nearly
/// dependent: the line is parallel to the primitive).
fn solve3(c: [[f64; 3]; 3], r: [f64; 3], tiny: f64) -> Option<[f64; 3]> {
    let c12 = cross(c[1], c[2]);
    let det = dot(c[0], c12);
    let size = norm(c[0]) * norm(c[1]) * norm(c[2]);
    if det.is_nan() || det.abs() <= tiny * size {
        return None;
    }
    Some([
        dot(r, c12) / det,
        dot(c[0], cross(r, c[2])) / det,
        dot(c[0], cross(c[1], r)) / det,
    ])
}

/// The line x − g n meets the 2D segment a–b (z = 0) at a + ξ (b − a).
/// Returns the meeting point and g.
pub(super) fn segment(
    x: [f64; 3],
    n: [f64; 3],
    a: [f64; 3],
    b: [f64; 3],
) -> Option<(Closest, f64)> {
    let e = sub(b, a);
    let r = sub(x, a);
    // ξ e + g n = x − a, in the xy-plane.
    let det = e[0] * n[1] - e[1] * n[0];
    let len = (e[0] * e[0] + e[1] * e[1]).sqrt();
    if det.is_nan() || det.abs() <= 1e-12 * len {
        return None;
    }
    let xi_raw = (r[0] * n[1] - r[1] * n[0]) / det;
    let g = (e[0] * r[1] - e[1] * r[0]) / det;
    if !(-BEYOND_TOL..=1.0 + BEYOND_TOL).contains(&xi_raw) {
        return None;
    }
    let xi = xi_raw.clamp(0.0, 1.0);
    let p = [a[0] + xi * e[0], a[1] + xi * e[1], a[2] + xi * e[2]];
    Some((hit(p, g, [1.0 - xi, xi, 0.0, 0.0], xi_raw, [0.0; 2]), g))
}

/// The line x − g n meets the triangle a–b–c at barycentric coordinates
/// (1 − u − v, u, v).
pub(super) fn triangle(
    x: [f64; 3],
    n: [f64; 3],
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
) -> Option<(Closest, f64)> {
    // u (b − a) + v (c − a) + g n = x − a
    let [u, v, g] = solve3([sub(b, a), sub(c, a), n], sub(x, a), 1e-12)?;
    let w = [1.0 - u - v, u, v];
    if w.iter().any(|&wk| wk < -BEYOND_TOL) {
        return None;
    }
    let w = clamp_simplex(w);
    let p = [
        w[0] * a[0] + w[1] * b[0] + w[2] * c[0],
        w[0] * a[1] + w[1] * b[1] + w[2] * c[1],
        w[0] * a[2] + w[1] * b[2] + w[2] * c[2],
    ];
    Some((hit(p, g, [w[0], w[1], w[2], 0.0], 0.0, [0.0; 2]), g))
}

/// Barycentric coordinates within rounding of the triangle, put on it.
fn clamp_simplex(w: [f64; 3]) -> [f64; 3] {
    let c = [w[0].max(0.0), w[1].max(0.0), w[2].max(0.0)];
    let s = c[0] + c[1] + c[2];
    [c[0] / s, c[1] / s, c[2] / s]
}

/// The line x − g n meets the bilinear quadrilateral x(ξ, η) = Σ N_k p_k:
/// Newton's method on x(ξ, η) + g n = x (quadratically convergent; for a
/// planar quad it is the inverse bilinear map), from the centre and, if that
/// fails, from where the line meets the triangle p0–p1–p2 or p0–p2–p3. The
/// weights are the bilinear shape functions at (ξ, η), clamped to [−1, 1]².
pub(super) fn quad(x: [f64; 3], n: [f64; 3], p: &[[f64; 3]; 4]) -> Option<(Closest, f64)> {
    let mut seeds = vec![[0.0, 0.0]];
    // Triangle p0-p1-p2 covers ξ ≥ η, p0-p2-p3 covers ξ ≤ η (reference
    // coordinates by the same barycentric weights).
    for tri in [[0, 1, 2], [0, 2, 3]] {
        if let Some((c, _)) = triangle(x, n, p[tri[0]], p[tri[1]], p[tri[2]]) {
            let mut s = [0.0; 2];
            for (k, &v) in tri.iter().enumerate() {
                s[0] += c.weights[k] * QUAD_CORNERS[v][0];
                s[1] += c.weights[k] * QUAD_CORNERS[v][1];
            }
            seeds.push(s);
        }
    }
    let [xi, eta, g] = seeds.into_iter().find_map(|s| quad_newton(x, n, p, s))?;
    let inside = |v: f64| v.abs() <= 1.0 + 2.0 * BEYOND_TOL;
    if !(inside(xi) && inside(eta)) {
        return None;
    }
    let (xi, eta) = (xi.clamp(-1.0, 1.0), eta.clamp(-1.0, 1.0));
    let (w, _, _) = bilinear(xi, eta);
    Some((hit(combine(w, p), g, w, 0.0, [xi, eta]), g))
}

/// Newton's method for x(ξ, η) + g n = x from (ξ, η) = `seed`; `Some((ξ, η,
/// g))` if it converged (wherever the solution lies).
fn quad_newton(x: [f64; 3], n: [f64; 3], p: &[[f64; 3]; 4], seed: [f64; 2]) -> Option<[f64; 3]> {
    let [mut xi, mut eta] = seed;
    let (w, _, _) = bilinear(xi, eta);
    let mut g = dot(n, sub(x, combine(w, p)));
    for _ in 0..50 {
        let (w, dxi, deta) = bilinear(xi, eta);
        let px = combine(w, p);
        let r = [
            x[0] - px[0] - g * n[0],
            x[1] - px[1] - g * n[1],
            x[2] - px[2] - g * n[2],
        ];
        let [dx, de, dg] = solve3([combine(dxi, p), combine(deta, p), n], r, 1e-12)?;
        xi += dx;
        eta += de;
        g += dg;
        if !(xi.abs() < 10.0 && eta.abs() < 10.0 && g.is_finite()) {
            return None;
        }
        if dx.abs() + de.abs() < 1e-13 {
            return Some([xi, eta, g]);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_meets_a_segment_inside_and_misses_it_outside() {
        let (a, b) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        // Tilted normal: from (0.5, 1) along −n, n = (−0.6, 0.8), meets y = 0 at
        // x = 0.5 + 0.75 = 1.25 after g = 1.25.
        let (c, g) = segment([0.5, 1.0, 0.0], [-0.6, 0.8, 0.0], a, b).unwrap();
        assert!((g - 1.25).abs() < 1e-15 && (c.x[0] - 1.25).abs() < 1e-15);
        assert!((c.weights[0] - 0.375).abs() < 1e-15 && (c.weights[1] - 0.625).abs() < 1e-15);
        // Below the segment: an overlap, g < 0.
        let (_, g) = segment([1.0, -0.5, 0.0], [0.0, 1.0, 0.0], a, b).unwrap();
        assert!((g + 0.5).abs() < 1e-15);
        // Parallel, and beyond the end.
        assert!(segment([1.0, 1.0, 0.0], [1.0, 0.0, 0.0], a, b).is_none());
        assert!(segment([2.5, 1.0, 0.0], [0.0, 1.0, 0.0], a, b).is_none());
    }

    #[test]
    fn a_line_meets_a_warped_quad_where_the_map_says() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.2],
            [1.2, 1.0, 0.0],
            [0.0, 1.0, 0.2],
        ];
        let (w, _, _) = bilinear(0.3, -0.6);
        let q = combine(w, &p);
        let n = [0.6, 0.0, 0.8];
        let x = [q[0] + 0.5 * n[0], q[1], q[2] + 0.5 * n[2]];
        let (c, g) = quad(x, n, &p).unwrap();
        assert!((g - 0.5).abs() < 1e-13, "{g}");
        assert!((c.xi_eta[0] - 0.3).abs() < 1e-13 && (c.xi_eta[1] + 0.6).abs() < 1e-13);
        assert!(norm(sub(c.x, q)) < 1e-13);
        // Shifted beyond side 1 (ξ = 1): missed.
        assert!(quad([x[0] + 2.0, x[1], x[2]], n, &p).is_none());
    }
}
