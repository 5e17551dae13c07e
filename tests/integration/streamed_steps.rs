//! Many load steps in flat memory: each step's fields
//! stream to disk as the step ends, `[output] steps` chooses which steps
//! write them, and a long cyclic run gives, at a chosen step, the fields of
//! the run that keeps every step.

use crate::common;

use std::path::Path;

use common::{cli_run, cli_run_ok, example, fresh_dir, max_rel, try_run, with_zone, PULLED_BLOCK};
use signorini_solver::{RunOptions, RunOutput};

/// examples/cyclic.toml coarsened, with `n` steps of its load cycle
/// (pull 0, ½, 1, ½, 0, −½, −1, −½, …) and `output` appended to `[output]`.
fn cyclic(n: usize, output: &str) -> String {
    let text = example("cyclic.toml")
        .replace(
            "divisions = 120, grading = 16.0",
            "divisions = 24, grading = 4.0",
        )
        .replace("divisions = [200, 30]", "divisions = [40, 6]");
    let head = &text[..text.find("[[steps]]").expect("cyclic.toml has steps")];
    let pull = [0.0, 0.5, 1.0, 0.5, 0.0, -0.5, -1.0, -0.5];
    let steps: String = (0..n)
        .map(|k| {
            format!(
                "[[steps]]\nscale = {{ press = 1.0, pull = {} }}\n\n",
                pull[k % 8]
            )
        })
        .collect();
    format!("{head}{steps}[output]\nprobes = [[0.0, 1.0]]\n{output}\n")
}

fn run_ok(text: &str) -> RunOutput {
    let out = try_run(text, RunOptions::default()).unwrap_or_else(|e| panic!("run: {e}"));
    assert!(out.report.converged, "{:?}", out.report.failure);
    out
}

/// Each body's displacement at every step kept, body after body.
fn kept(o: &RunOutput) -> Vec<Vec<Vec<f64>>> {
    o.bodies
        .iter()
        .map(|b| b.history.iter().map(|s| s.displacement.clone()).collect())
        .collect()
}

/// A long cyclic run (64 steps): the fields of the steps `[output] steps`
/// keeps equal those of the run that keeps every step, at the same steps;
/// the steps differ from each other (the selection cannot pass by picking
/// any step); contact rows and step reports cover every step either way.
#[test]
fn selected_steps_of_a_long_cyclic_run_equal_the_all_steps_run() {
    let n = 64;
    let all = run_ok(&cyclic(n, ""));
    let every = kept(&all);
    assert!(every.iter().all(|b| b.len() == n));
    let m = all.report.contact_points;
    assert_eq!(all.contact_rows.len(), n * m);
    // Step 13 (pull ½ on the way down) and step 15 (same load on the way up
    // of the next cycle) differ: the history of the slip.
    assert!(max_rel(&every[0][12], &every[0][14]) > 1e-3);
    for (output, chosen) in [
        ("steps = [13, 40, 7]", vec![7, 13, 40]),
        ("steps = { every = 20 }", vec![20, 40, 60, 64]),
        ("steps = \"last\"", vec![64]),
    ] {
        let some = run_ok(&cyclic(n, output));
        assert_eq!(some.report.steps.len(), n, "{output}");
        assert_eq!(some.contact_rows.len(), n * m, "{output}");
        let got = kept(&some);
        for (bi, body) in got.iter().enumerate() {
            assert_eq!(body.len(), chosen.len(), "{output}");
            for (u, &step) in body.iter().zip(&chosen) {
                let d = max_rel(u, &every[bi][step - 1]);
                assert!(
                    d <= 1e-13,
                    "{output}: body {bi} step {step} differs by {d:e}"
                );
            }
        }
        assert_eq!(
            some.report.contact_force, all.report.contact_force,
            "{output}"
        );
    }
}

/// The .vtu files of a directory, sorted.
fn vtu_files(dir: &Path) -> Vec<String> {
    let mut v = common::listing(dir);
    v.retain(|f| f.ends_with(".vtu"));
    v
}

/// The lines of a file.
fn lines(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .map(String::from)
        .collect()
}

/// `signorini run` writes exactly the VTU pieces `[output] steps` chooses,
/// listed in fields.pvd, byte for byte those of the all-steps run; contact.csv
/// and steps.csv keep every step and equal the all-steps run's.
#[test]
fn the_cli_writes_exactly_the_chosen_steps_and_every_csv_row() {
    let dir = fresh_dir("streamed", "cli");
    let n = 12;
    std::fs::write(dir.join("all.toml"), cyclic(n, "")).unwrap();
    cli_run_ok(dir.join("all.toml"), dir.join("all"));
    let all = dir.join("all");
    let every: Vec<String> = ["block", "cylinder"]
        .iter()
        .flat_map(|b| (1..=n).map(move |s| format!("{b}_{s}.vtu")))
        .collect();
    let mut sorted = every.clone();
    sorted.sort();
    assert_eq!(vtu_files(&all), sorted);
    for (tag, output, chosen) in [
        ("list", "steps = [10, 3]", vec![3, 10]),
        ("every", "steps = { every = 5 }", vec![5, 10, 12]),
        ("last", "steps = \"last\"", vec![12]),
    ] {
        let scene = dir.join(format!("{tag}.toml"));
        std::fs::write(&scene, cyclic(n, output)).unwrap();
        let out = dir.join(tag);
        cli_run_ok(&scene, &out);
        let mut want: Vec<String> = ["block", "cylinder"]
            .iter()
            .flat_map(|b| chosen.iter().map(move |s| format!("{b}_{s}.vtu")))
            .collect();
        want.sort();
        assert_eq!(vtu_files(&out), want, "{tag}");
        for f in &want {
            let (a, b) = (std::fs::read(all.join(f)), std::fs::read(out.join(f)));
            assert!(a.unwrap() == b.unwrap(), "{tag}: {f} differs");
        }
        let pvd = std::fs::read_to_string(out.join("fields.pvd")).unwrap();
        assert_eq!(pvd.matches("<DataSet").count(), want.len(), "{tag}: {pvd}");
        for s in &chosen {
            assert!(pvd.contains(&format!("timestep=\"{s}\"")), "{tag}: {pvd}");
        }
        for csv in ["contact.csv", "steps.csv", "displacement.csv", "stress.csv"] {
            assert_eq!(lines(&out.join(csv)), lines(&all.join(csv)), "{tag}: {csv}");
        }
        assert_eq!(lines(&out.join("steps.csv")).len(), n + 1);
        let hidden = hidden_entries(&out);
        assert_eq!(hidden, 0, "{tag}: the staging directory is left");
    }
}

/// A step list naming a step that does not exist, or a zero interval: exit
/// 1, a message naming the entry and the valid steps, nothing written.
#[test]
fn steps_out_of_range_are_refused_by_name_and_nothing_is_written() {
    let dir = fresh_dir("streamed", "invalid");
    for (tag, output, entry, valid) in [
        ("beyond", "steps = [2, 13]", "output.steps[1]", "1 to 12"),
        ("zero", "steps = [0]", "output.steps[0]", "1 to 12"),
        ("negative", "steps = [-1]", "output.steps[0]", "1 to 12"),
        (
            "every",
            "steps = { every = 0 }",
            "output.steps.every",
            ">= 1",
        ),
    ] {
        let scene = dir.join(format!("{tag}.toml"));
        std::fs::write(&scene, cyclic(12, output)).unwrap();
        let out = dir.join(tag).join("out");
        let o = cli_run(&scene, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{tag}: {err}");
        assert!(err.contains(entry) && err.contains(valid), "{tag}: {err}");
        assert!(!dir.join(tag).exists(), "{tag}: wrote output");
    }
}

/// A run that meets bad input at its second step (a box held by contact
/// alone pulled off its support), after its first step streamed its
/// fields: exit 1 and nothing left on disk, not even the directory.
#[test]
fn an_error_at_a_later_step_leaves_nothing_behind() {
    let dir = fresh_dir("streamed", "late-error");
    let text = common::floating_pulled_off_at_step_2("");
    let scene = dir.join("late.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("nested").join("out");
    let o = cli_run(&scene, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("step 2"), "{err}");
    assert!(!dir.join("nested").exists(), "wrote output");
}

/// Under `mpirun -n 2` (one body per rank) the steps go one at a time
/// through the transport: the same chosen pieces and the same contact.csv
/// as in one process.
#[cfg(feature = "mpi")]
#[test]
fn two_ranks_stream_the_same_steps_as_one_process() {
    if !common::have_mpirun() {
        eprintln!("mpirun missing: skipped");
        return;
    }
    let dir = fresh_dir("streamed", "mpi");
    let scene = dir.join("c.toml");
    std::fs::write(&scene, cyclic(10, "steps = [4, 9]")).unwrap();
    cli_run_ok(&scene, dir.join("one"));
    let o = common::mpirun(2)
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("two"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = std::fs::read_to_string(dir.join("two/report.json")).unwrap();
    assert!(report.contains("\"ranks\": 2"), "not run on 2 ranks");
    assert_eq!(vtu_files(&dir.join("two")), vtu_files(&dir.join("one")));
    assert_eq!(
        vtu_files(&dir.join("two")),
        [
            "block_4.vtu",
            "block_9.vtu",
            "cylinder_4.vtu",
            "cylinder_9.vtu"
        ]
    );
    let numbers = |p: &Path| -> Vec<f64> {
        lines(p)
            .iter()
            .skip(1)
            .flat_map(|l| {
                l.split(',')
                    .filter_map(|x| x.parse::<f64>().ok())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let d = max_rel(
        &numbers(&dir.join("one/contact.csv")),
        &numbers(&dir.join("two/contact.csv")),
    );
    assert!(d <= 1e-10, "contact.csv differs by {d:e}");
}

/// A candidate zone too small is widened after the first solve and the run
/// solved again: the streamed files are those of the second solve alone
/// (one contact.csv row per point and step, as the in-memory run), and the
/// same as the run without a zone.
#[test]
fn a_widened_zone_streams_the_second_solve_alone() {
    let dir = fresh_dir("streamed", "widened");
    let small = with_zone(&PULLED_BLOCK, "node_to_segment", 2e-3);
    let kept = try_run(&small, RunOptions::default()).unwrap();
    assert!(
        kept.report.messages.iter().any(|m| m.contains("widened")),
        "no widening: {:?}",
        kept.report.messages
    );
    std::fs::write(dir.join("small.toml"), &small).unwrap();
    std::fs::write(dir.join("full.toml"), PULLED_BLOCK).unwrap();
    cli_run_ok(dir.join("small.toml"), dir.join("small"));
    cli_run_ok(dir.join("full.toml"), dir.join("full"));
    let rows = lines(&dir.join("small/contact.csv"));
    assert_eq!(rows.len(), 1 + kept.contact_rows.len());
    assert_eq!(vtu_files(&dir.join("small")), vtu_files(&dir.join("full")));
    let hidden = hidden_entries(dir.join("small"));
    assert_eq!(hidden, 0, "the staging directory is left");
}

/// Entries of `dir` whose names start with a dot (the staging directory).
fn hidden_entries(dir: impl AsRef<std::path::Path>) -> usize {
    std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .starts_with('.')
        })
        .count()
}
