//! The units of LCP(W, q), taken out before a method runs when they are
//! extreme. W is a compliance (length per force) and q a length, so their
//! magnitudes follow the user's units: a problem in pascals and metres of a
//! stiff body may have ‖W‖ ~ 1e-120 or ~ 1e120, and a method's products
//! (the curvature dᵀW d of a descent direction, of order ‖q‖²/‖W‖ · ‖W‖²)
//! then under- or overflow, and an exact solution looks singular.
//!
//! The substitution λ = (s_q / s_W) λ̃, W = s_W W̃, q = s_q q̃ turns
//! LCP(W, q) into LCP(W̃, q̃) with max |W̃_ij| and max |q̃_i| near 1, and
//! g = s_q g̃: the same complementarity problem, whose natural residual
//! (relative to the force and gap scales, which scale with it) is
//! unchanged. The scales are powers of two, so the substitution and its
//! inverse are exact in floating point; a problem whose magnitudes are
//! ordinary is solved as given.

use faer::Mat;

use crate::lcp::LcpOptions;
use crate::solution::{ContactSolution, DualDetail, StopReason, UzawaStep};

/// Magnitudes within [2^-64, 2^64] are solved as given: the squares and
/// cubes the methods form stay far from the limits of f64.
const ORDINARY: f64 = 18446744073709551616.0; // 2^64

/// The power-of-two scales of W and q (both 1 for an ordinary problem).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ProblemScale {
    w: f64,
    q: f64,
}

/// The power of two nearest `magnitude` (1 for zero or a non-finite value,
/// which the methods report themselves).
fn power_of_two(magnitude: f64) -> f64 {
    if magnitude > 0.0 && magnitude.is_finite() {
        2f64.powi(magnitude.log2().round() as i32)
    } else {
        1.0
    }
}

/// max |v_i| (0 for an empty v), NaN entries dropped as `f64::max` drops
/// them, in eight lanes that the compiler keeps in vector registers: W has
/// m² entries, and a scalar fold, one dependent maximum after the other,
/// took as long as a status iteration on the half-space at m = 2025.
fn largest_magnitude(v: &[f64]) -> f64 {
    let mut lanes = [0.0f64; 8];
    let mut chunks = v.chunks_exact(8);
    for c in &mut chunks {
        for (l, x) in lanes.iter_mut().zip(c) {
            *l = l.max(x.abs());
        }
    }
    let tail = chunks
        .remainder()
        .iter()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    lanes.iter().fold(tail, |a, &l| a.max(l))
}

/// max |W_ij|. For a positive semi-definite W (a compliance, what every
/// method but Lemke's assumes) it is the largest diagonal entry, as
/// |W_ij| ≤ √(W_ii W_jj): m loads instead of the m² of a scan of W, which
/// took as long as the rest of the status method's iterations on the
/// half-space at m = 2025 but one factorisation. A square W with a
/// negative (or NaN) diagonal entry is not positive semi-definite: every
/// entry is read, as for a W that is not square.
fn largest_entry(w: &Mat<f64>) -> f64 {
    let m = w.nrows();
    let diagonal = (w.ncols() == m).then(|| (0..m).map(|i| w[(i, i)]).collect::<Vec<f64>>());
    match diagonal {
        Some(d) if d.iter().all(|&v| v >= 0.0) => d.iter().fold(0.0f64, |a, &v| a.max(v)),
        _ => (0..w.ncols()).fold(0.0f64, |a, j| a.max(largest_magnitude(w.col_as_slice(j)))),
    }
}

fn ordinary(magnitude: f64) -> bool {
    magnitude == 0.0 || (1.0 / ORDINARY..=ORDINARY).contains(&magnitude)
}

impl ProblemScale {
    /// The scales of LCP(W, q): `None` when both magnitudes are ordinary.
    pub(crate) fn of(w: &Mat<f64>, q: &[f64]) -> Option<Self> {
        let w_max = largest_entry(w);
        let q_max = q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if ordinary(w_max) && ordinary(q_max) {
            return None;
        }
        Some(Self {
            w: power_of_two(w_max),
            q: power_of_two(q_max),
        })
    }

    /// The force unit s_q / s_W.
    fn force(self) -> f64 {
        self.q / self.w
    }

    /// W̃, q̃, the options in the new units (force and gap scales), and the
    /// penalty stiffness per point (force per unit gap: k̃ = k s_W).
    pub(crate) fn scaled(
        self,
        w: &Mat<f64>,
        q: &[f64],
        stiffness: Option<&[f64]>,
        opts: &LcpOptions,
    ) -> (Mat<f64>, Vec<f64>, Option<Vec<f64>>, LcpOptions) {
        let w_s = Mat::from_fn(w.nrows(), w.ncols(), |i, j| w[(i, j)] / self.w);
        let q_s = q.iter().map(|v| v / self.q).collect();
        let k_s = stiffness.map(|k| k.iter().map(|v| v * self.w).collect());
        let opts_s = LcpOptions {
            force_scale: opts.force_scale / self.force(),
            gap_scale: opts.gap_scale / self.q,
            ..opts.clone()
        };
        (w_s, q_s, k_s, opts_s)
    }

    /// The answer of LCP(W̃, q̃) in the units of LCP(W, q).
    pub(crate) fn unscale(self, mut sol: ContactSolution) -> ContactSolution {
        let f = self.force();
        sol.forces.iter_mut().for_each(|v| *v *= f);
        sol.gaps.iter_mut().for_each(|v| *v *= self.q);
        sol.report.stop = self.unscale_stop(sol.report.stop);
        sol
    }

    /// A stopping reason's dimensional numbers (‖W‖, penetrations) in the
    /// problem's units; residuals and tolerances are relative and unchanged.
    fn unscale_stop(self, mut stop: StopReason) -> StopReason {
        match &mut stop {
            StopReason::MprgpConverged { norm_w, .. } => *norm_w *= self.w,
            StopReason::DualConverged { detail, .. } | StopReason::DualLimit { detail, .. } => {
                if let DualDetail::Uzawa {
                    step: UzawaStep::PowerIteration { norm },
                    ..
                } = detail
                {
                    *norm *= self.w;
                }
            }
            StopReason::RegularisedSolved { penetration, .. } => *penetration *= self.q,
            StopReason::ByPenalty {
                status,
                penetration,
            } => {
                *penetration *= self.q;
                self.unscale_boxed(status);
            }
            StopReason::InnerFailed { inner, .. } => self.unscale_boxed(inner),
            StopReason::Polished { before, .. } => self.unscale_boxed(before),
            _ => {}
        }
        stop
    }

    fn unscale_boxed(self, stop: &mut Box<StopReason>) {
        **stop = self.unscale_stop(std::mem::take(&mut **stop));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::registry::{Algorithm, METHODS};
    use crate::test_problems::{cases, rel_err};

    /// The eight-lane maximum is the scalar fold's, whatever the length
    /// (a tail shorter than a chunk included), the largest entry in any
    /// lane and NaN entries dropped.
    #[test]
    fn the_largest_magnitude_is_the_scalar_folds() {
        for n in [0, 1, 7, 8, 9, 23, 64] {
            for at in 0..n {
                let mut v: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.0) * 0.1).collect();
                v[at] = -3.0;
                v[(at + 1) % n] = f64::NAN;
                let scalar = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                assert_eq!(largest_magnitude(&v), scalar, "n {n}, at {at}");
            }
            assert_eq!(largest_magnitude(&vec![0.0; n]), 0.0);
        }
    }

    /// Every method of the registry answers LCP(s_W W, s_q q) with
    /// (s_q / s_W) λ and s_q g, λ the exact forces of LCP(W, q), for units
    /// 1e±150 on W and q together and apart (without the rescaling the
    /// projection methods' curvatures under- or overflowed and they called
    /// the problem singular); the residual is that of the problem as given.
    #[test]
    fn every_method_answers_in_the_problems_units() {
        let opts = LcpOptions {
            tolerance: 1e-12,
            max_iterations: 5000,
            ..Default::default()
        };
        let units = [
            (1e150, 1e150),
            (1e-150, 1e-150),
            (1e150, 1.0),
            (1.0, 1e-150),
        ];
        for case in cases().into_iter().filter(|c| c.q.len() <= 20) {
            for method in METHODS.iter().filter(|m| m.exact) {
                let alg = Algorithm::by_name(method.name).unwrap();
                for (s_w, s_q) in units {
                    let w = Mat::from_fn(case.q.len(), case.q.len(), |i, j| case.w[(i, j)] * s_w);
                    let q: Vec<f64> = case.q.iter().map(|v| v * s_q).collect();
                    let opts = LcpOptions {
                        force_scale: s_q / s_w,
                        gap_scale: s_q,
                        ..opts.clone()
                    };
                    let what = format!("{} by {} at W×{s_w:e}, q×{s_q:e}", case.name, method.name);
                    let sol = alg
                        .solve(&w, &q, None, &opts)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    assert!(sol.report.converged, "{what}: {}", sol.report.stop);
                    let want: Vec<f64> = case.exact.iter().map(|v| v * (s_q / s_w)).collect();
                    assert!(rel_err(&sol.forces, &want) <= 1e-9, "{what}");
                    let residual = crate::lcp::lcp_residual(&w, &q, &sol.forces, &opts);
                    assert!(residual <= 1e-10, "{what}: residual {residual:e}");
                }
            }
        }
    }

    /// The largest entry of a positive semi-definite W is read off its
    /// diagonal and equals that of every entry (random SPD W, and one of
    /// rank one with a zero row); a W with a negative diagonal entry, or not
    /// square, is read whole: its largest entry off the diagonal counts.
    #[test]
    fn the_largest_entry_of_a_compliance_is_on_its_diagonal() {
        let whole = |w: &Mat<f64>| {
            (0..w.ncols()).fold(0.0f64, |a, j| a.max(largest_magnitude(w.col_as_slice(j))))
        };
        let mut rng = crate::test_problems::XorShift(11);
        for m in [1, 7, 40] {
            let w = crate::test_problems::random_spd(m, &mut rng);
            assert_eq!(largest_entry(&w), whole(&w), "m {m}");
        }
        let v = [3.0, -2.0, 0.0, 0.5];
        let rank_one = Mat::from_fn(4, 4, |i, j| v[i] * v[j]);
        assert_eq!(largest_entry(&rank_one), 9.0);
        let mut indefinite = Mat::from_fn(3, 3, |i, j| if i == j { 1.0 } else { 0.0 });
        indefinite[(2, 2)] = -1.0;
        indefinite[(0, 1)] = 1e80;
        assert_eq!(largest_entry(&indefinite), 1e80);
        let wide = Mat::from_fn(2, 3, |i, j| (i + 2 * j) as f64);
        assert_eq!(largest_entry(&wide), 5.0);
    }

    #[test]
    fn an_ordinary_problem_is_solved_as_given() {
        let w = Mat::from_fn(2, 2, |i, j| if i == j { 1e-18 } else { 0.0 });
        assert_eq!(ProblemScale::of(&w, &[1e18, -1.0]), None);
        let scale = ProblemScale::of(&w, &[1e30, -1.0]).unwrap();
        assert_eq!(scale.q, 2f64.powi(100));
        assert_eq!(scale.w, 2f64.powi(-60));
    }
}
