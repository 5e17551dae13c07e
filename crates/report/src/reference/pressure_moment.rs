//! The moments `∫ p g dA` of the contact pressure from the nodal contact
//! forces, for a function `g` of the coordinate across the contact (`r²` for
//! the radius of a Hertz contact, docs/theory/validation-cases.md §2).
//!
//! A node's force is `F_a = ∫ p φ_a dA` with `φ_a` its shape function on the
//! slave faces, so `Σ F_a g_a = ∫ p g dA` exactly wherever `g = Σ φ_a g_a`:
//! with the faces' own basis, `g_a = g(x_a)` interpolates `g` (exactly for a
//! `g` of the faces' degree: `r²` on flat quadratic faces). On a quadratic
//! face whose slave basis is recombined edge by edge
//! (docs/theory/elements.md, `φ_c = N_c + α Σ N_m` at a corner,
//! `φ_m = (1 − 2α) N_m` at a mid-side), the forces are those of the
//! recombined functions, and `Σ φ_a g_a = Σ N_k g(x_k)` asks of a mid-side
//! node the value
//!
//! ```text
//! g_m = (g(x_m) − α (g(x_c1) + g(x_c2))) / (1 − 2α)
//! ```
//!
//! (corners keep `g(x_c)`). Taking `g(x_m)` there instead weighs α of the
//! mid-side's share at the corners' `g`: for `g = r²` and an edge of length h
//! across the rings, `(r_c1² + r_c2²)/2 − r_m² = h²/4`, a bias of order
//! `α h²/a²` in the Hertz radius a that does not fall with the solution's
//! error (it over-estimated a by 0.3–3.6 % on Hex20 hemispheres).

use super::NodalPressure;

/// The recombination of a mid-side node's shape function: the coordinates
/// (across the contact) of the two corners of its edge and the weight α.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recombined {
    pub corners: [f64; 2],
    pub alpha: f64,
}

/// `∫ p g(s) dA` from the nodal forces (see the module docs): `Σ F g(s)`, a
/// recombined mid-side node taking `(g(s) − α (g(s_c1) + g(s_c2))) / (1 − 2α)`.
pub fn pressure_moment(nodes: &[NodalPressure], g: impl Fn(f64) -> f64) -> f64 {
    nodes
        .iter()
        .map(|n| match n.recombined {
            None => n.force * g(n.s),
            Some(r) => {
                let corners = g(r.corners[0]) + g(r.corners[1]);
                n.force * (g(n.s) - r.alpha * corners) / (1.0 - 2.0 * r.alpha)
            }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::{hertz_sphere, hertz_sphere_exact};
    use std::collections::BTreeMap;

    const ALPHA: f64 = 0.2;

    /// The serendipity Quad8 functions at (ξ, η): corners (−1,−1), (1,−1),
    /// (1,1), (−1,1), then the mid-sides of the edges 0–1, 1–2, 2–3, 3–0.
    fn quad8(xi: f64, eta: f64) -> [f64; 8] {
        let c = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let mut n = [0.0; 8];
        for (k, &(a, b)) in c.iter().enumerate() {
            n[k] = 0.25 * (1.0 + a * xi) * (1.0 + b * eta) * (a * xi + b * eta - 1.0);
        }
        n[4] = 0.5 * (1.0 - xi * xi) * (1.0 - eta);
        n[5] = 0.5 * (1.0 + xi) * (1.0 - eta * eta);
        n[6] = 0.5 * (1.0 - xi * xi) * (1.0 + eta);
        n[7] = 0.5 * (1.0 - xi) * (1.0 - eta * eta);
        n
    }

    /// Hertz's pressure on a flat grid of n × n Quad8 faces over
    /// [−half, half]², integrated against the recombined functions
    /// (5-point Gauss on 12 × 12 sub-cells of each face, for the square-root
    /// edge at r = a): the nodes with their forces and measures. Node keys
    /// are positions on the grid of half-faces.
    fn sampled_on_quad8(n: usize, half: f64, p0: f64, a: f64) -> Vec<NodalPressure> {
        let gp = [
            (-0.906_179_845_938_664, 0.236_926_885_056_189),
            (-0.538_469_310_105_683, 0.478_628_670_499_366),
            (0.0, 0.568_888_888_888_889),
            (0.538_469_310_105_683, 0.478_628_670_499_366),
            (0.906_179_845_938_664, 0.236_926_885_056_189),
        ];
        let h = 2.0 * half / n as f64;
        let pos = |k: usize| -half + 0.5 * h * k as f64;
        let mut force: BTreeMap<(usize, usize), (f64, f64)> = BTreeMap::new();
        let sub = 12;
        for (ei, ej) in (0..n).flat_map(|i| (0..n).map(move |j| (i, j))) {
            let keys = [
                (2 * ei, 2 * ej),
                (2 * ei + 2, 2 * ej),
                (2 * ei + 2, 2 * ej + 2),
                (2 * ei, 2 * ej + 2),
                (2 * ei + 1, 2 * ej),
                (2 * ei + 2, 2 * ej + 1),
                (2 * ei + 1, 2 * ej + 2),
                (2 * ei, 2 * ej + 1),
            ];
            for (si, sj) in (0..sub).flat_map(|i| (0..sub).map(move |j| (i, j))) {
                for &(u, wu) in &gp {
                    for &(v, wv) in &gp {
                        let xi = -1.0 + (2.0 * si as f64 + 1.0 + u) / sub as f64;
                        let eta = -1.0 + (2.0 * sj as f64 + 1.0 + v) / sub as f64;
                        let (x, y) = (
                            pos(2 * ei + 1) + xi * h / 2.0,
                            pos(2 * ej + 1) + eta * h / 2.0,
                        );
                        let r2 = (x * x + y * y) / (a * a);
                        let p = p0 * (1.0 - r2).max(0.0).sqrt();
                        let w = wu * wv * (h / 2.0 / sub as f64).powi(2);
                        let nf = quad8(xi, eta);
                        let mut rec = nf;
                        for (m, [c1, c2]) in [(4, [0, 1]), (5, [1, 2]), (6, [2, 3]), (7, [3, 0])] {
                            rec[c1] += ALPHA * nf[m];
                            rec[c2] += ALPHA * nf[m];
                            rec[m] = (1.0 - 2.0 * ALPHA) * nf[m];
                        }
                        for (k, key) in keys.iter().enumerate() {
                            let e = force.entry(*key).or_insert((0.0, 0.0));
                            e.0 += w * p * rec[k];
                            e.1 += w * rec[k];
                        }
                    }
                }
            }
        }
        let radius = |i: usize, j: usize| pos(i).hypot(pos(j));
        force
            .into_iter()
            .map(|((i, j), (f, measure))| NodalPressure {
                s: radius(i, j),
                force: f,
                tributary: measure,
                pressure: f / measure,
                tangential: 0.0,
                stick: false,
                recombined: match (i % 2, j % 2) {
                    (1, _) => Some([radius(i - 1, j), radius(i + 1, j)]),
                    (_, 1) => Some([radius(i, j - 1), radius(i, j + 1)]),
                    _ => None,
                }
                .map(|corners| Recombined {
                    corners,
                    alpha: ALPHA,
                }),
            })
            .collect()
    }

    /// Hertz's pressure sampled on recombined Quad8 faces (h = a/5) gives
    /// back a to the quadrature's accuracy (1.4e-6); the moment of the
    /// forces at the nodes' own radii (the estimator before) over-estimates
    /// it by 0.67 %, of order α h²/a². The load is that of the profile
    /// (2π a² p0 / 3).
    #[test]
    fn hertz_pressure_on_recombined_quad8_faces_gives_back_a() {
        let (e_star, r, p) = (1.0, 1.0, 0.004);
        let (a, p0) = hertz_sphere_exact(p, e_star, r);
        let nodes = sampled_on_quad8(12, 1.2 * a, p0, a);
        let total: f64 = nodes.iter().map(|n| n.force).sum();
        assert!((total - p).abs() < 1e-5 * p, "load {total} vs {p}");
        let rep = hertz_sphere(&nodes, e_star, r);
        let q = &rep.quantities["a"];
        assert!(q.relative_error < 1e-5, "{q:?}");
        assert!((q.computed - a).abs() < 1e-5 * a, "{q:?} vs {a}");
        let naive: Vec<NodalPressure> = nodes
            .into_iter()
            .map(|n| NodalPressure {
                recombined: None,
                ..n
            })
            .collect();
        let before = hertz_sphere(&naive, e_star, r).quantities["a"].relative_error;
        assert!(before > 1e-3, "{before}");
        // p0 is the pole node's force over its measure, a weighted mean of
        // the pressure about the pole: within O((h/a)²) of the peak (0.41 %
        // here, h/a = 1/5)
        let p0_error = rep.quantities["p0"].relative_error;
        let h = 2.4 * a / 12.0;
        assert!(p0_error < 0.2 * (h / a).powi(2), "{p0_error}");
    }
}
