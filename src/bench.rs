//! `signorini bench`: scenes over levels, subdomains and paths; the stiff
//! and root suites.

use std::path::{Path, PathBuf};

use signorini_scene::{Method, SolvePath};

use crate::fail;
use signorini_solver::{RunEnvironment, SolveError};
use std::process::ExitCode;

pub(crate) fn bench(
    scenes: &[PathBuf],
    levels: &[f64],
    subdomains: &[usize],
    methods: &[Method],
    paths: &[SolvePath],
    env: &RunEnvironment,
    out: &Path,
) -> ExitCode {
    if levels.iter().any(|l| !(*l > 0.0 && l.is_finite())) {
        return fail(1, "--levels: refinement factors must be positive numbers");
    }
    if subdomains.contains(&0) {
        return fail(1, "--subdomains: counts must be at least 1");
    }
    let mut cases = Vec::new();
    for p in scenes {
        match signorini_scene::load(p) {
            Ok(scene) => cases.push(signorini_suite::bench::BenchCase {
                name: p
                    .file_name()
                    .map(|s| s.to_string_lossy().to_string())
                    .unwrap_or_default(),
                scene,
            }),
            Err(e) => return fail(1, &e.to_string()),
        }
    }
    // A progress bar on a terminal; nothing when stderr is not one.
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new(0)
    } else {
        indicatif::ProgressBar::hidden()
    };
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed_precise} {msg}")
    {
        bar.set_style(style);
    }
    let rows = signorini_suite::bench::bench(
        &cases,
        levels,
        subdomains,
        methods,
        paths,
        env,
        |done, total, label| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            bar.set_message(label.to_string());
        },
    );
    bar.finish_and_clear();
    let rows = match rows {
        Ok(r) => r,
        Err(SolveError::Input(m)) => return fail(1, &m),
        Err(e) => return fail(3, &e.to_string()),
    };
    if let Err(e) = std::fs::create_dir_all(out)
        .and_then(|_| signorini_suite::bench::write_csv(&out.join("bench.csv"), &rows))
    {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    let plots = signorini_suite::bench::write_plots(out, &rows);
    crate::say(&signorini_suite::bench::markdown(&rows));
    match plots {
        Ok(p) => crate::say(&format!(
            "bench.csv and {} plot(s) in {}\n",
            p.len(),
            out.display()
        )),
        Err(e) => crate::say(&format!("bench.csv in {} (no plot: {e})\n", out.display())),
    }
    if rows.iter().all(|r| r.converged) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    }
}

/// `signorini bench --plot CSV...`: the plots of the rows of bench.csv
/// files, together, into `out`.
pub(crate) fn plot(csvs: &[PathBuf], out: &Path) -> ExitCode {
    let mut rows = Vec::new();
    for p in csvs {
        let read = signorini_problems::regular_file(p)
            .and_then(|()| std::fs::read_to_string(p).map_err(|e| e.to_string()))
            .and_then(|text| signorini_suite::bench::read_csv(&text));
        match read {
            Ok(r) => rows.extend(r),
            Err(e) => return fail(1, &format!("--plot {}: {e}", p.display())),
        }
    }
    if rows.is_empty() {
        return fail(1, "--plot: the files hold no rows");
    }
    if let Err(e) = std::fs::create_dir_all(out) {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    match signorini_suite::bench::write_plots(out, &rows) {
        Ok(p) => {
            crate::say(&format!(
                "{} plot(s) of {} rows in {}\n",
                p.len(),
                rows.len(),
                out.display()
            ));
            ExitCode::SUCCESS
        }
        Err(e) => fail(3, &format!("cannot draw the plots: {e}")),
    }
}

/// `signorini bench --suite root`: every root method on the Delassus
/// problems of an elastic layer and of an elastic half-space (the
/// `families` named, or all), one line per run on stderr.
pub(crate) fn root_suite(
    quick: bool,
    export: bool,
    (sizes, families): (&[usize], &[String]),
    out: &Path,
) -> ExitCode {
    use signorini_suite::rootbench::{problem::Family, run};
    let mut chosen = Vec::new();
    for name in families {
        match Family::by_name(name) {
            Some(f) => chosen.push(f),
            None => {
                let known: Vec<&str> = Family::ALL.iter().map(|f| f.name()).collect();
                return fail(
                    1,
                    &format!(
                        "--families: no family {name:?}; known: {}",
                        known.join(", ")
                    ),
                );
            }
        }
    }
    if chosen.is_empty() {
        chosen = Family::ALL.to_vec();
    }
    if let Some(m) = sizes.iter().find(|&&m| !(2..=8192).contains(&m)) {
        return fail(
            1,
            &format!("--sizes: {m} contact points; each size must be in 2..=8192 (W is dense)"),
        );
    }
    let problems = out.join("problems");
    let made = std::fs::create_dir_all(if export { &problems } else { out });
    if let Err(e) = made {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    let o = run::SuiteOptions {
        sizes: match (quick, sizes.is_empty()) {
            (_, false) => sizes.to_vec(),
            (true, true) => vec![49, 196],
            (false, true) => vec![49, 196, 784, 2025, 8000],
        },
        families: chosen,
        tolerance: 1e-10,
        max_iterations: 5000,
        time_budget: 20.0,
        repeat: if quick { 1 } else { 3 },
    };
    let rows = run::run_suite(&o, export.then_some(problems.as_path()), |r| {
        eprintln!(
            "{} {}: {} in {:.4} s, residual {:.1e}, difference {:.1e}",
            r.problem,
            r.method,
            if r.converged {
                "converged"
            } else {
                "NOT converged"
            },
            r.time_s,
            r.residual,
            r.difference
        )
    });
    let rows = match rows {
        Ok(rows) => rows,
        Err(e) => return fail(3, &e),
    };
    let table = run::markdown(&rows);
    let written = std::fs::write(out.join("root.csv"), run::csv(&rows))
        .and_then(|_| std::fs::write(out.join("root.md"), &table))
        .map_err(|e| e.to_string())
        .and_then(|_| run::error_vs_time_svg(&out.join("root_error_vs_time.svg"), &rows));
    if let Err(e) = written {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    crate::say(&table);
    ExitCode::SUCCESS
}

/// `signorini bench --suite stiff`: every case of the stiff suite in this
/// process, a line on stderr as each ends, the table on stdout,
/// DIR/stiff.csv, DIR/stiff.md and each case's scene in DIR/stiff/; exit 1
/// naming the cases that fail their expectation.
pub(crate) fn stiff_suite(quick: bool, out: &Path) -> ExitCode {
    use signorini_suite::stiff;
    // Every case's scene beside the table, so that any case can be rerun
    // alone with `signorini run DIR/stiff/<case>.toml`.
    let cases = stiff::cases(quick);
    let scenes = out.join("stiff");
    if let Err(e) = std::fs::create_dir_all(&scenes).and_then(|_| {
        cases.iter().try_for_each(|c| {
            std::fs::write(
                scenes.join(format!("{}.toml", c.name)),
                format!(
                    "# signorini bench --suite stiff{}: case {} ({}, {})\n{}",
                    if quick { " --quick" } else { "" },
                    c.name,
                    c.family,
                    c.parameter,
                    c.text
                ),
            )
        })
    }) {
        return fail(3, &format!("cannot write {}: {e}", scenes.display()));
    }
    let n = cases.len();
    let mut rows = Vec::with_capacity(n);
    for (i, c) in cases.iter().enumerate() {
        let r = stiff::run_case(c);
        eprintln!(
            "[{}/{n}] {} ({}): {} in {:.3} s: {}",
            i + 1,
            r.case,
            r.parameter,
            if r.exit_code == 0 {
                "solved".to_string()
            } else {
                format!("exit {}", r.exit_code)
            },
            r.time_s,
            stiff::verdict_text(&r.verdict)
        );
        rows.push(r);
    }
    let table = stiff::markdown(&rows);
    crate::say(&format!("{table}\n"));
    if let Err(e) = std::fs::create_dir_all(out)
        .and_then(|_| stiff::write_csv(&out.join("stiff.csv"), &rows))
        .and_then(|_| std::fs::write(out.join("stiff.md"), &table))
    {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    let failed: Vec<&stiff::StiffRow> = rows.iter().filter(|r| r.failed()).collect();
    crate::say(&format!(
        "{} cases: {} passed, {} failed; stiff.csv, stiff.md and the scenes (stiff/<case>.toml) in {}\n",
        rows.len(),
        rows.iter().filter(|r| r.passed()).count(),
        failed.len(),
        out.display()
    ));
    if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        for r in &failed {
            eprintln!("error: {}: {}", r.case, stiff::verdict_text(&r.verdict));
        }
        ExitCode::from(1)
    }
}
