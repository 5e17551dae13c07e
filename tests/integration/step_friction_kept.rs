//! A load step that lowers μ of a regularised Coulomb contact (with
//! `slip_stiffness`) keeps the contact's slip stiffness: `{ coulomb = 0.1 }`
//! was refused as "another kind" unless the step repeated
//! `slip_stiffness`; it now gives the forces of the step that repeats it,
//! and a step with another slip stiffness is still refused.

use crate::common;

use common::bad_scene::run_scene;
use common::{converged, forces, with_method};
use signorini_scene::Method;

/// A Tet10 box pressed on a rigid floor, then dragged by its top; μ 0.5
/// with slip stiffness 1e4, lowered to 0.1 at step 3 by `step3`.
fn dragged(step3: &str) -> String {
    format!(
        r#"
dimension = 3
model = "solid"

[[materials]]
name = "m"
young = 1000.0
poisson = 0.3

[[bodies]]
name = "box"
material = "m"
mesh = {{ generator = "box", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = [3, 3, 1], element = "tet10" }}

[[bodies]]
name = "floor"
rigid = {{ shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}

[[boundary]]
name = "press"
body = "box"
surface = "zmax"
displacement = {{ z = -0.01, y = 0.0 }}

[[boundary]]
name = "drag"
body = "box"
surface = "zmax"
displacement = {{ x = 0.004 }}

[[contact]]
name = "c"
slave = {{ body = "box", surface = "zmin" }}
master = {{ body = "floor" }}
discretization = "node_to_face"
friction = {{ coulomb = 0.5, slip_stiffness = 1e4 }}

[[steps]]
scale = {{ press = 1.0, drag = 0.0 }}

[[steps]]
scale = {{ drag = 1.0 }}

[[steps]]
friction = {{ c = {step3} }}

[output]
fields = []
"#
    )
}

#[test]
fn a_step_keeps_the_slip_stiffness_it_leaves_out() {
    let left_out = converged(&dragged("{ coulomb = 0.1 }"), with_method(Method::Status));
    let repeated = converged(
        &dragged("{ coulomb = 0.1, slip_stiffness = 1e4 }"),
        with_method(Method::Status),
    );
    let (a, b) = (forces(&left_out), forces(&repeated));
    assert_eq!(a, b);
    // μ = 0.1 binds at step 3: some point slips there
    assert!(
        left_out.report.steps[2].slipping > 0,
        "{:?}",
        left_out.report.steps[2]
    );
}

#[test]
fn a_step_with_another_slip_stiffness_is_refused() {
    let scene = dragged("{ coulomb = 0.1, slip_stiffness = 2e4 }");
    let run = run_scene("step_friction_other_slip_stiffness", Some(&scene), &[]);
    run.assert_bad_input(&["steps[2].friction.c", "slip_stiffness"]);
}
