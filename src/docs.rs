//! `signorini docs cli`: the CLI reference, every command's `--help` as
//! clap prints it, in one Markdown file (docs/reference/cli.md).

use std::path::Path;
use std::process::ExitCode;

use crate::fail;

/// The command that regenerates docs/reference/cli.md.
const REGENERATE: &str = "cargo run --release -- docs cli --out docs/reference/cli.md";

/// Every command's help as `--help` prints it, the top-level command
/// first, then each subcommand depth-first in the order clap lists them;
/// clap's own `help` subcommand is left out.
pub(crate) fn cli_reference(cli: clap::Command) -> String {
    let mut text = format!(
        "# Command-line reference\n\n\
         <!-- Generated: do not edit. Regenerate from the repository's root with\n     \
         {REGENERATE} -->\n\n\
         What `signorini --help` and each command's `--help` print, generated from \
         the binary by `signorini docs cli`; `cargo test --release --test docs` fails \
         when this file and the binary disagree. The scene, the report and the \
         exit codes are described beside it, in docs/reference.\n"
    );
    let name = cli.get_name().to_string();
    section(&cli, &cli, &[name], &mut text);
    text
}

/// The help of `command`, reached from `root` by the names `path`, then of
/// its subcommands.
fn section(root: &clap::Command, command: &clap::Command, path: &[String], text: &mut String) {
    text.push_str(&format!(
        "\n## `{}`\n\n```text\n{}\n```\n",
        path.join(" "),
        help_of(root, path).trim_end()
    ));
    for sub in command.get_subcommands() {
        if sub.get_name() == "help" {
            continue;
        }
        let mut path = path.to_vec();
        path.push(sub.get_name().to_string());
        section(root, sub, &path, text);
    }
}

/// What `PATH... --help` prints: clap's own answer to that command line
/// (it chooses between the short and the long form as it does then).
fn help_of(root: &clap::Command, path: &[String]) -> String {
    let args = path.iter().map(String::as_str).chain(["--help"]);
    match root.clone().try_get_matches_from(args) {
        Err(e) => e.render().to_string(),
        Ok(_) => String::new(),
    }
}

/// Writes `text` to `out`, or prints it when there is none.
pub(crate) fn write_or_print(text: &str, out: Option<&Path>) -> ExitCode {
    let Some(out) = out else {
        crate::say(text);
        return ExitCode::SUCCESS;
    };
    let made = match out.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => std::fs::create_dir_all(dir),
        _ => Ok(()),
    };
    match made.and_then(|()| std::fs::write(out, text)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(
            1,
            &format!(
                "--out {}: cannot write it ({e}); give a file in a directory that can be created and written",
                out.display()
            ),
        ),
    }
}
