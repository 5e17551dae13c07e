//! Meshes of the deformable bodies: nodes, cells, and the named boundary
//! surfaces that loads and contact pairs refer to (docs/reference/scene-format.md, "Mesh generators").
//!
//! Coordinates are stored as `[f64; 3]` whatever the dimension (z = 0 in 2D), so
//! that 2D and 3D share one type. A surface is a list of boundary facets (2-node
//! segments in 2D); each facet remembers the cell it bounds, so outward normals
//! are oriented away from that cell whatever the facet's node order.
//!
//! The mesh crate owns geometry and topology (cells, surfaces, generators, Gmsh
//! files, METIS parts); it must not know elasticity, contact or the scene
//! format.

pub mod generators;
pub mod gmsh;
pub mod nested_dissection;
pub mod partition;
pub mod quadratic;
pub mod quadratic3d;
pub mod vec3;

use std::collections::BTreeMap;

/// Kind of a finite element cell. Node orders follow Gmsh and VTK: corners
/// first (counter-clockwise in 2D; for Tet4 a positive volume
/// `(x1−x0)·((x2−x0)×(x3−x0)) > 0`; for Hex8 the bottom face 0-1-2-3
/// counter-clockwise seen from the top face 4-5-6-7, node 4 above node 0),
/// then the mid-side nodes of second-order cells, edge by edge in the order of
/// [`CellKind::facets`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// Linear triangle (3 nodes, counter-clockwise).
    Tri3,
    /// Bilinear quadrilateral (4 nodes, counter-clockwise).
    Quad4,
    /// Quadratic triangle: 3 corners, then the mid-sides of 0-1, 1-2, 2-0.
    Tri6,
    /// Serendipity quadrilateral: 4 corners, then the mid-sides of 0-1, 1-2,
    /// 2-3, 3-0.
    Quad8,
    /// Linear tetrahedron (4 nodes, positive volume).
    Tet4,
    /// Trilinear hexahedron (8 nodes).
    Hex8,
    /// Quadratic tetrahedron: 4 corners, then the mid-sides of the edges
    /// 0-1, 1-2, 2-0, 0-3, 1-3, 2-3 (the VTK order; Gmsh swaps the last two).
    Tet10,
    /// Serendipity hexahedron: 8 corners, then the mid-sides of the edges
    /// 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7, 7-4, 0-4, 1-5, 2-6, 3-7 (the VTK
    /// order; Gmsh numbers them differently).
    Hex20,
}

/// The corner pairs of the mid-side nodes of a Tet10, in node order (node
/// `4 + e` is the middle of edge `e`).
pub const TET10_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// The corner pairs of the mid-side nodes of a Hex20, in node order (node
/// `8 + e` is the middle of edge `e`).
pub const HEX20_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// The number of corners of a facet of `len` nodes in a `dim`-dimensional
/// mesh: 2 in 2D; in 3D 3 for a triangle (Tri3, Tri6) and 4 for a
/// quadrilateral (Quad4, Quad8).
pub fn facet_corners(dim: usize, len: usize) -> usize {
    match (dim, len) {
        (2, _) => 2,
        (_, 3 | 6) => 3,
        _ => 4,
    }
}

/// Reference coordinates of the corners of a Hex8 cell, in node order
/// (the cube [−1, 1]³).
pub const HEX8_REFERENCE_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

impl CellKind {
    /// Number of nodes of the cell.
    pub fn nodes(self) -> usize {
        match self {
            CellKind::Tri3 => 3,
            CellKind::Quad4 => 4,
            CellKind::Tri6 => 6,
            CellKind::Quad8 => 8,
            CellKind::Tet4 => 4,
            CellKind::Hex8 => 8,
            CellKind::Tet10 => 10,
            CellKind::Hex20 => 20,
        }
    }

    /// Number of corner nodes (the first nodes of the cell).
    pub fn corners(self) -> usize {
        match self {
            CellKind::Tri3 | CellKind::Tri6 => 3,
            CellKind::Quad4 | CellKind::Quad8 | CellKind::Tet4 | CellKind::Tet10 => 4,
            CellKind::Hex8 | CellKind::Hex20 => 8,
        }
    }

    /// Space dimension of the cell.
    pub fn dim(self) -> usize {
        match self {
            CellKind::Tet4 | CellKind::Hex8 | CellKind::Tet10 | CellKind::Hex20 => 3,
            _ => 2,
        }
    }

    /// Polynomial order of the cell (1 or 2).
    pub fn order(self) -> usize {
        match self {
            CellKind::Tri6 | CellKind::Quad8 | CellKind::Tet10 | CellKind::Hex20 => 2,
            _ => 1,
        }
    }

    /// The scene-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            CellKind::Tri3 => "tri3",
            CellKind::Quad4 => "quad4",
            CellKind::Tri6 => "tri6",
            CellKind::Quad8 => "quad8",
            CellKind::Tet4 => "tet4",
            CellKind::Hex8 => "hex8",
            CellKind::Tet10 => "tet10",
            CellKind::Hex20 => "hex20",
        }
    }

    /// Local node indices of each facet (boundary part of dimension d−1):
    /// edges in 2D as `[corner, corner]` or, for second-order cells,
    /// `[corner, corner, mid-side]`; faces in 3D, ordered so that their
    /// right-hand normal points out of a well-oriented cell.
    pub fn facets(self) -> &'static [&'static [usize]] {
        match self {
            CellKind::Tri3 => &[&[0, 1], &[1, 2], &[2, 0]],
            CellKind::Quad4 => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
            CellKind::Tri6 => &[&[0, 1, 3], &[1, 2, 4], &[2, 0, 5]],
            CellKind::Quad8 => &[&[0, 1, 4], &[1, 2, 5], &[2, 3, 6], &[3, 0, 7]],
            CellKind::Tet4 => &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[0, 3, 2]],
            CellKind::Hex8 => &[
                &[0, 3, 2, 1],
                &[4, 5, 6, 7],
                &[0, 1, 5, 4],
                &[1, 2, 6, 5],
                &[2, 3, 7, 6],
                &[3, 0, 4, 7],
            ],
            CellKind::Tet10 => &[
                &[0, 2, 1, 6, 5, 4],
                &[0, 1, 3, 4, 8, 7],
                &[1, 2, 3, 5, 9, 8],
                &[0, 3, 2, 7, 9, 6],
            ],
            CellKind::Hex20 => &[
                &[0, 3, 2, 1, 11, 10, 9, 8],
                &[4, 5, 6, 7, 12, 13, 14, 15],
                &[0, 1, 5, 4, 8, 17, 12, 16],
                &[1, 2, 6, 5, 9, 18, 13, 17],
                &[2, 3, 7, 6, 10, 19, 14, 18],
                &[3, 0, 4, 7, 11, 16, 15, 19],
            ],
        }
    }

    /// The corner pairs of the mid-side nodes of a second-order 3D kind
    /// (Tet10, Hex20), in node order; empty for the other kinds.
    pub fn edges(self) -> &'static [[usize; 2]] {
        match self {
            CellKind::Tet10 => &TET10_EDGES,
            CellKind::Hex20 => &HEX20_EDGES,
            _ => &[],
        }
    }
}

/// One cell: its kind and its node indices (counter-clockwise in 2D).
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub kind: CellKind,
    pub nodes: Vec<usize>,
}

impl Cell {
    /// Checks that cell `c` has as many nodes as its kind: the message
    /// naming it otherwise.
    pub fn check_node_count(&self, c: usize) -> Result<(), String> {
        if self.nodes.len() != self.kind.nodes() {
            return Err(format!(
                "cell {c} ({}) has {} nodes",
                self.kind.name(),
                self.nodes.len()
            ));
        }
        Ok(())
    }
}

/// A boundary facet with the cell it belongs to: a segment in 2D (2 nodes, or
/// 3 for a second-order edge: `[corner, corner, mid-side]`), a triangle or a
/// quadrilateral in 3D. Its node order follows [`CellKind::facets`].
#[derive(Debug, Clone, PartialEq)]
pub struct Facet {
    pub nodes: Vec<usize>,
    pub cell: usize,
}

/// A named part of the boundary.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Surface {
    pub facets: Vec<Facet>,
}

impl Surface {
    /// Sorted, deduplicated node indices of the surface.
    pub fn nodes(&self) -> Vec<usize> {
        let mut n: Vec<usize> = self
            .facets
            .iter()
            .flat_map(|f| f.nodes.iter().copied())
            .collect();
        n.sort_unstable();
        n.dedup();
        n
    }
}

/// A mesh of one body.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Spatial dimension (2 or 3).
    pub dim: usize,
    pub coords: Vec<[f64; 3]>,
    pub cells: Vec<Cell>,
    pub surfaces: BTreeMap<String, Surface>,
    /// Named groups of cells (Gmsh physical groups of dimension d); empty for
    /// generated meshes.
    pub regions: BTreeMap<String, Vec<usize>>,
    /// Named sets of nodes (Gmsh physical groups of points, and of curves in
    /// 3D: dimension below d − 1), sorted; empty for generated meshes.
    pub node_sets: BTreeMap<String, Vec<usize>>,
}

/// The corners (lo, hi) of the smallest box holding `points` (lo = +∞,
/// hi = −∞ where there are none).
pub fn bounding_box<'a>(points: impl IntoIterator<Item = &'a [f64; 3]>) -> ([f64; 3], [f64; 3]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

impl Mesh {
    pub fn n_nodes(&self) -> usize {
        self.coords.len()
    }

    /// Diameter of the bounding box: the body's length scale.
    pub fn size(&self) -> f64 {
        if self.coords.is_empty() {
            return 0.0;
        }
        let (lo, hi) = bounding_box(&self.coords);
        (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
    }

    /// Pairs of distinct nodes at the same place (within 1e-9 of the mesh
    /// size), each pair once, the smaller node first, in order: the cells
    /// on either side of them are not joined (a Gmsh mesh of parts that
    /// were not made coherent).
    pub fn coincident_nodes(&self) -> Vec<(usize, usize)> {
        let tol = 1e-9 * self.size();
        let mut order: Vec<usize> = (0..self.coords.len()).collect();
        order.sort_by(|&a, &b| self.coords[a][0].total_cmp(&self.coords[b][0]));
        let mut pairs = Vec::new();
        for (i, &a) in order.iter().enumerate() {
            for &b in &order[i + 1..] {
                let (pa, pb) = (self.coords[a], self.coords[b]);
                if pb[0] - pa[0] > tol {
                    break;
                }
                if (0..3).all(|k| (pa[k] - pb[k]).abs() <= tol) {
                    pairs.push((a.min(b), a.max(b)));
                }
            }
        }
        pairs.sort_unstable();
        pairs
    }

    /// Centroid of a cell.
    pub fn cell_centroid(&self, c: usize) -> [f64; 3] {
        let cell = &self.cells[c];
        let mut x = [0.0; 3];
        for &n in &cell.nodes {
            for (xk, ck) in x.iter_mut().zip(self.coords[n]) {
                *xk += ck;
            }
        }
        let m = cell.nodes.len() as f64;
        [x[0] / m, x[1] / m, x[2] / m]
    }

    /// Outward unit normal and length of a 2D boundary facet (segment), oriented
    /// away from the centroid of the cell it bounds.
    pub fn facet_normal_2d(&self, f: &Facet) -> ([f64; 2], f64) {
        let a = self.coords[f.nodes[0]];
        let b = self.coords[f.nodes[1]];
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dy * dy).sqrt();
        let mut n = [dy / len, -dx / len];
        let c = self.cell_centroid(f.cell);
        let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        if n[0] * (mid[0] - c[0]) + n[1] * (mid[1] - c[1]) < 0.0 {
            n = [-n[0], -n[1]];
        }
        (n, len)
    }

    /// Outward unit normal and measure (length in 2D, area in 3D) of a
    /// boundary facet, oriented away from the centroid of the cell it bounds.
    /// Second-order edges are taken straight (their corners define them); a
    /// quadrilateral face's normal and area come from its diagonals,
    /// `½ (x2 − x0) × (x3 − x1)` (exact for a planar face).
    pub fn facet_normal(&self, f: &Facet) -> ([f64; 3], f64) {
        let p = |k: usize| self.coords[f.nodes[k]];
        let area_vec = if self.dim == 2 {
            let (a, b) = (p(0), p(1));
            [b[1] - a[1], -(b[0] - a[0]), 0.0]
        } else if facet_corners(3, f.nodes.len()) == 3 {
            let (u, v) = (vec3::sub(p(1), p(0)), vec3::sub(p(2), p(0)));
            let c = vec3::cross(u, v);
            [0.5 * c[0], 0.5 * c[1], 0.5 * c[2]]
        } else {
            let (u, v) = (vec3::sub(p(2), p(0)), vec3::sub(p(3), p(1)));
            let c = vec3::cross(u, v);
            [0.5 * c[0], 0.5 * c[1], 0.5 * c[2]]
        };
        let len = (area_vec[0].powi(2) + area_vec[1].powi(2) + area_vec[2].powi(2)).sqrt();
        let mut n = if len > 0.0 {
            [area_vec[0] / len, area_vec[1] / len, area_vec[2] / len]
        } else {
            [0.0; 3]
        };
        let corners = facet_corners(self.dim, f.nodes.len());
        let mut mid = [0.0; 3];
        for k in 0..corners {
            for (m, x) in mid.iter_mut().zip(p(k)) {
                *m += x / corners as f64;
            }
        }
        let c = self.cell_centroid(f.cell);
        let out = vec3::sub(mid, c);
        if n[0] * out[0] + n[1] * out[1] + n[2] * out[2] < 0.0 {
            n = [-n[0], -n[1], -n[2]];
        }
        (n, len)
    }

    /// Every facet of every cell that no other cell shares: the boundary of
    /// the mesh, in cell order. Facets are matched by their sorted corner
    /// nodes.
    pub fn boundary_facets(&self) -> Vec<Facet> {
        let mut count: std::collections::HashMap<Vec<usize>, usize> = Default::default();
        let key = |cell: &Cell, local: &[usize]| {
            let corners = facet_corners(cell.kind.dim(), local.len());
            let mut k: Vec<usize> = local[..corners].iter().map(|&i| cell.nodes[i]).collect();
            k.sort_unstable();
            k
        };
        for cell in &self.cells {
            for local in cell.kind.facets() {
                *count.entry(key(cell, local)).or_insert(0) += 1;
            }
        }
        let mut out = Vec::new();
        for (c, cell) in self.cells.iter().enumerate() {
            for local in cell.kind.facets() {
                if count[&key(cell, local)] == 1 {
                    out.push(Facet {
                        nodes: local.iter().map(|&i| cell.nodes[i]).collect(),
                        cell: c,
                    });
                }
            }
        }
        out
    }

    /// The connected parts of the mesh, two cells being connected when they
    /// share a node: the part of every node (numbered 0.. in order of their
    /// lowest node; a node of no cell is a part of its own) and their count.
    pub fn node_components(&self) -> (Vec<usize>, usize) {
        let n = self.n_nodes();
        // Union–find over the nodes, each cell joining its nodes.
        let mut parent: Vec<usize> = (0..n).collect();
        fn root(parent: &mut [usize], mut v: usize) -> usize {
            while parent[v] != v {
                parent[v] = parent[parent[v]];
                v = parent[v];
            }
            v
        }
        for cell in &self.cells {
            if let Some((&first, rest)) = cell.nodes.split_first() {
                for &v in rest {
                    let (a, b) = (root(&mut parent, first), root(&mut parent, v));
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        let mut part_of_root = vec![usize::MAX; n];
        let mut part = vec![0; n];
        let mut count = 0;
        for (v, p) in part.iter_mut().enumerate() {
            let r = root(&mut parent, v);
            if part_of_root[r] == usize::MAX {
                part_of_root[r] = count;
                count += 1;
            }
            *p = part_of_root[r];
        }
        (part, count)
    }

    /// Index of the node nearest to `p`, with its distance.
    pub fn nearest_node(&self, p: [f64; 3]) -> Option<(usize, f64)> {
        self.coords
            .iter()
            .enumerate()
            .map(|(i, x)| {
                let d =
                    ((x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2) + (x[2] - p[2]).powi(2)).sqrt();
                (i, d)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Surface by name, or an error listing the names that exist (and
    /// saying so when the name is a node set: a physical group of points or
    /// curves, or a physical surface inside the body).
    pub fn surface(&self, name: &str) -> Result<&Surface, MeshError> {
        let known = || self.surfaces.keys().cloned().collect::<Vec<_>>().join(", ");
        match self.surfaces.get(name) {
            Some(s) => Ok(s),
            None if self.node_sets.contains_key(name) => Err(MeshError::Invalid(format!(
                "\"{name}\" is a set of nodes of this body (a physical group of points or \
                 curves, or a physical surface inside the body, between its cells), not a \
                 surface on its boundary; its surfaces: {}",
                known()
            ))),
            None => Err(MeshError::UnknownSurface {
                name: name.to_string(),
                known: known(),
            }),
        }
    }

    /// Checks that every cell has a positive area (counter-clockwise nodes).
    pub fn check(&self) -> Result<(), MeshError> {
        for (c, cell) in self.cells.iter().enumerate() {
            cell.check_node_count(c).map_err(MeshError::Invalid)?;
            if cell.kind.dim() != self.dim {
                return Err(MeshError::Invalid(format!(
                    "cell {c} is a {} cell in a {}D mesh",
                    cell.kind.name(),
                    self.dim
                )));
            }
            if matches!(cell.kind, CellKind::Tet4 | CellKind::Tet10) {
                let p: Vec<[f64; 3]> = cell.nodes.iter().map(|&n| self.coords[n]).collect();
                let c3 = vec3::cross(vec3::sub(p[2], p[0]), vec3::sub(p[3], p[0]));
                let v = vec3::sub(p[1], p[0]);
                let vol = (v[0] * c3[0] + v[1] * c3[1] + v[2] * c3[2]) / 6.0;
                if vol <= 0.0 || vol.is_nan() {
                    return Err(MeshError::Invalid(format!(
                        "cell {c} ({}) has a non-positive volume {vol:e}",
                        cell.kind.name()
                    )));
                }
            }
            if self.dim == 2 {
                let corners = cell.kind.corners();
                let p: Vec<[f64; 3]> = cell.nodes[..corners]
                    .iter()
                    .map(|&n| self.coords[n])
                    .collect();
                let m = p.len();
                let area: f64 = (0..m)
                    .map(|i| {
                        let j = (i + 1) % m;
                        p[i][0] * p[j][1] - p[j][0] * p[i][1]
                    })
                    .sum::<f64>()
                    / 2.0;
                if area <= 0.0 {
                    return Err(MeshError::Invalid(format!(
                        "cell {c} has a non-positive area {area:e}"
                    )));
                }
            }
        }
        Ok(())
    }
}

#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("no surface named \"{name}\" (surfaces of this body: {known})")]
    UnknownSurface { name: String, known: String },
    #[error("{0}")]
    Invalid(String),
}

#[cfg(test)]
mod coincident_tests {
    use super::*;

    #[test]
    fn coincident_nodes_are_found_once_within_a_relative_tolerance() {
        let mut mesh = Mesh {
            dim: 2,
            coords: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [1.0 + 1e-12, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0 - 1e-12, 0.0],
            ],
            cells: vec![],
            surfaces: BTreeMap::new(),
            regions: BTreeMap::new(),
            node_sets: BTreeMap::new(),
        };
        assert_eq!(mesh.coincident_nodes(), vec![(2, 3), (2, 5), (3, 5)]);
        mesh.coords[3][0] = 1.0 + 1e-6;
        mesh.coords[5][1] = 1.0 - 1e-6;
        assert!(mesh.coincident_nodes().is_empty());
    }
}
