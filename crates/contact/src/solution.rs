//! What every contact solver (the LCP methods and the friction solvers)
//! returns: the contact forces λ, the gaps g, the rigid-mode amplitudes α of
//! the floating bodies, the report of the run with why it stopped
//! ([`StopReason`]), and with friction the statuses of the points
//! ([`FrictionTrace`]).
//!
//! The reason is data (the numbers each method stops on); it becomes words
//! only at the output edge, through its [`std::fmt::Display`], which gives the
//! texts of `report.json`'s `stopping_reason`.

use serde::Serialize;

use crate::options::{Stall, StatusVariant};

/// What a method says about its run (`report.json` → `solver`).
#[derive(Debug, Clone, Default, Serialize)]
pub struct SolverReport {
    pub method: String,
    pub converged: bool,
    pub iterations: usize,
    /// Products with W (or solves with a block of W, each counted once).
    pub operator_applications: usize,
    /// The natural residual after each iteration (see the LCP's natural residual).
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
    /// λ: the normal contact force at each point (compressive ≥ 0); with
    /// friction, every row (see [`FrictionTrace`]).
    pub forces: Vec<f64>,
    /// g = W λ + q (+ G α with floating bodies): the gap at each point;
    /// with friction, every row (the tangential ones: slip increments).
    pub gaps: Vec<f64>,
    /// α: the amplitudes of the rigid modes of the floating bodies; empty
    /// without floating bodies (and for the status method, whose active-set
    /// problem keeps them: see the Delassus problem).
    pub alpha: Vec<f64>,
    /// The points in contact at the end (sorted): the last active set of a
    /// status method, else the points with a positive force.
    pub active: Vec<usize>,
    pub report: SolverReport,
    /// How the statuses evolved (status methods; the default otherwise).
    pub statuses: StatusTrace,
    /// The friction statuses and the fixed point (friction solvers; the
    /// default otherwise).
    pub friction: FrictionTrace,
}

/// What a friction solver adds to its solution, whose forces and gaps then
/// hold every row (normal rows 0..m, then the tangential rows: the forces
/// and the slip increments), and whose `report.residual_history` holds the
/// residual after each fixed-point iteration (MPRGP's history for the
/// Tresca box).
#[derive(Debug, Clone, Default)]
pub struct FrictionTrace {
    /// The status of each of the m contact points.
    pub points: Vec<PointStatus>,
    /// Outer fixed-point iterations (0 for Tresca and the friction status
    /// method).
    pub fixed_point_iterations: usize,
    /// When the method that answers took over from another one, that one
    /// and why it stopped (3D Coulomb: the semi-smooth Newton method on
    /// Coulomb's law, then the fixed point on the threshold).
    pub fallback: Option<String>,
}

/// The story of the statuses of a status (active set) method (and of the
/// friction status method: its cycle flag).
#[derive(Debug, Clone, Default)]
pub struct StatusTrace {
    /// Size of the active set at each iteration.
    pub active_history: Vec<usize>,
    /// Iteration at which a cycle was first detected (the fallback to one
    /// status change per iteration), if any.
    pub cycle_detected_at: Option<usize>,
    /// Iteration at which the cycle was left by complementary pivoting
    /// (Lemke's method on the LCP, which cannot cycle), if it was.
    pub cycle_left_by_pivoting_at: Option<usize>,
    /// The variant the method ended with.
    pub variant_used: StatusVariant,
}

/// Status of a contact point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PointStatus {
    Open,
    /// In contact; sticking if the point has friction.
    Stick,
    /// Slipping with λ_t = +threshold (the slip increment is negative).
    SlipPlus,
    /// Slipping with λ_t = −threshold.
    SlipMinus,
    /// 3D: slipping in the tangent plane, the tangential force on the
    /// boundary of the disc / ellipse and opposing the slip.
    Slip,
}

impl PointStatus {
    pub fn is_slip(self) -> bool {
        matches!(
            self,
            PointStatus::SlipPlus | PointStatus::SlipMinus | PointStatus::Slip
        )
    }
}

impl ContactSolution {
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
            friction: FrictionTrace::default(),
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

    /// The friction statuses of the m points, and the points in contact:
    /// those not open.
    pub(crate) fn set_points(&mut self, points: Vec<PointStatus>) {
        self.active = (0..points.len())
            .filter(|&p| points[p] != PointStatus::Open)
            .collect();
        self.friction.points = points;
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
/// [`std::fmt::Display`] gives the words of `report.json`.
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
    /// The status method: no status changed (course notes §3.3).
    StatusesRepeated { iterations: usize },
    /// The status method cycled even with one status change per iteration.
    Cycling { iteration: usize },
    /// The status method (or the friction status method) reached its
    /// iteration limit.
    StatusLimit { limit: usize },
    /// The regularised law (course notes §3.6) solved exactly: its active set repeated.
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
    /// The friction status method (or Tresca's): no status changed after
    /// `solves` status solves (course notes §4.5).
    FrictionStatusesRepeated { solves: usize },
    /// The friction status method cycled even with one status change per
    /// iteration.
    FrictionCycling,
    /// A Tresca problem of the fixed point solved by MPRGP on its box (after
    /// the status method cycled on it).
    TrescaBoxSolved,
    /// `before`, with `count` inner Tresca problems solved by MPRGP on the
    /// box after the status method cycled.
    BoxFallbacks {
        before: Box<StopReason>,
        count: usize,
    },
    /// The fixed point on the threshold stopped on an inner Tresca problem
    /// that was not solved.
    InnerTresca(Box<StopReason>),
    /// The fixed point on the threshold (course notes §4.3) met the tolerance.
    FixedPointReached {
        map: ThresholdMapKind,
        iterations: usize,
    },
    /// The fixed point on the threshold reached its iteration limit.
    FixedPointLimit { map: ThresholdMapKind, limit: usize },
    /// The fixed point on the threshold came no closer than `best` (at
    /// iteration `at`) in `since` iterations: the map does not contract.
    FixedPointStalled {
        map: ThresholdMapKind,
        best: f64,
        at: usize,
        since: usize,
    },
    /// The semi-smooth Newton method met the tolerance.
    NewtonConverged { residual: f64, iterations: usize },
    /// The semi-smooth Newton method reached its iteration limit.
    NewtonLimit { limit: usize },
    /// The semi-smooth Newton method came no closer than its residual
    /// `best` (at iteration `at`) in `since` iterations: it cycles between
    /// statuses or creeps, and would spend its iteration limit so.
    NewtonStalled { best: f64, at: usize, since: usize },
    /// The semi-smooth Newton method's line search failed repeatedly (with
    /// floating bodies: no projected-gradient fallback).
    NewtonLineSearchFailed,
    /// The iterate became non-finite (NaN) at this iteration: the method's
    /// linear solves broke down; never an answer (see [`crate::norms`]).
    NonFinite { iteration: usize },
    /// Tresca friction solved in one solve (no fixed point): its reason.
    Tresca(Box<StopReason>),
    /// NSGS (friction::nsgs) met the tolerance after `sweeps` sweeps.
    NsgsConverged { residual: f64, sweeps: usize },
    /// NSGS reached its sweep limit.
    NsgsLimit { limit: usize },
    /// NSGS did not halve its best residual `best` (at sweep `at`) in
    /// `since` sweeps.
    NsgsStalled { best: f64, at: usize, since: usize },
    /// The wall-clock budget of the solve (`time_limit`) ran out after
    /// `iterations` iterations, at the natural residual `residual`.
    TimeLimit { iterations: usize, residual: f64 },
    /// A method met its tolerance but its forces leave a rigid motion of a
    /// body held by contact alone unbalanced: the load along it (with the
    /// contact forces) is `imbalance` times the magnitude of the forces
    /// along it. The method converged to a body moved far away, held by
    /// the regularisation alone: its loads have no static equilibrium.
    RigidMotionUnbalanced { iterations: usize, imbalance: f64 },
    /// A rigid motion of a floating body (column `mode` of G) is loaded
    /// beyond what friction can hold: the load along it not carried by the
    /// normal forces, `load`, exceeds `capacity`, the most the tangential
    /// forces can carry along it with their bounds (Σ μ λ_n ‖G_t‖) at the
    /// normal forces reached; no static equilibrium
    /// (the friction overload test).
    FrictionOverload {
        mode: usize,
        load: f64,
        capacity: f64,
    },
}

/// Which threshold map a fixed point on the threshold iterates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ThresholdMapKind {
    /// Coulomb: g ← μ λ_n.
    Coulomb,
    /// Norton–Hoff: g ← μ λ_n |Δs|^ρ.
    NortonHoff,
}

/// The residual a method measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The natural residual of the LCP (the LCP's natural residual).
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

impl StopReason {
    /// The semi-smooth Newton method stalled ([`crate::options::StallWatch`]).
    pub fn newton_stalled(Stall { best, at, since }: Stall) -> Self {
        StopReason::NewtonStalled { best, at, since }
    }

    /// NSGS stalled ([`crate::options::StallWatch`]).
    pub fn nsgs_stalled(Stall { best, at, since }: Stall) -> Self {
        StopReason::NsgsStalled { best, at, since }
    }

    /// The overloaded rigid motion (mode, load, capacity) when friction
    /// cannot hold a floating body, also as the fixed point's inner reason.
    pub fn friction_overload(&self) -> Option<(usize, f64, f64)> {
        match self {
            StopReason::FrictionOverload {
                mode,
                load,
                capacity,
            } => Some((*mode, *load, *capacity)),
            StopReason::InnerTresca(inner) => inner.friction_overload(),
            _ => None,
        }
    }

    /// A projection or dual method (here or as SMALBE's inner solver) ran
    /// out of `max_iterations` above the tolerance: more iterations, or a
    /// method that needs fewer, would go on.
    pub fn out_of_iterations(&self) -> bool {
        match self {
            StopReason::IterationLimit { .. } | StopReason::DualLimit { .. } => true,
            StopReason::InnerFailed { inner, .. } => inner.out_of_iterations(),
            StopReason::Smalbe(SmalbeStop::InnerFailed { inner, .. }) => inner.out_of_iterations(),
            _ => false,
        }
    }

    /// Any method stopped by its iteration limit (`[solver]
    /// max_iterations`): the status methods, the semi-smooth Newton method,
    /// the fixed point on the threshold and the regularised law's active
    /// set (also as the fixed point's inner Tresca solver), besides the
    /// projection and dual methods of [`Self::out_of_iterations`].
    pub fn iteration_limit(&self) -> bool {
        match self {
            StopReason::StatusLimit { .. }
            | StopReason::NewtonLimit { .. }
            | StopReason::NsgsLimit { .. }
            | StopReason::FixedPointLimit { .. }
            | StopReason::ActiveSetLimit { .. } => true,
            StopReason::InnerTresca(inner) | StopReason::BoxFallbacks { before: inner, .. } => {
                inner.iteration_limit()
            }
            other => other.out_of_iterations(),
        }
    }
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

mod display;
pub(crate) mod friction_iterate;

#[cfg(test)]
mod tests;
