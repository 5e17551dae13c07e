//! Friction by analogy with plasticity (course notes §6): elastic asperities and
//! roughness, i.e. the regularised Coulomb law (§4.1.3) with linear
//! kinematic hardening of the slip.
//!
//! The tangential jump splits into the asperities' elastic part and the
//! irreversible slip g (course notes eq. 20), [u_t] = [u_t]^a + g, with the state
//! laws (eqs. 21, 22) t = P [u_t]^a = k_e ([u_t] − g) (P = k_e, the
//! `slip_stiffness`) and the back force X = Q g (Q, the `roughness`). The
//! threshold is Coulomb's (eq. 23) on the force relative to the back force,
//!
//!   f(t, X) = ‖t − Q g‖ − μ |t_n| ≤ 0,
//!
//! and the flow is non-associated (course notes fig. 15): ġ = γ̇ (t − Q g)/‖t − Q g‖,
//! γ̇ ≥ 0, γ̇ f = 0 (the slip goes along the force, not normal to the cone,
//! whose normal has a component along t_n). Q = 0 is the regularised law.
//! Eq. 23 as the course notes print it reads ‖F_t‖ alone: with F_t^g = Q g it is the
//! threshold of the force conjugate to the slip, F_t − F_t^g, as in
//! plasticity with linear kinematic hardening.
//!
//! [`return_map`] is the closed-form return mapping at one point for a
//! given normal force: trial t* = k_e ([u_t] − g_old), ξ* = t* − Q g_old;
//! if ‖ξ*‖ ≤ μ|t_n| the step is elastic, else Δg = (‖ξ*‖ − μ|t_n|)/(k_e + Q)
//! n with n = ξ*/‖ξ*‖, t = t* − k_e Δg, and ξ = t − Q g = μ|t_n| n.
//!
//! [`slip_tangent`] is its consistent tangent at a point that slips, the
//! Jacobian of Newton's method on contact elements (course notes §7):
//!
//! ```text
//!   ∂t/∂[u_t] = k_e Q/(k_e + Q) I + k_e² μ|t_n|/((k_e + Q)‖ξ*‖) (I − n nᵀ),
//!   ∂t/∂(μ|t_n|) = k_e/(k_e + Q) n.
//! ```

/// The result of [`return_map`] at one point.
#[derive(Debug, Clone, PartialEq)]
pub struct ReturnMap {
    /// The tangential traction t = k_e ([u_t] − g).
    pub traction: Vec<f64>,
    /// The slip g at the end of the step.
    pub slip: Vec<f64>,
    /// Whether the point slipped in the step (f = 0, Δg ≠ 0).
    pub slipped: bool,
}

/// The closed-form return mapping of linear kinematic hardening at one
/// point (course notes §6, see the module doc): the tangential jump `jump` ([u_t],
/// one or two components), the slip `slip_old` at the start of the step, the
/// threshold `mu_tn` = μ |t_n| and the stiffnesses k_e, Q (per unit area or
/// nodal, the same for all three).
pub fn return_map(jump: &[f64], slip_old: &[f64], mu_tn: f64, k_e: f64, q: f64) -> ReturnMap {
    let trial: Vec<f64> = jump
        .iter()
        .zip(slip_old)
        .map(|(u, g)| k_e * (u - g))
        .collect();
    let xi: Vec<f64> = trial.iter().zip(slip_old).map(|(t, g)| t - q * g).collect();
    let norm = xi.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm <= mu_tn {
        return ReturnMap {
            traction: trial,
            slip: slip_old.to_vec(),
            slipped: false,
        };
    }
    let gamma = (norm - mu_tn) / (k_e + q);
    let dg: Vec<f64> = xi.iter().map(|x| gamma * x / norm).collect();
    ReturnMap {
        traction: trial.iter().zip(&dg).map(|(t, d)| t - k_e * d).collect(),
        slip: slip_old.iter().zip(&dg).map(|(g, d)| g + d).collect(),
        slipped: true,
    }
}

/// The consistent tangent of [`return_map`] at a point that slips (module
/// doc), over its one or two tangential components.
#[derive(Debug, Clone, PartialEq)]
pub struct SlipTangent {
    /// ∂t/∂[u_t].
    pub jump: [[f64; 2]; 2],
    /// ∂t/∂(μ|t_n|).
    pub threshold: [f64; 2],
}

/// The consistent tangent of [`return_map`] with the same arguments, at a
/// point where it slips.
pub fn slip_tangent(jump: &[f64], slip_old: &[f64], mu_tn: f64, k_e: f64, q: f64) -> SlipTangent {
    let xi: Vec<f64> = (0..jump.len())
        .map(|i| k_e * (jump[i] - slip_old[i]) - q * slip_old[i])
        .collect();
    let norm = xi.iter().map(|x| x * x).sum::<f64>().sqrt();
    let a = k_e * k_e * mu_tn / ((k_e + q) * norm);
    let b = k_e * q / (k_e + q);
    let mut out = SlipTangent {
        jump: [[0.0; 2]; 2],
        threshold: [0.0; 2],
    };
    for (i, xi_i) in xi.iter().enumerate() {
        let ni = xi_i / norm;
        for (j, xi_j) in xi.iter().enumerate() {
            let nj = xi_j / norm;
            let delta = f64::from(i == j);
            out.jump[i][j] = b * delta + a * (delta - ni * nj);
        }
        out.threshold[i] = k_e / (k_e + q) * ni;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Loading, unloading and reversal of one point on the closed forms:
    /// yield at k_e u = μp, then t = (μ p k_e + k_e Q u)/(k_e + Q); elastic
    /// unloading of slope k_e; reverse yield at t − Q g = −μ p.
    #[test]
    fn return_map_follows_the_closed_forms_of_linear_kinematic_hardening() {
        let (k, q, mp) = (1000.0, 250.0, 3.0);
        let tol = 1e-12 * mp;
        let r = return_map(&[0.002], &[0.0], mp, k, q);
        assert!(!r.slipped && (r.traction[0] - 2.0).abs() <= tol);
        let u = 0.01;
        let r = return_map(&[u], &[0.0], mp, k, q);
        let t = (mp * k + k * q * u) / (k + q);
        assert!(
            r.slipped && (r.traction[0] - t).abs() <= tol,
            "{r:?} vs {t}"
        );
        assert!((r.traction[0] - q * r.slip[0] - mp).abs() <= tol);
        let g = r.slip[0];
        let back = return_map(&[u - 0.004], &[g], mp, k, q);
        assert!(!back.slipped && (back.traction[0] - (t - 4.0)).abs() <= tol);
        // Reverse yield exactly at t − Q g = −μp.
        let u_rev = g + (q * g - mp) / k;
        let at = return_map(&[u_rev + 1e-9], &[g], mp, k, q);
        assert!(!at.slipped);
        let past = return_map(&[u_rev - 1e-3], &[g], mp, k, q);
        assert!(past.slipped && (past.traction[0] - q * past.slip[0] + mp).abs() <= tol);
    }

    /// 3D: the slip goes along t − Q g (non-associated), the return lands on
    /// the circle ‖t − Q g‖ = μ p.
    #[test]
    fn return_map_in_the_plane_slips_along_the_relative_force() {
        let (k, q, mp) = (1000.0, 400.0, 3.0);
        let g_old = [0.001, -0.002];
        let r = return_map(&[0.02, 0.01], &g_old, mp, k, q);
        let xi = [r.traction[0] - q * r.slip[0], r.traction[1] - q * r.slip[1]];
        assert!((xi[0].hypot(xi[1]) - mp).abs() <= 1e-12 * mp);
        let dg = [r.slip[0] - g_old[0], r.slip[1] - g_old[1]];
        assert!((dg[0] * xi[1] - dg[1] * xi[0]).abs() <= 1e-12 * dg[0].hypot(dg[1]) * mp);
        assert!(dg[0] * xi[0] + dg[1] * xi[1] > 0.0);
    }
}
