//! Redundant constraints and slave nodes shared by two contacts:
//! detected and reported, exact duplicates eliminated (the problem
//! is unchanged), never a NaN or a silent singular solve.

use crate::common;

use common::{
    assert_message, block_body, block_boundary, block_contact, contact_force, converged, example,
    material_2d, max_rel, rigid_plane, with_method,
};
use signorini_scene::Method;
use signorini_solver::RunOutput;

/// The contact block of examples/blocks.toml.
fn blocks_contact(text: &str) -> (usize, usize) {
    let i = text.find("[[contact]]").unwrap();
    let j = i + 5 + text[i + 5..].find("\n[").unwrap();
    (i, j)
}

/// blocks.toml with its contact pair added a second time, transformed by `f`.
fn with_second_pair(f: impl Fn(&str) -> String) -> String {
    let text = example("blocks.toml");
    let (i, j) = blocks_contact(&text);
    let pair = &text[i..j];
    assert!(pair.contains("name = \"pad-base\""), "{pair}");
    let second = f(&pair.replacen("name = \"", "name = \"second-", 1));
    format!("{}\n\n{second}{}", &text[..j], &text[j..])
}

fn pad_base_forces(o: &RunOutput) -> Vec<f64> {
    o.contact_rows
        .iter()
        .filter(|r| r.contact == "pad-base")
        .map(|r| r.normal_force)
        .collect()
}

fn check_same_as_single_pair(text: &str, what: &str) {
    let single = converged(&example("blocks.toml"), with_method(Method::Status));
    for m in [Method::Status, Method::Mprgp, Method::Lemke] {
        let out = converged(text, with_method(m));
        assert!(
            out.report
                .messages
                .iter()
                .any(|msg| msg.contains("\"second-pad-base\"") && msg.contains("redundant")),
            "{what}, {m:?}: {:?}",
            out.report.messages
        );
        let s = &out.report.contacts;
        let second = s.iter().find(|c| c.name == "second-pad-base").unwrap();
        assert_eq!(second.points, 0, "{what}: every duplicate dropped");
        let d = max_rel(&pad_base_forces(&out), &pad_base_forces(&single));
        assert!(d <= 1e-10, "{what}, {m:?}: forces differ by {d:e}");
        let q = &out.report.reference.as_ref().unwrap().quantities["pressure"];
        assert!(q.relative_error <= 1e-10, "{what}, {m:?}: {}", q.computed);
    }
}

#[test]
fn a_contact_pair_given_twice_is_one_set_of_constraints() {
    let text = with_second_pair(|p| p.to_string());
    check_same_as_single_pair(&text, "duplicate pair");
}

#[test]
fn two_pass_node_to_node_contact_drops_the_repeated_pass() {
    // Each surface slave of the other: with matching meshes the rows of the
    // second pass equal those of the first.
    let text = with_second_pair(|p| {
        p.replace("slave", "SLAVE")
            .replace("master", "slave")
            .replace("SLAVE", "master")
    });
    assert!(text.contains("slave = { body = \"base\""));
    check_same_as_single_pair(&text, "two-pass");
}

/// A block pushed into a rigid corner: the bottom-left node is a slave of
/// the floor and of the wall, two different constraints, both kept and
/// reported; the answer is the exact one (the block is compressed in x and y
/// by the imposed displacements, no friction).
#[test]
fn a_corner_node_against_two_obstacles_keeps_both_constraints() {
    let (e, nu, d) = (100.0f64, 0.3f64, 0.01f64);
    let dy = -d;
    let text = [
        material_2d(e, nu),
        block_body([0.0, 0.0], [1.0, 1.0], [4, 4], ""),
        rigid_plane("floor", [0.0, 0.0], [0.0, 1.0]),
        rigid_plane("wall", [0.0, 0.0], [1.0, 0.0]),
        block_boundary(
            r#"surface = "top""#,
            &format!("displacement = {{ y = {dy} }}"),
        ),
        block_boundary(
            r#"surface = "right""#,
            &format!("displacement = {{ x = {dy} }}"),
        ),
        block_contact("floor", "bottom", "floor"),
        block_contact("wall", "left", "wall"),
    ]
    .concat();
    for m in [Method::Status, Method::Mprgp] {
        let out = converged(&text, with_method(m));
        assert_message(&out, "1 slave node(s) belong to both");
        // Uniform biaxial compression ε_xx = ε_yy = −d: in plane strain
        // σ = E/((1+ν)(1−2ν)) · (−d) for each normal stress, so the
        // resultant on each unit side is that stress.
        let sigma = e / ((1.0 + nu) * (1.0 - 2.0 * nu)) * d;
        let floor = contact_force(&out, "floor");
        let wall = contact_force(&out, "wall");
        assert!(((floor[1] - sigma) / sigma).abs() <= 1e-10, "{:?}", floor);
        assert!(((wall[0] - sigma) / sigma).abs() <= 1e-10, "{:?}", wall);
        assert!(out.contact_rows.iter().all(|r| r.normal_force.is_finite()));
    }
}
