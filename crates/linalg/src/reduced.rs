//! The linear system of one status iteration (course notes §3.3 for contact, §4.5
//! for friction), reduced to the forces its statuses leave unknown (the
//! contact crate reduces a semi-smooth Newton step the same way, on
//! [`BlockFactor`] and [`schur_on_g`]).
//!
//! Each force r_i has one equation ([`VarEquation`]): a zero gap (closed or
//! stuck), a given value (open: 0; Tresca slip: ±g), or a multiple of
//! another force (Coulomb slip: λ_t = s μ λ_n). Only the first kind is an
//! unknown: with U the rows of zero gap, the given rows r_F = c and the
//! slipping rows r_i = f_i r_{o(i)} substituted, r = P r_U + r_F with
//! P = I on U plus f_i at (i, o(i)), and the system is
//!
//! ```text
//!   W_U· P r_U + G_U α = −q_U − W_U· r_F        (zero gaps)
//!   Gᵀ P r_U           = e − Gᵀ r_F              (floating bodies)
//! ```
//!
//! Without slipping rows W_U· P = W_UU is symmetric positive definite and
//! is factorised by Cholesky; with them by a partially pivoted LU. Floating
//! bodies (k ≤ 6 rigid modes each) go through the small Schur complement
//! Ĝᵀ A⁻¹ G_U (k × k). When a factorisation fails or its pivots say the
//! block is near singular (redundant constraints, a body the statuses do not
//! hold), the caller falls back to the rank-tested full solve, which keeps
//! its message and exit code.

use faer::prelude::Solve;
use faer::{Mat, Side};

use crate::bordered_factor::BorderedFactor;
use crate::pivot_policy::{cholesky_pivots_are_safe, pivots_are_safe};

/// The equation that determines one contact force in a status system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VarEquation {
    /// Its gap (normal) or slip increment (tangential) is zero: contact, stick.
    Gap,
    /// It has a given value: 0 when open, ±g when slipping under Tresca.
    Value(f64),
    /// It is `factor` times force `of`: ±μ λ_n when slipping under Coulomb.
    Ratio { of: usize, factor: f64 },
}

/// How the reduced block was factorised.
pub enum Factor {
    Llt(faer::linalg::solvers::Llt<f64>),
    Lu(faer::linalg::solvers::PartialPivLu<f64>),
    Block(Box<BlockFactor>),
}

impl Factor {
    pub fn solve(&self, rhs: &Mat<f64>) -> Mat<f64> {
        match self {
            Factor::Llt(f) => f.solve(rhs),
            Factor::Lu(f) => f.solve(rhs),
            Factor::Block(f) => f.solve(rhs),
        }
    }
}

/// The reduced block of a status vector with slipping points, by blocks:
/// the unknowns whose columns no slipping row touches (1) span a principal
/// block A₁₁ of W, symmetric positive definite (Cholesky); the others (2,
/// the normal rows of the slipping points, whose columns carry f W_·t) go
/// through the Schur complement S = A₂₂ − A₂₁ A₁₁⁻¹ A₁₂ (partially pivoted
/// LU). ⅓ n₁³ + 2 n₁² n₂ + 2 n₁ n₂² + ⅔ n₂³ flops against ⅔ n³ for the LU
/// of the whole block. The unknowns are reordered, 1 first ([`BorderedFactor`]
/// factorises the block in that order); `order` holds the unknown at each
/// block position.
pub struct BlockFactor {
    pub order: Vec<usize>,
    pub factor: BorderedFactor,
}

impl BlockFactor {
    /// `None` when A₁₁ is not positive definite or a pivot (L_ii² of A₁₁,
    /// U_ii of S) is not safe.
    fn new(a: &Mat<f64>, modified: &[bool]) -> Option<Self> {
        let n = a.nrows();
        let mut order: Vec<usize> = (0..n).filter(|&i| !modified[i]).collect();
        let n1 = order.len();
        order.extend((0..n).filter(|&i| modified[i]));
        let mut buf = vec![0.0; n * n];
        for (j, &c) in order.iter().enumerate() {
            for (i, &r) in order.iter().enumerate() {
                buf[i + j * n] = a[(r, c)];
            }
        }
        let factor = BorderedFactor::new(buf, n, n1).ok()?;
        Some(Self { order, factor })
    }

    /// A⁻¹ rhs: the rows of rhs in block order, solved, and put back.
    pub fn solve(&self, rhs: &Mat<f64>) -> Mat<f64> {
        let order = &self.order;
        let mut b = Mat::<f64>::from_fn(order.len(), rhs.ncols(), |i, j| rhs[(order[i], j)]);
        self.factor.solve_in_place(b.as_mut());
        let mut x = Mat::<f64>::zeros(b.nrows(), b.ncols());
        for (i, &u) in order.iter().enumerate() {
            for j in 0..b.ncols() {
                x[(u, j)] = b[(i, j)];
            }
        }
        x
    }

    /// The storage of the factor, for the next block.
    pub fn into_buffer(self) -> Vec<f64> {
        self.factor.into_buffer()
    }
}

/// Factorises the reduced block of `red`: by blocks
/// ([`BlockFactor`]) when its slipping rows touch few columns, else as
/// [`factorise`] does.
pub fn factorise_reduced(a: &Mat<f64>, red: &Reduction) -> Option<Factor> {
    let n = a.nrows();
    let mut modified = vec![false; n];
    for &(_, col, _) in &red.dependent {
        modified[col] = true;
    }
    let n2 = modified.iter().filter(|m| **m).count() as f64;
    let n1 = n as f64 - n2;
    let block = n1.powi(3) / 3.0 + 2.0 * n1 * n1 * n2 + 2.0 * n1 * n2 * n2 + 2.0 * n2.powi(3) / 3.0;
    if n2 > 0.0 && block < 0.85 * 2.0 * (n as f64).powi(3) / 3.0 {
        if let Some(b) = BlockFactor::new(a, &modified) {
            return Some(Factor::Block(Box::new(b)));
        }
    }
    factorise(a, red.dependent.is_empty())
}

/// Factorises the reduced block: Cholesky when symmetric, LU otherwise;
/// `None` when it fails or is near singular.
pub fn factorise(a: &Mat<f64>, symmetric: bool) -> Option<Factor> {
    let n = a.nrows();
    if symmetric {
        if let Ok(llt) = a.llt(Side::Lower) {
            let l = llt.L();
            let a_diag = (0..n).map(|i| a[(i, i)]);
            return cholesky_pivots_are_safe((0..n).map(|i| l[(i, i)]), a_diag, n)
                .then_some(Factor::Llt(llt));
        }
    }
    let lu = a.partial_piv_lu();
    let u = lu.U();
    pivots_are_safe((0..n).map(|i| u[(i, i)]), n).then_some(Factor::Lu(lu))
}

/// The unknowns and the substitution of the other rows.
pub struct Reduction {
    /// Rows with a zero gap (the unknowns), in order.
    pub unknown: Vec<usize>,
    /// Rows r_i = f r_{unknown}: (i, its unknown's position, f).
    pub dependent: Vec<(usize, usize, f64)>,
    /// Given forces (zero on the unknown and dependent rows).
    pub given: Vec<f64>,
}

pub fn reduce(eqs: &[VarEquation]) -> Option<Reduction> {
    let n = eqs.len();
    let unknown: Vec<usize> = (0..n)
        .filter(|&i| matches!(eqs[i], VarEquation::Gap))
        .collect();
    let mut position = vec![None; n];
    for (a, &i) in unknown.iter().enumerate() {
        position[i] = Some(a);
    }
    let mut dependent = Vec::new();
    let mut given = vec![0.0; n];
    for (i, eq) in eqs.iter().enumerate() {
        match *eq {
            VarEquation::Gap => {}
            VarEquation::Value(c) => given[i] = c,
            VarEquation::Ratio { of, factor } => match eqs.get(of)? {
                VarEquation::Gap => dependent.push((i, position[of]?, factor)),
                VarEquation::Value(c) => given[i] = factor * c,
                // A ratio of a ratio: not a status the methods produce.
                VarEquation::Ratio { .. } => return None,
            },
        }
    }
    Some(Reduction {
        unknown,
        dependent,
        given,
    })
}

/// The reduced block A = W_U· P: W on the unknowns, plus f times W's
/// column of each dependent row in its unknown's column.
pub fn reduced_block(w: &Mat<f64>, red: &Reduction) -> Mat<f64> {
    let nu = red.unknown.len();
    let mut a = Mat::<f64>::from_fn(nu, nu, |x, y| w[(red.unknown[x], red.unknown[y])]);
    for &(i, col, f) in &red.dependent {
        for (x, &u) in red.unknown.iter().enumerate() {
            a[(x, col)] += f * w[(u, i)];
        }
    }
    a
}

/// Solves the status system reduced to its unknowns; `None` when the fast
/// path cannot decide (a failed or near-singular factorisation, an unusual
/// equation), for the caller's rank-tested full solve. Returns (r, α).
pub fn solve_reduced(
    w: &Mat<f64>,
    q: &[f64],
    g: &Mat<f64>,
    e: &[f64],
    eqs: &[VarEquation],
) -> Option<(Vec<f64>, Vec<f64>)> {
    let red = reduce(eqs)?;
    let (nu, k) = (red.unknown.len(), g.ncols());
    let given: Vec<(usize, f64)> = (0..eqs.len())
        .filter(|&i| red.given[i] != 0.0)
        .map(|i| (i, red.given[i]))
        .collect();
    let a = reduced_block(w, &red);
    let rhs = Mat::<f64>::from_fn(nu, 1, |x, _| {
        let u = red.unknown[x];
        -q[u] - given.iter().map(|&(i, c)| w[(u, i)] * c).sum::<f64>()
    });
    let factor = factorise_reduced(&a, &red)?;
    let y = factor.solve(&rhs);
    let (r_u, alpha) = if k == 0 {
        (y, Vec::new())
    } else {
        floating_bodies(&red, g, e, &given, &factor, y)?
    };
    let mut r = red.given.clone();
    for (x, &u) in red.unknown.iter().enumerate() {
        r[u] = r_u[(x, 0)];
    }
    for &(i, col, f) in &red.dependent {
        r[i] = f * r_u[(col, 0)];
    }
    r.iter().all(|v| v.is_finite()).then_some((r, alpha))
}

/// The equilibrium of the floating bodies through the Schur complement on
/// G: with X = A⁻¹ G_U and y = A⁻¹ rhs, (Ĝᵀ X) α = Ĝᵀ y − (e − Gᵀ r_F) and
/// r_U = y − X α, Ĝ = Pᵀ G. Returns (r_U, α).
fn floating_bodies(
    red: &Reduction,
    g: &Mat<f64>,
    e: &[f64],
    given: &[(usize, f64)],
    factor: &Factor,
    y: Mat<f64>,
) -> Option<(Mat<f64>, Vec<f64>)> {
    let (nu, k) = (red.unknown.len(), g.ncols());
    let g_u = Mat::<f64>::from_fn(nu, k, |x, j| g[(red.unknown[x], j)]);
    let mut g_hat = g_u.clone();
    for &(i, col, f) in &red.dependent {
        for j in 0..k {
            g_hat[(col, j)] += f * g[(i, j)];
        }
    }
    let e_j: Vec<f64> = (0..k)
        .map(|j| e[j] - given.iter().map(|&(i, c)| g[(i, j)] * c).sum::<f64>())
        .collect();
    schur_on_g(&|b| factor.solve(b), &g_u, &g_hat, y, &e_j)
}

/// Solves [A G_U; Ĝᵀ 0] (r_U, α) = (A y, e_j) given A's factor and y:
/// with X = A⁻¹ G_U, (Ĝᵀ X) α = Ĝᵀ y − e_j and r_U = y − X α (the k × k
/// Schur complement, by a fully pivoted LU; `None` when near singular).
pub fn schur_on_g(
    solve: &dyn Fn(&Mat<f64>) -> Mat<f64>,
    g_u: &Mat<f64>,
    g_hat: &Mat<f64>,
    y: Mat<f64>,
    e_j: &[f64],
) -> Option<(Mat<f64>, Vec<f64>)> {
    let k = g_u.ncols();
    let x = solve(g_u);
    let schur = g_hat.transpose() * &x;
    let gy = g_hat.transpose() * &y;
    let rhs = Mat::<f64>::from_fn(k, 1, |j, _| gy[(j, 0)] - e_j[j]);
    let lu = schur.full_piv_lu();
    let u = lu.U();
    if !pivots_are_safe((0..k).map(|i| u[(i, i)]), k) {
        return None;
    }
    let alpha = lu.solve(&rhs);
    let r_u = &y - &x * &alpha;
    Some((r_u, (0..k).map(|j| alpha[(j, 0)]).collect()))
}
