//! The half disk ([`half_disk`], a half O-grid) and the quarter disk cut from it
//! ([`quarter_disk`]) for axisymmetric models.

use super::split::{build_2d, EdgeList, TriangleSplit};
use super::{graded_spacing, symmetric_graded_spacing, HalfBall, HALF_DISK, QUARTER_DISK};
use crate::{CellKind, Mesh, MeshError};
use std::f64::consts::PI;

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
pub fn half_disk(ball: &HalfBall<2>, kind: CellKind) -> Result<Mesh, MeshError> {
    let parts = half_disk_quads(ball)?;
    let mut mesh = build_2d(
        parts.coords,
        &parts.quads,
        vec![("flat", parts.flat), ("arc", parts.arc)],
        kind,
        TriangleSplit::Crossed,
    )?;
    arc_midsides_on_circle(&mut mesh, "arc", ball.center, ball.radius);
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
fn half_disk_quads(ball: &HalfBall<2>) -> Result<HalfDiskQuads, MeshError> {
    HALF_DISK.check(&ball.center, ball.radius, ball.divisions, ball.grading)?;
    let pn = (ball.pole[0] * ball.pole[0] + ball.pole[1] * ball.pole[1]).sqrt();
    if !(pn.is_finite() && pn > 0.0) {
        return Err(MeshError::Invalid(format!(
            "half_disk: pole must be a non-zero vector, got [{}, {}]",
            ball.pole[0], ball.pole[1]
        )));
    }
    let ep = [ball.pole[0] / pn, ball.pole[1] / pn];
    let et = [ep[1], -ep[0]];
    let phi: Vec<f64> = symmetric_graded_spacing(ball.divisions, ball.grading)
        .iter()
        .map(|t| PI * t)
        .collect();
    let grid = HalfDiskGrid::new(&phi);
    let mut local = grid.rectangle_nodes(&phi);
    grid.push_ring_nodes(&phi, ball.grading, &mut local);
    let (flat, arc) = grid.boundary_edges();
    let coords = local
        .iter()
        .map(|p| {
            [
                ball.center[0] + ball.radius * (p[0] * et[0] + p[1] * ep[0]),
                ball.center[1] + ball.radius * (p[0] * et[1] + p[1] * ep[1]),
                0.0,
            ]
        })
        .collect();
    Ok(HalfDiskQuads {
        coords,
        quads: grid.quads(),
        flat,
        arc,
    })
}

/// The index layout of [`half_disk`]'s half O-grid (unit radius, local frame
/// `u` along `e_t`, `v` along `e_p`): the inner rectangle's nodes `(i, j)`,
/// then the ring's, radial line by radial line along the arc.
struct HalfDiskGrid {
    /// Elements along the arc.
    n: usize,
    /// Arc index of the inner rectangle's corner (the angle nearest 45°); also
    /// its elements along `v`.
    m: usize,
    /// The inner rectangle's elements along `u`: `n − 2m`.
    ns: usize,
    /// The ring's layers: `ceil(n / 8)`.
    nr: usize,
}

impl HalfDiskGrid {
    /// The layout for the arc angles `phi` (`n + 1` of them, 0 to π).
    fn new(phi: &[f64]) -> HalfDiskGrid {
        let n = phi.len() - 1;
        // arc index of the inner rectangle's corner: the angle nearest 45°
        let m = (1..=(n - 1) / 2)
            .min_by(|&a, &b| {
                (phi[a] - PI / 4.0)
                    .abs()
                    .total_cmp(&(phi[b] - PI / 4.0).abs())
            })
            .unwrap_or(1);
        HalfDiskGrid {
            n,
            m,
            ns: n - 2 * m,
            nr: n.div_ceil(8).max(1),
        }
    }

    /// Node `(i, j)` of the inner rectangle (i along u, j along v).
    fn rid(&self, i: usize, j: usize) -> usize {
        j * (self.ns + 1) + i
    }

    /// The rectangle's boundary node on the radial line to arc node `k`.
    fn inner(&self, k: usize) -> usize {
        let (n, m, ns) = (self.n, self.m, self.ns);
        if k <= m {
            self.rid(ns, k)
        } else if k <= n - m {
            self.rid(ns - (k - m), m)
        } else {
            self.rid(0, n - k)
        }
    }

    /// Ring node `(k, l)`, `k = 0..=n` along the arc, `l = 0..=nr` outwards;
    /// `l = 0` is the rectangle's boundary.
    fn ring_id(&self, k: usize, l: usize) -> usize {
        if l == 0 {
            self.inner(k)
        } else {
            (self.ns + 1) * (self.m + 1) + k * self.nr + (l - 1)
        }
    }

    /// Ring quadrilateral `(k, l)` (after the rectangle's `ns m`).
    fn q_ring(&self, k: usize, l: usize) -> usize {
        self.ns * self.m + k * self.nr + l
    }

    /// The inner rectangle `[-a, a] x [0, b]`'s nodes, row by row: the right
    /// and top sides 15% the radial projection of the arc nodes, 85% uniform;
    /// inside, each column blends the uniform bottom and the top.
    fn rectangle_nodes(&self, phi: &[f64]) -> Vec<[f64; 2]> {
        let (n, m, ns) = (self.n, self.m, self.ns);
        let (a, b) = (HALF_DISK_CORE * phi[m].cos(), HALF_DISK_CORE * phi[m].sin());
        let w = HALF_DISK_BLEND;
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
        local
    }

    /// Appends the ring's nodes to the rectangle's (`local`): on the straight
    /// line from the rectangle's boundary node to each arc node, graded
    /// geometrically towards the arc (ratio `sqrt(grading)`), the last exactly
    /// on the arc (and the ends' on the flat line).
    fn push_ring_nodes(&self, phi: &[f64], grading: f64, local: &mut Vec<[f64; 2]>) {
        let (n, nr) = (self.n, self.nr);
        let g: Vec<f64> = graded_spacing(nr, grading.sqrt())
            .iter()
            .rev()
            .map(|t| 1.0 - t)
            .collect();
        for k in 0..=n {
            let p0 = local[self.inner(k)];
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
    }

    /// The counter-clockwise quadrilaterals: the rectangle's row by row, then
    /// the ring's radial line by radial line.
    fn quads(&self) -> Vec<[usize; 4]> {
        let (n, m, ns, nr) = (self.n, self.m, self.ns, self.nr);
        let mut quads: Vec<[usize; 4]> = Vec::with_capacity(ns * m + n * nr);
        for j in 0..m {
            for i in 0..ns {
                quads.push([
                    self.rid(i, j),
                    self.rid(i + 1, j),
                    self.rid(i + 1, j + 1),
                    self.rid(i, j + 1),
                ]);
            }
        }
        for k in 0..n {
            for l in 0..nr {
                // radial outwards, then ccw along the arc: counter-clockwise
                quads.push([
                    self.ring_id(k, l),
                    self.ring_id(k, l + 1),
                    self.ring_id(k + 1, l + 1),
                    self.ring_id(k + 1, l),
                ]);
            }
        }
        quads
    }

    /// The boundary edges "flat" and "arc", listed along the boundary (body on
    /// the left).
    fn boundary_edges(&self) -> (EdgeList, EdgeList) {
        let (n, ns, nr) = (self.n, self.ns, self.nr);
        let mut flat = Vec::new();
        for l in (0..nr).rev() {
            flat.push((
                self.ring_id(n, l + 1),
                self.ring_id(n, l),
                self.q_ring(n - 1, l),
            ));
        }
        for i in 0..ns {
            flat.push((self.rid(i, 0), self.rid(i + 1, 0), i));
        }
        for l in 0..nr {
            flat.push((
                self.ring_id(0, l),
                self.ring_id(0, l + 1),
                self.q_ring(0, l),
            ));
        }
        let arc = (0..n)
            .map(|k| {
                (
                    self.ring_id(k, nr),
                    self.ring_id(k + 1, nr),
                    self.q_ring(k, nr - 1),
                )
            })
            .collect();
        (flat, arc)
    }
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
    QUARTER_DISK.check(&center, radius, divisions, grading)?;
    let half = half_disk_quads(&HalfBall::new(
        center,
        radius,
        2 * divisions,
        [0.0, -1.0],
        grading,
    ))?;
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
