//! The bounded pairing: with the slave (or average) normal, a
//! slave node is paired with the master point its normal line meets, or is
//! not a contact point; every rule leaves out nodes beyond the search
//! distance. 2D (segments, rigid plane and disc) and 3D (bilinear quads,
//! triangles).

use super::*;

/// n = −(0.2, −1)/√1.04: the slave normal of an edge of slope 0.2 whose
/// outward normal points down (2D), or of a face tilted the same way about y
/// (3D).
fn tilted() -> [f64; 3] {
    unit([-0.2, 0.0, 1.0]).unwrap()
}

/// Quad4 cells (corners counter-clockwise) whose first edge (corner 0 to 1)
/// is in the surface "s": the bottoms of the slave bodies.
fn quads_2d(cells: &[[[f64; 2]; 4]]) -> Mesh {
    let mut m = Mesh {
        dim: 2,
        ..Default::default()
    };
    let mut facets = Vec::new();
    for c in cells {
        let first = m.coords.len();
        m.coords.extend(c.iter().map(|p| [p[0], p[1], 0.0]));
        m.cells.push(Cell {
            kind: CellKind::Quad4,
            nodes: (first..first + 4).collect(),
        });
        facets.push(Facet {
            nodes: vec![first, first + 1],
            cell: m.cells.len() - 1,
        });
    }
    m.surfaces.insert("s".into(), Surface { facets });
    m
}

/// A quad of height 0.5 above the edge from `a` along slope 0.2 over `dx`.
fn tilted_quad(a: [f64; 2], dx: f64) -> [[f64; 2]; 4] {
    let b = [a[0] + dx, a[1] + 0.2 * dx];
    [a, b, [b[0], b[1] + 0.5], [a[0], a[1] + 0.5]]
}

/// Checks that the master point of p lies on its normal line, at `want`,
/// and that its master weights sum to 1 and reproduce it.
fn check_on_the_line(p: &ContactPoint, master: &Mesh, want: [f64; 3]) {
    let on_line = [
        p.x[0] - p.gap0 * p.normal[0],
        p.x[1] - p.gap0 * p.normal[1],
        p.x[2] - p.gap0 * p.normal[2],
    ];
    assert_vec(on_line, want, 1e-14);
    let w = master_weights(p);
    assert!(close(w.iter().map(|t| t.1).sum::<f64>(), 1.0, 1e-14));
    let mut xm = [0.0; 3];
    for (node, wk) in w {
        for (x, c) in xm.iter_mut().zip(master.coords[node]) {
            *x += wk * c;
        }
    }
    assert_vec(xm, want, 1e-14);
}

#[test]
fn a_slave_normal_that_misses_the_master_segments_is_no_contact_point() {
    // Master: the top y = 1 of [0, 2] × [0, 1], four segments.
    let master = signorini_mesh::generators::rectangle(
        [0.0, 0.0],
        [2.0, 1.0],
        [4, 1],
        CellKind::Quad4,
        None,
    )
    .unwrap();
    let g = MasterGeometry::Surface {
        mesh: &master,
        surface: &master.surfaces["top"],
    };
    // Slave edges of slope 0.2: nodes 0, 1 above the master; 4, 5 beyond
    // its end x = 2 (their normal lines meet y = 1 at x = 2.24, 2.656); 8, 9
    // 1.5 above it, farther than the search distance (half the master's
    // size √5).
    let slave = quads_2d(&[
        tilted_quad([0.5, 1.2], 1.0),
        tilted_quad([2.2, 1.2], 0.4),
        tilted_quad([0.8, 2.5], 0.4),
    ]);
    let s = &slave.surfaces["s"];
    let pairing = node_to_segment_pairing(&slave, s, &g, NormalRule::Slave).unwrap();
    let reach = 0.5 * 5f64.sqrt();
    assert!(close(pairing.dropped.search_distance, reach, 1e-15));
    let by = points_by_node(&pairing.points);
    assert_eq!(by.keys().copied().collect::<Vec<_>>(), vec![0, 1]);
    let (off_surface, far, missed) = (0, 2, 2);
    assert_eq!(
        (
            pairing.dropped.off_surface,
            pairing.dropped.far,
            pairing.dropped.missed
        ),
        (off_surface, far, missed)
    );
    let note = pairing.dropped.note().unwrap();
    assert!(
        note.starts_with("4 slave node(s) are not contact points"),
        "{note}"
    );
    // Node 0 (0.5, 1.2): the line x − g n, n = (−0.2, 1)/√1.04, meets y = 1
    // at x = 0.54 after g = 0.2 √1.04: weights 0.92, 0.08 on the segment
    // (0.5, 1)–(1, 1). Node 1 (1.5, 1.4) meets it at 1.58.
    let n = tilted();
    let n2 = [n[0], n[2], 0.0];
    for (s, x, g) in [(0, 0.54, 0.2), (1, 1.58, 0.4)] {
        let p = by[&s];
        assert_vec(p.normal, n2, 1e-15);
        assert!(close(p.gap0, g * 1.04f64.sqrt(), 1e-14), "{}", p.gap0);
        check_on_the_line(p, &master, [x, 1.0, 0.0]);
    }
    let node_at = |x: f64| {
        (0..master.n_nodes())
            .find(|&v| master.coords[v] == [x, 1.0, 0.0])
            .unwrap()
    };
    let mut w = master_weights(by[&0]);
    w.sort_by_key(|t| t.0);
    let mut want = vec![(node_at(0.5), 0.92), (node_at(1.0), 0.08)];
    want.sort_by_key(|t| t.0);
    for (a, b) in w.iter().zip(&want) {
        assert!(a.0 == b.0 && close(a.1, b.1, 1e-14), "{w:?}");
    }
    // The master rule: nodes 4, 5 project beyond the free end (off the
    // surface), 8, 9 are far; the average rule meets the master like the
    // slave rule.
    let m = node_to_segment_pairing(&slave, s, &g, NormalRule::Master).unwrap();
    assert_eq!(
        (m.points.len(), m.dropped.off_surface, m.dropped.far),
        (2, 2, 2)
    );
    let a = node_to_segment_pairing(&slave, s, &g, NormalRule::Average).unwrap();
    assert_eq!((a.points.len(), a.dropped.missed, a.dropped.far), (2, 2, 2));
    for p in &a.points {
        let xm = [p.x[0] - p.gap0 * p.normal[0], p.x[1] - p.gap0 * p.normal[1]];
        assert!(close(xm[1], 1.0, 1e-14) && (0.0..=2.0).contains(&xm[0]));
    }
}

#[test]
fn a_slave_normal_parallel_to_a_rigid_obstacle_meets_nothing() {
    // The 2 × 1 rectangle above y = 1: its side x = −1 has the outward
    // normal (−1, 0), parallel to the plane y = 0 and passing above the disc.
    let slave = rectangle_above_the_origin();
    let plane = MasterGeometry::Plane {
        point: [0.0, 0.0, 0.0],
        normal: [0.0, 1.0, 0.0],
    };
    let disc = MasterGeometry::Sphere {
        center: [0.0, -0.5, 0.0],
        radius: 1.25,
    };
    // Search distance: half the slave's size √5. The side's nodes y = 1,
    // 1.5, 2 are 1, 1.5, 2 from the plane and 0.55, 0.99, 1.44 from the
    // disc: those within it are missed, the others far.
    let left = &slave.surfaces["left"];
    for (g, missed, far) in [(&plane, 1, 2), (&disc, 2, 1)] {
        let p = node_to_segment_pairing(&slave, left, g, NormalRule::Slave).unwrap();
        assert_eq!(p.points.len(), 0);
        assert_eq!((p.dropped.missed, p.dropped.far), (missed, far));
        // The master normal pairs those within reach (a gap of about 1:
        // harmless, but a contact point).
        let p = node_to_segment_pairing(&slave, left, g, NormalRule::Master).unwrap();
        assert_eq!((p.points.len(), p.dropped.far), (missed, far));
    }
    // The bottom y = 1 against the disc along the slave normal (0, 1): the
    // line x = const meets the circle at y = −0.5 + √(1.25² − x²).
    let bottom = &slave.surfaces["bottom"];
    let p = node_to_segment_pairing(&slave, bottom, &disc, NormalRule::Slave).unwrap();
    assert_eq!(p.points.len(), 5);
    for q in &p.points {
        let want = 1.0 - (-0.5 + (1.5625 - q.x[0] * q.x[0]).sqrt());
        assert!(close(q.gap0, want, 1e-14), "{} vs {want}", q.gap0);
        assert_vec(q.normal, [0.0, 1.0, 0.0], 0.0);
    }
}

/// A slave body whose surface "s" is two triangles tilted like [`tilted`]:
/// nodes 0–2 above (0.5..1, 0.5..1.5), nodes 3–5 the same shifted by
/// `shift` in x.
fn tilted_triangles(shift: f64) -> Mesh {
    let t = |dx: f64| {
        [
            [0.5 + dx, 0.5, 1.3],
            [0.5 + dx, 1.5, 1.3],
            [1.0 + dx, 0.5, 1.4],
        ]
    };
    let pts: Vec<[f64; 3]> = t(0.0).into_iter().chain(t(shift)).collect();
    triangle_surface(pts, &[[0, 1, 2], [3, 4, 5]], 1.0)
}

#[test]
fn a_slave_normal_meets_a_quad_or_triangle_master_or_is_dropped_in_3d() {
    // Masters: the top z = 1 of [0, 2]² as 2 × 2 bilinear quads, and of
    // [0, 2] × [0, 2] as four triangles.
    let quads = hex_grid(2, 2, 1.0, |_, _| 1.0);
    let corners = vec![
        [0.0, 0.0, 1.0],
        [2.0, 0.0, 1.0],
        [2.0, 2.0, 1.0],
        [0.0, 2.0, 1.0],
        [1.0, 1.0, 1.0],
    ];
    let tris = triangle_surface(corners, &[[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]], 1.0);
    // Triangle 3–5 lies beyond the edge x = 2 (its lines meet z = 1 at
    // x = 2.16, 2.66).
    let slave = tilted_triangles(1.6);
    let s = &slave.surfaces["s"];
    let n = tilted();
    for (master, surface) in [(&quads, "top"), (&tris, "s")] {
        let g = MasterGeometry::Surface {
            mesh: master,
            surface: &master.surfaces[surface],
        };
        let pairing = node_to_segment_pairing(&slave, s, &g, NormalRule::Slave).unwrap();
        assert_eq!(pairing.dropped.missed, 3, "{surface}");
        let by = points_by_node(&pairing.points);
        assert_eq!(by.keys().copied().collect::<Vec<_>>(), vec![0, 1, 2]);
        // Node 0 (0.5, 0.5, 1.3) meets z = 1 at (0.56, 0.5) after g = 0.3
        // √1.04; node 1 at (0.56, 1.5); node 2 (1, 0.5, 1.4) at (1.08, 0.5).
        for (v, xm, g) in [
            (0, [0.56, 0.5], 0.3),
            (1, [0.56, 1.5], 0.3),
            (2, [1.08, 0.5], 0.4),
        ] {
            let p = by[&v];
            assert_vec(p.normal, n, 1e-15);
            assert!(close(p.gap0, g * 1.04f64.sqrt(), 1e-14), "{}", p.gap0);
            check_on_the_line(p, master, [xm[0], xm[1], 1.0]);
        }
        // The weights of node 0: bilinear (1 − |x − X|)(1 − |y − Y|) on the
        // quad [0, 1]²; barycentric on the triangle (0,0)–(2,0)–(1,1):
        // (0.56, 0.5) = 0.47 (0,0) + 0.03 (2,0) + 0.5 (1,1).
        for (node, w) in master_weights(by[&0]) {
            let [x, y, _] = master.coords[node];
            let want = if surface == "top" {
                (1.0 - (0.56 - x).abs()) * (1.0 - (0.5 - y).abs())
            } else {
                match (x, y) {
                    (0.0, 0.0) => 0.47,
                    (2.0, 0.0) => 0.03,
                    _ => 0.5,
                }
            };
            assert!(
                close(w, want, 1e-14),
                "{surface}: node {node} weight {w} vs {want}"
            );
        }
    }
}
