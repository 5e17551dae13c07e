//! Helpers shared by the scene tests: a minimal valid scene and the
//! error kinds of `parse_toml`.
#![allow(dead_code)]

use signorini_scene::*;

/// A minimal valid 2D scene: a plate on a rigid plane.
pub const BASE: &str = r#"
dimension = 2

[[materials]]
name = "steel"
young = 1.0
poisson = 0.3

[[bodies]]
name = "plate"
material = "steel"
mesh = { generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }

[[bodies]]
name = "ground"
rigid = { shape = "plane", point = [0.0, 0.0], normal = [0.0, 1.0] }

[[boundary]]
name = "press"
body = "plate"
surface = "top"
displacement = { y = -0.01 }
"#;

pub fn with(extra: &str) -> String {
    format!("{BASE}\n{extra}")
}

/// The contact table with the given extra lines.
pub fn contact(lines: &str) -> String {
    with(&format!(
        "[[contact]]\nname = \"c\"\nslave = {{ body = \"plate\", surface = \"bottom\" }}\nmaster = {{ body = \"ground\" }}\n{lines}\n"
    ))
}

pub fn err(text: &str) -> String {
    match parse_toml(text) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

pub fn invalid_entry(text: &str) -> (String, String) {
    match parse_toml(text) {
        Err(SceneError::Invalid { entry, message }) => (entry, message),
        other => panic!("expected an Invalid error, got {other:?}"),
    }
}

pub fn parse_err(text: &str) -> String {
    match parse_toml(text) {
        Err(SceneError::Parse { message }) => message,
        other => panic!("expected a Parse error, got {other:?}"),
    }
}

/// Each `(lines, needles)` of `cases`: the valid contact with `lines` added
/// is a parse error whose message names each of `needles`.
#[track_caller]
pub fn assert_contact_parse_errors(cases: &[(&str, &[&str])]) {
    for (lines, needles) in cases {
        let m = parse_err(&contact(lines));
        for n in *needles {
            assert!(m.contains(n), "{lines}: {n:?} not in {m}");
        }
    }
}

/// Each `(from, to, entry, needles)` of `edits`: [`BASE`] with `from`
/// replaced by `to` (it must be there) is invalid at `entry`, its message
/// naming each of `needles`.
#[track_caller]
pub fn assert_invalid_edits(edits: &[(&str, &str, &str, &[&str])]) {
    for (from, to, entry, needles) in edits {
        assert!(BASE.contains(from), "test bug: no {from:?}");
        assert_invalid_texts(&[(BASE.replace(from, to), entry, needles)]);
    }
}

/// Each `(text, entry, needles)` of `cases`: the scene `text` is invalid at
/// `entry`, its message naming each of `needles`.
#[track_caller]
pub fn assert_invalid_texts(cases: &[(String, &str, &[&str])]) {
    for (text, entry, needles) in cases {
        let (e, m) = invalid_entry(text);
        assert_eq!(e, *entry, "{text}: {m}");
        for n in *needles {
            assert!(m.contains(n), "{entry}: {n:?} not in {m}");
        }
    }
}
