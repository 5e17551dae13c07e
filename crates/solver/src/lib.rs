//! The pipeline of DESIGN.md §1: scene → meshes → subdomains (a body, or a
//! METIS part of one), each condensed on its interface by the rank that owns
//! it (seed §8.2–8.3) → root: assembled interface problem, contact geometry,
//! contact algorithm → every rank recovers its interiors → report.
//!
//! The pipeline is written once against [`signorini_comm::Transport`]: in one
//! process every subdomain belongs to rank 0; under `mpirun` the subdomains are
//! dealt to the ranks (one each when the counts match, else by estimated cost).
//!
//! The direct path (`path = "direct"`) solves the same contact problem on the
//! whole sparse stiffness on the root, refactorised at each status iteration
//! (seed §3.3), for checking and benchmarking the condensed path.

pub mod bench;
mod certify;
mod checks;
mod compare;
mod conditioning;
mod direct_path;
mod friction_step;
mod kkt;
pub mod local;
pub mod model;
mod root;
pub mod stiff;
pub mod subdomain;

use std::time::Instant;

use faer::sparse::SparseColMat;
use faer::Mat;
use kkt::DirectProblem;
use serde::{Deserialize, Serialize};
use signorini_comm::{broadcast, deal, gather, Transport};
use signorini_condense::{spmv, spmv_with_magnitude, submatrix};
use signorini_contact::equilibrium::nnls;
use signorini_contact::friction::{
    coulomb_fixed_point, coulomb_status, tresca_projection, tresca_status, FrictionLayout,
    FrictionOptions, PointStatus, Threshold,
};
use signorini_contact::friction3d::{friction_3d, FrictionLayout3d, Law3d};
use signorini_contact::methods::{solve_lcp, solve_lcp_constrained, Algorithm};
use signorini_contact::{
    status_method, ActiveSetSolve, ContactError, DelassusOperator, DelassusProblem, LcpOptions,
    LcpSolution, SolverReport, StatusOptions, StatusOutcome, StatusVariant,
};
use signorini_report::{
    reference, Certificate, ContactRow, ContactSummary, Memory, Probe, RankStats, Regularisation,
    Report, StepReport, Timings,
};
use signorini_scene as scene;

use certify::*;
use checks::*;
use compare::*;
use direct_path::*;
use friction_step::*;
use model::{BodyModel, FixedPoint, PointFriction, PointModel};
use root::*;
use subdomain::{CondensedData, RecoveredData, Subdomain, SubdomainSpec};

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

/// Final fields of one body.
pub struct BodyResult {
    pub name: String,
    pub coords: Vec<[f64; 3]>,
    pub cells: Vec<Vec<usize>>,
    /// METIS part of each cell.
    pub parts: Vec<usize>,
    /// The fields at every load step (at least one).
    pub history: Vec<StepFields>,
}

impl BodyResult {
    /// The fields at the last load step.
    pub fn last(&self) -> &StepFields {
        self.history
            .last()
            .expect("a body result holds at least one step")
    }
}

/// The fields of one body at one load step.
pub struct StepFields {
    /// Displacement, `dim` values per node.
    pub displacement: Vec<f64>,
    /// Per cell: Voigt [sxx, syy, szz, sxy, syz, sxz] (axisymmetric: x = r,
    /// y = z, szz = the hoop stress); see `signorini_fem::cell_stress`. Empty
    /// unless `[output] fields` has "stress".
    pub stress: Vec<[f64; 6]>,
    /// Per cell: von Mises equivalent stress.
    pub von_mises: Vec<f64>,
}

pub struct RunOutput {
    pub report: Report,
    pub contact_rows: Vec<ContactRow>,
    pub bodies: Vec<BodyResult>,
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn contact_error(e: ContactError) -> SolveError {
    match e {
        ContactError::Singular(m) => SolveError::Input(format!(
            "the contact problem is singular: {m}; a body held only by contact needs contacts that can hold every rigid motion its supports leave free"
        )),
        other => SolveError::Internal(other.to_string()),
    }
}

fn wire<T>(r: Result<T, String>) -> Result<T, SolveError> {
    r.map_err(SolveError::Internal)
}

/// The scale of each load entry of each body at each step.
fn all_scales(sc: &scene::Scene, bodies: &[BodyModel]) -> Vec<Vec<Vec<f64>>> {
    sc.step_scales()
        .iter()
        .map(|st| bodies.iter().map(|b| b.scales(sc, st)).collect())
        .collect()
}

/// How many METIS parts each body gets: its `subdomains` count, and for
/// `"auto"` bodies the ranks left over, shared in proportion to their cells.
fn parts_per_body(sc: &scene::Scene, bodies: &[BodyModel], ranks: usize) -> Vec<usize> {
    let fixed: usize = bodies
        .iter()
        .map(|b| match sc.bodies[b.scene_index].subdomains {
            scene::Subdomains::Count(n) => n,
            scene::Subdomains::Auto => 0,
        })
        .sum();
    let auto: Vec<usize> = (0..bodies.len())
        .filter(|&i| sc.bodies[bodies[i].scene_index].subdomains == scene::Subdomains::Auto)
        .collect();
    let spare = ranks.saturating_sub(fixed).max(auto.len());
    let cells: usize = auto.iter().map(|&i| bodies[i].mesh.cells.len()).sum();
    let mut out: Vec<usize> = bodies
        .iter()
        .map(|b| match sc.bodies[b.scene_index].subdomains {
            scene::Subdomains::Count(n) => n,
            scene::Subdomains::Auto => 1,
        })
        .collect();
    let mut given = 0;
    for (k, &i) in auto.iter().enumerate() {
        let share = if k + 1 == auto.len() {
            spare - given
        } else {
            ((spare as f64 * bodies[i].mesh.cells.len() as f64 / cells.max(1) as f64).round()
                as usize)
                .max(1)
        };
        out[i] = share.max(1);
        given += out[i];
    }
    out
}

/// Partitions the bodies and numbers the interface Γ: the free DOFs of the
/// nodes on contact surfaces or shared between parts, body by body.
/// Returns (Γ index of every body DOF, size of Γ, owner part of every node).
fn interface_numbering(
    sc: &scene::Scene,
    bodies: &mut [BodyModel],
    ranks: usize,
) -> Result<InterfaceNumbering, SolveError> {
    let counts = parts_per_body(sc, bodies, ranks);
    let mut gamma_of = Vec::new();
    let mut owner = Vec::new();
    let mut n = 0;
    for (b, &k) in bodies.iter_mut().zip(&counts) {
        if k > 1 {
            b.parts = signorini_mesh::partition::partition_cells(&b.mesh, k).map_err(|e| {
                SolveError::Input(format!("bodies[{}].subdomains: {e}", b.scene_index))
            })?;
        }
        b.n_parts = k;
        let mut shared = vec![false; b.mesh.n_nodes()];
        for s in signorini_mesh::partition::shared_nodes(&b.mesh, &b.parts) {
            shared[s] = true;
        }
        let mut own = vec![usize::MAX; b.mesh.n_nodes()];
        for (c, cell) in b.mesh.cells.iter().enumerate() {
            for &v in &cell.nodes {
                own[v] = own[v].min(b.parts[c]);
            }
        }
        let mut g = vec![usize::MAX; b.n_dof];
        for (d, gd) in g.iter_mut().enumerate() {
            let node = d / b.mesh.dim;
            if !b.prescribed[d] && (shared[node] || b.contact_node[node]) {
                *gd = n;
                n += 1;
            }
        }
        gamma_of.push(g);
        owner.push(own);
    }
    Ok((gamma_of, n, owner))
}

/// Γ index of every body DOF, size of Γ, owner part of every body node.
type InterfaceNumbering = (Vec<Vec<usize>>, usize, Vec<Vec<usize>>);

/// The root's answer to every rank after the contact solve.
#[derive(Serialize, Deserialize)]
struct RootAnswer {
    /// u_Γ at every step.
    u_gamma: Vec<Vec<f64>>,
}

/// Per-rank figures for the report.
#[derive(Serialize, Deserialize, Clone, Default)]
struct RankFigures {
    condense_s: f64,
    recover_s: f64,
    peak_rss_bytes: u64,
    bytes_sent: u64,
    subdomains: usize,
}

/// Runs a scene on every rank of `comm`. Returns the output on the root,
/// `None` on the other ranks; an error is returned identically on every rank.
pub fn run(
    sc: &scene::Scene,
    scene_name: &str,
    opts: &RunOptions,
    comm: &dyn Transport,
) -> Result<Option<RunOutput>, SolveError> {
    let t_total = Instant::now();
    let mut timings = Timings::default();
    let method = opts.method.unwrap_or(sc.solver.method);
    let path = opts.path.unwrap_or(sc.solver.path);
    let algorithm = algorithm_of(&sc.solver, method);
    if path == scene::SolvePath::Direct
        && algorithm != Algorithm::Status(StatusVariant::All)
        && algorithm != Algorithm::Status(StatusVariant::Single)
    {
        return Err(SolveError::Input(format!(
            "solver.method: the direct path runs the status method with multipliers; \"{}\" runs on path = \"condensed\"",
            algorithm.name()
        )));
    }
    for c in &sc.contact {
        let tresca_by_mprgp = algorithm == Algorithm::Mprgp
            && sc
                .contact
                .iter()
                .all(|c| matches!(c.friction, scene::Friction::Tresca(_)));
        if c.friction != scene::Friction::None
            && (path == scene::SolvePath::Direct
                || !(matches!(algorithm, Algorithm::Status(_)) || tresca_by_mprgp))
        {
            return Err(SolveError::Input(format!(
                "contact \"{}\".friction: friction is solved on path = \"condensed\" by method = \"status\" (with solver.friction = \"fixed_point\" or \"status\"), not by \"{}\" on the {} path",
                c.name,
                algorithm.name(),
                path.as_str()
            )));
        }
        if let scene::Law::Penalty { .. } = c.law {
            if method != scene::Method::Penalty {
                return Err(SolveError::Input(format!(
                    "contact \"{}\".law: a regularised (penalty) law is solved by solver.method = \"penalty\", not \"{}\"",
                    c.name,
                    method.as_str()
                )));
            }
        }
    }
    let mut messages = Vec::new();
    let mut stages = vec!["mesh".to_string(), "assemble".to_string()];

    // Every rank builds the same description of the problem (cheap, and
    // deterministic: METIS runs with a fixed seed).
    let t = Instant::now();
    let mut bodies = model::build_bodies(sc)?;
    let (mut points, fixed_points) = model::build_contacts(sc, &mut bodies, &mut messages)?;
    messages.extend(model::eliminate_redundant(sc, &mut points));
    if !fixed_points.is_empty() {
        messages.push(format!(
            "{} slave node(s) have every normal DOF prescribed: their gap is known and they are not contact unknowns",
            fixed_points.len()
        ));
    }
    for b in &bodies {
        if !b.kernel.is_empty() {
            messages.push(format!(
                "body \"{}\" is held by contact in {} rigid motion(s): solved with the equilibrium of its rigid modes as a constraint (no artificial spring)",
                b.name,
                b.kernel.len()
            ));
        }
    }
    let condensed_path = path == scene::SolvePath::Condensed;
    let (gamma_of, n_gamma, owner_part) = interface_numbering(
        sc,
        &mut bodies,
        if condensed_path { comm.size() } else { 1 },
    )?;
    let specs = subdomain::subdomain_specs(&bodies);
    timings.setup = t.elapsed().as_secs_f64();
    let scales = all_scales(sc, &bodies);

    if !condensed_path {
        if !comm.is_root() {
            return Ok(None);
        }
        stages.push("contact".into());
        let partial = run_direct(
            sc,
            &bodies,
            &points,
            &fixed_points,
            &scales,
            &mut timings,
            &mut messages,
        )?;
        return finish_report(
            partial,
            sc,
            scene_name,
            method,
            path,
            &bodies,
            &points,
            &specs,
            comm,
            t_total,
            timings,
            messages,
            stages,
            0,
            vec![],
        )
        .map(Some);
    }

    // Condensation, on the rank that owns each subdomain.
    stages.push("condense".into());
    let costs: Vec<f64> = specs.iter().map(|s| s.cost()).collect();
    let owner_rank = deal(&costs, comm.size());
    if comm.size() > specs.len() && comm.is_root() {
        messages.push(format!(
            "{} ranks for {} subdomains: {} ranks idle (use subdomains = \"auto\" to split bodies over every rank)",
            comm.size(),
            specs.len(),
            comm.size() - specs.len()
        ));
    }
    let t = Instant::now();
    let par = faer::get_global_parallelism();
    let mine: Result<Vec<(Subdomain, CondensedData)>, String> = (|| {
        if let Ok(r) = std::env::var("SIGNORINI_FAIL_RANK") {
            if r.parse::<usize>().ok() == Some(comm.rank()) {
                return Err(format!(
                    "failure injected on rank {} (SIGNORINI_FAIL_RANK)",
                    comm.rank()
                ));
            }
        }
        specs
            .iter()
            .enumerate()
            .filter(|(i, _)| owner_rank[*i] == comm.rank())
            .map(|(i, spec)| {
                let b = &bodies[spec.body];
                Subdomain::condense(
                    i,
                    spec,
                    b,
                    &gamma_of[spec.body],
                    &owner_part[spec.body],
                    par,
                )
                .map_err(|e| {
                    format!(
                        "bodies[{}] \"{}\", subdomain {} (rank {}): {e}",
                        b.scene_index,
                        b.name,
                        spec.part,
                        comm.rank()
                    )
                })
            })
            .collect()
    })();
    let condense_s = t.elapsed().as_secs_f64();
    let (local, sent): (Vec<Subdomain>, Result<Vec<CondensedData>, String>) = match mine {
        Ok(v) => {
            let (a, b): (Vec<_>, Vec<_>) = v.into_iter().unzip();
            (a, Ok(b))
        }
        Err(e) => (Vec::new(), Err(e)),
    };
    let gathered = wire(gather(comm, &sent))?;

    // Root: the contact problem on Γ at every step.
    let t_root = Instant::now();
    let mut root_state = None;
    let mut root_cond = conditioning::RootConditioning::default();
    let answer: Result<RootAnswer, SolveError> = if let Some(all) = gathered {
        let mut data = Vec::new();
        let mut first_err = None;
        for r in all {
            match r {
                Ok(v) => data.extend(v),
                Err(e) => {
                    first_err.get_or_insert(e);
                }
            }
        }
        match first_err {
            Some(e) => Err(SolveError::Input(e)),
            None => {
                data.sort_by_key(|d| d.id);
                let input = RootInput {
                    sc,
                    algorithm,
                    bodies: &bodies,
                    points: &points,
                    fixed: &fixed_points,
                    specs: &specs,
                    data: &data,
                    gamma_of: &gamma_of,
                    n_gamma,
                };
                solve_root(&input, &scales, &mut root_cond).map(|(ans, state)| {
                    root_state = Some((state, data));
                    ans
                })
            }
        }
    } else {
        Err(SolveError::Internal("no answer".into()))
    };
    let contact_s = t_root.elapsed().as_secs_f64();
    let answer: Result<RootAnswer, SolveError> =
        wire(broadcast(comm, comm.is_root().then_some(&answer)))?;
    let answer = answer?;

    // Every rank recovers its subdomains at every step.
    let t = Instant::now();
    let recovered: Vec<RecoveredData> = local
        .iter()
        .map(|s| {
            let b = specs[s.id].body;
            let sc_b: Vec<Vec<f64>> = scales.iter().map(|st| st[b].clone()).collect();
            s.recover(&sc_b, &answer.u_gamma)
        })
        .collect();
    let recover_s = t.elapsed().as_secs_f64();
    let figures = RankFigures {
        condense_s,
        recover_s,
        peak_rss_bytes: signorini_report::peak_rss_bytes(),
        bytes_sent: comm.bytes_sent(),
        subdomains: local.len(),
    };
    let gathered = wire(gather(comm, &(recovered, figures)))?;
    let Some(all) = gathered else { return Ok(None) };
    let Some((state, data)) = root_state else {
        return Err(SolveError::Internal("root state missing".into()));
    };
    timings.delassus = state.iter().map(|st| st.operator_s).sum();
    let mut recovered: Vec<RecoveredData> = Vec::new();
    let mut figures = Vec::new();
    for (r, f) in all {
        recovered.extend(r);
        figures.push(f);
    }
    recovered.sort_by_key(|r| r.id);
    stages.push("contact".into());
    stages.push("recover".into());
    timings.condense = figures.iter().fold(0.0f64, |a, f| a.max(f.condense_s));
    timings.contact = contact_s;
    timings.recover = figures.iter().fold(0.0f64, |a, f| a.max(f.recover_s));
    let mut partial = finish_condensed(
        sc,
        &bodies,
        &points,
        &specs,
        &data,
        &gamma_of,
        &recovered,
        state,
        &answer.u_gamma,
        &mut messages,
    )?;
    partial.conditioning = Some(conditioning::condensed(
        &data,
        root_cond,
        sc.solver.tolerance,
        &mut messages,
    ));
    let bytes: u64 = figures.iter().map(|f| f.bytes_sent).sum();
    let stats: Vec<RankStats> = figures
        .iter()
        .enumerate()
        .map(|(r, f)| RankStats {
            rank: r,
            subdomains: f.subdomains,
            condense_s: f.condense_s,
            recover_s: f.recover_s,
            peak_rss_bytes: f.peak_rss_bytes,
            bytes_sent: f.bytes_sent,
        })
        .collect();
    finish_report(
        partial, sc, scene_name, method, path, &bodies, &points, &specs, comm, t_total, timings,
        messages, stages, bytes, stats,
    )
    .map(Some)
}

/// One step solved on the root.
struct StepSolution {
    outcome: StatusOutcome,
    gap0: Vec<f64>,
    f_scale: f64,
    length_scale: f64,
    solver: SolverReport,
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
    /// μ₁ (‖(λ_t1/μ₁, λ_t2/μ₂)‖ − λ_n) on the (elliptic) Coulomb cone.
    cone_excess: Vec<f64>,
}

/// The algorithm of a scene's `[solver]` (and `--method`).
pub fn algorithm_of(solver: &scene::Solver, method: scene::Method) -> Algorithm {
    let variant = match solver.status_changes {
        scene::StatusChanges::All => StatusVariant::All,
        scene::StatusChanges::Single => StatusVariant::Single,
    };
    match method {
        scene::Method::Status => match solver.constraints {
            scene::Constraints::Multipliers => Algorithm::Status(variant),
            scene::Constraints::Penalty => Algorithm::StatusPenalty(variant),
        },
        scene::Method::Lemke => Algorithm::Lemke,
        scene::Method::ProjectedGradient => Algorithm::ProjectedGradient,
        scene::Method::ProjectedConjugateGradient => Algorithm::ProjectedConjugateGradient,
        scene::Method::Mprgp => Algorithm::Mprgp,
        scene::Method::Uzawa => Algorithm::Uzawa,
        scene::Method::AugmentedLagrangian => Algorithm::AugmentedLagrangian,
        scene::Method::Penalty => Algorithm::Penalty,
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
    /// Full displacement of each body at every step.
    u_steps: Vec<Vec<Vec<f64>>>,
    dense_interface_bytes: u64,
    factor_bytes: u64,
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
}
