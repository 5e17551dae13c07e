//! `signorini docs validation`: every shipped example run at its shipped
//! size, and two Markdown tables of what it measured: the benchmarks with a
//! reference (DIR/README.md) and every example (DIR/examples.md). The tables
//! carry no timings, so that a fresh run can be compared with the committed
//! ones number by number (tests/docs.rs).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use signorini_comm::Local;
use signorini_report::Report;
use signorini_scene::Scene;
use signorini_solver::{RunOptions, SolveError};

use crate::{fail, tell};

/// The relative tolerance within which a fresh run must reproduce every
/// number of the tables (integers exactly); stated in the tables' headers
/// and applied by tests/docs.rs.
pub(crate) const RELATIVE_TOLERANCE: f64 = 1e-3;

/// Relative errors below this are round-off: the discretisation meets the
/// reference exactly (patch tests, resultants). Printed as such, since
/// their digits differ from one machine to another.
const ROUND_OFF: f64 = 1e-9;

/// A benchmark checked by equilibrium rather than by a `[reference]`: the
/// resultant contact force at the last step against the applied load
/// (component, exact value), read from the scene's own comments.
struct Resultant {
    scene: &'static str,
    source: &'static str,
    checks: &'static [(&'static str, usize, f64)],
}

/// SSNV128-like: a top pressure of 5 MPa on 40 mm (200 N/mm) and a side
/// pressure of 15 MPa on 10 mm (150 N/mm) held by the contact alone.
const RESULTANTS: &[Resultant] = &[Resultant {
    scene: "ssnv128.toml",
    source: "the applied loads; the setting of Code_Aster's SSNV128",
    checks: &[
        ("normal_resultant", 1, 200.0),
        ("tangential_resultant", 0, 150.0),
    ],
}];

/// The literature behind each `[reference] kind`.
fn source_of(kind: &str) -> &'static str {
    match kind {
        "hertz_cylinder" | "hertz_sphere" => {
            "Hertz (1882); Johnson, Contact Mechanics (1985), §4.2"
        }
        "flat_punch" => "Johnson, Contact Mechanics (1985), §2.8 (strip), §3.8 (circular)",
        "uniform_pressure" => "contact patch test: Taylor & Papadopoulos (1991)",
        "cattaneo_mindlin" => {
            "Cattaneo (1938), Mindlin (1949); Johnson, Contact Mechanics (1985), §7.2; \
             a reversed load: Mindlin & Deresiewicz (1953) by Masing's rules"
        }
        "sliding_block" => "Coulomb's law: every point slips, the reaction is μN",
        _ => "the scene's [reference]",
    }
}

/// Reference quantities that are inputs of the comparison (the computed
/// load), equal to their "exact" value by construction: not listed.
const INPUTS: &[&str] = &["load", "normal_load", "tangential_load_ratio"];

/// One compared quantity of one example.
struct Measured {
    name: String,
    computed: f64,
    exact: f64,
    relative_error: f64,
}

/// One example's run.
struct ExampleRun {
    file: String,
    report: Report,
    /// The reference kind, or "equilibrium".
    kind: Option<String>,
    source: &'static str,
    quantities: Vec<Measured>,
}

/// Runs every example of `examples` (*.toml, in name order) and writes
/// `out/README.md` and `out/examples.md`. Exit 1 (nothing written) when an
/// example cannot be read or run, or `out` cannot be written; 2 (tables
/// written) when one does not converge.
pub(crate) fn validation(examples: &Path, out: &Path) -> ExitCode {
    let scenes = match load_examples(examples) {
        Ok(s) => s,
        Err(e) => return fail(1, &e),
    };
    let total = scenes.len();
    let mut runs = Vec::with_capacity(total);
    for (i, (file, sc)) in scenes.into_iter().enumerate() {
        match run_example(file, &sc) {
            Ok(r) => {
                tell(&format!(
                    "[{}/{}] {}: {}, {} iterations",
                    i + 1,
                    total,
                    r.file,
                    match r.report.converged {
                        true => "converged",
                        false => "NOT converged",
                    },
                    iterations(&r.report)
                ));
                runs.push(r);
            }
            Err((file, SolveError::Input(m))) => return fail(1, &format!("{file}: {m}")),
            Err((file, e)) => return fail(3, &format!("{file}: {e}")),
        }
    }
    let written = std::fs::create_dir_all(out)
        .and_then(|()| std::fs::write(out.join("README.md"), validation_markdown(&runs)))
        .and_then(|()| std::fs::write(out.join("examples.md"), examples_markdown(&runs)));
    if let Err(e) = written {
        return fail(
            1,
            &format!(
                "--out {}: cannot write the tables there ({e}); give a directory that can be created and written",
                out.display()
            ),
        );
    }
    crate::say(&format!(
        "{} examples run; README.md and examples.md in {}\n",
        runs.len(),
        out.display()
    ));
    if runs.iter().all(|r| r.report.converged) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    }
}

/// Every *.toml scene of `dir` in name order, read and validated before
/// anything runs: an error names the directory or the scene.
fn load_examples(dir: &Path) -> Result<Vec<(String, Scene)>, String> {
    let shown = dir.display();
    let entries = std::fs::read_dir(dir).map_err(|e| {
        format!("--examples {shown}: cannot read it as a directory ({e}); give the directory of the scenes, the repository's examples")
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "toml"))
        .collect();
    if files.is_empty() {
        return Err(format!(
            "--examples {shown}: no *.toml scene in it; give the directory of the scenes, the repository's examples"
        ));
    }
    files.sort();
    (files.iter())
        .map(|path| {
            let file = path.file_name().unwrap_or_default().to_string_lossy();
            signorini_scene::load(path)
                .map(|sc| (file.to_string(), sc))
                .map_err(|e| format!("{}: {e}", path.display()))
        })
        .collect()
}

/// Runs one example in this process as `signorini run` would (its own
/// method and path), keeping its report and compared quantities; an error
/// comes with the example's name.
fn run_example(file: String, sc: &Scene) -> Result<ExampleRun, (String, SolveError)> {
    let out = match signorini_solver::run(sc, &file, &RunOptions::default(), &Local) {
        Ok(Some(out)) => out,
        Ok(None) => return Err((file, SolveError::Internal("no output in process".into()))),
        Err(e) => return Err((file, e)),
    };
    let report = out.report;
    let (kind, source, quantities) = match (&report.reference, resultant_checks(&file)) {
        (Some(rf), _) => (
            Some(rf.kind.clone()),
            source_of(&rf.kind),
            (rf.quantities.iter())
                .filter(|(k, _)| !INPUTS.contains(&k.as_str()))
                .map(|(k, q)| Measured {
                    name: k.clone(),
                    computed: q.computed,
                    exact: q.exact,
                    relative_error: q.relative_error,
                })
                .collect(),
        ),
        (None, Some(r)) => (
            Some("equilibrium".to_string()),
            r.source,
            resultants(&report, r),
        ),
        (None, None) => (None, "", Vec::new()),
    };
    Ok(ExampleRun {
        file,
        report,
        kind,
        source,
        quantities,
    })
}

fn resultant_checks(file: &str) -> Option<&'static Resultant> {
    RESULTANTS.iter().find(|r| r.scene == file)
}

/// The resultant contact force at the last step against the applied load.
fn resultants(report: &Report, r: &Resultant) -> Vec<Measured> {
    (r.checks.iter())
        .map(|&(name, component, exact)| {
            let computed = report
                .contact_force
                .get(component)
                .copied()
                .unwrap_or(f64::NAN);
            Measured {
                name: name.to_string(),
                computed,
                exact,
                relative_error: ((computed - exact) / exact).abs(),
            }
        })
        .collect()
}

fn iterations(report: &Report) -> usize {
    report.steps.iter().map(|s| s.iterations).sum()
}

/// A value with five significant digits; a decimal point or an exponent
/// always (so that it never reads as an integer).
pub(crate) fn number(x: f64) -> String {
    let scientific = format!("{x:.4e}");
    // the decade of the rounded value (0.99999999 prints as 1.0000)
    let a = scientific.parse::<f64>().unwrap_or(x).abs();
    if a == 0.0 {
        "0.0".to_string()
    } else if (1e-3..1e4).contains(&a) {
        let decimals = (4 - a.log10().floor() as i32).max(1) as usize;
        format!("{x:.decimals$}")
    } else {
        scientific
    }
}

/// A relative error, four significant digits, or round-off.
fn error(x: f64) -> String {
    if x < ROUND_OFF {
        format!("< {ROUND_OFF:e} (round-off)")
    } else {
        format!("{x:.3e}")
    }
}

/// The largest relative error of an example over its compared quantities,
/// with its name.
fn worst(run: &ExampleRun) -> String {
    let worst =
        (run.quantities.iter()).max_by(|a, b| a.relative_error.total_cmp(&b.relative_error));
    match worst {
        Some(q) if q.relative_error < ROUND_OFF => error(q.relative_error),
        Some(q) => format!("{} ({})", error(q.relative_error), q.name),
        None => "— (no closed form)".to_string(),
    }
}

fn link(file: &str) -> String {
    format!("[{file}](../../examples/{file})")
}

fn row(cells: &[String]) -> String {
    format!("| {} |\n", cells.join(" | "))
}

fn header(cells: &[&str]) -> String {
    row(&cells.iter().map(|c| c.to_string()).collect::<Vec<_>>())
        + &row(&cells.iter().map(|_| "---".to_string()).collect::<Vec<_>>())
}

const REGENERATE: &str = "signorini docs validation --examples examples --out docs/validation";

/// The header both tables share: how they are made and checked.
fn preamble(title: &str, what: &str) -> String {
    format!(
        "# {title}\n\n\
         <!-- Generated: do not edit. Regenerate from the repository's root with\n     \
         cargo run --release -- docs validation --examples examples --out docs/validation -->\n\n\
         {what}\n\n\
         Every number comes from the current build (`{REGENERATE}`, which \
         runs every `examples/*.toml` at its shipped size with its own method and \
         path, in one process). `cargo test --release --test docs` runs the same \
         command and fails when a number of a fresh run and of this file differ by \
         more than a relative {RELATIVE_TOLERANCE:e} (integers exactly, every other \
         cell as text); relative errors below {ROUND_OFF:e} are round-off and shown \
         as such. No timings are listed (`signorini bench` measures those).\n\n\
         The generated documents and the commands that regenerate them, from the \
         repository's root, after a change that moves their numbers:\n\n\
         ```sh\n\
         cargo run --release -- docs validation --examples examples --out docs/validation  # README.md, examples.md\n\
         cargo run --release -- docs cli --out docs/reference/cli.md  # the command-line reference\n\
         cargo test --release --test docs  # checks both, and runs docs/tutorial/*.md\n\
         ```\n\n"
    )
}

/// DIR/README.md: the benchmarks (one row per example with a reference),
/// then one row per compared quantity.
fn validation_markdown(runs: &[ExampleRun]) -> String {
    let mut text = preamble(
        "Validation",
        "Every shipped example with a closed-form reference, its source, the \
         quantities compared and their measured relative error. The report of \
         `signorini run` holds the same numbers under `reference` (report.json), \
         with notes on what each reference assumes (e.g. a half-space for Hertz). \
         The largest error of each example is in [examples.md](examples.md). \
         Scenes a new user writes (Gmsh assemblies, ties, point loads, units, \
         refusals), run on both paths and under `mpirun`, with their exit codes \
         and checks, are in [sweep.md](sweep.md) (written by hand, not generated).",
    );
    let checked: Vec<&ExampleRun> = runs.iter().filter(|r| r.kind.is_some()).collect();
    text += "## Benchmarks\n\n";
    text += &header(&["benchmark", "scene", "reference", "source"]);
    for r in &checked {
        text += &row(&[
            r.report.title.clone(),
            link(&r.file),
            format!("`{}`", r.kind.as_deref().unwrap_or_default()),
            r.source.to_string(),
        ]);
    }
    text += "\n## Measured\n\n";
    text += QUANTITIES;
    text += &header(&["scene", "quantity", "computed", "exact", "relative error"]);
    for r in &checked {
        for q in &r.quantities {
            text += &row(&[
                link(&r.file),
                format!("`{}`", q.name),
                number(q.computed),
                number(q.exact),
                error(q.relative_error),
            ]);
        }
    }
    text
}

/// What the quantities of the references are.
const QUANTITIES: &str = "Quantities: `p0` the peak pressure; `a` the contact \
    half-width from the pressure's moment, `a_last_node` from the last node with a \
    positive pressure; `profile_l2` the relative L2 deviation of the pressure \
    profile from the reference's (exact 0); `pressure` the nodal pressure farthest \
    from the uniform one, `resultant` the total contact force; `p_centre` and \
    `p_interior_worst` the punch pressure at the centre and farthest from the \
    reference within 0.8 b, `half_width` the last point with a positive force; \
    `stick_half_width` and `shear_profile_l2` the Cattaneo–Mindlin stick zone and \
    the deviation of the shear traction; `tangential_reaction` the friction force of \
    a sliding body; `normal_resultant` and `tangential_resultant` the resultant \
    contact force against the applied loads.\n\n";

/// DIR/examples.md: one row per example.
fn examples_markdown(runs: &[ExampleRun]) -> String {
    let mut text = preamble(
        "Examples",
        "Every shipped example: what it solves (its title), its size, the contact \
         iterations summed over its load steps, and its largest relative error \
         against its reference (the quantity named; the rows of \
         [README.md](README.md) give them all).",
    );
    text += &header(&[
        "scene",
        "what it solves",
        "method, path",
        "DOFs",
        "Γ DOFs",
        "contact points",
        "steps",
        "iterations",
        "converged",
        "largest error (quantity)",
    ]);
    for r in runs {
        let rep = &r.report;
        text += &row(&[
            link(&r.file),
            rep.title.clone(),
            format!("{}, {}", rep.method, rep.path),
            rep.dofs.to_string(),
            rep.interface_dofs.to_string(),
            rep.contact_points.to_string(),
            rep.steps.len().to_string(),
            iterations(rep).to_string(),
            if rep.converged { "yes" } else { "no" }.to_string(),
            worst(r),
        ]);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_never_read_as_integers_and_keep_five_digits() {
        assert_eq!(number(0.053099454), "0.053099");
        assert_eq!(number(200.00000000000387), "200.00");
        assert_eq!(number(9999.99), "1.0000e4");
        assert_eq!(number(0.9999999999999378), "1.0000");
        assert_eq!(number(999.99), "999.99");
        assert_eq!(number(12345.6), "1.2346e4");
        assert_eq!(number(-1.7e-19), "-1.7000e-19");
        assert_eq!(number(0.0), "0.0");
        assert_eq!(error(2.2160141e-3), "2.216e-3");
        assert_eq!(error(6.2e-14), "< 1e-9 (round-off)");
    }
}
