//! Sparse assembly of the global stiffness `K = Σ_e A_eᵀ K_e A_e` (§3.1.3 of the
//! notes: `[K][u] = [F]`), with the full DOF index `node * dim + component`.

use crate::element::{check_formulation, check_mesh, formulation_d, stiffness_of};
use crate::{Elasticity, FemError};
use faer::sparse::{SparseColMat, Triplet};
use signorini_mesh::Mesh;

/// Every entry of every element matrix as a `(row, col, value)` triplet in
/// global DOF numbering (both triangles, zeros included so the pattern depends
/// on the mesh only); duplicates are meant to be summed.
///
/// # Panics
/// On a cell that cannot be integrated (see [`check_mesh`]).
pub fn stiffness_triplets(mesh: &Mesh, mat: &Elasticity) -> Vec<Triplet<usize, usize, f64>> {
    try_stiffness_triplets(mesh, mat).unwrap_or_else(|e| panic!("{e}"))
}

/// [`stiffness_triplets`] returning an error on a bad cell.
pub fn try_stiffness_triplets(
    mesh: &Mesh,
    mat: &Elasticity,
) -> Result<Vec<Triplet<usize, usize, f64>>, FemError> {
    let dim = mesh.dim;
    let d = formulation_d(mat);
    let cap: usize = mesh
        .cells
        .iter()
        .map(|c| (c.nodes.len() * dim).pow(2))
        .sum();
    let mut t = Vec::with_capacity(cap);
    let mut dofs = Vec::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        let ke = stiffness_of(mesh, c, mat, &d)?;
        dofs.clear();
        dofs.extend(
            cell.nodes
                .iter()
                .flat_map(|&n| (0..dim).map(move |k| n * dim + k)),
        );
        for (j, &gj) in dofs.iter().enumerate() {
            for (i, &gi) in dofs.iter().enumerate() {
                t.push(Triplet::new(gi, gj, ke[(i, j)]));
            }
        }
    }
    Ok(t)
}

/// The global stiffness `K`, `n_dof × n_dof` (`n_dof = n_nodes · dim`), both
/// triangles stored, duplicates summed.
///
/// # Panics
/// On a bad cell (use [`try_assemble_stiffness`] for an error instead).
pub fn assemble_stiffness(mesh: &Mesh, mat: &Elasticity) -> SparseColMat<usize, f64> {
    try_assemble_stiffness(mesh, mat).unwrap_or_else(|e| panic!("{e}"))
}

/// [`assemble_stiffness`] after [`check_mesh`] (in the material's model),
/// the material check and [`check_formulation`] (the element formulation,
/// displacement or B-bar, is the material's).
pub fn try_assemble_stiffness(
    mesh: &Mesh,
    mat: &Elasticity,
) -> Result<SparseColMat<usize, f64>, FemError> {
    check_mesh(mesh, mat.model)?;
    check_formulation(mesh, mat)?;
    let n = mesh.n_nodes() * mesh.dim;
    let t = try_stiffness_triplets(mesh, mat)?;
    SparseColMat::try_new_from_triplets(n, n, &t).map_err(|e| FemError::Assembly(format!("{e:?}")))
}
