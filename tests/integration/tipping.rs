//! A body held by friction alone that its load tips over has no static
//! equilibrium: no path may report it converged. A tall Tet10 block (0.2 ×
//! 0.2 × 2) stands on a rigid floor, μ = 2 (sliding is not the limit), and a
//! force (Q, 0, −1) on its top: about a bottom edge the load's moment 2Q
//! against the weight's 0.1 tips it for Q > 0.05. The direct path solves the
//! whole system with K + γI (the block floats), so it used to find a block
//! moved 1e12 away, held by γ u, and report it converged (exit 0, contact
//! force (0.15, 0.12, 1.06) against the load (1, 0, −1)).

use crate::common;

use common::{converged_on, try_run};
use signorini_scene::SolvePath;
use signorini_solver::RunOptions;

fn block(q: f64) -> String {
    format!(
        r#"
dimension = 3
model = "solid"

[[materials]]
name = "m"
young = 1000.0
poisson = 0.3

[[bodies]]
name = "block"
material = "m"
mesh = {{ generator = "box", origin = [0.0, 0.0, 0.0], size = [0.2, 0.2, 2.0], divisions = [2, 2, 10], element = "tet10" }}

[[bodies]]
name = "floor"
rigid = {{ shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}

[[boundary]]
name = "push"
body = "block"
surface = "zmax"
force = [{q}, 0.0, -1.0]

[[contact]]
name = "c"
slave = {{ body = "block", surface = "zmin" }}
master = {{ body = "floor" }}
discretization = "node_to_face"
friction = {{ coulomb = 2.0 }}

[output]
fields = []
"#
    )
}

fn on(path: SolvePath) -> RunOptions {
    RunOptions {
        method: None,
        path: Some(path),
    }
}

/// Pushed at Q = 1 (twenty times the tipping load) neither path converges:
/// the direct path says a rigid motion is unbalanced.
#[test]
fn a_block_that_tips_over_is_not_converged_on_either_path() {
    let scene = block(1.0);
    let condensed = try_run(&scene, on(SolvePath::Condensed)).unwrap();
    assert!(!condensed.report.converged);
    let direct = try_run(&scene, on(SolvePath::Direct)).unwrap();
    assert!(
        !direct.report.converged,
        "{:?}",
        common::contact_force(&direct, "c")
    );
    let failure = direct.report.failure.as_deref().unwrap_or("");
    assert!(failure.contains("unbalanced"), "{failure}");
}

/// Below the tipping load (Q = 0.02) both paths converge and the floor
/// balances the load: contact force (−Q, 0, 1) to 1e-8 of the load.
#[test]
fn a_block_below_its_tipping_load_stands_on_both_paths() {
    let q = 0.02;
    let scene = block(q);
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let out = converged_on(&scene, path);
        let force = common::contact_force(&out, "c");
        let expected = [-q, 0.0, 1.0];
        for (f, e) in force.iter().zip(expected) {
            assert!((f - e).abs() <= 1e-8, "{path:?}: {force:?}");
        }
    }
}
