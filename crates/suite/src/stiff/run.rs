//! Running a case in process and judging it.

use std::time::Instant;

use signorini_comm::Local;
use signorini_solver::{run, RunOptions, RunOutput, SolveError};

use crate::stiff::{cases, nan, Case, Expectation, Reference, RowError, StiffRow, Verdict};

/// Whether any number of the run is NaN or infinite: every f64 of the report
/// as it serialises (a serializer that looks at each number, since
/// serde_json would write a non-finite one as `null`, like an absent
/// optional entry), the JSON values the report embeds (the solver accounts,
/// made by `serde_json::to_value` from structs without optional entries: a
/// `null` there is a number that was not finite), the contact rows and the
/// fields of every body at every step.
pub fn has_nan(o: &RunOutput) -> bool {
    let mut finder = nan::Finder::default();
    let report = serde::Serialize::serialize(&o.report, &mut finder).is_err() || finder.found;
    let bad = |x: f64| !x.is_finite();
    let rows = o.contact_rows.iter().any(|r| {
        [
            r.gap,
            r.normal_force,
            r.tangential_force,
            r.slip,
            r.tangential_force_2,
            r.slip_2,
            r.pressure,
        ]
        .into_iter()
        .chain(r.x)
        .any(bad)
    });
    let fields = o.bodies.iter().any(|b| {
        b.history.iter().any(|s| {
            s.displacement.iter().copied().any(bad)
                || s.stress.iter().flatten().copied().any(bad)
                || s.von_mises.iter().copied().any(bad)
        })
    });
    report || rows || fields
}

/// Runs one case in process (nothing written) and judges it.
pub fn run_case(case: &Case) -> StiffRow {
    let t = Instant::now();
    let mut row = empty_row(case);
    let result = execute(case);
    row.time_s = t.elapsed().as_secs_f64();
    let message = record(&mut row, &result);
    let references = case.expect.references(row.exit_code);
    let missing = match &result {
        Ok(o) => measure(&mut row, references, o),
        Err(_) => Vec::new(),
    };
    row.verdict = judge(case, &row, &message, &missing);
    row
}

/// The row of a case before it runs.
fn empty_row(case: &Case) -> StiffRow {
    StiffRow {
        case: case.name.clone(),
        family: case.family.to_string(),
        parameter: case.parameter.clone(),
        value: case.value,
        method: case
            .scene
            .as_ref()
            .map(|s| s.solver.method.as_str().to_string())
            .unwrap_or_default(),
        exit_code: 0,
        outcome: String::new(),
        converged: false,
        certificate: f64::NAN,
        tolerance: f64::NAN,
        max_error: 0.0,
        errors: vec![],
        iterations: 0,
        contact_points: 0,
        active: 0,
        dofs: 0,
        time_s: 0.0,
        any_nan: false,
        force_deviation: None,
        verdict: Verdict::Passed,
    }
}

/// Runs the case's scene: its output, or (exit code, message).
fn execute(case: &Case) -> Result<RunOutput, (u8, String)> {
    match &case.scene {
        Err(m) => Err((1, m.clone())),
        Ok(sc) => match run(sc, &case.name, &RunOptions::default(), &Local) {
            Ok(Some(o)) => Ok(o),
            Ok(None) => Err((3, "no output in process".into())),
            Err(SolveError::Input(m)) => Err((1, m)),
            Err(e @ SolveError::Internal(_)) => Err((3, e.to_string())),
        },
    }
}

/// Fills the row from the run's outcome; the stop message ("" if solved).
fn record(row: &mut StiffRow, result: &Result<RunOutput, (u8, String)>) -> String {
    match result {
        Err((code, m)) => {
            row.exit_code = *code;
            row.outcome = format!("stopped: {m}");
            m.clone()
        }
        Ok(o) => {
            let r = &o.report;
            row.converged = r.converged;
            row.certificate = r.certificate.max();
            row.tolerance = r.certificate.tolerance;
            row.iterations = r.steps.iter().map(|s| s.iterations).sum();
            row.contact_points = r.contact_points;
            row.active = r.steps.last().map_or(0, |s| s.active);
            row.dofs = r.dofs;
            row.method = r.method.clone();
            row.any_nan = has_nan(o);
            row.force_deviation = r
                .steps
                .last()
                .and_then(|s| s.regularisation.as_ref())
                .map(|g| g.force_deviation);
            if r.converged {
                row.exit_code = 0;
                row.outcome = "solved".into();
                String::new()
            } else {
                row.exit_code = 2;
                let f = r.failure.clone().unwrap_or_else(|| "not converged".into());
                row.outcome = format!("stopped: {f}");
                f
            }
        }
    }
}

/// Reads every reference on the run into the row's errors; the names of
/// those the run does not have.
fn measure(row: &mut StiffRow, references: &[Reference], o: &RunOutput) -> Vec<String> {
    let mut missing = Vec::new();
    for rf in references {
        match rf.measure.read(o) {
            Some((computed, exact)) => {
                let scale = rf.scale.unwrap_or(exact.abs());
                let error = if scale > 0.0 {
                    (computed - exact).abs() / scale
                } else {
                    (computed - exact).abs()
                };
                let error = if error.is_nan() { f64::INFINITY } else { error };
                row.max_error = row.max_error.max(error);
                row.errors.push(RowError {
                    name: rf.name.clone(),
                    computed,
                    exact,
                    error,
                    tolerance: rf.tolerance,
                });
            }
            None => missing.push(rf.name.clone()),
        }
    }
    missing
}

/// The verdict: NaN, false convergence, the expectation, the references.
fn judge(case: &Case, row: &StiffRow, message: &str, missing: &[String]) -> Verdict {
    let over: Vec<String> = row
        .errors
        .iter()
        .filter(|e| e.error > e.tolerance)
        .map(|e| format!("{} error {:.2e} > {:.1e}", e.name, e.error, e.tolerance))
        .chain(missing.iter().map(|m| format!("{m} not measured")))
        .collect();
    let stop_matches = |code: u8, m: &str| row.exit_code == code && message.contains(m);
    let expectation = match &case.expect {
        Expectation::Solves(_) if row.exit_code != 0 => Err(format!(
            "expected to solve, exit {}: {message}",
            row.exit_code
        )),
        Expectation::Stops {
            code, message: m, ..
        } if !stop_matches(*code, m) => Err(format!(
            "expected to stop with exit {code} (\"{m}\"), got exit {}{}",
            row.exit_code,
            if message.is_empty() {
                String::new()
            } else {
                format!(": {message}")
            }
        )),
        Expectation::Either {
            code, message: m, ..
        } if row.exit_code != 0 && !stop_matches(*code, m) => Err(format!(
            "expected to solve or to stop with exit {code} (\"{m}\"), got exit {}: {message}",
            row.exit_code
        )),
        _ if !over.is_empty() => Err(over.join("; ")),
        _ => Ok(()),
    };
    let false_convergence =
        row.converged && (row.certificate.is_nan() || row.certificate > row.tolerance);
    if row.any_nan {
        Verdict::Failed("NaN or infinity in the report or the fields".into())
    } else if false_convergence {
        Verdict::Failed(format!(
            "converged with a certificate {:.2e} above its tolerance {:.1e}",
            row.certificate, row.tolerance
        ))
    } else {
        match expectation {
            Ok(()) => Verdict::Passed,
            Err(why) => Verdict::Failed(why),
        }
    }
}

/// Runs every case; `progress(i, n, row)` after each.
pub fn run_suite(quick: bool, mut progress: impl FnMut(usize, usize, &StiffRow)) -> Vec<StiffRow> {
    let all = cases(quick);
    let n = all.len();
    let mut rows = Vec::with_capacity(n);
    for (i, c) in all.iter().enumerate() {
        let row = run_case(c);
        progress(i + 1, n, &row);
        rows.push(row);
    }
    rows
}
