//! Twins: a scene solved on the condensed and on the direct path, their
//! answers compared (docs/guide/choosing.md: both paths solve the same
//! contact problem), or the direct path's refusal of what it leaves to the
//! condensed path.

use super::{converged_on, max_rel, try_run};
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, RunOutput};

/// Every step's normal and tangential forces of contact.csv, one vector.
pub fn contact_forces(o: &RunOutput) -> Vec<f64> {
    let rows = &o.contact_rows;
    rows.iter()
        .map(|r| r.normal_force)
        .chain(rows.iter().map(|r| r.tangential_force))
        .chain(rows.iter().map(|r| r.tangential_force_2))
        .collect()
}

/// Every step's slip increments of contact.csv.
pub fn slips(o: &RunOutput) -> Vec<f64> {
    let rows = &o.contact_rows;
    rows.iter()
        .map(|r| r.slip)
        .chain(rows.iter().map(|r| r.slip_2))
        .collect()
}

/// The largest displacement component of any body at the last step.
fn displacement_scale(o: &RunOutput) -> f64 {
    o.bodies
        .iter()
        .flat_map(|b| b.last().displacement.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Solves `text` on both paths (each converged, certificate ≤ 1e-9) and
/// asserts that the contact forces (normal and tangential, every step), the
/// slips (relative to the largest slip or last displacement) and the
/// displacements of every step (relative to each body's largest) agree
/// to `tol`, and that the direct path ran its semi-smooth Newton method when
/// the scene has friction; returns (condensed, direct).
pub fn on_both_paths(text: &str, tol: f64) -> (RunOutput, RunOutput) {
    let c = converged_on(text, SolvePath::Condensed);
    let d = converged_on(text, SolvePath::Direct);
    assert_eq!(c.contact_rows.len(), d.contact_rows.len(), "contact rows");
    let (fc, fd) = (contact_forces(&c), contact_forces(&d));
    let force_error = max_rel(&fc, &fd);
    assert!(
        force_error <= tol,
        "contact forces differ by {force_error:e}"
    );
    let (sc, sd) = (slips(&c), slips(&d));
    // the larger of the last displacements and the slips (a step unloaded
    // to no load keeps slips from the steps before)
    let u_scale = sc
        .iter()
        .fold(displacement_scale(&c), |a, v| a.max(v.abs()));
    let slip_error = sc
        .iter()
        .zip(&sd)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    assert!(
        slip_error <= tol * u_scale,
        "slips differ by {slip_error:e} (displacement scale {u_scale:e})"
    );
    for (x, y) in c.bodies.iter().zip(&d.bodies) {
        // every step, relative to the body's largest displacement of the
        // run (a step unloaded to no load is compared on the loaded scale)
        let steps = x.history.iter().zip(&y.history);
        let scale = (x.history.iter())
            .flat_map(|s| s.displacement.iter())
            .fold(f64::MIN_POSITIVE, |a, v| a.max(v.abs()));
        for (i, (sx, sy)) in steps.enumerate() {
            let sd = (sx.displacement.iter().zip(&sy.displacement))
                .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
            let r = sd / scale;
            assert!(
                r <= tol,
                "body {} step {}: displacements differ by {r:e}",
                x.name,
                i + 1
            );
        }
    }
    let frictional = c.contact_rows.iter().any(|r| r.tangential_force != 0.0);
    if frictional {
        let method = d.report.steps[0].solver["method"].as_str().unwrap_or("");
        assert!(method.contains("direct_semismooth_newton"), "{method}");
    }
    (c, d)
}

/// The number of sticking and slipping points of the last step.
pub fn stick_slip(o: &RunOutput) -> (usize, usize) {
    let last = o.report.steps.last().expect("a step");
    (last.sticking, last.slipping)
}

/// Asserts that `text` runs on the condensed path and that the direct path
/// refuses it as bad input (not a failed solve) with a message containing
/// every one of `needles` and pointing at path = "condensed"; and that
/// path = "auto" picks the condensed path for it.
pub fn refused_on_direct(text: &str, needles: &[&str]) -> RunOutput {
    let c = converged_on(text, SolvePath::Condensed);
    let on = |path| RunOptions {
        method: None,
        path: Some(path),
    };
    let e = match try_run(text, on(SolvePath::Direct)) {
        Err(signorini_solver::SolveError::Input(m)) => m,
        Err(e) => panic!("refused as a failure, not as bad input: {e}"),
        Ok(_) => panic!("the direct path ran a scene it should refuse"),
    };
    for n in needles.iter().chain(&["condensed"]) {
        assert!(e.contains(n), "{n:?} not in {e:?}");
    }
    let auto = try_run(text, on(SolvePath::Auto)).unwrap_or_else(|e| panic!("auto: {e}"));
    assert_eq!(
        auto.report.path_choice.as_ref().map(|p| p.chosen.as_str()),
        Some("condensed")
    );
    c
}
