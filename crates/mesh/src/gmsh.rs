//! Gmsh `.msh` import: MSH 4.1 (ASCII and binary, through the `mshio` crate)
//! and MSH 2.2 ASCII (a small parser here; `mshio` reads 4.1 only).
//!
//! What becomes what:
//! * **cells**: the elements of dimension `dim` of the supported types, in
//!   file order: 3-node triangle (Gmsh type 2), 4-node quadrangle (3), 6-node
//!   triangle (9) and 8-node quadrangle (16) in 2D; 4-node tetrahedron (4) and
//!   8-node hexahedron (5) in 3D. Gmsh's node orders of these types are those
//!   of [`CellKind`] (corners first, then the mid-sides of edges 0-1, 1-2, 2-0
//!   or 0-1, 1-2, 2-3, 3-0). Cells given clockwise in 2D (Gmsh surfaces whose
//!   normal is −z) and tetrahedra or hexahedra of negative volume are turned
//!   over, mid-side nodes following their edges.
//! * **surfaces**: every physical group of dimension `dim − 1` becomes a
//!   [`Surface`] named by its physical name (its tag, e.g. `"3"`, when it has
//!   no name). Its facets are those of the cells they bound, matched by their
//!   sorted corner nodes, in the cells' own node order ([`CellKind::facets`]);
//!   a facet element that bounds no cell, or two (an interior interface), is
//!   an error naming the group. When the file has no physical group of
//!   dimension `dim − 1`, the whole boundary ([`Mesh::boundary_facets`]) is
//!   exposed as the surface `"boundary"`.
//! * **regions**: every physical group of dimension `dim` lists its cells in
//!   [`Mesh::regions`].
//! * **nodes**: only the nodes of cells are kept (geometry points and the like
//!   are dropped), numbered densely in the order of the file's `$Nodes`.
//!   In 2D every node must have `|z|` negligible against the mesh size; z is
//!   then set to 0.
//!
//! Points, and elements of dimension lower than `dim − 1`, are ignored. An
//! element of a type that is not supported is an error when it would be a
//! cell (dimension `dim`) or a facet of a physical surface; elements of
//! dimension higher than `dim` are an error too (a 3D file read as 2D).
//!
//! Pitfalls of `mshio` 0.4.2 handled here: it skips `$PhysicalNames` (parsed
//! by hand for both versions); when the node tags of a 4.1 file are dense it
//! drops them (`NodeBlock::node_tags` is `None`) and implies
//! `min_node_tag + running index`, which is wrong for a file whose dense tags
//! are not in increasing block order, so the tags are read again here from
//! the `$Nodes` section (ASCII or binary); its error messages end with a hex
//! dump of the rest of the file, cut off here.

use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::Path;

/// Reads a Gmsh `.msh` file (MSH 4.1 ASCII or binary, MSH 2.2 ASCII) as a mesh
/// of dimension `dim` (2 or 3). See the module documentation for what becomes
/// cells, surfaces and regions. Errors name the file.
pub fn read_msh(path: &Path, dim: usize) -> Result<Mesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|e| {
        MeshError::Invalid(format!("cannot read Gmsh file {}: {e}", path.display()))
    })?;
    parse_msh(&bytes, dim).map_err(|e| MeshError::Invalid(format!("{}: {e}", path.display())))
}

/// Parses the contents of a Gmsh `.msh` file (see [`read_msh`]).
pub fn parse_msh(bytes: &[u8], dim: usize) -> Result<Mesh, MeshError> {
    if dim != 2 && dim != 3 {
        return Err(invalid(format!(
            "a Gmsh mesh is read in 2 or 3 dimensions, not {dim}"
        )));
    }
    let format = mesh_format(bytes)?;
    let raw = match (format.version.as_str(), format.binary) {
        ("4.1", _) => read_v41(bytes)?,
        (v, false) if v == "2" || v.starts_with("2.") => read_v22(bytes)?,
        (v, true) if v == "2" || v.starts_with("2.") => {
            return Err(invalid(format!(
                "MSH {v} binary files are not supported; save the mesh as MSH 4.1 \
                 (`gmsh FILE.msh -save -format msh41 [-bin] -o OUT.msh`) or as MSH 2.2 ASCII"
            )))
        }
        (v, _) => {
            return Err(invalid(format!(
                "MSH version {v} is not supported (supported: 4.1 ASCII or binary, 2.2 ASCII); \
                 convert it with `gmsh FILE.msh -save -format msh41 -o OUT.msh`"
            )))
        }
    };
    build(raw, dim)
}

fn invalid(msg: String) -> MeshError {
    MeshError::Invalid(msg)
}

// ---------------------------------------------------------------------------
// Gmsh element types
// ---------------------------------------------------------------------------

/// Name and dimension of a Gmsh element type, when known.
fn type_info(t: i32) -> Option<(&'static str, usize)> {
    Some(match t {
        1 => ("2-node line", 1),
        2 => ("3-node triangle", 2),
        3 => ("4-node quadrangle", 2),
        4 => ("4-node tetrahedron", 3),
        5 => ("8-node hexahedron", 3),
        6 => ("6-node prism", 3),
        7 => ("5-node pyramid", 3),
        8 => ("3-node line", 1),
        9 => ("6-node triangle", 2),
        10 => ("9-node quadrangle", 2),
        11 => ("10-node tetrahedron", 3),
        12 => ("27-node hexahedron", 3),
        13 => ("18-node prism", 3),
        14 => ("14-node pyramid", 3),
        15 => ("1-node point", 0),
        16 => ("8-node quadrangle", 2),
        17 => ("20-node hexahedron", 3),
        18 => ("15-node prism", 3),
        19 => ("13-node pyramid", 3),
        20 => ("9-node triangle (incomplete 3rd order)", 2),
        21 => ("10-node triangle", 2),
        22 => ("12-node triangle (incomplete 4th order)", 2),
        23 => ("15-node triangle", 2),
        24 => ("15-node triangle (incomplete 5th order)", 2),
        25 => ("21-node triangle", 2),
        26 => ("4-node line", 1),
        27 => ("5-node line", 1),
        28 => ("6-node line", 1),
        29 => ("20-node tetrahedron", 3),
        30 => ("35-node tetrahedron", 3),
        31 => ("56-node tetrahedron", 3),
        36 => ("16-node quadrangle", 2),
        37 => ("25-node quadrangle", 2),
        38 => ("36-node quadrangle", 2),
        92 => ("64-node hexahedron", 3),
        93 => ("125-node hexahedron", 3),
        _ => return None,
    })
}

fn type_name(t: i32) -> String {
    match type_info(t) {
        Some((name, _)) => format!("{name} (type {t})"),
        None => format!("Gmsh element type {t}"),
    }
}

/// The cell kind of a Gmsh element type, when supported in dimension `dim`.
fn cell_kind(t: i32, dim: usize) -> Option<CellKind> {
    match (dim, t) {
        (2, 2) => Some(CellKind::Tri3),
        (2, 3) => Some(CellKind::Quad4),
        (2, 9) => Some(CellKind::Tri6),
        (2, 16) => Some(CellKind::Quad8),
        (3, 4) => Some(CellKind::Tet4),
        (3, 5) => Some(CellKind::Hex8),
        _ => None,
    }
}

/// Number of corner nodes of a supported facet type in dimension `dim`.
fn facet_corners(t: i32, dim: usize) -> Option<usize> {
    match (dim, t) {
        (2, 1) | (2, 8) => Some(2),
        (3, 2) => Some(3),
        (3, 3) => Some(4),
        _ => None,
    }
}

fn supported_list(dim: usize) -> String {
    let (cells, facets): (&[i32], &[i32]) = if dim == 2 {
        (&[2, 3, 9, 16], &[1, 8])
    } else {
        (&[4, 5], &[2, 3])
    };
    let names = |ts: &[i32]| {
        ts.iter()
            .map(|&t| type_name(t))
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "supported in {dim}D: cells {}; facets of physical groups {}",
        names(cells),
        names(facets)
    )
}

// ---------------------------------------------------------------------------
// Version-independent contents of a file
// ---------------------------------------------------------------------------

/// A run of elements of one type and the same physical groups.
struct Block {
    gmsh_type: i32,
    /// Dimension of the elements (from the type, or the entity in 4.1).
    dim: usize,
    /// Physical tags (of dimension `dim`); empty if none.
    physical: Vec<i32>,
    /// Number of nodes of each element.
    n_per: usize,
    /// Node tags, `n_per` per element.
    nodes: Vec<u64>,
}

impl Block {
    fn len(&self) -> usize {
        self.nodes.len().checked_div(self.n_per).unwrap_or(0)
    }
}

struct Raw {
    /// Node tags and coordinates, in file order.
    nodes: Vec<(u64, [f64; 3])>,
    blocks: Vec<Block>,
    /// Physical names by (dimension, tag).
    names: HashMap<(usize, i32), String>,
}

struct Format {
    version: String,
    binary: bool,
}

fn mesh_format(bytes: &[u8]) -> Result<Format, MeshError> {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let rest = &bytes[start..];
    let rest = rest.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(rest);
    let Some(rest) = rest.strip_prefix(b"$MeshFormat") else {
        return Err(invalid(
            "not a Gmsh MSH 2.2 or 4.1 file: it does not start with $MeshFormat".into(),
        ));
    };
    let line: Vec<u8> = rest
        .iter()
        .copied()
        .skip_while(|b| b.is_ascii_whitespace())
        .take_while(|&b| b != b'\n')
        .take(200)
        .collect();
    let line = String::from_utf8_lossy(&line);
    let mut tokens = line.split_whitespace();
    let (Some(version), Some(file_type)) = (tokens.next(), tokens.next()) else {
        return Err(invalid(format!("bad $MeshFormat line \"{}\"", line.trim())));
    };
    let binary = match file_type {
        "0" => false,
        "1" => true,
        _ => {
            return Err(invalid(format!(
                "bad $MeshFormat line \"{}\": file type must be 0 (ASCII) or 1 (binary)",
                line.trim()
            )))
        }
    };
    // "4.1" and "4.10" are the same version; keep the spelling for messages.
    let version = match version.parse::<f64>() {
        Ok(4.1) => "4.1".to_string(),
        Ok(2.2) => "2.2".to_string(),
        _ => version.to_string(),
    };
    Ok(Format { version, binary })
}

/// Finds a section header line `$NAME` (at the start of a line) and returns
/// the offset just after its line break.
fn find_section(bytes: &[u8], name: &str) -> Option<usize> {
    let pat = format!("${name}");
    let pat = pat.as_bytes();
    let mut from = 0;
    while from + pat.len() <= bytes.len() {
        let pos = from + bytes[from..].windows(pat.len()).position(|w| w == pat)?;
        let line_start = pos == 0 || bytes[pos - 1] == b'\n';
        let after = pos + pat.len();
        let rest = &bytes[after..];
        let eol = if rest.starts_with(b"\r\n") {
            Some(2)
        } else if rest.starts_with(b"\n") {
            Some(1)
        } else {
            None
        };
        if let (true, Some(eol)) = (line_start, eol) {
            return Some(after + eol);
        }
        from = pos + 1;
    }
    None
}

/// `$PhysicalNames` (ASCII in both versions and in binary files):
/// `count`, then lines `dim tag "name"`.
fn physical_names(bytes: &[u8]) -> Result<HashMap<(usize, i32), String>, MeshError> {
    let mut names = HashMap::new();
    let Some(start) = find_section(bytes, "PhysicalNames") else {
        return Ok(names);
    };
    let rest = &bytes[start..];
    let end = rest
        .windows(b"$EndPhysicalNames".len())
        .position(|w| w == b"$EndPhysicalNames")
        .ok_or_else(|| invalid("$PhysicalNames has no $EndPhysicalNames".into()))?;
    let text = String::from_utf8_lossy(&rest[..end]);
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    let count: usize = lines
        .next()
        .and_then(|l| l.parse().ok())
        .ok_or_else(|| invalid("$PhysicalNames: bad count".into()))?;
    for _ in 0..count {
        let line = lines
            .next()
            .ok_or_else(|| invalid(format!("$PhysicalNames: fewer than {count} names")))?;
        let bad = || invalid(format!("$PhysicalNames: bad line \"{line}\""));
        let mut it = line.splitn(3, char::is_whitespace);
        let d: usize = it.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let tag: i32 = it.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let name = it.next().unwrap_or("").trim();
        let name = name
            .strip_prefix('"')
            .and_then(|n| n.strip_suffix('"'))
            .unwrap_or(name);
        names.insert((d, tag.abs()), name.to_string());
    }
    Ok(names)
}

// ---------------------------------------------------------------------------
// MSH 2.2 ASCII
// ---------------------------------------------------------------------------

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

fn read_v22(bytes: &[u8]) -> Result<Raw, MeshError> {
    let text = String::from_utf8_lossy(bytes);
    let names = physical_names(bytes)?;

    let lines = section_lines(&text, "Nodes")
        .ok_or_else(|| invalid("MSH 2.2: no $Nodes section".into()))?;
    let count = header_count(&lines, "Nodes")?;
    // a count is the file's word: reserve no more than its lines can hold
    let mut nodes = Vec::with_capacity(count.min(lines.len()));
    for line in &lines[1..] {
        let bad = || invalid(format!("MSH 2.2 $Nodes: bad line \"{line}\""));
        let v: Vec<&str> = line.split_whitespace().collect();
        if v.len() != 4 {
            return Err(bad());
        }
        let tag: u64 = v[0].parse().map_err(|_| bad())?;
        let mut x = [0.0; 3];
        for (xk, s) in x.iter_mut().zip(&v[1..]) {
            *xk = s.parse().map_err(|_| bad())?;
        }
        nodes.push((tag, x));
    }
    if nodes.len() != count {
        return Err(invalid(format!(
            "MSH 2.2 $Nodes announces {count} nodes but lists {}",
            nodes.len()
        )));
    }

    let lines = section_lines(&text, "Elements")
        .ok_or_else(|| invalid("MSH 2.2: no $Elements section".into()))?;
    let count = header_count(&lines, "Elements")?;
    let mut blocks: Vec<Block> = Vec::new();
    for line in &lines[1..] {
        let bad = || invalid(format!("MSH 2.2 $Elements: bad line \"{line}\""));
        let v: Vec<i64> = line
            .split_whitespace()
            .map(|s| s.parse::<i64>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad())?;
        // tag type ntags tags... nodes...
        if v.len() < 3 {
            return Err(bad());
        }
        let gmsh_type = i32::try_from(v[1]).map_err(|_| bad())?;
        let ntags = usize::try_from(v[2]).map_err(|_| bad())?;
        if v.len() < 3 + ntags + 1 {
            return Err(bad());
        }
        let physical = match v.get(3) {
            Some(&p) if ntags > 0 && p != 0 => vec![i32::try_from(p.abs()).map_err(|_| bad())?],
            _ => vec![],
        };
        let node_tags: Vec<u64> = v[3 + ntags..]
            .iter()
            .map(|&n| u64::try_from(n).map_err(|_| bad()))
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
    Ok(Raw {
        nodes,
        blocks,
        names,
    })
}

fn header_count(lines: &[&str], section: &str) -> Result<usize, MeshError> {
    lines
        .first()
        .and_then(|l| l.parse().ok())
        .ok_or_else(|| invalid(format!("MSH 2.2 ${section}: bad count line")))
}

// ---------------------------------------------------------------------------
// MSH 4.1 through mshio
// ---------------------------------------------------------------------------

fn read_v41(bytes: &[u8]) -> Result<Raw, MeshError> {
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

    // Node tags: explicit when mshio kept them (sparse), else read again from
    // the file, else implied (min tag + running index).
    let needs_tags = msh_nodes.node_blocks.iter().any(|b| b.node_tags.is_none());
    let reread = if needs_tags {
        node_tags_v41(bytes, &msh.header)
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

    // Physical tags of each entity, by (dimension, entity tag).
    let mut entity_physicals: HashMap<(usize, i32), Vec<i32>> = HashMap::new();
    if let Some(ent) = &msh.data.entities {
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
    Ok(Raw {
        nodes,
        blocks,
        names,
    })
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
            let mut v = 0u64;
            let mut push = |x: &u8| v = (v << 8) | u64::from(*x);
            if big_endian {
                b.iter().for_each(&mut push);
            } else {
                b.iter().rev().for_each(&mut push);
            }
            Some(v)
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

// ---------------------------------------------------------------------------
// From the file's contents to a Mesh
// ---------------------------------------------------------------------------

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

fn build(raw: Raw, dim: usize) -> Result<Mesh, MeshError> {
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
