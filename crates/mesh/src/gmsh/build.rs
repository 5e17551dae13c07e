//! From the file's contents (nodes, element blocks, physical names) to a
//! [`Mesh`]: cells, regions and surfaces.

use super::select::{add_node_sets, keep_volume};
use super::{
    cell_kind, facet_corners, group_name, invalid, supported_list, type_name, Block, Names,
    NodeTags, Raw,
};
use crate::vec3::{cross, dot, sub};
use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

/// The physical groups of the cells that have some: (cell index, group tags).
type CellGroups<'a> = Vec<(usize, &'a [i32])>;

/// Element counts by type, written "n × type name, ...".
fn count_list(counts: &BTreeMap<i32, usize>) -> String {
    counts
        .iter()
        .map(|(&t, &n)| format!("{} × {}", n, type_name(t)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Builds the mesh of dimension `dim` from a file's contents: cells, their
/// nodes renumbered densely (in the plane z = 0 in 2D) and oriented, regions
/// and surfaces from the physical groups (see the module documentation of
/// [`gmsh`](super)). With `volume`, the body of that physical group of
/// dimension `dim` alone ([`select`](super::select)).
pub(super) fn build(raw: Raw, dim: usize, volume: Option<&str>) -> Result<Mesh, MeshError> {
    let Raw {
        nodes: raw_nodes,
        mut blocks,
        names,
    } = raw;
    if let Some(v) = volume {
        keep_volume(&mut blocks, &names, dim, v)?;
    }
    let present = check_element_types(&blocks, dim)?;
    if present.is_empty() {
        return Err(no_cells(&present, dim));
    }
    check_groups_kept(&blocks, &names, dim)?;
    let tags = NodeTags::new(&raw_nodes)?;
    let (mut cells, cell_groups) = read_cells(&blocks, dim, &tags)?;
    if cells.is_empty() {
        return Err(no_cells(&present, dim));
    }
    let (mut coords, new_index) = renumber_nodes(&raw_nodes, &mut cells);
    if dim == 2 {
        flatten_2d(&mut coords, &raw_nodes, &new_index)?;
    }
    for c in &mut cells {
        orient(c, &coords);
    }
    let mut mesh = Mesh {
        dim,
        coords,
        cells,
        surfaces: BTreeMap::new(),
        regions: BTreeMap::new(),
        node_sets: BTreeMap::new(),
    };
    add_regions(&mut mesh, cell_groups, &names);
    let facets = FacetIndex::new(&mesh, &tags, &new_index, volume.is_some());
    let interior = add_surfaces(&mut mesh, &blocks, &names, &facets)?;
    add_node_sets(&mut mesh, &blocks, &names, &tags, &new_index, &interior)?;
    if mesh.surfaces.is_empty() {
        mesh.surfaces.insert(
            "boundary".to_string(),
            Surface {
                facets: mesh.boundary_facets(),
            },
        );
    }
    mesh.check()?;
    Ok(mesh)
}

/// Checks the element types against a mesh of dimension `dim`: an error for
/// elements of a higher dimension, and for unsupported types that would be
/// cells or facets of a physical surface. Returns the count of every type
/// present.
fn check_element_types(blocks: &[Block], dim: usize) -> Result<BTreeMap<i32, usize>, MeshError> {
    let mut present: BTreeMap<i32, usize> = BTreeMap::new();
    let mut too_high: BTreeMap<i32, usize> = BTreeMap::new();
    let mut unsupported: BTreeMap<i32, usize> = BTreeMap::new();
    for b in blocks {
        let n = b.len();
        if n == 0 {
            continue;
        }
        *present.entry(b.gmsh_type).or_default() += n;
        // Unknown types of MSH 2.2 have no dimension (usize::MAX).
        if b.dim > 3 {
            *unsupported.entry(b.gmsh_type).or_default() += n;
        } else if b.dim > dim {
            *too_high.entry(b.gmsh_type).or_default() += n;
        } else if (b.dim == dim && cell_kind(b.gmsh_type, dim).is_none())
            || (b.dim + 1 == dim
                && !b.physical.is_empty()
                && facet_corners(b.gmsh_type, dim).is_none())
        {
            *unsupported.entry(b.gmsh_type).or_default() += n;
        }
    }
    if !too_high.is_empty() {
        let top = blocks.iter().map(|b| b.dim).filter(|&d| d <= 3).max();
        let top = top.unwrap_or(3);
        return Err(invalid(format!(
            "the file has elements of dimension higher than {dim} ({}): is it a {top}D mesh?",
            count_list(&too_high)
        )));
    }
    if !unsupported.is_empty() {
        return Err(invalid(format!(
            "unsupported Gmsh element type{} in a {dim}D mesh: {}; {}{}",
            if unsupported.len() > 1 { "s" } else { "" },
            count_list(&unsupported),
            supported_list(dim),
            remedy(&unsupported, dim)
        )));
    }
    Ok(present)
}

/// A file whose `$PhysicalNames` lists groups of dimension `dim − 1` while
/// none of its elements belongs to a physical group has lost them: Gmsh
/// writes MSH 2.2 files so with `Mesh.SaveAll = 1` (physical tag 0 on every
/// element). An error, rather than the whole boundary as `"boundary"` and a
/// scene's surfaces not found.
fn check_groups_kept(blocks: &[Block], names: &Names, dim: usize) -> Result<(), MeshError> {
    if blocks.iter().any(|b| !b.physical.is_empty()) {
        return Ok(());
    }
    let mut listed: Vec<String> = names
        .iter()
        .filter(|((d, _), _)| d + 1 == dim)
        .map(|(&(d, t), _)| format!("\"{}\"", group_name(names, d, t)))
        .collect();
    if listed.is_empty() {
        return Ok(());
    }
    listed.sort_unstable();
    Err(invalid(format!(
        "$PhysicalNames lists the physical groups {} of dimension {} but no element of \
         the file belongs to a physical group (physical tag 0 everywhere), so their \
         surfaces are lost; Gmsh writes MSH 2.2 files so with Mesh.SaveAll = 1: save \
         the mesh without Mesh.SaveAll (and a physical group for the body), or as MSH 4.1",
        listed.join(", "),
        dim - 1
    )))
}

/// What to change in Gmsh to get supported cells instead of the
/// `unsupported` types, when there is such a setting: 8-node instead of
/// 9-node quadrangles, 20-node instead of 27-node hexahedra, first-order cells for any other higher order; empty
/// otherwise (prisms, pyramids).
fn remedy(unsupported: &BTreeMap<i32, usize>, dim: usize) -> &'static str {
    let higher_order =
        |t: i32| super::type_info(t).is_some_and(|(_, d)| d == dim) && !matches!(t, 6 | 7 | 15);
    if dim == 2 && unsupported.keys().all(|&t| t == 10) {
        " (Gmsh writes 8-node quadrangles instead of 9-node ones with \
         Mesh.SecondOrderIncomplete = 1)"
    } else if dim == 3 && unsupported.keys().all(|&t| t == 12) {
        " (Gmsh writes 20-node hexahedra instead of 27-node ones with \
         Mesh.SecondOrderIncomplete = 1)"
    } else if unsupported.keys().any(|&t| higher_order(t)) {
        if dim == 2 {
            " (mesh with Mesh.ElementOrder = 1, or 2 for 6-node triangles and, with \
             Mesh.SecondOrderIncomplete = 1, 8-node quadrangles)"
        } else {
            " (mesh with Mesh.ElementOrder = 1, or 2 for 10-node tetrahedra and, with \
             Mesh.SecondOrderIncomplete = 1, 20-node hexahedra)"
        }
    } else {
        ""
    }
}

/// The cells: the elements of dimension `dim` in file order, with the indices
/// of their nodes in `$Nodes`, and the physical groups of each cell that has
/// some (by cell index).
fn read_cells<'a>(
    blocks: &'a [Block],
    dim: usize,
    tags: &NodeTags,
) -> Result<(Vec<Cell>, CellGroups<'a>), MeshError> {
    let mut cells: Vec<Cell> = Vec::new();
    let mut cell_groups: CellGroups = Vec::new();
    for b in blocks.iter().filter(|b| b.dim == dim) {
        let Some(kind) = cell_kind(b.gmsh_type, dim) else {
            continue;
        };
        if b.n_per != kind.nodes() {
            return Err(invalid(format!(
                "an element of type {} has {} nodes",
                type_name(b.gmsh_type),
                b.n_per
            )));
        }
        for el in b.nodes.chunks_exact(b.n_per) {
            let nodes = gmsh_to_cell_order(kind)
                .iter()
                .map(|&k| tags.lookup(el[k]))
                .collect::<Result<_, _>>()?;
            if !b.physical.is_empty() {
                cell_groups.push((cells.len(), &b.physical));
            }
            cells.push(Cell { kind, nodes });
        }
    }
    Ok((cells, cell_groups))
}

/// The error for a file without cells of dimension `dim`, listing the
/// elements `present` and the likely cause (physical groups without the body).
fn no_cells(present: &BTreeMap<i32, usize>, dim: usize) -> MeshError {
    if present.is_empty() {
        return invalid(format!(
            "the file has no elements: it holds no mesh (mesh the geometry in Gmsh, \
             e.g. gmsh -{dim} file.geo, and give the .msh it writes)"
        ));
    }
    let found = count_list(present);
    // 2D cells read as a 3D mesh: the file may be a 2D mesh (or the
    // triangles of a 3D one whose volume has no physical group)
    let flat = dim == 3 && present.keys().any(|&t| cell_kind(t, 2).is_some());
    let flat = if flat {
        "if it is a 2D mesh, set dimension = 2 in the scene; else "
    } else {
        ""
    };
    let what = if dim == 2 { "Surface" } else { "Volume" };
    invalid(format!(
        "no cell of dimension {dim} in the file (elements found: {found}); {flat}note that \
         when a .geo defines physical groups Gmsh saves only their elements: add a \
         Physical {what} for the body or set Mesh.SaveAll = 1"
    ))
}

/// Keeps the nodes of cells only, numbered densely in `$Nodes` order, and
/// renumbers the cells' nodes so. Returns their coordinates and the new index
/// of each node of `$Nodes` (`usize::MAX` for those dropped).
fn renumber_nodes(
    raw_nodes: &[(u64, [f64; 3])],
    cells: &mut [Cell],
) -> (Vec<[f64; 3]>, Vec<usize>) {
    let mut new_index = vec![usize::MAX; raw_nodes.len()];
    for c in cells.iter() {
        for &n in &c.nodes {
            new_index[n] = 0;
        }
    }
    let mut coords = Vec::new();
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = coords.len();
            coords.push(raw_nodes[i].1);
        }
    }
    for c in cells.iter_mut() {
        for n in &mut c.nodes {
            *n = new_index[*n];
        }
    }
    (coords, new_index)
}

/// Puts a 2D mesh in the plane z = 0: an error naming the node of largest
/// `|z|` if that is not negligible against the mesh size, else z set to 0.
fn flatten_2d(
    coords: &mut [[f64; 3]],
    raw_nodes: &[(u64, [f64; 3])],
    new_index: &[usize],
) -> Result<(), MeshError> {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in coords.iter() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt();
    let (worst, z) = coords
        .iter()
        .enumerate()
        .map(|(i, p)| (i, p[2]))
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .unwrap_or((0, 0.0));
    if z.is_nan() || z.abs() > 1e-8 * size {
        let tag = raw_nodes[new_index.iter().position(|&k| k == worst).unwrap_or(0)].0;
        return Err(invalid(format!(
            "a 2D mesh must lie in the plane z = 0, but node {tag} has z = {z:e} \
             (mesh size {size:e})"
        )));
    }
    for p in coords.iter_mut() {
        p[2] = 0.0;
    }
    Ok(())
}

/// Regions: each physical group of dimension `dim` lists its cells, sorted,
/// once each.
fn add_regions(mesh: &mut Mesh, cell_groups: CellGroups, names: &Names) {
    for (c, groups) in cell_groups {
        for &g in groups {
            mesh.regions
                .entry(group_name(names, mesh.dim, g))
                .or_default()
                .push(c);
        }
    }
    for cells in mesh.regions.values_mut() {
        cells.sort_unstable();
        cells.dedup();
    }
}

/// The facets of a mesh's cells by their sorted corner nodes, to find those
/// of a file's facet elements.
struct FacetIndex<'a> {
    dim: usize,
    /// Sorted corners → (number of cells, one cell, its local facet).
    facet_of: HashMap<Vec<usize>, (usize, usize, usize)>,
    tags: &'a NodeTags,
    /// New index of each node of `$Nodes` (`usize::MAX` if dropped).
    new_index: &'a [usize],
    /// One body of several: a facet element of no cell belongs to another.
    one_of_several: bool,
}

impl<'a> FacetIndex<'a> {
    /// Indexes the facets of every cell of `mesh`.
    fn new(
        mesh: &Mesh,
        tags: &'a NodeTags,
        new_index: &'a [usize],
        one_of_several: bool,
    ) -> FacetIndex<'a> {
        let dim = mesh.dim;
        let corner_key = |nodes: &[usize], local: &[usize]| {
            let m = crate::facet_corners(dim, local.len());
            let mut k: Vec<usize> = local[..m].iter().map(|&i| nodes[i]).collect();
            k.sort_unstable();
            k
        };
        let mut facet_of: HashMap<Vec<usize>, (usize, usize, usize)> = HashMap::new();
        for (c, cell) in mesh.cells.iter().enumerate() {
            for (f, local) in cell.kind.facets().iter().enumerate() {
                facet_of
                    .entry(corner_key(&cell.nodes, local))
                    .and_modify(|e| e.0 += 1)
                    .or_insert((1, c, f));
            }
        }
        FacetIndex {
            dim,
            facet_of,
            tags,
            new_index,
            one_of_several,
        }
    }

    /// The cell and its local facet whose corners are the first `m` nodes of
    /// element `el` of block `b` ([`FacetMatch`]); an error naming the
    /// block's group if it is the facet of no cell (of a body alone in its
    /// file).
    fn find(
        &self,
        b: &Block,
        el: &[u64],
        m: usize,
        names: &Names,
    ) -> Result<FacetMatch, MeshError> {
        let dim = self.dim;
        let mut key = Vec::with_capacity(m);
        let mut orphan = false;
        for &t in &el[..m] {
            match self.new_index.get(self.tags.lookup(t)?) {
                Some(&k) if k != usize::MAX => key.push(k),
                _ => orphan = true,
            }
        }
        key.sort_unstable();
        let found = if orphan {
            None
        } else {
            self.facet_of.get(&key)
        };
        match found {
            Some(&(1, c, f)) => Ok(FacetMatch::Boundary(c, f)),
            Some(_) => Ok(FacetMatch::Interior),
            None if self.one_of_several => Ok(FacetMatch::Elsewhere),
            None => {
                let g = b.physical[0];
                Err(invalid(format!(
                    "physical group \"{}\" (dimension {}, tag {g}): its element with nodes \
                     {:?} is not a facet of any cell; the facets of a surface must be faces \
                     of the mesh's cells",
                    group_name(names, dim - 1, g),
                    dim - 1,
                    el
                )))
            }
        }
    }
}

/// Where a facet element of a physical group of dimension d − 1 lies.
enum FacetMatch {
    /// On the boundary: the facet `.1` of cell `.0`.
    Boundary(usize, usize),
    /// Between two cells: its group is a set of nodes, not a surface.
    Interior,
    /// On no cell of this body (another body of the same file).
    Elsewhere,
}

/// Surfaces: every physical group of dimension `dim − 1` gets the cell facets
/// its elements match by their corners ([`FacetIndex::find`]), in the cells'
/// node order, each facet once. A group with a facet between two cells (a
/// surface inside the body) is no surface: its name is returned, for its
/// nodes to be a node set.
fn add_surfaces(
    mesh: &mut Mesh,
    blocks: &[Block],
    names: &Names,
    index: &FacetIndex,
) -> Result<BTreeSet<String>, MeshError> {
    let dim = mesh.dim;
    let mut seen: HashMap<String, HashSet<(usize, usize)>> = HashMap::new();
    let mut interior = BTreeSet::new();
    for b in blocks
        .iter()
        .filter(|b| b.dim + 1 == dim && !b.physical.is_empty())
    {
        let Some(m) = facet_corners(b.gmsh_type, dim) else {
            continue;
        };
        if b.n_per < m {
            return Err(invalid(format!(
                "an element of type {} has {} nodes",
                type_name(b.gmsh_type),
                b.n_per
            )));
        }
        for el in b.nodes.chunks_exact(b.n_per) {
            let (c, f) = match index.find(b, el, m, names)? {
                FacetMatch::Boundary(c, f) => (c, f),
                FacetMatch::Interior => {
                    interior.extend(b.physical.iter().map(|&g| group_name(names, dim - 1, g)));
                    continue;
                }
                FacetMatch::Elsewhere => continue,
            };
            let cell = &mesh.cells[c];
            let facet = Facet {
                nodes: cell.kind.facets()[f]
                    .iter()
                    .map(|&i| cell.nodes[i])
                    .collect(),
                cell: c,
            };
            for &g in &b.physical {
                let name = group_name(names, dim - 1, g);
                if seen.entry(name.clone()).or_default().insert((c, f)) {
                    mesh.surfaces
                        .entry(name)
                        .or_default()
                        .facets
                        .push(facet.clone());
                }
            }
        }
    }
    for name in &interior {
        mesh.surfaces.remove(name);
    }
    Ok(interior)
}

/// Node `i` of a cell of `kind` is node `order[i]` of the Gmsh element.
/// Gmsh and [`CellKind`] (VTK) agree but for the mid-side nodes of the
/// second-order solids: Gmsh numbers the Tet10's edges 0-1, 1-2, 2-0, 3-0,
/// 3-2, 3-1 and the Hex20's 0-1, 0-3, 0-4, 1-2, 1-5, 2-3, 2-6, 3-7, 4-5, 4-7,
/// 5-6, 6-7.
fn gmsh_to_cell_order(kind: CellKind) -> &'static [usize] {
    const IDENTITY: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    match kind {
        CellKind::Tet10 => &[0, 1, 2, 3, 4, 5, 6, 7, 9, 8],
        CellKind::Hex20 => &[
            0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
        ],
        other => &IDENTITY[..other.nodes()],
    }
}

/// Turns a cell over if it is clockwise (2D) or of negative volume (3D),
/// keeping each mid-side node on its edge.
fn orient(cell: &mut Cell, coords: &[[f64; 3]]) {
    let p = |k: usize| coords[cell.nodes[k]];
    let perm: &[usize] = match cell.kind {
        CellKind::Tri3 | CellKind::Quad4 | CellKind::Tri6 | CellKind::Quad8 => {
            let m = cell.kind.corners();
            let twice_area: f64 = (0..m)
                .map(|i| {
                    let (a, b) = (p(i), p((i + 1) % m));
                    a[0] * b[1] - b[0] * a[1]
                })
                .sum();
            if twice_area >= 0.0 {
                return;
            }
            match cell.kind {
                CellKind::Tri3 => &[0, 2, 1],
                CellKind::Quad4 => &[0, 3, 2, 1],
                CellKind::Tri6 => &[0, 2, 1, 5, 4, 3],
                _ => &[0, 3, 2, 1, 7, 6, 5, 4],
            }
        }
        CellKind::Tet4 | CellKind::Tet10 => {
            let (a, b, c) = (sub(p(1), p(0)), sub(p(2), p(0)), sub(p(3), p(0)));
            if dot(a, cross(b, c)) >= 0.0 {
                return;
            }
            if cell.kind == CellKind::Tet4 {
                &[0, 2, 1, 3]
            } else {
                &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8]
            }
        }
        CellKind::Hex8 | CellKind::Hex20 => {
            // Jacobian at the centre: mean edge vectors along ξ, η, ζ.
            let mut e = [[0.0; 3]; 3];
            for (dir, pairs) in [
                [(0, 1), (3, 2), (4, 5), (7, 6)],
                [(0, 3), (1, 2), (4, 7), (5, 6)],
                [(0, 4), (1, 5), (2, 6), (3, 7)],
            ]
            .iter()
            .enumerate()
            {
                for &(i, j) in pairs {
                    let d = sub(p(j), p(i));
                    for k in 0..3 {
                        e[dir][k] += d[k];
                    }
                }
            }
            if dot(e[0], cross(e[1], e[2])) >= 0.0 {
                return;
            }
            if cell.kind == CellKind::Hex8 {
                &[4, 5, 6, 7, 0, 1, 2, 3]
            } else {
                &[
                    4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19,
                ]
            }
        }
    };
    cell.nodes = perm.iter().map(|&i| cell.nodes[i]).collect();
}
