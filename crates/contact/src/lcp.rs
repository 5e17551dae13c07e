//! What every contact algorithm on the condensed problem shares: the LCP in
//! the contact forces (docs/theory/contact-problem.md), λ ≥ 0, w = W λ + q ≥ 0, λ·w = 0, with
//! W the Delassus operator (symmetric positive definite, or semi-definite
//! with redundant constraints) and q the gaps of the unconstrained solution;
//! the stopping test and the starts the methods share. What a method returns
//! is in [`crate::solution`].

pub mod augmented_lagrangian;
pub mod lemke;
pub mod mprgp;
pub mod mprgp_box;
pub mod penalty;
pub mod projected_gradient;
pub(crate) mod regularised;
pub mod smalbe;
pub mod uzawa;

use std::ops::Range;

use faer::Mat;

use crate::norms::{max_abs, nan_max, natural_map};
use crate::solution::{ContactSolution, DualDetail, SolverReport, StopReason};
use crate::ContactError;
pub(crate) use signorini_linalg::products::matvec;
use signorini_linalg::products::{add_columns_shared, affine, affine_into};

/// Options of an iterative or pivoting LCP method.
#[derive(Debug, Clone)]
pub struct LcpOptions {
    /// Relative tolerance of the natural residual (see [`lcp_residual`]).
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Force scale: forces are compared with tolerance × max(force_scale, ‖λ‖∞).
    pub force_scale: f64,
    /// Length scale: gaps are compared with tolerance × max(gap_scale, ‖w‖∞ of the active points).
    pub gap_scale: f64,
    /// Penalty or augmentation stiffness where the method has one (relative
    /// to the mean diagonal of W⁻¹, i.e. a multiple of the contact stiffness);
    /// `None` chooses a default.
    pub stiffness: Option<f64>,
    /// The wall-clock time at which every method stops, converged or not,
    /// after at least one iteration ([`LcpOptions::out_of_time`]): it then
    /// answers its last iterate with [`StopReason::TimeLimit`] (`None`: no
    /// time limit, the iteration limits alone).
    pub deadline: Option<std::time::Instant>,
}

impl Default for LcpOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 500,
            force_scale: 1.0,
            gap_scale: 1.0,
            stiffness: None,
            deadline: None,
        }
    }
}

impl LcpOptions {
    /// Whether a method that has made `iterations` iterations stops on its
    /// time limit: the deadline has passed and it made at least one, so
    /// that it answers an iterate of its own.
    pub(crate) fn out_of_time(&self, iterations: usize) -> bool {
        iterations > 0 && crate::options::deadline_passed(self.deadline)
    }
}

/// The stop of a method at its time limit after the iterations of
/// `report`, at the last residual of its history (`residual` if it has
/// none).
pub(crate) fn time_limit_stop(report: &SolverReport, residual: f64) -> StopReason {
    StopReason::TimeLimit {
        iterations: report.iterations,
        residual: report.residual_history.last().copied().unwrap_or(residual),
    }
}

impl ContactSolution {
    /// The solution with forces λ of LCP(W, q): its gaps W λ + q and the
    /// points with a positive force.
    pub fn from_forces(w: &Mat<f64>, q: &[f64], forces: Vec<f64>, report: SolverReport) -> Self {
        let gaps = gaps(w, q, &forces);
        Self::with_gaps(forces, gaps, Vec::new(), report)
    }
}

/// max(λ, 0) entry by entry (removes −0.0 and round-off below zero).
pub(crate) fn clamp(mut lambda: Vec<f64>) -> Vec<f64> {
    for v in &mut lambda {
        *v = if *v > 0.0 { *v } else { 0.0 };
    }
    lambda
}

/// w = W λ + q (column by column, skipping the zero forces: few points are
/// in contact).
pub fn gaps(w: &Mat<f64>, q: &[f64], lambda: &[f64]) -> Vec<f64> {
    affine(w, lambda, q)
}

/// g = W λ + q + G α: the gaps with the rigid-mode amplitudes α of the
/// floating bodies (G = B R).
pub fn constrained_gaps(
    w: &Mat<f64>,
    q: &[f64],
    g: &Mat<f64>,
    lambda: &[f64],
    alpha: &[f64],
) -> Vec<f64> {
    let mut gap = gaps(w, q, lambda);
    for (p, gp) in gap.iter_mut().enumerate() {
        for (j, a) in alpha.iter().enumerate() {
            *gp += g[(p, j)] * a;
        }
    }
    gap
}

/// The scaled natural residual of the LCP, max over points of
/// |min(λ_p / F, w_p / L)| with F = max(force_scale, ‖λ‖∞) and
/// L = gap_scale: zero exactly at a solution, and comparable with the
/// tolerance whatever the units.
pub fn lcp_residual(w: &Mat<f64>, q: &[f64], lambda: &[f64], opts: &LcpOptions) -> f64 {
    residual_from_gaps(lambda, &gaps(w, q, lambda), opts)
}

/// [`lcp_residual`] from gaps g = W λ + q already computed.
pub fn residual_from_gaps(lambda: &[f64], g: &[f64], opts: &LcpOptions) -> f64 {
    let f = opts.force_scale.max(max_abs(lambda)).max(f64::MIN_POSITIVE);
    let l = opts.gap_scale.max(f64::MIN_POSITIVE);
    lambda
        .iter()
        .zip(g)
        .map(|(&lp, &gp)| natural_map(lp / f, gp / l))
        .fold(0.0, nan_max)
}

/// [`check_input`], then the solution of the empty problem when m = 0
/// (`None`: there is something to solve).
pub(crate) fn checked_or_empty(
    w: &Mat<f64>,
    q: &[f64],
    method: &str,
) -> Result<Option<ContactSolution>, ContactError> {
    check_input(w, q, method)?;
    Ok(q.is_empty().then(|| ContactSolution::empty(method)))
}

/// How a dual method (Uzawa, augmented Lagrangian) starts from λ = 0.
pub(crate) enum DualStart {
    /// Nothing to iterate: the empty problem, or λ = 0 already within tolerance.
    Done(Box<ContactSolution>),
    /// Iterate from λ = 0.
    Iterate(DualIteration),
}

/// The start shared by the dual methods of course notes §3.2: checks the input,
/// answers the empty problem and a λ = 0 that already satisfies the
/// tolerance, and otherwise gives the iteration to run.
pub(crate) fn dual_start(
    w: &Mat<f64>,
    q: &[f64],
    opts: &LcpOptions,
    method: &str,
) -> Result<DualStart, ContactError> {
    if let Some(empty) = checked_or_empty(w, q, method)? {
        return Ok(DualStart::Done(Box::new(empty)));
    }
    let mut report = SolverReport {
        method: method.into(),
        ..Default::default()
    };
    let lambda = vec![0.0; q.len()];
    let r0 = residual_from_gaps(&lambda, q, opts);
    if r0 <= opts.tolerance {
        report.converged = true;
        report.stop = StopReason::ZeroForces { residual: r0 };
        return Ok(DualStart::Done(Box::new(ContactSolution::from_forces(
            w, q, lambda, report,
        ))));
    }
    Ok(DualStart::Iterate(DualIteration {
        report,
        r0,
        timed_out: false,
    }))
}

/// The iterations of a dual method (Uzawa, the augmented Lagrangian) from
/// λ = 0: their report, the residual `r0` of λ = 0, and whether they
/// stopped at the time limit.
pub(crate) struct DualIteration {
    pub(crate) report: SolverReport,
    r0: f64,
    timed_out: bool,
}

impl DualIteration {
    /// Starts the next iteration (counted in the report), or false at the
    /// iteration limit or, after the first iteration, at the time limit.
    pub(crate) fn next(&mut self, opts: &LcpOptions) -> bool {
        if self.report.iterations >= opts.max_iterations {
            return false;
        }
        if opts.out_of_time(self.report.iterations) {
            self.timed_out = true;
            return false;
        }
        self.report.iterations += 1;
        true
    }

    /// Records the natural residual after an iteration; true, and the
    /// report converged, when it meets the tolerance.
    pub(crate) fn converged_at(&mut self, residual: f64, opts: &LcpOptions) -> bool {
        self.report.residual_history.push(residual);
        if residual <= opts.tolerance {
            self.report.converged = true;
        }
        self.report.converged
    }

    /// Stops at the time limit reached inside an iteration.
    pub(crate) fn time_limit_reached(&mut self) {
        self.timed_out = true;
    }

    /// The answer λ, stopped as [`dual_stop`] says.
    pub(crate) fn finish(
        mut self,
        (w, q): (&Mat<f64>, &[f64]),
        lambda: Vec<f64>,
        detail: DualDetail,
        opts: &LcpOptions,
    ) -> ContactSolution {
        self.report.stop = dual_stop(opts, &self.report, self.r0, detail, self.timed_out);
        ContactSolution::from_forces(w, q, lambda, self.report)
    }
}

/// How a dual method (Uzawa, the augmented Lagrangian) stopped: converged at
/// its last residual, at its time limit (`timed_out`), or at its iteration
/// limit (the residual reached then, `r0` if it made no iteration).
fn dual_stop(
    opts: &LcpOptions,
    report: &SolverReport,
    r0: f64,
    detail: DualDetail,
    timed_out: bool,
) -> StopReason {
    let residual = report.residual_history.last().copied().unwrap_or(r0);
    if timed_out && !report.converged {
        return time_limit_stop(report, r0);
    }
    if report.converged {
        StopReason::DualConverged {
            residual,
            tolerance: opts.tolerance,
            iterations: report.iterations,
            detail,
        }
    } else {
        StopReason::DualLimit {
            limit: opts.max_iterations,
            residual,
            tolerance: opts.tolerance,
            detail,
        }
    }
}

/// Rejects a non-square W, a size mismatch with q, and any non-finite entry.
pub(crate) fn check_input(w: &Mat<f64>, q: &[f64], method: &str) -> Result<(), ContactError> {
    let m = q.len();
    if w.nrows() != m || w.ncols() != m {
        return Err(ContactError::Solve(format!(
            "{method}: W is {}×{} but q has {m} entries",
            w.nrows(),
            w.ncols()
        )));
    }
    check_finite(method, ("W", w), ("q", q))
}

/// Rejects the first non-finite entry of the vector `b` then of the matrix
/// `a` (column by column), naming it: "METHOD: q[i] = ... is not finite".
pub(crate) fn check_finite(
    method: &str,
    (a_name, a): (&str, &Mat<f64>),
    (b_name, b): (&str, &[f64]),
) -> Result<(), ContactError> {
    if let Some(p) = b.iter().position(|v| !v.is_finite()) {
        return Err(ContactError::Solve(format!(
            "{method}: {b_name}[{p}] = {} is not finite",
            b[p]
        )));
    }
    for j in 0..a.ncols() {
        if let Some(i) = a.col_as_slice(j).iter().position(|v| !v.is_finite()) {
            return Err(ContactError::Solve(format!(
                "{method}: {a_name}[({i}, {j})] = {} is not finite",
                a[(i, j)]
            )));
        }
    }
    Ok(())
}

/// g = W λ + q, into `g`.
pub(crate) fn gaps_into(w: &Mat<f64>, q: &[f64], lambda: &[f64], g: &mut [f64]) {
    affine_into(w, lambda, q, g);
}

/// g = W λ + q on the points outside `active` (sorted, and λ zero off it),
/// 0 on `active`, where the solve imposed it: |I|·|A| products instead of
/// m·|A|.
pub(crate) fn gaps_off_active(
    w: &Mat<f64>,
    q: &[f64],
    lambda: &[f64],
    active: &[usize],
) -> Vec<f64> {
    let m = q.len();
    let mut inactive = Vec::new();
    let mut start = 0;
    for &p in active.iter().chain(std::iter::once(&m)) {
        if p > start {
            inactive.push(start..p);
        }
        start = p + 1;
    }
    let mut g = vec![0.0; m];
    gaps_on_runs(w, q, lambda, active, &inactive, &mut g);
    g
}

/// g_p = W_p λ + q_p for the points p of `points` (sorted), λ being zero
/// off `active` (sorted); g elsewhere is left as it is.
pub(crate) fn gaps_on(
    w: &Mat<f64>,
    q: &[f64],
    lambda: &[f64],
    active: &[usize],
    points: &[usize],
    g: &mut [f64],
) {
    let mut runs: Vec<Range<usize>> = Vec::new();
    for &p in points {
        match runs.last_mut() {
            Some(r) if r.end == p => r.end += 1,
            _ => runs.push(p..p + 1),
        }
    }
    gaps_on_runs(w, q, lambda, active, &runs, g);
}

/// [`gaps_on`] on runs of consecutive points (whole slices of W's columns).
fn gaps_on_runs(
    w: &Mat<f64>,
    q: &[f64],
    lambda: &[f64],
    active: &[usize],
    runs: &[Range<usize>],
    g: &mut [f64],
) {
    for r in runs {
        g[r.clone()].copy_from_slice(&q[r.clone()]);
    }
    add_columns_shared(w, active, lambda, runs, g);
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The energy ½ λᵀ W λ + qᵀ λ = ½ λ·(g + q), from g = W λ + q.
pub(crate) fn energy_of(lambda: &[f64], g: &[f64], q: &[f64]) -> f64 {
    0.5 * lambda
        .iter()
        .zip(g.iter().zip(q))
        .map(|(l, (g, q))| l * (g + q))
        .sum::<f64>()
}

/// Mean of the diagonal of W (the mean compliance of a contact point).
pub(crate) fn mean_diag(w: &Mat<f64>) -> f64 {
    let m = w.nrows();
    if m == 0 {
        return 0.0;
    }
    (0..m).map(|i| w[(i, i)]).sum::<f64>() / m as f64
}

/// The largest eigenvalue of a symmetric positive semi-definite W by power
/// iteration: the Rayleigh quotient after at most `max_products` products,
/// stopping when it changes by at most `rel_tol` relatively. Returns
/// (Rayleigh quotient, products used).
pub(crate) fn power_iteration(w: &Mat<f64>, max_products: usize, rel_tol: f64) -> (f64, usize) {
    let m = w.nrows();
    // A deterministic start with components along every direction.
    let mut x: Vec<f64> = (0..m)
        .map(|i| 1.0 + 0.5 * ((i as f64) * 0.618_034).fract())
        .collect();
    let nx = dot(&x, &x).sqrt();
    if nx == 0.0 {
        return (0.0, 0);
    }
    x.iter_mut().for_each(|v| *v /= nx);
    let mut y = vec![0.0; m];
    let mut rq = 0.0;
    let mut products = 0;
    for _ in 0..max_products {
        matvec(w, &x, &mut y);
        products += 1;
        let new_rq = dot(&x, &y);
        let ny = dot(&y, &y).sqrt();
        if ny == 0.0 || !ny.is_finite() {
            break;
        }
        let done = (new_rq - rq).abs() <= rel_tol * new_rq.abs();
        rq = new_rq;
        if done {
            break;
        }
        for (xi, yi) in x.iter_mut().zip(&y) {
            *xi = yi / ny;
        }
    }
    (rq, products)
}

/// ‖W‖₂ for a fixed step length 1.9/‖W‖ (MPRGP's expansion step): the power
/// iteration to 10⁻³ in at most 50 products, enlarged by 1 % against the
/// under-estimate and capped by the upper bound ‖W‖∞ (also the fallback).
/// Returns (estimate, products used); the estimate is > 0 for W ≠ 0.
pub(crate) fn spectral_norm_estimate(w: &Mat<f64>) -> (f64, usize) {
    let m = w.nrows();
    let inf_norm = (0..m)
        .map(|i| (0..m).map(|j| w[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    if inf_norm == 0.0 {
        return (0.0, 0);
    }
    let (rq, products) = power_iteration(w, 50, 1e-3);
    if rq <= 0.0 {
        return (inf_norm, products);
    }
    ((1.01 * rq).min(inf_norm), products)
}

/// The system of the forces on an active set A with the equilibrium of the
/// floating bodies, [W_AA G_A; G_Aᵀ 0][λ_A; α] = [−q_A; e] (W_AA λ_A = −q_A
/// without them): its matrix and right-hand side.
pub(crate) fn saddle_point_system(
    w: &Mat<f64>,
    q: &[f64],
    g: &Mat<f64>,
    e: &[f64],
    active: &[usize],
) -> (Mat<f64>, Mat<f64>) {
    let (na, k) = (active.len(), g.ncols());
    let dim = na + k;
    let mut a = Mat::<f64>::zeros(dim, dim);
    let mut rhs = Mat::<f64>::zeros(dim, 1);
    for (ii, &p) in active.iter().enumerate() {
        for (jj, &r) in active.iter().enumerate() {
            a[(ii, jj)] = w[(p, r)];
        }
        for j in 0..k {
            a[(ii, na + j)] = g[(p, j)];
            a[(na + j, ii)] = g[(p, j)];
        }
        rhs[(ii, 0)] = -q[p];
    }
    for j in 0..k {
        rhs[(na + j, 0)] = e[j];
    }
    (a, rhs)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric W with entries of both signs (the sweeps must not
    /// rely on symmetry) and λ zero on some active points.
    fn problem(m: usize) -> (Mat<f64>, Vec<f64>, Vec<f64>, Vec<usize>) {
        let w = Mat::<f64>::from_fn(m, m, |i, j| ((3 * i + 7 * j) as f64 * 0.37).sin());
        let q: Vec<f64> = (0..m).map(|i| (i as f64 * 0.9).cos()).collect();
        let active: Vec<usize> = (0..m).filter(|&p| p % 5 != 0 && p != m - 2).collect();
        let mut lambda = vec![0.0; m];
        for &p in &active {
            lambda[p] = if p % 7 == 3 {
                0.0
            } else {
                1.0 + p as f64 * 0.1
            };
        }
        (w, q, lambda, active)
    }

    /// W λ + q by the definition, one entry after the other.
    fn reference(w: &Mat<f64>, q: &[f64], lambda: &[f64]) -> Vec<f64> {
        (0..q.len())
            .map(|i| q[i] + (0..q.len()).map(|j| w[(i, j)] * lambda[j]).sum::<f64>())
            .collect()
    }

    /// The sweeps four columns at a time (with a remainder) give W λ + q to
    /// round-off: on every point, off the active set only (0 on it), and
    /// then on the active set.
    #[test]
    fn gap_sweeps_agree_with_the_definition() {
        for m in [1, 4, 11, 30] {
            let (w, q, lambda, active) = problem(m);
            let want = reference(&w, &q, &lambda);
            let scale = 1.0 + want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let all = gaps(&w, &q, &lambda);
            let off = gaps_off_active(&w, &q, &lambda, &active);
            let mut on = off.clone();
            gaps_on(&w, &q, &lambda, &active, &active, &mut on);
            for p in 0..m {
                assert!((on[p] - want[p]).abs() <= 1e-13 * scale, "m {m}, {p}");
                assert!((all[p] - want[p]).abs() <= 1e-13 * scale, "m {m}, {p}");
                let expected = if active.contains(&p) { 0.0 } else { want[p] };
                assert!((off[p] - expected).abs() <= 1e-13 * scale, "m {m}, {p}");
            }
        }
    }
}
