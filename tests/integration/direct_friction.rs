//! Friction on the direct path (docs/theory/direct-friction.md): the
//! whole-system semi-smooth Newton method gives the condensed path's contact
//! forces, tangential forces, slips and displacements, in 2D and 3D, with
//! Tresca and Coulomb, over load steps with slip history, and for bodies
//! held by friction alone.

use crate::common;

use common::twins::{on_both_paths, stick_slip};
use common::{block_contact, example, rigid_plane, try_run};
use signorini_scene::SolvePath;
use signorini_solver::RunOptions;

/// A 1 × 1 × 0.1 rubber pad (Hex8, n × n × 2) on a rigid floor, its top
/// pressed down by 0.004 at step 1 and dragged by 0.004 along x (and
/// 0.002 along y) at step 2, with `friction`.
fn pad(n: usize, friction: &str) -> String {
    let mesh = format!("{{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.1], divisions = [{n}, {n}, 2] }}");
    let top = "surface = \"zmax\"";
    "dimension = 3\nmodel = \"solid\"\n".to_string()
        + &common::material("rubber", 10.0, 0.45)
        + &common::body("pad", "rubber", &mesh)
        + &rigid_plane("floor", [0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
        + &common::boundary("press", "pad", top, "displacement = { z = -0.004 }")
        + &common::boundary(
            "drag",
            "pad",
            top,
            "displacement = { x = 0.004, y = 0.002 }",
        )
        + "[[steps]]\nscale = { drag = 0.0 }\n[[steps]]\nscale = { drag = 1.0 }\n"
        + &common::contact("c", "pad", "zmin", "floor")
        + &format!("discretization = \"node_to_face\"\nfriction = {friction}\n")
}

#[test]
fn a_24_by_24_pad_pressed_then_dragged_has_the_condensed_forces_on_the_direct_path() {
    let (c, d) = on_both_paths(&pad(24, "{ coulomb = 0.3 }"), 1e-8);
    // every Newton direction by GMRES on the LDLᵀ of the symmetric part,
    // none by the LU: one LDLᵀ per Newton iteration
    let f = d.report.factorisation.clone().expect("a factorisation");
    let iterations: usize = d.report.steps.iter().map(|s| s.iterations).sum();
    assert_eq!(f.kind, "ldlt+gmres");
    assert_eq!(f.lu_fallbacks, Some(0));
    assert_eq!(f.factorisations, Some(iterations));
    assert!(f.refinement_steps.unwrap_or(0) >= iterations, "{f:?}");
    let (stick, slip) = stick_slip(&c);
    assert!(
        stick > 0 && slip > 0,
        "partial slip: {stick} stick, {slip} slip"
    );
}

#[test]
fn a_pad_with_tresca_friction_has_the_condensed_forces_on_the_direct_path() {
    let (c, _) = on_both_paths(&pad(8, "{ tresca = 0.0005 }"), 1e-8);
    let (stick, slip) = stick_slip(&c);
    assert!(stick + slip > 0, "{stick} stick, {slip} slip");
}

/// A 2 × 1 block (2D, 8 × 4) on a rigid floor, its top displaced by `top`,
/// no support in x: held sideways by friction alone; `steps` appended.
fn block_2d(friction: &str, top: &str, steps: &str) -> String {
    common::block_pressed_on_floor(top)
        + &block_contact("c", "bottom", "floor")
        + &format!("friction = {friction}\n{steps}\n")
}

#[test]
fn a_2d_block_with_coulomb_or_tresca_has_the_condensed_forces_on_the_direct_path() {
    for friction in ["{ coulomb = 0.3 }", "{ tresca = 0.05 }"] {
        let (c, _) = on_both_paths(&block_2d(friction, "{ x = 0.004, y = -0.01 }", ""), 1e-8);
        let (stick, slip) = stick_slip(&c);
        assert!(stick + slip > 0, "{friction}: {stick} stick, {slip} slip");
    }
}

#[test]
fn load_reversal_keeps_the_slip_history_on_the_direct_path() {
    let steps = "[[steps]]\nscale = { press = 1.0 }\n[[steps]]\nscale = { press = -1.0 }\n";
    let text = block_2d("{ coulomb = 0.3 }", "{ x = 0.05 }", steps).replace(
        "displacement = { x = 0.05 }",
        "displacement = { x = 0.05 }\n[[boundary]]\nname = \"down\"\nbody = \"block\"\nsurface = \"top\"\ndisplacement = { y = -0.01 }",
    );
    let (_, d) = on_both_paths(&text, 1e-8);
    // Step 1 slides in +x, step 2 back: the friction force μ N reverses.
    let resultant = |step: usize| {
        let rows = d.contact_rows.iter().filter(|r| r.step == step);
        rows.fold((0.0, 0.0), |(n, t), r| {
            (n + r.normal_force, t + r.tangential_force)
        })
    };
    let ((n1, t1), (n2, t2)) = (resultant(1), resultant(2));
    assert!((t1 + 0.3 * n1).abs() <= 1e-9 * n1, "step 1: {t1} vs {n1}");
    assert!((t2 - 0.3 * n2).abs() <= 1e-9 * n2, "step 2: {t2} vs {n2}");
}

#[test]
fn the_cattaneo_example_has_the_condensed_forces_on_the_direct_path() {
    on_both_paths(&example("cattaneo.toml"), 1e-8);
}

#[test]
fn the_sliding3d_example_over_three_steps_has_the_condensed_forces_on_the_direct_path() {
    on_both_paths(&example("sliding3d.toml"), 1e-8);
}

#[test]
fn a_3d_box_held_by_friction_alone_has_the_condensed_forces_on_the_direct_path() {
    // No support in x, y: the box is held sideways by friction alone, its
    // top pressed down and pushed sideways below μ N.
    let text = pad(6, "{ coulomb = 0.5 }").replace(
        "displacement = { x = 0.004, y = 0.002 }",
        "traction = [0.02, 0.01, 0.0]",
    );
    let (_, d) = on_both_paths(&text, 1e-8);
    let f = &d.report.contact_force;
    assert!(f[0].abs() > 0.0, "friction carries the push: {f:?}");
}

#[test]
fn norton_hoff_and_rough_contacts_are_refused_on_the_direct_path() {
    let direct = RunOptions {
        method: None,
        path: Some(SolvePath::Direct),
    };
    let rough = try_run(&example("rough_drag.toml"), direct.clone());
    let e = rough.err().expect("refused").to_string();
    assert!(e.contains("roughness") && e.contains("condensed"), "{e}");
    let nh = try_run(
        &block_2d(
            "{ norton_hoff = 0.3, rho = 0.2 }",
            "{ x = 0.004, y = -0.01 }",
            "",
        ),
        direct,
    );
    let e = nh.err().expect("refused").to_string();
    assert!(e.contains("Norton-Hoff") && e.contains("condensed"), "{e}");
}

#[test]
fn regularised_coulomb_has_the_condensed_forces_on_the_direct_path() {
    let friction = "{ coulomb = 0.3, slip_stiffness = 2000.0 }";
    let (c, _) = on_both_paths(&block_2d(friction, "{ x = 0.004, y = -0.01 }", ""), 1e-8);
    let (stick, slip) = stick_slip(&c);
    assert!(stick + slip > 0, "{stick} stick, {slip} slip");
}

#[test]
fn the_ssnv128_example_has_the_condensed_forces_on_the_direct_path() {
    on_both_paths(&example("ssnv128.toml"), 1e-8);
}

/// The 3D friction scenes of `friction3d` on the direct path: the elliptic
/// cone dragged along each axis and the Cattaneo–Mindlin sphere (partial
/// slip) give the condensed path's forces, slips and displacements, and the
/// same stick and slip counts.
#[test]
fn the_3d_friction_scenes_give_the_condensed_answer_on_the_direct_path() {
    use crate::friction3d::{box_scene, sphere_on_block};
    for drag in [[0.1, 0.0], [0.0, 0.1]] {
        on_both_paths(&box_scene("{ coulomb = [0.3, 0.1] }", drag, None), 1e-8);
    }
    let (c, d) = on_both_paths(&sphere_on_block(), 1e-8);
    assert_eq!(stick_slip(&c), stick_slip(&d));
}
