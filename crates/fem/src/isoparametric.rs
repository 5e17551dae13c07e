//! Isoparametric reference cells (course notes §3.1.1): shape functions,
//! the Jacobian and the strain–displacement matrix B that [`crate::element`]
//! and [`crate::bbar`] integrate with.
//!
//! **Geometry.** On the reference cell, `x(ξ) = Σ_a N_a(ξ) x_a`; the Jacobian
//! `J_ij = ∂x_j/∂ξ_i = Σ_a ∂N_a/∂ξ_i x_aj` gives `∇_x N_a = J⁻¹ ∇_ξ N_a`. Reference
//! cells and shape functions (node orders of [`CellKind`]):
//!
//! * Tri3: `(0,0), (1,0), (0,1)`, `N = [L1, L2, L3]`, `L1 = 1−ξ−η, L2 = ξ, L3 = η`.
//! * Tri6: corners `N_i = L_i (2 L_i − 1)`, mid-sides `4 L1 L2, 4 L2 L3, 4 L3 L1`.
//! * Quad4: `[−1,1]²`, corners `(−1,−1), (1,−1), (1,1), (−1,1)`,
//!   `N_a = ¼ (1 + ξ_a ξ)(1 + η_a η)`.
//! * Quad8 (serendipity): corners `¼ (1 + ξ_a ξ)(1 + η_a η)(ξ_a ξ + η_a η − 1)`,
//!   mid-sides `½ (1 − ξ²)(1 + η_a η)` (at `ξ_a = 0`) and `½ (1 + ξ_a ξ)(1 − η²)` (at `η_a = 0`).
//! * Tet4: `(0,0,0), (1,0,0), (0,1,0), (0,0,1)`, `N = [1−ξ−η−ζ, ξ, η, ζ]`.
//! * Hex8: `[−1,1]³`, bottom `ζ = −1` counter-clockwise then top,
//!   `N_a = ⅛ (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ)`.
//! * Tet10 and Hex20: [`crate::quadratic_solids`].
//!
//! **Strain–displacement matrix.** Element DOFs are node by node
//! (`[u_x1, u_y1, (u_z1), u_x2, ...]`) and `ε = B u_e` with, per node `a`
//! (`N,x = ∂N_a/∂x`, ...):
//!
//! ```text
//! plane [xx, yy, xy]     axisymmetric [rr, zz, θθ, rz]    solid [xx, yy, zz, xy, yz, xz]
//! | N,x   0  |           | N,r    0   |                   | N,x  0    0   |
//! |  0   N,y |           |  0    N,z  |                   | 0    N,y  0   |
//! | N,y  N,x |           | N/r    0   |                   | 0    0    N,z |
//!                        | N,z   N,r  |                   | N,y  N,x  0   |
//!                                                         | 0    N,z  N,y |
//!                                                         | N,z  0    N,x |
//! ```
//!
//! **Quadrature**: [`crate::quadrature`].

use crate::quadrature::QuadPoint;
use crate::{quadratic_solids, FemError, Model};
use nalgebra::{DMatrix, Matrix3};
use signorini_mesh::{CellKind, Mesh};
use std::f64::consts::PI;

/// Largest number of nodes of a cell.
const MAX_NODES: usize = 20;

/// Reference coordinates of the corners of a cell kind, in node order.
pub fn reference_corners(kind: CellKind) -> &'static [[f64; 3]] {
    match kind {
        CellKind::Tri3 | CellKind::Tri6 => &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        CellKind::Quad4 | CellKind::Quad8 => &[
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        CellKind::Tet4 | CellKind::Tet10 => &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        CellKind::Hex8 | CellKind::Hex20 => &signorini_mesh::HEX8_REFERENCE_CORNERS,
    }
}

/// Reference coordinates of the centre of a cell kind (the centroid of the
/// reference cell), where [`crate::cell_stress`] evaluates the stress.
pub fn reference_centre(kind: CellKind) -> [f64; 3] {
    match kind {
        CellKind::Tri3 | CellKind::Tri6 => [1.0 / 3.0, 1.0 / 3.0, 0.0],
        CellKind::Tet4 | CellKind::Tet10 => [0.25, 0.25, 0.25],
        CellKind::Quad4 | CellKind::Quad8 | CellKind::Hex8 | CellKind::Hex20 => [0.0, 0.0, 0.0],
    }
}

/// Shape function values and their derivatives (reference or physical) at a
/// point, for the first `len` nodes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Shape {
    pub(crate) len: usize,
    pub(crate) n: [f64; MAX_NODES],
    pub(crate) dn: [[f64; 3]; MAX_NODES],
}

/// Shape functions of `kind` and their reference derivatives at `xi`.
pub(crate) fn shape(kind: CellKind, xi: [f64; 3]) -> Shape {
    let mut s = Shape {
        len: kind.nodes(),
        n: [0.0; MAX_NODES],
        dn: [[0.0; 3]; MAX_NODES],
    };
    let [x, y, z] = xi;
    match kind {
        CellKind::Tri3 => {
            s.n[..3].copy_from_slice(&[1.0 - x - y, x, y]);
            s.dn[..3].copy_from_slice(&[[-1.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        }
        CellKind::Tri6 => {
            let l = [1.0 - x - y, x, y];
            // ∂L_i/∂(ξ, η)
            let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
            for i in 0..3 {
                s.n[i] = l[i] * (2.0 * l[i] - 1.0);
                let f = 4.0 * l[i] - 1.0;
                s.dn[i] = [f * dl[i][0], f * dl[i][1], 0.0];
            }
            for (m, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                s.n[3 + m] = 4.0 * l[i] * l[j];
                s.dn[3 + m] = [
                    4.0 * (dl[i][0] * l[j] + l[i] * dl[j][0]),
                    4.0 * (dl[i][1] * l[j] + l[i] * dl[j][1]),
                    0.0,
                ];
            }
        }
        CellKind::Quad4 => {
            for (a, c) in reference_corners(kind).iter().enumerate() {
                let (fx, fy) = (1.0 + c[0] * x, 1.0 + c[1] * y);
                s.n[a] = 0.25 * fx * fy;
                s.dn[a] = [0.25 * c[0] * fy, 0.25 * c[1] * fx, 0.0];
            }
        }
        CellKind::Quad8 => {
            for (a, c) in reference_corners(kind).iter().enumerate() {
                let (fx, fy) = (1.0 + c[0] * x, 1.0 + c[1] * y);
                let g = c[0] * x + c[1] * y - 1.0;
                s.n[a] = 0.25 * fx * fy * g;
                s.dn[a] = [
                    0.25 * c[0] * fy * (g + fx),
                    0.25 * c[1] * fx * (g + fy),
                    0.0,
                ];
            }
            // mid-sides of 0-1 (η = −1), 1-2 (ξ = 1), 2-3 (η = 1), 3-0 (ξ = −1)
            for (m, (cx, cy)) in [(0.0, -1.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)]
                .into_iter()
                .enumerate()
            {
                let a = 4 + m;
                if cx == 0.0 {
                    let fy = 1.0 + cy * y;
                    s.n[a] = 0.5 * (1.0 - x * x) * fy;
                    s.dn[a] = [-x * fy, 0.5 * (1.0 - x * x) * cy, 0.0];
                } else {
                    let fx = 1.0 + cx * x;
                    s.n[a] = 0.5 * fx * (1.0 - y * y);
                    s.dn[a] = [0.5 * cx * (1.0 - y * y), -y * fx, 0.0];
                }
            }
        }
        CellKind::Tet4 => {
            s.n[..4].copy_from_slice(&[1.0 - x - y - z, x, y, z]);
            s.dn[..4].copy_from_slice(&[
                [-1.0, -1.0, -1.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ]);
        }
        CellKind::Hex8 => {
            for (a, c) in reference_corners(kind).iter().enumerate() {
                let (fx, fy, fz) = (1.0 + c[0] * x, 1.0 + c[1] * y, 1.0 + c[2] * z);
                s.n[a] = 0.125 * fx * fy * fz;
                s.dn[a] = [
                    0.125 * c[0] * fy * fz,
                    0.125 * c[1] * fx * fz,
                    0.125 * c[2] * fx * fy,
                ];
            }
        }
        CellKind::Tet10 => quadratic_solids::tet10(xi, &mut s.n, &mut s.dn),
        CellKind::Hex20 => quadratic_solids::hex20(xi, &mut s.n, &mut s.dn),
    }
    s
}

/// Shape values, physical gradients `∇_x N_a` (in `dn`), `det J` and the
/// physical point `x(ξ)` of `cell` at the reference point `xi`.
fn point_geometry(
    mesh: &Mesh,
    cell: usize,
    xi: [f64; 3],
) -> Result<(Shape, f64, [f64; 3]), FemError> {
    let c = &mesh.cells[cell];
    let mut s = shape(c.kind, xi);
    let dim = c.kind.dim();
    let mut j = Matrix3::<f64>::zeros();
    let mut x = [0.0; 3];
    for a in 0..s.len {
        let p = mesh.coords[c.nodes[a]];
        for r in 0..dim {
            for (col, pc) in p.iter().enumerate().take(dim) {
                j[(r, col)] += s.dn[a][r] * pc;
            }
        }
        for (xk, pk) in x.iter_mut().zip(p) {
            *xk += s.n[a] * pk;
        }
    }
    if dim == 2 {
        j[(2, 2)] = 1.0;
    }
    let det = j.determinant();
    if det.is_nan() || det <= 0.0 {
        return Err(FemError::BadJacobian { cell, det });
    }
    let inv = j.try_inverse().ok_or(FemError::BadJacobian { cell, det })?;
    for a in 0..s.len {
        let g = inv * nalgebra::Vector3::from(s.dn[a]);
        s.dn[a] = [g[0], g[1], g[2]];
    }
    Ok((s, det, x))
}

/// The physical gradients `∇φ_a` of the nodes of 3D `cell` at the quadrature
/// point `q` (the first `kind.nodes()` entries) and the weight `q.w · det J`.
pub(crate) fn solid_gradients(
    mesh: &Mesh,
    cell: usize,
    q: &QuadPoint,
) -> Result<([[f64; 3]; MAX_NODES], f64), FemError> {
    let (s, det, _) = point_geometry(mesh, cell, q.xi)?;
    Ok((s.dn, q.w * det))
}

/// Fills `b` (`n_strain × dim·n`, zeroed here) with the strain–displacement
/// matrix of `cell` at the quadrature point `q` and returns the quadrature
/// weight `q.w · det J` (`· 2π r` in axisymmetry).
pub(crate) fn fill_b(
    mesh: &Mesh,
    cell: usize,
    model: Model,
    q: &QuadPoint,
    b: &mut DMatrix<f64>,
) -> Result<f64, FemError> {
    let (s, det, x) = point_geometry(mesh, cell, q.xi)?;
    b.fill(0.0);
    let mut w = q.w * det;
    match model {
        Model::PlaneStrain | Model::PlaneStress => {
            for a in 0..s.len {
                let [gx, gy, _] = s.dn[a];
                b[(0, 2 * a)] = gx;
                b[(1, 2 * a + 1)] = gy;
                b[(2, 2 * a)] = gy;
                b[(2, 2 * a + 1)] = gx;
            }
        }
        Model::Axisymmetric => {
            let r = x[0];
            if r.is_nan() || r <= 0.0 {
                return Err(FemError::PointOnAxis { cell, r });
            }
            w *= 2.0 * PI * r;
            for a in 0..s.len {
                let [gr, gz, _] = s.dn[a];
                b[(0, 2 * a)] = gr;
                b[(1, 2 * a + 1)] = gz;
                b[(2, 2 * a)] = s.n[a] / r;
                b[(3, 2 * a)] = gz;
                b[(3, 2 * a + 1)] = gr;
            }
        }
        Model::Solid => {
            for a in 0..s.len {
                let [gx, gy, gz] = s.dn[a];
                let c = 3 * a;
                b[(0, c)] = gx;
                b[(1, c + 1)] = gy;
                b[(2, c + 2)] = gz;
                b[(3, c)] = gy;
                b[(3, c + 1)] = gx;
                b[(4, c + 1)] = gz;
                b[(4, c + 2)] = gy;
                b[(5, c)] = gz;
                b[(5, c + 2)] = gx;
            }
        }
    }
    Ok(w)
}

/// A cell whose kind has the model's dimension.
pub(crate) fn check_kind(mesh: &Mesh, cell: usize, model: Model) -> Result<(), FemError> {
    let kind = mesh.cells[cell].kind;
    if kind.dim() != model.dim() {
        return Err(FemError::Unsupported(format!(
            "cell {cell} is a {} cell; the {} model takes {}D cells",
            kind.name(),
            model.name(),
            model.dim()
        )));
    }
    Ok(())
}

/// Strain–displacement matrix `B` (`n_strain × dim·n`, see the module docs)
/// of `cell` at the quadrature point `q`, with the quadrature weight
/// `q.w · det J(ξ)` (times `2π r(ξ)` in axisymmetry): `K_e = Σ_q weight Bᵀ D B`.
/// For `B` alone at any reference point, pass `w = 1`: the weight is then the
/// volume density `dV/dξ`.
///
/// # Errors
/// [`FemError::BadJacobian`] if `det J ≤ 0` at the point,
/// [`FemError::PointOnAxis`] if `r ≤ 0` there in axisymmetry,
/// [`FemError::Unsupported`] for a cell of the wrong dimension.
pub fn b_matrix(
    mesh: &Mesh,
    cell: usize,
    model: Model,
    q: &QuadPoint,
) -> Result<(DMatrix<f64>, f64), FemError> {
    check_kind(mesh, cell, model)?;
    let n = mesh.cells[cell].kind.nodes() * model.dim();
    let mut b = DMatrix::zeros(model.n_strain(), n);
    let w = fill_b(mesh, cell, model, q, &mut b)?;
    Ok((b, w))
}

/// Checks det J > 0 at the corners of a bilinear or trilinear cell (Quad4,
/// Hex8), where a non-convex cell folds although its quadrature points may
/// not show it; the other kinds have their Jacobian checked at their
/// quadrature points.
pub(crate) fn check_corner_jacobians(mesh: &Mesh, cell: usize) -> Result<(), FemError> {
    let kind = mesh.cells[cell].kind;
    if matches!(kind, CellKind::Quad4 | CellKind::Hex8) {
        for xi in reference_corners(kind) {
            point_geometry(mesh, cell, *xi)?;
        }
    }
    Ok(())
}
