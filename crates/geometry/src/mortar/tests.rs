use super::*;
use crate::pairing::TermSide;
use signorini_mesh::generators::rectangle;
use signorini_mesh::CellKind;

/// Two blocks [0, 1] × [0, 0.5] (master, `nm` elements along x) and
/// [0, 1] × [0.5 + gap, 1 + gap] (slave, `ns` elements).
fn blocks(nm: usize, ns: usize, gap: f64) -> (Mesh, Mesh) {
    let m = rectangle([0.0, 0.0], [1.0, 0.5], [nm, 2], CellKind::Quad4, None).unwrap();
    let s = rectangle([0.0, 0.5 + gap], [1.0, 0.5], [ns, 2], CellKind::Quad4, None).unwrap();
    (m, s)
}

fn pairing(m: &Mesh, s: &Mesh) -> MortarPairing {
    paired(mortar_pairing, (m, "top"), (s, "bottom"))
}

/// The pairing by `pair` (2D or 3D mortar) of the surface `slave` of `s`
/// against the surface `master` of `m`.
pub(crate) fn paired(
    pair: fn(&Mesh, &Surface, &MasterGeometry<'_>) -> Result<MortarPairing, GeometryError>,
    (m, master): (&Mesh, &str),
    (s, slave): (&Mesh, &str),
) -> MortarPairing {
    let master = MasterGeometry::Surface {
        mesh: m,
        surface: &m.surfaces[master],
    };
    pair(s, &s.surfaces[slave], &master).unwrap()
}

/// A straight slave edge from (0, 0) to (1, 0) of `count` nodes (outward
/// normal −y), and a master edge of 2 nodes.
fn unit_edge(count: usize) -> SlaveEdge {
    let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 0.0]];
    SlaveEdge {
        edge: edge::Edge {
            nodes: [0, 1, 2],
            count,
            x,
        },
        n: [[0.0, -1.0, 0.0]; 3],
    }
}

fn overlap(lo: f64, hi: f64) -> Overlap {
    Overlap {
        lo,
        hi,
        master: edge::Edge {
            nodes: [0, 1, 0],
            count: 2,
            x: [[0.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0; 3]],
        },
    }
}

#[test]
fn full_segment_dual_basis_is_two_n1_minus_n2() {
    let a = dual_coefficients(&unit_edge(2), &[overlap(0.0, 1.0)]).unwrap();
    let want = [[2.0, -1.0], [-1.0, 2.0]];
    for j in 0..2 {
        for k in 0..2 {
            assert!((a[j][k] - want[j][k]).abs() < 1e-13, "{a:?}");
        }
    }
}

/// ∫ Φ_j N_k over [lo, hi] = δ_jk ∫ N_k for the dual basis of a
/// `count`-node edge covered over [lo, hi].
fn assert_biorthogonal(count: usize, lo: f64, hi: f64) {
    let seg = unit_edge(count);
    let o = [overlap(lo, hi)];
    let a = dual_coefficients(&seg, &o).unwrap();
    let mut scale = 0.0f64;
    for (j, aj) in a.iter().enumerate().take(count) {
        for k in 0..count {
            let (mut pk, mut nk) = (0.0, 0.0);
            for (xi, w) in gauss_points(&o[0]) {
                let n = edge::shape(count, xi);
                let phi = aj[0] * n[0] + aj[1] * n[1] + aj[2] * n[2];
                pk += w * phi * n[k];
                nk += w * n[k];
            }
            scale = scale.max(nk.abs()).max(hi - lo);
            let want = if j == k { nk } else { 0.0 };
            // M_e's condition number grows as (hi − lo)⁻² on a quadratic edge.
            assert!(
                (pk - want).abs() < 1e-13 * scale / (hi - lo).powi(2),
                "{count} nodes on [{lo}, {hi}], j {j} k {k}: {pk} vs {want}"
            );
        }
    }
}

#[test]
fn partial_dual_basis_is_biorthogonal_on_the_covered_part() {
    assert_biorthogonal(2, 0.3, 0.8);
}

#[test]
fn quadratic_dual_basis_is_biorthogonal_full_and_partial() {
    assert_biorthogonal(3, 0.0, 1.0);
    assert_biorthogonal(3, 0.3, 0.8);
    assert_biorthogonal(3, 0.0, 0.01);
    // Full coverage: D_jj = ∫ N_j = 1/6, 1/6, 2/3, and the dual basis is
    // the closed form A = D M⁻¹ with M = (1/30)[[4, −1, 2], [−1, 4, 2], [2, 2, 16]].
    let a = dual_coefficients(&unit_edge(3), &[overlap(0.0, 1.0)]).unwrap();
    let want = [[1.5, 0.5, -0.25], [0.5, 1.5, -0.25], [-1.0, -1.0, 1.5]];
    for j in 0..3 {
        for k in 0..3 {
            assert!((a[j][k] - want[j][k]).abs() < 1e-12, "{a:?}");
        }
    }
}

/// Σ D_jj = the area (1), D_jj = ∫N_j = `d_of(x)`, Σ_l M_jl = D_jj (the
/// master weights sum to −1), gap0 = the gap and the normal +`axis` at every
/// slave node.
pub(crate) fn check_flat_rows(
    p: &MortarPairing,
    nodes: usize,
    gap: f64,
    axis: usize,
    d_of: impl Fn([f64; 3]) -> f64,
) {
    assert_eq!(p.pairing.points.len(), nodes);
    assert_eq!(p.pairing.dropped.total(), 0);
    let total: f64 = p.measure.values().sum();
    assert!((total - 1.0).abs() < 1e-13, "Σ D_jj = {total}");
    for pt in &p.pairing.points {
        let d = p.measure[&pt.slave_node];
        assert!((d - d_of(pt.x)).abs() < 1e-14, "D_jj {d} at {:?}", pt.x);
        let sum: f64 = pt.terms.iter().map(|t| t.weight).sum();
        assert!(sum.abs() < 1e-13, "row sum {sum}");
        assert!((pt.gap0 - gap).abs() < 1e-13, "gap0 {}", pt.gap0);
        assert!((pt.normal[axis] - 1.0).abs() < 1e-14);
    }
}

#[test]
fn non_matching_flat_rows_are_consistent() {
    let gap = 0.01;
    let (m, s) = blocks(7, 10, gap);
    let p = pairing(&m, &s);
    // D_jj = ∫ N_j: 0.1 inside, 0.05 at the ends.
    let d_of = |x: [f64; 3]| {
        if x[0] < 1e-9 || x[0] > 1.0 - 1e-9 {
            0.05
        } else {
            0.1
        }
    };
    check_flat_rows(&p, 11, gap, 1, d_of);
}

#[test]
fn quadratic_non_matching_flat_rows_are_consistent() {
    // Quad8 slave (10 edges, mid-side nodes included) on a Tri6 master (7).
    let gap = 0.01;
    let m = rectangle([0.0, 0.0], [1.0, 0.5], [7, 2], CellKind::Tri6, None).unwrap();
    let s = rectangle([0.0, 0.5 + gap], [1.0, 0.5], [10, 2], CellKind::Quad8, None).unwrap();
    let p = pairing(&m, &s);
    assert_eq!(p.pairing.points.len(), 21);
    assert_eq!(p.pairing.dropped.total(), 0);
    let total: f64 = p.measure.values().sum();
    assert!((total - 1.0).abs() < 1e-13, "Σ D_jj = {total}");
    let mids: std::collections::BTreeSet<usize> = s.surfaces["bottom"]
        .facets
        .iter()
        .map(|f| f.nodes[2])
        .collect();
    for pt in &p.pairing.points {
        // D_jj = ∫ N_j: 2h/3 at a mid-side node, h/3 at an inner corner,
        // h/6 at an end (h = 0.1).
        let d = p.measure[&pt.slave_node];
        let end = pt.x[0] < 1e-9 || pt.x[0] > 1.0 - 1e-9;
        let want = if mids.contains(&pt.slave_node) {
            0.2 / 3.0
        } else if end {
            0.1 / 6.0
        } else {
            0.1 / 3.0
        };
        assert!((d - want).abs() < 1e-14, "{d} vs {want}");
        let sum: f64 = pt.terms.iter().map(|t| t.weight).sum();
        assert!(sum.abs() < 1e-13, "row sum {sum}");
        assert!((pt.gap0 - gap).abs() < 1e-13, "gap0 {}", pt.gap0);
        // Master weights reproduce the slave node's abscissa (linear
        // fields are reproduced on a flat interface).
        let xm: f64 = pt
            .terms
            .iter()
            .filter(|t| t.side == TermSide::Master)
            .map(|t| -t.weight * m.coords[t.node][0])
            .sum();
        assert!((xm - pt.x[0]).abs() < 1e-13, "{xm} vs {}", pt.x[0]);
    }
}

#[test]
fn a_slave_wider_than_the_master_drops_the_uncovered_nodes() {
    let m = rectangle([0.25, 0.0], [0.5, 0.5], [3, 2], CellKind::Quad4, None).unwrap();
    let s = rectangle([0.0, 0.5], [1.0, 0.5], [8, 2], CellKind::Quad4, None).unwrap();
    let p = pairing(&m, &s);
    // Slave nodes at x = 0.25 … 0.75 (5 of them) carry the covered part.
    assert_eq!(p.pairing.points.len(), 5);
    assert_eq!(p.pairing.dropped.off_surface, 4);
    let total: f64 = p.measure.values().sum();
    assert!((total - 0.5).abs() < 1e-13, "Σ D_jj = {total}");
}

#[test]
fn rigid_masters_are_refused() {
    let (_, s) = blocks(2, 2, 0.0);
    let plane = MasterGeometry::Plane {
        point: [0.0; 3],
        normal: [0.0, 1.0, 0.0],
    };
    let e = mortar_pairing(&s, &s.surfaces["bottom"], &plane).unwrap_err();
    assert!(e.to_string().contains("deformable master"), "{e}");
}

/// The parabola y = 4η(1 − η)·h through (0, 0), (2, 0) with its mid-side
/// node at (1, h): a curved quadratic edge.
fn parabola(h: f64) -> edge::Edge {
    edge::Edge {
        nodes: [0, 1, 2],
        count: 3,
        x: [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, h, 0.0]],
    }
}

#[test]
fn projections_onto_a_curved_quadratic_edge_follow_its_curve() {
    let e = parabola(1.0);
    // x(η) = 2η: the vertical line x = 0.5 meets the curve at η = 1/4.
    let eta = e
        .parameter_along([0.5, 5.0, 0.0], [0.0, -1.0, 0.0])
        .unwrap();
    assert!((eta - 0.25).abs() < 1e-14, "{eta}");
    let p = e.point(eta);
    assert!((p[1] - 0.75).abs() < 1e-14, "{p:?}");
    // Beyond the end: the side is kept (a parameter > 1).
    let eta = e
        .parameter_along([2.5, 5.0, 0.0], [0.0, -1.0, 0.0])
        .unwrap();
    assert!(eta > 1.0, "{eta}");
    // A slave edge on the same curve with its exact unit normals at the
    // nodes: the normal line at the returned ξ passes through y.
    let unit_normal = |xi: f64| {
        let t = e.tangent(xi);
        let l = t[0].hypot(t[1]);
        [t[1] / l, -t[0] / l, 0.0]
    };
    let seg = SlaveEdge {
        edge: e,
        n: [unit_normal(0.0), unit_normal(1.0), unit_normal(0.5)],
    };
    // Beyond the normal line of the end c1 (along (−2, −1)/√5): ξ > 1.
    assert!(seg.parameter_of([1.9, -0.4, 0.0]).unwrap() > 1.0);
    for y in [[0.3, 0.2, 0.0], [1.2, 1.5, 0.0], [1.2, -0.1, 0.0]] {
        let xi = seg.parameter_of(y).unwrap();
        assert!((0.0..=1.0).contains(&xi), "y {y:?}: {xi}");
        let (x, n) = (seg.point(xi), seg.normal(xi));
        let miss = edge::cross2(sub(x, y), n) / norm(n);
        assert!(
            miss.abs() < 1e-13,
            "y {y:?}: ξ {xi}, off the line by {miss}"
        );
    }
}
