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
mod contact_rows;
mod direct_balance;
mod direct_forcing;
mod direct_friction;
mod direct_newton;
mod direct_path;
mod direct_system;
mod element_step;
mod error;
pub mod fill_model;
mod fixed_pattern;
mod friction_step;
mod gmres;
mod interface_problem;
mod kkt;
pub mod memory;
pub mod model;
mod options;
mod partition;
pub mod path_choice;
mod pieces;
mod pipeline;
mod plan;
mod pressure;
pub mod progress;
mod reactions;
mod root;
mod run_context;
mod sparse_lu;
mod step;
mod step_end;
mod step_friction;
pub mod subdomain;
pub(crate) mod symmetric_part;
mod ties;
pub mod timing;

pub use signorini_report::results::{BodyResult, RunOutput, StepFields};
pub use signorini_report::stream::{FieldWriter, StepResults, StepSink, StepsInMemory};

pub use error::SolveError;
pub use options::{RunEnvironment, RunOptions};
pub use pipeline::{run, run_streamed, run_with};
pub use plan::{algorithm_of, check_options, check_plan, choose_path};

pub use checks::PENETRATION_WARNING_FRACTION;
