//! Bad input that would exhaust memory or time, and internal errors
//!: the memory estimate refuses what cannot fit before
//! anything is built, `--max-memory` overrides the machine, an internal error
//! is one line and exit 3 (on every rank under mpirun), and stand-alone
//! problems and benchmarks that cannot fit are refused.

use crate::common;

use common::bad_scene::{
    base_scene_command, block_meshed, block_with, block_with_all, fresh_dir, run_scene,
    BLOCK_ON_PLANE,
};
use common::{run_limited, BIN};
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

// ---------------------------------------------------------------- item 5

#[test]
fn an_oversized_rectangle_is_refused_with_the_estimate_before_anything_is_built() {
    let scene = block_with("divisions = [4, 2]", "divisions = [100000, 100000]");
    let t = Instant::now();
    let run = run_scene("oversized_rectangle", Some(&scene), &[]);
    run.assert_bad_input(&[
        "memory: the scene needs about",
        "GiB",
        "available",
        "bodies[0].mesh.divisions",
        "coarser divisions",
    ]);
    assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
}

#[test]
fn a_half_disk_of_1e9_divisions_is_refused() {
    let scene = block_meshed(
        "{ generator = \"half_disk\", center = [0.0, 1.0], radius = 1.0, divisions = 1e9 }",
    );
    let run = run_scene("half_disk_1e9", Some(&scene), &[]);
    run.assert_bad_input(&["memory: the scene needs about", "bodies[0].mesh.divisions"]);
}

#[test]
fn the_3000_square_rectangle_does_not_fit_in_24_gib_and_max_memory_says_so() {
    let scene = block_with("divisions = [4, 2]", "divisions = [3000, 3000]");
    let run = run_scene("rectangle_3000", Some(&scene), &["--max-memory", "24G"]);
    run.assert_bad_input(&[
        "memory: the scene needs about",
        "--max-memory is 24 GiB",
        "or --max-memory",
    ]);
}

#[test]
fn max_memory_overrides_the_machine_both_ways() {
    // far too little for even the small block
    let run = run_scene(
        "max_memory_tiny",
        Some(&BLOCK_ON_PLANE),
        &["--max-memory", "1M"],
    );
    run.assert_bad_input(&["--max-memory is 1 MiB"]);
    // plenty
    let run = run_scene(
        "max_memory_plenty",
        Some(&BLOCK_ON_PLANE),
        &["--max-memory", "64G"],
    );
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
    // a bad size is a usage error naming the value
    let run = run_scene(
        "max_memory_bad",
        Some(&BLOCK_ON_PLANE),
        &["--max-memory", "lots"],
    );
    assert!(!run.output.status.success(), "{}", run.describe());
    assert!(run.stderr().contains("lots"), "{}", run.describe());
    run.assert_nothing_written();
}

#[test]
fn check_prints_the_memory_estimate_and_refuses_what_cannot_fit() {
    let (dir, mut check) = base_scene_command("check_memory", "check");
    let scene = dir.join("scene.toml");
    let out = check.output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(
        text.contains("memory (condensed path): about") && text.contains("MiB"),
        "{text}"
    );
    std::fs::write(
        &scene,
        block_with("divisions = [4, 2]", "divisions = [100000, 100000]"),
    )
    .unwrap();
    let out = Command::new(BIN).arg("check").arg(&scene).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("memory: the scene needs about"), "{err}");
}

#[test]
fn every_example_passes_check_with_its_memory_estimate() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let out = Command::new(BIN).arg("check").arg(&path).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}: {text}{}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(text.contains("memory ("), "{}: {text}", path.display());
        n += 1;
    }
    assert!(n >= 10, "{n} examples");
}

#[test]
fn the_estimate_is_near_the_measured_peak() {
    // 150 x 150 quad4 on a plane: about 150 MiB, well above the fixed part
    let scene = block_with_all(&[
        ("divisions = [4, 2]", "divisions = [150, 150]"),
        ("size = [1.0, 0.5]", "size = [1.0, 1.0]"),
        ("point = [0.0, 0.5]", "point = [0.0, 1.0]"),
    ]) + "[output]\nfields = []\n";
    let run = run_scene("estimate_near_peak", Some(&scene), &[]);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.out_dir().join("report.json")).unwrap())
            .unwrap();
    let memory = &report["memory"];
    let estimated = memory["estimated_bytes"].as_f64().unwrap();
    let peak = memory["peak_rss_bytes"].as_f64().unwrap();
    if peak > 0.0 {
        let ratio = estimated / peak;
        assert!(
            (0.9..2.0).contains(&ratio),
            "estimated {estimated:e} bytes, peak {peak:e}: ratio {ratio}"
        );
    }
}

#[test]
fn an_internal_error_is_one_line_and_exit_3() {
    let (dir, mut cmd) = base_scene_command("internal_error", "run");
    cmd.arg("--out")
        .arg(dir.join("out"))
        .env("SIGNORINI_INJECT_PANIC", "0");
    let (out, _) = run_limited(cmd, Duration::from_secs(60));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: internal error: panic injected on rank 0")
            && err.contains("(please report)"),
        "{err}"
    );
    assert!(
        !err.contains("panicked") && !err.contains("backtrace"),
        "{err}"
    );
    assert!(!dir.join("out").exists());
}

/// Under MPI a panic on one rank still ends every rank (crates/comm's hook
/// runs after the one-line message), never a hang.
#[cfg(feature = "mpi")]
#[test]
fn an_internal_error_under_mpirun_ends_every_rank() {
    if !common::have_mpirun() {
        return;
    }
    let dir = fresh_dir("internal_error_mpi");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, BLOCK_ON_PLANE).unwrap();
    let mut cmd = common::mpirun(2);
    cmd.arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .env("SIGNORINI_INJECT_PANIC", "1");
    let (out, elapsed) = run_limited(cmd, Duration::from_secs(60));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(elapsed < Duration::from_secs(60), "a rank hangs: {err}");
    assert!(!out.status.success(), "{err}");
    assert_eq!(
        err.matches("internal error: panic injected on rank 1")
            .count(),
        1,
        "{err}"
    );
    assert!(!err.contains("panicked at"), "{err}");
    assert!(!dir.join("out").exists());
}

// ---------------------------------------------------------------- local and bench

#[test]
fn local_problems_that_lie_about_their_shape_are_refused() {
    let dir = fresh_dir("local_bad");
    for (name, text, needle) in [
        (
            "ragged.json",
            r#"{"W": [[2, 1], [1]], "q": [-1, 1]}"#,
            "W must be 2 × 2",
        ),
        (
            "inf.json",
            r#"{"W": [[2, 1], [1, 2]], "q": [-1, 1e999]}"#,
            "out of range",
        ),
        (
            "asym.json",
            r#"{"W": [[2, 1], [0, 2]], "q": [-1, 1]}"#,
            "not symmetric",
        ),
        (
            "mu.json",
            r#"{"W": [[1, 0], [0, 1]], "q": [-1, 1], "mu": [-0.3], "dim": 2}"#,
            "mu[0]",
        ),
        (
            "ambiguous.json",
            r#"{"W": [[1, 0], [0, 1]], "q": [-1, 1], "mu": [0.3]}"#,
            "ambiguous",
        ),
        (
            "truncated.json",
            r#"{"W": [[2, 1], [1, 2]], "q": [-1,"#,
            "truncated.json",
        ),
        (
            "garbage.npz",
            "PK\u{3}\u{4} not a zip",
            "not a .npz archive",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let mut cmd = Command::new(BIN);
        cmd.arg("local").arg(&path);
        let (out, elapsed) = run_limited(cmd, Duration::from_secs(30));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains(needle), "{name}: {err}");
        assert!(
            err.lines().count() <= 2 && !err.contains("panicked"),
            "{name}: {err}"
        );
        assert!(elapsed < Duration::from_secs(10), "{name}: {elapsed:?}");
    }
}

#[test]
fn bench_refuses_a_refinement_that_cannot_fit() {
    let (dir, mut cmd) = base_scene_command("bench_huge", "bench");
    cmd.arg("--levels")
        .arg("1e9")
        .arg("--out")
        .arg(dir.join("out"));
    let (out, elapsed) = run_limited(cmd, Duration::from_secs(60));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("memory: the scene needs about"), "{err}");
    assert!(elapsed < Duration::from_secs(10), "{elapsed:?}");
    assert!(!dir.join("out").exists());
}

/// The slab of `examples/indent3d.toml` at 60 × 60 × 2 cells (3 721 top
/// nodes), its candidate zone `zone` (`None`: every top node).
fn slab_with_zone(zone: Option<&str>) -> String {
    let path = format!("{}/examples/indent3d.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains("divisions = [40, 40, 2]") && text.contains("search_distance = 0.01"));
    let text = text.replace("divisions = [40, 40, 2]", "divisions = [60, 60, 2]");
    match zone {
        Some(d) => text.replace("search_distance = 0.01", &format!("search_distance = {d}")),
        None => text.replace("search_distance = 0.01\n", ""),
    }
}

#[test]
fn a_candidate_zone_is_counted_in_the_memory_estimate_once_built() {
    // every top node a contact unknown: a dense interface of 3 721 DOFs,
    // refused before anything is built
    let run = run_scene(
        "zone_none",
        Some(&slab_with_zone(None)),
        &["--max-memory", "1G"],
    );
    run.assert_bad_input(&["3721 interface DOFs", "--max-memory is 1.0 GiB"]);
    // a zone of about a hundred nodes fits, and the report's estimate counts it
    let run = run_scene(
        "zone_small",
        Some(&slab_with_zone(Some("0.01"))),
        &["--max-memory", "1G"],
    );
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.out_dir().join("report.json")).unwrap())
            .unwrap();
    let estimated = report["memory"]["estimated_bytes"].as_f64().unwrap();
    let points = report["contact_points"].as_f64().unwrap();
    assert!((50.0..400.0).contains(&points), "{points} contact points");
    assert!(
        estimated < 0.5 * 1024f64.powi(3),
        "estimated {estimated} bytes"
    );
    // a zone that keeps every node is refused once built, naming its size
    let run = run_scene(
        "zone_wide",
        Some(&slab_with_zone(Some("10.0"))),
        &["--max-memory", "1G"],
    );
    run.assert_bad_input(&["interface DOFs", "--max-memory is 1.0 GiB"]);
    assert!(
        !run.stderr().contains(" 0 interface DOFs"),
        "{}",
        run.describe()
    );
}

#[test]
fn bench_plot_draws_the_rows_of_several_csvs_and_refuses_a_file_that_is_not_one() {
    let dir = fresh_dir("bench_plot");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, BLOCK_ON_PLANE).unwrap();
    let bench = |args: &[&str], out: &str| {
        let run = Command::new(BIN)
            .arg("bench")
            .args(args)
            .arg("--out")
            .arg(dir.join(out))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr).into_owned();
        (run, err)
    };
    let scene_arg = scene.to_str().unwrap();
    // two benches of one level each, then their plots together
    for level in ["1", "2"] {
        let (run, err) = bench(&["--levels", level, scene_arg], level);
        assert!(run.status.success(), "{err}");
    }
    let csvs = format!(
        "{},{}",
        dir.join("1/bench.csv").display(),
        dir.join("2/bench.csv").display()
    );
    let (run, err) = bench(&["--plot", &csvs], "both");
    assert!(run.status.success(), "{err}");
    assert!(String::from_utf8_lossy(&run.stdout).contains("plot(s) of 4 rows"));
    let memory = std::fs::read_to_string(dir.join("both/memory_vs_dofs.svg")).unwrap();
    assert!(memory.contains("peak resident set [MiB]") && memory.contains("direct"));
    // a scene given as a CSV: exit 1 naming the file, nothing drawn
    let (run, err) = bench(&["--plot", scene_arg], "bad");
    assert_eq!(run.status.code(), Some(1), "{err}");
    common::assert_mentions(&err, &["scene.toml", "no column"]);
    assert!(!dir.join("bad").exists());
}

/// A problem exported by NumPy with an integer `dim` (`np.array(2)` is
/// int64) and a file named in capitals (`.NPZ`) are read (they were refused:
/// "expected float64 data", and parsed as JSON).
#[test]
fn a_numpy_problem_with_an_integer_dim_or_a_capital_extension_is_read() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/local_int_dim.npz");
    let dir = fresh_dir("npz_capital");
    let capital = dir.join("LCP.NPZ");
    std::fs::copy(&data, &capital).unwrap();
    for path in [data, capital] {
        let out = Command::new(BIN).arg("local").arg(&path).output().unwrap();
        let text = common::stdout_of_success(&out, &path.display().to_string());
        assert!(
            text.contains("\"m\":4") && text.contains("\"dim\":2"),
            "{text}"
        );
        assert!(text.contains("\"converged\":true"), "{text}");
    }
}

/// A .npz whose arrays unpack to more than the solve may hold is refused
/// before they are read (a 3 MB file of deflated zeros unpacked to 3.2 GB,
/// then some 10 GB of copies); `local --max-memory` sets the budget.
#[test]
fn a_npz_that_unpacks_past_the_budget_is_refused_before_it_is_read() {
    let dir = fresh_dir("npz_budget");
    let path = dir.join("big.npz");
    let n = 1000; // W: 8 MB of f64
    let w = faer::Mat::<f64>::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.0 });
    signorini_problems::problem_file::write_npz(&path, &w, &vec![-1.0; n], &[], 1).unwrap();
    let run = |budget: &str| {
        Command::new(BIN)
            .args(["local", "--max-memory", budget])
            .arg(&path)
            .output()
            .unwrap()
    };
    let out = run("16M");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("W.npy unpacks to") && err.contains("16 MiB --max-memory"),
        "{err}"
    );
    let out = run("1G");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
