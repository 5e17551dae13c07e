//! Meshes of the deformable bodies: nodes, cells, and the named boundary
//! surfaces that loads and contact pairs refer to (SCENE.md, "Mesh generators").
//!
//! Coordinates are stored as `[f64; 3]` whatever the dimension (z = 0 in 2D), so
//! that 2D and 3D share one type. A surface is a list of boundary facets (2-node
//! segments in 2D); each facet remembers the cell it bounds, so outward normals
//! are oriented away from that cell whatever the facet's node order.

pub mod generators;
pub mod partition;

use std::collections::BTreeMap;

/// Kind of a finite element cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// Linear triangle (3 nodes, counter-clockwise).
    Tri3,
    /// Bilinear quadrilateral (4 nodes, counter-clockwise).
    Quad4,
}

impl CellKind {
    pub fn nodes(self) -> usize {
        match self {
            CellKind::Tri3 => 3,
            CellKind::Quad4 => 4,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            CellKind::Tri3 => "tri3",
            CellKind::Quad4 => "quad4",
        }
    }
}

/// One cell: its kind and its node indices (counter-clockwise in 2D).
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub kind: CellKind,
    pub nodes: Vec<usize>,
}

/// A boundary facet: a segment (2D) with the cell it belongs to.
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
}

impl Mesh {
    pub fn n_nodes(&self) -> usize {
        self.coords.len()
    }

    /// Diameter of the bounding box: the body's length scale.
    pub fn size(&self) -> f64 {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.coords {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if self.coords.is_empty() {
            return 0.0;
        }
        (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
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

    /// Surface by name, or an error listing the names that exist.
    pub fn surface(&self, name: &str) -> Result<&Surface, MeshError> {
        self.surfaces
            .get(name)
            .ok_or_else(|| MeshError::UnknownSurface {
                name: name.to_string(),
                known: self.surfaces.keys().cloned().collect::<Vec<_>>().join(", "),
            })
    }

    /// Checks that every cell has a positive area (counter-clockwise nodes).
    pub fn check(&self) -> Result<(), MeshError> {
        for (c, cell) in self.cells.iter().enumerate() {
            if cell.nodes.len() != cell.kind.nodes() {
                return Err(MeshError::Invalid(format!(
                    "cell {c} ({}) has {} nodes",
                    cell.kind.name(),
                    cell.nodes.len()
                )));
            }
            if self.dim == 2 {
                let p: Vec<[f64; 3]> = cell.nodes.iter().map(|&n| self.coords[n]).collect();
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
