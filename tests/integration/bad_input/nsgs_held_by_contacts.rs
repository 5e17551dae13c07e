//! `solver.friction = "nsgs"` with a body held by its contacts alone: NSGS
//! cannot hold the body's equilibrium, which couples every contact point.
//! It ended in "internal error" (exit 3) inside the solve; it is refused
//! before (exit 1, naming the key and the body, nothing written), and the
//! same scene with the body clamped is solved by NSGS; with Tresca
//! friction likewise (NSGS solves Coulomb's law only).

use super::BOX_ON_PLANE;
use crate::common::bad_scene::run_scene;

fn box_with_nsgs(extra: &str) -> String {
    format!(
        "{BOX_ON_PLANE}friction = {{ coulomb = 0.3 }}\n\n[solver]\nfriction = \"nsgs\"\n{extra}"
    )
}

#[test]
fn nsgs_with_a_body_held_by_contacts_alone_is_refused() {
    let run = run_scene("nsgs_held_by_contacts", Some(&box_with_nsgs("")), &[]);
    run.assert_bad_input(&[
        "solver.friction",
        "nsgs",
        "\"box\"",
        "held by its contacts alone",
    ]);
    // the direct path solves it (its own Newton method, not NSGS)
    let run = run_scene(
        "nsgs_held_by_contacts_direct",
        Some(&box_with_nsgs("path = \"direct\"\n")),
        &[],
    );
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
}

#[test]
fn nsgs_with_every_body_supported_runs() {
    let held = box_with_nsgs("").replace(
        "displacement = { x = 0.0 }",
        "displacement = { x = 0.0, z = 0.0 }",
    );
    let run = run_scene("nsgs_supported", Some(&held), &[]);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
}

/// NSGS with Tresca friction ended in "internal error" (exit 3) too: refused
/// naming the contact.
#[test]
fn nsgs_with_tresca_friction_is_refused() {
    let held = box_with_nsgs("")
        .replace(
            "displacement = { x = 0.0 }",
            "displacement = { x = 0.0, z = 0.0 }",
        )
        .replace(
            "friction = { coulomb = 0.3 }",
            "friction = { tresca = 0.1 }",
        );
    let run = run_scene("nsgs_tresca", Some(&held), &[]);
    run.assert_bad_input(&["solver.friction", "nsgs", "\"box-ground\"", "Tresca"]);
}
