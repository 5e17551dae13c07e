//! Sparse rows over a dense numbering.

/// A sparse row over the interface DOFs: (index, coefficient).
pub type SparseRow = Vec<(usize, f64)>;
