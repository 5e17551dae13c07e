//! Stress recovery: `σ = D B u_e` at the cell centroid.

use crate::element::b_matrix;
use crate::Elasticity;
use nalgebra::DVector;
use signorini_mesh::Mesh;

/// Stress of every cell at its centroid (T3: constant; Q4: at `ξ = η = 0`),
/// `[σ_xx, σ_yy, σ_xy, σ_zz]` with `[σ_xx, σ_yy, σ_xy] = D B u_e` and
/// `σ_zz = ν (σ_xx + σ_yy)` in plane strain, 0 in plane stress. `u` is the full
/// displacement vector (DOF `node * 2 + k`).
///
/// # Panics
/// On a cell with a non-positive Jacobian, a non-2D mesh, or a short `u`.
pub fn cell_stress(mesh: &Mesh, mat: &Elasticity, u: &[f64]) -> Vec<[f64; 4]> {
    assert_eq!(mesh.dim, 2, "cell_stress: 2D meshes only");
    assert!(u.len() >= 2 * mesh.n_nodes(), "cell_stress: u is too short");
    let d = mat.d_matrix();
    (0..mesh.cells.len())
        .map(|c| {
            let (b, _) = b_matrix(mesh, c, [0.0, 0.0]).unwrap_or_else(|e| panic!("{e}"));
            let nodes = &mesh.cells[c].nodes;
            let ue = DVector::from_iterator(
                2 * nodes.len(),
                nodes.iter().flat_map(|&n| [u[2 * n], u[2 * n + 1]]),
            );
            let eps = &b * ue;
            let s = d * nalgebra::Vector3::new(eps[0], eps[1], eps[2]);
            [s[0], s[1], s[2], mat.sigma_zz(s[0], s[1])]
        })
        .collect()
}

/// Von Mises equivalent stress of `[σ_xx, σ_yy, σ_xy, σ_zz]`:
/// `√(½[(σ_xx−σ_yy)² + (σ_yy−σ_zz)² + (σ_zz−σ_xx)²] + 3 σ_xy²)`.
pub fn von_mises(s: &[f64; 4]) -> f64 {
    let [xx, yy, xy, zz] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) + 3.0 * xy * xy).sqrt()
}
