//! The pipeline of docs/architecture.md: scene → meshes → subdomains (a body, or a
//! METIS part of one), each condensed on its interface by the rank that owns
//! it (course notes §8.2–8.3) → root: assembled interface problem, contact geometry,
//! contact algorithm → every rank recovers its interiors → report.
//!
//! The pipeline is written once against [`signorini_comm::Transport`]: in one
//! process every subdomain belongs to rank 0; under `mpirun` the subdomains are
//! dealt to the ranks (one each when the counts match, else by estimated cost).
//!
//! The direct path (`path = "direct"`) solves the same contact problem on the
//! whole sparse stiffness on the root, refactorised at each status iteration
//! (course notes §3.3), for checking and benchmarking the condensed path.
//!
//! The solver crate owns the pipeline (`pipeline.rs`: plan → model and
//! partition → condense → root → recover → certify and report) and is the only
//! one that knows the scene, the numerics and the transport together; it must
//! not know the command line.

mod certify;
mod checks;
mod compare;
mod conditioning;
pub mod contact_frames;
mod direct_path;
mod element_step;
mod friction_step;
mod interface_problem;
mod kkt;
pub mod memory;
pub mod model;
mod partition;
mod pieces;
mod pipeline;
mod plan;
pub mod progress;
mod reactions;
mod root;
mod step;
mod step_end;
pub mod subdomain;
mod timing;

use std::sync::Arc;

use serde::{Deserialize, Serialize};
use signorini_contact::ContactError;
pub use signorini_report::results::{BodyResult, RunOutput, StepFields};
pub use signorini_report::stream::{FieldWriter, StepSink, StepsInMemory};
use signorini_scene as scene;

pub use pipeline::{run, run_streamed, run_with};
pub use plan::{algorithm_of, check_options, check_plan};

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

/// Overrides from the command line.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub method: Option<scene::Method>,
    pub path: Option<scene::SolvePath>,
}

/// What the process that starts a run gives it besides the scene and the
/// options: the command line's `--max-memory` and its progress line.
#[derive(Clone, Default)]
pub struct RunEnvironment {
    /// The memory the run may use: a scene estimated above it is refused
    /// before anything is built (`None`: unknown, nothing is refused).
    pub budget: Option<memory::Budget>,
    /// Who hears of the run's progress on this rank (`None`: nobody).
    pub observer: Option<Arc<dyn progress::Observer>>,
    /// A rank that fails its condensation on purpose, for the tests of the
    /// MPI path's error handling (the command line's SIGNORINI_FAIL_RANK).
    pub fail_rank: Option<usize>,
}

impl RunEnvironment {
    /// The machine's memory ([`memory::machine_memory`]), no observer.
    pub fn machine() -> Self {
        Self {
            budget: memory::machine_memory(),
            observer: None,
            fail_rank: None,
        }
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    signorini_contact::norms::max_abs(v)
}

fn contact_error(e: ContactError) -> SolveError {
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

fn wire<T>(r: Result<T, String>) -> Result<T, SolveError> {
    r.map_err(SolveError::Internal)
}

/// The fraction of the local element size (tributary length) beyond which a
/// penalty penetration is warned about.
pub const PENETRATION_WARNING_FRACTION: f64 = 0.01;
