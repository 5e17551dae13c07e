//! Friction in 3D on the condensed problem (seed §4.1.1, §4.1.2, §4.3): each
//! frictional contact point has a normal force λ_n and a tangential force
//! λ_t = (λ_t1, λ_t2) in its tangent plane; the "gaps" of the two tangential
//! rows are the components (Δs1, Δs2) of the slip increment of the slave
//! relative to the master since the previous load step.
//!
//! Layout of the rows (forces and gaps, [`FrictionLayout`], shared with
//! 2D): rows 0..m are the normal rows of the m contact points (gap
//! g = g0 + B u ≥ 0, λ_n ≥ 0 compressive, λ_n g = 0); each frictional point p
//! has two further rows `tangent_rows[p] = [t1, t2]` (any rows ≥ m, each used
//! once), or one, `[t1]`, where a support prescribes the slip along the other
//! tangent (a node on a symmetry plane: the tangential force along t2 is then
//! a support reaction, not a friction unknown, and the admissible set is the
//! segment |λ_t1| ≤ g1). Sign convention: the tangential force opposes the
//! slip.
//!
//! Laws ([`crate::friction::FrictionLaw`]; threshold g for Tresca, μ λ_n for Coulomb; anisotropic Coulomb with
//! the elliptic section (λ_t1/μ1)² + (λ_t2/μ2)² ≤ λ_n², i.e. the semi-axes
//! g_i = μ_i λ_n):
//! - stick: λ_t inside the disc / ellipse and Δs = 0;
//! - slip: λ_t on its boundary and Δs = −γ ∇φ(λ_t), γ ≥ 0, with
//!   φ(λ_t) = (λ_t1/g1)² + (λ_t2/g2)² (maximum dissipation; isotropic:
//!   λ_t = −g Δs/‖Δs‖).
//!
//! With the thresholds fixed this is the convex program
//! min ½ rᵀ W r + qᵀ r over λ_n ≥ 0, λ_t in the disc / ellipse (plus the
//! equilibrium Gᵀ r = e of floating bodies). It is solved by a semi-smooth
//! Newton method on the Alart–Curnier projection equations (unknowns: the
//! forces and the rigid-mode amplitudes α), with an Armijo line search on
//! ½‖F‖² and, without floating bodies, an accelerated projected-gradient
//! fallback. Coulomb is the fixed point on the thresholds g ← μ λ_n (§4.3).
//!
//! As with the 2D projection method ([`crate::friction::tresca_projection`]),
//! a Tresca point that opens may still carry a tangential force up to its
//! threshold (Tresca's law does not depend on the normal force); with
//! Coulomb the threshold of an open point is zero.

use faer::prelude::Solve;
use faer::Mat;

use crate::delassus::{DelassusProblem, VarEquation};
use crate::fixed_point::{fixed_point, normal_change, InnerSolve, ThresholdMap, TrescaSolver};
use crate::friction::{FrictionLayout, FrictionOptions, FrictionOutcome, PointStatus};
use crate::ContactError;

/// Projection of x on the ellipse (x1/a1)² + (x2/a2)² ≤ 1 (Euclidean; a
/// semi-axis may be zero, both infinite means no bound).
fn project_ellipse(x: [f64; 2], a: [f64; 2]) -> [f64; 2] {
    if a[0].is_infinite() || a[1].is_infinite() {
        return x;
    }
    match (a[0] > 0.0, a[1] > 0.0) {
        (false, false) => return [0.0, 0.0],
        (false, true) => return [0.0, x[1].clamp(-a[1], a[1])],
        (true, false) => return [x[0].clamp(-a[0], a[0]), 0.0],
        _ => {}
    }
    if (x[0] / a[0]).powi(2) + (x[1] / a[1]).powi(2) <= 1.0 {
        return x;
    }
    // f(t) = Σ (a_i x_i / (a_i² + t))² − 1, decreasing and convex on t ≥ 0:
    // Newton from t = 0 converges monotonically to its root.
    let mut t = 0.0f64;
    for _ in 0..200 {
        let mut f = -1.0;
        let mut df = 0.0;
        for i in 0..2 {
            let d = a[i] * a[i] + t;
            let v = a[i] * x[i] / d;
            f += v * v;
            df -= 2.0 * v * v / d;
        }
        let step = -f / df;
        if !step.is_finite() || step <= 1e-16 * t.max(f64::MIN_POSITIVE) {
            break;
        }
        t += step;
    }
    [
        a[0] * a[0] * x[0] / (a[0] * a[0] + t),
        a[1] * a[1] * x[1] / (a[1] * a[1] + t),
    ]
}

/// The Tresca problem with fixed semi-axes: its rows, thresholds and scales.
struct Inner<'a> {
    problem: &'a DelassusProblem,
    layout: &'a FrictionLayout,
    /// Semi-axes (g1, g2) per point; infinite: no bound (stuck).
    thr: &'a [[f64; 2]],
    /// Newton's projection parameters per row (1 / diagonal of W).
    rho: Vec<f64>,
}

/// How a residual is scaled: `Newton` with ρ = 1/W_ii, `Check` with ρ = F/L
/// (the natural residual relative to the force and length scales).
#[derive(Clone, Copy, PartialEq)]
enum Scale {
    Newton,
    Check(f64),
}

impl<'a> Inner<'a> {
    fn new(problem: &'a DelassusProblem, layout: &'a FrictionLayout, thr: &'a [[f64; 2]]) -> Self {
        let n = problem.q.len();
        let rho = (0..n)
            .map(|i| {
                let d = problem.w[(i, i)];
                if d > 0.0 && d.is_finite() {
                    1.0 / d
                } else {
                    1.0
                }
            })
            .collect();
        Self {
            problem,
            layout,
            thr,
            rho,
        }
    }

    fn n(&self) -> usize {
        self.problem.q.len()
    }

    fn k(&self) -> usize {
        self.problem.g_mat.ncols()
    }

    /// y = W λ + q + G α.
    fn gaps(&self, x: &[f64]) -> Vec<f64> {
        let (n, k) = (self.n(), self.k());
        let mut y = crate::lcp::gaps(&self.problem.w, &self.problem.q, &x[..n]);
        for j in 0..k {
            let a = x[n + j];
            for (i, yi) in y.iter_mut().enumerate() {
                *yi += self.problem.g_mat[(i, j)] * a;
            }
        }
        y
    }

    /// Adds c times row i of [W G] to row `row` of the Jacobian.
    fn add_wg(&self, j: &mut Mat<f64>, row: usize, i: usize, c: f64) {
        let (n, k) = (self.n(), self.k());
        for col in 0..n {
            j[(row, col)] += c * self.problem.w[(i, col)];
        }
        for col in 0..k {
            j[(row, n + col)] += c * self.problem.g_mat[(i, col)];
        }
    }

    /// The Alart–Curnier residual F(x) and, if asked, its generalised
    /// Jacobian (rows: the n forces, then the k equilibrium equations).
    fn residual(&self, x: &[f64], scale: Scale, jac: Option<&mut Mat<f64>>) -> Vec<f64> {
        let (n, k) = (self.n(), self.k());
        let m = self.layout.n_points();
        let gm = &self.problem.g_mat;
        let y = self.gaps(x);
        let mut f = vec![0.0; n + k];
        let mut jac = jac;
        if let Some(j) = jac.as_deref_mut() {
            j.fill(0.0);
        }
        let add_wg = |j: &mut Mat<f64>, row: usize, i: usize, c: f64| self.add_wg(j, row, i, c);
        for p in 0..m {
            // Normal row.
            let rn = match scale {
                Scale::Newton => self.rho[p],
                Scale::Check(c) => c,
            };
            if x[p] - rn * y[p] > 0.0 {
                f[p] = rn * y[p];
                if let Some(j) = jac.as_deref_mut() {
                    add_wg(j, p, p, rn);
                }
            } else {
                f[p] = x[p];
                if let Some(j) = jac.as_deref_mut() {
                    j[(p, p)] = 1.0;
                }
            }
            let rows = &self.layout.tangent_rows[p];
            if rows.is_empty() {
                continue;
            }
            self.tangential_residual(x, &y, rows, self.thr[p], scale, &mut f, jac.as_deref_mut());
        }
        // Equilibrium of the rigid modes: Gᵀ λ = e.
        for jj in 0..k {
            let mut s = -self.problem.e[jj];
            for i in 0..n {
                s += gm[(i, jj)] * x[i];
            }
            f[n + jj] = s;
            if let Some(j) = jac.as_deref_mut() {
                for i in 0..n {
                    j[(n + jj, i)] = gm[(i, jj)];
                }
            }
        }
        f
    }

    /// The Alart–Curnier rows of one point's tangential force λ_t (one or
    /// two rows) with semi-axes `g`: stuck (Δs = 0) for an infinite bound,
    /// zero for a zero bound, else, scaled to the unit disc,
    /// ν = D⁺ λ_t, z = ν − c D Δs, F = λ_t − D proj(z) (seed §4.1.2).
    #[allow(clippy::too_many_arguments)]
    fn tangential_residual(
        &self,
        x: &[f64],
        y: &[f64],
        rows: &[usize],
        g: [f64; 2],
        scale: Scale,
        f: &mut [f64],
        mut jac: Option<&mut Mat<f64>>,
    ) {
        let add_wg = |j: &mut Mat<f64>, row: usize, i: usize, c: f64| self.add_wg(j, row, i, c);
        let rt = match scale {
            Scale::Newton => rows.iter().map(|&r| self.rho[r]).sum::<f64>() / rows.len() as f64,
            Scale::Check(c) => c,
        };
        let gbar = g[..rows.len()].iter().fold(0.0f64, |a, &v| a.max(v));
        if gbar.is_infinite() || gbar <= 0.0 {
            for &r in rows {
                if gbar.is_infinite() {
                    // No bound: stuck, Δs = 0.
                    f[r] = rt * y[r];
                    if let Some(j) = jac.as_deref_mut() {
                        add_wg(j, r, r, rt);
                    }
                } else {
                    f[r] = x[r];
                    if let Some(j) = jac.as_deref_mut() {
                        j[(r, r)] = 1.0;
                    }
                }
            }
            return;
        }
        let c = rt / (gbar * gbar);
        let dinv = g.map(|gi| if gi > 0.0 { 1.0 / gi } else { 0.0 });
        let mut z = [0.0; 2];
        for (i, &r) in rows.iter().enumerate() {
            z[i] = dinv[i] * x[r] - c * g[i] * y[r];
        }
        let nz = z[0].hypot(z[1]);
        let (pz, dp) = if nz <= 1.0 {
            (z, [[1.0, 0.0], [0.0, 1.0]])
        } else {
            let u = [z[0] / nz, z[1] / nz];
            (
                u,
                [
                    [(1.0 - u[0] * u[0]) / nz, -u[0] * u[1] / nz],
                    [-u[1] * u[0] / nz, (1.0 - u[1] * u[1]) / nz],
                ],
            )
        };
        for (i, &r) in rows.iter().enumerate() {
            f[r] = x[r] - g[i] * pz[i];
        }
        if let Some(j) = jac {
            // dF_i = dλ_i − g_i Σ_l dp[i][l] (dinv_l dλ_l − c g_l d(Δs_l)).
            for (i, &row) in rows.iter().enumerate() {
                j[(row, row)] += 1.0;
                for (l, &col) in rows.iter().enumerate() {
                    let coef = g[i] * dp[i][l];
                    if coef == 0.0 {
                        continue;
                    }
                    j[(row, col)] -= coef * dinv[l];
                    add_wg(j, row, col, coef * c * g[l]);
                }
            }
        }
    }

    /// One semi-smooth Newton step from x with an Armijo line search on
    /// ½‖F‖² (halving the step at most 30 times).
    fn newton_step(&self, x: &mut Vec<f64>, jac: &mut Mat<f64>) -> Step {
        let nk = self.n() + self.k();
        let merit = |f: &[f64]| 0.5 * f.iter().map(|v| v * v).sum::<f64>();
        let f = self.residual(x, Scale::Newton, Some(jac));
        let psi = merit(&f);
        let rhs = Mat::<f64>::from_fn(nk, 1, |i, _| -f[i]);
        let dx = jac.full_piv_lu().solve(&rhs);
        if !(0..nk).all(|i| dx[(i, 0)].is_finite()) {
            return Step::Singular;
        }
        let mut t = 1.0;
        for _ in 0..30 {
            let trial: Vec<f64> = (0..nk).map(|i| x[i] + t * dx[(i, 0)]).collect();
            let ft = self.residual(&trial, Scale::Newton, None);
            if merit(&ft) <= (1.0 - 1e-4 * t) * psi {
                *x = trial;
                return Step::Accepted;
            }
            t *= 0.5;
        }
        Step::Rejected(dx)
    }

    /// The scaled natural residual: max over the rows of |F_check| / F.
    fn check(&self, x: &[f64], opts: &FrictionOptions) -> f64 {
        let n = self.n();
        let fs = opts
            .force_scale
            .max(x[..n].iter().fold(0.0f64, |a, v| a.max(v.abs())))
            .max(f64::MIN_POSITIVE);
        let c = fs / opts.gap_scale.max(f64::MIN_POSITIVE);
        let f = self.residual(x, Scale::Check(c), None);
        f.iter().fold(0.0f64, |a, v| a.max(v.abs())) / fs
    }

    /// Accelerated projected gradient (FISTA with adaptive restart) on
    /// ½ λᵀ W λ + qᵀ λ over the product of half-lines and ellipses; no
    /// floating body.
    fn projected_gradient(&self, x: &mut [f64], iterations: usize) {
        let n = self.n();
        let m = self.layout.n_points();
        let w = &self.problem.w;
        // Gershgorin bound on the largest eigenvalue of W.
        let lip = (0..n)
            .map(|i| (0..n).map(|j| w[(i, j)].abs()).sum::<f64>())
            .fold(0.0f64, f64::max)
            .max(f64::MIN_POSITIVE);
        let project = |v: &mut [f64]| {
            for p in 0..m {
                v[p] = v[p].max(0.0);
                match self.layout.tangent_rows[p][..] {
                    [a, b] => {
                        let r = project_ellipse([v[a], v[b]], self.thr[p]);
                        v[a] = r[0];
                        v[b] = r[1];
                    }
                    [a] if self.thr[p][0].is_finite() => {
                        v[a] = v[a].clamp(-self.thr[p][0], self.thr[p][0]);
                    }
                    _ => {}
                }
            }
        };
        project(x);
        let mut prev = x.to_vec();
        let mut ypt = x.to_vec();
        let mut t = 1.0f64;
        for _ in 0..iterations {
            let grad = self.gaps(&ypt);
            let mut next: Vec<f64> = (0..n).map(|i| ypt[i] - grad[i] / lip).collect();
            project(&mut next);
            // Restart when the momentum points uphill.
            let uphill: f64 = (0..n).map(|i| grad[i] * (next[i] - prev[i])).sum();
            let t_next = if uphill > 0.0 {
                1.0
            } else {
                0.5 * (1.0 + (1.0 + 4.0 * t * t).sqrt())
            };
            let beta = if uphill > 0.0 {
                0.0
            } else {
                (t - 1.0) / t_next
            };
            for i in 0..n {
                ypt[i] = next[i] + beta * (next[i] - prev[i]);
            }
            prev = next;
            t = t_next;
        }
        x[..n].copy_from_slice(&prev);
    }
}

/// What a Newton step did.
enum Step {
    /// A step length decreased the merit: x moved.
    Accepted,
    /// No step length did; the Newton direction.
    Rejected(Mat<f64>),
    /// The Newton system is singular (a non-finite direction).
    Singular,
}

/// Semi-smooth Newton on the Alart–Curnier equations with fixed semi-axes
/// `thr`, from the forces `start`.
fn solve_inner(
    problem: &DelassusProblem,
    layout: &FrictionLayout,
    thr: &[[f64; 2]],
    start: &[f64],
    opts: &FrictionOptions,
) -> Result<(InnerSolve, usize), ContactError> {
    let inner = Inner::new(problem, layout, thr);
    let (n, k) = (inner.n(), inner.k());
    let mut x = vec![0.0; n + k];
    x[..n].copy_from_slice(start);
    // The rigid-mode amplitudes start from the problem's last solve.
    if problem.alpha().len() == k {
        x[n..].copy_from_slice(problem.alpha());
    }
    let mut jac = Mat::<f64>::zeros(n + k, n + k);
    let mut fallbacks = 0usize;
    let mut iterations = 0;
    let mut reason = format!("iteration limit {} reached", opts.max_iterations);
    let mut converged = false;
    for it in 0..opts.max_iterations {
        let res = inner.check(&x, opts);
        if res <= opts.tolerance {
            converged = true;
            reason = format!("natural residual {res:.2e} after {it} Newton iterations");
            break;
        }
        iterations = it + 1;
        let dx = match inner.newton_step(&mut x, &mut jac) {
            Step::Accepted => continue,
            Step::Rejected(dx) => Some(dx),
            Step::Singular => None,
        };
        fallbacks += 1;
        match dx {
            // Globalisation: accelerated projected gradient, then Newton again.
            _ if k == 0 => inner.projected_gradient(&mut x, 200 * fallbacks),
            // Floating bodies: no projection on the equilibrium; take the
            // full (non-monotone) Newton step.
            Some(dx) if fallbacks <= 5 => {
                for i in 0..n + k {
                    x[i] += dx[(i, 0)];
                }
            }
            Some(_) => {
                reason =
                    "the Newton line search failed repeatedly (floating bodies: no fallback)".into();
                break;
            }
            None => {
                return Err(ContactError::Singular(
                    "friction 3D: singular Newton system (a floating body not held by the contact and friction forces?)".into(),
                ))
            }
        }
    }
    if !converged {
        let res = inner.check(&x, opts);
        if res <= opts.tolerance {
            converged = true;
            reason = format!("natural residual {res:.2e} after {iterations} Newton iterations");
        }
    }
    let gaps = inner.gaps(&x);
    x.truncate(n);
    let solve = InnerSolve {
        statuses: statuses(layout, &x, &gaps, opts),
        forces: x,
        gaps,
        converged,
        reason,
    };
    Ok((solve, iterations))
}

/// Statuses: open (λ_n ≤ tol), slip (‖Δs‖ > tol, the force on the boundary
/// of the disc / ellipse), stick otherwise (in contact, and sticking if the
/// point has friction).
fn statuses(
    layout: &FrictionLayout,
    r: &[f64],
    g: &[f64],
    opts: &FrictionOptions,
) -> Vec<PointStatus> {
    let lmax = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let tol_f = opts.tolerance * opts.force_scale.max(lmax);
    let tol_g = opts.tolerance * opts.gap_scale;
    (0..layout.n_points())
        .map(|p| {
            if r[p] <= tol_f {
                PointStatus::Open
            } else {
                let slip = layout.tangent_rows[p]
                    .iter()
                    .map(|&t| g[t] * g[t])
                    .sum::<f64>();
                if slip.sqrt() > tol_g {
                    PointStatus::Slip
                } else {
                    PointStatus::Stick
                }
            }
        })
        .collect()
}

/// Friction in 3D: Tresca (and frictionless) points in one convex solve,
/// Coulomb by the fixed point on the thresholds g ← μ λ_n (seed §4.3),
/// started from `start` (the previous step's forces, all rows) or from the
/// solution with every frictional point stuck (so that a body held by
/// friction alone can start). The fixed point stops when
/// max |Δλ_n| / max(force_scale, ‖λ‖∞) ≤ tolerance; each inner problem stops
/// on its scaled natural residual. `iterations` counts the Newton iterations
/// of all inner solves.
///
/// With floating bodies, the rigid-mode amplitudes α used by
/// [`DelassusProblem::displacement`] are those of a final linear solve with
/// the statuses found (closed normal rows and stuck tangential rows: zero
/// gap; other rows: the forces found); if that system is singular (e.g. every
/// point of a friction-held body slips), α is left from the previous solve.
pub fn friction_3d(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
) -> Result<FrictionOutcome, ContactError> {
    let bilateral = match start {
        None if problem.n_kernel() > 0 => bilateral_start(problem),
        _ => None,
    };
    let out = solve_3d(problem, layout, start, bilateral, opts)?;
    if problem.n_kernel() > 0 {
        let mut eqs: Vec<VarEquation> = out.forces.iter().map(|&v| VarEquation::Value(v)).collect();
        for (p, st) in out.statuses.iter().enumerate() {
            if *st == PointStatus::Open {
                continue;
            }
            eqs[p] = VarEquation::Gap;
            if *st == PointStatus::Stick {
                for &t in &layout.tangent_rows[p] {
                    eqs[t] = VarEquation::Gap;
                }
            }
        }
        let _ = problem.solve_equations(&eqs);
    }
    Ok(out)
}

/// The forces (and, kept in `problem`, the rigid-mode amplitudes α) with
/// every point closed and stuck: the start of the first step of a problem
/// with floating bodies. From zero forces the Newton method would see a body
/// whose contacts start open (an initial gap) as held by nothing, a singular
/// system; closed everywhere, its position is determined, and the points
/// that come out in tension open in the iterations that follow. `None` when
/// that system is singular too.
fn bilateral_start(problem: &mut DelassusProblem) -> Option<Vec<f64>> {
    let eqs = vec![VarEquation::Gap; problem.q.len()];
    problem.solve_equations(&eqs).ok().map(|(r, _)| r)
}

/// The 3D Tresca problems of a fixed point on the threshold (seed §4.3):
/// the semi-smooth Newton method from the previous forces, counting the
/// Newton iterations of all solves.
struct Newton<'a> {
    problem: &'a DelassusProblem,
    layout: &'a FrictionLayout,
    opts: &'a FrictionOptions,
    iterations: usize,
}

impl Newton<'_> {
    /// The iterate of the forces `forces` (no solve): their gaps (rigid-mode
    /// amplitudes zero) and statuses.
    fn iterate(&self, forces: Vec<f64>) -> InnerSolve {
        let mut x = forces.clone();
        x.resize(forces.len() + self.problem.g_mat.ncols(), 0.0);
        let gaps = Inner::new(self.problem, self.layout, &[]).gaps(&x);
        InnerSolve {
            statuses: statuses(self.layout, &forces, &gaps, self.opts),
            forces,
            gaps,
            converged: false,
            reason: String::new(),
        }
    }
}

impl TrescaSolver for Newton<'_> {
    type Thresholds = Vec<[f64; 2]>;

    fn solve(&mut self, thr: &Vec<[f64; 2]>, start: &[f64]) -> Result<InnerSolve, ContactError> {
        let (solve, iterations) = solve_inner(self.problem, self.layout, thr, start, self.opts)?;
        self.iterations += iterations;
        Ok(solve)
    }
}

fn solve_3d(
    problem: &DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    first_guess: Option<Vec<f64>>,
    opts: &FrictionOptions,
) -> Result<FrictionOutcome, ContactError> {
    let n = problem.q.len();
    layout.validate(n, 3)?;
    let forces = match start {
        Some(f) if f.len() == n => f.to_vec(),
        Some(f) => {
            return Err(ContactError::Geometry(format!(
                "friction 3D: {} start forces for {n} rows",
                f.len()
            )))
        }
        None => first_guess.unwrap_or_else(|| vec![0.0; n]),
    };
    let mut newton = Newton {
        problem,
        layout,
        opts,
        iterations: 0,
    };
    if !layout.has_coulomb() {
        let res = newton.solve(&layout.thresholds(&forces), &forces)?;
        let (converged, reason) = (res.converged, format!("Tresca: {}", res.reason));
        return Ok(res.outcome(converged, newton.iterations, Vec::new(), reason, false));
    }
    let start = match start {
        Some(_) => newton.iterate(forces),
        None => newton.solve(&vec![[f64::INFINITY; 2]; layout.n_points()], &forces)?,
    };
    let map = ThresholdMap {
        threshold: &|r, _| layout.thresholds(r),
        residual: &normal_change,
        name: "fixed point on the threshold",
    };
    let end = fixed_point(&mut newton, start, &map, opts)?;
    let outcome = end.last.outcome(
        end.converged,
        newton.iterations,
        end.residuals,
        end.reason,
        false,
    );
    Ok(outcome)
}

#[cfg(test)]
mod tests;
