//! The admissible set of the tangential forces (course notes §4.1): the
//! disc ‖λ_t‖ ≤ g (Tresca g, Coulomb μ λ_n) or, with anisotropic Coulomb,
//! the ellipse (λ_t1/μ1)² + (λ_t2/μ2)² ≤ λ_n² (semi-axes μ_i λ_n, the
//! disc when μ1 = μ2): the projection on it, how far a force lies outside
//! it, and the natural-map residual of the law.

use crate::law::{FrictionLaw, FrictionLayout};
use crate::norms::{nan_max, natural_map};

/// Projection of x on the ellipse (x1/a1)² + (x2/a2)² ≤ 1 (Euclidean; a
/// semi-axis may be zero, both infinite means no bound).
pub(crate) fn project_ellipse(x: [f64; 2], a: [f64; 2]) -> [f64; 2] {
    if a[0].is_infinite() || a[1].is_infinite() {
        return x;
    }
    match (a[0] > 0.0, a[1] > 0.0) {
        (false, false) => return [0.0, 0.0],
        (false, true) => return [0.0, x[1].clamp(-a[1], a[1])],
        (true, false) => return [x[0].clamp(-a[0], a[0]), 0.0],
        _ => {}
    }
    if (x[0] / a[0]).powi(2) + (x[1] / a[1]).powi(2) <= 1.0 {
        return x;
    }
    // f(t) = Σ (a_i x_i / (a_i² + t))² − 1, decreasing and convex on t ≥ 0:
    // Newton from t = 0 converges monotonically to its root.
    let mut t = 0.0f64;
    for _ in 0..200 {
        let mut f = -1.0;
        let mut df = 0.0;
        for i in 0..2 {
            let d = a[i] * a[i] + t;
            let v = a[i] * x[i] / d;
            f += v * v;
            df -= 2.0 * v * v / d;
        }
        let step = -f / df;
        if !step.is_finite() || step <= 1e-16 * t.max(f64::MIN_POSITIVE) {
            break;
        }
        t += step;
    }
    [
        a[0] * a[0] * x[0] / (a[0] * a[0] + t),
        a[1] * a[1] * x[1] / (a[1] * a[1] + t),
    ]
}

/// The projection of the tangential force `x` (one or two components) on
/// the admissible set with semi-axes `a`: on a disc (equal semi-axes, or
/// one row) the radial shrink x · min(1, a/‖x‖), on an ellipse
/// [`project_ellipse`].
fn project(x: &[f64], a: [f64; 2]) -> Vec<f64> {
    if x.len() == 2 && a[0] != a[1] {
        return project_ellipse([x[0], x[1]], a).to_vec();
    }
    let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    let shrink = if norm > a[0] { a[0] / norm } else { 1.0 };
    x.iter().map(|v| shrink * v).collect()
}

impl FrictionLaw {
    /// How far the tangential force `lt` (its rows' components) lies
    /// outside the admissible set with the normal force `normal`, as a
    /// force (≤ 0 inside): one row |λ_t| − g; two rows, Coulomb
    /// μ1 (‖(λ_t1/μ1, λ_t2/μ2)‖ − λ_n⁺) (the elliptic cone, ‖λ_t‖ − μ λ_n
    /// when μ1 = μ2; ‖λ_t‖ if a coefficient is zero), other laws
    /// ‖λ_t‖ − g.
    pub fn cone_excess(&self, normal: f64, lt: &[f64]) -> f64 {
        let threshold = self.semi_axes(normal)[0];
        let [l1, l2] = match *lt {
            [l1] => return l1.abs() - threshold,
            [l1, l2] => [l1, l2],
            _ => return -threshold,
        };
        match self.coulomb_mu() {
            Some([mu1, mu2]) if mu1 > 0.0 && mu2 > 0.0 => {
                mu1 * (((l1 / mu1).powi(2) + (l2 / mu2).powi(2)).sqrt() - normal.max(0.0))
            }
            Some(_) => l1.hypot(l2),
            None => l1.hypot(l2) - threshold,
        }
    }
}

/// The natural-map residual of forces r and gaps g on `layout`, scaled:
/// the normal rows' |min(λ_n/F, g_n/L)| and, per frictional point,
/// |λ_t − P(λ_t − (F/L) Δs)| / F with P the projection on the point's
/// admissible set with the normal force λ_n (zero exactly when λ_t is in
/// the cone and, if the point slips, opposes its slip: cone and
/// complementarity together). NaN if any entry is.
pub fn natural_residual(layout: &FrictionLayout, r: &[f64], g: &[f64], f: f64, gap: f64) -> f64 {
    let mut worst = 0.0f64;
    for (c, rows) in layout.tangent_rows.iter().enumerate() {
        worst = nan_max(worst, natural_map(r[c] / f, g[c] / gap));
        if rows.is_empty() {
            continue;
        }
        let trial: Vec<f64> = rows.iter().map(|&t| r[t] - f / gap * g[t]).collect();
        let projected = project(&trial, layout.law[c].semi_axes(r[c]));
        for (k, &t) in rows.iter().enumerate() {
            worst = nan_max(worst, (r[t] - projected[k]).abs() / f);
        }
    }
    worst
}
