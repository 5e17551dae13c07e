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
use crate::lcp::LcpOptions;
use crate::options::FrictionOptions;
use crate::options::StatusVariant;
use crate::registry::Algorithm;
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
    if !restrictable(problem, layout) {
        return Ok(None);
    }
    let Some((mut inside, mut forces)) = first_zone(problem, m, start, opts) else {
        return Ok(None);
    };
    let mut statuses = statuses.to_vec();
    let (mut iterations, mut history) = (0, Vec::new());
    for _ in 0..MAX_GROWTH {
        let count = inside.iter().filter(|&&b| b).count();
        if count == 0 || count as f64 > (1.0 - LEFT_OUT) * m as f64 {
            break;
        }
        let zone = Zone::new((0..m).filter(|&p| inside[p]).collect(), layout);
        let mut sub = zone.problem(problem);
        let sub_start = forces.as_deref().map(|f| zone.restrict(f));
        let sub_statuses = zone.points.iter().map(|&p| statuses[p]).collect();
        let answer = solve(&mut sub, &zone.layout, sub_start.as_deref(), sub_statuses)?;
        problem.solves += sub.solves;
        iterations += answer.report.iterations;
        history.extend_from_slice(&answer.report.residual_history);
        let (r, u) = zone.extend(problem, &answer.forces);
        let closing = -1e-3 * opts.tolerance * opts.gap_scale;
        let closed: Vec<usize> = (0..m).filter(|&p| !inside[p] && u[p] < closing).collect();
        if closed.is_empty() || !answer.report.converged {
            let mut report = answer.report;
            (report.iterations, report.residual_history) = (iterations, history);
            let points = crate::friction::semismooth_newton::statuses(layout, &r, &u, opts, dim);
            let mut sol = ContactSolution::with_gaps(r, u, Vec::new(), report);
            sol.friction.fixed_point_iterations = answer.friction.fixed_point_iterations;
            sol.friction.fallback = answer.friction.fallback;
            sol.set_points(points);
            return Ok(Some(sol));
        }
        for (&p, &status) in zone.points.iter().zip(&answer.friction.points) {
            statuses[p] = status;
        }
        for &p in &closed {
            (inside[p], statuses[p]) = (true, PointStatus::Stick);
        }
        forces = Some(r);
    }
    Ok(None)
}

/// The first zone and the forces to start from: with starting forces, the
/// points they load and those closed at zero force (q_n < 0); else the
/// points the frictionless problem closes ([`frictionless`]) or leaves
/// within a tenth of the deepest initial penetration among those (where
/// friction may shift the contact), from its forces. `None` where the
/// frictionless problem has no answer by the status method (a singular
/// active block: redundant contacts of rigid bodies): the whole is solved.
fn first_zone(
    problem: &DelassusProblem,
    m: usize,
    start: Option<&[f64]>,
    opts: &FrictionOptions,
) -> Option<(Vec<bool>, Option<Vec<f64>>)> {
    if let Some(s) = start.filter(|s| s.len() == problem.q.len()) {
        let inside = (0..m).map(|p| s[p] > 0.0 || problem.q[p] < 0.0).collect();
        return Some((inside, Some(s.to_vec())));
    }
    let (forces, gaps) = frictionless(problem, m, opts).ok()?;
    let depth = (0..m)
        .filter(|&p| forces[p] > 0.0)
        .fold(0.0f64, |d, p| d.max(-problem.q[p]));
    let inside = (0..m)
        .map(|p| forces[p] > 0.0 || gaps[p] < 0.1 * depth)
        .collect();
    Some((inside, Some(forces)))
}

/// The forces of the frictionless problem of the m points (their normal
/// rows 0..m, by the status method) on every row, zero on the tangential
/// ones, and its normal gaps.
fn frictionless(
    problem: &DelassusProblem,
    m: usize,
    opts: &FrictionOptions,
) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
    let w = problem.w.submatrix(0, 0, m, m).to_owned();
    let lcp = LcpOptions {
        tolerance: opts.tolerance,
        max_iterations: 10 * m + 10,
        force_scale: opts.force_scale,
        gap_scale: opts.gap_scale,
        stiffness: None,
        deadline: opts.deadline,
    };
    let out = Algorithm::status(StatusVariant::All).solve(&w, &problem.q[..m], None, &lcp)?;
    let mut forces = vec![0.0; problem.q.len()];
    forces[..m].copy_from_slice(&out.forces);
    Ok((forces, out.gaps))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::driver::{solve_friction, FrictionMethod, FrictionStart};
    use crate::law::natural_residual;
    use crate::test_problems::{coulomb_layout, friction_options as opts, random_spd, XorShift};

    /// m points in `dim`, normals first, Coulomb μ = 0.3; W random SPD, the
    /// first third of the points pressed (q_n < 0), the others a little
    /// open, the tangential gaps random (a slide).
    fn problem(m: usize, dim: usize, seed: u64) -> (DelassusProblem, FrictionLayout) {
        let k = dim - 1;
        let mut rng = XorShift(seed);
        let w = random_spd(m * dim, &mut rng);
        let mut q: Vec<f64> = (0..m)
            .map(|p| match p < m / 3 {
                true => rng.uniform(-1.0, -0.2),
                false => rng.uniform(0.01, 0.3),
            })
            .collect();
        q.extend((0..m * k).map(|_| rng.uniform(-0.3, 0.3)));
        let layout = coulomb_layout(m, dim, 0.3);
        (DelassusProblem::from_operator(w, q), layout)
    }

    fn solve(dim: usize, seed: u64, method: FrictionMethod, zone: bool) -> (Vec<f64>, f64) {
        let (mut p, layout) = problem(30, dim, seed);
        let start = FrictionStart {
            statuses: vec![PointStatus::Stick; 30],
            forces: None,
            predict: false,
            zone,
        };
        let out = solve_friction(&mut p, &layout, method, start, &opts()).unwrap();
        assert!(
            out.solution.report.converged,
            "{}",
            out.solution.report.stop
        );
        // The residual of the whole problem, gaps recomputed here.
        let r = &out.solution.forces;
        let u = crate::lcp::gaps(&p.w, &p.q, r);
        let force = r.iter().fold(1.0f64, |s, v| s.max(v.abs()));
        (r.clone(), natural_residual(&layout, r, &u, force, 1.0))
    }

    /// On the contact zone NSGS and the semi-smooth Newton method give the
    /// forces they give on the whole problem, and those solve the whole
    /// problem (natural residual from gaps W r + q computed here).
    #[test]
    fn the_zone_gives_the_whole_problems_answer() {
        for (dim, methods) in [
            (3, [FrictionMethod::Nsgs3d, FrictionMethod::Newton3d]),
            (2, [FrictionMethod::Nsgs2d, FrictionMethod::CoulombStatus]),
        ] {
            for seed in [3, 17, 29] {
                for method in methods {
                    let (whole, _) = solve(dim, seed, method, false);
                    let (zoned, residual) = solve(dim, seed, method, true);
                    assert!(
                        residual <= 1e-9,
                        "{method:?} dim {dim} seed {seed}: {residual:e}"
                    );
                    let diff = crate::test_problems::rel_err(&zoned, &whole);
                    assert!(diff <= 1e-7, "{method:?} dim {dim} seed {seed}: {diff:e}");
                }
            }
        }
    }

    /// A deadline already passed stops every friction method, 2D and 3D,
    /// Coulomb, Tresca and Norton–Hoff, not converged, on the time limit,
    /// with a finite iterate and its residual.
    #[test]
    fn a_passed_deadline_stops_every_friction_method() {
        use crate::friction::FrictionLaw;
        use FrictionMethod::*;
        let tresca = Some(FrictionLaw::Tresca(0.1));
        let norton_hoff = Some(FrictionLaw::NortonHoff { mu: 0.3, rho: 0.5 });
        // The law of every point, `None`: the problem's Coulomb law.
        let runs: [(usize, FrictionMethod, Option<FrictionLaw>); 10] = [
            (2, CoulombFixedPoint, None),
            (2, CoulombStatus, None),
            (2, Newton, None),
            (2, Nsgs2d, None),
            (2, TrescaStatus, tresca),
            (2, TrescaBox, tresca),
            (2, NortonHoff, norton_hoff),
            (3, Newton3d, None),
            (3, FixedPoint3d, None),
            (3, Nsgs3d, None),
        ];
        for (dim, method, law) in runs {
            let (mut p, mut layout) = problem(30, dim, 5);
            if let Some(law) = law {
                layout.law.fill(law);
            }
            let start = FrictionStart {
                statuses: vec![PointStatus::Stick; 30],
                forces: None,
                predict: false,
                zone: false,
            };
            let o = crate::options::FrictionOptions {
                deadline: Some(std::time::Instant::now()),
                ..opts()
            };
            let out = solve_friction(&mut p, &layout, method, start, &o).unwrap();
            let report = &out.solution.report;
            assert!(!report.converged, "{method:?}");
            let crate::solution::StopReason::TimeLimit { residual, .. } = report.stop else {
                panic!("{method:?}: {}", report.stop);
            };
            assert!(!residual.is_nan(), "{method:?}");
            assert!(
                out.solution.forces.iter().all(|v| v.is_finite()),
                "{method:?}"
            );
        }
    }
}
