//! Contact: the algorithms that solve the contact problem, on the condensed
//! problem (Delassus operator) or on the whole sparse stiffness (direct
//! path). The contact points, normals, gaps and rows of B are the geometry
//! crate's (`signorini-geometry`).
//!
//! Conventions (docs/theory/contact-problem.md): the normal n points from master to slave; the
//! gap is g = g0 + B u with B the row operator n·(u_slave − u_master
//! interpolated); non-penetration g ≥ 0; the contact force λ ≥ 0 is the
//! compressive normal force on the slave (the course notes' F_n = −λ ≤ 0, §2.1);
//! complementarity λ g = 0.
//!
//! The contact crate owns the algebra on W, q (G, e); it must not know the
//! contact geometry, the scene format, MPI, the command line or
//! finite-element systems (the direct path's KKT solve lives in the solver).

pub mod active_set;
pub mod contact_elements;
pub mod delassus;
pub mod equilibrium;
pub mod friction;
pub mod law;
pub mod lcp;
pub mod norms;
pub mod observe;
pub mod options;
mod problem_scale;
mod reduced;
pub mod registry;
pub mod solution;

#[cfg(test)]
pub(crate) mod test_problems;

pub use active_set::signorini::{status_method, ActiveSetSolve, StatusOptions, StatusVariant};
pub use delassus::{DelassusOperator, DelassusProblem};

#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    #[error("{0}")]
    Geometry(String),
    #[error("the contact problem is singular: {0}")]
    Singular(String),
    /// The interface stiffness S is not positive definite beyond the rigid
    /// modes it was given: the factorisation failed at the Γ DOF `dof`.
    #[error("the contact problem is singular: the interface stiffness S is not positive definite beyond the rigid modes of the floating bodies (at interface DOF {dof}): a body is free to move in a way its supports do not prevent")]
    SingularInterface { dof: usize },
    /// The rigid modes that the supports leave free are not in the kernel
    /// of the interface stiffness S: ‖S r‖ = `residual` against the largest
    /// diagonal entry `stiffness` of S.
    #[error("the rigid modes left free by the supports are not in the kernel of the interface stiffness S (‖S r‖ = {residual:.2e} against a stiffness {stiffness:.2e})")]
    KernelMismatch { residual: f64, stiffness: f64 },
    #[error("linear solve failed: {0}")]
    Solve(String),
}

impl From<signorini_linalg::LinalgError> for ContactError {
    fn from(e: signorini_linalg::LinalgError) -> Self {
        match e {
            signorini_linalg::LinalgError::Singular(what) => ContactError::Singular(what),
            signorini_linalg::LinalgError::NotPositiveDefinite { index } => {
                ContactError::SingularInterface { dof: index }
            }
            signorini_linalg::LinalgError::NotKernel { residual, scale } => {
                ContactError::KernelMismatch {
                    residual,
                    stiffness: scale,
                }
            }
        }
    }
}
pub use lcp::{lcp_residual, LcpOptions};
pub use solution::{
    ContactSolution, FrictionTrace, SolverReport, StatusTrace, StopReason, ThresholdMapKind,
};
