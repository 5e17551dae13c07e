//! `signorini local`: a stand-alone condensed problem.

use std::path::Path;
use std::process::ExitCode;

use signorini_scene::Method;

use crate::fail;

/// The options of `signorini local`.
pub(crate) struct LocalOptions {
    /// The memory the solve may use (a larger problem is refused unread).
    pub budget: Option<signorini_report::budget::Budget>,
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Seconds a friction solve may take (`None`: the default).
    pub time_limit: Option<f64>,
    pub with_lambda: bool,
    pub friction: String,
    pub repeat: usize,
}

pub(crate) fn local(path: &Path, method: Method, o: LocalOptions) -> ExitCode {
    if !(o.tolerance > 0.0 && o.tolerance < 1.0) {
        return fail(
            1,
            &format!("--tolerance: must be in (0, 1), got {}", o.tolerance),
        );
    }
    if let Some(t) = o.time_limit.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return fail(
            1,
            &format!("--time-limit: must be a number of seconds > 0, got {t}"),
        );
    }
    let problem = match signorini_problems::local::load(path, o.budget) {
        Ok(p) => p,
        Err(e) => return fail(1, &e),
    };
    // The scene's defaults for the status variant and the constraints.
    let algorithm = signorini_solver::algorithm_of(&signorini_scene::Solver::default(), method);
    let name = path.display().to_string();
    let friction = if problem.mu.is_some() {
        if method != Method::Status {
            return fail(
                1,
                "--method: frictional local problems are solved by the friction solvers (--friction auto, fixed_point, status, newton or nsgs)",
            );
        }
        use signorini_problems::local::FrictionChoice;
        match FrictionChoice::from_name(&o.friction) {
            Ok(FrictionChoice::Method(f)) if problem.dim == 3 && !f.solves_3d() => {
                return fail(
                    1,
                    &format!(
                    "--friction {}: a 2D method; 3D problems: auto, fixed_point, newton or nsgs",
                    f.name()
                ),
                )
            }
            Ok(f) => Some(f),
            Err(e) => return fail(1, &e),
        }
    } else {
        None
    };
    let lcp = friction.is_none().then_some(algorithm);
    if let Err(e) = signorini_problems::local::accepts(&name, &problem, friction, lcp) {
        return fail(1, &e);
    }
    let limits = signorini_problems::local::Limits {
        tolerance: o.tolerance,
        max_iterations: o.max_iterations,
        time_limit: o.time_limit,
    };
    let solve = || match friction {
        Some(f) => {
            signorini_problems::local::solve_friction_by(&name, &problem, f, limits, o.with_lambda)
        }
        None => signorini_problems::local::solve_within(
            &name,
            &problem,
            algorithm,
            limits,
            o.with_lambda,
        ),
    };
    let result = signorini_problems::local::repeated(o.repeat, solve);
    match result {
        Ok(r) => {
            crate::say(&format!(
                "{}\n",
                serde_json::to_string(&r).unwrap_or_default()
            ));
            if r.converged {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(2)
            }
        }
        Err(e) => fail(2, &e),
    }
}
