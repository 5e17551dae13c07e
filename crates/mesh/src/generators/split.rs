//! How the 2D generators turn their quadrilaterals into cells: Quad4, or Tri3
//! cut from them ([`TriangleSplit`]); Quad8 / Tri6 are those made second-order.
//!
//! Cutting every quadrilateral of a structured grid in two along one of its
//! diagonals cannot give a mesh that is both the mirror image of itself about
//! a grid line and alike at every node along it: the two quadrilaterals on
//! either side of the line are then cut along mirrored diagonals, so a node on
//! the line is in 2 or 4 of their triangles where its neighbours are in 3
//! (alternating the diagonals, the "criss-cross" pattern, makes every other
//! node so). On the axis of a disk that node is the pole: its contact force
//! came out 8-14 % high (Hertz p0 as much too, docs/theory/validation-cases.md §1-2), and
//! criss-cross made the pressure zig-zag by as much. The disks are therefore
//! cut [`TriangleSplit::Crossed`]: four triangles about each quadrilateral's
//! centre, which is the mirror image of itself with its quadrilateral, so that
//! every node of the arc, the pole included, has the same kind of star.

use crate::quadratic::to_second_order;
use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use std::collections::BTreeMap;

/// Boundary edges `(node a, node b, owning quad)`.
pub(super) type EdgeList = Vec<(usize, usize, usize)>;

/// How a counter-clockwise quadrilateral `[a, b, c, d]` is cut into
/// counter-clockwise Tri3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum TriangleSplit {
    /// Two triangles `[a, b, c]`, `[a, c, d]` along the diagonal `a`–`c`, the
    /// same in every quadrilateral: every node of a structured grid has the
    /// same star, but the mesh is not mirror-symmetric. Same nodes as Quad4.
    Diagonal,
    /// Four triangles `[a, b, o]`, `[b, c, o]`, `[c, d, o]`, `[d, a, o]` about
    /// a node `o` at the mean of the corners, added after the quadrilaterals'
    /// nodes (in the quadrilaterals' order, so those keep their numbers): the
    /// mesh is as symmetric as its quadrilaterals.
    Crossed,
}

impl TriangleSplit {
    /// Triangles made from one quadrilateral.
    fn per_quad(self) -> usize {
        match self {
            TriangleSplit::Diagonal => 2,
            TriangleSplit::Crossed => 4,
        }
    }
}

/// Builds a 2D mesh from counter-clockwise quadrilaterals (as Quad4, or cut
/// into Tri3 by `split`; Quad8 and Tri6 are those made second-order by
/// [`to_second_order`], mid-side nodes at the edge midpoints) and named
/// boundary edges `(a, b, quad)`. A 3D kind is an error.
pub(super) fn build_2d(
    coords: Vec<[f64; 3]>,
    quads: &[[usize; 4]],
    edges: Vec<(&str, EdgeList)>,
    kind: CellKind,
    split: TriangleSplit,
) -> Result<Mesh, MeshError> {
    let first_order = match kind {
        CellKind::Quad4 | CellKind::Tri3 => kind,
        CellKind::Quad8 => CellKind::Quad4,
        CellKind::Tri6 => CellKind::Tri3,
        CellKind::Tet4 | CellKind::Hex8 => {
            return Err(MeshError::Invalid(format!(
                "a 2D generator cannot make {} cells (quad4, tri3, quad8, tri6)",
                kind.name()
            )))
        }
    };
    let mesh = build_2d_first_order(coords, quads, edges, first_order, split);
    mesh.check()?;
    if kind.order() == 2 {
        to_second_order(&mesh)
    } else {
        Ok(mesh)
    }
}

/// [`build_2d`] for Quad4 or Tri3.
fn build_2d_first_order(
    mut coords: Vec<[f64; 3]>,
    quads: &[[usize; 4]],
    edges: Vec<(&str, EdgeList)>,
    kind: CellKind,
    split: TriangleSplit,
) -> Mesh {
    let per_quad = match kind {
        CellKind::Quad4 => 1,
        CellKind::Tri3 => split.per_quad(),
        other => unreachable!("build_2d_first_order: {}", other.name()),
    };
    let mut cells = Vec::with_capacity(per_quad * quads.len());
    for q in quads {
        let nodes: Vec<Vec<usize>> = match (kind, split) {
            (CellKind::Quad4, _) => vec![q.to_vec()],
            (_, TriangleSplit::Diagonal) => vec![vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]],
            (_, TriangleSplit::Crossed) => {
                let o = coords.len();
                coords.push(quad_centre(&coords, q));
                (0..4).map(|i| vec![q[i], q[(i + 1) % 4], o]).collect()
            }
        };
        cells.extend(nodes.into_iter().map(|nodes| Cell { kind, nodes }));
    }
    let mut surfaces = BTreeMap::new();
    for (name, list) in edges {
        let facets = list
            .into_iter()
            .map(|(a, b, q)| edge_facet(&cells, q * per_quad..(q + 1) * per_quad, a, b))
            .collect();
        surfaces.insert(name.to_string(), Surface { facets });
    }
    Mesh {
        dim: 2,
        coords,
        cells,
        surfaces,
        regions: Default::default(),
        node_sets: Default::default(),
    }
}

/// The mean of a quadrilateral's corners (the centre of its bilinear map).
fn quad_centre(coords: &[[f64; 3]], q: &[usize; 4]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &n in q {
        for (ck, xk) in c.iter_mut().zip(coords[n]) {
            *ck += 0.25 * xk;
        }
    }
    c
}

/// The facet of the boundary edge `(a, b)`: the cell among `candidates` (those
/// made from the edge's quadrilateral) holding both nodes, with `(a, b)` in
/// that cell's counter-clockwise order.
fn edge_facet(cells: &[Cell], candidates: std::ops::Range<usize>, a: usize, b: usize) -> Facet {
    candidates
        .into_iter()
        .find_map(|c| {
            let n = &cells[c].nodes;
            let m = n.len();
            (0..m).find_map(|i| {
                let (x, y) = (n[i], n[(i + 1) % m]);
                ((x, y) == (a, b) || (x, y) == (b, a)).then(|| Facet {
                    nodes: vec![x, y],
                    cell: c,
                })
            })
        })
        .expect("boundary edge is an edge of its quad")
}
