//! What every contact solver returns: the contact forces λ, the gaps g, the
//! rigid-mode amplitudes α of the floating bodies, and the report of the run
//! with why it stopped ([`StopReason`]).
//!
//! The reason is data (the numbers each method stops on); it becomes words
//! only at the output edge, through its [`fmt::Display`], which gives the
//! texts of `report.json`'s `stopping_reason`.

use std::fmt;

use faer::Mat;
use serde::Serialize;

use crate::lcp::gaps;
use crate::status::StatusVariant;

/// What a method says about its run (`report.json` → `solver`).
#[derive(Debug, Clone, Default, Serialize)]
pub struct SolverReport {
    pub method: String,
    pub converged: bool,
    pub iterations: usize,
    /// Products with W (or solves with a block of W, each counted once).
    pub operator_applications: usize,
    /// The natural residual after each iteration (see [`crate::lcp_residual`]).
    pub residual_history: Vec<f64>,
    /// Why the method stopped; written as its text under `stopping_reason`.
    #[serde(rename = "stopping_reason", serialize_with = "as_text")]
    pub stop: StopReason,
}

fn as_text<S: serde::Serializer>(stop: &StopReason, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(stop)
}

impl SolverReport {
    /// Records a final polishing solve (`by`) that brought the residual to
    /// `residual`: one more operator application, the residual in the
    /// history, and the stop reason wrapped in [`StopReason::Polished`].
    pub(crate) fn record_polish(&mut self, residual: f64, by: PolishSolve) {
        self.operator_applications += 1;
        self.residual_history.push(residual);
        let before = Box::new(std::mem::take(&mut self.stop));
        self.stop = StopReason::Polished { before, by };
    }
}

/// The answer of a contact solver to one contact problem.
#[derive(Debug, Clone)]
pub struct ContactSolution {
    /// λ: the normal contact force at each point (compressive ≥ 0).
    pub forces: Vec<f64>,
    /// g = W λ + q (+ G α with floating bodies): the gap at each point.
    pub gaps: Vec<f64>,
    /// α: the amplitudes of the rigid modes of the floating bodies; empty
    /// without floating bodies (and for the status method, whose active-set
    /// problem keeps them, see [`crate::DelassusProblem`]).
    pub alpha: Vec<f64>,
    /// The points in contact at the end (sorted): the last active set of a
    /// status method, else the points with a positive force.
    pub active: Vec<usize>,
    pub report: SolverReport,
    /// How the statuses evolved (status methods; the default otherwise).
    pub statuses: StatusTrace,
}

/// The story of the statuses of a status (active set) method.
#[derive(Debug, Clone, Default)]
pub struct StatusTrace {
    /// Size of the active set at each iteration.
    pub active_history: Vec<usize>,
    /// Iteration at which a cycle was first detected (the fallback to one
    /// status change per iteration), if any.
    pub cycle_detected_at: Option<usize>,
    /// The variant the method ended with.
    pub variant_used: StatusVariant,
}

impl ContactSolution {
    /// The solution with forces λ of LCP(W, q): its gaps W λ + q and the
    /// points with a positive force.
    pub fn from_forces(w: &Mat<f64>, q: &[f64], forces: Vec<f64>, report: SolverReport) -> Self {
        let gaps = gaps(w, q, &forces);
        Self::with_gaps(forces, gaps, Vec::new(), report)
    }

    /// The solution with forces λ, gaps g and amplitudes α (the points with
    /// a positive force in contact).
    pub fn with_gaps(
        forces: Vec<f64>,
        gaps: Vec<f64>,
        alpha: Vec<f64>,
        report: SolverReport,
    ) -> Self {
        Self {
            active: positive(&forces),
            forces,
            gaps,
            alpha,
            report,
            statuses: StatusTrace::default(),
        }
    }

    /// The solution of the empty problem (m = 0) by `method`.
    pub(crate) fn empty(method: &str) -> Self {
        Self::with_gaps(
            Vec::new(),
            Vec::new(),
            Vec::new(),
            SolverReport {
                method: method.into(),
                converged: true,
                stop: StopReason::NoContactPoint,
                ..Default::default()
            },
        )
    }

    /// New forces and their gaps (the points in contact follow the forces).
    pub(crate) fn set_forces(&mut self, forces: Vec<f64>, gaps: Vec<f64>) {
        self.active = positive(&forces);
        self.forces = forces;
        self.gaps = gaps;
    }
}

/// The points with a positive force.
fn positive(forces: &[f64]) -> Vec<usize> {
    (0..forces.len()).filter(|&p| forces[p] > 0.0).collect()
}

/// Why a contact solver stopped, with the numbers it stopped on. The
/// [`fmt::Display`] gives the words of `report.json`.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum StopReason {
    /// The report is still being filled (never the reason of an answer).
    #[default]
    Pending,
    /// The problem has no contact point (m = 0).
    NoContactPoint,
    /// A dual method: λ = 0 already meets the tolerance.
    ZeroForces { residual: f64 },
    /// Lemke: q ≥ 0, so λ = 0 solves the LCP without a pivot.
    NoPivot,
    /// A projection method met the tolerance on the exact gaps.
    ResidualMet {
        residual: f64,
        tolerance: f64,
        iterations: usize,
    },
    /// MPRGP met the tolerance on the exact gradient.
    MprgpConverged {
        measure: Measure,
        residual: f64,
        tolerance: f64,
        iterations: usize,
        steps: MprgpSteps,
        /// The estimate of ‖W‖₂ of the expansion step 1.9/‖W‖.
        norm_w: f64,
        polish: BoxPolish,
    },
    /// MPRGP: the start, projected onto the box, meets the tolerance.
    StartMeetsTolerance {
        measure: Measure,
        residual: f64,
        tolerance: f64,
        polish: BoxPolish,
    },
    /// MPRGP with W = 0: the linear objective is minimised at the bounds.
    LinearObjective { residual: f64 },
    /// A dual method (Uzawa, augmented Lagrangian) met the tolerance.
    DualConverged {
        residual: f64,
        tolerance: f64,
        iterations: usize,
        detail: DualDetail,
    },
    /// A dual method reached its iteration limit.
    DualLimit {
        limit: usize,
        residual: f64,
        tolerance: f64,
        detail: DualDetail,
    },
    /// A projection method (or MPRGP, with its steps) reached its iteration
    /// limit above the tolerance.
    IterationLimit {
        limit: usize,
        measure: Measure,
        residual: f64,
        tolerance: f64,
        steps: Option<MprgpSteps>,
    },
    /// A projection method found no descent direction above the tolerance
    /// (the round-off floor).
    Stagnation {
        iteration: usize,
        measure: Measure,
        residual: f64,
        tolerance: f64,
    },
    /// The projected gradient's Armijo backtracking failed.
    LineSearchFailed { iteration: usize, residual: f64 },
    /// Lemke reached its pivot limit before z0 left the basis.
    PivotLimit { limit: usize, residual: f64 },
    /// Lemke: z0 left the basis and the forces meet the tolerance.
    Pivoted {
        pivots: usize,
        residual: f64,
        tolerance: f64,
        /// The forces were recomputed on the active set.
        polished: bool,
    },
    /// Lemke: z0 left the basis but round-off leaves the forces above the
    /// tolerance.
    PivotedAboveTolerance {
        pivots: usize,
        residual: f64,
        tolerance: f64,
    },
    /// The status method: no status changed (seed §3.3).
    StatusesRepeated { iterations: usize },
    /// The status method cycled even with one status change per iteration.
    Cycling { iteration: usize },
    /// The status method reached its iteration limit.
    StatusLimit { limit: usize },
    /// The regularised law (seed §3.6) solved exactly: its active set repeated.
    RegularisedSolved {
        active: usize,
        iterations: usize,
        /// Iteration of the switch to the least-index rule, if any.
        cycle_at: Option<usize>,
        penetration: f64,
    },
    /// The regularised law's active-set iteration cycled even with one
    /// change per iteration.
    NewtonCycling { iteration: usize, tolerance: f64 },
    /// The regularised law's active-set iteration reached its limit.
    ActiveSetLimit { limit: usize },
    /// The status method with the constraints imposed by penalty converged
    /// (`status` says how).
    ByPenalty {
        status: Box<StopReason>,
        penetration: f64,
    },
    /// The augmented Lagrangian's inner problem was not solved.
    InnerFailed {
        outer: usize,
        inner: Box<StopReason>,
    },
    /// SMALBE (floating bodies: the equality Gᵀλ = e).
    Smalbe(SmalbeStop),
    /// `before`, then one polishing solve on the identified active set.
    Polished {
        before: Box<StopReason>,
        by: PolishSolve,
    },
    /// A friction solver's reason, still in words (the friction solvers do
    /// not report a [`StopReason`] yet).
    Friction(String),
}

/// The residual a method measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The natural residual of the LCP ([`crate::lcp_residual`]).
    Natural,
    /// The projected-gradient residual of a box (MPRGP for Tresca).
    ProjectedGradient,
}

/// How many MPRGP steps of each kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MprgpSteps {
    pub cg: usize,
    pub expansion: usize,
    pub proportioning: usize,
}

/// What MPRGP's active-set polishing did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoxPolish {
    /// Not asked, nothing free, or the residual already zero.
    NotTried,
    Polished,
    /// Rejected: the polished point left the box.
    LeftTheBox,
    /// Rejected: the polished point had a larger residual.
    LargerResidual,
}

/// The polishing solve of [`StopReason::Polished`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PolishSolve {
    /// W_AA λ_A = −q_A on the active set.
    ActiveSet,
    /// The saddle-point system with the equality Gᵀλ = e (SMALBE).
    SaddlePoint,
}

/// What a dual method did, for its stopping reason.
#[derive(Debug, Clone, PartialEq)]
pub enum DualDetail {
    /// Uzawa: its step ρ and how often it was halved.
    Uzawa { step: UzawaStep, halvings: usize },
    /// The augmented Lagrangian: its inner Newton steps, the augmentation
    /// factor s of r = s / mean diag W, and how many inner problems cycled.
    Augmented {
        newton_steps: usize,
        factor: f64,
        cycles: usize,
    },
}

/// How Uzawa's step ρ was chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UzawaStep {
    /// ρ = factor / mean diag W (the stiffness option).
    Given { factor: f64 },
    /// ρ = 1.9 / ‖W‖₂ with ‖W‖₂ by power iteration.
    PowerIteration { norm: f64 },
    /// ρ = 1 (W = 0).
    ZeroOperator,
}

/// How far SMALBE got: outer and inner iterations, and the penalty ρ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmalbeProgress {
    pub outer: usize,
    pub inner_iterations: usize,
    pub rho: f64,
}

/// Why SMALBE stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum SmalbeStop {
    /// The natural and equilibrium residuals met the tolerance.
    Met {
        natural: f64,
        feasibility: f64,
        tolerance: f64,
        progress: SmalbeProgress,
        last_inner: Box<StopReason>,
    },
    /// The active set settled and one saddle-point solve on it met the tolerance.
    Settled {
        progress: SmalbeProgress,
        tolerance: f64,
        last_inner: Box<StopReason>,
    },
    /// The inner solver did not converge at the final precision.
    InnerFailed {
        outer: usize,
        inner: Box<StopReason>,
    },
    /// The outer iteration limit without meeting the tolerance.
    Exhausted {
        outer: usize,
        tolerance: f64,
        natural: f64,
        feasibility: f64,
        rho: f64,
        last_inner: Box<StopReason>,
    },
}

impl fmt::Display for Measure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Measure::Natural => "natural residual",
            Measure::ProjectedGradient => "projected-gradient residual",
        })
    }
}

impl fmt::Display for MprgpSteps {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} CG, {} expansion, {} proportioning steps",
            self.cg, self.expansion, self.proportioning
        )
    }
}

impl fmt::Display for BoxPolish {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BoxPolish::NotTried => "",
            BoxPolish::Polished => "; polished on the active set",
            BoxPolish::LeftTheBox => "; polishing rejected (left the box)",
            BoxPolish::LargerResidual => "; polishing rejected (larger residual)",
        })
    }
}

impl fmt::Display for PolishSolve {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PolishSolve::ActiveSet => "solve on the identified active set",
            PolishSolve::SaddlePoint => "saddle-point solve on the identified active set",
        })
    }
}

impl fmt::Display for UzawaStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UzawaStep::Given { factor } => write!(f, "{factor} / mean diag W"),
            UzawaStep::PowerIteration { norm } => {
                write!(f, "1.9 / ‖W‖₂ (power iteration: ‖W‖₂ ≈ {norm:.6e})")
            }
            UzawaStep::ZeroOperator => f.write_str("1 (W = 0)"),
        }
    }
}

impl DualDetail {
    /// What `report.iterations` counts.
    fn steps(&self) -> &'static str {
        match self {
            DualDetail::Uzawa { .. } => "iterations",
            DualDetail::Augmented { .. } => "outer iterations",
        }
    }

    /// The advice at the iteration limit.
    fn advice(&self) -> &'static str {
        match self {
            DualDetail::Uzawa { .. } => "Uzawa converges slowly when W is ill-conditioned",
            DualDetail::Augmented { .. } => {
                "a larger augmentation (stiffness option) converges in fewer outer iterations"
            }
        }
    }
}

impl fmt::Display for DualDetail {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DualDetail::Uzawa { step, halvings } => {
                write!(f, "ρ = {step}")?;
                if *halvings > 0 {
                    write!(
                        f,
                        ", halved {halvings} times because the dual energy increased"
                    )?;
                }
                Ok(())
            }
            DualDetail::Augmented {
                newton_steps,
                factor,
                cycles,
            } => {
                write!(
                    f,
                    "{newton_steps} inner Newton steps, r = {factor} / mean diag W"
                )?;
                if *cycles > 0 {
                    write!(
                        f,
                        "; {cycles} inner problems cycled and switched to one status change per step"
                    )?;
                }
                Ok(())
            }
        }
    }
}

impl fmt::Display for SmalbeProgress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "after {} outer iterations ({} inner iterations; ρ = {:.3e})",
            self.outer, self.inner_iterations, self.rho
        )
    }
}

impl fmt::Display for SmalbeStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SmalbeStop::Met {
                natural,
                feasibility,
                tolerance,
                progress,
                last_inner,
            } => write!(
                f,
                "SMALBE: natural residual {natural:.3e} and equilibrium residual {feasibility:.3e} ≤ tolerance {tolerance:.3e} {progress}; last inner: {last_inner}"
            ),
            SmalbeStop::Settled {
                progress,
                tolerance,
                last_inner,
            } => write!(
                f,
                "SMALBE: the active set settled {progress}; one saddle-point solve on it meets the tolerance {tolerance:.3e}; last inner: {last_inner}"
            ),
            SmalbeStop::InnerFailed { outer, inner } => write!(
                f,
                "SMALBE outer iteration {outer}: the inner solver did not converge: {inner}"
            ),
            SmalbeStop::Exhausted {
                outer,
                tolerance,
                natural,
                feasibility,
                rho,
                last_inner,
            } => write!(
                f,
                "SMALBE: {outer} outer iterations without meeting the tolerance {tolerance:.3e} (natural residual {natural:.3e}, equilibrium residual {feasibility:.3e}, ρ = {rho:.3e}); last inner: {last_inner}"
            ),
        }
    }
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use StopReason::*;
        match self {
            Pending => Ok(()),
            NoContactPoint => f.write_str("no contact point"),
            ZeroForces { residual } => write!(
                f,
                "λ = 0 already satisfies the tolerance (natural residual {residual:.3e}): no point in contact"
            ),
            NoPivot => f.write_str("q ≥ 0: λ = 0 solves the LCP (no pivot)"),
            ResidualMet {
                residual,
                tolerance,
                iterations,
            } => write!(
                f,
                "natural residual {residual:.3e} ≤ tolerance {tolerance:.3e} after {iterations} iterations"
            ),
            MprgpConverged { .. } | StartMeetsTolerance { .. } | LinearObjective { .. } => {
                self.fmt_mprgp(f)
            }
            DualConverged { .. } | DualLimit { .. } => self.fmt_dual(f),
            IterationLimit { .. } | Stagnation { .. } | LineSearchFailed { .. } => {
                self.fmt_projection(f)
            }
            PivotLimit { .. } | Pivoted { .. } | PivotedAboveTolerance { .. } => {
                self.fmt_lemke(f)
            }
            StatusesRepeated { .. } | Cycling { .. } | StatusLimit { .. } => self.fmt_status(f),
            RegularisedSolved { .. }
            | NewtonCycling { .. }
            | ActiveSetLimit { .. }
            | ByPenalty { .. } => self.fmt_penalty(f),
            InnerFailed { outer, inner } => write!(
                f,
                "inner problem of outer iteration {outer} not solved: {inner}"
            ),
            Smalbe(stop) => stop.fmt(f),
            Polished { before, by } => write!(f, "{before}; polished by one {by}"),
            Friction(text) => f.write_str(text),
        }
    }
}

impl StopReason {
    fn fmt_mprgp(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::MprgpConverged {
                measure,
                residual,
                tolerance,
                iterations,
                steps,
                norm_w,
                polish,
            } => write!(
                f,
                "{measure} {residual:.3e} ≤ tolerance {tolerance:.3e} after {iterations} iterations ({steps}; ᾱ = 1.9/‖W‖, ‖W‖ ≈ {norm_w:.6e}){polish}"
            ),
            StopReason::StartMeetsTolerance {
                measure,
                residual,
                tolerance,
                polish,
            } => write!(
                f,
                "the start projected onto the box meets the tolerance: {measure} {residual:.3e} ≤ tolerance {tolerance:.3e}{polish}"
            ),
            StopReason::LinearObjective { residual } => write!(
                f,
                "W = 0: the linear objective is minimised at the bounds, residual {residual:.3e}"
            ),
            _ => unreachable!("not an MPRGP reason"),
        }
    }

    fn fmt_dual(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::DualConverged {
                residual,
                tolerance,
                iterations,
                detail,
            } => write!(
                f,
                "natural residual {residual:.3e} ≤ tolerance {tolerance:.1e} after {iterations} {} ({detail})",
                detail.steps()
            ),
            StopReason::DualLimit {
                limit,
                residual,
                tolerance,
                detail,
            } => write!(
                f,
                "iteration limit {limit} reached: natural residual {residual:.3e} > tolerance {tolerance:.1e} ({detail}); {}",
                detail.advice()
            ),
            _ => unreachable!("not a dual reason"),
        }
    }

    fn fmt_projection(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::IterationLimit {
                limit,
                measure,
                residual,
                tolerance,
                steps,
            } => {
                write!(
                    f,
                    "iteration limit {limit} reached with {measure} {residual:.3e} above tolerance {tolerance:.3e} (not converged"
                )?;
                if let Some(steps) = steps {
                    write!(f, "; {steps}")?;
                }
                f.write_str(")")
            }
            StopReason::Stagnation {
                iteration,
                measure,
                residual,
                tolerance,
            } => write!(
                f,
                "stagnation at iteration {iteration}: no descent direction left at {measure} {residual:.3e} above tolerance {tolerance:.3e} (round-off floor; not converged)"
            ),
            StopReason::LineSearchFailed {
                iteration,
                residual,
            } => write!(
                f,
                "line search failed at iteration {iteration} (natural residual {residual:.3e})"
            ),
            _ => unreachable!("not a projection reason"),
        }
    }

    fn fmt_lemke(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::PivotLimit { limit, residual } => write!(
                f,
                "pivot limit {limit} reached before z0 left the basis (natural residual {residual:.3e}; not converged)"
            ),
            StopReason::Pivoted {
                pivots,
                residual,
                tolerance,
                polished,
            } => write!(
                f,
                "z0 left the basis after {pivots} pivots; natural residual {residual:.3e} ≤ tolerance {tolerance:.3e}{}",
                if *polished { " after polishing on the active set" } else { "" }
            ),
            StopReason::PivotedAboveTolerance {
                pivots,
                residual,
                tolerance,
            } => write!(
                f,
                "z0 left the basis after {pivots} pivots but the natural residual {residual:.3e} is above tolerance {tolerance:.3e} (round-off on an ill-conditioned W; not converged)"
            ),
            _ => unreachable!("not a Lemke reason"),
        }
    }

    fn fmt_status(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::StatusesRepeated { iterations } => {
                write!(f, "statuses repeated after {iterations} iterations")
            }
            StopReason::Cycling { iteration } => write!(
                f,
                "cycling: the active set of iteration {iteration} repeats an earlier one even with one status change per iteration (the contact zone is probably meshed too coarsely, seed §3.3)"
            ),
            StopReason::StatusLimit { limit } => write!(
                f,
                "iteration limit {limit} reached with statuses still changing"
            ),
            _ => unreachable!("not a status reason"),
        }
    }

    fn fmt_penalty(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::RegularisedSolved {
                active,
                iterations,
                cycle_at,
                penetration,
            } => {
                write!(
                    f,
                    "regularised law solved exactly: the active set ({active} points) repeated after {iterations} iterations"
                )?;
                if let Some(i) = cycle_at {
                    write!(
                        f,
                        " (an active set repeated at iteration {i}: switched to one status change per iteration, least index first)"
                    )?;
                }
                write!(
                    f,
                    "; max penetration {penetration:.3e} (O(1/k), seed §3.6)"
                )
            }
            StopReason::NewtonCycling {
                iteration,
                tolerance,
            } => write!(
                f,
                "cycling: the active set of iteration {iteration} repeats an earlier one even with one status change per iteration (round-off at the tolerance {tolerance:.1e}?)"
            ),
            StopReason::ActiveSetLimit { limit } => write!(
                f,
                "iteration limit {limit} reached with the active set still changing"
            ),
            StopReason::ByPenalty {
                status,
                penetration,
            } => write!(
                f,
                "{status} (constraints imposed by penalty); max penetration {penetration:.3e} (O(1/k))"
            ),
            _ => unreachable!("not a penalty reason"),
        }
    }
}

#[cfg(test)]
mod tests;
