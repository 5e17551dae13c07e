//! The contact solvers on the condensed problem LCP(W, q) (docs/theory/algorithms.md),
//! chosen by name: one table ([`METHODS`]) that the scene's plan, the
//! pipeline's root solve, `signorini local` and the benchmarks read, so that
//! no other place branches on a method's name.
//!
//! Each algorithm lives in its own file: [`crate::active_set::signorini`],
//! [`crate::lcp::lemke`], [`crate::lcp::projected_gradient`], [`crate::lcp::mprgp`],
//! [`crate::lcp::uzawa`], [`crate::lcp::augmented_lagrangian`], [`crate::lcp::penalty`];
//! bodies held by contact alone go through [`crate::lcp::smalbe`] with the method
//! as its inner solver.

use std::fmt;

use faer::Mat;

use crate::active_set::signorini::{status_method, ActiveSetSolve, StatusOptions, StatusVariant};
use crate::lcp::{
    constrained_gaps, gaps, gaps_off_active, gaps_on, lcp_residual, residual_from_gaps, LcpOptions,
};
use crate::problem_scale::ProblemScale;
use crate::solution::{ContactSolution, PolishSolve, StopReason};
use crate::{ContactError, DelassusProblem};
use signorini_linalg::active_factor::{solve_on_active_set, ActiveFactor};

/// The contact solvers on LCP(W, q), by identity: [`MethodId::as_str`] is
/// the name in scenes, on the command line and in `report.json` (the
/// [`METHODS`] table's), and [`str::parse`] reads it back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MethodId {
    Status,
    StatusPenalty,
    Lemke,
    ProjectedGradient,
    ProjectedConjugateGradient,
    Mprgp,
    Uzawa,
    AugmentedLagrangian,
    Penalty,
}

impl MethodId {
    /// The method's name in scenes, on the command line and in reports.
    pub fn as_str(self) -> &'static str {
        find(self).name
    }
}

impl fmt::Display for MethodId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::str::FromStr for MethodId {
    type Err = String;

    /// The method of a name, or an error listing the valid ones.
    fn from_str(name: &str) -> Result<Self, String> {
        let known = METHODS.iter().find(|m| m.name == name);
        known.map(|m| m.id).ok_or_else(|| {
            let all = METHODS.map(|m| m.name).join(", ");
            format!("\"{name}\" is not a contact method ({all})")
        })
    }
}

/// Which friction a method solves, and so which friction algorithms the
/// pipeline pairs it with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionSupport {
    /// Frictionless contact only.
    None,
    /// Tresca and Coulomb friction by the status methods of course notes §4 (the
    /// Coulomb fixed point, the friction status method).
    StatusMethods,
    /// Tresca friction only, as a box-constrained QP (MPRGP for simple bounds).
    TrescaBox,
}

/// How the status method imposes the constraints of its active set (course notes §3.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Constraints {
    Multipliers,
    Penalty,
}

/// One LCP(W, q) to solve, with what some methods read besides W and q.
pub struct Lcp<'a> {
    pub w: &'a Mat<f64>,
    pub q: &'a [f64],
    pub opts: &'a LcpOptions,
    /// Status methods: how many statuses change per iteration.
    pub variant: StatusVariant,
    /// Penalty methods: the stiffness of each point (force per unit gap);
    /// `None` takes `opts.stiffness` (default 1e8) / mean diag W.
    pub stiffness: Option<&'a [f64]>,
}

type Solve = fn(&Lcp) -> Result<ContactSolution, ContactError>;
type WarmSolve =
    fn(&Mat<f64>, &[f64], &[f64], &LcpOptions) -> Result<ContactSolution, ContactError>;

/// A contact solver as the registry knows it.
pub struct Method {
    pub id: MethodId,
    /// The name in scenes, on the command line and in `report.json`.
    pub name: &'static str,
    /// The answer is the solution of the LCP, not of a regularised law.
    pub exact: bool,
    /// The status method with multipliers: the pipeline runs it on its own
    /// active-set problem (the Delassus problem, or the whole stiffness on
    /// the direct path, the only method that path runs).
    pub active_set: bool,
    pub friction: FrictionSupport,
    solve: Solve,
    /// The warm-started solver SMALBE calls for its inner problems, when the
    /// method has one (else its `solve`).
    warm_start: Option<WarmSolve>,
    /// The same method with the constraints imposed by penalty.
    by_penalty: Option<&'static Method>,
}

impl Method {
    /// An exact iterative method is polished on its active set once it
    /// converged ([`polish`]); the status method is exact on its own.
    fn polished(&self) -> bool {
        self.exact && !self.active_set
    }
}

const fn method((id, name): (MethodId, &'static str), solve: Solve) -> Method {
    Method {
        id,
        name,
        exact: true,
        active_set: false,
        friction: FrictionSupport::None,
        solve,
        warm_start: None,
        by_penalty: None,
    }
}

static STATUS: Method = Method {
    active_set: true,
    friction: FrictionSupport::StatusMethods,
    by_penalty: Some(&STATUS_PENALTY),
    ..method((MethodId::Status, "status"), status)
};
static STATUS_PENALTY: Method = Method {
    exact: false,
    ..method((MethodId::StatusPenalty, "status_penalty"), status_penalty)
};
static LEMKE: Method = method((MethodId::Lemke, "lemke"), |p| {
    crate::lcp::lemke::lemke(p.w, p.q, p.opts)
});
static PROJECTED_GRADIENT: Method =
    method((MethodId::ProjectedGradient, "projected_gradient"), |p| {
        crate::lcp::projected_gradient::projected_gradient(p.w, p.q, p.opts)
    });
static PROJECTED_CONJUGATE_GRADIENT: Method = method(
    (
        MethodId::ProjectedConjugateGradient,
        "projected_conjugate_gradient",
    ),
    |p| crate::lcp::projected_gradient::projected_conjugate_gradient(p.w, p.q, p.opts),
);
static MPRGP: Method = Method {
    friction: FrictionSupport::TrescaBox,
    warm_start: Some(crate::lcp::mprgp::mprgp_from),
    ..method((MethodId::Mprgp, "mprgp"), |p| {
        crate::lcp::mprgp::mprgp(p.w, p.q, p.opts)
    })
};
static UZAWA: Method = method((MethodId::Uzawa, "uzawa"), |p| {
    crate::lcp::uzawa::uzawa(p.w, p.q, p.opts)
});
static AUGMENTED_LAGRANGIAN: Method = method(
    (MethodId::AugmentedLagrangian, "augmented_lagrangian"),
    |p| crate::lcp::augmented_lagrangian::augmented_lagrangian(p.w, p.q, p.opts),
);
static PENALTY: Method = Method {
    exact: false,
    ..method((MethodId::Penalty, "penalty"), |p| {
        crate::lcp::penalty::penalty(p.w, p.q, &penalty_stiffness(p), p.opts)
    })
};

/// Every contact solver on LCP(W, q).
pub static METHODS: [&Method; 9] = [
    &STATUS,
    &STATUS_PENALTY,
    &LEMKE,
    &PROJECTED_GRADIENT,
    &PROJECTED_CONJUGATE_GRADIENT,
    &MPRGP,
    &UZAWA,
    &AUGMENTED_LAGRANGIAN,
    &PENALTY,
];

/// The method `id`.
pub fn find(id: MethodId) -> &'static Method {
    METHODS
        .iter()
        .copied()
        .find(|m| m.id == id)
        .expect("every MethodId is in METHODS (tested)")
}

/// The status method on LCP(W, q): W_AA λ_A = −q_A on the active set, from
/// [`initial_contact`]. The iterations see the gaps of the inactive points
/// only ([`DenseLcp`]); the answer's gaps are W λ + q on every point, and its
/// residual history their natural residual.
fn status(p: &Lcp) -> Result<ContactSolution, ContactError> {
    let (w, q, opts) = (p.w, p.q, p.opts);
    let mut dense = DenseLcp::new(w, q);
    let initial = initial_contact(q, opts.tolerance * opts.gap_scale);
    let status_opts = StatusOptions::from_lcp(p.variant, opts, Some(initial));
    let mut out = status_method(&mut dense, &status_opts)?;
    out.report.operator_applications = dense.solves;
    match &dense.last_active {
        // The gaps off the set of the last solve are W λ + q already.
        Some(active) => gaps_on(w, q, &out.forces, active, active, &mut out.gaps),
        None => out.gaps = gaps(w, q, &out.forces),
    }
    let residual = residual_from_gaps(&out.forces, &out.gaps, opts);
    out.report.residual_history.push(residual);
    if let StopReason::TimeLimit { residual: r, .. } = &mut out.report.stop {
        *r = residual;
    }
    Ok(out)
}

/// The status method's first active set: the points that penetrate by at
/// least half the deepest penetration, q_p ≤ min(q) / 2 (or, when nothing
/// penetrates, the points whose gap is closed, q_p ≤ `closed`). On an
/// elastic half-space these are Hertz's contact zone, of radius √(Rδ): the
/// overlap of the indenter at half its approach; on a thinner body the
/// contact is wider and the method adds the points that penetrate. Adding
/// rows to the factor of W_AA costs a triangular solve, removing them
/// Givens sweeps that are slower per flop ([`signorini_linalg::active_factor`]),
/// so a start inside the contact zone is cheaper than one covering the whole
/// overlap q < 0 (about twice the contact zone on a half-space, eight times
/// the flops of its factorisation).
pub(crate) fn initial_contact(q: &[f64], closed: f64) -> Vec<usize> {
    let deepest = q.iter().copied().fold(f64::INFINITY, f64::min);
    let bound = if deepest < -closed {
        0.5 * deepest
    } else {
        closed
    };
    (0..q.len()).filter(|&i| q[i] <= bound).collect()
}

fn status_penalty(p: &Lcp) -> Result<ContactSolution, ContactError> {
    crate::lcp::penalty::status_with_penalty(p.w, p.q, &penalty_stiffness(p), p.variant, p.opts)
}

/// The penalty stiffness of each point: the given one, or `opts.stiffness`
/// (default 1e8) / mean diag W.
fn penalty_stiffness(p: &Lcp) -> Vec<f64> {
    p.stiffness.map(|k| k.to_vec()).unwrap_or_else(|| {
        crate::lcp::penalty::uniform_stiffness(p.w, p.opts.stiffness.unwrap_or(1e8))
    })
}

/// A method of the registry with its status variant: what a run solves its
/// contact problems with.
#[derive(Clone, Copy)]
pub struct Algorithm {
    method: &'static Method,
    variant: StatusVariant,
}

impl PartialEq for Algorithm {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self.method, other.method) && self.variant == other.variant
    }
}

impl fmt::Debug for Algorithm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Algorithm({}, {:?})", self.method.name, self.variant)
    }
}

impl Algorithm {
    /// The method `id`, its constraints imposed as `constraints` where it
    /// has the choice (the status method), with `variant`.
    pub fn of(id: MethodId, constraints: Constraints, variant: StatusVariant) -> Self {
        let method = find(id);
        let method = match (constraints, method.by_penalty) {
            (Constraints::Penalty, Some(penalised)) => penalised,
            _ => method,
        };
        Self { method, variant }
    }

    /// The method called `name` with multipliers, every status changing at once.
    pub fn by_name(name: &str) -> Option<Self> {
        let id = name.parse().ok()?;
        Some(Self::of(id, Constraints::Multipliers, StatusVariant::All))
    }

    /// The status method with multipliers (the exact reference).
    pub fn status(variant: StatusVariant) -> Self {
        Self {
            method: &STATUS,
            variant,
        }
    }

    pub fn id(self) -> MethodId {
        self.method.id
    }

    pub fn name(self) -> &'static str {
        self.method.name
    }

    /// Whether the answer is the exact solution of the LCP (not a regularised one).
    pub fn is_exact(self) -> bool {
        self.method.exact
    }

    /// Whether the pipeline runs it on its own active-set problem (see
    /// [`Method::active_set`]).
    pub fn on_active_set(self) -> bool {
        self.method.active_set
    }

    pub fn variant(self) -> StatusVariant {
        self.variant
    }

    pub fn friction(self) -> FrictionSupport {
        self.method.friction
    }

    /// Solves LCP(W, q). `stiffness` gives the penalty stiffness per point
    /// for the penalty methods (force per unit gap); `None` uses
    /// `opts.stiffness` (default 1e8) / mean diag W. Every method stops at
    /// `opts.deadline`, not converged ([`StopReason::TimeLimit`]). An exact
    /// iterative method that converged is polished on its active set. A
    /// problem in extreme units is solved in units where W and q are near 1
    /// ([`ProblemScale`]) and answered in its own.
    pub fn solve(
        self,
        w: &Mat<f64>,
        q: &[f64],
        stiffness: Option<&[f64]>,
        opts: &LcpOptions,
    ) -> Result<ContactSolution, ContactError> {
        match ProblemScale::of(w, q) {
            None => self.solve_as_given(w, q, stiffness, opts),
            Some(scale) => {
                let (w_s, q_s, k_s, opts_s) = scale.scaled(w, q, stiffness, opts);
                let sol = self.solve_as_given(&w_s, &q_s, k_s.as_deref(), &opts_s)?;
                Ok(scale.unscale(sol))
            }
        }
    }

    fn solve_as_given(
        self,
        w: &Mat<f64>,
        q: &[f64],
        stiffness: Option<&[f64]>,
        opts: &LcpOptions,
    ) -> Result<ContactSolution, ContactError> {
        let problem = Lcp {
            w,
            q,
            opts,
            variant: self.variant,
            stiffness,
        };
        let mut sol = (self.method.solve)(&problem)?;
        if self.method.polished() && sol.report.converged {
            polish(w, q, &mut sol, opts);
        }
        sol.report.method = self.name().into();
        if sol.report.residual_history.is_empty() {
            sol.report
                .residual_history
                .push(lcp_residual(w, q, &sol.forces, opts));
        }
        Ok(sol)
    }

    /// Solves LCP(W, q) with the equilibrium of floating bodies Gᵀλ = e (see
    /// [`crate::lcp::smalbe`]) by SMALBE with this method as the bound-constrained
    /// inner solver (warm-started where it can be, as MPRGP in Dostál's
    /// SMALBE-M). The penalty methods solve their regularised law,
    /// LCP(W + K⁻¹, q) with K the penalty stiffness per point (course notes §3.6),
    /// exactly inside SMALBE (the status method); their gaps are those of W.
    pub fn solve_constrained(
        self,
        w: &Mat<f64>,
        q: &[f64],
        (g, e): (&Mat<f64>, &[f64]),
        stiffness: Option<&[f64]>,
        opts: &LcpOptions,
    ) -> Result<ContactSolution, ContactError> {
        let regularised;
        let (w_eff, inner) = if self.is_exact() {
            (w, self)
        } else {
            let p = Lcp {
                w,
                q,
                opts,
                variant: self.variant,
                stiffness,
            };
            let mut wk = w.clone();
            for (i, ki) in penalty_stiffness(&p).into_iter().enumerate() {
                wk[(i, i)] += 1.0 / ki;
            }
            regularised = wk;
            (&regularised, Algorithm::status(StatusVariant::All))
        };
        let mut sol =
            crate::lcp::smalbe::smalbe(w_eff, q, g, e, opts, |wi, qi, l0, o| {
                match inner.method.warm_start {
                    Some(warm) => warm(wi, qi, l0, o),
                    None => inner.solve(wi, qi, None, o),
                }
            })?;
        sol.report.method = self.name().into();
        if !self.is_exact() {
            sol.gaps = constrained_gaps(w, q, g, &sol.forces, &sol.alpha);
        }
        Ok(sol)
    }

    /// Solves a step's Delassus problem: SMALBE with the equilibrium of the
    /// floating bodies when there are any ([`Self::solve_constrained`]),
    /// else LCP(W, q) ([`Self::solve`]).
    pub fn solve_delassus(
        self,
        problem: &DelassusProblem,
        stiffness: Option<&[f64]>,
        opts: &LcpOptions,
    ) -> Result<ContactSolution, ContactError> {
        let (w, q) = (&problem.w, problem.q.as_slice());
        if problem.n_kernel() > 0 {
            let equality = (&problem.g_mat, problem.e.as_slice());
            self.solve_constrained(w, q, equality, stiffness, opts)
        } else {
            self.solve(w, q, stiffness, opts)
        }
    }
}

/// LCP(W, q) as an [`ActiveSetSolve`]: W_AA λ_A = −q_A, the Cholesky
/// factor of W_AA carried from one active set to the next
/// ([`ActiveFactor`]); a block that is not safely positive definite goes to
/// the rank-tested solve. The gaps are W λ + q off the active set and 0 on
/// it, where the solve imposed them (the status rule reads only the former).
pub struct DenseLcp<'a> {
    pub w: &'a Mat<f64>,
    pub q: &'a [f64],
    pub solves: usize,
    factor: Option<ActiveFactor>,
    /// The active set of the last solve that succeeded.
    last_active: Option<Vec<usize>>,
}

impl<'a> DenseLcp<'a> {
    pub fn new(w: &'a Mat<f64>, q: &'a [f64]) -> Self {
        Self {
            w,
            q,
            solves: 0,
            factor: None,
            last_active: None,
        }
    }
}

impl ActiveSetSolve for DenseLcp<'_> {
    fn n_points(&self) -> usize {
        self.q.len()
    }
    fn pivoted_active_set(
        &mut self,
        opts: &crate::lcp::LcpOptions,
    ) -> Result<Option<Vec<usize>>, ContactError> {
        let none = Mat::<f64>::zeros(self.q.len(), 0);
        crate::lcp::lemke::pivoted_active_set(self.w, self.q, (&none, &[]), opts)
    }
    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        self.solves += 1;
        let lambda = match solve_on_active_set(&mut self.factor, self.w, self.q, active) {
            Some(lambda) => lambda,
            None => {
                let mut lambda = vec![0.0; self.q.len()];
                let na = active.len();
                let a = Mat::<f64>::from_fn(na, na, |i, j| self.w[(active[i], active[j])]);
                let rhs = Mat::<f64>::from_fn(na, 1, |i, _| -self.q[active[i]]);
                let x = signorini_linalg::pivot_policy::solve_checked(
                    &a,
                    &rhs,
                    "W_AA is singular: redundant contact constraints",
                )?;
                for (i, &p) in active.iter().enumerate() {
                    lambda[p] = x[(i, 0)];
                }
                lambda
            }
        };
        let g = gaps_off_active(self.w, self.q, &lambda, active);
        self.last_active = Some(active.to_vec());
        Ok((lambda, g))
    }
}

/// Active-set polishing: an iterative method that has converged to the
/// tolerance has (in all but degenerate cases) found the active set A of the
/// solution; solving W_AA λ_A = −q_A then gives the solution to round-off
/// instead of to the tolerance times the condition number of W. The polished
/// forces are kept only if they are a solution of the LCP at least as good as
/// the iterate (λ ≥ 0 and g ≥ 0 to tolerance).
fn polish(w: &Mat<f64>, q: &[f64], sol: &mut ContactSolution, opts: &LcpOptions) {
    let lmax = sol.forces.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let active: Vec<usize> = (0..q.len())
        .filter(|&p| sol.forces[p] > 1e-14 * lmax)
        .collect();
    let mut p = DenseLcp::new(w, q);
    let Ok((lambda, g)) = p.solve_active(&active) else {
        return;
    };
    let f = opts.force_scale.max(lmax).max(f64::MIN_POSITIVE);
    let feasible = lambda.iter().all(|&l| l >= -opts.tolerance * f)
        && g.iter()
            .enumerate()
            .all(|(i, &gi)| active.contains(&i) || gi >= -opts.tolerance * opts.gap_scale);
    let before = lcp_residual(w, q, &sol.forces, opts);
    let clamped: Vec<f64> = lambda.iter().map(|l| l.max(0.0)).collect();
    let g_clamped = gaps(w, q, &clamped);
    let after = crate::lcp::residual_from_gaps(&clamped, &g_clamped, opts);
    if feasible && after <= before.max(opts.tolerance) {
        sol.set_forces(clamped, g_clamped);
        sol.report.record_polish(after, PolishSolve::ActiveSet);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_problems::{cases, norm_inf, rel_err};

    /// Each method of the table has today's name, its MethodId finds it and
    /// its name reads back as its MethodId; a name that is no method is refused with the
    /// list of the valid ones.
    #[test]
    fn every_method_id_names_its_method() {
        let names = [
            "status",
            "status_penalty",
            "lemke",
            "projected_gradient",
            "projected_conjugate_gradient",
            "mprgp",
            "uzawa",
            "augmented_lagrangian",
            "penalty",
        ];
        assert_eq!(METHODS.map(|m| m.name), names);
        for m in METHODS {
            assert!(std::ptr::eq(find(m.id), m));
            assert_eq!(m.id.as_str(), m.name);
            assert_eq!(m.name.parse::<MethodId>(), Ok(m.id));
        }
        let err = "simplex".parse::<MethodId>().unwrap_err();
        assert!(
            err.contains("simplex") && err.contains("augmented_lagrangian"),
            "{err}"
        );
    }

    /// The status method on LCP(W, q) through the registry: the forces of
    /// the exact solution, the gaps W λ + q on every point (the iterations
    /// saw only the inactive ones), and the residual of those.
    #[test]
    fn status_answers_with_the_gaps_of_every_point() {
        let opts = LcpOptions {
            tolerance: 1e-12,
            ..Default::default()
        };
        for case in cases() {
            let sol = Algorithm::status(StatusVariant::All)
                .solve(&case.w, &case.q, None, &opts)
                .unwrap();
            assert!(sol.report.converged, "{}: {}", case.name, sol.report.stop);
            assert!(rel_err(&sol.forces, &case.exact) <= 1e-10, "{}", case.name);
            let want = gaps(&case.w, &case.q, &sol.forces);
            let scale = norm_inf(&case.q) + norm_inf(&want);
            for (p, (g, h)) in sol.gaps.iter().zip(&want).enumerate() {
                assert!((g - h).abs() <= 1e-13 * scale, "{}: point {p}", case.name);
            }
            // The same residual as from a product on every point, to round-off.
            let residual = lcp_residual(&case.w, &case.q, &sol.forces, &opts);
            let history = &sol.report.residual_history;
            assert_eq!(history.len(), 1, "{}", case.name);
            assert!((history[0] - residual).abs() <= 1e-13, "{}", case.name);
            assert!(history[0] <= opts.tolerance, "{}", case.name);
        }
    }

    /// A deadline already passed stops every method of the table after its
    /// first iteration (pivot, status solve, outer iteration), not
    /// converged, on the time limit, with a finite iterate and the natural
    /// residual of it. On this problem every method needs more than one
    /// iteration (the test checks that too).
    #[test]
    fn a_passed_deadline_stops_every_method_after_one_iteration() {
        use crate::test_problems::{
            assert_stopped_by_the_time_limit_after_one_iteration, q_from_solution, random_spd,
            XorShift,
        };
        let (m, mut rng) = (30, XorShift(7));
        let w = random_spd(m, &mut rng);
        let half = |i: usize, on: usize, rng: &mut XorShift| match i % 2 == on {
            true => rng.uniform(0.5, 1.5),
            false => 0.0,
        };
        let lambda: Vec<f64> = (0..m).map(|i| half(i, 0, &mut rng)).collect();
        let g: Vec<f64> = (0..m).map(|i| half(i, 1, &mut rng)).collect();
        let q = q_from_solution(&w, &lambda, &g);
        let unlimited = LcpOptions {
            tolerance: 1e-10,
            max_iterations: 10_000,
            ..Default::default()
        };
        for method in METHODS {
            let alg = Algorithm::by_name(method.name).unwrap();
            let free = alg.solve(&w, &q, None, &unlimited).unwrap();
            assert!(free.report.iterations > 1, "{}", method.name);
            let opts = LcpOptions {
                deadline: Some(std::time::Instant::now()),
                ..unlimited.clone()
            };
            let sol = alg.solve(&w, &q, None, &opts).unwrap();
            assert_stopped_by_the_time_limit_after_one_iteration(&sol.report);
            let finite = sol.forces.iter().chain(&sol.gaps).all(|v| v.is_finite());
            assert!(finite, "{}", method.name);
            let StopReason::TimeLimit { residual, .. } = sol.report.stop else {
                unreachable!()
            };
            let want = lcp_residual(&w, &q, &sol.forces, &opts);
            assert!(
                (residual - want).abs() <= 1e-9 * want,
                "{}: {residual:e} vs {want:e}",
                method.name
            );
            assert!(want > opts.tolerance, "{}", method.name);
        }
    }

    /// SMALBE (a floating body held by the contacts) stops at a passed
    /// deadline too, by its inner method's time limit or its own, with a
    /// finite iterate.
    #[test]
    fn a_passed_deadline_stops_smalbe() {
        let case = &cases()[1];
        let m = case.q.len();
        let g = Mat::<f64>::from_fn(m, 1, |i, _| 1.0 + 0.1 * i as f64);
        let opts = LcpOptions {
            tolerance: 1e-10,
            deadline: Some(std::time::Instant::now()),
            ..Default::default()
        };
        for name in ["status", "mprgp", "uzawa"] {
            let alg = Algorithm::by_name(name).unwrap();
            let sol = alg
                .solve_constrained(&case.w, &case.q, (&g, &[-5.0]), None, &opts)
                .unwrap();
            assert!(!sol.report.converged, "{name}");
            assert!(
                matches!(sol.report.stop, StopReason::TimeLimit { .. }),
                "{name}: {}",
                sol.report.stop
            );
            assert!(sol.forces.iter().all(|v| v.is_finite()), "{name}");
        }
    }
}
