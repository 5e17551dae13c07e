//! The semi-smooth Newton system of [`crate::friction::semismooth_newton`] reduced to
//! its coupled directions E (columns e_a over one or two rows): with h the
//! given part of dλ, s the coupled amplitudes and d their compliances,
//!
//! ```text
//!   (Eᵀ W E + diag d) s + Eᵀ G dα = v − Eᵀ W h
//!   Gᵀ E s                      = v_eq − Gᵀ h
//! ```
//!
//! symmetric (W symmetric positive definite, d ≥ 0): Cholesky, floating
//! bodies through the Schur complement on G. Coulomb's law itself adds the
//! normal forces to slipping rows ([`NewtonSystem`]): a given row f dλ_n
//! of a given normal row goes to h, of a coupled one (position y) is a
//! dependent direction, dλ = h + E s + Σ f e s_y =: h + P s; the block is
//! then Eᵀ W P + diag d (plus the coupled rows' own f dλ_n), by a partially
//! pivoted LU, and the equilibrium rows Gᵀ P s.
//!
//! Without floating bodies, the unknowns whose columns carry the
//! nonsymmetric terms (the normal forces of slipping points, Y) are ordered
//! last: the rest of the block (O) is symmetric positive definite, and the
//! block is factorised by Cholesky on O and a partially pivoted LU of the
//! |Y| × |Y| Schur complement ([`BorderedFactor`]), about half the work of
//! an LU of the whole block; when either factorisation fails or is near
//! singular, by the LU of the whole block. The block is written straight
//! into the storage of the previous factor (only the lower triangle of O),
//! so a Newton iteration touches no fresh pages.

use faer::Mat;

use crate::friction::semismooth_newton::{Dir, NewtonSystem};
use signorini_linalg::bordered_factor::{block_buffer, BorderedFactor, FactorFailure};
use signorini_linalg::reduced::{schur_on_g, BlockFactor};

/// Solves the reduced Newton system of `sys` (see the module); with `chord`,
/// only with the cached factor of the same structure. Returns dx = (dλ, dα),
/// or `None` for the caller's full solve.
pub(crate) fn solve_newton(
    w: &Mat<f64>,
    g: &Mat<f64>,
    sys: &NewtonSystem,
    cache: &mut Option<NewtonFactor>,
    chord: bool,
) -> Option<Vec<f64>> {
    let mut red = reduce_newton(sys, w.nrows());
    let reuse = chord && cache.as_ref().is_some_and(|c| c.key == red.key);
    if chord && !reuse {
        return None;
    }
    reduced_rhs(w, sys, &mut red);
    if !reuse {
        let storage = cache.take().map(|c| c.factor.into_buffer());
        let block = NewtonBlock::new(sys, &red, g.ncols() == 0);
        *cache = Some(NewtonFactor {
            key: red.key.clone(),
            factor: block.factorise(w, sys, &red, storage.unwrap_or_default())?,
        });
    }
    let factor = &cache.as_ref()?.factor;
    let y = factor.solve(&red.rhs);
    let (k, nu) = (g.ncols(), red.dirs.len());
    let on_g = |d: &Dir, j: usize| d.c[0] * g[(d.rows[0], j)] + d.c[1] * g[(d.rows[1], j)];
    let (s, alpha) = if k == 0 {
        (y, Vec::new())
    } else {
        // Floating bodies: through the k × k Schur complement on G.
        let g_u = Mat::<f64>::from_fn(nu, k, |x, j| on_g(&red.dirs[x], j));
        let mut g_hat = g_u.clone();
        for (d, y, f) in &red.dependent {
            for j in 0..k {
                g_hat[(*y, j)] += f * on_g(d, j);
            }
        }
        let e_j: Vec<f64> = (0..k)
            .map(|j| {
                let given: f64 = red.nonzero.iter().map(|&i| g[(i, j)] * red.h[i]).sum();
                sys.equilibrium[j] - given
            })
            .collect();
        schur_on_g(&|b| factor.solve(b), &g_u, &g_hat, y, &e_j)?
    };
    let mut dx = red.h;
    for (x, d) in red.dirs.iter().enumerate() {
        dx[d.rows[0]] += d.c[0] * s[(x, 0)];
        dx[d.rows[1]] += d.c[1] * s[(x, 0)];
    }
    for (d, y, f) in &red.dependent {
        dx[d.rows[0]] += d.c[0] * f * s[(*y, 0)];
        dx[d.rows[1]] += d.c[1] * f * s[(*y, 0)];
    }
    dx.extend(alpha);
    dx.iter().all(|v| v.is_finite()).then_some(dx)
}

/// The factor of a reduced Newton block and the structure it was built on
/// (its coupled and dependent rows, the unknowns of the normal-force
/// terms): a chord step may reuse it while the structure repeats.
pub(crate) struct NewtonFactor {
    key: Vec<usize>,
    factor: BlockFactor,
}

impl NewtonFactor {
    /// Whether the block was factorised bordered ([`BorderedFactor`]).
    #[cfg(test)]
    pub(crate) fn is_bordered(&self) -> bool {
        self.factor.factor.is_bordered()
    }
}

impl std::fmt::Debug for NewtonFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "NewtonFactor({} keys)", self.key.len())
    }
}

/// The reduction of a Newton system: its coupled directions, dependent
/// directions (direction, unknown, factor), given part h (its nonzero
/// rows), right-hand side and structure key.
struct NewtonReduction {
    dirs: Vec<Dir>,
    position: Vec<Option<usize>>,
    dependent: Vec<(Dir, usize, f64)>,
    h: Vec<f64>,
    nonzero: Vec<usize>,
    rhs: Mat<f64>,
    key: Vec<usize>,
}

/// The reduction of `sys` over `n` rows but its right-hand side (see
/// [`reduced_rhs`]): the structure key first, cheap to compare.
fn reduce_newton(sys: &NewtonSystem, n: usize) -> NewtonReduction {
    let dirs: Vec<Dir> = sys.coupled.iter().map(|(d, _, _)| *d).collect();
    // The unknown of each coupled single row (the normal rows).
    let mut position = vec![None; n];
    let mut key = Vec::new();
    for (x, d) in dirs.iter().enumerate() {
        if d.rows[0] == d.rows[1] {
            position[d.rows[0]] = Some(x);
        }
        key.extend(d.rows);
    }
    let mut h = vec![0.0; n];
    for (d, v) in &sys.given {
        h[d.rows[0]] += d.c[0] * v;
        h[d.rows[1]] += d.c[1] * v;
    }
    let mut dependent: Vec<(Dir, usize, f64)> = Vec::new();
    for &(i, r, f) in &sys.given_normal {
        let d = sys.given[i].0;
        match position[r] {
            Some(y) => {
                dependent.push((d, y, f));
                key.extend([usize::MAX, d.rows[0], d.rows[1], y]);
            }
            None => {
                let v = f * h[r];
                h[d.rows[0]] += d.c[0] * v;
                h[d.rows[1]] += d.c[1] * v;
            }
        }
    }
    let nonzero: Vec<usize> = (0..n).filter(|&i| h[i] != 0.0).collect();
    for &(x, r, _) in &sys.coupled_normal {
        if let Some(y) = position[r] {
            key.extend([usize::MAX - 1, x, y]);
        }
    }
    NewtonReduction {
        dirs,
        position,
        dependent,
        h,
        nonzero,
        rhs: Mat::zeros(0, 1),
        key,
    }
}

/// The right-hand side of the reduced system: the coupled rows' values
/// less their W rows on the given part h (and its normal-force terms).
fn reduced_rhs(w: &Mat<f64>, sys: &NewtonSystem, red: &mut NewtonReduction) {
    let (dirs, h) = (&red.dirs, &red.h);
    let mut wh = vec![0.0; w.nrows()];
    crate::lcp::matvec(w, h, &mut wh);
    let mut rhs = Mat::<f64>::from_fn(dirs.len(), 1, |x, _| sys.coupled[x].2 - dirs[x].dot(&wh));
    for &(x, r, f) in &sys.coupled_normal {
        if red.position[r].is_none() {
            rhs[(x, 0)] -= f * h[r];
        }
    }
    red.rhs = rhs;
}

/// The layout of the reduced block Eᵀ W P + diag d (+ the coupled rows'
/// normal-force terms): unknown x at block position `pos[x]` (`order` the
/// inverse), O first, then the `n_y` unknowns Y whose columns carry the
/// nonsymmetric terms (when reordered); whether it is symmetric.
struct NewtonBlock {
    order: Vec<usize>,
    pos: Vec<usize>,
    n_y: usize,
    symmetric: bool,
}

impl NewtonBlock {
    /// With `reorder`, the unknowns Y (the columns of the dependent
    /// directions and of the coupled rows' normal-force terms) last.
    fn new(sys: &NewtonSystem, red: &NewtonReduction, reorder: bool) -> Self {
        let nu = red.dirs.len();
        let mut in_y = vec![false; nu];
        let mut symmetric = red.dependent.is_empty();
        for (_, y, _) in &red.dependent {
            in_y[*y] = reorder;
        }
        for &(_, r, _) in &sys.coupled_normal {
            if let Some(y) = red.position[r] {
                in_y[y] = reorder;
                symmetric = false;
            }
        }
        let mut order: Vec<usize> = (0..nu).filter(|&x| !in_y[x]).collect();
        let n_y = nu - order.len();
        order.extend((0..nu).filter(|&x| in_y[x]));
        let mut pos = vec![0; nu];
        for (i, &x) in order.iter().enumerate() {
            pos[x] = i;
        }
        Self {
            order,
            pos,
            n_y,
            symmetric,
        }
    }

    /// Factorises the block in `storage`: bordered when some but not all
    /// unknowns are in Y, Cholesky when nothing is and the block is
    /// symmetric (near singular: `None`), else — or when those fail — the
    /// LU of the whole block.
    fn factorise(
        self,
        w: &Mat<f64>,
        sys: &NewtonSystem,
        red: &NewtonReduction,
        storage: Vec<f64>,
    ) -> Option<BlockFactor> {
        let nu = self.order.len();
        let n1 = match self.n_y {
            0 if self.symmetric => nu,
            0 => 0,
            n_y => nu - n_y,
        };
        let mut buf = block_buffer(storage, nu);
        if n1 > 0 {
            self.fill(w, sys, red, &mut buf, n1);
            match BorderedFactor::new(buf, nu, n1) {
                Ok(factor) => return Some(self.with(factor)),
                Err(FactorFailure::NearSingular(_)) if n1 == nu => return None,
                Err(FactorFailure::NotPositive(b) | FactorFailure::NearSingular(b)) => buf = b,
            }
        }
        self.fill(w, sys, red, &mut buf, 0);
        BorderedFactor::new(buf, nu, 0)
            .ok()
            .map(|factor| self.with(factor))
    }

    fn with(self, factor: BorderedFactor) -> BlockFactor {
        BlockFactor {
            order: self.order,
            factor,
        }
    }

    /// Writes the block into `buf` (column-major, block order); the strictly
    /// upper triangle of its leading `n1` × `n1` block is not written (the
    /// Cholesky reads the lower one). e_xᵀ W e_y from the columns of W on
    /// e_y's rows, read on e_x's rows; the columns shared between the cores.
    fn fill(
        &self,
        w: &Mat<f64>,
        sys: &NewtonSystem,
        red: &NewtonReduction,
        buf: &mut [f64],
        n1: usize,
    ) {
        let nu = self.order.len();
        let pos = &self.pos;
        let rows = BlockRows::new(&red.dirs, &self.order);
        // The dependent directions of each block column.
        let mut dependent: Vec<Vec<(Dir, f64)>> = vec![Vec::new(); nu];
        for (d, y, f) in &red.dependent {
            dependent[pos[*y]].push((*d, *f));
        }
        let work = (nu * nu + red.dependent.len() * (nu + 2 * w.nrows())) as f64;
        signorini_linalg::threads::for_each_chunk(&mut buf[..nu * nu], nu, work, |first, cols| {
            let mut mix = vec![0.0; w.nrows()];
            for (k, out) in cols.chunks_exact_mut(nu).enumerate() {
                let j = first + k;
                let top = if j < n1 { j } else { 0 };
                let (col, scale) = w_direction(w, &red.dirs[self.order[j]], 1.0, &mut mix);
                rows.gather(col, scale, top, out, false);
                for (d, f) in &dependent[j] {
                    let (col, scale) = w_direction(w, d, *f, &mut mix);
                    rows.gather(col, scale, 0, out, true);
                }
            }
        });
        for (x, (_, comp, _)) in sys.coupled.iter().enumerate() {
            buf[pos[x] + pos[x] * nu] += comp;
        }
        for &(x, r, f) in &sys.coupled_normal {
            if let Some(y) = red.position[r] {
                buf[pos[x] + pos[y] * nu] += f;
            }
        }
    }
}

/// W d f as (a column, its scale): a column of W for a direction on one row,
/// else the combination of its two columns in `mix`.
fn w_direction<'a>(w: &'a Mat<f64>, d: &Dir, f: f64, mix: &'a mut [f64]) -> (&'a [f64], f64) {
    let [r0, r1] = d.rows;
    if r0 == r1 {
        return (w.col_as_slice(r0), f * (d.c[0] + d.c[1]));
    }
    let (c0, c1) = (w.col_as_slice(r0), w.col_as_slice(r1));
    let (f0, f1) = (f * d.c[0], f * d.c[1]);
    for ((m, a), b) in mix.iter_mut().zip(c0).zip(c1) {
        *m = f0 * a + f1 * b;
    }
    (mix, 1.0)
}

/// The rows and coefficients of the coupled directions in block order: the
/// first row of every direction, and the second rows of those on two rows
/// (the slipping points' directions along and across their circle).
struct BlockRows {
    r0: Vec<u32>,
    c0: Vec<f64>,
    /// (block row, second row, its coefficient).
    second: Vec<(usize, usize, f64)>,
}

impl BlockRows {
    fn new(dirs: &[Dir], order: &[usize]) -> Self {
        let mut rows = BlockRows {
            r0: Vec::with_capacity(order.len()),
            c0: Vec::with_capacity(order.len()),
            second: Vec::new(),
        };
        for (i, &x) in order.iter().enumerate() {
            let Dir { rows: [r0, r1], c } = dirs[x];
            rows.r0.push(r0 as u32);
            if r0 == r1 {
                rows.c0.push(c[0] + c[1]);
            } else {
                rows.c0.push(c[0]);
                rows.second.push((i, r1, c[1]));
            }
        }
        rows
    }

    /// out[i] (= or +=) scale · e_iᵀ col for the block rows i ≥ `top`.
    fn gather(&self, col: &[f64], scale: f64, top: usize, out: &mut [f64], add: bool) {
        let rows = self.r0[top..].iter().zip(&self.c0[top..]);
        let out = &mut out[top..];
        if add {
            for (o, (&r, &c)) in out.iter_mut().zip(rows) {
                *o += scale * c * col[r as usize];
            }
        } else {
            for (o, (&r, &c)) in out.iter_mut().zip(rows) {
                *o = scale * c * col[r as usize];
            }
        }
        let from = self.second.partition_point(|&(i, _, _)| i < top);
        for &(i, r1, c1) in &self.second[from..] {
            out[i - top] += scale * c1 * col[r1];
        }
    }
}
