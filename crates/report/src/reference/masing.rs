//! The tangential load history of Cattaneo–Mindlin contacts: Mindlin and
//! Deresiewicz's unloading and reloading (1953) by Masing's rules, for a
//! tangential load that does not only grow.

/// One branch of a tangential load history between two turning points: its
/// sign times its factor (1 for the first loading, 2 for every branch after
/// a reversal) and the stick half-width c of its correction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Branch {
    pub weight: f64,
    pub c: f64,
}

/// The turning points of a tangential load history (the resultants Q of the
/// steps in order, the last one the current load), from the unloaded start
/// 0, by Masing's rules: a branch continuing its predecessor's direction
/// extends it; a branch reaching past the range of the one before closes
/// that loop and the memory of its two turning points is wiped (the first
/// loading, from 0 to T, is passed by a reversal beyond −T).
pub(super) fn turning_points(history: &[f64]) -> Vec<f64> {
    let mut pts = vec![0.0];
    for &q in history {
        let n = pts.len();
        if n >= 2 && (q - pts[n - 1]) * (pts[n - 1] - pts[n - 2]) >= 0.0 {
            pts[n - 1] = q;
        } else {
            pts.push(q);
        }
        loop {
            let n = pts.len();
            let span = |i: usize| (pts[i] - pts[i - 1]).abs();
            if n >= 4 && span(n - 1) >= span(n - 2) {
                pts.drain(n - 3..n - 1);
            } else if n == 3 && span(2) >= 2.0 * span(1) {
                pts.remove(1);
            } else {
                break;
            }
        }
    }
    pts
}

/// The branches of the turning points `pts`, for the friction capacity
/// `mu_p` = μP and the exponent of c/a (1/2 for cylinders, 1/3 for spheres):
/// a branch of load change ΔQ and factor k has c = a (1 − |ΔQ|/(k μP))^e.
pub(super) fn branches(pts: &[f64], a: f64, mu_p: f64, exponent: f64) -> Vec<Branch> {
    pts.windows(2)
        .enumerate()
        .map(|(j, w)| {
            let k = if j == 0 { 1.0 } else { 2.0 };
            let dq = w[1] - w[0];
            let ratio = if mu_p > 0.0 {
                dq.abs() / (k * mu_p)
            } else {
                f64::NAN
            };
            Branch {
                weight: k * dq.signum(),
                c: a * (1.0 - ratio).max(0.0).powf(exponent),
            }
        })
        .collect()
}

/// The shear traction at `x` of a history's `branches`: each adds its
/// weight times Cattaneo's μp(x) − μp0 (c/a) sqrt(1 − x²/c²) (the second
/// term inside its stick zone |x| < c). One branch of weight 1 is
/// Cattaneo–Mindlin's monotone loading.
pub(super) fn shear(branches: &[Branch], x: f64, mu_p0: f64, a: f64) -> f64 {
    let full = mu_p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt();
    branches
        .iter()
        .map(|b| {
            let stick = if x.abs() < b.c {
                mu_p0 * (b.c / a) * (1.0 - (x / b.c).powi(2)).max(0.0).sqrt()
            } else {
                0.0
            };
            b.weight * (full - stick)
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_growing_load_is_one_branch_from_zero() {
        assert_eq!(turning_points(&[0.0, 0.2, 0.5, 0.5, 1.0]), vec![0.0, 1.0]);
    }

    #[test]
    fn unloading_and_reversal_keep_the_peak_until_passed() {
        assert_eq!(turning_points(&[1.0, 0.5]), vec![0.0, 1.0, 0.5]);
        assert_eq!(turning_points(&[1.0, 0.5, -0.5]), vec![0.0, 1.0, -0.5]);
        // reversal beyond −Q*: the first loading is passed, from 0 again
        assert_eq!(turning_points(&[1.0, -1.5]), vec![0.0, -1.5]);
        // a reload past the last reversal's start closes that loop
        assert_eq!(
            turning_points(&[1.0, 0.2, 0.6, 0.3]),
            vec![0.0, 1.0, 0.2, 0.6, 0.3]
        );
        assert_eq!(
            turning_points(&[1.0, 0.2, 0.6, 0.9]),
            vec![0.0, 1.0, 0.2, 0.9]
        );
        assert_eq!(turning_points(&[1.0, 0.2, 1.2]), vec![0.0, 1.2]);
    }

    /// Mindlin–Deresiewicz: unloading from Q* to Q has its stick zone
    /// c' = a (1 − (Q* − Q)/(2μP))^(1/2) (cylinder) and the shear of the
    /// peak minus twice Cattaneo's of the load change; at Q = −Q* it is the
    /// peak's shear reversed.
    #[test]
    fn unloading_follows_mindlin_deresiewicz() {
        let (a, mu_p, mu_p0) = (1.0, 1.0, 2.0);
        let peak = branches(&[0.0, 0.6], a, mu_p, 0.5);
        let back = branches(&[0.0, 0.6, 0.2], a, mu_p, 0.5);
        assert!((back[1].c - (1.0f64 - 0.4 / 2.0).sqrt()).abs() <= 1e-15);
        let reversed = branches(&[0.0, 0.6, -0.6], a, mu_p, 0.5);
        for x in [0.0, 0.3, 0.63, 0.8, 0.99] {
            let q = shear(&reversed, x, mu_p0, a);
            let q_peak = shear(&peak, x, mu_p0, a);
            assert!((q + q_peak).abs() <= 1e-14 * mu_p0, "x = {x}: {q} {q_peak}");
        }
        // beyond the unloading's stick zone the shear is −μp(x)
        let x = 0.95;
        let full = mu_p0 * (1.0f64 - x * x).sqrt();
        assert!((shear(&back, x, mu_p0, a) + full).abs() <= 1e-14 * mu_p0);
    }
}
