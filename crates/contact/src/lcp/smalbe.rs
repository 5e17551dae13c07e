//! Bodies held by contact alone: the LCP with the equilibrium of their rigid
//! modes as an equality constraint, solved by SMALBE (semi-monotonic
//! augmented Lagrangian for bound and equality constraints: Z. Dostál,
//! *Optimal Quadratic Programming Algorithms*, Springer 2009, ch. 9; the
//! dual problem of TFETI, Dostál, Horák & Kučera 2006).
//!
//! A floating body makes the interface stiffness S singular with kernel R
//! (docs/theory/contact-problem.md, [`crate::delassus`]). Its contact forces must balance its
//! load on every rigid mode, Rᵀ(F' + Bᵀλ) = 0, i.e. Gᵀλ = e with G = B R and
//! e = −Rᵀ F'; the problem in the forces is the quadratic programme
//!
//! ```text
//! min f(λ) = ½ λᵀ W λ + qᵀ λ   subject to   λ ≥ 0,  Gᵀ λ = e,
//! ```
//!
//! whose KKT conditions are the Signorini conditions with the gaps
//! g = W λ + q + G α ≥ 0, λ ≥ 0, λ·g = 0: α, the multiplier of the equality,
//! is the amplitude of the rigid motion of the body (course notes §3.2 for the
//! projection methods on the forces, §3.4 for the augmented Lagrangian).
//!
//! SMALBE keeps the bound constraints in the inner problem and treats the
//! equality by an augmented Lagrangian with multiplier μ and penalty ρ:
//!
//! ```text
//! L(λ, μ, ρ) = f(λ) + μᵀ(Gᵀλ − e) + ρ/2 ‖Gᵀλ − e‖²,
//! ∇_λ L = (W + ρ G Gᵀ) λ + q + G μ − ρ G e.
//! ```
//!
//! Each outer iteration minimises L over λ ≥ 0 — an LCP with the SPD matrix
//! W + ρGGᵀ, solved by MPRGP (or any of the bound-constrained methods),
//! warm-started, to a precision tied to the current infeasibility
//! (‖gᴾ‖ ≤ min(M ‖Gᵀλ − e‖, η) in Dostál's form) — then updates
//! μ ← μ + ρ (Gᵀλ − e) and raises ρ when the infeasibility did not fall
//! enough. After the update the inner gradient is exactly the gap vector of
//! the original problem with α = μ, so the stopping test is the natural
//! residual of the Signorini conditions plus the equality residual. No
//! artificial spring is added: the answer satisfies Gᵀλ = e to the tolerance.
//!
//! The answer is finally polished by one saddle-point solve on the
//! identified active set A, [W_AA G_A; G_Aᵀ 0][λ_A; α] = [−q_A; e], kept
//! only if it is at least as good.

use faer::Mat;

use crate::lcp::{constrained_gaps, residual_from_gaps, spectral_norm_estimate, LcpOptions};
use crate::solution::{
    ContactSolution, PolishSolve, SmalbeProgress, SmalbeStop, SolverReport, StopReason,
};
use crate::ContactError;

/// Factor by which ρ grows when the infeasibility fell by less than
/// [`FEASIBILITY_DECREASE`] in one outer iteration (Dostál's β > 1).
const RHO_GROWTH: f64 = 10.0;
/// Required decrease of ‖Gᵀλ − e‖ per outer iteration before ρ grows.
const FEASIBILITY_DECREASE: f64 = 0.25;
/// ρ‖GGᵀ‖ is kept below this multiple of ‖W‖ (the conditioning of the
/// inner problem).
const RHO_CAP: f64 = 1e8;
/// Outer iterations at most (each solves an inner LCP).
const MAX_OUTER: usize = 60;

/// The relative residual of Gᵀλ = e: max_j |(Gᵀλ − e)_j| over the size of
/// the terms summed (max_j Σ_p |G_pj λ_p| and |e_j|, at least the force
/// scale times the largest |G_pj|), so that it compares with a tolerance in
/// any units.
pub fn equality_residual(g: &Mat<f64>, e: &[f64], lambda: &[f64], force_scale: f64) -> f64 {
    let (m, k) = (g.nrows(), g.ncols());
    let mut worst = 0.0f64;
    let gmax = g.norm_max();
    for j in 0..k {
        let mut sum = -e[j];
        let mut size = e[j].abs().max(force_scale * gmax);
        for p in 0..m {
            sum += g[(p, j)] * lambda[p];
            size = size.max((g[(p, j)] * lambda[p]).abs());
        }
        if size > 0.0 {
            worst = worst.max(sum.abs() / size);
        }
    }
    worst
}

fn equality_vector(g: &Mat<f64>, e: &[f64], lambda: &[f64]) -> Vec<f64> {
    (0..g.ncols())
        .map(|j| (0..g.nrows()).map(|p| g[(p, j)] * lambda[p]).sum::<f64>() - e[j])
        .collect()
}

/// Solves min ½λᵀWλ + qᵀλ over λ ≥ 0 with Gᵀλ = e by SMALBE (module
/// documentation). `inner(w, q, λ0, opts)` solves the bound-constrained
/// LCP(w, q) from the warm start λ0 (it may ignore it); the outer loop
/// passes it W + ρGGᵀ and q + Gμ − ρGe. The answer carries α, the
/// multiplier of the equality, and the gaps g = W λ + q + G α.
pub fn smalbe(
    w: &Mat<f64>,
    q: &[f64],
    g: &Mat<f64>,
    e: &[f64],
    opts: &LcpOptions,
    mut inner: impl FnMut(
        &Mat<f64>,
        &[f64],
        &[f64],
        &LcpOptions,
    ) -> Result<ContactSolution, ContactError>,
) -> Result<ContactSolution, ContactError> {
    let (m, k) = (g.nrows(), g.ncols());
    assert_eq!(m, q.len());
    assert_eq!(k, e.len());
    let pb = Constrained { w, q, g, e, opts };
    let mut report = SolverReport {
        method: "smalbe".into(),
        ..Default::default()
    };
    let (ggt, mut rho) = penalty_start(w, g, &mut report)?;
    let rho_max = RHO_CAP * rho;
    let mut mu = vec![0.0; k];
    let mut lambda = vec![0.0; m];
    let mut feas_prev = f64::INFINITY;
    let mut inner_iterations = 0usize;
    let mut last_inner = StopReason::Pending;
    let mut previous_active: Option<Vec<bool>> = None;
    for outer in 0..MAX_OUTER {
        if opts.out_of_time(outer) {
            return Ok(pb.timed_out(lambda, mu, report));
        }
        let (w_in, q_in) = inner_problem(w, q, g, e, &ggt, &mu, rho);
        let inner_opts = LcpOptions {
            tolerance: inner_tolerance(g, e, &lambda, opts, outer),
            ..opts.clone()
        };
        let sol = inner(&w_in, &q_in, &lambda, &inner_opts)?;
        inner_iterations += sol.report.iterations;
        report.operator_applications += sol.report.operator_applications;
        last_inner = sol.report.stop.clone();
        if let StopReason::TimeLimit { .. } = sol.report.stop {
            report.iterations = outer + 1;
            return Ok(pb.timed_out(sol.forces, mu, report));
        }
        if !sol.report.converged && inner_opts.tolerance <= opts.tolerance {
            return Ok(pb.inner_failed(sol, mu, report, outer));
        }
        lambda = sol.forces;
        update_multiplier(&mut mu, rho, &equality_vector(g, e, &lambda));
        let gap = constrained_gaps(w, q, g, &lambda, &mu);
        let natural = residual_from_gaps(&lambda, &gap, opts);
        let feas = equality_residual(g, e, &lambda, opts.force_scale);
        report.iterations = outer + 1;
        report.residual_history.push(natural.max(feas));
        let active: Vec<bool> = lambda.iter().map(|&l| l > 0.0).collect();
        let settled = k > 0 && previous_active.as_ref() == Some(&active);
        previous_active = Some(active);
        let met = natural <= opts.tolerance && feas <= opts.tolerance;
        let progress = SmalbeProgress {
            outer: outer + 1,
            inner_iterations,
            rho,
        };
        if settled && !met {
            // The active set has settled: one saddle-point solve on it may
            // finish the job (polish keeps it only if it is better).
            let trial =
                ContactSolution::with_gaps(lambda.clone(), gap.clone(), mu.clone(), report.clone());
            if let Some(done) = pb.polish_settled(trial, progress, &last_inner) {
                return Ok(done);
            }
        }
        if met {
            report.converged = true;
            report.stop = StopReason::Smalbe(SmalbeStop::Met {
                natural,
                feasibility: feas,
                tolerance: opts.tolerance,
                progress,
                last_inner: Box::new(last_inner),
            });
            return Ok(pb.polished(lambda, mu, gap, report));
        }
        if feas > FEASIBILITY_DECREASE * feas_prev && rho * RHO_GROWTH <= rho_max {
            rho *= RHO_GROWTH;
        }
        feas_prev = feas;
    }
    Ok(pb.exhausted(lambda, mu, report, rho, last_inner))
}

/// The data of the constrained problem, for the steps of [`smalbe`].
struct Constrained<'a> {
    w: &'a Mat<f64>,
    q: &'a [f64],
    g: &'a Mat<f64>,
    e: &'a [f64],
    opts: &'a LcpOptions,
}

impl Constrained<'_> {
    /// The converged iterate, polished on its active set ([`polish`] keeps
    /// the polished point only if it is at least as good).
    fn polished(
        &self,
        lambda: Vec<f64>,
        mu: Vec<f64>,
        gap: Vec<f64>,
        report: SolverReport,
    ) -> ContactSolution {
        let mut out = ContactSolution::with_gaps(lambda, gap, mu, report);
        polish(self.w, self.q, self.g, self.e, &mut out, self.opts);
        out
    }

    /// The inner solver did not converge at the final precision: its
    /// answer, with the gaps at the current μ, reported as not converged.
    fn inner_failed(
        &self,
        sol: ContactSolution,
        mu: Vec<f64>,
        mut report: SolverReport,
        outer: usize,
    ) -> ContactSolution {
        report.stop = StopReason::Smalbe(SmalbeStop::InnerFailed {
            outer: outer + 1,
            inner: Box::new(sol.report.stop),
        });
        report.iterations = outer + 1;
        let gap = constrained_gaps(self.w, self.q, self.g, &sol.forces, &mu);
        ContactSolution::with_gaps(sol.forces, gap, mu, report)
    }

    /// The active set has settled: one saddle-point solve on it
    /// ([`polish`]) may finish the job; the answer, marked converged, when
    /// it does. `progress` says after how many outer and inner iterations,
    /// at which ρ.
    fn polish_settled(
        &self,
        mut trial: ContactSolution,
        progress: SmalbeProgress,
        last_inner: &StopReason,
    ) -> Option<ContactSolution> {
        if !polish(self.w, self.q, self.g, self.e, &mut trial, self.opts) {
            return None;
        }
        trial.report.converged = true;
        let settled = SmalbeStop::Settled {
            progress,
            tolerance: self.opts.tolerance,
            last_inner: Box::new(last_inner.clone()),
        };
        // The reason says the saddle-point solve finished the job (it
        // replaces the polish's own record).
        trial.report.stop = StopReason::Smalbe(settled);
        Some(trial)
    }

    /// The deadline of the options passed (between outer iterations or in
    /// an inner solve): the iterate `lambda`, not converged, at its natural
    /// residual ([`StopReason::TimeLimit`]).
    fn timed_out(
        &self,
        lambda: Vec<f64>,
        mu: Vec<f64>,
        mut report: SolverReport,
    ) -> ContactSolution {
        let gap = constrained_gaps(self.w, self.q, self.g, &lambda, &mu);
        report.stop = StopReason::TimeLimit {
            iterations: report.iterations,
            residual: residual_from_gaps(&lambda, &gap, self.opts),
        };
        ContactSolution::with_gaps(lambda, gap, mu, report)
    }

    /// [`MAX_OUTER`] outer iterations without meeting the tolerance: the
    /// last iterate, reported as not converged with its residuals.
    fn exhausted(
        &self,
        lambda: Vec<f64>,
        mu: Vec<f64>,
        mut report: SolverReport,
        rho: f64,
        last_inner: StopReason,
    ) -> ContactSolution {
        let (g, opts) = (self.g, self.opts);
        let gap = constrained_gaps(self.w, self.q, g, &lambda, &mu);
        let natural = residual_from_gaps(&lambda, &gap, opts);
        let feas = equality_residual(g, self.e, &lambda, opts.force_scale);
        report.stop = StopReason::Smalbe(SmalbeStop::Exhausted {
            outer: MAX_OUTER,
            tolerance: opts.tolerance,
            natural,
            feasibility: feas,
            rho,
            last_inner: Box::new(last_inner),
        });
        ContactSolution::with_gaps(lambda, gap, mu, report)
    }
}

/// GGᵀ and the starting penalty ρ = ‖W‖ / ‖GᵀG‖ (the norm of GᵀG is the
/// largest eigenvalue of the k × k matrix); refused when G = 0, i.e. no
/// contact point acts on the rigid motions. Counts the products of the
/// estimate of ‖W‖ in the report.
fn penalty_start(
    w: &Mat<f64>,
    g: &Mat<f64>,
    report: &mut SolverReport,
) -> Result<(Mat<f64>, f64), ContactError> {
    let (m, k) = (g.nrows(), g.ncols());
    let mut ggt = Mat::<f64>::zeros(m, m);
    faer::linalg::matmul::matmul(
        ggt.as_mut(),
        faer::Accum::Replace,
        g.as_ref(),
        g.transpose(),
        1.0,
        faer::Par::Seq,
    );
    let gtg = g.transpose() * g;
    let norm_gtg = gtg
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .map(|v| v.iter().fold(0.0f64, |a, &x| a.max(x)))
        .unwrap_or(0.0);
    if k > 0 && (norm_gtg.is_nan() || norm_gtg <= 0.0) {
        return Err(ContactError::Singular(
            "a floating body has no contact point that acts on its rigid motions (G = B R = 0)"
                .into(),
        ));
    }
    let (norm_w, products) = spectral_norm_estimate(w);
    report.operator_applications += products;
    let norm_w = norm_w.max(f64::MIN_POSITIVE);
    let rho = if k > 0 { norm_w / norm_gtg } else { 0.0 };
    Ok((ggt, rho))
}

/// The multiplier update μ ← μ + ρ (Gᵀλ − e), `r` = Gᵀλ − e.
fn update_multiplier(mu: &mut [f64], rho: f64, r: &[f64]) {
    for (m, rj) in mu.iter_mut().zip(r) {
        *m += rho * rj;
    }
}

/// The inner problem of one outer iteration: LCP(W + ρGGᵀ, q + Gμ − ρGe).
fn inner_problem(
    w: &Mat<f64>,
    q: &[f64],
    g: &Mat<f64>,
    e: &[f64],
    ggt: &Mat<f64>,
    mu: &[f64],
    rho: f64,
) -> (Mat<f64>, Vec<f64>) {
    let (m, k) = (g.nrows(), g.ncols());
    let mut w_in = w.clone();
    if k > 0 {
        for j in 0..m {
            for i in 0..m {
                w_in[(i, j)] += rho * ggt[(i, j)];
            }
        }
    }
    let q_in: Vec<f64> = (0..m)
        .map(|p| {
            q[p] + (0..k)
                .map(|j| g[(p, j)] * (mu[j] - rho * e[j]))
                .sum::<f64>()
        })
        .collect();
    (w_in, q_in)
}

/// Inner precision: tied to the current infeasibility (Dostál's
/// ‖gᴾ‖ ≤ min(M‖Gᵀλ − e‖, η)) and tightened tenfold per outer
/// iteration (the two residuals are measured in different units, so
/// M is not known in advance), never tighter than the tolerance.
fn inner_tolerance(
    g: &Mat<f64>,
    e: &[f64],
    lambda: &[f64],
    opts: &LcpOptions,
    outer: usize,
) -> f64 {
    if g.ncols() == 0 {
        return opts.tolerance;
    }
    let feas_rel = if outer == 0 {
        1.0
    } else {
        equality_residual(g, e, lambda, opts.force_scale)
    };
    (feas_rel.min(1e-2) * 0.1f64.powi(outer as i32)).max(opts.tolerance)
}

/// One saddle-point solve on the active set of an answer (see the module
/// documentation); kept, and `true`, when it is a solution (compressive
/// forces, open gaps elsewhere).
fn polish(
    w: &Mat<f64>,
    q: &[f64],
    g: &Mat<f64>,
    e: &[f64],
    sol: &mut ContactSolution,
    opts: &LcpOptions,
) -> bool {
    let (m, k) = (g.nrows(), g.ncols());
    let lmax = sol.forces.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let active: Vec<usize> = (0..m).filter(|&p| sol.forces[p] > 1e-14 * lmax).collect();
    let na = active.len();
    if na + k == 0 {
        return false;
    }
    let (a, rhs) = crate::lcp::saddle_point_system(w, q, g, e, &active);
    let Ok(x) = signorini_linalg::pivot_policy::solve_checked(&a, &rhs, "polish") else {
        return false;
    };
    // The exact solution for this active set is the solution of the LCP
    // when its forces are compressive and its other gaps open (to the
    // tolerance): then it is kept, as the status method keeps its last
    // active set; the gaps of the active points vanish by construction, to
    // the round-off of W λ + q + G α.
    let raw: Vec<f64> = (0..na).map(|ii| x[(ii, 0)]).collect();
    let mut lambda = vec![0.0; m];
    for (ii, &p) in active.iter().enumerate() {
        lambda[p] = raw[ii].max(0.0);
    }
    let alpha: Vec<f64> = (0..k).map(|j| x[(na + j, 0)]).collect();
    let gap = constrained_gaps(w, q, g, &lambda, &alpha);
    let fscale = opts.force_scale.max(lmax);
    let compressive = raw.iter().all(|&l| l >= -opts.tolerance * fscale);
    let mut is_active = vec![false; m];
    active.iter().for_each(|&p| is_active[p] = true);
    let open = (0..m).all(|p| is_active[p] || gap[p] >= -opts.tolerance * opts.gap_scale);
    if compressive && open {
        let after = residual_from_gaps(&lambda, &gap, opts).max(equality_residual(
            g,
            e,
            &lambda,
            opts.force_scale,
        ));
        sol.set_forces(lambda, gap);
        sol.alpha = alpha;
        sol.report.record_polish(after, PolishSolve::SaddlePoint);
        return true;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::active_set::signorini::status_method;
    use crate::lcp::mprgp::mprgp_from;
    use crate::lcp::projected_gradient::test_support::{random_spd, random_vec, tight, Rng};
    use crate::DelassusProblem;
    use faer::prelude::Solve;

    fn inner_mprgp(
        w: &Mat<f64>,
        q: &[f64],
        l0: &[f64],
        o: &LcpOptions,
    ) -> Result<ContactSolution, ContactError> {
        mprgp_from(w, q, l0, o)
    }

    /// A point mass on two springs' worth of contacts: W = I, one rigid
    /// mode acting on both points (G = [1; 1]), load e = 3 to balance.
    /// min ½(λ1² + λ2²) − λ1 + λ2 with λ1 + λ2 = 3, λ ≥ 0: both in contact,
    /// g = λ + q + α = 0 gives λ1 = 1 − α, λ2 = −1 − α, so α = −1.5 and
    /// λ = (2.5, 0.5).
    #[test]
    fn a_floating_point_held_by_two_contacts_matches_the_hand_solution() {
        let w = Mat::<f64>::identity(2, 2);
        let q = [-1.0, 1.0];
        let g = Mat::<f64>::from_fn(2, 1, |_, _| 1.0);
        let sol = smalbe(&w, &q, &g, &[3.0], &tight(), inner_mprgp).unwrap();
        assert!(sol.report.converged, "{}", sol.report.stop);
        let tol = 1e-10 * 3.0;
        assert!((sol.forces[0] - 2.5).abs() <= tol, "{:?}", sol.forces);
        assert!((sol.forces[1] - 0.5).abs() <= tol, "{:?}", sol.forces);
        assert!((sol.alpha[0] + 1.5).abs() <= tol, "{:?}", sol.alpha);
        assert!(sol.gaps.iter().all(|v| v.abs() <= tol));
    }

    /// Random SPD W, random q, a random kernel: SMALBE with MPRGP inside
    /// gives the answer of the status method on the saddle-point systems
    /// (DelassusProblem with the same kernel), forces and rigid amplitudes.
    #[test]
    fn smalbe_agrees_with_the_status_method_on_floating_bodies() {
        for seed in 1..=12u64 {
            let mut rng = Rng::new(seed);
            let n = 24;
            let k = 1 + (seed as usize % 3);
            // S = A Aᵀ + (positive on the complement of R): build S from a
            // random SPD matrix projected off a random R, so S R = 0.
            let r = Mat::<f64>::from_fn(n, k, |_, _| rng.uniform() - 0.5);
            let spd = random_spd(n, &mut rng);
            // P = I − R (RᵀR)⁻¹ Rᵀ, the orthogonal projector off R.
            let rtr_inv = (r.transpose() * &r)
                .full_piv_lu()
                .solve(Mat::<f64>::identity(k, k));
            let p = Mat::<f64>::identity(n, n) - &r * &rtr_inv * r.transpose();
            let s = &p * &spd * &p;
            // Contacts: m rows, each a unit row on one DOF.
            let m = 10;
            let rows: Vec<Vec<(usize, f64)>> = (0..m).map(|i| vec![(2 * i, 1.0)]).collect();
            let gap0 = random_vec(m, &mut rng);
            // A load the contacts can balance: F' = −Bᵀ λ* for some λ* ≥ 0, plus
            // a self-equilibrated part.
            let lstar: Vec<f64> = (0..m).map(|_| 0.5 * (rng.uniform() + 1.0)).collect();
            let extra = random_vec(n, &mut rng);
            let mut f: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| p[(i, j)] * extra[j]).sum::<f64>())
                .collect();
            for (i, row) in rows.iter().enumerate() {
                for &(d, c) in row {
                    f[d] -= c * lstar[i];
                }
            }
            let mut prob = DelassusProblem::new(&s, &rows, &gap0, &f, &r).unwrap();
            let opts = tight();
            let exact = status_method(
                &mut prob,
                &crate::StatusOptions {
                    variant: crate::StatusVariant::All,
                    max_iterations: 200,
                    tolerance: 1e-12,
                    force_scale: 1.0,
                    gap_scale: 1.0,
                    initial_active: None,
                    deadline: None,
                },
            )
            .unwrap();
            assert!(exact.report.converged, "seed {seed}: {}", exact.report.stop);
            let sol = smalbe(&prob.w, &prob.q, &prob.g_mat, &prob.e, &opts, inner_mprgp).unwrap();
            assert!(sol.report.converged, "seed {seed}: {}", sol.report.stop);
            let scale = exact.forces.iter().fold(1.0f64, |a, v| a.max(v.abs()));
            let d = sol
                .forces
                .iter()
                .zip(&exact.forces)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            assert!(d <= 1e-8 * scale, "seed {seed}: forces differ by {d:e}");
            let da = sol
                .alpha
                .iter()
                .zip(prob.alpha())
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            let ascale = prob.alpha().iter().fold(1.0f64, |a, v| a.max(v.abs()));
            assert!(da <= 1e-7 * ascale, "seed {seed}: α differ by {da:e}");
        }
    }

    /// No kernel: SMALBE is the inner method itself, in one outer iteration.
    #[test]
    fn without_floating_bodies_smalbe_is_its_inner_method() {
        let mut rng = Rng::new(7);
        let w = random_spd(15, &mut rng);
        let q = random_vec(15, &mut rng);
        let g = Mat::<f64>::zeros(15, 0);
        let sol = smalbe(&w, &q, &g, &[], &tight(), inner_mprgp).unwrap();
        assert!(sol.report.converged);
        assert_eq!(sol.report.iterations, 1);
        let direct = crate::lcp::mprgp::mprgp(&w, &q, &tight()).unwrap();
        let d = sol
            .forces
            .iter()
            .zip(&direct.forces)
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(d <= 1e-8 * direct.forces.iter().fold(1.0f64, |a, v| a.max(v.abs())));
    }
}
