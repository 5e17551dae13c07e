//! Linear elastic finite elements on 2D meshes and their sparse assembly
//! (course notes §3.1.1, "Discrétisation éléments finis": `u = Σ φ_i u_i`, and
//! §3.1.3: the discrete energy `½ uᵀ K u − uᵀ F` gives `K u = F`).
//!
//! Conventions (DESIGN.md §3): small strain, linear elastic, isotropic (E, ν);
//! 2D plane strain or plane stress, thickness 1; any consistent set of units.
//! DOF numbering: the full DOF index of component `k` of node `n` is
//! `n * dim + k` (`dim = mesh.dim`, 2 for now). Voigt order
//! `[xx, yy, xy]` with the engineering shear strain `γ_xy = 2 ε_xy`.

pub mod assembly;
pub mod elasticity;
pub mod element;
pub mod loads;
pub mod stress;

pub use assembly::{assemble_stiffness, stiffness_triplets, try_assemble_stiffness};
pub use elasticity::{check_material, Elasticity, Model};
pub use element::{check_mesh, element_stiffness, try_element_stiffness};
pub use loads::{rigid_body_modes, surface_measure, traction_load, tributary_measure};
pub use stress::{cell_stress, von_mises};

/// Errors of the finite element layer.
#[derive(Debug, thiserror::Error)]
pub enum FemError {
    #[error("invalid material: {0}")]
    Material(String),
    #[error("cell {cell} has a non-positive Jacobian determinant {det:e} (nodes not counter-clockwise, or the element is degenerate or folded)")]
    BadJacobian { cell: usize, det: f64 },
    #[error("unsupported mesh: {0}")]
    Unsupported(String),
    #[error("sparse assembly failed: {0}")]
    Assembly(String),
}

pub use assembly::try_stiffness_triplets;

#[cfg(test)]
mod tests;
