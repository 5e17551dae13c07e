//! Structured mesh generators (docs/reference/scene-format.md, "Mesh generators").
//!
//! Every generator names its boundary parts; those names are the surfaces of the
//! body. `grading` is the ratio of the largest to the smallest element size along
//! the graded direction (1 = uniform); sizes vary geometrically.
//!
//! 2D ([`rectangle`], [`half_disk`], [`quarter_disk`]): all cells are
//! counter-clockwise (Quad4, Tri3, or those made second-order by
//! [`to_second_order`](crate::quadratic::to_second_order)). Facets of a surface are oriented along the boundary
//! with the body on their left (the order in which the owning cell lists the two
//! nodes), and `Facet::cell` is the owning cell.
//!
//! 3D ([`box_mesh`], [`hemisphere`], [`hemisphere_of_kind`]): cells have positive volumes (Tet4) or
//! positive Jacobians at their 8 corners (Hex8, VTK order), or are those made
//! second-order (Tet10, Hex20); a surface's facets
//! are faces of their cells with the node order of [`CellKind::facets`](crate::CellKind::facets)
//! (right-hand normal pointing out of the body).

mod box3d;
mod disk;
mod hemisphere;
mod hemisphere_kinds;
mod hemisphere_sector;
mod rectangle;
mod split;
#[cfg(test)]
mod tests;

pub use box3d::{box_mesh, BoxSide};
pub use disk::{half_disk, quarter_disk};
pub use hemisphere::hemisphere;
use hemisphere::pole_frame;
pub use hemisphere_kinds::hemisphere_of_kind;
pub use hemisphere_sector::{quarter_hemisphere, HemisphereSector, QUARTER_SURFACES};
pub use rectangle::{rectangle, RectSide};

use crate::{Facet, Mesh, MeshError, Surface};

/// Panics unless the grading ratio is finite and positive.
fn assert_ratio(ratio: f64) {
    assert!(
        ratio.is_finite() && ratio > 0.0,
        "grading ratio must be finite and positive, got {ratio}"
    );
}

/// `n + 1` increasing parameters `t_0 = 0 < t_1 < ... < t_n = 1` whose
/// increments `h_i = t_{i+1} - t_i` are geometric, `h_i = h_0 q^i`, with
/// `h_{n-1} / h_0 = ratio` (so `q = ratio^(1/(n-1))`): the smallest elements are
/// at 0 when `ratio >= 1`. `ratio = 1` (or `n = 1`) gives a uniform spacing.
/// `n = 0` gives `[0]`.
///
/// # Panics
/// If `ratio` is not finite and positive.
pub fn graded_spacing(n: usize, ratio: f64) -> Vec<f64> {
    assert_ratio(ratio);
    if n == 0 {
        return vec![0.0];
    }
    let q = if n >= 2 {
        ratio.powf(1.0 / (n - 1) as f64)
    } else {
        1.0
    };
    spacing_from_sizes((0..n).map(|i| q.powi(i as i32)).collect())
}

/// `n + 1` increasing parameters in `[0, 1]`, symmetric about 1/2, whose element
/// sizes grow geometrically from the middle (smallest) towards both ends
/// (largest), with largest / smallest = `ratio` (exactly so for odd `n`, and for
/// even `n >= 4`; `n <= 2` is uniform).
///
/// # Panics
/// If `ratio` is not finite and positive.
pub fn symmetric_graded_spacing(n: usize, ratio: f64) -> Vec<f64> {
    assert_ratio(ratio);
    if n == 0 {
        return vec![0.0];
    }
    // size of element i = q^{|i - c|}, c = (n - 1)/2; exponents range from
    // e_min (0 for odd n, 1/2 for even n) to (n - 1)/2.
    let c = (n as f64 - 1.0) / 2.0;
    let e_min = if n % 2 == 1 { 0.0 } else { 0.5 };
    let span = c - e_min;
    let q = if span > 0.0 {
        ratio.powf(1.0 / span)
    } else {
        1.0
    };
    let mut t = spacing_from_sizes(
        (0..n)
            .map(|i| q.powf((i as f64 - c).abs()))
            .collect::<Vec<_>>(),
    );
    // enforce the exact symmetry t_i + t_{n-i} = 1
    for i in 0..=n / 2 {
        let a = 0.5 * (t[i] + 1.0 - t[n - i]);
        t[i] = a;
        t[n - i] = 1.0 - a;
    }
    t
}

/// The `n + 1` parameters in `[0, 1]` of `n` elements of relative sizes `h`
/// (the last exactly 1).
fn spacing_from_sizes(h: Vec<f64>) -> Vec<f64> {
    let total: f64 = h.iter().sum();
    let mut t = Vec::with_capacity(h.len() + 1);
    let mut acc = 0.0;
    t.push(0.0);
    for hi in &h {
        acc += hi;
        t.push(acc / total);
    }
    *t.last_mut().unwrap() = 1.0;
    t
}

/// The `n + 1` parameters in `[0, 1]` of the grid lines along `axis`: graded
/// ([`graded_spacing`], smallest elements at the end 0, or at 1 if `at_max`) when
/// `grading = Some((axis, at_max, ratio))` names this axis, uniform otherwise.
fn axis_spacing(n: usize, axis: usize, grading: Option<(usize, bool, f64)>) -> Vec<f64> {
    match grading {
        Some((a, false, r)) if a == axis => graded_spacing(n, r),
        Some((a, true, r)) if a == axis => {
            graded_spacing(n, r).iter().rev().map(|v| 1.0 - v).collect()
        }
        _ => graded_spacing(n, 1.0),
    }
}

/// An error naming the generator `what` unless the grading ratio `r` is finite
/// and positive.
fn check_ratio(what: &str, r: f64) -> Result<(), MeshError> {
    if r.is_finite() && r > 0.0 {
        Ok(())
    } else {
        Err(MeshError::Invalid(format!(
            "{what}: grading ratio must be finite and positive, got {r}"
        )))
    }
}

/// A half ball: the part of the ball (a disk in 2D) of `radius` about `center`
/// on the side of `pole` (normalised by the generator; an error if zero),
/// `{x : |x − c| ≤ R, (x − c) · pole ≥ 0}`, meshed with `divisions` elements
/// along its curved boundary, graded towards the pole point `c + R pole`
/// (`grading` = largest / smallest element, 1 = uniform): what [`half_disk`]
/// (`D = 2`) and [`hemisphere`] (`D = 3`) mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfBall<const D: usize> {
    pub center: [f64; D],
    pub radius: f64,
    pub divisions: usize,
    pub pole: [f64; D],
    pub grading: f64,
}

impl<const D: usize> HalfBall<D> {
    pub fn new(
        center: [f64; D],
        radius: f64,
        divisions: usize,
        pole: [f64; D],
        grading: f64,
    ) -> HalfBall<D> {
        HalfBall {
            center,
            radius,
            divisions,
            pole,
            grading,
        }
    }
}

/// What the round generators (disks, hemisphere) check of their arguments:
/// the generator's name, the least number of divisions and what they divide.
pub(super) struct Round {
    name: &'static str,
    least: usize,
    along: &'static str,
}

pub(super) const HALF_DISK: Round = Round::new("half_disk", 4, "the arc");
pub(super) const QUARTER_DISK: Round = Round::new("quarter_disk", 2, "the arc");
pub(super) const HEMISPHERE: Round = Round::new("hemisphere", 2, "a quarter meridian");

impl Round {
    const fn new(name: &'static str, least: usize, along: &'static str) -> Round {
        Round { name, least, along }
    }

    /// A finite centre, a positive radius, at least `least` divisions and a
    /// valid grading ratio.
    pub(super) fn check(
        &self,
        center: &[f64],
        radius: f64,
        divisions: usize,
        grading: f64,
    ) -> Result<(), MeshError> {
        let Round { name, least, along } = *self;
        if !(radius.is_finite() && radius > 0.0) {
            return Err(MeshError::Invalid(format!(
                "{name}: radius must be positive, got {radius}"
            )));
        }
        if !center.iter().all(|c| c.is_finite()) {
            return Err(MeshError::Invalid(format!("{name}: center is not finite")));
        }
        if divisions < least {
            return Err(MeshError::Invalid(format!(
                "{name}: divisions (elements along {along}) must be at least {least}, got {divisions}"
            )));
        }
        check_ratio(name, grading)
    }
}

/// Names the boundary of a 3D mesh: every boundary facet
/// ([`Mesh::boundary_facets`]) goes to the surface `names[classify(facet nodes)]`.
fn name_boundary(
    mesh: &mut Mesh,
    names: &[&str],
    classify: impl Fn(&[usize]) -> usize,
) -> Result<(), MeshError> {
    let mut lists: Vec<Vec<Facet>> = vec![Vec::new(); names.len()];
    for f in mesh.boundary_facets() {
        lists[classify(&f.nodes)].push(f);
    }
    for (name, facets) in names.iter().zip(lists) {
        if facets.is_empty() {
            return Err(MeshError::Invalid(format!(
                "internal error: surface \"{name}\" has no facets"
            )));
        }
        mesh.surfaces.insert(name.to_string(), Surface { facets });
    }
    Ok(())
}

/// At each corner k of a Hex8 cell, the three corners joined to it by the edges
/// along the reference axes xi, eta, zeta.
pub const HEX_CORNER_AXES: [[usize; 3]; 8] = [
    [1, 3, 4],
    [0, 2, 5],
    [3, 1, 6],
    [2, 0, 7],
    [5, 7, 0],
    [4, 6, 1],
    [7, 5, 2],
    [6, 4, 3],
];

/// Determinants of the Jacobian of a Hex8 cell's trilinear map at its 8
/// corners (positive for a valid, well-oriented cell).
pub fn hex_corner_jacobians(mesh: &Mesh, cell: usize) -> [f64; 8] {
    let n = &mesh.cells[cell].nodes;
    let x = |k: usize| mesh.coords[n[k]];
    // sign of the reference axes' directions at each corner (from the corner
    // to its neighbour along xi, eta, zeta)
    const SIGN: [f64; 8] = [1.0, -1.0, 1.0, -1.0, -1.0, 1.0, -1.0, 1.0];
    let mut det = [0.0; 8];
    for k in 0..8 {
        let e = HEX_CORNER_AXES[k].map(|m| {
            let (a, b) = (x(k), x(m));
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
        });
        let c = [
            e[1][1] * e[2][2] - e[1][2] * e[2][1],
            e[1][2] * e[2][0] - e[1][0] * e[2][2],
            e[1][0] * e[2][1] - e[1][1] * e[2][0],
        ];
        det[k] = SIGN[k] * (e[0][0] * c[0] + e[0][1] * c[1] + e[0][2] * c[2]);
    }
    det
}
