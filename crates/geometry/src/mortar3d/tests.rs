use super::*;
use crate::mortar::tests::{check_flat_rows, paired};
use cells::MAX_FACE_NODES;
use signorini_mesh::generators::box_mesh;
use signorini_mesh::CellKind;

/// A box at `origin` of `size`, one layer of `n` × `n` cells of `kind`.
fn layer(origin: [f64; 3], size: [f64; 3], n: usize, kind: CellKind) -> Mesh {
    box_mesh(origin, size, [n, n, 1], kind, None).unwrap()
}

/// Two boxes [0, 1]² × [0, 0.5] (master, `nm` × `nm` faces on top) and
/// [0, 1]² × [0.5 + gap, 1 + gap] (slave, `ns` × `ns`), of `kind` cells.
fn boxes(nm: usize, ns: usize, gap: f64, kind: CellKind) -> (Mesh, Mesh) {
    let m = layer([0.0; 3], [1.0, 1.0, 0.5], nm, kind);
    let s = layer([0.0, 0.0, 0.5 + gap], [1.0, 1.0, 0.5], ns, kind);
    (m, s)
}

fn pairing(m: &Mesh, s: &Mesh) -> MortarPairing {
    paired(mortar3d_pairing, (m, "zmax"), (s, "zmin"))
}

#[test]
fn non_matching_quadrilaterals_give_consistent_rows() {
    let gap = 0.01;
    let (m, s) = boxes(5, 7, gap, CellKind::Hex8);
    let p = pairing(&m, &s);
    // D_jj = ∫N_j = h², h²/2 on the sides, h²/4 at the corners (h = 1/7).
    let h2 = 1.0 / 49.0;
    let d_of = |x: [f64; 3]| {
        let edge = |v: f64| !(1e-9..=1.0 - 1e-9).contains(&v);
        h2 / [1.0, 2.0, 4.0][usize::from(edge(x[0])) + usize::from(edge(x[1]))]
    };
    check_flat_rows(&p, 64, gap, 2, d_of);
}

#[test]
fn non_matching_triangles_give_consistent_rows() {
    let gap = -0.002;
    let (m, s) = boxes(4, 5, gap, CellKind::Tet4);
    let p = pairing(&m, &s);
    // Σ D_jj = 1 and D_jj = ∫N_j = (area of the faces around j)/3.
    let mut want = BTreeMap::<usize, f64>::new();
    for f in &s.surfaces["zmin"].facets {
        let (_, area) = s.facet_normal(f);
        for &v in &f.nodes {
            *want.entry(v).or_insert(0.0) += area / 3.0;
        }
    }
    let coords = s.coords.clone();
    let d_of = |x: [f64; 3]| {
        let k = coords.iter().position(|c| *c == x).unwrap();
        want[&k]
    };
    check_flat_rows(&p, 36, gap, 2, d_of);
}

#[test]
fn a_fully_covered_triangle_has_the_closed_form_dual_basis() {
    // Φ_i = 3N_i − N_j − N_k: A = [[3, −1, −1], ...].
    let tri = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let points: Vec<FacePoint> = polygon_rule(&tri, &TRIANGLE_RULE)
        .into_iter()
        .map(|(p, w)| FacePoint {
            w,
            ns: [1.0 - p[0] - p[1], p[0], p[1], 0.0, 0.0, 0.0, 0.0, 0.0],
            master: 0,
            nm: [0.0; MAX_FACE_NODES],
            normal: [0.0, 0.0, 1.0],
        })
        .collect();
    let a = dual_coefficients(&points, 3, 0.5).unwrap();
    for (j, row) in a.iter().enumerate().take(3) {
        for (k, &v) in row.iter().enumerate().take(3) {
            let want = if j == k { 3.0 } else { -1.0 };
            assert!((v - want).abs() < 1e-12, "{a:?}");
        }
    }
}

#[test]
fn a_slave_wider_than_the_master_keeps_the_covered_nodes_only() {
    let m = layer([0.25, 0.25, 0.0], [0.5, 0.5, 0.5], 3, CellKind::Hex8);
    let s = layer([0.0, 0.0, 0.5], [1.0, 1.0, 0.5], 4, CellKind::Hex8);
    let p = pairing(&m, &s);
    // The covered part is the square [0.25, 0.75]²: the 3 × 3 slave nodes in
    // it (the faces around them are partly covered).
    assert_eq!(p.pairing.points.len(), 9);
    assert_eq!(p.pairing.dropped.off_surface, 16);
    let total: f64 = p.measure.values().sum();
    assert!((total - 0.25).abs() < 1e-13, "Σ D_jj = {total}");
    for pt in &p.pairing.points {
        let sum: f64 = pt.terms.iter().map(|t| t.weight).sum();
        assert!(sum.abs() < 1e-13, "row sum {sum}");
    }
}

#[test]
fn rigid_masters_and_2d_meshes_are_refused() {
    let (m, s) = boxes(2, 2, 0.0, CellKind::Hex8);
    let plane = MasterGeometry::Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
    };
    let e = mortar3d_pairing(&s, &s.surfaces["zmin"], &plane).unwrap_err();
    assert!(e.to_string().contains("deformable master"), "{e}");
    let flat =
        signorini_mesh::generators::rectangle([0.0; 2], [1.0; 2], [2, 2], CellKind::Quad4, None)
            .unwrap();
    let master = MasterGeometry::Surface {
        mesh: &m,
        surface: &m.surfaces["zmax"],
    };
    let e = mortar3d_pairing(&flat, &flat.surfaces["bottom"], &master).unwrap_err();
    assert!(e.to_string().contains("3D"), "{e}");
}

/// Checks the rows of a flat interface z = 0.5 + gap (slave above): Σ D_jj is
/// the area, every D_jj > 0, each row reproduces a linear field (Σ over its
/// terms of weight × node position = (0, 0, gap)) and its gap0 is the gap.
fn check_linear_fields(p: &MortarPairing, s: &Mesh, m: &Mesh, nodes: usize, gap: f64) {
    assert_eq!(p.pairing.points.len(), nodes);
    let total: f64 = p.measure.values().sum();
    assert!((total - 1.0).abs() < 1e-13, "Σ D_jj = {total}");
    for pt in &p.pairing.points {
        assert!(p.measure[&pt.slave_node] > 0.0);
        let mut x = [0.0; 3];
        for t in &pt.terms {
            let y = match t.side {
                crate::TermSide::Slave => s.coords[t.node],
                crate::TermSide::Master => m.coords[t.node],
            };
            for k in 0..3 {
                x[k] += t.weight * y[k];
            }
        }
        let want = [0.0, 0.0, gap];
        for k in 0..3 {
            assert!((x[k] - want[k]).abs() < 1e-13, "{x:?} at {:?}", pt.x);
        }
        assert!((pt.gap0 - gap).abs() < 1e-13, "gap0 {}", pt.gap0);
    }
}

#[test]
fn non_matching_quadratic_faces_reproduce_linear_fields() {
    let gap = 0.01;
    for (ks, km, nodes) in [
        (CellKind::Hex20, CellKind::Hex20, 7 * 7 + 2 * 6 * 7),
        (CellKind::Tet10, CellKind::Hex20, 7 * 7 + 3 * 6 * 6 + 2 * 6),
        (CellKind::Hex20, CellKind::Tet10, 7 * 7 + 2 * 6 * 7),
        (CellKind::Tet4, CellKind::Hex20, 7 * 7),
    ] {
        let m = layer([0.0; 3], [1.0, 1.0, 0.5], 4, km);
        let s = layer([0.0, 0.0, 0.5 + gap], [1.0, 1.0, 0.5], 6, ks);
        let p = pairing(&m, &s);
        check_linear_fields(&p, &s, &m, nodes, gap);
    }
}

#[test]
fn a_flat_quad8_face_has_the_recombined_measures() {
    // One Quad8 face of area 1 on a larger master: A/20 at the corners, A/5
    // at the mid-sides.
    let m = layer([-0.5, -0.5, 0.0], [2.0, 2.0, 0.5], 3, CellKind::Hex20);
    let s = layer([0.0, 0.0, 0.5], [1.0, 1.0, 0.5], 1, CellKind::Hex20);
    let p = pairing(&m, &s);
    assert_eq!(p.pairing.points.len(), 8);
    for pt in &p.pairing.points {
        let corner = [0, 1].iter().all(|&k| pt.x[k] == 0.0 || pt.x[k] == 1.0);
        let want = if corner { 0.05 } else { 0.2 };
        let d = p.measure[&pt.slave_node];
        assert!((d - want).abs() < 1e-14, "D_jj {d} at {:?}", pt.x);
    }
}

#[test]
fn non_matching_gmsh_tet10_faces_are_covered_whole() {
    // Gmsh's nodes are off their lines by ~1e-13: the clipping's tolerance
    // band must not throw a clipped vertex far off (it once dropped 14 % of a
    // face here, and 0.2 % of Σ D_jj).
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/");
    let read = |f: &str| {
        signorini_mesh::gmsh::read_msh(std::path::Path::new(&format!("{root}{f}")), 3).unwrap()
    };
    let m = read("quadratic/block_tet10.msh");
    let s = read("quadratic_patch/block_upper_tet10.msh");
    let master = MasterGeometry::Surface {
        mesh: &m,
        surface: &m.surfaces["top"],
    };
    let p = mortar3d_pairing(&s, &s.surfaces["bottom"], &master).unwrap();
    let total: f64 = p.measure.values().sum();
    assert!((total - 1.0).abs() < 1e-11, "Σ D_jj = {total}");
}

/// The parabolic interface z = 0.5 + x²/4 that the quadratic meshes of
/// tests/data/quadratic_patch/parabolic_*.msh represent exactly: the
/// pairing of the upper block's bottom (`upper`) on the lower block's top.
fn parabolic(lower: &str, upper: &str) -> (Mesh, Mesh, MortarPairing) {
    let root = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/quadratic_patch/"
    );
    let read = |f: String| {
        signorini_mesh::gmsh::read_msh(std::path::Path::new(&format!("{root}{f}")), 3).unwrap()
    };
    let m = read(format!("parabolic_lower_{lower}.msh"));
    let s = read(format!("parabolic_upper_{upper}.msh"));
    let master = MasterGeometry::Surface {
        mesh: &m,
        surface: &m.surfaces["top"],
    };
    let p = mortar3d_pairing(&s, &s.surfaces["bottom"], &master).unwrap();
    (m, s, p)
}

/// A row Σ coefficient · u(node) with the slave nodes moved by `us` and the
/// master nodes by `um` (functions of the position).
fn apply(
    row: &[crate::VectorTerm],
    (s, m): (&Mesh, &Mesh),
    us: impl Fn([f64; 3]) -> [f64; 3],
    um: impl Fn([f64; 3]) -> [f64; 3],
) -> f64 {
    row.iter()
        .map(|t| match t.side {
            TermSide::Slave => dot(t.coefficient, us(s.coords[t.node])),
            TermSide::Master => dot(t.coefficient, um(m.coords[t.node])),
        })
        .sum()
}

/// On the curved interface the tangential rows carry the frame inside the
/// integral, ∫Φ_j t_k(x)·(u_s − u_m) dA / D_jj: a relative motion along the
/// surface's normal, v(x) = (−x/2, 0, 1) ∥ n(x) (linear, so the quadratic
/// slave interpolates it exactly), is no slip at all (the rows of the
/// nodal frame, t_kj·(ũ_j − Σ M_jl/D_jj u_l), measured up to 0.083 of |v|
/// there); a linear field common to both bodies gives no slip, matching
/// or not; and the tangents at the node are those of contact.csv's frame.
#[test]
fn curved_tangential_rows_see_no_normal_motion_and_no_common_linear_field() {
    let normal = |x: [f64; 3]| [-0.5 * x[0], 0.0, 1.0];
    let linear = |x: [f64; 3]| {
        [
            0.3 * x[0] - 0.2 * x[1] + 0.1 * x[2] + 0.05,
            0.1 * x[0] + 0.4 * x[2] - 0.02,
            -0.25 * x[0] + 0.15 * x[1] - 0.3 * x[2] + 0.01,
        ]
    };
    let zero = |_: [f64; 3]| [0.0; 3];
    for (lower, upper) in [
        ("hex20_3", "hex20_3"),
        ("hex20_3", "hex20_4"),
        ("tet10_3", "tet10_4"),
        ("hex20_3", "tet10_4"),
    ] {
        let (m, s, p) = parabolic(lower, upper);
        let mut nodal = 0.0f64;
        for pt in &p.pairing.points {
            assert!(!pt.normal_row.is_empty(), "{upper}: a curved node's rows");
            for (row, t_dir) in pt.tangent_rows.iter().zip([pt.tangent, pt.tangent2]) {
                assert!(!row.is_empty(), "{upper}: a curved node's tangential rows");
                let slip = apply(row, (&s, &m), normal, zero);
                assert!(slip.abs() <= 1e-12, "{upper} on {lower}: slip {slip:e}");
                let common = apply(row, (&s, &m), linear, linear);
                assert!(common.abs() <= 1e-11, "{upper} on {lower}: {common:e}");
                let along: f64 = (pt.terms.iter())
                    .filter(|t| t.side == TermSide::Slave)
                    .map(|t| t.weight * dot(t_dir, normal(s.coords[t.node])))
                    .sum();
                nodal = nodal.max(along.abs());
            }
            let g = apply(&pt.normal_row, (&s, &m), normal, zero);
            assert!((0.95..=1.2).contains(&g), "{upper} on {lower}: normal {g}");
        }
        eprintln!("{upper} on {lower}: nodal-frame slip of a normal motion {nodal:e}");
    }
}
