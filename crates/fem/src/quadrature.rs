//! Quadrature rules of the reference cells (course notes §3.1.1), with
//! which [`crate::element`], [`crate::bbar`] and [`crate::loads`] integrate.
//!
//! The quadrature rule of each cell ([`quadrature`]): Tri3 one point at the centroid in the
//! plane models (`B` is constant: exact); Tri3 in axisymmetry and Tri6 the
//! 3-point rule of degree 2 at `(1/6, 1/6), (2/3, 1/6), (1/6, 2/3)`, weights
//! 1/6 (exact for the quadratic stiffness of a straight-sided T6); Quad4 2×2
//! Gauss; Quad8 3×3 Gauss; Tet4 one point at the centroid (exact); Hex8
//! 2×2×2 Gauss; Tet10 the 4-point rule of degree 2 (`a = (5 + 3√5)/20`,
//! `b = (5 − √5)/20`, weights 1/24, exact for the stiffness of a
//! straight-sided Tet10); Hex20 3×3×3 Gauss (full integration). In
//! axisymmetry the hoop term `N_a / r` is evaluated at the
//! quadrature points only: they are interior to the cell, so `r > 0` there
//! even when nodes lie on the axis `r = 0`, and the axis itself is never
//! evaluated. The rules integrate `Bᵀ D B det J` exactly for straight-sided
//! simplices and parallelograms/parallelepipeds in the plane and solid
//! models, and pass the patch test (a uniform strain field reproduced
//! exactly) on distorted cells in every model: Q4 and Hex8 of any convex
//! shape, T6 and Q8 with straight sides and centred mid-side nodes. With
//! every cell's rule, the element kernel is exactly the model's rigid-body
//! motions (3 in the plane, the axial translation in axisymmetry, 6 in 3D;
//! [`crate::rigid_body_modes`]): no spurious zero-energy mode.

use crate::Model;
use signorini_mesh::CellKind;

/// A quadrature point of a reference cell: reference coordinates `xi`
/// (unused trailing ones are 0) and weight `w` (the weights of a rule sum to
/// the measure of the reference cell: 1/2 triangle, 4 square, 1/6
/// tetrahedron, 8 cube).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadPoint {
    pub xi: [f64; 3],
    pub w: f64,
}

const fn qp(x: f64, y: f64, z: f64, w: f64) -> QuadPoint {
    QuadPoint { xi: [x, y, z], w }
}

/// 1/√3, the 2-point Gauss abscissa.
const G2: f64 = 0.577_350_269_189_625_8;
/// √(3/5), the 3-point Gauss abscissa (weights 5/9, 8/9, 5/9).
const G3: f64 = 0.774_596_669_241_483_4;

/// Centroid of the reference triangle (weight 1/2).
pub const TRI_1: [QuadPoint; 1] = [qp(1.0 / 3.0, 1.0 / 3.0, 0.0, 0.5)];
/// Degree-2 triangle rule with interior points (weights 1/6).
pub const TRI_3: [QuadPoint; 3] = [
    qp(1.0 / 6.0, 1.0 / 6.0, 0.0, 1.0 / 6.0),
    qp(2.0 / 3.0, 1.0 / 6.0, 0.0, 1.0 / 6.0),
    qp(1.0 / 6.0, 2.0 / 3.0, 0.0, 1.0 / 6.0),
];
/// Weight and coordinates of the 6-point rule of degree 4 on the reference
/// triangle (Dunavant 1985): two orbits of three points.
const D4_A: f64 = 0.445_948_490_915_965;
const D4_B: f64 = 0.091_576_213_509_771;
const D4_WA: f64 = 0.223_381_589_678_011 / 2.0;
const D4_WB: f64 = 0.109_951_743_655_322 / 2.0;
/// The 6-point rule of degree 4 on the reference triangle, with which
/// [`crate::loads`] integrates the faces of second-order cells.
pub const TRI_6: [QuadPoint; 6] = [
    qp(D4_A, D4_A, 0.0, D4_WA),
    qp(1.0 - 2.0 * D4_A, D4_A, 0.0, D4_WA),
    qp(D4_A, 1.0 - 2.0 * D4_A, 0.0, D4_WA),
    qp(D4_B, D4_B, 0.0, D4_WB),
    qp(1.0 - 2.0 * D4_B, D4_B, 0.0, D4_WB),
    qp(D4_B, 1.0 - 2.0 * D4_B, 0.0, D4_WB),
];
/// 2×2 Gauss on the reference square (weights 1).
pub const GAUSS_2X2: [QuadPoint; 4] = [
    qp(-G2, -G2, 0.0, 1.0),
    qp(G2, -G2, 0.0, 1.0),
    qp(G2, G2, 0.0, 1.0),
    qp(-G2, G2, 0.0, 1.0),
];
/// 3×3 Gauss on the reference square.
pub const GAUSS_3X3: [QuadPoint; 9] = gauss3();
/// Centroid of the reference tetrahedron (weight 1/6).
pub const TET_1: [QuadPoint; 1] = [qp(0.25, 0.25, 0.25, 1.0 / 6.0)];
/// 2×2×2 Gauss on the reference cube (weights 1).
pub const GAUSS_2X2X2: [QuadPoint; 8] = {
    let mut out = [qp(0.0, 0.0, 0.0, 1.0); 8];
    let mut i = 0;
    while i < 8 {
        let x = if i & 1 == 0 { -G2 } else { G2 };
        let y = if i & 2 == 0 { -G2 } else { G2 };
        let z = if i & 4 == 0 { -G2 } else { G2 };
        out[i] = qp(x, y, z, 1.0);
        i += 1;
    }
    out
};

/// `(5 − √5)/20` and `(5 + 3√5)/20`, the coordinates of the 4-point rule.
const TB: f64 = 0.138_196_601_125_010_5;
const TA: f64 = 0.585_410_196_624_968_5;

/// The 4-point rule of degree 2 on the reference tetrahedron (weights 1/24).
pub const TET_4: [QuadPoint; 4] = [
    qp(TB, TB, TB, 1.0 / 24.0),
    qp(TA, TB, TB, 1.0 / 24.0),
    qp(TB, TA, TB, 1.0 / 24.0),
    qp(TB, TB, TA, 1.0 / 24.0),
];

/// 3×3×3 Gauss on the reference cube.
pub const GAUSS_3X3X3: [QuadPoint; 27] = gauss3();

/// The 3-point Gauss rule (abscissae 0, ±√(3/5), weights 8/9, 5/9) in each
/// direction of the square (`N` = 9) or the cube (`N` = 27), ξ fastest.
const fn gauss3<const N: usize>() -> [QuadPoint; N] {
    const X: [f64; 3] = [-G3, 0.0, G3];
    const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let mut out = [qp(0.0, 0.0, 0.0, 0.0); N];
    let mut i = 0;
    while i < N {
        let (a, b, c) = (i % 3, (i / 3) % 3, i / 9);
        out[i] = if N == 27 {
            qp(X[a], X[b], X[c], W[a] * W[b] * W[c])
        } else {
            qp(X[a], X[b], 0.0, W[a] * W[b])
        };
        i += 1;
    }
    out
}

/// The quadrature rule of a cell kind in a model (see the module docs).
pub fn quadrature(kind: CellKind, model: Model) -> &'static [QuadPoint] {
    match kind {
        CellKind::Tri3 if model == Model::Axisymmetric => &TRI_3,
        CellKind::Tri3 => &TRI_1,
        CellKind::Tri6 => &TRI_3,
        CellKind::Quad4 => &GAUSS_2X2,
        CellKind::Quad8 => &GAUSS_3X3,
        CellKind::Tet4 => &TET_1,
        CellKind::Hex8 => &GAUSS_2X2X2,
        CellKind::Tet10 => &TET_4,
        CellKind::Hex20 => &GAUSS_3X3X3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rules_integrate_their_cells_volume_and_quadratics() {
        let v: f64 = TET_4.iter().map(|q| q.w).sum();
        assert!((v - 1.0 / 6.0).abs() < 1e-15);
        // ∫ ξ² over the reference tetrahedron = 1/60
        let m2: f64 = TET_4.iter().map(|q| q.w * q.xi[0] * q.xi[0]).sum();
        assert!((m2 - 1.0 / 60.0).abs() < 1e-15);
        let v: f64 = GAUSS_3X3X3.iter().map(|q| q.w).sum();
        assert!((v - 8.0).abs() < 1e-14);
        // ∫ ξ⁴ η² over the cube = (2/5)(2/3)(2)
        let m: f64 = GAUSS_3X3X3
            .iter()
            .map(|q| q.w * q.xi[0].powi(4) * q.xi[1].powi(2))
            .sum();
        assert!((m - 0.4 * 2.0 / 3.0 * 2.0).abs() < 1e-14);
    }
}
