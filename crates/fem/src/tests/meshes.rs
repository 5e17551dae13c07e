//! Small hand-built meshes for the tests: a structured 2D rectangle of any 2D
//! kind and a structured 3D box of hexahedra or tetrahedra, with interior
//! nodes optionally moved (deterministic pseudo-random) so that no cell is a
//! parallelogram. Quadratic cells keep straight sides (mid-side nodes at the
//! middle of their edge). Surfaces are the boundary facets on each side:
//! 2D `bottom, right, top, left`; 3D `xmin, xmax, ymin, ymax, zmin, zmax`.

use signorini_mesh::{Cell, CellKind, Facet, Mesh};
use std::collections::HashMap;

/// Deterministic numbers in `[−1, 1]`.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Adds the mid-side nodes of `edges` (pairs of corner nodes), shared
/// between cells, at the middle of each edge; returns their indices.
fn mid_nodes(
    coords: &mut Vec<[f64; 3]>,
    mids: &mut HashMap<(usize, usize), usize>,
    edges: &[(usize, usize)],
) -> Vec<usize> {
    edges
        .iter()
        .map(|&(a, b)| signorini_mesh::quadratic::mid_node(coords, mids, a, b))
        .collect()
}

/// Names the boundary facets by the side of the box `[lo, hi]` they lie on:
/// `names[axis]` are the names of the low and the high side along `axis`.
fn side_surfaces(mesh: &mut Mesh, lo: [f64; 3], hi: [f64; 3], names: &[[&str; 2]]) {
    let tol = 1e-9 * mesh.size();
    let sides: Vec<(&str, usize, bool)> = (names.iter().enumerate())
        .flat_map(|(axis, [low, high])| [(*low, axis, false), (*high, axis, true)])
        .collect();
    for f in mesh.boundary_facets() {
        let corners = if mesh.dim == 2 { 2 } else { f.nodes.len() };
        for &(name, axis, high) in &sides {
            let v = if high { hi[axis] } else { lo[axis] };
            if f.nodes[..corners]
                .iter()
                .all(|&n| (mesh.coords[n][axis] - v).abs() <= tol)
            {
                mesh.surfaces
                    .entry(name.to_string())
                    .or_default()
                    .facets
                    .push(Facet {
                        nodes: f.nodes.clone(),
                        cell: f.cell,
                    });
            }
        }
    }
}

/// A rectangle `[x0, x0 + w] × [y0, y0 + h]` of `nx × ny` squares split into
/// cells of `kind` (two triangles per square for Tri3/Tri6), interior corner
/// nodes moved by up to `amp` times the cell size in each direction.
pub fn rect(kind: CellKind, origin: [f64; 2], size: [f64; 2], div: [usize; 2], amp: f64) -> Mesh {
    let [nx, ny] = div;
    let (hx, hy) = (size[0] / nx as f64, size[1] / ny as f64);
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut rng = Rng::new(12345);
    let mut coords = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let mut p = [origin[0] + i as f64 * hx, origin[1] + j as f64 * hy, 0.0];
            if i > 0 && i < nx && j > 0 && j < ny {
                p[0] += amp * hx * rng.next();
                p[1] += amp * hy * rng.next();
            }
            coords.push(p);
        }
    }
    let mut mids = HashMap::new();
    let mut cells = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            let tris = [[q[0], q[1], q[2]], [q[0], q[2], q[3]]];
            match kind {
                CellKind::Quad4 => cells.push(q.to_vec()),
                CellKind::Tri3 => cells.extend(tris.iter().map(|t| t.to_vec())),
                CellKind::Quad8 => {
                    let m = mid_nodes(
                        &mut coords,
                        &mut mids,
                        &[(q[0], q[1]), (q[1], q[2]), (q[2], q[3]), (q[3], q[0])],
                    );
                    cells.push([q.to_vec(), m].concat());
                }
                CellKind::Tri6 => {
                    for t in tris {
                        let m = mid_nodes(
                            &mut coords,
                            &mut mids,
                            &[(t[0], t[1]), (t[1], t[2]), (t[2], t[0])],
                        );
                        cells.push([t.to_vec(), m].concat());
                    }
                }
                other => panic!("rect: {other:?} is not a 2D kind"),
            }
        }
    }
    let mut mesh = of_cells(kind, coords, cells);
    let hi = [origin[0] + size[0], origin[1] + size[1], 0.0];
    side_surfaces(
        &mut mesh,
        [origin[0], origin[1], 0.0],
        hi,
        &[["left", "right"], ["bottom", "top"]],
    );
    mesh.check().unwrap();
    mesh
}

/// A box `[0, a] × [0, b] × [0, c]` of `nx × ny × nz` hexahedra (Hex8), or of
/// six tetrahedra per hexahedron (Tet4, the Kuhn subdivision along the
/// diagonal from the low to the high corner, conforming between
/// neighbours), interior nodes moved by up to `amp` times the cell size.
pub fn boxed(kind: CellKind, size: [f64; 3], div: [usize; 3], amp: f64) -> Mesh {
    let [nx, ny, nz] = div;
    let h = [
        size[0] / nx as f64,
        size[1] / ny as f64,
        size[2] / nz as f64,
    ];
    let id = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
    let mut rng = Rng::new(777);
    let mut coords = Vec::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let mut p = [i as f64 * h[0], j as f64 * h[1], k as f64 * h[2]];
                if i > 0 && i < nx && j > 0 && j < ny && k > 0 && k < nz {
                    for (pd, hd) in p.iter_mut().zip(h) {
                        *pd += amp * hd * rng.next();
                    }
                }
                coords.push(p);
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                // corner v(bits): x = bit 0, y = bit 1, z = bit 2
                let v = |b: usize| id(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
                match kind {
                    CellKind::Hex8 => cells.push(
                        [0, 1, 3, 2, 4, 5, 7, 6]
                            .iter()
                            .map(|&b| v(b))
                            .collect::<Vec<_>>(),
                    ),
                    CellKind::Tet4 => {
                        // the paths along the three axes, first and second
                        // steps in lexicographic order
                        let paths = (0..3)
                            .flat_map(|a| (0..3).filter(move |&b| b != a).map(move |b| (a, b)));
                        for (first, second) in paths {
                            let b1 = 1 << first;
                            let b2 = b1 | (1 << second);
                            let mut t = vec![v(0), v(b1), v(b2), v(7)];
                            if tet_volume(&coords, &t) < 0.0 {
                                t.swap(1, 2);
                            }
                            cells.push(t);
                        }
                    }
                    other => panic!("boxed: {other:?} is not a 3D kind"),
                }
            }
        }
    }
    let mut mesh = of_cells(kind, coords, cells);
    side_surfaces(
        &mut mesh,
        [0.0; 3],
        size,
        &[["xmin", "xmax"], ["ymin", "ymax"], ["zmin", "zmax"]],
    );
    mesh.check().unwrap();
    mesh
}

/// Signed volume of a tetrahedron.
pub fn tet_volume(coords: &[[f64; 3]], t: &[usize]) -> f64 {
    let p = |a: usize| coords[t[a]];
    let d = |a: usize| {
        let (q, o) = (p(a), p(0));
        [q[0] - o[0], q[1] - o[1], q[2] - o[2]]
    };
    let (u, v, w) = (d(1), d(2), d(3));
    (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]))
        / 6.0
}

/// A mesh of one cell with the given nodes.
pub fn single(kind: CellKind, coords: Vec<[f64; 3]>) -> Mesh {
    let n = coords.len();
    of_cells(kind, coords, vec![(0..n).collect()])
}

/// One 2D cell of `kind` on the corners `xy` (in the plane z = 0).
pub fn single_2d(kind: CellKind, xy: &[[f64; 2]]) -> Mesh {
    single(kind, xy.iter().map(|p| [p[0], p[1], 0.0]).collect())
}

/// A mesh of cells of `kind` (its dimension) on `coords`, no surfaces.
fn of_cells(kind: CellKind, coords: Vec<[f64; 3]>, cells: Vec<Vec<usize>>) -> Mesh {
    Mesh {
        dim: kind.dim(),
        coords,
        cells: cells
            .into_iter()
            .map(|nodes| Cell { kind, nodes })
            .collect(),
        ..Default::default()
    }
}

/// All node indices on any named surface, sorted and deduplicated.
pub fn boundary_nodes(mesh: &Mesh) -> Vec<usize> {
    let mut b: Vec<usize> = mesh.surfaces.values().flat_map(|s| s.nodes()).collect();
    b.sort_unstable();
    b.dedup();
    b
}
