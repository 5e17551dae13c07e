//! `mpirun -n 2` (and 3) against the in-process run: one subdomain per rank,
//! the same answer (docs/theory/validation-cases.md §7), errors printed once, no hang.
//! Built only with the cargo feature `mpi` (ci/test.sh builds with it).
#![cfg(feature = "mpi")]

mod common;

use common::{
    example_path as example, have_mpirun, hertz_in_units, listing, max_rel, patch3d_in_pa_and_m,
    BIN,
};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

/// Ends the test at once where `mpirun` is not installed (on CI its absence
/// is a failure: see `have_mpirun`).
macro_rules! require_mpirun {
    () => {
        if !have_mpirun() {
            return;
        }
    };
}

/// A command to its end within two minutes: a hang is a failure.
fn run_limited(cmd: Command) -> Output {
    let limit = Duration::from_secs(120);
    let (out, elapsed) = common::run_limited(cmd, limit);
    assert!(elapsed <= limit, "no answer within {limit:?}: a rank hangs");
    out
}

fn mpirun(np: usize, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = common::mpirun(np);
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    run_limited(c)
}

fn local(args: &[&str]) -> Output {
    let mut c = Command::new(BIN);
    c.args(args);
    run_limited(c)
}

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("mpi", name)
}

/// Numeric columns of a CSV file (header skipped, non-numbers dropped).
fn numbers(path: &Path, columns: &[&str]) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let idx: Vec<usize> = columns
        .iter()
        .map(|c| header.iter().position(|h| h == c).unwrap())
        .collect();
    lines
        .flat_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            idx.iter()
                .map(|&i| f[i].parse::<f64>().unwrap())
                .collect::<Vec<_>>()
        })
        .collect()
}

fn report(d: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(d.join("report.json")).unwrap()).unwrap()
}

/// Runs a scene in process and under `mpirun -n np`; both must agree to 1e-10.
fn compare(scene: &str, np: usize, tag: &str) {
    compare_with(scene, np, tag, &[]);
}

/// [`compare`] with `env` set for the `mpirun` run.
fn compare_with(scene: &str, np: usize, tag: &str, env: &[(&str, &str)]) {
    let d = dir(tag);
    let (a, b) = (d.join("local"), d.join("mpi"));
    let out = local(&["run", scene, "--out", a.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = mpirun(np, &["run", scene, "--out", b.to_str().unwrap()], env);
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let (ra, rb) = (report(&a), report(&b));
    assert_eq!(rb["ranks"], np);
    assert_eq!(rb["transport"], "mpi");
    assert_eq!(ra["transport"], "local");
    assert_eq!(rb["rank_stats"].as_array().unwrap().len(), np);
    assert!(rb["communication_bytes"].as_u64().unwrap() > 0);
    let fa = numbers(
        &a.join("contact.csv"),
        &["normal_force", "gap", "tangential_force", "slip"],
    );
    let fb = numbers(
        &b.join("contact.csv"),
        &["normal_force", "gap", "tangential_force", "slip"],
    );
    assert!(
        max_rel(&fa, &fb) <= 1e-10,
        "{tag}: contact differs by {:e}",
        max_rel(&fa, &fb)
    );
    let cols: &[&str] = if ra["contact_force"].as_array().unwrap().len() == 3 {
        &["ux", "uy", "uz"]
    } else {
        &["ux", "uy"]
    };
    let ua = numbers(&a.join("displacement.csv"), cols);
    let ub = numbers(&b.join("displacement.csv"), cols);
    assert!(
        max_rel(&ua, &ub) <= 1e-10,
        "{tag}: displacements differ by {:e}",
        max_rel(&ua, &ub)
    );
    let reactions = reaction_columns(&a.join("steps.csv"));
    let reactions: Vec<&str> = reactions.iter().map(String::as_str).collect();
    assert!(!reactions.is_empty(), "{tag}: no reaction in steps.csv");
    let ra = numbers(&a.join("steps.csv"), &reactions);
    let rb = numbers(&b.join("steps.csv"), &reactions);
    // relative to the largest reaction or contact force: a support that
    // carries nothing has a reaction of round-off on both runs
    let scale = (ra
        .iter()
        .chain(&numbers(&a.join("steps.csv"), &["normal_force"])))
    .fold(0.0f64, |m, v| m.max(v.abs()));
    let differ = ra
        .iter()
        .zip(&rb)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        differ <= 1e-10 * scale,
        "{tag}: reactions differ by {differ:e} (scale {scale:e})"
    );
}

/// The reaction and moment columns of a steps.csv.
fn reaction_columns(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let header = text.lines().next().unwrap();
    (header.split(','))
        .filter(|c| c.starts_with("reaction_") || c.starts_with("moment_"))
        .map(str::to_string)
        .collect()
}

#[test]
fn hertz_split_in_two_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let text = std::fs::read_to_string(example("hertz2d.toml")).unwrap();
    let text = common::with_subdomains(&text, "material = \"steel\"\n", 2);
    compare(
        &write_scene("hertz_scene", "hertz_split.toml", &text),
        2,
        "hertz",
    );
}

#[test]
fn stack_under_mpirun_2_and_3_equals_the_in_process_run() {
    require_mpirun!();
    compare(&example("stack.toml"), 2, "stack2");
    compare(&example("stack.toml"), 3, "stack3");
}

/// Buffers larger than MPI's 32-bit counts travel in rounds: forced here
/// with rounds of 4 kB (the S_i of the stack take hundreds of kB), the
/// answer is the in-process one.
#[test]
fn gathers_and_broadcasts_in_rounds_give_the_same_answer() {
    require_mpirun!();
    compare_with(
        &example("stack.toml"),
        3,
        "stack3_rounds",
        &[("SIGNORINI_MPI_CHUNK_BYTES", "4096")],
    );
}

#[test]
fn a_failing_rank_ends_every_rank_with_one_message() {
    require_mpirun!();
    let d = dir("fail");
    let out = mpirun(
        2,
        &[
            "run",
            &example("stack.toml"),
            "--out",
            d.join("out").to_str().unwrap(),
        ],
        &[("SIGNORINI_FAIL_RANK", "1")],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.matches("failure injected on rank 1").count(),
        1,
        "{err}"
    );
    assert!(!d.join("out").exists(), "nothing is written");
}

#[test]
fn bad_input_under_mpirun_is_reported_once_with_exit_1() {
    require_mpirun!();
    let d = dir("bad");
    let scene = d.join("bad.toml");
    std::fs::write(
        &scene,
        std::fs::read_to_string(example("stack.toml"))
            .unwrap()
            .replace("young = 70.0", "young = -70.0"),
    )
    .unwrap();
    let out = mpirun(
        2,
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            d.join("out").to_str().unwrap(),
        ],
        &[],
    );
    let err = common::stderr_of_exit(&out, 1);
    assert_eq!(err.matches("materials[1].young").count(), 1, "{err}");
    assert!(!d.join("out").exists());
}

#[test]
fn friction_with_a_split_block_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let body = "name = \"block\"\nmaterial = \"steel\"";
    let scene = split_example("cattaneo.toml", body, "cattaneo");
    compare(&scene, 2, "cattaneo");
}

/// Writes an example with its first deformable body split in two METIS parts.
fn split_example(name: &str, body_line: &str, tag: &str) -> String {
    let text = common::example_with_meshes(name)
        .replace(body_line, &format!("{body_line}\nsubdomains = 2"));
    assert!(
        text.contains("subdomains = 2"),
        "{name}: no line {body_line:?}"
    );
    write_scene(&format!("{tag}_scene"), name, &text)
}

/// Writes `text` as the scene `file` in the fresh directory `tag`; its path.
fn write_scene(tag: &str, file: &str, text: &str) -> String {
    let scene = dir(tag).join(file);
    std::fs::write(&scene, text).unwrap();
    scene.to_str().unwrap().to_string()
}

#[test]
fn solids_3d_under_mpirun_2_equal_the_in_process_run() {
    require_mpirun!();
    // two hexahedral boxes, one per rank
    compare(&example("patch3d.toml"), 2, "patch3d");
    // a Gmsh tetrahedral block split by METIS
    let scene = split_example("gmsh_block3d.toml", "material = \"steel\"", "gmsh3d");
    compare(&scene, 2, "gmsh3d");
}

#[test]
fn axisymmetric_hertz_split_in_two_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let scene = split_example("hertz_axi.toml", "material = \"steel\"", "axi");
    compare(&scene, 2, "axi");
}

/// Bodies held by contact alone under `mpirun -n 2`: the 2D pad of
/// blocks.toml split in two METIS parts, solved by SMALBE (mprgp), and the
/// 3D floating box split in two, equal the in-process runs.
#[test]
fn floating_bodies_under_mpirun_2_equal_the_in_process_run() {
    require_mpirun!();
    let text = std::fs::read_to_string(example("blocks.toml")).unwrap();
    let text = common::with_subdomains(&text, "material = \"rubber\"\n", 2);
    assert!(text.contains("subdomains = 2"));
    let text = if text.contains("[solver]") {
        text.replace("[solver]", "[solver]\nmethod = \"mprgp\"")
    } else {
        format!("{text}\n[solver]\nmethod = \"mprgp\"\n")
    };
    let scene = write_scene("floating_scene", "blocks_mprgp.toml", &text);
    compare(&scene, 2, "floating2d");
    let scene = split_example("floating3d.toml", "material = \"aluminium\"", "floating3d");
    compare(&scene, 2, "floating3d");
}

/// The units test (tests/integration/units.rs) across the two transports: Hertz in Pa
/// and m split over two ranks by `mpirun -n 2` equals Hertz in MPa and mm
/// (the same two subdomains) in one process, and likewise the 3D two-box
/// patch, after conversion, to 1e-10.
#[test]
fn units_under_mpirun_2_equal_the_other_units_in_process_2d_and_3d() {
    require_mpirun!();
    let d = dir("units");
    let split = |t: String| common::with_subdomains(&t, "material = \"steel\"\n", 2);
    let si = split(hertz_in_units("210e9", 0.01));
    assert!(si.contains("subdomains = 2"));
    let (si_scene, mm_scene) = (d.join("si.toml"), d.join("mm.toml"));
    std::fs::write(&si_scene, si).unwrap();
    std::fs::write(&mm_scene, split(hertz_in_units("210e3", 10.0))).unwrap();
    // plane strain: N/m against N/mm per unit thickness
    si_under_mpirun_equals_mm_in_process(
        &si_scene,
        &mm_scene,
        &d.join("hertz"),
        1000.0,
        &["ux", "uy"],
    );
    // 3D: the two-box patch (a box per rank), forces in N both ways
    let si_scene = d.join("patch3d_si.toml");
    std::fs::write(&si_scene, patch3d_in_pa_and_m()).unwrap();
    let mm_scene = PathBuf::from(example("patch3d.toml"));
    si_under_mpirun_equals_mm_in_process(
        &si_scene,
        &mm_scene,
        &d.join("patch3d"),
        1.0,
        &["ux", "uy", "uz"],
    );
}

/// Runs `si` (Pa, m) under `mpirun -n 2` and `mm` (MPa, mm) in one process
/// into `out`/si and `out`/mm: the contact forces (× `force_factor` from
/// the mm run's unit) and the displacements (mm → m) agree to 1e-10.
fn si_under_mpirun_equals_mm_in_process(
    si: &Path,
    mm: &Path,
    out: &Path,
    force_factor: f64,
    displacement_columns: &[&str],
) {
    let (a, b) = (out.join("si"), out.join("mm"));
    let run = mpirun(
        2,
        &["run", si.to_str().unwrap(), "--out", a.to_str().unwrap()],
        &[],
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let run = local(&["run", mm.to_str().unwrap(), "--out", b.to_str().unwrap()]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(report(&a)["transport"], "mpi");
    let tag = out.display();
    let f_si = numbers(&a.join("contact.csv"), &["normal_force"]);
    let f_mm: Vec<f64> = numbers(&b.join("contact.csv"), &["normal_force"])
        .iter()
        .map(|f| force_factor * f)
        .collect();
    let r = max_rel(&f_si, &f_mm);
    assert!(r <= 1e-10, "{tag}: forces differ by {r:e}");
    let u_si = numbers(&a.join("displacement.csv"), displacement_columns);
    let u_mm: Vec<f64> = numbers(&b.join("displacement.csv"), displacement_columns)
        .iter()
        .map(|u| u / 1000.0)
        .collect();
    let r = max_rel(&u_si, &u_mm);
    assert!(r <= 1e-10, "{tag}: displacements differ by {r:e}");
}

/// A candidate zone too small (`search_distance`, tests/integration/search_distance.rs)
/// under `mpirun -n 2`, the block split in two: every rank solves again with
/// the widened zone, the report says so once, and the answer equals the
/// in-process run's and the run without a zone.
#[test]
fn a_zone_widened_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let split = common::with_subdomains(&common::PULLED_BLOCK, "material = \"steel\"\n", 2);
    let zoned = common::with_zone(&split, "node_to_segment", 2e-3);
    let scene = write_scene("zone_scene", "zone.toml", &zoned);
    compare(&scene, 2, "zone");
    let full = write_scene("zone_full_scene", "full.toml", &split);
    let d = dir("zone_full");
    let out = local(&["run", &full, "--out", d.to_str().unwrap()]);
    assert!(out.status.success());
    let zoned_report = report(
        &Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join("mpi")
            .join("zone")
            .join("mpi"),
    );
    let widened = zoned_report["messages"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m.as_str().unwrap().contains("widened"))
        .count();
    assert!(widened >= 1, "{:?}", zoned_report["messages"]);
    let force = |r: &serde_json::Value| -> Vec<f64> {
        r["contact_force"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let (a, b) = (force(&report(&d)), force(&zoned_report));
    assert!(max_rel(&a, &b) <= 1e-9, "{a:?} against {b:?}");
}

/// report.json `rank_stats` of a run: one entry per rank.
fn rank_stats(d: &Path) -> Vec<serde_json::Value> {
    report(d)["rank_stats"].as_array().unwrap().clone()
}

fn sum_u64(stats: &[serde_json::Value], key: &str) -> u64 {
    stats.iter().map(|s| s[key].as_u64().unwrap()).sum()
}

#[test]
fn rank_stats_split_the_factors_and_schur_blocks_between_the_ranks() {
    require_mpirun!();
    let d = dir("rank_stats");
    let (a, b) = (d.join("local"), d.join("mpi"));
    let scene = example("stack.toml");
    let out = local(&["run", &scene, "--out", a.to_str().unwrap()]);
    assert!(out.status.success());
    let out = mpirun(2, &["run", &scene, "--out", b.to_str().unwrap()], &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (one, two) = (rank_stats(&a), rank_stats(&b));
    assert_eq!((one.len(), two.len()), (1, 2));
    // The factors are the same in one process and on two ranks (the same
    // subdomains, the same orderings), and sum to the report's.
    let total = report(&a)["factorisation"]["factor_bytes"]
        .as_u64()
        .unwrap();
    assert_eq!(sum_u64(&one, "factor_bytes"), total);
    assert_eq!(sum_u64(&two, "factor_bytes"), total);
    assert_eq!(
        report(&b)["factorisation"]["factor_bytes"]
            .as_u64()
            .unwrap(),
        total
    );
    assert_eq!(sum_u64(&two, "dense_bytes"), sum_u64(&one, "dense_bytes"));
    assert_eq!(sum_u64(&two, "subdomains"), 5);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    for (r, s) in two.iter().enumerate() {
        assert_eq!(s["rank"], r);
        let f = s["factor_bytes"].as_u64().unwrap();
        assert!(f > 0 && f < total, "rank {r}: {f} factor bytes of {total}");
        assert!(s["dense_bytes"].as_u64().unwrap() > 0);
        let (peak, setup) = (
            s["peak_rss_bytes"].as_u64().unwrap(),
            s["setup_peak_rss_bytes"].as_u64().unwrap(),
        );
        assert!(setup > 0 && setup <= peak, "rank {r}: {setup} > {peak}");
        assert!(s["condense_s"].as_f64().unwrap() > 0.0);
        assert!(s["setup_s"].as_f64().unwrap() > 0.0);
        // Two ranks on this machine: each its half of the cores.
        assert_eq!(s["threads"].as_u64().unwrap() as usize, (cores / 2).max(1));
    }
    // The interface problem is solved on the root only.
    assert!(two[0]["contact_s"].as_f64().unwrap() > 0.0);
    assert_eq!(two[1]["contact_s"].as_f64().unwrap(), 0.0);
}

#[test]
fn rayon_num_threads_sets_the_threads_of_every_rank() {
    require_mpirun!();
    let d = dir("rank_threads");
    let scene = example("stack.toml");
    let out = mpirun(
        2,
        &["run", &scene, "--out", d.to_str().unwrap()],
        &[("RAYON_NUM_THREADS", "3")],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats = rank_stats(&d);
    assert_eq!(stats.len(), 2);
    for s in &stats {
        assert_eq!(s["threads"], 3);
    }
}

/// `[output] pieces` under `mpirun -n 2`: each rank
/// writes the pieces of the subdomains it owns; every `.pvtu` index checks
/// against its gathered file (arrays, points, displacement, contact and
/// cell values), and the files are those of the in-process run (one piece
/// per subdomain, whatever the number of ranks).
#[test]
fn pieces_under_mpirun_2_equal_the_gathered_fields_and_the_in_process_files() {
    require_mpirun!();
    let scene = write_scene("pieces", "stack.toml", &common::stack_pieces(true));
    let d = Path::new(&scene).parent().unwrap().to_path_buf();
    let (a, b) = (d.join("local"), d.join("mpi"));
    let out = local(&["run", &scene, "--out", a.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = mpirun(2, &["run", &scene, "--out", b.to_str().unwrap()], &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    common::check_stack_pieces(&b);
    let stats = rank_stats(&b);
    assert!(stats.iter().all(|s| s["subdomains"].as_u64().unwrap() > 0));
    assert_eq!(listing(&a), listing(&b));
    assert_eq!(listing(&a.join("pieces")), listing(&b.join("pieces")));
}

/// An output directory that cannot be made (under a regular file) with
/// `[output] pieces`: refused before solving on every rank, one message,
/// exit 1, nothing written beside the file.
#[test]
fn pieces_into_a_bad_directory_under_mpirun_write_nothing() {
    require_mpirun!();
    let scene = write_scene("pieces-bad", "stack.toml", &common::stack_pieces(true));
    let d = Path::new(&scene).parent().unwrap().to_path_buf();
    std::fs::write(d.join("file"), "").unwrap();
    let out = mpirun(
        2,
        &["run", &scene, "--out", d.join("file/out").to_str().unwrap()],
        &[],
    );
    // Refused before solving, on every rank (the root's check is broadcast),
    // said once.
    let err = common::stderr_of_exit(&out, 1);
    assert_eq!(err.matches("is not a directory").count(), 1, "{err}");
    assert_eq!(listing(&d), vec!["file", "stack.toml"]);
}

/// Bad input met at a later step (the pad of examples/blocks.toml, held by
/// contact alone, pulled off its base at step 2) with `[output] pieces`
/// under mpirun -n 2 and 3: exit 1, one message, and nothing written, not
/// even the nested output directories the run created. Found by the fifth
/// robustness sweep: `out/a/b` were left behind (empty) under mpirun, where
/// the in-process run removes them: each rank's writer removed only what it
/// had created, while another rank's stage was still in them.
#[test]
fn bad_input_at_a_later_step_with_pieces_under_mpirun_leaves_no_directory() {
    require_mpirun!();
    let text = std::fs::read_to_string(example("blocks.toml")).unwrap()
        + "\n[[steps]]\nscale = { pressure = 1.0 }\n\n[[steps]]\nscale = { pressure = -1.0 }\n";
    let text = text.replace("[output]", "[output]\npieces = true");
    let text = common::with_subdomains(&text, "name = \"pad\"\nmaterial = \"rubber\"\n", 2);
    assert!(text.contains("pieces = true") && text.contains("subdomains = 2"));
    let scene = write_scene("later-bad", "blocks.toml", &text);
    let d = Path::new(&scene).parent().unwrap().to_path_buf();
    for np in [2, 3] {
        let out = d.join("out").join("a").join("b");
        let run = mpirun(np, &["run", &scene, "--out", out.to_str().unwrap()], &[]);
        let err = common::stderr_of_exit(&run, 1);
        assert_eq!(
            err.matches("cannot be in equilibrium at step 2").count(),
            1,
            "{err}"
        );
        assert_eq!(listing(&d), vec!["blocks.toml"], "-n {np}");
    }
}

/// `subdomains = "auto"` on a body of 2 cells under mpirun -n 3: 2 parts,
/// the third rank idle, the in-process answer. Found by the fifth
/// robustness sweep: it was refused (exit 1, "cannot split 2 cells into 3
/// non-empty parts"), though it runs in process and "auto" is meant to fit
/// the ranks.
#[test]
fn auto_subdomains_on_a_body_with_fewer_cells_than_ranks() {
    require_mpirun!();
    let text = common::bad_scene::BLOCK_ON_PLANE
        .replace("divisions = [4, 2]", "divisions = [2, 1]")
        .replace(
            "name = \"block\"\nmaterial = \"steel\"\n",
            "name = \"block\"\nmaterial = \"steel\"\nsubdomains = \"auto\"\n",
        );
    assert!(text.contains("divisions = [2, 1]") && text.contains("\"auto\""));
    let scene = write_scene("auto-few-cells-scene", "block.toml", &text);
    compare(&scene, 3, "auto-few-cells");
    let mpi = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mpi/auto-few-cells/mpi");
    let r = report(&mpi);
    assert_eq!(r["subdomains"], 2);
}

/// Contact elements (course notes §7) with friction through two load steps, the
/// pad on rank 1 and the base on rank 0, then the base split in two as well
/// (three subdomains on two ranks): the in-process answer.
#[test]
fn contact_elements_under_mpirun_2_equal_the_in_process_run() {
    require_mpirun!();
    compare(&example("contact_elements.toml"), 2, "contact_elements");
    let text = std::fs::read_to_string(example("contact_elements.toml")).unwrap();
    let text = common::with_subdomains(&text, "name = \"base\"\nmaterial = \"steel\"\n", 2);
    assert!(text.contains("subdomains = 2"));
    let scene = write_scene(
        "contact_elements_scene",
        "contact_elements_split.toml",
        &text,
    );
    compare(&scene, 2, "contact_elements_split");
}

/// `check` and `local` are one process's work: under `mpirun -n 2` they
/// print once, not once per rank.
#[test]
fn check_and_local_under_mpirun_print_once() {
    require_mpirun!();
    let out = mpirun(2, &["check", &example("stack.toml")], &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert_eq!(text.matches("valid scene").count(), 1, "{text}");
    let d = dir("local_once");
    let problem = d.join("p.json");
    std::fs::write(&problem, r#"{"W": [[2, 1], [1, 2]], "q": [-1, 1]}"#).unwrap();
    let out = mpirun(2, &["local", problem.to_str().unwrap()], &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert_eq!(text.lines().count(), 1, "{text}");
}

#[test]
fn direct_path_friction_under_mpirun_2_is_solved_on_the_root_and_equals_the_in_process_run() {
    require_mpirun!();
    let scene = common::example_path("cattaneo.toml");
    let d = dir("direct_friction");
    let (a, b) = (d.join("local"), d.join("mpi"));
    let run = ["run", &scene, "--path", "direct", "--out"];
    let out = local(&[&run[..], &[a.to_str().unwrap()]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = mpirun(2, &[&run[..], &[b.to_str().unwrap()]].concat(), &[]);
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{said}");
    assert!(
        said.contains("the root (rank 0) solves the whole system alone"),
        "{said}"
    );
    let rb = report(&b);
    assert_eq!(rb["ranks"], 2);
    assert!(rb["converged"].as_bool().unwrap());
    let method = rb["steps"][0]["solver"]["method"].as_str().unwrap();
    assert_eq!(method, "coulomb_direct_semismooth_newton");
    let columns = ["normal_force", "tangential_force", "slip"];
    let (fa, fb) = (
        numbers(&a.join("contact.csv"), &columns),
        numbers(&b.join("contact.csv"), &columns),
    );
    assert!(
        max_rel(&fa, &fb) <= 1e-10,
        "contact differs by {:e}",
        max_rel(&fa, &fb)
    );
}

/// An assembly read from one Gmsh file (three physical volumes, a tie, a
/// force on a node set, Coulomb friction changed by a step) under
/// `mpirun -n 2` equals the in-process run; so does it with the tied pad
/// split in two METIS parts (the tie eliminated from the subdomains' blocks).
#[test]
fn an_assembly_from_one_gmsh_file_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let scene = write_scene(
        "assembly_scene",
        "assembly_one_file.toml",
        &common::example_with_meshes("assembly_one_file.toml"),
    );
    compare(&scene, 2, "assembly");
    let body = "name = \"pad\"\nmaterial = \"soft\"";
    let scene = split_example("assembly_one_file.toml", body, "assembly_split");
    compare(&scene, 2, "assembly_split");
}

/// Mortar on quadratic faces (examples/patch3d.toml with a Hex20 base
/// 4 × 4 × 2 and a Tet10 block 5 × 5 × 2: Quad8 master faces, Tri6 slave
/// faces, non-matching), one box per rank: the in-process rows and forces.
#[test]
fn mortar_on_quadratic_faces_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let text = common::example("patch3d.toml")
        .replace(
            "divisions = [4, 4, 2] }",
            "divisions = [4, 4, 2], element = \"hex20\" }",
        )
        .replace(
            "divisions = [5, 5, 2] }",
            "divisions = [5, 5, 2], element = \"tet10\" }",
        )
        .replace(
            "discretization = \"node_to_face\"",
            "discretization = \"mortar\"",
        );
    assert!(text.contains("hex20") && text.contains("tet10") && text.contains("\"mortar\""));
    compare(
        &write_scene("quadratic_mortar_scene", "patch.toml", &text),
        2,
        "quadratic_mortar",
    );
}

/// The scene `text` of the curved patch blocks (tests/common/curved_patch.rs)
/// on two ranks against the in-process run, under the label `name`.
fn compare_curved(name: &str, text: &str) {
    compare(
        &write_scene(&format!("{name}_scene"), "curved.toml", text),
        2,
        name,
    );
}

/// Mortar on curved quadratic faces (the rows with the normal inside the
/// integral, tests/common/curved_patch.rs: Hex20 4 × 4 on Hex20 3 × 3 cut
/// along a parabolic cylinder, non-matching), one block per rank: the
/// in-process rows and forces.
#[test]
fn mortar_on_curved_quadratic_faces_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let text = common::curved_patch::parabolic("hex20_3", "hex20_4", "discretization = \"mortar\"");
    compare_curved("curved_mortar", &text);
}

/// Coulomb friction on mortar's curved quadratic faces (the tangential rows
/// with the frame inside the integral): the non-matching Hex20 parabolic
/// blocks under σ_zz = −1 held by μ = 1, the upper block held along x and y
/// by friction (tests/common/curved_patch.rs `held_by_friction`), one block
/// per rank: the in-process rows, forces and displacements.
#[test]
fn coulomb_on_curved_quadratic_mortar_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let interface = "discretization = \"mortar\"\nfriction = { coulomb = 1.0 }";
    let text = common::curved_patch::held_by_friction("hex20_3", "hex20_4", interface, true);
    compare_curved("curved_coulomb", &text);
}

/// Coulomb μ = 1 on curved quadratic mortar with the rollers of both
/// blocks on the symmetry planes x = 0, y = 0 (tests/common/curved_patch.rs
/// `rollers_on_both`: the tangential directions across the planes carry no
/// friction unknown), one block per rank: the in-process rows, forces and
/// displacements.
#[test]
fn coulomb_on_curved_mortar_with_rollers_on_both_bodies_under_mpirun_2_equals_the_in_process_run() {
    require_mpirun!();
    let interface = "discretization = \"mortar\"\nfriction = { coulomb = 1.0 }";
    let text = common::curved_patch::rollers_on_both("hex20_3", "hex20_4", interface);
    compare_curved("curved_rollers", &text);
}
