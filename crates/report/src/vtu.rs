//! VTU output for ParaView, through vtkio (notes §4.2): one unstructured
//! grid per body with point data (displacement, contact pressure, status,
//! tangential force) and cell data (stress, von Mises, subdomain), and a
//! `.pvd` index naming them; a `.pvtu` index of the pieces of one grid.

use std::path::Path;

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version,
    VertexNumbers,
};
use vtkio::Vtk;

/// One body's fields.
pub struct VtuPiece<'a> {
    pub title: String,
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

fn cell_type(dim: usize, n: usize) -> Result<CellType, String> {
    match (dim, n) {
        (2, 3) => Ok(CellType::Triangle),
        (2, 4) => Ok(CellType::Quad),
        (2, 6) => Ok(CellType::QuadraticTriangle),
        (2, 8) => Ok(CellType::QuadraticQuad),
        (3, 4) => Ok(CellType::Tetra),
        (3, 8) => Ok(CellType::Hexahedron),
        (d, other) => Err(format!("no VTK cell type for a {other}-node cell in {d}D")),
    }
}

/// Writes one `.vtu` file (XML, ASCII-free binary is left to vtkio's defaults).
pub fn write_vtu(path: &Path, piece: &VtuPiece<'_>) -> Result<(), String> {
    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    let mut types = Vec::new();
    for c in piece.cells {
        connectivity.extend(c.iter().map(|&n| n as u64));
        offsets.push(connectivity.len() as u64);
        types.push(cell_type(piece.dim, c.len())?);
    }
    let points: Vec<f64> = piece
        .coords
        .iter()
        .flat_map(|p| p.iter().copied())
        .collect();
    let attr = |(name, comps, values): &(String, u32, Vec<f64>)| {
        if *comps == 3 {
            Attribute::vectors(name.clone()).with_data(values.clone())
        } else {
            Attribute::scalars(name.clone(), *comps).with_data(values.clone())
        }
    };
    let mut point: Vec<Attribute> = piece.point_data.iter().map(attr).collect();
    if let Some(ids) = piece.node_ids {
        let ids: Vec<u64> = ids.iter().map(|&n| n as u64).collect();
        point.push(Attribute::scalars(NODE_ARRAY, 1).with_data(ids));
    }
    let vtk = Vtk {
        version: Version::new((1, 0)),
        title: piece.title.clone(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: points.into(),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            data: Attributes {
                point,
                cell: piece.cell_data.iter().map(attr).collect(),
            },
        }),
    };
    vtk.export(path)
        .map_err(|e| format!("{}: {e}", path.display()))
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
            title: "t".into(),
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
