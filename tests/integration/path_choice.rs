//! `solver.path = "auto"` (the default): the path chosen by cost, said in
//! report.json `path_choice` (docs/reference/scene-format.md, "Which path
//! solves the scene").

use crate::common;

use common::{converged, converged_on, example, forces};
use signorini_scene::SolvePath;
use signorini_solver::RunOptions;

/// A pad of n × n × 2 hex8 pressed on a rigid floor, frictionless
/// (docs/bench/pad).
fn pad(n: usize) -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/docs/bench/pad/pad48_frictionless.toml"
    ))
    .expect("the pad scene")
    .replace(
        "divisions = [48, 48, 2]",
        &format!("divisions = [{n}, {n}, 2]"),
    )
}

#[test]
fn auto_keeps_a_small_scene_condensed_and_says_so_in_the_report() {
    let o = converged(&example("blocks.toml"), RunOptions::default());
    assert_eq!(o.report.path, "condensed");
    let c = o.report.path_choice.as_ref().expect("path_choice");
    assert_eq!(
        (c.requested.as_str(), c.chosen.as_str()),
        ("auto", "condensed")
    );
    assert!(c.reason.contains("estimated"), "{}", c.reason);
    let direct = c
        .direct
        .as_ref()
        .expect("the direct path can run blocks.toml");
    assert!(c.condensed.memory_bytes > 0.0 && direct.memory_bytes > 0.0);
    assert!(c.condensed.fits && direct.fits);
    let json = serde_json::to_value(&o.report).expect("report.json");
    for key in ["requested", "chosen", "reason", "condensed", "direct"] {
        assert!(json["path_choice"].get(key).is_some(), "path_choice.{key}");
    }
    for key in [
        "memory_bytes",
        "sparse_flops",
        "dense_flops",
        "seconds",
        "fits",
    ] {
        assert!(json["path_choice"]["condensed"].get(key).is_some(), "{key}");
    }
    // an explicit path: asked for
    let o = converged_on(&example("blocks.toml"), SolvePath::Condensed);
    let c = o.report.path_choice.as_ref().expect("path_choice");
    assert_eq!(
        (c.requested.as_str(), c.reason.as_str()),
        ("condensed", "asked for")
    );
}

#[test]
fn auto_solves_a_large_flat_face_directly_with_the_condensed_answer() {
    let text = pad(40);
    let auto = converged(&text, RunOptions::default());
    assert_eq!(auto.report.path, "direct");
    let c = auto.report.path_choice.as_ref().expect("path_choice");
    assert!(c.reason.starts_with("faster"), "{}", c.reason);
    let condensed = converged_on(&text, SolvePath::Condensed);
    let (a, b) = (forces(&auto), forces(&condensed));
    let scale = b.iter().fold(0.0f64, |m, f| m.max(f.abs()));
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-8 * scale, "{x} against {y}");
    }
    // the direct path's memory estimate is the direct path's, not the
    // condensed one's: below it here
    let d = c.direct.as_ref().expect("direct estimate");
    assert!(d.memory_bytes < c.condensed.memory_bytes, "{c:?}");
    assert_eq!(auto.report.memory.estimated_bytes, d.memory_bytes as u64);
}
