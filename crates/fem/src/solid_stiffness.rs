//! The isotropic solid's element stiffness by node blocks: with `g_a = ∇φ_a`
//! at a quadrature point and Lamé's λ, μ, the 3 × 3 block of `Bᵀ D B` that
//! couples node `a` (row) with node `b` (column) is
//!
//! ```text
//! K_ab = Σ_g w_g [ λ g_a g_bᵀ + μ g_b g_aᵀ + μ (g_a · g_b) I₃ ]
//! ```
//!
//! (course notes §3.1.1, eq. 14, with the isotropic Hooke matrix written out),
//! the same `K_e = ∫_e Bᵀ D B dV` as [`crate::element`]'s product of the 6 × 3n
//! `B` without its zeros: about 12 multiplications per node pair and point
//! instead of the 6 × 3n × 3n of the dense product, which dominated the
//! assembly of second-order solids (Hex20: 27 points, 60 × 60). Only the
//! blocks `b ≥ a` are summed; the lower triangle is the upper's transpose, so
//! `K_e` is exactly symmetric.

use crate::isoparametric::solid_gradients;
use crate::quadrature::quadrature;
use crate::{FemError, Model};
use nalgebra::DMatrix;
use signorini_mesh::Mesh;

/// Lamé's λ and μ of an isotropic solid Hooke matrix `d` (Voigt order, the
/// three normal strains first), or `None` when `d` is not of that form.
pub(crate) fn isotropic_lame(d: &DMatrix<f64>) -> Option<(f64, f64)> {
    if d.nrows() != 6 || d.ncols() != 6 {
        return None;
    }
    let (lambda, mu) = (d[(0, 1)], d[(3, 3)]);
    let isotropic = (0..6).all(|i| {
        (0..6).all(|j| {
            let want = match (i < 3, j < 3) {
                (true, true) => lambda + if i == j { 2.0 * mu } else { 0.0 },
                _ if i == j => mu,
                _ => 0.0,
            };
            d[(i, j)] == want
        })
    });
    isotropic.then_some((lambda, mu))
}

/// `K_e` of 3D `cell` for Lamé's `lambda`, `mu` by the node blocks of the
/// module's formula, DOFs node by node.
///
/// # Errors
/// [`FemError::BadJacobian`] (naming the cell) if the Jacobian determinant is
/// not positive at a quadrature point.
pub(crate) fn isotropic_solid_stiffness(
    mesh: &Mesh,
    cell: usize,
    lambda: f64,
    mu: f64,
) -> Result<DMatrix<f64>, FemError> {
    let kind = mesh.cells[cell].kind;
    let nodes = kind.nodes();
    let mut k = DMatrix::zeros(3 * nodes, 3 * nodes);
    for q in quadrature(kind, Model::Solid) {
        let (g, w) = solid_gradients(mesh, cell, q)?;
        let (wl, wm) = (w * lambda, w * mu);
        for a in 0..nodes {
            let ga = g[a];
            for (b, gb) in g.iter().enumerate().take(nodes).skip(a) {
                let dot = wm * (ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2]);
                for i in 0..3 {
                    for j in 0..3 {
                        let diag = if i == j { dot } else { 0.0 };
                        k[(3 * a + i, 3 * b + j)] += wl * ga[i] * gb[j] + wm * gb[i] * ga[j] + diag;
                    }
                }
            }
        }
    }
    // the lower triangle (the diagonal blocks' too) is the upper's transpose
    for r in 0..3 * nodes {
        for c in r + 1..3 * nodes {
            k[(c, r)] = k[(r, c)];
        }
    }
    Ok(k)
}
