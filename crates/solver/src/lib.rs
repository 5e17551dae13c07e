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
mod conditioning;
pub mod local;
pub mod memory;
pub mod model;
pub mod stiff;
pub mod subdomain;

use std::time::Instant;

use faer::sparse::SparseColMat;
use faer::Mat;
use serde::{Deserialize, Serialize};
use signorini_comm::{broadcast, deal, gather, Transport};
use signorini_condense::{spmv, spmv_with_magnitude, submatrix};
use signorini_contact::direct::DirectProblem;
use signorini_contact::equilibrium::nnls;
use signorini_contact::friction::{
    coulomb_fixed_point, coulomb_status, tresca_projection, tresca_status, FrictionLayout,
    FrictionOptions, PointStatus, Threshold,
};
use signorini_contact::friction3d::{friction_3d, FrictionLayout3d, Law3d};
use signorini_contact::methods::{solve_lcp, solve_lcp_constrained, Algorithm};
use signorini_contact::{
    status_method, ActiveSetSolve, ContactError, DelassusProblem, LcpOptions, LcpSolution,
    SolverReport, StatusOptions, StatusOutcome, StatusVariant,
};
use signorini_report::{
    reference, Certificate, ContactRow, ContactSummary, Memory, Probe, RankStats, Regularisation,
    Report, StepReport, Timings,
};
use signorini_scene as scene;

use model::{BodyModel, FixedPoint, PointFriction, PointModel};
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
    // Refuse a scene that cannot fit before building anything (the root's
    // verdict on every rank: the machines' memory may differ).
    let fits = comm
        .is_root()
        .then(|| memory::check(sc, path, comm.size()).map(|_| ()));
    wire(broadcast(comm, fits.as_ref()))??;
    let mut messages = Vec::new();
    let mut stages = vec!["mesh".to_string(), "assemble".to_string()];

    // Every rank builds the same description of the problem (cheap, and
    // deterministic: METIS runs with a fixed seed).
    let t = Instant::now();
    let mut bodies = model::build_bodies(sc)?;
    let (mut points, fixed_points) = model::build_contacts(sc, &mut bodies)?;
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
                solve_root(
                    sc,
                    algorithm,
                    &bodies,
                    &points,
                    &fixed_points,
                    &specs,
                    &data,
                    &gamma_of,
                    n_gamma,
                    &scales,
                    &mut root_cond,
                )
                .map(|(ans, state)| {
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

/// The force that the master exerts on the slave at contact point `pi`,
/// λ_n n + λ_t1 t1 + λ_t2 t2 (the tangential parts from `friction`, zero
/// without it).
fn point_force(
    p: &PointModel,
    pi: usize,
    lambda_n: f64,
    friction: Option<&FrictionStep>,
) -> [f64; 3] {
    let (l1, l2) = friction.map_or((0.0, 0.0), |f| (f.tangential[pi], f.tangential2[pi]));
    let c = &p.point;
    [0, 1, 2].map(|k| lambda_n * c.normal[k] + l1 * c.tangent[k] + l2 * c.tangent2[k])
}

/// The coefficients (μ₁, μ₂) of a 3D Coulomb law; `None` for Tresca or
/// frictionless points.
fn p_law(law: &Law3d) -> Option<(f64, f64)> {
    match law {
        Law3d::Coulomb { mu } => Some((mu[0], mu[1])),
        _ => None,
    }
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

/// Solves one step's condensed problem with a method other than the status
/// method with multipliers; for the penalty methods, also the exact solution,
/// to report their deviation.
#[allow(clippy::too_many_arguments)]
fn solve_with_algorithm(
    sc: &scene::Scene,
    algorithm: Algorithm,
    problem: &mut DelassusProblem,
    points: &[PointModel],
    law_k: &[f64],
    f_scale: f64,
    length_scale: f64,
) -> Result<(StatusOutcome, SolverReport, Option<Regularisation>), SolveError> {
    let opts = LcpOptions {
        tolerance: sc.solver.tolerance,
        max_iterations: sc.solver.max_iterations,
        force_scale: f_scale,
        gap_scale: length_scale,
        stiffness: Some(sc.solver.penalty),
    };
    let uniform = signorini_contact::penalty::uniform_stiffness(&problem.w, sc.solver.penalty);
    let k: Vec<f64> = law_k
        .iter()
        .zip(&uniform)
        .map(|(&kl, &ku)| if kl > 0.0 { kl } else { ku })
        .collect();
    // Floating bodies: SMALBE with the method as inner solver, the
    // equilibrium of their rigid modes as the equality (contact::smalbe).
    let floating = problem.n_kernel() > 0;
    let solve = |algorithm: Algorithm,
                 k: Option<&[f64]>|
     -> Result<(LcpSolution, Vec<f64>, Vec<f64>), SolveError> {
        if floating {
            let c = solve_lcp_constrained(
                algorithm,
                &problem.w,
                &problem.q,
                &problem.g_mat,
                &problem.e,
                k,
                &opts,
            )
            .map_err(contact_error)?;
            Ok((
                LcpSolution {
                    lambda: c.lambda,
                    report: c.report,
                },
                c.gap,
                c.alpha,
            ))
        } else {
            let sol =
                solve_lcp(algorithm, &problem.w, &problem.q, k, &opts).map_err(contact_error)?;
            let gap = signorini_contact::lcp::gaps(&problem.w, &problem.q, &sol.lambda);
            Ok((sol, gap, vec![]))
        }
    };
    let (sol, gap, alpha) = solve(algorithm, Some(&k))?;
    let regularisation = if algorithm.is_exact() {
        None
    } else {
        let (exact, _, _) = solve(Algorithm::Status(StatusVariant::All), None)?;
        let lmax = inf_norm(&exact.lambda).max(f64::MIN_POSITIVE);
        let dev = sol
            .lambda
            .iter()
            .zip(&exact.lambda)
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()))
            / lmax;
        let sizes: Vec<f64> = points.iter().map(|p| p.tributary).collect();
        let pen = gap.iter().fold(0.0f64, |a, &g| a.max(-g));
        let rel = gap.iter().zip(&sizes).fold(
            0.0f64,
            |a, (&g, &h)| if h > 0.0 { a.max(-g / h) } else { a },
        );
        Some(Regularisation {
            stiffness_factor: sc.solver.penalty,
            force_deviation: dev,
            max_penetration: pen,
            penetration_over_element_size: rel,
            warning: signorini_contact::penalty::penetration_warning(
                &gap,
                &sizes,
                PENETRATION_WARNING_FRACTION,
            ),
        })
    };
    let active: Vec<usize> = (0..sol.lambda.len())
        .filter(|&p| sol.lambda[p] > 0.0)
        .collect();
    let outcome = StatusOutcome {
        converged: sol.report.converged,
        iterations: sol.report.iterations,
        solves: sol.report.operator_applications,
        active,
        lambda: sol.lambda,
        gap,
        stopping_reason: sol.report.stopping_reason.clone(),
        active_history: vec![],
        cycle_detected_at: None,
        variant_used: StatusVariant::All,
    };
    if floating {
        problem.set_alpha(&alpha);
    }
    Ok((outcome, sol.report, regularisation))
}

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

/// Prescribed displacement and external force of a body at a step.
fn body_step(b: &BodyModel, s: &[f64]) -> (Vec<f64>, Vec<f64>) {
    (
        b.combine(s, |l| &l.displacement),
        b.combine(s, |l| &l.force),
    )
}

/// Resultant of a force vector with `dim` components per node.
fn resultant(force: &[f64], dim: usize) -> Vec<f64> {
    let mut r = vec![0.0; dim];
    for (d, f) in force.iter().enumerate() {
        r[d % dim] += f;
    }
    r
}

/// Initial gaps at a step (g0 plus the prescribed displacements' share), and
/// the check that no fully prescribed slave node is pushed through its master.
fn step_gaps(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    fixed: &[FixedPoint],
    u_p: &[Vec<f64>],
    length_scale: f64,
    step: usize,
) -> Result<Vec<f64>, SolveError> {
    for fp in fixed {
        let g = fp.gap0 + fp.row.iter().map(|&(b, d, c)| c * u_p[b][d]).sum::<f64>();
        if g < -sc.solver.tolerance * length_scale {
            let x = bodies[fp.row[0].0].mesh.coords[fp.node];
            return Err(SolveError::Input(format!(
                "contact \"{}\": at step {} the prescribed displacements push slave node ({}, {}) through the master (gap {g:e}); a prescribed node cannot be held back by contact",
                sc.contact[fp.contact].name,
                step + 1,
                x[0],
                x[1]
            )));
        }
    }
    Ok(points
        .iter()
        .map(|p| {
            p.gap0
                + p.row
                    .iter()
                    .filter(|&&(b, d, _)| bodies[b].prescribed[d])
                    .map(|&(b, d, c)| c * u_p[b][d])
                    .sum::<f64>()
        })
        .collect())
}

/// Status method options; the initial active set is every point whose gap
/// is closed at the start of the step (within tolerance).
fn status_options(
    sc: &scene::Scene,
    f_scale: f64,
    length_scale: f64,
    gap0: &[f64],
) -> StatusOptions {
    let closed = sc.solver.tolerance * length_scale;
    StatusOptions {
        variant: StatusVariant::All,
        max_iterations: sc.solver.max_iterations,
        tolerance: sc.solver.tolerance,
        force_scale: f_scale,
        gap_scale: length_scale,
        initial_active: Some((0..gap0.len()).filter(|&p| gap0[p] <= closed).collect()),
    }
}

/// The length scale of a step, against which gaps and penetrations are
/// measured: the largest prescribed displacement, initial gap, or the
/// displacement ‖F‖/E the largest load gives the stiffest body.
fn length_scale(
    bodies: &[BodyModel],
    points: &[PointModel],
    u_p: &[Vec<f64>],
    f_scale: f64,
) -> f64 {
    let u_p_scale = u_p.iter().fold(0.0f64, |a, v| a.max(inf_norm(v)));
    let g0_scale = points.iter().fold(0.0f64, |a, p| a.max(p.gap0.abs()));
    let e_max = bodies.iter().fold(0.0f64, |a, b| a.max(b.material.young));
    u_p_scale.max(g0_scale).max(f_scale / e_max)
}

/// The solver report of a status-method solve.
fn status_report(method: &str, outcome: &StatusOutcome, linear_solves: usize) -> SolverReport {
    SolverReport {
        method: method.into(),
        converged: outcome.converged,
        iterations: outcome.iterations,
        operator_applications: linear_solves,
        residual_history: vec![],
        stopping_reason: outcome.stopping_reason.clone(),
    }
}

/// The root's contact solve on the assembled interface problem.
#[allow(clippy::too_many_arguments)]
fn solve_root(
    sc: &scene::Scene,
    algorithm: Algorithm,
    bodies: &[BodyModel],
    points: &[PointModel],
    fixed: &[FixedPoint],
    specs: &[SubdomainSpec],
    data: &[CondensedData],
    gamma_of: &[Vec<usize>],
    n_gamma: usize,
    scales: &[Vec<Vec<f64>>],
    cond: &mut conditioning::RootConditioning,
) -> Result<(RootAnswer, Vec<StepSolution>), SolveError> {
    // Assemble S and the condensed load of every entry on Γ.
    let mut s = Mat::<f64>::zeros(n_gamma, n_gamma);
    let mut fp_entries: Vec<Vec<Vec<f64>>> = bodies
        .iter()
        .map(|b| vec![vec![0.0; n_gamma]; b.loads.len()])
        .collect();
    for d in data {
        let nb = d.gamma.len();
        for j in 0..nb {
            for i in 0..nb {
                s[(d.gamma[i], d.gamma[j])] += d.schur[i + nb * j];
            }
        }
        let b = specs[d.id].body;
        for (e, f) in d.fprime.iter().enumerate() {
            for (i, v) in f.iter().enumerate() {
                fp_entries[b][e][d.gamma[i]] += v;
            }
        }
    }
    let n_kernel: usize = bodies.iter().map(|b| b.kernel.len()).sum();
    let mut kernel = Mat::<f64>::zeros(n_gamma, n_kernel);
    let mut col = 0;
    for (bi, b) in bodies.iter().enumerate() {
        for r in &b.kernel {
            for (d, &g) in gamma_of[bi].iter().enumerate() {
                if g != usize::MAX {
                    kernel[(g, col)] = r[d];
                }
            }
            col += 1;
        }
    }
    let to_gamma = |row: &[(usize, usize, f64)]| -> Vec<(usize, f64)> {
        row.iter()
            .filter(|&&(b, d, _)| !bodies[b].prescribed[d])
            .map(|&(b, d, c)| (gamma_of[b][d], c))
            .collect()
    };
    let mut rows: Vec<Vec<(usize, f64)>> = points.iter().map(|p| to_gamma(&p.row)).collect();
    // Tangential rows after the normal ones (seed eq. 16: the slip [u_t]).
    let m = points.len();
    let mut tangent_row = vec![None; m];
    let mut tangent_row2 = vec![None; m];
    for (pi, p) in points.iter().enumerate() {
        if let Some(t) = &p.trow {
            tangent_row[pi] = Some(rows.len());
            rows.push(to_gamma(t));
        }
        if let Some(t) = &p.trow2 {
            tangent_row2[pi] = Some(rows.len());
            rows.push(to_gamma(t));
        }
    }
    let layout_3d = FrictionLayout3d {
        tangent_rows: (0..m)
            .map(|p| tangent_row[p].zip(tangent_row2[p]).map(|(a, b)| [a, b]))
            .collect(),
        law: points
            .iter()
            .map(|p| match p.friction {
                PointFriction::Tresca(g) => Law3d::Tresca(g),
                PointFriction::Coulomb { mu, mu2, .. } => Law3d::Coulomb { mu: [mu, mu2] },
                _ => Law3d::None,
            })
            .collect(),
    };
    let three_d = tangent_row2.iter().any(|t| t.is_some());
    if three_d && sc.solver.friction == scene::FrictionSolver::Status {
        return Err(SolveError::Input(
            "solver.friction: the friction status method (seed §4.5) is 2D only; in 3D friction is solved by the fixed point on the threshold (friction = \"fixed_point\", the default)".into(),
        ));
    }
    let has_friction = tangent_row.iter().any(|t| t.is_some());
    let layout = FrictionLayout {
        tangent_row: tangent_row.clone(),
        threshold: points
            .iter()
            .map(|p| match p.friction {
                PointFriction::None => Threshold::None,
                PointFriction::Tresca(g) => Threshold::Tresca(g),
                PointFriction::Coulomb { mu, .. } => Threshold::Coulomb(mu),
                // No threshold: the law is single-valued (checked by its own residual).
                PointFriction::NortonHoff { .. } => Threshold::Tresca(f64::INFINITY),
            })
            .collect(),
    };
    let norton_hoff: Vec<Option<(f64, f64)>> = points
        .iter()
        .map(|p| match p.friction {
            PointFriction::NortonHoff { mu, rho } => Some((mu, rho)),
            _ => None,
        })
        .collect();
    let any_nh = norton_hoff.iter().any(|x| x.is_some());
    if any_nh
        && points.iter().any(|p| {
            matches!(
                p.friction,
                PointFriction::Tresca(_) | PointFriction::Coulomb { .. }
            )
        })
    {
        return Err(SolveError::Input(
            "contact.friction: Norton-Hoff cannot be mixed with Tresca or Coulomb contacts in one scene yet".into(),
        ));
    }
    let mut slip_total = vec![0.0; m];
    let mut slip_total2 = vec![0.0; m];
    let mut previous: Option<(Vec<PointStatus>, Vec<f64>)> = None;
    let mut steps = Vec::new();
    let mut u_gamma = Vec::new();
    for (si, st) in scales.iter().enumerate() {
        let mut fp = vec![0.0; n_gamma];
        let mut u_p = Vec::new();
        let mut f_scale = 0.0f64;
        let mut res = Vec::new();
        for (bi, b) in bodies.iter().enumerate() {
            for (e, &sv) in st[bi].iter().enumerate() {
                if sv != 0.0 {
                    for (o, v) in fp.iter_mut().zip(&fp_entries[bi][e]) {
                        *o += sv * v;
                    }
                }
            }
            let (u, f) = body_step(b, &st[bi]);
            f_scale = f_scale.max(inf_norm(&f));
            res.push(resultant(&f, b.mesh.dim));
            u_p.push(u);
        }
        f_scale = f_scale.max(inf_norm(&fp));
        let length_scale = length_scale(bodies, points, &u_p, f_scale);
        let gap0 = step_gaps(sc, bodies, points, fixed, &u_p, length_scale, si)?;
        // e = −Rᵀ F' for each floating body.
        let mut e_of = Vec::new();
        let mut col = 0;
        for b in bodies {
            let mut e = Vec::new();
            for _ in &b.kernel {
                e.push(-(0..n_gamma).map(|i| kernel[(i, col)] * fp[i]).sum::<f64>());
                col += 1;
            }
            e_of.push(e);
        }
        check_floating_equilibrium(bodies, points, &e_of, &res, si)?;
        if has_friction {
            // Tangential "gaps": the prescribed part of the slip minus the slip
            // at the end of the previous step, so that the tangential rows give
            // slip increments (seed §4.4).
            let mut gap0_all = gap0.clone();
            let prescribed = |t: &[(usize, usize, f64)]| -> f64 {
                t.iter()
                    .filter(|&&(b, d, _)| bodies[b].prescribed[d])
                    .map(|&(b, d, c)| c * u_p[b][d])
                    .sum()
            };
            // in the order of the rows: t1 then t2 of each point
            for (pi, p) in points.iter().enumerate() {
                if let Some(t) = &p.trow {
                    gap0_all.push(prescribed(t) - slip_total[pi]);
                }
                if let Some(t) = &p.trow2 {
                    gap0_all.push(prescribed(t) - slip_total2[pi]);
                }
            }
            let mut problem =
                conditioning::delassus_problem(&s, &rows, &gap0_all, &fp, &kernel, cond)
                    .map_err(contact_error)?;
            let mut compliance = vec![0.0; rows.len()];
            for (pi, p) in points.iter().enumerate() {
                if let (
                    PointFriction::Coulomb {
                        slip_stiffness: Some(k),
                        ..
                    },
                    Some(t),
                ) = (p.friction, tangent_row[pi])
                {
                    compliance[t] = 1.0 / k;
                    if let Some(t2) = tangent_row2[pi] {
                        compliance[t2] = 1.0 / k;
                    }
                }
            }
            problem.add_compliance(&compliance);
            let closed = sc.solver.tolerance * length_scale;
            let initial = previous.as_ref().map(|p| p.0.clone()).unwrap_or_else(|| {
                gap0.iter()
                    .map(|&g| {
                        if g <= closed {
                            PointStatus::Stick
                        } else {
                            PointStatus::Open
                        }
                    })
                    .collect()
            });
            let fopts = FrictionOptions {
                max_iterations: sc.solver.max_iterations,
                max_fixed_point: sc.solver.max_iterations,
                tolerance: sc.solver.tolerance,
                force_scale: f_scale,
                gap_scale: length_scale,
            };
            let all_tresca = layout
                .threshold
                .iter()
                .all(|t| !matches!(t, Threshold::Coulomb(_)));
            let (out, name) = if three_d {
                let start = previous.as_ref().map(|p| p.1.clone());
                (
                    friction_3d(&mut problem, &layout_3d, start.as_deref(), &fopts),
                    if all_tresca {
                        "tresca_3d_semismooth_newton"
                    } else {
                        "coulomb_3d_fixed_point"
                    },
                )
            } else if any_nh {
                (
                    signorini_contact::friction::norton_hoff(
                        &mut problem,
                        &layout,
                        &norton_hoff,
                        initial,
                        &fopts,
                    ),
                    "norton_hoff",
                )
            } else if all_tresca && algorithm == Algorithm::Mprgp {
                (
                    tresca_projection(&problem, &layout, &fopts),
                    "tresca_mprgp_box",
                )
            } else if all_tresca {
                (
                    tresca_status(&mut problem, &layout, initial, &fopts),
                    "tresca_status",
                )
            } else if sc.solver.friction == scene::FrictionSolver::Status {
                (
                    coulomb_status(&mut problem, &layout, initial, &fopts),
                    "friction_status",
                )
            } else {
                let start = previous.as_ref().map(|p| p.1.clone());
                (
                    coulomb_fixed_point(&mut problem, &layout, initial, start.as_deref(), &fopts),
                    "coulomb_fixed_point",
                )
            };
            let out = out.map_err(contact_error)?;
            let lambda: Vec<f64> = out.forces[..m].to_vec();
            let mut fr = FrictionStep {
                statuses: out.statuses.clone(),
                tangential: vec![0.0; m],
                slip_increment: vec![0.0; m],
                slip_total: vec![0.0; m],
                tangential2: vec![0.0; m],
                slip_increment2: vec![0.0; m],
                slip_total2: vec![0.0; m],
                threshold: vec![0.0; m],
                cone_excess: vec![0.0; m],
            };
            for pi in 0..m {
                if let Some(t) = tangent_row[pi] {
                    fr.tangential[pi] = out.forces[t];
                    fr.slip_increment[pi] = out.gaps[t];
                    slip_total[pi] += out.gaps[t];
                    fr.threshold[pi] = match layout.threshold[pi] {
                        Threshold::Tresca(g) => g,
                        Threshold::Coulomb(mu) => mu * lambda[pi].max(0.0),
                        Threshold::None => 0.0,
                    };
                    fr.cone_excess[pi] = fr.tangential[pi].abs() - fr.threshold[pi];
                }
                if let Some(t2) = tangent_row2[pi] {
                    fr.tangential2[pi] = out.forces[t2];
                    fr.slip_increment2[pi] = out.gaps[t2];
                    slip_total2[pi] += out.gaps[t2];
                    let (l1, l2) = (fr.tangential[pi], fr.tangential2[pi]);
                    fr.cone_excess[pi] = match p_law(&layout_3d.law[pi]) {
                        Some((mu1, mu2)) if mu1 > 0.0 && mu2 > 0.0 => {
                            mu1 * (((l1 / mu1).powi(2) + (l2 / mu2).powi(2)).sqrt()
                                - lambda[pi].max(0.0))
                        }
                        Some(_) => l1.hypot(l2),
                        None => l1.hypot(l2) - fr.threshold[pi],
                    };
                }
                fr.slip_total[pi] = slip_total[pi];
                fr.slip_total2[pi] = slip_total2[pi];
            }
            let outcome = StatusOutcome {
                converged: out.converged,
                iterations: out.iterations,
                solves: problem.solves,
                active: (0..m)
                    .filter(|&p| out.statuses[p] != PointStatus::Open)
                    .collect(),
                lambda,
                gap: out.gaps[..m].to_vec(),
                stopping_reason: out.stopping_reason.clone(),
                active_history: vec![],
                cycle_detected_at: out.cycle_detected.then_some(out.iterations),
                variant_used: StatusVariant::All,
            };
            let solver = SolverReport {
                method: name.into(),
                converged: out.converged,
                iterations: out.iterations,
                operator_applications: problem.solves,
                residual_history: out.fixed_point_residuals.clone(),
                stopping_reason: out.stopping_reason.clone(),
            };
            u_gamma.push(problem.displacement(&out.forces));
            previous = Some((out.statuses.clone(), out.forces.clone()));
            steps.push(StepSolution {
                outcome,
                gap0,
                f_scale,
                length_scale,
                solver,
                regularisation: None,
                law_k: vec![0.0; m],
                friction: Some(fr),
            });
            continue;
        }
        let mut problem = conditioning::delassus_problem(&s, &rows, &gap0, &fp, &kernel, cond)
            .map_err(contact_error)?;
        let law_k: Vec<f64> = points
            .iter()
            .map(|p| match sc.contact[p.contact].law {
                scene::Law::Penalty { penalty } => penalty * p.tributary,
                scene::Law::Unilateral => 0.0,
            })
            .collect();
        let mut solver_report = None;
        let mut regularisation = None;
        let outcome = if !points.is_empty() && !matches!(algorithm, Algorithm::Status(_)) {
            let (o, r, reg) = solve_with_algorithm(
                sc,
                algorithm,
                &mut problem,
                points,
                &law_k,
                f_scale,
                length_scale,
            )?;
            solver_report = Some(r);
            regularisation = reg;
            o
        } else if points.is_empty() {
            let (lambda, gap) = problem.solve_active(&[]).map_err(contact_error)?;
            StatusOutcome {
                converged: true,
                iterations: 0,
                solves: 1,
                active: vec![],
                lambda,
                gap,
                stopping_reason: "no contact point".into(),
                active_history: vec![],
                cycle_detected_at: None,
                variant_used: StatusVariant::All,
            }
        } else {
            let variant = match algorithm {
                Algorithm::Status(v) => v,
                _ => StatusVariant::All,
            };
            status_method(
                &mut problem,
                &StatusOptions {
                    variant,
                    ..status_options(sc, f_scale, length_scale, &gap0)
                },
            )
            .map_err(contact_error)?
        };
        let solver = solver_report
            .unwrap_or_else(|| status_report(algorithm.name(), &outcome, problem.solves));
        u_gamma.push(problem.displacement(&outcome.lambda));
        steps.push(StepSolution {
            outcome,
            gap0,
            f_scale,
            length_scale,
            solver,
            regularisation,
            law_k,
            friction: None,
        });
    }
    Ok((RootAnswer { u_gamma }, steps))
}

/// Residual pieces of one step for the certificate.
struct Residuals {
    /// Largest equilibrium residual (interior and Γ, contact forces included).
    equilibrium: f64,
    /// Largest internal or external force entry.
    force_scale: f64,
}

/// The certificate of DESIGN.md §4 at one step, from the equilibrium
/// residual and the final gaps and forces.
fn certificate_of(
    res: &Residuals,
    gaps: &[f64],
    lambda: &[f64],
    sol: &StepSolution,
    umax: f64,
    tolerance: f64,
) -> Certificate {
    let lmax = inf_norm(lambda);
    let lscale = sol.length_scale.max(umax).max(f64::MIN_POSITIVE);
    let fscale = sol.f_scale.max(lmax).max(f64::MIN_POSITIVE);
    // Points of a regularised law obey λ = k max(0, −g) instead of g ≥ 0, λ g = 0.
    let unilateral = |p: &usize| sol.law_k.get(*p).is_none_or(|k| *k == 0.0);
    let law = (0..lambda.len())
        .filter(|p| !unilateral(p))
        .fold(0.0f64, |a, p| {
            a.max((lambda[p] - sol.law_k[p] * (-gaps[p]).max(0.0)).abs())
        })
        / fscale;
    Certificate {
        equilibrium: res.equilibrium / res.force_scale.max(fscale),
        penetration: (0..gaps.len())
            .filter(unilateral)
            .fold(0.0f64, |a, p| a.max(-gaps[p]))
            / lscale,
        tension: lambda.iter().fold(0.0f64, |a, &l| a.max(-l)) / fscale,
        complementarity: (0..gaps.len())
            .filter(unilateral)
            .fold(0.0f64, |a, p| a.max((gaps[p] * lambda[p]).abs()))
            / (lscale * fscale),
        cone: sol.friction.as_ref().map_or(0.0, |f| {
            f.cone_excess.iter().fold(0.0f64, |a, &c| a.max(c)) / fscale
        }),
        dissipation: sol.friction.as_ref().map_or(0.0, |f| {
            (0..lambda.len()).fold(0.0f64, |a, p| {
                a.max(
                    f.tangential[p] * f.slip_increment[p] + f.tangential2[p] * f.slip_increment2[p],
                )
            }) / (fscale * lscale)
        }),
        law,
        tolerance: tolerance.max(1e-9),
        force_scale: fscale,
        length_scale: lscale,
    }
}

/// Certificate, contact.csv rows and the step report of one step; updates
/// the run's convergence.
#[allow(clippy::too_many_arguments)]
fn conclude_step(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    si: usize,
    sol: &StepSolution,
    gaps: &[f64],
    res: &Residuals,
    umax: f64,
    partial: &mut Partial,
    messages: &mut Vec<String>,
) {
    let lambda = &sol.outcome.lambda;
    let cert = certificate_of(res, gaps, lambda, sol, umax, sc.solver.tolerance);
    let outcome = &sol.outcome;
    if !outcome.converged {
        partial.converged = false;
        partial.failure.get_or_insert(format!(
            "step {}: {}: {}",
            si + 1,
            sol.solver.method,
            outcome.stopping_reason
        ));
    } else if cert.max() > cert.tolerance {
        partial.converged = false;
        partial.failure.get_or_insert(format!(
            "step {}: the certificate residual {:.3e} exceeds the tolerance {:.1e}",
            si + 1,
            cert.max(),
            cert.tolerance
        ));
    }
    if let Some(c) = outcome.cycle_detected_at {
        messages.push(format!(
            "step {}: the status method cycled (flip-flop) at iteration {c}; it fell back to one status change per iteration (seed §3.3)",
            si + 1
        ));
    }
    for (pi, p) in points.iter().enumerate() {
        let l = lambda[pi];
        partial.contact_rows.push(ContactRow {
            step: si + 1,
            contact: sc.contact[p.contact].name.clone(),
            body: bodies[p.slave_body].name.clone(),
            point: p.point.slave_node,
            x: p.point.x,
            gap: gaps[pi],
            normal_force: l,
            tangential_force: sol.friction.as_ref().map_or(0.0, |f| f.tangential[pi]),
            slip: sol.friction.as_ref().map_or(0.0, |f| f.slip_total[pi]),
            tangential_force_2: sol.friction.as_ref().map_or(0.0, |f| f.tangential2[pi]),
            slip_2: sol.friction.as_ref().map_or(0.0, |f| f.slip_total2[pi]),
            pressure: if p.tributary > 0.0 {
                l / p.tributary
            } else {
                0.0
            },
            status: match (
                outcome.active.binary_search(&pi).is_ok(),
                &sol.friction,
                p.trow.is_some(),
            ) {
                (false, _, _) => "open",
                (true, Some(f), true) if f.statuses[pi].is_slip() => "slip",
                (true, Some(_), true) => "stick",
                _ => "contact",
            },
        });
    }
    let (sticking, slipping) = match &sol.friction {
        Some(f) => (
            (0..points.len())
                .filter(|&p| points[p].trow.is_some() && f.statuses[p] == PointStatus::Stick)
                .count(),
            (0..points.len())
                .filter(|&p| points[p].trow.is_some() && f.statuses[p].is_slip())
                .count(),
        ),
        None => (0, 0),
    };
    let dim = sc.dimension as usize;
    let mut step_force = vec![0.0f64; dim];
    let (mut sum_n, mut sum_t, mut slip_sum, mut slip_count) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for (pi, p) in points.iter().enumerate() {
        let lt = sol.friction.as_ref().map_or(0.0, |f| f.tangential[pi]);
        let force = point_force(p, pi, lambda[pi], sol.friction.as_ref());
        for (f, fk) in step_force.iter_mut().zip(force) {
            *f += fk;
        }
        sum_n += lambda[pi];
        sum_t += lt;
        if let (Some(f), true) = (
            &sol.friction,
            p.trow.is_some() && outcome.active.binary_search(&pi).is_ok(),
        ) {
            slip_sum += f.slip_total[pi];
            slip_count += 1;
        }
    }
    partial.steps.push(StepReport {
        scale: sc.step_scales()[si].clone(),
        contact_force: step_force,
        normal_force: sum_n,
        tangential_force: sum_t,
        mean_slip: if slip_count > 0 {
            slip_sum / slip_count as f64
        } else {
            0.0
        },
        iterations: outcome.iterations,
        active: outcome.active.len(),
        sticking,
        slipping,
        converged: outcome.converged && cert.max() <= cert.tolerance,
        stopping_reason: outcome.stopping_reason.clone(),
        active_history: outcome.active_history.clone(),
        cycle_detected_at: outcome.cycle_detected_at,
        solver: serde_json::to_value(&sol.solver).unwrap_or_default(),
        regularisation: sol.regularisation.clone(),
    });
    if let Some(w) = sol.regularisation.as_ref().and_then(|r| r.warning.clone()) {
        messages.push(format!("step {}: {w}", si + 1));
    }
    partial.solver = serde_json::to_value(&sol.solver).unwrap_or_default();
    partial.certificate = cert;
    partial.lambda = lambda.clone();
    partial.friction = sol.friction.clone();
}

fn empty_partial() -> Partial {
    Partial {
        steps: vec![],
        certificate: Certificate::default(),
        converged: true,
        failure: None,
        contact_rows: vec![],
        lambda: vec![],
        u_steps: vec![],
        dense_interface_bytes: 0,
        factor_bytes: 0,
        n_gamma: 0,
        dofs: 0,
        solver: serde_json::Value::Null,
        friction: None,
        conditioning: None,
    }
}

/// Root: certificates from the residuals the ranks sent back, and the fields.
#[allow(clippy::too_many_arguments)]
fn finish_condensed(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    specs: &[SubdomainSpec],
    data: &[CondensedData],
    gamma_of: &[Vec<usize>],
    recovered: &[RecoveredData],
    steps: Vec<StepSolution>,
    u_gamma: &[Vec<f64>],
    messages: &mut Vec<String>,
) -> Result<Partial, SolveError> {
    let n_gamma = u_gamma.first().map(|u| u.len()).unwrap_or(0);
    let mut partial = empty_partial();
    // Full displacement of each body at every step.
    let mut u_steps: Vec<Vec<Vec<f64>>> = steps
        .iter()
        .map(|_| bodies.iter().map(|b| vec![0.0; b.n_dof]).collect())
        .collect();
    for r in recovered {
        let b = specs[r.id].body;
        let dim = r.dim;
        for (si, u) in r.displacements.iter().enumerate() {
            for (l, &n) in r.nodes.iter().enumerate() {
                u_steps[si][b][dim * n..dim * (n + 1)].copy_from_slice(&u[dim * l..dim * (l + 1)]);
            }
        }
    }
    let umax = u_steps
        .last()
        .map_or(0.0, |u| u.iter().fold(0.0f64, |a, ub| a.max(inf_norm(ub))));
    for (si, sol) in steps.iter().enumerate() {
        let lambda = &sol.outcome.lambda;
        // Γ residual: Σ_i (K_i u_i − f_i)_Γ − Bᵀλ; interior residuals as sent.
        let mut r_gamma = vec![0.0; n_gamma];
        let mut interior = 0.0f64;
        let mut force_scale = 0.0f64;
        for r in recovered {
            for &(g, v) in &r.gamma_residual[si] {
                r_gamma[g] += v;
            }
            interior = interior.max(r.interior_residual[si]);
            force_scale = force_scale.max(r.force_scale[si]);
        }
        let mut gaps = sol.gap0.clone();
        for (pi, p) in points.iter().enumerate() {
            for &(b, d, c) in &p.row {
                if !bodies[b].prescribed[d] {
                    let g = gamma_of[b][d];
                    r_gamma[g] -= c * lambda[pi];
                    gaps[pi] += c * u_gamma[si][g];
                }
            }
            if let (Some(t), Some(fr)) = (&p.trow, &sol.friction) {
                for &(b, d, c) in t {
                    if !bodies[b].prescribed[d] {
                        r_gamma[gamma_of[b][d]] -= c * fr.tangential[pi];
                    }
                }
            }
            if let (Some(t), Some(fr)) = (&p.trow2, &sol.friction) {
                for &(b, d, c) in t {
                    if !bodies[b].prescribed[d] {
                        r_gamma[gamma_of[b][d]] -= c * fr.tangential2[pi];
                    }
                }
            }
        }
        let res = Residuals {
            equilibrium: interior.max(inf_norm(&r_gamma)),
            force_scale: force_scale.max(inf_norm(lambda)),
        };
        conclude_step(
            sc,
            bodies,
            points,
            si,
            sol,
            &gaps,
            &res,
            umax,
            &mut partial,
            messages,
        );
    }
    let m = points.len();
    partial.u_steps = u_steps;
    partial.dense_interface_bytes = 8 * (n_gamma * n_gamma + m * m) as u64;
    partial.factor_bytes = data.iter().map(|d| d.factor_bytes as u64).sum();
    partial.n_gamma = n_gamma;
    partial.dofs = bodies
        .iter()
        .map(|b| b.prescribed.iter().filter(|p| !**p).count())
        .sum();
    Ok(partial)
}

/// The direct path on the root: every body's whole sparse stiffness, the
/// contact constraints added by Lagrange multipliers and the saddle-point
/// matrix refactorised at each status iteration (seed §3.3).
fn run_direct(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    fixed: &[FixedPoint],
    scales: &[Vec<Vec<f64>>],
    timings: &mut Timings,
    messages: &mut Vec<String>,
) -> Result<Partial, SolveError> {
    let t = Instant::now();
    let mut k_full = Vec::new();
    let mut free_offset = Vec::new();
    let mut free_index: Vec<Vec<usize>> = Vec::new();
    let mut frees: Vec<Vec<usize>> = Vec::new();
    let mut triplets = Vec::new();
    let mut n_free = 0;
    for b in bodies {
        let k = signorini_fem::try_assemble_stiffness(&b.mesh, &b.material)
            .map_err(|e| SolveError::Input(format!("bodies[{}].mesh: {e}", b.scene_index)))?;
        let free: Vec<usize> = (0..b.n_dof).filter(|&d| !b.prescribed[d]).collect();
        let mut idx = vec![usize::MAX; b.n_dof];
        for (i, &d) in free.iter().enumerate() {
            idx[d] = i;
        }
        let kff = submatrix(k.as_ref(), &free, &free);
        for j in 0..kff.ncols() {
            for (&i, &v) in kff.row_idx_of_col_raw(j).iter().zip(kff.val_of_col(j)) {
                triplets.push(faer::sparse::Triplet::new(n_free + i, n_free + j, v));
            }
        }
        free_offset.push(n_free);
        n_free += free.len();
        free_index.push(idx);
        frees.push(free);
        k_full.push(k);
    }
    let k_global = SparseColMat::<usize, f64>::try_new_from_triplets(n_free, n_free, &triplets)
        .map_err(|e| SolveError::Internal(format!("{e:?}")))?;
    timings.assemble = t.elapsed().as_secs_f64();
    let rows: Vec<Vec<(usize, f64)>> = points
        .iter()
        .map(|p| {
            p.row
                .iter()
                .filter(|&&(b, d, _)| !bodies[b].prescribed[d])
                .map(|&(b, d, c)| (free_offset[b] + free_index[b][d], c))
                .collect()
        })
        .collect();
    let mut partial = empty_partial();
    let t = Instant::now();
    let mut u_steps: Vec<Vec<Vec<f64>>> = Vec::new();
    let mut solutions = Vec::new();
    for (si, st) in scales.iter().enumerate() {
        let mut f = vec![0.0; n_free];
        let mut u_p = Vec::new();
        let mut forces = Vec::new();
        let mut f_scale = 0.0f64;
        for (bi, b) in bodies.iter().enumerate() {
            let (u, force) = body_step(b, &st[bi]);
            let ku = spmv(k_full[bi].as_ref(), &u);
            for (i, &d) in frees[bi].iter().enumerate() {
                f[free_offset[bi] + i] = force[d] - ku[d];
            }
            f_scale = f_scale.max(inf_norm(&force));
            u_p.push(u);
            forces.push(force);
        }
        f_scale = f_scale.max(inf_norm(&f));
        let length_scale = length_scale(bodies, points, &u_p, f_scale);
        let gap0 = step_gaps(sc, bodies, points, fixed, &u_p, length_scale, si)?;
        let e_of: Vec<Vec<f64>> = bodies
            .iter()
            .enumerate()
            .map(|(bi, b)| {
                b.kernel
                    .iter()
                    .map(|r| {
                        -frees[bi]
                            .iter()
                            .enumerate()
                            .map(|(i, &d)| r[d] * f[free_offset[bi] + i])
                            .sum::<f64>()
                    })
                    .collect()
            })
            .collect();
        let res: Vec<Vec<f64>> = forces
            .iter()
            .zip(bodies)
            .map(|(f, b)| resultant(f, b.mesh.dim))
            .collect();
        check_floating_equilibrium(bodies, points, &e_of, &res, si)?;
        let mut problem = DirectProblem::new(&k_global, &f, &rows, &gap0);
        let outcome = status_method(
            &mut problem,
            &status_options(sc, f_scale, length_scale, &gap0),
        )
        .map_err(contact_error)?;
        // `problem.u` is the displacement of the last solve, the one that
        // gave `outcome.lambda` (as the condensed path recovers it).
        let u_full: Vec<Vec<f64>> = bodies
            .iter()
            .enumerate()
            .map(|(bi, _)| {
                let mut u = u_p[bi].clone();
                for (i, &d) in frees[bi].iter().enumerate() {
                    u[d] = problem.u[free_offset[bi] + i];
                }
                u
            })
            .collect();
        let solver = status_report("status", &outcome, problem.factorisations);
        let law_k = vec![0.0; points.len()];
        let sol = StepSolution {
            outcome,
            gap0,
            f_scale,
            length_scale,
            solver,
            regularisation: None,
            law_k,
            friction: None,
        };
        let res = direct_residuals(
            bodies,
            &k_full,
            points,
            &forces,
            &u_full,
            &sol.outcome.lambda,
        );
        let gaps = gaps_of(points, &u_full);
        let umax = u_full.iter().fold(0.0f64, |a, u| a.max(inf_norm(u)));
        solutions.push((sol, gaps, res, umax));
        u_steps.push(u_full);
    }
    timings.contact = t.elapsed().as_secs_f64();
    // Outside the timed phases: one more sparse Cholesky, of K alone.
    partial.conditioning = Some(conditioning::direct(
        &k_global,
        bodies.iter().any(|b| !b.kernel.is_empty()),
        sc.solver.tolerance,
        messages,
    ));
    for (si, (sol, gaps, res, umax)) in solutions.iter().enumerate() {
        conclude_step(
            sc,
            bodies,
            points,
            si,
            sol,
            gaps,
            res,
            *umax,
            &mut partial,
            messages,
        );
    }
    partial.u_steps = u_steps;
    partial.dofs = n_free;
    Ok(partial)
}

/// Fills the report common to both paths.
#[allow(clippy::too_many_arguments)]
fn finish_report(
    partial: Partial,
    sc: &scene::Scene,
    scene_name: &str,
    method: scene::Method,
    path: scene::SolvePath,
    bodies: &[BodyModel],
    points: &[PointModel],
    specs: &[SubdomainSpec],
    comm: &dyn Transport,
    t_total: Instant,
    timings: Timings,
    messages: Vec<String>,
    mut stages: Vec<String>,
    communication_bytes: u64,
    rank_stats: Vec<RankStats>,
) -> Result<RunOutput, SolveError> {
    let lambda = &partial.lambda;
    let no_step = Vec::new();
    let u_full = partial.u_steps.last().unwrap_or(&no_step);
    let dim = sc.dimension as usize;
    let mut contact_force = vec![0.0; dim];
    let mut summaries: Vec<ContactSummary> = sc
        .contact
        .iter()
        .map(|c| ContactSummary {
            name: c.name.clone(),
            points: 0,
            active: 0,
            force: vec![0.0; dim],
        })
        .collect();
    for (pi, p) in points.iter().enumerate() {
        let s = &mut summaries[p.contact];
        s.points += 1;
        if lambda[pi] != 0.0 {
            s.active += 1;
        }
        let force = point_force(p, pi, lambda[pi], partial.friction.as_ref());
        for (k, total) in contact_force.iter_mut().enumerate() {
            s.force[k] += force[k];
            *total += force[k];
        }
    }
    let mut probes = Vec::new();
    for pr in &sc.output.probes {
        let x = model::point3(pr);
        let best = bodies
            .iter()
            .enumerate()
            .filter_map(|(bi, b)| b.mesh.nearest_node(x).map(|(n, d)| (bi, n, d)))
            .min_by(|a, b| a.2.total_cmp(&b.2));
        if let Some((bi, n, d)) = best {
            probes.push(Probe {
                point: pr.clone(),
                body: bodies[bi].name.clone(),
                node: n,
                distance: d,
                displacement: u_full[bi][n * dim..(n + 1) * dim].to_vec(),
            });
        }
    }
    let reference = match &sc.reference {
        None => None,
        Some(r) => Some(compare_reference(
            sc,
            r,
            points,
            lambda,
            partial.friction.as_ref(),
        )?),
    };
    let want_stress = sc.output.wants("stress");
    if want_stress {
        stages.push("stress".into());
    }
    if partial.steps.len() > 1 {
        stages.push(format!("steps ({})", partial.steps.len()));
    }
    let mut results = Vec::new();
    for (bi, b) in bodies.iter().enumerate() {
        let mut history: Vec<StepFields> = partial
            .u_steps
            .iter()
            .map(|u| {
                let stress = if want_stress {
                    signorini_fem::cell_stress(&b.mesh, &b.material, &u[bi])
                } else {
                    Vec::new()
                };
                StepFields {
                    von_mises: stress.iter().map(signorini_fem::von_mises).collect(),
                    displacement: u[bi].clone(),
                    stress,
                }
            })
            .collect();
        if history.is_empty() {
            history.push(StepFields {
                displacement: vec![0.0; b.n_dof],
                stress: Vec::new(),
                von_mises: Vec::new(),
            });
        }
        results.push(BodyResult {
            name: b.name.clone(),
            coords: b.mesh.coords.clone(),
            cells: b.mesh.cells.iter().map(|c| c.nodes.clone()).collect(),
            parts: b.parts.clone(),
            history,
        });
    }
    let report = Report {
        scene: scene_name.to_string(),
        title: sc.title.clone(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        ranks: comm.size(),
        transport: comm.kind().to_string(),
        subdomains: specs.len(),
        dofs: partial.dofs,
        interface_dofs: partial.n_gamma,
        contact_points: points.len(),
        converged: partial.converged,
        method: method.as_str().to_string(),
        path: path.as_str().to_string(),
        solver: partial.solver,
        stages,
        steps: partial.steps,
        timings_s: Timings {
            total: t_total.elapsed().as_secs_f64(),
            ..timings
        },
        memory: Memory {
            peak_rss_bytes: signorini_report::peak_rss_bytes(),
            dense_interface_bytes: partial.dense_interface_bytes,
            factor_bytes: partial.factor_bytes,
            estimated_bytes: memory::estimate(sc, path, comm.size()).bytes(),
        },
        communication_bytes,
        rank_timings_s: signorini_report::RankTimings::of(&rank_stats),
        rank_stats,
        certificate: partial.certificate,
        contact_force,
        contacts: summaries,
        probes,
        reference,
        conditioning: partial.conditioning,
        messages,
        failure: partial.failure,
    };
    Ok(RunOutput {
        report,
        contact_rows: partial.contact_rows,
        bodies: results,
    })
}

/// g_p = g0_p + Σ coef u over the full DOFs.
fn gaps_of(points: &[PointModel], u_full: &[Vec<f64>]) -> Vec<f64> {
    points
        .iter()
        .map(|p| p.gap0 + p.row.iter().map(|&(b, d, c)| c * u_full[b][d]).sum::<f64>())
        .collect()
}

/// Equilibrium residual of the direct path on the free DOFs of every body:
/// K u − f − Bᵀλ.
fn direct_residuals(
    bodies: &[BodyModel],
    k_full: &[SparseColMat<usize, f64>],
    points: &[PointModel],
    forces: &[Vec<f64>],
    u_full: &[Vec<f64>],
    lambda: &[f64],
) -> Residuals {
    let mut contact_force: Vec<Vec<f64>> = bodies.iter().map(|b| vec![0.0; b.n_dof]).collect();
    for (p, &l) in points.iter().zip(lambda) {
        for &(b, d, c) in &p.row {
            contact_force[b][d] += c * l;
        }
    }
    let mut eq = 0.0f64;
    let mut scale = 0.0f64;
    for (bi, b) in bodies.iter().enumerate() {
        let (ku, abs_ku) = spmv_with_magnitude(k_full[bi].as_ref(), &u_full[bi]);
        for d in (0..b.n_dof).filter(|&d| !b.prescribed[d]) {
            eq = eq.max((ku[d] - forces[bi][d] - contact_force[bi][d]).abs());
            scale = scale
                .max(abs_ku[d])
                .max(forces[bi][d].abs())
                .max(contact_force[bi][d].abs());
        }
    }
    Residuals {
        equilibrium: eq,
        force_scale: scale,
    }
}

/// A body held by contact needs compressive contact forces that balance the
/// load on its free rigid motions: Gᵀλ = e with λ ≥ 0, G = B R, e = −Rᵀ F
/// (see [`signorini_contact::equilibrium`]). Otherwise it cannot be in
/// equilibrium: bad input, exit 1, with the unbalanced resultant. `e[bi]` is
/// computed by the caller from its own load representation (the condensed
/// load on Γ or the load on the free DOFs: both give the same work on R).
fn check_floating_equilibrium(
    bodies: &[BodyModel],
    points: &[PointModel],
    e_of: &[Vec<f64>],
    resultant: &[Vec<f64>],
    step: usize,
) -> Result<(), SolveError> {
    for (bi, b) in bodies.iter().enumerate() {
        if b.kernel.is_empty() {
            continue;
        }
        let k = b.kernel.len();
        let friction = points.iter().any(|p| p.trow.is_some());
        let mut gt = Mat::<f64>::zeros(k, points.len() * if friction { 3 } else { 1 });
        for (pi, p) in points.iter().enumerate() {
            for &(pb, d, c) in &p.row {
                if pb == bi {
                    for (j, r) in b.kernel.iter().enumerate() {
                        gt[(j, pi)] += c * r[d];
                    }
                }
            }
            // Tangential forces hold rigid motions too (bounded by friction).
            for &(pb, d, c) in p.trow.iter().flatten() {
                if pb == bi {
                    for (j, r) in b.kernel.iter().enumerate() {
                        gt[(j, points.len() + pi)] += c * r[d];
                    }
                }
            }
            for &(pb, d, c) in p.trow2.iter().flatten() {
                if pb == bi {
                    for (j, r) in b.kernel.iter().enumerate() {
                        gt[(j, 2 * points.len() + pi)] += c * r[d];
                    }
                }
            }
        }
        let e = &e_of[bi];
        let fr = &resultant[bi];
        let fmax = inf_norm(e).max(inf_norm(fr));
        // Rigid motions that no contact can hold: the null space of Gᵀ (rank
        // test of G Gᵀ, scaled by its largest eigenvalue).
        let ggt = &gt * gt.transpose();
        let eig = ggt
            .self_adjoint_eigen(faer::Side::Lower)
            .map_err(|e| SolveError::Internal(format!("eigen decomposition of G Gᵀ: {e:?}")))?;
        let emax = (0..k).fold(0.0f64, |a, j| a.max(eig.S()[j]));
        let unheld = (0..k)
            .filter(|&j| eig.S()[j] <= 1e-12 * emax || emax == 0.0)
            .count();
        // Compressive normal forces alone must balance the load unless
        // friction can help (then the friction solve itself decides).
        let res = if friction { 0.0 } else { nnls(&gt, e).1 };
        if friction {
            check_friction_capacity(b, points, bi, fr, step)?;
        }
        if unheld > 0 {
            return Err(SolveError::Input(format!(
                "bodies[{}]: body \"{}\" is free to move: {unheld} of its rigid motions are prevented neither by a support nor by its contacts (frictionless contact only holds along the normals); add a [[boundary]] displacement that pins it (e.g. a point with x = 0)",
                b.scene_index, b.name
            )));
        }
        if res > 1e-8 * fmax.max(f64::MIN_POSITIVE) {
            return Err(SolveError::Input(format!(
                "bodies[{}]: body \"{}\" cannot be in equilibrium at step {}: it has no support against {} rigid motion(s), and its external load (resultant {}) cannot be balanced by its contacts, which can only push along their normals; add a [[boundary]] displacement that holds it, or change the load",
                b.scene_index,
                b.name,
                step + 1,
                k,
                fmt_vector(fr)
            )));
        }
    }
    Ok(())
}

/// A floating body on a flat frictional contact (every normal the same),
/// free to translate along the normal and along the tangential part R_t of
/// its load resultant R,
/// needs ‖R_t‖ ≤ μ |R·n| (VALIDATION.md §5: under force control a body
/// pushed past its friction has no static equilibrium). Exit 1 with the
/// numbers otherwise, instead of a failing friction solve.
fn check_friction_capacity(
    b: &BodyModel,
    points: &[PointModel],
    bi: usize,
    resultant: &[f64],
    step: usize,
) -> Result<(), SolveError> {
    let own: Vec<&PointModel> = points
        .iter()
        .filter(|p| p.slave_body == bi && p.trow.is_some())
        .collect();
    let Some(first) = own.first() else {
        return Ok(());
    };
    let n = first.point.normal;
    let flat = own
        .iter()
        .all(|p| (0..3).all(|k| (p.point.normal[k] - n[k]).abs() <= 1e-9));
    let mu = own.iter().try_fold(0.0f64, |m, p| match p.friction {
        PointFriction::Coulomb { mu, mu2, .. } => Some(m.max(mu).max(mu2)),
        _ => None,
    });
    let (true, Some(mu)) = (flat, mu) else {
        return Ok(());
    };
    let dim = b.mesh.dim;
    let r: Vec<f64> = (0..3)
        .map(|k| resultant.get(k).copied().unwrap_or(0.0))
        .collect();
    let rn: f64 = (0..3).map(|k| r[k] * n[k]).sum();
    let rt: Vec<f64> = (0..3).map(|k| r[k] - rn * n[k]).collect();
    let rt_norm = rt.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = rn.abs().max(rt_norm).max(f64::MIN_POSITIVE);
    // The translations along R_t and along n must be free (no prescribed DOF
    // along them): otherwise a support carries part of the load, and the
    // normal force is not known from the load alone.
    let free_along = (0..b.n_dof)
        .filter(|&d| b.prescribed[d])
        .all(|d| rt[d % dim].abs() <= 1e-12 * scale && n[d % dim].abs() <= 1e-12);
    if free_along && rt_norm > mu * (-rn).max(0.0) * (1.0 + 1e-9) + 1e-12 * scale {
        return Err(SolveError::Input(format!(
            "bodies[{}]: body \"{}\" cannot be in equilibrium at step {}: the tangential part of its load, {rt_norm:e}, exceeds what friction can hold, μ|N| = {:e} (μ = {mu}, normal load {:e}); a body pushed past its friction under force control has no static equilibrium: impose a tangential displacement instead, or add a support",
            b.scene_index,
            b.name,
            step + 1,
            mu * (-rn).max(0.0),
            -rn
        )));
    }
    Ok(())
}

/// `(a, b, c)` with every component in `{:e}`.
fn fmt_vector(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
    format!("({})", parts.join(", "))
}

fn contact_modulus(sc: &scene::Scene, body: &str) -> f64 {
    // 1/E* contribution of one body: (1 − ν²)/E in plane strain, 1/E in plane stress, 0 if rigid.
    let Some(b) = sc.body(body) else { return 0.0 };
    let Some(m) = b.material.as_deref().and_then(|n| sc.material(n)) else {
        return 0.0;
    };
    match sc.model {
        scene::Model::PlaneStress => 1.0 / m.young,
        _ => (1.0 - m.poisson * m.poisson) / m.young,
    }
}

fn compare_reference(
    sc: &scene::Scene,
    r: &scene::Reference,
    points: &[PointModel],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
) -> Result<signorini_report::ReferenceReport, SolveError> {
    let Some(pmax) = (0..points.len()).max_by(|&a, &b| lambda[a].total_cmp(&lambda[b])) else {
        return Err(SolveError::Input(
            "reference: the scene has no contact point to compare".into(),
        ));
    };
    // The coordinate of each point across the contact: along the tangent of
    // the most loaded point in 2D; the radius in an axisymmetric model; in 3D
    // the distance from the force-weighted centre within the contact plane.
    let t = points[pmax].point.tangent;
    let n0 = points[pmax].point.normal;
    let total: f64 = lambda.iter().map(|l| l.max(0.0)).sum();
    let mut centre = [0.0; 3];
    for (p, &l) in points.iter().zip(lambda) {
        for (c, x) in centre.iter_mut().zip(p.point.x) {
            *c += l.max(0.0) * x / total.max(f64::MIN_POSITIVE);
        }
    }
    let coordinate = |x: [f64; 3]| -> f64 {
        match sc.model {
            scene::Model::Axisymmetric => x[0],
            scene::Model::Solid => {
                let d = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
                let dn = d[0] * n0[0] + d[1] * n0[1] + d[2] * n0[2];
                ((d[0] - dn * n0[0]).powi(2)
                    + (d[1] - dn * n0[1]).powi(2)
                    + (d[2] - dn * n0[2]).powi(2))
                .sqrt()
            }
            _ => x[0] * t[0] + x[1] * t[1],
        }
    };
    // The tangential force of each point: along t in 2D; in 3D its component
    // along the direction of the total tangential force.
    let tangential_vector = |pi: usize| point_force(&points[pi], pi, 0.0, friction);
    let mut total_t = [0.0; 3];
    for pi in 0..points.len() {
        let v = tangential_vector(pi);
        (0..3).for_each(|k| total_t[k] += v[k]);
    }
    let norm_t = (total_t[0].powi(2) + total_t[1].powi(2) + total_t[2].powi(2)).sqrt();
    let direction = if norm_t > 0.0 {
        total_t.map(|x| x / norm_t)
    } else {
        t
    };
    let nodes: Vec<reference::NodalPressure> = points
        .iter()
        .zip(lambda)
        .enumerate()
        .map(|(pi, (p, &l))| reference::NodalPressure {
            s: coordinate(p.point.x),
            force: l.max(0.0),
            tributary: p.tributary,
            tangential: if sc.dimension == 3 {
                let v = tangential_vector(pi);
                v[0] * direction[0] + v[1] * direction[1] + v[2] * direction[2]
            } else {
                friction.map_or(0.0, |f| f.tangential[pi])
            },
            stick: friction.is_some_and(|f| f.statuses[pi] == PointStatus::Stick),
        })
        .collect();
    let first = sc
        .contact
        .first()
        .ok_or_else(|| SolveError::Input("reference: needs a [[contact]]".into()))?;
    let e_star =
        || 1.0 / (contact_modulus(sc, &first.slave.body) + contact_modulus(sc, &first.master.body));
    let radius = || {
        r.radius.ok_or_else(|| {
            SolveError::Input(format!(
                "reference.radius: {} needs the radius",
                r.kind.as_str()
            ))
        })
    };
    // The coefficient in the direction of the tangential force: μ, or on an
    // elliptic cone (3D, μ₁ along t1, μ₂ along t2) 1/‖(d₁/μ₁, d₂/μ₂)‖.
    let directional = |c: &[f64]| -> Option<f64> {
        match c {
            [mu] => Some(*mu),
            [mu1, mu2] => {
                let p = &points[pmax].point;
                let d1: f64 = (0..3).map(|k| direction[k] * p.tangent[k]).sum();
                let d2: f64 = (0..3).map(|k| direction[k] * p.tangent2[k]).sum();
                Some(1.0 / ((d1 / mu1).powi(2) + (d2 / mu2).powi(2)).sqrt())
            }
            _ => None,
        }
    };
    let mu = || -> Result<f64, SolveError> {
        r.friction
            .or(match &first.friction {
                scene::Friction::Coulomb { coefficient, .. } => directional(coefficient),
                _ => None,
            })
            .ok_or_else(|| {
                SolveError::Input(format!(
                    "reference.friction: {} needs μ (or a Coulomb contact)",
                    r.kind.as_str()
                ))
            })
    };
    match r.kind {
        scene::ReferenceKind::HertzCylinder if sc.dimension == 2 && sc.model != scene::Model::Axisymmetric => {
            Ok(reference::hertz_cylinder(&nodes, e_star(), radius()?))
        }
        scene::ReferenceKind::HertzCylinder => Err(SolveError::Input(
            "reference.kind: \"hertz_cylinder\" is a plane strain / plane stress reference; for a sphere (3D or axisymmetric) use \"hertz_sphere\"".into(),
        )),
        scene::ReferenceKind::HertzSphere if sc.model == scene::Model::Axisymmetric || sc.dimension == 3 => {
            Ok(reference::hertz_sphere(&nodes, e_star(), radius()?))
        }
        scene::ReferenceKind::HertzSphere => Err(SolveError::Input(
            "reference.kind: \"hertz_sphere\" needs model = \"axisymmetric\" or dimension = 3; in plane strain use \"hertz_cylinder\"".into(),
        )),
        scene::ReferenceKind::UniformPressure => Ok(reference::uniform_pressure(&nodes, r.pressure, None)),
        scene::ReferenceKind::CattaneoMindlin => Ok(reference::cattaneo_mindlin(&nodes, e_star(), radius()?, mu()?)),
        scene::ReferenceKind::SlidingBlock => Ok(reference::sliding_block(&nodes, mu()?, None)),
        other => Err(SolveError::Input(format!(
            "reference.kind: \"{}\" is not supported yet (supported: hertz_cylinder, hertz_sphere, uniform_pressure, cattaneo_mindlin, sliding_block)",
            other.as_str()
        ))),
    }
}
