//! Rigid flat punch on an elastic half-space (docs/theory/validation-cases.md §4; Johnson,
//! *Contact Mechanics*, §2.8 and §3.8): a flat-ended rigid punch of
//! half-width b pressed by a load P.
//! - 2D (plane strain or stress, P per unit thickness):
//!   p(x) = P / (π sqrt(b² − x²)), |x| < b;
//! - circular punch of radius b (axisymmetric or 3D):
//!   p(r) = P / (2π b sqrt(b² − r²)), r < b.
//!
//! The pressure is singular at the edges, where no mesh resolves it: the
//! profile is compared away from them, on |x| ≤ 0.8 b, as docs/theory/validation-cases.md
//! asks. The profile does not depend on the elastic constants, only on P
//! and b: a punch much stiffer than the half-space (E_punch ≥ 1000 E)
//! approximates the rigid one.

use std::collections::BTreeMap;

use super::NodalPressure;
use crate::{Quantity, ReferenceReport};

/// The part of the punch face compared with the singular profile.
const INTERIOR: f64 = 0.8;

/// The shape of a contact: a strip (2D: a punch, a cylinder) or a circle
/// (axisymmetric, 3D: a punch, a sphere).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PunchShape {
    Strip,
    Circle,
}

/// The exact pressure at distance `x` from the centre of a punch of
/// half-width (radius) `b` under the load `p`.
pub fn flat_punch_pressure(shape: PunchShape, p: f64, b: f64, x: f64) -> f64 {
    let root = (b * b - x * x).max(0.0).sqrt();
    match shape {
        PunchShape::Strip => p / (std::f64::consts::PI * root),
        PunchShape::Circle => p / (2.0 * std::f64::consts::PI * b * root),
    }
}

/// Compares nodal pressures with the flat punch. `s` of each node is its
/// coordinate across the contact (2D; the centre is the force-weighted
/// mean) or its distance from the punch's axis (circle). `half_width` is b;
/// `None` takes the half-extent of the points in contact (noted). Reports
/// the load, the pressure at the node nearest the centre, and the relative
/// L2 and largest errors of the profile on |x| ≤ 0.8 b.
pub fn flat_punch(
    nodes: &[NodalPressure],
    shape: PunchShape,
    half_width: Option<f64>,
) -> ReferenceReport {
    let total: f64 = nodes.iter().map(|n| n.force).sum();
    let centre = match shape {
        PunchShape::Strip if total > 0.0 => {
            nodes.iter().map(|n| n.force * n.s).sum::<f64>() / total
        }
        _ => 0.0,
    };
    let x = |n: &NodalPressure| (n.s - centre).abs();
    let extent = nodes
        .iter()
        .filter(|n| n.force > 0.0)
        .fold(0.0f64, |m, n| m.max(x(n)));
    let b = half_width.unwrap_or(extent);
    let exact = |n: &NodalPressure| flat_punch_pressure(shape, total, b, x(n));
    let inside: Vec<&NodalPressure> = nodes
        .iter()
        .filter(|n| x(n) <= INTERIOR * b && n.tributary > 0.0)
        .collect();
    let (mut num, mut den, mut worst, mut worst_at) = (0.0, 0.0, 0.0f64, None);
    for n in &inside {
        let (p, pe) = (n.pressure, exact(n));
        num += (p - pe).powi(2) * n.tributary;
        den += pe * pe * n.tributary;
        if (p - pe).abs() >= worst * pe.max(f64::MIN_POSITIVE) || worst_at.is_none() {
            worst = (p - pe).abs() / pe.max(f64::MIN_POSITIVE);
            worst_at = Some((p, pe));
        }
    }
    let mut q = BTreeMap::new();
    q.insert("load".to_string(), Quantity::new(total, total));
    if let Some(n) = inside.iter().min_by(|a, b| x(a).total_cmp(&x(b))) {
        q.insert("p_centre".to_string(), Quantity::new(n.pressure, exact(n)));
    }
    if let Some((p, pe)) = worst_at {
        q.insert("p_interior_worst".to_string(), Quantity::new(p, pe));
    }
    let l2 = if den > 0.0 { (num / den).sqrt() } else { 0.0 };
    q.insert("profile_l2".to_string(), Quantity::new(l2, 0.0));
    if half_width.is_some() {
        q.insert("half_width".to_string(), Quantity::new(extent, b));
    }
    ReferenceReport {
        kind: "flat_punch".into(),
        quantities: q,
        notes: notes(shape, b, half_width.is_none(), inside.len()),
    }
}

fn notes(shape: PunchShape, b: f64, measured: bool, compared: usize) -> Vec<String> {
    let formula = match shape {
        PunchShape::Strip => "p(x) = P / (π sqrt(b² − x²)), P the computed load per unit thickness",
        PunchShape::Circle => "p(r) = P / (2π b sqrt(b² − r²)), P the computed load",
    };
    let mut notes = vec![
        format!("{formula}, b = {b:e}"),
        format!("the profile is compared on the {compared} contact points within 0.8 b of the centre (the pressure is singular at the edges); p_interior_worst is the point farthest from it there, half_width the last point with a positive force"),
        "a rigid punch on a half-space: a deformable punch and a finite body deviate from it, the more the softer the punch and the closer the body's boundaries".into(),
    ];
    if measured {
        notes.push("b was not given (reference.half_width): it is the half-extent of the points in contact".into());
    }
    notes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nodes at spacing h across [−1, 1] (and their tributaries) carrying
    /// the exact strip pressure of P = 2 off-centre by 0.3, and a zero
    /// force outside.
    fn strip(h: f64) -> Vec<NodalPressure> {
        let n = (2.0 / h).round() as i64;
        (-n / 2 - 2..=n / 2 + 2)
            .map(|i| {
                let x = i as f64 * h;
                let inside = x.abs() < 1.0;
                let p = if inside {
                    flat_punch_pressure(PunchShape::Strip, 2.0, 1.0, x)
                } else {
                    0.0
                };
                NodalPressure {
                    s: x + 0.3,
                    force: p * h,
                    tributary: h,
                    pressure: p,
                    tangential: 0.0,
                    stick: false,
                    recombined: None,
                }
            })
            .collect()
    }

    #[test]
    fn the_exact_strip_profile_has_no_interior_error() {
        let nodes = strip(0.01);
        let total: f64 = nodes.iter().map(|n| n.force).sum();
        let r = flat_punch(&nodes, PunchShape::Strip, Some(1.0));
        // The load of the lumped nodes is not exactly 2 (the edges): the
        // profile is that of the computed load, off by the same ratio.
        let off = (2.0 / total - 1.0).abs();
        assert!(
            r.quantities["profile_l2"].relative_error <= off + 1e-3,
            "{:?}",
            r.quantities
        );
        assert!(r.quantities["p_centre"].relative_error <= off + 1e-3);
        assert!((r.quantities["half_width"].computed - 1.0).abs() <= 0.011);
        // The circle's formula at the same b is half the strip's at the centre.
        let c = flat_punch(&nodes, PunchShape::Circle, Some(1.0));
        assert!(c.quantities["p_centre"].relative_error > 0.3);
    }

    #[test]
    fn the_half_width_defaults_to_the_contact_extent() {
        let r = flat_punch(&strip(0.05), PunchShape::Strip, None);
        assert!(!r.quantities.contains_key("half_width"));
        assert!(r.notes.iter().any(|n| n.contains("not given")));
    }
}
