//! The box on a structured grid of hexahedra or tetrahedra ([`box_mesh`]) and its
//! faces ([`BoxSide`]).

use super::{axis_spacing, check_ratio, name_boundary};
use crate::{Cell, CellKind, Mesh, MeshError};
use std::collections::BTreeMap;

/// A face of a box, used to say where the smallest elements go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BoxSide {
    Xmin,
    Xmax,
    Ymin,
    Ymax,
    Zmin,
    Zmax,
}

impl BoxSide {
    /// All sides, in the order xmin, xmax, ymin, ymax, zmin, zmax.
    pub const ALL: [BoxSide; 6] = [
        BoxSide::Xmin,
        BoxSide::Xmax,
        BoxSide::Ymin,
        BoxSide::Ymax,
        BoxSide::Zmin,
        BoxSide::Zmax,
    ];

    /// Parses "xmin", "xmax", "ymin", "ymax", "zmin", "zmax".
    pub fn from_name(name: &str) -> Option<BoxSide> {
        BoxSide::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The side's name: "xmin", "xmax", "ymin", "ymax", "zmin" or "zmax".
    pub fn name(self) -> &'static str {
        match self {
            BoxSide::Xmin => "xmin",
            BoxSide::Xmax => "xmax",
            BoxSide::Ymin => "ymin",
            BoxSide::Ymax => "ymax",
            BoxSide::Zmin => "zmin",
            BoxSide::Zmax => "zmax",
        }
    }

    /// The coordinate axis normal to the side (0, 1, 2) and whether the side is
    /// at the upper end of it.
    pub fn axis(self) -> (usize, bool) {
        match self {
            BoxSide::Xmin => (0, false),
            BoxSide::Xmax => (0, true),
            BoxSide::Ymin => (1, false),
            BoxSide::Ymax => (1, true),
            BoxSide::Zmin => (2, false),
            BoxSide::Zmax => (2, true),
        }
    }
}

/// Box `[x0, x0 + sx] x [y0, y0 + sy] x [z0, z0 + sz]` on a structured grid of
/// `nx x ny x nz` hexahedra.
///
/// Node `(i, j, k)` has index `(k (ny + 1) + j) (nx + 1) + i`; the grid lines of
/// the last layer are exactly at `origin + size`. `grading = Some((side, r))`
/// grades the direction normal to `side` geometrically ([`graded_spacing`](super::graded_spacing)),
/// with the smallest elements along `side` and largest / smallest = `r`.
///
/// `kind`: Hex8, the grid's cells `(i, j, k)` in the VTK order (bottom 0-1-2-3
/// counter-clockwise seen from above, 4-7 above them); or Tet4, each hexahedron
/// split in the 6 tetrahedra of the Kuhn (Freudenthal) triangulation around its
/// diagonal from corner `(i, j, k)` to corner `(i+1, j+1, k+1)`: one per order
/// in which the path along the three directions visits them. Every hexahedron
/// is split the same way, so each quadrilateral face is cut along the same
/// diagonal from both sides (conforming). Each tetrahedron's nodes are ordered
/// for a positive volume.
///
/// Surfaces "xmin", "xmax", "ymin", "ymax", "zmin", "zmax": the boundary facets
/// (quadrilaterals, or triangles for Tet4) on each face, each with its cell and
/// its node order from [`CellKind::facets`] (outward right-hand normal).
pub fn box_mesh(
    origin: [f64; 3],
    size: [f64; 3],
    divisions: [usize; 3],
    kind: CellKind,
    grading: Option<(BoxSide, f64)>,
) -> Result<Mesh, MeshError> {
    let [nx, ny, nz] = divisions;
    if nx == 0 || ny == 0 || nz == 0 {
        return Err(MeshError::Invalid(format!(
            "box: divisions must be positive, got [{nx}, {ny}, {nz}]"
        )));
    }
    if !size.iter().all(|s| s.is_finite() && *s > 0.0) {
        return Err(MeshError::Invalid(format!(
            "box: size must be positive, got [{}, {}, {}]",
            size[0], size[1], size[2]
        )));
    }
    if !origin.iter().all(|o| o.is_finite()) {
        return Err(MeshError::Invalid("box: origin is not finite".into()));
    }
    if !matches!(kind, CellKind::Hex8 | CellKind::Tet4) {
        return Err(MeshError::Invalid(format!(
            "box: cells must be hex8 or tet4, got {}",
            kind.name()
        )));
    }
    let grading = match grading {
        Some((side, r)) => {
            check_ratio("box", r)?;
            let (axis, at_max) = side.axis();
            Some((axis, at_max, r))
        }
        None => None,
    };
    let mut mesh = Mesh {
        dim: 3,
        coords: grid_nodes(origin, size, divisions, grading),
        cells: grid_cells(divisions, kind),
        surfaces: BTreeMap::new(),
        regions: Default::default(),
        node_sets: Default::default(),
    };
    let coords = mesh.coords.clone();
    let names = BoxSide::ALL.map(|s| s.name());
    name_boundary(&mut mesh, &names, |nodes| {
        BoxSide::ALL
            .iter()
            .position(|s| {
                let (a, at_max) = s.axis();
                let v = if at_max {
                    origin[a] + size[a]
                } else {
                    origin[a]
                };
                nodes.iter().all(|&n| coords[n][a] == v)
            })
            .expect("a boundary facet of the box lies on one of its faces")
    })?;
    mesh.check()?;
    Ok(mesh)
}

/// The grid's nodes, node `(i, j, k)` at index `(k (ny + 1) + j) (nx + 1) + i`,
/// on the grid lines along each axis of the box at `origin` of `size`
/// ([`axis_spacing`]: graded along the axis `grading` names, uniform along the
/// others), the last line exactly at `origin + size`.
fn grid_nodes(
    origin: [f64; 3],
    size: [f64; 3],
    divisions: [usize; 3],
    grading: Option<(usize, bool, f64)>,
) -> Vec<[f64; 3]> {
    let [nx, ny, nz] = divisions;
    let lines: Vec<Vec<f64>> = (0..3)
        .map(|a| {
            let n = divisions[a];
            axis_spacing(n, a, grading)
                .iter()
                .enumerate()
                .map(|(i, t)| {
                    if i == n {
                        origin[a] + size[a]
                    } else {
                        origin[a] + size[a] * t
                    }
                })
                .collect()
        })
        .collect();
    let mut coords = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for &z in &lines[2] {
        for &y in &lines[1] {
            for &x in &lines[0] {
                coords.push([x, y, z]);
            }
        }
    }
    coords
}

/// The cells of the `nx x ny x nz` grid, hexahedron `(i, j, k)` by hexahedron
/// (i fastest): one Hex8 in the VTK order, or its 6 Tet4 of the Kuhn split
/// ([`kuhn_tetrahedra`]).
fn grid_cells(divisions: [usize; 3], kind: CellKind) -> Vec<Cell> {
    let [nx, ny, nz] = divisions;
    let id = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
    let mut cells = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let v = |a: usize, b: usize, c: usize| id(i + a, j + b, k + c);
                if kind == CellKind::Hex8 {
                    cells.push(Cell {
                        kind,
                        nodes: vec![
                            v(0, 0, 0),
                            v(1, 0, 0),
                            v(1, 1, 0),
                            v(0, 1, 0),
                            v(0, 0, 1),
                            v(1, 0, 1),
                            v(1, 1, 1),
                            v(0, 1, 1),
                        ],
                    });
                } else {
                    cells.extend(kuhn_tetrahedra(v));
                }
            }
        }
    }
    cells
}

/// The 6 Tet4 of the Kuhn split of the hexahedron whose corner at offset
/// `(a, b, c)` (each 0 or 1) is node `corner(a, b, c)`: the path (0,0,0) ->
/// +e_p0 -> +e_p1 -> (1,1,1) for each permutation p; an odd permutation gives a
/// negative volume in path order, so its last two nodes are swapped.
fn kuhn_tetrahedra(corner: impl Fn(usize, usize, usize) -> usize) -> Vec<Cell> {
    let mut cells = Vec::with_capacity(6);
    for (p, odd) in [
        ([0, 1, 2], false),
        ([1, 2, 0], false),
        ([2, 0, 1], false),
        ([1, 0, 2], true),
        ([0, 2, 1], true),
        ([2, 1, 0], true),
    ] {
        let mut o = [0usize; 3];
        let mut path = vec![corner(0, 0, 0)];
        for &axis in &p {
            o[axis] = 1;
            path.push(corner(o[0], o[1], o[2]));
        }
        if odd {
            path.swap(2, 3);
        }
        cells.push(Cell {
            kind: CellKind::Tet4,
            nodes: path,
        });
    }
    cells
}
