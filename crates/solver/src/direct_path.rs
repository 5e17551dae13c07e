//! The direct path: the status method on the whole sparse stiffness with
//! the contact constraints as Lagrange multipliers (a finite-element KKT
//! solve refactorised at each status iteration, seed §3.3), to check and to
//! benchmark condensation.

use super::*;

/// The direct path on the root: every body's whole sparse stiffness, the
/// contact constraints added by Lagrange multipliers and the saddle-point
/// matrix refactorised at each status iteration (seed §3.3).
pub(crate) fn run_direct(
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
        let t_step = Instant::now();
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
            solve_s: t_step.elapsed().as_secs_f64(),
            operator_s: 0.0,
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

/// g_p = g0_p + Σ coef u over the full DOFs.
pub(crate) fn gaps_of(points: &[PointModel], u_full: &[Vec<f64>]) -> Vec<f64> {
    points
        .iter()
        .map(|p| p.gap0 + p.row.iter().map(|&(b, d, c)| c * u_full[b][d]).sum::<f64>())
        .collect()
}

/// Equilibrium residual of the direct path on the free DOFs of every body:
/// K u − f − Bᵀλ.
pub(crate) fn direct_residuals(
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
