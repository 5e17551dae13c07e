//! The linear algebra of the contact solver, on faer alone: one pivot (rank)
//! policy and the checked solve that applies it (`pivot_policy`), the dense
//! factors and their updates (the active-block Cholesky `active_factor`, the
//! bordered and recursive Cholesky, the growing LU, the solves with a
//! row-permuted Cholesky factor `ordered_cholesky`), the reduced linear
//! system of a status iteration (`reduced`), the Hager–Higham condition
//! estimator (`conditioning`), sparse rows (`sparse`) and the one way loops
//! share the cores (`threads`). It knows nothing of contact, meshes or MPI.

pub mod active_factor;
pub mod bordered_factor;
pub mod capacitance;
pub mod conditioning;
pub mod growing_lu;
pub mod ordered_cholesky;
pub mod pivot_policy;
pub mod products;
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
    /// A symmetric matrix meant to be positive definite (beyond a given
    /// kernel) has a pivot that is not positive at row `index`.
    #[error("the matrix is not positive definite (pivot at row {index})")]
    NotPositiveDefinite { index: usize },
    /// The given kernel R is not in the kernel of the matrix A: ‖A r‖ =
    /// `residual` against its largest diagonal entry `scale`.
    #[error("the given kernel is not the matrix's (‖A r‖ = {residual:.2e} against {scale:.2e})")]
    NotKernel { residual: f64, scale: f64 },
}

/// A generalised inverse A⁺ of a symmetric positive semi-definite matrix A
/// (A A⁺ A = A), held as a factor: the interface stiffness's, which the
/// Delassus operator applies.
pub trait GeneralisedInverse: Send + Sync {
    /// A⁺ v.
    fn solve(&self, v: &[f64]) -> Vec<f64>;
}
