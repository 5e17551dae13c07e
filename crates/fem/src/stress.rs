//! Stress recovery: `σ = D B u_e` at the centre of each cell (`D B̄ u_e`
//! for the B-bar formulation, [`crate::bbar`]).

use crate::bbar::{b_bar_matrix, d_matrix_bbar, full_stress_bbar};
use crate::isoparametric::{b_matrix, reference_centre};
use crate::quadrature::QuadPoint;
use crate::{Elasticity, Formulation};
use nalgebra::DVector;
use signorini_mesh::Mesh;

/// Stress of every cell at the centre of its reference cell (T3, Tet4:
/// constant; T6 at `L_i = 1/3`; Q4, Q8, Hex8 at `ξ = 0`), as the full 3D Voigt
/// vector `[σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz]` ([`Elasticity::full_stress`]
/// of `D B u_e`):
///
/// * plane strain: `σ_zz = ν (σ_xx + σ_yy)`; plane stress: `σ_zz = 0`;
///   `σ_yz = σ_xz = 0`;
/// * axisymmetric: `[σ_rr, σ_zz, σ_θθ, σ_rz, 0, 0]`: slot xx is radial, yy
///   axial, **zz the hoop stress**, xy the rz shear;
/// * solid: all six.
///
/// With [`Formulation::BBar`] the stress is `D B̄ u_e` with the stiffness's
/// `B̄` ([`crate::bbar`]), in the same layout; in plane strain its σ_zz is
/// the zz component of `D B̄ u_e` (B̄ has an ε_zz row), which at the centre
/// of a Q4, where the dilatation is the element mean, is `ν (σ_xx + σ_yy)`.
///
/// `u` is the full displacement vector (DOF `node * dim + k`).
///
/// # Panics
/// On a cell that cannot be integrated (see [`crate::check_mesh`]) or a short `u`.
pub fn cell_stress(mesh: &Mesh, mat: &Elasticity, u: &[f64]) -> Vec<[f64; 6]> {
    let dim = mesh.dim;
    assert!(
        u.len() >= dim * mesh.n_nodes(),
        "cell_stress: u is too short"
    );
    let bbar = mat.formulation == Formulation::BBar;
    let d = if bbar {
        d_matrix_bbar(mat)
    } else {
        mat.d_matrix()
    };
    let mut ue = DVector::zeros(0);
    (0..mesh.cells.len())
        .map(|c| {
            let cell = &mesh.cells[c];
            let q = QuadPoint {
                xi: reference_centre(cell.kind),
                w: 1.0,
            };
            let (b, _) = if bbar {
                b_bar_matrix(mesh, c, mat.model, &q)
            } else {
                b_matrix(mesh, c, mat.model, &q)
            }
            .unwrap_or_else(|e| panic!("{e}"));
            ue.resize_vertically_mut(dim * cell.nodes.len(), 0.0);
            for (a, &n) in cell.nodes.iter().enumerate() {
                for k in 0..dim {
                    ue[dim * a + k] = u[dim * n + k];
                }
            }
            let s = &d * (&b * &ue);
            if bbar {
                full_stress_bbar(mat.model, s.as_slice())
            } else {
                mat.full_stress(s.as_slice())
            }
        })
        .collect()
}

/// Von Mises equivalent stress of `[σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz]`:
/// `√(½[(σ_xx−σ_yy)² + (σ_yy−σ_zz)² + (σ_zz−σ_xx)²] + 3 (σ_xy² + σ_yz² + σ_xz²))`
/// (axisymmetric stresses in the layout of [`cell_stress`] give the right
/// value: the hoop stress is a principal normal stress).
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, xz] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + xz * xz))
        .sqrt()
}
