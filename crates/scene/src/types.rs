//! The schema: one Rust type per table of the scene file.

use crate::output::{Output, Reference};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

/// A whole scene file.
///
/// Deserialization goes through a private raw struct (with `deny_unknown_fields`) so
/// that a missing `model` can default according to `dimension`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(from = "SceneRaw")]
pub struct Scene {
    /// Free text, echoed in the report.
    pub title: String,
    /// Space dimension: 2 or 3.
    pub dimension: u8,
    /// The mechanical model. Defaults to `plane_strain` when `dimension = 2` and
    /// `solid` when `dimension = 3`.
    pub model: Model,
    /// `[[materials]]`: named linear elastic materials.
    pub materials: Vec<Material>,
    /// `[[bodies]]`: deformable (meshed) bodies and rigid obstacles.
    pub bodies: Vec<Body>,
    /// `[[boundary]]`: Dirichlet and Neumann conditions.
    pub boundary: Vec<Boundary>,
    /// `[[contact]]`: contact pairs.
    pub contact: Vec<Contact>,
    /// `[[steps]]`: load steps; empty means one step with every load at scale 1.
    pub steps: Vec<Step>,
    /// `[solver]`.
    pub solver: Solver,
    /// `[reference]`: an optional analytic solution to report the error against.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<Reference>,
    /// `[output]`.
    pub output: Output,
}

/// The file form of [`Scene`]: `model` is optional there.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneRaw {
    #[serde(default)]
    title: String,
    #[serde(deserialize_with = "crate::serde_impls::dimension")]
    dimension: u8,
    #[serde(default)]
    model: Option<Model>,
    #[serde(default)]
    materials: Vec<Material>,
    #[serde(default)]
    bodies: Vec<Body>,
    #[serde(default)]
    boundary: Vec<Boundary>,
    #[serde(default)]
    contact: Vec<Contact>,
    #[serde(default)]
    steps: Vec<Step>,
    #[serde(default)]
    solver: Solver,
    #[serde(default)]
    reference: Option<Reference>,
    #[serde(default)]
    output: Output,
}

impl From<SceneRaw> for Scene {
    fn from(raw: SceneRaw) -> Self {
        let model = raw.model.unwrap_or(if raw.dimension == 3 {
            Model::Solid
        } else {
            Model::PlaneStrain
        });
        Scene {
            title: raw.title,
            dimension: raw.dimension,
            model,
            materials: raw.materials,
            bodies: raw.bodies,
            boundary: raw.boundary,
            contact: raw.contact,
            steps: raw.steps,
            solver: raw.solver,
            reference: raw.reference,
            output: raw.output,
        }
    }
}

impl Scene {
    /// The same scene with every generated mesh refined: `divisions`
    /// multiplied by `factor` (rounded, at least 1; half-disk arcs stay even
    /// so that the pole is a node). For refinement studies (`signorini bench`).
    pub fn refined(&self, factor: f64) -> Scene {
        let mut sc = self.clone();
        let scale = |n: usize| ((n as f64 * factor).round() as usize).max(1);
        for b in &mut sc.bodies {
            if let Some(MeshSpec::Generator(g)) = &mut b.mesh {
                match g {
                    Generator::Rectangle { divisions, .. } => *divisions = divisions.map(scale),
                    Generator::Box { divisions, .. } => *divisions = divisions.map(scale),
                    Generator::HalfDisk { divisions, .. }
                    | Generator::QuarterDisk { divisions, .. } => {
                        *divisions = (scale(*divisions) / 2 * 2).max(4)
                    }
                    Generator::Hemisphere { divisions, .. } => {
                        *divisions = scale(*divisions).max(4)
                    }
                }
            }
        }
        sc
    }

    /// The same scene with every deformable body split into `n` subdomains.
    pub fn with_subdomains(&self, n: usize) -> Scene {
        let mut sc = self.clone();
        for b in &mut sc.bodies {
            if b.mesh.is_some() {
                b.subdomains = Subdomains::Count(n.max(1));
            }
        }
        sc
    }

    /// The `[[materials]]` entry of that name.
    pub fn material(&self, name: &str) -> Option<&Material> {
        self.materials.iter().find(|m| m.name == name)
    }

    /// The `[[bodies]]` entry of that name.
    pub fn body(&self, name: &str) -> Option<&Body> {
        self.bodies.iter().find(|b| b.name == name)
    }

    /// Index in `bodies` of the body of that name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The `[[boundary]]` entry of that name.
    pub fn boundary_entry(&self, name: &str) -> Option<&Boundary> {
        self.boundary
            .iter()
            .find(|b| b.name.as_deref() == Some(name))
    }

    /// The scale of every *named* boundary entry at every load step, after applying
    /// the rule of `docs/reference/scene-format.md`: loads not named in a step keep their previous scale
    /// (first step: 1). With no `[[steps]]`, one step with every scale 1. Unnamed
    /// boundary entries are always at scale 1.
    /// The friction law of every contact at every load step: the contact's
    /// own until a step's `friction` changes it, which holds from that step
    /// on. With no `[[steps]]`, one step with the contacts' own laws.
    pub fn step_frictions(&self) -> Vec<Vec<Friction>> {
        let mut current: Vec<Friction> = self.contact.iter().map(|c| c.friction.clone()).collect();
        if self.steps.is_empty() {
            return vec![current];
        }
        self.steps
            .iter()
            .map(|step| {
                for (name, f) in &step.friction {
                    if let Some(ci) = self.contact.iter().position(|c| &c.name == name) {
                        current[ci] = f.clone();
                    }
                }
                current.clone()
            })
            .collect()
    }

    pub fn step_scales(&self) -> Vec<BTreeMap<String, f64>> {
        let mut current: BTreeMap<String, f64> = self
            .boundary
            .iter()
            .filter_map(|b| b.name.clone())
            .map(|n| (n, 1.0))
            .collect();
        if self.steps.is_empty() {
            return vec![current];
        }
        self.steps
            .iter()
            .map(|step| {
                for (name, scale) in &step.scale {
                    current.insert(name.clone(), *scale);
                }
                current.clone()
            })
            .collect()
    }
}

/// `model`: how a 2D scene is interpreted, or `solid` in 3D.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Model {
    /// 2D, ε_zz = 0.
    PlaneStrain,
    /// 2D, σ_zz = 0, thickness 1.
    PlaneStress,
    /// 2D, x = r, y = z.
    Axisymmetric,
    /// 3D.
    Solid,
}

impl Model {
    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Model::PlaneStrain => "plane_strain",
            Model::PlaneStress => "plane_stress",
            Model::Axisymmetric => "axisymmetric",
            Model::Solid => "solid",
        }
    }

    /// The space dimension this model lives in.
    pub fn dimension(self) -> usize {
        match self {
            Model::Solid => 3,
            _ => 2,
        }
    }
}

/// `[[materials]]`: an isotropic linear elastic material.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Unique name, referenced by `bodies.material`.
    pub name: String,
    /// Young's modulus E > 0.
    pub young: f64,
    /// Poisson's ratio, -1 < ν < 0.5.
    pub poisson: f64,
}

/// `bodies.subdomains`: METIS parts of this body, an integer ≥ 1 or `"auto"` (spread
/// the MPI ranks). Default 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subdomains {
    Count(usize),
    Auto,
}

impl Default for Subdomains {
    fn default() -> Self {
        Subdomains::Count(1)
    }
}

/// `[[bodies]]`: a deformable body (`mesh` and `material`) or a rigid obstacle
/// (`rigid`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Unique name, referenced by boundary conditions and contact pairs.
    pub name: String,
    /// Name of a `[[materials]]` entry; required for a deformable body, forbidden for
    /// a rigid one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// METIS parts of this body; `"auto"` spreads the ranks.
    #[serde(default)]
    pub subdomains: Subdomains,
    /// The mesh of a deformable body: a generator or a Gmsh file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshSpec>,
    /// The shape of a rigid obstacle. Exactly one of `mesh` / `rigid`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rigid: Option<RigidShape>,
    /// Element formulation of a deformable body: `"displacement"` (default)
    /// or `"b_bar"` (mean dilatation, against locking as ν → 0.5; quad4 in
    /// plane strain and axisymmetry, hex8 in 3D).
    #[serde(default, skip_serializing_if = "Formulation::is_displacement")]
    pub formulation: Formulation,
}

/// `bodies.formulation`: how the elements of a deformable body relate strains
/// to displacements.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Formulation {
    /// The standard displacement elements.
    #[default]
    Displacement,
    /// Mean-dilatation B-bar (Hughes 1980): the volumetric strain is the
    /// element mean, which cures the volumetric locking of quad4 and hex8
    /// as ν → 0.5 (plane strain, axisymmetric, solid).
    BBar,
}

impl Formulation {
    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Formulation::Displacement => "displacement",
            Formulation::BBar => "b_bar",
        }
    }

    /// The default, `"displacement"` (not written when serializing).
    pub fn is_displacement(&self) -> bool {
        *self == Formulation::Displacement
    }
}

impl Body {
    /// A body with a `mesh`.
    pub fn is_deformable(&self) -> bool {
        self.mesh.is_some()
    }

    /// A body with a `rigid` shape (and no mesh).
    pub fn is_rigid(&self) -> bool {
        self.rigid.is_some() && self.mesh.is_none()
    }
}

/// `bodies.mesh`: `{ generator = "...", ... }` or `{ file = "part.msh" }`.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(untagged)]
pub enum MeshSpec {
    /// A built-in mesh generator.
    Generator(Generator),
    /// A Gmsh 2.2 or 4.1 file; physical groups of dimension d−1 name the surfaces,
    /// of dimension d the regions. [`crate::load`] makes a relative path relative to
    /// the scene file's directory. With `volume`, the body is the cells of that
    /// physical group of dimension d alone (one body of a file holding several).
    File {
        file: PathBuf,
        volume: Option<String>,
    },
}

/// A mesh generator, tagged by the key `generator`. Every generator names its
/// boundary parts; those names are the surfaces of the body. `grading` is the ratio
/// of the largest to the smallest element size along the graded direction (1 =
/// uniform); sizes vary geometrically.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "generator", rename_all = "snake_case", deny_unknown_fields)]
pub enum Generator {
    /// 2D. Surfaces: left, right, bottom, top.
    Rectangle {
        /// Lower-left corner [x, y].
        origin: [f64; 2],
        /// [width, height] > 0.
        size: [f64; 2],
        /// [nx, ny] ≥ 1.
        divisions: [usize; 2],
        /// `quad4` (default) or `tri3`.
        #[serde(default = "Element::quad4")]
        element: Element,
        /// Grading towards `bottom` | `top` | `left` | `right`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        grading: Option<Grading>,
    },
    /// 2D. Surfaces: flat, arc.
    HalfDisk {
        /// Centre of the circle, on the flat side.
        center: [f64; 2],
        radius: f64,
        /// Elements along the arc (≥ 4).
        divisions: usize,
        /// Unit vector from the centre to the middle of the arc (default [0, -1]).
        #[serde(default = "default_pole2")]
        pole: [f64; 2],
        /// Smallest elements at the pole (default 1 = uniform).
        #[serde(default = "one")]
        grading: f64,
        /// `quad4` (default) or `tri3`.
        #[serde(default = "Element::quad4")]
        element: Element,
    },
    /// 3D. Surfaces: xmin, xmax, ymin, ymax, zmin, zmax.
    Box {
        origin: [f64; 3],
        size: [f64; 3],
        divisions: [usize; 3],
        /// `hex8` (default) or `tet4`.
        #[serde(default = "Element::hex8")]
        element: Element,
        /// Grading towards `xmin` .. `zmax`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        grading: Option<Grading>,
    },
    /// 3D. Surfaces: flat, dome.
    Hemisphere {
        center: [f64; 3],
        radius: f64,
        divisions: usize,
        /// Default [0, 0, -1].
        #[serde(default = "default_pole3")]
        pole: [f64; 3],
        #[serde(default = "one")]
        grading: f64,
        /// `hex8` (default) | `tet4` | `hex20` | `tet10`.
        #[serde(default = "Element::hex8")]
        element: Element,
        /// `whole` (default) or `quarter`: the cells on one side of the two
        /// planes through the pole and the local axes, with their surfaces
        /// symmetry_1 and symmetry_2 (for symmetric loads).
        #[serde(default, skip_serializing_if = "Sector::is_whole")]
        sector: Sector,
    },
    /// Axisymmetric only. Surfaces: axis, flat, arc. Grading towards the pole on the
    /// axis.
    QuarterDisk {
        center: [f64; 2],
        radius: f64,
        divisions: usize,
        #[serde(default = "one")]
        grading: f64,
        #[serde(default = "Element::quad4")]
        element: Element,
    },
}

impl Generator {
    /// The scene-file spelling of the generator.
    pub fn name(&self) -> &'static str {
        match self {
            Generator::Rectangle { .. } => "rectangle",
            Generator::HalfDisk { .. } => "half_disk",
            Generator::Box { .. } => "box",
            Generator::Hemisphere { .. } => "hemisphere",
            Generator::QuarterDisk { .. } => "quarter_disk",
        }
    }

    /// The element type of the generated cells.
    pub fn element(&self) -> Element {
        match self {
            Generator::Rectangle { element, .. }
            | Generator::HalfDisk { element, .. }
            | Generator::Box { element, .. }
            | Generator::QuarterDisk { element, .. }
            | Generator::Hemisphere { element, .. } => *element,
        }
    }

    /// The space dimension of the generated mesh.
    pub fn dimension(&self) -> usize {
        match self {
            Generator::Box { .. } | Generator::Hemisphere { .. } => 3,
            _ => 2,
        }
    }

    /// The names of the surfaces this generator creates.
    pub fn surfaces(&self) -> &'static [&'static str] {
        match self {
            Generator::Rectangle { .. } => &["left", "right", "bottom", "top"],
            Generator::HalfDisk { .. } => &["flat", "arc"],
            Generator::Box { .. } => &["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"],
            Generator::Hemisphere {
                sector: Sector::Quarter,
                ..
            } => &["flat", "dome", "symmetry_1", "symmetry_2"],
            Generator::Hemisphere { .. } => &["flat", "dome"],
            Generator::QuarterDisk { .. } => &["axis", "flat", "arc"],
        }
    }
}

fn default_pole2() -> [f64; 2] {
    [0.0, -1.0]
}
fn default_pole3() -> [f64; 3] {
    [0.0, 0.0, -1.0]
}
fn one() -> f64 {
    1.0
}

/// Element type: `quad4` | `tri3` | `quad8` | `tri6` (2D, the last two of
/// second order), `hex8` | `tet4` | `hex20` | `tet10` (3D, the last two of
/// second order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Element {
    Quad4,
    Tri3,
    Quad8,
    Tri6,
    Hex8,
    Tet4,
    Hex20,
    Tet10,
}

impl Element {
    fn quad4() -> Self {
        Element::Quad4
    }
    fn hex8() -> Self {
        Element::Hex8
    }

    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Element::Quad4 => "quad4",
            Element::Tri3 => "tri3",
            Element::Quad8 => "quad8",
            Element::Tri6 => "tri6",
            Element::Hex8 => "hex8",
            Element::Tet4 => "tet4",
            Element::Hex20 => "hex20",
            Element::Tet10 => "tet10",
        }
    }
}

/// `sector` of the hemisphere generator: the whole hemisphere or a quarter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sector {
    #[default]
    Whole,
    Quarter,
}

impl Sector {
    fn is_whole(&self) -> bool {
        *self == Sector::Whole
    }
}

impl<'de> Deserialize<'de> for Sector {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        match s.as_str() {
            "whole" => Ok(Sector::Whole),
            "quarter" => Ok(Sector::Quarter),
            other => Err(serde::de::Error::custom(format!(
                "sector: expected \"whole\" or \"quarter\", got \"{other}\""
            ))),
        }
    }
}

/// `grading = { towards, ratio }` of the rectangle and box generators.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Grading {
    /// Where the smallest elements are: rectangle `bottom`|`top`|`left`|`right`, box
    /// `xmin`|`xmax`|`ymin`|`ymax`|`zmin`|`zmax`.
    pub towards: String,
    /// Largest over smallest element size, ≥ 1.
    pub ratio: f64,
}

/// `bodies.rigid`: a rigid obstacle, tagged by the key `shape`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum RigidShape {
    /// A line (2D) or plane (3D) through `point` with outward `normal` (towards the
    /// deformable bodies); both have `dimension` components.
    Plane { point: Vec<f64>, normal: Vec<f64> },
    /// 2D only.
    Circle { center: Vec<f64>, radius: f64 },
    /// 3D only.
    Sphere { center: Vec<f64>, radius: f64 },
}

/// `[[boundary]]`: a condition on a surface (or a single node) of a deformable body.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Boundary {
    /// Optional unique name; load steps scale a condition by its name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// A deformable body.
    pub body: String,
    /// A surface of the body (checked by the solver, once meshes exist).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<String>,
    /// Instead of `surface`: the body's node at that point (error if none within 1e-6
    /// of the body size); for pinning a corner.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<Vec<f64>>,
    /// Instead of `surface`: the nodes of a physical group of the body's Gmsh
    /// file (points, curves or surfaces); a `force` is shared equally by them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nodes: Option<String>,
    /// Imposed displacement components (others free).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement: Option<Displacement>,
    /// Force per unit length (2D) / area (3D), at the current scale.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction: Option<Vec<f64>>,
    /// Resultant force, spread uniformly over the surface.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force: Option<Vec<f64>>,
    /// With `displacement`: the point about which the moment of the entry's
    /// reaction is reported (`dimension` components; default the origin).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moment_about: Option<Vec<f64>>,
}

/// `displacement = { x, y, z }`: components given are imposed, others free.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Displacement {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<f64>,
    /// 3D only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
}

impl Displacement {
    /// The imposed value of each component (length 3; z is `None` in 2D).
    pub fn components(&self) -> [Option<f64>; 3] {
        [self.x, self.y, self.z]
    }
}

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

/// `[[steps]]`: `scale = { <boundary name> = <factor> }`. Loads not named keep
/// their previous scale (first step: 1). See [`Scene::step_scales`].
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Step {
    #[serde(default)]
    pub scale: BTreeMap<String, f64>,
    /// `friction = { <contact name> = { coulomb = mu } }` (or `{ tresca = g }`):
    /// the contact's coefficient from this step on (its law's kind unchanged).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub friction: BTreeMap<String, Friction>,
}

/// `[solver]`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Solver {
    /// The contact algorithm (default `status`).
    pub method: Method,
    /// `auto` (default: the cheaper of the two, estimated), `condensed`
    /// (static condensation onto the interface) or `direct`.
    pub path: SolvePath,
    /// Convergence tolerance, 0 < tol < 1 (default 1e-10).
    pub tolerance: f64,
    /// ≥ 1 (default 500).
    #[serde(deserialize_with = "crate::serde_impls::max_iterations")]
    pub max_iterations: usize,
    /// Friction outer loop: `fixed_point` (default), `status`, `newton` or `nsgs`.
    pub friction: FrictionSolver,
    /// The wall-clock budget of each contact solve, in seconds (> 0): every
    /// method on the condensed path, friction solves on the direct path;
    /// default: 10 s + 2e-9 s × rows³ of the solve's problem. A solve that
    /// reaches it stops, not converged.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_limit: Option<f64>,
    /// Status method: `all` statuses changed at each iteration (default) or a
    /// `single` one (the variant with the convergence proof, course notes §3.3).
    pub status_changes: StatusChanges,
    /// Status method: impose the active constraints by `multipliers`
    /// (default) or by `penalty` (course notes §3.3, step 1).
    pub constraints: Constraints,
    /// Penalty stiffness of `method = "penalty"` and of the penalty-imposed
    /// status method, as a multiple of the contact stiffness 1/mean diag(W)
    /// (default 1e8). A `law = { penalty = k }` contact uses its own k.
    pub penalty: f64,
    /// Also the condition estimates that cost a factorisation of their own
    /// (κ(K) on the direct path: one more sparse LDLᵀ of the whole
    /// stiffness); default false: only those the run's own factors give.
    pub condition_estimate: bool,
}

/// `solver.status_changes`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StatusChanges {
    #[default]
    All,
    Single,
}

/// `solver.constraints`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Constraints {
    #[default]
    Multipliers,
    Penalty,
}

impl Default for Solver {
    fn default() -> Self {
        Solver {
            method: Method::Status,
            path: SolvePath::Auto,
            tolerance: 1e-10,
            max_iterations: 500,
            friction: FrictionSolver::FixedPoint,
            time_limit: None,
            status_changes: StatusChanges::All,
            constraints: Constraints::Multipliers,
            penalty: 1e8,
            condition_estimate: false,
        }
    }
}

/// `solver.method`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    #[default]
    Status,
    Lemke,
    ProjectedGradient,
    Mprgp,
    Uzawa,
    AugmentedLagrangian,
    Penalty,
    /// Projected conjugate gradient (an addition to docs/reference/scene-format.md's list).
    ProjectedConjugateGradient,
}

impl Method {
    /// Every method, in the order of `docs/reference/scene-format.md`, then the additions.
    pub const ALL: [Method; 8] = [
        Method::Status,
        Method::Lemke,
        Method::ProjectedGradient,
        Method::Mprgp,
        Method::Uzawa,
        Method::AugmentedLagrangian,
        Method::Penalty,
        Method::ProjectedConjugateGradient,
    ];

    /// The scene-file / CLI spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Method::Status => "status",
            Method::Lemke => "lemke",
            Method::ProjectedGradient => "projected_gradient",
            Method::Mprgp => "mprgp",
            Method::Uzawa => "uzawa",
            Method::AugmentedLagrangian => "augmented_lagrangian",
            Method::Penalty => "penalty",
            Method::ProjectedConjugateGradient => "projected_conjugate_gradient",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Method {
    type Err = String;
    /// Accepts the scene spelling; `-` may replace `_` (`projected-gradient`).
    fn from_str(s: &str) -> Result<Self, String> {
        let key = s.trim().replace('-', "_");
        Method::ALL
            .into_iter()
            .find(|m| m.as_str() == key)
            .ok_or_else(|| {
                format!(
                    "unknown method \"{s}\"; valid methods: {}",
                    Method::ALL.map(Method::as_str).join(", ")
                )
            })
    }
}

/// `solver.path`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolvePath {
    /// Static condensation onto the contact interface.
    Condensed,
    /// The full system.
    Direct,
    /// The cheaper of the two for the scene, estimated from its mesh and
    /// contact sizes before anything is built (docs/guide/choosing.md).
    #[default]
    Auto,
}

impl SolvePath {
    pub const ALL: [SolvePath; 3] = [SolvePath::Condensed, SolvePath::Direct, SolvePath::Auto];

    /// The scene-file / CLI spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            SolvePath::Condensed => "condensed",
            SolvePath::Direct => "direct",
            SolvePath::Auto => "auto",
        }
    }
}

impl fmt::Display for SolvePath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for SolvePath {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let key = s.trim();
        SolvePath::ALL
            .into_iter()
            .find(|m| m.as_str() == key)
            .ok_or_else(|| format!("unknown path \"{s}\"; valid paths: condensed, direct, auto"))
    }
}

/// `solver.friction`: the outer loop for friction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionSolver {
    #[default]
    FixedPoint,
    Status,
    /// The fixed point on the threshold with each Tresca problem solved by
    /// the semi-smooth Newton method (2D; in 3D the fixed point already
    /// does).
    Newton,
    /// The nonsmooth Gauss–Seidel method, contact by contact (2D and 3D
    /// Coulomb).
    Nsgs,
}

impl FrictionSolver {
    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            FrictionSolver::FixedPoint => "fixed_point",
            FrictionSolver::Status => "status",
            FrictionSolver::Newton => "newton",
            FrictionSolver::Nsgs => "nsgs",
        }
    }
}
