//! The Alart–Curnier equations of the contact points (Alart & Curnier
//! 1991; course notes §4.1.2) and their generalised Jacobian, point by point
//! on the vectors of forces λ and gaps y (normal rows, then each point's
//! tangential rows, [`FrictionLayout`]), whatever gives the gaps: the
//! condensed problem's y = W λ + q + G α ([`super`]) or the whole sparse
//! system's y = B u + q (the direct path). With ρ > 0, D = diag(g1, g2)
//! the semi-axes of a point's disc / ellipse and c = ρ / max(g_i)²,
//!
//! ```text
//!   normal:      F_n = λ_n − max(0, λ_n − ρ y_n)
//!   tangential:  F_t = λ_t − D proj_B(z),   z = D⁺ λ_t − c D Δs   (B: unit disc)
//! ```
//!
//! and their linearisation on the iterate's statuses, one equation per force
//! row ([`NewtonSystem`]: given rows on dλ alone, coupled rows on dλ and dy).

use crate::law::FrictionLayout;

/// A unit direction over at most two force rows (`c[1] = 0` for one row).
#[derive(Debug, Clone, Copy)]
pub struct Dir {
    pub rows: [usize; 2],
    pub c: [f64; 2],
}

impl Dir {
    pub fn one(row: usize) -> Self {
        Self {
            rows: [row, row],
            c: [1.0, 0.0],
        }
    }

    /// cᵀ v on the direction's rows.
    pub fn dot(&self, v: &[f64]) -> f64 {
        self.c[0] * v[self.rows[0]] + self.c[1] * v[self.rows[1]]
    }
}

/// The linearised Alart–Curnier equations at an iterate, one equation per
/// force row on orthonormal directions (so that dλ = Σ given + Σ coupled):
/// `given` cᵀ dλ = v; `coupled` d cᵀ dλ + cᵀ (W dλ + G dα) = v (d ≥ 0);
/// `equilibrium` Gᵀ dλ = v_j. With `secant`, a slipping point with one
/// tangential row is linearised on the secant of the projection (see
/// [`slip_rows`]). Coulomb's law (threshold μ λ_n, [`solve_coulomb`]) adds
/// the normal force dλ_n of a slipping point to its rows: `given_normal`
/// (i, row, f) makes given equation i cᵀ dλ = v + f dλ_row, and
/// `coupled_normal` (i, row, f) adds f dλ_row to the left of coupled
/// equation i (the system is then nonsymmetric).
#[derive(Debug, Default)]
pub struct NewtonSystem {
    pub secant: bool,
    pub given: Vec<(Dir, f64)>,
    pub coupled: Vec<(Dir, f64, f64)>,
    pub equilibrium: Vec<f64>,
    pub given_normal: Vec<(usize, usize, f64)>,
    pub coupled_normal: Vec<(usize, usize, f64)>,
    /// The last factor of the reduced system, for chord steps.
    pub(crate) factor: Option<crate::reduced::NewtonFactor>,
}

/// The trial z = D⁺ λ_t − c D Δs of a point's rows in the unit disc
/// (D = diag(g), D⁺ its pseudo-inverse), with c and D⁺.
fn scaled_trial(
    x: &[f64],
    y: &[f64],
    rows: &[usize],
    g: [f64; 2],
    c: f64,
) -> (f64, [f64; 2], [f64; 2]) {
    let dinv = g.map(|gi| if gi > 0.0 { 1.0 / gi } else { 0.0 });
    let mut z = [0.0; 2];
    for (i, &r) in rows.iter().enumerate() {
        z[i] = dinv[i] * x[r] - c * g[i] * y[r];
    }
    (c, dinv, z)
}

/// Row `r` held at one bound: with `Some(c)` its gap y_r = 0 (F_r = c y_r,
/// the coupled row dy_r = −y_r with no compliance: a point in contact, a
/// stuck row), else its force λ_r = 0 (F_r = λ_r, the given row
/// dλ_r = −λ_r: an open point, a row with a zero bound).
fn held_row(
    r: usize,
    c: Option<f64>,
    (x, y): (&[f64], &[f64]),
    f: &mut [f64],
    sys: Option<&mut NewtonSystem>,
) {
    match c {
        Some(c) => {
            f[r] = c * y[r];
            if let Some(s) = sys {
                s.coupled.push((Dir::one(r), 0.0, -y[r]));
            }
        }
        None => {
            f[r] = x[r];
            if let Some(s) = sys {
                s.given.push((Dir::one(r), -x[r]));
            }
        }
    }
}

/// How a residual is scaled: `Newton` with ρ = 1/W_ii, `Check` with ρ = F/L
/// (the natural residual relative to the force and length scales).
#[derive(Clone, Copy, PartialEq)]
pub enum Scale {
    Newton,
    Check(f64),
}

/// The Alart–Curnier equations of a layout's points: the semi-axes of the
/// points with a fixed bound (`thr`), the projection parameter ρ of each
/// row, and whether Coulomb points take μ_i λ_n of the iterate (Coulomb's
/// law itself) instead of `thr`.
pub struct AlartCurnier<'a> {
    pub layout: &'a FrictionLayout,
    /// Semi-axes (g1, g2) per point; infinite: no bound (stuck).
    pub thr: &'a [[f64; 2]],
    /// Newton's projection parameter per row.
    pub rho: Vec<f64>,
    /// Coulomb's law itself: the semi-axes of a Coulomb point are μ_i λ_n
    /// of the iterate (`thr` holds the other points' bounds).
    pub coulomb: bool,
}

impl AlartCurnier<'_> {
    /// The semi-axes of point p at x and, for Coulomb's law itself, their
    /// derivatives in λ_n (μ_i where λ_n > 0).
    pub fn bound(&self, p: usize, x: &[f64]) -> ([f64; 2], Option<[f64; 2]>) {
        let law = &self.layout.law[p];
        match law.coulomb_mu() {
            Some(mu) if self.coulomb => {
                let dg = if x[p] > 0.0 { mu } else { [0.0; 2] };
                (law.semi_axes(x[p]), Some(dg))
            }
            _ => (self.thr[p], None),
        }
    }

    /// The residual rows F of every point at forces `x` and gaps `y` into
    /// `f` (its first rows: one per force row), and, if asked, their
    /// linearisation on the statuses of (x, y), `sys` cleared first (its
    /// `secant` choice kept).
    pub fn residual(
        &self,
        x: &[f64],
        y: &[f64],
        scale: Scale,
        f: &mut [f64],
        mut sys: Option<&mut NewtonSystem>,
    ) {
        if let Some(s) = sys.as_deref_mut() {
            *s = NewtonSystem {
                secant: s.secant,
                factor: s.factor.take(),
                ..NewtonSystem::default()
            };
        }
        for p in 0..self.layout.n_points() {
            let rn = match scale {
                Scale::Newton => self.rho[p],
                Scale::Check(c) => c,
            };
            let in_contact = x[p] - rn * y[p] > 0.0;
            held_row(p, in_contact.then_some(rn), (x, y), f, sys.as_deref_mut());
            let rows = &self.layout.tangent_rows[p];
            if !rows.is_empty() {
                let sys = sys.as_deref_mut();
                let (g, dg) = self.bound(p, x);
                let normal = dg.map(|dg| (p, dg));
                self.tangential_residual(x, y, rows, (g, normal), scale, f, sys);
            }
        }
    }

    /// The Alart–Curnier rows of one point's tangential force λ_t (one or
    /// two rows) with semi-axes `g`: stuck (Δs = 0) for an infinite bound,
    /// zero for a zero bound, else, scaled to the unit disc,
    /// ν = D⁺ λ_t, z = ν − c D Δs, F = λ_t − D proj(z) (course notes §4.1.2).
    /// `normal`: Coulomb's law itself, (normal row, ∂g/∂λ_n) (see
    /// [`slip_rows`]).
    #[allow(clippy::too_many_arguments)]
    fn tangential_residual(
        &self,
        x: &[f64],
        y: &[f64],
        rows: &[usize],
        (g, normal): ([f64; 2], Option<(usize, [f64; 2])>),
        scale: Scale,
        f: &mut [f64],
        mut sys: Option<&mut NewtonSystem>,
    ) {
        let rt = match scale {
            Scale::Newton => rows.iter().map(|&r| self.rho[r]).sum::<f64>() / rows.len() as f64,
            Scale::Check(c) => c,
        };
        let gbar = g[..rows.len()].iter().fold(0.0f64, |a, &v| a.max(v));
        let (c, dinv, z) = scaled_trial(x, y, rows, g, rt / (gbar * gbar));
        let nz = z[0].hypot(z[1]);
        // A bound so small that c = ρ/ḡ² or z overflows (μ λ_n of a
        // round-off λ_n) is a zero bound: the point carries no λ_t.
        let negligible = !(c.is_finite() && nz.is_finite());
        if gbar.is_infinite() || gbar <= 0.0 || negligible {
            // No bound: stuck, Δs = 0; else no force.
            let stuck = gbar.is_infinite().then_some(rt);
            for &r in rows {
                held_row(r, stuck, (x, y), f, sys.as_deref_mut());
            }
            return;
        }
        let pz = if nz <= 1.0 { z } else { [z[0] / nz, z[1] / nz] };
        for (i, &r) in rows.iter().enumerate() {
            f[r] = x[r] - g[i] * pz[i];
        }
        let Some(sys) = sys else { return };
        if nz <= 1.0 {
            // Stuck: zero slip on the rows with a bound, zero force on the others.
            for (i, &r) in rows.iter().enumerate() {
                if g[i] > 0.0 {
                    sys.coupled.push((Dir::one(r), 0.0, -y[r]));
                } else {
                    sys.given.push((Dir::one(r), -f[r]));
                }
            }
        } else {
            let coulomb = normal.map(|(p, dg)| (p, [dg[0] * pz[0], dg[1] * pz[1]]));
            slip_rows(sys, rows, (g, dinv), pz, nz, c, f, coulomb);
        }
    }
}

/// The rows of a slipping point (‖z‖ > 1, u = proj(z) on the unit
/// circle): with τ ⊥ u, a = D τ, b = D⁺ τ, the linearised equations
/// dλ_t − a bᵀ dλ_t / ‖z‖ + c a aᵀ (W_t dλ + G_t dα) / ‖z‖ = −F_t give the
/// component of dλ_t across a, and along â = a/‖a‖ the coupled row with
/// the compliance (‖z‖ − aᵀb) / (c ‖a‖²) (positive: aᵀb ≤ 1 < ‖z‖). When
/// a vanishes (one bounded row, or D τ = 0) the rows are the identity.
/// With `sys.secant`, every row of the point is linearised on the
/// projection's secant slope 1/‖z‖ instead of its derivative (zero across
/// the boundary): (1 − 1/‖z‖) dλ_ti + c g_i² (W_ti dλ + G_ti dα) / ‖z‖ =
/// −F_ti, the compliance (‖z‖ − 1) / (c g_i²) (a body held by friction
/// alone, all its points slipping at an iterate, is otherwise held by
/// nothing along their slip: a singular step).
///
/// Coulomb's law itself (`coulomb` = (normal row, m), m = (∂D/∂λ_n) u, i.e.
/// μ_i u_i): with D = λ_n diag(μ), u does not depend on λ_n (z = w / λ_n)
/// and F_t = λ_t − D u gains −m dλ_n; the equations above hold with −F_t
/// replaced by −F_t + m dλ_n, all linear in F_t: the component across a
/// (isotropic: the radial one) follows the normal force, and the coupled
/// row gains a multiple of dλ_n ([`NewtonSystem`]).
#[allow(clippy::too_many_arguments)]
fn slip_rows(
    sys: &mut NewtonSystem,
    rows: &[usize],
    (g, dinv): ([f64; 2], [f64; 2]),
    u: [f64; 2],
    nz: f64,
    c: f64,
    f: &[f64],
    coulomb: Option<(usize, [f64; 2])>,
) {
    let (normal, m) = coulomb.unwrap_or((0, [0.0; 2]));
    let given = |sys: &mut NewtonSystem, d: Dir, v: f64, fm: f64| {
        if fm != 0.0 {
            sys.given_normal.push((sys.given.len(), normal, fm));
        }
        sys.given.push((d, v));
    };
    let coupled = |sys: &mut NewtonSystem, d: Dir, comp: f64, v: f64, fm: f64| {
        if fm != 0.0 {
            sys.coupled_normal.push((sys.coupled.len(), normal, fm));
        }
        sys.coupled.push((d, comp, v));
    };
    let tau = [-u[1], u[0]];
    let two = rows.len() == 2;
    let a = [g[0] * tau[0], if two { g[1] * tau[1] } else { 0.0 }];
    let b = [dinv[0] * tau[0], if two { dinv[1] * tau[1] } else { 0.0 }];
    let na = a[0].hypot(a[1]);
    if sys.secant {
        for (i, &r) in rows.iter().enumerate() {
            let cg = c * g[i] * g[i];
            if cg > 0.0 && cg.is_finite() {
                let (comp, v, fm) = ((nz - 1.0) / cg, -nz * f[r] / cg, -nz * m[i] / cg);
                coupled(sys, Dir::one(r), comp, v, fm);
            } else {
                given(sys, Dir::one(r), -f[r], m[i]);
            }
        }
        return;
    }
    if !two || na <= 1e-12 * g[0].max(g[1]) {
        for (i, &r) in rows.iter().enumerate() {
            given(sys, Dir::one(r), -f[r], m[i]);
        }
        return;
    }
    let ah = [a[0] / na, a[1] / na];
    let across = Dir {
        rows: [rows[0], rows[1]],
        c: [-ah[1], ah[0]],
    };
    let along = Dir {
        rows: across.rows,
        c: ah,
    };
    // cᵀ v, zero below its rounding (isotropic: a ⊥ u, b ⊥ â⊥ exactly,
    // and the system keeps the structure key of its chord steps).
    let on = |d: &Dir, v: [f64; 2]| {
        let p = d.c[0] * v[0] + d.c[1] * v[1];
        let bound = 8.0 * f64::EPSILON * (v[0].abs() + v[1].abs());
        if p.abs() <= bound {
            0.0
        } else {
            p
        }
    };
    let beta = -across.dot(f);
    let ab = a[0] * b[0] + a[1] * b[1];
    let bv = on(&across, b);
    let comp = (nz - ab) / (c * na * na);
    let rhs = -nz * along.dot(f) / (c * na * na) + beta * bv / (c * na);
    let kappa = on(&across, m);
    let eta = nz * on(&along, m) / (c * na * na) + kappa * bv / (c * na);
    given(sys, across, beta, kappa);
    coupled(sys, along, comp, rhs, -eta);
}
