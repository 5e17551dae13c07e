//! From the file's contents (nodes, element blocks, physical names) to a
//! [`Mesh`]: cells, regions and surfaces.

use super::{cell_kind, facet_corners, invalid, supported_list, type_name, Raw};
use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use std::collections::{BTreeMap, HashMap, HashSet};

fn group_name(names: &HashMap<(usize, i32), String>, dim: usize, tag: i32) -> String {
    match names.get(&(dim, tag)) {
        Some(name) if !name.is_empty() => name.clone(),
        _ => tag.to_string(),
    }
}

fn count_list(counts: &BTreeMap<i32, usize>) -> String {
    counts
        .iter()
        .map(|(&t, &n)| format!("{} × {}", n, type_name(t)))
        .collect::<Vec<_>>()
        .join(", ")
}

pub(super) fn build(raw: Raw, dim: usize) -> Result<Mesh, MeshError> {
    let Raw {
        nodes: raw_nodes,
        blocks,
        names,
    } = raw;

    // Element types: too high a dimension, unsupported, present.
    let mut present: BTreeMap<i32, usize> = BTreeMap::new();
    let mut too_high: BTreeMap<i32, usize> = BTreeMap::new();
    let mut unsupported: BTreeMap<i32, usize> = BTreeMap::new();
    for b in &blocks {
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
            "unsupported Gmsh element type{} in a {dim}D mesh: {}; {}",
            if unsupported.len() > 1 { "s" } else { "" },
            count_list(&unsupported),
            supported_list(dim)
        )));
    }

    // Node tags → index in raw_nodes.
    let mut by_tag: HashMap<u64, usize> = HashMap::with_capacity(raw_nodes.len());
    for (i, (tag, _)) in raw_nodes.iter().enumerate() {
        if by_tag.insert(*tag, i).is_some() {
            return Err(invalid(format!("node tag {tag} appears twice in $Nodes")));
        }
    }
    let lookup = |tag: u64| -> Result<usize, MeshError> {
        by_tag.get(&tag).copied().ok_or_else(|| {
            invalid(format!(
                "an element refers to node {tag}, which is not in $Nodes"
            ))
        })
    };

    // Cells, with raw node indices first.
    let mut cells: Vec<Cell> = Vec::new();
    let mut cell_groups: Vec<(usize, &[i32])> = Vec::new();
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
            let nodes = el.iter().map(|&t| lookup(t)).collect::<Result<_, _>>()?;
            if !b.physical.is_empty() {
                cell_groups.push((cells.len(), &b.physical));
            }
            cells.push(Cell { kind, nodes });
        }
    }
    if cells.is_empty() {
        let found = if present.is_empty() {
            "none".to_string()
        } else {
            count_list(&present)
        };
        let what = if dim == 2 { "Surface" } else { "Volume" };
        return Err(invalid(format!(
            "no cell of dimension {dim} in the file (elements found: {found}); note that when \
             a .geo defines physical groups Gmsh saves only their elements: add a \
             Physical {what} for the body or set Mesh.SaveAll = 1"
        )));
    }

    // Dense renumbering of the nodes of cells, in $Nodes order.
    let mut new_index = vec![usize::MAX; raw_nodes.len()];
    for c in &cells {
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
    for c in &mut cells {
        for n in &mut c.nodes {
            *n = new_index[*n];
        }
    }

    // 2D meshes lie in the plane z = 0.
    if dim == 2 {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &coords {
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
        for p in &mut coords {
            p[2] = 0.0;
        }
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
    };

    // Regions: physical groups of dimension dim.
    for (c, groups) in cell_groups {
        for &g in groups {
            mesh.regions
                .entry(group_name(&names, dim, g))
                .or_default()
                .push(c);
        }
    }
    for cells in mesh.regions.values_mut() {
        cells.sort_unstable();
        cells.dedup();
    }

    // Surfaces: physical groups of dimension dim − 1, matched to cell facets.
    let corner_key = |nodes: &[usize], local: &[usize]| {
        let m = if dim == 2 { 2 } else { local.len() };
        let mut k: Vec<usize> = local[..m].iter().map(|&i| nodes[i]).collect();
        k.sort_unstable();
        k
    };
    // sorted corners → (number of cells, one cell, its local facet)
    let mut facet_of: HashMap<Vec<usize>, (usize, usize, usize)> = HashMap::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        for (f, local) in cell.kind.facets().iter().enumerate() {
            facet_of
                .entry(corner_key(&cell.nodes, local))
                .and_modify(|e| e.0 += 1)
                .or_insert((1, c, f));
        }
    }
    let mut seen: HashMap<String, HashSet<(usize, usize)>> = HashMap::new();
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
            let mut key = Vec::with_capacity(m);
            let mut orphan = false;
            for &t in &el[..m] {
                match new_index.get(lookup(t)?) {
                    Some(&k) if k != usize::MAX => key.push(k),
                    _ => orphan = true,
                }
            }
            key.sort_unstable();
            let found = if orphan { None } else { facet_of.get(&key) };
            let (c, f) = match found {
                Some(&(1, c, f)) => (c, f),
                other => {
                    let g = b.physical[0];
                    let why = match other {
                        Some(&(n, _, _)) => format!("an interior facet shared by {n} cells"),
                        _ => "not a facet of any cell".to_string(),
                    };
                    return Err(invalid(format!(
                        "physical group \"{}\" (dimension {}, tag {g}): its element with nodes \
                         {:?} is {why}; the facets of a surface must lie on the boundary",
                        group_name(&names, dim - 1, g),
                        dim - 1,
                        el
                    )));
                }
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
                let name = group_name(&names, dim - 1, g);
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
        CellKind::Tet4 => {
            let (a, b, c) = (sub(p(1), p(0)), sub(p(2), p(0)), sub(p(3), p(0)));
            if dot(a, cross(b, c)) >= 0.0 {
                return;
            }
            &[0, 2, 1, 3]
        }
        CellKind::Hex8 => {
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
            &[4, 5, 6, 7, 0, 1, 2, 3]
        }
    };
    cell.nodes = perm.iter().map(|&i| cell.nodes[i]).collect();
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
