//! The root solve of the condensed path: S and F' of every subdomain
//! assembled on Γ, the Delassus operator built once, and each load step's
//! contact problem solved by the chosen algorithm (course notes §3–4).

use crate::checks::{check_floating_equilibrium, inf_norm, PENETRATION_WARNING_FRACTION};
use crate::conditioning;
use crate::contact_rows::ContactRows;
use crate::element_step::{element_step, ElementHistory};
use crate::error::{contact_error, SolveError};
use crate::friction_step::{deadline, friction_rows, friction_step, FrictionHistory, FrictionRows};
use crate::interface_problem::{Interface, RootInput, StepLoad};
use crate::model::{BodyModel, FixedPoint, PointModel};
use crate::progress::{Event, Progress};
use crate::step::{FrictionStep, StepSolution};
use crate::subdomain::CondensedData;
use crate::timing::timed;
use faer::Mat;
use signorini_condense::interface::{InterfaceStiffness, SchurBlock};
use signorini_contact::registry::Algorithm;
use signorini_contact::{
    status_method, ActiveSetSolve, ContactError, ContactSolution, DelassusOperator,
    DelassusProblem, LcpOptions, SolverReport, StatusOptions, StatusVariant, StopReason,
};
use signorini_report::Regularisation;
use signorini_scene as scene;

/// The force that the master exerts on the slave at contact point `pi`,
/// λ_n n + λ_t1 t1 + λ_t2 t2 (the tangential parts from `friction`, zero
/// without it).
pub(crate) fn point_force(
    p: &PointModel,
    pi: usize,
    lambda_n: f64,
    friction: Option<&FrictionStep>,
) -> [f64; 3] {
    let (l1, l2) = friction.map_or((0.0, 0.0), |f| (f.tangential[pi], f.tangential2[pi]));
    let c = &p.point;
    [0, 1, 2].map(|k| lambda_n * c.normal[k] + l1 * c.tangent[k] + l2 * c.tangent2[k])
}

/// The net force of a sum of point forces: in an axisymmetric model each
/// point force is that of a whole ring, whose radial parts cancel around the
/// axis, so only the axial component (y = z) remains.
pub(crate) fn net_force(model: scene::Model, mut force: Vec<f64>) -> Vec<f64> {
    if model == scene::Model::Axisymmetric {
        force[0] = 0.0;
    }
    force
}

/// Solves one step's condensed problem with a method other than the status
/// method with multipliers; for the penalty methods, also the exact solution,
/// to report their deviation. The floating bodies' amplitudes α go into
/// `problem`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_with_algorithm(
    sc: &scene::Scene,
    algorithm: Algorithm,
    problem: &mut DelassusProblem,
    points: &[PointModel],
    law_k: &[f64],
    f_scale: f64,
    length_scale: f64,
) -> Result<(ContactSolution, Option<Regularisation>), SolveError> {
    let opts = LcpOptions {
        tolerance: sc.solver.tolerance,
        max_iterations: sc.solver.max_iterations,
        force_scale: f_scale,
        gap_scale: length_scale,
        stiffness: Some(sc.solver.penalty),
        deadline: Some(deadline(sc.solver.time_limit, problem.q.len())),
    };
    let uniform = signorini_contact::lcp::penalty::uniform_stiffness(&problem.w, sc.solver.penalty);
    let k: Vec<f64> = law_k
        .iter()
        .zip(&uniform)
        .map(|(&kl, &ku)| if kl > 0.0 { kl } else { ku })
        .collect();
    let sol = algorithm
        .solve_delassus(problem, Some(&k), &opts)
        .map_err(contact_error)?;
    let regularisation = if algorithm.is_exact() {
        None
    } else {
        let exact = Algorithm::status(StatusVariant::All)
            .solve_delassus(problem, None, &opts)
            .map_err(contact_error)?;
        Some(regularisation_of(
            sc,
            points,
            &sol.forces,
            &exact.forces,
            &sol.gaps,
        ))
    };
    if problem.n_kernel() > 0 {
        problem.set_alpha(&sol.alpha);
    }
    Ok((sol, regularisation))
}

/// What a penalty method gave up against the exact solution: the largest
/// force deviation over the largest exact force, the largest penetration,
/// absolute and over the points' tributary sizes, and a warning when it
/// is large.
fn regularisation_of(
    sc: &scene::Scene,
    points: &[PointModel],
    lambda: &[f64],
    exact: &[f64],
    gap: &[f64],
) -> Regularisation {
    let lmax = inf_norm(exact).max(f64::MIN_POSITIVE);
    let dev = lambda
        .iter()
        .zip(exact)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()))
        / lmax;
    let sizes: Vec<f64> = points.iter().map(|p| p.tributary).collect();
    let pen = gap.iter().fold(0.0f64, |a, &g| a.max(-g));
    let rel = gap.iter().zip(&sizes).fold(
        0.0f64,
        |a, (&g, &h)| if h > 0.0 { a.max(-g / h) } else { a },
    );
    Regularisation {
        stiffness_factor: sc.solver.penalty,
        force_deviation: dev,
        max_penetration: pen,
        penetration_over_element_size: rel,
        warning: signorini_contact::lcp::penalty::penetration_warning(
            gap,
            &sizes,
            PENETRATION_WARNING_FRACTION,
        ),
    }
}

/// Prescribed displacement and external force of a body at a step.
pub(crate) fn body_step(b: &BodyModel, s: &[f64]) -> (Vec<f64>, Vec<f64>) {
    (
        b.combine(s, |l| &l.displacement),
        b.combine(s, |l| &l.force),
    )
}

/// Resultant of a force vector with `dim` components per node.
pub(crate) fn resultant(force: &[f64], dim: usize) -> Vec<f64> {
    let mut r = vec![0.0; dim];
    for (d, f) in force.iter().enumerate() {
        r[d % dim] += f;
    }
    r
}

/// Initial gaps at a step (g0 plus the prescribed displacements' share), and
/// the check that no fully prescribed slave node is pushed through its master.
pub(crate) fn step_gaps(
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
pub(crate) fn status_options(
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
        deadline: None,
    }
}

/// The length scale of a step, against which gaps and penetrations are
/// measured: the largest prescribed displacement, initial gap, or the
/// displacement the largest load gives the stiffest body ([`load_displacement`]).
pub(crate) fn length_scale(
    bodies: &[BodyModel],
    points: &[PointModel],
    u_p: &[Vec<f64>],
    f_scale: f64,
) -> f64 {
    let u_p_scale = u_p.iter().fold(0.0f64, |a, v| a.max(inf_norm(v)));
    let g0_scale = points.iter().fold(0.0f64, |a, p| a.max(p.gap0.abs()));
    let u_f = bodies
        .iter()
        .map(|b| load_displacement(b, f_scale))
        .filter(|u| u.is_finite())
        .fold(f64::INFINITY, f64::min);
    let u_f = if u_f.is_finite() { u_f } else { 0.0 };
    u_p_scale.max(g0_scale).max(u_f)
}

/// The displacement a force `f` gives body `b`: f/E in the plane models,
/// whose forces are per unit thickness, and f/(E h) in the axisymmetric
/// (forces of whole rings) and 3D models, whose forces are forces, h being
/// the diagonal of the body's bounding box; f/E alone would be an area
/// there, and the gap tolerances would change with the length unit.
fn load_displacement(b: &BodyModel, f: f64) -> f64 {
    let e = b.material.young;
    let volumic = b.mesh.dim == 3 || b.material.model == signorini_fem::Model::Axisymmetric;
    if !volumic {
        return f / e;
    }
    f / (e * b.mesh.size())
}

/// The report of a status-method solve: the method's name as the run
/// calls it, and the linear solves its active-set problem counted.
pub(crate) fn status_report(outcome: &mut ContactSolution, method: &str, linear_solves: usize) {
    outcome.report.method = method.into();
    outcome.report.operator_applications = linear_solves;
    outcome.report.residual_history.clear();
}

/// The root's contact solve on the assembled interface problem, one load
/// step at a time ([`RootSolve::step`], so that each step is recovered and
/// written before the next is solved): the interface assembled and the
/// friction rows set up once, the Delassus operator built at the first step,
/// then each step's right-hand side and contact (and friction) solve, with
/// what a step hands to the next (slip history, warm start).
pub(crate) struct RootSolve<'a> {
    input: &'a RootInput<'a>,
    interface: Interface,
    kind: StepKind,
    operator: Option<DelassusOperator>,
}

/// How the root solves every step of a run, chosen once from the contacts,
/// with what a step hands to the next.
enum StepKind {
    /// Contact elements, or penalty laws with friction: the return mapping
    /// (course notes §7), with each contact row's slip history.
    ReturnMapping(ElementHistory),
    /// Friction: its rows on Γ and each point's slip history.
    Friction(FrictionRows, FrictionHistory),
    /// Frictionless contact, warm-started from the last step's answer.
    Frictionless(WarmStart),
}

impl<'a> RootSolve<'a> {
    /// The root's solve of `input`, with S = Σ S_i already assembled
    /// ([`take_interface_stiffness`]).
    pub(crate) fn new(input: &'a RootInput<'a>, s: InterfaceStiffness) -> Result<Self, SolveError> {
        let interface = assemble_interface(input, s);
        let kind = if input.return_mapping {
            StepKind::ReturnMapping(ElementHistory::new(interface.rows.len()))
        } else {
            match friction_rows(input, &interface)? {
                Some(rows) => StepKind::Friction(rows, FrictionHistory::new(input.points.len())),
                None => StepKind::Frictionless(WarmStart::default()),
            }
        };
        Ok(RootSolve {
            input,
            interface,
            kind,
            operator: None,
        })
    }

    /// Load step `si` with the load scales `st` (per body, per load entry):
    /// the step's solution and u_Γ.
    pub(crate) fn step(
        &mut self,
        si: usize,
        st: &[Vec<f64>],
        cond: &mut conditioning::RootConditioning,
    ) -> Result<(StepSolution, Vec<f64>), SolveError> {
        // S is needed once, to build the operator: it leaves memory then.
        let stiffness = match self.operator {
            None => self.interface.s.take(),
            Some(_) => None,
        };
        let (input, interface) = (self.input, &self.interface);
        let (mut operator_s, mut step_s) = (0.0, 0.0);
        let (mut step, u) = timed(&mut step_s, || {
            let load = step_load(input, interface, st, si)?;
            let op =
                delassus_operator(&mut self.operator, &mut operator_s, input.progress, || {
                    let s = stiffness.ok_or_else(|| {
                        SolveError::Internal(
                            "the interface stiffness was already factorised".into(),
                        )
                    })?;
                    conditioning::delassus_operator(s, &interface.rows, &interface.kernel, cond)
                        .map_err(|e| interface_error(input, e))
                })?;
            match &mut self.kind {
                StepKind::ReturnMapping(h) => element_step(input, interface, h, op, load),
                StepKind::Friction(fr, h) => {
                    fr.at_step(input, si);
                    friction_step(input, interface, fr, h, op, load)
                }
                StepKind::Frictionless(warm) => frictionless_step(input, op, load, warm),
            }
        })?;
        step.operator_s = operator_s;
        step.solve_s = step_s - operator_s;
        let u = match input.ties {
            Some(t) => t.expand(&u),
            None => u,
        };
        Ok((step, u))
    }
}

/// Assembles S and the condensed load of every entry on Γ from the
/// subdomains' blocks, the kernel R on Γ, and the contact rows on Γ
/// (tangential rows after the normal ones, course notes eq. 16: the slip [u_t]).
fn assemble_interface(input: &RootInput, s: InterfaceStiffness) -> Interface {
    let (bodies, n_gamma) = (input.bodies, input.n_gamma);
    let mut fp_entries: Vec<Vec<Vec<f64>>> = bodies
        .iter()
        .map(|b| vec![vec![0.0; n_gamma]; b.loads.len()])
        .collect();
    for d in input.data {
        let b = input.specs[d.id].body;
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
        let frames = input.frames.local(bi, b.mesh.dim, None);
        for r in &b.kernel {
            let r = frames.to_local(r);
            for (d, &g) in input.gamma_of[bi].iter().enumerate() {
                let g = match input.ties {
                    Some(t) if g != usize::MAX => t.kept(g).unwrap_or(usize::MAX),
                    _ => g,
                };
                if g != usize::MAX {
                    kernel[(g, col)] = r[d];
                }
            }
            col += 1;
        }
    }
    let ContactRows {
        rows,
        tangent_row,
        tangent_row2,
    } = rows_on_gamma(input);
    Interface {
        s: Some(s),
        fp_entries,
        kernel,
        rows,
        tangent_row,
        tangent_row2,
    }
}

/// S = Σ S_i, taking the subdomains' blocks S_i: dense for one subdomain;
/// with several, the blocks themselves (factorised over the tree of
/// subdomains, `signorini_condense::interface`).
pub(crate) fn take_interface_stiffness(
    data: &mut [CondensedData],
    n_gamma: usize,
) -> InterfaceStiffness {
    if data.len() > 1 {
        let blocks = data
            .iter_mut()
            .map(|d| SchurBlock {
                gamma: d.gamma.clone(),
                values: std::mem::take(&mut d.schur),
            })
            .collect();
        return InterfaceStiffness::Blocks { n: n_gamma, blocks };
    }
    let mut s = Mat::<f64>::zeros(n_gamma, n_gamma);
    for d in data {
        let nb = d.gamma.len();
        for j in 0..nb {
            for i in 0..nb {
                s[(d.gamma[i], d.gamma[j])] += d.schur[i + nb * j];
            }
        }
        d.schur = Vec::new();
    }
    InterfaceStiffness::Dense(s)
}

/// The rows of B on Γ (prescribed DOFs left out).
fn rows_on_gamma(input: &RootInput) -> ContactRows {
    let (bodies, gamma_of) = (input.bodies, input.gamma_of);
    ContactRows::of(input.points, |row| {
        let row = input.frames.gamma_row(bodies, gamma_of, row);
        match input.ties {
            Some(t) => t.row(&row),
            None => row,
        }
    })
}

/// The load of step `si` on Γ (Σ s_e F'_e), the prescribed displacements,
/// the force and length scales, the initial gaps, and the check that every
/// body held by contact alone can be balanced by its contacts.
fn step_load(
    input: &RootInput,
    interface: &Interface,
    st: &[Vec<f64>],
    si: usize,
) -> Result<StepLoad, SolveError> {
    let (bodies, points) = (input.bodies, input.points);
    let mut fp = vec![0.0; input.n_gamma];
    let mut u_p = Vec::new();
    let mut f_scale = 0.0f64;
    let mut res = Vec::new();
    for (bi, b) in bodies.iter().enumerate() {
        for (e, &sv) in st[bi].iter().enumerate() {
            if sv != 0.0 {
                for (o, v) in fp.iter_mut().zip(&interface.fp_entries[bi][e]) {
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
    let gap0 = step_gaps(
        input.sc,
        bodies,
        points,
        input.fixed,
        &u_p,
        length_scale,
        si,
    )?;
    // e = −Rᵀ F' for each floating body.
    let mut e_of = Vec::new();
    let mut col = 0;
    for b in bodies {
        let mut e = Vec::new();
        for _ in &b.kernel {
            e.push(
                -(0..input.n_gamma)
                    .map(|i| interface.kernel[(i, col)] * fp[i])
                    .sum::<f64>(),
            );
            col += 1;
        }
        e_of.push(e);
    }
    check_floating_equilibrium(bodies, points, &e_of, &res, si)?;
    Ok(StepLoad {
        fp,
        u_p,
        f_scale,
        length_scale,
        gap0,
    })
}

/// What a frictionless status step hands to the next load step: its
/// active set (the next step's first guess) and the Cholesky factor of
/// its active block (W does not change over the steps, so the next step
/// updates that factor instead of factorising).
#[derive(Default)]
pub(crate) struct WarmStart {
    active: Option<Vec<usize>>,
    factor: Option<signorini_linalg::active_factor::ActiveFactor>,
}

/// One frictionless step: the chosen algorithm (or the status method) on
/// the step's problem; returns the step and u_Γ.
fn frictionless_step(
    input: &RootInput,
    op: &DelassusOperator,
    load: StepLoad,
    warm: &mut WarmStart,
) -> Result<(StepSolution, Vec<f64>), SolveError> {
    let (sc, algorithm, points) = (input.sc, input.algorithm, input.points);
    let mut problem = op
        .problem(&load.gap0, &load.fp)
        .with_factor(warm.factor.take());
    let law_k: Vec<f64> = points
        .iter()
        .map(|p| match sc.contact[p.contact].law {
            scene::Law::Penalty { penalty } => penalty * p.tributary,
            scene::Law::Unilateral | scene::Law::Tied => 0.0,
        })
        .collect();
    let (f_scale, length_scale) = (load.f_scale, load.length_scale);
    let mut regularisation = None;
    let outcome = if !points.is_empty() && !algorithm.on_active_set() {
        let (o, reg) = solve_with_algorithm(
            sc,
            algorithm,
            &mut problem,
            points,
            &law_k,
            f_scale,
            length_scale,
        )?;
        regularisation = reg;
        o
    } else if points.is_empty() {
        let (lambda, gap) = problem.solve_active(&[]).map_err(contact_error)?;
        let report = SolverReport {
            converged: true,
            stop: StopReason::NoContactPoint,
            ..Default::default()
        };
        let mut outcome = ContactSolution::with_gaps(lambda, gap, vec![], report);
        status_report(&mut outcome, algorithm.name(), problem.solves);
        outcome
    } else {
        let mut opts = status_options(sc, f_scale, length_scale, &load.gap0);
        opts.variant = algorithm.variant();
        opts.deadline = Some(deadline(sc.solver.time_limit, points.len()));
        if let Some(active) = warm.active.take() {
            opts.initial_active = Some(active);
        }
        let mut outcome = status_method(&mut problem, &opts).map_err(contact_error)?;
        status_report(&mut outcome, algorithm.name(), problem.solves);
        warm.active = Some(outcome.active.clone());
        warm.factor = problem.take_factor();
        outcome
    };
    let u = problem.displacement(&outcome.forces);
    Ok((
        StepSolution {
            outcome,
            gap0: load.gap0,
            f_scale,
            length_scale,
            regularisation,
            law_k,
            friction: None,
            solve_s: 0.0,
            operator_s: 0.0,
        },
        u,
    ))
}

/// The run's Delassus operator, built by `build` at its first use (once per
/// run: S, B and R do not change over the steps), with the seconds it took
/// in `seconds`.
pub(crate) fn delassus_operator<'a>(
    slot: &'a mut Option<DelassusOperator>,
    seconds: &mut f64,
    progress: &Progress,
    build: impl FnOnce() -> Result<DelassusOperator, SolveError>,
) -> Result<&'a DelassusOperator, SolveError> {
    if slot.is_none() {
        progress.emit(Event::Detail("Delassus operator"));
        *slot = Some(timed(seconds, build)?);
    }
    slot.as_ref()
        .ok_or_else(|| SolveError::Internal("the Delassus operator was not built".into()))
}

/// The error of building the Delassus operator: an interface stiffness S
/// that is not positive definite beyond the rigid modes is named by the body
/// that holds the Γ DOF of the failing pivot (S is block diagonal by body,
/// so that body is one that can move freely); any other as `contact_error`.
fn interface_error(input: &RootInput, e: ContactError) -> SolveError {
    let ContactError::SingularInterface { dof } = e else {
        return contact_error(e);
    };
    let Some(b) = (0..input.bodies.len()).find(|&b| input.gamma_of[b].contains(&dof)) else {
        return contact_error(e);
    };
    let body = &input.bodies[b];
    SolveError::Input(format!(
        "bodies[{}]: body \"{}\": {e}; a body held only by contact needs contacts that can hold every rigid motion its supports leave free, and parts of a mesh that meet only at a node (or along an edge in 3D) hinge there",
        body.scene_index, body.name
    ))
}
