//! The status (active set) method, seed §3.3.
//!
//! 1. impose g_p = 0 on the points of the active set A (by Lagrange
//!    multipliers), 2. solve, 3. check the statuses: a point of A whose force
//!    λ_p is a tension (λ_p < 0) is released; a point outside A that
//!    penetrates (g_p < 0) is imposed. Loop on 2–3 until the statuses repeat.
//!
//! The seed proves convergence only when one status changes per iteration
//! ([`StatusVariant::Single`]); changing all at once ([`StatusVariant::All`])
//! is faster in practice but may flip-flop at the edge of a coarse contact
//! zone. Cycling is detected (an active set seen before) and reported; the
//! `All` variant then falls back to `Single`.
//!
//! The linear solve of step 2 is abstracted by [`ActiveSetSolve`]: the
//! condensed path solves with the Delassus operator on the forces
//! ([`crate::DelassusProblem`]), the direct path refactorises the whole
//! sparse stiffness with the active constraints ([`crate::direct`]).

use std::collections::HashSet;

use crate::ContactError;

/// Solves the equality-constrained problem for a given active set.
pub trait ActiveSetSolve {
    /// Number of contact points.
    fn n_points(&self) -> usize;
    /// With g_p = 0 imposed for p in `active` (sorted) and λ_p = 0 elsewhere,
    /// returns (λ, g) for every point.
    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError>;
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StatusVariant {
    /// Every violated status changes at each iteration.
    All,
    /// Only the most violated status changes (the variant with the proof).
    Single,
}

#[derive(Debug, Clone)]
pub struct StatusOptions {
    pub variant: StatusVariant,
    pub max_iterations: usize,
    /// Relative tolerance.
    pub tolerance: f64,
    /// Force scale: tensions below tolerance × max(force_scale, ‖λ‖∞) are zero.
    pub force_scale: f64,
    /// Length scale: penetrations below tolerance × max(gap_scale, ‖g‖∞) are zero.
    pub gap_scale: f64,
    /// Initial active set (sorted); `None` starts with every point active.
    pub initial_active: Option<Vec<usize>>,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct StatusOutcome {
    pub converged: bool,
    pub iterations: usize,
    /// Number of linear solves (one per iteration).
    pub solves: usize,
    pub active: Vec<usize>,
    pub lambda: Vec<f64>,
    pub gap: Vec<f64>,
    /// Why it stopped, in words.
    pub stopping_reason: String,
    /// Size of the active set at each iteration.
    pub active_history: Vec<usize>,
    /// Iteration at which a cycle was detected, if any.
    pub cycle_detected_at: Option<usize>,
    pub variant_used: StatusVariant,
}

/// Runs the status method of seed §3.3 on `problem`.
pub fn status_method(
    problem: &mut dyn ActiveSetSolve,
    opts: &StatusOptions,
) -> Result<StatusOutcome, ContactError> {
    let m = problem.n_points();
    let mut active: Vec<usize> = opts
        .initial_active
        .clone()
        .unwrap_or_else(|| (0..m).collect());
    let mut variant = opts.variant;
    let mut seen: HashSet<Vec<usize>> = HashSet::new();
    let mut history = Vec::new();
    let mut cycle_at = None;
    let mut iterations = 0;
    let mut lambda = vec![0.0; m];
    let mut gap = vec![0.0; m];
    let mut reason = String::new();
    let mut converged = false;
    while iterations < opts.max_iterations {
        iterations += 1;
        history.push(active.len());
        seen.insert(active.clone());
        let (l, g) = problem.solve_active(&active)?;
        lambda = l;
        gap = g;
        if lambda.iter().chain(&gap).any(|v| !v.is_finite()) {
            return Err(ContactError::Singular(format!(
                "non-finite forces or gaps at status iteration {iterations} with {} active points",
                active.len()
            )));
        }
        let lmax = lambda.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let gmax = gap.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let tol_f = opts.tolerance * opts.force_scale.max(lmax);
        let tol_g = opts.tolerance * opts.gap_scale.max(gmax);
        let mut is_active = vec![false; m];
        for &p in &active {
            is_active[p] = true;
        }
        // Violations, scaled to compare forces with gaps.
        let mut changes: Vec<(usize, f64)> = Vec::new();
        for p in 0..m {
            if is_active[p] && lambda[p] < -tol_f {
                changes.push((p, -lambda[p] / tol_f.max(f64::MIN_POSITIVE)));
            } else if !is_active[p] && gap[p] < -tol_g {
                changes.push((p, -gap[p] / tol_g.max(f64::MIN_POSITIVE)));
            }
        }
        if changes.is_empty() {
            converged = true;
            reason = format!("statuses repeated after {iterations} iterations");
            break;
        }
        let to_change: Vec<usize> = match variant {
            StatusVariant::All => changes.iter().map(|c| c.0).collect(),
            StatusVariant::Single => {
                let worst = changes
                    .iter()
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|c| c.0)
                    .into_iter()
                    .collect();
                worst
            }
        };
        for p in to_change {
            is_active[p] = !is_active[p];
        }
        let next: Vec<usize> = (0..m).filter(|&p| is_active[p]).collect();
        if seen.contains(&next) {
            cycle_at.get_or_insert(iterations);
            if variant == StatusVariant::All {
                // Flip-flop: fall back to one change per iteration (seed §3.3).
                variant = StatusVariant::Single;
                seen.clear();
                let worst = changes
                    .iter()
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|c| c.0)
                    .unwrap_or(0);
                let mut is_active = vec![false; m];
                for &p in &active {
                    is_active[p] = true;
                }
                is_active[worst] = !is_active[worst];
                active = (0..m).filter(|&p| is_active[p]).collect();
                continue;
            }
            reason = format!(
                "cycling: the active set of iteration {iterations} repeats an earlier one even with one status change per iteration (the contact zone is probably meshed too coarsely, seed §3.3)"
            );
            break;
        }
        active = next;
    }
    if !converged && reason.is_empty() {
        reason = format!(
            "iteration limit {} reached with statuses still changing",
            opts.max_iterations
        );
    }
    Ok(StatusOutcome {
        converged,
        iterations,
        solves: iterations,
        active,
        lambda,
        gap,
        stopping_reason: reason,
        active_history: history,
        cycle_detected_at: cycle_at,
        variant_used: variant,
    })
}
