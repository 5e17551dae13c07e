//! The scene's entries and mesh files: each test writes a tiny scene into its own directory under
//! `CARGO_TARGET_TMPDIR` and runs the real binary on it with `--out DIR/out`.

use super::{block_from_file, BOX_ON_PLANE};
use crate::common;

use common::bad_scene::{
    block_with, fresh_dir, run_in, run_scene, scene_dir, Run, BLOCK_ON_PLANE, PIN,
};
use common::BIN;
use std::path::Path;
use std::process::Command;

#[test]
fn base_scene_is_valid() {
    // Guards the other tests: they fail for the one thing they change.
    let run = run_scene("base_scene_is_valid", Some(&BLOCK_ON_PLANE), &[]);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
    assert!(
        run.out_dir().join("report.json").is_file(),
        "{}",
        run.describe()
    );
}

#[test]
fn missing_scene_file() {
    let run = run_scene("missing_scene_file", None, &[]);
    run.assert_bad_input(&["scene.toml"]);
}

/// One edit of the base scene each, refused naming the entry: the test
/// directory, what is replaced, by what, and what the error must name.
#[test]
fn one_edit_of_the_base_scene_is_refused_naming_the_entry() {
    #[rustfmt::skip]
    let cases: [(&str, &str, &str, &[&str]); 13] = [
        ("toml_syntax_error_names_the_line", "young = 1.0", "young = = 1.0", &["line"]),
        ("unknown_key_in_materials", "poisson = 0.3\n", "poisson = 0.3\ncolour = \"grey\"\n", &["colour", "line"]),
        ("unknown_body_in_boundary", "name = \"press\"\nbody = \"block\"", "name = \"press\"\nbody = \"blok\"", &["blok", "boundary[1]"]),
        ("unknown_surface_lists_valid_ones", "surface = \"top\"", "surface = \"lid\"", &["lid", "top", "bottom"]),
        ("unknown_material_name", "material = \"steel\"", "material = \"unobtainium\"", &["unobtainium", "bodies[0].material"]),
        ("young_modulus_zero", "young = 1.0", "young = 0.0", &["materials[0].young"]),
        ("young_modulus_negative", "young = 1.0", "young = -2.0", &["materials[0].young"]),
        ("poisson_ratio_one_half", "poisson = 0.3", "poisson = 0.5", &["materials[0].poisson"]),
        ("poisson_ratio_minus_one", "poisson = 0.3", "poisson = -1.0", &["materials[0].poisson"]),
        // No Dirichlet condition in y: the block is held by the contact alone, and
        // the traction pulls it away from the plane.
        ("block_pulled_off_the_plane_cannot_be_in_equilibrium", "traction = [0.0, -1.0]", "traction = [0.0, 1.0]", &["block", "equilibrium"]),
        // Pressed down onto the plane (so the normal direction is fine) but with
        // no support in x at all: frictionless contact cannot hold a sideways
        // motion, so the problem is singular; the error must name the body.
        ("block_without_support_in_x_is_rejected", PIN, "", &["block"]),
        ("contact_slave_surface_does_not_exist", "slave = { body = \"block\", surface = \"bottom\" }", "slave = { body = \"block\", surface = \"underside\" }", &["underside", "block-ground", "bottom"]),
        ("fractional_divisions", "divisions = [4, 2]", "divisions = [8.5, 4]", &["mesh.divisions: expected positive whole numbers", "got 8.5"]),
    ];
    for (test, from, to, needles) in cases {
        let run = run_scene(test, Some(&block_with(from, to)), &[]);
        eprintln!("case {test}");
        run.assert_bad_input(needles);
    }
}

/// Scenes other than an edit of the base one, refused naming the entry: a
/// key before it, no body at all, a step scaling a condition it lacks.
#[test]
fn a_key_before_the_base_scene_no_body_or_an_unknown_step_scale_is_named() {
    #[rustfmt::skip]
    let cases: [(&str, String, &[&str]); 3] = [
        ("unknown_top_level_key", format!("frobnicate = 1\n{BLOCK_ON_PLANE}"), &["frobnicate", "line"]),
        ("scene_without_bodies", "dimension = 2\n".to_string(), &["bodies"]),
        ("step_scale_names_unknown_boundary", format!("{BLOCK_ON_PLANE}\n[[steps]]\nscale = {{ squeeze = 0.5 }}\n"), &["squeeze", "steps[0]"]),
    ];
    for (test, scene, needles) in cases {
        eprintln!("case {test}");
        run_scene(test, Some(&scene), &[]).assert_bad_input(needles);
    }
}

#[test]
fn unknown_method_on_command_line() {
    // clap rejects the value (its usage-error code is 2); only require failure.
    let run = run_scene(
        "unknown_method_on_command_line",
        Some(&BLOCK_ON_PLANE),
        &["--method", "nonsense"],
    );
    assert!(!run.output.status.success(), "{}", run.describe());
    assert!(
        run.stderr().contains("nonsense"),
        "stderr does not name the bad value\n{}",
        run.describe()
    );
    run.assert_nothing_written();
}

/// `signorini check` on the shipped examples: exit 0 and nothing written.
fn check_example(test: &str, example: &str) {
    let dir = fresh_dir(test);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(example);
    let output = Command::new(BIN)
        .arg("check")
        .arg(&scene)
        .current_dir(&dir)
        .output()
        .expect("cannot start the signorini binary");
    assert_eq!(
        output.status.code(),
        Some(0),
        "check {} failed\n--- stdout ---\n{}\n--- stderr ---\n{}",
        scene.display(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    // The default output directory (out/<stem>) is relative to the working
    // directory, which is this empty one: it must stay empty.
    let written: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert!(written.is_empty(), "check wrote {written:?}");
}

#[test]
fn check_accepts_hertz2d_and_writes_nothing() {
    check_example("check_accepts_hertz2d_and_writes_nothing", "hertz2d.toml");
}

#[test]
fn check_accepts_blocks_and_writes_nothing() {
    check_example("check_accepts_blocks_and_writes_nothing", "blocks.toml");
}

/// A Gmsh 2.2 file holding one 9-node quadrangle (Gmsh type 10), which the
/// solver does not support.
const QUAD9_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0 0\n6 1 0.5 0\n7 0.5 1 0\n8 0 0.5 0\n9 0.5 0.5 0\n$EndNodes\n$Elements\n1\n1 10 2 1 1 1 2 3 4 5 6 7 8 9\n$EndElements\n";

/// `signorini COMMAND` (`run` with `--out DIR/out`) on the base scene
/// meshed by the Gmsh file `name` of text `msh`, in a fresh directory for
/// `test`.
fn on_gmsh_file(test: &str, command: &str, (name, msh): (&str, &str)) -> Run {
    let dir = scene_dir(test, &block_from_file(name), &[(name, msh)]);
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let extra: &[&str] = if command == "run" {
        &["--out", out]
    } else {
        &[]
    };
    run_in(dir, command, extra)
}

#[test]
fn gmsh_file_with_an_unsupported_element_type_is_named_and_counted() {
    let run = on_gmsh_file("gmsh_unsupported", "run", ("quad9.msh", QUAD9_MSH));
    run.assert_bad_input(&["bodies[0].mesh", "9-node quadrangle", "1"]);
}

#[test]
fn check_reads_the_gmsh_files_run_would_refuse() {
    // `check` said "valid scene" (exit 0) for a scene whose Gmsh file `run`
    // refuses: it did not read file meshes at all.
    let run = on_gmsh_file("check_gmsh_unsupported", "check", ("quad9.msh", QUAD9_MSH));
    run.assert_bad_input(&[
        "bodies[0].mesh",
        "9-node quadrangle",
        "SecondOrderIncomplete",
    ]);
}

/// `BLOCK_ON_PLANE`'s block as two quadrangles stacked at y = 0.25 that do
/// not share their nodes there (nodes 3, 4 and 5, 6 at the same places): a
/// Gmsh mesh of two surfaces not made coherent.
const UNJOINED_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"bottom\"\n1 2 \"top\"\n2 3 \"block\"\n1 4 \"left\"\n$EndPhysicalNames\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 0.25 0\n4 0 0.25 0\n5 0 0.25 0\n6 1 0.25 0\n7 1 0.5 0\n8 0 0.5 0\n$EndNodes\n$Elements\n6\n1 1 2 1 1 1 2\n2 1 2 2 2 7 8\n3 3 2 3 3 1 2 3 4\n4 3 2 3 3 5 6 7 8\n5 1 2 4 4 4 1\n6 1 2 4 4 8 5\n$EndElements\n";

/// A body whose Gmsh mesh has distinct nodes at the same place is free to
/// move because its parts are not joined: the refusal says so, with the
/// first pair and how to merge them. Found by the fifth robustness sweep:
/// it advised only to pin the body, which would have left the two parts
/// unjoined (solved as one body in two pieces).
#[test]
fn a_free_body_whose_mesh_has_unjoined_parts_says_so() {
    let run = on_gmsh_file("gmsh_unjoined", "run", ("unjoined.msh", UNJOINED_MSH));
    run.assert_bad_input(&[
        "bodies[0]",
        "is free to move",
        "its mesh has 2 pair(s) of distinct nodes at the same place (the first: nodes 2 and 5 at (1, 0.25))",
        "Coherence Mesh",
    ]);
}

/// The same mesh held on its left side and pressed by a displacement of its
/// top: both parts are held, the upper one moves down alone and the contact
/// carries nothing. It runs (a body may have separate pieces), and the
/// report's messages say that its parts are not joined.
#[test]
fn a_held_body_whose_mesh_has_unjoined_parts_is_noted() {
    let scene = block_from_file("unjoined.msh")
        .replace(PIN, "[[boundary]]\nname = \"left\"\nbody = \"block\"\nsurface = \"left\"\ndisplacement = { x = 0.0 }\n")
        .replace("traction = [0.0, -1.0]", "displacement = { y = -0.001 }");
    assert!(scene.contains("surface = \"left\"") && scene.contains("y = -0.001"));
    let dir = scene_dir(
        "gmsh_unjoined_held",
        &scene,
        &[("unjoined.msh", UNJOINED_MSH)],
    );
    let out = dir.join("out");
    let run = run_in(dir, "run", &["--out", out.to_str().unwrap()]);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.stderr());
    let report = std::fs::read_to_string(out.join("report.json")).unwrap();
    assert!(
        report.contains(
            "body \\\"block\\\": its mesh has 2 pair(s) of distinct nodes at the same place"
        ),
        "{report}"
    );
}

/// The shipped block2d.msh: it names bottom, top, left, right.
fn block2d_msh() -> String {
    format!("{}/examples/meshes/block2d.msh", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn gmsh_file_without_the_surface_the_scene_names() {
    let scene =
        block_from_file(&block2d_msh()).replace("surface = \"bottom\"", "surface = \"base\"");
    let run = run_scene("gmsh_missing_surface", Some(&scene), &[]);
    run.assert_bad_input(&["base", "bottom"]);
}

/// `signorini check` refuses a surface its body's mesh does not have, as
/// `run` does (it said "valid scene"): a generator's surfaces, and a Gmsh
/// file's physical groups; exit 1 naming the entry and the valid names.
#[test]
fn check_refuses_a_surface_the_mesh_does_not_have() {
    let generated = block_with("surface = \"top\"", "surface = \"lid\"");
    let dir = scene_dir("check_generator_surface", &generated, &[]);
    run_in(dir, "check", &[]).assert_bad_input(&[
        "boundary[",
        "\"lid\"",
        "bottom, left, right, top",
    ]);
    let from_file =
        block_from_file(&block2d_msh()).replace("surface = \"bottom\"", "surface = \"base\"");
    let dir = scene_dir("check_gmsh_surface", &from_file, &[]);
    run_in(dir, "check", &[]).assert_bad_input(&["contact[0].slave.surface", "\"base\"", "bottom"]);
}

/// `signorini check` refuses what `run` refuses before it builds anything,
/// and `run` refuses a reference the scene's model cannot be compared with
/// before solving (found by a fourth robustness sweep: check said "valid
/// scene" for friction on the direct path and for a reference of another
/// model, which run refused at once, or only after the whole solve; and for
/// mortar or contact elements against a rigid master and the friction status
/// method in 3D, which run refused once it had built the model).
#[test]
fn check_and_run_refuse_the_solver_choice_and_reference_up_front() {
    let friction = block_with(
        "discretization = \"node_to_segment\"\n",
        "discretization = \"node_to_segment\"\nfriction = { norton_hoff = 0.3, rho = 0.2 }\n",
    );
    // the direct path solves Tresca and Coulomb friction, not Norton–Hoff's law
    let direct = format!("{friction}\n[solver]\npath = \"direct\"\n");
    let needles = ["contact \"block-ground\".friction", "path = \"condensed\""];
    for command in ["check", "run"] {
        let dir = scene_dir(&format!("check_plan_direct_{command}"), &direct, &[]);
        run_in(dir, command, &[]).assert_bad_input(&needles);
    }
    let dir = scene_dir("check_plan_direct_flag", &friction, &[]);
    run_in(dir, "check", &["--path", "direct"]).assert_bad_input(&needles);
    let sphere = format!("{BLOCK_ON_PLANE}\n[reference]\nkind = \"hertz_sphere\"\nradius = 1.0\n");
    let sliding = format!("{BLOCK_ON_PLANE}\n[reference]\nkind = \"sliding_block\"\n");
    let discretized = |d: &str| block_with("\"node_to_segment\"", d);
    let friction_status_3d = BOX_ON_PLANE.replacen(
        "master = { body = \"ground\" }",
        "master = { body = \"ground\" }\nfriction = { coulomb = 0.3 }\n[solver]\nfriction = \"status\"",
        1,
    );
    let cases = [
        ("sphere", sphere, ["reference.kind", "\"hertz_cylinder\""]),
        (
            "sliding",
            sliding,
            ["reference.friction", "sliding_block needs μ"],
        ),
        (
            "mortar_rigid",
            discretized("\"mortar\""),
            [
                "contact \"block-ground\"",
                "mortar needs a deformable master",
            ],
        ),
        (
            "elements_rigid",
            discretized("\"contact_elements\"\nlaw = { penalty = 1e3 }"),
            [
                "contact \"block-ground\"",
                "contact elements join two deformable bodies",
            ],
        ),
        (
            "friction_status_3d",
            friction_status_3d,
            ["solver.friction", "2D only"],
        ),
    ];
    for (name, scene, needles) in cases {
        for command in ["check", "run"] {
            let dir = scene_dir(&format!("check_reference_{name}_{command}"), &scene, &[]);
            run_in(dir, command, &[]).assert_bad_input(&needles);
        }
    }
}

#[test]
fn gmsh_file_that_does_not_exist() {
    let run = run_scene(
        "gmsh_missing_file",
        Some(&block_from_file("nowhere.msh")),
        &[],
    );
    run.assert_bad_input(&["bodies[0].mesh", "nowhere.msh"]);
}

// ---------------------------------------------------------------- item 6

#[test]
fn negative_divisions_name_the_key_the_value_and_what_is_valid() {
    let scene = block_with("divisions = [4, 2]", "divisions = [-8, 4]");
    let run = run_scene("negative_divisions", Some(&scene), &[]);
    run.assert_bad_input(&["mesh.divisions: expected positive whole numbers", "got -8"]);
    assert!(!run.stderr().contains("usize"), "{}", run.describe());
}

#[test]
fn nan_and_inf_in_a_mesh_name_the_entry() {
    for (test, from, to, entry) in [
        (
            "nan_size",
            "size = [1.0, 0.5]",
            "size = [nan, 0.5]",
            "bodies[0].mesh.size",
        ),
        (
            "inf_origin",
            "origin = [0.0, 0.0]",
            "origin = [0.0, inf]",
            "bodies[0].mesh.origin",
        ),
        (
            "nan_grading",
            "divisions = [4, 2]",
            "divisions = [4, 2], grading = { towards = \"top\", ratio = nan }",
            "bodies[0].mesh.grading.ratio",
        ),
    ] {
        let run = run_scene(test, Some(&block_with(from, to)), &[]);
        run.assert_bad_input(&[entry, "must be"]);
        assert!(!run.stderr().contains("null"), "{}", run.describe());
    }
}

/// A JSON scene's type error names the key, as a TOML scene's does (serde_json
/// alone gave only a line and column).
#[test]
fn a_json_type_error_names_its_key() {
    let json = r#"{"title": "t", "dimension": 2, "model": "plane_strain",
        "materials": [{"name": "steel", "young": "x", "poisson": 0.3}]}"#;
    let err = signorini_scene::parse_json(json).unwrap_err().to_string();
    assert!(err.contains("`materials[0].young`"), "{err}");
    assert!(err.contains("expected f64"), "{err}");
    let at_top = signorini_scene::parse_json("{}").unwrap_err().to_string();
    assert!(at_top.contains("missing field `dimension`"), "{at_top}");
}
