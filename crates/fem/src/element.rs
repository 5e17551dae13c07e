//! Element stiffness matrices of the linear triangle (T3) and the bilinear
//! quadrilateral (Q4), thickness 1: `K_e = ∫_e Bᵀ D B dA`.
//!
//! Element DOFs are ordered node by node, `[u_x1, u_y1, u_x2, u_y2, ...]`, and
//! `ε = B u_e` with, for each node `a` of shape function `N_a`,
//!
//! ```text
//!        | ∂N_a/∂x     0     |
//! B_a =  |    0     ∂N_a/∂y  |      (ε = [ε_xx, ε_yy, γ_xy])
//!        | ∂N_a/∂y  ∂N_a/∂x  |
//! ```
//!
//! * T3: `N_a` linear, `B` constant: with `2A = (x2−x1)(y3−y1) − (x3−x1)(y2−y1)`,
//!   `∂N_1/∂x = (y2−y3)/2A`, `∂N_1/∂y = (x3−x2)/2A` and cyclically; `K_e = A Bᵀ D B`
//!   (exact).
//! * Q4: `N_a(ξ, η) = ¼ (1 + ξ_a ξ)(1 + η_a η)` on the reference square
//!   `[−1, 1]²` (corners `(−1,−1), (1,−1), (1,1), (−1,1)`), Jacobian
//!   `J = Σ_a [∂N_a/∂ξ; ∂N_a/∂η] [x_a, y_a]`, `[∂N_a/∂x; ∂N_a/∂y] = J⁻¹ [∂N_a/∂ξ; ∂N_a/∂η]`,
//!   `K_e = Σ_g Bᵀ D B det J` over the 2×2 Gauss points `ξ, η = ±1/√3` (weights 1),
//!   exact for parallelograms and the standard full integration otherwise.

use crate::{Elasticity, FemError};
use nalgebra::{DMatrix, Matrix2};
use signorini_mesh::{CellKind, Mesh};

/// The 2×2 Gauss points of the reference square (weights 1).
pub const GAUSS_2X2: [[f64; 2]; 4] = {
    const G: f64 = 0.577_350_269_189_625_8; // 1/√3
    [[-G, -G], [G, -G], [G, G], [-G, G]]
};

const Q4_CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

fn require_2d(mesh: &Mesh) {
    assert_eq!(
        mesh.dim, 2,
        "signorini-fem handles 2D meshes only (mesh.dim = {})",
        mesh.dim
    );
}

/// Strain-displacement matrix `B` (3 × 2n) of `cell` at the reference point `xi`
/// (ignored for T3), with the quadrature factor: the area `A` for T3 (one point,
/// `K_e = A Bᵀ D B`), `det J` at `xi` for Q4 (`dA = det J dξ dη`).
///
/// # Errors
/// [`FemError::BadJacobian`] if the determinant is not positive.
pub fn b_matrix(mesh: &Mesh, cell: usize, xi: [f64; 2]) -> Result<(DMatrix<f64>, f64), FemError> {
    let c = &mesh.cells[cell];
    let p = |a: usize| mesh.coords[c.nodes[a]];
    // dN/dx, dN/dy per node, and the measure factor
    let (grads, factor): (Vec<[f64; 2]>, f64) = match c.kind {
        CellKind::Tri3 => {
            let (p1, p2, p3) = (p(0), p(1), p(2));
            let two_a = (p2[0] - p1[0]) * (p3[1] - p1[1]) - (p3[0] - p1[0]) * (p2[1] - p1[1]);
            if two_a.is_nan() || two_a <= 0.0 {
                return Err(FemError::BadJacobian { cell, det: two_a });
            }
            let g = vec![
                [(p2[1] - p3[1]) / two_a, (p3[0] - p2[0]) / two_a],
                [(p3[1] - p1[1]) / two_a, (p1[0] - p3[0]) / two_a],
                [(p1[1] - p2[1]) / two_a, (p2[0] - p1[0]) / two_a],
            ];
            (g, 0.5 * two_a)
        }
        CellKind::Quad4 => {
            let (x, e) = (xi[0], xi[1]);
            let dn: Vec<[f64; 2]> = Q4_CORNERS
                .iter()
                .map(|a| {
                    [
                        0.25 * a[0] * (1.0 + a[1] * e),
                        0.25 * a[1] * (1.0 + a[0] * x),
                    ]
                })
                .collect();
            let mut j = Matrix2::<f64>::zeros();
            for (a, d) in dn.iter().enumerate() {
                let q = p(a);
                j[(0, 0)] += d[0] * q[0];
                j[(0, 1)] += d[0] * q[1];
                j[(1, 0)] += d[1] * q[0];
                j[(1, 1)] += d[1] * q[1];
            }
            let det: f64 = j.determinant();
            if det.is_nan() || det <= 0.0 {
                return Err(FemError::BadJacobian { cell, det });
            }
            let inv = Matrix2::new(j[(1, 1)], -j[(0, 1)], -j[(1, 0)], j[(0, 0)]) / det;
            let g = dn
                .iter()
                .map(|d| {
                    [
                        inv[(0, 0)] * d[0] + inv[(0, 1)] * d[1],
                        inv[(1, 0)] * d[0] + inv[(1, 1)] * d[1],
                    ]
                })
                .collect();
            (g, det)
        }
        other => {
            return Err(FemError::Unsupported(format!(
                "{} cells are not supported yet",
                other.name()
            )))
        }
    };
    let n = grads.len();
    let mut b = DMatrix::zeros(3, 2 * n);
    for (a, g) in grads.iter().enumerate() {
        b[(0, 2 * a)] = g[0];
        b[(1, 2 * a + 1)] = g[1];
        b[(2, 2 * a)] = g[1];
        b[(2, 2 * a + 1)] = g[0];
    }
    Ok((b, factor))
}

/// Element stiffness `K_e = ∫ Bᵀ D B dA` (thickness 1), `(2n) × (2n)` with `n`
/// the number of nodes of the cell; T3 exact, Q4 by 2×2 Gauss quadrature.
///
/// # Errors
/// [`FemError::BadJacobian`] (naming the cell) if the Jacobian determinant is
/// not positive at an integration point.
pub fn try_element_stiffness(
    mesh: &Mesh,
    cell: usize,
    mat: &Elasticity,
) -> Result<DMatrix<f64>, FemError> {
    require_2d(mesh);
    let d = mat.d_matrix();
    let d = DMatrix::from_fn(3, 3, |i, j| d[(i, j)]);
    let points: &[[f64; 2]] = match mesh.cells[cell].kind {
        CellKind::Tri3 => &[[0.0, 0.0]],
        CellKind::Quad4 => &GAUSS_2X2,
        _ => &[[0.0, 0.0]],
    };
    let n = 2 * mesh.cells[cell].nodes.len();
    let mut k = DMatrix::zeros(n, n);
    for &xi in points {
        let (b, w) = b_matrix(mesh, cell, xi)?;
        let db = &d * &b;
        k.gemm_tr(w, &b, &db, 1.0);
    }
    // exact symmetry (rounding in the product is not symmetric)
    for i in 0..n {
        for j in 0..i {
            let s = 0.5 * (k[(i, j)] + k[(j, i)]);
            k[(i, j)] = s;
            k[(j, i)] = s;
        }
    }
    Ok(k)
}

/// [`try_element_stiffness`] for a valid cell.
///
/// # Panics
/// If the cell's Jacobian is not positive (see [`check_mesh`]) or the mesh is
/// not 2D.
pub fn element_stiffness(mesh: &Mesh, cell: usize, mat: &Elasticity) -> DMatrix<f64> {
    try_element_stiffness(mesh, cell, mat).unwrap_or_else(|e| panic!("{e}"))
}

/// Checks that every cell can be integrated: a 2D mesh, and a positive
/// Jacobian determinant at every corner of every cell (for Q4 this is
/// equivalent to a strictly convex counter-clockwise quadrilateral, and implies
/// a positive determinant everywhere inside, Gauss points included).
///
/// # Errors
/// [`FemError::BadJacobian`] naming the first bad cell, or
/// [`FemError::Unsupported`] for a mesh that is not 2D.
pub fn check_mesh(mesh: &Mesh) -> Result<(), FemError> {
    if mesh.dim != 2 {
        return Err(FemError::Unsupported(format!(
            "only 2D meshes are supported (dim = {})",
            mesh.dim
        )));
    }
    for (c, cell) in mesh.cells.iter().enumerate() {
        if cell.nodes.len() != cell.kind.nodes() {
            return Err(FemError::Unsupported(format!(
                "cell {c} ({}) has {} nodes",
                cell.kind.name(),
                cell.nodes.len()
            )));
        }
        match cell.kind {
            CellKind::Tri3 => {
                b_matrix(mesh, c, [0.0, 0.0])?;
            }
            CellKind::Quad4 => {
                for xi in Q4_CORNERS {
                    b_matrix(mesh, c, xi)?;
                }
            }
            other => {
                return Err(FemError::Unsupported(format!(
                    "{} cells are not supported yet",
                    other.name()
                )))
            }
        }
    }
    Ok(())
}
