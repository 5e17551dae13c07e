//! The scene format of `docs/reference/scene-format.md` (version 1): serde schema, parsing and validation.
//!
//! A scene is one TOML file (JSON with the same structure is accepted). It is the
//! user's contract: unknown keys are an error that names the key and its line, and
//! every validation error names the entry (`bodies[1].mesh.radius`,
//! `contact "cyl-ground".slave.surface`, `materials[0].poisson`) and says what would
//! be valid.
//!
//! ```
//! let scene = signorini_scene::parse_toml(r#"
//!     dimension = 2
//!     [[materials]]
//!     name = "steel"
//!     young = 1.0
//!     poisson = 0.3
//!     [[bodies]]
//!     name = "plate"
//!     material = "steel"
//!     mesh = { generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 1.0], divisions = [4, 4] }
//! "#).unwrap();
//! assert_eq!(scene.model, signorini_scene::Model::PlaneStrain);
//! ```
//!
//! The scene crate owns the user contract (the scene file and its validation);
//! it must not know meshes, finite elements, contact algorithms or MPI.

use std::path::Path;

mod output;
mod serde_impls;
mod types;
mod validate;

pub use output::*;
pub use serde_impls::Shown;
pub use types::*;
pub use validate::MAX_STEPS;

/// Everything that can go wrong while reading a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene file {path}: {message}")]
    Io { path: String, message: String },
    /// TOML/JSON syntax error, a wrong type, an unknown key or a missing key. The
    /// message is the one of the `toml` / `serde_json` crate, which gives the line
    /// and column (when read by [`load`], it is prefixed by the file path).
    #[error("{message}")]
    Parse { message: String },
    /// The scene parsed but is not valid. `entry` names the offending entry, e.g.
    /// `bodies[1].mesh.radius`, `contact "cyl-ground"`, `materials[0].poisson`;
    /// `message` says what would be valid.
    #[error("{entry}: {message}")]
    Invalid { entry: String, message: String },
}

/// The most a scene file may hold: a scene is a few kilobytes (meshes are
/// files of their own), and reading stops here, so that a device or an
/// endless pipe given as the scene cannot take the machine's memory.
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// The text of a scene file (or pipe), at most [`MAX_SCENE_BYTES`].
fn read_scene_text(path: &Path) -> Result<String, String> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut text = String::new();
    (file.take(MAX_SCENE_BYTES + 1))
        .read_to_string(&mut text)
        .map_err(|e| e.to_string())?;
    if text.len() as u64 > MAX_SCENE_BYTES {
        return Err(format!(
            "holds more than {} MiB: not a scene file (meshes go in files of their own, `mesh = {{ file = ... }}`)",
            MAX_SCENE_BYTES >> 20
        ));
    }
    Ok(text)
}

/// Reads, parses and validates a scene file: `*.json` is read as JSON, anything else
/// as TOML.
///
/// Relative `mesh = { file = ... }` paths are resolved against the directory of the
/// scene file (after validation), so the returned scene can be used from any working
/// directory. `output.directory` is left as written (relative to the working
/// directory; see [`Output::directory_for`] for its default).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = read_scene_text(path).map_err(|message| SceneError::Io {
        path: path.display().to_string(),
        message,
    })?;
    let is_json = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let parsed = if is_json {
        from_json(&text)
    } else {
        from_toml(&text)
    };
    let mut scene = parsed.map_err(|e| match e {
        SceneError::Parse { message } => SceneError::Parse {
            message: format!("{}: {}", path.display(), message),
        },
        other => other,
    })?;
    scene.validate()?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        for body in &mut scene.bodies {
            if let Some(MeshSpec::File { file, .. }) = &mut body.mesh {
                if file.is_relative() {
                    *file = dir.join(&*file);
                }
            }
        }
    }
    Ok(scene)
}

/// Parses a scene written in TOML, then [`Scene::validate`]s it.
pub fn parse_toml(text: &str) -> Result<Scene, SceneError> {
    let scene = from_toml(text)?;
    scene.validate()?;
    Ok(scene)
}

/// Parses a scene written in JSON (same structure as the TOML form), then
/// [`Scene::validate`]s it.
pub fn parse_json(text: &str) -> Result<Scene, SceneError> {
    let scene = from_json(text)?;
    scene.validate()?;
    Ok(scene)
}

fn from_toml(text: &str) -> Result<Scene, SceneError> {
    toml::from_str(text).map_err(|e| SceneError::Parse {
        message: shorten_snippet(e.to_string().trim_end()),
    })
}

/// The `toml` crate quotes the whole offending line under its caret; a scene
/// with a very long line (a generated one, or 10^5 brackets) would make the
/// message as long. Keep a window of the line around the caret.
fn shorten_snippet(message: &str) -> String {
    const WIDTH: usize = 100;
    let lines: Vec<&str> = message.lines().collect();
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    for i in 0..lines.len().saturating_sub(1) {
        // "NN | source" followed by "   |   ^^^^"
        let (Some(bar), Some(caret_bar)) = (lines[i].find(" | "), lines[i + 1].find(" | ")) else {
            continue;
        };
        let source: Vec<char> = lines[i][bar + 3..].chars().collect();
        let carets: Vec<char> = lines[i + 1][caret_bar + 3..].chars().collect();
        if source.len() <= WIDTH || !carets.contains(&'^') {
            continue;
        }
        let first = carets.iter().position(|&c| c == '^').unwrap_or(0);
        let start = first.saturating_sub(WIDTH / 4).min(source.len());
        let end = (start + WIDTH).min(source.len());
        let lead = if start > 0 { "…" } else { "" };
        let tail = if end < source.len() { "…" } else { "" };
        let text: String = source[start..end].iter().collect();
        out[i] = format!("{} | {lead}{text}{tail}", &lines[i][..bar]);
        let span = carets[first..]
            .iter()
            .take_while(|&&c| c == '^')
            .count()
            .min(end.saturating_sub(first))
            .max(1);
        out[i + 1] = format!(
            "{} | {}{}",
            &lines[i + 1][..caret_bar],
            " ".repeat(first - start + lead.chars().count()),
            "^".repeat(span)
        );
    }
    out.join("\n")
}

/// A JSON scene; an error names the key it is at (`materials[0].young`), as
/// the TOML parser's does.
fn from_json(text: &str) -> Result<Scene, SceneError> {
    let parse_error = |message: String| SceneError::Parse {
        message: format!("JSON parse error{message}"),
    };
    let mut de = serde_json::Deserializer::from_str(text);
    let scene: Scene = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let at = match e.path().to_string().as_str() {
            "." | "" => String::new(),
            path => format!(" at `{path}`"),
        };
        parse_error(format!("{at}: {}", e.inner()))
    })?;
    // Trailing characters after the scene are an error, as in from_str.
    de.end().map_err(|e| parse_error(format!(": {e}")))?;
    Ok(scene)
}
