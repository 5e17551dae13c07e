//! The 3D generators: `box_mesh` (Hex8, Tet4) and `hemisphere`.

use signorini_mesh::generators::{
    box_mesh, hemisphere, hex_corner_jacobians, BoxSide, HalfBall, HEX_CORNER_AXES,
};
use signorini_mesh::vec3::{dot, norm, sub};
use signorini_mesh::{CellKind, Facet, Mesh, HEX8_REFERENCE_CORNERS};
use std::collections::HashMap;
use std::f64::consts::PI;

fn det3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Volume of a Hex8 cell: the integral of the trilinear map's Jacobian by 2x2x2
/// Gauss points (exact: the Jacobian is at most quadratic in each variable).
fn hex_volume(m: &Mesh, c: usize) -> f64 {
    let n = &m.cells[c].nodes;
    let g = 1.0 / 3f64.sqrt();
    let mut v = 0.0;
    for q in [[-g, -g, -g], [g, -g, -g], [g, g, -g], [-g, g, -g]]
        .into_iter()
        .flat_map(|q| [q, [q[0], q[1], -q[2]]])
    {
        // columns of the Jacobian: dx/dxi_d
        let mut col = [[0.0; 3]; 3];
        for (k, r) in HEX8_REFERENCE_CORNERS.iter().enumerate() {
            let x = m.coords[n[k]];
            for d in 0..3 {
                let mut dn = r[d] / 8.0;
                for e in 0..3 {
                    if e != d {
                        dn *= 1.0 + r[e] * q[e];
                    }
                }
                for i in 0..3 {
                    col[d][i] += x[i] * dn;
                }
            }
        }
        v += det3(col[0], col[1], col[2]);
    }
    v
}

fn tet_volume(m: &Mesh, c: usize) -> f64 {
    let p: Vec<[f64; 3]> = m.cells[c].nodes.iter().map(|&n| m.coords[n]).collect();
    det3(sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0])) / 6.0
}

fn volume(m: &Mesh) -> f64 {
    (0..m.cells.len())
        .map(|c| match m.cells[c].kind {
            CellKind::Hex8 => hex_volume(m, c),
            CellKind::Tet4 => tet_volume(m, c),
            k => panic!("not a 3D cell: {k:?}"),
        })
        .sum()
}

fn area(m: &Mesh, name: &str) -> f64 {
    let s = m.surface(name).unwrap();
    s.facets.iter().map(|f| m.facet_normal(f).1).sum()
}

/// Every facet of a surface is a boundary facet of the mesh (same nodes in the
/// same order, same cell), and the surfaces together hold every boundary facet
/// exactly once.
fn check_surfaces_cover_boundary(m: &Mesh) {
    let key = |f: &Facet| (f.nodes.clone(), f.cell);
    let mut boundary: HashMap<(Vec<usize>, usize), usize> =
        m.boundary_facets().iter().map(|f| (key(f), 0)).collect();
    for (name, s) in &m.surfaces {
        for f in &s.facets {
            let seen = boundary
                .get_mut(&key(f))
                .unwrap_or_else(|| panic!("{name}: {f:?} is not a boundary facet"));
            *seen += 1;
        }
    }
    assert!(boundary.values().all(|&n| n == 1), "boundary covered once");
}

/// Every corner Jacobian of every cell is positive; returns the smallest one
/// divided by the product of the three edge lengths at its corner.
fn min_scaled_jacobian(m: &Mesh) -> f64 {
    let mut worst = f64::INFINITY;
    for c in 0..m.cells.len() {
        let det = hex_corner_jacobians(m, c);
        let n = &m.cells[c].nodes;
        for k in 0..8 {
            assert!(det[k] > 0.0, "cell {c} corner {k}: Jacobian {}", det[k]);
            let l: f64 = HEX_CORNER_AXES[k]
                .iter()
                .map(|&j| norm(sub(m.coords[n[j]], m.coords[n[k]])))
                .product();
            worst = worst.min(det[k] / l);
        }
    }
    worst
}

/// Largest ratio of the longest to the shortest edge of a Hex8 cell.
fn max_edge_ratio(m: &Mesh) -> f64 {
    // the Hex8 edges are the corner pairs of the Hex20 mid-sides
    const EDGES: [[usize; 2]; 12] = signorini_mesh::HEX20_EDGES;
    let mut worst: f64 = 0.0;
    for cell in &m.cells {
        let l: Vec<f64> = EDGES
            .iter()
            .map(|e| norm(sub(m.coords[cell.nodes[e[0]]], m.coords[cell.nodes[e[1]]])))
            .collect();
        let (lo, hi) = l
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        worst = worst.max(hi / lo);
    }
    worst
}

#[test]
fn box_side_names() {
    for s in BoxSide::ALL {
        assert_eq!(BoxSide::from_name(s.name()), Some(s));
    }
    let names: Vec<&str> = BoxSide::ALL.iter().map(|s| s.name()).collect();
    assert_eq!(names, ["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"]);
    assert_eq!(BoxSide::from_name("top"), None);
}

#[test]
fn box_hex_and_tet() {
    let (o, s, d) = ([1.0, -2.0, 0.5], [2.0, 3.0, 1.5], [2usize, 3, 4]);
    for (kind, per_hex, per_face) in [(CellKind::Hex8, 1, 1), (CellKind::Tet4, 6, 2)] {
        let m = box_mesh(o, s, d, kind, None).unwrap();
        m.check().unwrap();
        assert_eq!(m.dim, 3);
        assert_eq!(m.n_nodes(), 3 * 4 * 5);
        assert_eq!(m.cells.len(), 24 * per_hex);
        assert!(m.cells.iter().all(|c| c.kind == kind));
        if kind == CellKind::Tet4 {
            assert!((0..m.cells.len()).all(|c| tet_volume(&m, c) > 0.0));
        } else {
            assert!(min_scaled_jacobian(&m) > 1.0 - 1e-12, "boxes");
        }
        assert!((volume(&m) - 9.0).abs() < 1e-13, "volume {}", volume(&m));
        check_surfaces_cover_boundary(&m);
        // conforming: every interior face is shared, so the boundary holds only
        // the faces on the box's sides
        let n_bnd = 2 * (d[1] * d[2] + d[0] * d[2] + d[0] * d[1]) * per_face;
        assert_eq!(m.boundary_facets().len(), n_bnd);
        for side in BoxSide::ALL {
            let (axis, at_max) = side.axis();
            let sf = m.surface(side.name()).unwrap();
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            assert_eq!(sf.facets.len(), d[a] * d[b] * per_face, "{}", side.name());
            let expect_area = s[a] * s[b];
            let ar = area(&m, side.name());
            assert!((ar - expect_area).abs() < 1e-13, "{}: {ar}", side.name());
            let plane = if at_max { o[axis] + s[axis] } else { o[axis] };
            for n in sf.nodes() {
                assert_eq!(m.coords[n][axis], plane);
            }
            let sign = if at_max { 1.0 } else { -1.0 };
            for f in &sf.facets {
                assert_eq!(f.nodes.len(), if kind == CellKind::Hex8 { 4 } else { 3 });
                let (nrm, _) = m.facet_normal(f);
                let mut expect = [0.0; 3];
                expect[axis] = sign;
                assert!(norm(sub(nrm, expect)) < 1e-14, "{}: {nrm:?}", side.name());
                // the facet's own right-hand normal points out as well
                let p: Vec<[f64; 3]> = f.nodes.iter().map(|&k| m.coords[k]).collect();
                let rh = det3(sub(p[1], p[0]), sub(p[2], p[0]), expect);
                assert!(rh > 0.0, "{}: facet node order", side.name());
            }
        }
    }
}

#[test]
fn box_grading() {
    for side in BoxSide::ALL {
        for kind in [CellKind::Hex8, CellKind::Tet4] {
            let m = box_mesh(
                [0.0; 3],
                [1.0, 2.0, 3.0],
                [4, 5, 6],
                kind,
                Some((side, 8.0)),
            )
            .unwrap();
            m.check().unwrap();
            let (axis, at_max) = side.axis();
            let mut lines: Vec<f64> = m.coords.iter().map(|x| x[axis]).collect();
            lines.sort_by(f64::total_cmp);
            lines.dedup();
            assert_eq!(lines.len(), [4, 5, 6][axis] + 1);
            let h: Vec<f64> = lines.windows(2).map(|w| w[1] - w[0]).collect();
            let (first, last) = (h[0], h[h.len() - 1]);
            let ratio = if at_max { first / last } else { last / first };
            assert!((ratio - 8.0).abs() < 1e-9, "{}: {ratio}", side.name());
            // geometric
            for w in h.windows(3) {
                assert!((w[1] * w[1] - w[0] * w[2]).abs() < 1e-12);
            }
            assert!((volume(&m) - 6.0).abs() < 1e-12);
            check_surfaces_cover_boundary(&m);
        }
    }
}

#[test]
fn box_errors() {
    let ok = |d: [usize; 3], s: [f64; 3], k: CellKind, g: Option<(BoxSide, f64)>| {
        box_mesh([0.0; 3], s, d, k, g).is_ok()
    };
    assert!(ok([1, 1, 1], [1.0; 3], CellKind::Hex8, None));
    assert!(!ok([1, 0, 1], [1.0; 3], CellKind::Hex8, None));
    assert!(!ok([1, 1, 1], [1.0, -1.0, 1.0], CellKind::Hex8, None));
    assert!(!ok([1, 1, 1], [1.0; 3], CellKind::Quad4, None));
    assert!(!ok(
        [1, 1, 1],
        [1.0; 3],
        CellKind::Hex8,
        Some((BoxSide::Xmin, 0.0))
    ));
}

/// Checks a hemisphere's geometry and returns (volume, flat area, dome area).
fn check_hemisphere(c: [f64; 3], r: f64, d: usize, pole: [f64; 3], g: f64) -> (Mesh, [f64; 3]) {
    let m = hemisphere(&HalfBall::new(c, r, d, pole, g)).unwrap();
    m.check().unwrap();
    assert!(m.cells.iter().all(|cell| cell.kind == CellKind::Hex8));
    min_scaled_jacobian(&m);
    check_surfaces_cover_boundary(&m);
    let pn = norm(pole);
    let p = pole.map(|x| x / pn);
    let tol = 1e-14 * r;
    // dome nodes on the sphere, on the pole's side
    for n in m.surface("dome").unwrap().nodes() {
        let x = sub(m.coords[n], c);
        assert!(
            (norm(x) - r).abs() <= 2.0 * tol,
            "dome node off the sphere by {}",
            norm(x) - r
        );
        assert!(dot(x, p) >= -tol);
    }
    // flat nodes on the plane through the centre
    for n in m.surface("flat").unwrap().nodes() {
        let x = sub(m.coords[n], c);
        assert!(
            dot(x, p).abs() <= tol,
            "flat node off the plane by {}",
            dot(x, p)
        );
    }
    // every node in the half ball
    for x in &m.coords {
        let x = sub(*x, c);
        assert!(norm(x) <= r * (1.0 + 1e-14) && dot(x, p) >= -tol);
    }
    // outward normals: flat against the pole, dome radial
    for f in &m.surface("flat").unwrap().facets {
        let (nrm, _) = m.facet_normal(f);
        assert!(norm(sub(nrm, p.map(|x| -x))) < 1e-12, "{nrm:?}");
    }
    for f in &m.surface("dome").unwrap().facets {
        let (nrm, _) = m.facet_normal(f);
        let mid = f.nodes.iter().fold([0.0; 3], |a, &k| {
            [
                a[0] + m.coords[k][0],
                a[1] + m.coords[k][1],
                a[2] + m.coords[k][2],
            ]
        });
        let radial = sub(mid.map(|x| x / 4.0), c);
        assert!(dot(nrm, radial) / norm(radial) > 0.9);
    }
    // the pole is a node
    let tip = [c[0] + r * p[0], c[1] + r * p[1], c[2] + r * p[2]];
    let (_, dist) = m.nearest_node(tip).unwrap();
    assert!(dist < 1e-14 * r, "no node at the pole ({dist})");
    let measures = [volume(&m), area(&m, "flat"), area(&m, "dome")];
    (m, measures)
}

#[test]
fn hemisphere_measures_converge() {
    let (c, r) = ([0.3, -0.2, 1.1], 2.0f64);
    let exact = [2.0 / 3.0 * PI * r.powi(3), PI * r * r, 2.0 * PI * r * r];
    for g in [1.0, 4.0] {
        let mut prev: Option<[f64; 3]> = None;
        // measured relative errors (inscribed, so all below the exact values):
        // divisions 4: volume 6.5e-2 (g = 1) / 8.5e-2 (g = 4), flat 2.6e-2, dome 4.3e-2;
        // each halving of the elements divides them by 2.8 to 4
        for (d, bound) in [(4usize, 0.1), (8, 0.03), (16, 0.008)] {
            let (_, meas) = check_hemisphere(c, r, d, [0.0, 0.0, -1.0], g);
            let err: Vec<f64> = (0..3).map(|k| 1.0 - meas[k] / exact[k]).collect();
            for k in 0..3 {
                assert!(
                    err[k] > 0.0 && err[k] < bound,
                    "g={g} d={d}: errors {err:?}"
                );
            }
            if let Some(p) = prev {
                for k in 0..3 {
                    assert!(err[k] < p[k] / 2.5, "g={g} d={d}: {err:?} vs {p:?}");
                }
            }
            prev = Some([err[0], err[1], err[2]]);
        }
    }
}

#[test]
fn hemisphere_any_pole() {
    for pole in [
        [0.0, 0.0, 1.0],
        [0.0, 2.0, 0.0],
        [-1.0, 0.0, 0.0],
        [1.0, 2.0, -2.0],
    ] {
        let (m, meas) = check_hemisphere([1.0, 2.0, 3.0], 0.5, 6, pole, 3.0);
        let v = 2.0 / 3.0 * PI * 0.125;
        assert!((meas[0] / v - 1.0).abs() < 0.05);
        assert_eq!(m.surfaces.len(), 2);
    }
    assert!(hemisphere(&HalfBall::new([0.0; 3], 1.0, 8, [0.0; 3], 1.0)).is_err());
    assert!(hemisphere(&HalfBall::new([0.0; 3], -1.0, 8, [0.0, 0.0, -1.0], 1.0)).is_err());
    assert!(hemisphere(&HalfBall::new([0.0; 3], 1.0, 1, [0.0, 0.0, -1.0], 1.0)).is_err());
    assert!(hemisphere(&HalfBall::new([0.0; 3], 1.0, 8, [0.0, 0.0, -1.0], -2.0)).is_err());
}

#[test]
fn hemisphere_quality() {
    for d in [2usize, 3, 4, 5, 7, 8, 13, 16] {
        for g in [1.0, 2.0, 4.0, 8.0, 16.0, 32.0] {
            let m = hemisphere(&HalfBall::new([0.0; 3], 1.0, d, [0.0, 0.0, -1.0], g)).unwrap();
            let sj = min_scaled_jacobian(&m);
            let ratio = max_edge_ratio(&m);
            // measured (divisions 3..20): scaled Jacobian >= 0.26 (>= 0.34 for
            // g <= 16); for divisions >= 8 edge ratio <= 4.6 (g <= 4), 8.1 (g <= 16),
            // 13.5 (g = 32). Divisions 2 is the coarsest possible mesh.
            let sj_min = match (d, g) {
                (2, _) => 0.04,
                (_, g) if g <= 16.0 => 0.33,
                _ => 0.25,
            };
            assert!(sj > sj_min, "d={d} g={g}: scaled Jacobian {sj}");
            if d >= 8 {
                let r_max = if g <= 4.0 {
                    5.0
                } else if g <= 16.0 {
                    8.5
                } else {
                    14.0
                };
                assert!(ratio < r_max, "d={d} g={g}: edge ratio {ratio}");
            }
        }
    }
}

#[test]
fn hemisphere_grading_and_counts() {
    let m = hemisphere(&HalfBall::new([0.0; 3], 1.0, 8, [0.0, 0.0, -1.0], 4.0)).unwrap();
    // m = 3, ns = 10, n_r = 4: 11² 4 + (11² + 4 10 3) 4 nodes, 10² 3 + (10² + 120) 4 cells
    assert_eq!(m.n_nodes(), 1448);
    assert_eq!(m.cells.len(), 1180);
    // the meridian in the plane y = 0 (x >= 0) from the pole to the equator:
    // 8 elements, angles geometric with largest / smallest = 4
    let mut ang: Vec<f64> = m
        .surface("dome")
        .unwrap()
        .nodes()
        .iter()
        .map(|&k| m.coords[k])
        .filter(|x| x[1] == 0.0 && x[0] >= 0.0)
        .map(|x| x[0].atan2(-x[2]))
        .collect();
    ang.sort_by(f64::total_cmp);
    assert_eq!(ang.len(), 9);
    assert!(ang[0].abs() < 1e-15 && (ang[8] - PI / 2.0).abs() < 1e-15);
    let h: Vec<f64> = ang.windows(2).map(|w| w[1] - w[0]).collect();
    assert!((h[7] / h[0] - 4.0).abs() < 1e-9, "{h:?}");
    for w in h.windows(2) {
        assert!((w[1] / w[0] - 4f64.powf(1.0 / 7.0)).abs() < 1e-9);
    }
    // the cells at the pole are nearly cubes of the smallest meridian element
    let (pole, _) = m.nearest_node([0.0, 0.0, -1.0]).unwrap();
    let at_pole: Vec<usize> = (0..m.cells.len())
        .filter(|&c| m.cells[c].nodes.contains(&pole))
        .collect();
    assert_eq!(at_pole.len(), 4);
    for &c in &at_pole {
        let n = &m.cells[c].nodes;
        for e in [[0, 1], [1, 2], [4, 5], [5, 6], [0, 4], [2, 6]] {
            let l = norm(sub(m.coords[n[e[0]]], m.coords[n[e[1]]]));
            assert!(
                l > 0.8 * h[0] && l < 1.3 * h[0],
                "pole cell edge {l} vs {}",
                h[0]
            );
        }
    }
    // uniform: the same, all elements equal
    let u = hemisphere(&HalfBall::new([0.0; 3], 1.0, 8, [0.0, 0.0, -1.0], 1.0)).unwrap();
    // m = 4, ns = 8, n_r = 4
    assert_eq!(u.n_nodes(), 81 * 5 + (81 + 4 * 8 * 4) * 4);
    assert_eq!(u.cells.len(), 64 * 4 + (64 + 4 * 8 * 4) * 4);
}
