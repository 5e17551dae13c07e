//! The solid half ball of hexahedra ([`hemisphere`], a half cube-sphere O-grid).

use super::{
    graded_spacing, hex_corner_jacobians, name_boundary, symmetric_graded_spacing, HalfBall,
    HEMISPHERE,
};
use crate::{Cell, CellKind, Mesh, MeshError};
use std::collections::BTreeMap;
use std::f64::consts::PI;

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
pub fn hemisphere(ball: &HalfBall<3>) -> Result<Mesh, MeshError> {
    HEMISPHERE.check(&ball.center, ball.radius, ball.divisions, ball.grading)?;
    let frame = pole_frame(ball.pole)?;
    let lattice = Lattice::new(ball.divisions, ball.grading);
    let nodes = HemisphereNodes::new(&lattice, ball.grading);
    let mut cells = lattice.block_cells();
    cells.extend(nodes.shell_cells(&lattice));
    let mut mesh = Mesh {
        dim: 3,
        coords: nodes.global_coords(ball.center, ball.radius, frame),
        cells,
        surfaces: BTreeMap::new(),
        regions: Default::default(),
        node_sets: Default::default(),
    };
    name_boundary(&mut mesh, &["flat", "dome"], |facet| {
        if facet.iter().all(|&v| nodes.on_flat[v]) {
            0
        } else {
            debug_assert!(facet.iter().all(|&v| nodes.on_dome[v]));
            1
        }
    })?;
    for c in 0..mesh.cells.len() {
        let det = hex_corner_jacobians(&mesh, c);
        if let Some(d) = det.iter().find(|d| d.is_nan() || **d <= 0.0) {
            return Err(MeshError::Invalid(format!(
                "hemisphere: cell {c} has a corner Jacobian {d:e} <= 0 (divisions {}, grading {})",
                ball.divisions, ball.grading
            )));
        }
    }
    mesh.check()?;
    Ok(mesh)
}

/// The local right-handed frame `[e1, e2, e_p]` of [`hemisphere`]: `e_p` the
/// normalised `pole` (an error if zero), `e1` the coordinate axis least aligned
/// with the pole made orthogonal to it, `e2 = e_p x e1`.
pub(super) fn pole_frame(pole: [f64; 3]) -> Result<[[f64; 3]; 3], MeshError> {
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
    Ok([e1, e2, ep])
}

/// The lattice `(I, J, K) ∈ [0, ns]² x [0, m]` of [`hemisphere`] with the
/// meridian angles it is graded by (unit radius, local frame).
struct Lattice {
    /// Elements along a quarter meridian (`divisions`).
    n: usize,
    /// Lattice levels of the sides: `K = 0` the equator, `K = m` the top face.
    m: usize,
    /// Lattice cells along `I` and along `J`: `2n − 2m`.
    ns: usize,
    /// The middle lattice line `ns / 2` (through the pole).
    c: usize,
    /// `A = −θ_m`, the angle from the pole of the top face's edge.
    big_a: f64,
    /// `T = tan A`.
    tan_a: f64,
    /// Lateral coordinates in [-1, 1] uniform in azimuth on the equator.
    lat_eq: Vec<f64>,
    /// Lateral coordinates in [-1, 1] uniform along the lattice line.
    lat_uniform: Vec<f64>,
    /// Half-width of the top face's square ring `r` (gnomonic, scaled by 1/T).
    ring: Vec<f64>,
    /// Cot of the angle from the pole of side level `K` (0 on the equator, 1/T
    /// on the top edge).
    zc: Vec<f64>,
}

impl Lattice {
    /// The meridian angles graded by `grading` over `2 divisions` elements,
    /// the lattice sizes and the dome's lateral and ring coordinates.
    fn new(divisions: usize, grading: f64) -> Lattice {
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
        Lattice {
            n,
            m,
            ns,
            c,
            big_a,
            tan_a,
            lat_eq,
            lat_uniform,
            ring,
            zc,
        }
    }

    /// Index of the inner block's node at lattice point `(i, j, k)`.
    fn lid(&self, i: usize, j: usize, k: usize) -> usize {
        (k * (self.ns + 1) + j) * (self.ns + 1) + i
    }

    /// Number of the inner block's nodes, `(ns + 1)² (m + 1)`.
    fn n_block_nodes(&self) -> usize {
        (self.ns + 1) * (self.ns + 1) * (self.m + 1)
    }

    /// Whether lattice point `(i, j, k)` is on the block's boundary but its
    /// bottom (the flat face's interior).
    fn is_boundary(&self, i: usize, j: usize, k: usize) -> bool {
        let ns = self.ns;
        k == self.m || i == 0 || i == ns || j == 0 || j == ns
    }

    /// Gnomonic coordinates (scaled by 1/T) of the top face's lattice point
    /// `(i, j)`: on the square ring `max(|i − c|, |j − c|)`, uniform along it.
    fn top(&self, i: usize, j: usize) -> [f64; 2] {
        let c = self.c;
        let (p, q) = (i as f64 - c as f64, j as f64 - c as f64);
        let r = i.abs_diff(c).max(j.abs_diff(c));
        if r == 0 {
            return [0.0, 0.0];
        }
        let f = self.ring[r] / r as f64;
        [f * p, f * q]
    }

    /// Unnormalised direction of the dome node of boundary lattice point
    /// `(i, j, k)`.
    fn dome_dir(&self, i: usize, j: usize, k: usize) -> [f64; 3] {
        let (m, ns, zc) = (self.m, self.ns, &self.zc);
        if k == m {
            let [x, y] = self.top(i, j);
            return [x, y, zc[m]];
        }
        let s = 1.0 - zc[k] * self.tan_a;
        let y = |l: usize| (1.0 - s) * self.lat_uniform[l] + s * self.lat_eq[l];
        if i == ns {
            [1.0, y(j), zc[k]]
        } else if i == 0 {
            [-1.0, y(j), zc[k]]
        } else if j == ns {
            [y(i), 1.0, zc[k]]
        } else {
            [y(i), -1.0, zc[k]]
        }
    }

    /// The inner block's nodes: columns `(I, J)` blended from the uniform grid
    /// and the top face's, at heights blended from uniform and the sides'
    /// levels; in lattice order ([`Lattice::lid`]).
    fn block_nodes(&self) -> Vec<[f64; 3]> {
        let (m, ns) = (self.m, self.ns);
        let w = HEMISPHERE_BLEND;
        let (a, b) = (
            HEMISPHERE_CORE * self.big_a.sin(),
            HEMISPHERE_CORE * self.big_a.cos(),
        );
        let column = |i: usize, j: usize| -> [f64; 2] {
            let t = self.top(i, j);
            [
                a * (w * self.lat_uniform[i] + (1.0 - w) * t[0]),
                a * (w * self.lat_uniform[j] + (1.0 - w) * t[1]),
            ]
        };
        let hin: Vec<f64> = (0..=m)
            .map(|k| {
                if k == m {
                    b
                } else {
                    w * b * k as f64 / m as f64 + (1.0 - w) * a * self.zc[k]
                }
            })
            .collect();
        let mut local = Vec::with_capacity(self.n_block_nodes());
        for &h in &hin {
            for j in 0..=ns {
                for i in 0..=ns {
                    let [x, y] = column(i, j);
                    local.push([x, y, h]);
                }
            }
        }
        local
    }

    /// The inner block's hexahedra, lattice cell by lattice cell.
    fn block_cells(&self) -> Vec<Cell> {
        let ns = self.ns;
        let mut cells = Vec::new();
        for k in 0..self.m {
            for j in 0..ns {
                for i in 0..ns {
                    cells.push(Cell {
                        kind: CellKind::Hex8,
                        nodes: vec![
                            self.lid(i, j, k),
                            self.lid(i + 1, j, k),
                            self.lid(i + 1, j + 1, k),
                            self.lid(i, j + 1, k),
                            self.lid(i, j, k + 1),
                            self.lid(i + 1, j, k + 1),
                            self.lid(i + 1, j + 1, k + 1),
                            self.lid(i, j + 1, k + 1),
                        ],
                    });
                }
            }
        }
        cells
    }

    /// The block's boundary quadrilaterals (lattice points), counter-clockwise
    /// seen from outside: the top face, then the four sides level by level.
    fn boundary_quads(&self) -> Vec<[(usize, usize, usize); 4]> {
        let (m, ns) = (self.m, self.ns);
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
        quads
    }
}

/// The nodes of [`hemisphere`] in the local frame at unit radius: the inner
/// block's, then for each boundary lattice point its `n_r` shell nodes out to
/// the dome.
struct HemisphereNodes {
    local: Vec<[f64; 3]>,
    /// Whether the node lies on the flat face.
    on_flat: Vec<bool>,
    /// Whether the node lies on the dome.
    on_dome: Vec<bool>,
    /// Index among the boundary lattice points of each block node
    /// (`usize::MAX` if not on the boundary).
    bindex: Vec<usize>,
    /// Shell layers `n_r`.
    nr: usize,
}

impl HemisphereNodes {
    /// The block's nodes, then the shell's: straight lines from each boundary
    /// lattice point to its dome node, cut in `n_r` layers graded towards the
    /// dome (ratio `sqrt(grading)` at the pole fading to 1 at the equator).
    fn new(lattice: &Lattice, grading: f64) -> HemisphereNodes {
        let (m, ns) = (lattice.m, lattice.ns);
        let n_inner = lattice.n_block_nodes();
        let mut local = lattice.block_nodes();
        // the flat face: level K = 0, the first (ns + 1)² block nodes
        let mut on_flat: Vec<bool> = (0..n_inner).map(|v| v < (ns + 1) * (ns + 1)).collect();
        // boundary lattice points (all but the bottom face's interior), their
        // index among them
        let mut bindex = vec![usize::MAX; n_inner];
        let mut bpoints = Vec::new();
        for k in 0..=m {
            for j in 0..=ns {
                for i in 0..=ns {
                    if lattice.is_boundary(i, j, k) {
                        bindex[lattice.lid(i, j, k)] = bpoints.len();
                        bpoints.push((i, j, k));
                    }
                }
            }
        }
        let nr = lattice.n.div_ceil(2).max(2);
        let mut on_dome = vec![false; n_inner];
        for &(i, j, k) in &bpoints {
            let p0 = local[lattice.lid(i, j, k)];
            let d = lattice.dome_dir(i, j, k);
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
        HemisphereNodes {
            local,
            on_flat,
            on_dome,
            bindex,
            nr,
        }
    }

    /// Node of boundary lattice point `(i, j, k)` at shell layer `l` (0: the
    /// block's node).
    fn sid(&self, lattice: &Lattice, (i, j, k): (usize, usize, usize), l: usize) -> usize {
        let v = lattice.lid(i, j, k);
        if l == 0 {
            v
        } else {
            lattice.n_block_nodes() + self.bindex[v] * self.nr + (l - 1)
        }
    }

    /// The shell's hexahedra: each boundary quadrilateral of the block extruded
    /// into `n_r` of them, layer by layer out to the dome.
    fn shell_cells(&self, lattice: &Lattice) -> Vec<Cell> {
        let mut cells = Vec::new();
        for q in &lattice.boundary_quads() {
            for l in 0..self.nr {
                let mut nodes: Vec<usize> = q.iter().map(|&p| self.sid(lattice, p, l)).collect();
                nodes.extend(q.iter().map(|&p| self.sid(lattice, p, l + 1)));
                cells.push(Cell {
                    kind: CellKind::Hex8,
                    nodes,
                });
            }
        }
        cells
    }

    /// The nodes in global coordinates: scaled by `radius` in `frame`
    /// (`[e1, e2, e_p]`) about `center`, dome nodes put exactly on the sphere.
    fn global_coords(&self, center: [f64; 3], radius: f64, frame: [[f64; 3]; 3]) -> Vec<[f64; 3]> {
        let [e1, e2, ep] = frame;
        self.local
            .iter()
            .zip(&self.on_dome)
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
            .collect()
    }
}
