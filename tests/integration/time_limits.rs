//! Every contact method stops on its wall-clock budget: `signorini local
//! --time-limit` ends the solve of an LCP by any `--method` after its first
//! iteration when the budget is already spent, with exit 2, the time-limit
//! reason and the residual reached.

use crate::common;

use common::{fresh_dir, run_limited, BIN};
use signorini_scene::Method;
use std::path::Path;
use std::process::{Command, Output};
use std::time::Duration;

/// An LCP of 40 points that no method solves in one iteration: W the
/// exponential kernel e^(−|i−j|) (positive definite) plus the identity; q
/// deep, middle and shallow penetrations in turn, so that neither the
/// deepest points (the status method's start) nor all that penetrate (the
/// penalty method's) are the contact set.
fn problem_file() -> std::path::PathBuf {
    let m = 40;
    let w: Vec<Vec<f64>> = (0..m)
        .map(|i: usize| {
            (0..m)
                .map(|j: usize| (-(i.abs_diff(j) as f64)).exp() + if i == j { 1.0 } else { 0.0 })
                .collect()
        })
        .collect();
    let q: Vec<f64> = (0..m).map(|i| [-1.0, -0.45, -0.05][i % 3]).collect();
    let path = fresh_dir("time_limits", "lcp").join("lcp40.json");
    let text = serde_json::json!({ "W": w, "q": q }).to_string();
    std::fs::write(&path, text).unwrap();
    path
}

fn local(path: &Path, method: Method, extra: &[&str]) -> (Output, serde_json::Value) {
    let mut cmd = Command::new(BIN);
    cmd.arg("local")
        .arg(path)
        .args(["--method", method.as_str()]);
    cmd.args(extra);
    let (out, _) = run_limited(cmd, Duration::from_secs(60));
    let json = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
    (out, json)
}

/// Without a limit every method converges in more than one iteration;
/// with `--time-limit 1e-9` every one stops after its first, exit 2, not
/// converged, with the reason the status method gives and a finite residual
/// above the tolerance.
#[test]
fn a_spent_time_limit_stops_every_method_with_exit_2() {
    let path = problem_file();
    for method in Method::ALL {
        let (out, free) = local(&path, method, &[]);
        assert_eq!(out.status.code(), Some(0), "{method:?}: {free}");
        assert!(
            free["iterations"].as_u64().unwrap() > 1,
            "{method:?}: {free}"
        );
        let (out, v) = local(&path, method, &["--time-limit", "1e-9"]);
        assert_eq!(out.status.code(), Some(2), "{method:?}: {v}");
        assert_eq!(v["converged"], false, "{method:?}: {v}");
        assert_eq!(v["iterations"], 1, "{method:?}: {v}");
        let reason = v["stopping_reason"].as_str().unwrap();
        assert!(
            reason.starts_with("time limit reached after 1 iterations"),
            "{method:?}: {reason}"
        );
        let residual = v["residual"].as_f64().unwrap();
        assert!(residual.is_finite() && residual > 1e-10, "{method:?}: {v}");
    }
}

/// The scene's `solver.time_limit` bounds the condensed path's contact
/// solve by every method: with a budget already spent, each stops not
/// converged and the report says it was the time limit; with the default
/// budget the same scene converges.
#[test]
fn the_scenes_time_limit_stops_every_method_of_the_condensed_path() {
    let hertz = common::example("hertz2d.toml").replace(
        "path = \"condensed\"",
        "path = \"condensed\"\nmax_iterations = 100000",
    );
    let spent = hertz.replace(
        "path = \"condensed\"",
        "path = \"condensed\"\ntime_limit = 1e-9",
    );
    for method in Method::ALL {
        let out = common::try_run(&hertz, common::with_method(method)).unwrap();
        assert!(out.report.converged, "{method:?}: {:?}", out.report.failure);
        let out = common::try_run(&spent, common::with_method(method)).unwrap();
        assert!(!out.report.converged, "{method:?}");
        let failure = out.report.failure.as_deref().unwrap_or("");
        assert!(failure.contains("time limit"), "{method:?}: {failure}");
    }
}

/// The direct path's frictionless status solve stops on `solver.time_limit`
/// too: the Hertz cylinder on the direct path takes more than one status
/// iteration; with a budget already spent it stops after its first, not
/// converged, the report naming the time limit, and `signorini run` exits
/// 2 (not 0, not 1).
#[test]
fn the_scenes_time_limit_stops_the_direct_paths_status_solve() {
    let hertz = common::example("hertz2d.toml").replace(
        "path = \"condensed\"",
        "path = \"direct\"\nmax_iterations = 100000",
    );
    let free = common::try_run(&hertz, common::with_method(Method::Status)).unwrap();
    assert!(free.report.converged, "{:?}", free.report.failure);
    let iterations: usize = free.report.steps.iter().map(|s| s.iterations).sum();
    assert!(iterations > 1, "{iterations}");
    let spent = hertz.replace(
        "max_iterations = 100000",
        "max_iterations = 100000\ntime_limit = 1e-9",
    );
    let out = common::try_run(&spent, common::with_method(Method::Status)).unwrap();
    assert!(!out.report.converged);
    assert_eq!(out.report.steps[0].iterations, 1);
    let failure = out.report.failure.as_deref().unwrap_or("");
    assert!(failure.contains("time limit"), "{failure}");
    let dir = fresh_dir("time_limits", "direct_status");
    let scene = dir.join("hertz_direct.toml");
    std::fs::write(&scene, &spent).unwrap();
    let run = common::cli_run(&scene, dir.join("out"));
    let err = common::stderr_of_exit(&run, 2);
    assert!(err.contains("time limit"), "{err}");
}
