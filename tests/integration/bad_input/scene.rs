//! Bad input is rejected up front (docs/reference/scene-format.md, "Commands"): `signorini run` exits
//! with code 1, prints one short error on stderr that names the offending entry
//! or key, and writes nothing, not even the output directory.
//!
//! Each test writes a tiny scene into its own directory under
//! `CARGO_TARGET_TMPDIR` and runs the real binary on it with `--out DIR/out`.

use crate::common;

use common::bad_scene::{
    block_meshed, block_with, block_with_all, fresh_dir, run_in, run_scene, scene_dir, BLOCK_MESH,
    BLOCK_ON_PLANE, PIN,
};
use common::{run_limited, BIN};
use std::path::Path;
use std::process::{Command, Output};
use std::time::Duration;

#[test]
fn base_scene_is_valid() {
    // Guards the other tests: they fail for the one thing they change.
    let run = run_scene("base_scene_is_valid", Some(BLOCK_ON_PLANE), &[]);
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

#[test]
fn toml_syntax_error_names_the_line() {
    let scene = block_with("young = 1.0", "young = = 1.0");
    let run = run_scene("toml_syntax_error_names_the_line", Some(&scene), &[]);
    run.assert_bad_input(&["line"]);
}

#[test]
fn unknown_top_level_key() {
    let scene = format!("frobnicate = 1\n{BLOCK_ON_PLANE}");
    let run = run_scene("unknown_top_level_key", Some(&scene), &[]);
    run.assert_bad_input(&["frobnicate", "line"]);
}

#[test]
fn unknown_key_in_materials() {
    let scene = block_with("poisson = 0.3\n", "poisson = 0.3\ncolour = \"grey\"\n");
    let run = run_scene("unknown_key_in_materials", Some(&scene), &[]);
    run.assert_bad_input(&["colour", "line"]);
}

#[test]
fn unknown_body_in_boundary() {
    let scene = block_with(
        "name = \"press\"\nbody = \"block\"",
        "name = \"press\"\nbody = \"blok\"",
    );
    let run = run_scene("unknown_body_in_boundary", Some(&scene), &[]);
    run.assert_bad_input(&["blok", "boundary[1]"]);
}

#[test]
fn unknown_surface_lists_valid_ones() {
    let scene = block_with("surface = \"top\"", "surface = \"lid\"");
    let run = run_scene("unknown_surface_lists_valid_ones", Some(&scene), &[]);
    run.assert_bad_input(&["lid", "top", "bottom"]);
}

#[test]
fn unknown_material_name() {
    let scene = block_with("material = \"steel\"", "material = \"unobtainium\"");
    let run = run_scene("unknown_material_name", Some(&scene), &[]);
    run.assert_bad_input(&["unobtainium", "bodies[0].material"]);
}

#[test]
fn young_modulus_zero() {
    let scene = block_with("young = 1.0", "young = 0.0");
    let run = run_scene("young_modulus_zero", Some(&scene), &[]);
    run.assert_bad_input(&["materials[0].young"]);
}

#[test]
fn young_modulus_negative() {
    let scene = block_with("young = 1.0", "young = -2.0");
    let run = run_scene("young_modulus_negative", Some(&scene), &[]);
    run.assert_bad_input(&["materials[0].young"]);
}

#[test]
fn poisson_ratio_one_half() {
    let scene = block_with("poisson = 0.3", "poisson = 0.5");
    let run = run_scene("poisson_ratio_one_half", Some(&scene), &[]);
    run.assert_bad_input(&["materials[0].poisson"]);
}

#[test]
fn poisson_ratio_minus_one() {
    let scene = block_with("poisson = 0.3", "poisson = -1.0");
    let run = run_scene("poisson_ratio_minus_one", Some(&scene), &[]);
    run.assert_bad_input(&["materials[0].poisson"]);
}

#[test]
fn scene_without_bodies() {
    let run = run_scene("scene_without_bodies", Some("dimension = 2\n"), &[]);
    run.assert_bad_input(&["bodies"]);
}

#[test]
fn block_pulled_off_the_plane_cannot_be_in_equilibrium() {
    // No Dirichlet condition in y: the block is held by the contact alone, and
    // the traction pulls it away from the plane.
    let scene = block_with("traction = [0.0, -1.0]", "traction = [0.0, 1.0]");
    let run = run_scene(
        "block_pulled_off_the_plane_cannot_be_in_equilibrium",
        Some(&scene),
        &[],
    );
    run.assert_bad_input(&["block", "equilibrium"]);
}

#[test]
fn block_without_support_in_x_is_rejected() {
    // Pressed down onto the plane (so the normal direction is fine) but with
    // no support in x at all: frictionless contact cannot hold a sideways
    // motion, so the problem is singular; the error must name the body.
    let scene = block_with(PIN, "");
    let run = run_scene("block_without_support_in_x_is_rejected", Some(&scene), &[]);
    run.assert_bad_input(&["block"]);
}

#[test]
fn step_scale_names_unknown_boundary() {
    let scene = format!("{BLOCK_ON_PLANE}\n[[steps]]\nscale = {{ squeeze = 0.5 }}\n");
    let run = run_scene("step_scale_names_unknown_boundary", Some(&scene), &[]);
    run.assert_bad_input(&["squeeze", "steps[0]"]);
}

#[test]
fn unknown_method_on_command_line() {
    // clap rejects the value (its usage-error code is 2); only require failure.
    let run = run_scene(
        "unknown_method_on_command_line",
        Some(BLOCK_ON_PLANE),
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

#[test]
fn contact_slave_surface_does_not_exist() {
    let scene = block_with(
        "slave = { body = \"block\", surface = \"bottom\" }",
        "slave = { body = \"block\", surface = \"underside\" }",
    );
    let run = run_scene("contact_slave_surface_does_not_exist", Some(&scene), &[]);
    run.assert_bad_input(&["underside", "block-ground", "bottom"]);
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

/// `BLOCK_ON_PLANE` meshed by the Gmsh file `file`.
fn block_from_file(file: &str) -> String {
    block_meshed(&format!("{{ file = \"{file}\" }}"))
}

#[test]
fn gmsh_file_with_an_unsupported_element_type_is_named_and_counted() {
    let files = [("quad9.msh", QUAD9_MSH)];
    let dir = scene_dir("gmsh_unsupported", &block_from_file("quad9.msh"), &files);
    let out = dir.join("out");
    let run = run_in(dir, "run", &["--out", out.to_str().unwrap()]);
    run.assert_bad_input(&["bodies[0].mesh", "9-node quadrangle", "1"]);
}

#[test]
fn check_reads_the_gmsh_files_run_would_refuse() {
    // `check` said "valid scene" (exit 0) for a scene whose Gmsh file `run`
    // refuses: it did not read file meshes at all.
    let files = [("quad9.msh", QUAD9_MSH)];
    let dir = scene_dir(
        "check_gmsh_unsupported",
        &block_from_file("quad9.msh"),
        &files,
    );
    run_in(dir, "check", &[]).assert_bad_input(&[
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
    let files = [("unjoined.msh", UNJOINED_MSH)];
    let dir = scene_dir("gmsh_unjoined", &block_from_file("unjoined.msh"), &files);
    let out = dir.join("out");
    let run = run_in(dir, "run", &["--out", out.to_str().unwrap()]);
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
        "discretization = \"node_to_segment\"\nfriction = { coulomb = 0.3 }\n",
    );
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

// ============================================================================
// No input crashes, hangs or allocates without a
// check, and every message names the key.
// ============================================================================

/// A 3D box resting on a rigid plane, pinned sideways at two corners, pressed
/// on its top: the 3D base of the sweep (it runs fine as it is).
const BOX_ON_PLANE: &str = r#"dimension = 3

[[materials]]
name = "steel"
young = 1.0
poisson = 0.3

[[bodies]]
name = "box"
material = "steel"
mesh = { generator = "box", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = [2, 2, 1] }

[[bodies]]
name = "ground"
rigid = { shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }

[[boundary]]
body = "box"
surface = "xmin"
displacement = { x = 0.0 }

[[boundary]]
body = "box"
surface = "ymin"
displacement = { y = 0.0 }

[[boundary]]
body = "box"
surface = "zmax"
traction = [0.0, 0.0, -1.0]

[[contact]]
name = "box-ground"
slave = { body = "box", surface = "zmin" }
master = { body = "ground" }
"#;

fn box_meshed(mesh: &str) -> String {
    let from = "mesh = { generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = [2, 2, 1] }";
    assert!(BOX_ON_PLANE.contains(from));
    BOX_ON_PLANE.replacen(from, &format!("mesh = {mesh}"), 1)
}

/// One entry of the sweep: a scene (and files beside it), extra arguments,
/// and what its one-line error must contain.
struct Bad {
    name: &'static str,
    scene: String,
    needles: Vec<&'static str>,
    args: Vec<&'static str>,
    files: Vec<(&'static str, Vec<u8>)>,
}

fn bad(name: &'static str, scene: String, needles: &[&'static str]) -> Bad {
    Bad {
        name,
        scene,
        needles: needles.to_vec(),
        args: Vec::new(),
        files: Vec::new(),
    }
}

impl Bad {
    fn args(mut self, args: &[&'static str]) -> Bad {
        self.args = args.to_vec();
        self
    }

    fn file(mut self, name: &'static str, bytes: Vec<u8>) -> Bad {
        self.files.push((name, bytes));
        self
    }
}

/// What is wrong with the answer to a bad scene, if anything: exit 1 within
/// a few seconds, a few lines on stderr naming the entry (every needle), no
/// panic or backtrace, nothing written.
fn judge(dir: &Path, output: &Output, elapsed: Duration, needles: &[&str]) -> Option<String> {
    let err = String::from_utf8_lossy(&output.stderr);
    let mut wrong = Vec::new();
    if output.status.code() != Some(1) {
        wrong.push(format!(
            "exit status {:?}, expected 1",
            output.status.code()
        ));
    }
    if elapsed > Duration::from_secs(10) {
        wrong.push(format!("took {elapsed:?}"));
    }
    let lines = err.lines().count();
    if err.trim().is_empty() || lines > 6 || err.len() > 800 {
        wrong.push(format!("{lines} lines, {} characters on stderr", err.len()));
    }
    for word in [
        "panicked",
        "backtrace",
        "internal error",
        "memory allocation",
    ] {
        if err.contains(word) {
            wrong.push(format!("stderr mentions {word:?}"));
        }
    }
    for n in needles {
        if !err.contains(n) {
            wrong.push(format!("stderr does not mention {n:?}"));
        }
    }
    if dir.join("out").exists() {
        wrong.push("the output directory was created".into());
    }
    (!wrong.is_empty()).then(|| {
        format!(
            "{}\n--- stderr ---\n{}",
            wrong.join("; "),
            err.chars().take(1500).collect::<String>()
        )
    })
}

/// A Gmsh 2.2 file of two triangles with physical names, valid as it is.
const TWO_TRIANGLES_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n2 2 \"block\"\n$EndPhysicalNames\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n3\n1 1 2 1 1 1 2\n2 2 2 2 1 1 2 3\n3 2 2 2 1 1 3 4\n$EndElements\n";

/// Three quads with a hanging node at (1, 0.5): the left quad's edge
/// (1, 0)–(1, 1) meets the two right quads' half edges, no whole edge.
const HANGING_NODE_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n2 2 \"block\"\n$EndPhysicalNames\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n6 2 0.5 0\n7 1 0.5 0\n8 2 1 0\n$EndNodes\n$Elements\n5\n1 1 2 1 1 1 2\n2 1 2 1 1 2 5\n3 3 2 2 1 1 2 3 4\n4 3 2 2 1 2 5 6 7\n5 3 2 2 1 7 6 8 3\n$EndElements\n";

fn sweep() -> Vec<Bad> {
    let half = |rest: &str| {
        block_meshed(&format!(
            "{{ generator = \"half_disk\", center = [0.0, 1.0], radius = 1.0, {rest} }}"
        ))
    };
    let quarter = |rest: &str| {
        block_with_all(&[
            ("model = \"plane_strain\"", "model = \"axisymmetric\""),
            (
                BLOCK_MESH,
                &format!(
                    "mesh = {{ generator = \"quarter_disk\", center = [0.0, 1.0], radius = 1.0, {rest} }}"
                ),
            ),
        ])
    };
    let hemisphere = |rest: &str| {
        box_meshed(&format!(
            "{{ generator = \"hemisphere\", center = [0.0, 0.0, 1.0], radius = 1.0, {rest} }}"
        ))
    };
    let boxed = |divisions: &str| {
        box_meshed(&format!(
            "{{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = {divisions} }}"
        ))
    };
    let gmsh = || block_with(BLOCK_MESH, "mesh = { file = \"part.msh\" }");
    let msh = TWO_TRIANGLES_MSH.as_bytes();
    let many_steps = format!(
        "steps = [{}]\n{BLOCK_ON_PLANE}",
        vec!["{ scale = { press = 1.0 } }"; 20_000].join(", ")
    );
    let contact = "[[contact]]\nname = \"block-ground\"";
    let mut garbage = Vec::new();
    let mut x: u32 = 12345;
    for _ in 0..4000 {
        x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
        garbage.push((x >> 16) as u8);
    }
    vec![
        // divisions: negative, fractional, zero, not a number, huge, for every generator
        bad("rectangle_divisions_negative", block_with("divisions = [4, 2]", "divisions = [-8, 4]"), &["mesh.divisions", "positive whole numbers", "got -8", "line 13"]),
        bad("rectangle_divisions_fractional", block_with("divisions = [4, 2]", "divisions = [8.5, 4]"), &["mesh.divisions", "got 8.5"]),
        bad("rectangle_divisions_zero", block_with("divisions = [4, 2]", "divisions = [0, 4]"), &["bodies[0].mesh.divisions", ">= 1"]),
        bad("rectangle_divisions_text", block_with("divisions = [4, 2]", "divisions = \"many\""), &["mesh.divisions", "\"many\""]),
        bad("rectangle_100000_squared", block_with("divisions = [4, 2]", "divisions = [100000, 100000]"), &["memory", "GiB", "bodies[0].mesh.divisions", "coarser"]),
        bad("rectangle_1e9_by_4", block_with("divisions = [4, 2]", "divisions = [1000000000, 4]"), &["memory", "bodies[0].mesh.divisions"]),
        bad("rectangle_3000_squared_on_24_gib", block_with("divisions = [4, 2]", "divisions = [3000, 3000]"), &["memory", "GiB", "--max-memory is 24 GiB"]).args(&["--max-memory", "24G"]),
        bad("half_disk_divisions_1e9", half("divisions = 1e9"), &["memory", "bodies[0].mesh.divisions"]),
        bad("half_disk_divisions_negative", half("divisions = -3"), &["mesh.divisions", "got -3", "elements along the arc"]),
        bad("half_disk_divisions_fractional", half("divisions = 2.5"), &["mesh.divisions", "got 2.5"]),
        bad("half_disk_divisions_array", half("divisions = [8]"), &["mesh.divisions", "an array"]),
        bad("half_disk_divisions_3", half("divisions = 3"), &["bodies[0].mesh.divisions", ">= 4"]),
        bad("quarter_disk_divisions_1e9", quarter("divisions = 1000000000"), &["memory", "bodies[0].mesh.divisions"]),
        bad("quarter_disk_divisions_negative", quarter("divisions = -1"), &["mesh.divisions", "got -1"]),
        bad("box_2000_cubed", boxed("[2000, 2000, 2000]"), &["memory", "bodies[0].mesh.divisions"]),
        bad("box_divisions_negative", boxed("[4, -1, 2]"), &["mesh.divisions", "got -1"]),
        bad("box_divisions_fractional", boxed("[4, 1.5, 2]"), &["mesh.divisions", "got 1.5"]),
        bad("hemisphere_divisions_1e6", hemisphere("divisions = 1000000"), &["memory", "bodies[0].mesh.divisions"]),
        bad("hemisphere_divisions_fractional", hemisphere("divisions = 0.5"), &["mesh.divisions", "got 0.5", "quarter meridian"]),
        // sizes and radii
        bad("rectangle_size_zero", block_with("size = [1.0, 0.5]", "size = [1.0, 0.0]"), &["bodies[0].mesh.size", "> 0"]),
        bad("rectangle_size_negative", block_with("size = [1.0, 0.5]", "size = [-1.0, 0.5]"), &["bodies[0].mesh.size"]),
        bad("rectangle_size_text", block_with("size = [1.0, 0.5]", "size = [1.0, \"big\"]"), &["mesh.size", "\"big\""]),
        bad("half_disk_radius_zero", half("divisions = 8").replace("radius = 1.0", "radius = 0.0"), &["bodies[0].mesh.radius", "> 0"]),
        bad("half_disk_radius_negative", half("divisions = 8").replace("radius = 1.0", "radius = -1.0"), &["bodies[0].mesh.radius"]),
        bad("box_size_zero", box_meshed("{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 0.0, 0.5], divisions = [2, 2, 1] }"), &["bodies[0].mesh.size"]),
        bad("hemisphere_radius_negative", hemisphere("divisions = 4").replace("radius = 1.0", "radius = -2.0"), &["bodies[0].mesh.radius"]),
        bad("rigid_circle_radius_zero", block_with("rigid = { shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }", "rigid = { shape = \"circle\", center = [0.0, -1.0], radius = 0.0 }"), &["bodies[1].rigid.radius"]),
        // NaN and infinities in every kind of float key
        bad("nan_in_size", block_with("size = [1.0, 0.5]", "size = [nan, 0.5]"), &["bodies[0].mesh.size", "NaN"]),
        bad("inf_in_origin", block_with("origin = [0.0, 0.0]", "origin = [inf, 0.0]"), &["bodies[0].mesh.origin", "inf"]),
        bad("nan_in_grading_ratio", block_with("divisions = [4, 2]", "divisions = [4, 2], grading = { towards = \"top\", ratio = nan }"), &["bodies[0].mesh.grading.ratio", "NaN"]),
        bad("inf_in_half_disk_grading", half("divisions = 8, grading = inf"), &["bodies[0].mesh.grading", "inf"]),
        bad("nan_in_half_disk_center", half("divisions = 8").replace("center = [0.0, 1.0]", "center = [0.0, nan]"), &["bodies[0].mesh.center", "NaN"]),
        bad("nan_in_pole", half("divisions = 8, pole = [nan, -1.0]"), &["bodies[0].mesh.pole", "NaN"]),
        bad("nan_in_young", block_with("young = 1.0", "young = nan"), &["materials[0].young", "NaN"]),
        bad("inf_in_young", block_with("young = 1.0", "young = inf"), &["materials[0].young", "inf"]),
        bad("nan_in_poisson", block_with("poisson = 0.3", "poisson = nan"), &["materials[0].poisson", "NaN"]),
        bad("nan_in_rigid_point", block_with("point = [0.0, 0.0]", "point = [nan, 0.0]"), &["bodies[1].rigid.point", "NaN"]),
        bad("inf_in_rigid_normal", block_with("normal = [0.0, 1.0]", "normal = [0.0, -inf]"), &["bodies[1].rigid.normal", "inf"]),
        bad("nan_in_boundary_point", block_with("point = [0.0, 0.5]", "point = [nan, 0.5]"), &["boundary[0].point", "NaN"]),
        bad("nan_in_displacement", block_with("displacement = { x = 0.0 }", "displacement = { x = nan }"), &["boundary[0].displacement.x", "NaN"]),
        bad("inf_in_traction", block_with("traction = [0.0, -1.0]", "traction = [0.0, -inf]"), &["boundary[1].traction", "inf"]),
        bad("nan_in_gap", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\ngap = nan"), &["contact \"block-ground\".gap", "NaN"]),
        bad("nan_in_coulomb", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\nfriction = { coulomb = nan }"), &["contact \"block-ground\".friction.coulomb", "NaN"]),
        bad("penalty_law_1e-300", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\nlaw = { penalty = 1e-300 }"), &["contact \"block-ground\".law.penalty", "outside", "other units"]),
        bad("inf_in_penalty_law", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\nlaw = { penalty = inf }"), &["contact \"block-ground\".law.penalty", "inf"]),
        bad("nan_in_step_scale", format!("{BLOCK_ON_PLANE}\n[[steps]]\nscale = {{ press = nan }}\n"), &["steps[0].scale.press", "NaN"]),
        bad("nan_in_tolerance", format!("{BLOCK_ON_PLANE}\n[solver]\ntolerance = nan\n"), &["solver.tolerance", "NaN"]),
        bad("inf_in_solver_penalty", format!("{BLOCK_ON_PLANE}\n[solver]\npenalty = inf\n"), &["solver.penalty", "inf"]),
        bad("nan_in_reference_radius", format!("{BLOCK_ON_PLANE}\n[reference]\nkind = \"hertz_cylinder\"\nradius = nan\n"), &["reference.radius", "NaN"]),
        bad("nan_in_probe", format!("{BLOCK_ON_PLANE}\n[output]\nprobes = [[nan, 0.0]]\n"), &["output.probes[0]", "NaN"]),
        // materials
        bad("young_zero", block_with("young = 1.0", "young = 0.0"), &["materials[0].young", "> 0"]),
        bad("young_negative", block_with("young = 1.0", "young = -2.0"), &["materials[0].young"]),
        bad("poisson_one_half", block_with("poisson = 0.3", "poisson = 0.5"), &["materials[0].poisson", "0.5"]),
        bad("poisson_above_one_half", block_with("poisson = 0.3", "poisson = 0.7"), &["materials[0].poisson"]),
        bad("poisson_minus_one", block_with("poisson = 0.3", "poisson = -1.0"), &["materials[0].poisson", "-1"]),
        // whole numbers elsewhere
        bad("dimension_negative", block_with("dimension = 2", "dimension = -2"), &["dimension: expected 2 or 3, got -2"]),
        bad("dimension_four", block_with("dimension = 2", "dimension = 4"), &["dimension", "2 or 3"]),
        bad("max_iterations_negative", format!("{BLOCK_ON_PLANE}\n[solver]\nmax_iterations = -3\n"), &["solver.max_iterations", "got -3"]),
        bad("subdomains_negative", block_with("name = \"block\"\nmaterial", "name = \"block\"\nsubdomains = -2\nmaterial"), &["subdomains", "-2"]),
        bad("subdomains_more_than_cells", block_with("name = \"block\"\nmaterial", "name = \"block\"\nsubdomains = 1000000000\nmaterial"), &["bodies[0].subdomains", "8 cells", "give at most 8, or \"auto\""]),
        // structure: unknown keys, missing bodies, wrong references
        bad("unknown_top_level_key", format!("frobnicate = 1\n{BLOCK_ON_PLANE}"), &["frobnicate", "line 1"]),
        bad("unknown_generator_key", block_with("divisions = [4, 2]", "divisions = [4, 2], radus = 1.0"), &["radus"]),
        bad("unknown_generator", block_with("\"rectangle\"", "\"disk\""), &["disk", "half_disk"]),
        bad("no_bodies", "dimension = 2\n[[materials]]\nname = \"steel\"\nyoung = 1.0\npoisson = 0.3\n".into(), &["bodies", "no deformable body"]),
        bad("contact_to_missing_surface", block_with("surface = \"bottom\"", "surface = \"underside\""), &["underside", "block-ground", "bottom"]),
        bad("contact_to_missing_body", block_with("master = { body = \"ground\" }", "master = { body = \"nowhere\" }"), &["contact \"block-ground\".master.body", "nowhere"]),
        bad("boundary_on_missing_body", block_with("name = \"press\"\nbody = \"block\"", "name = \"press\"\nbody = \"blok\""), &["boundary[1].body", "blok"]),
        bad("unknown_body_among_thousands", format!("{}{}", block_with("master = { body = \"ground\" }", "master = { body = \"nowhere\" }"), (0..5000).map(|i| format!("\n[[bodies]]\nname = \"g{i}\"\nrigid = {{ shape = \"plane\", point = [0.0, -{i}.0], normal = [0.0, 1.0] }}\n")).collect::<String>()), &["contact \"block-ground\".master.body", "nowhere", "and 4990 more"]),
        bad("duplicate_contact_name", format!("{BLOCK_ON_PLANE}\n{contact}\nslave = {{ body = \"block\", surface = \"bottom\" }}\nmaster = {{ body = \"ground\" }}\n"), &["block-ground", "unique"]),
        // steps
        bad("step_scale_not_a_number", format!("{BLOCK_ON_PLANE}\n[[steps]]\nscale = {{ press = \"half\" }}\n"), &["scale = { press = \"half\" }", "f64"]),
        bad("too_many_steps", many_steps, &["steps", "20000 load steps, at most 10000", "a row of steps.csv"]),
        // Gmsh files: missing, garbage, truncated, lying about its size
        bad("gmsh_missing", block_with(BLOCK_MESH, "mesh = { file = \"nowhere.msh\" }"), &["bodies[0].mesh", "nowhere.msh"]),
        bad("gmsh_garbage", gmsh(), &["bodies[0].mesh", "part.msh"]).file("part.msh", garbage),
        bad("gmsh_truncated", gmsh(), &["bodies[0].mesh", "part.msh"]).file("part.msh", msh[..msh.len() / 2].to_vec()),
        bad("gmsh_huge_node_count", gmsh(), &["bodies[0].mesh", "part.msh", "announces 99999999999999 nodes"]).file("part.msh", TWO_TRIANGLES_MSH.replace("$Nodes\n4\n", "$Nodes\n99999999999999\n").into_bytes()),
        bad("gmsh_empty", gmsh(), &["bodies[0].mesh", "part.msh"]).file("part.msh", Vec::new()),
        bad("gmsh_nan_coordinate", gmsh(), &["bodies[0].mesh", "part.msh", "node 3", "not a finite number"]).file("part.msh", TWO_TRIANGLES_MSH.replace("3 1 1 0\n", "3 nan 1 0\n").into_bytes()),
        // a hanging node: the left quad's right edge against two half edges
        bad("gmsh_hanging_node", gmsh(), &["bodies[0].mesh", "part.msh", "non-conforming", "share the node at [1.0, 0.0, 0.0]"]).file("part.msh", HANGING_NODE_MSH.as_bytes().to_vec()),
        // a modulus whose stiffness overflows or underflows double precision
        bad("young_1e308", block_with("young = 1.0", "young = 1e308"), &["materials[0].young", "outside", "other units"]),
        bad("young_1e-310", block_with("young = 1.0", "young = 1e-310"), &["materials[0].young", "outside"]),
        // extreme numbers are shown as written (1e-300), not as hundreds of
        // digits; a 3D point has its z (found by a third robustness sweep)
        bad("grading_1e-300", half("divisions = 8, grading = 1e-300"), &["bodies[0].mesh.grading", "got 1e-300"]),
        bad("tolerance_1e300", format!("{BLOCK_ON_PLANE}\n[solver]\ntolerance = 1e300\n"), &["solver.tolerance", "got 1e300"]),
        bad("pin_at_1e300", block_with("point = [0.0, 0.5]", "point = [1e300, 0.5]"), &["boundary[0].point", "no node at (1e300, 0.5)"]),
        bad("pin_above_a_3d_box", BOX_ON_PLANE.replacen("surface = \"xmin\"", "point = [0.0, 0.0, 0.7]", 1), &["boundary[0].point", "no node at (0, 0, 0.7)", "nearest is (0, 0, 0.5)"]),
        // inputs that ended in an internal error (exit 3): a grading whose
        // smallest cells are NaN, μ·λ_n overflowing the 3D thresholds, a plane
        // normal whose length underflows (found by a third robustness sweep)
        bad("hemisphere_grading_1e100", hemisphere("divisions = 4, grading = 1e100"), &["bodies[0].mesh.grading", "between 1 and 1e12", "got 1e100"]),
        bad("coulomb_1e200_in_3d", BOX_ON_PLANE.replacen("master = { body = \"ground\" }", "master = { body = \"ground\" }\nfriction = { coulomb = 1e200 }", 1), &["contact \"box-ground\".friction", "<= 1e100", "got 1e200"]),
        bad("plane_normal_1e-300", BOX_ON_PLANE.replacen("normal = [0.0, 0.0, 1.0]", "normal = [1e-300, 1e-300, 1e-300]", 1), &["bodies[1].rigid.normal", "normalised"]),
        // a line of 200 000 characters: the message quotes a window of it
        bad("very_long_line", format!("x = [{}]\n{BLOCK_ON_PLANE}", vec!["1"; 40_000].join(", ")), &["unknown field `x`", "line 1"]),
    ]
}

#[test]
fn sweep_of_malformed_and_oversized_scenes_exits_1_naming_the_entry() {
    let cases = sweep();
    assert!(cases.len() >= 30);
    let mut failures = Vec::new();
    for case in &cases {
        let dir = fresh_dir(&format!("sweep/{}", case.name));
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, &case.scene).unwrap();
        for (name, bytes) in &case.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let mut cmd = Command::new(BIN);
        cmd.arg("run")
            .arg(&scene)
            .arg("--out")
            .arg(dir.join("out"))
            .args(&case.args)
            .current_dir(&dir);
        let (output, elapsed) = run_limited(cmd, Duration::from_secs(60));
        if let Some(why) = judge(&dir, &output, elapsed, &case.needles) {
            failures.push(format!("== {}: {why}", case.name));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} bad scenes were not refused as they should:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
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
fn fractional_divisions_name_the_key_and_the_value() {
    let scene = block_with("divisions = [4, 2]", "divisions = [8.5, 4]");
    let run = run_scene("fractional_divisions", Some(&scene), &[]);
    run.assert_bad_input(&["mesh.divisions: expected positive whole numbers", "got 8.5"]);
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

// ============================================================================
// Bad inputs a hostile sweep found mishandled: each refused (exit 1) with
// the entry or file and what would be valid, nothing written, by `check` as
// by `run` when the scene alone shows it.
// ============================================================================

/// Runs `signorini ARGS...` in `dir`.
fn signorini_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("cannot start the signorini binary")
}

/// Exit 1, every needle on stderr, nothing on stdout (`local` writes its
/// answer there) and nothing written in `dir` but the `inputs`.
fn assert_refused(dir: &Path, out: &Output, needles: &[&str], inputs: &[&str]) {
    let err = common::stderr_of_exit(out, 1);
    for n in needles {
        assert!(err.contains(n), "stderr does not mention {n:?}\n{err}");
    }
    assert!(err.len() < 600 && !err.contains("panicked"), "{err}");
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let mut written: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !inputs.contains(&n.as_str()))
        .collect();
    written.sort();
    assert!(written.is_empty(), "written: {written:?}");
}

/// `scene` (and `files`) refused by both `check` and `run`, naming `needles`.
fn check_and_run_refuse(test: &str, scene: &str, files: &[(&str, &str)], needles: &[&str]) {
    for command in ["check", "run"] {
        let dir = scene_dir(&format!("{test}_{command}"), scene, files);
        run_in(dir, command, &[]).assert_bad_input(needles);
    }
}

/// The NumPy problem of tests/data (stored members W, q, mu, dim).
fn numpy_problem() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/local_int_dim.npz"))
        .unwrap()
}

/// The offset of the first value of the first array (W) of a stored .npz.
fn first_array_data(npz: &[u8]) -> usize {
    let magic = npz.windows(6).position(|w| w == b"\x93NUMPY").unwrap();
    let header_len = u16::from_le_bytes([npz[magic + 8], npz[magic + 9]]) as usize;
    magic + 10 + header_len
}

/// A flipped bit in W's numbers left a valid-looking array that was solved
/// with exit 0: every member's CRC-32 is checked against the archive's.
#[test]
fn a_flipped_byte_inside_a_npz_array_is_refused_by_its_crc() {
    let mut npz = numpy_problem();
    let at = first_array_data(&npz) + 6;
    npz[at] ^= 0x10;
    let dir = fresh_dir("npz_flipped_byte");
    std::fs::write(dir.join("flipped.npz"), &npz).unwrap();
    let out = signorini_in(&dir, &["local", "flipped.npz"]);
    assert_refused(
        &dir,
        &out,
        &["flipped.npz: W.npy is damaged", "CRC-32"],
        &["flipped.npz"],
    );
}

/// The CRC-32 of `bytes` (zip's polynomial), to damage a member and record
/// the damage in the archive as a writer would.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// A member that is not a NumPy array (its magic changed, its CRC-32
/// recorded anew in the local and central headers) is refused naming the
/// file and the member (it named the member alone).
#[test]
fn a_damaged_npz_member_names_the_file() {
    let mut npz = numpy_problem();
    let magic = npz.windows(6).position(|w| w == b"\x93NUMPY").unwrap();
    npz[magic + 1] = b'X';
    // W.npy is the first member (stored, its sizes in a zip64 field): its
    // data ends where the next member's local header starts.
    let end = magic
        + npz[magic..]
            .windows(4)
            .position(|w| w == b"PK\x03\x04")
            .unwrap();
    let crc = crc32(&npz[magic..end]).to_le_bytes();
    npz[14..18].copy_from_slice(&crc);
    let central = npz.windows(4).position(|w| w == b"PK\x01\x02").unwrap();
    npz[central + 16..central + 20].copy_from_slice(&crc);
    let dir = fresh_dir("npz_damaged_member");
    std::fs::write(dir.join("damaged.npz"), &npz).unwrap();
    let out = signorini_in(&dir, &["local", "damaged.npz"]);
    assert_refused(&dir, &out, &["damaged.npz: W.npy"], &["damaged.npz"]);
}

/// `local` reads problem files: a scene named it "expected value at line 1
/// column 1"; the refusal says which formats `local` reads.
#[test]
fn local_on_a_scene_says_which_formats_it_reads() {
    let dir = fresh_dir("local_on_a_scene");
    std::fs::write(dir.join("scene.toml"), BLOCK_ON_PLANE).unwrap();
    std::fs::write(dir.join("scene.txt"), BLOCK_ON_PLANE).unwrap();
    let inputs = ["scene.toml", "scene.txt"];
    let out = signorini_in(&dir, &["local", "scene.toml"]);
    let needles = [
        "scene.toml",
        "signorini run",
        "JSON, NumPy .npz or FCLib .hdf5/.h5",
    ];
    assert_refused(&dir, &out, &needles, &inputs);
    let out = signorini_in(&dir, &["local", "scene.txt"]);
    let needles = [
        "scene.txt: not a JSON problem",
        "JSON, NumPy .npz or FCLib .hdf5/.h5",
    ];
    assert_refused(&dir, &out, &needles, &inputs);
}

/// `local --max-iterations 0` ran (a solve of no iteration): at least 1.
#[test]
fn local_refuses_zero_iterations() {
    let dir = fresh_dir("local_zero_iterations");
    std::fs::write(dir.join("p.npz"), numpy_problem()).unwrap();
    let out = signorini_in(&dir, &["local", "--max-iterations", "0", "p.npz"]);
    assert_refused(
        &dir,
        &out,
        &["--max-iterations", "must be at least 1, got 0"],
        &["p.npz"],
    );
}

/// `--max-memory -5G` as a separate argument was read as an unknown option
/// `-5`: the refusal names --max-memory and the valid form, for every
/// command that takes it.
#[test]
fn a_negative_max_memory_names_the_option() {
    let dir = fresh_dir("max_memory_negative");
    std::fs::write(dir.join("scene.toml"), BLOCK_ON_PLANE).unwrap();
    std::fs::write(dir.join("p.npz"), numpy_problem()).unwrap();
    for args in [
        ["run", "scene.toml", "--max-memory", "-5G"],
        ["check", "scene.toml", "--max-memory", "-5G"],
        ["local", "p.npz", "--max-memory", "-5G"],
    ] {
        let out = signorini_in(&dir, &args);
        let needles = ["--max-memory", "-5G", "expected a positive size"];
        assert_refused(&dir, &out, &needles, &["scene.toml", "p.npz"]);
    }
}

/// A Gmsh file with physical names and no element: the refusal spoke of
/// physical groups; it says the file has no elements.
#[test]
fn a_gmsh_file_without_elements_says_so() {
    let empty = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n2 2 \"block\"\n$EndPhysicalNames\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 1 1 0\n$EndNodes\n$Elements\n0\n$EndElements\n";
    let needles = [
        "bodies[0].mesh",
        "empty.msh",
        "the file has no elements",
        "gmsh -2",
    ];
    let scene = block_from_file("empty.msh");
    check_and_run_refuse(
        "gmsh_no_elements",
        &scene,
        &[("empty.msh", empty)],
        &needles,
    );
    let dir = scene_dir("gmsh_no_elements_words", &scene, &[("empty.msh", empty)]);
    let err = run_in(dir, "run", &[]).stderr();
    assert!(!err.contains("physical"), "{err}");
}

/// Two `$PhysicalNames` entries of one dimension and tag replaced one
/// another, and two groups of one name and dimension merged into one
/// surface: both refused, naming the tags.
#[test]
fn gmsh_physical_names_that_clash_are_refused() {
    let twice = TWO_TRIANGLES_MSH.replace(
        "$PhysicalNames\n2\n1 1 \"bottom\"\n",
        "$PhysicalNames\n3\n1 1 \"bottom\"\n1 1 \"base\"\n",
    );
    let one_name = TWO_TRIANGLES_MSH
        .replace(
            "$PhysicalNames\n2\n1 1 \"bottom\"\n",
            "$PhysicalNames\n3\n1 1 \"bottom\"\n1 3 \"bottom\"\n",
        )
        .replace("$Elements\n3\n", "$Elements\n4\n")
        .replace("$EndElements", "4 1 2 3 3 2 3\n$EndElements");
    assert!(twice.contains("\"base\"") && one_name.contains("4 1 2 3 3 2 3"));
    let scene = block_from_file("part.msh");
    check_and_run_refuse(
        "gmsh_tag_named_twice",
        &scene,
        &[("part.msh", &twice)],
        &[
            "bodies[0].mesh",
            "part.msh",
            "dimension 1 and tag 1 twice",
            "\"bottom\" and \"base\"",
        ],
    );
    check_and_run_refuse(
        "gmsh_one_name_two_groups",
        &scene,
        &[("part.msh", &one_name)],
        &[
            "bodies[0].mesh",
            "two physical groups of dimension 1 \"bottom\" (tags 1 and 3)",
        ],
    );
}

/// `normal = "slave"` on a mortar contact was silently ignored (mortar
/// uses the slave's averaged normal whatever the key says); and
/// `solver.friction` with contact elements, solved by the return mapping.
#[test]
fn keys_a_discretization_does_not_use_are_refused() {
    let mortar = common::example("mortar_patch.toml").replacen(
        "discretization = \"mortar\"\n",
        "discretization = \"mortar\"\nnormal = \"slave\"\n",
        1,
    );
    assert!(mortar.contains("normal = \"slave\""));
    check_and_run_refuse(
        "mortar_normal_slave",
        &mortar,
        &[],
        &[
            "contact \"pad-base\".normal",
            "\"slave\" is not used by mortar",
            "leave the key out",
        ],
    );
    let elements = format!(
        "{}\n[solver]\nfriction = \"newton\"\n",
        common::example("contact_elements.toml")
    );
    check_and_run_refuse(
        "contact_elements_friction_method",
        &elements,
        &[],
        &[
            "solver.friction = \"newton\"",
            "return mapping",
            "remove the key",
        ],
    );
}

/// `roughness = 1e300` was accepted while `law.penalty = 1e300` was refused:
/// the same range of representable stiffnesses.
#[test]
fn a_roughness_out_of_double_precision_is_refused_like_a_penalty() {
    let scene = block_with(
        "discretization = \"node_to_segment\"\n",
        "discretization = \"node_to_segment\"\nfriction = { coulomb = 0.3, slip_stiffness = 1.0, roughness = 1e300 }\n",
    );
    check_and_run_refuse(
        "roughness_1e300",
        &scene,
        &[],
        &[
            "contact \"block-ground\".friction.roughness",
            "1e300 is outside [1e-100, 1e100]",
            "other units",
        ],
    );
}

/// Contact elements of `penalty = 1e100` ended in "the Newton matrix ... is
/// singular", naming no key: refused before the solve, naming
/// `law.penalty` and the largest penalty that solves, which does
/// (examples/contact_elements.toml, E = 210 000, h = 0.25).
#[test]
fn contact_elements_too_stiff_for_double_precision_name_the_penalty() {
    let scene =
        common::example("contact_elements.toml").replace("penalty = 10000.0", "penalty = 1e100");
    assert!(scene.contains("penalty = 1e100"));
    let run = run_scene("contact_elements_1e100", Some(&scene), &[]);
    run.assert_bad_input(&[
        "contact \"joint\".law.penalty: 1e100",
        "give law.penalty <= ",
    ]);
    let err = run.stderr();
    let at = err.find("give law.penalty <= ").unwrap() + "give law.penalty <= ".len();
    let largest: f64 = err[at..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(largest > 1e9 && largest < 1e15, "{largest:e}");
    let at_limit = common::example("contact_elements.toml").replace(
        "penalty = 10000.0",
        &format!("penalty = {:e}", 0.99 * largest),
    );
    let run = run_scene("contact_elements_at_the_limit", Some(&at_limit), &[]);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
}
