//! Tests of the 2D generators and the grid spacings.

use super::*;
use crate::{CellKind, Mesh};
use std::f64::consts::PI;

fn area(mesh: &Mesh, c: usize) -> f64 {
    let p: Vec<[f64; 3]> = mesh.cells[c]
        .nodes
        .iter()
        .map(|&n| mesh.coords[n])
        .collect();
    let m = p.len();
    (0..m)
        .map(|i| {
            let j = (i + 1) % m;
            p[i][0] * p[j][1] - p[j][0] * p[i][1]
        })
        .sum::<f64>()
        / 2.0
}

/// (min over corners of sin(angle), max edge / min edge) over all cells.
fn quality(mesh: &Mesh) -> (f64, f64) {
    let mut min_sin = f64::INFINITY;
    let mut max_aspect: f64 = 0.0;
    for cell in &mesh.cells {
        let p: Vec<[f64; 3]> = cell.nodes.iter().map(|&n| mesh.coords[n]).collect();
        let m = p.len();
        let mut lmin = f64::INFINITY;
        let mut lmax: f64 = 0.0;
        for i in 0..m {
            let a = p[(i + m - 1) % m];
            let b = p[i];
            let c = p[(i + 1) % m];
            let e1 = [c[0] - b[0], c[1] - b[1]];
            let e0 = [a[0] - b[0], a[1] - b[1]];
            let l1 = e1[0].hypot(e1[1]);
            let l0 = e0[0].hypot(e0[1]);
            // interior angle at b, ccw: sin = (e1 x e0) / (|e1||e0|)
            min_sin = min_sin.min((e1[0] * e0[1] - e1[1] * e0[0]) / (l1 * l0));
            lmin = lmin.min(l1);
            lmax = lmax.max(l1);
        }
        max_aspect = max_aspect.max(lmax / lmin);
    }
    (min_sin, max_aspect)
}

fn total_area(mesh: &Mesh) -> f64 {
    (0..mesh.cells.len()).map(|c| area(mesh, c)).sum()
}

/// Every facet is an edge of its cell, and each surface is a connected chain.
fn check_surfaces(mesh: &Mesh) {
    for s in mesh.surfaces.values() {
        for f in &s.facets {
            let n = &mesh.cells[f.cell].nodes;
            assert!(n.contains(&f.nodes[0]) && n.contains(&f.nodes[1]));
        }
        for w in s.facets.windows(2) {
            assert_eq!(w[0].nodes[1], w[1].nodes[0], "surface facets form a chain");
        }
    }
}

#[test]
fn graded_spacing_ratio() {
    let t = graded_spacing(10, 8.0);
    assert_eq!(t.len(), 11);
    assert_eq!(t[0], 0.0);
    assert_eq!(t[10], 1.0);
    let h: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(h.windows(2).all(|w| w[1] > w[0]));
    assert!((h[9] / h[0] - 8.0).abs() < 1e-12);
    let u = graded_spacing(4, 1.0);
    for (i, v) in u.iter().enumerate() {
        assert!((v - i as f64 / 4.0).abs() < 1e-15);
    }
    assert_eq!(graded_spacing(1, 5.0), vec![0.0, 1.0]);
    for n in [5usize, 6, 9, 128] {
        let s = symmetric_graded_spacing(n, 16.0);
        let h: Vec<f64> = s.windows(2).map(|w| w[1] - w[0]).collect();
        let (lo, hi) = h
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        assert!((hi / lo - 16.0).abs() < 1e-9, "n = {n}: {}", hi / lo);
        for i in 0..=n {
            assert!((s[i] + s[n - i] - 1.0).abs() < 1e-15);
        }
    }
}

#[test]
fn rectangle_quad_and_tri() {
    for (kind, per) in [(CellKind::Quad4, 1), (CellKind::Tri3, 2)] {
        let m = rectangle([1.0, -2.0], [3.0, 2.0], [6, 4], kind, None).unwrap();
        m.check().unwrap();
        assert_eq!(m.dim, 2);
        assert_eq!(m.n_nodes(), 7 * 5);
        assert_eq!(m.cells.len(), 24 * per);
        assert!((0..m.cells.len()).all(|c| area(&m, c) > 0.0));
        assert!((total_area(&m) - 6.0).abs() < 1e-13);
        check_surfaces(&m);
        let side = |name: &str, k: usize, v: f64, nf: usize| {
            let s = m.surface(name).unwrap();
            assert_eq!(s.facets.len(), nf);
            for n in s.nodes() {
                assert_eq!(m.coords[n][k], v, "{name}");
            }
            let len: f64 = s.facets.iter().map(|f| m.facet_normal_2d(f).1).sum();
            let expect = if k == 0 { 2.0 } else { 3.0 };
            assert!((len - expect).abs() < 1e-14);
        };
        side("left", 0, 1.0, 4);
        side("right", 0, 4.0, 4);
        side("bottom", 1, -2.0, 6);
        side("top", 1, 0.0, 6);
        // outward normals
        let s = m.surface("top").unwrap();
        for f in &s.facets {
            let (n, _) = m.facet_normal_2d(f);
            assert!((n[1] - 1.0).abs() < 1e-15);
        }
    }
}

#[test]
fn rectangle_grading() {
    for side in [
        RectSide::Bottom,
        RectSide::Top,
        RectSide::Left,
        RectSide::Right,
    ] {
        let m = rectangle(
            [0.0, 0.0],
            [2.0, 1.0],
            [8, 8],
            CellKind::Quad4,
            Some((side, 10.0)),
        )
        .unwrap();
        m.check().unwrap();
        let (k, along): (usize, Vec<usize>) = match side {
            RectSide::Bottom | RectSide::Top => (1, (0..=8).map(|j| j * 9).collect()),
            _ => (0, (0..=8).collect()),
        };
        let h: Vec<f64> = along
            .windows(2)
            .map(|w| m.coords[w[1]][k] - m.coords[w[0]][k])
            .collect();
        let (first, last) = (h[0], h[7]);
        match side {
            RectSide::Bottom | RectSide::Left => {
                assert!((last / first - 10.0).abs() < 1e-10)
            }
            _ => assert!((first / last - 10.0).abs() < 1e-10),
        }
        assert!((total_area(&m) - 2.0).abs() < 1e-13);
    }
    assert!(rectangle([0.0, 0.0], [1.0, 1.0], [0, 2], CellKind::Quad4, None).is_err());
    assert!(rectangle([0.0, 0.0], [-1.0, 1.0], [2, 2], CellKind::Quad4, None).is_err());
}

fn check_half_disk(c: [f64; 2], r: f64, n: usize, pole: [f64; 2], g: f64, kind: CellKind) -> Mesh {
    let m = half_disk(&HalfBall::new(c, r, n, pole, g), kind).unwrap();
    m.check().unwrap();
    check_surfaces(&m);
    let pn = pole[0].hypot(pole[1]);
    let p = [pole[0] / pn, pole[1] / pn];
    // arc nodes on the circle, on the pole's side
    let arc = m.surface("arc").unwrap();
    assert_eq!(arc.facets.len(), n);
    for k in arc.nodes() {
        let x = m.coords[k];
        let d = (x[0] - c[0]).hypot(x[1] - c[1]);
        assert!(
            (d - r).abs() <= 1e-12 * r,
            "arc node off the circle: {}",
            d - r
        );
        assert!((x[0] - c[0]) * p[0] + (x[1] - c[1]) * p[1] >= -1e-12 * r);
    }
    // flat nodes on the diameter, within the disk
    let flat = m.surface("flat").unwrap();
    let flen: f64 = flat.facets.iter().map(|f| m.facet_normal_2d(f).1).sum();
    assert!((flen - 2.0 * r).abs() < 1e-12 * r);
    for f in &flat.facets {
        let (nrm, _) = m.facet_normal_2d(f);
        assert!((nrm[0] + p[0]).abs() < 1e-12 && (nrm[1] + p[1]).abs() < 1e-12);
    }
    for k in flat.nodes() {
        let x = m.coords[k];
        assert!(((x[0] - c[0]) * p[0] + (x[1] - c[1]) * p[1]).abs() <= 1e-12 * r);
        assert!((x[0] - c[0]).hypot(x[1] - c[1]) <= r * (1.0 + 1e-12));
    }
    // area: polygon inscribed in the arc, error sum(R² Δφ³/12) <= R² π max(Δφ)²/12
    let a = total_area(&m);
    let exact = PI * r * r / 2.0;
    assert!(a < exact);
    let dphi_max = PI * g / n as f64; // generous bound on the largest arc element
    assert!(
        exact - a <= r * r * PI * dphi_max * dphi_max / 12.0,
        "area {a} vs {exact}"
    );
    assert!((0..m.cells.len()).all(|c| area(&m, c) > 0.0));
    m
}

#[test]
fn half_disk_shapes() {
    for kind in [CellKind::Quad4, CellKind::Tri3] {
        for (n, g) in [
            (4usize, 1.0),
            (7, 1.0),
            (16, 1.0),
            (32, 4.0),
            (128, 16.0),
            (129, 16.0),
        ] {
            for pole in [[0.0, -1.0], [0.0, 2.0], [1.0, 1.0], [-3.0, 0.5]] {
                let m = check_half_disk([0.3, -1.2], 2.5, n, pole, g, kind);
                let (min_sin, aspect) = quality(&m);
                // measured: quads min sin 0.68 (angles in [43°, 137°]), aspect <= 7.0;
                // triangles (four per quad) min sin 0.145 (angles >= 8°), aspect <= 3.6
                let sin_min = if kind == CellKind::Quad4 { 0.6 } else { 0.12 };
                assert!(min_sin > sin_min, "n={n} g={g} {kind:?}: min sin {min_sin}");
                assert!(aspect < 8.0, "n={n} g={g} {kind:?}: aspect {aspect}");
            }
        }
    }
    // a zero pole, a zero radius, too few divisions
    for bad in [
        HalfBall::new([0.0, 0.0], 1.0, 16, [0.0, 0.0], 1.0),
        HalfBall::new([0.0, 0.0], 0.0, 16, [0.0, 1.0], 1.0),
        HalfBall::new([0.0, 0.0], 1.0, 3, [0.0, 1.0], 1.0),
    ] {
        assert!(half_disk(&bad, CellKind::Quad4).is_err(), "{bad:?}");
    }
}

#[test]
fn half_disk_counts() {
    let ball = HalfBall::new([0.0, 0.0], 1.0, 16, [0.0, -1.0], 1.0);
    let m = half_disk(&ball, CellKind::Quad4).unwrap();
    // uniform 16: corner at arc node 4 (45°), rectangle 8 x 4, ring 16 x 2
    assert_eq!(m.cells.len(), 8 * 4 + 16 * 2);
    assert_eq!(m.n_nodes(), 9 * 5 + 17 * 2);
    // Tri3: four triangles about a node added at each quad's centre
    let t = half_disk(&ball, CellKind::Tri3).unwrap();
    assert_eq!(t.cells.len(), 4 * m.cells.len());
    assert_eq!(t.n_nodes(), m.n_nodes() + m.cells.len());
    assert_eq!(
        &t.coords[..m.n_nodes()],
        &m.coords[..],
        "the quads' nodes keep their numbers"
    );
    assert_eq!(t.surface("arc").unwrap().nodes().len(), 17);
    assert_eq!(t.surface("flat").unwrap().nodes().len(), 9 + 2 * 2);
}

#[test]
fn half_disk_contact_zone_resolution() {
    let r = 0.05;
    let c = [0.0, r];
    let pole = [0.0, -1.0];
    let m = half_disk(&HalfBall::new(c, r, 128, pole, 16.0), CellKind::Quad4).unwrap();
    let tip = [c[0] + r * pole[0], c[1] + r * pole[1]];
    let arc = m.surface("arc").unwrap();
    let near = arc
        .nodes()
        .iter()
        .filter(|&&k| {
            let x = m.coords[k];
            (x[0] - tip[0]).hypot(x[1] - tip[1]) <= 0.1 * r
        })
        .count();
    assert!(near >= 20, "only {near} arc nodes within 0.1 R of the pole");
    // the pole itself is a node
    let (_, d) = m.nearest_node([tip[0], tip[1], 0.0]).unwrap();
    assert!(d < 1e-15);
}

/// Surfaces' facets are boundary facets of the mesh (same nodes, order and
/// cell), and together they hold each boundary facet exactly once.
fn check_boundary_cover(mesh: &Mesh) {
    let mut seen: std::collections::HashMap<(Vec<usize>, usize), usize> = mesh
        .boundary_facets()
        .into_iter()
        .map(|f| ((f.nodes, f.cell), 0))
        .collect();
    for (name, s) in &mesh.surfaces {
        for f in &s.facets {
            *seen
                .get_mut(&(f.nodes.clone(), f.cell))
                .unwrap_or_else(|| panic!("{name}: {f:?} is not a boundary facet")) += 1;
        }
    }
    assert!(seen.values().all(|&n| n == 1));
}

fn check_quarter_disk(c: [f64; 2], r: f64, n: usize, g: f64, kind: CellKind) -> Mesh {
    let m = quarter_disk(c, r, n, g, kind).unwrap();
    m.check().unwrap();
    assert!(m.cells.iter().all(|cell| cell.kind == kind));
    check_surfaces(&m);
    check_boundary_cover(&m);
    let tol = 1e-14 * r;
    for x in &m.coords {
        assert!(x[0] >= c[0], "node at x - c_x = {:e}", x[0] - c[0]);
        assert!(x[1] <= c[1] + tol);
        assert!((x[0] - c[0]).hypot(x[1] - c[1]) <= r * (1.0 + 1e-14));
    }
    let facet_len = |name: &str| -> f64 {
        let s = m.surface(name).unwrap();
        s.facets.iter().map(|f| m.facet_normal(f).1).sum()
    };
    // axis: exactly on x = c_x, from the centre to the pole, normal -x
    let axis = m.surface("axis").unwrap();
    for k in axis.nodes() {
        assert_eq!(m.coords[k][0], c[0]);
    }
    assert!((facet_len("axis") - r).abs() < 1e-13 * r);
    for f in &axis.facets {
        let (nrm, _) = m.facet_normal(f);
        assert!((nrm[0] + 1.0).abs() < 1e-14 && nrm[1].abs() < 1e-14);
    }
    // flat: on y = c_y, normal +y
    let flat = m.surface("flat").unwrap();
    for k in flat.nodes() {
        assert!((m.coords[k][1] - c[1]).abs() <= tol);
    }
    assert!((facet_len("flat") - r).abs() < 1e-13 * r);
    for f in &flat.facets {
        let (nrm, _) = m.facet_normal(f);
        assert!((nrm[1] - 1.0).abs() < 1e-14);
    }
    // arc: on the circle, from the pole to (c_x + R, c_y)
    let arc = m.surface("arc").unwrap();
    assert_eq!(arc.facets.len(), n);
    for k in arc.nodes() {
        let x = m.coords[k];
        assert!(((x[0] - c[0]).hypot(x[1] - c[1]) - r).abs() <= 2.0 * tol);
    }
    let first = m.coords[arc.facets[0].nodes[0]];
    assert_eq!(first[0], c[0]);
    assert!(
        (first[1] - (c[1] - r)).abs() <= tol,
        "the arc starts at the pole"
    );
    m
}

#[test]
fn quarter_disk_shapes() {
    let (c, r) = ([0.0, 1.5], 1.5);
    for kind in [
        CellKind::Quad4,
        CellKind::Tri3,
        CellKind::Quad8,
        CellKind::Tri6,
    ] {
        for (n, g) in [
            (2usize, 1.0),
            (3, 2.0),
            (8, 1.0),
            (16, 4.0),
            (33, 16.0),
            (64, 8.0),
        ] {
            let m = check_quarter_disk(c, r, n, g, kind);
            if kind.order() == 1 {
                let (min_sin, aspect) = quality(&m);
                // the half disk's measured bounds
                let sin_min = if kind == CellKind::Quad4 { 0.6 } else { 0.12 };
                assert!(min_sin > sin_min, "n={n} g={g} {kind:?}: min sin {min_sin}");
                assert!(aspect < 8.0, "n={n} g={g} {kind:?}: aspect {aspect}");
            }
        }
    }
    // off-axis centre
    check_quarter_disk([2.0, -1.0], 0.5, 12, 3.0, CellKind::Quad4);
    assert!(quarter_disk(c, r, 1, 1.0, CellKind::Quad4).is_err());
    assert!(quarter_disk(c, 0.0, 8, 1.0, CellKind::Quad4).is_err());
    assert!(quarter_disk(c, r, 8, 0.0, CellKind::Quad4).is_err());
    assert!(quarter_disk(c, r, 8, 1.0, CellKind::Hex8).is_err());
}

#[test]
fn quarter_disk_area_converges() {
    let r = 2.0;
    let exact = PI * r * r / 4.0;
    for kind in [CellKind::Quad4, CellKind::Tri3] {
        for g in [1.0, 4.0] {
            let mut prev = f64::INFINITY;
            for n in [4usize, 8, 16, 32] {
                let m = check_quarter_disk([0.0, 0.0], r, n, g, kind);
                let err = 1.0 - total_area(&m) / exact;
                // inscribed polygon: below the exact area, the error divided
                // by about 4 per refinement (1.0e-2 for n = 4, g = 1)
                assert!(err > 0.0 && err < 0.05, "n={n} g={g}: {err}");
                assert!(err < prev / 3.0, "n={n} g={g}: {err} vs {prev}");
                prev = err;
            }
        }
    }
}

#[test]
fn quarter_disk_grading_and_counts() {
    let m = quarter_disk([0.0, 0.0], 1.0, 16, 4.0, CellKind::Quad4).unwrap();
    assert_eq!(m.n_nodes(), 140);
    assert_eq!(m.cells.len(), 119);
    // arc angles from the pole: geometric, largest / smallest = 4
    let arc = m.surface("arc").unwrap();
    let mut ang: Vec<f64> = arc
        .nodes()
        .iter()
        .map(|&k| m.coords[k][0].atan2(-m.coords[k][1]))
        .collect();
    ang.sort_by(f64::total_cmp);
    assert_eq!(ang.len(), 17);
    assert_eq!(ang[0], 0.0);
    let h: Vec<f64> = ang.windows(2).map(|w| w[1] - w[0]).collect();
    assert!((h[15] / h[0] - 4.0).abs() < 1e-9, "{h:?}");
    for w in h.windows(2) {
        assert!((w[1] / w[0] - 4f64.powf(1.0 / 15.0)).abs() < 1e-9);
    }
    // the right half of the half disk with twice the divisions, same nodes
    let ball = HalfBall::new([0.0, 0.0], 1.0, 32, [0.0, -1.0], 4.0);
    let half = half_disk(&ball, CellKind::Quad4).unwrap();
    assert_eq!(
        half.coords.iter().filter(|x| x[0] > 1e-12).count()
            + m.surface("axis").unwrap().nodes().len(),
        m.n_nodes()
    );
    assert_eq!(2 * m.cells.len(), half.cells.len());
    // second order: arc mid-side nodes on the circle
    let q8 = quarter_disk([0.0, 0.0], 1.0, 16, 4.0, CellKind::Quad8).unwrap();
    for f in &q8.surface("arc").unwrap().facets {
        assert_eq!(f.nodes.len(), 3);
        let x = q8.coords[f.nodes[2]];
        assert!((x[0].hypot(x[1]) - 1.0).abs() < 1e-15);
    }
    for f in &q8.surface("axis").unwrap().facets {
        assert_eq!(q8.coords[f.nodes[2]][0], 0.0);
    }
}

#[test]
fn build_2d_rejects_3d_kinds() {
    for kind in [CellKind::Hex8, CellKind::Tet4] {
        assert!(rectangle([0.0, 0.0], [1.0, 1.0], [2, 2], kind, None).is_err());
        assert!(half_disk(&HalfBall::new([0.0, 0.0], 1.0, 8, [0.0, -1.0], 1.0), kind).is_err());
    }
    for kind in [CellKind::Quad8, CellKind::Tri6] {
        let m = rectangle([0.0, 0.0], [1.0, 1.0], [2, 2], kind, None).unwrap();
        m.check().unwrap();
        assert!(m.cells.iter().all(|c| c.kind == kind));
        check_boundary_cover(&m);
    }
}
