//! The nonsmooth Gauss–Seidel method (NSGS) for Coulomb friction, 2D and
//! 3D (Jean 1999; Acary, Cadoux, Lemaréchal & Malick 2011, §3: the
//! method of Siconos' `fc3d_nsgs`).
//!
//! A sweep visits the contact points in turn. Point i, the others' forces
//! held, has the local problem of its own rows (normal n, tangential t):
//!
//! ```text
//!   u_i = W_ii r_i + q̃_i,   q̃_i = q_i + Σ_{j ≠ i} W_ij r_j,
//!   r_i in the Coulomb cone, Coulomb's law between r_i and u_i,
//! ```
//!
//! solved exactly, in the order of the cases of the law:
//! - open: q̃_n ≥ 0, r_i = 0;
//! - stick: W_ii r_i = −q̃_i (u_i = 0) with r_i in the cone;
//! - slip: u_n = 0, r_t on the boundary of the cone, r_t = D(θ) r_n with
//!   D(θ) = (μ1 cos θ, μ2 sin θ) (2D: ±μ), and the slip u_t opposite to
//!   the outer normal ν(θ) = (cos θ / μ1, sin θ / μ2) of the section
//!   (maximum dissipation): with θ given, u_n = 0 is linear in r_n,
//!   r_n = −q̃_n / (W_nn + W_nt D(θ)), and θ is a root of
//!   c(θ) = u_t(θ) × ν(θ) with u_t(θ) · ν(θ) ≤ 0, bracketed near the
//!   previous direction (else on a scan of [0, 2π)) and refined by the
//!   Illinois method. 2D has the two candidates θ = 0, π.
//!
//! Only the diagonal blocks W_ii are solved with: the method needs neither
//! a symmetric W nor one of full rank (the Delassus operators of rigid
//! multibody systems, W = H M⁻¹ Hᵀ with more contact rows than degrees of
//! freedom); a singular W_ii is regularised by 1e-12 of its largest entry.
//! The gaps u = W r + q are kept up to date by the columns of W of the
//! rows that changed, and computed afresh before a convergence is
//! accepted. A sweep ends with the natural-map residual of the law
//! ([`natural_residual`]); the method stops when it meets the tolerance,
//! at the sweep limit, when [`STALLED_AFTER`] sweeps have not halved the
//! best residual, or at the deadline of the options.

use crate::delassus::DelassusProblem;
use crate::law::{natural_residual, FrictionLaw, FrictionLayout};
use crate::norms::max_abs;
use crate::options::{FrictionOptions, StallWatch};
use crate::solution::{ContactSolution, SolverReport, StopReason};
use crate::ContactError;

/// Sweeps without halving the best residual after which NSGS stops as
/// stalled (it converges linearly: where it converges, the residual halves
/// in tens of sweeps).
pub const STALLED_AFTER: usize = 1000;

/// The local problem of one contact point: its block A = W_ii (k + 1
/// rows: normal, then k tangential), the gaps b = q̃_i of zero own force,
/// and its coefficients of friction (semi-axes per unit normal force).
struct LocalProblem {
    a: [[f64; 3]; 3],
    b: [f64; 3],
    k: usize,
    mu: [f64; 2],
}

/// The solution of a (k + 1) square system A x = rhs by Gaussian
/// elimination with partial pivoting; `None` when a pivot is below 1e-13
/// of max |A| (singular).
fn solve_small(a: [[f64; 3]; 3], rhs: [f64; 3], n: usize) -> Option<[f64; 3]> {
    let (mut a, mut x) = (a, rhs);
    let scale = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .fold(0.0f64, |s, (i, j)| s.max(a[i][j].abs()));
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() <= 1e-13 * scale || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        x.swap(c, p);
        let pivot_row = a[c];
        for i in c + 1..n {
            let f = a[i][c] / pivot_row[c];
            for (aij, pj) in a[i][c..n].iter_mut().zip(&pivot_row[c..n]) {
                *aij -= f * pj;
            }
            x[i] -= f * x[c];
        }
    }
    for c in (0..n).rev() {
        let s: f64 = (c + 1..n).map(|j| a[c][j] * x[j]).sum();
        x[c] = (x[c] - s) / a[c][c];
    }
    Some(x)
}

impl LocalProblem {
    /// The gaps A r + b.
    fn gaps(&self, r: [f64; 3]) -> [f64; 3] {
        let mut u = self.b;
        for (i, ui) in u.iter_mut().enumerate().take(self.k + 1) {
            *ui += (0..=self.k).map(|j| self.a[i][j] * r[j]).sum::<f64>();
        }
        u
    }

    /// Whether r_t lies in the section of semi-axes μ r_n (to round-off).
    fn in_cone(&self, r: [f64; 3]) -> bool {
        let phi: f64 = (0..self.k)
            .map(|i| (r[i + 1] / (self.mu[i] * r[0])).powi(2))
            .sum();
        r[0] >= 0.0 && phi <= 1.0 + 1e-12
    }

    /// The force of stick, A r = −b, A regularised when singular.
    fn stick(&self) -> Option<[f64; 3]> {
        let n = self.k + 1;
        let rhs = self.b.map(|v| -v);
        solve_small(self.a, rhs, n).or_else(|| {
            let d = (0..n).fold(0.0f64, |s, i| s.max(self.a[i][i].abs()));
            let mut a = self.a;
            (0..n).for_each(|i| a[i][i] += 1e-12 * d.max(f64::MIN_POSITIVE));
            solve_small(a, rhs, n)
        })
    }

    /// The slip force of direction θ (r_t = D(θ) r_n, u_n = 0), the slip
    /// u_t and the cross product c(θ) = u_t × ν(θ) (2D: u_t ν); `None`
    /// where W_nn + W_nt D(θ) ≤ 0 (no positive r_n).
    fn slip_at(&self, theta: f64) -> Option<([f64; 3], f64, f64)> {
        let (s, c) = theta.sin_cos();
        let d = [self.mu[0] * c, self.mu[1] * s];
        let den = self.a[0][0] + (0..self.k).map(|i| self.a[0][i + 1] * d[i]).sum::<f64>();
        if den <= 0.0 || !den.is_finite() {
            return None;
        }
        let rn = -self.b[0] / den;
        let r = [rn, d[0] * rn, if self.k == 2 { d[1] * rn } else { 0.0 }];
        let u = self.gaps(r);
        let nu = [c / self.mu[0], s / self.mu[1].max(f64::MIN_POSITIVE)];
        if self.k == 1 {
            return Some((r, u[1] * nu[0], 0.0));
        }
        let along = u[1] * nu[0] + u[2] * nu[1];
        Some((r, along, u[1] * nu[1] - u[2] * nu[0]))
    }

    /// The slip force with θ a root of c(θ) in [lo, hi] (c changes sign
    /// there), refined by the Illinois method; `None` if it is not a slip
    /// against ν (u_t · ν > 0 there).
    fn slip_root(
        &self,
        (mut lo, mut hi): (f64, f64),
        (mut clo, mut chi): (f64, f64),
    ) -> Option<[f64; 3]> {
        let mut side = 0i8;
        for _ in 0..100 {
            let mid = (lo * chi - hi * clo) / (chi - clo);
            let mid = if mid > lo && mid < hi {
                mid
            } else {
                0.5 * (lo + hi)
            };
            let (_, _, cm) = self.slip_at(mid)?;
            if cm == 0.0 || hi - lo <= 1e-15 * (1.0 + hi.abs()) {
                lo = mid;
                hi = mid;
                break;
            }
            if (cm > 0.0) == (chi > 0.0) {
                (hi, chi) = (mid, cm);
                if side == 1 {
                    clo *= 0.5;
                }
                side = 1;
            } else {
                (lo, clo) = (mid, cm);
                if side == -1 {
                    chi *= 0.5;
                }
                side = -1;
            }
        }
        let (r, along, _) = self.slip_at(0.5 * (lo + hi))?;
        (along <= 0.0).then_some(r)
    }

    /// The slip force in 3D: a root of c(θ) bracketed within ±0.1 of
    /// `guess`, else in a scan of [0, 2π) by 48 steps (the one nearest
    /// `guess`).
    fn slip_3d(&self, guess: f64) -> Option<[f64; 3]> {
        let bracket = |lo: f64, hi: f64| {
            let (_, _, clo) = self.slip_at(lo)?;
            let (_, _, chi) = self.slip_at(hi)?;
            ((clo <= 0.0) != (chi <= 0.0)).then(|| self.slip_root((lo, hi), (clo, chi)))?
        };
        if let Some(r) = bracket(guess - 0.1, guess + 0.1) {
            return Some(r);
        }
        const STEPS: usize = 48;
        let step = std::f64::consts::TAU / STEPS as f64;
        let mut best: Option<([f64; 3], f64)> = None;
        for s in 0..STEPS {
            let lo = guess + s as f64 * step;
            if let Some(r) = bracket(lo, lo + step) {
                let off = (s as f64 + 0.5) * step;
                let off = off.min(std::f64::consts::TAU - off);
                if best.is_none_or(|(_, o)| off < o) {
                    best = Some((r, off));
                }
            }
        }
        best.map(|(r, _)| r)
    }

    /// The point's force: open, stick or slip (module doc); a point whose
    /// local problem has no exact solution (W_ii far from positive) keeps
    /// the stick force projected on the cone. `previous` gives the
    /// direction of slip to look near first.
    fn solve(&self, previous: [f64; 3]) -> [f64; 3] {
        if self.b[0] >= 0.0 {
            return [0.0; 3];
        }
        let frictionless = self.k == 0 || self.mu[..self.k].iter().all(|&m| m <= 0.0);
        if frictionless {
            let rn = -self.b[0] / self.a[0][0].max(f64::MIN_POSITIVE);
            return [rn.max(0.0), 0.0, 0.0];
        }
        let stick = self.stick();
        if let Some(r) = stick.filter(|&r| self.in_cone(r)) {
            return r;
        }
        let slip = match self.k {
            1 => [0.0, std::f64::consts::PI]
                .into_iter()
                .filter_map(|t| self.slip_at(t).filter(|s| s.1 <= 0.0))
                .map(|s| s.0)
                .next(),
            _ => {
                let towards = match previous[1] != 0.0 || previous[2] != 0.0 {
                    true => previous,
                    false => stick.unwrap_or(self.b.map(|v| -v)),
                };
                self.slip_3d((towards[2] / self.mu[1]).atan2(towards[1] / self.mu[0]))
            }
        };
        slip.unwrap_or_else(|| {
            let mut r = stick.unwrap_or([0.0; 3]);
            r[0] = r[0].max(0.0);
            let norm = (0..self.k)
                .map(|i| (r[i + 1] / self.mu[i]).powi(2))
                .sum::<f64>();
            let shrink = (r[0] / norm.sqrt().max(f64::MIN_POSITIVE)).min(1.0);
            (1..=self.k).for_each(|i| r[i] *= shrink);
            r
        })
    }
}

/// The rows of point p (normal first) and its coefficients of friction;
/// an error for a law NSGS does not solve.
fn point_rows(layout: &FrictionLayout, p: usize) -> Result<(Vec<usize>, [f64; 2]), ContactError> {
    let mut rows = vec![p];
    rows.extend(&layout.tangent_rows[p]);
    let mu = match layout.law[p] {
        FrictionLaw::None => [0.0; 2],
        FrictionLaw::Coulomb { mu } => mu,
        _ => {
            return Err(ContactError::Geometry(
                "nsgs solves Coulomb's law (and frictionless points); Tresca and Norton–Hoff friction are solved by friction = \"newton\" or \"fixed_point\"".into(),
            ))
        }
    };
    Ok((rows, mu))
}

/// Where a run of sweeps stands.
struct Sweeps {
    r: Vec<f64>,
    u: Vec<f64>,
    residual: f64,
}

impl Sweeps {
    /// One sweep over the points: each point's local problem solved, the
    /// gaps updated by the columns of its rows.
    fn sweep(&mut self, problem: &DelassusProblem, points: &[(Vec<usize>, [f64; 2])]) {
        let w = &problem.w;
        for (rows, mu) in points {
            let k = rows.len() - 1;
            let mut local = LocalProblem {
                a: [[0.0; 3]; 3],
                b: [0.0; 3],
                k,
                mu: *mu,
            };
            let mut old = [0.0; 3];
            for (i, &ri) in rows.iter().enumerate() {
                old[i] = self.r[ri];
                for (j, &rj) in rows.iter().enumerate() {
                    local.a[i][j] = w[(ri, rj)];
                }
            }
            for (i, &ri) in rows.iter().enumerate() {
                let own: f64 = (0..=k).map(|j| local.a[i][j] * old[j]).sum();
                local.b[i] = self.u[ri] - own;
            }
            let new = local.solve(old);
            for (i, &ri) in rows.iter().enumerate() {
                let delta = new[i] - old[i];
                if delta != 0.0 {
                    self.r[ri] = new[i];
                    let col = w.col_as_slice(ri);
                    self.u
                        .iter_mut()
                        .zip(col)
                        .for_each(|(u, c)| *u += c * delta);
                }
            }
        }
    }

    fn measure(&mut self, layout: &FrictionLayout, opts: &FrictionOptions) -> f64 {
        let force = opts
            .force_scale
            .max(max_abs(&self.r))
            .max(f64::MIN_POSITIVE);
        self.residual = natural_residual(layout, &self.r, &self.u, force, opts.gap_scale);
        self.residual
    }
}

/// Coulomb friction (2D or 3D, `dim`) by NSGS from the forces `start` (or
/// zero); see the module doc for the method and its stops. Refused: bodies
/// held by contact alone (the equilibrium Gᵀλ = e is not a local problem)
/// and laws other than Coulomb's.
pub fn nsgs(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
    dim: usize,
) -> Result<ContactSolution, ContactError> {
    let n = problem.q.len();
    layout.validate(n, dim)?;
    if problem.g_mat.ncols() > 0 {
        return Err(ContactError::Geometry(
            "nsgs does not solve bodies held by contact alone (their equilibrium couples all the points); friction = \"newton\" or \"fixed_point\" does".into(),
        ));
    }
    let points = (0..layout.n_points())
        .map(|p| point_rows(layout, p))
        .collect::<Result<Vec<_>, _>>()?;
    let r = match start {
        Some(s) if s.len() == n => s.to_vec(),
        _ => vec![0.0; n],
    };
    let u = signorini_linalg::products::affine(&problem.w, &r, &problem.q);
    let mut at = Sweeps {
        r,
        u,
        residual: f64::INFINITY,
    };
    let mut history = Vec::new();
    let mut watch = StallWatch::new(0.5, STALLED_AFTER, opts.deadline);
    let mut stop = StopReason::NsgsLimit {
        limit: opts.max_iterations,
    };
    let mut sweeps = 0;
    while sweeps < opts.max_iterations {
        sweeps += 1;
        at.sweep(problem, &points);
        let mut residual = at.measure(layout, opts);
        if residual <= opts.tolerance {
            at.u = signorini_linalg::products::affine(&problem.w, &at.r, &problem.q);
            residual = at.measure(layout, opts);
        }
        history.push(residual);
        if residual <= opts.tolerance {
            stop = StopReason::NsgsConverged { residual, sweeps };
            break;
        }
        if residual.is_nan() {
            stop = StopReason::NonFinite { iteration: sweeps };
            break;
        }
        if let Some(stall) = watch.stalled(residual, sweeps) {
            stop = StopReason::nsgs_stalled(stall);
            break;
        }
        if watch.time_up() {
            stop = StopReason::TimeLimit {
                iterations: sweeps,
                residual,
            };
            break;
        }
    }
    problem.solves += sweeps;
    let Sweeps { r, u, .. } = at;
    let converged = matches!(stop, StopReason::NsgsConverged { .. });
    let report = SolverReport {
        method: match dim {
            2 => "coulomb_nsgs",
            _ => "coulomb_3d_nsgs",
        }
        .into(),
        converged,
        iterations: sweeps,
        operator_applications: sweeps,
        residual_history: history,
        stop,
    };
    let statuses = crate::friction::semismooth_newton::statuses(layout, &r, &u, opts, dim);
    let mut sol = ContactSolution::with_gaps(r, u, Vec::new(), report);
    sol.set_points(statuses);
    Ok(sol)
}

#[cfg(test)]
mod tests;
