//! Sparse assembly of the global stiffness `K = Σ_e A_eᵀ K_e A_e` (§3.1.3 of the
//! notes: `[K][u] = [F]`), with the full DOF index `node * dim + component`.

use crate::element::{check_formulation, check_mesh, formulation_d, stiffness_of};
use crate::{Elasticity, FemError};
use faer::sparse::{SparseColMat, Triplet};
use faer::Par;
use nalgebra::DMatrix;
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
    let cap: usize = mesh
        .cells
        .iter()
        .map(|c| (c.nodes.len() * dim).pow(2))
        .sum();
    let mut t = Vec::with_capacity(cap);
    let mut dofs = Vec::new();
    for_each_element_matrix(mesh, mat, Par::Seq, |c, ke| {
        dofs.clear();
        dofs.extend(
            mesh.cells[c]
                .nodes
                .iter()
                .flat_map(|&n| (0..dim).map(move |k| n * dim + k)),
        );
        for (j, &gj) in dofs.iter().enumerate() {
            for (i, &gi) in dofs.iter().enumerate() {
                t.push(Triplet::new(gi, gj, ke[(i, j)]));
            }
        }
    })?;
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
/// displacement or B-bar, is the material's), on one thread.
pub fn try_assemble_stiffness(
    mesh: &Mesh,
    mat: &Elasticity,
) -> Result<SparseColMat<usize, f64>, FemError> {
    try_assemble_stiffness_par(mesh, mat, Par::Seq)
}

/// [`try_assemble_stiffness`] with the element matrices integrated on the
/// threads of `par` ([`for_each_element_matrix`]); they are added in the
/// cells' order, so K is the same to the last bit whatever `par` is.
pub fn try_assemble_stiffness_par(
    mesh: &Mesh,
    mat: &Elasticity,
    par: Par,
) -> Result<SparseColMat<usize, f64>, FemError> {
    check_mesh(mesh, mat.model)?;
    check_formulation(mesh, mat)?;
    let dim = mesh.dim;
    let pattern = NodePattern::of(mesh);
    let (col_ptr, row_idx) = pattern.dof_pattern(dim);
    let mut values = vec![0.0; row_idx.len()];
    for_each_element_matrix(mesh, mat, par, |c, ke| {
        let cell = &mesh.cells[c];
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
    })?;
    let n = mesh.n_nodes() * dim;
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    Ok(SparseColMat::new(symbolic, values))
}

/// Cells integrated by one thread before the element matrices are added:
/// a batch of Hex8 matrices is 256 × 4.6 KB.
const CELLS_PER_BATCH: usize = 256;

/// Calls `add(c, K_c)` for every cell c in order, the element matrices
/// integrated side by side on the `par.degree()` threads, a batch of
/// [`CELLS_PER_BATCH`] cells each, while `add` runs on the calling thread
/// between batches. The first bad cell (in the cells' order) is the error.
fn for_each_element_matrix(
    mesh: &Mesh,
    mat: &Elasticity,
    par: Par,
    mut add: impl FnMut(usize, &DMatrix<f64>),
) -> Result<(), FemError> {
    let d = formulation_d(mat);
    let threads = par.degree().max(1);
    let integrate = |cells: &std::ops::Range<usize>| -> Result<Vec<DMatrix<f64>>, FemError> {
        cells
            .clone()
            .map(|c| stiffness_of(mesh, c, mat, &d))
            .collect()
    };
    let n = mesh.cells.len();
    let mut start = 0;
    while start < n {
        let ranges: Vec<_> = (0..threads)
            .map(|t| {
                let a = (start + t * CELLS_PER_BATCH).min(n);
                a..(a + CELLS_PER_BATCH).min(n)
            })
            .collect();
        let batches: Vec<_> = if threads == 1 || ranges[1].is_empty() {
            vec![integrate(&ranges[0])]
        } else {
            std::thread::scope(|s| {
                let others: Vec<_> = (ranges[1..].iter())
                    .map(|r| s.spawn(|| integrate(r)))
                    .collect();
                let first = integrate(&ranges[0]);
                std::iter::once(first)
                    .chain(others.into_iter().map(|h| {
                        h.join()
                            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
                    }))
                    .collect()
            })
        };
        for (range, batch) in ranges.into_iter().zip(batches) {
            for (c, ke) in range.zip(batch?.iter()) {
                add(c, ke);
            }
        }
        start = (start + threads * CELLS_PER_BATCH).min(n);
    }
    Ok(())
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
