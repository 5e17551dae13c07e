//! Can the contacts of a floating body balance its load?
//!
//! A body held only by contact needs forces λ ≥ 0 with Gᵀ λ = e (G = B R:
//! how each contact force works on the body's rigid modes, e = −Rᵀ F').
//! This is a non-negative least-squares problem, min ‖Gᵀλ − e‖ over λ ≥ 0,
//! solved by the active-set algorithm of Lawson & Hanson (1974, ch. 23); a
//! residual above tolerance means no compressive contact forces can balance
//! the load.

use faer::prelude::Solve;
use faer::Mat;

/// Non-negative least squares: min ‖A x − b‖ for x ≥ 0 (A is r × c, small r).
/// Returns (x, ‖A x − b‖).
pub fn nnls(a: &Mat<f64>, b: &[f64]) -> (Vec<f64>, f64) {
    let (r, c) = (a.nrows(), a.ncols());
    let mut x = vec![0.0; c];
    let mut passive = vec![false; c];
    let amax = a.norm_max().max(f64::MIN_POSITIVE);
    let tol = 1e-12
        * amax
        * b.iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE)
        * (c as f64);
    let residual = |x: &[f64]| -> Vec<f64> {
        (0..r)
            .map(|i| b[i] - (0..c).map(|j| a[(i, j)] * x[j]).sum::<f64>())
            .collect()
    };
    let ls = |set: &[usize]| -> Vec<f64> {
        // least squares on the passive columns by normal equations + LU
        let k = set.len();
        let mut ata = Mat::<f64>::zeros(k, k);
        let mut atb = Mat::<f64>::zeros(k, 1);
        for (ii, &p) in set.iter().enumerate() {
            for (jj, &q) in set.iter().enumerate() {
                ata[(ii, jj)] = (0..r).map(|t| a[(t, p)] * a[(t, q)]).sum();
            }
            atb[(ii, 0)] = (0..r).map(|t| a[(t, p)] * b[t]).sum();
        }
        let z = ata.full_piv_lu().solve(&atb);
        (0..k).map(|i| z[(i, 0)]).collect()
    };
    for _outer in 0..(3 * c + 10) {
        let res = residual(&x);
        let w: Vec<f64> = (0..c)
            .map(|j| (0..r).map(|i| a[(i, j)] * res[i]).sum())
            .collect();
        let cand = (0..c)
            .filter(|&j| !passive[j] && w[j] > tol)
            .max_by(|&p, &q| w[p].total_cmp(&w[q]));
        let Some(t) = cand else { break };
        passive[t] = true;
        for _inner in 0..(3 * c + 10) {
            let set: Vec<usize> = (0..c).filter(|&j| passive[j]).collect();
            let z = ls(&set);
            if z.iter().all(|v| *v > 0.0 && v.is_finite()) {
                for (ii, &p) in set.iter().enumerate() {
                    x[p] = z[ii];
                }
                break;
            }
            let mut alpha = 1.0f64;
            for (ii, &p) in set.iter().enumerate() {
                if z[ii].is_nan() || z[ii] <= 0.0 {
                    let d = x[p] - z[ii];
                    if d > 0.0 {
                        alpha = alpha.min(x[p] / d);
                    } else {
                        alpha = 0.0;
                    }
                }
            }
            for (ii, &p) in set.iter().enumerate() {
                let zi = if z[ii].is_finite() { z[ii] } else { x[p] };
                x[p] += alpha * (zi - x[p]);
                if x[p] <= 1e-15 * amax {
                    x[p] = 0.0;
                    passive[p] = false;
                }
            }
        }
    }
    let res = residual(&x);
    (x, res.iter().map(|v| v * v).sum::<f64>().sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nnls_finds_a_balancing_compressive_force_or_reports_the_residual() {
        // Two contacts pushing up (+y) on a block; rigid modes (x, y).
        let a = Mat::<f64>::from_fn(2, 2, |i, _| if i == 1 { 1.0 } else { 0.0 });
        let (x, res) = nnls(&a, &[0.0, 2.0]);
        assert!(res <= 1e-12 * 2.0);
        assert!((x[0] + x[1] - 2.0).abs() <= 1e-12 * 2.0);
        // Pulling down cannot be balanced by compressive forces.
        let (_, res) = nnls(&a, &[0.0, -2.0]);
        assert!((res - 2.0).abs() <= 1e-12 * 2.0);
        // Nor can a sideways load.
        let (_, res) = nnls(&a, &[1.0, 2.0]);
        assert!((res - 1.0).abs() <= 1e-12);
    }
}
