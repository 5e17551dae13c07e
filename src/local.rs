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
                "--method: frictional local problems are solved by the friction solvers (--friction fixed_point, status or newton)",
            );
        }
        match signorini_problems::local::FrictionMethod::from_name(&o.friction) {
            Ok(f) if problem.dim == 3 && !f.solves_3d() => {
                return fail(
                    1,
                    &format!(
                        "--friction {}: a 2D method; 3D problems: fixed_point or newton",
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
    let solve = || match friction {
        Some(f) => signorini_problems::local::solve_friction(
            &name,
            &problem,
            f,
            o.tolerance,
            o.max_iterations,
            o.with_lambda,
        ),
        None => signorini_problems::local::solve(
            &name,
            &problem,
            algorithm,
            o.tolerance,
            o.max_iterations,
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
