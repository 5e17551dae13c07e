//! `search_distance`, the candidate zone of a contact: the slave nodes whose
//! initial gap exceeds it (plus the prescribed motion) are neither contact
//! unknowns nor interface DOFs. The answer must be the one without a zone
//! (contact forces and displacements), with fewer contact points and
//! interface DOFs; a zone too small is widened after the solve (a note says
//! so) and still gives the same answer; a bad value is refused (exit 1).

use crate::common;

use common::{converged, converged_on, example, max_rel, with_zone, PULLED_BLOCK};
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, RunOutput};

/// Every body's displacement at every step, one vector.
fn displacements(o: &RunOutput) -> Vec<f64> {
    o.bodies
        .iter()
        .flat_map(|b| b.history.iter().flat_map(|s| s.displacement.clone()))
        .collect()
}

/// The normal force of every contact point of `full` at the last step, and
/// the same points' forces in `zoned` (zero where `zoned` has no point: it
/// left the node out).
fn matched_forces(full: &RunOutput, zoned: &RunOutput) -> (Vec<f64>, Vec<f64>) {
    let last = |o: &RunOutput| o.contact_rows.iter().map(|r| r.step).max().unwrap_or(0);
    let (lf, lz) = (last(full), last(zoned));
    let rows = |o: &RunOutput, l| {
        o.contact_rows
            .iter()
            .filter(|r| r.step == l)
            .cloned()
            .collect::<Vec<_>>()
    };
    let (rf, rz) = (rows(full, lf), rows(zoned, lz));
    let a: Vec<f64> = rf.iter().map(|r| r.normal_force).collect();
    let b: Vec<f64> = rf
        .iter()
        .map(|r| {
            rz.iter()
                .find(|q| q.contact == r.contact && q.x == r.x)
                .map_or(0.0, |q| q.normal_force)
        })
        .collect();
    (a, b)
}

/// The zoned run equals the full one (resultant, per-point forces,
/// displacements within `tol`) with fewer contact points and interface DOFs.
fn assert_same_answer(full: &RunOutput, zoned: &RunOutput, tol: f64) {
    let (rf, rz) = (&full.report, &zoned.report);
    let d = max_rel(&rf.contact_force, &rz.contact_force);
    assert!(d <= tol, "contact force differs by {d:e}");
    let (a, b) = matched_forces(full, zoned);
    assert!(a.iter().any(|&f| f > 0.0), "no point in contact");
    let d = max_rel(&a, &b);
    assert!(d <= tol, "nodal forces differ by {d:e}");
    let d = max_rel(&displacements(full), &displacements(zoned));
    assert!(d <= tol, "displacements differ by {d:e}");
}

fn zone_notes(o: &RunOutput) -> (usize, usize) {
    let m = &o.report.messages;
    (
        m.iter()
            .filter(|s| s.contains("search_distance keeps"))
            .count(),
        m.iter()
            .filter(|s| s.contains("solved again with the candidate zone widened"))
            .count(),
    )
}

#[test]
fn hertz_2d_with_a_zone_equals_the_full_run_with_fewer_unknowns() {
    let text = example("hertz2d.toml");
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let full = converged_on(&text, path);
        let zoned = converged_on(&with_zone(&text, "node_to_segment", 0.05), path);
        assert_same_answer(&full, &zoned, 1e-9);
        let (rf, rz) = (&full.report, &zoned.report);
        // The arc has 161 nodes, R = 1: initial gaps 1 − cos θ ≤ 0.065 keep
        // |θ| ≤ 21°, about half of the nodes (graded towards the pole).
        assert!(
            rz.contact_points * 3 < rf.contact_points * 2,
            "{path:?}: {} of {} points",
            rz.contact_points,
            rf.contact_points
        );
        if path == SolvePath::Condensed {
            assert!(rz.interface_dofs * 3 < rf.interface_dofs * 2);
            // one Γ DOF per node: frictionless on a rigid plane, the
            // contact frames condense the normal component only
            assert_eq!(rz.interface_dofs, rz.contact_points);
        }
        assert_eq!(zone_notes(&zoned), (1, 0), "{:?}", rz.messages);
        assert_eq!(zone_notes(&full), (0, 0));
    }
}

/// The example `name` solved without and with the zone `d` on its contact
/// of `discretization`, checked to give the same answer.
fn full_and_zoned(name: &str, discretization: &str, d: f64) -> (RunOutput, RunOutput) {
    let text = example(name);
    let full = converged(&text, RunOptions::default());
    let zoned = converged(&with_zone(&text, discretization, d), RunOptions::default());
    assert_same_answer(&full, &zoned, 1e-9);
    (full, zoned)
}

#[test]
fn hertz_3d_with_a_zone_equals_the_full_run_with_fewer_interface_dofs() {
    let (full, zoned) = full_and_zoned("hertz3d.toml", "node_to_face", 0.02);
    let (rf, rz) = (&full.report, &zoned.report);
    // one Γ DOF per contact node (contact frames)
    assert_eq!((rf.contact_points, rf.interface_dofs), (505, 505));
    // gaps ≤ 0.02 + the press 0.01: the rings within θ ≈ 14° of the pole.
    assert!(rz.contact_points < rf.contact_points / 4);
    assert_eq!(rz.interface_dofs, rz.contact_points);
    assert_eq!(zone_notes(&zoned), (1, 0));
}

#[test]
fn a_zone_too_small_is_widened_and_gives_the_same_answer() {
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let full = converged_on(&PULLED_BLOCK, path);
        let small = with_zone(&PULLED_BLOCK, "node_to_segment", 2e-3);
        let zoned = converged_on(&small, path);
        assert_same_answer(&full, &zoned, 1e-9);
        let (_, widened) = zone_notes(&zoned);
        assert!(
            widened >= 1,
            "{path:?}: no widening: {:?}",
            zoned.report.messages
        );
        let touching = full
            .contact_rows
            .iter()
            .filter(|r| r.normal_force > 0.0)
            .count();
        assert!(touching >= 5, "{path:?}: {touching} points touch");
        assert!(zoned.report.contact_points >= touching);
        assert!(zoned.report.contact_points < full.report.contact_points);
    }
}

#[test]
fn a_zone_with_a_deformable_master_friction_steps_and_node_to_node_keeps_the_answer() {
    // cyclic.toml with the sideways pull prescribed (the cylinder is then
    // supported): a cylinder on a deformable block, Coulomb friction over
    // eleven load steps.
    let cyclic =
        example("cyclic.toml").replace("force = [0.0006, 0.0]", "displacement = { x = 2e-4 }");
    assert!(cyclic.contains("x = 2e-4"));
    let full = converged(&cyclic, RunOptions::default());
    let zoned_text = with_zone(&cyclic, "node_to_segment", 0.02);
    let zoned = converged(&zoned_text, RunOptions::default());
    assert_same_answer(&full, &zoned, 1e-8);
    let (rf, rz) = (&full.report, &zoned.report);
    assert!(rz.interface_dofs < rf.interface_dofs && rz.contact_points < rf.contact_points);
    assert!(rz.steps.len() == rf.steps.len() && rz.steps.len() > 5);
    assert_eq!(zone_notes(&zoned), (1, 0), "{:?}", rz.messages);
    // blocks.toml pressed by a prescribed displacement, node-to-node between
    // matching meshes: every gap is 0, every node is kept, and the interface
    // built from the kept rows is both surfaces, as without a zone.
    let blocks =
        example("blocks.toml").replace("traction = [0.0, -1.0]", "displacement = { y = -0.01 }");
    let full = converged(&blocks, RunOptions::default());
    let zoned = converged(
        &with_zone(&blocks, "node_to_node", 1e-3),
        RunOptions::default(),
    );
    assert_same_answer(&full, &zoned, 1e-12);
    assert_eq!(zoned.report.interface_dofs, full.report.interface_dofs);
    assert_eq!(zoned.report.contact_points, full.report.contact_points);
    assert_eq!(zone_notes(&zoned), (0, 0));
}

#[test]
fn a_body_held_by_contact_alone_ignores_the_zone_with_a_note() {
    // cyclic.toml as shipped: the cylinder is held sideways by friction alone.
    let text = example("cyclic.toml");
    let zoned = converged(
        &with_zone(&text, "node_to_segment", 0.02),
        RunOptions::default(),
    );
    let full = converged(&text, RunOptions::default());
    assert_same_answer(&full, &zoned, 1e-12);
    assert_eq!(zoned.report.contact_points, full.report.contact_points);
    assert_eq!(zoned.report.interface_dofs, full.report.interface_dofs);
    common::assert_message(&zoned, "search_distance does not apply");
}

#[test]
fn a_search_distance_that_is_not_a_positive_length_is_refused() {
    for (tag, v) in [
        ("zero", "0.0"),
        ("negative", "-1.0"),
        ("nan", "nan"),
        ("inf", "inf"),
    ] {
        let dir = common::fresh_dir("search_distance", tag);
        let scene = dir.join("scene.toml");
        let text = PULLED_BLOCK.replace(
            "discretization = \"node_to_segment\"\n",
            &format!("discretization = \"node_to_segment\"\nsearch_distance = {v}\n"),
        );
        std::fs::write(&scene, text).unwrap();
        let out = common::cli_run(&scene, dir.join("out"));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{tag}: {err}");
        assert!(
            err.contains("contact \"block-cylinder\".search_distance")
                && err.contains("positive finite length"),
            "{tag}: {err}"
        );
        assert!(!dir.join("out").exists(), "{tag}: wrote output");
    }
}

#[test]
fn axisymmetric_hertz_with_a_zone_equals_the_full_run() {
    let (full, zoned) = full_and_zoned("hertz_axi.toml", "node_to_segment", 0.05);
    let (rf, rz) = (&full.report, &zoned.report);
    assert!(rz.contact_points * 3 < rf.contact_points * 2);
    assert!(rz.interface_dofs * 3 < rf.interface_dofs * 2);
    assert_eq!(zone_notes(&zoned), (1, 0));
}

#[test]
fn a_widened_zone_that_does_not_fit_is_refused_saying_why() {
    let dir = common::fresh_dir("search_distance", "widened_memory");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, with_zone(&PULLED_BLOCK, "node_to_segment", 2e-3)).unwrap();
    // the widened zone's estimate, as the report keeps it
    common::cli_run_ok(&scene, dir.join("free"));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("free/report.json")).unwrap())
            .unwrap();
    let widened = report["memory"]["estimated_bytes"].as_u64().unwrap();
    let messages = report["messages"].to_string();
    assert!(
        messages.contains("solved again with the candidate zone widened"),
        "{messages}"
    );
    // one byte less: the first zone fits, the widened one does not
    let out = std::process::Command::new(common::BIN)
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("tight"))
        .args(["--max-memory", &(widened - 1).to_string()])
        .output()
        .unwrap();
    let err = common::stderr_of_exit(&out, 1);
    assert!(
        err.contains("the candidate zone widened to hold it does not fit")
            && err.contains("memory: the scene needs about"),
        "{err}"
    );
    assert!(!dir.join("tight").exists());
}

/// Friction with a candidate zone on the direct path: cyclic.toml with its
/// pull prescribed and held by friction alone, each with a zone, gives the
/// condensed path's forces, slips and displacements.
#[test]
fn a_zone_with_friction_has_the_condensed_forces_on_the_direct_path() {
    let cyclic = example("cyclic.toml");
    let pulled = cyclic.replace("force = [0.0006, 0.0]", "displacement = { x = 2e-4 }");
    for text in [pulled, cyclic] {
        common::twins::on_both_paths(&with_zone(&text, "node_to_segment", 0.02), 1e-8);
    }
}
