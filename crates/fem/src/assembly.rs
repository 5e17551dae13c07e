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
    let dim = mesh.dim;
    let d = formulation_d(mat);
    let pattern = NodePattern::of(mesh);
    let (col_ptr, row_idx) = pattern.dof_pattern(dim);
    let mut values = vec![0.0; row_idx.len()];
    for (c, cell) in mesh.cells.iter().enumerate() {
        let ke = stiffness_of(mesh, c, mat, &d)?;
        for (b, &nb) in cell.nodes.iter().enumerate() {
            for (a, &na) in cell.nodes.iter().enumerate() {
                let at = pattern.position(nb, na);
                for k in 0..dim {
                    let base = col_ptr[nb * dim + k] + at * dim;
                    for l in 0..dim {
                        values[base + l] += ke[(a * dim + l, b * dim + k)];
                    }
                }
            }
        }
    }
    let n = mesh.n_nodes() * dim;
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    Ok(SparseColMat::new(symbolic, values))
}

/// The node graph of a mesh: for each node, the sorted nodes it shares a
/// cell with (itself included). K's pattern is this graph with each node
/// expanded to its `dim` DOFs, so the assembly adds every element matrix
/// into place instead of sorting its triplets.
struct NodePattern {
    start: Vec<usize>,
    neighbours: Vec<usize>,
}

impl NodePattern {
    fn of(mesh: &Mesh) -> Self {
        let mut lists: Vec<Vec<usize>> = vec![Vec::new(); mesh.n_nodes()];
        for cell in &mesh.cells {
            for &a in &cell.nodes {
                lists[a].extend_from_slice(&cell.nodes);
            }
        }
        let mut start = Vec::with_capacity(lists.len() + 1);
        let mut neighbours = Vec::new();
        start.push(0);
        for (n, mut l) in lists.into_iter().enumerate() {
            l.push(n);
            l.sort_unstable();
            l.dedup();
            neighbours.extend_from_slice(&l);
            start.push(neighbours.len());
        }
        Self { start, neighbours }
    }

    /// The position of node `m` among the neighbours of node `n`.
    fn position(&self, n: usize, m: usize) -> usize {
        let list = &self.neighbours[self.start[n]..self.start[n + 1]];
        list.binary_search(&m)
            .expect("the nodes of a cell are neighbours of each other")
    }

    /// Column pointers and sorted row indices of the DOF matrix.
    fn dof_pattern(&self, dim: usize) -> (Vec<usize>, Vec<usize>) {
        let nodes = self.start.len() - 1;
        let mut col_ptr = Vec::with_capacity(nodes * dim + 1);
        let mut row_idx = Vec::with_capacity(self.neighbours.len() * dim * dim);
        col_ptr.push(0);
        for n in 0..nodes {
            let list = &self.neighbours[self.start[n]..self.start[n + 1]];
            for _ in 0..dim {
                for &m in list {
                    row_idx.extend((0..dim).map(|l| m * dim + l));
                }
                col_ptr.push(row_idx.len());
            }
        }
        (col_ptr, row_idx)
    }
}
