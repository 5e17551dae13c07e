//! `Scene::validate`: the semantic checks of `docs/reference/scene-format.md`. Every error names the entry
//! and says what would be valid. Surface names cannot be checked here (meshes do not
//! exist yet); the solver does that.

use crate::output::*;
use crate::types::*;
use crate::{SceneError, Shown};
use std::collections::{BTreeMap, BTreeSet};

mod assembly;
mod generators;
use assembly::{validate_place, validate_step_friction, validate_tie};
use generators::{validate_rigid, GeneratorCheck};

type Result<T = ()> = std::result::Result<T, SceneError>;

/// The most `[[steps]]` a scene may have: every step is a contact solve whose
/// fields are kept for the report and written as one VTU file per body.
pub const MAX_STEPS: usize = 10_000;

/// A contact side's `surface` that must be given (`missing` is the message
/// when it is not) and not be blank.
fn named_surface(
    entry: &str,
    surface: &Option<String>,
    missing: impl FnOnce() -> String,
) -> Result {
    match surface {
        None => Err(invalid(entry, missing())),
        Some(s) if s.trim().is_empty() => Err(invalid(entry, "must not be empty")),
        Some(_) => Ok(()),
    }
}

/// The name of a material or body (`what`) at entry `e`: not blank, and not
/// already in `seen`.
fn unique_name<'a>(seen: &mut BTreeSet<&'a str>, e: &str, name: &'a str, what: &str) -> Result {
    if name.trim().is_empty() {
        return Err(invalid(format!("{e}.name"), "must not be empty"));
    }
    if !seen.insert(name) {
        return Err(invalid(
            format!("{e}.name"),
            format!("\"{name}\" is already the name of another {what}; names must be unique"),
        ));
    }
    Ok(())
}

/// The output file stem of deformable body `i` ([`crate::file_stem`]): not
/// too long and not already another body's (`stems`: stem → body index).
fn file_stem_of(stems: &mut BTreeMap<String, usize>, i: usize, name: &str) -> Result {
    let e = format!("bodies[{i}].name");
    let stem = crate::file_stem(name);
    if stem.len() > crate::MAX_FILE_STEM {
        return Err(invalid(
            e,
            format!(
                "is {} characters long; a body's name names its output files, so at most {} are allowed",
                stem.len(),
                crate::MAX_FILE_STEM
            ),
        ));
    }
    if let Some(j) = stems.insert(stem.clone(), i) {
        return Err(invalid(
            e,
            format!(
                "\"{name}\" and bodies[{j}].name would write the same output files ({stem}_<step>.vtu: characters other than letters, digits, '-' and '_' become '_'); rename one"
            ),
        ));
    }
    Ok(())
}

fn invalid(entry: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        entry: entry.into(),
        message: message.into(),
    }
}

/// `"a", "b"` or a note that there is none; a long list is cut after a dozen
/// names (the message stays a line).
fn known(names: &[&str], what: &str, table: &str) -> String {
    const SHOWN: usize = 12;
    if names.is_empty() {
        format!("no {table} entry is defined")
    } else {
        let list: Vec<String> = names
            .iter()
            .take(SHOWN)
            .map(|n| format!("\"{n}\""))
            .collect();
        let more = match names.len().saturating_sub(SHOWN) {
            0 => String::new(),
            n => format!(" and {n} more"),
        };
        format!("known {what}: {}{more}", list.join(", "))
    }
}

/// The Young's moduli a run can represent: products of stiffnesses,
/// displacements and their squares (energies, Delassus entries) stay within
/// double precision (1e±308) for lengths of any sane unit.
const YOUNG_RANGE: (f64, f64) = (1e-100, 1e100);

/// A stiffness (Young's modulus, a penalty law's k_n) that is positive and
/// within [`YOUNG_RANGE`].
fn representable_stiffness(entry: &str, v: f64) -> Result {
    positive(entry, v)?;
    if !(YOUNG_RANGE.0..=YOUNG_RANGE.1).contains(&v) {
        return Err(invalid(
            entry,
            format!(
                "{:e} is outside [{:e}, {:e}]: the stiffness, loads and their products would overflow or underflow double precision; choose other units (MPa instead of Pa, mm instead of m)",
                v, YOUNG_RANGE.0, YOUNG_RANGE.1
            ),
        ));
    }
    Ok(())
}

fn positive(entry: &str, v: f64) -> Result {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(entry, format!("must be > 0, got {}", Shown(v))))
    }
}

/// `reference.radius2`: the other body's radius of a two-body Hertz
/// contact, finite and non-zero, with `radius`, and for a concave seat
/// (negative) wider than the body (a positive combined radius).
fn check_radius2(r: &Reference, v: f64) -> Result {
    let entry = "reference.radius2";
    if !matches!(
        r.kind,
        ReferenceKind::HertzCylinder | ReferenceKind::HertzSphere | ReferenceKind::CattaneoMindlin
    ) {
        return Err(invalid(
            entry,
            format!(
                "is the second radius of a two-body Hertz contact (hertz_cylinder, hertz_sphere, cattaneo_mindlin), not of kind = \"{}\"",
                r.kind.as_str()
            ),
        ));
    }
    if !(v.is_finite() && v != 0.0) {
        return Err(invalid(
            entry,
            format!(
                "must be a finite non-zero radius (> 0 convex, < 0 a concave seat), got {}",
                Shown(v)
            ),
        ));
    }
    match r.radius {
        Some(r1) if v < 0.0 && -v <= r1 => Err(invalid(
            entry,
            format!("a concave seat (radius2 < 0) must be wider than the body in it: |{}| <= radius = {}", Shown(v), Shown(r1)),
        )),
        Some(_) => Ok(()),
        None => Err(invalid(entry, "needs `radius`, the first body's radius")),
    }
}

/// `reference.symmetry` and `reference.center`: a 3D Hertz sphere's, the
/// centre of `dimension` finite coordinates, given with a symmetry.
fn check_reference_centre(r: &Reference, dimension: u8, model: Model) -> Result {
    let sphere_3d = r.kind == ReferenceKind::HertzSphere && dimension == 3 && model == Model::Solid;
    let what = "applies to kind = \"hertz_sphere\" in 3D";
    if let Some(s) = r.symmetry {
        if !sphere_3d {
            return Err(invalid("reference.symmetry", what));
        }
        if r.center.is_none() {
            return Err(invalid(
                "reference.center",
                format!("symmetry = \"{}\" needs the centre of the whole contact, a point of the symmetry planes: [x, y, z]", s.as_str()),
            ));
        }
    }
    if let Some(c) = &r.center {
        if !sphere_3d {
            return Err(invalid("reference.center", what));
        }
        if c.len() != 3 || c.iter().any(|v| !v.is_finite()) {
            return Err(invalid(
                "reference.center",
                format!("must be 3 finite coordinates [x, y, z], got {c:?}"),
            ));
        }
    }
    Ok(())
}

fn non_negative(entry: &str, v: f64) -> Result {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(entry, format!("must be >= 0, got {}", Shown(v))))
    }
}

fn finite(entry: &str, v: f64) -> Result {
    if v.is_finite() {
        Ok(())
    } else {
        Err(invalid(
            entry,
            format!("must be a finite number, got {}", Shown(v)),
        ))
    }
}

fn finite_all(entry: &str, v: &[f64]) -> Result {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(invalid(
            entry,
            format!("component {i} must be a finite number, got {}", Shown(v[i])),
        )),
    }
}

/// `dim` finite components.
fn vector(entry: &str, v: &[f64], dim: usize) -> Result {
    if v.len() != dim {
        return Err(invalid(
            entry,
            format!(
                "needs {dim} components (dimension = {dim}), got {}: {v:?}",
                v.len()
            ),
        ));
    }
    finite_all(entry, v)
}

fn non_zero(entry: &str, v: &[f64]) -> Result {
    finite_all(entry, v)?;
    if v.iter().all(|x| *x == 0.0) {
        Err(invalid(entry, "must be a non-zero vector"))
    } else {
        Ok(())
    }
}

/// The largest grading ratio: beyond, the smallest elements are lost in the
/// round-off of the body's coordinates (a hemisphere graded 1e30 has
/// degenerate cells, 1e100 NaN nodes).
const MAX_GRADING: f64 = 1e12;

fn grading_ratio(entry: &str, v: f64) -> Result {
    if (1.0..=MAX_GRADING).contains(&v) {
        Ok(())
    } else {
        Err(invalid(
            entry,
            format!(
                "must be between 1 and {MAX_GRADING:e} (largest over smallest element size; 1 = uniform; beyond, the smallest elements are lost in the round-off of the coordinates), got {}",
                Shown(v)
            ),
        ))
    }
}

/// The largest friction coefficient: μ times a normal force must stay
/// within double precision (μ = 1e200 overflowed the 3D thresholds).
const MAX_FRICTION_COEFFICIENT: f64 = 1e100;

fn friction_coefficient(entry: &str, v: f64) -> Result {
    non_negative(entry, v)?;
    if v <= MAX_FRICTION_COEFFICIENT {
        Ok(())
    } else {
        Err(invalid(
            entry,
            format!(
                "must be <= {MAX_FRICTION_COEFFICIENT:e} (μ times the normal force would overflow double precision; a contact that must stick is held by any μ above its tangential over normal force), got {}",
                Shown(v)
            ),
        ))
    }
}

impl Scene {
    /// Checks everything that can be checked before the meshes exist; the first
    /// problem found is returned as [`SceneError::Invalid`].
    pub fn validate(&self) -> Result {
        let dim = self.dimension as usize;
        if dim != 2 && dim != 3 {
            return Err(invalid(
                "dimension",
                format!("must be 2 or 3, got {}", self.dimension),
            ));
        }
        match (dim, self.model) {
            (2, Model::Solid) => {
                return Err(invalid(
                    "model",
                    "\"solid\" needs dimension = 3; with dimension = 2 use \"plane_strain\", \"plane_stress\" or \"axisymmetric\"",
                ))
            }
            (3, m) if m != Model::Solid => {
                return Err(invalid(
                    "model",
                    format!(
                        "\"{}\" needs dimension = 2; with dimension = 3 use \"solid\"",
                        m.as_str()
                    ),
                ))
            }
            _ => {}
        }
        self.validate_materials()?;
        self.validate_bodies()?;
        if !self.bodies.iter().any(|b| b.is_deformable()) {
            return Err(invalid(
                "bodies",
                "the scene has no deformable body; add a [[bodies]] entry with a mesh",
            ));
        }
        self.validate_boundary()?;
        self.validate_contact()?;
        self.validate_steps()?;
        self.validate_solver()?;
        self.validate_reference()?;
        self.validate_output()
    }

    fn validate_materials(&self) -> Result {
        let mut seen = BTreeSet::new();
        for (i, m) in self.materials.iter().enumerate() {
            let e = format!("materials[{i}]");
            unique_name(&mut seen, &e, &m.name, "material")?;
            representable_stiffness(&format!("{e}.young"), m.young)?;
            if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
                return Err(invalid(
                    format!("{e}.poisson"),
                    format!("must satisfy -1 < poisson < 0.5, got {}", Shown(m.poisson)),
                ));
            }
        }
        Ok(())
    }

    fn validate_bodies(&self) -> Result {
        let dim = self.dimension as usize;
        let materials: Vec<&str> = self.materials.iter().map(|m| m.name.as_str()).collect();
        let mut seen = BTreeSet::new();
        let mut stems = BTreeMap::new();
        for (i, b) in self.bodies.iter().enumerate() {
            let e = format!("bodies[{i}]");
            unique_name(&mut seen, &e, &b.name, "body")?;
            if b.mesh.is_some() {
                file_stem_of(&mut stems, i, &b.name)?;
            }
            if let Subdomains::Count(0) = b.subdomains {
                return Err(invalid(
                    format!("{e}.subdomains"),
                    "must be an integer >= 1 or \"auto\", got 0",
                ));
            }
            match (&b.mesh, &b.rigid) {
                (Some(_), Some(_)) => {
                    return Err(invalid(
                        &e,
                        format!("body \"{}\" has both `mesh` and `rigid`; give `mesh` for a deformable body or `rigid` for a rigid obstacle, not both", b.name),
                    ))
                }
                (None, None) => {
                    return Err(invalid(
                        &e,
                        format!("body \"{}\" has neither `mesh` nor `rigid`; give `mesh` (and `material`) for a deformable body or `rigid` for a rigid obstacle", b.name),
                    ))
                }
                (Some(mesh), None) => {
                    match &b.material {
                        None => {
                            return Err(invalid(
                                format!("{e}.material"),
                                format!(
                                    "a deformable body needs `material`, the name of a [[materials]] entry ({})",
                                    known(&materials, "materials", "[[materials]]")
                                ),
                            ))
                        }
                        Some(name) if !materials.contains(&name.as_str()) => {
                            return Err(invalid(
                                format!("{e}.material"),
                                format!(
                                    "unknown material \"{name}\"; {}",
                                    known(&materials, "materials", "[[materials]]")
                                ),
                            ))
                        }
                        Some(_) => {}
                    }
                    self.validate_mesh(&format!("{e}.mesh"), mesh)?;
                    self.validate_formulation(&format!("{e}.formulation"), b.formulation, mesh)?;
                }
                (None, Some(shape)) => {
                    if b.material.is_some() {
                        return Err(invalid(
                            format!("{e}.material"),
                            "a rigid body has no material; remove `material` (or give a `mesh` instead of `rigid` for a deformable body)",
                        ));
                    }
                    if !b.formulation.is_displacement() {
                        return Err(invalid(
                            format!("{e}.formulation"),
                            "a rigid body has no elements; remove `formulation`",
                        ));
                    }
                    validate_rigid(&format!("{e}.rigid"), shape, dim)?;
                }
            }
        }
        Ok(())
    }

    /// `b_bar` needs a model that locks (not plane stress) and quad4 / hex8
    /// cells; a Gmsh file's cells are checked by the solver once it is read.
    fn validate_formulation(&self, e: &str, f: Formulation, mesh: &MeshSpec) -> Result {
        if f != Formulation::BBar {
            return Ok(());
        }
        const VALID: &str = "\"b_bar\" takes quad4 cells in plane_strain and axisymmetric models and hex8 cells in solid models; otherwise use \"displacement\" (the default)";
        if self.model == Model::PlaneStress {
            return Err(invalid(
                e,
                format!("\"b_bar\" is refused with model = \"plane_stress\", which does not lock as poisson -> 0.5 (sigma_zz = 0 leaves eps_zz free); {VALID}"),
            ));
        }
        if let MeshSpec::Generator(g) = mesh {
            let el = g.element();
            if !matches!(el, Element::Quad4 | Element::Hex8) {
                return Err(invalid(
                    e,
                    format!(
                        "\"b_bar\" is not available for {} cells (mesh.element = \"{}\"); {VALID}",
                        el.as_str(),
                        el.as_str()
                    ),
                ));
            }
        }
        Ok(())
    }

    fn validate_mesh(&self, e: &str, mesh: &MeshSpec) -> Result {
        let dim = self.dimension as usize;
        let g = match mesh {
            MeshSpec::File { file, volume } => {
                if file.as_os_str().is_empty() {
                    return Err(invalid(
                        format!("{e}.file"),
                        "must be the path of a Gmsh 2.2 or 4.1 file",
                    ));
                }
                if volume.as_ref().is_some_and(|v| v.trim().is_empty()) {
                    return Err(invalid(
                        format!("{e}.volume"),
                        "must be the name of a physical group of dimension `dimension` in the file",
                    ));
                }
                return Ok(());
            }
            MeshSpec::Generator(g) => g,
        };
        if g.dimension() != dim {
            let valid = if dim == 2 {
                "rectangle, half_disk, quarter_disk (axisymmetric only)"
            } else {
                "box, hemisphere"
            };
            return Err(invalid(
                format!("{e}.generator"),
                format!(
                    "\"{}\" is a {}D generator but dimension = {dim}; {dim}D generators: {valid}",
                    g.name(),
                    g.dimension()
                ),
            ));
        }
        GeneratorCheck { e, g }.check(self.model)
    }

    fn validate_boundary(&self) -> Result {
        let dim = self.dimension as usize;
        let mut names = BTreeSet::new();
        for (i, bc) in self.boundary.iter().enumerate() {
            let e = format!("boundary[{i}]");
            if let Some(name) = &bc.name {
                if name.trim().is_empty() {
                    return Err(invalid(format!("{e}.name"), "must not be empty when given"));
                }
                if !names.insert(name.as_str()) {
                    return Err(invalid(
                        format!("{e}.name"),
                        format!("\"{name}\" is already the name of another [[boundary]] entry; names must be unique"),
                    ));
                }
            }
            self.deformable_body(&format!("{e}.body"), &bc.body, "boundary conditions")?;
            validate_place(&e, bc, dim)?;
            let given = [
                bc.displacement.is_some(),
                bc.traction.is_some(),
                bc.force.is_some(),
            ]
            .iter()
            .filter(|x| **x)
            .count();
            if given != 1 {
                return Err(invalid(
                    &e,
                    format!(
                        "give exactly one of `displacement`, `traction` or `force` (got {given})"
                    ),
                ));
            }
            if let Some(t) = &bc.traction {
                vector(&format!("{e}.traction"), t, dim)?;
            }
            if let Some(f) = &bc.force {
                vector(&format!("{e}.force"), f, dim)?;
            }
            if let Some(p) = &bc.moment_about {
                self.validate_moment_about(&format!("{e}.moment_about"), bc, p)?;
            }
            if let Some(d) = &bc.displacement {
                let de = format!("{e}.displacement");
                if d.x.is_none() && d.y.is_none() && d.z.is_none() {
                    let comps = if dim == 3 { "x, y, z" } else { "x, y" };
                    return Err(invalid(
                        de,
                        format!("give at least one component ({comps}); components given are imposed, others free"),
                    ));
                }
                if dim == 2 && d.z.is_some() {
                    return Err(invalid(
                        format!("{de}.z"),
                        "a 2D scene has only x and y components",
                    ));
                }
                for (c, v) in [("x", d.x), ("y", d.y), ("z", d.z)] {
                    if let Some(v) = v {
                        finite(&format!("{de}.{c}"), v)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// `moment_about` of a boundary entry: a point of `dimension` finite
    /// coordinates, on a prescribed displacement (the only entry with a
    /// reaction), not in an axisymmetric model (a ring's reaction is axial).
    fn validate_moment_about(&self, e: &str, bc: &Boundary, p: &[f64]) -> Result {
        if bc.displacement.is_none() {
            return Err(invalid(
                e,
                "is the point of the reaction's moment, and only a `displacement` entry has a reaction; remove it, or give `displacement`",
            ));
        }
        if self.model == Model::Axisymmetric {
            return Err(invalid(
                e,
                "an axisymmetric reaction is the axial force of a whole ring, with no moment; remove it",
            ));
        }
        vector(e, p, self.dimension as usize)
    }

    /// The body named `name` must exist and be deformable.
    fn deformable_body(&self, entry: &str, name: &str, what: &str) -> Result<&Body> {
        let body = self.body_exists(entry, name)?;
        if !body.is_deformable() {
            return Err(invalid(
                entry,
                format!(
                    "body \"{name}\" is rigid; {what} apply to deformable bodies ({})",
                    self.known_bodies(true)
                ),
            ));
        }
        Ok(body)
    }

    fn body_exists(&self, entry: &str, name: &str) -> Result<&Body> {
        self.body(name).ok_or_else(|| {
            invalid(
                entry,
                format!("unknown body \"{name}\"; {}", self.known_bodies(false)),
            )
        })
    }

    fn known_bodies(&self, deformable_only: bool) -> String {
        let names: Vec<&str> = self
            .bodies
            .iter()
            .filter(|b| !deformable_only || b.is_deformable())
            .map(|b| b.name.as_str())
            .collect();
        if deformable_only {
            known(&names, "deformable bodies", "deformable [[bodies]]")
        } else {
            known(&names, "bodies", "[[bodies]]")
        }
    }

    fn validate_contact(&self) -> Result {
        let dim = self.dimension as usize;
        let mut names = BTreeSet::new();
        for (i, c) in self.contact.iter().enumerate() {
            if c.name.trim().is_empty() {
                return Err(invalid(format!("contact[{i}].name"), "must not be empty"));
            }
            let e = format!("contact \"{}\"", c.name);
            if !names.insert(c.name.as_str()) {
                return Err(invalid(
                    format!("{e}.name"),
                    "is already the name of another [[contact]] entry; names must be unique",
                ));
            }
            self.validate_contact_sides(&e, c)?;
            validate_tie(self, &e, c)?;
            if let Law::Penalty { penalty } = c.law {
                representable_stiffness(&format!("{e}.law.penalty"), penalty)?;
            }
            validate_friction(&e, &c.friction, dim)?;
            if let Gap::Uniform(g) = c.gap {
                finite(&format!("{e}.gap"), g)?;
            }
            if let Some(d) = c.search_distance {
                if !(d.is_finite() && d > 0.0) {
                    return Err(invalid(
                        format!("{e}.search_distance"),
                        format!("must be a positive finite length (in the scene's units), got {}; leave it out to keep every slave node a contact candidate", Shown(d)),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The slave and master sides of the contact entry `e`: bodies that
    /// exist, surfaces where needed (and only there), not the same body.
    fn validate_contact_sides(&self, e: &str, c: &Contact) -> Result {
        // slave
        self.deformable_body(&format!("{e}.slave.body"), &c.slave.body, "the slave side")?;
        named_surface(&format!("{e}.slave.surface"), &c.slave.surface, || {
            format!(
                    "the slave side needs `surface`, the surface of body \"{}\" that may touch: slave = {{ body = \"{}\", surface = \"...\" }}",
                    c.slave.body, c.slave.body
                )
        })?;
        // master
        let master = self.body_exists(&format!("{e}.master.body"), &c.master.body)?;
        if master.is_deformable() {
            named_surface(&format!("{e}.master.surface"), &c.master.surface, || {
                format!(
                        "body \"{}\" is deformable, so the master side needs `surface`: master = {{ body = \"{}\", surface = \"...\" }}",
                        c.master.body, c.master.body
                    )
            })?;
        } else if c.master.surface.is_some() {
            return Err(invalid(
                format!("{e}.master.surface"),
                format!(
                    "body \"{}\" is rigid and has no surfaces; write master = {{ body = \"{}\" }}",
                    c.master.body, c.master.body
                ),
            ));
        }
        if c.slave.body == c.master.body {
            return Err(invalid(
                    e,
                    format!(
                        "self-contact (slave and master both body \"{}\") is not supported; the master must be another body",
                        c.slave.body
                    ),
                ));
        }
        Ok(())
    }
    fn validate_steps(&self) -> Result {
        if self.steps.len() > MAX_STEPS {
            return Err(invalid(
                "steps",
                format!(
                    "{} load steps, at most {MAX_STEPS} (each is a contact solve, a row of steps.csv and of report.json, and by default one VTU file per body); use fewer, larger steps",
                    self.steps.len()
                ),
            ));
        }
        let names: Vec<&str> = self
            .boundary
            .iter()
            .filter_map(|b| b.name.as_deref())
            .collect();
        for (i, step) in self.steps.iter().enumerate() {
            for (name, v) in &step.scale {
                let e = format!("steps[{i}].scale.{name}");
                if !names.contains(&name.as_str()) {
                    return Err(invalid(
                        e,
                        format!(
                            "\"{name}\" is not the name of a [[boundary]] entry; {}",
                            known(&names, "boundary names", "named [[boundary]]")
                        ),
                    ));
                }
                finite(&e, *v)?;
            }
        }
        validate_step_friction(self)
    }

    fn validate_solver(&self) -> Result {
        let t = self.solver.tolerance;
        if !(t.is_finite() && t > 0.0 && t < 1.0) {
            return Err(invalid(
                "solver.tolerance",
                format!("must satisfy 0 < tolerance < 1, got {}", Shown(t)),
            ));
        }
        if !(self.solver.penalty > 0.0 && self.solver.penalty.is_finite()) {
            return Err(invalid(
                "solver.penalty",
                format!(
                    "must be a positive multiple of the contact stiffness, got {}",
                    Shown(self.solver.penalty)
                ),
            ));
        }
        if self.solver.max_iterations == 0 {
            return Err(invalid("solver.max_iterations", "must be >= 1, got 0"));
        }
        if let Some(t) = self.solver.time_limit {
            if !(t.is_finite() && t > 0.0) {
                return Err(invalid(
                    "solver.time_limit",
                    format!("must be a number of seconds > 0, got {}", Shown(t)),
                ));
            }
        }
        Ok(())
    }

    fn validate_reference(&self) -> Result {
        let Some(r) = &self.reference else {
            return Ok(());
        };
        if let Some(v) = r.radius {
            positive("reference.radius", v)?;
        }
        if let Some(v) = r.radius2 {
            check_radius2(r, v)?;
        }
        if let Some(v) = r.half_width {
            positive("reference.half_width", v)?;
        }
        if let Some(v) = r.pressure {
            finite("reference.pressure", v)?;
        }
        if let Some(v) = r.friction {
            non_negative("reference.friction", v)?;
        }
        check_reference_centre(r, self.dimension, self.model)?;
        if matches!(
            r.kind,
            ReferenceKind::HertzCylinder | ReferenceKind::HertzSphere
        ) && r.radius.is_none()
        {
            return Err(invalid(
                "reference.radius",
                format!(
                    "kind = \"{}\" needs `radius`, the radius of the {}",
                    r.kind.as_str(),
                    if r.kind == ReferenceKind::HertzCylinder {
                        "cylinder"
                    } else {
                        "sphere"
                    }
                ),
            ));
        }
        Ok(())
    }

    fn validate_output(&self) -> Result {
        let dim = self.dimension as usize;
        let mut seen = BTreeSet::new();
        for (i, f) in self.output.fields.iter().enumerate() {
            if !Output::FIELDS.contains(&f.as_str()) {
                return Err(invalid(
                    format!("output.fields[{i}]"),
                    format!("unknown field \"{f}\"; valid: displacement, stress, contact"),
                ));
            }
            if !seen.insert(f.as_str()) {
                return Err(invalid(
                    format!("output.fields[{i}]"),
                    format!("\"{f}\" is listed twice"),
                ));
            }
        }
        for (i, p) in self.output.probes.iter().enumerate() {
            vector(&format!("output.probes[{i}]"), p, dim)?;
        }
        self.validate_output_steps()?;
        if let Some(d) = &self.output.directory {
            if d.as_os_str().is_empty() {
                return Err(invalid(
                    "output.directory",
                    "must not be empty (omit it for out/<scene file stem>)",
                ));
            }
        }
        Ok(())
    }
}

impl Scene {
    /// `output.steps`: `every` at least 1; list entries between 1 and the
    /// number of load steps, each once.
    fn validate_output_steps(&self) -> Result {
        let n = self.step_scales().len();
        match &self.output.steps {
            OutputSteps::Every(k) if *k < 1 => Err(invalid(
                "output.steps.every",
                format!("must be a whole number >= 1 (write the fields of every N-th step and the last), got {k}"),
            )),
            OutputSteps::List(l) => {
                if l.is_empty() {
                    return Err(invalid(
                        "output.steps",
                        "the list is empty; list step numbers from 1 to the number of steps, or write \"last\" (or fields = [] for no field output)",
                    ));
                }
                let mut seen = BTreeSet::new();
                for (i, &s) in l.iter().enumerate() {
                    if s < 1 || s as usize > n {
                        return Err(invalid(
                            format!("output.steps[{i}]"),
                            format!("step {s} does not exist: the scene has {n} load step(s), numbered 1 to {n}"),
                        ));
                    }
                    if !seen.insert(s) {
                        return Err(invalid(
                            format!("output.steps[{i}]"),
                            format!("step {s} is listed twice"),
                        ));
                    }
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

/// The friction law of the contact entry `e` in dimension `dim`.
fn validate_friction(e: &str, friction: &Friction, dim: usize) -> Result {
    match friction {
        Friction::None => {}
        Friction::Tresca(g) => non_negative(&format!("{e}.friction.tresca"), *g)?,
        Friction::Coulomb {
            coefficient,
            slip_stiffness,
            roughness,
        } => {
            let fe = format!("{e}.friction.coulomb");
            match (coefficient.len(), dim) {
                        (1, _) | (2, 3) => {}
                        (2, _) => {
                            return Err(invalid(
                                fe,
                                "two coefficients (anisotropic, elliptic cone) need dimension = 3; give one number",
                            ))
                        }
                        (n, _) => {
                            return Err(invalid(
                                fe,
                                format!("give one coefficient (or two in 3D: [mu1, mu2]), got {n}"),
                            ))
                        }
                    }
            for mu in coefficient {
                friction_coefficient(&fe, *mu)?;
            }
            if coefficient.len() == 2 && coefficient.contains(&0.0) && coefficient != &[0.0, 0.0] {
                return Err(invalid(
                    fe,
                    format!(
                        "an elliptic cone needs both coefficients > 0, got {coefficient:?}: friction in one tangential direction alone is not a cone; give one coefficient, or two positive ones"
                    ),
                ));
            }
            if let Some(k) = slip_stiffness {
                positive(&format!("{e}.friction.slip_stiffness"), *k)?;
            }
            if let Some(q) = roughness {
                let re = format!("{e}.friction.roughness");
                non_negative(&re, *q)?;
                // Q = 0 is the regularised law; else a stiffness as k_n is.
                if *q != 0.0 {
                    representable_stiffness(&re, *q)?;
                }
                if slip_stiffness.is_none() {
                    return Err(invalid(
                        re,
                        "the roughness Q (kinematic hardening of the slip, course notes §6) needs the asperities' stiffness: give slip_stiffness = <k_e> with it",
                    ));
                }
            }
        }
        Friction::NortonHoff { coefficient, rho } => {
            friction_coefficient(&format!("{e}.friction.norton_hoff"), *coefficient)?;
            if !(rho.is_finite() && *rho > 0.0 && *rho < 1.0) {
                return Err(invalid(
                    format!("{e}.friction.rho"),
                    format!("must satisfy 0 < rho < 1, got {}", Shown(*rho)),
                ));
            }
        }
    }
    Ok(())
}
