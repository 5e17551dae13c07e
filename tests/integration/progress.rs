//! `signorini run`'s progress: on a terminal, the stages
//! with their subdomains and steps on stderr; nothing with `--quiet` or when
//! stderr is not a terminal; and the output files the same either way.
//!
//! The terminal is a pseudo-terminal from util-linux `script` (package
//! bsdutils, essential on Debian; ci/setup.sh checks it): `script -qec CMD
//! /dev/null` runs CMD with its stdin, stdout and stderr on a pty and copies
//! what CMD writes to its own stdout.

use crate::common;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use common::{example_path, fresh_dir, BIN};

/// The stage lines of a run of examples/cattaneo.toml (two subdomains, two
/// load steps): the subdomains and the steps are facts of the scene.
const STAGE_LINES: [&str; 4] = [
    "meshing and contact search: ",
    "condensing 2 subdomain(s): ",
    "contact solve, 2 step(s) (last: status iteration",
    "writing the output: ",
];

fn have_script() -> bool {
    common::have_program("script", "ci/setup.sh must install bsdutils (util-linux)")
}

/// One thread for faer (through rayon), so that two runs give the same
/// bits whatever the machine's cores.
fn command(program: &str) -> Command {
    let mut c = Command::new(program);
    c.env("RAYON_NUM_THREADS", "1");
    c
}

/// `signorini run cattaneo.toml --out DIR [extra]` on a pseudo-terminal:
/// everything it wrote to the terminal (stdout and stderr).
fn run_on_terminal(out: &Path, extra: &str) -> String {
    on_terminal("", out, extra)
}

/// `LAUNCHER signorini run cattaneo.toml --out DIR [extra]` on a
/// pseudo-terminal.
fn on_terminal(launcher: &str, out: &Path, extra: &str) -> String {
    let cmd = format!(
        "{launcher} {BIN} run {} --out {} {extra}",
        example_path("cattaneo.toml"),
        out.display()
    );
    let mut script = command("script");
    common::mpi_env(&mut script);
    let o = script.args(["-qec", &cmd, "/dev/null"]).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{text}");
    text
}

/// The output files of a run by name, report.json without its times and
/// memory (every field ending in `_s`, every field of `timings_s`, peak RSS).
fn outputs(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn scrub(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(m) => {
                m.retain(|k, _| !k.ends_with("_s") && !k.contains("rss"));
                m.values_mut().for_each(scrub);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(scrub),
            _ => {}
        }
    }
    let mut files = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let mut bytes = std::fs::read(&path).unwrap();
        if name == "report.json" {
            let mut report: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
            assert!(report["timings_s"]["total"].as_f64().unwrap() > 0.0);
            scrub(&mut report);
            bytes = serde_json::to_vec_pretty(&report).unwrap();
        }
        files.insert(name, bytes);
    }
    files
}

#[test]
fn run_shows_progress_on_a_terminal_only_and_never_in_its_output_files() {
    if !have_script() {
        eprintln!("skipped: no `script` (util-linux) for a pseudo-terminal");
        return;
    }
    let dir = fresh_dir("progress", "terminal");
    let (shown, quiet, piped) = (dir.join("shown"), dir.join("quiet"), dir.join("piped"));

    // On a terminal: every stage line, the summary after them.
    let text = run_on_terminal(&shown, "");
    for line in STAGE_LINES {
        assert!(text.contains(line), "no {line:?} in:\n{text}");
    }
    let summary = "cattaneo.toml: 42281 DOFs";
    assert!(text.find(STAGE_LINES[3]) < text.find(summary), "{text}");

    // --quiet on a terminal: the summary alone.
    let text = run_on_terminal(&quiet, "--quiet");
    assert!(text.contains(summary), "{text}");
    for line in STAGE_LINES {
        assert!(!text.contains(line), "{line:?} despite --quiet:\n{text}");
    }
    assert!(!text.contains("condensing"), "{text}");

    // stderr piped: nothing on it (no stage, no escape sequence), the
    // summary on stdout.
    let o = command(BIN)
        .args(["run", &example_path("cattaneo.toml"), "--out"])
        .arg(&piped)
        .output()
        .unwrap();
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert!(o.status.success(), "{err}");
    assert!(out.contains(summary), "{out}");
    assert!(err.is_empty(), "stderr not a terminal, yet:\n{err}");

    // The files: the same names and bytes (times and memory aside).
    let files = outputs(&shown);
    for name in ["report.json", "contact.csv", "steps.csv", "fields.pvd"] {
        assert!(files.contains_key(name), "no {name}");
    }
    for other in [&quiet, &piped] {
        let o = outputs(other);
        assert_eq!(
            files.keys().collect::<Vec<_>>(),
            o.keys().collect::<Vec<_>>()
        );
        for (name, bytes) in &files {
            assert!(o[name] == *bytes, "{name} differs in {}", other.display());
        }
    }
}

/// Under `mpirun -n 2` on a terminal the root shows the stages, with every
/// rank's subdomains once they arrive; with the launcher's stderr piped,
/// nothing unless `--progress` asks for it.
#[cfg(feature = "mpi")]
#[test]
fn mpirun_shows_progress_on_the_roots_terminal_with_every_ranks_subdomains() {
    if !have_script() || !common::have_mpirun() {
        eprintln!("skipped: no `script` or no `mpirun`");
        return;
    }
    let dir = fresh_dir("progress", "mpirun");
    let text = on_terminal("mpirun -n 2", &dir.join("shown"), "");
    let condensed = "condensing 2 subdomain(s) on 2 ranks (rank 0: 1, rank 1: 1): ";
    for line in [condensed, STAGE_LINES[2], STAGE_LINES[3]] {
        assert!(text.contains(line), "no {line:?} in:\n{text}");
    }
    // Once: the root alone prints.
    assert_eq!(text.matches(STAGE_LINES[3]).count(), 1, "{text}");

    let piped = |extra: &[&str]| {
        let mut c = command("mpirun");
        common::mpi_env(&mut c)
            .args([
                "-n",
                "2",
                BIN,
                "run",
                &example_path("cattaneo.toml"),
                "--out",
            ])
            .arg(dir.join("piped"))
            .args(extra);
        let o = c.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{err}");
        err
    };
    let err = piped(&[]);
    assert!(!err.contains("condensing"), "stderr piped, yet:\n{err}");
    let err = piped(&["--progress"]);
    assert!(err.contains(condensed), "--progress, yet:\n{err}");
}
