//! Helpers shared by the integration tests (each test file is its own crate,
//! so not every helper is used by every file).
#![allow(dead_code)]

pub mod bad_scene;
pub mod curved_patch;
mod reference;
mod scene_text;
pub mod twins;
#[allow(unused_imports)]
pub use reference::{assert_patch_test_passes, assert_reference_within, reference_error};
#[allow(unused_imports)]
pub use scene_text::*;

use signorini_comm::Local;
use signorini_scene::{parse_toml, Method, SolvePath};
use signorini_solver::{run, RunOptions, RunOutput, SolveError};
use std::sync::LazyLock;

/// The path of a shipped example.
pub fn example_path(name: &str) -> String {
    format!("{}/examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The text of a shipped example.
pub fn example(name: &str) -> String {
    std::fs::read_to_string(example_path(name)).unwrap()
}

/// The text of a shipped example with its mesh paths made absolute, for a
/// scene parsed from text without its directory (the Gmsh examples name
/// their meshes relative to the scene).
pub fn example_with_meshes(name: &str) -> String {
    example(name).replace(
        "file = \"meshes/",
        &format!("file = \"{}/examples/meshes/", env!("CARGO_MANIFEST_DIR")),
    )
}

/// The names of a directory's entries, sorted.
pub fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Runs a scene given as TOML text in one process.
pub fn try_run(text: &str, opts: RunOptions) -> Result<RunOutput, SolveError> {
    let sc = parse_toml(text).unwrap_or_else(|e| panic!("scene: {e}"));
    run(&sc, "test", &opts, &Local).map(|o| o.expect("the root has the output"))
}

/// Runs a scene and asserts that it converged with every certificate
/// residual at most 1e-9.
pub fn converged(text: &str, opts: RunOptions) -> RunOutput {
    let out = try_run(text, opts).unwrap_or_else(|e| panic!("run: {e}"));
    assert!(
        out.report.converged,
        "not converged: {:?}",
        out.report.failure
    );
    assert!(
        out.report.certificate.max() <= 1e-9,
        "certificate above 1e-9: {:?}",
        out.report.certificate
    );
    out
}

/// Solves on a path, asserting convergence and the certificate.
pub fn converged_on(text: &str, path: SolvePath) -> RunOutput {
    converged(
        text,
        RunOptions {
            method: None,
            path: Some(path),
        },
    )
}

/// The normal force of every contact.csv row.
pub fn forces(o: &RunOutput) -> Vec<f64> {
    o.contact_rows.iter().map(|r| r.normal_force).collect()
}

/// The resultant force of the contact entry `name` in the report.
pub fn contact_force<'a>(o: &'a RunOutput, name: &str) -> &'a [f64] {
    &o.report
        .contacts
        .iter()
        .find(|c| c.name == name)
        .unwrap()
        .force
}

/// `signorini run <scene> --out <out>` as a user runs it, asserting that it
/// succeeded (with its stderr otherwise).
pub fn cli_run_ok(
    scene: impl AsRef<std::ffi::OsStr>,
    out: impl AsRef<std::ffi::OsStr>,
) -> std::process::Output {
    let status = cli_run(scene, out);
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    status
}

/// max |a − b| over max(|a|, |b|): the relative difference of two results.
pub fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a
        .iter()
        .chain(b)
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// A Hertz example's scene (a unit disk centred at [0, 1], pressed by the
/// displacement `press` of its top) with its lengths scaled by `l`: the
/// disk, the press and the reference's radius.
pub fn hertz_lengths_scaled(scene: &str, l: f64, press: f64) -> String {
    scene
        .replace(
            "center = [0.0, 1.0], radius = 1.0",
            &format!("center = [0.0, {l:e}], radius = {l:e}"),
        )
        .replace(
            &format!("displacement = {{ y = {press} }}"),
            &format!("displacement = {{ y = {:e} }}", press * l),
        )
        .replace("radius = 1.0\n", &format!("radius = {l:e}\n"))
}

/// hertz2d.toml (coarsened) with E in `young`, lengths scaled by `l`.
pub fn hertz_in_units(young: &str, l: f64) -> String {
    let scene = example("hertz2d.toml")
        .replace("young = 1.0", &format!("young = {young}"))
        .replace("divisions = 160", "divisions = 40");
    hertz_lengths_scaled(&scene, l, -0.015)
        .replace("point = [0.0, 1.0]", &format!("point = [0.0, {l:e}]"))
        .replace(
            "[[0.0, 0.0], [0.0, 1.0]]",
            &format!("[[0.0, 0.0], [0.0, {l:e}]]"),
        )
}

/// examples/patch3d.toml (consistent units of its own, read as MPa and mm)
/// in Pa and m: E × 1e6, lengths × 1e-3, traction × 1e6.
pub fn patch3d_in_pa_and_m() -> String {
    let si = example("patch3d.toml")
        .replace("young = 210.0", "young = 210e6")
        .replace("size = [1.0, 1.0, 0.5]", "size = [1e-3, 1e-3, 5e-4]")
        .replace("origin = [0.0, 0.0, 0.5]", "origin = [0.0, 0.0, 5e-4]")
        .replace("traction = [0.0, 0.0, -1.0]", "traction = [0.0, 0.0, -1e6]")
        .replace("pressure = 1.0", "pressure = 1e6");
    assert!(si.contains("size = [1e-3, 1e-3, 5e-4]") && si.contains("origin = [0.0, 0.0, 5e-4]"));
    si
}

/// A fresh, empty scratch directory `group/test` under `CARGO_TARGET_TMPDIR`.
pub fn fresh_dir(group: &str, test: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(test);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Asserts that a command exited with `code` (showing its stderr otherwise);
/// returns its stderr.
pub fn stderr_of_exit(out: &std::process::Output, code: i32) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{err}");
    err
}

/// Asserts that `text` (an error message) contains every one of `needles`.
#[track_caller]
pub fn assert_mentions(text: &str, needles: &[&str]) {
    let missing: Vec<&str> = needles
        .iter()
        .copied()
        .filter(|n| !text.contains(n))
        .collect();
    assert!(missing.is_empty(), "{missing:?} not in: {text}");
}

/// A run of the binary refused with exit 1, naming every one of `needles`
/// on stderr, and `out` not written.
#[track_caller]
pub fn assert_refused_unwritten(
    run: &std::process::Output,
    needles: &[&str],
    out: &std::path::Path,
) {
    let err = stderr_of_exit(run, 1);
    assert_mentions(&err, needles);
    assert!(!out.exists());
}

/// `value` of each contact row of `o` at `step` (1-based), in row order.
pub fn at_step<T>(
    o: &RunOutput,
    step: usize,
    value: impl Fn(&signorini_report::ContactRow) -> T,
) -> Vec<T> {
    (o.contact_rows.iter())
        .filter(|r| r.step == step)
        .map(value)
        .collect()
}

/// Asserts that `deviation(k)` falls at each slip stiffness k of
/// `stiffnesses` (in increasing order); returns the last deviation.
#[track_caller]
pub fn assert_falls_with_stiffness(stiffnesses: &[f64], deviation: impl Fn(f64) -> f64) -> f64 {
    let mut previous = f64::INFINITY;
    for &k in stiffnesses {
        let d = deviation(k);
        assert!(
            d < previous,
            "k_e = {k:e}: deviation {d:e} did not fall (previous {previous:e})"
        );
        previous = d;
    }
    previous
}

/// Asserts that one of the report's messages contains `needle`.
#[track_caller]
pub fn assert_message(out: &RunOutput, needle: &str) {
    assert_any_mentions(&out.report.messages, needle);
}

/// Asserts that one of `lines` contains `needle`.
#[track_caller]
pub fn assert_any_mentions(lines: &[String], needle: &str) {
    assert!(lines.iter().any(|m| m.contains(needle)), "{lines:?}");
}

/// The mortar patch example `name` (the surface `faces.0` of "pad",
/// slave, on the surface `faces.1` of "base", master) with
/// `discretization` instead; with `stiff_slave` the roles swapped.
pub fn mortar_patch_as(
    name: &str,
    discretization: &str,
    stiff_slave: bool,
    (pad, base): (&str, &str),
) -> String {
    let line = "discretization = \"mortar\"";
    let t = example(name).replace(line, &format!("discretization = \"{discretization}\""));
    if !stiff_slave {
        return t;
    }
    let side =
        |body: &str, surface: &str| format!("{{ body = \"{body}\", surface = \"{surface}\" }}");
    t.replace(
        &format!("slave = {}", side("pad", pad)),
        &format!("slave = {}", side("base", base)),
    )
    .replace(
        &format!("master = {}", side("base", base)),
        &format!("master = {}", side("pad", pad)),
    )
}

/// The example `name` with each `(from, to)` of `edits` replaced in turn.
pub fn example_with(name: &str, edits: &[(&str, &str)]) -> String {
    (edits.iter()).fold(example(name), |text, (from, to)| text.replace(from, to))
}

/// floating3d.toml (a box held by contact alone) with `extra` tables and
/// two steps, the second pulling the box off its support: bad input met
/// after the first step has written its output.
pub fn floating_pulled_off_at_step_2(extra: &str) -> String {
    format!(
        "{}\n{extra}[[steps]]\nscale = {{ load = 1.0 }}\n\n[[steps]]\nscale = {{ load = -1.0 }}\n",
        example("floating3d.toml")
    )
}

/// Asserts that a command succeeded (showing `context` and its stderr
/// otherwise); returns its stdout.
#[track_caller]
pub fn stdout_of_success(out: &std::process::Output, context: &str) -> String {
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{context}: {text} {}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// `text` with the line `subdomains = n` inserted after the first line
/// `after` (with its newline): the body of that line split in `n` parts.
pub fn with_subdomains(text: &str, after: &str, n: usize) -> String {
    text.replacen(after, &format!("{after}subdomains = {n}\n"), 1)
}

/// `text` with `search_distance = d` added to its (single) `[[contact]]`,
/// after its `discretization` line.
pub fn with_zone(text: &str, discretization: &str, d: f64) -> String {
    let line = format!("discretization = \"{discretization}\"\n");
    assert!(text.contains(&line), "test bug: no {line:?}");
    text.replacen(&line, &format!("{line}search_distance = {d}\n"), 1)
}

/// `text` with `friction = friction` added to each `[[contact]]` of the
/// `discretization` (after its `discretization` line).
pub fn with_friction(text: &str, discretization: &str, friction: &str) -> String {
    let line = format!("discretization = \"{discretization}\"");
    assert!(text.contains(&line), "test bug: no {line:?}");
    text.replace(&line, &format!("{line}\nfriction = {friction}"))
}

/// A block clamped on its top, pulled down by a traction on its bottom onto
/// a rigid cylinder 10⁻³ below: no prescribed motion, so the zone is the
/// search distance alone and 2 × 10⁻³ keeps 3 of the bottom nodes, while
/// the block touches the cylinder on about a fifth of its width.
pub const PULLED_BLOCK: SceneText = SceneText(|| {
    static TEXT: LazyLock<String> = LazyLock::new(|| {
        steel_block_scene(
        "block pulled onto a rigid cylinder",
        "{ generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [40, 10] }",
        &[
            "[[bodies]]\nname = \"cylinder\"\nrigid = { shape = \"circle\", center = [0.5, -1.001], radius = 1.0 }\n".to_string(),
            boundary("clamp", "block", "surface = \"top\"", "displacement = { x = 0.0, y = 0.0 }"),
            boundary("pull", "block", "surface = \"bottom\"", "traction = [0.0, -0.02]"),
            contact("block-cylinder", "block", "bottom", "cylinder")
                + "discretization = \"node_to_segment\"\n",
        ],
    )
    });
    &TEXT
});

/// Displacements of every body and contact forces agree to `tol`.
pub fn assert_same(a: &RunOutput, b: &RunOutput, tol: f64) {
    let fa: Vec<f64> = a.contact_rows.iter().map(|r| r.normal_force).collect();
    let fb: Vec<f64> = b.contact_rows.iter().map(|r| r.normal_force).collect();
    assert!(
        max_rel(&fa, &fb) <= tol,
        "contact forces differ by {:e}",
        max_rel(&fa, &fb)
    );
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        let r = max_rel(&x.last().displacement, &y.last().displacement);
        assert!(r <= tol, "body {}: displacements differ by {r:e}", x.name);
    }
}

/// The environment every `mpirun` of the tests runs with: as root in a
/// container, more ranks than cores, no binding (Open MPI 4 and 5).
pub fn mpi_env(c: &mut std::process::Command) -> &mut std::process::Command {
    c.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .env("PRTE_MCA_rmaps_default_mapping_policy", ":oversubscribe")
        .env("OMPI_MCA_hwloc_base_binding_policy", "none")
}

/// The `.pvtu` index of `body` at `step` in the output directory `dir`
/// against the gathered `<body>_<step>.vtu` (`[output] pieces`): the index
/// parses, declares the gathered arrays and `node`; each piece it names
/// exists and holds exactly the declared arrays (names, components, types);
/// the pieces cover every node of the body, each point at its node's
/// coordinates with its node's point values (to 1e-12 of each array's
/// largest value), and their cells are the body's (the same count, and the
/// same values of each cell array component, sorted). Returns the pieces.
pub fn check_pieces(dir: &std::path::Path, body: &str, step: usize) -> Vec<String> {
    use signorini_report::vtu::{read_pvtu, read_vtu, ArrayData};
    let index = dir.join(format!("{body}_{step}.pvtu"));
    let (declared, sources) = read_pvtu(&index).unwrap_or_else(|e| panic!("{e}"));
    let whole = read_vtu(&dir.join(format!("{body}_{step}.vtu"))).unwrap();
    let decl = |a: &[ArrayData]| -> Vec<(String, u32, String)> {
        (a.iter())
            .map(|x| (x.name.clone(), x.components, x.scalar_type.clone()))
            .collect()
    };
    let mut expected = decl(&whole.point_data);
    expected.push(("node".into(), 1, "U64".into()));
    assert_eq!(decl(&declared.point_data), expected, "{}", index.display());
    assert_eq!(decl(&declared.cell_data), decl(&whole.cell_data));
    assert!(!sources.is_empty());
    let scale = |a: &ArrayData| {
        a.values
            .iter()
            .fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()))
    };
    let mut seen = vec![false; whole.points.len()];
    let (mut cells, mut cell_values) = (0, vec![Vec::new(); whole.cell_data.len()]);
    for s in &sources {
        let piece = read_vtu(&dir.join(s)).unwrap_or_else(|e| panic!("piece {s}: {e}"));
        assert_eq!(decl(&piece.point_data), decl(&declared.point_data), "{s}");
        assert_eq!(decl(&piece.cell_data), decl(&declared.cell_data), "{s}");
        let node = &piece.point_data.last().unwrap().values;
        assert_eq!(node.len(), piece.points.len());
        for (l, &g) in node.iter().enumerate() {
            let g = g as usize;
            seen[g] = true;
            assert_eq!(piece.points[l], whole.points[g], "{s}: point {l}");
            for (a, b) in whole.point_data.iter().zip(&piece.point_data) {
                let c = a.components as usize;
                let (x, y) = (&a.values[c * g..c * (g + 1)], &b.values[c * l..c * (l + 1)]);
                for (x, y) in x.iter().zip(y) {
                    assert!((x - y).abs() <= 1e-12 * scale(a), "{s}: {} {x} {y}", a.name);
                }
            }
        }
        cells += piece.cells;
        for (v, b) in cell_values.iter_mut().zip(&piece.cell_data) {
            v.extend_from_slice(&b.values);
        }
    }
    assert!(
        seen.iter().all(|&s| s),
        "{body} step {step}: a node in no piece"
    );
    assert_eq!(cells, whole.cells);
    for (a, v) in whole.cell_data.iter().zip(cell_values) {
        let c = a.components as usize;
        assert_eq!(v.len(), a.values.len());
        for k in 0..c {
            let sorted = |x: &[f64]| {
                let mut col: Vec<f64> = x.iter().skip(k).step_by(c).copied().collect();
                col.sort_by(f64::total_cmp);
                col
            };
            for (x, y) in sorted(&a.values).iter().zip(sorted(&v)) {
                assert!((x - y).abs() <= 1e-12 * scale(a), "{} {x} {y}", a.name);
            }
        }
    }
    sources
}

/// examples/stack.toml (roller 1 subdomain, plate and base 2 each) in two
/// load steps, with `[output] pieces` as given.
pub fn stack_pieces(pieces: bool) -> String {
    example("stack.toml").replace("[output]\n", &format!("[output]\npieces = {pieces}\n"))
        + "\n[[steps]]\nscale = { press = 0.5 }\n\n[[steps]]\nscale = { press = 1.0 }\n"
}

/// [`check_pieces`] on every body of [`stack_pieces`] at both steps: the
/// pieces are those of the subdomains, pieces.pvd names the six indexes.
pub fn check_stack_pieces(out: &std::path::Path) {
    for step in [1, 2] {
        for (body, parts) in [("roller", 1), ("plate", 2), ("base", 2)] {
            let sources = check_pieces(out, body, step);
            let expected: Vec<String> = (0..parts)
                .map(|p| format!("pieces/{body}_{step}_s{p}.vtu"))
                .collect();
            assert_eq!(sources, expected);
        }
    }
    let pvd = std::fs::read_to_string(out.join("pieces.pvd")).unwrap();
    assert_eq!(pvd.matches(".pvtu\"/>").count(), 6, "{pvd}");
    assert_eq!(std::fs::read_dir(out.join("pieces")).unwrap().count(), 10);
}

/// Hertz between two bodies, `scene(discretization)` solved on the
/// condensed path: mortar's relative errors of p0, of the pressure profile
/// (L2) and of a are at most `bounds`, and those of p0 and the profile
/// (and of a with `a_too`) at most `other`'s.
pub fn assert_mortar_at_least_as_accurate(
    scene: impl Fn(&str) -> String,
    other: &str,
    bounds: [f64; 3],
    a_too: bool,
) {
    let err = |d: &str| {
        let (p0, a, profile, _) = hertz_errors(&converged_on(&scene(d), SolvePath::Condensed));
        [p0, profile, a]
    };
    let (m, n) = (err("mortar"), err(other));
    eprintln!("mortar p0, profile, a {m:.4?}; {other} {n:.4?}");
    for (k, what) in ["p0", "profile", "a"].into_iter().enumerate() {
        let against = k < 2 || a_too;
        assert!(
            (!against || m[k] <= n[k]) && m[k] <= bounds[k],
            "{what}: mortar {}, {other} {}",
            m[k],
            n[k]
        );
    }
}

/// The relative errors of Hertz's p0, a and pressure profile (L2) of a
/// run, and the exact a.
pub fn hertz_errors(o: &RunOutput) -> (f64, f64, f64, f64) {
    let q = &o.report.reference.as_ref().unwrap().quantities;
    (
        q["p0"].relative_error,
        q["a"].relative_error,
        q["profile_l2"].relative_error,
        q["a"].exact,
    )
}

/// The binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_signorini");

/// `signorini <args>` as a user runs it, to its end.
pub fn signorini(args: &[&str]) -> std::process::Output {
    std::process::Command::new(BIN).args(args).output().unwrap()
}

/// `signorini run <scene> --out <out>` as a user runs it, to its end.
pub fn cli_run(
    scene: impl AsRef<std::ffi::OsStr>,
    out: impl AsRef<std::ffi::OsStr>,
) -> std::process::Output {
    std::process::Command::new(BIN)
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// Whether `mpirun` runs here; on CI (`CI` set) its absence is a failure,
/// elsewhere the MPI tests are skipped.
pub fn have_mpirun() -> bool {
    have_program("mpirun", "ci/setup.sh must install openmpi-bin")
}

/// Whether `program --version` runs here; on CI (`CI` set) its absence is a
/// failure (`install` says what provides it).
pub fn have_program(program: &str, install: &str) -> bool {
    let ok = std::process::Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok && std::env::var_os("CI").is_some() {
        panic!("`{program}` is missing on CI: {install}");
    }
    ok
}

/// `mpirun -n <np> signorini` with [`mpi_env`]: add the arguments.
pub fn mpirun(np: usize) -> std::process::Command {
    let mut c = std::process::Command::new("mpirun");
    c.arg("-n").arg(np.to_string()).arg(BIN);
    mpi_env(&mut c);
    c
}

/// The patch test `scene` run in one process and under `mpirun -n 2` (in
/// the fresh directory `group/mpirun2`, returned; `None` without mpirun):
/// two ranks and two subdomains, `rows` rows of contact.csv the same to
/// 1e-10, and the pressure (the column `from_end` from the row's end) the
/// unit traction.
pub fn patch_under_mpirun_2(
    group: &str,
    scene: &str,
    rows: usize,
    from_end: usize,
) -> Option<std::path::PathBuf> {
    if !have_mpirun() {
        return None;
    }
    let d = fresh_dir(group, "mpirun2");
    let a = contact_csv_of_run(false, scene, &d.join("local"));
    let b = contact_csv_of_run(true, scene, &d.join("mpi"));
    let report = std::fs::read_to_string(d.join("mpi").join("report.json")).unwrap();
    let report: serde_json::Value = serde_json::from_str(&report).unwrap();
    assert_eq!(report["ranks"], 2);
    assert_eq!(report["subdomains"], 2);
    assert_eq!(a.len(), rows);
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!(max_rel(x, y) <= 1e-10, "{x:?} vs {y:?}");
    }
    for r in &b {
        let p = r[r.len() - from_end];
        assert!((p - 1.0).abs() <= 1e-8, "pressure {p}");
    }
    Some(d)
}

/// contact.csv of `signorini run <scene> --out <out>`, in one process or
/// under `mpirun -n 2`, asserting that the run succeeded: its rows' numbers
/// (header skipped, the fields that are not numbers dropped).
pub fn contact_csv_of_run(
    mpi: bool,
    scene: impl AsRef<std::ffi::OsStr>,
    out: &std::path::Path,
) -> Vec<Vec<f64>> {
    let mut c = if mpi {
        mpirun(2)
    } else {
        std::process::Command::new(BIN)
    };
    let o = c
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| l.split(',').filter_map(|v| v.parse().ok()).collect())
        .collect()
}

/// The message of the bad-input error a scene given as text is refused with.
pub fn input_error(text: &str) -> String {
    match try_run(text, RunOptions::default()) {
        Err(SolveError::Input(m)) => m,
        Err(e) => panic!("not an input error: {e}"),
        Ok(_) => panic!("accepted"),
    }
}

/// The example `name` with its `discretization` made mortar is refused as
/// bad input naming each of `needles`.
#[track_caller]
pub fn assert_mortar_refused(name: &str, discretization: &str, needles: &[&str]) {
    let from = format!("\"{discretization}\"");
    assert_mentions(
        &input_error(&example(name).replace(&from, "\"mortar\"")),
        needles,
    );
}

/// Run options choosing `method`, the path left to the scene.
pub fn with_method(method: Method) -> RunOptions {
    RunOptions {
        method: Some(method),
        path: None,
    }
}

/// The largest relative deviation of the contact pressure from `p` over
/// contact.csv's rows, and the total normal force.
pub fn pressure_error(o: &RunOutput, p: f64) -> (f64, f64) {
    let dev = o
        .contact_rows
        .iter()
        .fold(0.0f64, |m, r| m.max((r.pressure - p).abs() / p));
    (dev, o.contact_rows.iter().map(|r| r.normal_force).sum())
}

/// Runs the binary with a time limit (a hang is a failure, not a stuck
/// test), and with `RUST_BACKTRACE=1`, so that a backtrace would show.
pub fn run_limited(
    mut cmd: std::process::Command,
    limit: std::time::Duration,
) -> (std::process::Output, std::time::Duration) {
    let t = std::time::Instant::now();
    let mut child = cmd
        .env("RUST_BACKTRACE", "1")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("cannot start the signorini binary");
    loop {
        if child.try_wait().expect("wait").is_some() {
            return (child.wait_with_output().expect("output"), t.elapsed());
        }
        if t.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().expect("output");
            return (out, t.elapsed());
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}
