//! The schema of `[reference]` and `[output]` (split from `types.rs`).

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// `[reference]`: an analytic solution to report the error against; the load is the
/// computed one.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Reference {
    pub kind: ReferenceKind,
    /// Radius of the cylinder / sphere (required by `hertz_cylinder` and
    /// `hertz_sphere`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Radius of the other body's surface in a two-body Hertz contact
    /// (optional; hertz_cylinder, hertz_sphere, cattaneo_mindlin): > 0 for
    /// a convex surface (two cylinders or spheres), < 0 for a concave seat
    /// wider than the first body. The reference then uses the combined
    /// radius 1/R = 1/radius + 1/radius2 (see [`Reference::effective_radius`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<f64>,
    /// Half width of a flat punch.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub half_width: Option<f64>,
    /// Friction coefficient (cattaneo_mindlin, sliding_block).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// The model is this part of a contact symmetric about planes through
    /// `center` (hertz_sphere in 3D): the reference takes each contact point
    /// for itself and its mirror images, so its load is 4 (`quarter`) or 2
    /// (`half`) times the computed resultant.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub symmetry: Option<Symmetry>,
    /// The centre of the contact (hertz_sphere in 3D; needed with
    /// `symmetry`, a point of its planes): radii are measured from it rather
    /// than from the force-weighted centre of the contact points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<Vec<f64>>,
}

/// `reference.symmetry`: the part of a symmetric contact a model holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Symmetry {
    Half,
    Quarter,
}

impl Symmetry {
    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Symmetry::Half => "half",
            Symmetry::Quarter => "quarter",
        }
    }

    /// How many copies of the model make the whole contact.
    pub fn copies(self) -> f64 {
        match self {
            Symmetry::Half => 2.0,
            Symmetry::Quarter => 4.0,
        }
    }
}

impl Reference {
    /// The radius Hertz's formulas take: `radius`, or with `radius2` the
    /// combined radius R = 1/(1/radius + 1/radius2) (positive once
    /// validated: a concave seat is wider than the body in it).
    pub fn effective_radius(&self) -> Option<f64> {
        let r = self.radius?;
        Some(self.radius2.map_or(r, |r2| 1.0 / (1.0 / r + 1.0 / r2)))
    }
}

/// `reference.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReferenceKind {
    HertzCylinder,
    HertzSphere,
    FlatPunch,
    UniformPressure,
    CattaneoMindlin,
    SlidingBlock,
}

impl ReferenceKind {
    /// The scene-file / report spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            ReferenceKind::HertzCylinder => "hertz_cylinder",
            ReferenceKind::HertzSphere => "hertz_sphere",
            ReferenceKind::FlatPunch => "flat_punch",
            ReferenceKind::UniformPressure => "uniform_pressure",
            ReferenceKind::CattaneoMindlin => "cattaneo_mindlin",
            ReferenceKind::SlidingBlock => "sliding_block",
        }
    }
}

/// `[output]`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Output {
    /// Output directory; default `out/<scene file stem>` (see
    /// [`Output::directory_for`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub directory: Option<PathBuf>,
    /// VTU content: any of `displacement`, `stress`, `contact` (default all three);
    /// `[]` writes none.
    pub fields: Vec<String>,
    /// Points whose displacement goes in the report (nearest node of any body).
    pub probes: Vec<Vec<f64>>,
    /// Which load steps write their fields (VTU pieces); contact.csv and
    /// steps.csv keep every step.
    #[serde(skip_serializing_if = "OutputSteps::is_all")]
    pub steps: OutputSteps,
    /// Also write each subdomain's VTU piece, by the rank that owns it, with a
    /// `.pvtu` index per body and step (default false: the gathered
    /// files alone).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub pieces: bool,
}

/// `[output] steps`: the load steps whose fields are written, `"all"` (the
/// default), `"last"`, `{ every = N }` (steps N, 2N, … and the last) or a
/// list of 1-based step numbers. Entries are checked by validation
/// (`output.steps`), against the number of steps.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum OutputSteps {
    #[default]
    All,
    Last,
    Every(i64),
    List(Vec<i64>),
}

impl OutputSteps {
    pub fn is_all(&self) -> bool {
        *self == OutputSteps::All
    }

    /// Whether load step `step` (1-based) of `n` writes its fields.
    pub fn selects(&self, step: usize, n: usize) -> bool {
        match self {
            OutputSteps::All => true,
            OutputSteps::Last => step == n,
            OutputSteps::Every(k) => step == n || (*k > 0 && step as i64 % k == 0),
            OutputSteps::List(l) => l.contains(&(step as i64)),
        }
    }
}

impl Default for Output {
    fn default() -> Self {
        Output {
            directory: None,
            fields: vec![
                "displacement".to_string(),
                "stress".to_string(),
                "contact".to_string(),
            ],
            probes: Vec::new(),
            steps: OutputSteps::All,
            pieces: false,
        }
    }
}

impl Output {
    /// The valid `fields` names.
    pub const FIELDS: [&'static str; 3] = ["displacement", "stress", "contact"];

    /// `directory`, or `out/<stem of scene_path>` when not given.
    pub fn directory_for(&self, scene_path: &Path) -> PathBuf {
        match &self.directory {
            Some(d) => d.clone(),
            None => {
                let stem = scene_path
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "scene".to_string());
                Path::new("out").join(stem)
            }
        }
    }

    /// Whether `fields` asks for that field.
    pub fn wants(&self, field: &str) -> bool {
        self.fields.iter().any(|f| f == field)
    }
}

/// Longest file stem a body's name gives its output files (`<stem>_<step>.vtu`):
/// well under the 255 bytes a file name may have on common file systems.
pub const MAX_FILE_STEM: usize = 100;

/// A body's name as the stem of its output files (`<stem>_<step>.vtu`,
/// `pieces/<stem>_<step>_s<part>.vtu`): ASCII letters, digits, '-' and '_'
/// kept, anything else '_'. Validation refuses two bodies with one stem, or
/// a stem longer than [`MAX_FILE_STEM`].
pub fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}
