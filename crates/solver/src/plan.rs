//! The plan stage: the solver choices of the scene and the command line,
//! checked once before anything is built (which method runs on which path,
//! friction and regularised laws with the methods that solve them).

use super::*;

/// The checked choices of a run.
pub(crate) struct Plan {
    pub method: scene::Method,
    pub path: scene::SolvePath,
    pub algorithm: Algorithm,
}

/// The method and path of the run (the command line overrides the scene),
/// refused with the entry and what would be valid when they cannot run the
/// scene's contacts.
pub(crate) fn plan(sc: &scene::Scene, opts: &RunOptions) -> Result<Plan, SolveError> {
    let method = opts.method.unwrap_or(sc.solver.method);
    let path = opts.path.unwrap_or(sc.solver.path);
    let algorithm = algorithm_of(&sc.solver, method);
    if path == scene::SolvePath::Direct
        && algorithm != Algorithm::Status(StatusVariant::All)
        && algorithm != Algorithm::Status(StatusVariant::Single)
    {
        return Err(SolveError::Input(format!(
            "solver.method: the direct path runs the status method with multipliers; \"{}\" runs on path = \"condensed\"",
            algorithm.name()
        )));
    }
    let tresca_by_mprgp = algorithm == Algorithm::Mprgp
        && sc
            .contact
            .iter()
            .all(|c| matches!(c.friction, scene::Friction::Tresca(_)));
    for c in &sc.contact {
        if c.friction != scene::Friction::None
            && (path == scene::SolvePath::Direct
                || !(matches!(algorithm, Algorithm::Status(_)) || tresca_by_mprgp))
        {
            return Err(SolveError::Input(format!(
                "contact \"{}\".friction: friction is solved on path = \"condensed\" by method = \"status\" (with solver.friction = \"fixed_point\", \"status\" or \"newton\"), not by \"{}\" on the {} path",
                c.name,
                algorithm.name(),
                path.as_str()
            )));
        }
        if let scene::Law::Penalty { .. } = c.law {
            if method != scene::Method::Penalty {
                return Err(SolveError::Input(format!(
                    "contact \"{}\".law: a regularised (penalty) law is solved by solver.method = \"penalty\", not \"{}\"",
                    c.name,
                    method.as_str()
                )));
            }
        }
    }
    Ok(Plan {
        method,
        path,
        algorithm,
    })
}

/// The contact algorithm of a scene's `[solver]` with the method `method`.
pub fn algorithm_of(solver: &scene::Solver, method: scene::Method) -> Algorithm {
    let variant = match solver.status_changes {
        scene::StatusChanges::All => StatusVariant::All,
        scene::StatusChanges::Single => StatusVariant::Single,
    };
    match method {
        scene::Method::Status => match solver.constraints {
            scene::Constraints::Multipliers => Algorithm::Status(variant),
            scene::Constraints::Penalty => Algorithm::StatusPenalty(variant),
        },
        scene::Method::Lemke => Algorithm::Lemke,
        scene::Method::ProjectedGradient => Algorithm::ProjectedGradient,
        scene::Method::ProjectedConjugateGradient => Algorithm::ProjectedConjugateGradient,
        scene::Method::Mprgp => Algorithm::Mprgp,
        scene::Method::Uzawa => Algorithm::Uzawa,
        scene::Method::AugmentedLagrangian => Algorithm::AugmentedLagrangian,
        scene::Method::Penalty => Algorithm::Penalty,
    }
}
