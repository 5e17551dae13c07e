//! Second-order meshes from first-order ones.
//!
//! [`to_second_order`] turns a 2D mesh of Tri3 / Quad4 cells into Tri6 / Quad8
//! cells: every edge gets one mid-side node at its midpoint, shared by the cells
//! around it, and every surface facet `[a, b]` becomes `[a, b, mid-side]`.

use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use std::collections::HashMap;

/// The node at the middle of the edge `a`-`b`, shared by the cells around the
/// edge: found in `mids` (keyed by the sorted pair), or pushed onto `coords`.
pub fn mid_node(
    coords: &mut Vec<[f64; 3]>,
    mids: &mut HashMap<(usize, usize), usize>,
    a: usize,
    b: usize,
) -> usize {
    *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
        let (p, q) = (coords[a], coords[b]);
        coords.push([
            0.5 * (p[0] + q[0]),
            0.5 * (p[1] + q[1]),
            0.5 * (p[2] + q[2]),
        ]);
        coords.len() - 1
    })
}

/// The second-order kind of a first-order 2D kind: Tri3 → Tri6, Quad4 → Quad8.
fn second_order_kind(kind: CellKind) -> Option<CellKind> {
    match kind {
        CellKind::Tri3 => Some(CellKind::Tri6),
        CellKind::Quad4 => Some(CellKind::Quad8),
        _ => None,
    }
}

/// An error `"{what}, this mesh is {d}D"` unless `mesh` is of dimension `dim`.
pub(crate) fn of_dimension(mesh: &Mesh, dim: usize, what: &str) -> Result<(), MeshError> {
    if mesh.dim == dim {
        Ok(())
    } else {
        Err(MeshError::Invalid(format!(
            "{what}, this mesh is {}D",
            mesh.dim
        )))
    }
}

/// The same mesh with Tri3 cells turned into Tri6 and Quad4 cells into Quad8
/// (2D meshes only).
///
/// Every edge of the mesh (a pair of consecutive corners of a cell) gets one new
/// node at its midpoint, shared by the cells around that edge; the new nodes come
/// after the existing ones, numbered in the order the edges are first met (cell
/// by cell, edge by edge in the order of [`CellKind::facets`]). A cell keeps its
/// corners and appends the mid-side nodes of its edges in that order, which is
/// the Gmsh/VTK order of Tri6 and Quad8. Cell indices do not change, so surface
/// facets keep their cell; a facet `[a, b]` becomes `[a, b, m]` with `m` the
/// mid-side node of the edge a-b. Regions are kept.
///
/// Errors: a 3D mesh, a cell that is not Tri3 or Quad4 (including cells that are
/// already second-order), or a surface facet that is not a 2-node edge of its cell.
pub fn to_second_order(mesh: &Mesh) -> Result<Mesh, MeshError> {
    of_dimension(
        mesh,
        2,
        "to_second_order: only 2D meshes (Tri3, Quad4) can be made second-order",
    )?;
    let mut coords = mesh.coords.clone();
    let key = |a: usize, b: usize| (a.min(b), a.max(b));
    let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
    let mut cells = Vec::with_capacity(mesh.cells.len());
    for (c, cell) in mesh.cells.iter().enumerate() {
        let kind = second_order_kind(cell.kind).ok_or_else(|| {
            MeshError::Invalid(format!(
                "to_second_order: cell {c} is a {} cell (expected tri3 or quad4)",
                cell.kind.name()
            ))
        })?;
        cell.check_node_count(c)
            .map_err(|m| MeshError::Invalid(format!("to_second_order: {m}")))?;
        let mut nodes = cell.nodes.clone();
        for local in cell.kind.facets() {
            let (a, b) = (cell.nodes[local[0]], cell.nodes[local[1]]);
            nodes.push(mid_node(&mut coords, &mut mid, a, b));
        }
        cells.push(Cell { kind, nodes });
    }
    let mut surfaces = std::collections::BTreeMap::new();
    for (name, s) in &mesh.surfaces {
        let mut facets = Vec::with_capacity(s.facets.len());
        for f in &s.facets {
            let corners = &mesh.cells.get(f.cell).map(|c| &c.nodes);
            let ok = f.nodes.len() == 2
                && corners.is_some_and(|n| n.contains(&f.nodes[0]) && n.contains(&f.nodes[1]));
            let m = if ok {
                mid.get(&key(f.nodes[0], f.nodes[1]))
            } else {
                None
            };
            let m = *m.ok_or_else(|| {
                MeshError::Invalid(format!(
                    "to_second_order: a facet {:?} of surface \"{name}\" is not an edge of its cell {}",
                    f.nodes, f.cell
                ))
            })?;
            facets.push(Facet {
                nodes: vec![f.nodes[0], f.nodes[1], m],
                cell: f.cell,
            });
        }
        surfaces.insert(name.clone(), Surface { facets });
    }
    Ok(Mesh {
        dim: 2,
        coords,
        cells,
        surfaces,
        regions: mesh.regions.clone(),
        node_sets: mesh.node_sets.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{half_disk, rectangle, HalfBall};

    fn mid_uses(mesh: &Mesh, first_mid: usize) -> HashMap<usize, usize> {
        let mut uses = HashMap::new();
        for cell in &mesh.cells {
            for &n in &cell.nodes[cell.kind.corners()..] {
                assert!(n >= first_mid, "mid-side nodes are the new nodes");
                *uses.entry(n).or_insert(0) += 1;
            }
        }
        uses
    }

    /// A rectangle of `size` from the origin in `divisions` cells of `kind`,
    /// and that mesh made second-order (checked).
    fn grid_to_second_order(size: [f64; 2], divisions: [usize; 2], kind: CellKind) -> (Mesh, Mesh) {
        let first = rectangle([0.0, 0.0], size, divisions, kind, None).unwrap();
        let second = to_second_order(&first).unwrap();
        second.check().unwrap();
        (first, second)
    }

    #[test]
    fn quad_grid_to_quad8() {
        let (nx, ny) = (5, 3);
        let (q4, m) = grid_to_second_order([2.0, 1.0], [nx, ny], CellKind::Quad4);
        assert_eq!(
            m.n_nodes(),
            (nx + 1) * (ny + 1) + nx * (ny + 1) + ny * (nx + 1)
        );
        assert_eq!(m.cells.len(), nx * ny);
        assert!(m.cells.iter().all(|c| c.kind == CellKind::Quad8));
        // corners unchanged
        for (a, b) in q4.cells.iter().zip(&m.cells) {
            assert_eq!(a.nodes[..], b.nodes[..4]);
        }
        // interior edges' mid-side nodes are shared by two cells, boundary ones by one
        let uses = mid_uses(&m, q4.n_nodes());
        assert_eq!(uses.len(), nx * (ny + 1) + ny * (nx + 1));
        assert_eq!(uses.values().filter(|&&u| u == 1).count(), 2 * (nx + ny));
        assert!(uses.values().all(|&u| u == 1 || u == 2));
        // mid-side nodes at the midpoints of their edges
        for cell in &m.cells {
            for (e, local) in cell.kind.facets().iter().enumerate() {
                let (a, b, c) = (
                    m.coords[cell.nodes[local[0]]],
                    m.coords[cell.nodes[local[1]]],
                    m.coords[cell.nodes[local[2]]],
                );
                assert_eq!(local[2], 4 + e);
                for k in 0..3 {
                    assert!((c[k] - 0.5 * (a[k] + b[k])).abs() < 1e-15);
                }
            }
        }
        // surfaces: 3-node facets [corner, corner, mid], boundary facets of the new mesh
        let boundary = m.boundary_facets();
        let mut total = 0;
        for (name, s) in &m.surfaces {
            let old = q4.surface(name).unwrap();
            assert_eq!(s.facets.len(), old.facets.len());
            for (f, g) in s.facets.iter().zip(&old.facets) {
                assert_eq!(f.nodes.len(), 3);
                assert_eq!(f.nodes[..2], g.nodes[..]);
                assert_eq!(f.cell, g.cell);
                assert_eq!(uses[&f.nodes[2]], 1);
                assert!(
                    boundary.contains(f),
                    "{name}: {f:?} is not a boundary facet"
                );
            }
            total += s.facets.len();
        }
        assert_eq!(total, boundary.len());
        let top = m.surface("top").unwrap();
        let len: f64 = top.facets.iter().map(|f| m.facet_normal(f).1).sum();
        assert!((len - 2.0).abs() < 1e-14);
    }

    #[test]
    fn tri_grid_to_tri6() {
        let (nx, ny) = (4, 3);
        let (t3, m) = grid_to_second_order([1.0, 1.0], [nx, ny], CellKind::Tri3);
        // + one diagonal per quad
        let edges = nx * (ny + 1) + ny * (nx + 1) + nx * ny;
        assert_eq!(m.n_nodes(), (nx + 1) * (ny + 1) + edges);
        assert!(m.cells.iter().all(|c| c.kind == CellKind::Tri6));
        let uses = mid_uses(&m, t3.n_nodes());
        assert_eq!(uses.len(), edges);
        assert_eq!(uses.values().filter(|&&u| u == 1).count(), 2 * (nx + ny));
        for s in m.surfaces.values() {
            assert!(s.facets.iter().all(|f| f.nodes.len() == 3));
        }
        // the generators build the same mesh directly
        let direct = rectangle([0.0, 0.0], [1.0, 1.0], [nx, ny], CellKind::Tri6, None).unwrap();
        assert_eq!(direct, m);
    }

    #[test]
    fn errors() {
        let m = rectangle([0.0, 0.0], [1.0, 1.0], [2, 2], CellKind::Quad8, None).unwrap();
        assert!(to_second_order(&m).is_err(), "already second-order");
        let mut d3 = m.clone();
        d3.dim = 3;
        assert!(to_second_order(&d3).is_err());
        let mut bad = rectangle([0.0, 0.0], [1.0, 1.0], [2, 2], CellKind::Quad4, None).unwrap();
        bad.surfaces.get_mut("top").unwrap().facets[0].cell = 0;
        assert!(
            to_second_order(&bad).is_err(),
            "facet not an edge of its cell"
        );
    }

    #[test]
    fn half_disk_quad8_arc_on_circle() {
        let (c, r) = ([0.5, 2.0], 1.5);
        for kind in [CellKind::Quad8, CellKind::Tri6] {
            let m = half_disk(&HalfBall::new(c, r, 16, [0.0, -1.0], 4.0), kind).unwrap();
            m.check().unwrap();
            let first =
                half_disk(&HalfBall::new(c, r, 16, [0.0, -1.0], 4.0), CellKind::Quad4).unwrap();
            assert!(m.n_nodes() > first.n_nodes());
            let arc = m.surface("arc").unwrap();
            assert_eq!(arc.facets.len(), 16);
            for f in &arc.facets {
                for &n in &f.nodes {
                    let x = m.coords[n];
                    let d = (x[0] - c[0]).hypot(x[1] - c[1]);
                    assert!(
                        (d - r).abs() < 1e-13 * r,
                        "arc node off the circle by {}",
                        d - r
                    );
                }
            }
            // flat mid-side nodes stay at the midpoints
            for f in &m.surface("flat").unwrap().facets {
                let (a, b, mm) = (
                    m.coords[f.nodes[0]],
                    m.coords[f.nodes[1]],
                    m.coords[f.nodes[2]],
                );
                assert!((mm[0] - 0.5 * (a[0] + b[0])).abs() < 1e-15);
                assert!((mm[1] - c[1]).abs() < 1e-15);
            }
        }
    }
}
