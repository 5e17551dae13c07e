//! Substructuring in one process (course notes §8.3): bodies split into METIS parts
//! glue exactly and reproduce the unsplit solution (docs/theory/validation-cases.md §7).

use crate::common;

use common::{
    assert_same, block_body, block_boundary, contact_force, converged_on as solve, example,
    material_2d, max_rel,
};
use signorini_scene::SolvePath;
use signorini_solver::RunOutput;

#[test]
fn hertz_half_disk_split_in_two_equals_the_unsplit_body() {
    let one = example("hertz2d.toml").replace("divisions = 160", "divisions = 96");
    let two = common::with_subdomains(&one, "material = \"steel\"\n", 2);
    assert_ne!(one, two);
    let a = solve(&one, SolvePath::Condensed);
    let b = solve(&two, SolvePath::Condensed);
    assert_eq!(b.report.subdomains, 2);
    assert!(
        b.report.interface_dofs > a.report.interface_dofs,
        "the cut adds glued DOFs to Γ"
    );
    assert_same(&a, &b, 1e-8);
}

/// A block on a frictionless support under a uniform traction is a linear
/// patch: split into 4 METIS parts, the glued interfaces transmit it exactly.
#[test]
fn glued_interfaces_of_four_parts_transmit_a_linear_patch_exactly() {
    let block = |parts: usize| {
        [
            material_2d(1000.0, 0.25),
            block_body([0.0, 0.0], [2.0, 1.0], [16, 9], ", element = \"tri3\"").replace(
                "material = \"m\"\n",
                &format!("material = \"m\"\nsubdomains = {parts}\n"),
            ),
            block_boundary(r#"surface = "bottom""#, "displacement = { y = 0.0 }"),
            block_boundary("point = [0.0, 0.0]", "displacement = { x = 0.0 }"),
            block_boundary(r#"surface = "top""#, "traction = [0.0, -3.0]"),
        ]
        .concat()
    };
    let a = solve(&block(1), SolvePath::Condensed);
    let b = solve(&block(4), SolvePath::Condensed);
    assert_eq!(b.report.subdomains, 4);
    assert!(b.report.interface_dofs > 0);
    let r = max_rel(
        &a.bodies[0].last().displacement,
        &b.bodies[0].last().displacement,
    );
    assert!(r <= 1e-10, "split vs unsplit: {r:e}");
    // And both are the exact patch: u_y = −p y (1 − ν²)/E in plane strain.
    let body = &b.bodies[0];
    for (n, x) in body.coords.iter().enumerate() {
        let exact = -3.0 * x[1] * (1.0 - 0.0625) / 1000.0;
        assert!(
            (body.last().displacement[2 * n + 1] - exact).abs() <= 1e-10 * 3.0 / 1000.0,
            "node {n}"
        );
    }
}

#[test]
fn stack_of_split_blocks_equals_the_unsplit_stack_and_the_direct_path() {
    let split = example("stack.toml");
    let whole = split.replace("subdomains = 2\n", "");
    assert_ne!(split, whole);
    let a = solve(&whole, SolvePath::Condensed);
    let b = solve(&split, SolvePath::Condensed);
    let c = solve(&split, SolvePath::Direct);
    assert_eq!(b.report.subdomains, 5);
    assert_same(&a, &b, 1e-8);
    assert_same(&b, &c, 1e-9);
    // Equilibrium of the stack: what the roller pushes, the floor carries.
    let force = |o: &RunOutput, name: &str| contact_force(o, name)[1];
    let roller = force(&b, "roller-plate");
    for pair in ["plate-base", "base-floor"] {
        assert!((force(&b, pair) - roller).abs() <= 1e-9 * roller, "{pair}");
    }
}
