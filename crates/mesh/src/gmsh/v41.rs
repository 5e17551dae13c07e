//! MSH 4.1 (ASCII and binary) through `mshio`, with the node tags read again
//! where `mshio` drops them.

use super::{find_section, invalid, physical_names, type_name, Block, Raw};
use crate::MeshError;
use std::collections::HashMap;

/// The mesh data of `mshio`'s 4.1 reading.
type MshData = mshio::MshData<u64, i32, f64>;

/// Reads an MSH 4.1 file (ASCII or binary): its nodes with their tags, its
/// element blocks with the physical groups of their entities, and the physical
/// names.
pub(super) fn read_v41(bytes: &[u8]) -> Result<Raw, MeshError> {
    let msh = mshio::parse_msh_bytes(bytes).map_err(|e| {
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
    let msh_nodes = msh
        .data
        .nodes
        .as_ref()
        .ok_or_else(|| invalid("MSH 4.1: no $Nodes section".into()))?;
    let elements = msh
        .data
        .elements
        .as_ref()
        .ok_or_else(|| invalid("MSH 4.1: no $Elements section".into()))?;
    let nodes = tagged_nodes(bytes, &msh.header, msh_nodes)?;
    let blocks = element_blocks(elements, &entity_physicals(&msh.data))?;
    Ok(Raw {
        nodes,
        blocks,
        names,
    })
}

/// The nodes with their tags, in file order. Tags are explicit when `mshio`
/// kept them (sparse), else read again from the file ([`node_tags_v41`]),
/// else implied (min tag + running index).
fn tagged_nodes(
    bytes: &[u8],
    header: &mshio::MshHeader,
    msh_nodes: &mshio::Nodes<u64, i32, f64>,
) -> Result<Vec<(u64, [f64; 3])>, MeshError> {
    let needs_tags = msh_nodes.node_blocks.iter().any(|b| b.node_tags.is_none());
    let reread = if needs_tags {
        node_tags_v41(bytes, header)
    } else {
        None
    };
    let mut nodes = Vec::with_capacity((msh_nodes.num_nodes as usize).min(bytes.len()));
    let mut implicit = msh_nodes.min_node_tag;
    let mut offset = 0usize;
    for block in &msh_nodes.node_blocks {
        let tags: Vec<u64> = match (&block.node_tags, &reread) {
            (Some(map), _) => {
                let mut t = vec![0u64; block.nodes.len()];
                for (&tag, &i) in map {
                    if let Some(slot) = t.get_mut(i) {
                        *slot = tag;
                    }
                }
                t
            }
            (None, Some(all)) => all
                .get(offset..offset + block.nodes.len())
                .ok_or_else(|| invalid("MSH 4.1 $Nodes: node count mismatch".into()))?
                .to_vec(),
            (None, None) => (0..block.nodes.len() as u64)
                .map(|i| implicit + i)
                .collect(),
        };
        implicit += block.nodes.len() as u64;
        offset += block.nodes.len();
        for (tag, p) in tags.into_iter().zip(&block.nodes) {
            nodes.push((tag, [p.x, p.y, p.z]));
        }
    }
    Ok(nodes)
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

/// The node tags of the `$Nodes` section of an MSH 4.1 file, in file order,
/// read directly (ASCII or binary); `None` if the section cannot be followed.
fn node_tags_v41(bytes: &[u8], header: &mshio::MshHeader) -> Option<Vec<u64>> {
    let start = find_section(bytes, "Nodes")?;
    let data = &bytes[start..];
    if header.file_type == 0 {
        let end = data
            .windows(b"$EndNodes".len())
            .position(|w| w == b"$EndNodes")?;
        let text = std::str::from_utf8(&data[..end]).ok()?;
        let mut tok = text.split_ascii_whitespace();
        let mut next = || tok.next();
        let n_blocks: usize = next()?.parse().ok()?;
        let n_nodes: usize = next()?.parse().ok()?;
        next()?;
        next()?;
        let mut tags = Vec::with_capacity(n_nodes.min(data.len()));
        for _ in 0..n_blocks {
            next()?; // entity dim
            next()?; // entity tag
            let parametric: i32 = next()?.parse().ok()?;
            let n: usize = next()?.parse().ok()?;
            if parametric != 0 {
                return None;
            }
            for _ in 0..n {
                tags.push(next()?.parse().ok()?);
            }
            for _ in 0..3 * n {
                next()?;
            }
        }
        (tags.len() == n_nodes).then_some(tags)
    } else {
        let size_t = header.size_t_size;
        if size_t != 4 && size_t != 8 {
            return None;
        }
        let big_endian = binary_is_big_endian(bytes)?;
        let mut pos = 0usize;
        let mut read = |len: usize| -> Option<u64> {
            let b = data.get(pos..pos + len)?;
            pos += len;
            if len > 8 {
                return Some(0); // skipped
            }
            Some(super::uint_of_bytes(b, big_endian))
        };
        let n_blocks = usize::try_from(read(size_t)?).ok()?;
        let n_nodes = usize::try_from(read(size_t)?).ok()?;
        read(size_t)?; // min tag
        read(size_t)?; // max tag
        let mut tags = Vec::with_capacity(n_nodes.min(data.len()));
        for _ in 0..n_blocks {
            read(4)?; // entity dim
            read(4)?; // entity tag
            let parametric = read(4)?;
            let n = usize::try_from(read(size_t)?).ok()?;
            if parametric != 0 {
                return None;
            }
            for _ in 0..n {
                tags.push(read(size_t)?);
            }
            for _ in 0..n {
                read(24)?; // skip x, y, z
            }
        }
        (tags.len() == n_nodes).then_some(tags)
    }
}

/// Byte order of a binary MSH 4.1 file: the int 1 written right after the
/// `$MeshFormat` line.
fn binary_is_big_endian(bytes: &[u8]) -> Option<bool> {
    let start = find_section(bytes, "MeshFormat")?;
    let eol = bytes[start..].iter().position(|&b| b == b'\n')?;
    let one = bytes.get(start + eol + 1..start + eol + 5)?;
    match one {
        [0, 0, 0, 1] => Some(true),
        [1, 0, 0, 0] => Some(false),
        _ => None,
    }
}
