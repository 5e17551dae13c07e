//! Structured mesh generators (SCENE.md, "Mesh generators").
//!
//! Every generator names its boundary parts; those names are the surfaces of the
//! body. `grading` is the ratio of the largest to the smallest element size along
//! the graded direction (1 = uniform); sizes vary geometrically.
//!
//! 2D ([`rectangle`], [`half_disk`], [`quarter_disk`]): all cells are
//! counter-clockwise (Quad4, Tri3, or those made second-order by
//! [`to_second_order`](crate::quadratic::to_second_order)). Facets of a surface are oriented along the boundary
//! with the body on their left (the order in which the owning cell lists the two
//! nodes), and `Facet::cell` is the owning cell.
//!
//! 3D ([`box_mesh`], [`hemisphere`]): cells have positive volumes (Tet4) or
//! positive Jacobians at their 8 corners (Hex8, VTK order); a surface's facets
//! are faces of their cells with the node order of [`CellKind::facets`]
//! (right-hand normal pointing out of the body).

mod split;

use crate::{Cell, CellKind, Facet, Mesh, MeshError, Surface};
use split::{build_2d, EdgeList, TriangleSplit};
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

/// The `n + 1` parameters in `[0, 1]` of the grid lines along `axis`: graded
/// ([`graded_spacing`], smallest elements at the end 0, or at 1 if `at_max`) when
/// `grading = Some((axis, at_max, ratio))` names this axis, uniform otherwise.
fn axis_spacing(n: usize, axis: usize, grading: Option<(usize, bool, f64)>) -> Vec<f64> {
    match grading {
        Some((a, false, r)) if a == axis => graded_spacing(n, r),
        Some((a, true, r)) if a == axis => {
            graded_spacing(n, r).iter().rev().map(|v| 1.0 - v).collect()
        }
        _ => graded_spacing(n, 1.0),
    }
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

/// Rectangle `[x0, x0 + w] x [y0, y0 + h]` with `nx x ny` quadrilaterals on a
/// structured grid (Quad4, or each quad split in two Tri3 along its diagonal
/// from node `(i, j)` to `(i + 1, j + 1)`, the same in every quad
/// (`TriangleSplit::Diagonal`: every node has the same star, no node is set
/// apart, but the mesh is not mirror-symmetric); Quad8 / Tri6: those made
/// second-order by [`to_second_order`](crate::quadratic::to_second_order), the
/// mid-side nodes at the edge midpoints). `grading = Some((side, r))` grades the
/// direction normal to `side` geometrically, with the smallest elements along
/// `side` and largest / smallest = `r`.
///
/// Node `(i, j)` (i along x, j along y) has index `j * (nx + 1) + i` (the
/// mid-side nodes of second-order cells come after them).
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
    let grading = match grading {
        Some((side, r)) => {
            check_ratio("rectangle", r)?;
            let (axis, at_max) = match side {
                RectSide::Left => (0, false),
                RectSide::Right => (0, true),
                RectSide::Bottom => (1, false),
                RectSide::Top => (1, true),
            };
            Some((axis, at_max, r))
        }
        None => None,
    };
    let sx = axis_spacing(nx, 0, grading);
    let sy = axis_spacing(ny, 1, grading);
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
    build_2d(
        coords,
        &quads,
        vec![
            ("bottom", bottom),
            ("right", right),
            ("top", top),
            ("left", left),
        ],
        kind,
        TriangleSplit::Diagonal,
    )
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
/// 4..129, grading 1..16): quad angles in [43°, 137°], edge ratio <= 7.
///
/// Tri3: each quad cut in four triangles about a node at the mean of its
/// corners (`TriangleSplit::Crossed`; those nodes come after the quads'), so
/// that the mesh is the mirror image of itself about the pole's radius (for an
/// even `divisions`) and the pole has the same kind of star as its neighbours
/// (cut in two, the pole's force was 8-14 % off its neighbours' and the Hertz
/// p0 as much); angles >= 8°.
///
/// Second-order kinds (Quad8, Tri6) are the first-order mesh made second-order by
/// [`to_second_order`](crate::quadratic::to_second_order), with the mid-side nodes of the arc's facets then moved
/// radially onto the circle (the other mid-side nodes stay at the midpoints).
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
    let parts = half_disk_quads(center, radius, divisions, pole, grading)?;
    let mut mesh = build_2d(
        parts.coords,
        &parts.quads,
        vec![("flat", parts.flat), ("arc", parts.arc)],
        kind,
        TriangleSplit::Crossed,
    )?;
    arc_midsides_on_circle(&mut mesh, "arc", center, radius);
    Ok(mesh)
}

/// Moves the mid-side nodes (third nodes) of the facets of `surface` radially
/// onto the circle of `radius` about `center` (nothing to do for first-order
/// facets).
fn arc_midsides_on_circle(mesh: &mut Mesh, surface: &str, center: [f64; 2], radius: f64) {
    let mids: Vec<usize> = mesh.surfaces[surface]
        .facets
        .iter()
        .filter_map(|f| f.nodes.get(2).copied())
        .collect();
    for n in mids {
        let p = &mut mesh.coords[n];
        let (dx, dy) = (p[0] - center[0], p[1] - center[1]);
        let d = dx.hypot(dy);
        p[0] = center[0] + radius * dx / d;
        p[1] = center[1] + radius * dy / d;
    }
}

/// The quadrilaterals of [`half_disk`] (counter-clockwise) with its boundary
/// edges, each listed along the boundary with the body on its left.
struct HalfDiskQuads {
    coords: Vec<[f64; 3]>,
    quads: Vec<[usize; 4]>,
    flat: EdgeList,
    arc: EdgeList,
}

/// The construction of [`half_disk`], before the quadrilaterals become cells.
fn half_disk_quads(
    center: [f64; 2],
    radius: f64,
    divisions: usize,
    pole: [f64; 2],
    grading: f64,
) -> Result<HalfDiskQuads, MeshError> {
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
    Ok(HalfDiskQuads {
        coords,
        quads,
        flat,
        arc,
    })
}

/// Quarter of the disk of `radius` about `center` for axisymmetric models (x = r,
/// y = z): `{x : |x - c| <= R, x >= c_x, y <= c_y}`, the lower right quarter,
/// whose pole `(c_x, c_y - R)` on the axis is where the body touches a plane
/// below it.
///
/// `divisions` elements along the quarter arc (at least 2), graded towards the
/// pole (smallest there, largest / smallest = `grading`, sizes geometric).
///
/// Construction: the [`half_disk`] of `2 divisions` elements along its arc with
/// pole `[0, -1]` is symmetric about the axis `x = c_x`, which is one of its grid
/// lines (the middle column of its inner rectangle and the radial line to the
/// pole); its quadrilaterals on the side `x >= c_x` are kept (nodes on the axis
/// set to `x = c_x` exactly, no node has `x < c_x`) and become cells as in
/// [`half_disk`] (Quad4, Tri3 four per quad about its centre, Quad8 / Tri6 with
/// the arc's mid-side nodes on the circle).
///
/// Surfaces, each listed along the boundary with the body on its left: "flat"
/// (the radius on `y = c_y`, from `x = c_x + R` to the axis), "axis" (the radius
/// on `x = c_x`, from the centre down to the pole) and "arc" (from the pole to
/// `(c_x + R, c_y)`).
pub fn quarter_disk(
    center: [f64; 2],
    radius: f64,
    divisions: usize,
    grading: f64,
    kind: CellKind,
) -> Result<Mesh, MeshError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(MeshError::Invalid(format!(
            "quarter_disk: radius must be positive, got {radius}"
        )));
    }
    if !(center[0].is_finite() && center[1].is_finite()) {
        return Err(MeshError::Invalid(
            "quarter_disk: center is not finite".into(),
        ));
    }
    if divisions < 2 {
        return Err(MeshError::Invalid(format!(
            "quarter_disk: divisions (elements along the arc) must be at least 2, got {divisions}"
        )));
    }
    check_ratio("quarter_disk", grading)?;
    let half = half_disk_quads(center, radius, 2 * divisions, [0.0, -1.0], grading)?;
    // the axis is the half disk's middle grid line: within rounding of x = c_x,
    // while every other node is at least a fraction of an element away
    let tol = 1e-9 * radius;
    let on_axis: Vec<bool> = half
        .coords
        .iter()
        .map(|p| (p[0] - center[0]).abs() <= tol)
        .collect();
    let keep: Vec<bool> = half
        .quads
        .iter()
        .map(|q| q.iter().map(|&n| half.coords[n][0]).sum::<f64>() > 4.0 * center[0])
        .collect();
    let mut new_node = vec![usize::MAX; half.coords.len()];
    let mut coords = Vec::new();
    let mut quads = Vec::new();
    let mut new_quad = vec![usize::MAX; half.quads.len()];
    for (q, quad) in half.quads.iter().enumerate() {
        if !keep[q] {
            continue;
        }
        let mut nq = [0; 4];
        for (k, &n) in quad.iter().enumerate() {
            if new_node[n] == usize::MAX {
                new_node[n] = coords.len();
                let mut p = half.coords[n];
                if on_axis[n] {
                    p[0] = center[0];
                } else if p[0] < center[0] {
                    return Err(MeshError::Invalid(format!(
                        "quarter_disk: internal error, node at x - c_x = {:e}",
                        p[0] - center[0]
                    )));
                }
                coords.push(p);
            }
            nq[k] = new_node[n];
        }
        new_quad[q] = quads.len();
        quads.push(nq);
    }
    let kept = |list: EdgeList| -> EdgeList {
        list.into_iter()
            .filter(|&(_, _, q)| keep[q])
            .map(|(a, b, q)| (new_node[a], new_node[b], new_quad[q]))
            .collect()
    };
    let flat = kept(half.flat);
    let arc = kept(half.arc);
    // axis edges: counter-clockwise edges of the kept quads with both ends on
    // the axis (body on their left: downwards), from the centre to the pole
    let mut axis: EdgeList = Vec::new();
    for (q, quad) in quads.iter().enumerate() {
        for i in 0..4 {
            let (a, b) = (quad[i], quad[(i + 1) % 4]);
            if coords[a][0] == center[0] && coords[b][0] == center[0] {
                axis.push((a, b, q));
            }
        }
    }
    axis.sort_by(|x, y| coords[y.0][1].total_cmp(&coords[x.0][1]));
    let mut mesh = build_2d(
        coords,
        &quads,
        vec![("flat", flat), ("axis", axis), ("arc", arc)],
        kind,
        TriangleSplit::Crossed,
    )?;
    arc_midsides_on_circle(&mut mesh, "arc", center, radius);
    Ok(mesh)
}

/// A face of a box, used to say where the smallest elements go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BoxSide {
    Xmin,
    Xmax,
    Ymin,
    Ymax,
    Zmin,
    Zmax,
}

impl BoxSide {
    /// All sides, in the order xmin, xmax, ymin, ymax, zmin, zmax.
    pub const ALL: [BoxSide; 6] = [
        BoxSide::Xmin,
        BoxSide::Xmax,
        BoxSide::Ymin,
        BoxSide::Ymax,
        BoxSide::Zmin,
        BoxSide::Zmax,
    ];

    /// Parses "xmin", "xmax", "ymin", "ymax", "zmin", "zmax".
    pub fn from_name(name: &str) -> Option<BoxSide> {
        BoxSide::ALL.into_iter().find(|s| s.name() == name)
    }

    pub fn name(self) -> &'static str {
        match self {
            BoxSide::Xmin => "xmin",
            BoxSide::Xmax => "xmax",
            BoxSide::Ymin => "ymin",
            BoxSide::Ymax => "ymax",
            BoxSide::Zmin => "zmin",
            BoxSide::Zmax => "zmax",
        }
    }

    /// The coordinate axis normal to the side (0, 1, 2) and whether the side is
    /// at the upper end of it.
    pub fn axis(self) -> (usize, bool) {
        match self {
            BoxSide::Xmin => (0, false),
            BoxSide::Xmax => (0, true),
            BoxSide::Ymin => (1, false),
            BoxSide::Ymax => (1, true),
            BoxSide::Zmin => (2, false),
            BoxSide::Zmax => (2, true),
        }
    }
}

/// Names the boundary of a 3D mesh: every boundary facet
/// ([`Mesh::boundary_facets`]) goes to the surface `names[classify(facet nodes)]`.
fn name_boundary(
    mesh: &mut Mesh,
    names: &[&str],
    classify: impl Fn(&[usize]) -> usize,
) -> Result<(), MeshError> {
    let mut lists: Vec<Vec<Facet>> = vec![Vec::new(); names.len()];
    for f in mesh.boundary_facets() {
        lists[classify(&f.nodes)].push(f);
    }
    for (name, facets) in names.iter().zip(lists) {
        if facets.is_empty() {
            return Err(MeshError::Invalid(format!(
                "internal error: surface \"{name}\" has no facets"
            )));
        }
        mesh.surfaces.insert(name.to_string(), Surface { facets });
    }
    Ok(())
}

/// Box `[x0, x0 + sx] x [y0, y0 + sy] x [z0, z0 + sz]` on a structured grid of
/// `nx x ny x nz` hexahedra.
///
/// Node `(i, j, k)` has index `(k (ny + 1) + j) (nx + 1) + i`; the grid lines of
/// the last layer are exactly at `origin + size`. `grading = Some((side, r))`
/// grades the direction normal to `side` geometrically ([`graded_spacing`]),
/// with the smallest elements along `side` and largest / smallest = `r`.
///
/// `kind`: Hex8, the grid's cells `(i, j, k)` in the VTK order (bottom 0-1-2-3
/// counter-clockwise seen from above, 4-7 above them); or Tet4, each hexahedron
/// split in the 6 tetrahedra of the Kuhn (Freudenthal) triangulation around its
/// diagonal from corner `(i, j, k)` to corner `(i+1, j+1, k+1)`: one per order
/// in which the path along the three directions visits them. Every hexahedron
/// is split the same way, so each quadrilateral face is cut along the same
/// diagonal from both sides (conforming). Each tetrahedron's nodes are ordered
/// for a positive volume.
///
/// Surfaces "xmin", "xmax", "ymin", "ymax", "zmin", "zmax": the boundary facets
/// (quadrilaterals, or triangles for Tet4) on each face, each with its cell and
/// its node order from [`CellKind::facets`] (outward right-hand normal).
pub fn box_mesh(
    origin: [f64; 3],
    size: [f64; 3],
    divisions: [usize; 3],
    kind: CellKind,
    grading: Option<(BoxSide, f64)>,
) -> Result<Mesh, MeshError> {
    let [nx, ny, nz] = divisions;
    if nx == 0 || ny == 0 || nz == 0 {
        return Err(MeshError::Invalid(format!(
            "box: divisions must be positive, got [{nx}, {ny}, {nz}]"
        )));
    }
    if !size.iter().all(|s| s.is_finite() && *s > 0.0) {
        return Err(MeshError::Invalid(format!(
            "box: size must be positive, got [{}, {}, {}]",
            size[0], size[1], size[2]
        )));
    }
    if !origin.iter().all(|o| o.is_finite()) {
        return Err(MeshError::Invalid("box: origin is not finite".into()));
    }
    if !matches!(kind, CellKind::Hex8 | CellKind::Tet4) {
        return Err(MeshError::Invalid(format!(
            "box: cells must be hex8 or tet4, got {}",
            kind.name()
        )));
    }
    let grading = match grading {
        Some((side, r)) => {
            check_ratio("box", r)?;
            let (axis, at_max) = side.axis();
            Some((axis, at_max, r))
        }
        None => None,
    };
    // grid line coordinates along each axis, the ends exact
    let lines: Vec<Vec<f64>> = (0..3)
        .map(|a| {
            let n = divisions[a];
            axis_spacing(n, a, grading)
                .iter()
                .enumerate()
                .map(|(i, t)| {
                    if i == n {
                        origin[a] + size[a]
                    } else {
                        origin[a] + size[a] * t
                    }
                })
                .collect()
        })
        .collect();
    let id = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
    let mut coords = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for &z in &lines[2] {
        for &y in &lines[1] {
            for &x in &lines[0] {
                coords.push([x, y, z]);
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let v = |a: usize, b: usize, c: usize| id(i + a, j + b, k + c);
                if kind == CellKind::Hex8 {
                    cells.push(Cell {
                        kind,
                        nodes: vec![
                            v(0, 0, 0),
                            v(1, 0, 0),
                            v(1, 1, 0),
                            v(0, 1, 0),
                            v(0, 0, 1),
                            v(1, 0, 1),
                            v(1, 1, 1),
                            v(0, 1, 1),
                        ],
                    });
                    continue;
                }
                // Kuhn split: the path (0,0,0) -> +e_p0 -> +e_p1 -> (1,1,1) for
                // each permutation p; an odd permutation gives a negative volume
                // in path order, so its last two nodes are swapped
                for (p, odd) in [
                    ([0, 1, 2], false),
                    ([1, 2, 0], false),
                    ([2, 0, 1], false),
                    ([1, 0, 2], true),
                    ([0, 2, 1], true),
                    ([2, 1, 0], true),
                ] {
                    let mut o = [0usize; 3];
                    let mut path = vec![v(0, 0, 0)];
                    for &axis in &p {
                        o[axis] = 1;
                        path.push(v(o[0], o[1], o[2]));
                    }
                    if odd {
                        path.swap(2, 3);
                    }
                    cells.push(Cell { kind, nodes: path });
                }
            }
        }
    }
    let mut mesh = Mesh {
        dim: 3,
        coords,
        cells,
        surfaces: BTreeMap::new(),
        regions: Default::default(),
    };
    let coords = mesh.coords.clone();
    let names = BoxSide::ALL.map(|s| s.name());
    name_boundary(&mut mesh, &names, |nodes| {
        BoxSide::ALL
            .iter()
            .position(|s| {
                let (a, at_max) = s.axis();
                let v = if at_max {
                    origin[a] + size[a]
                } else {
                    origin[a]
                };
                nodes.iter().all(|&n| coords[n][a] == v)
            })
            .expect("a boundary facet of the box lies on one of its faces")
    })?;
    mesh.check()?;
    Ok(mesh)
}

/// Determinants of the Jacobian of a Hex8 cell's trilinear map at its 8
/// corners (positive for a valid, well-oriented cell).
pub fn hex_corner_jacobians(mesh: &Mesh, cell: usize) -> [f64; 8] {
    let n = &mesh.cells[cell].nodes;
    let x = |k: usize| mesh.coords[n[k]];
    // at corner k, the three edges along the reference axes xi, eta, zeta
    const AXES: [[usize; 3]; 8] = [
        [1, 3, 4],
        [0, 2, 5],
        [3, 1, 6],
        [2, 0, 7],
        [5, 7, 0],
        [4, 6, 1],
        [7, 5, 2],
        [6, 4, 3],
    ];
    // sign of the reference axes' directions at each corner (from the corner
    // to its neighbour along xi, eta, zeta)
    const SIGN: [f64; 8] = [1.0, -1.0, 1.0, -1.0, -1.0, 1.0, -1.0, 1.0];
    let mut det = [0.0; 8];
    for k in 0..8 {
        let e = AXES[k].map(|m| {
            let (a, b) = (x(k), x(m));
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
        });
        let c = [
            e[1][1] * e[2][2] - e[1][2] * e[2][1],
            e[1][2] * e[2][0] - e[1][0] * e[2][2],
            e[1][0] * e[2][1] - e[1][1] * e[2][0],
        ];
        det[k] = SIGN[k] * (e[0][0] * c[0] + e[0][1] * c[1] + e[0][2] * c[2]);
    }
    det
}

/// Fraction of the body radius at which [`hemisphere`]'s inner block's top
/// edges lie (the middle of each edge).
const HEMISPHERE_CORE: f64 = 0.6;
/// Weight of the uniform spacing in the inner block's grid of [`hemisphere`]
/// (the rest follows the dome's grading by radial projection).
const HEMISPHERE_BLEND: f64 = 0.85;

/// Solid half ball of `radius` about `center` on the side of `pole` (normalised;
/// an error if zero): `{x : |x - c| <= R, (x - c) . pole >= 0}`, made of Hex8
/// cells. The default pole `[0, 0, -1]` makes a ball resting on a plane below it.
///
/// `divisions` (at least 2) elements along every quarter meridian in the two
/// planes through the pole and the local axes (below), graded towards the pole:
/// sizes geometric and smallest at the pole, largest / smallest = `grading`
/// along those meridians.
///
/// Construction (a half "cube-sphere" O-grid). In the local right-handed frame
/// `(e1, e2, e_p)`, `e_p = pole`, `e1` the coordinate axis least aligned with the
/// pole made orthogonal to it, the meridian angles from the pole are
/// `θ_k = π (t_k − ½)`, `k = 0..2n`, with `t` the [`symmetric_graded_spacing`] of
/// `2n = 2 divisions` elements and ratio `grading` (so `θ_n = 0` is the pole).
/// `m` is the index with `θ_m` nearest −45° (`1 <= m < n`), `A = −θ_m`,
/// `T = tan A`, `ns = 2n − 2m`, `c = ns / 2`. A lattice
/// `(I, J, K) ∈ [0, ns]² x [0, m]` is meshed three ways:
///
/// * the dome: the boundary of the half lattice box but its bottom (`K = m`, or
///   `I ∈ {0, ns}`, or `J ∈ {0, ns}`) is mapped to directions from the centre,
///   then onto the sphere. The top face `K = m` (around the pole) is made of
///   square rings `r = max(|I − c|, |J − c|)` of directions
///   `(tan θ_{n+r} (I − c) / r, tan θ_{n+r} (J − c) / r, 1)` (gnomonic
///   coordinates: ring `r` at angle `θ_{n+r}` from the pole along the local
///   axes, its nodes uniform along it). The side face `I = ns` has directions
///   `(1, Y, cot ψ_K)`, `ψ_K = −θ_K` the angle from the pole (`K = 0` the
///   equator, `K = m` the top face's edge), the lateral coordinate `Y` going
///   linearly in `1 − T cot ψ_K` from `−1 + 2J / ns` (the top face's edge) to
///   `tan(−45° + 90° J / ns)` (uniform in azimuth on the equator); the other
///   sides alike. The meridians in the planes `(e1, e_p)` and `(e2, e_p)` pass
///   exactly through the graded angles `θ_k`; the rings keep the cells about
///   the pole nearly square.
/// * the inner block `[-a, a]² x [0, b]`, `(a, b) = 0.6 (sin A, cos A)`: a grid
///   of straight vertical columns, column `(I, J)` at `a (0.85 u + 0.15 g)` with
///   `u = (−1 + 2I / ns, −1 + 2J / ns)` uniform and `g` the top face's
///   gnomonic coordinates above (scaled by `1 / T`), at heights
///   `0.85 b K / m + 0.15 a cot ψ_K` (85% uniform, 15% the radial projection of
///   the dome's grid, so that the fine spacing at the pole does not run deep
///   into the body).
/// * the shell: straight lines from each boundary node of the inner block (but
///   the bottom) to its dome node, cut in `n_r = max(2, ceil(divisions / 2))`
///   layers graded geometrically towards the dome, with ratio
///   `sqrt(grading)^cos ψ` (`ψ` the dome node's angle from the pole: as fine as
///   the dome at the pole, uniform at the equator); each quadrilateral of the
///   block's boundary is extruded into `n_r` hexahedra.
///
/// Measured quality (divisions 3..32, grading 1..32): corner Jacobians scaled
/// by the edge lengths >= 0.26 (>= 0.34 for grading <= 16; 0.577 is the
/// cube-sphere's 120° corners); for divisions >= 8 the edge ratio is <= 4.6 for
/// grading 4 and <= 8 for grading 16 (coarser meshes are as anisotropic as
/// their growth factor `grading^(1/(divisions−1))` makes them); the cells at
/// the pole are nearly cubes of the smallest meridian element.
///
/// Dome nodes are then put exactly on the sphere (`c + R (x − c) / |x − c|`),
/// flat nodes lie on the plane through the centre (their pole component is
/// exactly 0 in the local frame). Every cell is checked to have a positive
/// Jacobian at its 8 corners ([`hex_corner_jacobians`]); an error otherwise.
/// Counts: `(ns + 1)² (m + 1) + ((ns + 1)² + 4 ns m) n_r` nodes,
/// `ns² m + (ns² + 4 ns m) n_r` cells.
///
/// Surfaces: "flat" (the disk through the centre, perpendicular to the pole) and
/// "dome", quadrilateral facets with their cells and the node order of
/// [`CellKind::facets`].
pub fn hemisphere(
    center: [f64; 3],
    radius: f64,
    divisions: usize,
    pole: [f64; 3],
    grading: f64,
) -> Result<Mesh, MeshError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(MeshError::Invalid(format!(
            "hemisphere: radius must be positive, got {radius}"
        )));
    }
    if !center.iter().all(|c| c.is_finite()) {
        return Err(MeshError::Invalid(
            "hemisphere: center is not finite".into(),
        ));
    }
    if divisions < 2 {
        return Err(MeshError::Invalid(format!(
            "hemisphere: divisions (elements along a quarter meridian) must be at least 2, got {divisions}"
        )));
    }
    check_ratio("hemisphere", grading)?;
    let pn = pole.iter().map(|p| p * p).sum::<f64>().sqrt();
    if !(pn.is_finite() && pn > 0.0) {
        return Err(MeshError::Invalid(format!(
            "hemisphere: pole must be a non-zero vector, got [{}, {}, {}]",
            pole[0], pole[1], pole[2]
        )));
    }
    let ep = pole.map(|p| p / pn);
    let k_min = (0..3)
        .min_by(|&a, &b| ep[a].abs().total_cmp(&ep[b].abs()))
        .unwrap();
    let mut e1 = [0.0; 3];
    e1[k_min] = 1.0;
    let dot = ep[k_min];
    let e1 = {
        let v = [
            e1[0] - dot * ep[0],
            e1[1] - dot * ep[1],
            e1[2] - dot * ep[2],
        ];
        let l = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.map(|x| x / l)
    };
    let e2 = [
        ep[1] * e1[2] - ep[2] * e1[1],
        ep[2] * e1[0] - ep[0] * e1[2],
        ep[0] * e1[1] - ep[1] * e1[0],
    ];

    let n = divisions;
    let t = symmetric_graded_spacing(2 * n, grading);
    // meridian angles, exactly antisymmetric about the pole
    let theta: Vec<f64> = (0..=2 * n)
        .map(|k| match k.cmp(&n) {
            std::cmp::Ordering::Less => PI * (t[k] - 0.5),
            std::cmp::Ordering::Equal => 0.0,
            std::cmp::Ordering::Greater => -PI * (t[2 * n - k] - 0.5),
        })
        .collect();
    let m = (1..n)
        .min_by(|&a, &b| {
            (theta[a] + PI / 4.0)
                .abs()
                .total_cmp(&(theta[b] + PI / 4.0).abs())
        })
        .unwrap();
    let ns = 2 * n - 2 * m;
    let big_a = -theta[m];
    let tan_a = big_a.tan();
    let c = ns / 2;
    // unit coordinate in [-1, 1] of lattice line i, exact at the ends and in
    // the middle
    let unit = |i: usize, f: &dyn Fn(usize) -> f64| -> f64 {
        if i == 0 {
            -1.0
        } else if i == ns {
            1.0
        } else if i == c {
            0.0
        } else {
            f(i)
        }
    };
    let lat_eq: Vec<f64> = (0..=ns)
        .map(|i| unit(i, &|i| (-PI / 4.0 + PI / 2.0 * i as f64 / ns as f64).tan()))
        .collect();
    let lat_uniform: Vec<f64> = (0..=ns)
        .map(|i| unit(i, &|i| -1.0 + 2.0 * i as f64 / ns as f64))
        .collect();
    // top face (gnomonic coordinates scaled by 1/T): square ring r about the
    // pole at half-width tan θ_{n+r} / T, its nodes uniform along it
    let ring: Vec<f64> = (0..=c)
        .map(|r| match r {
            0 => 0.0,
            _ if r == c => 1.0,
            _ => theta[n + r].tan() / tan_a,
        })
        .collect();
    let top = |i: usize, j: usize| -> [f64; 2] {
        let (p, q) = (i as f64 - c as f64, j as f64 - c as f64);
        let r = i.abs_diff(c).max(j.abs_diff(c));
        if r == 0 {
            return [0.0, 0.0];
        }
        let f = ring[r] / r as f64;
        [f * p, f * q]
    };
    // cot of the angle from the pole of side level K (0 on the equator, 1/T on
    // the top edge)
    let zc: Vec<f64> = (0..=m)
        .map(|k| {
            if k == 0 {
                0.0
            } else if k == m {
                1.0 / tan_a
            } else {
                1.0 / (-theta[k]).tan()
            }
        })
        .collect();
    // unnormalised direction of the dome node of boundary lattice point (I, J, K)
    let dome_dir = |i: usize, j: usize, k: usize| -> [f64; 3] {
        if k == m {
            let [x, y] = top(i, j);
            return [x, y, zc[m]];
        }
        let s = 1.0 - zc[k] * tan_a;
        let y = |l: usize| (1.0 - s) * lat_uniform[l] + s * lat_eq[l];
        if i == ns {
            [1.0, y(j), zc[k]]
        } else if i == 0 {
            [-1.0, y(j), zc[k]]
        } else if j == ns {
            [y(i), 1.0, zc[k]]
        } else {
            [y(i), -1.0, zc[k]]
        }
    };
    // inner block: columns (I, J) blended from the uniform grid and the top
    // face's, at heights blended from uniform and the sides' levels
    let w = HEMISPHERE_BLEND;
    let (a, b) = (HEMISPHERE_CORE * big_a.sin(), HEMISPHERE_CORE * big_a.cos());
    let column = |i: usize, j: usize| -> [f64; 2] {
        let t = top(i, j);
        [
            a * (w * lat_uniform[i] + (1.0 - w) * t[0]),
            a * (w * lat_uniform[j] + (1.0 - w) * t[1]),
        ]
    };
    let hin: Vec<f64> = (0..=m)
        .map(|k| {
            if k == m {
                b
            } else {
                w * b * k as f64 / m as f64 + (1.0 - w) * a * zc[k]
            }
        })
        .collect();
    let lid = |i: usize, j: usize, k: usize| (k * (ns + 1) + j) * (ns + 1) + i;
    let n_inner = (ns + 1) * (ns + 1) * (m + 1);
    let mut local: Vec<[f64; 3]> = Vec::new();
    let mut on_flat: Vec<bool> = Vec::new();
    for (k, &h) in hin.iter().enumerate() {
        for j in 0..=ns {
            for i in 0..=ns {
                let [x, y] = column(i, j);
                local.push([x, y, h]);
                on_flat.push(k == 0);
            }
        }
    }
    // boundary lattice points (all but the bottom face's interior), their
    // index among them
    let is_boundary =
        |i: usize, j: usize, k: usize| k == m || i == 0 || i == ns || j == 0 || j == ns;
    let mut bindex = vec![usize::MAX; n_inner];
    let mut bpoints = Vec::new();
    for k in 0..=m {
        for j in 0..=ns {
            for i in 0..=ns {
                if is_boundary(i, j, k) {
                    bindex[lid(i, j, k)] = bpoints.len();
                    bpoints.push((i, j, k));
                }
            }
        }
    }
    let nr = n.div_ceil(2).max(2);
    let mut on_dome = vec![false; n_inner];
    for &(i, j, k) in &bpoints {
        let p0 = local[lid(i, j, k)];
        let d = dome_dir(i, j, k);
        let dl = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        let p1 = d.map(|x| x / dl);
        // layers graded towards the dome, ratio sqrt(grading) at the pole
        // fading to 1 (uniform) at the equator: sqrt(grading)^cos(angle from the pole)
        let g: Vec<f64> = graded_spacing(nr, grading.powf(0.5 * p1[2]))
            .iter()
            .rev()
            .map(|t| 1.0 - t)
            .collect();
        for (l, &gl) in g.iter().enumerate().skip(1) {
            let mut p = if l == nr {
                p1
            } else {
                [
                    p0[0] + gl * (p1[0] - p0[0]),
                    p0[1] + gl * (p1[1] - p0[1]),
                    p0[2] + gl * (p1[2] - p0[2]),
                ]
            };
            if k == 0 {
                p[2] = 0.0;
            }
            local.push(p);
            on_flat.push(k == 0);
            on_dome.push(l == nr);
        }
    }
    // node of boundary lattice point (i, j, k) at shell layer l (0: the block)
    let sid = |(i, j, k): (usize, usize, usize), l: usize| -> usize {
        if l == 0 {
            lid(i, j, k)
        } else {
            n_inner + bindex[lid(i, j, k)] * nr + (l - 1)
        }
    };
    let mut cells = Vec::new();
    for k in 0..m {
        for j in 0..ns {
            for i in 0..ns {
                cells.push(Cell {
                    kind: CellKind::Hex8,
                    nodes: vec![
                        lid(i, j, k),
                        lid(i + 1, j, k),
                        lid(i + 1, j + 1, k),
                        lid(i, j + 1, k),
                        lid(i, j, k + 1),
                        lid(i + 1, j, k + 1),
                        lid(i + 1, j + 1, k + 1),
                        lid(i, j + 1, k + 1),
                    ],
                });
            }
        }
    }
    // the block's boundary quadrilaterals, counter-clockwise seen from outside
    let mut quads: Vec<[(usize, usize, usize); 4]> = Vec::new();
    for j in 0..ns {
        for i in 0..ns {
            quads.push([(i, j, m), (i + 1, j, m), (i + 1, j + 1, m), (i, j + 1, m)]);
        }
    }
    for k in 0..m {
        for l in 0..ns {
            // x = +a: (J, K); x = -a: (K, J); y = +a: (K, I); y = -a: (I, K)
            quads.push([
                (ns, l, k),
                (ns, l + 1, k),
                (ns, l + 1, k + 1),
                (ns, l, k + 1),
            ]);
            quads.push([(0, l, k), (0, l, k + 1), (0, l + 1, k + 1), (0, l + 1, k)]);
            quads.push([
                (l, ns, k),
                (l, ns, k + 1),
                (l + 1, ns, k + 1),
                (l + 1, ns, k),
            ]);
            quads.push([(l, 0, k), (l + 1, 0, k), (l + 1, 0, k + 1), (l, 0, k + 1)]);
        }
    }
    for q in &quads {
        for l in 0..nr {
            let mut nodes: Vec<usize> = q.iter().map(|&p| sid(p, l)).collect();
            nodes.extend(q.iter().map(|&p| sid(p, l + 1)));
            cells.push(Cell {
                kind: CellKind::Hex8,
                nodes,
            });
        }
    }
    let coords: Vec<[f64; 3]> = local
        .iter()
        .zip(&on_dome)
        .map(|(p, &dome)| {
            let mut x = [0.0; 3];
            for k in 0..3 {
                x[k] = radius * (p[0] * e1[k] + p[1] * e2[k] + p[2] * ep[k]);
            }
            if dome {
                let l = x.iter().map(|v| v * v).sum::<f64>().sqrt();
                x = x.map(|v| radius * v / l);
            }
            [center[0] + x[0], center[1] + x[1], center[2] + x[2]]
        })
        .collect();
    let mut mesh = Mesh {
        dim: 3,
        coords,
        cells,
        surfaces: BTreeMap::new(),
        regions: Default::default(),
    };
    name_boundary(&mut mesh, &["flat", "dome"], |nodes| {
        if nodes.iter().all(|&v| on_flat[v]) {
            0
        } else {
            debug_assert!(nodes.iter().all(|&v| on_dome[v]));
            1
        }
    })?;
    for c in 0..mesh.cells.len() {
        let det = hex_corner_jacobians(&mesh, c);
        if let Some(d) = det.iter().find(|d| d.is_nan() || **d <= 0.0) {
            return Err(MeshError::Invalid(format!(
                "hemisphere: cell {c} has a corner Jacobian {d:e} <= 0 (divisions {divisions}, grading {grading})"
            )));
        }
    }
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
                    // triangles (four per quad) min sin 0.145 (angles >= 8°), aspect <= 3.6
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
        // Tri3: four triangles about a node added at each quad's centre
        let t = half_disk([0.0, 0.0], 1.0, 16, [0.0, -1.0], 1.0, CellKind::Tri3).unwrap();
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
        let half = half_disk([0.0, 0.0], 1.0, 32, [0.0, -1.0], 4.0, CellKind::Quad4).unwrap();
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
            assert!(half_disk([0.0, 0.0], 1.0, 8, [0.0, -1.0], 1.0, kind).is_err());
        }
        for kind in [CellKind::Quad8, CellKind::Tri6] {
            let m = rectangle([0.0, 0.0], [1.0, 1.0], [2, 2], kind, None).unwrap();
            m.check().unwrap();
            assert!(m.cells.iter().all(|c| c.kind == kind));
            check_boundary_cover(&m);
        }
    }
}
