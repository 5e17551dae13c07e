//! The direct path: the status method on the whole sparse stiffness with
//! the contact constraints as Lagrange multipliers (a finite-element KKT
//! solve refactorised at each status iteration, course notes §3.3), to check and to
//! benchmark condensation.

use crate::checks::inf_norm;
use crate::conditioning;
use crate::direct_friction::{has_friction, run_direct_friction};
use crate::direct_system::{
    assemble_direct, check_floating, direct_loads, direct_residuals, full_displacements,
    tied_residual, DirectSystem,
};
use crate::error::{contact_error, SolveError};
use crate::kkt::{ldlt_factorisation, DirectProblem, KktSystem};
use crate::model::{gaps_of, BodyModel, FixedPoint, PointModel};
use crate::progress::Phase;
use crate::root::{length_scale, status_options, status_report, step_gaps};
use crate::run_context::{RunContext, RunLog};
use crate::step::{Residuals, StepSolution};
use crate::step_end::StepLoop;
use crate::timing::timed;
use signorini_contact::status_method;
use signorini_scene as scene;
use std::time::Instant;

/// The direct path on the root: every body's whole sparse stiffness, the
/// contact constraints added by Lagrange multipliers and the saddle-point
/// matrix refactorised at each status iteration (course notes §3.3); each step
/// ended (`steps`) before the next is solved.
pub(crate) fn run_direct(
    ctx: RunContext,
    steps: &mut StepLoop,
    log: &mut RunLog,
) -> Result<(), SolveError> {
    let (sc, model) = (ctx.sc, ctx.model);
    let (bodies, points) = (&model.bodies[..], &model.points[..]);
    ctx.progress.phase(Phase::Assembling);
    let system = timed(&mut log.timings.assemble, || {
        assemble_direct(bodies, &model.tied)
    })?;
    if has_friction(points) {
        // friction beside ties is refused by the plan (check_direct_friction)
        return run_direct_friction(&ctx, &system, steps, log);
    }
    let rows: Vec<Vec<(usize, f64)>> = points
        .iter()
        .map(|p| {
            let row: Vec<(usize, f64)> = p
                .row
                .iter()
                .filter(|&&(b, d, _)| !bodies[b].prescribed[d])
                .map(|&(b, d, c)| (system.offset[b] + bodies[b].free_index[d], c))
                .collect();
            match &system.ties {
                Some(t) => t.row(&row),
                None => row,
            }
        })
        .collect();
    ctx.progress.phase(Phase::Contact);
    let floating = bodies.iter().any(|b| !b.kernel.is_empty());
    let mut kkt = timed(&mut log.timings.contact, || {
        KktSystem::new(&system.k_global, &rows, floating).map_err(contact_error)
    })?;
    // One more factorisation, of K alone (the KKT's ordering), timed apart,
    // when the scene asks for it (solver.condition_estimate).
    let estimate = sc.solver.condition_estimate;
    let mut conditioning = || {
        conditioning::direct(
            &mut kkt,
            (floating, estimate),
            sc.solver.tolerance,
            &mut log.messages,
        )
    };
    let conditioning = match estimate {
        true => timed(&mut log.timings.conditioning, conditioning),
        false => conditioning(),
    };
    for (si, st) in model.scales.iter().enumerate() {
        ctx.progress.step(si, model.scales.len());
        let ((sol, gaps, res), u_full) = timed(&mut log.timings.contact, || {
            direct_step(sc, bodies, points, &model.fixed, &system, &mut kkt, st, si)
        })?;
        timed(&mut log.timings.output, || {
            steps.end_step(si, &sol, &gaps, &res, u_full, &mut log.messages)
        })?;
    }
    let partial = &mut steps.partial;
    partial.factorisation = Some(kkt_factorisation(&kkt));
    partial.factor_bytes = 8 * kkt.ordered().stats.values as u64;
    partial.conditioning = Some(conditioning);
    partial.dofs = system.n_free;
    Ok(())
}

/// The KKT factorisation of the run for report.json: its ordering, size and
/// flops (of one factorisation), how many were done, the refinement steps
/// and the LU fallbacks.
fn kkt_factorisation(kkt: &KktSystem<'_>) -> signorini_report::Factorisation {
    ldlt_factorisation(kkt.ordered(), "ldlt", kkt.counts)
}

/// A step's solution with its final gaps, residuals and largest
/// displacement, as [`conclude_step`] takes them.
type DirectStep = (StepSolution, Vec<f64>, Residuals);

/// One load step of the direct path: the loads on the free DOFs, the
/// floating bodies' equilibrium checked, the status method on the KKT
/// system; returns the step and each body's full displacement.
#[allow(clippy::too_many_arguments)]
fn direct_step(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    fixed: &[FixedPoint],
    system: &DirectSystem,
    kkt: &mut KktSystem<'_>,
    st: &[Vec<f64>],
    si: usize,
) -> Result<(DirectStep, Vec<Vec<f64>>), SolveError> {
    let started = Instant::now();
    let loads = direct_loads(bodies, system, st);
    let f_scale = loads.f_scale;
    let length_scale = length_scale(bodies, points, &loads.u_p, f_scale);
    let gap0 = step_gaps(sc, bodies, points, fixed, &loads.u_p, length_scale, si)?;
    check_floating(bodies, points, system, &loads, si)?;
    let f = match &system.ties {
        Some(t) => t.fold(&loads.f),
        None => loads.f.clone(),
    };
    let mut problem = DirectProblem::new(kkt, &f, &gap0);
    let mut opts = status_options(sc, f_scale, length_scale, &gap0);
    opts.deadline = Some(system.deadline(sc.solver.time_limit, points.len()));
    let mut outcome = status_method(&mut problem, &opts).map_err(contact_error)?;
    // `problem.u` is the displacement of the last solve, the one that
    // gave `outcome.forces` (as the condensed path recovers it).
    let u = match &system.ties {
        Some(t) => t.expand(&problem.u),
        None => problem.u.clone(),
    };
    let u_full = full_displacements(bodies, system, &loads.u_p, &u);
    status_report(&mut outcome, "status", problem.factorisations);
    let sol = StepSolution {
        outcome,
        gap0,
        f_scale,
        length_scale,
        regularisation: None,
        law_k: vec![0.0; points.len()],
        friction: None,
        solve_s: started.elapsed().as_secs_f64(),
        operator_s: 0.0,
    };
    let lambda = &sol.outcome.forces;
    let mut res = direct_residuals(
        bodies,
        &system.k_full,
        points,
        &loads.forces,
        &u_full,
        lambda,
        None,
    );
    if let Some(t) = &system.ties {
        let r = tied_residual(bodies, system, &loads.forces, &u_full, points, lambda);
        res.equilibrium = inf_norm(&t.fold(&r));
        let dim = sc.dimension as usize;
        res.ties = system.tied.forces(dim, |b, d| {
            let i = bodies[b].free_index[d];
            if i == usize::MAX {
                0.0
            } else {
                r[system.offset[b] + i]
            }
        });
    }
    let gaps = gaps_of(points, &u_full);
    Ok(((sol, gaps, res), u_full))
}
