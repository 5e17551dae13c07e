//! Norton–Hoff's law (course notes §4.1.4, eq. 19): the threshold
//! μ λ_n ‖Δs‖^ρ and the misfit of a solution to the law.

use crate::law::{FrictionLaw, FrictionLayout};
use crate::norms::nan_max;
use crate::options::FrictionOptions;
use crate::solution::PointStatus;

/// Norton–Hoff's law at the points of a layout, in 2D (one tangential row)
/// and 3D (two, isotropic in the tangent plane: ‖λ_t‖ = μ λ_n ‖Δs‖^ρ
/// opposing Δs). A slip below 1e-14 times the length scale is no slip: the
/// threshold is then the floor's μ λ_n (1e-14 L)^ρ, and such a point
/// satisfies the law when its force lies within it (a law steep at zero
/// slip, ρ small, needs slips far below round-off to carry a force; a block
/// pressed without drag, its Poisson slips tiny and none at the middle,
/// stalled when a stuck point was asked to oppose a slip of zero).
pub struct NortonHoffLaw<'a> {
    layout: &'a FrictionLayout,
    /// The slip below which a point does not slip.
    s_min: f64,
}

impl<'a> NortonHoffLaw<'a> {
    pub(crate) fn new(layout: &'a FrictionLayout, opts: &FrictionOptions) -> Self {
        let s_min = 1e-14 * opts.gap_scale.max(f64::MIN_POSITIVE);
        Self { layout, s_min }
    }

    /// (μ λ_n, ρ, ‖Δs‖ floored) of point p, when it has tangential rows and
    /// a Norton–Hoff law.
    fn at(&self, r: &[f64], g: &[f64], p: usize) -> Option<(f64, f64, f64)> {
        let FrictionLaw::NortonHoff { mu, rho } = self.layout.law[p] else {
            return None;
        };
        let rows = &self.layout.tangent_rows[p];
        let slip = rows.iter().map(|&t| g[t] * g[t]).sum::<f64>().sqrt();
        (!rows.is_empty()).then_some((mu * r[p].max(0.0), rho, slip.max(self.s_min)))
    }

    /// The threshold μ λ_n ‖Δs‖^ρ of point p from the forces r and gaps g.
    fn threshold(&self, r: &[f64], g: &[f64], p: usize) -> Option<f64> {
        self.at(r, g, p)
            .map(|(bound, rho, slip)| bound * slip.powf(rho))
    }

    /// The threshold of every point from the forces r and gaps g, as the
    /// solver's thresholds `of_radius` makes them (2D a force, 3D the
    /// semi-axes of a disc): μ λ_n ‖Δs‖^ρ where the law is Norton–Hoff,
    /// `fallback(p)` at the other points.
    pub(crate) fn thresholds<T>(
        &self,
        r: &[f64],
        g: &[f64],
        of_radius: impl Fn(f64) -> T,
        fallback: impl Fn(usize) -> T,
    ) -> Vec<T> {
        (0..self.layout.n_points())
            .map(|p| match self.threshold(r, g, p) {
                Some(radius) => of_radius(radius),
                None => fallback(p),
            })
            .collect()
    }

    /// The largest ‖λ_t + μ λ_n ‖Δs‖^(ρ−1) Δs‖ over the points in contact
    /// (below the slip floor: how far ‖λ_t‖ passes the floor's threshold).
    pub(crate) fn misfit(&self, r: &[f64], g: &[f64], statuses: &[PointStatus]) -> f64 {
        let closed = (0..statuses.len()).filter(|&p| statuses[p] != PointStatus::Open);
        closed.fold(0.0f64, |worst, p| {
            let Some((bound, rho, slip)) = self.at(r, g, p) else {
                return worst;
            };
            let rows = &self.layout.tangent_rows[p];
            let off = match slip <= self.s_min {
                true => {
                    let force = rows.iter().map(|&t| r[t] * r[t]).sum::<f64>().sqrt();
                    (force - bound * self.s_min.powf(rho)).max(0.0)
                }
                false => {
                    let scale = bound * slip.powf(rho - 1.0);
                    let off = rows.iter().map(|&t| (r[t] + scale * g[t]).powi(2));
                    off.sum::<f64>().sqrt()
                }
            };
            nan_max(worst, off)
        })
    }
}
