//! The files an earlier run left in the output directory that this run
//! did not write again: a run with fewer steps, `fields = []`, no
//! `pieces`, or no friction plot left the earlier `fields.pvd` (naming the
//! earlier VTU files), `displacement.csv`, `stress.csv`, `friction.svg`
//! and pieces beside the new report, so that ParaView and a script showed
//! the earlier answer. Only names this program writes are touched: the
//! fixed names below, and `<stem>_<step>.vtu`, `<stem>_<step>.pvtu` and
//! `pieces/<stem>_<step>_s<part>.vtu` of this run's bodies.

use std::collections::BTreeSet;
use std::path::Path;

/// Output files of a fixed name that a run may or may not write.
const OPTIONAL: [&str; 5] = [
    "displacement.csv",
    "stress.csv",
    "friction.svg",
    "fields.pvd",
    "pieces.pvd",
];

/// Whether `rest` is `<step>.<ext>` (in the directory) or
/// `<step>_s<part>.vtu` (in `pieces/`), the step and part decimal.
fn step_suffix(rest: &str, piece: bool) -> bool {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if piece {
        let Some(rest) = rest.strip_suffix(".vtu") else {
            return false;
        };
        return rest
            .split_once("_s")
            .is_some_and(|(step, part)| digits(step) && digits(part));
    }
    let step = rest
        .strip_suffix(".vtu")
        .or_else(|| rest.strip_suffix(".pvtu"));
    step.is_some_and(digits)
}

/// Whether `name` (relative to the output directory) is a file a run of
/// bodies with file stems `stems` writes.
fn ours(name: &str, stems: &[String]) -> bool {
    if OPTIONAL.contains(&name) {
        return true;
    }
    let (file, piece) = match name.strip_prefix("pieces/") {
        Some(f) => (f, true),
        None => (name, false),
    };
    stems.iter().any(|s| {
        file.strip_prefix(s.as_str())
            .and_then(|r| r.strip_prefix('_'))
            .is_some_and(|r| step_suffix(r, piece))
    })
}

/// Removes from `dir` (and `dir/pieces`) the files of [`ours`] that are
/// not in `written` (paths relative to `dir`, `pieces/` for pieces), and
/// `dir/pieces` when this run wrote no piece and it is left empty. Returns
/// the names removed, sorted.
pub fn remove_stale(
    dir: &Path,
    stems: &[String],
    written: &BTreeSet<String>,
) -> std::io::Result<Vec<String>> {
    let mut removed = Vec::new();
    for sub in ["", "pieces/"] {
        let Ok(list) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        for entry in list {
            let entry = entry?;
            let name = format!("{sub}{}", entry.file_name().to_string_lossy());
            if entry.file_type()?.is_file() && ours(&name, stems) && !written.contains(&name) {
                std::fs::remove_file(entry.path())?;
                removed.push(name);
            }
        }
    }
    if !written.iter().any(|w| w.starts_with("pieces/")) {
        // Kept when anything else is in it.
        let _ = std::fs::remove_dir(dir.join("pieces"));
    }
    removed.sort();
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_names_of_this_runs_bodies_are_ours() {
        let stems = ["a".to_string(), "b_1".to_string()];
        for name in [
            "fields.pvd",
            "a_3.vtu",
            "a_12.pvtu",
            "b_1_2.vtu",
            "pieces/a_3_s0.vtu",
            "pieces/b_1_2_s11.vtu",
        ] {
            assert!(ours(name, &stems), "{name}");
        }
        for name in [
            "report.json",
            "contact.csv",
            "a.vtu",
            "a_x.vtu",
            "a_3.csv",
            "c_3.vtu",
            "a_b_3.vtu",
            "pieces/a_3.vtu",
            "pieces/a_3_s.vtu",
            "a_3_s0.vtu",
            "notes.txt",
        ] {
            assert!(!ours(name, &stems), "{name}");
        }
    }
}
