//! Contact elements (course notes §7): zero-thickness elements between two layers
//! of coincident nodes, each carrying the regularised laws of §3.6 (normal)
//! and §4.1.3 / §6 (friction, with elastic asperities and roughness),
//! solved "like plasticity": a return mapping at each element and Newton's
//! method with the consistent tangent on the condensed problem.
//!
//! # The element law (one element e, its rows n, t1 [, t2])
//!
//! With h = W r + q + G α the jumps of the condensed problem (the normal
//! jump h_n, the gap, negative in compression; the total tangential jump
//! h_t = [u_t]), the element's forces (crate signs: λ_n ≥ 0 compressive,
//! λ_t = −t) are
//!
//! ```text
//!   λ_n = k_n max(0, −h_n)                                  (§3.6)
//!   trial   t* = k_t (h_t − g_old),  ξ* = t* − Q g_old        (§6, eqs. 20–22)
//!   ‖ξ*‖ ≤ τ: stick,  t = t*, g = g_old
//!   ‖ξ*‖ > τ: slip,   Δg = (‖ξ*‖ − τ)/(k_t + Q) n,  n = ξ*/‖ξ*‖,
//!                     t = t* − k_t Δg,  g = g_old + Δg      (radial return)
//! ```
//!
//! with the threshold τ = μ λ_n (Coulomb, §4.1.2, eq. 23), the Tresca
//! threshold (§4.1.1), and Q the roughness (linear kinematic hardening,
//! Q = 0: the regularised Coulomb law of §4.1.3); the closed form is
//! [`crate::law::hardening::return_map`], its tangent
//! [`crate::law::hardening::slip_tangent`]. An open element
//! (h_n ≥ 0) carries no force and its whole tangential jump becomes slip
//! (the asperities are unloaded on separation). The stiffnesses k_n, k_t, Q
//! and the Tresca threshold are the element's: the per-area values times its
//! tributary area.
//!
//! # Consistent tangent
//!
//! C_e = ∂(λ_n, λ_t)/∂(h_n, h_t): ∂λ_n/∂h_n = −k_n in compression, 0 open;
//! stick ∂t/∂h_t = k_t I; slip
//!
//! ```text
//!   ∂t/∂h_t = k_t Q/(k_t + Q) I + k_t² τ/((k_t + Q)‖ξ*‖) (I − n nᵀ),
//!   ∂t/∂τ   = k_t/(k_t + Q) n,   ∂τ/∂h_n = μ ∂λ_n/∂h_n (Coulomb).
//! ```
//!
//! # Newton on the condensed problem
//!
//! The unknowns are the forces r of every row and the amplitudes α of the
//! floating bodies' rigid modes: R(r, α) = r − Φ(W r + q + G α) = 0 with
//! Gᵀ r = e. Each iteration evaluates the return mapping at every element
//! and solves
//!
//! ```text
//!   [ I − C W   −C G ] [Δr]   [ −R        ]
//!   [   Gᵀ        0 ] [Δα] = [ e − Gᵀ r ]
//! ```
//!
//! (C block diagonal, the elements' tangents), with a backtracking line
//! search on ‖R‖. The law is piecewise linear in 2D (the Newton step with
//! the right statuses is exact) and smooth on each status in 3D (quadratic
//! convergence). Converged when ‖R‖∞ ≤ tolerance × force scale; otherwise
//! the solution says it did not converge.

use faer::prelude::Solve;
use faer::Mat;

use crate::delassus::DelassusProblem;
use crate::law::hardening::{return_map, slip_tangent};
use crate::solution::{ContactSolution, FrictionTrace, PointStatus, SolverReport, StopReason};
use crate::ContactError;

/// The slip threshold of an element's friction law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SlipThreshold {
    /// Frictionless (no tangential rows).
    None,
    /// Tresca: a given force.
    Tresca(f64),
    /// Coulomb: μ λ_n.
    Coulomb(f64),
}

/// One contact element: its rows in the condensed problem and its law (the
/// stiffnesses are the element's, force per unit jump).
#[derive(Debug, Clone)]
pub struct ContactElement {
    pub normal_row: usize,
    /// One tangential row in 2D, two in 3D; none without friction.
    pub tangent_rows: Vec<usize>,
    /// k_n A.
    pub normal_stiffness: f64,
    /// k_t A.
    pub tangential_stiffness: f64,
    /// Q A (0 without roughness).
    pub roughness: f64,
    pub threshold: SlipThreshold,
}

/// Newton iterations from the previous step's forces before [`solve`]
/// restarts from the elastic predictor (where it converges it takes a few).
const WARM_START_ITERATIONS: usize = 50;

/// Stopping rule of [`solve`].
#[derive(Debug, Clone, Copy)]
pub struct ElementOptions {
    pub max_iterations: usize,
    pub tolerance: f64,
    /// The force scale of the step (loads), against which ‖R‖∞ is measured.
    pub force_scale: f64,
}

/// The answer of [`solve`]: the forces and jumps of every row, the floating
/// amplitudes, the statuses, and the slip g of every row at the end of the
/// step (zero on normal rows).
#[derive(Debug, Clone)]
pub struct ElementSolution {
    pub solution: ContactSolution,
    pub slip: Vec<f64>,
}

/// The return mapping at one element: its forces (n, t1, t2), the tangent
/// C_e over the same rows, its slip and status.
struct Local {
    forces: [f64; 3],
    tangent: [[f64; 3]; 3],
    slip: [f64; 2],
    status: PointStatus,
}

/// The element law of the module doc at one element, for the jumps `h_n`,
/// `h_t` and the slip `g_old` at the start of the step.
fn element_law(e: &ContactElement, h_n: f64, h_t: &[f64], g_old: &[f64]) -> Local {
    let nt = h_t.len();
    let mut out = Local {
        forces: [0.0; 3],
        tangent: [[0.0; 3]; 3],
        slip: [0.0; 2],
        status: PointStatus::Open,
    };
    out.slip[..nt].copy_from_slice(h_t);
    if h_n >= 0.0 {
        return out;
    }
    let k_n = e.normal_stiffness;
    out.forces[0] = -k_n * h_n;
    out.tangent[0][0] = -k_n;
    out.status = PointStatus::Stick;
    let (tau, dtau) = match e.threshold {
        SlipThreshold::None => return out,
        SlipThreshold::Tresca(g) => (g, 0.0),
        SlipThreshold::Coulomb(mu) => (mu * out.forces[0], -mu * k_n),
    };
    if nt == 0 {
        return out;
    }
    let (k, q) = (e.tangential_stiffness, e.roughness);
    let rm = return_map(h_t, g_old, tau, k, q);
    for i in 0..nt {
        out.forces[1 + i] = -rm.traction[i];
        out.slip[i] = rm.slip[i];
    }
    if !rm.slipped {
        (0..nt).for_each(|i| out.tangent[1 + i][1 + i] = -k);
        return out;
    }
    let dt = slip_tangent(h_t, g_old, tau, k, q);
    for i in 0..nt {
        for j in 0..nt {
            out.tangent[1 + i][1 + j] = -dt.jump[i][j];
        }
        out.tangent[1 + i][0] = -dt.threshold[i] * dtau;
    }
    out.status = match (nt, out.forces[1] > 0.0) {
        (1, true) => PointStatus::SlipPlus,
        (1, false) => PointStatus::SlipMinus,
        _ => PointStatus::Slip,
    };
    out
}

/// The jumps h = W r + q + G α of every row.
fn jumps(problem: &DelassusProblem, r: &[f64], alpha: &[f64]) -> Vec<f64> {
    let (w, g) = (&problem.w, &problem.g_mat);
    (0..r.len())
        .map(|i| {
            let wr: f64 = (0..r.len()).map(|j| w[(i, j)] * r[j]).sum();
            let ga: f64 = alpha.iter().enumerate().map(|(j, a)| g[(i, j)] * a).sum();
            wr + problem.q[i] + ga
        })
        .collect()
}

/// The elements of a step with the slip `slip_old` of every row at its
/// start (zero on normal rows): what the return mapping maps from.
struct StepElements<'a> {
    elements: &'a [ContactElement],
    slip_old: &'a [f64],
}

impl StepElements<'_> {
    /// Every element's return mapping at the jumps `h`.
    fn evaluate(&self, h: &[f64]) -> Vec<Local> {
        self.elements
            .iter()
            .map(|e| {
                let h_t: Vec<f64> = e.tangent_rows.iter().map(|&t| h[t]).collect();
                let g_old: Vec<f64> = e.tangent_rows.iter().map(|&t| self.slip_old[t]).collect();
                element_law(e, h[e.normal_row], &h_t, &g_old)
            })
            .collect()
    }

    /// The residual (R, Gᵀ r − e) of (r, α) and its largest entry, with the
    /// elements' return mappings.
    fn residual(
        &self,
        problem: &DelassusProblem,
        r: &[f64],
        alpha: &[f64],
    ) -> (Vec<f64>, f64, Vec<Local>) {
        let h = jumps(problem, r, alpha);
        let local = self.evaluate(&h);
        let mut res = r.to_vec();
        for (e, l) in self.elements.iter().zip(&local) {
            res[e.normal_row] -= l.forces[0];
            for (i, &t) in e.tangent_rows.iter().enumerate() {
                res[t] -= l.forces[1 + i];
            }
        }
        let g = &problem.g_mat;
        for j in 0..alpha.len() {
            let gr: f64 = (0..r.len()).map(|i| g[(i, j)] * r[i]).sum();
            res.push(gr - problem.e[j]);
        }
        let norm = res.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        (res, norm, local)
    }
}

/// The Newton matrix [[I − C W, −C G], [Gᵀ, 0]] of the module doc; with
/// `elastic`, C is every element's closed and sticking tangent
/// diag(−k_n, −k_t, −k_t) (the elastic predictor).
fn newton_matrix(
    problem: &DelassusProblem,
    elements: &[ContactElement],
    local: &[Local],
    elastic: bool,
) -> Mat<f64> {
    let (n, k) = (problem.q.len(), problem.g_mat.ncols());
    let (w, g) = (&problem.w, &problem.g_mat);
    let mut j = Mat::<f64>::zeros(n + k, n + k);
    for i in 0..n {
        j[(i, i)] = 1.0;
    }
    for (e, l) in elements.iter().zip(local) {
        let rows: Vec<usize> = std::iter::once(e.normal_row)
            .chain(e.tangent_rows.iter().copied())
            .collect();
        for (a, &ra) in rows.iter().enumerate() {
            for (b, &rb) in rows.iter().enumerate() {
                let c = match (elastic, a == b, a) {
                    (false, ..) => l.tangent[a][b],
                    (true, false, _) => 0.0,
                    (true, true, 0) => -e.normal_stiffness,
                    (true, true, _) => -e.tangential_stiffness,
                };
                if c == 0.0 {
                    continue;
                }
                for col in 0..n {
                    j[(ra, col)] -= c * w[(rb, col)];
                }
                for col in 0..k {
                    j[(ra, n + col)] -= c * g[(rb, col)];
                }
            }
        }
    }
    for col in 0..k {
        for i in 0..n {
            j[(n + col, i)] = g[(i, col)];
        }
    }
    j
}

/// Solves the contact elements' problem on the condensed problem by the
/// return mapping and Newton's method (module doc), from the forces `start`
/// (the previous step's, or zero), with the slip `slip_old` of every row at
/// the start of the step (zero on normal rows). The floating amplitudes go
/// into `problem` (for its displacement).
pub fn solve(
    problem: &mut DelassusProblem,
    elements: &[ContactElement],
    slip_old: &[f64],
    start: Option<&[f64]>,
    opts: &ElementOptions,
) -> Result<ElementSolution, ContactError> {
    let step = StepElements { elements, slip_old };
    if start.is_none() {
        return solve_from(problem, &step, None, opts);
    }
    let warm_opts = ElementOptions {
        max_iterations: opts.max_iterations.min(WARM_START_ITERATIONS),
        ..*opts
    };
    let warm = solve_from(problem, &step, start, &warm_opts)?;
    if warm.solution.report.converged {
        return Ok(warm);
    }
    // The previous step's forces can start Newton where its residual is not
    // smooth enough to converge (a block unloaded from 100 to 1 cycled to
    // the iteration limit): once more from the elastic predictor, as a
    // first step starts, the iterations of both counted.
    let mut cold = solve_from(problem, &step, None, opts)?;
    cold.solution.report.iterations += warm.solution.report.iterations;
    Ok(cold)
}

/// [`solve`] from the forces `start` (or from the elastic predictor).
fn solve_from(
    problem: &mut DelassusProblem,
    step_elements: &StepElements,
    start: Option<&[f64]>,
    opts: &ElementOptions,
) -> Result<ElementSolution, ContactError> {
    let elements = step_elements.elements;
    let n = problem.q.len();
    let k = problem.g_mat.ncols();
    let mut r = start.map_or(vec![0.0; n], <[f64]>::to_vec);
    let mut alpha = vec![0.0; k];
    let mut report = SolverReport {
        method: "contact_elements_return_mapping".into(),
        ..Default::default()
    };
    let (mut res, mut norm, mut local) = step_elements.residual(problem, &r, &alpha);
    let scale = |r: &[f64]| {
        opts.force_scale
            .max(r.iter().fold(0.0f64, |a, v| a.max(v.abs())))
    };
    // The statuses before the last step and that step's largest change.
    let mut before: Vec<PointStatus> = vec![];
    let mut last_change = f64::INFINITY;
    loop {
        let s = scale(&r);
        report.residual_history.push(norm / s);
        let settled = statuses(&local) == before && last_change <= opts.tolerance * s;
        if norm <= opts.tolerance * s || settled {
            report.converged = true;
            report.stop = StopReason::NewtonConverged {
                residual: norm / s,
                iterations: report.iterations,
            };
            break;
        }
        if report.iterations >= opts.max_iterations {
            report.stop = StopReason::NewtonLimit {
                limit: opts.max_iterations,
            };
            break;
        }
        report.iterations += 1;
        // The first iteration from zero forces takes the elastic predictor
        // (every element closed and sticking): from open elements the
        // bodies held by contact alone would be free.
        let elastic = start.is_none() && report.iterations == 1;
        let step = newton_step(problem, elements, &local, &res, elastic)?;
        problem.solves += 1;
        // Backtracking on ‖R‖∞; the full step when no fraction decreases it
        // (the residual is not smooth across status changes).
        let mut t = 1.0;
        let next = loop {
            let (rt, at) = advance(&r, &alpha, &step, t);
            let trial = step_elements.residual(problem, &rt, &at);
            if trial.1 < (1.0 - 1e-4 * t) * norm || t < 1.0 / 64.0 {
                break (rt, at, trial, t);
            }
            t *= 0.5;
        };
        let (rt, at, trial, t) = if next.2 .1 < norm {
            next
        } else {
            let (rt, at) = advance(&r, &alpha, &step, 1.0);
            let trial = step_elements.residual(problem, &rt, &at);
            (rt, at, trial, 1.0)
        };
        last_change = t * step[..r.len()].iter().fold(0.0f64, |a, v| a.max(v.abs()));
        before = statuses(&local);
        (r, alpha) = (rt, at);
        (res, norm, local) = trial;
    }
    Ok(finish(problem, elements, r, alpha, local, report))
}

/// The elements' statuses.
fn statuses(local: &[Local]) -> Vec<PointStatus> {
    local.iter().map(|l| l.status).collect()
}

/// One Newton correction (Δr, Δα) for the residual `res`; when the
/// consistent tangent is singular (open elements around a body held by
/// contact alone), the elastic predictor's.
fn newton_step(
    problem: &DelassusProblem,
    elements: &[ContactElement],
    local: &[Local],
    res: &[f64],
    elastic: bool,
) -> Result<Vec<f64>, ContactError> {
    let rhs = Mat::<f64>::from_fn(res.len(), 1, |i, _| -res[i]);
    let rhs_norm = res.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let solve = |elastic: bool| -> Option<Vec<f64>> {
        let j = newton_matrix(problem, elements, local, elastic);
        let d = j.full_piv_lu().solve(&rhs);
        let check = &j * &d - &rhs;
        let err = (0..res.len()).fold(0.0f64, |a, i| a.max(check[(i, 0)].abs()));
        let step: Vec<f64> = (0..res.len()).map(|i| d[(i, 0)]).collect();
        (step.iter().all(|v| v.is_finite()) && err <= 1e-8 * rhs_norm).then_some(step)
    };
    let step = solve(elastic)
        .or_else(|| (!elastic).then(|| solve(true)).flatten())
        .unwrap_or_default();
    if step.is_empty() {
        return Err(ContactError::Singular(
            "contact elements: the Newton matrix of the return mapping is singular (an element law that holds no rigid motion of a body held by contact alone: frictionless or open elements)".into(),
        ));
    }
    Ok(step)
}

/// (r, α) + s (Δr, Δα).
fn advance(r: &[f64], alpha: &[f64], step: &[f64], s: f64) -> (Vec<f64>, Vec<f64>) {
    let n = r.len();
    let rt = (0..n).map(|i| r[i] + s * step[i]).collect();
    let at = (0..alpha.len())
        .map(|j| alpha[j] + s * step[n + j])
        .collect();
    (rt, at)
}

/// The solution at (r, α): the elements' forces (r = Φ(h) to the
/// tolerance), the jumps, the slips and statuses.
fn finish(
    problem: &mut DelassusProblem,
    elements: &[ContactElement],
    r: Vec<f64>,
    alpha: Vec<f64>,
    local: Vec<Local>,
    report: SolverReport,
) -> ElementSolution {
    let gaps = jumps(problem, &r, &alpha);
    let mut slip = vec![0.0; r.len()];
    let mut statuses = vec![PointStatus::Open; elements.len()];
    for (p, (e, l)) in elements.iter().zip(&local).enumerate() {
        statuses[p] = l.status;
        for (i, &t) in e.tangent_rows.iter().enumerate() {
            slip[t] = l.slip[i];
        }
    }
    if !alpha.is_empty() {
        problem.set_alpha(&alpha);
    }
    let active = (0..elements.len())
        .filter(|&p| statuses[p] != PointStatus::Open)
        .collect();
    let solution = ContactSolution {
        forces: r,
        gaps,
        alpha,
        active,
        report,
        statuses: Default::default(),
        friction: FrictionTrace {
            points: statuses,
            ..Default::default()
        },
    };
    ElementSolution { solution, slip }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn element(threshold: SlipThreshold, nt: usize, q: f64) -> ContactElement {
        ContactElement {
            normal_row: 0,
            tangent_rows: (1..=nt).collect(),
            normal_stiffness: 1000.0,
            tangential_stiffness: 400.0,
            roughness: q,
            threshold,
        }
    }

    /// The tangent of the element law against central differences, in
    /// stick and slip, 2D and 3D, with and without roughness.
    #[test]
    fn consistent_tangent_is_the_derivative_of_the_return_mapping() {
        let cases = [
            (1, 0.0, vec![-0.01, 0.001]),
            (1, 0.0, vec![-0.01, 0.02]),
            (1, 100.0, vec![-0.01, -0.03]),
            (2, 0.0, vec![-0.01, 0.02, -0.01]),
            (2, 100.0, vec![-0.01, 0.03, 0.02]),
        ];
        for (nt, q, h) in cases {
            let e = element(SlipThreshold::Coulomb(0.3), nt, q);
            let g_old = vec![0.001; nt];
            let at = |h: &[f64]| element_law(&e, h[0], &h[1..], &g_old);
            let l = at(&h);
            for col in 0..=nt {
                let d = 1e-7;
                let mut hp = h.clone();
                hp[col] += d;
                let mut hm = h.clone();
                hm[col] -= d;
                let (fp, fm) = (at(&hp).forces, at(&hm).forces);
                for row in 0..=nt {
                    let fd = (fp[row] - fm[row]) / (2.0 * d);
                    let scale = 1000.0;
                    assert!(
                        (fd - l.tangent[row][col]).abs() <= 1e-6 * scale,
                        "nt {nt} q {q} ({row},{col}): {fd} vs {}",
                        l.tangent[row][col]
                    );
                }
            }
        }
    }

    /// One element on a rigid support (W = 0 but for the element rows'
    /// zero compliance): the jumps are q, and the forces the law's.
    #[test]
    fn newton_on_one_element_gives_the_law_at_the_prescribed_jumps() {
        let e = element(SlipThreshold::Coulomb(0.3), 1, 0.0);
        let w = Mat::<f64>::zeros(2, 2);
        let mut p = DelassusProblem::from_operator(w, vec![-0.01, 0.05]);
        let opts = ElementOptions {
            max_iterations: 20,
            tolerance: 1e-12,
            force_scale: 10.0,
        };
        let out = solve(&mut p, &[e], &[0.0, 0.0], None, &opts).unwrap();
        let s = &out.solution;
        assert!(s.report.converged);
        assert!((s.forces[0] - 10.0).abs() <= 1e-12 * 10.0);
        assert!((s.forces[1] + 3.0).abs() <= 1e-12 * 10.0);
        // Slip g = h_t − t/k_t = 0.05 − 3/400.
        assert!((out.slip[1] - (0.05 - 3.0 / 400.0)).abs() <= 1e-14);
        assert_eq!(s.friction.points[0], PointStatus::SlipMinus);
    }
}
