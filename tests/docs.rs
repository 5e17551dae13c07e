//! The generated documentation stays true: the validation and examples
//! tables (docs/validation) agree with a fresh run of the examples, the
//! command-line reference (docs/reference/cli.md) with the binary's help,
//! and the tutorials (docs/tutorial/*.md) run.
//!
//! What a tutorial runs, in the order of the file, in a scratch directory
//! where the repository's examples are `examples/`:
//! - a block with the info string `toml file=NAME.toml` is written to
//!   NAME.toml (a relative path, no `..`);
//! - each line of a `sh` block is one command, run by `sh -c` in that
//!   directory (so a `cd` lasts one line; a line ending in `\` goes on with
//!   the next); `signorini` is the binary under test (not `cargo run`);
//!   lines starting with `mpirun` run only in a build with the `mpi` feature
//!   where mpirun exists; `#` lines and empty lines are skipped; each must
//!   exit 0 (`|| true` for a command shown failing);
//! - every other block (`toml` without `file=`, `text`, `console`, ...) is
//!   prose.
//!
//! A failure names the tutorial and the line of the command, with its
//! stdout and stderr.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The relative tolerance between a committed number and a fresh run's;
/// the tables' headers state it (asserted below).
const RELATIVE_TOLERANCE: f64 = 1e-3;

const REGENERATE_TABLES: &str =
    "cargo run --release -- docs validation --examples examples --out docs/validation";
const REGENERATE_CLI: &str = "cargo run --release -- docs cli --out docs/reference/cli.md";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn signorini() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

/// A fresh directory under the system's temporary one.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-docs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

// ---------------------------------------------------------------------------
// Tables compared number by number

/// A token of a table cell: a number (compared within the tolerance, or
/// exactly when an integer) or text (compared exactly).
fn tokens(cell: &str) -> Vec<&str> {
    cell.split_whitespace()
        .map(|t| t.trim_matches(|c| matches!(c, '(' | ')' | ',' | ';')))
        .filter(|t| !t.is_empty())
        .collect()
}

fn is_integer(t: &str) -> bool {
    let digits = t.strip_prefix('-').unwrap_or(t);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
}

/// Why two tokens disagree, or None.
fn token_difference(committed: &str, fresh: &str, tolerance: f64) -> Option<String> {
    if committed == fresh {
        return None;
    }
    let numbers = (committed.parse::<f64>(), fresh.parse::<f64>());
    let (Ok(a), Ok(b)) = numbers else {
        return Some(format!("committed \"{committed}\", fresh \"{fresh}\""));
    };
    if is_integer(committed) && is_integer(fresh) || !(a.is_finite() && b.is_finite()) {
        return Some(format!("committed {committed}, fresh {fresh}"));
    }
    let difference = (a - b).abs() / a.abs().max(b.abs());
    (difference > tolerance).then(|| {
        format!(
            "committed {committed}, fresh {fresh}: relative difference {difference:.2e} > {tolerance:e}"
        )
    })
}

fn cells(row: &str) -> Vec<&str> {
    row.trim()
        .trim_matches('|')
        .split('|')
        .map(str::trim)
        .collect()
}

/// Compares a committed generated file with a fresh one: table rows cell
/// by cell, token by token (numbers within `tolerance`), every other line
/// as text. Every disagreement is listed, naming the file, line, row and
/// column.
fn compare_tables(name: &str, committed: &str, fresh: &str, tolerance: f64) -> Vec<String> {
    let (old, new): (Vec<&str>, Vec<&str>) = (committed.lines().collect(), fresh.lines().collect());
    if old.len() != new.len() {
        return vec![format!(
            "{name}: {} lines committed, {} in a fresh run (an example or a quantity added or removed)",
            old.len(),
            new.len()
        )];
    }
    let mut header: Vec<&str> = Vec::new();
    let mut found = Vec::new();
    for (i, (a, b)) in old.iter().zip(&new).enumerate() {
        let at = format!("{name}:{}", i + 1);
        if !(a.starts_with('|') && b.starts_with('|')) {
            if a != b {
                found.push(format!("{at}: committed \"{a}\", fresh \"{b}\""));
            }
            header.clear();
            continue;
        }
        let (ca, cb) = (cells(a), cells(b));
        if header.is_empty() {
            header = ca.clone();
        }
        if ca.len() != cb.len() {
            found.push(format!(
                "{at}: {} cells committed, {} fresh",
                ca.len(),
                cb.len()
            ));
            continue;
        }
        for (c, (x, y)) in ca.iter().zip(&cb).enumerate() {
            let column = header.get(c).copied().unwrap_or("?");
            let (tx, ty) = (tokens(x), tokens(y));
            let why = if tx.len() != ty.len() {
                Some(format!("committed \"{x}\", fresh \"{y}\""))
            } else {
                (tx.iter().zip(&ty)).find_map(|(p, q)| token_difference(p, q, tolerance))
            };
            if let Some(why) = why {
                let row = ca[..ca.len().min(2)].join(" | ");
                found.push(format!("{at} (row \"{row}\"), column \"{column}\": {why}"));
            }
        }
    }
    found
}

#[test]
fn the_table_comparison_accepts_round_off_and_names_a_real_difference() {
    let committed =
        "# T\n\n| scene | DOFs | error |\n| --- | --- | --- |\n| a.toml | 120 | 2.216e-3 (p0) |\n";
    let close = committed.replace("2.216e-3", "2.2161e-3");
    assert!(compare_tables("t.md", committed, &close, 1e-3).is_empty());
    // beyond the tolerance: named by file, line, row and column
    let far = committed.replace("2.216e-3", "2.3e-3");
    let found = compare_tables("t.md", committed, &far, 1e-3);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with("t.md:5 (row \"a.toml | 120\"), column \"error\"")
            && found[0].contains("2.216e-3")
            && found[0].contains("2.3e-3"),
        "{}",
        found[0]
    );
    // integers exactly, text exactly, rows and prose counted
    let dofs = committed.replace("| 120 |", "| 121 |");
    assert!(compare_tables("t.md", committed, &dofs, 1e-3)[0].contains("column \"DOFs\""));
    let name = committed.replace("(p0)", "(a)");
    assert!(compare_tables("t.md", committed, &name, 1e-3)[0].contains("\"p0\""));
    let prose = committed.replace("# T", "# U");
    assert!(compare_tables("t.md", committed, &prose, 1e-3)[0].starts_with("t.md:1:"));
    let more = format!("{committed}| b.toml | 1 | 0.1 |\n");
    assert!(compare_tables("t.md", committed, &more, 1e-3)[0].contains("lines"));
}

/// Runs every example (at its shipped size) and compares both tables with
/// the committed ones.
#[test]
fn the_validation_and_examples_tables_agree_with_a_fresh_run() {
    let out = scratch("validation");
    let run = signorini()
        .current_dir(root())
        .args(["docs", "validation", "--examples", "examples", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "docs validation: {:?}\n{}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    let mut found = Vec::new();
    for file in ["README.md", "examples.md"] {
        let name = format!("docs/validation/{file}");
        let committed = read(&root().join(&name));
        let stated = format!("more than a relative {RELATIVE_TOLERANCE:e}");
        assert!(
            committed.contains(&stated),
            "{name} must state \"{stated}\""
        );
        found.extend(compare_tables(
            &name,
            &committed,
            &read(&out.join(file)),
            RELATIVE_TOLERANCE,
        ));
    }
    assert!(
        found.is_empty(),
        "the committed tables disagree with a fresh run; if the change is meant, regenerate them with `{REGENERATE_TABLES}`:\n{}",
        found.join("\n")
    );
    // every example has its row, and every reference at least one quantity
    let examples = read(&root().join("docs/validation/examples.md"));
    for entry in std::fs::read_dir(root().join("examples")).unwrap() {
        let file = entry.unwrap().file_name().to_string_lossy().to_string();
        if file.ends_with(".toml") {
            assert!(examples.contains(&format!("[{file}]")), "{file} has no row");
            let scene = read(&root().join("examples").join(&file));
            let validation = read(&root().join("docs/validation/README.md"));
            if scene.contains("\n[reference]") {
                assert!(
                    validation.contains(&format!("[{file}]")),
                    "{file}: no quantity"
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// Bad input to `docs validation` and `docs cli`: exit 1, the entry named,
/// nothing written.
#[test]
fn docs_refuses_a_missing_examples_directory_a_bad_scene_and_an_unwritable_out() {
    let dir = scratch("bad");
    let out = dir.join("tables");
    let validation = |examples: &Path, out: &Path| {
        let o = signorini()
            .args(["docs", "validation", "--examples"])
            .arg(examples)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (code, e) = validation(&dir.join("none"), &out);
    assert_eq!(code, Some(1), "{e}");
    assert!(e.contains("--examples") && e.contains("none"), "{e}");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let (code, e) = validation(&empty, &out);
    assert_eq!(code, Some(1), "{e}");
    assert!(e.contains("no *.toml scene"), "{e}");
    // a bad scene beside a good one: named, and no table written
    let mixed = dir.join("mixed");
    std::fs::create_dir_all(&mixed).unwrap();
    std::fs::copy(root().join("examples/blocks.toml"), mixed.join("a.toml")).unwrap();
    std::fs::write(mixed.join("b.toml"), "dimension = 4\n").unwrap();
    let (code, e) = validation(&mixed, &out);
    assert_eq!(code, Some(1), "{e}");
    assert!(e.contains("b.toml") && e.contains("dimension"), "{e}");
    assert!(!out.exists(), "nothing is written");
    // --out under a regular file
    let file = dir.join("file");
    std::fs::write(&file, "").unwrap();
    let (code, e) = validation(&root().join("examples"), &file.join("tables"));
    assert_eq!(code, Some(1), "{e}");
    assert!(e.contains("--out"), "{e}");
    let o = signorini()
        .args(["docs", "cli", "--out"])
        .arg(file.join("cli.md"))
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("--out") && e.contains("cli.md"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------
// The command-line reference

#[test]
fn the_cli_reference_is_what_the_binary_prints() {
    let printed = signorini().args(["docs", "cli"]).output().unwrap();
    assert!(printed.status.success());
    let printed = String::from_utf8(printed.stdout).unwrap();
    let committed = read(&root().join("docs/reference/cli.md"));
    assert!(
        committed == printed,
        "docs/reference/cli.md differs from what the binary prints; regenerate it with `{REGENERATE_CLI}`"
    );
    // each command's own --help, verbatim
    let commands: Vec<Vec<&str>> = vec![
        vec![],
        vec!["run"],
        vec!["check"],
        vec!["local"],
        vec!["bench"],
        vec!["docs"],
        vec!["docs", "validation"],
        vec!["docs", "cli"],
    ];
    for args in commands {
        let help = signorini().args(&args).arg("--help").output().unwrap();
        assert!(help.status.success(), "{args:?} --help");
        let help = String::from_utf8(help.stdout).unwrap();
        let title = format!(
            "## `{}`",
            ["signorini"]
                .iter()
                .chain(&args)
                .copied()
                .collect::<Vec<_>>()
                .join(" ")
        );
        let block = format!("{title}\n\n```text\n{}\n```\n", help.trim_end());
        assert!(
            committed.contains(&block),
            "docs/reference/cli.md: no section {title} holding `--help` verbatim"
        );
    }
}

// ---------------------------------------------------------------------------
// Tutorials that run

/// What a tutorial asks to do, in order, with the 1-based line it is on.
#[derive(Debug, PartialEq)]
enum Action {
    /// A ```toml file=NAME block: its text, written to NAME.
    Write {
        line: usize,
        name: String,
        text: String,
    },
    /// A line of a ```sh block (continuation lines joined).
    Command { line: usize, command: String },
}

/// The actions of a tutorial: ```toml file=NAME blocks and the lines of
/// ```sh blocks, `#` comments and empty lines left out; every other block
/// is prose. An unterminated block is an error naming its line.
fn tutorial_actions(text: &str) -> Result<Vec<Action>, String> {
    let mut actions = Vec::new();
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    while let Some((start, line)) = lines.next() {
        let Some(info) = line.trim_start().strip_prefix("```") else {
            continue;
        };
        let mut body = Vec::new();
        let closed = loop {
            match lines.next() {
                Some((_, l)) if l.trim() == "```" => break true,
                Some((n, l)) => body.push((n, l)),
                None => break false,
            }
        };
        if !closed {
            return Err(format!("line {start}: a ``` block is never closed"));
        }
        let words: Vec<&str> = info.split_whitespace().collect();
        match words.first().copied() {
            Some("toml") => {
                let name = words.iter().find_map(|w| w.strip_prefix("file="));
                if let Some(name) = name {
                    let bad = name.is_empty()
                        || name.starts_with('/')
                        || name.split('/').any(|p| p == "..");
                    if bad {
                        return Err(format!("line {start}: file={name}: a relative path within the tutorial's directory is needed"));
                    }
                    let text = body.iter().map(|(_, l)| format!("{l}\n")).collect();
                    actions.push(Action::Write {
                        line: start,
                        name: name.to_string(),
                        text,
                    });
                }
            }
            Some("sh") => actions.extend(sh_commands(&body)),
            _ => {}
        }
    }
    Ok(actions)
}

/// The commands of a ```sh block: a line ending in `\` goes on with the
/// next one.
fn sh_commands(body: &[(usize, &str)]) -> Vec<Action> {
    let mut commands = Vec::new();
    let mut pending: Option<(usize, String)> = None;
    for &(n, l) in body {
        let t = l.trim();
        if pending.is_none() && (t.is_empty() || t.starts_with('#')) {
            continue;
        }
        let (line, mut command) = pending.take().unwrap_or((n, String::new()));
        match t.strip_suffix('\\') {
            Some(part) => {
                command.push_str(part);
                command.push(' ');
                pending = Some((line, command));
            }
            None => {
                command.push_str(t);
                commands.push(Action::Command { line, command });
            }
        }
    }
    if let Some((line, command)) = pending {
        commands.push(Action::Command { line, command });
    }
    commands
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(program).is_file()))
}

/// Runs a tutorial in a scratch directory where the repository's examples
/// are `examples/` and `signorini` is the built binary; `mpirun` lines run
/// only in a build with MPI where mpirun exists. Returns the number of
/// commands run, or the first failure naming `name` and its line.
fn run_tutorial(name: &str, text: &str) -> Result<usize, String> {
    let actions = tutorial_actions(text).map_err(|e| format!("{name}: {e}"))?;
    let dir = scratch(&name.replace('/', "_"));
    let work = dir.join("tutorial");
    let bin = dir.join("bin");
    std::fs::create_dir_all(&work).unwrap();
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(root().join("examples"), work.join("examples")).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_signorini"), bin.join("signorini")).unwrap();
    let path = std::env::join_paths(std::iter::once(bin.clone()).chain(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    )))
    .unwrap();
    let mpi = cfg!(feature = "mpi") && on_path("mpirun");
    let mut ran = 0;
    for action in actions {
        match action {
            Action::Write {
                line,
                name: file,
                text,
            } => {
                let target = work.join(&file);
                std::fs::create_dir_all(target.parent().unwrap()).unwrap();
                std::fs::write(&target, text)
                    .map_err(|e| format!("{name}:{line}: cannot write {file}: {e}"))?;
            }
            Action::Command { command, .. } if command.starts_with("mpirun") && !mpi => {}
            Action::Command { line, command } => {
                let out = Command::new("sh")
                    .arg("-c")
                    .arg(&command)
                    .current_dir(&work)
                    .env("PATH", &path)
                    .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
                    .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
                    .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
                    .env("OMPI_MCA_hwloc_base_binding_policy", "none")
                    .output()
                    .map_err(|e| format!("{name}:{line}: cannot start sh: {e}"))?;
                if !out.status.success() {
                    return Err(format!(
                        "{name}:{line}: `{command}` failed ({}) in {}\n--- stdout\n{}--- stderr\n{}",
                        out.status,
                        work.display(),
                        String::from_utf8_lossy(&out.stdout),
                        String::from_utf8_lossy(&out.stderr)
                    ));
                }
                ran += 1;
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(ran)
}

const FIXTURE: &str = r#"# A tutorial

Write the scene:

```toml file=small.toml
dimension = 2
[[materials]]
name = "m"
young = 1.0
poisson = 0.3
[[bodies]]
name = "block"
material = "m"
mesh = { generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }
[[bodies]]
name = "ground"
rigid = { shape = "plane", point = [0.0, 0.0], normal = [0.0, 1.0] }
[[boundary]]
body = "block"
surface = "top"
displacement = { y = -0.01 }
[[boundary]]
body = "block"
point = [0.0, 0.5]
displacement = { x = 0.0 }
[[contact]]
name = "c"
slave = { body = "block", surface = "bottom" }
master = { body = "ground" }
```

```toml
# not a file: never written
```

Run it:

```sh
# a comment
signorini check small.toml
signorini run small.toml \
    --out out/small --quiet
test -f out/small/report.json
ls examples/hertz2d.toml
mpirun -n 2 signorini run small.toml --out out/mpi --quiet
```

```text
this is not run
false
```
"#;

#[test]
fn a_tutorial_is_read_as_files_and_commands_in_order() {
    let actions = tutorial_actions(FIXTURE).unwrap();
    assert_eq!(actions.len(), 6, "{actions:?}");
    match &actions[0] {
        Action::Write { line, name, text } => {
            assert_eq!((*line, name.as_str()), (5, "small.toml"));
            assert!(
                text.starts_with("dimension = 2\n")
                    && text.ends_with("master = { body = \"ground\" }\n")
            );
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        actions[2],
        Action::Command {
            line: 41,
            command: "signorini run small.toml  --out out/small --quiet".into()
        }
    );
    assert!(tutorial_actions("```sh\nls\n")
        .unwrap_err()
        .contains("line 1"));
    let e = tutorial_actions("```toml file=../x.toml\n```\n").unwrap_err();
    assert!(e.contains("line 1") && e.contains("../x.toml"), "{e}");
}

#[test]
fn a_tutorial_runs_and_a_failing_command_is_named_by_file_and_line() {
    let ran = run_tutorial("fixture.md", FIXTURE).unwrap_or_else(|e| panic!("{e}"));
    let mpi = cfg!(feature = "mpi") && on_path("mpirun");
    assert_eq!(ran, if mpi { 5 } else { 4 });
    let broken = FIXTURE.replace("signorini check small.toml", "signorini check missing.toml");
    let e = run_tutorial("broken.md", &broken).unwrap_err();
    assert!(
        e.starts_with("broken.md:40: `signorini check missing.toml` failed"),
        "{e}"
    );
    assert!(e.contains("missing.toml"), "{e}");
}

/// Every docs/tutorial/*.md runs.
#[test]
fn the_tutorials_run() {
    let dir = root().join("docs/tutorial");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return;
    };
    let mut files: Vec<PathBuf> = entries
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    files.sort();
    for file in files {
        let name = file.strip_prefix(root()).unwrap().display().to_string();
        if let Err(e) = run_tutorial(&name, &read(&file)) {
            panic!("{e}");
        }
    }
}

// ---------------------------------------------------------------------------
// The crate graph of docs/architecture.md

/// Each crate (its directory under `crates/`) and the workspace crates it
/// depends on.
type Graph = BTreeMap<String, BTreeSet<String>>;

const GRAPH_HEADING: &str = "## Crate dependencies";

/// The table under [`GRAPH_HEADING`] of docs/architecture.md: rows
/// `` | `crate` | `dep`, `dep` | ``, after the header and its rule.
fn documented_graph(text: &str) -> Result<Graph, String> {
    let start = text
        .find(GRAPH_HEADING)
        .ok_or_else(|| format!("no \"{GRAPH_HEADING}\" section"))?;
    let names = |cell: &str| -> BTreeSet<String> {
        cell.split(',')
            .map(|n| n.trim().trim_matches('`').to_string())
            .filter(|n| !n.is_empty())
            .collect()
    };
    let mut graph = Graph::new();
    let rows = text[start..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2);
    for row in rows {
        let cells: Vec<&str> = row.trim_matches('|').split('|').collect();
        let [krate, deps] = cells[..] else {
            return Err(format!("the row \"{row}\" has not two cells"));
        };
        let krate = krate.trim().trim_matches('`').to_string();
        if graph.insert(krate.clone(), names(deps)).is_some() {
            return Err(format!("the crate {krate} has two rows"));
        }
    }
    if graph.is_empty() {
        return Err(format!("the \"{GRAPH_HEADING}\" section has no table"));
    }
    Ok(graph)
}

/// The workspace dependencies (`signorini-*`: dependencies, dev- and
/// build-dependencies) of every `crates/*/Cargo.toml`.
fn declared_graph(root: &Path) -> Graph {
    let mut graph = Graph::new();
    for entry in std::fs::read_dir(root.join("crates")).unwrap() {
        let dir = entry.unwrap().path();
        let manifest = dir.join("Cargo.toml");
        if !manifest.exists() {
            continue;
        }
        let name = dir.file_name().unwrap().to_string_lossy().to_string();
        let parsed: toml::Table = read(&manifest)
            .parse()
            .unwrap_or_else(|e| panic!("{}: {e}", manifest.display()));
        let package = parsed["package"]["name"].as_str().unwrap_or_default();
        assert_eq!(
            package,
            format!("signorini-{name}"),
            "{}",
            manifest.display()
        );
        let deps = ["dependencies", "dev-dependencies", "build-dependencies"]
            .iter()
            .filter_map(|section| parsed.get(*section).and_then(|t| t.as_table()))
            .flat_map(|t| t.keys())
            .filter_map(|k| k.strip_prefix("signorini-"))
            .map(str::to_string)
            .collect();
        graph.insert(name, deps);
    }
    graph
}

/// What differs between the documented graph and the declared one, and a
/// cycle of the documented graph, one line each.
fn graph_differences(documented: &Graph, declared: &Graph) -> Vec<String> {
    let empty = BTreeSet::new();
    let mut found = Vec::new();
    let crates: BTreeSet<&String> = documented.keys().chain(declared.keys()).collect();
    for krate in crates {
        let (doc, dec) = (documented.get(krate), declared.get(krate));
        match (doc, dec) {
            (None, _) => found.push(format!("crates/{krate} has no row in the table")),
            (_, None) => found.push(format!("the table's {krate} is not a crate under crates/")),
            _ => {}
        }
        let (doc, dec) = (doc.unwrap_or(&empty), dec.unwrap_or(&empty));
        for d in dec.difference(doc) {
            found.push(format!(
                "crates/{krate}/Cargo.toml depends on {d}, which the table does not allow"
            ));
        }
        for d in doc.difference(dec) {
            found.push(format!(
                "the table lists {krate} -> {d}, which crates/{krate}/Cargo.toml does not declare"
            ));
        }
    }
    found.extend(
        graph_cycle(documented).map(|c| format!("the table has a cycle: {}", c.join(" -> "))),
    );
    found
}

/// A cycle of the graph (its crates in order, the first repeated last), if any.
fn graph_cycle(graph: &Graph) -> Option<Vec<String>> {
    fn visit(
        graph: &Graph,
        at: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == at) {
            let mut cycle = path[i..].to_vec();
            cycle.push(at.to_string());
            return Some(cycle);
        }
        if done.contains(at) {
            return None;
        }
        path.push(at.to_string());
        for next in graph.get(at).into_iter().flatten() {
            if let Some(c) = visit(graph, next, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(at.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|k| visit(graph, k, &mut Vec::new(), &mut done))
}

#[test]
fn the_crate_graph_is_the_one_docs_architecture_states() {
    let documented = documented_graph(&read(&root().join("docs/architecture.md")))
        .unwrap_or_else(|e| panic!("docs/architecture.md: {e}"));
    let found = graph_differences(&documented, &declared_graph(&root()));
    assert!(
        found.is_empty(),
        "the crates' manifests and the table \"{GRAPH_HEADING}\" of docs/architecture.md disagree:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_crate_graph_check_names_an_extra_dependency_a_stale_row_and_a_cycle() {
    let table = format!(
        "{GRAPH_HEADING}\n\ntext\n\n| crate | depends on |\n|---|---|\n| `mesh` | |\n| `fem` | `mesh` |\n| `contact` | `mesh`, `fem` |\n\nprose\n"
    );
    let documented = documented_graph(&table).unwrap();
    assert_eq!(documented["contact"].len(), 2);
    assert!(documented["mesh"].is_empty());
    let set = |names: &[&str]| names.iter().map(|n| n.to_string()).collect::<BTreeSet<_>>();
    let mut declared = Graph::new();
    declared.insert("mesh".into(), set(&[]));
    declared.insert("fem".into(), set(&["mesh"]));
    declared.insert("contact".into(), set(&["mesh", "fem"]));
    assert!(graph_differences(&documented, &declared).is_empty());
    // a dependency the table does not allow, and one it lists in vain
    declared.insert("fem".into(), set(&["contact"]));
    let found = graph_differences(&documented, &declared);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(
        found[0].contains("crates/fem/Cargo.toml depends on contact"),
        "{found:?}"
    );
    assert!(
        found[1].contains("the table lists fem -> mesh"),
        "{found:?}"
    );
    // a crate without a row
    declared.insert("geometry".into(), set(&["mesh"]));
    let found = graph_differences(&documented, &declared);
    assert!(
        found
            .iter()
            .any(|f| f == "crates/geometry has no row in the table"),
        "{found:?}"
    );
    // a cycle in the table
    let cyclic = table.replace("| `mesh` | |", "| `mesh` | `contact` |");
    let found = graph_differences(&documented_graph(&cyclic).unwrap(), &Graph::new());
    let cycle = found
        .iter()
        .find(|f| f.starts_with("the table has a cycle"))
        .unwrap();
    assert!(
        cycle.ends_with("contact -> fem -> mesh -> contact"),
        "{cycle}"
    );
    assert!(documented_graph("# no table\n").is_err());
}

// ---------------------------------------------------------------------------
// The size rules of docs/architecture.md

#[path = "docs/structure.rs"]
mod structure;

#[test]
fn no_file_is_over_a_thousand_lines_and_no_function_over_a_hundred_and_fifty() {
    use structure::{function_lengths, repository_files, MAX_FILE_LINES, MAX_FN_LINES};
    let files = repository_files(&root());
    assert!(files.len() > 100, "only {} Rust files found", files.len());
    let mut over = Vec::new();
    let (mut longest_file, mut longest_fn) = ((0, String::new()), (0, String::new()));
    for file in &files {
        let text = read(file);
        let name = file.strip_prefix(root()).unwrap().display().to_string();
        let lines = text.lines().count();
        longest_file = longest_file.max((lines, name.clone()));
        if lines > MAX_FILE_LINES {
            over.push(format!("{name}: {lines} lines (at most {MAX_FILE_LINES})"));
        }
        for (f, line, length) in function_lengths(&text) {
            longest_fn = longest_fn.max((length, format!("{name}:{line} {f}")));
            if length > MAX_FN_LINES {
                over.push(format!(
                    "{name}:{line}: fn {f} has {length} lines (at most {MAX_FN_LINES})"
                ));
            }
        }
    }
    eprintln!("longest file {longest_file:?}, longest function {longest_fn:?}");
    assert!(over.is_empty(), "{}", over.join("\n"));
}

#[test]
fn a_function_runs_to_its_closing_brace_past_braces_in_strings_and_comments() {
    let text = "/// fn not_this() {\nfn outer(a: [u8; 2]) -> u8 {\n    let s = \"}\";\n    let r = r#\"{ \" }\"#;\n    // }\n    /* } /* } */ */\n    let c = '}';\n    fn inner<'a>(x: &'a str) -> &'a str {\n        x\n    }\n    a[0]\n}\ntrait T {\n    fn declared(&self);\n}\nfn two() {}\n";
    let found = structure::function_lengths(text);
    let names: Vec<(&str, usize, usize)> = found
        .iter()
        .map(|(n, first, len)| (n.as_str(), *first, *len))
        .collect();
    assert_eq!(
        names,
        [("outer", 2, 11), ("inner", 8, 3), ("two", 16, 1)],
        "{found:?}"
    );
}
