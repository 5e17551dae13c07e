//! The tangential directions of a contact point that supports hold at both
//! bodies: a symmetry plane (or a guide) through the slave node and the
//! master surface beneath it.
//!
//! On a symmetry plane x = 0 the shear traction across the plane vanishes
//! (σ_xz = 0), so the friction force along a direction the plane holds at
//! both bodies is zero: the supports carry it (docs/theory/mortar.md,
//! "Symmetry planes on both bodies"). A node-to-face row there has no free
//! DOF (`contacts::free_tangential_rows` drops it); a mortar row keeps the
//! master nodes of its support that lie off the plane, whose DOFs are free,
//! so the rows of the plane's slave nodes act on a few shared master DOFs:
//! dependent rows, a singular W, undetermined friction multipliers. A
//! tangential direction d (a combination of the point's nodal frame t1, t2)
//! is held at both bodies when
//!
//! - the slave node is held along d: d has no component along a free DOF of
//!   the node (the null space of the Gram matrix S of the frame's free
//!   components), and
//! - the master part of the row along d has a prescribed DOF (the master is
//!   held along d there: d is outside the null space of the Gram matrix H
//!   of the rows' prescribed master parts).
//!
//! A guided slave against a master free along d has friction along d: its
//! row is kept.

use std::collections::BTreeMap;

use signorini_geometry::ContactPoint;

use super::BodyModel;

/// A row of B as (body, DOF, coefficient) entries.
pub(super) type Row = Vec<(usize, usize, f64)>;

/// A row's entries keyed by (body, DOF), the coefficients of a DOF summed.
pub(super) type Part = BTreeMap<(usize, usize), f64>;

/// Below this fraction of the rows' squared norm, a Gram eigenvalue is
/// round-off: the combination has no entry of that kind.
pub(super) const NEGLIGIBLE: f64 = 1e-10;

/// The entries of a row that `keep` selects, keyed by (body, DOF).
pub(super) fn part(r: &Row, keep: impl Fn(usize, usize) -> bool) -> Part {
    let mut m = Part::new();
    for &(b, d, c) in r.iter().filter(|&&(b, d, _)| keep(b, d)) {
        *m.entry((b, d)).or_insert(0.0) += c;
    }
    m
}

/// The dot product of two parts.
pub(super) fn dot_parts(a: &Part, b: &Part) -> f64 {
    a.iter()
        .map(|(k, v)| v * b.get(k).copied().unwrap_or(0.0))
        .sum()
}

/// The smallest eigenvalue of the symmetric 2×2 matrix [[a, b], [b, c]]
/// and a unit eigenvector (cs, sn) of it.
pub(super) fn least_eigenpair(a: f64, b: f64, c: f64) -> (f64, [f64; 2]) {
    let lmin = 0.5 * (a + c - ((a - c).powi(2) + 4.0 * b * b).sqrt());
    let (v1, v2) = if (a - lmin).abs() >= (c - lmin).abs() {
        (-b, a - lmin)
    } else {
        (c - lmin, -b)
    };
    let nv = v1.hypot(v2);
    if nv == 0.0 {
        return (lmin, [1.0, 0.0]); // a multiple of the identity
    }
    (lmin, [v1 / nv, v2 / nv])
}

/// The directions, in the frame of a point's tangential rows, that supports
/// hold at both bodies.
#[derive(Debug, PartialEq)]
pub(super) enum HeldTangents {
    /// None: every row keeps its friction unknown.
    None,
    /// The combination cs t1 + sn t2 (3D): its friction force is zero, the
    /// other direction keeps a row.
    Direction([f64; 2]),
    /// Every tangential direction (2D: the tangent).
    All,
}

/// The tangential directions of a contact point `p` (rows `t1` and, in 3D,
/// `t2`, along its nodal frame) held at both bodies, `slave_body` being the
/// slave's body model.
pub(super) fn held_at_both_bodies(
    bodies: &[BodyModel],
    slave_body: usize,
    p: &ContactPoint,
    t1: &Row,
    t2: Option<&Row>,
) -> HeldTangents {
    let slave = &bodies[slave_body];
    let dim = slave.mesh.dim;
    let free_axes: Vec<usize> = (0..dim)
        .filter(|&k| !slave.prescribed[p.slave_node * dim + k])
        .collect();
    // The slave node's motion along tangents u, v: its free components.
    let slave_gram = |u: [f64; 3], v: [f64; 3]| free_axes.iter().map(|&k| u[k] * v[k]).sum::<f64>();
    let held_master = |r: &Row| part(r, |b, d| b != slave_body && bodies[b].prescribed[d]);
    let norm2 = |r: &Row| r.iter().map(|e| e.2 * e.2).sum::<f64>();
    let Some(t2) = t2 else {
        let h = held_master(t1);
        let held = slave_gram(p.tangent, p.tangent) <= NEGLIGIBLE
            && dot_parts(&h, &h) > NEGLIGIBLE * norm2(t1);
        return if held {
            HeldTangents::All
        } else {
            HeldTangents::None
        };
    };
    let tol = NEGLIGIBLE * (norm2(t1) + norm2(t2));
    let (h1, h2) = (held_master(t1), held_master(t2));
    let (ha, hb, hc) = (
        dot_parts(&h1, &h1),
        dot_parts(&h1, &h2),
        dot_parts(&h2, &h2),
    );
    let (sa, sb, sc) = (
        slave_gram(p.tangent, p.tangent),
        slave_gram(p.tangent, p.tangent2),
        slave_gram(p.tangent2, p.tangent2),
    );
    let (slave_min, v) = least_eigenpair(sa, sb, sc);
    if slave_min > NEGLIGIBLE {
        return HeldTangents::None; // the slave node moves along every tangent
    }
    if sa + sc - slave_min > NEGLIGIBLE {
        // The slave node is held along v only.
        let along_v = v[0] * v[0] * ha + 2.0 * v[0] * v[1] * hb + v[1] * v[1] * hc;
        return if along_v > tol {
            HeldTangents::Direction(v)
        } else {
            HeldTangents::None
        };
    }
    // The slave node is held along every tangent: those the master holds too.
    let (master_min, w) = least_eigenpair(ha, hb, hc);
    if master_min > tol {
        HeldTangents::All
    } else if ha + hc - master_min > tol {
        // The master is free along w only: the other direction is held.
        HeldTangents::Direction([-w[1], w[0]])
    } else {
        HeldTangents::None
    }
}
