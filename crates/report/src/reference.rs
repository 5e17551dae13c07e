//! Analytic references (docs/theory/validation-cases.md). Each takes the computed load, so the
//! error shown is that of the contact solution, not of the load.

use std::collections::BTreeMap;

use crate::{Quantity, ReferenceReport};

mod flat_punch;
mod masing;
mod pressure_moment;
pub use flat_punch::{flat_punch, flat_punch_pressure, PunchShape};
pub use pressure_moment::{pressure_moment, Recombined};

/// Nodal contact data along the contact line: tangential coordinate,
/// normal force, tributary length and pressure of each contact point.
pub struct NodalPressure {
    pub s: f64,
    pub force: f64,
    pub tributary: f64,
    /// The contact pressure, force / tributary where the tributary measure
    /// is not zero (the caller's rule elsewhere, as in contact.csv).
    pub pressure: f64,
    /// Tangential force (0 without friction).
    pub tangential: f64,
    /// Whether the point sticks (friction).
    pub stick: bool,
    /// On a quadratic face whose shape functions were recombined, the
    /// mid-side point's edge (see [`Recombined`]); `None` for a point whose
    /// force is that of its own shape function.
    pub recombined: Option<Recombined>,
}

/// Hertz, cylinder on a plane (docs/theory/validation-cases.md §1): with P the load per unit
/// thickness, E* the contact modulus and R the relative radius,
/// a = sqrt(4PR/(πE*)), p0 = 2P/(πa) = sqrt(PE*/(πR)) (this form, finite
/// with no load), p(x) = p0 sqrt(1 − x²/a²).
pub fn hertz_cylinder_exact(p: f64, e_star: f64, r: f64) -> (f64, f64) {
    let a = (4.0 * p * r / (std::f64::consts::PI * e_star)).sqrt();
    (a, (p * e_star / (std::f64::consts::PI * r)).sqrt())
}

/// Compares the nodal pressures with Hertz: p0 (max nodal pressure), a from
/// the pressure moment a_mom = 2 sqrt(∫p x² / ∫p) (exact for the Hertz
/// ellipse), the last node in contact, and the relative L2 error of the
/// profile on [−a, a].
pub fn hertz_cylinder(nodes: &[NodalPressure], e_star: f64, r: f64) -> ReferenceReport {
    let total: f64 = nodes.iter().map(|n| n.force).sum();
    let (a, p0) = hertz_cylinder_exact(total, e_star, r);
    let centre = if total > 0.0 {
        nodes.iter().map(|n| n.force * n.s).sum::<f64>() / total
    } else {
        0.0
    };
    let second: f64 = nodes.iter().map(|n| n.force * (n.s - centre).powi(2)).sum();
    let a_mom = if total > 0.0 {
        2.0 * (second / total).sqrt()
    } else {
        0.0
    };
    let q = hertz_quantities(nodes, centre, total, a_mom, a, p0);
    ReferenceReport {
        kind: "hertz_cylinder".into(),
        quantities: q,
        notes: vec![
            format!("E* = {e_star:e}, R = {r:e}; the load P is the computed resultant contact force per unit thickness"),
            "Hertz assumes a half-space: a finite body deviates by about 0.3 % in p0 and a at a/R ≈ 0.1, growing like (a/R)²".into(),
            "a is estimated from the pressure moment 2·sqrt(∫p x²/∫p); a_last_node is the last node with a positive pressure (within a node spacing)".into(),
        ],
    }
}

/// The quantities both Hertz references report, for the profile
/// p0 sqrt(1 − x²/a²) in the coordinate `s − centre`: the load, p0 (max nodal
/// pressure = force / tributary measure), a (from the pressure moment,
/// `a_mom`), the last node in contact, and the relative L2 error of the
/// profile on |x| ≤ a weighted by the tributary measures.
fn hertz_quantities(
    nodes: &[NodalPressure],
    centre: f64,
    total: f64,
    a_mom: f64,
    a: f64,
    p0: f64,
) -> BTreeMap<String, Quantity> {
    let pressures: Vec<(f64, f64, f64)> = nodes
        .iter()
        .map(|n| (n.s - centre, n.pressure, n.tributary))
        .collect();
    let p0_c = pressures.iter().fold(0.0f64, |m, p| m.max(p.1));
    let a_last = pressures
        .iter()
        .filter(|p| p.1 > 0.0)
        .fold(0.0f64, |m, p| m.max(p.0.abs()));
    let (mut num, mut den) = (0.0, 0.0);
    for &(x, p, w) in &pressures {
        if x.abs() <= a {
            let pe = p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt();
            num += (p - pe).powi(2) * w;
            den += pe * pe * w;
        }
    }
    let l2 = if den > 0.0 { (num / den).sqrt() } else { 0.0 };
    let mut q = BTreeMap::new();
    q.insert("load".to_string(), Quantity::new(total, total));
    q.insert("p0".to_string(), Quantity::new(p0_c, p0));
    q.insert("a".to_string(), Quantity::new(a_mom, a));
    q.insert("a_last_node".to_string(), Quantity::new(a_last, a));
    q.insert("profile_l2".to_string(), Quantity::new(l2, 0.0));
    q
}

/// Hertz, sphere on a plane (docs/theory/validation-cases.md §2): with P the total load, E*
/// the contact modulus and R the relative radius, a = (3PR/(4E*))^(1/3),
/// p0 = 3P/(2πa²) = (6PE*²/(π³R²))^(1/3) (this form, finite with no load).
pub fn hertz_sphere_exact(p: f64, e_star: f64, r: f64) -> (f64, f64) {
    let a = (3.0 * p * r / (4.0 * e_star)).cbrt();
    let pi = std::f64::consts::PI;
    (a, (6.0 * p * e_star * e_star / (pi.powi(3) * r * r)).cbrt())
}

/// Compares nodal pressures with the Hertz sphere. `s` of each node is its
/// distance from the axis of the contact (the radius r in an axisymmetric
/// model; in 3D the distance from the force-weighted centre in the contact
/// plane), `tributary` its area (2π r ds in an axisymmetric model). Reports
/// p0 (max nodal pressure), a from the pressure moment
/// a_mom = sqrt(5/2 · ∫p r² dA / ∫p dA) (exact for the Hertz profile:
/// ∫p r² dA / ∫p dA = 2a²/5; the moment from the nodal forces by
/// [`pressure_moment`], exact on quadratic faces, recombined or not), the
/// last node in contact and the relative L2 error of the profile on r ≤ a.
pub fn hertz_sphere(nodes: &[NodalPressure], e_star: f64, r: f64) -> ReferenceReport {
    let total: f64 = nodes.iter().map(|n| n.force).sum();
    let (a, p0) = hertz_sphere_exact(total, e_star, r);
    let second = pressure_moment(nodes, |s| s * s);
    let a_mom = if total > 0.0 {
        (2.5 * second / total).sqrt()
    } else {
        0.0
    };
    let q = hertz_quantities(nodes, 0.0, total, a_mom, a, p0);
    ReferenceReport {
        kind: "hertz_sphere".into(),
        quantities: q,
        notes: vec![
            format!("E* = {e_star:e}, R = {r:e}; the load P is the computed resultant contact force (the whole ring in an axisymmetric model)"),
            "Hertz assumes a half-space: a finite body deviates slightly, growing like (a/R)²".into(),
            "a is estimated from the pressure moment sqrt(5/2 · ∫p r² dA / ∫p dA); a_last_node is the last node with a positive pressure (within a node spacing)".into(),
        ],
    }
}

/// Uniform pressure (docs/theory/validation-cases.md §3): every contact point carries the
/// pressure p. `exact_pressure` is the applied traction when known, else the
/// mean pressure P / L over the slave surface.
pub fn uniform_pressure(
    nodes: &[NodalPressure],
    exact_pressure: Option<f64>,
    applied_resultant: Option<f64>,
) -> ReferenceReport {
    let total: f64 = nodes.iter().map(|n| n.force).sum();
    let length: f64 = nodes.iter().map(|n| n.tributary).sum();
    let p = exact_pressure.unwrap_or(if length > 0.0 { total / length } else { 0.0 });
    let mut worst = 0.0f64;
    let mut worst_p = p;
    for n in nodes.iter().filter(|n| n.tributary > 0.0) {
        let pi = n.pressure;
        let dev = (pi - p).abs();
        if dev >= worst {
            worst = dev;
            worst_p = pi;
        }
    }
    let mut q = BTreeMap::new();
    q.insert("pressure".to_string(), Quantity::new(worst_p, p));
    q.insert(
        "resultant".to_string(),
        Quantity::new(total, applied_resultant.unwrap_or(p * length)),
    );
    ReferenceReport {
        kind: "uniform_pressure".into(),
        quantities: q,
        notes: vec![
            "pressure: the nodal pressure (force / tributary length) farthest from the exact one; its relative_error is the largest deviation over the contact points".into(),
            "one-pass node-to-segment on non-matching meshes is known not to pass this patch test exactly (Taylor & Papadopoulos 1991): expect a deviation there; the resultant stays exact".into(),
        ],
    }
}

/// Cattaneo–Mindlin partial slip (docs/theory/validation-cases.md §6): two elastically similar
/// cylinders (`Strip`) or spheres (`Circle`, 3D), or one on a half-space of
/// the same material, under a normal load P, then a tangential load Q < μP:
/// stick zone half-width c = a (1 − Q/(μP))^k with k = 1/2 (cylinder) or
/// 1/3 (sphere), a and p0 Hertz's; shear traction
/// q(x) = μ p0 sqrt(1 − x²/a²) − μ p0 (c/a) sqrt(1 − x²/c²) for |x| < c and
/// μ p(x) for c ≤ |x| ≤ a. P and Q are the computed resultants; `s` of each
/// node is its coordinate across the contact (cylinder) or its distance from
/// the centre (sphere). `history` holds the tangential resultants of the
/// steps before the last, along the final tangential load (positive that
/// way): a load that did not only grow (unloading, reversal) is compared
/// with Mindlin and Deresiewicz's solution by Masing's rules (`masing.rs`).
pub fn cattaneo_mindlin(
    nodes: &[NodalPressure],
    shape: PunchShape,
    e_star: f64,
    r: f64,
    mu: f64,
    history: &[f64],
) -> ReferenceReport {
    let p_total: f64 = nodes.iter().map(|n| n.force).sum();
    let q_signed: f64 = nodes.iter().map(|n| n.tangential).sum();
    let q_total = q_signed.abs();
    let (a, p0, exponent) = match shape {
        PunchShape::Strip => {
            let (a, p0) = hertz_cylinder_exact(p_total, e_star, r);
            (a, p0, 0.5)
        }
        PunchShape::Circle => {
            let (a, p0) = hertz_sphere_exact(p_total, e_star, r);
            (a, p0, 1.0 / 3.0)
        }
    };
    let centre = match shape {
        PunchShape::Strip if p_total > 0.0 => {
            nodes.iter().map(|n| n.force * n.s).sum::<f64>() / p_total
        }
        _ => 0.0,
    };
    let ratio = if mu * p_total > 0.0 {
        q_total / (mu * p_total)
    } else {
        f64::NAN
    };
    let turning = masing::turning_points(&[history, &[q_total]].concat());
    let branches = masing::branches(&turning, a, mu * p_total, exponent);
    let c_exact = branches.last().map_or(a, |b| b.c);
    let c_computed = stick_half_width(nodes, centre);
    let sign = if q_signed < 0.0 { -1.0 } else { 1.0 };
    let (l2, no_shear) = shear_profile_l2(nodes, centre, sign, mu * p0, a, &branches);
    let mut qs = BTreeMap::new();
    qs.insert("load".to_string(), Quantity::new(p_total, p_total));
    qs.insert(
        "tangential_load_ratio".to_string(),
        Quantity::new(ratio, ratio),
    );
    qs.insert(
        "stick_half_width".to_string(),
        Quantity::new(c_computed, c_exact),
    );
    qs.insert(
        "shear_profile_l2".to_string(),
        Quantity {
            computed: l2,
            exact: 0.0,
            relative_error: l2,
        },
    );
    let notes = cattaneo_notes(shape, [e_star, r, mu], &turning, no_shear);
    ReferenceReport {
        kind: "cattaneo_mindlin".into(),
        quantities: qs,
        notes,
    }
}

/// The notes of [`cattaneo_mindlin`]: its data and formulas, what it
/// needs, how the stick zone is measured, and the load history's turning
/// points when the load was not monotone.
fn cattaneo_notes(
    shape: PunchShape,
    [e_star, r, mu]: [f64; 3],
    turning: &[f64],
    no_shear: bool,
) -> Vec<String> {
    let exponent = match shape {
        PunchShape::Strip => 0.5,
        PunchShape::Circle => 1.0 / 3.0,
    };
    let (body, zone) = match shape {
        PunchShape::Strip => ("a = sqrt(4PR/(πE*))", "c = a·sqrt(1 − Q/(μP))"),
        PunchShape::Circle => ("a = (3PR/(4E*))^(1/3)", "c = a·(1 − Q/(μP))^(1/3)"),
    };
    let mut notes = vec![
        format!("E* = {e_star:e}, R = {r:e}, μ = {mu}; P and Q are the computed resultants, {body}, {zone}"),
        "needs elastically similar bodies (same E and ν): for an elastic body on a rigid plane the normal and tangential problems couple and the stick zone is off-centre and narrower".into(),
        "stick_half_width is measured half a node spacing beyond the outermost sticking node (at the outermost loaded node when no loaded node slips beyond it)".into(),
    ];
    if turning.len() > 2 {
        notes.push(format!("the tangential load was not monotone: after Mindlin and Deresiewicz by Masing's rules, from the turning points Q = [{}] along the final load (each branch after a reversal adds twice Cattaneo's correction of its load change, c = a·(1 − |ΔQ|/(2μP))^{exponent:.3}); stick_half_width is the last branch's c", turning.iter().map(|q| format!("{q:.3e}")).collect::<Vec<_>>().join(", ")));
    }
    if no_shear {
        notes.push("Q/(μP) is round-off: the exact shear vanishes, and shear_profile_l2 is relative to the full-slip profile μp(x)".into());
    }
    notes
}

/// The stick zone of the computation, as a distance from `centre`: from the
/// outermost sticking point to the next loaded point out (half a spacing
/// beyond), on each side; a sticking point with no loaded point beyond it
/// reaches the edge of the contact and counts at its own distance.
fn stick_half_width(nodes: &[NodalPressure], centre: f64) -> f64 {
    let mut sorted: Vec<&NodalPressure> = nodes.iter().filter(|n| n.force > 0.0).collect();
    sorted.sort_by(|x, y| x.s.total_cmp(&y.s));
    let mut c = 0.0f64;
    for (i, n) in sorted.iter().enumerate().filter(|(_, n)| n.stick) {
        for j in [i.wrapping_sub(1), i + 1] {
            match sorted.get(j) {
                Some(m) if !m.stick => c = c.max(((n.s + m.s) / 2.0 - centre).abs()),
                Some(_) => {}
                None => c = c.max((n.s - centre).abs()),
            }
        }
    }
    c
}

/// The relative L2 error of the shear traction (tangential force over
/// tributary measure, times `sign` to point along the final tangential
/// load) against that of the load history's `branches` on |x| ≤ a, with
/// `mu_p0` = μ p0, and whether the exact shear
/// vanished: without a tangential load it is zero up to round-off (norm
/// below 1e-8 of the full-slip profile μp(x)'s), and the error is relative
/// to μp(x) instead of to that round-off.
fn shear_profile_l2(
    nodes: &[NodalPressure],
    centre: f64,
    sign: f64,
    mu_p0: f64,
    a: f64,
    branches: &[masing::Branch],
) -> (f64, bool) {
    let (mut num, mut den, mut slip) = (0.0, 0.0, 0.0);
    for n in nodes.iter().filter(|n| n.tributary > 0.0) {
        let x = n.s - centre;
        if x.abs() > a {
            continue;
        }
        let full = mu_p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt();
        let q = masing::shear(branches, x, mu_p0, a);
        let qc = sign * n.tangential / n.tributary;
        num += (qc - q).powi(2) * n.tributary;
        den += q * q * n.tributary;
        slip += full * full * n.tributary;
    }
    let no_shear = den <= 1e-16 * slip;
    let den = if no_shear { slip } else { den };
    let l2 = if den > 0.0 { (num / den).sqrt() } else { 0.0 };
    (l2, no_shear && slip > 0.0)
}

/// Block on a plane with Coulomb friction (docs/theory/validation-cases.md §5): when every
/// contact point slips the tangential reaction is μN; when it sticks, the
/// applied tangential load `applied` (if known).
pub fn sliding_block(nodes: &[NodalPressure], mu: f64, applied: Option<f64>) -> ReferenceReport {
    let n: f64 = nodes.iter().map(|p| p.force).sum();
    let t: f64 = nodes.iter().map(|p| p.tangential).sum::<f64>().abs();
    let sliding = nodes.iter().filter(|p| p.force > 0.0).all(|p| !p.stick);
    let exact = if sliding {
        mu * n
    } else {
        applied.unwrap_or(t)
    };
    let mut qs = BTreeMap::new();
    qs.insert("normal_load".to_string(), Quantity::new(n, n));
    qs.insert("tangential_reaction".to_string(), Quantity::new(t, exact));
    ReferenceReport {
        kind: "sliding_block".into(),
        quantities: qs,
        notes: vec![if sliding {
            format!("every contact point slips: the tangential reaction is μN with μ = {mu}")
        } else {
            "some contact points stick: the tangential reaction is the applied tangential load"
                .to_string()
        }],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` nodes evenly spaced over `[−a, a]`, `node(s, w)` at `s` with its
    /// trapezoidal weight `w`.
    fn sampled(a: f64, n: usize, node: impl Fn(f64, f64) -> NodalPressure) -> Vec<NodalPressure> {
        let h = 2.0 * a / (n - 1) as f64;
        (0..n)
            .map(|i| {
                let s = -a + i as f64 * h;
                let w = if i == 0 || i == n - 1 { h / 2.0 } else { h };
                node(s, w)
            })
            .collect()
    }

    /// Hertz's pressure p and Mindlin's shear q at distance `x` from the
    /// centre of a contact of half-width `a`, peak `p0` and stick zone `c`:
    /// q = μ p less the stick zone's μ p0 (c/a) sqrt(1 − (x/c)²).
    fn mindlin_traction(x: f64, a: f64, p0: f64, c: f64, mu: f64) -> (f64, f64) {
        let pe = p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt();
        let mut q = mu * pe;
        if x < c {
            q -= mu * p0 * (c / a) * (1.0 - (x / c).powi(2)).max(0.0).sqrt();
        }
        (pe, q)
    }

    /// The analytic Cattaneo–Mindlin traction, sampled finely, gives back c.
    #[test]
    fn cattaneo_mindlin_profile_sampled_finely_recovers_the_stick_zone() {
        let (e_star, r, p, mu, ratio) = (0.55, 1.0, 0.004, 0.3, 0.5);
        let (a, p0) = hertz_cylinder_exact(p, e_star, r);
        let c = a * (1.0f64 - ratio).sqrt();
        let nodes = sampled(a, 4001, |x, w| {
            let (pe, q) = mindlin_traction(x.abs(), a, p0, c, mu);
            NodalPressure {
                s: x,
                force: pe * w,
                tributary: w,
                pressure: pe,
                tangential: -q * w,
                stick: x.abs() < c,
                recombined: None,
            }
        });
        let rep = cattaneo_mindlin(&nodes, PunchShape::Strip, e_star, r, mu, &[]);
        let q = &rep.quantities;
        assert!(
            (q["tangential_load_ratio"].computed - ratio).abs() < 1e-3,
            "{}",
            q["tangential_load_ratio"].computed
        );
        assert!(q["stick_half_width"].relative_error < 1e-3);
        assert!(q["shear_profile_l2"].relative_error < 1e-2);
    }

    /// The 4001 nodes at s = i h (h = a / 4000) of a contact of radius `a`,
    /// each with the area w of its ring [s − h/2, s + h/2] within [0, a]:
    /// `node(s, w)`.
    fn rings(a: f64, node: impl Fn(f64, f64) -> NodalPressure) -> Vec<NodalPressure> {
        let n = 4000;
        let h = a / n as f64;
        (0..=n)
            .map(|i| {
                let s = i as f64 * h;
                let (lo, hi) = ((s - h / 2.0).max(0.0), (s + h / 2.0).min(a));
                node(s, std::f64::consts::PI * (hi * hi - lo * lo))
            })
            .collect()
    }

    /// Mindlin's traction on the rings of a sphere's contact (3D: `s` the
    /// distance from the centre, area 2π r dr) gives back
    /// c = a (1 − Q/(μP))^(1/3) with the sphere's a, not the cylinder's
    /// sqrt(1 − Q/(μP)) and a = sqrt(4PR/(πE*)) (2.4 times too small here).
    #[test]
    fn cattaneo_mindlin_sphere_rings_sampled_finely_recover_the_stick_zone() {
        let (e_star, r, p, mu, ratio) = (0.55, 1.0, 0.0009, 0.3, 0.4);
        let (a, p0) = hertz_sphere_exact(p, e_star, r);
        let c = a * (1.0f64 - ratio).cbrt();
        let nodes = rings(a, |x, w| {
            let (pe, q) = mindlin_traction(x, a, p0, c, mu);
            NodalPressure {
                s: x,
                force: pe * w,
                tributary: w,
                pressure: pe,
                tangential: q * w,
                stick: x < c,
                recombined: None,
            }
        });
        let rep = cattaneo_mindlin(&nodes, PunchShape::Circle, e_star, r, mu, &[]);
        let q = &rep.quantities;
        let ratio_c = q["tangential_load_ratio"].computed;
        assert!((ratio_c - ratio).abs() < 1e-3, "Q/μP = {ratio_c}");
        let load = q["load"].computed;
        let exact = (3.0 * load * r / (4.0 * e_star)).cbrt() * (1.0 - ratio_c).cbrt();
        let sw = &q["stick_half_width"];
        assert!(
            (sw.exact - exact).abs() <= 1e-12 * exact,
            "{sw:?} vs {exact}"
        );
        assert!(sw.relative_error < 1e-3, "{sw:?}");
        assert!(q["shear_profile_l2"].relative_error < 1e-2);
    }

    /// Every loaded point sticking: the stick zone reaches the outermost
    /// one (it was reported as 0, a relative error of 1).
    #[test]
    fn cattaneo_mindlin_all_sticking_reaches_the_outermost_loaded_point() {
        let (e_star, r, a) = (1.0, 1.0, 0.1);
        let nodes = sampled(a, 21, |s, w| NodalPressure {
            stick: true,
            tangential: 1e-3 * w,
            ..hertz_node(s, w, 1.0, 2.0 * a)
        });
        let rep = cattaneo_mindlin(&nodes, PunchShape::Strip, e_star, r, 0.3, &[]);
        let c = rep.quantities["stick_half_width"].computed;
        assert!((c - a).abs() <= 1e-12 * a, "stick half-width {c} vs {a}");
    }

    /// A last step with no contact (unloaded): every Hertz quantity is a
    /// number, p0 = 0 (2P/(πa) and 3P/(2πa²) were 0/0, null in report.json).
    #[test]
    fn hertz_references_without_load_report_zero_not_nan() {
        let open = [hertz_node(0.0, 0.1, 0.0, 1.0)];
        for rep in [
            hertz_cylinder(&open, 1.0, 1.0),
            hertz_sphere(&open, 1.0, 1.0),
        ] {
            for (name, q) in &rep.quantities {
                assert_eq!((q.exact, q.relative_error), (0.0, 0.0), "{name}: {q:?}");
            }
        }
        let (e_star, r, p) = (1.3, 0.7, 0.02);
        let (a, p0) = hertz_cylinder_exact(p, e_star, r);
        assert!((p0 - 2.0 * p / (std::f64::consts::PI * a)).abs() <= 1e-14 * p0);
        let (a, p0) = hertz_sphere_exact(p, e_star, r);
        assert!((p0 - 3.0 * p / (2.0 * std::f64::consts::PI * a * a)).abs() <= 1e-14 * p0);
    }

    /// Without a tangential load the exact shear vanishes: a computed shear of
    /// 0.1 % of μp(x) is an error of 0.1 % of the full-slip profile, not
    /// 1e14 times the round-off of the exact one (a third robustness sweep's
    /// cattaneo.toml without its pull step reported 1.3e14, converged).
    #[test]
    fn cattaneo_mindlin_without_tangential_load_is_measured_against_full_slip() {
        let (e_star, r, p, mu) = (0.55, 1.0, 0.004, 0.3);
        let (a, p0) = hertz_cylinder_exact(p, e_star, r);
        let nodes = sampled(a, 400, |x, w| {
            let pe = p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt();
            NodalPressure {
                s: x,
                force: pe * w,
                tributary: w,
                pressure: pe,
                tangential: 1e-3 * mu * pe * w * x.signum(),
                stick: true,
                recombined: None,
            }
        });
        let rep = cattaneo_mindlin(&nodes, PunchShape::Strip, e_star, r, mu, &[]);
        let l2 = rep.quantities["shear_profile_l2"].relative_error;
        assert!((l2 - 1e-3).abs() < 1e-4, "{l2}");
        assert!(rep.notes.iter().any(|n| n.contains("full-slip")));
    }

    /// An axisymmetric sampling of the Hertz sphere pressure (rings of area
    /// 2π r dr) gives back p0 and a from the moment estimate.
    #[test]
    fn hertz_sphere_rings_sampled_finely_recover_p0_and_a() {
        let (e_star, r, p) = (2.0, 0.5, 0.01);
        let (a, p0) = hertz_sphere_exact(p, e_star, r);
        assert!((p - 2.0 / 3.0 * std::f64::consts::PI * a * a * p0).abs() <= 1e-12 * p);
        let nodes = rings(a, |s, w| hertz_node(s, w, p0, a));
        let rep = hertz_sphere(&nodes, e_star, r);
        let q = &rep.quantities;
        assert!(q["p0"].relative_error < 1e-3, "{:?}", q["p0"]);
        assert!(q["a"].relative_error < 1e-3, "{:?}", q["a"]);
        assert!(q["profile_l2"].relative_error < 1e-2);
    }

    /// A node at `s` of tributary `w` carrying the exact Hertz pressure
    /// p0 √(1 − (s/a)²), stick-free.
    fn hertz_node(s: f64, w: f64, p0: f64, a: f64) -> NodalPressure {
        NodalPressure {
            s,
            force: p0 * (1.0 - (s / a).powi(2)).max(0.0).sqrt() * w,
            tributary: w,
            pressure: p0 * (1.0 - (s / a).powi(2)).max(0.0).sqrt(),
            tangential: 0.0,
            stick: false,
            recombined: None,
        }
    }

    #[test]
    fn hertz_profile_sampled_finely_recovers_p0_and_a() {
        let (e_star, r, p) = (1.1, 1.0, 0.02);
        let (a, p0) = hertz_cylinder_exact(p, e_star, r);
        assert!((p0 - (p * e_star / (std::f64::consts::PI * r)).sqrt()).abs() <= 1e-14 * p0);
        let nodes = sampled(a, 2001, |s, w| hertz_node(s, w, p0, a));
        let rep = hertz_cylinder(&nodes, e_star, r);
        assert!(rep.quantities["p0"].relative_error < 1e-3);
        assert!(rep.quantities["a"].relative_error < 1e-3);
        assert!(rep.quantities["profile_l2"].relative_error < 1e-2);
    }
}
