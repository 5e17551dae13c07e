//! The checks of the mesh generators' entries and of rigid shapes.

use super::*;

/// The elements of the plane generators (rectangle, half and quarter disk).
const PLANE_ELEMENTS: [Element; 4] = [Element::Quad4, Element::Tri3, Element::Quad8, Element::Tri6];

/// The elements of the solid generators (box, hemisphere).
const SOLID_ELEMENTS: [Element; 4] = [Element::Hex8, Element::Tet4, Element::Hex20, Element::Tet10];

/// The checks of the entries of one generator `g` of the mesh entry `e`.
pub(super) struct GeneratorCheck<'a> {
    pub(super) e: &'a str,
    pub(super) g: &'a Generator,
}

impl GeneratorCheck<'_> {
    /// The entries of the generator, in the order of its table.
    pub(super) fn check(&self, model: Model) -> Result {
        let e = self.e;
        match self.g {
            Generator::Rectangle(b) => {
                self.block(b, &PLANE_ELEMENTS)?;
                self.grading(&b.grading, &["bottom", "top", "left", "right"])
            }
            Generator::Box(b) => {
                self.block(b, &SOLID_ELEMENTS)?;
                self.grading(
                    &b.grading,
                    &["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"],
                )
            }
            Generator::HalfDisk(d) => self.half_disk(d),
            Generator::Hemisphere(h) => {
                self.element(h.element, &SOLID_ELEMENTS)?;
                self.disk(&h.center, h.radius, h.divisions)?;
                non_zero(&format!("{e}.pole"), &h.pole)?;
                grading_ratio(&format!("{e}.grading"), h.grading)
            }
            Generator::QuarterDisk(d) => {
                if model != Model::Axisymmetric {
                    return Err(invalid(
                        format!("{e}.generator"),
                        format!(
                            "\"quarter_disk\" needs model = \"axisymmetric\" (model is \"{}\"); use half_disk otherwise",
                            model.as_str()
                        ),
                    ));
                }
                self.disk(&d.center, d.radius, d.divisions)?;
                grading_ratio(&format!("{e}.grading"), d.grading)?;
                self.element(d.element, &PLANE_ELEMENTS)
            }
        }
    }

    fn element(&self, el: Element, valid: &[Element]) -> Result {
        if valid.contains(&el) {
            Ok(())
        } else {
            let names: Vec<&str> = valid.iter().map(|x| x.as_str()).collect();
            Err(invalid(
                format!("{}.element", self.e),
                format!(
                    "\"{}\" is not available for the {} generator; use {}",
                    el.as_str(),
                    self.g.name(),
                    names.join(" or ")
                ),
            ))
        }
    }

    fn sizes(&self, s: &[f64]) -> Result {
        finite_all(&format!("{}.size", self.e), s)?;
        if s.iter().any(|x| *x <= 0.0) {
            Err(invalid(
                format!("{}.size", self.e),
                format!("every component must be > 0, got {s:?}"),
            ))
        } else {
            Ok(())
        }
    }

    fn divisions(&self, d: &[usize]) -> Result {
        if d.contains(&0) {
            Err(invalid(
                format!("{}.divisions", self.e),
                format!("every component must be >= 1, got {d:?}"),
            ))
        } else {
            Ok(())
        }
    }

    fn grading(&self, gr: &Option<Grading>, valid: &[&str]) -> Result {
        if let Some(gr) = gr {
            if !valid.contains(&gr.towards.as_str()) {
                return Err(invalid(
                    format!("{}.grading.towards", self.e),
                    format!(
                        "unknown side \"{}\"; valid: {}",
                        gr.towards,
                        valid.join(", ")
                    ),
                ));
            }
            grading_ratio(&format!("{}.grading.ratio", self.e), gr.ratio)?;
        }
        Ok(())
    }

    /// Origin, size, divisions and element of a rectangle or a box.
    fn block<const D: usize>(&self, b: &Block<D>, elements: &[Element]) -> Result {
        finite_all(&format!("{}.origin", self.e), &b.origin)?;
        self.sizes(&b.size)?;
        self.divisions(&b.divisions)?;
        self.element(b.element, elements)
    }

    /// Center, radius and divisions of a hemisphere or a quarter disk.
    fn disk(&self, center: &[f64], radius: f64, divisions: usize) -> Result {
        finite_all(&format!("{}.center", self.e), center)?;
        positive(&format!("{}.radius", self.e), radius)?;
        self.divisions(&[divisions])
    }

    fn half_disk(&self, d: &HalfDisk) -> Result {
        let e = self.e;
        finite_all(&format!("{e}.center"), &d.center)?;
        positive(&format!("{e}.radius"), d.radius)?;
        if d.divisions < 4 {
            return Err(invalid(
                format!("{e}.divisions"),
                format!("must be >= 4 (elements along the arc), got {}", d.divisions),
            ));
        }
        non_zero(&format!("{e}.pole"), &d.pole)?;
        grading_ratio(&format!("{e}.grading"), d.grading)?;
        self.element(d.element, &PLANE_ELEMENTS)
    }
}

/// A circle (2D) or a sphere (3D): `(name, its dimension, the other's
/// name)`, its centre and its radius.
fn validate_round(
    e: &str,
    (name, own, other): (&str, usize, &str),
    center: &[f64],
    radius: f64,
    dim: usize,
) -> Result {
    if dim != own {
        return Err(invalid(
            format!("{e}.shape"),
            format!(
                "\"{name}\" is a {own}D shape; with dimension = {dim} use \"{other}\" or \"plane\""
            ),
        ));
    }
    vector(&format!("{e}.center"), center, dim)?;
    positive(&format!("{e}.radius"), radius)
}

/// A direction whose length squared is a normal double, so that it can be
/// made a unit vector ([1e-300, 1e-300, 1e-300] underflows to a zero length
/// and NaN normals).
fn normalisable(entry: &str, v: &[f64]) -> Result {
    let n2: f64 = v.iter().map(|x| x * x).sum();
    if n2.is_normal() {
        Ok(())
    } else {
        Err(invalid(
            entry,
            format!(
                "its length must be between 1e-150 and 1e150 to be normalised (a direction: [0.0, 1.0] will do), got {v:?}"
            ),
        ))
    }
}

pub(super) fn validate_rigid(e: &str, shape: &RigidShape, dim: usize) -> Result {
    match shape {
        RigidShape::Plane { point, normal } => {
            vector(&format!("{e}.point"), point, dim)?;
            vector(&format!("{e}.normal"), normal, dim)?;
            non_zero(&format!("{e}.normal"), normal)?;
            normalisable(&format!("{e}.normal"), normal)?;
        }
        RigidShape::Circle { center, radius } => {
            validate_round(e, ("circle", 2, "sphere"), center, *radius, dim)?;
        }
        RigidShape::Sphere { center, radius } => {
            validate_round(e, ("sphere", 3, "circle"), center, *radius, dim)?;
        }
    }
    Ok(())
}
