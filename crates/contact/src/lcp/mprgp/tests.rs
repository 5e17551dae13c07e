//! Tests of [`super`] and [`crate::lcp::mprgp_box`]: MPRGP on the LCP (λ ≥ 0)
//! and on general boxes.

use super::*;
use crate::lcp::lemke::lemke;
use crate::lcp::mprgp_box::{box_residual, mprgp_box, mprgp_box_from};
use crate::lcp::projected_gradient::projected_conjugate_gradient;
use crate::lcp::projected_gradient::test_support::{
    assert_close, edge_cases, inf_norm, iterates_to_the_status_method, random_spd, random_vec,
    redundant_constraints, reports_iteration_limit, tight, Rng,
};
use crate::lcp::{gaps, lcp_residual, spectral_norm_estimate};
use proptest::prelude::*;

#[test]
fn mprgp_agrees_with_the_status_method() {
    iterates_to_the_status_method("mprgp", mprgp);
}

#[test]
fn mprgp_handles_redundant_constraints() {
    redundant_constraints(mprgp, false);
}

#[test]
fn mprgp_edge_cases() {
    edge_cases(mprgp);
    reports_iteration_limit(mprgp, 3);
}

#[test]
fn norm_estimate_is_close_to_the_largest_eigenvalue() {
    // Diagonal W: ‖W‖ = 5 exactly.
    let w = Mat::<f64>::from_fn(
        4,
        4,
        |i, j| if i == j { [1.0, 5.0, 2.0, 4.0][i] } else { 0.0 },
    );
    let (est, n) = spectral_norm_estimate(&w);
    assert!(n > 0 && (5.0 * 0.99..=5.0 * 1.02).contains(&est), "{est}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random SPD W and q: projected CG, MPRGP and Lemke all solve the
    /// LCP and agree with each other.
    #[test]
    fn pcg_mprgp_and_lemke_agree(m in 1usize..30, seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let w = random_spd(m, &mut rng);
        let q = random_vec(m, &mut rng);
        let opts = tight();
        let a = projected_conjugate_gradient(&w, &q, &opts).unwrap();
        let b = mprgp(&w, &q, &opts).unwrap();
        let c = lemke(&w, &q, &opts).unwrap();
        for s in [&a, &b, &c] {
            prop_assert!(s.report.converged, "{}: {}", s.report.method, s.report.stop);
            prop_assert!(s.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
            let r = lcp_residual(&w, &q, &s.forces, &opts);
            prop_assert!(r <= 1e-8, "{}: residual {r:e}", s.report.method);
        }
        let scale = inf_norm(&c.forces).max(1.0);
        for s in [&a, &b] {
            let d = s.forces.iter().zip(&c.forces).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            prop_assert!(d <= 1e-7 * scale, "{} vs lemke: {d:e}", s.report.method);
        }
    }
}

const INF: f64 = f64::INFINITY;

/// mprgp_box with l = 0, u = +∞: an LCP method.
fn as_lcp(w: &Mat<f64>, q: &[f64], opts: &LcpOptions) -> Result<ContactSolution, ContactError> {
    let m = q.len();
    mprgp_box(w, q, &vec![0.0; m], &vec![INF; m], opts)
}

/// Every x with each variable at its lower bound, free or at its upper
/// bound (3ⁿ combinations; infinite bounds skipped), the free part from
/// A_FF x_F = −b_F − A_FB x_B. Returns the KKT points and the others.
fn brute_force(a: &Mat<f64>, b: &[f64], l: &[f64], u: &[f64]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    use faer::prelude::Solve;
    let n = b.len();
    let (mut kkt, mut others) = (Vec::new(), Vec::new());
    'combo: for c in 0..3usize.pow(n as u32) {
        let status: Vec<usize> = (0..n).map(|i| (c / 3usize.pow(i as u32)) % 3).collect();
        let mut x = vec![0.0; n];
        for i in 0..n {
            x[i] = match status[i] {
                0 => l[i],
                2 => u[i],
                _ => 0.0,
            };
            if !x[i].is_finite() {
                continue 'combo;
            }
        }
        let free: Vec<usize> = (0..n).filter(|&i| status[i] == 1).collect();
        if !free.is_empty() {
            let nf = free.len();
            let aff = Mat::<f64>::from_fn(nf, nf, |r, s| a[(free[r], free[s])]);
            let rhs = Mat::<f64>::from_fn(nf, 1, |r, _| {
                let i = free[r];
                -(b[i]
                    + (0..n)
                        .filter(|&j| status[j] != 1)
                        .map(|j| a[(i, j)] * x[j])
                        .sum::<f64>())
            });
            let sol = aff.llt(faer::Side::Lower).unwrap().solve(&rhs);
            for (k, &i) in free.iter().enumerate() {
                x[i] = sol[(k, 0)];
            }
        }
        let g = gaps(a, b, &x);
        let tol = 1e-12;
        let ok = (0..n).all(|i| {
            x[i] >= l[i] - tol
                && x[i] <= u[i] + tol
                && match status[i] {
                    0 => g[i] >= -tol || l[i] == u[i],
                    2 => g[i] <= tol || l[i] == u[i],
                    _ => true,
                }
        });
        if ok {
            kkt.push(x);
        } else {
            others.push(x);
        }
    }
    (kkt, others)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// A Tresca-like problem: x = [λ_n; λ_t], l = [0; −g], u = [∞; g].
fn tresca(m: usize, seed: u64) -> (Mat<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let a = random_spd(2 * m, &mut rng);
    let b: Vec<f64> = random_vec(2 * m, &mut rng)
        .iter()
        .map(|v| 2.0 * v)
        .collect();
    let g: Vec<f64> = (0..m).map(|_| 0.05 + 0.5 * rng.uniform().abs()).collect();
    let mut l = vec![0.0; m];
    l.extend(g.iter().map(|v| -v));
    let mut u = vec![INF; m];
    u.extend(g.iter().copied());
    (a, b, l, u)
}

#[test]
fn mprgp_box_equals_mprgp_on_the_lcp() {
    let opts = tight();
    let mut rng = Rng::new(11);
    for m in [5, 20, 60] {
        let w = random_spd(m, &mut rng);
        let q = random_vec(m, &mut rng);
        let reference = mprgp(&w, &q, &opts).unwrap();
        let sol = as_lcp(&w, &q, &opts).unwrap();
        assert!(sol.report.converged, "{}", sol.report.stop);
        assert!(sol.forces.iter().all(|v| v.is_finite() && *v >= 0.0));
        let r = lcp_residual(&w, &q, &sol.forces, &opts);
        assert_eq!(sol.report.residual_history.last(), Some(&r));
        assert!(r <= 1e-12, "m = {m}: residual {r:.3e}");
        let d = max_diff(&sol.forces, &reference.forces);
        eprintln!(
            "m = {m}: mprgp_box {} iterations / {} products, mprgp {} / {}; ‖Δλ‖∞ = {d:.2e}, residual {r:.2e}; {}",
            sol.report.iterations,
            sol.report.operator_applications,
            reference.report.iterations,
            reference.report.operator_applications,
            sol.report.stop
        );
        assert!(
            d <= 1e-8 * inf_norm(&reference.forces).max(1.0),
            "m = {m}: {d:.3e}"
        );
        assert!(sol.forces.contains(&0.0) && sol.forces.iter().any(|v| *v > 0.0));
    }
}

#[test]
fn mprgp_box_passes_the_lcp_test_suite() {
    iterates_to_the_status_method("mprgp_box as LCP", as_lcp);
    redundant_constraints(as_lcp, false);
    edge_cases(as_lcp);
    reports_iteration_limit(as_lcp, 3);
}

#[test]
fn mprgp_box_tresca_matches_brute_force() {
    let opts = tight();
    let m = 3;
    // Which status each block reached over the seeds:
    // [normal at 0, normal free, tangent at −g, tangent free, tangent at +g].
    let mut seen = [0usize; 5];
    for seed in 0..40u64 {
        let (a, b, l, u) = tresca(m, seed);
        let (kkt, others) = brute_force(&a, &b, &l, &u);
        assert!(!kkt.is_empty(), "seed {seed}: no KKT point");
        for k in &kkt[1..] {
            assert!(
                max_diff(k, &kkt[0]) <= 1e-10,
                "seed {seed}: KKT points differ"
            );
        }
        assert!(kkt.len() + others.len() <= 729 && kkt.len() + others.len() == 216);
        let exact = &kkt[0];
        let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
        assert!(sol.report.converged, "seed {seed}: {}", sol.report.stop);
        let x = &sol.forces;
        assert!((0..2 * m).all(|i| x[i] >= l[i] && x[i] <= u[i]));
        let d = max_diff(x, exact);
        assert!(d <= 1e-10, "seed {seed}: ‖x − x_bf‖∞ = {d:.3e}");
        for i in 0..m {
            seen[if x[i] == 0.0 { 0 } else { 1 }] += 1;
            let t = m + i;
            seen[if x[t] == l[t] {
                2
            } else if x[t] == u[t] {
                4
            } else {
                3
            }] += 1;
        }
    }
    eprintln!("Tresca statuses over 40 seeds [n=0, n free, t=−g, t free, t=+g]: {seen:?}");
    assert!(seen.iter().all(|&c| c > 0), "{seen:?}");
}

#[test]
fn mprgp_box_with_fixed_and_two_sided_bounds_matches_brute_force() {
    let opts = tight();
    let (a, b, mut l, mut u) = tresca(3, 77);
    // Fix one tangential variable, bound a normal one from above, free one
    // variable on both sides.
    l[4] = 0.1;
    u[4] = 0.1;
    u[1] = 0.05;
    l[5] = -INF;
    u[5] = INF;
    let (kkt, _) = brute_force(&a, &b, &l, &u);
    let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
    assert!(sol.report.converged, "{}", sol.report.stop);
    assert_eq!(sol.forces[4], 0.1);
    let d = max_diff(&sol.forces, &kkt[0]);
    assert!(d <= 1e-10, "‖x − x_bf‖∞ = {d:.3e}");
}

#[test]
fn mprgp_box_all_fixed_returns_the_bounds() {
    let mut rng = Rng::new(5);
    let a = random_spd(7, &mut rng);
    let b = random_vec(7, &mut rng);
    let l = random_vec(7, &mut rng);
    let sol = mprgp_box(&a, &b, &l, &l, &tight()).unwrap();
    assert!(sol.report.converged, "{}", sol.report.stop);
    assert_eq!(sol.forces, l);
    assert_eq!(sol.report.iterations, 0);
    assert_eq!(sol.report.residual_history, vec![0.0]);
    assert_eq!(box_residual(&a, &b, &l, &l, &l, &tight()), 0.0);
}

#[test]
fn mprgp_box_unbounded_semidefinite_is_singular() {
    let opts = tight();
    // A = [[1, −1], [−1, 1]] (null vector (1, 1)), b = (−1, −1):
    // f(t, t) = −2t → −∞ on x ≥ 0.
    let a = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { 1.0 } else { -1.0 });
    let b = [-1.0, -1.0];
    let r = mprgp_box(&a, &b, &[0.0, 0.0], &[INF, INF], &opts);
    assert!(matches!(r, Err(ContactError::Singular(_))), "{r:?}");
    assert!(!format!("{:?}", r.unwrap_err()).contains("NaN"));
    // Tresca-like: the tangential pair unbounded on both sides.
    let r = mprgp_box(&a, &[0.5, 0.5], &[-INF, -INF], &[INF, INF], &opts);
    assert!(matches!(r, Err(ContactError::Singular(_))), "{r:?}");
    // A = 0 with b pointing to an infinite bound.
    let r = mprgp_box(
        &Mat::zeros(2, 2),
        &[-1.0, 1.0],
        &[0.0, 0.0],
        &[INF, 3.0],
        &opts,
    );
    assert!(matches!(r, Err(ContactError::Singular(_))), "{r:?}");
    // The same A = 0 with finite bounds: x = (l_0, u_1).
    let sol = mprgp_box(
        &Mat::zeros(2, 2),
        &[1.0, -1.0],
        &[0.0, 0.0],
        &[2.0, 3.0],
        &opts,
    )
    .unwrap();
    assert!(sol.report.converged);
    assert_eq!(sol.forces, vec![0.0, 3.0]);
    // Semi-definite but bounded by u_1 = 5: x = (6, 5).
    let sol = mprgp_box(&a, &b, &[0.0, 0.0], &[INF, 5.0], &opts).unwrap();
    assert!(sol.report.converged, "{}", sol.report.stop);
    assert_close(&sol.forces, &[6.0, 5.0], 1e-12, "bounded semi-definite");
    assert_eq!(
        box_residual(&a, &b, &[6.0, 5.0], &[0.0, 0.0], &[INF, 5.0], &opts),
        0.0
    );
}

#[test]
fn box_residual_is_zero_exactly_at_the_solution() {
    let opts = tight();
    // Exactly representable: x* = (1, 0.5, −0.25), x_0 and x_2 free,
    // x_1 at its upper bound with g_1 = −1.
    let a = Mat::<f64>::from_fn(3, 3, |i, j| {
        [[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]][i][j]
    });
    let b = [-4.5, -3.25, 0.0];
    let (l, u) = ([0.0, -0.5, -1.0], [INF, 0.5, 1.0]);
    let xs = [1.0, 0.5, -0.25];
    assert_eq!(box_residual(&a, &b, &xs, &l, &u, &opts), 0.0);
    let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
    assert!(sol.report.converged);
    assert_close(&sol.forces, &xs, 1e-14, "exact case");
    // Perturbations: free variable moved, bound variable moved inward,
    // a point outside the box.
    for (i, dx, expected) in [(0, 1e-3, 4e-3), (1, -1e-3, 1e-3), (2, -1.0, 1.8)] {
        let mut y = xs;
        y[i] += dx;
        let r = box_residual(&a, &b, &y, &l, &u, &opts);
        assert!(
            (r - expected).abs() <= 1e-12,
            "x_{i} + {dx}: residual {r:e}, expected {expected:e}"
        );
    }
    // Random Tresca problem: round-off zero at the brute-force solution,
    // positive at every other candidate of the enumeration.
    let (a, b, l, u) = tresca(3, 3);
    let (kkt, others) = brute_force(&a, &b, &l, &u);
    let r = box_residual(&a, &b, &kkt[0], &l, &u, &opts);
    assert!(r <= 1e-15, "at the solution: {r:e}");
    let rmin = others
        .iter()
        .filter(|x| max_diff(x, &kkt[0]) > 1e-12)
        .map(|x| box_residual(&a, &b, x, &l, &u, &opts))
        .fold(INF, f64::min);
    eprintln!("box_residual at the solution {r:.2e}, smallest elsewhere {rmin:.3e}");
    assert!(rmin > 1e-6, "{rmin:e}");
    // Non-finite data.
    assert_eq!(box_residual(&a, &b, &[f64::NAN; 6], &l, &u, &opts), INF);
}

#[test]
fn mprgp_box_converges_on_many_tresca_and_semidefinite_problems() {
    let opts = tight();
    let mut worst_iterations = 0;
    for seed in 0..200u64 {
        let m = 1 + (seed as usize) % 15;
        let (a, b, l, u) = tresca(m, 1000 + seed);
        let sol = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
        assert!(sol.report.converged, "seed {seed}: {}", sol.report.stop);
        assert!((0..2 * m).all(|i| sol.forces[i] >= l[i] && sol.forces[i] <= u[i]));
        let r = box_residual(&a, &b, &sol.forces, &l, &u, &opts);
        assert!(r <= 1e-12, "seed {seed}: residual {r:e}");
        assert_eq!(sol.report.residual_history.last(), Some(&r));
        worst_iterations = worst_iterations.max(sol.report.iterations);
        // Rank-deficient A = C Cᵀ (C is 2m × m) in the finite box [−1, 1]:
        // bounded, so it must converge.
        let mut rng = Rng::new(seed);
        let c = Mat::<f64>::from_fn(2 * m, m, |_, _| rng.uniform());
        let s = &c * c.transpose();
        let s = Mat::<f64>::from_fn(2 * m, 2 * m, |i, j| 0.5 * (s[(i, j)] + s[(j, i)]));
        let (lo, hi) = (vec![-1.0; 2 * m], vec![1.0; 2 * m]);
        let sol = mprgp_box(&s, &b, &lo, &hi, &opts).unwrap();
        assert!(
            sol.report.converged,
            "semi-definite seed {seed}: {}",
            sol.report.stop
        );
        let r = box_residual(&s, &b, &sol.forces, &lo, &hi, &opts);
        assert!(r <= 1e-12, "semi-definite seed {seed}: residual {r:e}");
    }
    eprintln!("Tresca m ≤ 15, 200 seeds: at most {worst_iterations} iterations");
}

#[test]
fn mprgp_box_rejects_bad_input_and_reports_the_limit() {
    let opts = LcpOptions::default();
    let a = Mat::<f64>::identity(3, 3);
    let b = [1.0, -1.0, 0.5];
    for (l, u, idx) in [
        ([0.0, 2.0, 0.0], [1.0, 1.0, 1.0], "[1]"),
        ([0.0, 0.0, f64::NAN], [1.0, 1.0, 1.0], "[2]"),
        ([INF, 0.0, 0.0], [INF, 1.0, 1.0], "[0]"),
        ([0.0, 0.0, 0.0], [1.0, -INF, 1.0], "[1]"),
    ] {
        match mprgp_box(&a, &b, &l, &u, &opts) {
            Err(ContactError::Solve(msg)) => assert!(msg.contains(idx), "{msg}"),
            other => panic!("{other:?}"),
        }
    }
    match mprgp_box(&a, &[1.0, f64::INFINITY, 0.0], &[0.0; 3], &[1.0; 3], &opts) {
        Err(ContactError::Solve(msg)) => assert!(msg.contains("b[1]"), "{msg}"),
        other => panic!("{other:?}"),
    }
    // Iteration limit on a Tresca problem: Ok, not converged, in the box.
    let (a, b, l, u) = tresca(20, 9);
    let sol = mprgp_box(
        &a,
        &b,
        &l,
        &u,
        &LcpOptions {
            tolerance: 1e-14,
            max_iterations: 2,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(!sol.report.converged);
    assert!(sol.report.stop.to_string().contains("not converged"));
    assert_eq!(sol.report.iterations, 2);
    assert!((0..40).all(|i| sol.forces[i] >= l[i] && sol.forces[i] <= u[i]));
    // Larger Tresca problem: converges to the tolerance.
    let sol = mprgp_box(&a, &b, &l, &u, &tight()).unwrap();
    assert!(sol.report.converged, "{}", sol.report.stop);
    assert!(box_residual(&a, &b, &sol.forces, &l, &u, &tight()) <= 1e-12);
    eprintln!("Tresca m = 20: {}", sol.report.stop);
}

/// The warm start: from the solution no iteration is made; from a start
/// outside the box (projected first) the same solution is found; a start of
/// the wrong length or with a NaN is an input error.
#[test]
fn mprgp_warm_start_is_projected_and_reused() {
    let opts = tight();
    let (a, b, l, u) = tresca(8, 21);
    let cold = mprgp_box(&a, &b, &l, &u, &opts).unwrap();
    assert!(cold.report.converged, "{}", cold.report.stop);
    let again = mprgp_box_from(&a, &b, &l, &u, &cold.forces, &opts).unwrap();
    assert!(again.report.converged, "{}", again.report.stop);
    assert_eq!(again.report.iterations, 0);
    assert_eq!(again.forces, cold.forces);
    let outside: Vec<f64> = (0..16)
        .map(|i| if i % 2 == 0 { -5.0 } else { 5.0 })
        .collect();
    let warm = mprgp_box_from(&a, &b, &l, &u, &outside, &opts).unwrap();
    assert!(warm.report.converged, "{}", warm.report.stop);
    let scale = inf_norm(&cold.forces).max(1.0);
    assert!(max_diff(&warm.forces, &cold.forces) <= 1e-10 * scale);
    // The LCP entry point: λ0 < 0 is set to zero.
    let mut rng = Rng::new(4);
    let w = random_spd(20, &mut rng);
    let q = random_vec(20, &mut rng);
    let reference = mprgp(&w, &q, &opts).unwrap();
    let warm = mprgp_from(&w, &q, &[-1.0; 20], &opts).unwrap();
    assert_eq!(warm.forces, reference.forces);
    assert_eq!(warm.report.iterations, reference.report.iterations);
    let from_solution = mprgp_from(&w, &q, &reference.forces, &opts).unwrap();
    assert!(from_solution.report.converged && from_solution.report.iterations == 0);
    for bad in [vec![0.0; 19], vec![f64::NAN; 20]] {
        assert!(matches!(
            mprgp_from(&w, &q, &bad, &opts),
            Err(ContactError::Solve(_))
        ));
        assert!(matches!(
            mprgp_box_from(&w, &q, &[0.0; 20], &[INF; 20], &bad, &opts),
            Err(ContactError::Solve(_))
        ));
    }
}
