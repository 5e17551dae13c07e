//! The edges of 2D mortar contact (see the parent module): linear `[c0, c1]`
//! and quadratic `[c0, c1, mid]` edges on the parameter ξ ∈ [0, 1], their
//! curved geometry x(ξ) = Σ N_k(ξ) x_k, and the projections along a normal
//! that the overlap and the integration points need.
//!
//! Shape functions (s = 2ξ − 1): linear N = (1 − ξ, ξ); quadratic
//! N = (s(s − 1)/2, s(s + 1)/2, 1 − s²) for (c0, c1, mid), whose integrals
//! (1/6, 1/6, 2/3 of a straight edge's length) are all positive, so the dual
//! basis A = D M⁻¹ of a 3-node slave edge is well defined without the
//! modification Popp et al. need for quadratic faces in 3D.
//!
//! Projections: on a straight 2-node edge the equations are polynomial of
//! degree ≤ 2 and solved in closed form (extrapolated beyond the edge); on a
//! quadratic edge they are solved by Newton's method kept inside [0, 1]
//! (bisection where a Newton step would leave the bracket), and a point
//! outside the edge gets the chord's (2-node) estimate, whose side is all
//! that is used of it.

use signorini_mesh::vec3::{norm, sub};
use signorini_mesh::{Facet, Mesh};

/// Steps of a parameter of the unit range [0, 1] below which Newton's method
/// has converged (round-off of that range).
const PARAMETER_TOLERANCE: f64 = 16.0 * f64::EPSILON;

/// The most Newton / bisection steps of one projection (bisection alone
/// reaches the tolerance in about 50).
const MAX_STEPS: usize = 100;

/// A 2D edge of 2 or 3 nodes (`count`): its nodes and their coordinates
/// (unused entries zero).
#[derive(Debug, Clone, Copy)]
pub(super) struct Edge {
    pub nodes: [usize; 3],
    pub count: usize,
    pub x: [[f64; 3]; 3],
}

impl Edge {
    /// The edge of a surface facet of 2 or 3 nodes.
    pub fn of(mesh: &Mesh, f: &Facet) -> Edge {
        let count = f.nodes.len().min(3);
        let (mut nodes, mut x) = ([0; 3], [[0.0; 3]; 3]);
        for k in 0..count {
            nodes[k] = f.nodes[k];
            x[k] = mesh.coords[f.nodes[k]];
        }
        Edge { nodes, count, x }
    }

    pub fn nodes(&self) -> &[usize] {
        &self.nodes[..self.count]
    }

    pub fn shape(&self, xi: f64) -> [f64; 3] {
        shape(self.count, xi)
    }

    pub fn point(&self, xi: f64) -> [f64; 3] {
        interpolate(&self.x, self.shape(xi))
    }

    /// dx/dξ.
    pub fn tangent(&self, xi: f64) -> [f64; 3] {
        interpolate(&self.x, shape_derivative(self.count, xi))
    }

    /// The chord's length |x_c1 − x_c0|.
    pub fn chord(&self) -> f64 {
        norm(sub(self.x[1], self.x[0]))
    }

    /// The parameter η of the point y(η) of the edge on the line through x
    /// along n, cross(y(η) − x, n) = 0 (None when they are parallel).
    pub fn parameter_along(&self, x: [f64; 3], n: [f64; 3]) -> Option<f64> {
        let chord = line_parameter(self.x[0], self.x[1], x, n);
        if self.count == 2 {
            return chord;
        }
        root_in_unit(|eta| {
            (
                cross2(sub(self.point(eta), x), n),
                cross2(self.tangent(eta), n),
            )
        })
        .or_else(|| chord.map(outside))
    }
}

/// A slave edge with the outward nodal normals of its nodes, interpolated
/// with its shape functions: n(ξ) = Σ N_k(ξ) n_k (not unit).
pub(super) struct SlaveEdge {
    pub edge: Edge,
    pub n: [[f64; 3]; 3],
}

impl SlaveEdge {
    pub fn point(&self, xi: f64) -> [f64; 3] {
        self.edge.point(xi)
    }

    pub fn normal(&self, xi: f64) -> [f64; 3] {
        interpolate(&self.n, self.edge.shape(xi))
    }

    /// |dx/dξ|: the length element of the (curved) edge.
    pub fn jacobian(&self, xi: f64) -> f64 {
        norm(self.edge.tangent(xi))
    }

    /// The slave parameter ξ whose normal line passes through y:
    /// cross(x(ξ) − y, n(ξ)) = 0. Outside [0, 1] on a quadratic edge, the
    /// chord's estimate (only its side is used).
    pub fn parameter_of(&self, y: [f64; 3]) -> Option<f64> {
        let chord = self.chord_parameter_of(y);
        if self.edge.count == 2 {
            return chord;
        }
        let dn = |xi: f64| interpolate(&self.n, shape_derivative(3, xi));
        root_in_unit(|xi| {
            let r = sub(self.point(xi), y);
            (
                cross2(r, self.normal(xi)),
                cross2(self.edge.tangent(xi), self.normal(xi)) + cross2(r, dn(xi)),
            )
        })
        .or_else(|| chord.map(outside))
    }

    /// [`SlaveEdge::parameter_of`] on the chord c0–c1 with the corner
    /// normals interpolated linearly: a quadratic in ξ, the root nearest the
    /// middle.
    fn chord_parameter_of(&self, y: [f64; 3]) -> Option<f64> {
        let (x, n) = (&self.edge.x, &self.n);
        let r = sub(x[0], y);
        let e = sub(x[1], x[0]);
        let dn = sub(n[1], n[0]);
        let (c0, c1, c2) = (
            cross2(r, n[0]),
            cross2(r, dn) + cross2(e, n[0]),
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

/// The chord's estimate of a parameter when the curved edge has no root in
/// [0, 1]: the root is outside, on the side the estimate gives (an estimate
/// inside becomes the nearer end).
fn outside(chord: f64) -> f64 {
    match chord {
        c if (0.0..0.5).contains(&c) => 0.0,
        c if (0.5..=1.0).contains(&c) => 1.0,
        c => c,
    }
}

/// The shape functions of a `count`-node edge at ξ (unused entries zero).
pub(super) fn shape(count: usize, xi: f64) -> [f64; 3] {
    if count == 2 {
        [1.0 - xi, xi, 0.0]
    } else {
        let s = 2.0 * xi - 1.0;
        [0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s]
    }
}

/// dN/dξ of a `count`-node edge.
fn shape_derivative(count: usize, xi: f64) -> [f64; 3] {
    if count == 2 {
        [-1.0, 1.0, 0.0]
    } else {
        let s = 2.0 * xi - 1.0;
        [2.0 * s - 1.0, 2.0 * s + 1.0, -4.0 * s]
    }
}

fn interpolate(v: &[[f64; 3]; 3], n: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|k| n[0] * v[0][k] + n[1] * v[1][k] + n[2] * v[2][k])
}

pub(super) fn cross2(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The parameter η ∈ ℝ of the point of the line c–d met by the line
/// through x along n (None when they are parallel).
fn line_parameter(c: [f64; 3], d: [f64; 3], x: [f64; 3], n: [f64; 3]) -> Option<f64> {
    let f = sub(d, c);
    let den = cross2(f, n);
    (den.abs() > 1e-14 * norm(f) * norm(n)).then(|| -cross2(sub(c, x), n) / den)
}

/// The root in [0, 1] of f (given with its derivative) when f(0) and f(1)
/// differ in sign (else None): Newton's steps while they stay inside the
/// bracket, bisection otherwise.
fn root_in_unit(f: impl Fn(f64) -> (f64, f64)) -> Option<f64> {
    let (f0, f1) = (f(0.0).0, f(1.0).0);
    if f0 == 0.0 {
        return Some(0.0);
    }
    if f1 == 0.0 {
        return Some(1.0);
    }
    if !(f0.is_finite() && f1.is_finite()) || f0.signum() == f1.signum() {
        return None;
    }
    // f(neg) < 0 < f(pos).
    let (mut neg, mut pos) = if f0 < 0.0 { (0.0, 1.0) } else { (1.0, 0.0) };
    let mut t = 0.5;
    for _ in 0..MAX_STEPS {
        let (v, d) = f(t);
        if v == 0.0 {
            return Some(t);
        }
        if v < 0.0 {
            neg = t;
        } else {
            pos = t;
        }
        let (lo, hi) = if neg < pos { (neg, pos) } else { (pos, neg) };
        let newton = t - v / d;
        let next = if d != 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - t).abs() <= PARAMETER_TOLERANCE || hi - lo <= PARAMETER_TOLERANCE {
            return Some(next);
        }
        t = next;
    }
    Some(t)
}
