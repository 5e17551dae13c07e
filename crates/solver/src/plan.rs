//! The plan stage: the solver choices of the scene and the command line,
//! checked once before anything is built (which method runs on which path,
//! friction and regularised laws with the methods that solve them).

use crate::element_step::{check_return_mapping, uses_return_mapping};
use crate::error::SolveError;
use crate::memory::Budget;
use crate::options::RunOptions;
use crate::path_choice;
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
    /// How `path` was chosen (report.json `path_choice`).
    pub choice: signorini_report::PathChoice,
}

/// The method and path of the run (the command line overrides the scene;
/// `path = "auto"` by [`path_choice`], for `ranks` ranks within `budget`),
/// refused with the entry and what would be valid when they cannot run the
/// scene's contacts.
pub(crate) fn plan(
    sc: &scene::Scene,
    opts: &RunOptions,
    ranks: usize,
    budget: Option<Budget>,
) -> Result<Plan, SolveError> {
    check_supported(sc)?;
    let requested = opts.path.unwrap_or(sc.solver.path);
    let condensed = path_choice::cost(sc, scene::SolvePath::Condensed, ranks, budget);
    let direct = match plan_on(sc, opts, scene::SolvePath::Direct) {
        Ok(_) => Ok(path_choice::cost(sc, scene::SolvePath::Direct, 1, budget)),
        Err(e) => Err(e.to_string()),
    };
    let (path, reason) = path_choice::rule(requested, &condensed, &direct);
    if requested == scene::SolvePath::Auto {
        // the refusal says why this path
        let counts = crate::memory::ContactCounts::Surfaces;
        crate::memory::check(sc, (path, ranks), counts, budget).map_err(|e| match e {
            SolveError::Input(m) => SolveError::Input(format!(
                "{m} (solver.path = \"auto\" chose the {} path: {reason})",
                path.as_str()
            )),
            e => e,
        })?;
    }
    let mut plan = plan_on(sc, opts, path)?;
    plan.choice = path_choice::report(requested, path, &reason, &condensed, &direct);
    Ok(plan)
}

/// [`plan`] on `path` (condensed or direct).
fn plan_on(
    sc: &scene::Scene,
    opts: &RunOptions,
    path: scene::SolvePath,
) -> Result<Plan, SolveError> {
    let method = opts.method.unwrap_or(sc.solver.method);
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
            choice: Default::default(),
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
        let by_box = tresca_by_box && path == scene::SolvePath::Condensed;
        if c.friction != scene::Friction::None
            && !(algorithm.friction() == FrictionSupport::StatusMethods || by_box)
        {
            return Err(SolveError::Input(format!(
                "contact \"{}\".friction: friction is solved by method = \"status\" (on path = \"condensed\" with solver.friction = \"fixed_point\", \"status\" or \"newton\"; on path = \"direct\" by the whole-system Newton method), not by \"{}\" on the {} path",
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
    if path == scene::SolvePath::Direct {
        check_direct_friction(sc)?;
    }
    Ok(Plan {
        method,
        path,
        algorithm,
        return_mapping: false,
        choice: Default::default(),
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

/// What the direct path does not solve with friction (the condensed path
/// does): Norton–Hoff's law and rough contacts (course notes §6), friction
/// beside tied contacts, a friction law changed by a load step and the
/// friction status method; `Err` names the entry and what would run. Checked
/// by the plan before anything is built, so that `path = "auto"` leaves the
/// direct path out for such a scene.
fn check_direct_friction(sc: &scene::Scene) -> Result<(), SolveError> {
    if sc
        .contact
        .iter()
        .all(|c| c.friction == scene::Friction::None)
    {
        return Ok(());
    }
    for c in &sc.contact {
        let refused = match &c.friction {
            scene::Friction::NortonHoff { .. } => Some("Norton-Hoff friction"),
            scene::Friction::Coulomb {
                roughness: Some(_), ..
            } => Some("a rough contact (roughness)"),
            _ => None,
        };
        if let Some(what) = refused {
            return Err(SolveError::Input(format!(
                "contact \"{}\".friction: {what} is solved on path = \"condensed\" only; path = \"direct\" solves Tresca and Coulomb friction (with slip_stiffness)",
                c.name
            )));
        }
    }
    if let Some(c) = sc.contact.iter().find(|c| c.law == scene::Law::Tied) {
        return Err(SolveError::Input(format!(
            "contact \"{}\".law = \"tied\": friction with tied bodies is solved on path = \"condensed\" only; use path = \"condensed\"",
            c.name
        )));
    }
    if let Some(i) = sc.steps.iter().position(|s| !s.friction.is_empty()) {
        return Err(SolveError::Input(format!(
            "steps[{i}].friction: a friction law changed by a load step is solved on path = \"condensed\" only; use path = \"condensed\""
        )));
    }
    if sc.solver.friction == scene::FrictionSolver::Status {
        return Err(SolveError::Input(
            "solver.friction = \"status\": on path = \"direct\" friction is solved by the semi-smooth Newton method on the whole system; use friction = \"newton\" or \"fixed_point\" (the default), or path = \"condensed\"".into(),
        ));
    }
    Ok(())
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
    plan(sc, opts, 1, None).map(|_| ())
}

/// The path `run` would take with the overrides `opts`, on `ranks` ranks
/// within `budget`, and why (`path = "auto"`: by the estimates).
pub fn choose_path(
    sc: &scene::Scene,
    opts: &RunOptions,
    ranks: usize,
    budget: Option<Budget>,
) -> Result<signorini_report::PathChoice, SolveError> {
    plan(sc, opts, ranks, budget).map(|p| p.choice)
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

#[cfg(test)]
mod path_tests {
    use super::*;

    /// A pad of n × n × 2 hex8 pressed on a rigid floor (docs/bench/pad),
    /// with the contact's `friction` entry (empty: frictionless).
    fn pad(n: usize, friction: &str, path: &str) -> scene::Scene {
        scene::parse_toml(&format!(
            "dimension = 3\nmodel = \"solid\"\n[[materials]]\nname = \"r\"\nyoung = 10.0\npoisson = 0.45\n[[bodies]]\nname = \"pad\"\nmaterial = \"r\"\nmesh = {{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.1], divisions = [{n}, {n}, 2] }}\n[[bodies]]\nname = \"floor\"\nrigid = {{ shape = \"plane\", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}\n[[boundary]]\nbody = \"pad\"\nsurface = \"zmax\"\ndisplacement = {{ x = 0.0, y = 0.0, z = -0.005 }}\n[[contact]]\nname = \"c\"\nslave = {{ body = \"pad\", surface = \"zmin\" }}\nmaster = {{ body = \"floor\" }}\ndiscretization = \"node_to_face\"\n{friction}\n[solver]\npath = \"{path}\"\n"
        ))
        .expect("a valid pad scene")
    }

    const COULOMB: &str = "friction = { coulomb = 0.3 }";
    const NORTON_HOFF: &str = "friction = { norton_hoff = 0.3, rho = 0.2 }";

    fn chosen(sc: &scene::Scene, opts: &RunOptions) -> (scene::SolvePath, String) {
        let p = plan(sc, opts, 1, None).expect("a valid plan");
        assert_eq!(p.choice.chosen, p.path.as_str());
        (p.path, p.choice.reason)
    }

    #[test]
    fn auto_condenses_a_small_face_and_goes_direct_on_a_large_flat_one() {
        let none = RunOptions::default();
        // 25 × 25 contact nodes: either path is quick, condensed
        let (path, _) = chosen(&pad(24, "", "auto"), &none);
        assert_eq!(path, scene::SolvePath::Condensed);
        // 101 × 101: the dense interface costs far more than the sparse factors
        let (path, why) = chosen(&pad(100, "", "auto"), &none);
        assert_eq!(path, scene::SolvePath::Direct);
        assert!(why.starts_with("faster"), "{why}");
        let p = plan(&pad(100, "", "auto"), &none, 1, None).unwrap();
        let d = p
            .choice
            .direct
            .clone()
            .expect("the direct path runs the frictionless pad");
        assert!(
            d.seconds * 10.0 < p.choice.condensed.seconds,
            "{:?}",
            p.choice
        );
        assert_eq!(p.choice.requested, "auto");
    }

    #[test]
    fn an_explicit_path_is_honoured_and_friction_the_direct_path_cannot_run_stays_condensed() {
        let none = RunOptions::default();
        let (path, why) = chosen(&pad(100, "", "condensed"), &none);
        assert_eq!(
            (path, why.as_str()),
            (scene::SolvePath::Condensed, "asked for")
        );
        let direct = RunOptions {
            path: Some(scene::SolvePath::Direct),
            ..Default::default()
        };
        assert_eq!(
            chosen(&pad(4, "", "auto"), &direct).0,
            scene::SolvePath::Direct
        );
        // Coulomb friction runs on both paths: the large face goes direct
        let (path, why) = chosen(&pad(100, COULOMB, "auto"), &none);
        assert_eq!(path, scene::SolvePath::Direct, "{why}");
        // Norton–Hoff friction: the direct path cannot run it
        let p = plan(&pad(100, NORTON_HOFF, "auto"), &none, 1, None).unwrap();
        assert_eq!(p.path, scene::SolvePath::Condensed);
        assert!(p.choice.reason.contains("cannot run") && p.choice.direct.is_none());
        // ... and when the condensed path does not fit either, the refusal says why
        let budget = Budget {
            bytes: 1 << 30,
            source: "--max-memory",
        };
        let Err(e) = plan(&pad(100, NORTON_HOFF, "auto"), &none, 1, Some(budget)) else {
            panic!("the friction pad fits in 1 GiB");
        };
        let m = e.to_string();
        assert!(
            m.contains("path = \"auto\" chose the condensed path") && m.contains("friction"),
            "{m}"
        );
        // a frictionless pad that does not fit condensed goes direct
        let budget = Budget {
            bytes: 2 << 30,
            source: "--max-memory",
        };
        let p = plan(&pad(100, "", "auto"), &none, 1, Some(budget)).unwrap();
        assert_eq!(p.path, scene::SolvePath::Direct);
        assert!(
            p.choice.reason.contains("condensed estimate exceeds"),
            "{}",
            p.choice.reason
        );
    }
}
