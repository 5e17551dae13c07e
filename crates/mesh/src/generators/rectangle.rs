//! The rectangle on a structured grid ([`rectangle`]) and its sides ([`RectSide`]).

use super::split::{build_2d, TriangleSplit};
use super::{axis_spacing, check_ratio};
use crate::{CellKind, Mesh, MeshError};

/// A side of a rectangle, used to say where the smallest elements go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RectSide {
    Left,
    Right,
    Bottom,
    Top,
}

impl RectSide {
    /// Parses "left", "right", "bottom", "top".
    pub fn from_name(name: &str) -> Option<RectSide> {
        match name {
            "left" => Some(RectSide::Left),
            "right" => Some(RectSide::Right),
            "bottom" => Some(RectSide::Bottom),
            "top" => Some(RectSide::Top),
            _ => None,
        }
    }

    /// The side's name: "left", "right", "bottom" or "top".
    pub fn name(self) -> &'static str {
        match self {
            RectSide::Left => "left",
            RectSide::Right => "right",
            RectSide::Bottom => "bottom",
            RectSide::Top => "top",
        }
    }
}

/// Rectangle `[x0, x0 + w] x [y0, y0 + h]` with `nx x ny` quadrilaterals on a
/// structured grid (Quad4, or each quad split in two Tri3 along its diagonal
/// from node `(i, j)` to `(i + 1, j + 1)`, the same in every quad
/// (`TriangleSplit::Diagonal`: every node has the same star, no node is set
/// apart, but the mesh is not mirror-symmetric); Quad8 / Tri6: those made
/// second-order by [`to_second_order`](crate::quadratic::to_second_order), the
/// mid-side nodes at the edge midpoints). `grading = Some((side, r))` grades the
/// direction normal to `side` geometrically, with the smallest elements along
/// `side` and largest / smallest = `r`.
///
/// Node `(i, j)` (i along x, j along y) has index `j * (nx + 1) + i` (the
/// mid-side nodes of second-order cells come after them).
/// Surfaces: "left", "right", "bottom", "top".
pub fn rectangle(
    origin: [f64; 2],
    size: [f64; 2],
    divisions: [usize; 2],
    kind: CellKind,
    grading: Option<(RectSide, f64)>,
) -> Result<Mesh, MeshError> {
    let [nx, ny] = divisions;
    if nx == 0 || ny == 0 {
        return Err(MeshError::Invalid(format!(
            "rectangle: divisions must be positive, got [{nx}, {ny}]"
        )));
    }
    if !(size[0].is_finite() && size[1].is_finite() && size[0] > 0.0 && size[1] > 0.0) {
        return Err(MeshError::Invalid(format!(
            "rectangle: size must be positive, got [{}, {}]",
            size[0], size[1]
        )));
    }
    if !(origin[0].is_finite() && origin[1].is_finite()) {
        return Err(MeshError::Invalid("rectangle: origin is not finite".into()));
    }
    let grading = match grading {
        Some((side, r)) => {
            check_ratio("rectangle", r)?;
            let (axis, at_max) = match side {
                RectSide::Left => (0, false),
                RectSide::Right => (0, true),
                RectSide::Bottom => (1, false),
                RectSide::Top => (1, true),
            };
            Some((axis, at_max, r))
        }
        None => None,
    };
    let sx = axis_spacing(nx, 0, grading);
    let sy = axis_spacing(ny, 1, grading);
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut coords = Vec::with_capacity((nx + 1) * (ny + 1));
    for (j, ty) in sy.iter().enumerate() {
        for (i, tx) in sx.iter().enumerate() {
            // exact end coordinates on the boundary lines
            let x = if i == nx {
                origin[0] + size[0]
            } else {
                origin[0] + size[0] * tx
            };
            let y = if j == ny {
                origin[1] + size[1]
            } else {
                origin[1] + size[1] * ty
            };
            coords.push([x, y, 0.0]);
        }
    }
    let mut quads = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let q = |i: usize, j: usize| j * nx + i;
    let bottom = (0..nx).map(|i| (id(i, 0), id(i + 1, 0), q(i, 0))).collect();
    let right = (0..ny)
        .map(|j| (id(nx, j), id(nx, j + 1), q(nx - 1, j)))
        .collect();
    let top = (0..nx)
        .rev()
        .map(|i| (id(i + 1, ny), id(i, ny), q(i, ny - 1)))
        .collect();
    let left = (0..ny)
        .rev()
        .map(|j| (id(0, j + 1), id(0, j), q(0, j)))
        .collect();
    build_2d(
        coords,
        &quads,
        vec![
            ("bottom", bottom),
            ("right", right),
            ("top", top),
            ("left", left),
        ],
        kind,
        TriangleSplit::Diagonal,
    )
}
