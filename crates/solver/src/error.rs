//! What went wrong in a run, and the contact algorithms' and the transport's
//! errors told in the words of the scene.

use serde::{Deserialize, Serialize};
use signorini_contact::ContactError;

/// What went wrong, with the exit code it maps to.
#[derive(Debug, Clone, thiserror::Error, Serialize, Deserialize)]
pub enum SolveError {
    /// Bad input: exit 1, nothing written.
    #[error("{0}")]
    Input(String),
    /// A bug or an unexpected numerical failure: exit 3.
    #[error("internal error: {0}")]
    Internal(String),
}

pub(crate) fn contact_error(e: ContactError) -> SolveError {
    match e {
        ContactError::Singular(m) => SolveError::Input(format!(
            "the contact problem is singular: {m}; a body held only by contact needs contacts that can hold every rigid motion its supports leave free"
        )),
        e @ ContactError::SingularInterface { .. } => SolveError::Input(format!(
            "{e}; a body held only by contact needs contacts that can hold every rigid motion its supports leave free"
        )),
        e @ ContactError::KernelMismatch { .. } => SolveError::Input(format!(
            "{e}: the condensation lost the body's rigid motions to round-off. S = K_ΓΓ − K_ΓI K_II⁻¹ K_IΓ is the difference of far larger stiffnesses when a body is very thin or its elements very flat (a plate one element thick, aspect ratio 1e5 or more); solver.path = \"direct\" factorises the whole stiffness and does not condense"
        )),
        other => SolveError::Internal(other.to_string()),
    }
}

pub(crate) fn wire<T>(r: Result<T, String>) -> Result<T, SolveError> {
    r.map_err(SolveError::Internal)
}
