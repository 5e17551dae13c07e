//! Tests of [`super`]: the three-dimensional Coulomb friction solver.

use super::*;
use crate::friction::{FrictionLaw, PointStatus};
use faer::Mat;

fn opts() -> FrictionOptions {
    FrictionOptions {
        max_iterations: 100,
        max_fixed_point: 200,
        tolerance: 1e-12,
        force_scale: 1.0,
        gap_scale: 1.0,
        deadline: None,
    }
}

fn one_point_layout(law: FrictionLaw) -> FrictionLayout {
    FrictionLayout {
        tangent_rows: vec![vec![1, 2]],
        law: vec![law],
        shadow: Vec::new(),
    }
}

/// W = diag(kn, kt, kt), pushed by a penetration d, driven by s0 along (cos θ, sin θ).
fn one_point(kn: f64, kt: f64, d: f64, s0: f64, theta: f64) -> DelassusProblem {
    let w = Mat::<f64>::from_fn(3, 3, |i, j| match (i, j) {
        (0, 0) => kn,
        (1, 1) | (2, 2) => kt,
        _ => 0.0,
    });
    DelassusProblem::from_operator(w, vec![-d, s0 * theta.cos(), s0 * theta.sin()])
}

#[test]
fn a_point_sticks_below_the_cone_and_slips_on_it_in_any_direction() {
    let (kn, kt, d, mu) = (5.0, 2.0, 0.6, 0.5);
    let ln = d / kn; // 0.12, threshold μ λ_n = 0.06
    for k in 0..12 {
        let theta = 0.37 + k as f64 * std::f64::consts::PI / 6.0;
        let dir = [theta.cos(), theta.sin()];
        let law = FrictionLaw::Coulomb { mu: [mu, mu] };
        // Drive 0.02: the stuck reaction s0 / kt = 0.01 < 0.06.
        let mut p = one_point(kn, kt, d, 0.02, theta);
        let out = friction_3d(&mut p, &one_point_layout(law), None, &opts()).unwrap();
        assert!(out.report.converged, "{}", out.report.stop);
        assert_eq!(out.friction.points, vec![PointStatus::Stick]);
        assert!((out.forces[0] - ln).abs() < 1e-12 * ln);
        for (i, di) in dir.iter().enumerate() {
            assert!(
                (out.forces[1 + i] + 0.01 * di).abs() < 1e-12,
                "{:?}",
                out.forces
            );
            assert!(out.gaps[1 + i].abs() < 1e-12);
        }
        // Drive 0.2: s0 / kt = 0.1 > 0.06: slips by 0.2 − kt · 0.06 = 0.08.
        let mut p = one_point(kn, kt, d, 0.2, theta);
        let out = friction_3d(&mut p, &one_point_layout(law), None, &opts()).unwrap();
        assert!(out.report.converged, "{}", out.report.stop);
        assert_eq!(out.friction.points, vec![PointStatus::Slip]);
        let lt = [out.forces[1], out.forces[2]];
        let s = [out.gaps[1], out.gaps[2]];
        assert!((lt[0].hypot(lt[1]) - mu * out.forces[0]).abs() < 1e-9 * mu * ln);
        for i in 0..2 {
            assert!(
                (lt[i] + mu * ln * dir[i]).abs() < 1e-12,
                "θ {theta}: {lt:?}"
            );
            assert!((s[i] - 0.08 * dir[i]).abs() < 1e-12, "θ {theta}: {s:?}");
        }
        // Exactly opposite to the slip.
        let cross = lt[0] * s[1] - lt[1] * s[0];
        assert!(cross.abs() < 1e-12 * lt[0].hypot(lt[1]) * s[0].hypot(s[1]));
        assert!(lt[0] * s[0] + lt[1] * s[1] < 0.0);
        assert!(out.report.residual_history.last().unwrap() <= &1e-12);
    }
}

#[test]
fn tresca_point_slips_at_its_threshold() {
    let mut p = one_point(5.0, 2.0, 0.6, 0.1, 1.0);
    let out = friction_3d(
        &mut p,
        &one_point_layout(FrictionLaw::Tresca(0.03)),
        None,
        &opts(),
    )
    .unwrap();
    assert!(out.report.converged);
    assert_eq!(out.friction.points, vec![PointStatus::Slip]);
    assert!((out.forces[1].hypot(out.forces[2]) - 0.03).abs() < 1e-12);
    assert!((out.gaps[1].hypot(out.gaps[2]) - (0.1 - 2.0 * 0.03)).abs() < 1e-12);
    assert_eq!(out.friction.fixed_point_iterations, 0);
}

/// The elliptic cone: the force on (λ1/μ1)² + (λ2/μ2)² = λ_n², its outward
/// normal (λ1/μ1², λ2/μ2²) along −Δs.
fn check_ellipse_slip(lt: [f64; 2], s: [f64; 2], a: [f64; 2]) {
    let phi = (lt[0] / a[0]).powi(2) + (lt[1] / a[1]).powi(2);
    assert!((phi - 1.0).abs() < 1e-9, "φ = {phi}");
    let nrm = [lt[0] / (a[0] * a[0]), lt[1] / (a[1] * a[1])];
    let cross = nrm[0] * s[1] - nrm[1] * s[0];
    let size = nrm[0].hypot(nrm[1]) * s[0].hypot(s[1]);
    assert!(cross.abs() < 1e-9 * size, "normal {nrm:?}, slip {s:?}");
    assert!(nrm[0] * s[0] + nrm[1] * s[1] < 0.0);
}

#[test]
fn elliptic_cone_bounds_each_direction_by_its_coefficient() {
    let (kn, kt, d) = (5.0, 2.0, 0.6);
    let ln = d / kn;
    let law = FrictionLaw::Coulomb { mu: [0.3, 0.1] };
    for (theta, mu) in [(0.0, 0.3), (std::f64::consts::FRAC_PI_2, 0.1)] {
        let mut p = one_point(kn, kt, d, 1.0, theta);
        let out = friction_3d(&mut p, &one_point_layout(law), None, &opts()).unwrap();
        assert!(out.report.converged, "{}", out.report.stop);
        assert_eq!(out.friction.points, vec![PointStatus::Slip]);
        let lt = out.forces[1].hypot(out.forces[2]);
        assert!((lt - mu * ln).abs() < 1e-9 * mu * ln, "{:?}", out.forces);
    }
    // A diagonal drive: not along the force, but along the ellipse's normal.
    let mut p = one_point(kn, kt, d, 1.0, std::f64::consts::FRAC_PI_4);
    let out = friction_3d(&mut p, &one_point_layout(law), None, &opts()).unwrap();
    assert!(out.report.converged, "{}", out.report.stop);
    assert_eq!(out.friction.points, vec![PointStatus::Slip]);
    let lt = [out.forces[1], out.forces[2]];
    let s = [out.gaps[1], out.gaps[2]];
    check_ellipse_slip(lt, s, [0.3 * out.forces[0], 0.1 * out.forces[0]]);
    // The slip is not parallel to the force.
    assert!((lt[0] * s[1] - lt[1] * s[0]).abs() > 1e-3 * lt[0].hypot(lt[1]) * s[0].hypot(s[1]));
}

#[test]
fn a_coupled_point_slips_opposite_to_its_slip() {
    // A full SPD W (normal-tangential coupling): fixed point needed.
    let w = Mat::<f64>::from_fn(3, 3, |i, j| {
        [[4.0, 0.8, -0.5], [0.8, 2.0, 0.3], [-0.5, 0.3, 1.5]][i][j]
    });
    for mu in [[0.4, 0.4], [0.5, 0.2]] {
        let mut p = DelassusProblem::from_operator(w.clone(), vec![-1.0, 0.7, -0.4]);
        let out = friction_3d(
            &mut p,
            &one_point_layout(FrictionLaw::Coulomb { mu }),
            None,
            &opts(),
        )
        .unwrap();
        assert!(out.report.converged, "{}", out.report.stop);
        assert_eq!(out.friction.points, vec![PointStatus::Slip]);
        assert!(out.gaps[0].abs() < 1e-12);
        let a = [mu[0] * out.forces[0], mu[1] * out.forces[0]];
        check_ellipse_slip(
            [out.forces[1], out.forces[2]],
            [out.gaps[1], out.gaps[2]],
            a,
        );
    }
}

/// Pseudo-random numbers in [−1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn random_problem(m: usize, seed: u64) -> (DelassusProblem, FrictionLayout) {
    let n = 3 * m;
    let mut rng = Lcg(seed);
    let a = Mat::<f64>::from_fn(n, n, |_, _| rng.next());
    let mut w = &a * a.transpose();
    for i in 0..n {
        w[(i, i)] += 0.1 * n as f64;
    }
    let q: Vec<f64> = (0..n)
        .map(|i| {
            if i < m {
                rng.next() - 0.3
            } else {
                0.5 * rng.next()
            }
        })
        .collect();
    let layout = FrictionLayout {
        tangent_rows: (0..m).map(|p| vec![m + 2 * p, m + 2 * p + 1]).collect(),
        law: (0..m)
            .map(|p| match p % 3 {
                0 => FrictionLaw::Coulomb { mu: [0.3, 0.3] },
                1 => FrictionLaw::Coulomb { mu: [0.6, 0.15] },
                _ => FrictionLaw::Coulomb { mu: [0.1, 0.4] },
            })
            .collect(),
        shadow: Vec::new(),
    };
    (DelassusProblem::from_operator(w, q), layout)
}

/// Every condition of the law at every point, to `tol` (relative to the
/// largest force and gap).
fn check_conditions(out: &ContactSolution, layout: &FrictionLayout, tol: f64) {
    let fs = out.forces.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    let gs = out.gaps.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    for (p, (rows, law)) in layout.tangent_rows.iter().zip(&layout.law).enumerate() {
        let (ln, gn) = (out.forces[p], out.gaps[p]);
        assert!(
            ln >= -tol * fs && gn >= -tol * gs,
            "point {p}: λ {ln}, g {gn}"
        );
        assert!(
            (ln * gn).abs() <= tol * fs * gs,
            "point {p}: λ g = {}",
            ln * gn
        );
        let (&[a, b], FrictionLaw::Coulomb { mu }) = (&rows[..], law) else {
            continue;
        };
        let lt = [out.forces[a], out.forces[b]];
        let s = [out.gaps[a], out.gaps[b]];
        let ax = [mu[0] * ln.max(0.0), mu[1] * ln.max(0.0)];
        if ax[0] <= tol * fs {
            assert!(lt[0].hypot(lt[1]) <= tol * fs);
            continue;
        }
        let phi = ((lt[0] / ax[0]).powi(2) + (lt[1] / ax[1]).powi(2)).sqrt();
        // Distances to the boundary in force units.
        let amin = ax[0].min(ax[1]);
        assert!(
            (phi - 1.0) * amin <= tol * fs,
            "point {p}: outside the cone, φ = {phi}"
        );
        match out.friction.points[p] {
            PointStatus::Stick => {
                assert!(s[0].hypot(s[1]) <= tol * gs, "point {p}: stuck slips {s:?}")
            }
            PointStatus::Slip => {
                assert!(
                    (phi - 1.0).abs() * amin <= tol * fs,
                    "point {p}: slip inside the cone, φ = {phi}"
                );
                // Δs = −γ ∇φ: maximal dissipation.
                let nrm = [lt[0] / (ax[0] * ax[0]), lt[1] / (ax[1] * ax[1])];
                let size = nrm[0].hypot(nrm[1]) * s[0].hypot(s[1]);
                let angle = tol * (fs / amin + gs / s[0].hypot(s[1]));
                assert!(
                    (nrm[0] * s[1] - nrm[1] * s[0]).abs() <= angle * size,
                    "point {p}: slip {s:?} not along the normal {nrm:?}"
                );
                assert!(nrm[0] * s[0] + nrm[1] * s[1] < 0.0);
            }
            st => panic!("point {p}: unexpected status {st:?}"),
        }
    }
}

#[test]
fn random_problems_satisfy_every_condition() {
    let mut seen_slip = 0;
    let mut seen_stick = 0;
    let mut seen_open = 0;
    for (m, seed) in [(2, 1), (3, 2), (5, 3), (8, 4), (20, 5), (40, 6)] {
        let (mut p, layout) = random_problem(m, seed);
        let mut o = opts();
        o.tolerance = 1e-10;
        let out = friction_3d(&mut p, &layout, None, &o).unwrap();
        assert!(out.report.converged, "m = {m}: {}", out.report.stop);
        check_conditions(&out, &layout, 1e-8);
        for st in &out.friction.points {
            match st {
                PointStatus::Slip => seen_slip += 1,
                PointStatus::Stick => seen_stick += 1,
                _ => seen_open += 1,
            }
        }
        // Restarted from its own answer: converges at once to the same forces.
        let again = friction_3d(&mut p, &layout, Some(&out.forces), &o).unwrap();
        assert!(again.report.converged);
        assert!(again.friction.fixed_point_iterations <= 2);
        for (x, y) in again.forces.iter().zip(&out.forces) {
            assert!((x - y).abs() < 1e-8);
        }
    }
    assert!(
        seen_slip > 0 && seen_stick > 0 && seen_open > 0,
        "{seen_slip} {seen_stick} {seen_open}"
    );
}

#[test]
fn zero_friction_equals_the_frictionless_answer() {
    let m = 6;
    let (p, mut layout) = random_problem(m, 11);
    for law in layout.law.iter_mut() {
        *law = FrictionLaw::Coulomb { mu: [0.0, 0.0] };
    }
    let mut pf = DelassusProblem::from_operator(p.w.clone(), p.q.clone());
    let out = friction_3d(&mut pf, &layout, None, &opts()).unwrap();
    assert!(out.report.converged, "{}", out.report.stop);
    // Frictionless: only the normal rows, W_nn.
    let wn = Mat::<f64>::from_fn(m, m, |i, j| p.w[(i, j)]);
    let mut pn = DelassusProblem::from_operator(wn, p.q[..m].to_vec());
    let none = FrictionLayout {
        tangent_rows: vec![vec![]; m],
        law: vec![FrictionLaw::None; m],
        shadow: Vec::new(),
    };
    let plain = friction_3d(&mut pn, &none, None, &opts()).unwrap();
    assert!(plain.report.converged);
    for i in 0..m {
        assert!((out.forces[i] - plain.forces[i]).abs() < 1e-10, "{i}");
        assert!((out.gaps[i] - plain.gaps[i]).abs() < 1e-10, "{i}");
    }
    assert!(out.forces[m..].iter().all(|v| v.abs() < 1e-12));
    // And it is the LCP answer.
    let lcp = crate::lcp::lcp_residual(&pn.w, &pn.q, &plain.forces, &crate::LcpOptions::default());
    assert!(lcp < 1e-10);
}

#[test]
fn a_floating_body_held_by_friction_alone() {
    // One node resting on a plane: stiff normally, free tangentially (the
    // kernel: translations x, y). Load (fx, fy, −fn).
    let s = Mat::<f64>::from_fn(3, 3, |i, j| if i == j && i == 2 { 5.0 } else { 0.0 });
    let kernel = Mat::<f64>::from_fn(3, 2, |i, j| if i == j { 1.0 } else { 0.0 });
    let rows = vec![vec![(2, 1.0)], vec![(0, 1.0)], vec![(1, 1.0)]];
    let (fx, fy, fn_) = (0.3, -0.2, 2.0);
    let mut p = DelassusProblem::new(&s, &rows, &[0.0; 3], &[fx, fy, -fn_], &kernel).unwrap();
    assert_eq!(p.n_kernel(), 2);
    let law = FrictionLaw::Coulomb { mu: [0.5, 0.5] };
    let out = friction_3d(&mut p, &one_point_layout(law), None, &opts()).unwrap();
    assert!(out.report.converged, "{}", out.report.stop);
    assert_eq!(out.friction.points, vec![PointStatus::Stick]);
    assert!((out.forces[0] - fn_).abs() < 1e-12);
    assert!((out.forces[1] + fx).abs() < 1e-12 && (out.forces[2] + fy).abs() < 1e-12);
    assert!(out.gaps[1].abs() < 1e-12 && out.gaps[2].abs() < 1e-12);
}
