//! The Tri3 meshes of the disks: `half_disk` is the mirror image of itself
//! about the pole's radius, and every node of the arc has the same kind of star
//! (the pole included), so that no node of a contact zone at the pole is set
//! apart from its neighbours (docs/theory/validation-cases.md §1-2).

use signorini_mesh::generators::{
    box_mesh, half_disk, quarter_disk, rectangle, BoxSide, HalfBall, RectSide,
};
use signorini_mesh::{CellKind, Mesh};
use std::collections::HashSet;

/// The node at `p` within `tol` (nodes sorted by x in `by_x`), if any.
fn node_at(m: &Mesh, by_x: &[usize], p: [f64; 2], tol: f64) -> Option<usize> {
    let start = by_x.partition_point(|&n| m.coords[n][0] < p[0] - tol);
    by_x[start..]
        .iter()
        .take_while(|&&n| m.coords[n][0] <= p[0] + tol)
        .copied()
        .find(|&n| (m.coords[n][1] - p[1]).abs() <= tol)
}

/// Asserts that the mirror image about the line through `center` along `axis`
/// of every node is a node and of every cell a cell.
fn assert_mirror_symmetric(m: &Mesh, center: [f64; 2], axis: [f64; 2], tol: f64, what: &str) {
    let l = axis[0].hypot(axis[1]);
    let e = [axis[0] / l, axis[1] / l];
    let mut by_x: Vec<usize> = (0..m.n_nodes()).collect();
    by_x.sort_by(|&a, &b| m.coords[a][0].total_cmp(&m.coords[b][0]));
    let mirror: Vec<usize> = (0..m.n_nodes())
        .map(|n| {
            let d = [m.coords[n][0] - center[0], m.coords[n][1] - center[1]];
            let s = 2.0 * (d[0] * e[0] + d[1] * e[1]);
            let p = [center[0] + s * e[0] - d[0], center[1] + s * e[1] - d[1]];
            node_at(m, &by_x, p, tol)
                .unwrap_or_else(|| panic!("{what}: no node at the mirror image of node {n}"))
        })
        .collect();
    let sorted = |nodes: &mut Vec<usize>| {
        nodes.sort_unstable();
        nodes.clone()
    };
    let cells: HashSet<Vec<usize>> = m
        .cells
        .iter()
        .map(|c| sorted(&mut c.nodes.clone()))
        .collect();
    for (c, cell) in m.cells.iter().enumerate() {
        let mut image: Vec<usize> = cell.nodes.iter().map(|&n| mirror[n]).collect();
        assert!(
            cells.contains(&sorted(&mut image)),
            "{what}: the mirror image of cell {c} is not a cell"
        );
    }
}

/// The number of cells holding each node of the surface `name`, along it.
fn stars(m: &Mesh, name: &str) -> Vec<usize> {
    m.surface(name)
        .unwrap()
        .nodes()
        .iter()
        .map(|&n| m.cells.iter().filter(|c| c.nodes.contains(&n)).count())
        .collect()
}

#[test]
fn tri3_half_disk_is_its_own_mirror_image_about_the_pole_radius() {
    // an odd count too: the pole is then the middle of an arc facet
    for (n, g) in [(16, 1.0), (17, 2.0), (32, 4.0), (160, 16.0)] {
        for (c, r, pole) in [
            ([0.0, 1.0], 1.0, [0.0, -1.0]),
            ([0.3, -1.2], 2.5, [1.0, 2.0]),
        ] {
            let m = half_disk(&HalfBall::new(c, r, n, pole, g), CellKind::Tri3).unwrap();
            assert_mirror_symmetric(&m, c, pole, 1e-9 * r, &format!("n={n} g={g} pole={pole:?}"));
        }
    }
}

#[test]
fn every_arc_node_of_the_tri3_disks_has_the_same_star() {
    // half disk: the pole alike its neighbours (cut in two, it was in 2 or 4
    // triangles where they were in 3)
    for (n, g) in [(16, 1.0), (80, 16.0), (160, 16.0)] {
        let ball = HalfBall::new([0.0, 1.0], 1.0, n, [0.0, -1.0], g);
        let m = half_disk(&ball, CellKind::Tri3).unwrap();
        let s = stars(&m, "arc");
        assert_eq!(s.len(), n + 1);
        // the two ends are corners of the flat side
        assert!(s[1..n].iter().all(|&k| k == 4), "n={n}: stars {s:?}");
    }
    // quarter disk: the pole on the axis holds half of its neighbours' star
    for (n, g) in [(8, 1.0), (40, 16.0), (80, 16.0)] {
        let m = quarter_disk([0.0, 1.0], 1.0, n, g, CellKind::Tri3).unwrap();
        let s = stars(&m, "arc");
        assert_eq!(s.len(), n + 1);
        assert_eq!(s[0], 2, "n={n}: the pole's star {s:?}");
        assert!(s[1..n].iter().all(|&k| k == 4), "n={n}: stars {s:?}");
    }
}

/// The rectangle (Tri3) and the box (Tet4) cut every cell the same way: not
/// mirror-symmetric, but no node of a side is set apart from the others (the
/// disks' defect was a node unlike its neighbours).
#[test]
fn rectangle_tri3_and_box_tet4_nodes_along_a_side_have_the_same_star() {
    let grading = Some((RectSide::Bottom, 4.0));
    let m = rectangle([0.0, 0.0], [2.0, 1.0], [8, 5], CellKind::Tri3, grading).unwrap();
    let s = stars(&m, "bottom");
    assert!(s[1..8].iter().all(|&k| k == 3), "rectangle: {s:?}");
    let b = box_mesh(
        [0.0; 3],
        [1.0; 3],
        [4, 4, 3],
        CellKind::Tet4,
        Some((BoxSide::Zmin, 4.0)),
    )
    .unwrap();
    // the interior nodes of the bottom face (z = 0): 12 tetrahedra each (24 inside)
    let interior =
        |x: [f64; 3]| x[2] == 0.0 && x[0] > 0.0 && x[0] < 1.0 && x[1] > 0.0 && x[1] < 1.0;
    let stars: Vec<usize> = (0..b.n_nodes())
        .filter(|&n| interior(b.coords[n]))
        .map(|n| b.cells.iter().filter(|c| c.nodes.contains(&n)).count())
        .collect();
    assert_eq!(stars.len(), 9);
    assert!(stars.iter().all(|&k| k == 12), "box: {stars:?}");
}
