//! Friction on the direct path: each load step solved on the whole sparse
//! system by the semi-smooth Newton method of [`crate::direct_newton`], with
//! the condensed path's friction rows, law, slip history and report: the
//! contact rows are the direct path's normal rows and the points'
//! tangential rows on the free DOFs (in the condensed path's order), the
//! tangential "gaps" the prescribed slip minus the slip total of the steps
//! before (course notes §4.4), and each step starts from the previous step's
//! displacements and forces.

use crate::contact_rows::ContactRows;
use crate::direct_balance::{contact_forces, rigid_motion_imbalance};
use crate::direct_newton::{solve_whole, WholeLoad, WholeSolution, WholeSystem};
use crate::direct_system::{
    check_floating, direct_loads, direct_residuals, full_displacements, DirectSystem,
};
use crate::error::{contact_error, SolveError};
use crate::friction_step::{
    friction_state, layout_of, prescribed_slip_friction, row_gaps, FrictionHistory, FrictionRows,
};
use crate::interface_problem::initial_statuses;
use crate::kkt::{ldlt_factorisation, KktCounts};
use crate::model::{gaps_of, BodyModel, FixedPoint, PointModel};
use crate::progress::Phase;
use crate::root::{length_scale, step_gaps};
use crate::run_context::{RunContext, RunLog};
use crate::step::{FrictionStep, StepSolution};
use crate::step_end::StepLoop;
use crate::timing::timed;
use signorini_contact::friction::{statuses, FrictionLaw, FrictionOptions, PointStatus};
use signorini_contact::law::regularised;
use signorini_contact::{ContactSolution, SolverReport, StopReason};
use signorini_scene as scene;
use std::time::Instant;

/// The contact rows of the direct path with friction on the global free
/// DOFs (prescribed DOFs left out).
pub(crate) fn direct_rows(
    bodies: &[BodyModel],
    points: &[PointModel],
    system: &DirectSystem,
) -> ContactRows {
    ContactRows::of(points, |row| {
        row.iter()
            .filter(|&&(b, d, _)| !bodies[b].prescribed[d])
            .map(|&(b, d, c)| (system.offset[b] + bodies[b].free_index[d], c))
            .collect()
    })
}

/// The elastic slip compliance 1/k_e of a regularised law on each
/// tangential row (course notes §4.1.3), zero elsewhere.
fn compliance(points: &[PointModel], rows: &ContactRows) -> Vec<f64> {
    let tangential = |pi: usize| [rows.tangent_row[pi], rows.tangent_row2[pi]];
    let points = points.iter().enumerate();
    regularised::slip_compliance(
        rows.rows.len(),
        points.map(|(pi, p)| (p.slip_stiffness, tangential(pi))),
    )
}

/// The direct path with friction on the root (module doc); each step ended
/// (`steps`) before the next is solved.
pub(crate) fn run_direct_friction(
    ctx: &RunContext,
    system: &DirectSystem,
    steps: &mut StepLoop,
    log: &mut RunLog,
) -> Result<(), SolveError> {
    let (sc, model) = (ctx.sc, ctx.model);
    let (bodies, points) = (&model.bodies[..], &model.points[..]);
    let rows = direct_rows(bodies, points, system);
    let tangent_rows = (&rows.tangent_row[..], &rows.tangent_row2[..]);
    let fr = layout_of(sc, points, &rows.rows, tangent_rows)?
        .ok_or_else(|| SolveError::Internal("friction without a tangential row".into()))?;
    let compliance = compliance(points, &rows);
    ctx.progress.phase(Phase::Contact);
    let mut whole = timed(&mut log.timings.contact, || {
        let floating = bodies.iter().any(|b| !b.kernel.is_empty());
        WholeSystem::new(
            &system.k_global,
            &rows.rows,
            &fr.layout,
            &compliance,
            floating,
        )
        .map_err(contact_error)
    })?;
    let mut stepper = Stepper {
        sc,
        bodies,
        points,
        fixed: &model.fixed,
        system,
        rows: &rows,
        fr: &fr,
        history: FrictionHistory::new(points.len()),
        start: None,
    };
    for (si, st) in model.scales.iter().enumerate() {
        ctx.progress.step(si, model.scales.len());
        let (sol, gaps, res, u_full) = timed(&mut log.timings.contact, || {
            stepper.step(&mut whole, st, si)
        })?;
        timed(&mut log.timings.output, || {
            steps.end_step(si, &sol, &gaps, &res, u_full, &mut log.messages)
        })?;
    }
    let (lu, _, ldlt, krylov_steps) = whole.counts();
    let counts = KktCounts {
        factorisations: ldlt,
        refinement_steps: krylov_steps,
        lu_fallbacks: lu,
    };
    let partial = &mut steps.partial;
    partial.factorisation = Some(ldlt_factorisation(whole.ordered(), "ldlt+gmres", counts));
    partial.dofs = system.n_free;
    Ok(())
}

/// What one step of the direct path with friction reads, and what it hands
/// to the next: the slip history and the start (u, λ).
struct Stepper<'a> {
    sc: &'a scene::Scene,
    bodies: &'a [BodyModel],
    points: &'a [PointModel],
    fixed: &'a [FixedPoint],
    system: &'a DirectSystem,
    rows: &'a ContactRows,
    fr: &'a FrictionRows,
    history: FrictionHistory,
    start: Option<(Vec<f64>, Vec<f64>)>,
}

/// A step's solution, final gaps, residuals and full displacements.
type FrictionStepOut = (
    StepSolution,
    Vec<f64>,
    crate::step::Residuals,
    Vec<Vec<f64>>,
);

impl Stepper<'_> {
    /// One load step: the loads, the floating bodies' balance checked, the
    /// rows' q with the slip history, the whole-system Newton solve, the
    /// friction state and the slip totals carried on.
    fn step(
        &mut self,
        whole: &mut WholeSystem<'_>,
        st: &[Vec<f64>],
        si: usize,
    ) -> Result<FrictionStepOut, SolveError> {
        let started = Instant::now();
        let (bodies, points, system) = (self.bodies, self.points, self.system);
        let loads = direct_loads(bodies, system, st);
        let length = length_scale(bodies, points, &loads.u_p, loads.f_scale);
        let gap0 = step_gaps(self.sc, bodies, points, self.fixed, &loads.u_p, length, si)?;
        check_floating(bodies, points, system, &loads, si)?;
        let (f_scale, length) = self.history.scales(loads.f_scale, length);
        let history = &self.history;
        let q = row_gaps(bodies, points, &gap0, &loads.u_p, |pi| {
            (history.slip_total[pi], history.slip_total2[pi])
        });
        let opts = FrictionOptions {
            max_iterations: self.sc.solver.max_iterations,
            max_fixed_point: self.sc.solver.max_iterations,
            tolerance: self.sc.solver.tolerance,
            force_scale: f_scale,
            gap_scale: length,
            deadline: Some(system.deadline(self.sc.solver.time_limit, q.len())),
        };
        let start = match self.start.take() {
            Some(start) => start,
            None => self.cold_start(&q, whole.rho(), (f_scale, length)),
        };
        let load = WholeLoad { f: &loads.f, q: &q };
        let solved = solve_whole(whole, &load, start, &opts);
        let (out, m) = (self.outcome(&solved, &opts), points.len());
        let tangent_rows = (&self.rows.tangent_row[..], &self.rows.tangent_row2[..]);
        let mut friction = friction_state(tangent_rows, self.fr, &mut self.history, &out, m);
        let slip = (&loads.u_p[..], length);
        let lambda_n = &out.forces[..m];
        prescribed_slip_friction(
            bodies,
            points,
            self.fr,
            slip,
            &mut self.history,
            &mut friction,
            lambda_n,
        );
        let u_full = full_displacements(bodies, system, &loads.u_p, &solved.u);
        self.start = Some((solved.u, solved.lambda));
        let mut outcome = out;
        outcome.forces.truncate(m);
        outcome.gaps.truncate(m);
        self.check_balance(&mut outcome, (&loads.f, f_scale), &friction);
        let res = direct_residuals(
            bodies,
            &system.k_full,
            points,
            &loads.forces,
            &u_full,
            &outcome.forces,
            Some(&friction),
        );
        let gaps = gaps_of(points, &u_full);
        let sol = StepSolution {
            outcome,
            gap0,
            f_scale,
            length_scale: length,
            regularisation: None,
            law_k: vec![0.0; m],
            friction: Some(friction),
            solve_s: started.elapsed().as_secs_f64(),
            operator_s: 0.0,
        };
        Ok((sol, gaps, res, u_full))
    }

    /// Marks a converged `outcome` not converged when its forces leave a
    /// rigid motion of a body held by contact alone unbalanced
    /// ([`rigid_motion_imbalance`] above √tolerance: far above the
    /// rounding and the regularisation of a balanced solve, far below the
    /// imbalance of a load with no equilibrium, of the order of the load);
    /// `f` the step's load on the free DOFs, `f_scale` its force scale.
    fn check_balance(
        &self,
        outcome: &mut ContactSolution,
        (f, f_scale): (&[f64], f64),
        friction: &FrictionStep,
    ) {
        let bodies = self.bodies;
        if !outcome.report.converged || bodies.iter().all(|b| b.kernel.is_empty()) {
            return;
        }
        let contact = contact_forces(bodies, self.points, &outcome.forces, Some(friction));
        let offset = &self.system.offset;
        let f_of: Vec<&[f64]> = (bodies.iter().zip(offset))
            .map(|(b, &o)| &f[o..o + b.free.len()])
            .collect();
        let imbalance = rigid_motion_imbalance(bodies, &f_of, &contact, f_scale);
        if imbalance > self.sc.solver.tolerance.sqrt() {
            outcome.report.converged = false;
            outcome.report.stop = StopReason::RigidMotionUnbalanced {
                iterations: outcome.report.iterations,
                imbalance,
            };
        }
    }

    /// The first step's start: no displacement, no force, but on the points
    /// the condensed path starts closed (initially closed within the
    /// tolerance, or on a body held by contact alone:
    /// [`initial_statuses`]) a normal force that closes them (λ_n > ρ y_n:
    /// twice ρ times the initial gap, at least the tolerance times the force
    /// scale), and with it a positive Coulomb threshold: they start closed and
    /// stuck, and the Newton steps open those whose force comes out tensile.
    fn cold_start(&self, q: &[f64], rho: &[f64], scales: (f64, f64)) -> (Vec<f64>, Vec<f64>) {
        let (f_scale, length) = scales;
        let tolerance = self.sc.solver.tolerance;
        let m = self.points.len();
        let closed = initial_statuses(self.bodies, self.points, &q[..m], tolerance * length, true);
        let least = (tolerance * f_scale).max(f64::MIN_POSITIVE);
        let mut lambda = vec![0.0; q.len()];
        for (pi, status) in closed.iter().enumerate() {
            if *status != PointStatus::Open {
                lambda[pi] = (2.0 * rho[pi] * q[pi].max(0.0)).max(least);
            }
        }
        (vec![0.0; self.system.n_free], lambda)
    }

    /// The contact solution of a whole-system solve (every row), with the
    /// friction statuses and the report of the method.
    fn outcome(&self, solved: &WholeSolution, opts: &FrictionOptions) -> ContactSolution {
        let dim = if self.fr.three_d { 3 } else { 2 };
        let layout = &self.fr.layout;
        let points = statuses(layout, &solved.lambda, &solved.gaps, opts, dim);
        let method = if layout.has_coulomb() {
            "coulomb_direct_semismooth_newton"
        } else {
            "tresca_direct_semismooth_newton"
        };
        let report = SolverReport {
            method: method.into(),
            converged: solved.converged,
            iterations: solved.iterations,
            operator_applications: solved.iterations,
            residual_history: solved.residual_history.clone(),
            stop: solved.reason.clone(),
        };
        let mut out = ContactSolution::with_gaps(
            solved.lambda.clone(),
            solved.gaps.clone(),
            Vec::new(),
            report,
        );
        out.active = (0..points.len())
            .filter(|&p| points[p] != PointStatus::Open)
            .collect();
        out.friction.points = points;
        out
    }
}

/// Whether any point of the model has a friction unknown.
pub(crate) fn has_friction(points: &[PointModel]) -> bool {
    points
        .iter()
        .any(|p| p.trow.is_some() && p.friction != FrictionLaw::None)
}
