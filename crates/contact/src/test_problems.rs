//! Deterministic test problems shared by the tests of the LCP methods (the
//! dual and regularised methods, the projected gradients, the status
//! method), and the reference solution by the status method.
use faer::Mat;

use crate::active_set::signorini::{status_method, StatusOptions, StatusVariant};
use crate::friction::{FrictionLaw, FrictionLayout, FrictionOptions};
use crate::lcp::{gaps, LcpOptions};
use crate::solution::{ContactSolution, SolverReport, StopReason};
use crate::DelassusProblem;

/// The options of the LCP methods' tests: a tolerance and an iteration limit.
pub fn lcp_options(tolerance: f64, max_iterations: usize) -> LcpOptions {
    LcpOptions {
        tolerance,
        max_iterations,
        ..Default::default()
    }
}

/// The options of the friction methods' tests on problems in unit scales:
/// a tight tolerance and generous iteration limits.
pub fn friction_options() -> FrictionOptions {
    FrictionOptions {
        max_iterations: 20_000,
        max_fixed_point: 20_000,
        tolerance: 1e-11,
        force_scale: 1.0,
        gap_scale: 1.0,
        deadline: None,
    }
}

/// The block layout of m points in `dim` (normals first, then each point's
/// dim − 1 tangential rows), isotropic Coulomb μ everywhere.
pub fn coulomb_layout(m: usize, dim: usize, mu: f64) -> FrictionLayout {
    let k = dim - 1;
    FrictionLayout {
        tangent_rows: (0..m)
            .map(|p| (m + k * p..m + k * p + k).collect())
            .collect(),
        law: vec![FrictionLaw::coulomb(mu); m],
        shadow: vec![None; m],
    }
}

pub struct XorShift(pub u64);

impl XorShift {
    pub fn next_f64(&mut self) -> f64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        (x >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn uniform(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next_f64()
    }
}

/// W = AᵀA + εI with A (3m × m) uniform in [−1, 1): SPD, condition ~ 15.
pub fn random_spd(m: usize, rng: &mut XorShift) -> Mat<f64> {
    let a = Mat::<f64>::from_fn(3 * m, m, |_, _| rng.uniform(-1.0, 1.0));
    let mut w = a.transpose() * &a;
    for i in 0..m {
        w[(i, i)] += 1e-3;
    }
    for j in 0..m {
        for i in j + 1..m {
            let v = 0.5 * (w[(i, j)] + w[(j, i)]);
            w[(i, j)] = v;
            w[(j, i)] = v;
        }
    }
    w
}

/// q = g* − W λ* for a prescribed complementary pair (λ*, g*).
pub fn q_from_solution(w: &Mat<f64>, lambda: &[f64], g: &[f64]) -> Vec<f64> {
    let m = lambda.len();
    (0..m)
        .map(|i| g[i] - (0..m).map(|j| w[(i, j)] * lambda[j]).sum::<f64>())
        .collect()
}

/// A Delassus problem whose operator is W and whose free gaps are q (built
/// on S = I with one unit row a point, then W and q put in).
pub fn lcp_problem(w: &Mat<f64>, q: &[f64]) -> DelassusProblem {
    let m = q.len();
    let mut p = DelassusProblem::new(
        &Mat::<f64>::identity(m, m),
        &(0..m).map(|i| vec![(i, 1.0)]).collect::<Vec<_>>(),
        &vec![0.0; m],
        &vec![0.0; m],
        &Mat::zeros(m, 0),
    )
    .unwrap();
    p.w = w.clone();
    p.q = q.to_vec();
    p
}

/// The forces of LCP(W, q) by the status method (course notes §3.3, all statuses
/// at once) to the relative `tolerance`; asserts that it converged.
pub fn status_solution(w: &Mat<f64>, q: &[f64], tolerance: f64) -> Vec<f64> {
    let m = q.len();
    let mut p = lcp_problem(w, q);
    let out = status_method(
        &mut p,
        &StatusOptions {
            variant: StatusVariant::All,
            max_iterations: 10 * m + 10,
            tolerance,
            force_scale: 1.0,
            gap_scale: 1.0,
            initial_active: None,
            deadline: None,
        },
    )
    .unwrap();
    assert!(out.report.converged, "status method: {}", out.report.stop);
    out.forces
}

/// The exact solution by the status method (course notes §3.3).
pub fn exact_solution(w: &Mat<f64>, q: &[f64]) -> Vec<f64> {
    status_solution(w, q, 1e-13)
        .iter()
        .map(|v| v.max(0.0))
        .collect()
}

pub fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, x| a.max(x.abs()))
}

/// ‖a − b‖∞ / ‖b‖∞ (absolute when b = 0).
pub fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let d = a
        .iter()
        .zip(b)
        .fold(0.0f64, |acc, (x, y)| acc.max((x - y).abs()));
    d / norm_inf(b).max(1e-300)
}

/// A named LCP and its exact solution.
pub struct Case {
    pub name: String,
    pub w: Mat<f64>,
    pub q: Vec<f64>,
    pub exact: Vec<f64>,
}

/// Random mixed-sign problems (m = 5, 20, 60), all active, none active,
/// and a weakly active point (q_p = 0 … zero force and zero gap).
pub fn cases() -> Vec<Case> {
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let mut out = Vec::new();
    for m in [5usize, 20, 60] {
        let w = random_spd(m, &mut rng);
        let scale = crate::lcp::mean_diag(&w);
        let q: Vec<f64> = (0..m).map(|_| rng.uniform(-1.0, 1.0) * scale).collect();
        let exact = exact_solution(&w, &q);
        out.push(Case {
            name: format!("random mixed m = {m}"),
            w,
            q,
            exact,
        });
    }
    let m = 20;
    let w = random_spd(m, &mut rng);
    let l: Vec<f64> = (0..m).map(|_| rng.uniform(0.5, 1.5)).collect();
    let q = q_from_solution(&w, &l, &vec![0.0; m]);
    let exact = exact_solution(&w, &q);
    out.push(Case {
        name: "all active".into(),
        w,
        q,
        exact,
    });
    let w = random_spd(m, &mut rng);
    let q: Vec<f64> = (0..m).map(|_| rng.uniform(0.1, 1.0)).collect();
    out.push(Case {
        name: "none active".into(),
        w,
        q,
        exact: vec![0.0; m],
    });
    // Points 0..8 active, 8..18 open, 18 and 19 weakly active (λ = g = 0).
    let w = random_spd(m, &mut rng);
    let l: Vec<f64> = (0..m)
        .map(|p| if p < 8 { rng.uniform(0.5, 1.5) } else { 0.0 })
        .collect();
    let g: Vec<f64> = (0..m)
        .map(|p| {
            if (8..18).contains(&p) {
                rng.uniform(0.1, 1.0)
            } else {
                0.0
            }
        })
        .collect();
    let q = q_from_solution(&w, &l, &g);
    let ex = exact_solution(&w, &q);
    assert!(rel_err(&ex, &l) < 1e-12);
    out.push(Case {
        name: "weakly active".into(),
        w,
        q,
        exact: l,
    });
    out
}

/// A redundant problem: point 0 of a regular problem (m0 = 8) doubled
/// (two identical rows, W singular), point 0 active. Returns (W, q) of
/// the doubled problem and (λ, g) of the regular one.
pub fn redundant() -> (Mat<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = XorShift(0x2545_F491_4F6C_DD1D);
    let m0 = 8;
    let w0 = random_spd(m0, &mut rng);
    let l: Vec<f64> = (0..m0)
        .map(|p| if p < 4 { rng.uniform(0.5, 1.5) } else { 0.0 })
        .collect();
    let g: Vec<f64> = (0..m0)
        .map(|p| if p < 4 { 0.0 } else { rng.uniform(0.1, 1.0) })
        .collect();
    let q0 = q_from_solution(&w0, &l, &g);
    let map = |i: usize| if i == 0 { 0 } else { i - 1 };
    let m = m0 + 1;
    let w = Mat::<f64>::from_fn(m, m, |i, j| w0[(map(i), map(j))]);
    let q: Vec<f64> = (0..m).map(|i| q0[map(i)]).collect();
    (w, q, l, g)
}

/// Asserts that `sol` solves the case `c`: converged, λ ≥ 0 and finite,
/// relative error ≤ 1e-8 against the exact solution (exactly 0 when it
/// is 0), one residual in the history per iteration. `label` names the
/// run in the messages.
pub fn assert_solves_case(c: &Case, sol: &ContactSolution, label: &str) {
    assert!(sol.report.converged, "{}: {}", c.name, sol.report.stop);
    assert!(sol.forces.iter().all(|v| *v >= 0.0 && v.is_finite()));
    let e = rel_err(&sol.forces, &c.exact);
    if norm_inf(&c.exact) == 0.0 {
        assert_eq!(e, 0.0, "{}", c.name);
    } else {
        assert!(e <= 1e-8, "{label}: relative error {e:e}");
    }
    assert_eq!(sol.report.residual_history.len(), sol.report.iterations);
}

/// Asserts that `sol` solves the problem (W, q) of [`redundant`] with the
/// regular (λ, g) = (`l0`, `g0`): converged, λ ≥ 0 and finite, the two
/// doubled points share the force of point 0 and both have zero gap, the
/// others as in the regular problem (to 1e-8 relative).
pub fn assert_solves_redundant(
    w: &Mat<f64>,
    q: &[f64],
    l0: &[f64],
    g0: &[f64],
    sol: &ContactSolution,
) {
    assert!(sol.report.converged, "{}", sol.report.stop);
    let l = &sol.forces;
    assert!(l.iter().all(|v| v.is_finite() && *v >= 0.0));
    let g = gaps(w, q, l);
    let scale = norm_inf(l0);
    assert!(((l[0] + l[1]) - l0[0]).abs() <= 1e-8 * scale);
    for i in 1..l0.len() {
        assert!((l[i + 1] - l0[i]).abs() <= 1e-8 * scale);
    }
    let gs = norm_inf(g0);
    assert!(g[0].abs() <= 1e-8 * gs && g[1].abs() <= 1e-8 * gs);
    for i in 1..g0.len() {
        assert!(
            (g[i + 1] - g0[i]).abs() <= 1e-8 * gs,
            "{} vs {}",
            g[i + 1],
            g0[i]
        );
    }
}

/// Asserts that a run stopped on its time limit after its first iteration,
/// not converged.
#[track_caller]
pub fn assert_stopped_by_the_time_limit_after_one_iteration(report: &SolverReport) {
    assert!(!report.converged);
    assert_eq!(report.iterations, 1);
    assert!(
        matches!(report.stop, StopReason::TimeLimit { iterations: 1, .. }),
        "{}",
        report.stop
    );
}
