//! The size rules of docs/architecture.md ("Structure checks"): no Rust
//! file of the repository over [`MAX_FILE_LINES`] lines, no function over
//! [`MAX_FN_LINES`]. A function runs from the line of its `fn` to the line
//! of the brace that closes its body, found by matching braces outside
//! comments, strings and character literals.

use std::path::{Path, PathBuf};

pub const MAX_FILE_LINES: usize = 1000;
pub const MAX_FN_LINES: usize = 150;

/// The directories of the repository that hold Rust sources.
const SOURCE_DIRS: [&str; 3] = ["src", "crates", "tests"];

/// Every `.rs` file below `dir`, but in `target` directories.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() && path.file_name().is_some_and(|n| n != "target") {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The Rust files of the repository at `root`.
pub fn repository_files(root: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for dir in SOURCE_DIRS {
        rust_files(&root.join(dir), &mut files);
    }
    files.sort();
    files
}

/// The end (exclusive) of the literal or comment that starts at `i`, or
/// `None` when none starts there.
fn skip_literal(s: &[u8], i: usize) -> Option<usize> {
    let at = |k: usize| s.get(k).copied().unwrap_or(0);
    let find = |from: usize, pat: &[u8]| {
        (from..s.len())
            .find(|&k| s[k..].starts_with(pat))
            .map_or(s.len(), |k| k + pat.len())
    };
    let word_before = i > 0 && (s[i - 1].is_ascii_alphanumeric() || s[i - 1] == b'_');
    match at(i) {
        b'/' if at(i + 1) == b'/' => Some(find(i, b"\n")),
        b'/' if at(i + 1) == b'*' => {
            let (mut depth, mut k) = (0usize, i);
            while k < s.len() {
                if s[k..].starts_with(b"/*") {
                    (depth, k) = (depth + 1, k + 2);
                } else if s[k..].starts_with(b"*/") {
                    (depth, k) = (depth - 1, k + 2);
                    if depth == 0 {
                        break;
                    }
                } else {
                    k += 1;
                }
            }
            Some(k)
        }
        b'r' | b'b' if !word_before => {
            let start = if at(i) == b'b' && at(i + 1) == b'r' {
                i + 2
            } else {
                i + 1
            };
            let hashes = (start..s.len()).take_while(|&k| s[k] == b'#').count();
            if at(i) == b'r' || start == i + 2 {
                if at(start + hashes) != b'"' {
                    return None;
                }
                let mut close = vec![b'"'];
                close.extend(std::iter::repeat_n(b'#', hashes));
                return Some(find(start + hashes + 1, &close));
            }
            None
        }
        b'"' => {
            let mut k = i + 1;
            while k < s.len() && s[k] != b'"' {
                k += if s[k] == b'\\' { 2 } else { 1 };
            }
            Some(k + 1)
        }
        // A character literal ('a', '\n', '\u{..}'), not a lifetime ('a).
        b'\'' if at(i + 1) == b'\\' => Some(find(i + 2, b"'")),
        b'\'' if at(i + 2) == b'\'' => Some(i + 3),
        b'\'' if at(i + 1) >= 0x80 => Some(find(i + 1, b"'")),
        _ => None,
    }
}

/// `text` with comments, strings and character literals blanked (newlines
/// kept), so that the braces left are the code's.
fn code_only(text: &str) -> Vec<u8> {
    let s = text.as_bytes();
    let mut out = Vec::with_capacity(s.len());
    let mut i = 0;
    while i < s.len() {
        if let Some(end) = skip_literal(s, i) {
            let end = end.min(s.len());
            out.extend(
                s[i..end]
                    .iter()
                    .map(|&c| if c == b'\n' { b'\n' } else { b' ' }),
            );
            i = end;
        } else {
            out.push(s[i]);
            i += 1;
        }
    }
    out
}

/// Each function with a body in `text`: its name, first line (1-based) and
/// length in lines.
pub fn function_lengths(text: &str) -> Vec<(String, usize, usize)> {
    let s = code_only(text);
    let line_of = |k: usize| 1 + s[..k].iter().filter(|&&c| c == b'\n').count();
    let is_word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut found = Vec::new();
    for i in 0..s.len().saturating_sub(3) {
        let keyword = s[i..].starts_with(b"fn ") && (i == 0 || !is_word(s[i - 1]));
        if !keyword {
            continue;
        }
        let name: String = s[i + 3..]
            .iter()
            .skip_while(|c| c.is_ascii_whitespace())
            .take_while(|&&c| is_word(c))
            .map(|&c| c as char)
            .collect();
        // The body's brace: the first `{` outside the signature's brackets,
        // unless a `;` ends a declaration first.
        let mut depth = 0i32;
        let mut open = None;
        for (k, &c) in s.iter().enumerate().skip(i + 3) {
            match c {
                b'(' | b'[' => depth += 1,
                b')' | b']' => depth -= 1,
                b';' if depth == 0 => break,
                b'{' if depth == 0 => {
                    open = Some(k);
                    break;
                }
                _ => {}
            }
        }
        let Some(open) = open else { continue };
        let mut braces = 0i32;
        let close = (open..s.len()).find(|&k| {
            braces += match s[k] {
                b'{' => 1,
                b'}' => -1,
                _ => 0,
            };
            braces == 0
        });
        let close = close.unwrap_or(s.len() - 1);
        let first = line_of(i);
        found.push((name, first, line_of(close) - first + 1));
    }
    found
}
