//! MSH 4.1 (ASCII and binary) through `mshio`, with the node tags read again
//! where `mshio` drops them.

use super::fields::Fields;
use super::{invalid, physical_names, type_name, Block, Format, Raw};
use crate::MeshError;
use std::collections::{BTreeSet, HashMap, HashSet};

/// The mesh data of `mshio`'s 4.1 reading.
type MshData = mshio::MshData<u64, i32, f64>;

/// Reads an MSH 4.1 file (ASCII or binary): its nodes with their tags, its
/// element blocks with the physical groups of their entities (plain or
/// partitioned), and the physical names. The `$Nodes` section is read here
/// ([`read_nodes`]) and cut out of what `mshio` parses.
pub(super) fn read_v41(bytes: &[u8], format: &Format) -> Result<Raw, MeshError> {
    let size_t = format.binary.then_some(format.size_t);
    let (nodes, (begin, end)) = read_nodes(bytes, size_t)?;
    let rest = [&bytes[..begin], &bytes[end..]].concat();
    let msh = mshio::parse_msh_bytes(&rest).map_err(|e| {
        let mut msg = e.to_string();
        // mshio appends a hex dump of the rest of the file.
        if let Some(k) = msg.find("Hex dump") {
            msg.truncate(k);
        }
        let msg: String = msg.chars().take(2000).collect();
        invalid(format!(
            "cannot parse the MSH 4.1 file: {}",
            msg.trim().replace('\n', " ").replace('\t', "")
        ))
    })?;
    let names = physical_names(bytes)?;
    let elements = msh
        .data
        .elements
        .as_ref()
        .ok_or_else(|| invalid("MSH 4.1: no $Elements section".into()))?;
    let mut physicals = entity_physicals(&msh.data);
    let partitioned = read_partitioned(bytes, size_t)?;
    check_all_partitions(&partitioned, elements)?;
    physicals.extend(partitioned.physicals);
    let blocks = element_blocks(elements, &physicals)?;
    Ok(Raw {
        nodes,
        blocks,
        names,
    })
}

/// The `$Nodes` section: the nodes with their tags and coordinates, in file
/// order (parametric coordinates skipped), and the span of the section in
/// the file, from its `$Nodes` to the end of its `$EndNodes`.
fn read_nodes(bytes: &[u8], size_t: Option<usize>) -> Result<NodesAndSpan, MeshError> {
    let mut f = Fields::of_section(bytes, "Nodes", size_t)
        .ok_or_else(|| invalid("MSH 4.1: no $Nodes section".into()))?;
    let bad = |what: String| invalid(format!("MSH 4.1 $Nodes: {what}"));
    let head = (|| Some([f.count()?, f.count()?, f.count()?, f.count()?]))();
    let [n_blocks, n_nodes, _, _] = head.ok_or_else(|| bad("bad header".into()))?;
    // a count is the file's word: reserve no more than the file can hold
    let mut nodes = Vec::with_capacity(n_nodes.min(bytes.len() / 8));
    for k in 0..n_blocks {
        node_block(&mut f, &mut nodes).ok_or_else(|| {
            bad(format!(
                "node block {} of {n_blocks} is cut short or malformed",
                k + 1
            ))
        })?;
    }
    if nodes.len() != n_nodes {
        return Err(bad(format!(
            "announces {n_nodes} nodes but lists {}",
            nodes.len()
        )));
    }
    let end = section_end(bytes, f.offset(), "$EndNodes")
        .ok_or_else(|| bad("no $EndNodes after the last node block".into()))?;
    Ok((nodes, (f.header(), end)))
}

/// Nodes with their tags, and a section's span in the file.
type NodesAndSpan = (Vec<(u64, [f64; 3])>, (usize, usize));

/// Reads one node block (entity dimension and tag, parametric flag, count,
/// tags, then x y z and as many parametric coordinates as the dimension when
/// the flag is set) onto `nodes`; `None` if it is cut short or malformed.
fn node_block(f: &mut Fields, nodes: &mut Vec<(u64, [f64; 3])>) -> Option<()> {
    let dim = usize::try_from(f.int()?).ok().filter(|&d| d <= 3)?;
    f.int()?; // entity tag
    let parametric = match f.int()? {
        0 => 0,
        1 => dim,
        _ => return None,
    };
    let n = f.count()?;
    let first = nodes.len();
    for _ in 0..n {
        nodes.push((f.size_t()?, [0.0; 3]));
    }
    for node in &mut nodes[first..] {
        for x in &mut node.1 {
            *x = f.double()?;
        }
        f.skip_doubles(parametric)?;
    }
    Some(())
}

/// The offset just after the line `end_tag` that follows `from` (after
/// white space only); `None` if something else comes first.
fn section_end(bytes: &[u8], from: usize, end_tag: &str) -> Option<usize> {
    let rest = bytes.get(from..)?;
    let skip = rest.iter().position(|b| !b.is_ascii_whitespace())?;
    let after = from + skip + end_tag.len();
    rest[skip..]
        .starts_with(end_tag.as_bytes())
        .then_some(after)
}

/// Physical tags of each entity, by (dimension, entity tag): positive, sorted,
/// once each (none without `$Entities`).
fn entity_physicals(data: &MshData) -> HashMap<(usize, i32), Vec<i32>> {
    let mut entity_physicals: HashMap<(usize, i32), Vec<i32>> = HashMap::new();
    if let Some(ent) = &data.entities {
        let mut add = |d: usize, tag: i32, phys: &[i32]| {
            let mut p: Vec<i32> = phys.iter().map(|t| t.abs()).filter(|&t| t != 0).collect();
            p.sort_unstable();
            p.dedup();
            entity_physicals.insert((d, tag), p);
        };
        for e in &ent.points {
            add(0, e.tag, &e.physical_tags);
        }
        for e in &ent.curves {
            add(1, e.tag, &e.physical_tags);
        }
        for e in &ent.surfaces {
            add(2, e.tag, &e.physical_tags);
        }
        for e in &ent.volumes {
            add(3, e.tag, &e.physical_tags);
        }
    }
    entity_physicals
}

/// One [`Block`] per element block of the file, with the physical groups of its
/// entity; an element with the wrong number of nodes for its type is an error.
fn element_blocks(
    elements: &mshio::Elements<u64, i32>,
    entity_physicals: &HashMap<(usize, i32), Vec<i32>>,
) -> Result<Vec<Block>, MeshError> {
    let mut blocks = Vec::with_capacity(elements.element_blocks.len());
    for eb in &elements.element_blocks {
        let gmsh_type = eb.element_type as i32;
        let dim = usize::try_from(eb.entity_dim)
            .map_err(|_| invalid(format!("MSH 4.1: bad entity dimension {}", eb.entity_dim)))?;
        let n_per = eb.element_type.nodes().unwrap_or(0);
        let mut node_tags = Vec::with_capacity(eb.elements.len() * n_per);
        for el in &eb.elements {
            if el.nodes.len() != n_per {
                return Err(invalid(format!(
                    "MSH 4.1: an element of type {} has {} nodes",
                    type_name(gmsh_type),
                    el.nodes.len()
                )));
            }
            node_tags.extend_from_slice(&el.nodes);
        }
        blocks.push(Block {
            gmsh_type,
            dim,
            physical: entity_physicals
                .get(&(dim, eb.entity_tag))
                .cloned()
                .unwrap_or_default(),
            n_per,
            nodes: node_tags,
        });
    }
    Ok(blocks)
}

/// What `$PartitionedEntities` says of a mesh Gmsh has partitioned
/// (`gmsh.model.mesh.partition`): its elements lie on partition entities,
/// which carry the physical tags of their parents. `mshio` skips it.
#[derive(Default)]
struct Partitioned {
    /// Number of partitions (0: the file has no such section).
    parts: usize,
    /// Tags of the ghost entities.
    ghosts: HashSet<i32>,
    /// Physical tags by (dimension, entity tag), as [`entity_physicals`].
    physicals: HashMap<(usize, i32), Vec<i32>>,
    /// Partitions of each entity, by (dimension, entity tag).
    partitions: HashMap<(usize, i32), Vec<i32>>,
}

/// Reads `$PartitionedEntities` (ASCII or binary); empty without it.
fn read_partitioned(bytes: &[u8], size_t: Option<usize>) -> Result<Partitioned, MeshError> {
    let mut p = Partitioned::default();
    let Some(mut f) = Fields::of_section(bytes, "PartitionedEntities", size_t) else {
        return Ok(p);
    };
    partitioned_entities(&mut f, &mut p)
        .ok_or_else(|| invalid("MSH 4.1 $PartitionedEntities: cut short or malformed".into()))?;
    Ok(p)
}

/// Reads the body of `$PartitionedEntities` into `p`: partition and ghost
/// counts, then points, curves, surfaces and volumes, each with its tag,
/// parent, partitions, bounding box (a point: its coordinates), physical
/// tags and (but points) bounding entities.
fn partitioned_entities(f: &mut Fields, p: &mut Partitioned) -> Option<()> {
    p.parts = f.count()?;
    for _ in 0..f.count()? {
        p.ghosts.insert(f.int()?);
        f.int()?; // its partition
    }
    let counts = [f.count()?, f.count()?, f.count()?, f.count()?];
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = f.int()?;
            f.int()?; // parent dimension
            f.int()?; // parent tag
            let parts = (0..f.count()?).map(|_| f.int()).collect::<Option<_>>()?;
            p.partitions.insert((dim, tag), parts);
            f.skip_doubles(if dim == 0 { 3 } else { 6 })?;
            let mut phys = Vec::new();
            for _ in 0..f.count()? {
                let t = f.int()?.unsigned_abs();
                phys.push(i32::try_from(t).ok()?);
            }
            if dim > 0 {
                for _ in 0..f.count()? {
                    f.int()?; // bounding entity
                }
            }
            phys.retain(|&t| t != 0);
            phys.sort_unstable();
            phys.dedup();
            p.physicals.insert((dim, tag), phys);
        }
    }
    Some(())
}

/// A partitioned file whose elements of the highest dimension (ghosts
/// aside) lie in some of its partitions only is one piece of a mesh saved
/// one file per partition (`Mesh.PartitionSplitMeshFiles = 1`): an error,
/// since the body would be that fragment.
fn check_all_partitions(
    p: &Partitioned,
    elements: &mshio::Elements<u64, i32>,
) -> Result<(), MeshError> {
    let blocks = || {
        elements
            .element_blocks
            .iter()
            .filter(|b| !b.elements.is_empty())
    };
    let Some(top) = blocks().map(|b| b.entity_dim).max() else {
        return Ok(());
    };
    let mut present = BTreeSet::new();
    for b in blocks().filter(|b| b.entity_dim == top && !p.ghosts.contains(&b.entity_tag)) {
        let key = (usize::try_from(top).unwrap_or(0), b.entity_tag);
        present.extend(p.partitions.get(&key).into_iter().flatten().copied());
    }
    if p.parts < 2 || present.is_empty() || present.len() >= p.parts {
        return Ok(());
    }
    let list: Vec<String> = present.iter().map(i32::to_string).collect();
    Err(invalid(format!(
        "the file holds partition{} {} of a mesh Gmsh partitioned into {} parts and saved \
         one file per partition (Mesh.PartitionSplitMeshFiles = 1): the body would be that \
         piece only; save the whole mesh in one file (Mesh.PartitionSplitMeshFiles = 0)",
        if list.len() > 1 { "s" } else { "" },
        list.join(", "),
        p.parts
    )))
}
