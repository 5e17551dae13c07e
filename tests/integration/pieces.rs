//! `[output] pieces`: each subdomain's VTU piece with a
//! `.pvtu` index per body and step, beside the gathered files, which stay
//! byte for byte as without it. In one process (condensed and direct
//! paths) here; under `mpirun -n 2` in tests/mpi.rs.

use crate::common;

use common::{
    check_stack_pieces, cli_run, cli_run_ok, fresh_dir, listing, signorini, stack_pieces as stack,
};

#[test]
fn pieces_in_one_process_equal_the_gathered_fields_which_do_not_change() {
    let dir = fresh_dir("pieces", "local");
    for on in [false, true] {
        std::fs::write(dir.join(format!("{on}.toml")), stack(on)).unwrap();
        cli_run_ok(
            dir.join(format!("{on}.toml")),
            dir.join(format!("out-{on}")),
        );
    }
    let (off, on) = (dir.join("out-false"), dir.join("out-true"));
    check_stack_pieces(&on);
    let gathered = listing(&off);
    assert!(!gathered
        .iter()
        .any(|f| f.contains("pvtu") || f.starts_with("pieces")));
    for f in gathered.iter().filter(|f| *f != "report.json") {
        let same = std::fs::read(off.join(f)).unwrap() == std::fs::read(on.join(f)).unwrap();
        assert!(same, "{f} differs with pieces = true");
    }
    let mut with: Vec<String> = listing(&on);
    with.retain(|f| !f.ends_with(".pvtu") && f != "pieces" && f != "pieces.pvd");
    assert_eq!(with, gathered);
}

/// The direct path has no subdomain solves, but the same METIS parts: the
/// root writes the same pieces from the whole displacement.
#[test]
fn the_direct_path_writes_the_same_pieces() {
    let dir = fresh_dir("pieces", "direct");
    std::fs::write(dir.join("s.toml"), stack(true)).unwrap();
    let out = dir.join("out");
    let o = signorini(&[
        "run",
        dir.join("s.toml").to_str().unwrap(),
        "--path",
        "direct",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    check_stack_pieces(&out);
}

/// Bad input met at step 2, after step 1 wrote its pieces: exit 1 and
/// nothing on disk; `pieces` not a boolean: exit 1 naming it.
#[test]
fn errors_leave_no_pieces_behind() {
    let dir = fresh_dir("pieces", "errors");
    let late = common::floating_pulled_off_at_step_2("[output]\npieces = true\n\n");
    let bad = stack(true).replace("pieces = true", "pieces = \"yes\"");
    for (tag, text, says) in [("late", late, "step 2"), ("bad", bad, "pieces")] {
        let scene = dir.join(format!("{tag}.toml"));
        std::fs::write(&scene, text).unwrap();
        let out = dir.join(tag).join("out");
        let o = cli_run(&scene, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{tag}: {err}");
        assert!(err.contains(says), "{tag}: {err}");
        assert!(!dir.join(tag).exists(), "{tag}: wrote output");
    }
}
