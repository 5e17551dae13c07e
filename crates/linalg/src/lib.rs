//! The linear algebra of the contact solver, on faer alone: one pivot (rank)
//! policy and the checked solve that applies it (`pivot_policy`), the dense
//! factors and their updates (the active-block Cholesky `active_factor`, the
//! bordered and recursive Cholesky, the growing LU), and the one way loops
//! share the cores (`threads`). It knows nothing of contact, meshes or MPI.

pub mod active_factor;
pub mod bordered_factor;
pub mod growing_lu;
pub mod pivot_policy;
pub mod recursive_cholesky;
pub mod reduced;
pub mod sparse;
pub mod threads;

/// A factorisation or solve that the pivot policy rejects.
#[derive(Debug, thiserror::Error)]
pub enum LinalgError {
    /// The matrix is (numerically) singular; the message names it and its
    /// rank deficiency.
    #[error("singular matrix: {0}")]
    Singular(String),
}
