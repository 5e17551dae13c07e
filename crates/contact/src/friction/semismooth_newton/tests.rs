//! The semi-smooth Newton method on Coulomb's law against the fixed point
//! (2D: status method inner solves, and the friction status method; 3D:
//! Newton inner solves) (course notes §4.3, §4.5).

use faer::Mat;

use crate::active_set::friction_status::coulomb_status;
use crate::friction::friction3d::{coulomb_3d_fixed_point, friction_3d};
use crate::friction::{
    coulomb_fixed_point, coulomb_newton, FrictionLaw, FrictionLayout, FrictionOptions, PointStatus,
};
use crate::test_problems::{random_spd, XorShift};

use super::{Inner, NewtonSystem, Scale};
use crate::{ContactSolution, DelassusProblem};

fn opts() -> FrictionOptions {
    FrictionOptions {
        max_iterations: 200,
        max_fixed_point: 200,
        tolerance: 1e-11,
        force_scale: 1.0,
        gap_scale: 1.0,
        deadline: None,
    }
}

/// m points in 2D (normal rows 0..m, tangential row m + p), W random SPD,
/// about half the points pressed, pulled sideways; μ 0.2 to 0.6.
fn random_2d(m: usize, seed: u64) -> (DelassusProblem, FrictionLayout) {
    let mut rng = XorShift(seed);
    let problem = random_problem(m, 2 * m, &mut rng);
    let layout = FrictionLayout {
        tangent_rows: (0..m).map(|p| vec![m + p]).collect(),
        law: (0..m)
            .map(|p| FrictionLaw::coulomb(0.2 + 0.1 * (p % 5) as f64))
            .collect(),
        shadow: vec![None; m],
    };
    (problem, layout)
}

/// A random SPD W of `n` rows and q: the first `m` (normal) rows about half
/// pressed, the others pulled sideways.
fn random_problem(m: usize, n: usize, rng: &mut XorShift) -> DelassusProblem {
    let w = random_spd(n, rng);
    let q: Vec<f64> = (0..n)
        .map(|i| {
            if i < m {
                rng.uniform(-1.0, 0.6)
            } else {
                rng.uniform(-0.8, 0.8)
            }
        })
        .collect();
    DelassusProblem::from_operator(w, q)
}

/// The statuses agree and the forces and gaps are within `tol`.
fn assert_same(a: &ContactSolution, b: &ContactSolution, tol: f64, what: &str) {
    assert!(
        a.report.converged && b.report.converged,
        "{what}: {} / {}",
        a.report.stop,
        b.report.stop
    );
    assert_eq!(a.friction.points, b.friction.points, "{what}");
    for (i, (x, y)) in a.forces.iter().zip(&b.forces).enumerate() {
        assert!((x - y).abs() <= tol, "{what}: force {i}: {x} vs {y}");
    }
    for (i, (x, y)) in a.gaps.iter().zip(&b.gaps).enumerate() {
        assert!((x - y).abs() <= tol, "{what}: gap {i}: {x} vs {y}");
    }
}

/// Adds the points of `points` to `seen`'s counts of open, stick and slip.
fn count_statuses(seen: &mut [usize; 3], points: &[PointStatus]) {
    for st in points {
        seen[match st {
            PointStatus::Open => 0,
            PointStatus::Stick => 1,
            _ => 2,
        }] += 1;
    }
}

#[test]
fn newton_agrees_with_the_fixed_point_and_the_status_method_in_2d() {
    let mut seen = [0usize; 3];
    for (m, seed) in [(2, 3), (4, 5), (8, 7), (16, 11), (30, 13)] {
        let (p, layout) = random_2d(m, seed);
        // Initially closed points start stuck.
        let closed = |q: &f64| *q <= 0.0;
        let start_status = |c| [PointStatus::Open, PointStatus::Stick][c as usize];
        let initial: Vec<PointStatus> = p.q[..m].iter().map(closed).map(start_status).collect();
        let fresh = || DelassusProblem::from_operator(p.w.clone(), p.q.clone());
        let newton = coulomb_newton(&mut fresh(), &layout, None, &opts()).unwrap();
        assert_eq!(newton.friction.fixed_point_iterations, 0, "m = {m}: direct");
        let fp =
            coulomb_fixed_point(&mut fresh(), &layout, initial.clone(), None, &opts()).unwrap();
        let status = coulomb_status(&mut fresh(), &layout, initial, &opts()).unwrap();
        assert_same(&newton, &fp, 1e-9, &format!("m = {m}, fixed point"));
        assert_same(&newton, &status, 1e-9, &format!("m = {m}, status method"));
        count_statuses(&mut seen, &newton.friction.points);
    }
    assert!(seen.iter().all(|&c| c > 0), "open, stick, slip: {seen:?}");
}

/// Two nodes A, B on a plane joined by a spring along x (k = 2), free in x
/// (the rigid mode: both translate), held normally (5): A pulled by Q = 1
/// pressed by 1, B pressed by 5, μ = 0.5: A slips at μ N_A = 0.5 and B holds
/// the rest, 0.5 < μ N_B = 2.5.
fn two_nodes_held_by_friction() -> DelassusProblem {
    let k = 2.0;
    let s = Mat::<f64>::from_fn(4, 4, |i, j| match (i, j) {
        (0, 0) | (2, 2) => k,
        (0, 2) | (2, 0) => -k,
        (1, 1) | (3, 3) => 5.0,
        _ => 0.0,
    });
    let r = std::f64::consts::FRAC_1_SQRT_2;
    let kernel = Mat::<f64>::from_fn(4, 1, |i, _| if i % 2 == 0 { r } else { 0.0 });
    // Rows: normals y_A, y_B; tangents x_A, x_B.
    let rows = vec![
        vec![(1, 1.0)],
        vec![(3, 1.0)],
        vec![(0, 1.0)],
        vec![(2, 1.0)],
    ];
    DelassusProblem::new(&s, &rows, &[0.0; 4], &[1.0, -1.0, 0.0, -5.0], &kernel).unwrap()
}

#[test]
fn newton_holds_a_floating_body_by_friction_like_the_fixed_point() {
    let layout = FrictionLayout {
        tangent_rows: vec![vec![2], vec![3]],
        law: vec![FrictionLaw::coulomb(0.5); 2],
        shadow: vec![None; 2],
    };
    let mut p = two_nodes_held_by_friction();
    assert_eq!(p.n_kernel(), 1);
    let newton = coulomb_newton(&mut p, &layout, None, &opts()).unwrap();
    assert_eq!(
        newton.friction.points,
        vec![PointStatus::SlipMinus, PointStatus::Stick]
    );
    let expected = [1.0, 5.0, -0.5, -0.5];
    for (i, (x, y)) in newton.forces.iter().zip(expected).enumerate() {
        assert!((x - y).abs() < 1e-10, "force {i}: {x} vs {y}");
    }
    // A slips in +x, against its friction force.
    assert!(newton.gaps[2] > 1e-3 && newton.gaps[3].abs() < 1e-10);
    let mut q = two_nodes_held_by_friction();
    let initial = vec![PointStatus::Stick; 2];
    let fp = coulomb_fixed_point(&mut q, &layout, initial, None, &opts()).unwrap();
    assert_same(&newton, &fp, 1e-10, "floating body");
}

/// m points in 3D (normal rows 0..m, then each point's tangential rows:
/// two, or one for every fifth point — a support along t2), W random SPD,
/// about half the points pressed, pulled sideways; μ 0.2 to 0.6, every
/// third point anisotropic (μ2 = 2 μ1) when `anisotropic`.
fn random_3d(m: usize, seed: u64, anisotropic: bool) -> (DelassusProblem, FrictionLayout) {
    let mut rng = XorShift(seed);
    let mut tangent_rows = Vec::new();
    let mut next = m;
    for p in 0..m {
        let k = if p % 5 == 4 { 1 } else { 2 };
        tangent_rows.push((next..next + k).collect::<Vec<usize>>());
        next += k;
    }
    let problem = random_problem(m, next, &mut rng);
    let law = (0..m)
        .map(|p| {
            let mu = 0.2 + 0.1 * (p % 5) as f64;
            let mu2 = if anisotropic && p % 3 == 0 {
                2.0 * mu
            } else {
                mu
            };
            FrictionLaw::Coulomb { mu: [mu, mu2] }
        })
        .collect();
    let layout = FrictionLayout {
        tangent_rows,
        law,
        shadow: vec![None; m],
    };
    (problem, layout)
}

#[test]
fn newton_on_coulomb_agrees_with_the_fixed_point_in_3d() {
    let mut seen = [0usize; 3];
    for (m, seed, anisotropic) in [
        (2, 3, false),
        (5, 5, false),
        (10, 7, true),
        (20, 11, false),
        (30, 13, true),
    ] {
        let (p, layout) = random_3d(m, seed, anisotropic);
        let fresh = || DelassusProblem::from_operator(p.w.clone(), p.q.clone());
        let newton = friction_3d(&mut fresh(), &layout, None, &opts()).unwrap();
        let fp = coulomb_3d_fixed_point(&mut fresh(), &layout, None, &opts()).unwrap();
        let what = format!("m = {m}");
        // The direct method itself converged, no fallback.
        assert_eq!(
            newton.report.method, "coulomb_3d_semismooth_newton",
            "{what}"
        );
        assert_eq!(newton.friction.fixed_point_iterations, 0, "{what}");
        assert_eq!(fp.report.method, "coulomb_3d_fixed_point", "{what}");
        assert_same(&newton, &fp, 1e-9, &what);
        count_statuses(&mut seen, &newton.friction.points);
    }
    assert!(seen.iter().all(|&c| c > 0), "open, stick, slip: {seen:?}");
}

/// Cut short (two Newton iterations in all), neither the direct method nor
/// its fixed-point fallback converges, and the solution says so.
#[test]
fn newton_on_coulomb_cut_short_is_not_reported_converged() {
    let (p, layout) = random_3d(30, 13, true);
    let o = FrictionOptions {
        max_iterations: 2,
        max_fixed_point: 2,
        ..opts()
    };
    let mut q = DelassusProblem::from_operator(p.w.clone(), p.q.clone());
    let out = friction_3d(&mut q, &layout, None, &o).unwrap();
    assert!(!out.report.converged, "{}", out.report.stop);
    assert_eq!(out.report.method, "coulomb_3d_fixed_point");
}

/// Newton tells an observer (crate::observe) of each iterate: from 0 within
/// each inner solve, the last within the tolerance, with the points of
/// positive normal force of the answer in contact.
#[test]
fn newton_reports_each_iterate_to_an_observer() {
    use crate::observe::{observed, Iteration};
    use std::{cell::RefCell, rc::Rc};
    let m = 16;
    let (mut p, layout) = random_2d(m, 11);
    let seen: Rc<RefCell<Vec<Iteration>>> = Rc::default();
    let log = seen.clone();
    let sol = observed(
        move |i: &Iteration| log.borrow_mut().push(*i),
        || coulomb_newton(&mut p, &layout, None, &opts()).unwrap(),
    );
    let seen = seen.borrow();
    assert!(sol.report.converged);
    assert!(seen.len() > 2, "{seen:?}");
    assert!(seen.iter().all(|i| i.method == "newton"));
    assert_eq!(seen[0].iteration, 0);
    assert!(seen
        .windows(2)
        .all(|w| w[1].iteration == w[0].iteration + 1 || w[1].iteration == 0));
    let last = seen[seen.len() - 1];
    assert!(last.residual <= 1.0 && seen[0].residual > 1.0, "{seen:?}");
    let lmax = sol.forces[..m].iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let pressed = sol.forces[..m]
        .iter()
        .filter(|&&l| l > opts().tolerance * lmax.max(1.0))
        .count();
    assert_eq!(last.active, pressed);
    assert!(pressed > 0 && pressed < m);
}

/// A Newton system on Coulomb's law itself at an iterate with slipping
/// points (two steps from zero forces on a random 3D problem): its rows and
/// the problem.
fn coulomb_system_with_slip() -> (DelassusProblem, NewtonSystem, usize) {
    coulomb_system_after(2)
}

/// The Coulomb Newton system of a random 3D problem after `steps` steps.
fn coulomb_system_after(steps: usize) -> (DelassusProblem, NewtonSystem, usize) {
    let (p, layout) = random_3d(30, 13, true);
    let thr = layout.thresholds(&vec![0.0; p.q.len()]);
    let mut inner = Inner::new(&p, &layout, &thr);
    inner.law.coulomb = true;
    let mut x = inner.iterate(inner.start(&vec![0.0; p.q.len()]));
    let mut sys = NewtonSystem::default();
    for _ in 0..steps {
        inner.newton_step(&mut x, &mut sys);
    }
    inner.residual(&x, Scale::Newton, Some(&mut sys));
    let slipping = sys.given_normal.len();
    sys.factor = None;
    (p, sys, slipping)
}

/// The reduced Newton step, bordered (Cholesky on the symmetric unknowns,
/// LU of the Schur complement on the slipping points' normal forces), is
/// the step of the full system by a fully pivoted LU; a chord step on the
/// same structure reuses the factor and gives the same step.
#[test]
fn bordered_newton_step_matches_the_full_solve() {
    let (p, sys, slipping) = coulomb_system_with_slip();
    assert!(slipping > 0, "no slipping point at the iterate");
    let (w, g) = (&p.w, &p.g_mat);
    let mut cache = None;
    let dx = crate::reduced::solve_newton(w, g, &sys, &mut cache, false).unwrap();
    assert!(cache.as_ref().unwrap().is_bordered());
    let full = sys.solve_full(w, g).unwrap();
    let scale = full.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(scale > 0.0);
    for (i, (a, b)) in dx.iter().zip(&full).enumerate() {
        assert!((a - b).abs() <= 1e-9 * scale, "row {i}: {a} vs {b}");
    }
    let chord = crate::reduced::solve_newton(w, g, &sys, &mut cache, true).unwrap();
    for (i, (a, b)) in chord.iter().zip(&dx).enumerate() {
        assert!((a - b).abs() <= 1e-12 * scale, "chord row {i}: {a} vs {b}");
    }
}

/// A reduced Newton step factorised in the storage of another step's factor
/// (a block of another size, its old entries left where the new block does
/// not write) is still the step of the full system.
#[test]
fn newton_steps_in_recycled_storage_match_the_full_solve() {
    let systems: Vec<_> = (0..4).map(coulomb_system_after).collect();
    let mut cache = None;
    for (p, sys, _) in systems.iter().chain(systems.iter().rev()) {
        let (w, g) = (&p.w, &p.g_mat);
        let dx = crate::reduced::solve_newton(w, g, sys, &mut cache, false).unwrap();
        let full = sys.solve_full(w, g).unwrap();
        let scale = full.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(scale > 0.0);
        for (i, (a, b)) in dx.iter().zip(&full).enumerate() {
            assert!((a - b).abs() <= 1e-9 * scale, "row {i}: {a} vs {b}");
        }
    }
    let sizes: Vec<usize> = systems.iter().map(|(_, s, _)| s.coupled.len()).collect();
    assert!(
        sizes.windows(2).any(|w| w[0] != w[1]),
        "one block size only: {sizes:?}"
    );
}

/// A bound μ λ_n of a round-off λ_n (1e-170: ḡ² underflows, c = ρ/ḡ² is
/// infinite) is a zero bound: the residual is finite and asks λ_t = 0,
/// where it was NaN — which a stopping test reading f64::max took for zero
/// (a pile of 64 rigid spheres "converged" to NaN forces).
#[test]
fn a_bound_of_round_off_is_a_zero_bound_not_a_nan() {
    let w = random_spd(3, &mut XorShift(5));
    let p = DelassusProblem::from_operator(w, vec![-1.0, 0.3, -0.2]);
    let layout = FrictionLayout {
        tangent_rows: vec![vec![1, 2]],
        law: vec![FrictionLaw::coulomb(0.3)],
        shadow: vec![None],
    };
    let x = [1.0, 0.25, -0.5];
    for (tiny, scale) in [
        (1e-170, Scale::Check(1.0)),
        (1e-170, Scale::Newton),
        (0.0, Scale::Newton),
    ] {
        let thr = [[tiny; 2]];
        let inner = Inner::new(&p, &layout, &thr);
        let f = inner.residual(&inner.iterate(x.to_vec()), scale, None);
        assert!(f.iter().all(|v| v.is_finite()), "bound {tiny:e}: {f:?}");
        assert_eq!(&f[1..], &x[1..], "bound {tiny:e}: λ_t driven to zero");
    }
}
