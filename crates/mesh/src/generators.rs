//! Structured mesh generators (SCENE.md, "Mesh generators").
//!
//! Every generator names its boundary parts; those names are the surfaces of the
//! body. `grading` is the ratio of the largest to the smallest element size along
//! the graded direction (1 = uniform); sizes vary geometrically.
//!
//! All cells are counter-clockwise. Facets of a surface are oriented along the
//! boundary with the body on their left (the order in which the owning cell lists
//! the two nodes), and `Facet::cell` is the owning cell.

use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// A side of a rectangle, used to say where the smallest elements go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RectSide {
    Left,
    Right,
    Bottom,
    Top,
}

impl RectSide {
    /// Parses "left", "right", "bottom", "top".
    pub fn from_name(name: &str) -> Option<RectSide> {
        match name {
            "left" => Some(RectSide::Left),
            "right" => Some(RectSide::Right),
            "bottom" => Some(RectSide::Bottom),
            "top" => Some(RectSide::Top),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            RectSide::Left => "left",
            RectSide::Right => "right",
            RectSide::Bottom => "bottom",
            RectSide::Top => "top",
        }
    }
}

/// `n + 1` increasing parameters `t_0 = 0 < t_1 < ... < t_n = 1` whose
/// increments `h_i = t_{i+1} - t_i` are geometric, `h_i = h_0 q^i`, with
/// `h_{n-1} / h_0 = ratio` (so `q = ratio^(1/(n-1))`): the smallest elements are
/// at 0 when `ratio >= 1`. `ratio = 1` (or `n = 1`) gives a uniform spacing.
/// `n = 0` gives `[0]`.
///
/// # Panics
/// If `ratio` is not finite and positive.
pub fn graded_spacing(n: usize, ratio: f64) -> Vec<f64> {
    assert!(
        ratio.is_finite() && ratio > 0.0,
        "grading ratio must be finite and positive, got {ratio}"
    );
    if n == 0 {
        return vec![0.0];
    }
    let q = if n >= 2 {
        ratio.powf(1.0 / (n - 1) as f64)
    } else {
        1.0
    };
    spacing_from_sizes((0..n).map(|i| q.powi(i as i32)).collect())
}

/// `n + 1` increasing parameters in `[0, 1]`, symmetric about 1/2, whose element
/// sizes grow geometrically from the middle (smallest) towards both ends
/// (largest), with largest / smallest = `ratio` (exactly so for odd `n`, and for
/// even `n >= 4`; `n <= 2` is uniform).
///
/// # Panics
/// If `ratio` is not finite and positive.
pub fn symmetric_graded_spacing(n: usize, ratio: f64) -> Vec<f64> {
    assert!(
        ratio.is_finite() && ratio > 0.0,
        "grading ratio must be finite and positive, got {ratio}"
    );
    if n == 0 {
        return vec![0.0];
    }
    // size of element i = q^{|i - c|}, c = (n - 1)/2; exponents range from
    // e_min (0 for odd n, 1/2 for even n) to (n - 1)/2.
    let c = (n as f64 - 1.0) / 2.0;
    let e_min = if n % 2 == 1 { 0.0 } else { 0.5 };
    let span = c - e_min;
    let q = if span > 0.0 {
        ratio.powf(1.0 / span)
    } else {
        1.0
    };
    let mut t = spacing_from_sizes(
        (0..n)
            .map(|i| q.powf((i as f64 - c).abs()))
            .collect::<Vec<_>>(),
    );
    // enforce the exact symmetry t_i + t_{n-i} = 1
    for i in 0..=n / 2 {
        let a = 0.5 * (t[i] + 1.0 - t[n - i]);
        t[i] = a;
        t[n - i] = 1.0 - a;
    }
    t
}

fn spacing_from_sizes(h: Vec<f64>) -> Vec<f64> {
    let total: f64 = h.iter().sum();
    let mut t = Vec::with_capacity(h.len() + 1);
    let mut acc = 0.0;
    t.push(0.0);
    for hi in &h {
        acc += hi;
        t.push(acc / total);
    }
    *t.last_mut().unwrap() = 1.0;
    t
}

fn check_ratio(what: &str, r: f64) -> Result<(), MeshError> {
    if r.is_finite() && r > 0.0 {
        Ok(())
    } else {
        Err(MeshError::Invalid(format!(
            "{what}: grading ratio must be finite and positive, got {r}"
        )))
    }
}

/// Boundary edges `(node a, node b, owning quad)`.
type EdgeList = Vec<(usize, usize, usize)>;

/// Builds a 2D mesh from counter-clockwise quadrilaterals (as Quad4, or split in
/// two Tri3 along the shorter diagonal) and named boundary edges `(a, b, quad)`.
fn build_2d(
    coords: Vec<[f64; 3]>,
    quads: &[[usize; 4]],
    edges: Vec<(&str, EdgeList)>,
    kind: CellKind,
) -> Mesh {
    let d2 = |a: usize, b: usize| {
        let (p, q) = (coords[a], coords[b]);
        (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
    };
    let mut cells = Vec::new();
    // cells made from quad q: first index and count
    let mut first = Vec::with_capacity(quads.len());
    for q in quads {
        first.push(cells.len());
        match kind {
            CellKind::Quad4 => cells.push(Cell {
                kind,
                nodes: q.to_vec(),
            }),
            CellKind::Tri3 => {
                let [a, b, c, d] = *q;
                // the shorter diagonal (ties: a-c)
                if d2(a, c) <= d2(b, d) * (1.0 + 1e-12) {
                    cells.push(Cell {
                        kind,
                        nodes: vec![a, b, c],
                    });
                    cells.push(Cell {
                        kind,
                        nodes: vec![a, c, d],
                    });
                } else {
                    cells.push(Cell {
                        kind,
                        nodes: vec![a, b, d],
                    });
                    cells.push(Cell {
                        kind,
                        nodes: vec![b, c, d],
                    });
                }
            }
            other => panic!("build_2d: {} is not a first-order 2D kind", other.name()),
        }
    }
    let ncell_per_quad = if kind == CellKind::Quad4 { 1 } else { 2 };
    let mut surfaces = BTreeMap::new();
    for (name, list) in edges {
        let mut facets = Vec::with_capacity(list.len());
        for (a, b, q) in list {
            // the cell of quad q holding both nodes, and the ccw order of (a, b) in it
            let (cell, nodes) = (first[q]..first[q] + ncell_per_quad)
                .find_map(|c| {
                    let n = &cells[c].nodes;
                    let m = n.len();
                    (0..m).find_map(|i| {
                        let (x, y) = (n[i], n[(i + 1) % m]);
                        if (x, y) == (a, b) || (x, y) == (b, a) {
                            Some((c, vec![x, y]))
                        } else {
                            None
                        }
                    })
                })
                .expect("boundary edge is an edge of its quad");
            facets.push(Facet { nodes, cell });
        }
        surfaces.insert(name.to_string(), Surface { facets });
    }
    Mesh {
        dim: 2,
        coords,
        cells,
        surfaces,
        regions: Default::default(),
    }
}

/// Rectangle `[x0, x0 + w] x [y0, y0 + h]` with `nx x ny` quadrilaterals on a
/// structured grid (Quad4, or each quad split in two Tri3 along its shorter
/// diagonal). `grading = Some((side, r))` grades the direction normal to `side`
/// geometrically, with the smallest elements along `side` and largest / smallest
/// = `r`.
///
/// Node `(i, j)` (i along x, j along y) has index `j * (nx + 1) + i`.
/// Surfaces: "left", "right", "bottom", "top".
pub fn rectangle(
    origin: [f64; 2],
    size: [f64; 2],
    divisions: [usize; 2],
    kind: CellKind,
    grading: Option<(RectSide, f64)>,
) -> Result<Mesh, MeshError> {
    let [nx, ny] = divisions;
    if nx == 0 || ny == 0 {
        return Err(MeshError::Invalid(format!(
            "rectangle: divisions must be positive, got [{nx}, {ny}]"
        )));
    }
    if !(size[0].is_finite() && size[1].is_finite() && size[0] > 0.0 && size[1] > 0.0) {
        return Err(MeshError::Invalid(format!(
            "rectangle: size must be positive, got [{}, {}]",
            size[0], size[1]
        )));
    }
    if !(origin[0].is_finite() && origin[1].is_finite()) {
        return Err(MeshError::Invalid("rectangle: origin is not finite".into()));
    }
    let mut sx = graded_spacing(nx, 1.0);
    let mut sy = graded_spacing(ny, 1.0);
    if let Some((side, r)) = grading {
        check_ratio("rectangle", r)?;
        let rev = |t: Vec<f64>| t.iter().rev().map(|v| 1.0 - v).collect::<Vec<_>>();
        match side {
            RectSide::Left => sx = graded_spacing(nx, r),
            RectSide::Right => sx = rev(graded_spacing(nx, r)),
            RectSide::Bottom => sy = graded_spacing(ny, r),
            RectSide::Top => sy = rev(graded_spacing(ny, r)),
        }
    }
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut coords = Vec::with_capacity((nx + 1) * (ny + 1));
    for (j, ty) in sy.iter().enumerate() {
        for (i, tx) in sx.iter().enumerate() {
            // exact end coordinates on the boundary lines
            let x = if i == nx {
                origin[0] + size[0]
            } else {
                origin[0] + size[0] * tx
            };
            let y = if j == ny {
                origin[1] + size[1]
            } else {
                origin[1] + size[1] * ty
            };
            coords.push([x, y, 0.0]);
        }
    }
    let mut quads = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let q = |i: usize, j: usize| j * nx + i;
    let bottom = (0..nx).map(|i| (id(i, 0), id(i + 1, 0), q(i, 0))).collect();
    let right = (0..ny)
        .map(|j| (id(nx, j), id(nx, j + 1), q(nx - 1, j)))
        .collect();
    let top = (0..nx)
        .rev()
        .map(|i| (id(i + 1, ny), id(i, ny), q(i, ny - 1)))
        .collect();
    let left = (0..ny)
        .rev()
        .map(|j| (id(0, j + 1), id(0, j), q(0, j)))
        .collect();
    let mesh = build_2d(
        coords,
        &quads,
        vec![
            ("bottom", bottom),
            ("right", right),
            ("top", top),
            ("left", left),
        ],
        kind,
    );
    mesh.check()?;
    Ok(mesh)
}

/// Radius (relative to the disk's) of the inner block's corner in [`half_disk`].
const HALF_DISK_CORE: f64 = 0.7;
/// Weight of the uniform spacing in the inner block's boundary (the rest follows
/// the arc's grading by radial projection).
const HALF_DISK_BLEND: f64 = 0.85;

/// Half of the disk of `radius` about `center` on the side of `pole` (normalised;
/// an error if zero): `{x : |x - c| <= R, (x - c) . pole >= 0}`.
///
/// `divisions` elements along the whole arc, graded towards the pole point
/// `c + R pole` (smallest elements there, largest / smallest = `grading` along the
/// arc, sizes geometric and symmetric about the pole).
///
/// Construction (a half O-grid, all cells structured quadrilaterals): in the local
/// right-handed frame `e_t = (p_y, -p_x)`, `e_p = pole`, the arc points are
/// `c + R (cos φ e_t + sin φ e_p)`, `φ ∈ [0, π]`, at the graded angles `φ_k`.
/// An inner rectangle `[-a, a] x [0, b]` (`a = 0.7 R cos φ_m`, `b = 0.7 R sin φ_m`,
/// `φ_m` the arc angle nearest 45°) is meshed `(divisions - 2m) x m`; the ring
/// between its three free sides and the arc is meshed `divisions x n_r` with
/// straight radial lines from the rectangle's boundary node k to arc node k,
/// graded geometrically towards the arc (ratio `sqrt(grading)`, `n_r =
/// ceil(divisions / 8)` layers). The rectangle's boundary nodes are 15% the
/// radial projection of the arc nodes, 85% uniform, so the fine spacing at the
/// pole does not run into slivers deep in the body. Measured quality (divisions
/// 4..129, grading 1..16): quad angles in [43°, 137°], edge ratio <= 7; Tri3
/// (quads split along the shorter diagonal) angles >= 8°.
///
/// Surfaces: "flat" (the diameter through the centre, perpendicular to the pole)
/// and "arc".
pub fn half_disk(
    center: [f64; 2],
    radius: f64,
    divisions: usize,
    pole: [f64; 2],
    grading: f64,
    kind: CellKind,
) -> Result<Mesh, MeshError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(MeshError::Invalid(format!(
            "half_disk: radius must be positive, got {radius}"
        )));
    }
    if !(center[0].is_finite() && center[1].is_finite()) {
        return Err(MeshError::Invalid("half_disk: center is not finite".into()));
    }
    if divisions < 4 {
        return Err(MeshError::Invalid(format!(
            "half_disk: divisions (elements along the arc) must be at least 4, got {divisions}"
        )));
    }
    check_ratio("half_disk", grading)?;
    let pn = (pole[0] * pole[0] + pole[1] * pole[1]).sqrt();
    if !(pn.is_finite() && pn > 0.0) {
        return Err(MeshError::Invalid(format!(
            "half_disk: pole must be a non-zero vector, got [{}, {}]",
            pole[0], pole[1]
        )));
    }
    let ep = [pole[0] / pn, pole[1] / pn];
    let et = [ep[1], -ep[0]];
    let n = divisions;
    let phi: Vec<f64> = symmetric_graded_spacing(n, grading)
        .iter()
        .map(|t| PI * t)
        .collect();
    // arc index of the inner rectangle's corner: the angle nearest 45°
    let m = (1..=(n - 1) / 2)
        .min_by(|&a, &b| {
            (phi[a] - PI / 4.0)
                .abs()
                .total_cmp(&(phi[b] - PI / 4.0).abs())
        })
        .unwrap_or(1);
    let ns = n - 2 * m;
    let nr = n.div_ceil(8).max(1);
    let (a, b) = (HALF_DISK_CORE * phi[m].cos(), HALF_DISK_CORE * phi[m].sin());
    let w = HALF_DISK_BLEND;
    // inner rectangle in unit-radius local coordinates (u along e_t, v along e_p)
    // right side heights y_j (j = 0..=m), from arc nodes 0..=m
    let ys: Vec<f64> = (0..=m)
        .map(|j| {
            if j == m {
                b
            } else {
                (1.0 - w) * a * phi[j].tan() + w * b * j as f64 / m as f64
            }
        })
        .collect();
    // top side abscissae x_i (i = 0..=ns, increasing), from arc node k = n - m - i
    let xt: Vec<f64> = (0..=ns)
        .map(|i| {
            if i == 0 {
                -a
            } else if i == ns {
                a
            } else {
                let k = n - m - i;
                let ray = b * phi[k].cos() / phi[k].sin();
                (1.0 - w) * ray + w * (-a + 2.0 * a * i as f64 / ns as f64)
            }
        })
        .collect();
    let xb: Vec<f64> = (0..=ns)
        .map(|i| -a + 2.0 * a * i as f64 / ns as f64)
        .collect();

    let mut local: Vec<[f64; 2]> = Vec::new();
    let rid = |i: usize, j: usize| j * (ns + 1) + i;
    for (j, &y) in ys.iter().enumerate() {
        let s = y / b;
        for i in 0..=ns {
            let x = if j == m {
                xt[i]
            } else {
                (1.0 - s) * xb[i] + s * xt[i]
            };
            local.push([x, y]);
        }
    }
    let n_rect = local.len();
    // ring: node (k, l), k = 0..=n along the arc, l = 0..=nr outwards; l = 0 is
    // the rectangle's boundary.
    let inner = |k: usize| -> usize {
        if k <= m {
            rid(ns, k)
        } else if k <= n - m {
            rid(ns - (k - m), m)
        } else {
            rid(0, n - k)
        }
    };
    let g: Vec<f64> = graded_spacing(nr, grading.sqrt())
        .iter()
        .rev()
        .map(|t| 1.0 - t)
        .collect();
    let ring_id = |k: usize, l: usize| -> usize {
        if l == 0 {
            inner(k)
        } else {
            n_rect + k * nr + (l - 1)
        }
    };
    for k in 0..=n {
        let p0 = local[inner(k)];
        let p1 = [phi[k].cos(), phi[k].sin()];
        for (l, &gl) in g.iter().enumerate().skip(1) {
            if l == nr {
                // exactly on the arc (and on the flat line at the ends)
                let p = match k {
                    0 => [1.0, 0.0],
                    _ if k == n => [-1.0, 0.0],
                    _ => p1,
                };
                local.push(p);
            } else {
                let mut p = [p0[0] + gl * (p1[0] - p0[0]), p0[1] + gl * (p1[1] - p0[1])];
                if k == 0 || k == n {
                    p[1] = 0.0;
                }
                local.push(p);
            }
        }
    }
    let mut quads: Vec<[usize; 4]> = Vec::with_capacity(ns * m + n * nr);
    for j in 0..m {
        for i in 0..ns {
            quads.push([rid(i, j), rid(i + 1, j), rid(i + 1, j + 1), rid(i, j + 1)]);
        }
    }
    let q_ring = |k: usize, l: usize| ns * m + k * nr + l;
    for k in 0..n {
        for l in 0..nr {
            // radial outwards, then ccw along the arc: counter-clockwise
            quads.push([
                ring_id(k, l),
                ring_id(k, l + 1),
                ring_id(k + 1, l + 1),
                ring_id(k + 1, l),
            ]);
        }
    }
    // boundary edges, listed along the boundary (body on the left)
    let mut flat = Vec::new();
    for l in (0..nr).rev() {
        flat.push((ring_id(n, l + 1), ring_id(n, l), q_ring(n - 1, l)));
    }
    for i in 0..ns {
        flat.push((rid(i, 0), rid(i + 1, 0), i));
    }
    for l in 0..nr {
        flat.push((ring_id(0, l), ring_id(0, l + 1), q_ring(0, l)));
    }
    let arc = (0..n)
        .map(|k| (ring_id(k, nr), ring_id(k + 1, nr), q_ring(k, nr - 1)))
        .collect();
    let coords = local
        .iter()
        .map(|p| {
            [
                center[0] + radius * (p[0] * et[0] + p[1] * ep[0]),
                center[1] + radius * (p[0] * et[1] + p[1] * ep[1]),
                0.0,
            ]
        })
        .collect();
    let mesh = build_2d(coords, &quads, vec![("flat", flat), ("arc", arc)], kind);
    mesh.check()?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

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

    fn check_half_disk(
        c: [f64; 2],
        r: f64,
        n: usize,
        pole: [f64; 2],
        g: f64,
        kind: CellKind,
    ) -> Mesh {
        let m = half_disk(c, r, n, pole, g, kind).unwrap();
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
                    // triangles (quads split) min sin 0.14 (angles >= 8°)
                    let sin_min = if kind == CellKind::Quad4 { 0.6 } else { 0.12 };
                    assert!(min_sin > sin_min, "n={n} g={g} {kind:?}: min sin {min_sin}");
                    assert!(aspect < 8.0, "n={n} g={g} {kind:?}: aspect {aspect}");
                }
            }
        }
        assert!(half_disk([0.0, 0.0], 1.0, 16, [0.0, 0.0], 1.0, CellKind::Quad4).is_err());
        assert!(half_disk([0.0, 0.0], 0.0, 16, [0.0, 1.0], 1.0, CellKind::Quad4).is_err());
        assert!(half_disk([0.0, 0.0], 1.0, 3, [0.0, 1.0], 1.0, CellKind::Quad4).is_err());
    }

    #[test]
    fn half_disk_counts() {
        let m = half_disk([0.0, 0.0], 1.0, 16, [0.0, -1.0], 1.0, CellKind::Quad4).unwrap();
        // uniform 16: corner at arc node 4 (45°), rectangle 8 x 4, ring 16 x 2
        assert_eq!(m.cells.len(), 8 * 4 + 16 * 2);
        assert_eq!(m.n_nodes(), 9 * 5 + 17 * 2);
        let t = half_disk([0.0, 0.0], 1.0, 16, [0.0, -1.0], 1.0, CellKind::Tri3).unwrap();
        assert_eq!(t.cells.len(), 2 * m.cells.len());
        assert_eq!(t.n_nodes(), m.n_nodes());
        assert_eq!(t.surface("arc").unwrap().nodes().len(), 17);
        assert_eq!(t.surface("flat").unwrap().nodes().len(), 9 + 2 * 2);
    }

    #[test]
    fn half_disk_contact_zone_resolution() {
        let r = 0.05;
        let c = [0.0, r];
        let pole = [0.0, -1.0];
        let m = half_disk(c, r, 128, pole, 16.0, CellKind::Quad4).unwrap();
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
}
