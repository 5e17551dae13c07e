//! `[[contact]]`: a contact pair, its discretization, normal, law, friction
//! and gap.

use serde::{Deserialize, Serialize};

/// `[[contact]]`: a contact pair.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Contact {
    /// Unique name.
    pub name: String,
    /// A deformable body and its (required) surface.
    pub slave: ContactSide,
    /// A rigid body (no surface), or a deformable body and its surface.
    pub master: ContactSide,
    /// `node_to_node` (matching meshes) | `node_to_segment` (default) |
    /// `mortar` | `contact_elements` (coincident nodes, course notes §7).
    #[serde(default)]
    pub discretization: Discretization,
    /// Normal rule: `master` (default) | `slave` | `average` | `points`.
    #[serde(default)]
    pub normal: NormalRule,
    /// `"unilateral"` (default) or `{ penalty = <stiffness> }`.
    #[serde(default)]
    pub law: Law,
    /// `"none"` (default), `{ tresca = g }`, `{ coulomb = mu }`,
    /// `{ coulomb = mu, slip_stiffness = k }`,
    /// `{ coulomb = mu, slip_stiffness = k, roughness = Q }`,
    /// `{ coulomb = [mu1, mu2] }`, `{ norton_hoff = mu, rho = r }`.
    #[serde(default)]
    pub friction: Friction,
    /// `"geometric"` (default, from coordinates) or a number (uniform initial gap).
    #[serde(default)]
    pub gap: Gap,
    /// The candidate zone, a length: slave nodes whose initial gap exceeds
    /// it plus the largest prescribed displacement of the pair's bodies are
    /// not contact unknowns (nor interface DOFs). `None` (default): every
    /// slave node is a candidate. Excluded nodes are checked after the solve.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search_distance: Option<f64>,
    /// `"given"` (default): `slave` is the slave side; `"auto"`: the slave
    /// is the softer side of the pair (lower E/(1 − ν²)), or the finer when
    /// the two moduli are within 10 %.
    #[serde(default, skip_serializing_if = "SlaveChoice::is_given")]
    pub slave_choice: SlaveChoice,
}

/// `contact.slave_choice`: which side of a pair is the slave.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SlaveChoice {
    /// The side written as `slave`.
    #[default]
    Given,
    /// The softer side, or the finer one between equally stiff sides.
    Auto,
}

impl SlaveChoice {
    /// Whether this is the default, the side written as `slave`.
    pub fn is_given(&self) -> bool {
        *self == SlaveChoice::Given
    }
}

/// `slave` / `master` of a contact pair: `{ body, surface }`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactSide {
    pub body: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<String>,
}

/// `contact.discretization`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Discretization {
    /// Matching meshes.
    NodeToNode,
    /// Node-to-segment in 2D, node-to-face in 3D (`node_to_face` is accepted
    /// as another spelling).
    #[default]
    #[serde(alias = "node_to_face")]
    NodeToSegment,
    Mortar,
    /// Zero-thickness contact elements between coincident nodes (course notes §7),
    /// with the regularised law `law = { penalty = k_n }`.
    ContactElements,
}

impl Discretization {
    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Discretization::NodeToNode => "node_to_node",
            Discretization::NodeToSegment => "node_to_segment",
            Discretization::Mortar => "mortar",
            Discretization::ContactElements => "contact_elements",
        }
    }
}

/// `contact.normal`: which normal the gap is measured along.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalRule {
    #[default]
    Master,
    Slave,
    Average,
    Points,
}

impl NormalRule {
    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            NormalRule::Master => "master",
            NormalRule::Slave => "slave",
            NormalRule::Average => "average",
            NormalRule::Points => "points",
        }
    }
}

/// `contact.law`: `"unilateral"` (Signorini) or `{ penalty = <stiffness> }`
/// (regularised).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum Law {
    #[default]
    Unilateral,
    Penalty {
        penalty: f64,
    },
    /// `"tied"`: the two surfaces bonded, the displacement continuous in every
    /// direction (mortar equality constraints, docs/theory/mortar.md).
    Tied,
}

/// `contact.friction`.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum Friction {
    /// `"none"`: frictionless.
    #[default]
    None,
    /// `{ tresca = g }`: given slip threshold g ≥ 0.
    Tresca(f64),
    /// `{ coulomb = mu }`, `{ coulomb = [mu1, mu2] }` (3D anisotropic, elliptic
    /// cone), optionally `slip_stiffness = k` (regularised, course notes §4.1.3) and
    /// with it `roughness = Q` (the plasticity analogy of course notes §6: linear
    /// kinematic hardening of the slip, threshold ‖t − Q g‖ ≤ μ |t_n|).
    Coulomb {
        coefficient: Vec<f64>,
        slip_stiffness: Option<f64>,
        roughness: Option<f64>,
    },
    /// `{ norton_hoff = mu, rho = r }`, 0 < r < 1.
    NortonHoff { coefficient: f64, rho: f64 },
}

/// `contact.gap`: `"geometric"` (from coordinates) or a number (uniform initial gap).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum Gap {
    #[default]
    Geometric,
    Uniform(f64),
}
