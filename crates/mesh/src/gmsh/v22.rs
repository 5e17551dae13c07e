//! MSH 2.2 ASCII, read by a small parser here (`mshio` reads 4.1 only).

use super::{invalid, physical_names, type_info, Block, Raw};
use crate::MeshError;

/// The lines of section `$NAME`, up to `$EndNAME`.
fn section_lines<'a>(text: &'a str, name: &str) -> Option<Vec<&'a str>> {
    let begin = format!("${name}");
    let end = format!("$End{name}");
    let mut lines = text.lines().map(str::trim);
    lines.find(|l| *l == begin)?;
    Some(
        lines
            .take_while(|l| *l != end)
            .filter(|l| !l.is_empty())
            .collect(),
    )
}

/// Reads an MSH 2.2 ASCII file: its `$Nodes`, its `$Elements` gathered into
/// blocks of consecutive elements of one type and physical group, and the
/// physical names; the counts the sections announce must match their lines.
pub(super) fn read_v22(bytes: &[u8]) -> Result<Raw, MeshError> {
    let text = String::from_utf8_lossy(bytes);
    let names = physical_names(bytes)?;
    let nodes = read_nodes(&text)?;
    let blocks = read_element_blocks(&text)?;
    Ok(Raw {
        nodes,
        blocks,
        names,
    })
}

/// The `$Nodes` section: node tags and coordinates, in file order. A file
/// saved with `Mesh.SaveParametric = 1` has `$ParametricNodes` instead, whose
/// lines add the node's entity and parametric coordinates (ignored here).
fn read_nodes(text: &str) -> Result<Vec<(u64, [f64; 3])>, MeshError> {
    let (section, lines) = match section_lines(text, "Nodes") {
        Some(lines) => ("Nodes", lines),
        None => (
            "ParametricNodes",
            section_lines(text, "ParametricNodes")
                .ok_or_else(|| invalid("MSH 2.2: no $Nodes section".into()))?,
        ),
    };
    let parametric = section == "ParametricNodes";
    let count = header_count(&lines, section)?;
    // a count is the file's word: reserve no more than its lines can hold
    let mut nodes = Vec::with_capacity(count.min(lines.len()));
    for line in &lines[1..] {
        let bad = || invalid(format!("MSH 2.2 ${section}: bad line \"{line}\""));
        let v: Vec<&str> = line.split_whitespace().collect();
        if v.len() != 4 && !(parametric && v.len() >= 6) {
            return Err(bad());
        }
        let tag: u64 = v[0].parse().map_err(|_| bad())?;
        let mut x = [0.0; 3];
        for (xk, s) in x.iter_mut().zip(&v[1..4]) {
            *xk = s.parse().map_err(|_| bad())?;
        }
        nodes.push((tag, x));
    }
    if nodes.len() != count {
        return Err(invalid(format!(
            "MSH 2.2 ${section} announces {count} nodes but lists {}",
            nodes.len()
        )));
    }
    Ok(nodes)
}

/// The `$Elements` section: runs of consecutive elements of one type, number of
/// nodes and physical group, each a [`Block`].
fn read_element_blocks(text: &str) -> Result<Vec<Block>, MeshError> {
    let lines = section_lines(text, "Elements")
        .ok_or_else(|| invalid("MSH 2.2: no $Elements section".into()))?;
    let count = header_count(&lines, "Elements")?;
    let mut blocks: Vec<Block> = Vec::new();
    for line in &lines[1..] {
        let bad = || invalid(format!("MSH 2.2 $Elements: bad line \"{line}\""));
        // tag type ntags tags... nodes... (tags of elements and nodes up to
        // 2⁶⁴ − 1, as in $Nodes; the others are ints)
        let v: Vec<&str> = line.split_whitespace().collect();
        if v.len() < 3 {
            return Err(bad());
        }
        let gmsh_type: i32 = v[1].parse().map_err(|_| bad())?;
        let ntags: usize = v[2].parse().map_err(|_| bad())?;
        if v.len() < 3 + ntags + 1 || v[0].parse::<u64>().is_err() {
            return Err(bad());
        }
        let tags: Vec<i32> = v[3..3 + ntags]
            .iter()
            .map(|s| s.parse().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        let physical = match tags.first() {
            Some(&p) if p != 0 => vec![p.checked_abs().ok_or_else(bad)?],
            _ => vec![],
        };
        let node_tags: Vec<u64> = v[3 + ntags..]
            .iter()
            .map(|s| s.parse().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        let n_per = node_tags.len();
        let dim = type_info(gmsh_type).map_or(usize::MAX, |(_, d)| d);
        match blocks.last_mut() {
            Some(b) if b.gmsh_type == gmsh_type && b.physical == physical && b.n_per == n_per => {
                b.nodes.extend(node_tags)
            }
            _ => blocks.push(Block {
                gmsh_type,
                dim,
                physical,
                n_per,
                nodes: node_tags,
            }),
        }
    }
    let listed: usize = blocks.iter().map(Block::len).sum();
    if listed != count {
        return Err(invalid(format!(
            "MSH 2.2 $Elements announces {count} elements but lists {listed}"
        )));
    }
    Ok(blocks)
}

/// The count on the first line of a section's `lines`.
fn header_count(lines: &[&str], section: &str) -> Result<usize, MeshError> {
    lines
        .first()
        .and_then(|l| l.parse().ok())
        .ok_or_else(|| invalid(format!("MSH 2.2 ${section}: bad count line")))
}
