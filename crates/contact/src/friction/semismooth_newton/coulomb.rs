//! Friction by the semi-smooth Newton method of [`super`]: the driver
//! ([`friction_newton`]), Newton on Coulomb's law itself ([`solve_coulomb`],
//! thresholds μ λ_n of the iterate) and the fixed point on the thresholds
//! around the fixed-threshold method as its fallback (course notes §4.1.2, §4.3).

use super::tresca_inner::Newton;
use super::*;

/// Coulomb (or Tresca) in 2D by the semi-smooth Newton method on the
/// Alart–Curnier equations ([`crate::friction::semismooth_newton`]): Newton steps on
/// Coulomb's law itself (threshold μ λ_n of the iterate, no outer fixed
/// point), each on the reduced system of its statuses (a primal–dual
/// active set method); where that does not converge, the fixed point
/// g ← μ λ_n (§4.3) with each inner Tresca problem solved by the same
/// Newton steps. Statuses open, stick, slip± as the other 2D methods
/// report them. Started from `start` (the previous step's forces) or zero
/// (the fixed point: from the solution with every point stuck).
pub fn coulomb_newton(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    friction_newton(problem, layout, start, opts, 2, true)
}

/// Friction by the semi-smooth Newton method (`dim` 2 or 3): Tresca (and
/// frictionless) points in one solve; Coulomb, with `direct`, by the Newton
/// method on Coulomb's law itself ([`solve_coulomb`]), and when that does
/// not converge (or without `direct`) by the fixed point on the thresholds
/// g ← μ λ_n (course notes §4.3), started from `start` (the previous step's forces,
/// all rows) or from the solution with every frictional point stuck (so
/// that a body held by friction alone can start). The direct method stops
/// on its scaled natural residual (cone and complementarity); the fixed
/// point when max |Δλ_n| / max(force_scale, ‖λ‖∞) ≤ tolerance, each inner
/// problem on its scaled natural residual. `iterations` counts the Newton
/// iterations of all solves.
///
/// With floating bodies, the rigid-mode amplitudes α used by
/// [`DelassusProblem::displacement`] are the Newton method's own, read back
/// from the gaps it met its tolerance on
/// ([`DelassusProblem::set_alpha_from_gaps`]). (A final linear solve with the
/// statuses found, closed and stuck rows at zero gap, is singular when the
/// points holding a body along a rigid motion all slip, and left α at zero:
/// the block of a pushed assembly then sank into its pad.)
pub(crate) fn friction_newton(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
    dim: usize,
    direct: bool,
) -> Result<ContactSolution, ContactError> {
    let bilateral = match start {
        None if problem.n_kernel() > 0 => bilateral_start(problem),
        _ => None,
    };
    let mut out = newton_fixed_point(problem, layout, start, bilateral, direct, opts, dim)?;
    if problem.n_kernel() > 0 {
        problem.set_alpha_from_gaps(&out.forces, &out.gaps);
    }
    out.report.operator_applications = problem.solves;
    Ok(out)
}

/// The forces (and, kept in `problem`, the rigid-mode amplitudes α) with
/// every point closed and stuck: the start of the first step of a problem
/// with floating bodies. From zero forces the Newton method would see a body
/// whose contacts start open (an initial gap) as held by nothing, a singular
/// system; closed everywhere, its position is determined, and the points
/// that come out in tension open in the iterations that follow. `None` when
/// that system is singular too.
fn bilateral_start(problem: &mut DelassusProblem) -> Option<Vec<f64>> {
    let eqs = vec![VarEquation::Gap; problem.q.len()];
    problem.solve_equations(&eqs).ok().map(|(r, _)| r)
}

/// The thresholds of the start of the fixed point: every point initially
/// closed (q_n ≤ 0) stuck, the others free, as the 2D fixed point starts
/// (§4.3: g = 0 cannot hold a body held by friction); from the bilateral
/// start of floating bodies (`guessed`), every point stuck. Stuck open
/// points would couple all 2m tangential rows of the Newton systems.
fn stuck_thresholds(
    problem: &DelassusProblem,
    layout: &FrictionLayout,
    guessed: bool,
) -> Vec<[f64; 2]> {
    (0..layout.n_points())
        .map(|p| {
            if guessed || problem.q[p] <= 0.0 {
                [f64::INFINITY; 2]
            } else {
                [0.0; 2]
            }
        })
        .collect()
}

/// The factor on ρ of the second try of the Newton method on Coulomb's law.
pub const RETRY_RHO_SCALE: f64 = 0.1;

/// With `direct`, the Newton method on Coulomb's law itself (once more with
/// ρ scaled by [`RETRY_RHO_SCALE`] when it does not converge), else (or when
/// it fails) the fixed point on the threshold with the Newton inner solves,
/// from `start` (previous step) or `first_guess` (floating bodies) or zero.
fn newton_fixed_point(
    problem: &DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    first_guess: Option<Vec<f64>>,
    direct: bool,
    opts: &FrictionOptions,
    dim: usize,
) -> Result<ContactSolution, ContactError> {
    let n = problem.q.len();
    layout.validate(n, dim)?;
    let forces = match start {
        Some(f) if f.len() == n => f.to_vec(),
        Some(f) => {
            return Err(ContactError::Geometry(format!(
                "friction {dim}D: {} start forces for {n} rows",
                f.len()
            )))
        }
        None => first_guess.clone().unwrap_or_else(|| vec![0.0; n]),
    };
    let guessed = first_guess.is_some();
    let mut newton = Newton {
        problem,
        layout,
        opts,
        iterations: 0,
        dim,
        trusted: false,
        rho_scale: 1.0,
        failures: 0,
        last_failure: None,
    };
    let tresca = match dim {
        2 => "tresca_semismooth_newton",
        _ => "tresca_3d_semismooth_newton",
    };
    if layout.has_norton_hoff() {
        // As in 2D, every step from the solution with the closed points stuck.
        let stuck = newton.solve(&stuck_thresholds(problem, layout, guessed), &forces)?;
        return super::norton_hoff::norton_hoff_fixed_point(&mut newton, stuck);
    }
    if !layout.has_coulomb() {
        let last = newton.solve(&layout.thresholds(&forces), &forces)?;
        let end = FixedPoint {
            converged: last.converged,
            reason: StopReason::Tresca(Box::new(last.reason.clone())),
            residuals: Vec::new(),
            last,
        };
        return Ok(end.solution(tresca, newton.iterations, false));
    }
    let direct_name = match dim {
        2 => "coulomb_semismooth_newton",
        _ => "coulomb_3d_semismooth_newton",
    };
    let mut fallback = None;
    if direct {
        let failed = match solve_coulomb(&mut newton, &forces)? {
            Ok(sol) => return Ok(sol),
            Err(failed) => failed,
        };
        // Once more with smaller projection parameters: a shorter trial
        // step into the cone, which left the status cycle of an assembly
        // pushed sideways (pad slave, half of μ N: stalled at 1.2e-2 with ρ
        // = 1/W_ii, converged in 20 iterations with a tenth of it).
        newton.rho_scale = RETRY_RHO_SCALE;
        let retried = solve_coulomb(&mut newton, &forces)?;
        newton.rho_scale = 1.0;
        if let Ok(sol) = retried {
            return Ok(sol);
        }
        fallback = Some(format!("{direct_name} stopped: {}", failed.reason));
    }
    let start = match start {
        Some(_) => {
            newton.trusted = true;
            newton.iterate(forces)
        }
        None => newton.solve(&stuck_thresholds(problem, layout, guessed), &forces)?,
    };
    let map = ThresholdMap {
        threshold: &|r, _| layout.thresholds(r),
        residual: &normal_change,
        kind: ThresholdMapKind::Coulomb,
    };
    let end = fixed_point(&mut newton, start, &map, opts)?;
    let coulomb = match dim {
        2 => "coulomb_semismooth_newton",
        _ => "coulomb_3d_fixed_point",
    };
    let mut sol = end.solution(coulomb, newton.iterations, false);
    sol.friction.fallback = fallback;
    Ok(sol)
}

/// The semi-smooth Newton method on Coulomb's law itself (Alart & Curnier
/// 1991; course notes §4.1.2), no outer fixed point: the semi-axes of a Coulomb
/// point are μ_i λ_n of the iterate (the threshold μ λ_n rather than
/// μ [λ_n − ρ y_n]₊: the two have the same zeros, and with λ_n the
/// slipping rows depend on the normal force alone, a substitution in the
/// reduced system instead of a W row; an open point's λ_n is driven to
/// zero by its own row, and with it the threshold). Each step linearises
/// F on the iterate's statuses: open points λ = 0, closed normal rows and
/// stuck points the W rows, slipping points the force on the boundary of
/// the disc / ellipse whose radius follows dλ_n ([`slip_rows`]); the
/// reduced system is nonsymmetric (LU). From `forces`; its last iterate
/// (and why it stopped) when it does not meet the tolerance (the caller's
/// fixed point then decides), never a non-converged answer.
fn solve_coulomb(
    newton: &mut Newton,
    forces: &[f64],
) -> Result<Result<ContactSolution, InnerSolve>, ContactError> {
    let thr = newton.layout.thresholds(forces);
    let (direct, iterations) = solve_inner(newton, &thr, forces, true)?;
    newton.iterations += iterations;
    let StopReason::NewtonConverged { residual, .. } = direct.reason else {
        return Ok(Err(direct));
    };
    let method = match newton.dim {
        2 => "coulomb_semismooth_newton",
        _ => "coulomb_3d_semismooth_newton",
    };
    let end = FixedPoint {
        converged: true,
        reason: direct.reason.clone(),
        residuals: vec![residual],
        last: direct,
    };
    let mut sol = end.solution(method, newton.iterations, false);
    sol.friction.fixed_point_iterations = 0;
    Ok(Ok(sol))
}
