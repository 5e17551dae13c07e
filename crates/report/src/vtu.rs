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
    let vtk = Vtk::import(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        return Err("not an unstructured grid".into());
    };
    let piece = pieces
        .into_iter()
        .next()
        .and_then(|p| p.into_loaded_piece_data(None).ok())
        .ok_or("no piece")?;
    let names = |a: &[Attribute]| {
        a.iter()
            .filter_map(|x| match x {
                Attribute::DataArray(d) => Some(d.name.clone()),
                _ => None,
            })
            .collect()
    };
    Ok((
        piece.num_points(),
        piece.cells.types.len(),
        names(&piece.data.point),
        names(&piece.data.cell),
    ))
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
