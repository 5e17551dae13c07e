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
mod step_end;
pub mod subdomain;
mod timing;

use std::sync::Arc;

use serde::{Deserialize, Serialize};
use signorini_contact::friction::PointStatus;
use signorini_contact::{ContactError, ContactSolution};
pub use signorini_report::output::{BodyResult, RunOutput, StepFields};
pub use signorini_report::stream::{FieldWriter, StepSink, StepsInMemory};
use signorini_report::{Certificate, ContactRow, Regularisation, StepReport};
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
}

impl RunEnvironment {
    /// The machine's memory ([`memory::machine_memory`]), no observer.
    pub fn machine() -> Self {
        Self {
            budget: memory::machine_memory(),
            observer: None,
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

/// One step solved on the root.
struct StepSolution {
    /// The contact problem's answer, with the report of the method that ran.
    outcome: ContactSolution,
    gap0: Vec<f64>,
    f_scale: f64,
    length_scale: f64,
    regularisation: Option<Regularisation>,
    /// Penalty stiffness of each point whose contact has a regularised law (0: unilateral).
    law_k: Vec<f64>,
    /// Friction state at the end of the step, when a contact has friction.
    friction: Option<FrictionStep>,
    /// Seconds of this step's root solve, and of building the Delassus
    /// operator when this step built it (the first step), else 0.
    solve_s: f64,
    operator_s: f64,
}

/// Friction at one step, per contact point (zeros for frictionless points).
#[derive(Clone)]
struct FrictionStep {
    statuses: Vec<PointStatus>,
    tangential: Vec<f64>,
    slip_increment: Vec<f64>,
    slip_total: Vec<f64>,
    /// Along the second tangent (3D; zeros in 2D).
    tangential2: Vec<f64>,
    slip_increment2: Vec<f64>,
    slip_total2: Vec<f64>,
    /// The threshold in force at the solution (Tresca g or μ λ_n).
    threshold: Vec<f64>,
    /// How far the tangential force lies outside its admissible set, in
    /// force (≤ 0 inside): |λ_t| − g in 2D, ‖λ_t‖ − g on the Tresca disc,
    /// μ₁ (‖(λ_t1/μ₁, λ_t2/μ₂)‖ − λ_n) on the (elliptic) Coulomb cone;
    /// with roughness, of the slider force λ_t + Q g (course notes §6).
    cone_excess: Vec<f64>,
    /// The back force Q g of a rough point (course notes §6; zero without
    /// roughness), along t1 and t2: the slider force is λ_t + Q g.
    back_force: Vec<f64>,
    back_force2: Vec<f64>,
}

impl FrictionStep {
    /// The statuses of `m` points with every force, slip, threshold and
    /// excess zero, for the step's solver to fill in.
    fn zeros(statuses: Vec<PointStatus>, m: usize) -> Self {
        FrictionStep {
            statuses,
            tangential: vec![0.0; m],
            slip_increment: vec![0.0; m],
            slip_total: vec![0.0; m],
            tangential2: vec![0.0; m],
            slip_increment2: vec![0.0; m],
            slip_total2: vec![0.0; m],
            threshold: vec![0.0; m],
            cone_excess: vec![0.0; m],
            back_force: vec![0.0; m],
            back_force2: vec![0.0; m],
        }
    }
}

/// The fraction of the local element size (tributary length) beyond which a
/// penalty penetration is warned about.
pub const PENETRATION_WARNING_FRACTION: f64 = 0.01;

/// What both paths hand to the report.
struct Partial {
    steps: Vec<StepReport>,
    certificate: Certificate,
    converged: bool,
    failure: Option<String>,
    contact_rows: Vec<ContactRow>,
    lambda: Vec<f64>,
    /// Full displacement of each body at the last step.
    u_last: Vec<Vec<f64>>,
    /// Each body's mesh, and (once the last step ended) its fields at the
    /// last step.
    bodies: Vec<BodyResult>,
    /// The lowest gap over the steps of each point left out of the contact
    /// zone (`ModelData::excluded`), for the check that none penetrates.
    excluded_gaps: Vec<f64>,
    dense_interface_bytes: u64,
    factor_bytes: u64,
    /// Ordering, size and flops of the factorisation (report.json
    /// `factorisation`).
    factorisation: Option<signorini_report::Factorisation>,
    n_gamma: usize,
    dofs: usize,
    solver: serde_json::Value,
    /// Friction at the last step.
    friction: Option<FrictionStep>,
    /// Condition estimates (report.json `conditioning`).
    conditioning: Option<signorini_report::Conditioning>,
}

/// Residual pieces of one step for the certificate.
struct Residuals {
    /// Largest equilibrium residual (interior and Γ, contact forces included).
    equilibrium: f64,
    /// Largest internal or external force entry.
    force_scale: f64,
    /// K u − f on the prescribed DOFs, as (body, DOF, value); a DOF shared
    /// by subdomains appears once per subdomain, their values to be summed.
    support: Vec<(usize, usize, f64)>,
}
