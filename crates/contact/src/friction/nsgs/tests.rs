//! NSGS against the hand solutions of one point, against the semi-smooth
//! Newton method on random problems, and on rank-deficient and
//! nonsymmetric operators checked by the natural map computed here.

use faer::Mat;

use super::{nsgs, LocalProblem};
use crate::friction::friction3d::friction_3d;
use crate::friction::{FrictionLaw, FrictionOptions, PointStatus};
use crate::test_problems::{coulomb_layout, friction_options as opts, random_spd, XorShift};
use crate::DelassusProblem;

/// One point, W = diag(1, 2, 2): pressed by q_n = −1 it carries r_n = 1;
/// pulled by q_t = (0.3, −0.4) (|r_t| = 0.25 at stick) it sticks under
/// μ = 0.5 and slips under μ = 0.1 with r_t = −0.1 q_t / |q_t|; pulled
/// off (q_n = +1) it is open.
#[test]
fn one_point_opens_sticks_or_slips_as_by_hand() {
    let local = |qn: f64, mu: f64| LocalProblem {
        a: [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]],
        b: [qn, 0.3, -0.4],
        k: 2,
        mu: [mu, mu],
    };
    assert_eq!(local(1.0, 0.5).solve([0.0; 3]), [0.0; 3]);
    let stick = local(-1.0, 0.5).solve([0.0; 3]);
    for (a, b) in stick.iter().zip([1.0, -0.15, 0.2]) {
        assert!((a - b).abs() <= 1e-15, "{stick:?}");
    }
    let slip = local(-1.0, 0.1).solve([0.0; 3]);
    for (a, b) in slip.iter().zip([1.0, -0.06, 0.08]) {
        assert!((a - b).abs() <= 1e-14, "{slip:?}");
    }
    // 2D: the two candidates ±μ; pulled by q_t = 0.3 under μ = 0.1.
    let two = LocalProblem {
        a: [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0; 3]],
        b: [-1.0, 0.3, 0.0],
        k: 1,
        mu: [0.1, 0.1],
    };
    assert_eq!(two.solve([0.0; 3]), [1.0, -0.1, 0.0]);
}

/// A random coupled W_ii (normal–tangential coupling, anisotropic μ): the
/// slip force found is on the cone, with u_n = 0 and the slip opposite to
/// the outer normal of the ellipse.
#[test]
fn a_coupled_anisotropic_point_slips_on_its_cone_against_the_slip() {
    let mut rng = XorShift(5);
    for _ in 0..200 {
        let w = random_spd(3, &mut rng);
        let mu = [rng.uniform(0.05, 0.4), rng.uniform(0.05, 0.4)];
        let local = LocalProblem {
            a: std::array::from_fn(|i| std::array::from_fn(|j| w[(i, j)])),
            b: [-1.0, rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)],
            k: 2,
            mu,
        };
        let r = local.solve([0.0; 3]);
        let u = local.gaps(r);
        let phi = (r[1] / (mu[0] * r[0])).powi(2) + (r[2] / (mu[1] * r[0])).powi(2);
        assert!(r[0] > 0.0 && u[0].abs() <= 1e-12, "{r:?} {u:?}");
        if u[1].hypot(u[2]) > 1e-12 {
            assert!((phi - 1.0).abs() <= 1e-10, "{phi}");
            let nu = [r[1] / (mu[0] * mu[0]), r[2] / (mu[1] * mu[1])];
            let cross = u[1] * nu[1] - u[2] * nu[0];
            let along = u[1] * nu[0] + u[2] * nu[1];
            let scale = u[1].hypot(u[2]) * nu[0].hypot(nu[1]);
            assert!(
                cross.abs() <= 1e-9 * scale && along < 0.0,
                "{cross} {along}"
            );
        } else {
            assert!(phi <= 1.0 + 1e-12, "{phi}");
        }
    }
}

/// On random SPD problems NSGS finds the semi-smooth Newton method's forces.
#[test]
fn nsgs_finds_the_newton_forces_on_random_problems() {
    let mut rng = XorShift(17);
    let mut seen = [0usize; 3];
    for m in [3, 8, 20] {
        let n = 3 * m;
        let w = random_spd(n, &mut rng);
        let q: Vec<f64> = (0..n)
            .map(|i| match i < m {
                true => rng.uniform(-1.0, 0.6),
                false => rng.uniform(-0.8, 0.8),
            })
            .collect();
        let mut layout = coulomb_layout(m, 3, 0.3);
        for (p, law) in layout.law.iter_mut().enumerate() {
            let mu = 0.2 + 0.5 * (p % 3) as f64;
            *law = FrictionLaw::Coulomb { mu: [mu, mu] };
        }
        let mut a = DelassusProblem::from_operator(w.clone(), q.clone());
        let ours = nsgs(&mut a, &layout, None, &opts(), 3).unwrap();
        let mut b = DelassusProblem::from_operator(w, q);
        let newton = friction_3d(&mut b, &layout, None, &opts()).unwrap();
        assert!(ours.report.converged, "m = {m}: {}", ours.report.stop);
        assert!(newton.report.converged, "m = {m}: {}", newton.report.stop);
        let scale = crate::norms::max_abs(&newton.forces);
        for (x, y) in ours.forces.iter().zip(&newton.forces) {
            assert!((x - y).abs() <= 1e-8 * scale, "m = {m}: {x} vs {y}");
        }
        for s in &ours.friction.points {
            seen[match s {
                PointStatus::Open => 0,
                PointStatus::Stick => 1,
                _ => 2,
            }] += 1;
        }
    }
    assert!(seen.iter().all(|&c| c > 0), "open, stick, slip: {seen:?}");
}

/// The natural map of Coulomb's law (normal min(r_n, u_n), tangential
/// r_t − proj(r_t − u_t) on the disc μ r_n), computed here from W, q and
/// the forces alone, relative to max |r| and max |q|.
fn coulomb_residual(w: &Mat<f64>, q: &[f64], r: &[f64], m: usize, mu: f64) -> f64 {
    let n = q.len();
    let u: Vec<f64> = (0..n)
        .map(|i| q[i] + (0..n).map(|j| w[(i, j)] * r[j]).sum::<f64>())
        .collect();
    let (f, g) = (crate::norms::max_abs(r), crate::norms::max_abs(q));
    let mut worst = 0.0f64;
    for p in 0..m {
        worst = worst.max((r[p] / f).min(u[p] / g).abs());
        let t = [m + 2 * p, m + 2 * p + 1];
        let trial = [r[t[0]] / f - u[t[0]] / g, r[t[1]] / f - u[t[1]] / g];
        let radius = mu * r[p].max(0.0) / f;
        let norm = trial[0].hypot(trial[1]);
        let s = if norm > radius { radius / norm } else { 1.0 };
        for k in 0..2 {
            worst = worst.max((r[t[k]] / f - s * trial[k]).abs());
        }
    }
    worst
}

/// W = Hᵀ H of rank 2/3 of its rows (more contact rows than degrees of
/// freedom, as rigid bodies give), then made nonsymmetric by 1e-3 of its
/// largest entry: NSGS solves both to the tolerance, checked here.
#[test]
fn rank_deficient_and_nonsymmetric_operators_are_solved() {
    let mut rng = XorShift(29);
    let m = 30;
    let (n, dofs) = (3 * m, 2 * m);
    let h = Mat::<f64>::from_fn(dofs, n, |_, _| rng.uniform(-1.0, 1.0));
    let w = h.transpose() * &h;
    let q: Vec<f64> = (0..n)
        .map(|i| match i < m {
            true => rng.uniform(-1.0, 0.2),
            false => rng.uniform(-0.3, 0.3),
        })
        .collect();
    let wmax = w.norm_max();
    let skew = Mat::<f64>::from_fn(n, n, |i, j| match i == j {
        true => 0.0,
        false => 1e-3 * wmax * (((i * 7 + j * 13) % 11) as f64 / 11.0 - 0.5),
    });
    for (what, w) in [("rank deficient", w.clone()), ("nonsymmetric", &w + &skew)] {
        let layout = coulomb_layout(m, 3, 0.4);
        let mut p = DelassusProblem::from_operator(w.clone(), q.clone());
        let sol = nsgs(&mut p, &layout, None, &opts(), 3).unwrap();
        assert!(sol.report.converged, "{what}: {}", sol.report.stop);
        let res = coulomb_residual(&w, &q, &sol.forces, m, 0.4);
        assert!(res <= 1e-9, "{what}: {res:e}");
    }
}

/// A deadline already past stops NSGS after one sweep, not converged, with
/// the time limit as its reason.
#[test]
fn a_past_deadline_stops_after_one_sweep() {
    let mut rng = XorShift(3);
    let m = 10;
    let w = random_spd(3 * m, &mut rng);
    let q: Vec<f64> = (0..3 * m).map(|i| if i < m { -1.0 } else { 0.5 }).collect();
    let o = FrictionOptions {
        deadline: Some(std::time::Instant::now()),
        tolerance: 1e-15,
        ..opts()
    };
    let mut p = DelassusProblem::from_operator(w, q);
    let sol = nsgs(&mut p, &coulomb_layout(m, 3, 0.3), None, &o, 3).unwrap();
    crate::test_problems::assert_stopped_by_the_time_limit_after_one_iteration(&sol.report);
}
