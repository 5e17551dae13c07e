//! Gmsh import: MSH 2.2 ASCII and MSH 4.1 ASCII/binary.
//!
//! The files under `tests/data/` and `examples/meshes/` were written by Gmsh
//! 4.8.4 (no Gmsh is needed to run these tests):
//!   cd examples/meshes
//!   gmsh -2 block2d.geo -o block2d.msh
//!   gmsh -3 block3d.geo -o block3d.msh
//!   gmsh block2d.msh -save -format msh22 -o ../../crates/mesh/tests/data/block2d_v22.msh
//!   gmsh block2d.msh -save -bin -o ../../crates/mesh/tests/data/block2d_bin.msh
//! (the 2.2 and binary twins are conversions of the same mesh; `-format msh22`
//! on the .geo would be overridden by its `Mesh.MshFileVersion = 4.1`).

use signorini_mesh::gmsh::{parse_msh, read_msh};
use signorini_mesh::{CellKind, Mesh, MeshError};
use std::path::{Path, PathBuf};

fn manifest() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn examples() -> PathBuf {
    manifest().join("../../examples/meshes")
}

fn parse(text: &str, dim: usize) -> Mesh {
    match parse_msh(text.as_bytes(), dim) {
        Ok(m) => m,
        Err(e) => panic!("parse failed: {e}"),
    }
}

fn parse_err(text: &str, dim: usize) -> String {
    match parse_msh(text.as_bytes(), dim) {
        Ok(m) => panic!("expected an error, got a mesh of {} cells", m.cells.len()),
        Err(MeshError::Invalid(msg)) => msg,
        Err(e) => panic!("unexpected error kind: {e}"),
    }
}

/// Area of a 2D mesh from the corners of its cells (each must be positive).
fn area(mesh: &Mesh) -> f64 {
    mesh.cells
        .iter()
        .map(|c| {
            let m = c.kind.corners();
            let a: f64 = (0..m)
                .map(|i| {
                    let (p, q) = (mesh.coords[c.nodes[i]], mesh.coords[c.nodes[(i + 1) % m]]);
                    p[0] * q[1] - q[0] * p[1]
                })
                .sum::<f64>()
                / 2.0;
            assert!(a > 0.0, "clockwise cell {c:?}");
            a
        })
        .sum()
}

/// Volume enclosed by the boundary of a 3D mesh, ∮ x·n dA / 3 (exact for
/// planar facets): checks the facets' outward normals as well.
fn volume(mesh: &Mesh) -> f64 {
    mesh.boundary_facets()
        .iter()
        .map(|f| {
            let (n, a) = mesh.facet_normal(f);
            let k = f.nodes.len() as f64;
            let mut x = [0.0; 3];
            for &v in &f.nodes {
                for (xd, cd) in x.iter_mut().zip(mesh.coords[v]) {
                    *xd += cd / k;
                }
            }
            (x[0] * n[0] + x[1] * n[1] + x[2] * n[2]) * a / 3.0
        })
        .sum()
}

/// Sum of the tetrahedra's volumes (each must be positive).
fn tet_volume(mesh: &Mesh) -> f64 {
    mesh.cells
        .iter()
        .map(|c| {
            assert_eq!(c.kind, CellKind::Tet4);
            let p: Vec<[f64; 3]> = c.nodes.iter().map(|&n| mesh.coords[n]).collect();
            let u = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
            let v = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
            let w = [p[3][0] - p[0][0], p[3][1] - p[0][1], p[3][2] - p[0][2]];
            let vol = (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]))
                / 6.0;
            assert!(vol > 0.0);
            vol
        })
        .sum()
}

/// Length (2D) or area (3D) of a surface.
fn measure(mesh: &Mesh, name: &str) -> f64 {
    mesh.surface(name)
        .unwrap()
        .facets
        .iter()
        .map(|f| mesh.facet_normal(f).1)
        .sum()
}

/// Every facet of a surface is the facet of its cell, in the cell's order,
/// and its normal is `n`.
fn check_surface(mesh: &Mesh, name: &str, n: [f64; 3]) {
    for f in &mesh.surface(name).unwrap().facets {
        let cell = &mesh.cells[f.cell];
        assert!(
            cell.kind
                .facets()
                .iter()
                .any(|l| l.iter().map(|&i| cell.nodes[i]).collect::<Vec<_>>() == f.nodes),
            "facet {f:?} is not a facet of its cell"
        );
        let (m, _) = mesh.facet_normal(f);
        for k in 0..3 {
            assert!(
                (m[k] - n[k]).abs() < 1e-12,
                "{name}: normal {m:?}, expected {n:?}"
            );
        }
    }
}

/// Mid-side nodes lie in the middle of their edges.
fn check_midsides(mesh: &Mesh) {
    for c in &mesh.cells {
        for l in c.kind.facets() {
            if l.len() == 3 && c.kind.dim() == 2 {
                let (a, b, m) = (
                    mesh.coords[c.nodes[l[0]]],
                    mesh.coords[c.nodes[l[1]]],
                    mesh.coords[c.nodes[l[2]]],
                );
                for k in 0..3 {
                    assert!((m[k] - (a[k] + b[k]) / 2.0).abs() < 1e-14, "cell {c:?}");
                }
            }
        }
    }
}

fn names<T>(map: &std::collections::BTreeMap<String, T>) -> Vec<&str> {
    map.keys().map(String::as_str).collect()
}

// ---------------------------------------------------------------------------
// MSH 2.2
// ---------------------------------------------------------------------------

/// Unit square of two triangles, the second clockwise; a geometry point
/// element and an unused node (tag 99) are dropped.
const SQUARE_TRI_V22: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 \"bottom\"
1 2 \"top\"
2 3 \"square\"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
99 5 5 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
5
1 15 2 0 1 1
2 1 2 1 1 1 2
3 1 2 2 3 3 4
4 2 2 3 1 1 2 3
5 2 2 3 1 1 4 3
$EndElements
";

#[test]
fn v22_square_of_two_triangles() {
    let m = parse(SQUARE_TRI_V22, 2);
    assert_eq!(m.dim, 2);
    assert_eq!(m.n_nodes(), 4);
    assert_eq!(m.cells.len(), 2);
    assert!(m.cells.iter().all(|c| c.kind == CellKind::Tri3));
    assert!((area(&m) - 1.0).abs() < 1e-14);
    assert_eq!(names(&m.surfaces), ["bottom", "top"]);
    assert_eq!(m.surfaces["bottom"].facets.len(), 1);
    assert_eq!(m.surfaces["top"].facets.len(), 1);
    assert!((measure(&m, "bottom") - 1.0).abs() < 1e-14);
    assert!((measure(&m, "top") - 1.0).abs() < 1e-14);
    check_surface(&m, "bottom", [0.0, -1.0, 0.0]);
    check_surface(&m, "top", [0.0, 1.0, 0.0]);
    assert_eq!(m.regions["square"], vec![0, 1]);
    // Nodes keep the file's order: (0,0), (1,0), (1,1), (0,1).
    assert_eq!(m.coords[2], [1.0, 1.0, 0.0]);
}

#[test]
fn v22_without_physical_groups_gives_the_boundary() {
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n\
                4 0 1 0\n$EndNodes\n$Elements\n2\n1 2 2 0 1 1 2 3\n2 2 2 0 1 1 3 4\n$EndElements\n";
    let m = parse(text, 2);
    assert_eq!(names(&m.surfaces), ["boundary"]);
    assert_eq!(m.surfaces["boundary"].facets.len(), 4);
    assert!((measure(&m, "boundary") - 4.0).abs() < 1e-14);
    assert!(m.regions.is_empty());
}

/// Unit cube as one hexahedron, given upside down (negative volume), with
/// physical quadrangles at z = 0 and z = 1 and no physical names.
#[test]
fn v22_tags_up_to_u64_max() {
    // Node tags up to 2⁶⁴ − 1 were read in $Nodes but refused in $Elements
    // ("bad line": the element lines were parsed as i64).
    let big = |t: u64| (u64::MAX - 10 + t).to_string();
    let mut text = SQUARE_TRI_V22.to_string();
    for (old, new) in [
        ("\n1 0 0 0\n", format!("\n{} 0 0 0\n", big(1))),
        ("\n2 1 0 0\n", format!("\n{} 1 0 0\n", big(2))),
        ("\n3 1 1 0\n", format!("\n{} 1 1 0\n", big(3))),
        ("\n4 0 1 0\n", format!("\n{} 0 1 0\n", big(4))),
        (
            "1 15 2 0 1 1\n",
            format!("{} 15 2 0 1 {}\n", big(0), big(1)),
        ),
        (
            "2 1 2 1 1 1 2\n",
            format!("2 1 2 1 1 {} {}\n", big(1), big(2)),
        ),
        (
            "3 1 2 2 3 3 4\n",
            format!("3 1 2 2 3 {} {}\n", big(3), big(4)),
        ),
        (
            "4 2 2 3 1 1 2 3\n",
            format!("4 2 2 3 1 {} {} {}\n", big(1), big(2), big(3)),
        ),
        (
            "5 2 2 3 1 1 4 3\n",
            format!("5 2 2 3 1 {} {} {}\n", big(1), big(4), big(3)),
        ),
    ] {
        assert!(text.contains(old), "{old}");
        text = text.replace(old, &new);
    }
    same_mesh(&parse(&text, 2), &parse(SQUARE_TRI_V22, 2));
}

#[test]
fn msh_1_is_named() {
    let e = parse_err("$NOD\n1\n1 0 0 0\n$ENDNOD\n$ELM\n0\n$ENDELM\n", 2);
    assert!(e.contains("MSH 1.0") && e.contains("-format msh41"), "{e}");
}

#[test]
fn a_2d_mesh_read_as_3d_says_so() {
    let e = parse_err(SQUARE_TRI_V22, 3);
    assert!(e.contains("no cell of dimension 3"), "{e}");
    assert!(e.contains("if it is a 2D mesh, set dimension = 2"), "{e}");
}

#[test]
fn v22_cube_of_one_hexahedron() {
    let nodes = "$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n5 0 0 1\n6 1 0 1\n7 0 1 1\n\
                 8 1 1 1\n$EndNodes\n";
    for hex in ["1 2 4 3 5 6 8 7", "5 6 8 7 1 2 4 3"] {
        let text = format!(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n{nodes}$Elements\n3\n\
             1 3 2 11 1 1 3 4 2\n2 3 2 12 2 5 6 8 7\n3 5 2 13 1 {hex}\n$EndElements\n"
        );
        let m = parse(&text, 3);
        assert_eq!((m.n_nodes(), m.cells.len()), (8, 1));
        assert_eq!(m.cells[0].kind, CellKind::Hex8);
        assert!((volume(&m) - 1.0).abs() < 1e-14);
        assert_eq!(names(&m.surfaces), ["11", "12"]);
        assert!((measure(&m, "11") - 1.0).abs() < 1e-14);
        check_surface(&m, "11", [0.0, 0.0, -1.0]);
        check_surface(&m, "12", [0.0, 0.0, 1.0]);
        assert_eq!(m.regions["13"], vec![0]);
    }
}

/// Second-order cells given clockwise are turned over with their mid-side
/// nodes; a 3-node line is a facet of a physical group.
#[test]
fn v22_second_order_cells_turned_over() {
    let tri = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n\
               4 0.5 0 0\n5 0.5 0.5 0\n6 0 0.5 0\n$EndNodes\n$Elements\n2\n\
               1 8 2 1 1 1 2 4\n2 9 2 2 1 ELEMENT\n$EndElements\n";
    for el in ["1 2 3 4 5 6", "1 3 2 6 5 4"] {
        let m = parse(&tri.replace("ELEMENT", el), 2);
        assert_eq!(m.cells[0].kind, CellKind::Tri6);
        assert_eq!(m.cells[0].nodes[..3], [0, 1, 2]);
        check_midsides(&m);
        assert!((area(&m) - 0.5).abs() < 1e-14);
        assert_eq!(m.surfaces["1"].facets.len(), 1);
        assert_eq!(m.surfaces["1"].facets[0].nodes, vec![0, 1, 3]);
        check_surface(&m, "1", [0.0, -1.0, 0.0]);
    }
    let quad = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n\
                4 0 1 0\n5 0.5 0 0\n6 1 0.5 0\n7 0.5 1 0\n8 0 0.5 0\n$EndNodes\n$Elements\n2\n\
                1 8 2 1 1 3 4 7\n2 16 2 2 1 ELEMENT\n$EndElements\n";
    for el in ["1 2 3 4 5 6 7 8", "1 4 3 2 8 7 6 5"] {
        let m = parse(&quad.replace("ELEMENT", el), 2);
        assert_eq!(m.cells[0].kind, CellKind::Quad8);
        check_midsides(&m);
        assert!((area(&m) - 1.0).abs() < 1e-14);
        check_surface(&m, "1", [0.0, 1.0, 0.0]);
        assert_eq!(m.regions["2"], vec![0]);
    }
}

// ---------------------------------------------------------------------------
// MSH 4.1
// ---------------------------------------------------------------------------

/// Unit square of four quadrangles (3 × 3 nodes). The node tags are dense but
/// the blocks list 5..9 before 1..4: mshio's implied tags would be wrong. The
/// surface's physical group (3) has no name.
const SQUARE_QUAD_V41: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
1 1 \"bottom\"
1 2 \"top\"
$EndPhysicalNames
$Entities
4 4 1 0
1 0 0 0 0
2 1 0 0 0
3 1 1 0 0
4 0 1 0 0
1 0 0 0 1 0 0 1 1 2 1 -2
2 1 0 0 1 1 0 0 2 2 -3
3 0 1 0 1 1 0 1 2 2 3 -4
4 0 0 0 0 1 0 0 2 4 -1
1 0 0 0 1 1 0 1 3 4 1 2 3 4
$EndEntities
$Nodes
2 9 1 9
2 1 0 5
5
6
7
8
9
0.5 0.5 0
1 0.5 0
0 1 0
0.5 1 0
1 1 0
1 1 0 4
1
2
3
4
0 0 0
0.5 0 0
1 0 0
0 0.5 0
$EndNodes
$Elements
3 8 1 8
1 1 1 2
1 1 2
2 2 3
1 3 1 2
3 9 8
4 8 7
2 1 3 4
5 1 2 5 4
6 2 3 6 5
7 4 5 8 7
8 5 6 9 8
$EndElements
";

#[test]
fn v41_square_of_four_quadrangles() {
    let m = parse(SQUARE_QUAD_V41, 2);
    assert_eq!((m.n_nodes(), m.cells.len()), (9, 4));
    assert!(m.cells.iter().all(|c| c.kind == CellKind::Quad4));
    assert!((area(&m) - 1.0).abs() < 1e-14);
    // every cell is a square of side 1/2 (wrong tags would distort them)
    for c in 0..4 {
        let x = m.cell_centroid(c);
        assert!(((x[0] - 0.25) * 4.0).fract().abs() < 1e-14, "{x:?}");
        assert!(((x[1] - 0.25) * 4.0).fract().abs() < 1e-14, "{x:?}");
    }
    assert_eq!(names(&m.surfaces), ["bottom", "top"]);
    assert_eq!(m.surfaces["bottom"].facets.len(), 2);
    assert_eq!(m.surfaces["top"].facets.len(), 2);
    assert!((measure(&m, "bottom") - 1.0).abs() < 1e-14);
    check_surface(&m, "bottom", [0.0, -1.0, 0.0]);
    check_surface(&m, "top", [0.0, 1.0, 0.0]);
    assert_eq!(names(&m.regions), ["3"]);
    assert_eq!(m.regions["3"], vec![0, 1, 2, 3]);
}

/// Unit cube of six tetrahedra around the diagonal (Kuhn), half of them of
/// negative volume as given; physical triangles at z = 0 and z = 1.
const CUBE_TET_V41: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
2 1 \"bottom\"
2 2 \"top\"
3 3 \"cube\"
$EndPhysicalNames
$Entities
0 0 2 1
1 0 0 0 1 1 0 1 1 0
2 0 0 1 1 1 1 1 2 0
1 0 0 0 1 1 1 1 3 2 1 2
$EndEntities
$Nodes
1 8 1 8
3 1 0 8
1
2
3
4
5
6
7
8
0 0 0
1 0 0
0 1 0
1 1 0
0 0 1
1 0 1
0 1 1
1 1 1
$EndNodes
$Elements
3 10 1 10
2 1 2 2
1 1 2 4
2 1 4 3
2 2 2 2
3 5 6 8
4 5 8 7
3 1 4 6
5 1 2 4 8
6 1 3 4 8
7 1 2 6 8
8 1 5 6 8
9 1 3 7 8
10 1 5 7 8
$EndElements
";

#[test]
fn v41_cube_of_six_tetrahedra() {
    let m = parse(CUBE_TET_V41, 3);
    assert_eq!((m.n_nodes(), m.cells.len()), (8, 6));
    assert!((tet_volume(&m) - 1.0).abs() < 1e-14);
    assert!((volume(&m) - 1.0).abs() < 1e-14);
    assert_eq!(names(&m.surfaces), ["bottom", "top"]);
    assert_eq!(m.surfaces["bottom"].facets.len(), 2);
    assert_eq!(m.surfaces["top"].facets.len(), 2);
    assert!((measure(&m, "bottom") - 1.0).abs() < 1e-14);
    assert!((measure(&m, "top") - 1.0).abs() < 1e-14);
    check_surface(&m, "bottom", [0.0, 0.0, -1.0]);
    check_surface(&m, "top", [0.0, 0.0, 1.0]);
    assert_eq!(m.regions["cube"], vec![0, 1, 2, 3, 4, 5]);
}

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

#[test]
fn unsupported_element_type_is_named_and_counted() {
    // two 14-node pyramids (type 14): only the ids matter here
    let mut text = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n14\n");
    for i in 1..=14 {
        text += &format!("{i} {} {} {}\n", i % 2, (i / 2) % 2, i / 4);
    }
    let ids: Vec<String> = (1..=14).map(|i| i.to_string()).collect();
    let ids = ids.join(" ");
    text += &format!(
        "$EndNodes\n$Elements\n3\n1 14 2 1 1 {ids}\n2 14 2 1 1 {ids}\n3 15 2 0 1 1\n$EndElements\n"
    );
    let e = parse_err(&text, 3);
    assert!(e.contains("2 × 14-node pyramid (type 14)"), "{e}");
    assert!(e.contains("4-node tetrahedron (type 4)"), "{e}");
    assert!(e.contains("8-node hexahedron (type 5)"), "{e}");
    assert!(e.contains("10-node tetrahedron (type 11)"), "{e}");
    assert!(e.contains("20-node hexahedron (type 17)"), "{e}");
    // and what to set in Gmsh to get supported cells
    assert!(e.contains("Mesh.ElementOrder = 1"), "{e}");

    // 4.1: four 9-node quadrangles (type 10) in 2D
    let mut text = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 9 1 9\n2 1 0 9\n");
    for i in 1..=9 {
        text += &format!("{i}\n");
    }
    for i in 0..9 {
        text += &format!("{} {} 0\n", i % 3, i / 3);
    }
    text += "$EndNodes\n$Elements\n1 4 1 4\n2 1 10 4\n";
    for i in 1..=4 {
        text += &format!("{i} 1 3 9 7 2 6 8 4 5\n");
    }
    text += "$EndElements\n";
    let e = parse_err(&text, 2);
    assert!(e.contains("4 × 9-node quadrangle (type 10)"), "{e}");
    assert!(e.contains("3-node triangle (type 2)"), "{e}");
    assert!(e.contains("Mesh.SecondOrderIncomplete = 1"), "{e}");
}

#[test]
fn unsupported_facet_of_a_physical_group() {
    // a 9-node quadrangle as a physical face of a 3D mesh of tetrahedra
    let text = CUBE_TET_V41.replace(
        "2 1 2 2\n1 1 2 4\n2 1 4 3\n",
        "2 1 10 2\n1 1 2 4 1 2 4 1 2 4\n2 1 4 3 1 4 3 1 4 3\n",
    );
    let e = parse_err(&text, 3);
    assert!(e.contains("2 × 9-node quadrangle (type 10)"), "{e}");
}

#[test]
fn facet_not_on_the_boundary_names_its_group() {
    // A physical surface inside the body (the square's diagonal, between its
    // two triangles) is read as the set of its nodes: a file may hold groups
    // the scene does not use; as a surface it is refused, naming it.
    let text = SQUARE_TRI_V22
        .replace("3 1 2 2 3 3 4", "3 1 2 2 3 1 3")
        .replace("\"top\"", "\"diagonal\"");
    let mesh = parse_msh(text.as_bytes(), 2).unwrap();
    assert!(!mesh.surfaces.contains_key("diagonal"));
    assert_eq!(mesh.node_sets["diagonal"].len(), 2);
    let e = mesh.surface("diagonal").unwrap_err().to_string();
    assert!(
        e.contains("\"diagonal\"") && e.contains("inside the body"),
        "{e}"
    );

    let text = SQUARE_TRI_V22.replace("3 1 2 2 3 3 4", "3 1 2 2 3 3 99");
    let e = parse_err(&text, 2);
    assert!(
        e.contains("\"top\"") && e.contains("not a facet of any cell"),
        "{e}"
    );
}

#[test]
fn other_errors() {
    let e = parse_err(&SQUARE_TRI_V22.replace("2.2 0 8", "3.0 0 8"), 2);
    assert!(
        e.contains("version 3.0") && e.contains("not supported"),
        "{e}"
    );
    let e = parse_err(&SQUARE_TRI_V22.replace("2.2 0 8", "4 0 8"), 2);
    assert!(e.contains("version 4 ") && e.contains("4.1"), "{e}");
    let e = parse_err(&SQUARE_TRI_V22.replace("2.2 0 8", "2.2 1 8"), 2);
    assert!(e.contains("binary") && e.contains("not supported"), "{e}");
    let e = parse_err("hello", 2);
    assert!(e.contains("$MeshFormat"), "{e}");
    let e = parse_err(&SQUARE_TRI_V22.replace("$Nodes", "$Nodez"), 2);
    assert!(e.contains("no $Nodes"), "{e}");
    let nodes41 = &SQUARE_QUAD_V41
        [SQUARE_QUAD_V41.find("$Nodes").unwrap()..SQUARE_QUAD_V41.find("$Elements").unwrap()];
    let e = parse_err(&SQUARE_QUAD_V41.replace(nodes41, ""), 2);
    assert!(e.contains("no $Nodes"), "{e}");
    // a 2D mesh read as 3D, a 3D mesh read as 2D
    let e = parse_err(SQUARE_TRI_V22, 3);
    assert!(e.contains("no cell of dimension 3"), "{e}");
    assert!(e.contains("2 × 3-node triangle (type 2)"), "{e}");
    let e = parse_err(CUBE_TET_V41, 2);
    assert!(e.contains("dimension higher than 2"), "{e}");
    // a 2D mesh off the plane z = 0
    let e = parse_err(&SQUARE_TRI_V22.replace("3 1 1 0", "3 1 1 0.01"), 2);
    assert!(e.contains("z = 0") && e.contains("node 3"), "{e}");
    // but rounding noise is accepted
    let m = parse(&SQUARE_TRI_V22.replace("3 1 1 0", "3 1 1 1e-17"), 2);
    assert_eq!(m.coords[2], [1.0, 1.0, 0.0]);
    // an element on a missing node
    let e = parse_err(
        &SQUARE_TRI_V22.replace("4 2 2 3 1 1 2 3", "4 2 2 3 1 1 2 7"),
        2,
    );
    assert!(e.contains("node 7"), "{e}");
    // mshio's own parse errors are kept short (no hex dump of the file)
    let e = parse_err(&SQUARE_QUAD_V41.replace("5 1 2 5 4", "5 1 2 x 4"), 2);
    assert!(e.contains("cannot parse the MSH 4.1 file"), "{e}");
    assert!(!e.contains("Hex dump") && e.len() < 2100, "{e}");
    // a missing file names its path
    let e = read_msh(Path::new("/nonexistent/part.msh"), 2).unwrap_err();
    assert!(e.to_string().contains("/nonexistent/part.msh"), "{e}");
}

// ---------------------------------------------------------------------------
// Files written by Gmsh
// ---------------------------------------------------------------------------

fn same_mesh(a: &Mesh, b: &Mesh) {
    assert_eq!(a.n_nodes(), b.n_nodes());
    for (p, q) in a.coords.iter().zip(&b.coords) {
        for k in 0..3 {
            assert!((p[k] - q[k]).abs() < 1e-14, "{p:?} vs {q:?}");
        }
    }
    assert_eq!(a.cells, b.cells);
    assert_eq!(a.surfaces, b.surfaces);
    assert_eq!(a.regions, b.regions);
}

#[test]
fn block2d_in_three_formats() {
    let v41 = read_msh(&examples().join("block2d.msh"), 2).unwrap();
    let v22 = read_msh(&manifest().join("tests/data/block2d_v22.msh"), 2).unwrap();
    let bin = read_msh(&manifest().join("tests/data/block2d_bin.msh"), 2).unwrap();
    assert_eq!(v41.n_nodes(), 266);
    assert_eq!(v41.cells.len(), 235);
    assert!(v41.cells.iter().all(|c| c.kind == CellKind::Quad4));
    assert!((area(&v41) - 2.0).abs() < 1e-12);
    assert_eq!(names(&v41.surfaces), ["bottom", "left", "right", "top"]);
    assert_eq!(names(&v41.regions), ["block"]);
    assert_eq!(v41.regions["block"].len(), 235);
    let sides = [
        ("bottom", 2.0, [0.0, -1.0, 0.0], 20),
        ("top", 2.0, [0.0, 1.0, 0.0], 20),
        ("left", 1.0, [-1.0, 0.0, 0.0], 10),
        ("right", 1.0, [1.0, 0.0, 0.0], 10),
    ];
    for (name, len, n, facets) in sides {
        assert_eq!(v41.surfaces[name].facets.len(), facets, "{name}");
        assert!((measure(&v41, name) - len).abs() < 1e-12, "{name}");
        check_surface(&v41, name, n);
    }
    assert_eq!(v41.boundary_facets().len(), 60);
    same_mesh(&v41, &v22);
    same_mesh(&v41, &bin);
}

/// The 1 × 0.5 block of the files `block2d_partitioned*` and
/// `block2d_*parametric*` (tests/data, written by Gmsh 4.15 from the sweep's
/// block with h = 0.25): its four named sides and its region.
fn check_small_block(m: &Mesh) {
    assert!((area(m) - 0.5).abs() < 1e-12);
    assert_eq!(names(&m.surfaces), ["bottom", "left", "right", "top"]);
    let sides = [
        ("bottom", 1.0, [0.0, -1.0, 0.0]),
        ("top", 1.0, [0.0, 1.0, 0.0]),
        ("left", 0.5, [-1.0, 0.0, 0.0]),
        ("right", 0.5, [1.0, 0.0, 0.0]),
    ];
    for (name, len, n) in sides {
        assert!((measure(m, name) - len).abs() < 1e-12, "{name}");
        check_surface(m, name, n);
    }
    let facets: usize = m.surfaces.values().map(|s| s.facets.len()).sum();
    assert_eq!(facets, m.boundary_facets().len());
    assert_eq!(m.regions["block"].len(), m.cells.len());
}

#[test]
fn partitioned_files_keep_their_physical_groups() {
    // Gmsh's gmsh.model.mesh.partition(n) puts the elements on partition
    // entities listed in $PartitionedEntities (which mshio skips); their
    // physical groups were lost and the sides read as one "boundary".
    for (file, parts) in [
        ("block2d_partitioned.msh", 2),
        ("block2d_partitioned_bin.msh", 3), // binary, with ghost cells
    ] {
        let m = read_msh(&manifest().join("tests/data").join(file), 2).unwrap();
        check_small_block(&m);
        assert!(m.cells.len() > 2 * parts, "{file}");
    }
}

/// The error reading `tests/data/<file>` in 2D, which names every one of
/// `parts`.
fn refused_naming(file: &str, parts: &[&str]) -> String {
    let e = read_msh(&manifest().join("tests/data").join(file), 2)
        .unwrap_err()
        .to_string();
    for part in parts {
        assert!(e.contains(part), "{e}");
    }
    e
}

#[test]
fn one_file_of_a_partitioned_mesh_saved_per_partition_is_refused() {
    // Mesh.PartitionSplitMeshFiles = 1 writes one file per partition: one of
    // them was read as the whole body (a fragment, solved without a word).
    refused_naming(
        "block2d_piece_1_of_2.msh",
        &[
            "partition 1 of",
            "into 2 parts",
            "PartitionSplitMeshFiles = 0",
        ],
    );
}

#[test]
fn parametric_nodes_are_read() {
    // Mesh.SaveParametric = 1: node blocks with parametric coordinates (MSH
    // 4.1, which mshio refused) or $ParametricNodes (MSH 2.2, "no $Nodes").
    let data = manifest().join("tests/data");
    let a = read_msh(&data.join("block2d_parametric.msh"), 2).unwrap();
    let b = read_msh(&data.join("block2d_parametric_bin.msh"), 2).unwrap();
    let c = read_msh(&data.join("block2d_v22_parametric.msh"), 2).unwrap();
    check_small_block(&a);
    same_mesh(&a, &b);
    same_mesh(&a, &c);
}

#[test]
fn v22_saved_with_save_all_has_lost_its_groups() {
    // Gmsh writes every element of a 2.2 file saved with Mesh.SaveAll = 1
    // with physical tag 0: its named sides were silently replaced by one
    // "boundary" surface.
    let e = refused_naming(
        "block2d_v22_saveall.msh",
        &[
            "block2d_v22_saveall.msh",
            "\"bottom\", \"left\", \"right\", \"top\"",
        ],
    );
    assert!(e.contains("Mesh.SaveAll") && e.contains("MSH 4.1"), "{e}");
}

#[test]
fn block3d_of_tetrahedra() {
    let m = read_msh(&examples().join("block3d.msh"), 3).unwrap();
    assert_eq!(m.n_nodes(), 693);
    assert_eq!(m.cells.len(), 2570);
    assert!((tet_volume(&m) - 0.5).abs() < 1e-12);
    assert!((volume(&m) - 0.5).abs() < 1e-12);
    assert_eq!(
        names(&m.surfaces),
        ["bottom", "top", "xmax", "xmin", "ymax", "ymin"]
    );
    assert!((measure(&m, "bottom") - 1.0).abs() < 1e-12);
    assert!((measure(&m, "top") - 1.0).abs() < 1e-12);
    for side in ["xmin", "xmax", "ymin", "ymax"] {
        assert!((measure(&m, side) - 0.5).abs() < 1e-12, "{side}");
    }
    check_surface(&m, "bottom", [0.0, 0.0, -1.0]);
    check_surface(&m, "top", [0.0, 0.0, 1.0]);
    check_surface(&m, "xmax", [1.0, 0.0, 0.0]);
    let facets: usize = m.surfaces.values().map(|s| s.facets.len()).sum();
    assert_eq!(facets, m.boundary_facets().len());
    assert_eq!(m.regions["block"].len(), 2570);
}

// ---------------------------------------------------------------------------
// Binary MSH 4.1 written here from the ASCII strings above
// ---------------------------------------------------------------------------

/// Rewrites an ASCII MSH 4.1 file as binary (size_t of 8 bytes, the given
/// byte order); `$PhysicalNames` stays ASCII, as Gmsh writes it.
fn to_binary_v41(text: &str, big_endian: bool) -> Vec<u8> {
    fn nodes_of(t: i64) -> usize {
        match t {
            15 => 1,
            1 => 2,
            2 | 8 => 3,
            3 | 4 => 4,
            9 => 6,
            5 | 16 => 8,
            _ => panic!("type {t}"),
        }
    }
    let mut out: Vec<u8> = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let section = line.trim_start_matches('$');
        if line == "$MeshFormat" {
            lines.next();
            out.extend_from_slice(b"$MeshFormat\n4.1 1 8\n");
            let one = if big_endian {
                1i32.to_be_bytes()
            } else {
                1i32.to_le_bytes()
            };
            out.extend_from_slice(&one);
            out.push(b'\n');
            continue;
        }
        if !["$Entities", "$Nodes", "$Elements"].contains(&line) {
            out.extend_from_slice(line.as_bytes());
            out.push(b'\n');
            continue;
        }
        let end = format!("$End{section}");
        let body: Vec<&str> = lines.by_ref().take_while(|l| *l != end).collect();
        let mut tok = body.iter().flat_map(|l| l.split_whitespace());
        let mut bin: Vec<u8> = Vec::new();
        let size = |t: &mut dyn Iterator<Item = &str>, bin: &mut Vec<u8>| -> u64 {
            let v: u64 = t.next().unwrap().parse().unwrap();
            bin.extend_from_slice(&if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            });
            v
        };
        let int = |t: &mut dyn Iterator<Item = &str>, bin: &mut Vec<u8>| -> i64 {
            let v: i32 = t.next().unwrap().parse().unwrap();
            bin.extend_from_slice(&if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            });
            v as i64
        };
        let dbl = |t: &mut dyn Iterator<Item = &str>, bin: &mut Vec<u8>| {
            let v: f64 = t.next().unwrap().parse().unwrap();
            bin.extend_from_slice(&if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            });
        };
        let t: &mut dyn Iterator<Item = &str> = &mut tok;
        match section {
            "Entities" => {
                let counts: Vec<u64> = (0..4).map(|_| size(t, &mut bin)).collect();
                for (kind, &n) in counts.iter().enumerate() {
                    for _ in 0..n {
                        int(t, &mut bin);
                        for _ in 0..if kind == 0 { 3 } else { 6 } {
                            dbl(t, &mut bin);
                        }
                        for _ in 0..size(t, &mut bin) {
                            int(t, &mut bin);
                        }
                        if kind > 0 {
                            for _ in 0..size(t, &mut bin) {
                                int(t, &mut bin);
                            }
                        }
                    }
                }
            }
            "Nodes" => {
                let blocks = size(t, &mut bin);
                for _ in 0..3 {
                    size(t, &mut bin);
                }
                for _ in 0..blocks {
                    for _ in 0..3 {
                        int(t, &mut bin);
                    }
                    let n = size(t, &mut bin);
                    for _ in 0..n {
                        size(t, &mut bin);
                    }
                    for _ in 0..3 * n {
                        dbl(t, &mut bin);
                    }
                }
            }
            _ => {
                let blocks = size(t, &mut bin);
                for _ in 0..3 {
                    size(t, &mut bin);
                }
                for _ in 0..blocks {
                    for _ in 0..2 {
                        int(t, &mut bin);
                    }
                    let k = nodes_of(int(t, &mut bin));
                    let n = size(t, &mut bin);
                    for _ in 0..n * (k as u64 + 1) {
                        size(t, &mut bin);
                    }
                }
            }
        }
        assert!(tok.next().is_none(), "{section}: tokens left over");
        out.extend_from_slice(line.as_bytes());
        out.push(b'\n');
        out.extend_from_slice(&bin);
        out.push(b'\n');
        out.extend_from_slice(end.as_bytes());
        out.push(b'\n');
    }
    out
}

#[test]
fn v41_binary_reads_as_its_ascii_twin() {
    for (text, dim) in [(SQUARE_QUAD_V41, 2), (CUBE_TET_V41, 3)] {
        let ascii = parse(text, dim);
        for big_endian in [false, true] {
            let bytes = to_binary_v41(text, big_endian);
            let bin = parse_msh(&bytes, dim).unwrap();
            assert_eq!(ascii, bin, "big endian: {big_endian}");
        }
    }
}
