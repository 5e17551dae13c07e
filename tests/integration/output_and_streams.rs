//! The run's surroundings as bad input: an output directory that cannot be
//! written is refused before solving (exit 1), a bad command-line value is
//! exit 1 (not clap's 2, which means "not converged"), a device given as a
//! scene or a mesh is refused instead of read forever, two bodies whose
//! output files would collide are refused, and a closed or full stdout
//! loses the summary, not the run.

use crate::common;

use common::bad_scene::{block_meshed, fresh_dir, run_scene, BLOCK_ON_PLANE};
use common::{run_limited, BIN};
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, SolveError};
use std::process::{Command, Stdio};
use std::time::Duration;

fn block_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, BLOCK_ON_PLANE).unwrap();
    scene
}

#[test]
fn an_output_directory_that_is_a_file_is_refused_before_solving() {
    let dir = fresh_dir("out_is_a_file");
    let scene = block_scene(&dir);
    let file = dir.join("out");
    std::fs::write(&file, "keep me").unwrap();
    for out in [file.clone(), file.join("sub")] {
        let run = Command::new(BIN)
            .args(["run", "-q"])
            .arg(&scene)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{err}");
        assert!(err.contains("output directory"), "{err}");
        assert!(err.contains("exists and is not a directory"), "{err}");
        assert!(err.contains("--out"), "{err}");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");
    }
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(left.len(), 2, "only the scene and the file: {left:?}");
}

#[test]
fn bad_command_line_values_are_bad_input_and_help_is_not_an_error() {
    let dir = fresh_dir("bad_flags");
    let scene = block_scene(&dir);
    for flags in [
        ["--max-memory", "garbage"],
        ["--method", "no_such_method"],
        ["--path", "sideways"],
    ] {
        let run = Command::new(BIN)
            .arg("run")
            .arg(&scene)
            .args(flags)
            .arg("--out")
            .arg(dir.join("out"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{flags:?}: {err}");
        assert!(err.contains(flags[0]) && err.contains(flags[1]), "{err}");
        assert!(!dir.join("out").exists());
    }
    let help = Command::new(BIN).args(["run", "--help"]).output().unwrap();
    assert_eq!(help.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&help.stdout).contains("--max-memory"));
}

#[test]
fn a_device_as_mesh_or_scene_is_refused_not_read_forever() {
    let mesh = block_meshed("{ file = \"/dev/zero\" }");
    let dir = fresh_dir("device_mesh");
    std::fs::write(dir.join("scene.toml"), &mesh).unwrap();
    let mut cmd = Command::new(BIN);
    cmd.arg("run")
        .arg(dir.join("scene.toml"))
        .arg("--out")
        .arg(dir.join("out"));
    let (out, _) = run_limited(cmd, Duration::from_secs(60));
    let needles = ["bodies[0].mesh.file", "not a regular file"];
    common::assert_refused_unwritten(&out, &needles, &dir.join("out"));

    let mut cmd = Command::new(BIN);
    cmd.args(["run", "/dev/zero", "--out"]).arg(dir.join("out"));
    let (out, _) = run_limited(cmd, Duration::from_secs(60));
    let needles = ["/dev/zero", "not a scene file"];
    common::assert_refused_unwritten(&out, &needles, &dir.join("out"));
}

#[test]
fn bodies_whose_output_files_would_collide_or_not_fit_a_file_name_are_refused() {
    // The block renamed "a/b", and a copy of it named "a_b" beside it.
    let renamed = BLOCK_ON_PLANE.replace("\"block\"", "\"a/b\"");
    let second = "\n[[bodies]]\nname = \"a_b\"\nmaterial = \"steel\"\nmesh = { generator = \"rectangle\", origin = [3.0, 0.0], size = [1.0, 0.5], divisions = [2, 1] }\n";
    let run = run_scene("stem_collision", Some(&format!("{renamed}{second}")), &[]);
    run.assert_bad_input(&[
        "bodies[2].name",
        "bodies[0].name",
        "a_b_<step>.vtu",
        "rename",
    ]);

    let long = "b".repeat(101);
    let scene = BLOCK_ON_PLANE.replace("\"block\"", &format!("\"{long}\""));
    let run = run_scene("long_name", Some(&scene), &[]);
    run.assert_bad_input(&["bodies[0].name", "101 characters", "at most 100"]);
}

#[test]
fn a_full_stdout_loses_the_summary_not_the_run() {
    let dir = fresh_dir("full_stdout");
    let scene = block_scene(&dir);
    let run = Command::new(BIN)
        .args(["run", "-q"])
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .stdout(Stdio::from(std::fs::File::create("/dev/full").unwrap()))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{err}");
    assert!(!err.contains("internal error"), "{err}");
    let report = std::fs::read_to_string(dir.join("out/report.json")).unwrap();
    assert!(report.contains("\"converged\": true"), "{report}");
}

/// The files in `dir` and `dir/pieces`, sorted.
fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names = common::listing(dir);
    if dir.join("pieces").is_dir() {
        names.extend(
            common::listing(&dir.join("pieces"))
                .iter()
                .map(|n| format!("pieces/{n}")),
        );
    }
    names.sort();
    names
}

/// A run into the directory of an earlier one with more steps, pieces and
/// fields removes the earlier files it does not write again, and nothing
/// else. Found by the fifth robustness sweep: after a 3-step run, a 1-step
/// run with `fields = []` left the earlier fields.pvd (naming the earlier
/// VTU files), displacement.csv, stress.csv and pieces beside its report,
/// so ParaView and scripts read the earlier answer.
#[test]
fn a_run_removes_the_files_an_earlier_run_left_that_it_does_not_write() {
    let dir = fresh_dir("stale_outputs");
    let out = dir.join("out");
    let three = dir.join("three.toml");
    let steps = "[[steps]]\nscale = { press = 1.0 }\n".repeat(3);
    std::fs::write(
        &three,
        format!("{BLOCK_ON_PLANE}\n{steps}\n[output]\npieces = true\n"),
    )
    .unwrap();
    common::cli_run_ok(&three, &out);
    assert_eq!(
        listing(&out).len(),
        3 + 3 * 2 + 3 + 5,
        "{:?}",
        listing(&out)
    );
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    std::fs::write(out.join("other_2.vtu"), "mine").unwrap();
    let one = dir.join("one.toml");
    std::fs::write(&one, format!("{BLOCK_ON_PLANE}\n[output]\nfields = []\n")).unwrap();
    common::cli_run_ok(&one, &out);
    assert_eq!(
        listing(&out),
        [
            "contact.csv",
            "notes.txt",
            "other_2.vtu",
            "report.json",
            "steps.csv"
        ]
    );
    let report = std::fs::read_to_string(out.join("report.json")).unwrap();
    assert!(
        report.contains("removed 13 file(s) an earlier run left in"),
        "{report}"
    );
    // Fields again, one step: its VTU file and series alone.
    std::fs::write(&one, BLOCK_ON_PLANE).unwrap();
    common::cli_run_ok(&one, &out);
    let pvd = std::fs::read_to_string(out.join("fields.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 1, "{pvd}");
    assert!(listing(&out).contains(&"block_1.vtu".to_string()));
}

/// The columns `names` of every row of a CSV file, by header name.
fn csv_columns(path: &std::path::Path, names: &[&str]) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at: Vec<usize> = (names.iter())
        .map(|n| {
            header
                .iter()
                .position(|h| h == n)
                .unwrap_or_else(|| panic!("no {n}: {header:?}"))
        })
        .collect();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            at.iter().map(|&i| f[i].to_string()).collect()
        })
        .collect()
}

/// steps.csv in 3D has the whole resultant and the second tangent, as
/// contact.csv does: each step's force_z is the report's, and equals the
/// sum of contact.csv's normal forces on the plane z = 0; its
/// tangential_force_2 is the sum of contact.csv's. Found by the fifth
/// robustness sweep: force_z was missing (a 3D box pressed on a plane had
/// no normal resultant in steps.csv), and the tangential sum and the mean
/// slip were along the first tangent alone (dragged along y, the box showed
/// a tangential force of 0.035 for 0.22).
#[test]
fn steps_csv_in_3d_has_the_z_resultant_and_the_second_tangent() {
    let dir = fresh_dir("steps_csv_3d");
    let out = dir.join("out");
    common::cli_run_ok(common::example_path("sliding3d.toml"), &out);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let steps = csv_columns(
        &out.join("steps.csv"),
        &["step", "force_z", "tangential_force_2"],
    );
    let rows = csv_columns(
        &out.join("contact.csv"),
        &["step", "normal_force", "tangential_force_2"],
    );
    assert_eq!(steps.len(), 3);
    let num = |s: &str| s.parse::<f64>().unwrap();
    for (i, s) in steps.iter().enumerate() {
        let of_step = rows.iter().filter(|r| r[0] == s[0]);
        let (n, t2) = of_step.fold((0.0, 0.0), |(n, t), r| (n + num(&r[1]), t + num(&r[2])));
        let z = report["steps"][i]["contact_force"][2].as_f64().unwrap();
        assert_eq!(num(&s[1]), z, "step {}", i + 1);
        assert!(
            (z - n).abs() <= 1e-12 * n,
            "step {}: {z} against {n}",
            i + 1
        );
        assert!((num(&s[2]) - t2).abs() <= 1e-12 * n, "step {}", i + 1);
    }
    // The last step drags along y (the second tangent): about -0.218.
    assert!(num(&steps[2][2]) < -0.2, "{:?}", steps[2]);
    // The method of each step, as report.json's step entry says (appended
    // columns): the Newton method on Coulomb's law, no fallback.
    let methods = csv_columns(&out.join("steps.csv"), &["method", "fallback"]);
    for (i, m) in methods.iter().enumerate() {
        let step = &report["steps"][i];
        assert_eq!(m[0], step["method"].as_str().unwrap(), "step {}", i + 1);
        assert_eq!(step["method"], step["solver"]["method"]);
        assert_eq!(m[0], "coulomb_3d_semismooth_newton");
        assert!(m[1].is_empty() && step["fallback"].is_null(), "{m:?}");
    }
}

/// The scenes of examples/, by file name, sorted.
fn shipped_examples() -> Vec<String> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut names = common::listing(&dir);
    names.retain(|n| n.ends_with(".toml"));
    names
}

/// The bodies of a scene held by prescribed displacements alone (no force
/// or traction entry): their reactions balance their contact forces.
fn pressed_bodies(sc: &signorini_scene::Scene) -> Vec<String> {
    sc.bodies
        .iter()
        .filter(|b| b.is_deformable())
        .filter(|b| {
            let mut entries = sc.boundary.iter().filter(|e| e.body == b.name).peekable();
            entries.peek().is_some() && entries.all(|e| e.displacement.is_some())
        })
        .map(|b| b.name.clone())
        .collect()
}

/// At every step, the reactions on `body` plus the contact forces on it
/// (as slave, minus as master) vanish, relative to the largest contact
/// resultant of the step; returns the largest relative residual.
fn reaction_balance(
    sc: &signorini_scene::Scene,
    out: &signorini_solver::RunOutput,
    body: &str,
) -> f64 {
    let mut worst = 0.0f64;
    for step in &out.report.steps {
        let dim = step.contacts[0].force.len();
        let mut sum = vec![0.0; dim];
        for r in step.reactions.iter().filter(|r| r.body == body) {
            (0..dim).for_each(|k| sum[k] += r.force[k]);
        }
        let mut scale = 0.0f64;
        for (c, entry) in step.contacts.iter().zip(&sc.contact) {
            assert_eq!(c.name, entry.name);
            let sign = match (entry.slave.body == body, entry.master.body == body) {
                (true, false) => 1.0,
                (false, true) => -1.0,
                _ => 0.0,
            };
            (0..dim).for_each(|k| sum[k] += sign * c.force[k]);
            scale = c.force.iter().fold(scale, |m, f| m.max(f.abs()));
        }
        let residual = sum.iter().fold(0.0f64, |m, f| m.max(f.abs()));
        worst = worst.max(residual / scale.max(f64::MIN_POSITIVE));
    }
    worst
}

/// The reaction of a pressed face is the contact force it transmits: on
/// every shipped example, each body held by prescribed displacements alone
/// has Σ reactions + its contact force = 0 to 1e-8 of the contact force at
/// every step, on the condensed path and (where the scene allows it) the
/// direct one; 2D, axisymmetric (whole rings) and 3D among them.
#[test]
fn the_reaction_of_a_pressed_face_is_the_contact_force_it_transmits() {
    let mut checked = Vec::new();
    for name in shipped_examples() {
        let text = common::example_with_meshes(&name);
        let sc = signorini_scene::parse_toml(&text).unwrap();
        let bodies = pressed_bodies(&sc);
        if bodies.is_empty() {
            continue;
        }
        for path in [SolvePath::Condensed, SolvePath::Direct] {
            let opts = RunOptions {
                method: None,
                path: Some(path),
            };
            let out = match common::try_run(&text, opts) {
                Ok(out) => out,
                // friction and contact elements: condensed path only
                Err(SolveError::Input(_)) if path == SolvePath::Direct => continue,
                Err(e) => panic!("{name}: {e}"),
            };
            assert!(out.report.converged, "{name}: {:?}", out.report.failure);
            for body in &bodies {
                let r = reaction_balance(&sc, &out, body);
                assert!(r <= 1e-8, "{name} {path:?} {body}: {r:e}");
                checked.push(format!("{name} {path:?} {body}"));
            }
        }
    }
    for expected in [
        "hertz2d.toml Condensed cylinder",
        "hertz2d.toml Direct cylinder",
        "hertz_axi.toml Condensed sphere",
        "hertz_axi.toml Direct sphere",
        "hertz3d.toml Direct sphere",
        "flat_punch.toml Condensed punch",
        "sliding3d.toml Condensed box",
        "cyclic.toml Condensed block",
        "stack.toml Condensed roller",
    ] {
        assert!(
            checked.iter().any(|c| c == expected),
            "{expected}: {checked:?}"
        );
    }
}

/// The moment of a reaction: about `moment_about` it is the moment about
/// the origin minus p × F, and about the origin it balances the moments
/// of the contact forces at their points (contact.csv's positions, forces
/// and frame): examples/sliding3d.toml (3D, friction) and
/// examples/flat_punch.toml (2D).
#[test]
fn the_moment_of_a_reaction_balances_the_contact_forces_and_moves_with_its_point() {
    for (name, body, p) in [
        ("sliding3d.toml", "box", [0.3f64, -0.2, 0.7]),
        ("flat_punch.toml", "punch", [0.25, 1.5, 0.0]),
    ] {
        let text = common::example(name);
        let out = common::converged(&text, RunOptions::default());
        let sc = signorini_scene::parse_toml(&text).unwrap();
        let dim = sc.dimension as usize;
        let last = out.report.steps.len();
        let step = out.report.steps.last().unwrap();
        let cross = |r: [f64; 3], f: [f64; 3]| {
            [
                r[1] * f[2] - r[2] * f[1],
                r[2] * f[0] - r[0] * f[2],
                r[0] * f[1] - r[1] * f[0],
            ]
        };
        let mut contact = [0.0f64; 3];
        let mut lever = p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for row in out
            .contact_rows
            .iter()
            .filter(|r| r.step == last && r.body == body)
        {
            let t = row.tangential_vector();
            let f = [0, 1, 2].map(|k| row.normal_force * row.normal[k] + t[k]);
            let m = cross(row.x, f);
            (0..3).for_each(|k| contact[k] += m[k]);
            lever = row.x.iter().fold(lever, |m, x| m.max(x.abs()));
        }
        let axes = if dim == 2 { 2..3 } else { 0..3 };
        let mut reaction = [0.0f64; 3];
        let mut force = [0.0f64; 3];
        for r in step.reactions.iter().filter(|r| r.body == body) {
            assert_eq!(r.moment_about.as_deref(), Some(&[0.0; 3][..dim]));
            let m = r.moment.as_ref().unwrap();
            for (k, a) in axes.clone().enumerate() {
                reaction[a] += m[k];
            }
            (0..dim).for_each(|k| force[k] += r.force[k]);
        }
        // a moment's scale: the force times the largest lever
        let scale = lever * force.iter().fold(0.0f64, |m, f| m.max(f.abs()));
        assert!(scale > 0.0, "{name}");
        for a in axes.clone() {
            assert!(
                (reaction[a] + contact[a]).abs() <= 1e-8 * scale,
                "{name} axis {a}: {reaction:?} {contact:?}"
            );
        }
        // The same scene with every entry of the body about p.
        let about = format!("moment_about = {:?}\n", &p[..dim]);
        let moved = text.replace(
            &format!("body = \"{body}\"\n"),
            &format!("body = \"{body}\"\n{about}"),
        );
        let moved = signorini_scene::parse_toml(&moved).unwrap();
        let moved_out = signorini_solver::run(
            &moved,
            "test",
            &RunOptions::default(),
            &signorini_comm::Local,
        )
        .unwrap()
        .unwrap();
        let shift = cross(p, force);
        let mut about_p = [0.0f64; 3];
        for r in &moved_out.report.steps.last().unwrap().reactions {
            if r.body == body {
                assert_eq!(r.moment_about.as_deref(), Some(&p[..dim]));
                for (k, a) in axes.clone().enumerate() {
                    about_p[a] += r.moment.as_ref().unwrap()[k];
                }
            }
        }
        for a in axes {
            let expected = reaction[a] - shift[a];
            assert!(
                (about_p[a] - expected).abs() <= 1e-10 * scale,
                "{name} axis {a}: {about_p:?} against {expected}"
            );
            assert!(expected.abs() > 1e-3 * scale, "{name} axis {a}: {expected}");
        }
    }
}

/// steps.csv has a column group per contact pair, named after it: read
/// back, each step's normal and tangential sums add up to the step's
/// totals and equal the report's, and the terminal lists each contact and
/// reaction. examples/stack.toml (three pairs, 2D) and
/// examples/sliding3d.toml (friction, the second tangent, 3D).
#[test]
fn steps_csv_has_each_contact_and_reaction_summing_to_the_totals() {
    let dir = fresh_dir("steps_csv_contacts");
    for (scene, contacts, tangents) in [
        (
            "stack.toml",
            &["roller-plate", "plate-base", "base-floor"][..],
            1,
        ),
        ("sliding3d.toml", &["box-floor"][..], 2),
    ] {
        let out = dir.join(scene);
        let run = common::cli_run_ok(common::example_path(scene), &out);
        let stdout = String::from_utf8_lossy(&run.stdout);
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap())
                .unwrap();
        let mut names = vec!["normal_force".to_string(), "tangential_force".to_string()];
        if tangents == 2 {
            names.push("tangential_force_2".into());
        }
        let mut columns = names.clone();
        for c in contacts {
            assert!(stdout.contains(&format!("contact \"{c}\"")), "{stdout}");
            columns.extend(names.iter().map(|n| format!("{n}_{c}")));
        }
        let refs: Vec<&str> = columns.iter().map(String::as_str).collect();
        let rows = csv_columns(&out.join("steps.csv"), &refs);
        assert_eq!(rows.len(), report["steps"].as_array().unwrap().len());
        let num = |s: &str| s.parse::<f64>().unwrap();
        for (i, row) in rows.iter().enumerate() {
            let total_normal = num(&row[0]);
            assert!(total_normal > 0.0, "{scene} step {}", i + 1);
            for (k, n) in names.iter().enumerate() {
                let parts: Vec<f64> = (0..contacts.len())
                    .map(|c| num(&row[names.len() * (c + 1) + k]))
                    .collect();
                let sum: f64 = parts.iter().sum();
                assert!(
                    (sum - num(&row[k])).abs() <= 1e-12 * total_normal,
                    "{scene} step {} {n}: {parts:?} against {}",
                    i + 1,
                    row[k]
                );
                for (c, part) in parts.iter().enumerate() {
                    let json = report["steps"][i]["contacts"][c][n].as_f64().unwrap();
                    assert!(
                        (part - json).abs() <= 1e-15 * total_normal,
                        "{scene} step {} {n}: {part} against {json}",
                        i + 1
                    );
                }
            }
        }
        let reactions = report["steps"][0]["reactions"].as_array().unwrap();
        assert!(!reactions.is_empty());
        for r in reactions {
            let name = r["boundary"].as_str().unwrap();
            assert!(stdout.contains(&format!("reaction \"{name}\"")), "{stdout}");
            let rows = csv_columns(&out.join("steps.csv"), &[&format!("reaction_y_{name}")]);
            let json = r["force"][1].as_f64().unwrap();
            assert!((num(&rows[0][0]) - json).abs() <= 4.0 * f64::EPSILON * json.abs());
        }
    }
    // sliding3d drags along y at its last step: its contact carries it.
    let rows = csv_columns(
        &dir.join("sliding3d.toml").join("steps.csv"),
        &["tangential_force_2_box-floor"],
    );
    assert!(rows[2][0].parse::<f64>().unwrap() < -0.2, "{rows:?}");
}
