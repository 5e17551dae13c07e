//! The direct path: the status method on the whole sparse stiffness with
//! the contact constraints as Lagrange multipliers (a finite-element KKT
//! solve refactorised at each status iteration, course notes §3.3), to check and to
//! benchmark condensation.

use crate::checks::check_floating_equilibrium;
use crate::checks::inf_norm;
use crate::conditioning;
use crate::direct_friction::{has_friction, run_direct_friction};
use crate::error::{contact_error, SolveError};
use crate::kkt::{DirectProblem, KktSystem};
use crate::model::{gaps_of, BodyModel, FixedPoint, PointModel, Ties};
use crate::progress::Phase;
use crate::root::{body_step, length_scale, resultant, status_options, status_report, step_gaps};
use crate::run_context::RunContext;
use crate::step::{FrictionStep, Residuals, StepSolution};
use crate::step_end::StepLoop;
use crate::ties::TieReduction;
use crate::timing::timed;
use faer::sparse::SparseColMat;
use signorini_condense::{spmv, spmv_with_magnitude, submatrix};
use signorini_contact::status_method;
use signorini_report::Timings;
use signorini_scene as scene;
use std::time::Instant;

/// The direct path on the root: every body's whole sparse stiffness, the
/// contact constraints added by Lagrange multipliers and the saddle-point
/// matrix refactorised at each status iteration (course notes §3.3); each step
/// ended (`steps`) before the next is solved.
pub(crate) fn run_direct(
    ctx: RunContext,
    steps: &mut StepLoop,
    timings: &mut Timings,
    messages: &mut Vec<String>,
) -> Result<(), SolveError> {
    let (sc, model) = (ctx.sc, ctx.model);
    let (bodies, points) = (&model.bodies[..], &model.points[..]);
    ctx.progress.phase(Phase::Assembling);
    let system = timed(&mut timings.assemble, || {
        assemble_direct(bodies, &model.tied)
    })?;
    if has_friction(points) {
        // friction beside ties is refused by the plan (check_direct_friction)
        return run_direct_friction(&ctx, &system, steps, timings, messages);
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
    let mut kkt = timed(&mut timings.contact, || {
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
            messages,
        )
    };
    let conditioning = match estimate {
        true => timed(&mut timings.conditioning, conditioning),
        false => conditioning(),
    };
    for (si, st) in model.scales.iter().enumerate() {
        ctx.progress.step(si, model.scales.len());
        let ((sol, gaps, res), u_full) = timed(&mut timings.contact, || {
            direct_step(sc, bodies, points, &model.fixed, &system, &mut kkt, st, si)
        })?;
        timed(&mut timings.output, || {
            steps.end_step(si, &sol, &gaps, &res, u_full, messages)
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
    let ordered = kkt.ordered();
    let stats = ordered.stats;
    signorini_report::Factorisation {
        kind: "ldlt".into(),
        ordering: stats.ordering.as_str().into(),
        factor_nnz: stats.nnz as u64,
        factor_bytes: 8 * stats.values as u64,
        flops: stats.flops,
        candidates: ordered
            .candidates
            .iter()
            .map(|c| signorini_report::OrderingCandidate {
                ordering: c.ordering.as_str().into(),
                factor_nnz: c.nnz as u64,
                flops: c.flops,
            })
            .collect(),
        factorisations: Some(kkt.counts.factorisations),
        refinement_steps: Some(kkt.counts.refinement_steps),
        lu_fallbacks: Some(kkt.counts.lu_fallbacks),
        interface: None,
    }
}

/// The stiffness of the direct path: each body's whole stiffness, and the
/// global one over the free DOFs of all bodies, body after body.
pub(crate) struct DirectSystem {
    pub(crate) k_full: Vec<SparseColMat<usize, f64>>,
    /// Where each body's free DOFs start in the global numbering.
    pub(crate) offset: Vec<usize>,
    pub(crate) k_global: SparseColMat<usize, f64>,
    pub(crate) n_free: usize,
    /// The elimination of the tied DOFs from the free ones (`crate::ties`):
    /// `k_global` is then Tᵀ K T.
    pub(crate) ties: Option<TieReduction>,
    /// The tied DOFs (for the ties' forces).
    tied: Ties,
}

/// Assembles every body's stiffness and the global stiffness on the free
/// DOFs (the bodies' free-free blocks on the diagonal).
fn assemble_direct(bodies: &[BodyModel], tied: &Ties) -> Result<DirectSystem, SolveError> {
    let mut k_full = Vec::new();
    let mut offset = Vec::new();
    let mut triplets = Vec::new();
    let mut n_free = 0;
    for b in bodies {
        let par = faer::get_global_parallelism();
        let k = signorini_fem::try_assemble_stiffness_par(&b.mesh, &b.material, par)
            .map_err(|e| SolveError::Input(format!("bodies[{}].mesh: {e}", b.scene_index)))?;
        let kff = submatrix(k.as_ref(), &b.free, &b.free);
        for j in 0..kff.ncols() {
            for (&i, &v) in kff.row_idx_of_col_raw(j).iter().zip(kff.val_of_col(j)) {
                triplets.push(faer::sparse::Triplet::new(n_free + i, n_free + j, v));
            }
        }
        offset.push(n_free);
        n_free += b.free.len();
        k_full.push(k);
    }
    let mut k_global = SparseColMat::<usize, f64>::try_new_from_triplets(n_free, n_free, &triplets)
        .map_err(|e| SolveError::Internal(format!("{e:?}")))?;
    let index: Vec<Vec<usize>> = bodies
        .iter()
        .zip(&offset)
        .map(|(b, &o)| {
            (b.free_index.iter())
                .map(|&i| if i == usize::MAX { i } else { o + i })
                .collect()
        })
        .collect();
    let ties = TieReduction::new(tied, &index, n_free);
    if let Some(t) = &ties {
        k_global = t.reduce_matrix(&k_global)?;
    }
    Ok(DirectSystem {
        k_full,
        offset,
        k_global,
        n_free,
        ties,
        tied: tied.clone(),
    })
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
    let mut outcome = status_method(
        &mut problem,
        &status_options(sc, f_scale, length_scale, &gap0),
    )
    .map_err(contact_error)?;
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

/// Checks that each floating body's loads can be balanced by contact
/// (`check_floating_equilibrium`): the work e = −Rᵀ f of the free load on
/// its rigid motions, and the resultant of its external force.
pub(crate) fn check_floating(
    bodies: &[BodyModel],
    points: &[PointModel],
    system: &DirectSystem,
    loads: &DirectLoads,
    si: usize,
) -> Result<(), SolveError> {
    let e_of: Vec<Vec<f64>> = bodies
        .iter()
        .enumerate()
        .map(|(bi, b)| {
            b.kernel
                .iter()
                .map(|r| {
                    -b.free
                        .iter()
                        .enumerate()
                        .map(|(i, &d)| r[d] * loads.f[system.offset[bi] + i])
                        .sum::<f64>()
                })
                .collect()
        })
        .collect();
    let res: Vec<Vec<f64>> = loads
        .forces
        .iter()
        .zip(bodies)
        .map(|(f, b)| resultant(f, b.mesh.dim))
        .collect();
    check_floating_equilibrium(bodies, points, &e_of, &res, si)?;
    Ok(())
}

/// Each body's full displacement: the prescribed `u_p`, and on its free
/// DOFs the global solution `u`.
pub(crate) fn full_displacements(
    bodies: &[BodyModel],
    system: &DirectSystem,
    u_p: &[Vec<f64>],
    u: &[f64],
) -> Vec<Vec<f64>> {
    bodies
        .iter()
        .enumerate()
        .map(|(bi, b)| {
            let mut full = u_p[bi].clone();
            for (i, &d) in b.free.iter().enumerate() {
                full[d] = u[system.offset[bi] + i];
            }
            full
        })
        .collect()
}

/// The loads of a step on the direct path.
pub(crate) struct DirectLoads {
    /// Global load on the free DOFs: f − K u_p.
    pub(crate) f: Vec<f64>,
    /// Each body's prescribed displacement.
    pub(crate) u_p: Vec<Vec<f64>>,
    /// Each body's external force.
    pub(crate) forces: Vec<Vec<f64>>,
    /// The largest external or free-DOF load entry.
    pub(crate) f_scale: f64,
}

/// A step's loads: each body's prescribed displacement and force at the
/// step's scales, and the global load f − K u_p on the free DOFs.
pub(crate) fn direct_loads(
    bodies: &[BodyModel],
    system: &DirectSystem,
    st: &[Vec<f64>],
) -> DirectLoads {
    let mut f = vec![0.0; system.n_free];
    let mut u_p = Vec::new();
    let mut forces = Vec::new();
    let mut f_scale = 0.0f64;
    for (bi, b) in bodies.iter().enumerate() {
        let (u, force) = body_step(b, &st[bi]);
        let ku = spmv(system.k_full[bi].as_ref(), &u);
        for (i, &d) in b.free.iter().enumerate() {
            f[system.offset[bi] + i] = force[d] - ku[d];
        }
        f_scale = f_scale.max(inf_norm(&force));
        u_p.push(u);
        forces.push(force);
    }
    f_scale = f_scale.max(inf_norm(&f));
    DirectLoads {
        f,
        u_p,
        forces,
        f_scale,
    }
}

/// Equilibrium residual of the direct path on the free DOFs of every body:
/// K u − f − Bᵀλ (with `friction`, the tangential rows times the
/// tangential forces in Bᵀλ); and K u − f on the prescribed ones (the
/// reactions).
pub(crate) fn direct_residuals(
    bodies: &[BodyModel],
    k_full: &[SparseColMat<usize, f64>],
    points: &[PointModel],
    forces: &[Vec<f64>],
    u_full: &[Vec<f64>],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
) -> Residuals {
    let mut contact_force: Vec<Vec<f64>> = bodies.iter().map(|b| vec![0.0; b.n_dof]).collect();
    for (pi, (p, &l)) in points.iter().zip(lambda).enumerate() {
        let (t1, t2) = friction.map_or((0.0, 0.0), |f| (f.tangential[pi], f.tangential2[pi]));
        let rows = [
            (Some(&p.row), l),
            (p.trow.as_ref(), t1),
            (p.trow2.as_ref(), t2),
        ];
        for (row, force) in rows.into_iter().filter_map(|(r, f)| r.map(|r| (r, f))) {
            for &(b, d, c) in row {
                contact_force[b][d] += c * force;
            }
        }
    }
    let mut eq = 0.0f64;
    let mut scale = 0.0f64;
    let mut support = Vec::new();
    for (bi, b) in bodies.iter().enumerate() {
        let (ku, abs_ku) = spmv_with_magnitude(k_full[bi].as_ref(), &u_full[bi]);
        support.extend(
            (0..b.n_dof)
                .filter(|&d| b.prescribed[d])
                .map(|d| (bi, d, ku[d] - forces[bi][d])),
        );
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
        support,
        ties: Vec::new(),
    }
}

/// The residual K u − f − Bᵀλ on the free DOFs of every body (in the
/// global numbering): at the tied slave DOFs, the force the tie exerts; the
/// equilibrium residual is Tᵀ r (the tie's forces are internal).
fn tied_residual(
    bodies: &[BodyModel],
    system: &DirectSystem,
    forces: &[Vec<f64>],
    u_full: &[Vec<f64>],
    points: &[PointModel],
    lambda: &[f64],
) -> Vec<f64> {
    let mut r = vec![0.0; system.n_free];
    for (bi, b) in bodies.iter().enumerate() {
        let ku = spmv(system.k_full[bi].as_ref(), &u_full[bi]);
        for (i, &d) in b.free.iter().enumerate() {
            r[system.offset[bi] + i] = ku[d] - forces[bi][d];
        }
    }
    for (p, &l) in points.iter().zip(lambda) {
        for &(b, d, c) in p.row.iter().filter(|&&(b, d, _)| !bodies[b].prescribed[d]) {
            r[system.offset[b] + bodies[b].free_index[d]] -= c * l;
        }
    }
    r
}
