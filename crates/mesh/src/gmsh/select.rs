//! One body of a file that holds several (an assembly): the cells of one
//! physical group of dimension d (`volume`), and the node sets of the
//! physical groups of points (and curves in 3D) that loads name.
//!
//! A body chosen by its volume keeps the nodes of its own cells alone: a node
//! two volumes share becomes one node of each body. The file's surfaces are
//! restricted to the body: a facet element whose corners are not all nodes of
//! its cells, or that bounds none of them, belongs to another body and is
//! skipped; a surface left without facets is not one of the body's.

use super::{group_name, invalid, Block, Names, NodeTags};
use crate::{Mesh, MeshError};
use std::collections::BTreeSet;

/// Keeps of the blocks of dimension `dim` those of the physical group named
/// `volume` (its name, or its tag when it has none); an error naming the
/// file's groups of dimension `dim` when there is none of that name.
pub(super) fn keep_volume(
    blocks: &mut Vec<Block>,
    names: &Names,
    dim: usize,
    volume: &str,
) -> Result<(), MeshError> {
    let mut known: Vec<(String, i32)> = blocks
        .iter()
        .filter(|b| b.dim == dim)
        .flat_map(|b| b.physical.iter().map(|&t| (group_name(names, dim, t), t)))
        .collect();
    known.sort_unstable();
    known.dedup();
    let tags: Vec<i32> = known
        .iter()
        .filter(|(n, _)| n == volume)
        .map(|&(_, t)| t)
        .collect();
    if tags.is_empty() {
        let listed: Vec<String> = known.iter().map(|(n, _)| format!("\"{n}\"")).collect();
        let listed = if listed.is_empty() {
            "none".to_string()
        } else {
            listed.join(", ")
        };
        return Err(invalid(format!(
            "no physical group of dimension {dim} named \"{volume}\" (the file's physical \
             groups of dimension {dim}, the bodies it holds: {listed})"
        )));
    }
    blocks.retain(|b| b.dim != dim || b.physical.iter().any(|t| tags.contains(t)));
    Ok(())
}

/// The node sets: every physical group of dimension below `dim − 1` lists the
/// nodes of its elements that are nodes of the mesh, sorted, once each; a
/// group with none (on another body) is left out.
pub(super) fn add_node_sets(
    mesh: &mut Mesh,
    blocks: &[Block],
    names: &Names,
    tags: &NodeTags,
    new_index: &[usize],
    interior: &BTreeSet<String>,
) -> Result<(), MeshError> {
    let named = |b: &Block, g: i32| group_name(names, b.dim, g);
    let is_set = |b: &Block, g: i32| b.dim + 1 < mesh.dim || interior.contains(&named(b, g));
    for b in blocks.iter().filter(|b| b.dim < mesh.dim) {
        let groups: Vec<i32> = b
            .physical
            .iter()
            .copied()
            .filter(|&g| is_set(b, g))
            .collect();
        if groups.is_empty() {
            continue;
        }
        let mut nodes = Vec::with_capacity(b.nodes.len());
        for &t in &b.nodes {
            match new_index.get(tags.lookup(t)?) {
                Some(&k) if k != usize::MAX => nodes.push(k),
                _ => {}
            }
        }
        if nodes.is_empty() {
            continue;
        }
        for g in groups {
            mesh.node_sets
                .entry(named(b, g))
                .or_default()
                .extend(&nodes);
        }
    }
    for nodes in mesh.node_sets.values_mut() {
        nodes.sort_unstable();
        nodes.dedup();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::gmsh::{parse_msh, parse_msh_volume};

    /// Two rectangles meshed apart in one file (tests/data/tied_blocks_2d.geo).
    const FILE: &[u8] = include_bytes!("../../../../tests/data/tied_blocks_2d.msh");

    #[test]
    fn a_volume_is_one_body_with_its_own_surfaces_and_node_sets() {
        let whole = parse_msh(FILE, 2).unwrap();
        let lower = parse_msh_volume(FILE, 2, Some("lower")).unwrap();
        let upper = parse_msh_volume(FILE, 2, Some("upper")).unwrap();
        // every cell in one body or the other, the nodes apart
        assert_eq!(lower.cells.len() + upper.cells.len(), whole.cells.len());
        assert_eq!(lower.n_nodes() + upper.n_nodes(), whole.n_nodes());
        let names = |m: &crate::Mesh| m.surfaces.keys().cloned().collect::<Vec<_>>();
        assert_eq!(names(&lower), ["lower_bottom", "lower_top"]);
        assert_eq!(names(&upper), ["upper_bottom", "upper_top"]);
        // the physical point at the origin is a node set of the lower body
        let origin = &lower.node_sets["origin"];
        assert_eq!(origin.len(), 1);
        assert_eq!(lower.coords[origin[0]], [0.0, 0.0, 0.0]);
        assert!(!upper.node_sets.contains_key("origin"));
        assert_eq!(upper.node_sets["top_corners"].len(), 2);
    }

    #[test]
    fn an_unknown_volume_is_refused_listing_the_files_volumes() {
        let e = parse_msh_volume(FILE, 2, Some("middle"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("\"middle\"") && e.contains("\"lower\", \"upper\""),
            "{e}"
        );
    }
}
