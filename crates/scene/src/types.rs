//! The schema: one Rust type per table of the scene file.

use crate::output::{Output, Reference};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

mod body;
mod contact;
mod solver;
pub use body::{
    Block, Body, Element, Formulation, Generator, Grading, HalfDisk, Hemisphere, MeshSpec,
    QuarterDisk, RigidShape, Sector, Subdomains,
};
pub use contact::{
    Contact, ContactSide, Discretization, Friction, Gap, Law, NormalRule, SlaveChoice,
};
pub use solver::{Constraints, FrictionSolver, Method, SolvePath, Solver, StatusChanges};

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
                    Generator::Rectangle(b) => b.divisions = b.divisions.map(scale),
                    Generator::Box(b) => b.divisions = b.divisions.map(scale),
                    Generator::HalfDisk(HalfDisk { divisions, .. })
                    | Generator::QuarterDisk(QuarterDisk { divisions, .. }) => {
                        *divisions = (scale(*divisions) / 2 * 2).max(4)
                    }
                    Generator::Hemisphere(h) => h.divisions = scale(h.divisions).max(4),
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
    pub fn step_scales(&self) -> Vec<BTreeMap<String, f64>> {
        let first: BTreeMap<String, f64> = self
            .boundary
            .iter()
            .filter_map(|b| b.name.clone())
            .map(|n| (n, 1.0))
            .collect();
        self.per_step(first, |step, current| {
            for (name, scale) in &step.scale {
                current.insert(name.clone(), *scale);
            }
        })
    }

    /// The friction law of every contact at every load step: the contact's
    /// own until a step's `friction` changes it, which holds from that step
    /// on. With no `[[steps]]`, one step with the contacts' own laws.
    pub fn step_frictions(&self) -> Vec<Vec<Friction>> {
        let first: Vec<Friction> = self.contact.iter().map(|c| c.friction.clone()).collect();
        self.per_step(first, |step, current| {
            for (name, f) in &step.friction {
                if let Some(ci) = self.contact.iter().position(|c| &c.name == name) {
                    current[ci] = f.clone();
                }
            }
        })
    }

    /// A value at every load step: `first` changed by each step in turn
    /// (`change`), what a step does not change held from the step before.
    /// With no `[[steps]]`, one step with `first`.
    fn per_step<T: Clone>(&self, first: T, change: impl Fn(&Step, &mut T)) -> Vec<T> {
        if self.steps.is_empty() {
            return vec![first];
        }
        let mut current = first;
        self.steps
            .iter()
            .map(|step| {
                change(step, &mut current);
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
