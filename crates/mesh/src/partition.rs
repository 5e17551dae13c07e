//! Domain decomposition of a mesh: splitting its cells into connected parts of
//! balanced size with METIS (k-way partitioning or recursive bisection of the
//! element dual graph, whichever gives the smaller interface), and
//! the interface nodes shared between parts.
//!
//! The dual graph is built here, not by `metis::mesh_to_dual`: two cells are
//! neighbours when they share a facet (an edge in 2D), found by keying every
//! facet of every cell by its sorted node list. The graph is symmetric and has
//! no self loops, as METIS requires.

use std::collections::{HashMap, VecDeque};

use metis::{option, Graph, Idx};

use crate::{CellKind, Mesh, MeshError};

/// Seed of METIS's random number generator (fixed for reproducible partitions).
pub(crate) const SEED: Idx = 42;

/// METIS keeps its random number generator in global state: two partitions
/// computed at once (threads of one process) interleave their draws and
/// neither is reproducible any more. Every call into METIS holds this lock.
pub(crate) static METIS: std::sync::Mutex<()> = std::sync::Mutex::new(());
/// Allowed load imbalance of METIS in thousandths: 30 → parts at most 3 % above
/// the average size (before the contiguity constraint is enforced).
const UFACTOR: Idx = 30;

/// Splits the cells of a mesh into `nparts` connected parts of balanced size by
/// METIS (k-way or recursive bisection of the element dual graph where two cells are neighbours when
/// they share a facet: an edge in 2D; options `Contig(true)`, `Seed(42)` for
/// reproducibility, `UFactor(30)`). Returns the part of every cell.
/// `nparts == 1` → all zeros without calling METIS.
///
/// A mesh of several connected pieces is split piece by piece
/// ([`partition_pieces`]).
///
/// Errors (`MeshError::Invalid`): `nparts == 0`, `nparts` greater than the
/// number of cells, a cell with the wrong number of nodes, a METIS
/// failure, or a part that comes out empty or not connected. Both k-way
/// partitioning and recursive bisection are run; of the usable ones, the one
/// with fewer interface nodes is returned (k-way on a tie).
pub fn partition_cells(mesh: &Mesh, nparts: usize) -> Result<Vec<usize>, MeshError> {
    let ncells = mesh.cells.len();
    if nparts == 0 {
        return Err(MeshError::Invalid(
            "partition: the number of parts must be at least 1, got 0".into(),
        ));
    }
    if nparts > ncells {
        return Err(MeshError::Invalid(format!(
            "partition: cannot split {ncells} cells into {nparts} non-empty parts: give at most {ncells}, or \"auto\""
        )));
    }
    if nparts == 1 {
        return Ok(vec![0; ncells]);
    }
    let nparts_idx = Idx::try_from(nparts).map_err(|_| {
        MeshError::Invalid(format!("partition: {nparts} parts do not fit METIS's i32"))
    })?;

    let (xadj, adjncy) = dual_graph(mesh)?;
    let pieces = connected_pieces(&xadj, &adjncy);
    if pieces.len() > 1 {
        return partition_pieces(mesh, &pieces, nparts);
    }

    let graph = || -> Result<Graph<'_>, MeshError> {
        Ok(Graph::new(1, nparts_idx, &xadj, &adjncy)
            .map_err(|e| {
                MeshError::Invalid(format!("partition: METIS rejected the dual graph: {e}"))
            })?
            .set_option(option::Seed(SEED))
            .set_option(option::Contig(true))
            .set_option(option::UFactor(UFACTOR)))
    };

    // A panic elsewhere while holding the lock leaves nothing half-done here.
    let _metis = METIS.lock().unwrap_or_else(|e| e.into_inner());
    let mut part = vec![0 as Idx; ncells];
    let kway = graph()?
        .part_kway(&mut part)
        .map_err(|e| format!("k-way partitioning failed: {e}"))
        .and_then(|_| check_parts(&xadj, &adjncy, &part, nparts));
    let recursive = graph()?
        .part_recursive(&mut part)
        .map_err(|e| format!("recursive bisection failed: {e}"))
        .and_then(|_| check_parts(&xadj, &adjncy, &part, nparts));
    match (kway, recursive) {
        (Ok(k), Ok(r)) => Ok(smaller_interface(mesh, k, r)),
        (Ok(parts), Err(_)) | (Err(_), Ok(parts)) => Ok(parts),
        (Err(kway_err), Err(rec_err)) => Err(MeshError::Invalid(format!(
            "partition: METIS could not split {ncells} cells into {nparts} connected parts \
             ({kway_err}; {rec_err})"
        ))),
    }
}

/// The cells of each connected piece of the dual graph (pieces in the
/// order of their first cell, cells sorted).
fn connected_pieces(xadj: &[Idx], adjncy: &[Idx]) -> Vec<Vec<usize>> {
    let n = xadj.len() - 1;
    let mut piece_of = vec![usize::MAX; n];
    let mut pieces: Vec<Vec<usize>> = Vec::new();
    for start in 0..n {
        if piece_of[start] != usize::MAX {
            continue;
        }
        let id = pieces.len();
        piece_of[start] = id;
        let mut cells = vec![start];
        let mut queue = VecDeque::from([start]);
        while let Some(v) = queue.pop_front() {
            for &w in &adjncy[xadj[v] as usize..xadj[v + 1] as usize] {
                let w = w as usize;
                if piece_of[w] == usize::MAX {
                    piece_of[w] = id;
                    cells.push(w);
                    queue.push_back(w);
                }
            }
        }
        cells.sort_unstable();
        pieces.push(cells);
    }
    pieces
}

/// A mesh of several connected pieces in `nparts` parts. With at least as
/// many parts as pieces, each piece gets parts in proportion to its cells
/// (at least one; largest remainders, then the larger pieces first) and is
/// split on its own like a connected mesh, so every part is connected.
/// With fewer parts than pieces, whole pieces are dealt out, the largest
/// first, each to the part with the fewest cells so far: a part is then
/// several pieces, which condense as one subdomain as an unsplit body of
/// several pieces does.
fn partition_pieces(
    mesh: &Mesh,
    pieces: &[Vec<usize>],
    nparts: usize,
) -> Result<Vec<usize>, MeshError> {
    let mut part = vec![0usize; mesh.cells.len()];
    let mut order: Vec<usize> = (0..pieces.len()).collect();
    order.sort_by_key(|&p| std::cmp::Reverse(pieces[p].len()));
    if nparts < pieces.len() {
        let mut load = vec![0usize; nparts];
        for &p in &order {
            let target = (0..nparts).min_by_key(|&q| (load[q], q)).unwrap_or(0);
            load[target] += pieces[p].len();
            pieces[p].iter().for_each(|&c| part[c] = target);
        }
        return Ok(part);
    }
    let counts = parts_per_piece(pieces, &order, nparts);
    let mut first = 0;
    for (p, cells) in pieces.iter().enumerate() {
        let sub = Mesh {
            dim: mesh.dim,
            coords: mesh.coords.clone(),
            cells: cells.iter().map(|&c| mesh.cells[c].clone()).collect(),
            surfaces: Default::default(),
            regions: Default::default(),
            node_sets: Default::default(),
        };
        let within = partition_cells(&sub, counts[p])?;
        for (&c, q) in cells.iter().zip(within) {
            part[c] = first + q;
        }
        first += counts[p];
    }
    Ok(part)
}

/// How many of `nparts` (≥ pieces) each piece gets: one each, the rest in
/// proportion to the cells by largest remainders, never more than a
/// piece's cells.
fn parts_per_piece(pieces: &[Vec<usize>], order: &[usize], nparts: usize) -> Vec<usize> {
    let total: usize = pieces.iter().map(Vec::len).sum();
    let spare = nparts - pieces.len();
    let share = |p: usize| spare as f64 * pieces[p].len() as f64 / total as f64;
    let mut counts: Vec<usize> = (0..pieces.len())
        .map(|p| 1 + (share(p).floor() as usize).min(pieces[p].len() - 1))
        .collect();
    let mut by_remainder = order.to_vec();
    by_remainder.sort_by(|&a, &b| share(b).fract().total_cmp(&share(a).fract()));
    let mut left = nparts - counts.iter().sum::<usize>();
    while left > 0 {
        let before = left;
        for &p in &by_remainder {
            if left > 0 && counts[p] < pieces[p].len() {
                counts[p] += 1;
                left -= 1;
            }
        }
        if left == before {
            break;
        }
    }
    counts
}

/// Of two partitions, the one with fewer interface nodes (the first on a
/// tie). The interface is what condensation makes dense and the root
/// factorises, so it decides the cost: k-way partitioning minimises the
/// edge cut, recursive bisection cuts along nested separators, and on 3D
/// bodies the latter is often the smaller interface (8 parts of a Hex8
/// hemisphere, 12,339 DOFs: 2,826 interface DOFs against 3,320, half the
/// flops of the interface factor).
fn smaller_interface(mesh: &Mesh, first: Vec<usize>, second: Vec<usize>) -> Vec<usize> {
    if shared_nodes(mesh, &second).len() < shared_nodes(mesh, &first).len() {
        second
    } else {
        first
    }
}

/// Nodes shared by cells of two or more different parts, sorted.
///
/// # Panics
/// If `parts.len()` differs from the number of cells.
pub fn shared_nodes(mesh: &Mesh, parts: &[usize]) -> Vec<usize> {
    assert_eq!(
        parts.len(),
        mesh.cells.len(),
        "shared_nodes: one part per cell expected"
    );
    // First part seen at each node, and whether a second one was seen.
    let mut first: Vec<Option<usize>> = vec![None; mesh.n_nodes()];
    let mut shared = vec![false; mesh.n_nodes()];
    for (cell, &p) in mesh.cells.iter().zip(parts) {
        for &n in &cell.nodes {
            match first[n] {
                None => first[n] = Some(p),
                Some(q) if q != p => shared[n] = true,
                Some(_) => {}
            }
        }
    }
    (0..mesh.n_nodes()).filter(|&n| shared[n]).collect()
}

/// Facets of a cell as sorted corner-node lists (edges in 2D, faces in 3D),
/// from [`CellKind::facets`].
fn cell_facets(kind: CellKind, nodes: &[usize]) -> Vec<Vec<usize>> {
    kind.facets()
        .iter()
        .map(|local| {
            let corners = if kind.dim() == 2 { 2 } else { local.len() };
            let mut f: Vec<usize> = local[..corners].iter().map(|&i| nodes[i]).collect();
            f.sort_unstable();
            f
        })
        .collect()
}

/// Element dual graph in CSR form (`xadj`, `adjncy`) for METIS: cells `a` and
/// `b` are adjacent when they share a facet. Symmetric, sorted rows, no self
/// loops, no duplicates.
fn dual_graph(mesh: &Mesh) -> Result<(Vec<Idx>, Vec<Idx>), MeshError> {
    let ncells = mesh.cells.len();
    let mut by_facet: HashMap<Vec<usize>, Vec<usize>> = HashMap::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        if cell.nodes.len() != cell.kind.nodes() {
            return Err(MeshError::Invalid(format!(
                "partition: cell {c} ({}) has {} nodes, expected {}",
                cell.kind.name(),
                cell.nodes.len(),
                cell.kind.nodes()
            )));
        }
        for f in cell_facets(cell.kind, &cell.nodes) {
            by_facet.entry(f).or_default().push(c);
        }
    }
    let mut nbrs: Vec<Vec<usize>> = vec![Vec::new(); ncells];
    for cells in by_facet.values() {
        for (i, &a) in cells.iter().enumerate() {
            for &b in &cells[i + 1..] {
                if a != b {
                    nbrs[a].push(b);
                    nbrs[b].push(a);
                }
            }
        }
    }
    let too_big = || MeshError::Invalid("partition: dual graph too large for METIS's i32".into());
    let mut xadj: Vec<Idx> = Vec::with_capacity(ncells + 1);
    let mut adjncy: Vec<Idx> = Vec::new();
    xadj.push(0);
    for row in &mut nbrs {
        row.sort_unstable();
        row.dedup();
        for &b in row.iter() {
            adjncy.push(Idx::try_from(b).map_err(|_| too_big())?);
        }
        xadj.push(Idx::try_from(adjncy.len()).map_err(|_| too_big())?);
    }
    Ok((xadj, adjncy))
}

/// Refuses cells that share a node without being joined through whole
/// facets (edges in 2D, faces in 3D) to the cells around it: a
/// non-conforming mesh (hexahedra against tetrahedra without pyramids,
/// hanging nodes) or parts meeting at a point or an edge only. Neither
/// carries a continuous displacement across, and the answer would be wrong
/// without a warning (a hexahedron under tetrahedra: 6.9 % off a patch
/// test). Disconnected parts, which share no node, are fine.
pub fn check_conforming(mesh: &Mesh) -> Result<(), MeshError> {
    let (xadj, adjncy) = dual_graph(mesh)?;
    // Facet-connected components of the cells.
    let mut label = vec![0usize; mesh.cells.len()];
    for (id, cells) in connected_pieces(&xadj, &adjncy).iter().enumerate() {
        cells.iter().for_each(|&c| label[c] = id);
    }
    // A node reached by two components: the witness.
    let mut at_node = vec![usize::MAX; mesh.n_nodes()];
    for (c, cell) in mesh.cells.iter().enumerate() {
        for &n in &cell.nodes {
            match at_node[n] {
                usize::MAX => at_node[n] = c,
                first if label[first] != label[c] => {
                    return Err(MeshError::Invalid(format!(
                        "cells {first} ({}) and {c} ({}) share the node at {:?} but are not joined through whole {}: the mesh is non-conforming (e.g. hexahedra against tetrahedra without pyramids, or hanging nodes) or two parts meet at a point or an edge only, and the displacement would not be continuous there; mesh it conforming",
                        mesh.cells[first].kind.name(),
                        cell.kind.name(),
                        mesh.coords[n],
                        if mesh.dim == 3 { "faces" } else { "edges" }
                    )))
                }
                _ => {}
            }
        }
    }
    Ok(())
}

/// Whether the vertices `set` (non-empty) induce a connected subgraph.
fn is_connected(xadj: &[Idx], adjncy: &[Idx], set: &[usize]) -> bool {
    let n = xadj.len() - 1;
    let mut inside = vec![false; n];
    for &v in set {
        inside[v] = true;
    }
    let mut seen = vec![false; n];
    let mut queue = VecDeque::from([set[0]]);
    seen[set[0]] = true;
    let mut reached = 1;
    while let Some(v) = queue.pop_front() {
        for &w in &adjncy[xadj[v] as usize..xadj[v + 1] as usize] {
            let w = w as usize;
            if inside[w] && !seen[w] {
                seen[w] = true;
                reached += 1;
                queue.push_back(w);
            }
        }
    }
    reached == set.len()
}

/// Converts METIS's part array and checks every part is non-empty and
/// connected.
fn check_parts(
    xadj: &[Idx],
    adjncy: &[Idx],
    part: &[Idx],
    nparts: usize,
) -> Result<Vec<usize>, String> {
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); nparts];
    let mut parts = Vec::with_capacity(part.len());
    for (c, &p) in part.iter().enumerate() {
        let p = usize::try_from(p)
            .ok()
            .filter(|&p| p < nparts)
            .ok_or_else(|| format!("cell {c} was put in part {p}, outside 0..{nparts}"))?;
        members[p].push(c);
        parts.push(p);
    }
    for (p, cells) in members.iter().enumerate() {
        if cells.is_empty() {
            return Err(format!("part {p} is empty"));
        }
        if !is_connected(xadj, adjncy, cells) {
            return Err(format!("part {p} ({} cells) is not connected", cells.len()));
        }
    }
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{half_disk, rectangle, HalfBall};
    use crate::Cell;

    /// Checks non-empty, connected and balanced (within 30 % of n / nparts) parts.
    fn check_partition(mesh: &Mesh, parts: &[usize], nparts: usize) {
        assert_eq!(parts.len(), mesh.cells.len());
        let (xadj, adjncy) = dual_graph(mesh).unwrap();
        let ideal = mesh.cells.len() as f64 / nparts as f64;
        for p in 0..nparts {
            let cells: Vec<usize> = (0..parts.len()).filter(|&c| parts[c] == p).collect();
            assert!(!cells.is_empty(), "part {p} is empty");
            assert!(
                is_connected(&xadj, &adjncy, &cells),
                "part {p} is not connected"
            );
            let dev = (cells.len() as f64 - ideal).abs() / ideal;
            assert!(
                dev <= 0.3,
                "part {p} has {} cells, ideal {ideal}",
                cells.len()
            );
        }
        assert!(parts.iter().all(|&p| p < nparts));
    }

    /// Every shared node touches cells of >= 2 parts, every other node of 1.
    fn check_shared(mesh: &Mesh, parts: &[usize], shared: &[usize]) {
        let mut node_parts: Vec<Vec<usize>> = vec![Vec::new(); mesh.n_nodes()];
        for (cell, &p) in mesh.cells.iter().zip(parts) {
            for &n in &cell.nodes {
                node_parts[n].push(p);
            }
        }
        for ps in &mut node_parts {
            ps.sort_unstable();
            ps.dedup();
        }
        assert!(shared.windows(2).all(|w| w[0] < w[1]), "not sorted");
        let expected: Vec<usize> = (0..mesh.n_nodes())
            .filter(|&n| node_parts[n].len() >= 2)
            .collect();
        assert_eq!(shared, expected.as_slice());
    }

    #[test]
    fn dual_graph_of_quads_is_symmetric() {
        let mesh = rectangle([0., 0.], [2., 1.], [3, 2], CellKind::Quad4, None).unwrap();
        let (xadj, adjncy) = dual_graph(&mesh).unwrap();
        assert_eq!(xadj.len(), 7);
        // 3 x 2 grid: 3 vertical-neighbour pairs + 4 horizontal ones = 7 edges.
        assert_eq!(adjncy.len(), 14);
        for v in 0..6 {
            for &w in &adjncy[xadj[v] as usize..xadj[v + 1] as usize] {
                let w = w as usize;
                assert_ne!(v, w);
                let back = &adjncy[xadj[w] as usize..xadj[w + 1] as usize];
                assert!(back.contains(&(v as Idx)));
            }
        }
    }

    #[test]
    fn rectangle_quad_and_tri_into_2_and_4_parts() {
        for kind in [CellKind::Quad4, CellKind::Tri3] {
            let mesh = rectangle([0., 0.], [2., 1.], [16, 8], kind, None).unwrap();
            for nparts in [2, 4] {
                let parts = partition_cells(&mesh, nparts).unwrap();
                check_partition(&mesh, &parts, nparts);
                let again = partition_cells(&mesh, nparts).unwrap();
                assert_eq!(parts, again, "{kind:?} into {nparts}: not deterministic");
                let shared = shared_nodes(&mesh, &parts);
                assert!(!shared.is_empty());
                check_shared(&mesh, &parts, &shared);
            }
        }
    }

    #[test]
    fn half_disk_into_2_parts() {
        let ball = HalfBall::new([0., 1.], 1.0, 64, [0., -1.], 8.0);
        let mesh = half_disk(&ball, CellKind::Quad4).unwrap();
        let parts = partition_cells(&mesh, 2).unwrap();
        check_partition(&mesh, &parts, 2);
        let shared = shared_nodes(&mesh, &parts);
        assert!(!shared.is_empty());
        check_shared(&mesh, &parts, &shared);
    }

    /// Of strips and blocks of an 8 × 8 grid in 4 parts, the blocks (17
    /// interface nodes against 27), whatever the order; the first on a tie.
    #[test]
    fn the_partition_with_the_smaller_interface_is_kept() {
        let mesh = rectangle([0., 0.], [1., 1.], [8, 8], CellKind::Quad4, None).unwrap();
        let centre = |c: &Cell| {
            let n = c.nodes.len() as f64;
            let x = c.nodes.iter().map(|&i| mesh.coords[i][0]).sum::<f64>() / n;
            let y = c.nodes.iter().map(|&i| mesh.coords[i][1]).sum::<f64>() / n;
            (x, y)
        };
        let strips: Vec<usize> = mesh
            .cells
            .iter()
            .map(|c| (centre(c).0 * 4.0) as usize)
            .collect();
        let blocks: Vec<usize> = mesh
            .cells
            .iter()
            .map(|c| {
                let (x, y) = centre(c);
                2 * (y * 2.0) as usize + (x * 2.0) as usize
            })
            .collect();
        assert_eq!(shared_nodes(&mesh, &strips).len(), 27);
        assert_eq!(shared_nodes(&mesh, &blocks).len(), 17);
        assert_eq!(
            smaller_interface(&mesh, strips.clone(), blocks.clone()),
            blocks
        );
        assert_eq!(
            smaller_interface(&mesh, blocks.clone(), strips.clone()),
            blocks
        );
        let mirrored: Vec<usize> = blocks.iter().map(|&p| 3 - p).collect();
        assert_eq!(smaller_interface(&mesh, mirrored.clone(), blocks), mirrored);
    }

    #[test]
    fn one_part_is_all_zeros() {
        let mesh = rectangle([0., 0.], [1., 1.], [4, 4], CellKind::Tri3, None).unwrap();
        let parts = partition_cells(&mesh, 1).unwrap();
        assert_eq!(parts, vec![0; mesh.cells.len()]);
        assert!(shared_nodes(&mesh, &parts).is_empty());
    }

    #[test]
    fn as_many_parts_as_cells() {
        let mesh = rectangle([0., 0.], [1., 1.], [2, 2], CellKind::Quad4, None).unwrap();
        let parts = partition_cells(&mesh, 4).unwrap();
        let mut sorted = parts.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, vec![0, 1, 2, 3]);
    }

    #[test]
    fn bad_part_counts_are_errors() {
        let mesh = rectangle([0., 0.], [2., 1.], [4, 2], CellKind::Quad4, None).unwrap();
        let err = partition_cells(&mesh, 0).unwrap_err().to_string();
        assert!(err.contains("at least 1"), "{err}");
        let err = partition_cells(&mesh, 9).unwrap_err().to_string();
        assert!(err.contains("8 cells into 9"), "{err}");
        let empty = Mesh::default();
        assert!(partition_cells(&empty, 1).is_err());
    }

    /// Two pieces: a 4 × 2 rectangle (8 cells) and a separate quad. In two
    /// or three parts each piece has its own (the quad one, the rectangle
    /// the rest, connected); in one part all together; more parts than
    /// cells are refused as for a connected mesh.
    #[test]
    fn a_mesh_of_two_pieces_is_split_piece_by_piece() {
        let mut mesh = rectangle([0., 0.], [2., 1.], [4, 2], CellKind::Quad4, None).unwrap();
        let base = mesh.n_nodes();
        mesh.coords
            .extend([[5., 0., 0.], [6., 0., 0.], [6., 1., 0.], [5., 1., 0.]]);
        mesh.cells.push(Cell {
            kind: CellKind::Quad4,
            nodes: (base..base + 4).collect(),
        });
        let (xadj, adjncy) = dual_graph(&mesh).unwrap();
        for n in [2, 3, 5] {
            let parts = partition_cells(&mesh, n).unwrap();
            let quad = parts[8];
            assert!(parts[..8].iter().all(|&p| p != quad), "n = {n}: {parts:?}");
            for p in 0..n {
                let cells: Vec<usize> = (0..9).filter(|&c| parts[c] == p).collect();
                assert!(
                    !cells.is_empty() && is_connected(&xadj, &adjncy, &cells),
                    "n = {n}: part {p}"
                );
            }
        }
        assert!(partition_cells(&mesh, 1).unwrap().iter().all(|&p| p == 0));
        assert!(partition_cells(&mesh, 10).is_err());
    }

    /// Parts per piece: one each, the rest by largest remainders, never more
    /// than a piece's cells; fewer parts than pieces deal whole pieces out.
    #[test]
    fn pieces_get_parts_in_proportion_to_their_cells() {
        let pieces = vec![
            (0..90).collect::<Vec<_>>(),
            (90..100).collect(),
            (100..101).collect(),
        ];
        let order = [0, 1, 2];
        assert_eq!(parts_per_piece(&pieces, &order, 3), [1, 1, 1]);
        assert_eq!(parts_per_piece(&pieces, &order, 13), [10, 2, 1]);
        let two = vec![(0..3).collect::<Vec<_>>(), (3..4).collect()];
        assert_eq!(parts_per_piece(&two, &[0, 1], 4), [3, 1]);
    }
}
