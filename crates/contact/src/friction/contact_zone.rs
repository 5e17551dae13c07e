//! Friction on the contact zone: a Coulomb problem solved on the points
//! that can touch, the others checked.
//!
//! A point that carries no force and whose gap is open satisfies Coulomb's
//! law whatever its slip. So, with S a set of points, r_S the answer of the
//! problem restricted to S (the rows of its points in W and q) and r = 0
//! outside S, r solves the whole problem as soon as every point p outside S
//! is open:
//!
//! ```text
//!   u_n(p) = q_n(p) + Σ_{j in rows(S)} W_{n(p) j} r_j ≥ 0.
//! ```
//!
//! S starts with the points that touch at zero force (q_n < 0) and those
//! that carry a starting force; the points found closed outside S join it
//! and the restricted problem is solved again from its answer. Under an
//! indenter the closed points are a fraction of the surface (about 45 % on
//! the problems of the root benchmark), and an iteration of each method
//! costs the square (NSGS sweeps, products with W) or the cube
//! (factorisations) of its rows. Only problems without floating bodies
//! (their equilibrium couples every point) and with Coulomb or frictionless
//! points (a Tresca point may carry a tangential force while open) are
//! restricted.

use faer::Mat;

use crate::delassus::DelassusProblem;
use crate::law::{FrictionLaw, FrictionLayout};
use crate::options::FrictionOptions;
use crate::solution::{ContactSolution, PointStatus};
use crate::ContactError;

/// Times the zone grows before the whole problem is solved instead.
const MAX_GROWTH: usize = 20;

/// A zone worth solving on leaves out at least this fraction of the points.
const LEFT_OUT: f64 = 0.1;

/// A set of points and the problem of their rows: point k of the zone is
/// point `points[k]` of the whole; its normal row k, then the tangential
/// rows of each point in turn.
struct Zone {
    points: Vec<usize>,
    /// Row of the whole problem of each row of the zone.
    rows: Vec<usize>,
    layout: FrictionLayout,
}

impl Zone {
    fn new(points: Vec<usize>, layout: &FrictionLayout) -> Self {
        let mut rows = points.clone();
        let mut tangent_rows = Vec::with_capacity(points.len());
        for &p in &points {
            let t = &layout.tangent_rows[p];
            tangent_rows.push((rows.len()..rows.len() + t.len()).collect());
            rows.extend(t);
        }
        let layout = FrictionLayout {
            tangent_rows,
            law: points.iter().map(|&p| layout.law[p]).collect(),
            shadow: vec![None; points.len()],
        };
        Self {
            points,
            rows,
            layout,
        }
    }

    /// The problem of the zone's rows.
    fn problem(&self, whole: &DelassusProblem) -> DelassusProblem {
        let n = self.rows.len();
        let mut w = Mat::zeros(n, n);
        for (j, &cj) in self.rows.iter().enumerate() {
            let col = whole.w.col_as_slice(cj);
            for (wij, &ri) in w.col_as_slice_mut(j).iter_mut().zip(&self.rows) {
                *wij = col[ri];
            }
        }
        let q = self.rows.iter().map(|&r| whole.q[r]).collect();
        DelassusProblem::from_operator(w, q)
    }

    /// Values of the whole problem's rows on the zone's rows.
    fn restrict<T: Copy>(&self, v: &[T]) -> Vec<T> {
        self.rows.iter().map(|&r| v[r]).collect()
    }

    /// The forces of the whole problem (zero outside the zone) and its gaps
    /// W r + q, by the columns of the zone's rows.
    fn extend(&self, whole: &DelassusProblem, r_zone: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut r = vec![0.0; whole.q.len()];
        let mut u = whole.q.clone();
        for (&row, &rj) in self.rows.iter().zip(r_zone) {
            r[row] = rj;
            if rj != 0.0 {
                let col = whole.w.col_as_slice(row);
                u.iter_mut().zip(col).for_each(|(ui, c)| *ui += c * rj);
            }
        }
        (r, u)
    }
}

/// Whether a problem may be solved on its contact zone (module doc).
fn restrictable(problem: &DelassusProblem, layout: &FrictionLayout) -> bool {
    problem.g_mat.ncols() == 0
        && layout.shadow.iter().all(Option::is_none)
        && layout
            .law
            .iter()
            .all(|l| matches!(l, FrictionLaw::None | FrictionLaw::Coulomb { .. }))
}

/// Solves the problem by `solve` (on a problem, its layout, its starting
/// forces and the statuses of its points) on its contact zone (module doc);
/// `None` where the zone would hold nearly every point, or the problem
/// cannot be restricted: the caller solves the whole. `dim` gives the
/// statuses of the answer.
pub fn solve_on_contact_zone(
    problem: &mut DelassusProblem,
    layout: &FrictionLayout,
    start: Option<&[f64]>,
    statuses: &[PointStatus],
    opts: &FrictionOptions,
    dim: usize,
    mut solve: impl FnMut(
        &mut DelassusProblem,
        &FrictionLayout,
        Option<&[f64]>,
        Vec<PointStatus>,
    ) -> Result<ContactSolution, ContactError>,
) -> Result<Option<ContactSolution>, ContactError> {
    let m = layout.n_points();
    let start = start.filter(|s| s.len() == problem.q.len());
    let mut inside: Vec<bool> = (0..m)
        .map(|p| problem.q[p] < 0.0 || start.is_some_and(|s| s[p] > 0.0))
        .collect();
    let count = inside.iter().filter(|&&b| b).count();
    if !restrictable(problem, layout) || count == 0 || count as f64 > (1.0 - LEFT_OUT) * m as f64 {
        return Ok(None);
    }
    let mut forces = start.map(<[f64]>::to_vec);
    let (mut iterations, mut history) = (0, Vec::new());
    for _ in 0..MAX_GROWTH {
        let zone = Zone::new((0..m).filter(|&p| inside[p]).collect(), layout);
        let mut sub = zone.problem(problem);
        let sub_start = forces.as_deref().map(|f| zone.restrict(f));
        let answer = solve(
            &mut sub,
            &zone.layout,
            sub_start.as_deref(),
            zone.points.iter().map(|&p| statuses[p]).collect(),
        )?;
        problem.solves += sub.solves;
        iterations += answer.report.iterations;
        history.extend_from_slice(&answer.report.residual_history);
        let (r, u) = zone.extend(problem, &answer.forces);
        let closing = -1e-3 * opts.tolerance * opts.gap_scale;
        let outside_closed: Vec<usize> = (0..m).filter(|&p| !inside[p] && u[p] < closing).collect();
        if outside_closed.is_empty() || !answer.report.converged {
            let mut report = answer.report;
            (report.iterations, report.residual_history) = (iterations, history);
            let points = crate::friction::semismooth_newton::statuses(layout, &r, &u, opts, dim);
            let mut sol = ContactSolution::with_gaps(r, u, Vec::new(), report);
            sol.friction.fixed_point_iterations = answer.friction.fixed_point_iterations;
            sol.friction.fallback = answer.friction.fallback;
            sol.set_points(points);
            return Ok(Some(sol));
        }
        outside_closed.iter().for_each(|&p| inside[p] = true);
        forces = Some(r);
        if inside.iter().filter(|&&b| b).count() as f64 > (1.0 - LEFT_OUT) * m as f64 {
            break;
        }
    }
    Ok(None)
}
