//! Second-order solid meshes, and tetrahedra cut from hexahedra.
//!
//! [`to_second_order_3d`] turns Tet4 / Hex8 cells into Tet10 / Hex20: every
//! edge gets one mid-side node at its midpoint, shared by the cells around it
//! (as [`crate::quadratic::to_second_order`] does in 2D), and every surface
//! facet becomes the Tri6 / Quad8 face of its cell. [`hexes_to_tetrahedra`]
//! cuts each Hex8 into 12 Tet4 about a new node at its centre, the diagonal
//! of each face through its lowest-numbered corner, so two cells sharing a
//! face cut it alike and the tetrahedra are conforming on any hexahedral mesh.

use crate::quadratic::{mid_node, of_dimension};
use crate::vec3::{cross, dot, sub};
use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use std::collections::{BTreeMap, HashMap};

/// The sorted corner nodes of a facet (its key among a cell's facets).
fn corner_key(nodes: &[usize], corners: usize) -> Vec<usize> {
    let mut k = nodes[..corners].to_vec();
    k.sort_unstable();
    k
}

/// The local facet of `cell` whose corners are those of `facet`.
fn local_facet(cell: &Cell, facet: &[usize]) -> Option<usize> {
    let key = corner_key(facet, facet.len().min(4));
    cell.kind.facets().iter().position(|local| {
        let nodes: Vec<usize> = local.iter().map(|&i| cell.nodes[i]).collect();
        let m = crate::facet_corners(3, nodes.len());
        m == key.len() && corner_key(&nodes, m) == key
    })
}

/// The surfaces of `mesh` carried over to `cells` (the same cell indices, or
/// the cell each facet is found in by `owner`): each facet becomes the facet
/// of its new cell with the same corners.
fn carry_surfaces(
    mesh: &Mesh,
    cells: &[Cell],
    owner: impl Fn(&Facet) -> Vec<usize>,
    what: &str,
) -> Result<BTreeMap<String, Surface>, MeshError> {
    let mut surfaces = BTreeMap::new();
    for (name, s) in &mesh.surfaces {
        let mut facets = Vec::with_capacity(s.facets.len());
        for f in &s.facets {
            let corners = crate::facet_corners(3, f.nodes.len());
            let pieces = owner(f);
            if pieces.is_empty() {
                return Err(MeshError::Invalid(format!(
                    "{what}: a facet {:?} of surface \"{name}\" is not a face of its cell {}",
                    f.nodes, f.cell
                )));
            }
            for c in pieces {
                let cell = &cells[c];
                let local = local_facet(cell, &f.nodes[..corners]).ok_or_else(|| {
                    MeshError::Invalid(format!(
                        "{what}: a facet {:?} of surface \"{name}\" is not a face of its cell {}",
                        f.nodes, f.cell
                    ))
                })?;
                let nodes = cell.kind.facets()[local]
                    .iter()
                    .map(|&i| cell.nodes[i])
                    .collect();
                facets.push(Facet { nodes, cell: c });
            }
        }
        surfaces.insert(name.clone(), Surface { facets });
    }
    Ok(surfaces)
}

/// The same mesh with Tet4 cells turned into Tet10 and Hex8 cells into
/// Hex20 (3D meshes only): one new node at the midpoint of each edge, after
/// the existing nodes, in the order the edges are first met (cell by cell,
/// edge by edge in the order of [`CellKind::edges`]). Cells keep their index
/// and corners; surface facets become the Tri6 / Quad8 faces of their cells.
/// Regions and node sets are kept.
///
/// Errors: a 2D mesh, a cell that is not Tet4 or Hex8, or a surface facet
/// that is not a face of its cell.
pub fn to_second_order_3d(mesh: &Mesh) -> Result<Mesh, MeshError> {
    of_dimension(mesh, 3, "to_second_order_3d: only 3D meshes (tet4, hex8)")?;
    let mut coords = mesh.coords.clone();
    let mut mids: HashMap<(usize, usize), usize> = HashMap::new();
    let mut cells = Vec::with_capacity(mesh.cells.len());
    for (c, cell) in mesh.cells.iter().enumerate() {
        let kind = match cell.kind {
            CellKind::Tet4 => CellKind::Tet10,
            CellKind::Hex8 => CellKind::Hex20,
            other => {
                return Err(MeshError::Invalid(format!(
                    "to_second_order_3d: cell {c} is a {} cell (expected tet4 or hex8)",
                    other.name()
                )))
            }
        };
        cell.check_node_count(c)
            .map_err(|m| MeshError::Invalid(format!("to_second_order_3d: {m}")))?;
        let mut nodes = cell.nodes.clone();
        for &[i, j] in kind.edges() {
            nodes.push(mid_node(
                &mut coords,
                &mut mids,
                cell.nodes[i],
                cell.nodes[j],
            ));
        }
        cells.push(Cell { kind, nodes });
    }
    let surfaces = carry_surfaces(mesh, &cells, |f| vec![f.cell], "to_second_order_3d")?;
    Ok(Mesh {
        dim: 3,
        coords,
        cells,
        surfaces,
        regions: mesh.regions.clone(),
        node_sets: mesh.node_sets.clone(),
    })
}

/// The 12 Tet4 of one Hex8 about its centre node `centre`: each face cut
/// along the diagonal through its lowest-numbered corner, each half joined
/// to the centre, with a positive volume.
fn hex_tetrahedra(coords: &[[f64; 3]], hex: &[usize], centre: usize) -> Vec<Cell> {
    let mut out = Vec::with_capacity(12);
    for local in CellKind::Hex8.facets() {
        let q: Vec<usize> = local.iter().map(|&i| hex[i]).collect();
        let low = (0..4).min_by_key(|&k| q[k]).unwrap_or(0);
        let r = |k: usize| q[(low + k) % 4];
        for tri in [[r(0), r(1), r(2)], [r(0), r(2), r(3)]] {
            let p = |v: usize| coords[v];
            let vol = dot(
                sub(p(tri[1]), p(tri[0])),
                cross(sub(p(tri[2]), p(tri[0])), sub(p(centre), p(tri[0]))),
            );
            let nodes = if vol > 0.0 {
                vec![tri[0], tri[1], tri[2], centre]
            } else {
                vec![tri[0], tri[2], tri[1], centre]
            };
            out.push(Cell {
                kind: CellKind::Tet4,
                nodes,
            });
        }
    }
    out
}

/// The same solid with every Hex8 cut into 12 Tet4 about a new node at its
/// centre (the mean of its corners; the new nodes follow the existing ones,
/// one per hexahedron in cell order). Cell `c` becomes cells `12 c .. 12 c + 12`;
/// a surface quadrilateral becomes its two triangles (faces of the
/// tetrahedra, outward as before); regions list the tetrahedra of their
/// hexahedra.
///
/// Errors: a cell that is not a Hex8.
pub fn hexes_to_tetrahedra(mesh: &Mesh) -> Result<Mesh, MeshError> {
    let mut coords = mesh.coords.clone();
    let mut cells = Vec::with_capacity(12 * mesh.cells.len());
    for (c, cell) in mesh.cells.iter().enumerate() {
        if cell.kind != CellKind::Hex8 {
            return Err(MeshError::Invalid(format!(
                "hexes_to_tetrahedra: cell {c} is a {} cell (expected hex8)",
                cell.kind.name()
            )));
        }
        let mut x = [0.0; 3];
        for &v in &cell.nodes {
            for k in 0..3 {
                x[k] += coords[v][k] / 8.0;
            }
        }
        coords.push(x);
        cells.extend(hex_tetrahedra(&coords, &cell.nodes, coords.len() - 1));
    }
    // A quadrilateral facet becomes the faces of its cell's tetrahedra
    // whose corners are all among its own.
    let mut surfaces = BTreeMap::new();
    for (name, s) in &mesh.surfaces {
        let mut facets = Vec::with_capacity(2 * s.facets.len());
        for f in &s.facets {
            for (t, tet) in cells.iter().enumerate().skip(12 * f.cell).take(12) {
                for local in tet.kind.facets() {
                    let nodes: Vec<usize> = local.iter().map(|&i| tet.nodes[i]).collect();
                    if nodes.iter().all(|v| f.nodes.contains(v)) {
                        facets.push(Facet { nodes, cell: t });
                    }
                }
            }
        }
        if facets.len() != 2 * s.facets.len() {
            return Err(MeshError::Invalid(format!(
                "hexes_to_tetrahedra: surface \"{name}\" has a facet that is not a face of its cell"
            )));
        }
        surfaces.insert(name.clone(), Surface { facets });
    }
    let regions = mesh
        .regions
        .iter()
        .map(|(name, list)| {
            let tets = list.iter().flat_map(|&c| 12 * c..12 * c + 12).collect();
            (name.clone(), tets)
        })
        .collect();
    Ok(Mesh {
        dim: 3,
        coords,
        cells,
        surfaces,
        regions,
        node_sets: mesh.node_sets.clone(),
    })
}
