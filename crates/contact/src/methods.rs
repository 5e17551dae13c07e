//! One entry point for every algorithm on LCP(W, q) (DESIGN.md §4), so that
//! the pipeline, `signorini local` and the benchmarks select them by name.
//! Each algorithm lives in its own file: [`crate::status`],
//! [`crate::lemke`], [`crate::projected_gradient`], [`crate::mprgp`],
//! [`crate::uzawa`], [`crate::augmented_lagrangian`], [`crate::penalty`].

use faer::Mat;

use crate::lcp::{gaps, lcp_residual, LcpOptions, LcpSolution, SolverReport};
use crate::status::{status_method, ActiveSetSolve, StatusOptions, StatusVariant};
use crate::ContactError;

/// The algorithms on the condensed problem in the forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Algorithm {
    /// Status method (seed §3.3), constraints by Lagrange multipliers.
    Status(StatusVariant),
    /// Status method with the active constraints imposed by penalty (seed §3.3).
    StatusPenalty(StatusVariant),
    Lemke,
    ProjectedGradient,
    ProjectedConjugateGradient,
    Mprgp,
    Uzawa,
    AugmentedLagrangian,
    /// The penalty method / regularised law (seed §3.6).
    Penalty,
}

impl Algorithm {
    pub fn name(self) -> &'static str {
        match self {
            Algorithm::Status(_) => "status",
            Algorithm::StatusPenalty(_) => "status_penalty",
            Algorithm::Lemke => "lemke",
            Algorithm::ProjectedGradient => "projected_gradient",
            Algorithm::ProjectedConjugateGradient => "projected_conjugate_gradient",
            Algorithm::Mprgp => "mprgp",
            Algorithm::Uzawa => "uzawa",
            Algorithm::AugmentedLagrangian => "augmented_lagrangian",
            Algorithm::Penalty => "penalty",
        }
    }

    /// Whether the answer is the exact solution of the LCP (not a regularised one).
    pub fn is_exact(self) -> bool {
        !matches!(self, Algorithm::Penalty | Algorithm::StatusPenalty(_))
    }
}

/// LCP(W, q) as an [`ActiveSetSolve`]: W_AA λ_A = −q_A.
pub struct DenseLcp<'a> {
    pub w: &'a Mat<f64>,
    pub q: &'a [f64],
    pub solves: usize,
}

impl ActiveSetSolve for DenseLcp<'_> {
    fn n_points(&self) -> usize {
        self.q.len()
    }
    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        use faer::prelude::Solve;
        self.solves += 1;
        let m = self.q.len();
        let na = active.len();
        let mut lambda = vec![0.0; m];
        if na > 0 {
            let a = Mat::<f64>::from_fn(na, na, |i, j| self.w[(active[i], active[j])]);
            let rhs = Mat::<f64>::from_fn(na, 1, |i, _| -self.q[active[i]]);
            let x = match a.llt(faer::Side::Lower) {
                Ok(l) => l.solve(&rhs),
                Err(_) => crate::delassus::solve_checked(
                    &a,
                    &rhs,
                    "W_AA is singular: redundant contact constraints",
                )?,
            };
            for (i, &p) in active.iter().enumerate() {
                lambda[p] = x[(i, 0)];
            }
        }
        let g = gaps(self.w, self.q, &lambda);
        Ok((lambda, g))
    }
}

/// Solves LCP(W, q) with `algorithm`. `stiffness` gives the penalty
/// stiffness per point for the penalty algorithms (force per unit gap);
/// `None` uses `opts.stiffness` (default 1e8) / mean diag W.
pub fn solve_lcp(
    algorithm: Algorithm,
    w: &Mat<f64>,
    q: &[f64],
    stiffness: Option<&[f64]>,
    opts: &LcpOptions,
) -> Result<LcpSolution, ContactError> {
    let k = || -> Vec<f64> {
        stiffness
            .map(|k| k.to_vec())
            .unwrap_or_else(|| crate::penalty::uniform_stiffness(w, opts.stiffness.unwrap_or(1e8)))
    };
    let mut sol = match algorithm {
        Algorithm::Status(variant) => {
            let mut p = DenseLcp { w, q, solves: 0 };
            let closed = opts.tolerance * opts.gap_scale;
            let out = status_method(
                &mut p,
                &StatusOptions::from_lcp(
                    variant,
                    opts,
                    Some((0..q.len()).filter(|&i| q[i] <= closed).collect()),
                ),
            )?;
            LcpSolution {
                report: SolverReport {
                    method: "status".into(),
                    converged: out.converged,
                    iterations: out.iterations,
                    operator_applications: p.solves,
                    residual_history: vec![],
                    stopping_reason: out.stopping_reason,
                },
                lambda: out.lambda,
            }
        }
        Algorithm::StatusPenalty(variant) => {
            crate::penalty::status_with_penalty(w, q, &k(), variant, opts)?
        }
        Algorithm::Lemke => crate::lemke::lemke(w, q, opts)?,
        Algorithm::ProjectedGradient => crate::projected_gradient::projected_gradient(w, q, opts)?,
        Algorithm::ProjectedConjugateGradient => {
            crate::projected_gradient::projected_conjugate_gradient(w, q, opts)?
        }
        Algorithm::Mprgp => crate::mprgp::mprgp(w, q, opts)?,
        Algorithm::Uzawa => crate::uzawa::uzawa(w, q, opts)?,
        Algorithm::AugmentedLagrangian => {
            crate::augmented_lagrangian::augmented_lagrangian(w, q, opts)?
        }
        Algorithm::Penalty => crate::penalty::penalty(w, q, &k(), opts)?,
    };
    if algorithm.is_exact() && !matches!(algorithm, Algorithm::Status(_)) && sol.report.converged {
        polish(w, q, &mut sol, opts);
    }
    sol.report.method = algorithm.name().into();
    if sol.report.residual_history.is_empty() {
        sol.report
            .residual_history
            .push(lcp_residual(w, q, &sol.lambda, opts));
    }
    Ok(sol)
}

/// Active-set polishing: an iterative method that has converged to the
/// tolerance has (in all but degenerate cases) found the active set A of the
/// solution; solving W_AA λ_A = −q_A then gives the solution to round-off
/// instead of to the tolerance times the condition number of W. The polished
/// forces are kept only if they are a solution of the LCP at least as good as
/// the iterate (λ ≥ 0 and g ≥ 0 to tolerance).
fn polish(w: &Mat<f64>, q: &[f64], sol: &mut LcpSolution, opts: &LcpOptions) {
    let lmax = sol.lambda.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let active: Vec<usize> = (0..q.len())
        .filter(|&p| sol.lambda[p] > 1e-14 * lmax)
        .collect();
    let mut p = DenseLcp { w, q, solves: 0 };
    let Ok((lambda, g)) = p.solve_active(&active) else {
        return;
    };
    let f = opts.force_scale.max(lmax).max(f64::MIN_POSITIVE);
    let feasible = lambda.iter().all(|&l| l >= -opts.tolerance * f)
        && g.iter()
            .enumerate()
            .all(|(i, &gi)| active.contains(&i) || gi >= -opts.tolerance * opts.gap_scale);
    let before = lcp_residual(w, q, &sol.lambda, opts);
    let clamped: Vec<f64> = lambda.iter().map(|l| l.max(0.0)).collect();
    let after = lcp_residual(w, q, &clamped, opts);
    if feasible && after <= before.max(opts.tolerance) {
        sol.lambda = clamped;
        sol.report
            .record_polish(after, "solve on the identified active set");
    }
}

/// Solves LCP(W, q) with the equilibrium of floating bodies Gᵀλ = e (see
/// [`crate::smalbe`]) by SMALBE with `algorithm` as the bound-constrained
/// inner solver (MPRGP warm-started, as in Dostál's SMALBE-M). The penalty
/// algorithms solve their regularised law, LCP(W + K⁻¹, q) with K the
/// penalty stiffness per point (seed §3.6), exactly inside SMALBE. Without
/// a kernel (G with no column) this is one call of [`solve_lcp`].
pub fn solve_lcp_constrained(
    algorithm: Algorithm,
    w: &Mat<f64>,
    q: &[f64],
    g: &Mat<f64>,
    e: &[f64],
    stiffness: Option<&[f64]>,
    opts: &LcpOptions,
) -> Result<crate::smalbe::ConstrainedSolution, ContactError> {
    let regularised;
    let (w_eff, inner_algorithm) = if algorithm.is_exact() {
        (w, algorithm)
    } else {
        let k = stiffness
            .map(|k| k.to_vec())
            .unwrap_or_else(|| crate::penalty::uniform_stiffness(w, opts.stiffness.unwrap_or(1e8)));
        let mut wk = w.clone();
        for (i, &ki) in k.iter().enumerate() {
            wk[(i, i)] += 1.0 / ki;
        }
        regularised = wk;
        (&regularised, Algorithm::Status(StatusVariant::All))
    };
    let mut sol = crate::smalbe::smalbe(w_eff, q, g, e, opts, |wi, qi, l0, o| {
        if inner_algorithm == Algorithm::Mprgp {
            crate::mprgp::mprgp_from(wi, qi, l0, o)
        } else {
            solve_lcp(inner_algorithm, wi, qi, None, o)
        }
    })?;
    sol.report.method = algorithm.name().into();
    if !algorithm.is_exact() {
        // The gaps of the regularised law are those of W, not W + K⁻¹.
        sol.gap = crate::lcp::constrained_gaps(w, q, g, &sol.lambda, &sol.alpha);
    }
    Ok(sol)
}
