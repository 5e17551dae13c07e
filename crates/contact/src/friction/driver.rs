//! The friction driver: one entry for every friction solver on the
//! condensed problem, in the pattern of a solver driver (check the problem,
//! dispatch to the method, compute the residual of the answer once), used
//! by the pipeline's load steps and by `signorini local`.
//!
//! The caller asks for an outer algorithm ([`FrictionSolver`]: the scene's
//! `solver.friction`, `signorini local --friction`); [`FrictionMethod::choose`]
//! turns it, with the dimension and the laws of the points, into the method
//! that runs; [`solve_friction`] runs it.

use crate::active_set::friction_status::{coulomb_status, predicted_statuses, tresca_status};
use crate::delassus::DelassusProblem;
use crate::friction::contact_zone::solve_on_contact_zone;
use crate::friction::friction3d::{coulomb_3d_fixed_point, friction_3d};
use crate::friction::nsgs::nsgs;
use crate::friction::{coulomb_fixed_point, coulomb_newton, norton_hoff, tresca_projection};
use crate::law::{natural_residual, FrictionLayout};
use crate::norms::max_abs;
use crate::options::FrictionOptions;
use crate::solution::{ContactSolution, PointStatus};
use crate::ContactError;

/// The outer algorithm asked for friction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionSolver {
    /// The fixed point on the threshold (course notes §4.3), 2D and 3D.
    FixedPoint,
    /// The friction status method (course notes §4.5), 2D.
    Status,
    /// The semi-smooth Newton method on the Alart–Curnier equations of
    /// Coulomb's law itself (no outer fixed point; the fixed point with
    /// Newton inner solves where it fails), 2D and 3D.
    Newton,
    /// The nonsmooth Gauss–Seidel method on Coulomb's law, contact by
    /// contact ([`nsgs`]), 2D and 3D.
    Nsgs,
}

impl FrictionSolver {
    pub const ALL: [FrictionSolver; 4] = [
        FrictionSolver::FixedPoint,
        FrictionSolver::Status,
        FrictionSolver::Newton,
        FrictionSolver::Nsgs,
    ];

    pub fn name(self) -> &'static str {
        match self {
            FrictionSolver::FixedPoint => "fixed_point",
            FrictionSolver::Status => "status",
            FrictionSolver::Newton => "newton",
            FrictionSolver::Nsgs => "nsgs",
        }
    }

    /// Whether it solves 3D problems (there the fixed point has Newton
    /// inner solves).
    pub fn solves_3d(self) -> bool {
        self != FrictionSolver::Status
    }

    /// The solver of a name, or an error listing the valid ones.
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|m| m.name()).collect();
                format!("--friction: \"{name}\" is not one of {}", names.join(", "))
            })
    }
}

/// The friction methods that run, each a function of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionMethod {
    /// 2D Tresca by the status method ([`tresca_status`]).
    TrescaStatus,
    /// 2D Tresca as a box QP by MPRGP ([`tresca_projection`]).
    TrescaBox,
    /// 2D Coulomb by the fixed point on the threshold ([`coulomb_fixed_point`]).
    CoulombFixedPoint,
    /// 2D Coulomb by the friction status method ([`coulomb_status`]).
    CoulombStatus,
    /// 2D Coulomb or Tresca by semi-smooth Newton ([`coulomb_newton`]).
    Newton,
    /// 2D Norton–Hoff by the fixed point on its threshold ([`norton_hoff`]).
    NortonHoff,
    /// 3D by semi-smooth Newton, Coulomb on its law itself with the fixed
    /// point as fallback ([`friction_3d`]).
    Newton3d,
    /// 3D Coulomb by the fixed point alone ([`coulomb_3d_fixed_point`]).
    FixedPoint3d,
    /// Coulomb by NSGS ([`nsgs`]), 2D.
    Nsgs2d,
    /// Coulomb by NSGS ([`nsgs`]), 3D.
    Nsgs3d,
}

impl FrictionMethod {
    /// The method that answers `asked` in dimension `dim` on the laws of
    /// `layout`, with `tresca_box` when the LCP method solves Tresca as a box
    /// QP; `None` for the friction status method in 3D.
    pub fn choose(
        asked: FrictionSolver,
        dim: usize,
        layout: &FrictionLayout,
        tresca_box: bool,
    ) -> Option<Self> {
        let all_tresca = layout.law.iter().all(|l| l.coulomb_mu().is_none());
        let norton_hoff = layout.law.iter().any(|l| l.is_norton_hoff());
        Some(match (dim, asked) {
            (3, FrictionSolver::Status) => return None,
            (3, FrictionSolver::Nsgs) => FrictionMethod::Nsgs3d,
            (_, FrictionSolver::Nsgs) => FrictionMethod::Nsgs2d,
            (3, FrictionSolver::Newton) => FrictionMethod::Newton3d,
            (3, _) => FrictionMethod::FixedPoint3d,
            _ if norton_hoff => FrictionMethod::NortonHoff,
            (_, FrictionSolver::Newton) => FrictionMethod::Newton,
            _ if all_tresca && tresca_box => FrictionMethod::TrescaBox,
            _ if all_tresca => FrictionMethod::TrescaStatus,
            (_, FrictionSolver::Status) => FrictionMethod::CoulombStatus,
            (_, FrictionSolver::FixedPoint) => FrictionMethod::CoulombFixedPoint,
        })
    }

    /// Whether it starts from the statuses of the points (the 2D status
    /// methods and the fixed points on them).
    fn predicts(self) -> bool {
        matches!(
            self,
            FrictionMethod::TrescaStatus | FrictionMethod::CoulombStatus
        )
    }
}

/// Where a friction solve starts.
pub struct FrictionStart<'a> {
    /// The statuses of the points (the 2D status methods and fixed points).
    pub statuses: Vec<PointStatus>,
    /// The previous step's forces, if any.
    pub forces: Option<&'a [f64]>,
    /// Whether the status methods predict the slip from q first
    /// ([`predicted_statuses`]: at a cold start without floating bodies).
    pub predict: bool,
    /// Whether the method runs on the contact zone
    /// ([`solve_on_contact_zone`]) where the problem allows it.
    pub zone: bool,
}

/// A friction solution with its residual.
pub struct FrictionAnswer {
    pub solution: ContactSolution,
    /// The natural-map residual of the law at the answer
    /// ([`natural_residual`]), forces relative to max(force scale, ‖λ‖∞),
    /// gaps to the gap scale.
    pub residual: f64,
}

/// Solves the friction problem by `method` from `start`.
pub fn solve_friction(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    method: FrictionMethod,
    start: FrictionStart,
    opts: &FrictionOptions,
) -> Result<FrictionAnswer, ContactError> {
    let dim = match method {
        FrictionMethod::Newton3d | FrictionMethod::FixedPoint3d | FrictionMethod::Nsgs3d => 3,
        _ => 2,
    };
    layout.validate(problem.q.len(), dim)?;
    let statuses = match start.predict && method.predicts() {
        true => predicted_statuses(layout, &problem.q, start.statuses, opts),
        false => start.statuses,
    };
    let zoned = match start.zone {
        true => solve_on_contact_zone(
            problem,
            layout,
            start.forces,
            &statuses,
            opts,
            dim,
            |p, l, f, s| run(method, p, l, f, s, opts),
        )?,
        false => None,
    };
    let solution = match zoned {
        Some(solution) => solution,
        None => run(method, problem, layout, start.forces, statuses, opts)?,
    };
    let force = opts.force_scale.max(max_abs(&solution.forces));
    let residual = natural_residual(
        layout,
        &solution.forces,
        &solution.gaps,
        force,
        opts.gap_scale,
    );
    Ok(FrictionAnswer { solution, residual })
}

/// Runs `method` on a problem from `forces` (or its own start) and the
/// statuses of its points.
fn run(
    method: FrictionMethod,
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    forces: Option<&[f64]>,
    statuses: Vec<PointStatus>,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    match method {
        FrictionMethod::TrescaStatus => tresca_status(problem, layout, statuses, opts),
        FrictionMethod::TrescaBox => tresca_projection(problem, layout, opts),
        FrictionMethod::CoulombFixedPoint => {
            coulomb_fixed_point(problem, layout, statuses, forces, opts)
        }
        FrictionMethod::CoulombStatus => coulomb_status(problem, layout, statuses, opts),
        FrictionMethod::Newton => coulomb_newton(problem, layout, forces, opts),
        FrictionMethod::NortonHoff => norton_hoff(problem, layout, statuses, opts),
        FrictionMethod::Newton3d => friction_3d(problem, layout, forces, opts),
        FrictionMethod::FixedPoint3d => coulomb_3d_fixed_point(problem, layout, forces, opts),
        FrictionMethod::Nsgs2d => nsgs(problem, layout, forces, opts, 2),
        FrictionMethod::Nsgs3d => nsgs(problem, layout, forces, opts, 3),
    }
}
