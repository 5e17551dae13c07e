//! Second-order solids (Tet10, Hex20) and node-to-face contact on their
//! quadratic faces (docs/theory/elements.md): the contact patch test on
//! generated and Gmsh meshes, matching and not, 3D mortar on them, and
//! the Hertz sphere.

use crate::common;

use common::{
    assert_patch_test_passes, assert_reference_within, converged, example, reference_error,
};
use signorini_solver::{RunOptions, RunOutput};

/// examples/patch3d.toml (two stacked boxes, uniform pressure) with the
/// base divided `base` and the block `block`, both in `element` cells.
fn stacked(element: &str, base: &str, block: &str) -> String {
    example("patch3d.toml")
        .replace(
            "divisions = [4, 4, 2] }",
            &format!("divisions = {base}, element = \"{element}\" }}"),
        )
        .replace(
            "divisions = [5, 5, 2] }",
            &format!("divisions = {block}, element = \"{element}\" }}"),
        )
}

/// The run of [`stacked`] with the base divided [4, 4, 2].
fn stacked_run(element: &str, block: &str) -> RunOutput {
    converged(&stacked(element, "[4, 4, 2]", block), RunOptions::default())
}

/// Matching quadratic meshes pass the contact patch test to round-off:
/// every nodal pressure (force over the recombined measure) is the applied
/// one. Without the recombination the Hex20 corners, whose consistent
/// measure is −A/12, could not carry their tensile share (32 % off).
#[test]
fn stacked_quadratic_blocks_pass_the_patch_test_on_matching_meshes() {
    for element in ["tet10", "hex20"] {
        let out = stacked_run(element, "[4, 4, 2]");
        assert_patch_test_passes(&out, 1e-10, element);
    }
}

/// One-pass node-to-face on non-matching meshes does not pass the patch
/// test, in second order as in first (examples/patch3d.toml): the deviation
/// is reported, the resultant stays exact.
#[test]
fn stacked_quadratic_blocks_on_non_matching_meshes_keep_the_resultant() {
    for element in ["tet10", "hex20"] {
        let out = stacked_run(element, "[5, 5, 2]");
        assert!(reference_error(&out, "resultant") <= 1e-12, "{element}");
        assert!(
            reference_error(&out, "pressure") > 1e-3,
            "{element}: the deviation is reported"
        );
    }
}

/// Gmsh second-order meshes (tests/data/quadratic: `gmsh -3 -order 2`, Tet10
/// with Tri6 faces, Hex20 with Quad8 faces) on a rigid plane under a
/// uniform pressure: the pressure everywhere.
#[test]
fn gmsh_second_order_blocks_pass_the_uniform_pressure_patch_test() {
    for mesh in ["block_tet10.msh", "block_hex20.msh"] {
        let path = format!("{}/tests/data/quadratic/{mesh}", env!("CARGO_MANIFEST_DIR"));
        let text = example("gmsh_block3d.toml").replace(
            "file = \"meshes/block3d.msh\"",
            &format!("file = \"{path}\""),
        );
        assert!(text.contains(&path));
        let out = converged(&text, RunOptions::default());
        assert_patch_test_passes(&out, 1e-10, mesh);
    }
}

/// 3D mortar takes quadratic faces (it refused them before): the same
/// non-matching blocks pass the patch test (tests/integration/quadratic_patch.rs
/// for the rest).
#[test]
fn mortar_takes_quadratic_faces() {
    let text = stacked("hex20", "[4, 4, 2]", "[5, 5, 2]").replace(
        "discretization = \"node_to_face\"",
        "discretization = \"mortar\"",
    );
    let out = converged(&text, RunOptions::default());
    assert!(
        reference_error(&out, "pressure") <= 1e-10,
        "{}",
        reference_error(&out, "pressure")
    );
    assert!(reference_error(&out, "resultant") <= 1e-12);
}

/// examples/hertz3d_quadratic.toml: the Hex20 quarter hemisphere on a rigid
/// plane (17 049 DOFs, its symmetry planes held) has p0 and a within 0.5 %
/// of Hertz, and within 0.1 % (measured 0.036 % and 0.009 %, a from the
/// pressure moment in the faces' own basis); the resultant is along z.
#[test]
fn hertz_sphere_in_hex20_within_half_a_percent() {
    let out = converged(&example("hertz3d_quadratic.toml"), RunOptions::default());
    assert_reference_within(&out, &[("p0", 0.005), ("a", 0.005)], "");
    assert_reference_within(&out, &[("p0", 0.001), ("a", 0.001)], "");
    let f = &out.report.contact_force;
    assert!(f[0].abs() + f[1].abs() <= 1e-9 * f[2].abs(), "{f:?}");
}

/// The Tet10 quarter hemisphere (hexahedra cut in 12 tetrahedra about their
/// centre, made second-order) against Hertz: within 2 % on a coarse mesh
/// (measured p0 1.3 %, a 0.22 %).
#[test]
fn hertz_sphere_in_tet10_within_two_percent() {
    let text = example("hertz3d_quadratic.toml")
        .replace("divisions = 13,", "divisions = 7,")
        .replace("element = \"hex20\"", "element = \"tet10\"");
    let out = converged(&text, RunOptions::default());
    assert_reference_within(&out, &[("p0", 0.02), ("a", 0.04)], "");
}

/// CalculiX's deck contact4.inp (two C3D20 cubes, docs/performance/calculix.md)
/// translated to docs/peers/calculix/contact4.toml: the contact carries the
/// applied 100 × 0.5² = 25, and the punch (ν = 0, its top held in x and y,
/// uniform pressure on top, exact contact below) is in uniform compression:
/// top and bottom move apart by 100 · 0.5 / E, the bottom face stays flat.
#[test]
fn calculix_contact4_translation_carries_the_load_in_uniform_compression() {
    let dir = format!("{}/docs/peers/calculix", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(format!("{dir}/contact4.toml"))
        .unwrap()
        .replace(
            "file = \"contact4.msh\"",
            &format!("file = \"{dir}/contact4.msh\""),
        );
    let out = converged(&text, RunOptions::default());
    let f = &out.report.contact_force;
    assert!((f[2] - 25.0).abs() <= 1e-12 * 25.0, "{f:?}");
    let uz: Vec<f64> = out.bodies[1]
        .last()
        .displacement
        .chunks(3)
        .map(|u| u[2])
        .collect();
    let (top, bottom) = uz
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &u| (lo.min(u), hi.max(u)));
    let squeeze = 100.0 * 0.5 / 210000.0;
    assert!(
        ((bottom - top) - squeeze).abs() <= 1e-9 * squeeze,
        "{top:e} {bottom:e}"
    );
    let flat = uz.iter().filter(|&&u| (u - bottom).abs() <= 1e-9 * squeeze);
    assert_eq!(flat.count(), 8, "the punch's bottom face moves as one");
}
