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
//!   [`Surface`](crate::Surface) named by its physical name (its tag, e.g. `"3"`, when it has
//!   no name). Its facets are those of the cells they bound, matched by their
//!   sorted corner nodes, in the cells' own node order ([`CellKind::facets`]);
//!   a facet element that bounds no cell, or two (an interior interface), is
//!   an error naming the group. When the file has no physical group of
//!   dimension `dim − 1`, the whole boundary ([`Mesh::boundary_facets`]) is
//!   exposed as the surface `"boundary"`.
//! * **regions**: every physical group of dimension `dim` lists its cells in
//!   [`Mesh::regions`]; with a `volume` ([`read_msh_volume`]) the cells of
//!   that group alone are read, one body of an assembly ([`select`]).
//! * **node sets**: every physical group of dimension below `dim − 1`
//!   (points; curves in 3D) lists its nodes in [`Mesh::node_sets`].
//! * **nodes**: only the nodes of cells are kept (geometry points and the like
//!   are dropped), numbered densely in the order of the file's `$Nodes`.
//!   In 2D every node must have `|z|` negligible against the mesh size; z is
//!   then set to 0.
//!
//! Points, and elements of dimension lower than `dim − 1`, give node sets only. An
//! element of a type that is not supported is an error when it would be a
//! cell (dimension `dim`) or a facet of a physical surface; elements of
//! dimension higher than `dim` are an error too (a 3D file read as 2D).
//!
//! Variants Gmsh writes that are read too: partitioned files
//! (`gmsh.model.mesh.partition`: the elements of 4.1 files lie on the
//! entities of `$PartitionedEntities`, which carry the physical groups),
//! parametric nodes (`Mesh.SaveParametric`: node blocks with parametric
//! coordinates in 4.1, `$ParametricNodes` in 2.2; those coordinates are
//! ignored), node tags in any order and up to 2⁶⁴ − 1. One file of a
//! partitioned mesh saved one file per partition
//! (`Mesh.PartitionSplitMeshFiles = 1`) is refused: it holds a piece only.
//!
//! Pitfalls of `mshio` 0.4.2 handled here: it skips `$PhysicalNames` and
//! `$PartitionedEntities` (both parsed by hand); it refuses parametric nodes,
//! and when the node tags of a 4.1 file are dense it drops them and implies
//! `min_node_tag + running index`, wrong for dense tags not in increasing
//! block order, so the `$Nodes` section is read here (ASCII or binary,
//! [`fields`]) and cut out of what `mshio` parses; its error messages end
//! with a hex dump of the rest of the file, cut off here.

mod build;
mod fields;
mod select;
mod v22;
mod v41;

use crate::{CellKind, Mesh, MeshError};
use build::build;
use std::collections::HashMap;
use std::path::Path;
use v22::read_v22;
use v41::read_v41;

/// Reads a Gmsh `.msh` file (MSH 4.1 ASCII or binary, MSH 2.2 ASCII) as a mesh
/// of dimension `dim` (2 or 3). See the module documentation for what becomes
/// cells, surfaces and regions. Errors name the file.
pub fn read_msh(path: &Path, dim: usize) -> Result<Mesh, MeshError> {
    read_msh_volume(path, dim, None)
}

/// Reads one body of a Gmsh file: with `volume`, the cells of the physical
/// group of dimension `dim` of that name alone, with the file's surfaces and
/// node sets restricted to its nodes (the module [`select`]); without, the
/// whole file as [`read_msh`].
pub fn read_msh_volume(path: &Path, dim: usize, volume: Option<&str>) -> Result<Mesh, MeshError> {
    // A device or a pipe has no size: the memory estimate (which reads the
    // header and the file's size) cannot bound it, and reading may not end.
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        return Err(MeshError::Invalid(format!(
            "cannot read Gmsh file {}: not a regular file",
            path.display()
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| {
        MeshError::Invalid(format!("cannot read Gmsh file {}: {e}", path.display()))
    })?;
    parse_msh_volume(&bytes, dim, volume)
        .map_err(|e| MeshError::Invalid(format!("{}: {e}", path.display())))
}

/// Parses the contents of a Gmsh `.msh` file (see [`read_msh`]).
pub fn parse_msh(bytes: &[u8], dim: usize) -> Result<Mesh, MeshError> {
    parse_msh_volume(bytes, dim, None)
}

/// Parses one body of the contents of a Gmsh `.msh` file (see
/// [`read_msh_volume`]).
pub fn parse_msh_volume(bytes: &[u8], dim: usize, volume: Option<&str>) -> Result<Mesh, MeshError> {
    if dim != 2 && dim != 3 {
        return Err(invalid(format!(
            "a Gmsh mesh is read in 2 or 3 dimensions, not {dim}"
        )));
    }
    let format = mesh_format(bytes)?;
    let raw = match (format.version.as_str(), format.binary) {
        ("4.1", _) => read_v41(bytes, &format)?,
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
    if let Some((tag, x)) = raw
        .nodes
        .iter()
        .find(|(_, x)| !x.iter().all(|c| c.is_finite()))
    {
        return Err(invalid(format!(
            "node {tag} has a coordinate that is not a finite number: {x:?}"
        )));
    }
    let mesh = build(raw, dim, volume)?;
    crate::partition::check_conforming(&mesh)?;
    Ok(mesh)
}

/// The error for a bad file, with message `msg`.
/// The unsigned integer of the bytes `b` (at most 8) of a binary file, in
/// its byte order.
pub fn uint_of_bytes(b: &[u8], big_endian: bool) -> u64 {
    let mut v = 0u64;
    let mut push = |x: &u8| v = (v << 8) | u64::from(*x);
    if big_endian {
        b.iter().for_each(&mut push);
    } else {
        b.iter().rev().for_each(&mut push);
    }
    v
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

/// A Gmsh element type as messages name it: "name (type t)", or the bare
/// number when unknown.
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
        (3, 11) => Some(CellKind::Tet10),
        (3, 17) => Some(CellKind::Hex20),
        _ => None,
    }
}

/// Number of corner nodes of a supported facet type in dimension `dim`.
fn facet_corners(t: i32, dim: usize) -> Option<usize> {
    match (dim, t) {
        (2, 1) | (2, 8) => Some(2),
        (3, 2) => Some(3),
        (3, 3) | (3, 16) => Some(4),
        (3, 9) => Some(3),
        _ => None,
    }
}

/// The sentence listing the supported cell and facet types in dimension `dim`.
fn supported_list(dim: usize) -> String {
    let (cells, facets): (&[i32], &[i32]) = if dim == 2 {
        (&[2, 3, 9, 16], &[1, 8])
    } else {
        (&[4, 5, 11, 17], &[2, 3, 9, 16])
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
    /// Number of elements in the block.
    fn len(&self) -> usize {
        self.nodes.len().checked_div(self.n_per).unwrap_or(0)
    }
}

/// A file's contents, whatever its version.
struct Raw {
    /// Node tags and coordinates, in file order.
    nodes: Vec<(u64, [f64; 3])>,
    blocks: Vec<Block>,
    /// Physical names by (dimension, tag).
    names: Names,
}

/// Physical names by (dimension, tag).
type Names = HashMap<(usize, i32), String>;

/// The name of physical group `tag` of dimension `dim`: its physical name, or
/// the tag itself when it has none.
fn group_name(names: &Names, dim: usize, tag: i32) -> String {
    match names.get(&(dim, tag)) {
        Some(name) if !name.is_empty() => name.clone(),
        _ => tag.to_string(),
    }
}

/// Node tags → index in the file's `$Nodes` order.
struct NodeTags(HashMap<u64, usize>);

impl NodeTags {
    /// Indexes the tags of `raw_nodes`; a tag listed twice is an error.
    fn new(raw_nodes: &[(u64, [f64; 3])]) -> Result<NodeTags, MeshError> {
        let mut by_tag: HashMap<u64, usize> = HashMap::with_capacity(raw_nodes.len());
        for (i, (tag, _)) in raw_nodes.iter().enumerate() {
            if by_tag.insert(*tag, i).is_some() {
                return Err(invalid(format!("node tag {tag} appears twice in $Nodes")));
            }
        }
        Ok(NodeTags(by_tag))
    }

    /// The index of node `tag`; an error if `$Nodes` does not list it.
    fn lookup(&self, tag: u64) -> Result<usize, MeshError> {
        self.0.get(&tag).copied().ok_or_else(|| {
            invalid(format!(
                "an element refers to node {tag}, which is not in $Nodes"
            ))
        })
    }
}

/// The `$MeshFormat` line: version (as spelled for messages) and whether the
/// file is binary.
struct Format {
    version: String,
    binary: bool,
    /// The size of `size_t` in a binary file (the line's third number).
    size_t: usize,
}

/// Reads the `$MeshFormat` line that must start the file.
fn mesh_format(bytes: &[u8]) -> Result<Format, MeshError> {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let rest = &bytes[start..];
    let rest = rest.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(rest);
    let Some(rest) = rest.strip_prefix(b"$MeshFormat") else {
        // MSH 1.0, which Gmsh still writes (Mesh.MshFileVersion = 1), opens
        // with $NOD
        let what = if rest.starts_with(b"$NOD") {
            "an MSH 1.0 file (it starts with $NOD), which is not supported; convert it \
             with `gmsh FILE.msh -save -format msh41 -o OUT.msh`"
        } else {
            "not a Gmsh MSH 2.2 or 4.1 file: it does not start with $MeshFormat"
        };
        return Err(invalid(what.into()));
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
    let size_t = data_size(binary, tokens.next(), &line)?;
    // "4.1" and "4.10" are the same version; keep the spelling for messages.
    let version = match version.parse::<f64>() {
        Ok(4.1) => "4.1".to_string(),
        Ok(2.2) => "2.2".to_string(),
        _ => version.to_string(),
    };
    Ok(Format {
        version,
        binary,
        size_t,
    })
}

/// The size of `size_t` from the third number `token` of the `$MeshFormat`
/// line `line`: 4 or 8 in a binary file, unused (8) in an ASCII one.
fn data_size(binary: bool, token: Option<&str>, line: &str) -> Result<usize, MeshError> {
    match (binary, token.and_then(|t| t.parse().ok())) {
        (_, Some(n @ (4 | 8))) => Ok(n),
        (false, _) => Ok(8),
        (true, _) => Err(invalid(format!(
            "bad $MeshFormat line \"{}\": the data size of a binary file must be 4 or 8",
            line.trim()
        ))),
    }
}

/// Finds a section header line `$NAME` (at the start of a line) and returns
/// the offset just after its line break.
fn find_section(bytes: &[u8], name: &str) -> Option<usize> {
    find_section_span(bytes, name).map(|(_, after)| after)
}

/// Finds a section header line `$NAME` (at the start of a line) and returns
/// the offsets of its `$` and just after its line break.
fn find_section_span(bytes: &[u8], name: &str) -> Option<(usize, usize)> {
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
            return Some((pos, after + eol));
        }
        from = pos + 1;
    }
    None
}

/// `$PhysicalNames` (ASCII in both versions and in binary files):
/// `count`, then lines `dim tag "name"`.
fn physical_names(bytes: &[u8]) -> Result<Names, MeshError> {
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
        if let Some(before) = names.insert((d, tag.abs()), name.to_string()) {
            return Err(invalid(format!(
                "$PhysicalNames names the physical group of dimension {d} and tag {} twice \
                 (\"{before}\" and \"{name}\"): give each group one name",
                tag.abs()
            )));
        }
    }
    check_names_unique(&names)?;
    Ok(names)
}

/// Two physical groups of one dimension under one name would be read as one
/// surface or region: refused, naming both tags.
fn check_names_unique(names: &Names) -> Result<(), MeshError> {
    let mut seen: HashMap<(usize, &str), i32> = HashMap::new();
    let mut sorted: Vec<_> = names.iter().filter(|(_, n)| !n.is_empty()).collect();
    sorted.sort();
    for (&(d, tag), name) in sorted {
        if let Some(first) = seen.insert((d, name.as_str()), tag) {
            return Err(invalid(format!(
                "$PhysicalNames names two physical groups of dimension {d} \"{name}\" \
                 (tags {first} and {tag}): they would be read as one group; give them \
                 different names, or make them one physical group in Gmsh"
            )));
        }
    }
    Ok(())
}
