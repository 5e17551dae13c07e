//! `[[bodies]]`: a deformable body's mesh (a generator or a Gmsh file) and
//! element kind, or a rigid obstacle's shape.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

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
    /// 2D. Surfaces: left, right, bottom, top. Default element `quad4`;
    /// grading towards `bottom` | `top` | `left` | `right`.
    Rectangle(Block<2>),
    /// 2D. Surfaces: flat, arc.
    HalfDisk(HalfDisk),
    /// 3D. Surfaces: xmin, xmax, ymin, ymax, zmin, zmax. Default element
    /// `hex8`; grading towards `xmin` .. `zmax`.
    Box(Block<3>),
    /// 3D. Surfaces: flat, dome.
    Hemisphere(Hemisphere),
    /// Axisymmetric only. Surfaces: axis, flat, arc. Grading towards the pole on the
    /// axis.
    QuarterDisk(QuarterDisk),
}

/// The entries of the rectangle (`D` = 2) and box (`D` = 3) generators: an
/// axis-aligned block of `divisions` cells a side.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(
    deny_unknown_fields,
    bound(
        serialize = "[f64; D]: Serialize, [usize; D]: Serialize",
        deserialize = "[f64; D]: Deserialize<'de>, [usize; D]: Deserialize<'de>"
    )
)]
pub struct Block<const D: usize> {
    /// The corner of least coordinates ([x, y] lower left of a rectangle).
    pub origin: [f64; D],
    /// The side lengths, > 0 ([width, height] of a rectangle).
    pub size: [f64; D],
    /// The cells along each side, ≥ 1.
    pub divisions: [usize; D],
    /// `quad4` (default in 2D), `hex8` (default in 3D), or another element
    /// of the dimension.
    #[serde(default = "Element::block_default::<D>")]
    pub element: Element,
    /// Grading towards one of the block's surfaces.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grading: Option<Grading>,
}

/// The entries of the half-disk generator.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HalfDisk {
    /// Centre of the circle, on the flat side.
    pub center: [f64; 2],
    pub radius: f64,
    /// Elements along the arc (≥ 4).
    pub divisions: usize,
    /// Unit vector from the centre to the middle of the arc (default [0, -1]).
    #[serde(default = "default_pole2")]
    pub pole: [f64; 2],
    /// Smallest elements at the pole (default 1 = uniform).
    #[serde(default = "one")]
    pub grading: f64,
    /// `quad4` (default) or `tri3`.
    #[serde(default = "Element::quad4")]
    pub element: Element,
}

/// The entries of the hemisphere generator.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Hemisphere {
    pub center: [f64; 3],
    pub radius: f64,
    pub divisions: usize,
    /// Default [0, 0, -1].
    #[serde(default = "default_pole3")]
    pub pole: [f64; 3],
    #[serde(default = "one")]
    pub grading: f64,
    /// `hex8` (default) | `tet4` | `hex20` | `tet10`.
    #[serde(default = "Element::hex8")]
    pub element: Element,
    /// `whole` (default) or `quarter`: the cells on one side of the two
    /// planes through the pole and the local axes, with their surfaces
    /// symmetry_1 and symmetry_2 (for symmetric loads).
    #[serde(default, skip_serializing_if = "Sector::is_whole")]
    pub sector: Sector,
}

/// The entries of the quarter-disk generator.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct QuarterDisk {
    pub center: [f64; 2],
    pub radius: f64,
    pub divisions: usize,
    #[serde(default = "one")]
    pub grading: f64,
    #[serde(default = "Element::quad4")]
    pub element: Element,
}

impl Generator {
    /// The scene-file spelling of the generator.
    pub fn name(&self) -> &'static str {
        match self {
            Generator::Rectangle(_) => "rectangle",
            Generator::HalfDisk(_) => "half_disk",
            Generator::Box(_) => "box",
            Generator::Hemisphere(_) => "hemisphere",
            Generator::QuarterDisk(_) => "quarter_disk",
        }
    }

    /// The element type of the generated cells.
    pub fn element(&self) -> Element {
        match self {
            Generator::Rectangle(b) => b.element,
            Generator::HalfDisk(d) => d.element,
            Generator::Box(b) => b.element,
            Generator::QuarterDisk(d) => d.element,
            Generator::Hemisphere(h) => h.element,
        }
    }

    /// The space dimension of the generated mesh.
    pub fn dimension(&self) -> usize {
        match self {
            Generator::Box(_) | Generator::Hemisphere(_) => 3,
            _ => 2,
        }
    }

    /// The names of the surfaces this generator creates.
    pub fn surfaces(&self) -> &'static [&'static str] {
        match self {
            Generator::Rectangle(_) => &["left", "right", "bottom", "top"],
            Generator::HalfDisk(_) => &["flat", "arc"],
            Generator::Box(_) => &["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"],
            Generator::Hemisphere(h) if h.sector == Sector::Quarter => {
                &["flat", "dome", "symmetry_1", "symmetry_2"]
            }
            Generator::Hemisphere(_) => &["flat", "dome"],
            Generator::QuarterDisk(_) => &["axis", "flat", "arc"],
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
    /// The default element of a [`Block`] of dimension `D`.
    fn block_default<const D: usize>() -> Self {
        if D == 3 {
            Element::Hex8
        } else {
            Element::Quad4
        }
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
