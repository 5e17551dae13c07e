//! The plan stage: the solver choices of the scene and the command line,
//! checked once before anything is built (which method runs on which path,
//! friction and regularised laws with the methods that solve them).

use crate::element_step::{check_return_mapping, uses_return_mapping};
use crate::error::SolveError;
use crate::options::RunOptions;
use signorini_contact::registry::{Algorithm, Constraints, FrictionSupport, MethodId};
use signorini_contact::StatusVariant;
use signorini_scene as scene;

/// The checked choices of a run.
pub(crate) struct Plan {
    pub method: scene::Method,
    pub path: scene::SolvePath,
    pub algorithm: Algorithm,
    /// The contacts are contact elements solved by the return mapping
    /// (course notes §7, [`crate::element_step`]): no `method` applies.
    pub return_mapping: bool,
}

/// The method and path of the run (the command line overrides the scene),
/// refused with the entry and what would be valid when they cannot run the
/// scene's contacts.
pub(crate) fn plan(sc: &scene::Scene, opts: &RunOptions) -> Result<Plan, SolveError> {
    check_supported(sc)?;
    let method = opts.method.unwrap_or(sc.solver.method);
    let path = opts.path.unwrap_or(sc.solver.path);
    let algorithm = algorithm_of(&sc.solver, method);
    if uses_return_mapping(sc) {
        check_return_mapping(sc, path)?;
        if let Some(m) = opts.method.filter(|&m| m != scene::Method::Status) {
            return Err(SolveError::Input(format!(
                "--method {}: the scene's contacts are contact elements or penalty laws with friction, solved by the return mapping (course notes §7); no method applies (leave --method out)",
                m.as_str()
            )));
        }
        if sc.solver.friction != scene::Solver::default().friction {
            return Err(SolveError::Input(format!(
                "solver.friction = \"{}\": the scene's contacts are contact elements or penalty laws with friction, solved by the return mapping (course notes §7); no friction method applies (remove the key)",
                sc.solver.friction.as_str()
            )));
        }
        if sc.solver.method != scene::Method::Status {
            return Err(SolveError::Input(format!(
                "solver.method = \"{}\": the scene's contacts are contact elements or penalty laws with friction, solved by the return mapping (course notes §7); no method applies (remove the key)",
                sc.solver.method.as_str()
            )));
        }
        if let Some(i) = sc.steps.iter().position(|s| !s.friction.is_empty()) {
            return Err(SolveError::Input(format!(
                "steps[{i}].friction: the scene's contacts are contact elements or penalty laws with friction, solved by the return mapping (course notes §7), whose friction law does not change with the step; remove the key"
            )));
        }
        return Ok(Plan {
            method,
            path,
            algorithm,
            return_mapping: true,
        });
    }
    if path == scene::SolvePath::Direct && !algorithm.on_active_set() {
        return Err(SolveError::Input(format!(
            "solver.method: the direct path runs the status method with multipliers; \"{}\" runs on path = \"condensed\"",
            algorithm.name()
        )));
    }
    let tresca_by_box = algorithm.friction() == FrictionSupport::TrescaBox
        && sc
            .contact
            .iter()
            .all(|c| matches!(c.friction, scene::Friction::Tresca(_)));
    for c in &sc.contact {
        if c.friction != scene::Friction::None
            && (path == scene::SolvePath::Direct
                || !(algorithm.friction() == FrictionSupport::StatusMethods || tresca_by_box))
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
        return_mapping: false,
    })
}

/// What the solver refuses of a scene from the scene alone, before anything
/// is built (found by a fourth robustness sweep: these were refused while the
/// model was built or after the solve, and `check` called such scenes valid):
/// each contact's discretization, friction and master
/// (`model::check_contact_supported`), the friction status method in 3D,
/// and the reference against the model (`compare::check_reference`).
fn check_supported(sc: &scene::Scene) -> Result<(), SolveError> {
    for c in &sc.contact {
        crate::model::check_contact_supported(sc, c, &format!("contact \"{}\"", c.name))?;
    }
    let frictional = sc
        .contact
        .iter()
        .any(|c| c.friction != scene::Friction::None);
    if frictional && sc.dimension == 3 && sc.solver.friction == scene::FrictionSolver::Status {
        return Err(SolveError::Input(
            "solver.friction: the friction status method (course notes §4.5) is 2D only; in 3D friction is solved by the fixed point on the threshold (friction = \"fixed_point\", the default)".into(),
        ));
    }
    crate::compare::check_reference(sc)
}

/// What `signorini check` asks of the solver: the checks `run` makes of the
/// scene's method, path and reference before it builds anything (the
/// command line's `--path` overriding the scene's).
pub fn check_plan(sc: &scene::Scene, path: Option<scene::SolvePath>) -> Result<(), SolveError> {
    check_options(sc, &RunOptions { method: None, path })
}

/// Whether `run` would run the scene with the overrides `opts` (the checks
/// of the plan, made before anything is built).
pub fn check_options(sc: &scene::Scene, opts: &RunOptions) -> Result<(), SolveError> {
    plan(sc, opts).map(|_| ())
}

/// The contact algorithm of a scene's `[solver]` with the method `method`:
/// the registry's method of that name (contact::registry), with the
/// scene's constraints and status variant.
pub fn algorithm_of(solver: &scene::Solver, method: scene::Method) -> Algorithm {
    let variant = match solver.status_changes {
        scene::StatusChanges::All => StatusVariant::All,
        scene::StatusChanges::Single => StatusVariant::Single,
    };
    let constraints = match solver.constraints {
        scene::Constraints::Multipliers => Constraints::Multipliers,
        scene::Constraints::Penalty => Constraints::Penalty,
    };
    Algorithm::of(method_id(method), constraints, variant)
}

/// The registry's method of a scene's `method`.
fn method_id(method: scene::Method) -> MethodId {
    match method {
        scene::Method::Status => MethodId::Status,
        scene::Method::Lemke => MethodId::Lemke,
        scene::Method::ProjectedGradient => MethodId::ProjectedGradient,
        scene::Method::Mprgp => MethodId::Mprgp,
        scene::Method::Uzawa => MethodId::Uzawa,
        scene::Method::AugmentedLagrangian => MethodId::AugmentedLagrangian,
        scene::Method::Penalty => MethodId::Penalty,
        scene::Method::ProjectedConjugateGradient => MethodId::ProjectedConjugateGradient,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scene_method_is_the_registry_method_of_its_name() {
        for method in scene::Method::ALL {
            let solver = scene::Solver::default();
            assert_eq!(algorithm_of(&solver, method).name(), method.as_str());
        }
        let penalised = scene::Solver {
            constraints: scene::Constraints::Penalty,
            status_changes: scene::StatusChanges::Single,
            ..Default::default()
        };
        let a = algorithm_of(&penalised, scene::Method::Status);
        assert_eq!(a.name(), "status_penalty");
        assert_eq!(a.variant(), StatusVariant::Single);
        assert!(!a.is_exact() && !a.on_active_set());
        assert_eq!(
            algorithm_of(&penalised, scene::Method::Lemke).name(),
            "lemke"
        );
    }
}
