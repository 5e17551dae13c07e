//! Isoparametric elements and their stiffness matrices (course notes §3.1.1,
//! "Discrétisation éléments finis": `u = Σ_a φ_a u_a = [φ]ᵗ[u]`, eq. 14):
//!
//! ```text
//! K_e = ∫_e Bᵀ D B dV  ≈  Σ_g w_g Bᵀ(ξ_g) D B(ξ_g) det J(ξ_g) · (2π r(ξ_g) if axisymmetric)
//! ```
//!
//! with `dV = dA` (thickness 1) in plane strain and plane stress, `dV = 2π r dA`
//! in axisymmetry (the full ring), and `dV` the volume element in 3D.
//!
//! The reference cells and B are in [`crate::isoparametric`], the quadrature
//! rules in [`crate::quadrature`].

use crate::isoparametric::{check_corner_jacobians, check_kind, fill_b};
use crate::quadrature::quadrature;
use crate::solid_stiffness::{isotropic_lame, isotropic_solid_stiffness};
use crate::{bbar, Elasticity, FemError, Formulation, Model};
use nalgebra::DMatrix;
use signorini_mesh::Mesh;

/// Element stiffness with a given Hooke matrix `d` of `model` (assembly
/// computes `D` once).
pub(crate) fn stiffness_with(
    mesh: &Mesh,
    cell: usize,
    model: Model,
    d: &DMatrix<f64>,
) -> Result<DMatrix<f64>, FemError> {
    check_kind(mesh, cell, model)?;
    if model == Model::Solid {
        if let Some((lambda, mu)) = isotropic_lame(d) {
            return isotropic_solid_stiffness(mesh, cell, lambda, mu);
        }
    }
    let kind = mesh.cells[cell].kind;
    let n = kind.nodes() * model.dim();
    let mut k = DMatrix::zeros(n, n);
    let mut b = DMatrix::zeros(model.n_strain(), n);
    let mut db = DMatrix::zeros(model.n_strain(), n);
    for q in quadrature(kind, model) {
        let w = fill_b(mesh, cell, model, q, &mut b)?;
        db.gemm(1.0, d, &b, 0.0);
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

/// The Hooke matrix the material's formulation integrates with:
/// [`Elasticity::d_matrix`], or [`crate::bbar::d_matrix_bbar`] for B-bar.
pub(crate) fn formulation_d(mat: &Elasticity) -> DMatrix<f64> {
    match mat.formulation {
        Formulation::Displacement => mat.d_matrix(),
        Formulation::BBar => bbar::d_matrix_bbar(mat),
    }
}

/// Element stiffness of the material's formulation, with `d` =
/// [`formulation_d`] (assembly computes it once).
pub(crate) fn stiffness_of(
    mesh: &Mesh,
    cell: usize,
    mat: &Elasticity,
    d: &DMatrix<f64>,
) -> Result<DMatrix<f64>, FemError> {
    match mat.formulation {
        Formulation::Displacement => stiffness_with(mesh, cell, mat.model, d),
        Formulation::BBar => bbar::stiffness_bbar(mesh, cell, mat.model, d),
    }
}

/// Element stiffness `K_e = ∫_e Bᵀ D B dV` by the cell's [`quadrature`] rule,
/// `(dim·n) × (dim·n)` with `n` the number of nodes of the cell, DOFs node by
/// node (thickness 1 in the plane models, the full 360° ring in
/// axisymmetry); with [`Formulation::BBar`], `∫_e B̄ᵀ D B̄ dV`
/// ([`crate::bbar`]).
///
/// # Errors
/// [`FemError::BadJacobian`] (naming the cell) if the Jacobian determinant is
/// not positive at a quadrature point, [`FemError::PointOnAxis`] if a
/// quadrature point has `r ≤ 0` in axisymmetry, [`FemError::Unsupported`] if
/// the cell's dimension is not the model's, or for B-bar on a cell kind or
/// model that has none ([`Formulation::supports`]).
pub fn try_element_stiffness(
    mesh: &Mesh,
    cell: usize,
    mat: &Elasticity,
) -> Result<DMatrix<f64>, FemError> {
    stiffness_of(mesh, cell, mat, &formulation_d(mat))
}

/// Checks that the material's [`Formulation`] applies to every cell of
/// `mesh` (and [`Elasticity::check`]): B-bar takes Quad4 cells in plane
/// strain and axisymmetry and Hex8 cells in 3D only.
///
/// # Errors
/// [`FemError::Unsupported`] naming the first cell of another kind, or the
/// plane stress model; [`FemError::Material`] for a bad material.
pub fn check_formulation(mesh: &Mesh, mat: &Elasticity) -> Result<(), FemError> {
    mat.check()?;
    if let Some((c, cell)) = mesh
        .cells
        .iter()
        .enumerate()
        .find(|(_, cell)| !mat.formulation.supports(cell.kind, mat.model))
    {
        return Err(bbar::unsupported(c, cell.kind.name(), mat.model));
    }
    Ok(())
}

/// [`try_element_stiffness`] for a valid cell.
///
/// # Panics
/// On any error of [`try_element_stiffness`] (see [`check_mesh`]).
pub fn element_stiffness(mesh: &Mesh, cell: usize, mat: &Elasticity) -> DMatrix<f64> {
    try_element_stiffness(mesh, cell, mat).unwrap_or_else(|e| panic!("{e}"))
}

/// Checks that every cell can be integrated in `model`:
///
/// * the mesh dimension is the model's (2 for the plane and axisymmetric
///   models, 3 for solids), every cell has that dimension, its number of
///   nodes, and node indices inside the mesh;
/// * axisymmetry: no node has `x = r < 0` beyond round-off (`−10⁻¹²` times
///   the mesh size); nodes on the axis are fine;
/// * a positive Jacobian determinant at the corners of Q4 and Hex8 cells
///   (for Q4 this is equivalent to a strictly convex counter-clockwise
///   quadrilateral) and at every quadrature point of every cell (constant
///   for T3 and Tet4: a positive area or volume), with `r > 0` at every
///   quadrature point in axisymmetry.
///
/// # Errors
/// [`FemError::Unsupported`] for a dimension or node-count mismatch,
/// [`FemError::NegativeRadius`] naming the node, [`FemError::BadJacobian`] or
/// [`FemError::PointOnAxis`] naming the first bad cell.
pub fn check_mesh(mesh: &Mesh, model: Model) -> Result<(), FemError> {
    if mesh.dim != model.dim() {
        return Err(FemError::Unsupported(format!(
            "the {} model needs a {}D mesh (the mesh is {}D)",
            model.name(),
            model.dim(),
            mesh.dim
        )));
    }
    let n_nodes = mesh.n_nodes();
    for (c, cell) in mesh.cells.iter().enumerate() {
        cell.check_node_count(c).map_err(FemError::Unsupported)?;
        if let Some(&n) = cell.nodes.iter().find(|&&n| n >= n_nodes) {
            return Err(FemError::Unsupported(format!(
                "cell {c} refers to node {n}; the mesh has {n_nodes} nodes"
            )));
        }
        check_kind(mesh, c, model)?;
    }
    if model == Model::Axisymmetric {
        let tol = 1e-12 * mesh.size();
        if let Some((node, p)) = mesh
            .coords
            .iter()
            .enumerate()
            .find(|(_, p)| p[0] < -tol || p[0].is_nan())
        {
            return Err(FemError::NegativeRadius { node, r: p[0] });
        }
    }
    let d = model.n_strain();
    for (c, cell) in mesh.cells.iter().enumerate() {
        let kind = cell.kind;
        check_corner_jacobians(mesh, c)?;
        let mut b = DMatrix::zeros(d, kind.nodes() * model.dim());
        for q in quadrature(kind, model) {
            fill_b(mesh, c, model, q, &mut b)?;
        }
    }
    Ok(())
}
