//! The contact pressure at each contact point, from its force and its
//! tributary measure (the certificate's rows and the analytic comparisons).

use crate::model::PointModel;

/// The contact pressure at every point, its force over its tributary
/// measure. A point whose consistent tributary measure vanishes — the corner
/// node of a quadratic edge on the axis of an axisymmetric model, where
/// ∫ N r dr = 0 on a straight edge and O((h/R)²) of its neighbour's on an
/// arc — carries no force from a smooth pressure, so force over measure says
/// nothing there; it takes the pressure of the nearest point of its contact
/// that has a measure.
pub(crate) fn nodal_pressures(points: &[PointModel], lambda: &[f64]) -> Vec<f64> {
    let largest = points.iter().fold(0.0f64, |a, p| a.max(p.tributary));
    let measured: Vec<bool> = (0..points.len())
        .map(|i| has_measure(points, i, largest))
        .collect();
    let own: Vec<f64> = points
        .iter()
        .zip(lambda)
        .zip(&measured)
        .map(|((p, l), &m)| if m { l / p.tributary } else { 0.0 })
        .collect();
    (0..points.len())
        .map(|pi| {
            if measured[pi] {
                return own[pi];
            }
            nearest_in_contact(points, pi, |qi| measured[qi]).map_or(0.0, |qi| own[qi])
        })
        .collect()
}

/// A consistent nodal measure is at least a sixth of its nearest
/// neighbour's on a smoothly graded surface, first or second order (a
/// linear axis node: 1/6; a quadratic corner against its midside node: 1/4);
/// below this fraction it is a vanishing one.
const VANISHING_MEASURE: f64 = 1e-2;

/// Whether point `i` has a tributary measure of its own: positive and not a
/// vanishing fraction of its nearest neighbour's in the same contact (only
/// points small against the `largest` measure are compared, so the search
/// stays rare).
fn has_measure(points: &[PointModel], i: usize, largest: f64) -> bool {
    let t = points[i].tributary;
    if t <= 0.0 {
        return false;
    }
    if t >= VANISHING_MEASURE * largest {
        return true;
    }
    nearest_in_contact(points, i, |_| true)
        .is_none_or(|q| t >= VANISHING_MEASURE * points[q].tributary)
}

/// The point of the same contact as `i`, other than `i` and accepted by
/// `keep`, nearest to it.
fn nearest_in_contact(
    points: &[PointModel],
    i: usize,
    keep: impl Fn(usize) -> bool,
) -> Option<usize> {
    let p = &points[i];
    let dist2 = |q: &PointModel| {
        (0..3)
            .map(|k| (q.point.x[k] - p.point.x[k]).powi(2))
            .sum::<f64>()
    };
    points
        .iter()
        .enumerate()
        .filter(|&(qi, q)| qi != i && q.contact == p.contact && keep(qi))
        .min_by(|a, b| dist2(a.1).total_cmp(&dist2(b.1)))
        .map(|(qi, _)| qi)
}
