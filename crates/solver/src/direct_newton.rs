//! Friction on the whole sparse system: the semi-smooth Newton method on
//! the Alart–Curnier equations (Alart & Curnier 1991; course notes §4.1.2)
//! with the displacements of every free DOF as unknowns beside the contact
//! forces, instead of the condensed problem's forces alone.
//!
//! Unknowns x = (u, λ): u on the free DOFs of all bodies, λ the forces of
//! the contact rows B (normal rows, then each frictional point's one or two
//! tangential rows). With the gaps y = B u + q + C λ (C the elastic slip
//! compliance of a regularised law, zero elsewhere) the equations are
//!
//! ```text
//!   equilibrium:  R(u, λ) = K u − Bᵀ λ − f = 0
//!   contact:      F(λ, y) = 0   (the Alart–Curnier rows of each point)
//! ```
//!
//! with F the condensed path's own rows
//! ([`signorini_contact::friction::AlartCurnier`]): on the tangential rows
//! y are the slip increments since the previous step (q carries the slip
//! total, course notes §4.4), and Coulomb points take the semi-axes μ_i λ_n of
//! the iterate (Coulomb's law itself). A Newton step linearises F on the
//! iterate's statuses ([`signorini_contact::friction::NewtonSystem`]: given
//! rows cᵀ dλ = v, coupled rows d cᵀ dλ + cᵀ dy = v with dy = B du + C dλ,
//! Coulomb's dλ_n terms) and solves
//!
//! ```text
//!   [ K      −Bᵀ  ] [du]   [ −R ]
//!   [ J_y B  J_λ  ] [dλ] = [  v ]
//! ```
//!
//! nonsymmetric with Coulomb: by GMRES preconditioned by the LDLᵀ of its
//! symmetric part, the given rows eliminated ([`crate::symmetric_part`]),
//! and when that does not reach the LU's backward error, by a sparse LU
//! whose pattern (every row of every point, whatever its status) and
//! symbolic factor are computed once per run ([`crate::sparse_lu`]). A body held by contact alone needs no
//! rigid-mode unknowns: its K is singular but the whole matrix is not while
//! its contacts hold it.
//!
//! Globalisation as on the condensed path: an Armijo line search on
//! ½(‖F‖² + ‖R‖²) (both in force), a full step when it fails (at most five
//! times), the stall rule of the condensed Newton method, and the whole
//! solve once more with ρ scaled by the condensed path's retry factor when
//! it does not converge. The projection parameter ρ_i of row i is
//! 1 / w_i with w_i = (bᵢᵀ bᵢ)² / (bᵢᵀ K bᵢ) ≤ (B K⁻¹ Bᵀ)_ii, the
//! Cauchy–Schwarz bound of the condensed path's 1 / W_ii that needs no
//! solve. It converges where the natural residual of the condensed path's
//! check is within the tolerance and R is within it relative to the force
//! scale.

use faer::sparse::{Pair, SparseColMat};

use crate::direct_forcing::{Forcing, POLISH_ABOVE};
use crate::sparse_lu::SparseLu;
use crate::symmetric_part::{Points, Rotation, SymmetricPart};
use signorini_condense::spmv_with_magnitude;
use signorini_contact::friction::{
    merit, AlartCurnier, FrictionLayout, FrictionOptions, NewtonSystem, Scale, RETRY_RHO_SCALE,
    STALLED_AFTER, STALL_DECREASE,
};
use signorini_contact::options::StallWatch;
use signorini_contact::{ContactError, StopReason};
use signorini_linalg::sparse::SparseRow;

/// Full (non-monotone) steps taken when the line search fails, before the
/// solve stops on it (as the condensed Newton method with floating bodies).
const FULL_STEPS: usize = 5;

/// The compliance, relative to each row's own 1 / ρ, added to the coupled
/// contact rows of the Newton matrix when both its tangent and secant forms
/// are singular: rows that constrain the same motion twice (a node on a
/// floor that sticks and on a wall, both along x) make the matrix singular
/// however the forces split. Only the matrix is shifted, not the residual,
/// so a converged answer satisfies the exact equations (a
/// Levenberg–Marquardt step, as the condensed path's full system takes
/// with 1e-6 of its largest entry).
const REDUNDANT_ROWS_SHIFT: f64 = 1e-6;

/// The whole system of a run: K on the free DOFs, the contact rows B on
/// them, the friction layout and the rows' compliance; the Jacobian's
/// pattern and its symbolic LU, built once.
pub(crate) struct WholeSystem<'a> {
    k: &'a SparseColMat<usize, f64>,
    rows: &'a [SparseRow],
    layout: &'a FrictionLayout,
    compliance: &'a [f64],
    /// The rows of each point: its normal row, then its tangential rows.
    point_rows: Vec<Vec<usize>>,
    /// The point of each row.
    owner: Vec<usize>,
    /// Where the values of equation row s start: its λ block (one per row
    /// of its point), then its u block (the point's rows' entries).
    lam_at: Vec<usize>,
    u_at: Vec<usize>,
    /// Where each row's entries start in its point's u block.
    row_in_block: Vec<usize>,
    /// The value count of the pattern.
    n_values: usize,
    /// ρ of each row (module doc).
    rho: Vec<f64>,
    lu: SparseLu,
    symmetric: SymmetricPart,
    /// The Jacobian's values in the pattern's order (reused).
    values: Vec<f64>,
}

/// One load step's data: the load on the free DOFs and the rows' q.
pub(crate) struct WholeLoad<'s> {
    pub f: &'s [f64],
    pub q: &'s [f64],
}

/// The answer of a step: u, λ and the gaps y, whether it met the
/// tolerance, why it stopped, and its Newton iterations.
pub(crate) struct WholeSolution {
    pub u: Vec<f64>,
    pub lambda: Vec<f64>,
    pub gaps: Vec<f64>,
    pub converged: bool,
    pub reason: StopReason,
    pub iterations: usize,
    pub residual_history: Vec<f64>,
}

impl<'a> WholeSystem<'a> {
    /// The whole system of stiffness `k` (both triangles stored) and rows
    /// `rows` (normal rows 0..m, then the layout's tangential rows);
    /// `floating` when K is singular.
    pub(crate) fn new(
        k: &'a SparseColMat<usize, f64>,
        rows: &'a [SparseRow],
        layout: &'a FrictionLayout,
        compliance: &'a [f64],
        floating: bool,
    ) -> Result<Self, ContactError> {
        let (n, m) = (k.nrows(), layout.n_points());
        let point_rows: Vec<Vec<usize>> = (0..m)
            .map(|p| {
                std::iter::once(p)
                    .chain(layout.tangent_rows[p].iter().copied())
                    .collect()
            })
            .collect();
        let mut owner = vec![0; rows.len()];
        for (p, pr) in point_rows.iter().enumerate() {
            pr.iter().for_each(|&r| owner[r] = p);
        }
        let mut pairs: Vec<Pair<usize, usize>> = Vec::new();
        for j in 0..n {
            pairs.extend(k.row_idx_of_col_raw(j).iter().map(|&i| Pair::new(i, j)));
        }
        for (r, row) in rows.iter().enumerate() {
            pairs.extend(row.iter().map(|&(i, _)| Pair::new(i, n + r)));
        }
        let (mut lam_at, mut u_at) = (vec![0; rows.len()], vec![0; rows.len()]);
        let mut row_in_block = vec![0; rows.len()];
        for pr in &point_rows {
            let mut at = 0;
            for &r in pr {
                row_in_block[r] = at;
                at += rows[r].len();
            }
            for &s in pr {
                lam_at[s] = pairs.len();
                pairs.extend(pr.iter().map(|&r| Pair::new(n + s, n + r)));
                u_at[s] = pairs.len();
                for &r in pr {
                    pairs.extend(rows[r].iter().map(|&(i, _)| Pair::new(n + s, i)));
                }
            }
        }
        let lu = SparseLu::new(n + rows.len(), &pairs).map_err(ContactError::Solve)?;
        let points = Points {
            rows,
            point_rows: &point_rows,
            owner: &owner,
        };
        let symmetric = SymmetricPart::new(k, &points, floating).map_err(ContactError::Solve)?;
        Ok(Self {
            rho: row_rho(k, rows),
            k,
            rows,
            layout,
            compliance,
            point_rows,
            owner,
            lam_at,
            u_at,
            row_in_block,
            n_values: pairs.len(),
            lu,
            symmetric,
            values: Vec::with_capacity(pairs.len()),
        })
    }

    /// Numerical LU factorisations and refinement steps so far, and the
    /// numerical LDLᵀ factorisations of the symmetric part and their
    /// Krylov steps.
    pub(crate) fn counts(&self) -> (usize, usize, usize, usize) {
        (
            self.lu.factorisations,
            self.lu.refinement_steps,
            self.symmetric.factorisations,
            self.symmetric.krylov_steps,
        )
    }

    /// The ordering and size of the symmetric part's LDLᵀ factor.
    pub(crate) fn ordered(&self) -> &signorini_condense::ordering::OrderedSymbolic {
        self.symmetric.ordered()
    }

    /// The contact row of J holding each given and each coupled equation
    /// of `sys`: the point's rows in turn, given equations first.
    fn slots(&self, sys: &NewtonSystem) -> (Vec<usize>, Vec<usize>) {
        let mut next = vec![0usize; self.point_rows.len()];
        let mut slot = |first_row: usize| {
            let p = self.owner[first_row];
            let s = self.point_rows[p][next[p]];
            next[p] += 1;
            s
        };
        let given = sys.given.iter().map(|(d, _)| slot(d.rows[0])).collect();
        let coupled = sys
            .coupled
            .iter()
            .map(|(d, _, _)| slot(d.rows[0]))
            .collect();
        (given, coupled)
    }

    /// The Newton direction of `sys` (the matrix of the values last set by
    /// [`WholeSystem::jacobian`], right-hand side `rhs`): by the symmetric
    /// part and GMRES (to the relative residual `forcing` when given,
    /// [`crate::direct_forcing`]), else by the LU.
    fn solve(
        &mut self,
        (sys, shift): (&NewtonSystem, f64),
        rhs: &[f64],
        forcing: Option<f64>,
    ) -> Option<Vec<f64>> {
        let (given, coupled) = self.slots(sys);
        let points = Points {
            rows: self.rows,
            point_rows: &self.point_rows,
            owner: &self.owner,
        };
        let equations = (given.iter().zip(&sys.given))
            .map(|(&s, (d, _))| (s, *d, true, 0.0))
            .chain(
                (coupled.iter().zip(&sys.coupled)).map(|(&s, (d, comp, _))| (s, *d, false, *comp)),
            );
        let rot = Rotation::new(&points, equations);
        let chat: Vec<f64> = (self.compliance.iter().zip(&self.rho))
            .map(|(c, r)| c + shift / r)
            .collect();
        let j = self.lu.set(&self.values);
        if let Some(x) = self
            .symmetric
            .solve(self.k, &points, (&rot, &chat), (j, rhs), forcing)
        {
            return Some(x);
        }
        self.lu.solve(rhs)
    }

    /// ρ of each row (module doc).
    pub(crate) fn rho(&self) -> &[f64] {
        &self.rho
    }

    fn n(&self) -> usize {
        self.k.nrows()
    }

    /// y = B u + q + C λ.
    fn gaps(&self, u: &[f64], lambda: &[f64], q: &[f64]) -> Vec<f64> {
        self.rows
            .iter()
            .enumerate()
            .map(|(r, row)| {
                q[r] + self.compliance[r] * lambda[r]
                    + row.iter().map(|&(i, c)| c * u[i]).sum::<f64>()
            })
            .collect()
    }

    /// R = K u − Bᵀ λ − f, and the magnitude of its terms (the largest
    /// of |K||u|, |Bᵀλ| and |f| over the rows).
    fn equilibrium(&self, u: &[f64], lambda: &[f64], f: &[f64]) -> (Vec<f64>, f64) {
        let (mut r, size) = spmv_with_magnitude(self.k.as_ref(), u);
        let mut scale = size.iter().fold(0.0f64, |a, &v| a.max(v));
        let mut bl = vec![0.0; self.n()];
        for (row, &l) in self.rows.iter().zip(lambda) {
            row.iter().for_each(|&(i, c)| bl[i] += c * l);
        }
        for i in 0..self.n() {
            r[i] -= bl[i] + f[i];
            scale = scale.max(bl[i].abs()).max(f[i].abs());
        }
        (r, scale)
    }

    /// The Jacobian's values (in the pattern's order, kept for
    /// [`WholeSystem::solve`]) for the linearised rows `sys`, and the
    /// right-hand side of the contact rows; `shift` adds the compliance
    /// shift / ρ_r to each coupled row r (a Levenberg–Marquardt step where
    /// the rows are redundant, module doc).
    fn jacobian(&mut self, sys: &NewtonSystem, shift: f64) -> Vec<f64> {
        let n = self.n();
        let mut v = std::mem::take(&mut self.values);
        v.clear();
        v.extend_from_slice(self.k.val());
        for row in self.rows {
            v.extend(row.iter().map(|&(_, c)| -c));
        }
        v.resize(self.n_values, 0.0);
        let mut rhs = vec![0.0; self.rows.len()];
        let (given_slot, coupled_slot) = self.slots(sys);
        let lam = |s: usize, r: usize| {
            let p = self.owner[s];
            self.lam_at[s] + self.point_rows[p].iter().position(|&x| x == r).unwrap_or(0)
        };
        for ((d, value), &s) in sys.given.iter().zip(&given_slot) {
            for l in 0..2 {
                v[lam(s, d.rows[l])] += d.c[l];
            }
            rhs[s] = *value;
        }
        for &(i, r, f) in &sys.given_normal {
            v[lam(given_slot[i], r)] -= f;
        }
        for ((d, comp, value), &s) in sys.coupled.iter().zip(&coupled_slot) {
            for l in 0..2 {
                let (r, c) = (d.rows[l], d.c[l]);
                if c == 0.0 {
                    continue;
                }
                v[lam(s, r)] += c * (comp + self.compliance[r] + shift / self.rho[r]);
                let at = self.u_at[s] + self.row_in_block[r];
                for (e, &(_, b)) in self.rows[r].iter().enumerate() {
                    v[at + e] += c * b;
                }
            }
            rhs[s] = *value;
        }
        for &(i, r, f) in &sys.coupled_normal {
            v[lam(coupled_slot[i], r)] += f;
        }
        debug_assert!(v.len() == self.n_values && n == self.k.nrows());
        self.values = v;
        rhs
    }
}

/// ρ_i = (bᵢᵀ K bᵢ) / (bᵢᵀ bᵢ)² of each row (module doc; a DOF repeated
/// in a row counts once, its coefficients summed), 1 where that is not
/// positive and finite.
fn row_rho(k: &SparseColMat<usize, f64>, rows: &[SparseRow]) -> Vec<f64> {
    let mut dense = vec![0.0; k.nrows()];
    rows.iter()
        .map(|row| {
            row.iter().for_each(|&(i, c)| dense[i] += c);
            let mut dofs: Vec<usize> = row.iter().map(|&(i, _)| i).collect();
            dofs.sort_unstable();
            dofs.dedup();
            let mut bkb = 0.0;
            for &j in &dofs {
                let col = k.row_idx_of_col_raw(j).iter().zip(k.val_of_col(j));
                bkb += dense[j] * col.map(|(&i, &a)| a * dense[i]).sum::<f64>();
            }
            let btb: f64 = dofs.iter().map(|&i| dense[i] * dense[i]).sum();
            dofs.iter().for_each(|&i| dense[i] = 0.0);
            let rho = bkb / (btb * btb);
            if rho > 0.0 && rho.is_finite() {
                rho
            } else {
                1.0
            }
        })
        .collect()
}

/// How a Newton step went: taken (by an inexact direction or not),
/// rejected by the line search (its direction), or without a direction.
enum Stepped {
    Taken { inexact: bool },
    Rejected(Vec<f64>),
    NoDirection,
}

/// The current iterate: u, λ, their gaps and equilibrium residual.
struct Iterate {
    u: Vec<f64>,
    lambda: Vec<f64>,
    y: Vec<f64>,
    r: Vec<f64>,
    r_scale: f64,
}

/// The Newton solve of one step on a whole system, with its ρ scale.
struct Solve<'s, 'a> {
    system: &'s mut WholeSystem<'a>,
    load: &'s WholeLoad<'s>,
    opts: &'s FrictionOptions,
    thr: Vec<[f64; 2]>,
    rho: Vec<f64>,
}

impl Solve<'_, '_> {
    fn iterate(&self, u: Vec<f64>, lambda: Vec<f64>) -> Iterate {
        let y = self.system.gaps(&u, &lambda, self.load.q);
        let (r, r_scale) = self.system.equilibrium(&u, &lambda, self.load.f);
        Iterate {
            u,
            lambda,
            y,
            r,
            r_scale,
        }
    }

    /// The residual of the condensed path's check (the scaled natural
    /// residual of the points), and of the equilibrium relative to the
    /// force scale: the larger.
    fn check(&self, it: &Iterate, law: &AlartCurnier) -> f64 {
        let m = self.system.layout.n_points();
        let fs = (self.opts.force_scale)
            .max(signorini_contact::norms::max_abs(&it.lambda[..m]))
            .max(f64::MIN_POSITIVE);
        let c = fs / self.opts.gap_scale.max(f64::MIN_POSITIVE);
        let mut f = vec![0.0; it.lambda.len()];
        law.residual(&it.lambda, &it.y, Scale::Check(c), &mut f, None);
        let contact = signorini_contact::norms::max_abs(&f) / fs;
        let eq = signorini_contact::norms::max_abs(&it.r) / fs.max(it.r_scale);
        contact.max(eq)
    }

    /// ½(‖F‖² + ‖R‖²) at (λ, y) with equilibrium residual `r`.
    fn merit(&self, law: &AlartCurnier, lambda: &[f64], y: &[f64], r: &[f64]) -> f64 {
        let mut f = vec![0.0; lambda.len()];
        law.residual(lambda, y, Scale::Newton, &mut f, None);
        merit(&f) + merit(r)
    }

    /// The Newton direction (du, dλ) at `it`: on the secants of the
    /// slipping points when the tangent system is singular, and with the
    /// coupled rows' compliance shifted by [`REDUNDANT_ROWS_SHIFT`] / ρ when
    /// that is singular too (redundant rows); to the relative residual
    /// `forcing` when given (an inexact Newton step); `None` when no system
    /// can be solved.
    fn direction(
        &mut self,
        it: &Iterate,
        law: &AlartCurnier,
        forcing: Option<f64>,
    ) -> Option<Vec<f64>> {
        let mut sys = NewtonSystem::default();
        let mut f = vec![0.0; it.lambda.len()];
        for (secant, shift) in [(false, 0.0), (true, 0.0), (false, REDUNDANT_ROWS_SHIFT)] {
            sys.secant = secant;
            law.residual(&it.lambda, &it.y, Scale::Newton, &mut f, Some(&mut sys));
            let contact_rhs = self.system.jacobian(&sys, shift);
            let mut rhs: Vec<f64> = it.r.iter().map(|v| -v).collect();
            rhs.extend(contact_rhs);
            let d = self.system.solve((&sys, shift), &rhs, forcing);
            if let Some(d) = d.filter(|d| d.iter().all(|v| v.is_finite())) {
                return Some(d);
            }
        }
        None
    }

    /// The Armijo line search on the merit along d from `it` (merit `psi`),
    /// halving the step at most 30 times; whether a step was taken.
    fn line_search(&self, it: &mut Iterate, d: &[f64], psi: f64, law: &AlartCurnier) -> bool {
        let n = self.system.n();
        let dy = self.system.gaps(&d[..n], &d[n..], &vec![0.0; d.len() - n]);
        let mut t = 1.0;
        for _ in 0..30 {
            let lambda: Vec<f64> = it
                .lambda
                .iter()
                .zip(&d[n..])
                .map(|(a, b)| a + t * b)
                .collect();
            let y: Vec<f64> = it.y.iter().zip(&dy).map(|(a, b)| a + t * b).collect();
            let r: Vec<f64> = it.r.iter().map(|v| (1.0 - t) * v).collect();
            if self.merit(law, &lambda, &y, &r) <= (1.0 - 1e-4 * t) * psi {
                let u = it.u.iter().zip(&d[..n]).map(|(a, b)| a + t * b).collect();
                *it = self.iterate(u, lambda);
                return true;
            }
            t *= 0.5;
        }
        false
    }

    /// One Newton step from `it` with the forcing term `eta` (exact when
    /// `None`): the direction and the line search along it; an inexact
    /// direction the line search rejects is solved again exactly before
    /// the step counts as rejected.
    fn step(&mut self, it: &mut Iterate, law: &AlartCurnier, eta: Option<f64>) -> Stepped {
        let Some(d) = self.direction(it, law, eta) else {
            return Stepped::NoDirection;
        };
        let psi = self.merit(law, &it.lambda, &it.y, &it.r);
        if self.line_search(it, &d, psi, law) {
            return Stepped::Taken {
                inexact: eta.is_some(),
            };
        }
        let Some(exact) = eta.and_then(|_| self.direction(it, law, None)) else {
            return Stepped::Rejected(d);
        };
        if self.line_search(it, &exact, psi, law) {
            return Stepped::Taken { inexact: false };
        }
        Stepped::Rejected(exact)
    }

    /// The Newton iterations from (u, λ): the last iterate, why it stopped,
    /// its iterations and residuals.
    fn run(&mut self, u: Vec<f64>, lambda: Vec<f64>) -> (Iterate, StopReason, usize, Vec<f64>) {
        let thr = self.thr.clone();
        let law = AlartCurnier {
            layout: self.system.layout,
            thr: &thr,
            rho: self.rho.clone(),
            coulomb: true,
        };
        let n = self.system.n();
        let mut it = self.iterate(u, lambda);
        let mut watch = StallWatch::new(STALL_DECREASE, STALLED_AFTER, self.opts.deadline);
        let mut history = Vec::new();
        let mut full_steps = 0;
        let mut forcing = Forcing::default();
        let mut inexact = false;
        for iteration in 0..self.opts.max_iterations {
            let residual = self.check(&it, &law);
            history.push(residual);
            if residual <= self.opts.tolerance {
                // After inexact steps, one exact step more
                // (crate::direct_forcing).
                let polish = residual > POLISH_ABOVE * self.opts.tolerance;
                if std::mem::take(&mut inexact)
                    && polish
                    && matches!(self.step(&mut it, &law, None), Stepped::Taken { .. })
                {
                    continue;
                }
                let reason = StopReason::NewtonConverged {
                    residual,
                    iterations: iteration,
                };
                return (it, reason, iteration, history);
            }
            if residual.is_nan() {
                return (it, StopReason::NonFinite { iteration }, iteration, history);
            }
            if watch.time_up() {
                let reason = StopReason::TimeLimit {
                    iterations: iteration,
                    residual,
                };
                return (it, reason, iteration, history);
            }
            if let Some(stall) = watch.stalled(residual, iteration) {
                return (it, StopReason::newton_stalled(stall), iteration, history);
            }
            let d = match self.step(&mut it, &law, forcing.next(residual)) {
                Stepped::Taken { inexact: i } => {
                    inexact |= i;
                    continue;
                }
                Stepped::Rejected(d) => d,
                Stepped::NoDirection => {
                    let reason = StopReason::NonFinite {
                        iteration: iteration + 1,
                    };
                    return (it, reason, iteration + 1, history);
                }
            };
            full_steps += 1;
            if full_steps > FULL_STEPS {
                return (
                    it,
                    StopReason::NewtonLineSearchFailed,
                    iteration + 1,
                    history,
                );
            }
            let u = it.u.iter().zip(&d[..n]).map(|(a, b)| a + b).collect();
            let lambda = it.lambda.iter().zip(&d[n..]).map(|(a, b)| a + b).collect();
            it = self.iterate(u, lambda);
        }
        let limit = self.opts.max_iterations;
        let residual = self.check(&it, &law);
        let reason = if residual <= self.opts.tolerance {
            StopReason::NewtonConverged {
                residual,
                iterations: limit,
            }
        } else {
            StopReason::NewtonLimit { limit }
        };
        (it, reason, limit, history)
    }
}

/// One step's Newton solve on the whole system from (u, λ) = `start`
/// (module doc): with ρ, and when that does not converge once more with ρ
/// scaled by the retry factor; never a non-converged answer marked
/// converged.
pub(crate) fn solve_whole(
    system: &mut WholeSystem<'_>,
    load: &WholeLoad<'_>,
    start: (Vec<f64>, Vec<f64>),
    opts: &FrictionOptions,
) -> WholeSolution {
    let thr = system.layout.thresholds(&start.1);
    let rho = system.rho.clone();
    let mut total = 0;
    let mut all_history = Vec::new();
    let mut last = None;
    for scale in [1.0, RETRY_RHO_SCALE] {
        let mut solve = Solve {
            system,
            load,
            opts,
            thr: thr.clone(),
            rho: rho.iter().map(|r| r * scale).collect(),
        };
        let (it, reason, iterations, history) = solve.run(start.0.clone(), start.1.clone());
        total += iterations;
        all_history.extend(history);
        let converged = matches!(reason, StopReason::NewtonConverged { .. });
        last = Some(WholeSolution {
            u: it.u,
            lambda: it.lambda,
            gaps: it.y,
            converged,
            reason,
            iterations: total,
            residual_history: all_history.clone(),
        });
        if converged {
            break;
        }
    }
    last.expect("one solve ran")
}
