//! The root solve of the condensed path: S and F' of every subdomain
//! assembled on Γ, the Delassus operator built once, and each load step's
//! contact problem solved by the chosen algorithm (seed §3–4).

use super::*;

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

/// The coefficients (μ₁, μ₂) of a 3D Coulomb law; `None` for Tresca or
/// frictionless points.
pub(crate) fn p_law(law: &Law3d) -> Option<(f64, f64)> {
    match law {
        Law3d::Coulomb { mu } => Some((mu[0], mu[1])),
        _ => None,
    }
}

/// Solves one step's condensed problem with a method other than the status
/// method with multipliers; for the penalty methods, also the exact solution,
/// to report their deviation.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_with_algorithm(
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
    }
}

/// The length scale of a step, against which gaps and penetrations are
/// measured: the largest prescribed displacement, initial gap, or the
/// displacement ‖F‖/E the largest load gives the stiffest body.
pub(crate) fn length_scale(
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
pub(crate) fn status_report(
    method: &str,
    outcome: &StatusOutcome,
    linear_solves: usize,
) -> SolverReport {
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
pub(crate) fn solve_root(
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
            .map(|p| {
                [tangent_row[p], tangent_row2[p]]
                    .into_iter()
                    .flatten()
                    .collect()
            })
            .collect(),
        law: points
            .iter()
            .map(|p| match p.friction {
                _ if p.trow.is_none() => Law3d::None,
                PointFriction::Tresca(g) => Law3d::Tresca(g),
                PointFriction::Coulomb { mu, mu2, .. } => Law3d::Coulomb { mu: [mu, mu2] },
                _ => Law3d::None,
            })
            .collect(),
    };
    let three_d = sc.dimension == 3 && tangent_row.iter().any(|t| t.is_some());
    if three_d && sc.solver.friction == scene::FrictionSolver::Status {
        return Err(SolveError::Input(
            "solver.friction: the friction status method (seed §4.5) is 2D only; in 3D friction is solved by the fixed point on the threshold (friction = \"fixed_point\", the default)".into(),
        ));
    }
    let has_friction = tangent_row.iter().any(|t| t.is_some());
    let layout = FrictionLayout {
        shadow: signorini_contact::redundancy::tangent_shadows(&rows, m, &tangent_row),
        tangent_row: tangent_row.clone(),
        threshold: points
            .iter()
            .map(|p| match p.friction {
                // A point whose slip is prescribed by a support has no
                // tangential unknown (see model::free_tangential_rows).
                _ if p.trow.is_none() => Threshold::None,
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
    let mut operator: Option<DelassusOperator> = None;
    for (si, st) in scales.iter().enumerate() {
        let t_step = Instant::now();
        let mut operator_s = 0.0;
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
            let op = delassus_operator(&mut operator, &mut operator_s, || {
                conditioning::delassus_operator(&s, &rows, &kernel, cond)
            })?;
            let mut problem = op.problem(&gap0_all, &fp);
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
            let initial = previous
                .as_ref()
                .map(|p| p.0.clone())
                .unwrap_or_else(|| initial_statuses(bodies, points, &gap0, closed, true));
            // A body held by contact alone starts closed at the first step;
            // if that start is singular (e.g. a corner stuck on one contact
            // and closed on another along the same DOF), start from the gaps.
            let retry_from_gaps = previous.is_none() && bodies.iter().any(|b| !b.kernel.is_empty());
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
            } else {
                let solve_2d = |problem: &mut DelassusProblem, initial: Vec<PointStatus>| {
                    if any_nh {
                        (
                            signorini_contact::friction::norton_hoff(
                                problem,
                                &layout,
                                &norton_hoff,
                                initial,
                                &fopts,
                            ),
                            "norton_hoff",
                        )
                    } else if all_tresca && algorithm == Algorithm::Mprgp {
                        (
                            tresca_projection(problem, &layout, &fopts),
                            "tresca_mprgp_box",
                        )
                    } else if all_tresca {
                        (
                            tresca_status(problem, &layout, initial, &fopts),
                            "tresca_status",
                        )
                    } else if sc.solver.friction == scene::FrictionSolver::Status {
                        (
                            coulomb_status(problem, &layout, initial, &fopts),
                            "friction_status",
                        )
                    } else {
                        let start = previous.as_ref().map(|p| p.1.clone());
                        (
                            coulomb_fixed_point(
                                problem,
                                &layout,
                                initial,
                                start.as_deref(),
                                &fopts,
                            ),
                            "coulomb_fixed_point",
                        )
                    }
                };
                match solve_2d(&mut problem, initial) {
                    (Err(ContactError::Singular(_)), _) if retry_from_gaps => solve_2d(
                        &mut problem,
                        initial_statuses(bodies, points, &gap0, closed, false),
                    ),
                    other => other,
                }
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
                solve_s: t_step.elapsed().as_secs_f64() - operator_s,
                operator_s,
            });
            continue;
        }
        let op = delassus_operator(&mut operator, &mut operator_s, || {
            conditioning::delassus_operator(&s, &rows, &kernel, cond)
        })?;
        let mut problem = op.problem(&gap0, &fp);
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
            solve_s: t_step.elapsed().as_secs_f64() - operator_s,
            operator_s,
        });
    }
    Ok((RootAnswer { u_gamma }, steps))
}

/// The run's Delassus operator, built by `build` at its first use (once per
/// run: S, B and R do not change over the steps), with the seconds it took
/// in `seconds`.
pub(crate) fn delassus_operator<'a>(
    slot: &'a mut Option<DelassusOperator>,
    seconds: &mut f64,
    build: impl FnOnce() -> Result<DelassusOperator, ContactError>,
) -> Result<&'a DelassusOperator, SolveError> {
    if slot.is_none() {
        let t = Instant::now();
        *slot = Some(build().map_err(contact_error)?);
        *seconds = t.elapsed().as_secs_f64();
    }
    slot.as_ref()
        .ok_or_else(|| SolveError::Internal("the Delassus operator was not built".into()))
}

/// The statuses a friction solve starts from at its first step: closed
/// points stick, open ones are open, except that every point of a body held
/// by contact alone starts closed. While such a body's contacts are open
/// nothing determines its rigid motion along them (its position is a free
/// unknown, the saddle-point system of its equilibrium is singular): starting
/// closed, the status iterations open the points whose forces come out
/// tensile, so that a body with an initial gap reaches the closed state
/// directly, under displacement or force control (Code_Aster SSNV503).
pub(crate) fn initial_statuses(
    bodies: &[BodyModel],
    points: &[PointModel],
    gap0: &[f64],
    closed: f64,
    close_floating: bool,
) -> Vec<PointStatus> {
    points
        .iter()
        .zip(gap0)
        .map(|(p, &g)| {
            let floating =
                close_floating && p.row.iter().any(|&(b, _, _)| !bodies[b].kernel.is_empty());
            if g <= closed || floating {
                PointStatus::Stick
            } else {
                PointStatus::Open
            }
        })
        .collect()
}
