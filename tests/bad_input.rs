//! Bad input is rejected up front (SCENE.md, "Commands"): `signorini run` exits
//! with code 1, prints one short error on stderr that names the offending entry
//! or key, and writes nothing, not even the output directory.
//!
//! Each test writes a tiny scene into its own directory under
//! `CARGO_TARGET_TMPDIR` and runs the real binary on it with `--out DIR/out`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_signorini");

/// One elastic block (1 x 0.5, 4 x 2 quads) resting on a rigid plane, pinned in
/// x at its top-left corner and pressed down by a traction on its top. It runs
/// fine as it is; each test breaks one thing in it.
const BLOCK_ON_PLANE: &str = r#"title = "block on a rigid plane"
dimension = 2
model = "plane_strain"

[[materials]]
name = "steel"
young = 1.0
poisson = 0.3

[[bodies]]
name = "block"
material = "steel"
mesh = { generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }

[[bodies]]
name = "ground"
rigid = { shape = "plane", point = [0.0, 0.0], normal = [0.0, 1.0] }

[[boundary]]
name = "pin"
body = "block"
point = [0.0, 0.5]
displacement = { x = 0.0 }

[[boundary]]
name = "press"
body = "block"
surface = "top"
traction = [0.0, -1.0]

[[contact]]
name = "block-ground"
slave = { body = "block", surface = "bottom" }
master = { body = "ground" }
discretization = "node_to_segment"
"#;

/// The pin of `BLOCK_ON_PLANE`, to remove it.
const PIN: &str = r#"[[boundary]]
name = "pin"
body = "block"
point = [0.0, 0.5]
displacement = { x = 0.0 }
"#;

/// `BLOCK_ON_PLANE` with `from` replaced by `to`; panics if `from` is absent, so
/// that a test can never silently run the unmodified (valid) scene.
fn block_with(from: &str, to: &str) -> String {
    assert!(
        BLOCK_ON_PLANE.contains(from),
        "test bug: {from:?} is not in the base scene"
    );
    BLOCK_ON_PLANE.replacen(from, to, 1)
}

/// A fresh, empty directory for one test.
fn fresh_dir(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("bad_input")
        .join(test);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

struct Run {
    dir: PathBuf,
    output: Output,
}

impl Run {
    fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.output.stderr).into_owned()
    }

    fn out_dir(&self) -> PathBuf {
        self.dir.join("out")
    }

    fn describe(&self) -> String {
        format!(
            "exit status {:?}\n--- stdout ---\n{}\n--- stderr ---\n{}",
            self.output.status.code(),
            String::from_utf8_lossy(&self.output.stdout),
            self.stderr()
        )
    }

    /// Nothing written: the output directory does not exist.
    fn assert_nothing_written(&self) {
        assert!(
            !self.out_dir().exists(),
            "{} was created for bad input\n{}",
            self.out_dir().display(),
            self.describe()
        );
    }

    /// Exit code 1, a short non-empty error on stderr containing every one of
    /// `needles`, and nothing written.
    fn assert_bad_input(&self, needles: &[&str]) {
        assert_eq!(
            self.output.status.code(),
            Some(1),
            "expected exit code 1 (bad input)\n{}",
            self.describe()
        );
        let err = self.stderr();
        assert!(
            !err.trim().is_empty(),
            "stderr is empty\n{}",
            self.describe()
        );
        assert!(
            err.len() < 600,
            "stderr is {} characters long, expected a short message (< 600)\n{}",
            err.len(),
            self.describe()
        );
        for n in needles {
            assert!(
                err.contains(n),
                "stderr does not mention {n:?}\n{}",
                self.describe()
            );
        }
        self.assert_nothing_written();
    }
}

/// Write `scene` (if any) to DIR/scene.toml and run `signorini run DIR/scene.toml
/// --out DIR/out EXTRA...`.
fn run_scene(test: &str, scene: Option<&str>, extra: &[&str]) -> Run {
    let dir = fresh_dir(test);
    let scene_path = dir.join("scene.toml");
    if let Some(text) = scene {
        std::fs::write(&scene_path, text).unwrap();
    }
    let output = Command::new(BIN)
        .arg("run")
        .arg(&scene_path)
        .arg("--out")
        .arg(dir.join("out"))
        .args(extra)
        .current_dir(&dir)
        .output()
        .expect("cannot start the signorini binary");
    Run { dir, output }
}

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

#[test]
fn gmsh_file_with_an_unsupported_element_type_is_named_and_counted() {
    let scene = block_with(
        "mesh = { generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }",
        "mesh = { file = \"quad9.msh\" }",
    );
    let dir = fresh_dir("gmsh_unsupported");
    std::fs::write(dir.join("quad9.msh"), QUAD9_MSH).unwrap();
    std::fs::write(dir.join("scene.toml"), &scene).unwrap();
    let output = Command::new(BIN)
        .arg("run")
        .arg(dir.join("scene.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let run = Run { dir, output };
    run.assert_bad_input(&["bodies[0].mesh", "9-node quadrangle", "1"]);
}

#[test]
fn gmsh_file_without_the_surface_the_scene_names() {
    // the shipped block2d.msh names bottom, top, left, right: not "base"
    let msh = format!("{}/examples/meshes/block2d.msh", env!("CARGO_MANIFEST_DIR"));
    let scene = block_with(
        "mesh = { generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }",
        &format!("mesh = {{ file = \"{msh}\" }}"),
    )
    .replace("surface = \"bottom\"", "surface = \"base\"");
    let run = run_scene("gmsh_missing_surface", Some(&scene), &[]);
    run.assert_bad_input(&["base", "bottom"]);
}

#[test]
fn gmsh_file_that_does_not_exist() {
    let scene = block_with(
        "mesh = { generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }",
        "mesh = { file = \"nowhere.msh\" }",
    );
    let run = run_scene("gmsh_missing_file", Some(&scene), &[]);
    run.assert_bad_input(&["bodies[0].mesh", "nowhere.msh"]);
}
