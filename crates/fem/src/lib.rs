//! Linear elastic finite elements and their sparse assembly (course notes
//! §3.1.1, "Discrétisation éléments finis": `u = Σ φ_i u_i`, and §3.1.3: the
//! discrete energy `½ uᵀ K u − uᵀ F` gives `K u = F`).
//!
//! Conventions (docs/theory/contact-problem.md): small strain, linear elastic, isotropic (E, ν);
//! any consistent set of units. Models ([`Model`]): 2D plane strain and plane
//! stress (thickness 1), axisymmetric (`x = r ≥ 0`, `y = z`, every integral
//! weighted by `2π r`: stiffness, forces and measures of the full 360° ring),
//! and 3D solids. Cells: T3, Q4, T6, Q8 in 2D, Tet4, Hex8, Tet10 and Hex20 in 3D
//! ([`element`]). Near-incompressible bodies (ν → ½) can use the
//! mean-dilatation B-bar formulation on Q4 and Hex8 ([`Formulation`],
//! [`bbar`]; Hughes 1980).
//!
//! DOF numbering: the full DOF index of component `k` of node `n` is
//! `n * dim + k` (`dim = mesh.dim`; in axisymmetry `k = 0` is `u_r`, `k = 1`
//! is `u_z`). Voigt orders, with engineering shear strains `γ_ij = 2 ε_ij`:
//! plane `[xx, yy, xy]`, axisymmetric `[rr, zz, θθ, rz]`, solid
//! `[xx, yy, zz, xy, yz, xz]`. Recovered stresses ([`cell_stress`]) are always
//! full 3D `[xx, yy, zz, xy, yz, xz]` (axisymmetric: `[rr, zz, θθ, rz, 0, 0]`).
//!
//! The fem crate owns elements, their stiffness and loads; it must not know
//! contact, the scene format or MPI.

pub mod assembly;
pub mod bbar;
pub mod elasticity;
pub mod element;
pub mod isoparametric;
pub mod loads;
pub mod quadratic_solids;
pub mod quadrature;
mod solid_stiffness;
pub mod stress;

pub use assembly::{
    assemble_stiffness, stiffness_triplets, try_assemble_stiffness, try_assemble_stiffness_par,
    try_stiffness_triplets,
};
pub use bbar::{b_bar_matrix, d_matrix_bbar};
pub use elasticity::{check_material, Elasticity, Formulation, Model};
pub use element::{check_formulation, check_mesh, element_stiffness, try_element_stiffness};
pub use isoparametric::b_matrix;
pub use loads::{
    nodal_area_vectors, rigid_body_modes, surface_measure, traction_load, tributary_measure,
};
pub use quadrature::{quadrature, QuadPoint};
pub use stress::{cell_stress, von_mises};

/// Errors of the finite element layer.
#[derive(Debug, thiserror::Error)]
pub enum FemError {
    #[error("invalid material: {0}")]
    Material(String),
    #[error("cell {cell} has a non-positive Jacobian determinant {det:e} (nodes not counter-clockwise / not positively oriented, or the element is degenerate or folded)")]
    BadJacobian { cell: usize, det: f64 },
    #[error("node {node} lies at x = r = {r:e} < 0; an axisymmetric mesh lies in the half-plane x = r ≥ 0 (x is the radius, y the axis)")]
    NegativeRadius { node: usize, r: f64 },
    #[error("cell {cell} has a quadrature point at r = {r:e} ≤ 0; the axisymmetric hoop strain u_r / r needs r > 0 inside every cell")]
    PointOnAxis { cell: usize, r: f64 },
    #[error("unsupported mesh: {0}")]
    Unsupported(String),
    #[error("sparse assembly failed: {0}")]
    Assembly(String),
}

#[cfg(test)]
mod tests;
