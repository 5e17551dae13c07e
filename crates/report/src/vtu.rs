//! VTU output for ParaView (docs/architecture.md, "Libraries"; written here, streamed, and read
//! back through vtkio): one unstructured
//! grid per body with point data (displacement, contact pressure, status,
//! tangential force) and cell data (stress, von Mises, subdomain), and a
//! `.pvd` index naming them; a `.pvtu` index of the pieces of one grid.

use std::path::Path;

use std::io::Write;

use vtkio::model::{Attribute, DataSet};
use vtkio::Vtk;

/// One body's fields.
pub struct VtuPiece<'a> {
    /// Space dimension of the mesh (2 or 3): tells a 4-node quadrilateral
    /// from a tetrahedron.
    pub dim: usize,
    pub coords: &'a [[f64; 3]],
    /// Cells as node lists in the VTK orders (2D: 3 triangle, 4 quadrilateral,
    /// 6 quadratic triangle, 8 quadratic quadrilateral; 3D: 4 tetrahedron, 8
    /// hexahedron).
    pub cells: &'a [Vec<usize>],
    /// (name, components, values) at the points.
    pub point_data: Vec<(String, u32, Vec<f64>)>,
    /// (name, components, values) on the cells.
    pub cell_data: Vec<(String, u32, Vec<f64>)>,
    /// The point array `node` (UInt64): the body node number of each point
    /// (a subdomain's piece; `None` for a whole body).
    pub node_ids: Option<&'a [usize]>,
}

/// The VTK cell type number of an `n`-node cell in `dim` dimensions.
fn cell_type(dim: usize, n: usize) -> Result<u8, String> {
    match (dim, n) {
        (2, 3) => Ok(5),   // VTK_TRIANGLE
        (2, 4) => Ok(9),   // VTK_QUAD
        (2, 6) => Ok(22),  // VTK_QUADRATIC_TRIANGLE
        (2, 8) => Ok(23),  // VTK_QUADRATIC_QUAD
        (3, 4) => Ok(10),  // VTK_TETRA
        (3, 8) => Ok(12),  // VTK_HEXAHEDRON
        (3, 10) => Ok(24), // VTK_QUADRATIC_TETRA (node order of CellKind::Tet10)
        (3, 20) => Ok(25), // VTK_QUADRATIC_HEXAHEDRON (node order of CellKind::Hex20)
        (d, other) => Err(format!("no VTK cell type for a {other}-node cell in {d}D")),
    }
}

/// Writes one `.vtu` file: XML, every array inline in VTK's `binary`
/// format (base64 of a UInt64 byte count and the little-endian values),
/// streamed to the file array by array, so that writing holds no copy of
/// the fields (vtkio's writer held the whole document in memory, several
/// times the fields: 0.5 GB for a 700k-DOF mesh, at the run's peak).
pub fn write_vtu(path: &Path, piece: &VtuPiece<'_>) -> Result<(), String> {
    let types = (piece.cells.iter())
        .map(|c| cell_type(piece.dim, c.len()))
        .collect::<Result<Vec<u8>, String>>()?;
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut w = std::io::BufWriter::new(file);
    write_grid(&mut w, piece, &types)
        .and_then(|()| w.flush())
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The document of [`write_vtu`].
fn write_grid(w: &mut impl Write, piece: &VtuPiece<'_>, types: &[u8]) -> std::io::Result<()> {
    write!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"><UnstructuredGrid><Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\" NumberOfVerts=\"0\">",
        piece.coords.len(),
        piece.cells.len()
    )?;
    let node_ids = piece.node_ids.map(|_| NODE_ARRAY);
    write_attributes(w, "PointData", &piece.point_data, node_ids, |w| {
        let Some(ids) = piece.node_ids else {
            return Ok(());
        };
        data_array(w, "UInt64", Some(NODE_ARRAY), 1, ids.len(), |e| {
            write_le(e, ids.iter().map(|&n| (n as u64).to_le_bytes()))
        })
    })?;
    write_attributes(w, "CellData", &piece.cell_data, None, |_| Ok(()))?;
    w.write_all(b"<Points>")?;
    data_array(w, "Float64", None, 3, 3 * piece.coords.len(), |e| {
        write_le(e, piece.coords.iter().flatten().map(|x| x.to_le_bytes()))
    })?;
    w.write_all(b"</Points><Cells>")?;
    let connectivity = piece.cells.iter().map(Vec::len).sum();
    data_array(w, "UInt64", Some("connectivity"), 1, connectivity, |e| {
        write_le(
            e,
            piece
                .cells
                .iter()
                .flatten()
                .map(|&n| (n as u64).to_le_bytes()),
        )
    })?;
    let offsets = piece.cells.iter().scan(0u64, |end, c| {
        *end += c.len() as u64;
        Some(end.to_le_bytes())
    });
    data_array(w, "UInt64", Some("offsets"), 1, piece.cells.len(), |e| {
        write_le(e, offsets)
    })?;
    data_array(w, "UInt8", Some("types"), 1, types.len(), |e| {
        e.write_all(types)
    })?;
    w.write_all(b"</Cells></Piece></UnstructuredGrid></VTKFile>")
}

/// `<PointData>` or `<CellData>`: the Float64 arrays, then the scalar
/// array `more` writes (named `extra`); the first scalar and the first
/// 3-component array are named active, as ParaView expects.
fn write_attributes<W: Write>(
    w: &mut W,
    tag: &str,
    arrays: &[(String, u32, Vec<f64>)],
    extra: Option<&str>,
    more: impl FnOnce(&mut W) -> std::io::Result<()>,
) -> std::io::Result<()> {
    write!(w, "<{tag}")?;
    let scalars = (arrays.iter().find(|a| a.1 != 3))
        .map(|a| a.0.as_str())
        .or(extra);
    let vectors = arrays.iter().find(|a| a.1 == 3).map(|a| a.0.as_str());
    for (key, name) in [("Scalars", scalars), ("Vectors", vectors)] {
        if let Some(name) = name {
            write!(w, " {key}=\"{}\"", xml_escape(name))?;
        }
    }
    w.write_all(b">")?;
    for (name, comps, values) in arrays {
        data_array(w, "Float64", Some(name), *comps, values.len(), |e| {
            write_le(e, values.iter().map(|x| x.to_le_bytes()))
        })?;
    }
    more(w)?;
    write!(w, "</{tag}>")
}

/// One `<DataArray>` of `len` values of `ty`, written by `values` into a
/// base64 encoder after the UInt64 byte count.
fn data_array<W: Write>(
    w: &mut W,
    ty: &str,
    name: Option<&str>,
    comps: u32,
    len: usize,
    values: impl FnOnce(&mut base64::write::EncoderWriter<&mut W>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    write!(w, "<DataArray type=\"{ty}\"")?;
    if let Some(name) = name {
        write!(w, " Name=\"{}\"", xml_escape(name))?;
    }
    write!(w, " format=\"binary\" NumberOfComponents=\"{comps}\">")?;
    let width: u64 = match ty {
        "UInt8" => 1,
        _ => 8,
    };
    let mut e = base64::write::EncoderWriter::new(&mut *w, base64::STANDARD);
    e.write_all(&(width * len as u64).to_le_bytes())?;
    values(&mut e)?;
    e.finish()?;
    drop(e);
    w.write_all(b"</DataArray>")
}

/// Writes 8-byte little-endian values in blocks (not one call per value).
fn write_le(w: &mut impl Write, values: impl Iterator<Item = [u8; 8]>) -> std::io::Result<()> {
    let mut block = Vec::with_capacity(8 * 1024);
    for v in values {
        block.extend_from_slice(&v);
        if block.len() == block.capacity() {
            w.write_all(&block)?;
            block.clear();
        }
    }
    w.write_all(&block)
}

/// The point array of a piece's body node numbers.
pub const NODE_ARRAY: &str = "node";

/// The arrays a piece holds, as a `.pvtu` index declares them: (name,
/// components, VTK type) at the points, then on the cells.
pub fn declared_arrays(piece: &VtuPiece<'_>) -> [Vec<(String, u32, &'static str)>; 2] {
    let f64s = |d: &[(String, u32, Vec<f64>)]| -> Vec<(String, u32, &'static str)> {
        d.iter()
            .map(|(n, c, _)| (n.clone(), *c, "Float64"))
            .collect()
    };
    let mut point = f64s(&piece.point_data);
    if piece.node_ids.is_some() {
        point.push((NODE_ARRAY.to_string(), 1, "UInt64"));
    }
    [point, f64s(&piece.cell_data)]
}

/// A `.pvtu` index (PUnstructuredGrid): the arrays every piece holds
/// ([`declared_arrays`]), Float64 points, and one `<Piece Source=…/>` per
/// `.vtu` piece (paths relative to the index).
pub fn write_pvtu(
    path: &Path,
    arrays: &[Vec<(String, u32, &'static str)>; 2],
    sources: &[String],
) -> std::io::Result<()> {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n",
    );
    for (tag, list) in ["PPointData", "PCellData"].iter().zip(arrays) {
        s.push_str(&format!("    <{tag}>\n"));
        for (name, comps, ty) in list {
            s.push_str(&format!(
                "      <PDataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{comps}\"/>\n",
                xml_escape(name)
            ));
        }
        s.push_str(&format!("    </{tag}>\n"));
    }
    s.push_str("    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n");
    for src in sources {
        s.push_str(&format!("    <Piece Source=\"{}\"/>\n", xml_escape(src)));
    }
    s.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
    std::fs::write(path, s)
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// One dataset of a `.pvd` collection: a `.vtu` file (path relative to the
/// `.pvd`) at a time step (the load step number) for a part (the body).
pub struct PvdEntry {
    pub timestep: f64,
    pub part: usize,
    pub file: String,
}

/// A `.pvd` collection: the time series of every body's `.vtu` files, which
/// ParaView opens as one animated dataset.
pub fn write_pvd(path: &Path, entries: &[PvdEntry]) -> std::io::Result<()> {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n",
    );
    for e in entries {
        s.push_str(&format!(
            "    <DataSet timestep=\"{}\" part=\"{}\" file=\"{}\"/>\n",
            e.timestep, e.part, e.file
        ));
    }
    s.push_str("  </Collection>\n</VTKFile>\n");
    std::fs::write(path, s)
}

/// Reads a `.vtu` back: (points, cells, point data names, cell data names).
pub fn read_summary(path: &Path) -> Result<(usize, usize, Vec<String>, Vec<String>), String> {
    let g = read_vtu(path)?;
    let names = |a: &[ArrayData]| a.iter().map(|x| x.name.clone()).collect();
    Ok((
        g.points.len(),
        g.cells,
        names(&g.point_data),
        names(&g.cell_data),
    ))
}

/// A data array read back: its values as f64 (empty for a `.pvtu`
/// declaration), its components and its type (vtkio's name of it).
#[derive(Debug, Clone, PartialEq)]
pub struct ArrayData {
    pub name: String,
    pub components: u32,
    pub scalar_type: String,
    pub values: Vec<f64>,
}

/// A `.vtu` grid read back (a `.pvtu` index: its declarations alone).
#[derive(Debug, Clone, Default)]
pub struct GridData {
    pub points: Vec<[f64; 3]>,
    pub cells: usize,
    pub point_data: Vec<ArrayData>,
    pub cell_data: Vec<ArrayData>,
}

fn arrays_of(attributes: Vec<Attribute>) -> Vec<ArrayData> {
    (attributes.into_iter())
        .filter_map(|x| match x {
            Attribute::DataArray(d) => Some(ArrayData {
                name: d.name,
                components: d.elem.num_comp(),
                scalar_type: format!("{:?}", d.data.scalar_type()),
                values: d.data.cast_into::<f64>().unwrap_or_default(),
            }),
            Attribute::Field { .. } => None,
        })
        .collect()
}

fn import(path: &Path) -> Result<DataSet, String> {
    let vtk = Vtk::import(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(vtk.data)
}

/// Reads a `.vtu` file back (its first piece).
pub fn read_vtu(path: &Path) -> Result<GridData, String> {
    let DataSet::UnstructuredGrid { pieces, .. } = import(path)? else {
        return Err(format!("{}: not an unstructured grid", path.display()));
    };
    let piece = pieces
        .into_iter()
        .next()
        .and_then(|p| p.into_loaded_piece_data(None).ok())
        .ok_or_else(|| format!("{}: no piece", path.display()))?;
    let xyz: Vec<f64> = piece.points.cast_into::<f64>().unwrap_or_default();
    Ok(GridData {
        points: xyz.chunks(3).map(|p| [p[0], p[1], p[2]]).collect(),
        cells: piece.cells.types.len(),
        point_data: arrays_of(piece.data.point),
        cell_data: arrays_of(piece.data.cell),
    })
}

/// Reads a `.pvtu` index back: its declared arrays (no values) and the
/// sources of its pieces, as written (relative to the index).
pub fn read_pvtu(path: &Path) -> Result<(GridData, Vec<String>), String> {
    let DataSet::UnstructuredGrid { meta, pieces } = import(path)? else {
        return Err(format!("{}: not an unstructured grid", path.display()));
    };
    let Some(vtkio::model::MetaData::UnstructuredGrid { attributes, .. }) = meta.map(|m| *m) else {
        return Err(format!("{}: not a PUnstructuredGrid", path.display()));
    };
    let declared = |a: Vec<vtkio::model::ArrayMetaData>| {
        a.into_iter()
            .map(|m| ArrayData {
                name: m.name,
                components: m.elem.num_comp(),
                scalar_type: format!("{:?}", m.scalar_type),
                values: Vec::new(),
            })
            .collect()
    };
    let sources = (pieces.into_iter())
        .map(|p| match p {
            vtkio::model::Piece::Source(s, _) => Ok(s),
            _ => Err(format!("{}: a piece without Source", path.display())),
        })
        .collect::<Result<_, _>>()?;
    let grid = GridData {
        point_data: declared(attributes.point_data),
        cell_data: declared(attributes.cell_data),
        ..GridData::default()
    };
    Ok((grid, sources))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_two_cell_mesh_reads_back_with_its_counts_and_fields() {
        let dir = crate::test_dir("vtu");
        let coords = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        let cells = vec![vec![0, 1, 2, 3], vec![1, 4, 2]];
        let piece = VtuPiece {
            dim: 2,
            coords: &coords,
            cells: &cells,
            point_data: vec![
                ("displacement".into(), 3, vec![0.5; 15]),
                ("contact_pressure".into(), 1, vec![1.0; 5]),
            ],
            cell_data: vec![("von_mises".into(), 1, vec![2.0, 3.0])],
            node_ids: None,
        };
        let path = dir.join("b.vtu");
        write_vtu(&path, &piece).unwrap();
        let (np, nc, pd, cd) = read_summary(&path).unwrap();
        assert_eq!((np, nc), (5, 2));
        assert_eq!(pd, vec!["displacement", "contact_pressure"]);
        assert_eq!(cd, vec!["von_mises"]);
        // The values come back through vtkio's reader, not ours.
        let g = read_vtu(&path).unwrap();
        assert_eq!(g.points, coords.to_vec());
        assert_eq!(g.point_data[0].values, vec![0.5; 15]);
        assert_eq!(g.cell_data[0].values, vec![2.0, 3.0]);
        let ids = [7, 1, 9, 3, 1 << 40];
        let with_ids = VtuPiece {
            dim: 2,
            coords: &coords,
            cells: &cells,
            point_data: Vec::new(),
            cell_data: Vec::new(),
            node_ids: Some(&ids),
        };
        write_vtu(&path, &with_ids).unwrap();
        let g = read_vtu(&path).unwrap();
        assert_eq!(g.point_data[0].name, NODE_ARRAY);
        assert_eq!(g.point_data[0].scalar_type, "U64");
        assert_eq!(g.point_data[0].values, ids.map(|n| n as f64).to_vec());
        let bad = vec![vec![0, 1]];
        assert!(write_vtu(
            &path,
            &VtuPiece {
                cells: &bad,
                ..piece
            }
        )
        .is_err());
    }
}
