//! The pipeline of DESIGN.md §1: scene → meshes → per-body stiffness,
//! condensation on the interface (seed §8.2) → root: interface problem,
//! contact geometry, contact algorithm → interior recovery → report.
//!
//! The direct path (`path = "direct"`) solves the same contact problem on
//! the whole sparse stiffness instead, refactorised at each status iteration
//! (seed §3.3), for checking and benchmarking the condensed path.

pub mod model;

use std::collections::BTreeMap;
use std::time::Instant;

use faer::{Mat, Par};
use signorini_condense::{spmv, Condensed};
use signorini_contact::direct::DirectProblem;
use signorini_contact::equilibrium::nnls;
use signorini_contact::{
    status_method, ContactError, DelassusProblem, StatusOptions, StatusOutcome, StatusVariant,
};
use signorini_report::{
    reference, Certificate, ContactRow, ContactSummary, Memory, Probe, Report, StepReport, Timings,
};
use signorini_scene as scene;

use model::{BodyModel, PointModel};

/// What went wrong, with the exit code it maps to.
#[derive(Debug, thiserror::Error)]
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
    /// Displacement, `dim` values per node.
    pub displacement: Vec<f64>,
    /// Per cell: [sxx, syy, sxy, szz].
    pub stress: Vec<[f64; 4]>,
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

/// Per-step state on every body.
struct StepLoads {
    /// Load on the free DOFs of each body.
    free_load: Vec<Vec<f64>>,
    /// External force on all DOFs of each body.
    force: Vec<Vec<f64>>,
    /// Prescribed displacement on all DOFs of each body.
    displacement: Vec<Vec<f64>>,
}

fn step_loads(sc: &scene::Scene, bodies: &[BodyModel], step: &BTreeMap<String, f64>) -> StepLoads {
    let mut out = StepLoads {
        free_load: vec![],
        force: vec![],
        displacement: vec![],
    };
    for b in bodies {
        let s = b.scales(sc, step);
        let fl = b.combine(&s, |l| &l.free_load);
        out.free_load.push(if fl.is_empty() {
            vec![0.0; b.free.len()]
        } else {
            fl
        });
        let f = b.combine(&s, |l| &l.force);
        out.force
            .push(if f.is_empty() { vec![0.0; b.n_dof] } else { f });
        let d = b.combine(&s, |l| &l.displacement);
        out.displacement
            .push(if d.is_empty() { vec![0.0; b.n_dof] } else { d });
    }
    out
}

/// Runs a scene.
pub fn run(
    sc: &scene::Scene,
    scene_name: &str,
    opts: &RunOptions,
) -> Result<RunOutput, SolveError> {
    let t_total = Instant::now();
    let mut timings = Timings::default();
    let method = opts.method.unwrap_or(sc.solver.method);
    let path = opts.path.unwrap_or(sc.solver.path);
    if method != scene::Method::Status {
        return Err(SolveError::Input(format!(
            "solver.method: \"{}\" is not supported yet (supported: status)",
            method.as_str()
        )));
    }
    let condensed_path = path == scene::SolvePath::Condensed;
    let mut messages = Vec::new();
    let mut stages = vec!["mesh".to_string(), "assemble".to_string()];

    // Setup and assembly.
    let t = Instant::now();
    let mut bodies = model::build_bodies(sc)?;
    let (points, fixed_points) = model::build_contacts(sc, &mut bodies)?;
    if !fixed_points.is_empty() {
        messages.push(format!(
            "{} slave node(s) have every normal DOF prescribed: their gap is known and they are not contact unknowns",
            fixed_points.len()
        ));
    }
    timings.assemble = t.elapsed().as_secs_f64();
    timings.setup = 0.0;
    for b in &bodies {
        if !b.kernel.is_empty() {
            let touched = points
                .iter()
                .any(|p| p.row.iter().any(|&(bi, _, _)| std::ptr::eq(&bodies[bi], b)));
            if !touched {
                return Err(SolveError::Input(format!(
                    "bodies[{}]: body \"{}\" has no support that prevents its rigid motion and no contact; add a [[boundary]] displacement",
                    b.scene_index, b.name
                )));
            }
            messages.push(format!(
                "body \"{}\" is held by contact in {} rigid motion(s): solved with the equilibrium of its rigid modes as a constraint (no artificial spring)",
                b.name,
                b.kernel.len()
            ));
        }
    }
    let m = points.len();
    let dofs: usize = bodies.iter().map(|b| b.free.len()).sum();

    // Condensation of each body on its interface (seed §8.2).
    let t = Instant::now();
    let mut condensed: Vec<Condensed> = Vec::new();
    let mut gamma_offset = Vec::new();
    let mut n_gamma = 0;
    for b in &bodies {
        gamma_offset.push(n_gamma);
        n_gamma += b.interface.len();
    }
    if condensed_path {
        stages.push("condense".into());
        for b in &bodies {
            let c = Condensed::new(b.k_ff.as_ref(), &b.interface, Par::Seq).map_err(|e| {
                SolveError::Input(format!("bodies[{}] \"{}\": {e}", b.scene_index, b.name))
            })?;
            condensed.push(c);
        }
    }
    timings.condense = t.elapsed().as_secs_f64();

    // Dense interface stiffness S (block diagonal over bodies) and kernel.
    let mut s_global = Mat::<f64>::zeros(
        if condensed_path { n_gamma } else { 0 },
        if condensed_path { n_gamma } else { 0 },
    );
    let n_kernel: usize = bodies.iter().map(|b| b.kernel.len()).sum();
    let mut kernel_gamma = Mat::<f64>::zeros(if condensed_path { n_gamma } else { 0 }, n_kernel);
    if condensed_path {
        let mut col = 0;
        for (bi, (b, c)) in bodies.iter().zip(&condensed).enumerate() {
            let o = gamma_offset[bi];
            for j in 0..b.interface.len() {
                for i in 0..b.interface.len() {
                    s_global[(o + i, o + j)] = c.schur[(i, j)];
                }
            }
            for r in &b.kernel {
                for (i, &d) in b.interface.iter().enumerate() {
                    kernel_gamma[(o + i, col)] = r[d];
                }
                col += 1;
            }
        }
    }
    // Global free-DOF numbering for the direct path.
    let mut free_offset = Vec::new();
    let mut n_free = 0;
    for b in &bodies {
        free_offset.push(n_free);
        n_free += b.free.len();
    }
    let k_global = if condensed_path {
        None
    } else {
        let mut t = Vec::new();
        for (bi, b) in bodies.iter().enumerate() {
            let o = free_offset[bi];
            for j in 0..b.k_ff.ncols() {
                for (&i, &v) in b
                    .k_ff
                    .row_idx_of_col_raw(j)
                    .iter()
                    .zip(b.k_ff.val_of_col(j))
                {
                    t.push(faer::sparse::Triplet::new(o + i, o + j, v));
                }
            }
        }
        Some(
            faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n_free, n_free, &t)
                .map_err(|e| SolveError::Internal(format!("{e:?}")))?,
        )
    };

    let steps = sc.step_scales();
    let mut step_reports = Vec::new();
    let mut contact_rows = Vec::new();
    let mut converged = true;
    let mut failure: Option<String> = None;
    let mut last: Option<(Vec<Vec<f64>>, Vec<f64>, StepLoads)> = None;
    let e_max = bodies.iter().fold(0.0f64, |a, b| a.max(b.material.young));
    let mut t_contact = 0.0;
    let mut t_recover = 0.0;
    let mut certificate = Certificate::default();
    if m > 0 {
        stages.push("contact".into());
    }
    stages.push("recover".into());
    if steps.len() > 1 {
        stages.push(format!("steps ({})", steps.len()));
    }
    for (si, step) in steps.iter().enumerate() {
        let loads = step_loads(sc, &bodies, step);
        // Gaps at this step: g0 + contribution of prescribed DOFs.
        let gap0: Vec<f64> = points
            .iter()
            .map(|p| {
                p.gap0
                    + p.row
                        .iter()
                        .filter(|&&(b, d, _)| bodies[b].prescribed[d])
                        .map(|&(b, d, c)| c * loads.displacement[b][d])
                        .sum::<f64>()
            })
            .collect();
        let f_scale = loads
            .free_load
            .iter()
            .chain(&loads.force)
            .fold(0.0f64, |a, v| a.max(inf_norm(v)));
        let u_p_scale = loads
            .displacement
            .iter()
            .fold(0.0f64, |a, v| a.max(inf_norm(v)));
        let length_scale = u_p_scale.max(inf_norm(&gap0)).max(f_scale / e_max);
        check_floating_equilibrium(&bodies, &points, &loads, si)?;
        for fp in &fixed_points {
            let g = fp.gap0
                + fp.row
                    .iter()
                    .map(|&(b, d, c)| c * loads.displacement[b][d])
                    .sum::<f64>();
            if g < -sc.solver.tolerance * length_scale {
                let x = bodies[fp.row[0].0].mesh.coords[fp.node];
                return Err(SolveError::Input(format!(
                    "contact \"{}\": at step {} the prescribed displacements push slave node ({}, {}) through the master (gap {g:e}); a prescribed node cannot be held back by contact",
                    sc.contact[fp.contact].name, si + 1, x[0], x[1]
                )));
            }
        }
        let status_opts = StatusOptions {
            variant: StatusVariant::All,
            max_iterations: sc.solver.max_iterations,
            tolerance: sc.solver.tolerance,
            force_scale: f_scale,
            gap_scale: length_scale,
            initial_active: None,
        };
        let t = Instant::now();
        let (outcome, u_free): (StatusOutcome, Vec<Vec<f64>>) = if condensed_path {
            let mut fp = vec![0.0; n_gamma];
            for (bi, c) in condensed.iter().enumerate() {
                let f = c.condensed_load(&loads.free_load[bi]);
                fp[gamma_offset[bi]..gamma_offset[bi] + f.len()].copy_from_slice(&f);
            }
            let rows: Vec<Vec<(usize, f64)>> = points
                .iter()
                .map(|p| {
                    p.row
                        .iter()
                        .filter(|&&(b, d, _)| !bodies[b].prescribed[d])
                        .map(|&(b, d, c)| {
                            let local = bodies[b].free_index[d];
                            let pos = bodies[b]
                                .interface
                                .binary_search(&local)
                                .expect("contact DOFs are interface DOFs");
                            (gamma_offset[b] + pos, c)
                        })
                        .collect()
                })
                .collect();
            let mut problem = DelassusProblem::new(&s_global, &rows, &gap0, &fp, &kernel_gamma)
                .map_err(contact_error)?;
            let outcome = if m > 0 {
                status_method(&mut problem, &status_opts).map_err(contact_error)?
            } else {
                use signorini_contact::ActiveSetSolve;
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
            };
            let u_gamma = problem.displacement(&outcome.lambda);
            t_contact += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let u_free = bodies
                .iter()
                .enumerate()
                .map(|(bi, b)| {
                    let ub = &u_gamma[gamma_offset[bi]..gamma_offset[bi] + b.interface.len()];
                    condensed[bi].recover(b.k_ff.as_ref(), &loads.free_load[bi], ub)
                })
                .collect();
            t_recover += t.elapsed().as_secs_f64();
            (outcome, u_free)
        } else {
            let k = k_global.as_ref().expect("built for the direct path");
            let mut f = vec![0.0; n_free];
            for (bi, fl) in loads.free_load.iter().enumerate() {
                f[free_offset[bi]..free_offset[bi] + fl.len()].copy_from_slice(fl);
            }
            let rows: Vec<Vec<(usize, f64)>> = points
                .iter()
                .map(|p| {
                    p.row
                        .iter()
                        .filter(|&&(b, d, _)| !bodies[b].prescribed[d])
                        .map(|&(b, d, c)| (free_offset[b] + bodies[b].free_index[d], c))
                        .collect()
                })
                .collect();
            let mut problem = DirectProblem::new(k, &f, &rows, &gap0);
            let outcome = status_method(
                &mut problem,
                &StatusOptions {
                    ..status_opts.clone()
                },
            )
            .map_err(contact_error)?;
            // Re-solve with the final active set so that `problem.u` is the answer.
            use signorini_contact::ActiveSetSolve;
            let _ = problem
                .solve_active(&outcome.active)
                .map_err(contact_error)?;
            t_contact += t.elapsed().as_secs_f64();
            let u_free = bodies
                .iter()
                .enumerate()
                .map(|(bi, b)| problem.u[free_offset[bi]..free_offset[bi] + b.free.len()].to_vec())
                .collect();
            (outcome, u_free)
        };
        // Full displacement of each body.
        let u_full: Vec<Vec<f64>> = bodies
            .iter()
            .enumerate()
            .map(|(bi, b)| {
                let mut u = loads.displacement[bi].clone();
                for (i, &d) in b.free.iter().enumerate() {
                    u[d] = u_free[bi][i];
                }
                u
            })
            .collect();
        let lambda = outcome.lambda.clone();
        let cert = certify(
            &bodies,
            &points,
            &loads,
            &u_full,
            &lambda,
            f_scale,
            length_scale,
            sc.solver.tolerance,
        );
        if !outcome.converged {
            converged = false;
            failure.get_or_insert(format!(
                "step {}: status method: {}",
                si + 1,
                outcome.stopping_reason
            ));
        } else if cert.max() > cert.tolerance {
            converged = false;
            failure.get_or_insert(format!(
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
        // contact.csv rows.
        let gaps = gaps_of(&points, &u_full);
        for (pi, p) in points.iter().enumerate() {
            let l = lambda[pi];
            contact_rows.push(ContactRow {
                step: si + 1,
                contact: sc.contact[p.contact].name.clone(),
                body: bodies[p.slave_body].name.clone(),
                point: p.point.slave_node,
                x: p.point.x,
                gap: gaps[pi],
                normal_force: l,
                tangential_force: 0.0,
                slip: 0.0,
                pressure: if p.tributary > 0.0 {
                    l / p.tributary
                } else {
                    0.0
                },
                status: if outcome.active.binary_search(&pi).is_ok() {
                    "contact"
                } else {
                    "open"
                },
            });
        }
        step_reports.push(StepReport {
            scale: step.clone(),
            iterations: outcome.iterations,
            active: outcome.active.len(),
            sticking: 0,
            slipping: 0,
            converged: outcome.converged && cert.max() <= cert.tolerance,
            stopping_reason: outcome.stopping_reason.clone(),
            active_history: outcome.active_history.clone(),
            cycle_detected_at: outcome.cycle_detected_at,
        });
        certificate = cert;
        last = Some((u_full, lambda, loads));
    }
    timings.contact = t_contact;
    timings.recover = t_recover;
    let (u_full, lambda, _loads) =
        last.ok_or_else(|| SolveError::Internal("no load step ran".into()))?;

    // Resultants.
    let mut contact_force = vec![0.0; 2];
    let mut summaries: Vec<ContactSummary> = sc
        .contact
        .iter()
        .map(|c| ContactSummary {
            name: c.name.clone(),
            points: 0,
            active: 0,
            force: vec![0.0; 2],
        })
        .collect();
    for (pi, p) in points.iter().enumerate() {
        let s = &mut summaries[p.contact];
        s.points += 1;
        if lambda[pi] != 0.0 {
            s.active += 1;
        }
        for (k, n) in p.point.normal.iter().take(2).enumerate() {
            s.force[k] += lambda[pi] * n;
            contact_force[k] += lambda[pi] * n;
        }
    }

    // Probes.
    let mut probes = Vec::new();
    for pr in &sc.output.probes {
        let x = [pr[0], pr.get(1).copied().unwrap_or(0.0), 0.0];
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
                displacement: vec![u_full[bi][n * 2], u_full[bi][n * 2 + 1]],
            });
        }
    }

    // Reference.
    let reference = match &sc.reference {
        None => None,
        Some(r) => Some(compare_reference(sc, r, &bodies, &points, &lambda)?),
    };

    // Fields.
    let mut results = Vec::new();
    let want_stress = sc.output.wants("stress");
    if want_stress {
        stages.push("stress".into());
    }
    for (bi, b) in bodies.iter().enumerate() {
        let stress = if want_stress {
            signorini_fem::cell_stress(&b.mesh, &b.material, &u_full[bi])
        } else {
            Vec::new()
        };
        results.push(BodyResult {
            von_mises: stress.iter().map(signorini_fem::von_mises).collect(),
            name: b.name.clone(),
            coords: b.mesh.coords.clone(),
            cells: b.mesh.cells.iter().map(|c| c.nodes.clone()).collect(),
            displacement: u_full[bi].clone(),
            stress,
        });
    }

    let factor_bytes: usize = condensed.iter().map(|c| c.memory_bytes()).sum();
    let report = Report {
        scene: scene_name.to_string(),
        title: sc.title.clone(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        ranks: 1,
        subdomains: bodies.len(),
        dofs,
        interface_dofs: n_gamma,
        contact_points: m,
        converged,
        method: method.as_str().to_string(),
        path: path.as_str().to_string(),
        stages,
        steps: step_reports,
        timings_s: Timings {
            total: t_total.elapsed().as_secs_f64(),
            ..timings
        },
        memory: Memory {
            peak_rss_bytes: signorini_report::peak_rss_bytes(),
            dense_interface_bytes: if condensed_path {
                8 * (n_gamma * n_gamma + m * m) as u64
            } else {
                0
            },
            factor_bytes: factor_bytes as u64,
        },
        certificate,
        contact_force,
        contacts: summaries,
        probes,
        reference,
        messages,
        failure,
    };
    Ok(RunOutput {
        report,
        contact_rows,
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

/// The certificate of DESIGN.md §4 on the final fields: equilibrium of every
/// body on its free DOFs, penetration, tension and complementarity.
#[allow(clippy::too_many_arguments)]
fn certify(
    bodies: &[BodyModel],
    points: &[PointModel],
    loads: &StepLoads,
    u_full: &[Vec<f64>],
    lambda: &[f64],
    f_scale: f64,
    length_scale: f64,
    tolerance: f64,
) -> Certificate {
    // Bᵀλ on each body.
    let mut contact_force: Vec<Vec<f64>> = bodies.iter().map(|b| vec![0.0; b.n_dof]).collect();
    for (p, &l) in points.iter().zip(lambda) {
        for &(b, d, c) in &p.row {
            contact_force[b][d] += c * l;
        }
    }
    let lmax = inf_norm(lambda);
    let mut eq_res = 0.0f64;
    let mut eq_scale = f_scale.max(lmax);
    for (bi, b) in bodies.iter().enumerate() {
        let ku = spmv(b.k_full.as_ref(), &u_full[bi]);
        for &d in &b.free {
            let r = ku[d] - loads.force[bi][d] - contact_force[bi][d];
            eq_res = eq_res.max(r.abs());
            eq_scale = eq_scale.max(ku[d].abs()).max(contact_force[bi][d].abs());
        }
    }
    let gaps = gaps_of(points, u_full);
    let umax = u_full.iter().fold(0.0f64, |a, u| a.max(inf_norm(u)));
    let lscale = length_scale.max(umax).max(f64::MIN_POSITIVE);
    let fscale = f_scale.max(lmax).max(f64::MIN_POSITIVE);
    let penetration = gaps.iter().fold(0.0f64, |a, &g| a.max(-g)) / lscale;
    let tension = lambda.iter().fold(0.0f64, |a, &l| a.max(-l)) / fscale;
    let complementarity = gaps
        .iter()
        .zip(lambda)
        .fold(0.0f64, |a, (&g, &l)| a.max((g * l).abs()))
        / (lscale * fscale);
    Certificate {
        equilibrium: eq_res / eq_scale.max(f64::MIN_POSITIVE),
        penetration,
        tension,
        complementarity,
        cone: 0.0,
        tolerance: tolerance.max(1e-9),
        force_scale: fscale,
        length_scale: lscale,
    }
}

/// A body held by contact needs compressive contact forces that balance the
/// load on its free rigid motions: Gᵀλ = e with λ ≥ 0 (see
/// [`signorini_contact::equilibrium`]). Otherwise it cannot be in equilibrium:
/// bad input, exit 1, with the unbalanced resultant.
fn check_floating_equilibrium(
    bodies: &[BodyModel],
    points: &[PointModel],
    loads: &StepLoads,
    step: usize,
) -> Result<(), SolveError> {
    for (bi, b) in bodies.iter().enumerate() {
        if b.kernel.is_empty() {
            continue;
        }
        let k = b.kernel.len();
        // Rows of G for this body: how each contact force works on its rigid modes.
        let mut gt = Mat::<f64>::zeros(k, points.len());
        for (pi, p) in points.iter().enumerate() {
            for &(pb, d, c) in &p.row {
                if pb == bi && !b.prescribed[d] {
                    let i = b.free_index[d];
                    for (j, r) in b.kernel.iter().enumerate() {
                        gt[(j, pi)] += c * r[i];
                    }
                }
            }
        }
        let e: Vec<f64> = b
            .kernel
            .iter()
            .map(|r| {
                -r.iter()
                    .zip(&loads.free_load[bi])
                    .map(|(a, f)| a * f)
                    .sum::<f64>()
            })
            .collect();
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
        let (_, res) = nnls(&gt, &e);
        let fmax = inf_norm(&loads.free_load[bi]).max(inf_norm(&e));
        let mut fx = 0.0;
        let mut fy = 0.0;
        for n in 0..b.mesh.n_nodes() {
            fx += loads.force[bi][2 * n];
            fy += loads.force[bi][2 * n + 1];
        }
        if unheld > 0 {
            return Err(SolveError::Input(format!(
                "bodies[{}]: body \"{}\" is free to move: {unheld} of its rigid motions are prevented neither by a support nor by its contacts (frictionless contact only holds along the normals); add a [[boundary]] displacement that pins it (e.g. a point with x = 0)",
                b.scene_index, b.name
            )));
        }
        if res > 1e-8 * fmax.max(f64::MIN_POSITIVE) {
            return Err(SolveError::Input(format!(
                "bodies[{}]: body \"{}\" cannot be in equilibrium at step {}: it has no support against {} rigid motion(s), and its external load (resultant ({fx:e}, {fy:e})) cannot be balanced by its contacts, which can only push along their normals; add a [[boundary]] displacement that holds it, or change the load",
                b.scene_index,
                b.name,
                step + 1,
                k
            )));
        }
    }
    Ok(())
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
    _bodies: &[BodyModel],
    points: &[PointModel],
    lambda: &[f64],
) -> Result<signorini_report::ReferenceReport, SolveError> {
    let Some(pmax) = (0..points.len()).max_by(|&a, &b| lambda[a].total_cmp(&lambda[b])) else {
        return Err(SolveError::Input(
            "reference: the scene has no contact point to compare".into(),
        ));
    };
    let t = points[pmax].point.tangent;
    let nodes: Vec<reference::NodalPressure> = points
        .iter()
        .zip(lambda)
        .map(|(p, &l)| reference::NodalPressure {
            s: p.point.x[0] * t[0] + p.point.x[1] * t[1],
            force: l.max(0.0),
            tributary: p.tributary,
        })
        .collect();
    match r.kind {
        scene::ReferenceKind::HertzCylinder => {
            let c = sc.contact.first().ok_or_else(|| SolveError::Input("reference: hertz_cylinder needs a [[contact]]".into()))?;
            let inv = contact_modulus(sc, &c.slave.body) + contact_modulus(sc, &c.master.body);
            let radius = r.radius.ok_or_else(|| SolveError::Input("reference.radius: hertz_cylinder needs the radius".into()))?;
            Ok(reference::hertz_cylinder(&nodes, 1.0 / inv, radius))
        }
        scene::ReferenceKind::UniformPressure => Ok(reference::uniform_pressure(&nodes, r.pressure, None)),
        other => Err(SolveError::Input(format!(
            "reference.kind: \"{}\" is not supported yet (supported: hertz_cylinder, uniform_pressure)",
            other.as_str()
        ))),
    }
}
