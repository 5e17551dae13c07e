//! The harness of the bad-input tests (tests/integration/bad_input/,
//! tests/integration/bad_input_limits.rs): a small valid scene to break, and runs of the
//! real binary on it with or without a time limit.

use super::{boundary, contact, rigid_plane, steel_block_scene, SceneText, BIN};
use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::LazyLock;

/// One elastic block (1 x 0.5, 4 x 2 quads) resting on a rigid plane, pinned in
/// x at its top-left corner and pressed down by a traction on its top. It runs
/// fine as it is; each test breaks one thing in it.
pub const BLOCK_ON_PLANE: SceneText = SceneText(|| {
    static TEXT: LazyLock<String> = LazyLock::new(|| {
        steel_block_scene(
        "block on a rigid plane",
        "{ generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }",
        &[
            rigid_plane("ground", [0.0, 0.0], [0.0, 1.0]),
            PIN.to_string(),
            boundary("press", "block", "surface = \"top\"", "traction = [0.0, -1.0]"),
            contact("block-ground", "block", "bottom", "ground")
                + "discretization = \"node_to_segment\"\n",
        ],
    )
    });
    &TEXT
});

/// The pin of `BLOCK_ON_PLANE`, to remove it.
pub const PIN: &str = r#"[[boundary]]
name = "pin"
body = "block"
point = [0.0, 0.5]
displacement = { x = 0.0 }
"#;

/// `BLOCK_ON_PLANE` with `from` replaced by `to`; panics if `from` is absent, so
/// that a test can never silently run the unmodified (valid) scene.
pub fn block_with(from: &str, to: &str) -> String {
    assert!(
        BLOCK_ON_PLANE.contains(from),
        "test bug: {from:?} is not in the base scene"
    );
    BLOCK_ON_PLANE.replacen(from, to, 1)
}

/// A fresh directory for `test` holding `BLOCK_ON_PLANE` as scene.toml,
/// and the command `signorini COMMAND scene.toml` to run on it.
pub fn base_scene_command(test: &str, command: &str) -> (PathBuf, Command) {
    let dir = fresh_dir(test);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, BLOCK_ON_PLANE).unwrap();
    let mut cmd = Command::new(BIN);
    cmd.arg(command).arg(&scene);
    (dir, cmd)
}

/// A fresh, empty directory for one test.
pub fn fresh_dir(test: &str) -> PathBuf {
    super::fresh_dir("bad_input", test)
}

pub struct Run {
    pub dir: PathBuf,
    pub output: Output,
}

impl Run {
    pub fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.output.stderr).into_owned()
    }

    pub fn out_dir(&self) -> PathBuf {
        self.dir.join("out")
    }

    pub fn describe(&self) -> String {
        format!(
            "exit status {:?}\n--- stdout ---\n{}\n--- stderr ---\n{}",
            self.output.status.code(),
            String::from_utf8_lossy(&self.output.stdout),
            self.stderr()
        )
    }

    /// Nothing written: the output directory does not exist.
    pub fn assert_nothing_written(&self) {
        assert!(
            !self.out_dir().exists(),
            "{} was created for bad input\n{}",
            self.out_dir().display(),
            self.describe()
        );
    }

    /// Exit code 1, a short non-empty error on stderr containing every one of
    /// `needles`, and nothing written.
    pub fn assert_bad_input(&self, needles: &[&str]) {
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
pub fn run_scene(test: &str, scene: Option<&str>, extra: &[&str]) -> Run {
    let dir = fresh_dir(test);
    if let Some(text) = scene {
        std::fs::write(dir.join("scene.toml"), text).unwrap();
    }
    let out = dir.join("out");
    let mut args = vec!["--out", out.to_str().unwrap()];
    args.extend(extra);
    run_in(dir, "run", &args)
}

/// A fresh directory for `test` holding `scene` as scene.toml and each
/// `(name, text)` of `files` beside it (a mesh the scene reads).
pub fn scene_dir(test: &str, scene: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = fresh_dir(test);
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    dir
}

/// Runs `signorini COMMAND DIR/scene.toml EXTRA...` in `dir`.
pub fn run_in(dir: PathBuf, command: &str, extra: &[&str]) -> Run {
    let output = Command::new(BIN)
        .arg(command)
        .arg(dir.join("scene.toml"))
        .args(extra)
        .current_dir(&dir)
        .output()
        .expect("cannot start the signorini binary");
    Run { dir, output }
}

/// The mesh line of `BLOCK_ON_PLANE`, to swap generators in.
pub const BLOCK_MESH: &str = "mesh = { generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }";

/// `BLOCK_ON_PLANE` with every `(from, to)` replaced (each `from` must be in
/// it, in turn).
pub fn block_with_all(edits: &[(&str, &str)]) -> String {
    edits
        .iter()
        .fold(BLOCK_ON_PLANE.to_string(), |s, (from, to)| {
            assert!(s.contains(from), "test bug: {from:?} is not in the scene");
            s.replacen(from, to, 1)
        })
}

/// `BLOCK_ON_PLANE` with another mesh (a generator table).
pub fn block_meshed(mesh: &str) -> String {
    block_with(BLOCK_MESH, &format!("mesh = {mesh}"))
}

/// Each `(name, from, to, needles)` of `edits`: `base` with `from` replaced
/// by `to` (once; `from` must be in it) is refused as bad input naming each
/// of `needles`, run in the fresh directory `PREFIX_NAME`.
pub fn assert_edits_refused(prefix: &str, base: &str, edits: &[(&str, &str, &str, &[&str])]) {
    for (name, from, to, needles) in edits {
        assert!(base.contains(from), "test bug: {name}: no {from:?}");
        let dir = scene_dir(
            &format!("{prefix}_{name}"),
            &base.replacen(from, to, 1),
            &[],
        );
        run_in(dir, "run", &["--out", "out"]).assert_bad_input(needles);
    }
}
