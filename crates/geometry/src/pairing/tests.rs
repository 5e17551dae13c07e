use super::*;
use crate::closest::TRAPEZOID;
use crate::search::MasterIndex;
use signorini_mesh::{Cell, CellKind, Facet};

const TOL: f64 = 1e-12;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn assert_vec(a: [f64; 3], b: [f64; 3], tol: f64) {
    for k in 0..3 {
        assert!(close(a[k], b[k], tol), "{a:?} != {b:?} (tol {tol:e})");
    }
}

/// Bilinear shape functions of the reference square (node order of the
/// quad's corners (−1,−1), (1,−1), (1,1), (−1,1)).
fn bilinear(xi: f64, eta: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ]
}

fn map(w: [f64; 4], p: &[[f64; 3]; 4]) -> [f64; 3] {
    let mut x = [0.0; 3];
    for k in 0..4 {
        for d in 0..3 {
            x[d] += w[k] * p[k][d];
        }
    }
    x
}

/// A mesh of one cell of `kind` on the nodes `coords` in order, with the
/// surfaces "bottom" and "top" of one facet each (`facets`, in that order).
fn one_cell(dim: usize, kind: CellKind, coords: Vec<[f64; 3]>, facets: [Vec<usize>; 2]) -> Mesh {
    let n = coords.len();
    let mut m = Mesh {
        dim,
        coords,
        cells: vec![Cell {
            kind,
            nodes: (0..n).collect(),
        }],
        ..Default::default()
    };
    for (name, nodes) in ["bottom", "top"].into_iter().zip(facets) {
        let facets = vec![Facet { nodes, cell: 0 }];
        m.surfaces.insert(name.into(), Surface { facets });
    }
    m
}

/// One Hex8 cell: `bottom` corners counter-clockwise seen from above, the top
/// ones `height` above them. Surfaces "bottom" and "top".
fn hex(bottom: [[f64; 3]; 4], height: f64) -> Mesh {
    let mut coords = bottom.to_vec();
    coords.extend(bottom.iter().map(|p| [p[0], p[1], p[2] + height]));
    one_cell(
        3,
        CellKind::Hex8,
        coords,
        [vec![0, 3, 2, 1], vec![4, 5, 6, 7]],
    )
}

/// A structured block of nx × ny × 1 Hex8 cells over [0, nx·h] × [0, ny·h],
/// bottom at z = 0, top at z = top(x, y). Surfaces "top" and "bottom".
fn hex_grid(nx: usize, ny: usize, h: f64, top: impl Fn(f64, f64) -> f64) -> Mesh {
    let id = |i: usize, j: usize, k: usize| k * (nx + 1) * (ny + 1) + j * (nx + 1) + i;
    let mut coords = vec![[0.0; 3]; 2 * (nx + 1) * (ny + 1)];
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64 * h, j as f64 * h);
            coords[id(i, j, 0)] = [x, y, 0.0];
            coords[id(i, j, 1)] = [x, y, top(x, y)];
        }
    }
    let mut cells = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let b = [
                id(i, j, 0),
                id(i + 1, j, 0),
                id(i + 1, j + 1, 0),
                id(i, j + 1, 0),
            ];
            let t = [
                id(i, j, 1),
                id(i + 1, j, 1),
                id(i + 1, j + 1, 1),
                id(i, j + 1, 1),
            ];
            cells.push(Cell {
                kind: CellKind::Hex8,
                nodes: b.iter().chain(&t).copied().collect(),
            });
        }
    }
    let mut m = Mesh {
        dim: 3,
        coords,
        cells,
        ..Default::default()
    };
    let all = m.boundary_facets();
    let pick = |k: usize| Surface {
        facets: all
            .iter()
            .filter(|f| f.nodes.iter().all(|&v| v >= k * (nx + 1) * (ny + 1)))
            .filter(|f| f.nodes.iter().all(|&v| v < (k + 1) * (nx + 1) * (ny + 1)))
            .cloned()
            .collect(),
    };
    let (bottom, top) = (pick(0), pick(1));
    m.surfaces.insert("bottom".into(), bottom);
    m.surfaces.insert("top".into(), top);
    m
}

/// A 3D mesh whose surface "s" is the given triangles: each triangle bounds
/// a Tet4 cell whose fourth node lies `depth` below it (against its
/// right-hand normal), so the outward normal is the right-hand one.
fn triangle_surface(points: Vec<[f64; 3]>, tris: &[[usize; 3]], depth: f64) -> Mesh {
    let mut coords = points;
    let mut cells = Vec::new();
    let mut facets = Vec::new();
    for t in tris {
        let [a, b, c] = t.map(|v| coords[v]);
        let n = unit(cross(sub(b, a), sub(c, a))).unwrap();
        let g = [
            (a[0] + b[0] + c[0]) / 3.0 - depth * n[0],
            (a[1] + b[1] + c[1]) / 3.0 - depth * n[1],
            (a[2] + b[2] + c[2]) / 3.0 - depth * n[2],
        ];
        coords.push(g);
        cells.push(Cell {
            kind: CellKind::Tet4,
            nodes: vec![t[0], t[1], t[2], coords.len() - 1],
        });
        facets.push(Facet {
            nodes: t.to_vec(),
            cell: cells.len() - 1,
        });
    }
    let mut m = Mesh {
        dim: 3,
        coords,
        cells,
        ..Default::default()
    };
    m.surfaces.insert("s".into(), Surface { facets });
    m
}

/// The master geometry of the surface "top" of `mesh`.
fn top_of(mesh: &Mesh) -> MasterGeometry<'_> {
    MasterGeometry::Surface {
        mesh,
        surface: &mesh.surfaces["top"],
    }
}

/// Node-to-segment points of the surface "bottom" of `slave` on `g`, by the
/// master's normals.
fn segment_points_on(slave: &Mesh, g: &MasterGeometry) -> Vec<ContactPoint> {
    node_to_segment_pairing(slave, &slave.surfaces["bottom"], g, NormalRule::Master)
        .unwrap()
        .points
}

/// The 2 × 1 rectangle of 4 × 2 Quad4 cells above y = 1, over x ∈ [−1, 1].
fn rectangle_above_the_origin() -> Mesh {
    signorini_mesh::generators::rectangle([-1.0, 1.0], [2.0, 1.0], [4, 2], CellKind::Quad4, None)
        .unwrap()
}

fn points_by_node(pts: &[ContactPoint]) -> std::collections::BTreeMap<usize, &ContactPoint> {
    pts.iter().map(|p| (p.slave_node, p)).collect()
}

fn master_weights(p: &ContactPoint) -> Vec<(usize, f64)> {
    p.terms
        .iter()
        .filter(|t| t.side == TermSide::Master)
        .map(|t| (t.node, -t.weight))
        .collect()
}

fn check_frame(p: &ContactPoint) {
    let (t1, t2, n) = (p.tangent, p.tangent2, p.normal);
    for (a, b, want) in [
        (t1, t1, 1.0),
        (t2, t2, 1.0),
        (n, n, 1.0),
        (t1, t2, 0.0),
        (t1, n, 0.0),
        (t2, n, 0.0),
    ] {
        assert!(close(dot(a, b), want, 1e-14), "{p:?}");
    }
    assert_vec(cross(t1, t2), n, 1e-14);
}

#[test]
fn slave_nodes_above_a_flat_trapezoidal_quad_get_the_bilinear_weights_and_gap() {
    // Master top face: the trapezoid (0,0) (4,0) (3,2) (1,2) at z = 1 (nodes
    // 4..7 of the hex), where x(ξ, η) is not affine.
    let master = hex(TRAPEZOID, 1.0);
    let face = TRAPEZOID.map(|c| [c[0], c[1], 1.0]);
    // Slave: a hex whose bottom corners sit 0.05 above x(ξ, η) of the face.
    let gap = 0.05;
    let params = [[-0.5, -0.6], [0.7, -0.5], [0.4, 0.3], [-0.2, 0.9]];
    let bottom = params.map(|[xi, eta]| {
        let x = map(bilinear(xi, eta), &face);
        [x[0], x[1], x[2] + gap]
    });
    let slave = hex(bottom, 1.0);
    let g = top_of(&master);
    for rule in [
        NormalRule::Master,
        NormalRule::Slave,
        NormalRule::Average,
        NormalRule::Points,
    ] {
        let pts = node_to_segment_pairing(&slave, &slave.surfaces["bottom"], &g, rule)
            .unwrap()
            .points;
        assert_eq!(pts.len(), 4, "{rule:?}");
        let by = points_by_node(&pts);
        for (s, [xi, eta]) in params.into_iter().enumerate() {
            let p = by[&s];
            assert!(close(p.gap0, gap, 1e-14), "{rule:?}: gap {}", p.gap0);
            assert_vec(p.normal, [0.0, 0.0, 1.0], 1e-14);
            assert_vec(p.tangent, [1.0, 0.0, 0.0], 1e-14);
            assert_vec(p.tangent2, [0.0, 1.0, 0.0], 1e-14);
            check_frame(p);
            let want = bilinear(xi, eta);
            let w = master_weights(p);
            assert_eq!(w.iter().map(|t| t.0).collect::<Vec<_>>(), vec![4, 5, 6, 7]);
            for k in 0..4 {
                assert!(close(w[k].1, want[k], 1e-13), "{w:?} vs {want:?}");
            }
            assert!(close(w.iter().map(|t| t.1).sum::<f64>(), 1.0, 1e-15));
            assert_eq!(p.terms[0], Term::slave(s));
        }
    }
}

#[test]
fn a_slave_node_above_a_triangle_gets_its_barycentric_weights() {
    // A tilted triangle; the slave node is 0.1 along its normal above the
    // point of barycentric coordinates (0.2, 0.3, 0.5).
    let (a, b, c) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.5], [0.0, 1.5, 0.25]);
    let master = triangle_surface(vec![a, b, c], &[[0, 1, 2]], 1.0);
    let n = unit(cross(sub(b, a), sub(c, a))).unwrap();
    let lam = [0.2, 0.3, 0.5];
    let h = 0.1;
    let x = [0, 1, 2].map(|d| lam[0] * a[d] + lam[1] * b[d] + lam[2] * c[d] + h * n[d]);
    // The slave: one small triangle of a second surface, its first node at x.
    let e = unit(sub(b, a)).unwrap();
    let f = cross(n, e);
    let q = |s: f64, t: f64| [0, 1, 2].map(|d| x[d] + s * e[d] + t * f[d]);
    // Reverse order: the slave's outward normal faces the master (−n).
    let slave = triangle_surface(vec![x, q(0.0, 0.1), q(0.1, 0.0)], &[[0, 1, 2]], 1.0);
    let g = MasterGeometry::Surface {
        mesh: &master,
        surface: &master.surfaces["s"],
    };
    let pts = node_to_segment_pairing(&slave, &slave.surfaces["s"], &g, NormalRule::Master)
        .unwrap()
        .points;
    let p = points_by_node(&pts)[&0];
    assert!(close(p.gap0, h, 1e-14), "{}", p.gap0);
    assert_vec(p.normal, n, 1e-14);
    let w = master_weights(p);
    for k in 0..3 {
        assert_eq!(w[k].0, k);
        assert!(close(w[k].1, lam[k], 1e-14), "{w:?}");
    }
    check_frame(p);
    // The slave's own normal is −n: the slave rule gives the same normal.
    let pts = node_to_segment_pairing(&slave, &slave.surfaces["s"], &g, NormalRule::Slave)
        .unwrap()
        .points;
    assert_vec(points_by_node(&pts)[&0].normal, n, 1e-14);
}

#[test]
fn nodes_beyond_the_free_edge_of_the_master_are_skipped_and_kinks_inside_are_kept() {
    // Master: 2 × 2 quads over [0, 2]², top at z = 1.
    let master = hex_grid(2, 2, 1.0, |_, _| 1.0);
    let surf = &master.surfaces["top"];
    assert_eq!(surf.facets.len(), 4);
    let g = MasterGeometry::Surface {
        mesh: &master,
        surface: surf,
    };
    // Slave triangles whose nodes are: 0 above an interior vertex (1, 1),
    // 1 on the free edge x = 2, 2 beyond it, 3 beyond by less than the
    // tolerance, 4 beyond the corner (2, 2).
    let xs = vec![
        [1.0, 1.0, 1.2],
        [2.0, 0.5, 1.2],
        [2.3, 0.5, 1.2],
        [2.0 + 1e-9, 1.5, 1.2],
        [2.1, 2.1, 1.2],
    ];
    let slave = triangle_surface(xs, &[[0, 2, 1], [1, 2, 3], [3, 2, 4]], 1.0);
    let pts = node_to_segment_pairing(&slave, &slave.surfaces["s"], &g, NormalRule::Master)
        .unwrap()
        .points;
    let by = points_by_node(&pts);
    assert_eq!(by.keys().copied().collect::<Vec<_>>(), vec![0, 1, 3]);
    // Above the interior vertex: one master node, weight 1.
    let top_node = |x: f64, y: f64| {
        master
            .coords
            .iter()
            .position(|p| p[0] == x && p[1] == y && p[2] == 1.0)
            .unwrap()
    };
    assert_eq!(master_weights(by[&0]), vec![(top_node(1.0, 1.0), 1.0)]);
    assert!(close(by[&0].gap0, 0.2, 1e-14));
    // On the free edge at y = 0.5: half and half between (2, 0) and (2, 1).
    let mut w = master_weights(by[&1]);
    w.sort_by_key(|t| t.0);
    let mut want = vec![(top_node(2.0, 0.0), 0.5), (top_node(2.0, 1.0), 0.5)];
    want.sort_by_key(|t| t.0);
    assert_eq!(w.len(), 2);
    for (a, b) in w.iter().zip(&want) {
        assert_eq!(a.0, b.0);
        assert!(close(a.1, b.1, 1e-14));
    }
    // Within tolerance beyond the edge: clamped onto it.
    assert!(close(by[&3].gap0, 0.2, 1e-14));
    assert!(close(
        master_weights(by[&3]).iter().map(|t| t.1).sum::<f64>(),
        1.0,
        1e-15
    ));

    // A convex ridge along x = 1 (z = 1 − 0.5 |x − 1|): a node above the
    // ridge projects beyond both faces, on their shared side: kept, clamped on
    // the ridge; the points rule gives the true distance.
    let roof = hex_grid(2, 1, 1.0, |x, _| 1.0 - 0.5 * (x - 1.0).abs());
    let g = top_of(&roof);
    let slave = triangle_surface(
        vec![[1.0, 0.5, 1.5], [1.1, 0.5, 1.6], [1.0, 0.6, 1.6]],
        &[[0, 2, 1]],
        1.0,
    );
    let pts = node_to_segment_pairing(&slave, &slave.surfaces["s"], &g, NormalRule::Points)
        .unwrap()
        .points;
    let p = points_by_node(&pts)[&0];
    assert!(close(p.gap0, 0.5, 1e-14), "{}", p.gap0);
    assert_vec(p.normal, [0.0, 0.0, 1.0], 1e-14);
    let w = master_weights(p);
    assert_eq!(w.len(), 2);
    assert!(w.iter().all(|t| close(t.1, 0.5, 1e-14)));
    let pts = node_to_segment_pairing(&slave, &slave.surfaces["s"], &g, NormalRule::Master)
        .unwrap()
        .points;
    let p = points_by_node(&pts)[&0];
    // The left face's normal (−0.5, 0, 1)/|·| (lowest facet at the tie).
    assert!(
        close(p.gap0, 1.0 / 1.25f64.sqrt() * 0.5, 1e-14),
        "{}",
        p.gap0
    );
}

/// Triangles of the cap θ ≤ theta_max of the sphere of radius r about the
/// origin (lat-long: a pole fan, then rings), outward normals.
/// `inward`: the body is outside the sphere (normals towards the centre).
fn sphere_cap(
    r: f64,
    theta_max: f64,
    rings: usize,
    sectors: usize,
    twist: f64,
    inward: bool,
) -> Mesh {
    let mut pts = vec![[0.0, 0.0, r]];
    for i in 1..=rings {
        let th = theta_max * i as f64 / rings as f64;
        for j in 0..sectors {
            let ph = 2.0 * std::f64::consts::PI * (j as f64 + twist * i as f64) / sectors as f64;
            pts.push([
                r * th.sin() * ph.cos(),
                r * th.sin() * ph.sin(),
                r * th.cos(),
            ]);
        }
    }
    let id = |i: usize, j: usize| 1 + (i - 1) * sectors + j % sectors;
    let mut tris = Vec::new();
    for j in 0..sectors {
        tris.push([0, id(1, j), id(1, j + 1)]);
    }
    for i in 1..rings {
        for j in 0..sectors {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    if inward {
        for t in &mut tris {
            t.swap(1, 2);
        }
    }
    triangle_surface(pts, &tris, 0.5 * r)
}

#[test]
fn a_faceted_sphere_cap_gives_the_gap_within_the_chord_error() {
    let r = 1.0;
    let (theta, rings, sectors) = (0.6, 6, 24);
    let master = sphere_cap(r, theta, rings, sectors, 0.0, false);
    // Chord error: the sagitta of the longest edge's arc bounds how far a
    // flat triangle is from the sphere.
    let longest = master.surfaces["s"]
        .facets
        .iter()
        .flat_map(|f| (0..3).map(move |k| (f.nodes[k], f.nodes[(k + 1) % 3])))
        .map(|(a, b)| norm(sub(master.coords[a], master.coords[b])))
        .fold(0.0, f64::max);
    let sagitta = r - (r * r - longest * longest / 4.0).sqrt();
    let h = 0.02;
    // The slave: a finer, twisted cap of radius r + h inside the master's.
    let slave = sphere_cap(r + h, 0.5, 7, 31, 0.37, true);
    let g = MasterGeometry::Surface {
        mesh: &master,
        surface: &master.surfaces["s"],
    };
    let n_slave = slave.surfaces["s"].nodes().len();
    for rule in [NormalRule::Master, NormalRule::Points, NormalRule::Average] {
        let pts = node_to_segment_pairing(&slave, &slave.surfaces["s"], &g, rule)
            .unwrap()
            .points;
        assert_eq!(
            pts.len(),
            n_slave,
            "{rule:?}: every slave node faces the cap"
        );
        let mut worst: f64 = 0.0;
        for p in &pts {
            worst = worst.max((p.gap0 - h).abs());
            if rule == NormalRule::Points {
                // The distance to the facets: they lie inside the ball, by
                // at most the sagitta.
                assert!(p.gap0 >= h - 1e-14, "{} < {h}", p.gap0);
                assert!(p.gap0 <= h + sagitta, "{} vs {h} + {sagitta}", p.gap0);
            } else {
                // At a kink (the pole fan) the face normal is tilted from
                // x − x_m: n·(x − x_m) is a little below the distance.
                assert!((p.gap0 - h).abs() <= sagitta, "{rule:?}: {} vs {h}", p.gap0);
            }
            // The normal is close to the radial direction.
            let radial = unit(p.x).unwrap();
            assert!(dot(p.normal, radial) > (longest / r).cos(), "{p:?}");
            check_frame(p);
            let w: f64 = master_weights(p).iter().map(|t| t.1).sum();
            assert!(close(w, 1.0, 1e-14));
        }
        assert!(worst > 0.0 && worst <= sagitta);
    }
}

/// Small deterministic generator (xorshift64*), uniform in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn the_r_tree_finds_the_same_facet_as_a_loop_over_all_facets() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    // A rough, jittered height field: 32 × 30 cells, two triangles each.
    let (nx, ny) = (32, 30);
    let mut pts = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            pts.push([
                i as f64 + 0.3 * (rng.next() - 0.5),
                j as f64 + 0.3 * (rng.next() - 0.5),
                2.0 * rng.next(),
            ]);
        }
    }
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    assert_eq!(tris.len(), 1920);
    let mesh = triangle_surface(pts, &tris, 0.5);
    let index = MasterIndex::new(&mesh, &mesh.surfaces["s"]).unwrap();
    let mut far = 0;
    let mut near_visits = 0;
    for q in 0..1000 {
        // Most queries near the surface, some far away.
        let spread = if q % 10 == 0 { 40.0 } else { 1.0 };
        let x = [
            -2.0 + 36.0 * rng.next(),
            -2.0 + 34.0 * rng.next(),
            1.0 + spread * (2.0 * rng.next() - 1.0) * 2.0,
        ];
        let (hit, visits) = index.closest_counting(x);
        let hit = hit.unwrap();
        let (k, c) = index.closest_brute_force(x).unwrap();
        assert_eq!(hit.piece, k, "query {x:?}");
        assert_eq!(hit.closest.dist, c.dist);
        far += usize::from(spread > 1.0);
        if spread == 1.0 {
            near_visits += visits;
        }
    }
    assert!(far > 0);
    // The index prunes: near the surface a query projects on a few dozen
    // triangles at most, not on all 1920.
    let mean = near_visits as f64 / 900.0;
    assert!(mean < 40.0, "{mean} projections per query");

    // Warped bilinear quads: the same.
    let quads = hex_grid(20, 20, 1.0, |x, y| {
        1.0 + 0.4 * (1.3 * x).sin() * (0.7 * y).cos()
    });
    let index = MasterIndex::new(&quads, &quads.surfaces["top"]).unwrap();
    for _ in 0..300 {
        let x = [
            -1.0 + 22.0 * rng.next(),
            -1.0 + 22.0 * rng.next(),
            3.0 * rng.next(),
        ];
        let hit = index.closest(x).unwrap();
        let (k, c) = index.closest_brute_force(x).unwrap();
        assert_eq!(hit.piece, k, "query {x:?}");
        assert_eq!(hit.closest.dist, c.dist);
    }
}

#[test]
fn tangent_frames_are_orthonormal_and_right_handed() {
    let mut rng = Rng(12345);
    let mut normals = vec![
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        unit([1.0, 1.0, 1.0]).unwrap(),
        unit([-1.0, 1.0, 1.0]).unwrap(),
    ];
    for _ in 0..1000 {
        if let Some(n) = unit([rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5]) {
            normals.push(n);
        }
    }
    for n in normals {
        let (t1, t2) = tangent_frame(n);
        let p = ContactPoint {
            slave_node: 0,
            x: [0.0; 3],
            normal: n,
            tangent: t1,
            tangent2: t2,
            gap0: 0.0,
            terms: vec![],
            normal_row: vec![],
            tangent_rows: [vec![], vec![]],
        };
        check_frame(&p);
        // Deterministic: the same normal gives the same frame.
        assert_eq!(tangent_frame(n), (t1, t2));
    }
    assert_eq!(
        tangent_frame([0.0, 0.0, 1.0]),
        ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    );
    assert_eq!(
        tangent_frame([1.0, 0.0, 0.0]),
        ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
    );
    // Rounding noise in a computed normal does not flip the frame.
    for noise in [[1e-16, -3e-17], [-2e-17, 1e-15], [0.0, 1e-12]] {
        let n = unit([noise[0], noise[1], 1.0]).unwrap();
        let (t1, t2) = tangent_frame(n);
        assert_vec(t1, [1.0, 0.0, 0.0], 1e-11);
        assert_vec(t2, [0.0, 1.0, 0.0], 1e-11);
        let n = unit([-1.0, noise[0], noise[1]]).unwrap();
        let (t1, t2) = tangent_frame(n);
        assert_vec(t1, [0.0, 1.0, 0.0], 1e-11);
        assert_vec(t2, [0.0, 0.0, -1.0], 1e-11);
    }
}

#[test]
fn rigid_sphere_and_plane_in_3d() {
    let slave = hex(
        [
            [0.0, 0.0, 2.0],
            [1.0, 0.0, 2.0],
            [1.0, 1.0, 2.0],
            [0.0, 1.0, 2.0],
        ],
        1.0,
    );
    let surf = &slave.surfaces["bottom"];
    let (c, r) = ([0.2, 0.3, 0.5], 1.2);
    let g = MasterGeometry::Sphere {
        center: c,
        radius: r,
    };
    let pts = node_to_segment_pairing(&slave, surf, &g, NormalRule::Master)
        .unwrap()
        .points;
    assert_eq!(pts.len(), 4);
    for p in &pts {
        let d = sub(p.x, c);
        assert!(
            close(p.gap0, norm(d) - r, TOL),
            "{} vs {}",
            p.gap0,
            norm(d) - r
        );
        assert_vec(p.normal, unit(d).unwrap(), 1e-15);
        assert_eq!(p.terms, vec![Term::slave(p.slave_node)]);
        check_frame(p);
    }
    // The points rule agrees with the master rule on a sphere.
    let pts2 = node_to_node_pairing(&slave, surf, &g, NormalRule::Points)
        .unwrap()
        .points;
    for (a, b) in pts.iter().zip(&pts2) {
        assert!(close(a.gap0, b.gap0, TOL));
        assert_vec(a.normal, b.normal, 1e-14);
    }
    // Overlap: a node inside the sphere has a negative gap, normal outward.
    let big = MasterGeometry::Sphere {
        center: c,
        radius: 2.0,
    };
    let pts = node_to_segment_pairing(&slave, surf, &big, NormalRule::Master)
        .unwrap()
        .points;
    for p in &pts {
        let d = sub(p.x, c);
        assert!(p.gap0 < 0.0 && close(p.gap0, norm(d) - 2.0, TOL));
        assert_vec(p.normal, unit(d).unwrap(), 1e-15);
    }
    for bad in [0.0, -1.0, f64::NAN] {
        let g = MasterGeometry::Sphere {
            center: c,
            radius: bad,
        };
        assert!(node_to_segment_pairing(&slave, surf, &g, NormalRule::Master).is_err());
    }
    // A node at the centre has no normal.
    let g = MasterGeometry::Sphere {
        center: slave.coords[0],
        radius: 0.5,
    };
    assert!(node_to_segment_pairing(&slave, surf, &g, NormalRule::Master).is_err());

    // Tilted plane: gap = signed distance, tangents in the plane.
    let n = unit([0.1, -0.2, 1.0]).unwrap();
    let g = MasterGeometry::Plane {
        point: [0.5, 0.5, 1.0],
        normal: n,
    };
    let pts = node_to_segment_pairing(&slave, surf, &g, NormalRule::Master)
        .unwrap()
        .points;
    for p in &pts {
        assert!(close(p.gap0, dot(sub(p.x, [0.5, 0.5, 1.0]), n), TOL));
        assert_vec(p.normal, n, 0.0);
        check_frame(p);
    }
}

#[test]
fn rigid_disc_in_2d() {
    let slave = rectangle_above_the_origin();
    let surf = &slave.surfaces["bottom"];
    // The centre's z is ignored in 2D.
    let g = MasterGeometry::Sphere {
        center: [0.1, -0.5, 7.0],
        radius: 1.25,
    };
    let pts = node_to_segment_pairing(&slave, surf, &g, NormalRule::Master)
        .unwrap()
        .points;
    assert_eq!(pts.len(), 5);
    for p in &pts {
        let d = [p.x[0] - 0.1, p.x[1] + 0.5, 0.0];
        assert!(close(p.gap0, norm(d) - 1.25, TOL));
        assert_vec(p.normal, unit(d).unwrap(), 1e-15);
        assert_vec(p.tangent, [p.normal[1], -p.normal[0], 0.0], 0.0);
        assert_eq!(p.tangent2, [0.0; 3]);
    }
}

/// One Quad8 cell: corners `c` (counter-clockwise), mid-sides `m` of 0-1,
/// 1-2, 2-3, 3-0; surfaces "bottom" (edge 0-1) and "top" (edge 2-3) as
/// quadratic edges `[corner, corner, mid]`.
fn quad8(c: [[f64; 2]; 4], m: [[f64; 2]; 4]) -> Mesh {
    let coords = c.iter().chain(&m).map(|p| [p[0], p[1], 0.0]).collect();
    one_cell(2, CellKind::Quad8, coords, [vec![0, 1, 4], vec![2, 3, 6]])
}

/// The unit square as one Quad8, the mid-side node 6 of its top edge at
/// (0.5, `top_mid_y`).
fn unit_square_quad8(top_mid_y: f64) -> Mesh {
    quad8(
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        [[0.5, 0.0], [1.0, 0.5], [0.5, top_mid_y], [0.0, 0.5]],
    )
}

#[test]
fn quadratic_edges_are_piecewise_linear_through_the_mid_side_node() {
    // Master: the unit square's top edge 2-3, its mid-side node 6 raised to
    // (0.5, 1.1): two straight halves (1,1)–(0.5,1.1) and (0.5,1.1)–(0,1).
    let master = unit_square_quad8(1.1);
    // Slave: a Quad8 above, bottom edge nodes 0 (0.2, 1.5), 1 (0.9, 1.5) and
    // mid-side 4 (0.55, 1.5) (a straight edge).
    let slave = quad8(
        [[0.2, 1.5], [0.9, 1.5], [0.9, 2.5], [0.2, 2.5]],
        [[0.55, 1.5], [0.9, 2.0], [0.55, 2.5], [0.2, 2.0]],
    );
    let g = top_of(&master);
    let pts = segment_points_on(&slave, &g);
    let by = points_by_node(&pts);
    // The mid-side node is a contact point like the corners.
    assert_eq!(by.keys().copied().collect::<Vec<_>>(), vec![0, 1, 4]);
    // Half c0–mid = (1,1)–(0.5,1.1) (nodes 2, 6); half mid–c1 = (0.5,1.1)–(0,1)
    // (nodes 6, 3). Expected: the projection on the straight half, its linear
    // weights, the half's normal.
    for (s, a, b) in [(0, 6, 3), (1, 2, 6)] {
        let p = by[&s];
        let (pa, pb) = (master.coords[a], master.coords[b]);
        let ab = sub(pb, pa);
        let t = dot(sub(p.x, pa), ab) / dot(ab, ab);
        assert!((0.0..=1.0).contains(&t));
        let xm = [pa[0] + t * ab[0], pa[1] + t * ab[1], 0.0];
        let mut nrm = unit([ab[1], -ab[0], 0.0]).unwrap();
        if nrm[1] < 0.0 {
            nrm = [-nrm[0], -nrm[1], 0.0];
        }
        assert_vec(p.normal, nrm, 1e-15);
        assert!(close(p.gap0, dot(nrm, sub(p.x, xm)), 1e-15));
        assert!(
            close(p.gap0, norm(sub(p.x, xm)), 1e-15),
            "the closest point"
        );
        let mut w = master_weights(p);
        w.sort_by_key(|x| x.0);
        let mut want = vec![(a, 1.0 - t), (b, t)];
        want.sort_by_key(|x| x.0);
        for (u, v) in w.iter().zip(&want) {
            assert_eq!(u.0, v.0);
            assert!(close(u.1, v.1, 1e-15), "{w:?} vs {want:?}");
        }
        assert_eq!(p.tangent, [p.normal[1], -p.normal[0], 0.0]);
        assert_eq!(p.tangent2, [0.0; 3]);
    }
    // Node 4 (0.55, 1.5) lies beyond both halves, over the convex kink at the
    // mid-side node (inside the master): kept, on node 6 alone; the points
    // rule gives the distance to it.
    assert_eq!(master_weights(by[&4]), vec![(6, 1.0)]);
    let pts = node_to_segment_pairing(&slave, &slave.surfaces["bottom"], &g, NormalRule::Points)
        .unwrap()
        .points;
    let p = points_by_node(&pts)[&4];
    let d = sub(p.x, master.coords[6]);
    assert!(close(p.gap0, norm(d), 1e-15));
    assert_vec(p.normal, unit(d).unwrap(), 1e-15);

    // A straight quadratic edge: a node above x = 0.8 projects on the half
    // (1,1)–(0.5,1) at ξ = 0.4: weights 0.6 (corner 2) and 0.4 (mid 6).
    let flat = unit_square_quad8(1.0);
    let slave = quad8(
        [[0.8, 1.25], [1.6, 1.25], [1.6, 2.0], [0.8, 2.0]],
        [[1.2, 1.25], [1.6, 1.6], [1.2, 2.0], [0.8, 1.6]],
    );
    let g = top_of(&flat);
    let pts = segment_points_on(&slave, &g);
    let by = points_by_node(&pts);
    // Node 4 (1.2, 1.25) and node 1 (1.6, 1.25) lie beyond the free end (1, 1).
    assert_eq!(by.keys().copied().collect::<Vec<_>>(), vec![0]);
    let p = by[&0];
    assert!(close(p.gap0, 0.25, 1e-15));
    assert_vec(p.normal, [0.0, 1.0, 0.0], 0.0);
    let w = master_weights(p);
    assert_eq!(w.len(), 2);
    assert_eq!((w[0].0, w[1].0), (2, 6));
    assert!(
        close(w[0].1, 0.6, 1e-15) && close(w[1].1, 0.4, 1e-15),
        "{w:?}"
    );
}

#[test]
fn nodal_normals_of_quadratic_edges_and_3d_faces() {
    // Quadratic edge bent upwards symmetrically: the mid-side node's normal
    // is vertical, the corners' lean outwards by the halves' slope.
    let m = unit_square_quad8(1.2);
    let nn: std::collections::BTreeMap<_, _> =
        nodal_normals(&m, &m.surfaces["top"]).into_iter().collect();
    assert_eq!(nn.keys().copied().collect::<Vec<_>>(), vec![2, 3, 6]);
    assert_vec(nn[&6], [0.0, 1.0, 0.0], 1e-15);
    let s = unit([0.2, 0.5, 0.0]).unwrap();
    assert_vec(nn[&2], s, 1e-15);
    assert_vec(nn[&3], [-s[0], s[1], 0.0], 1e-15);

    // A unit cube: each corner's normal is the diagonal (±1, ±1, ±1)/√3.
    let mut cube = hex(
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        1.0,
    );
    let all = Surface {
        facets: cube.boundary_facets(),
    };
    assert_eq!(all.facets.len(), 6);
    cube.surfaces.insert("all".into(), all);
    for (v, n) in nodal_normals(&cube, &cube.surfaces["all"]) {
        let x = cube.coords[v];
        let want = unit([x[0] - 0.5, x[1] - 0.5, x[2] - 0.5]).unwrap();
        assert_vec(n, want, 1e-15);
    }
    // On a flat grid every normal is +z.
    let grid = hex_grid(3, 2, 0.7, |x, y| 2.0 + 0.0 * x * y);
    for (_, n) in nodal_normals(&grid, &grid.surfaces["top"]) {
        assert_vec(n, [0.0, 0.0, 1.0], 1e-15);
    }
}

#[test]
fn node_to_node_in_3d_on_matching_meshes() {
    let master = hex_grid(3, 2, 0.5, |_, _| 1.0);
    // The slave: the same grid shifted up by 1.0 + gap; its bottom faces the
    // master's top.
    let gap = 0.01;
    let mut slave = hex_grid(3, 2, 0.5, |_, _| 1.0);
    for p in &mut slave.coords {
        p[2] += 1.0 + gap;
    }
    let g = top_of(&master);
    for rule in [NormalRule::Master, NormalRule::Slave, NormalRule::Points] {
        let pts = node_to_node_pairing(&slave, &slave.surfaces["bottom"], &g, rule)
            .unwrap()
            .points;
        assert_eq!(pts.len(), 12);
        for p in &pts {
            assert!(close(p.gap0, gap, 1e-14), "{rule:?} {}", p.gap0);
            assert_vec(p.normal, [0.0, 0.0, 1.0], 1e-15);
            let w = master_weights(p);
            assert_eq!(w.len(), 1);
            let xm = master.coords[w[0].0];
            assert!(close(xm[0], p.x[0], 0.0) && close(xm[1], p.x[1], 0.0));
            assert!(close(w[0].1, 1.0, 0.0));
            check_frame(p);
        }
    }
    // A shifted slave has no facing master node: an error naming x, y, z,
    // whatever the rule; the points rule's normal joins the two nodes, so it
    // has no offset of its own to show (it passed, found by a third
    // robustness sweep: a flat punch on a coarser block "converged" 25 % off).
    for p in &mut slave.coords {
        p[0] += 0.1;
    }
    for rule in [
        NormalRule::Master,
        NormalRule::Slave,
        NormalRule::Average,
        NormalRule::Points,
    ] {
        let e = node_to_node_pairing(&slave, &slave.surfaces["bottom"], &g, rule)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("matching meshes") && e.contains("1.010000)"),
            "{rule:?}: {e}"
        );
    }
    // 2D slave against a 3D master: refused.
    let flat = signorini_mesh::generators::rectangle(
        [0.0, 0.0],
        [1.0, 1.0],
        [1, 1],
        CellKind::Quad4,
        None,
    )
    .unwrap();
    assert!(node_to_node_pairing(&flat, &flat.surfaces["top"], &g, NormalRule::Master).is_err());
    assert!(node_to_segment_pairing(&flat, &flat.surfaces["top"], &g, NormalRule::Master).is_err());
}

#[test]
fn linear_2d_node_to_segment_weights_and_skips() {
    // Master: the top of [0, 2] × [0, 1] with two edges; slave nodes at
    // x = −0.5, 0, 0.5, 1.5, 2, 2.5 (y = 1.1).
    let master = signorini_mesh::generators::rectangle(
        [0.0, 0.0],
        [2.0, 1.0],
        [2, 1],
        CellKind::Quad4,
        None,
    )
    .unwrap();
    let slave = signorini_mesh::generators::rectangle(
        [-0.5, 1.1],
        [3.0, 1.0],
        [6, 1],
        CellKind::Quad4,
        None,
    )
    .unwrap();
    let g = top_of(&master);
    let pts = segment_points_on(&slave, &g);
    let xs: Vec<f64> = pts.iter().map(|p| p.x[0]).collect();
    assert_eq!(xs, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
    for p in &pts {
        assert!(close(p.gap0, 0.1, 1e-15));
        assert_eq!(p.normal, [0.0, 1.0, 0.0]);
        assert_eq!(p.tangent, [1.0, 0.0, 0.0]);
        assert_eq!(p.tangent2, [0.0; 3]);
        let w = master_weights(p);
        let sum: f64 = w.iter().map(|t| t.1).sum();
        assert!(close(sum, 1.0, 1e-15));
        if p.x[0] == 0.5 {
            assert_eq!(w.len(), 2);
            assert!(w.iter().all(|t| close(t.1, 0.5, 1e-15)));
        }
    }
}

mod pairing;
