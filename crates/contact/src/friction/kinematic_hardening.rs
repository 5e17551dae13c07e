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
//! On the condensed problem the point's unknown is taken as the slider force
//! ξ = t − Q g instead of t ([`harden`]): with the slip increments Δg as the
//! tangential gaps (course notes §4.4) and the compliance 1/k_e already on W's
//! tangential diagonal, ξ and Δg obey Coulomb's law exactly as the
//! regularised law's force and slip do, so every friction solver of the
//! crate (the fixed point on the normal forces, the status and Newton
//! methods, 3D) solves the hardened law, each point's stick/slip split being
//! the return mapping above. Eliminating t = ξ − Q (g_old + Δg) from the
//! gaps Δg = W_ho r_o + A t + q_h (A = W_hh + 1/k_e) gives, with
//! M = I + D A (D = diag Q) and Z = M⁻¹ D, c = g_old + q_h:
//!
//!   W'_oo = W_oo − W_oh Z W_ho,  W'_oh = W_oh M⁻¹,  W'_hh = A M⁻¹,
//!   q'_o = q_o − W_oh Z c,       q'_h = q_h − A Z c,
//!
//! symmetric (A M⁻¹ = (A⁻¹ + D)⁻¹) and positive; t = M⁻¹ ξ − Z (W_ho r_o + c)
//! recovers the traction for the displacement and the report.

use faer::prelude::Solve;
use faer::Mat;

use crate::delassus::DelassusProblem;
use crate::ContactError;

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

/// What [`harden`] keeps to recover the tractions t of the hardened rows
/// from the solution (r_o, ξ) of the transformed problem.
#[derive(Debug, Clone)]
pub struct Hardened {
    /// The hardened tangential rows (those with Q > 0).
    pub rows: Vec<usize>,
    /// Q of each hardened row.
    pub roughness: Vec<f64>,
    minv: Mat<f64>,
    z: Mat<f64>,
    /// W's hardened rows restricted to the other columns (zero on h).
    w_ho: Mat<f64>,
    /// c = g_old + q_h.
    c: Vec<f64>,
}

impl Hardened {
    /// The tractions t of the hardened rows from the forces `r` of the
    /// transformed problem (ξ on the hardened rows):
    /// t = M⁻¹ ξ − Z (W_ho r_o + c).
    pub fn tractions(&self, r: &[f64]) -> Vec<f64> {
        let k = self.rows.len();
        let xi: Vec<f64> = self.rows.iter().map(|&i| r[i]).collect();
        let wr: Vec<f64> = (0..k)
            .map(|a| {
                let row = (0..r.len()).map(|j| self.w_ho[(a, j)] * r[j]);
                row.sum::<f64>() + self.c[a]
            })
            .collect();
        (0..k)
            .map(|a| {
                (0..k)
                    .map(|b| self.minv[(a, b)] * xi[b] - self.z[(a, b)] * wr[b])
                    .sum()
            })
            .collect()
    }

    /// The forces of the original problem: `r` with the hardened rows' ξ
    /// replaced by the tractions t.
    pub fn physical_forces(&self, r: &[f64]) -> Vec<f64> {
        let mut out = r.to_vec();
        for (&i, t) in self.rows.iter().zip(self.tractions(r)) {
            out[i] = t;
        }
        out
    }
}

/// Takes the slider force ξ = t − Q g as the unknown of the tangential rows
/// `rows` with roughness `roughness` (> 0) and slip `slip_old` at the start
/// of the step (module doc): transforms the problem's W and q in place. Call
/// it on a fresh step problem, after [`DelassusProblem::add_compliance`] and
/// before any solve. The rigid modes of floating bodies must not move the
/// hardened rows (G_h = 0), else the elimination would couple ξ with the
/// modes' amplitudes: refused.
pub fn harden(
    problem: &mut DelassusProblem,
    rows: &[usize],
    roughness: &[f64],
    slip_old: &[f64],
) -> Result<Hardened, ContactError> {
    let (n, k) = (problem.w.nrows(), rows.len());
    // G = B R with R orthonormal: an entry of a hardened row is round-off
    // against G's largest entry, or a real motion.
    let g = &problem.g_mat;
    let g_max = (0..n).fold(0.0f64, |a, i| {
        (0..g.ncols()).fold(a, |a, j| a.max(g[(i, j)].abs()))
    });
    let moved = rows
        .iter()
        .any(|&i| (0..g.ncols()).any(|j| g[(i, j)].abs() > 1e-10 * g_max));
    if moved {
        return Err(ContactError::Geometry(
            "friction roughness: a rigid motion of a floating body slides a rough contact point; hold the body tangentially (a support) to use roughness".into(),
        ));
    }
    let mut in_h = vec![false; n];
    rows.iter().for_each(|&i| in_h[i] = true);
    let a = Mat::<f64>::from_fn(k, k, |x, y| problem.w[(rows[x], rows[y])]);
    let m = Mat::<f64>::from_fn(k, k, |x, y| f64::from(x == y) + roughness[x] * a[(x, y)]);
    let minv = m.full_piv_lu().solve(&Mat::<f64>::identity(k, k));
    let z = Mat::<f64>::from_fn(k, k, |x, y| minv[(x, y)] * roughness[y]);
    let w_ho = Mat::<f64>::from_fn(k, n, |x, j| {
        if in_h[j] {
            0.0
        } else {
            problem.w[(rows[x], j)]
        }
    });
    let c: Vec<f64> = (0..k).map(|x| slip_old[x] + problem.q[rows[x]]).collect();
    let hardened = Hardened {
        rows: rows.to_vec(),
        roughness: roughness.to_vec(),
        minv,
        z,
        w_ho,
        c,
    };
    transform(problem, &hardened, &a, &in_h);
    Ok(hardened)
}

/// W' and q' of the module doc, then symmetrised against round-off.
fn transform(problem: &mut DelassusProblem, h: &Hardened, a: &Mat<f64>, in_h: &[bool]) {
    let (n, k) = (problem.w.nrows(), h.rows.len());
    let w_oh = h.w_ho.transpose().to_owned(); // n × k, zero on hardened rows
    let zw = &h.z * &h.w_ho; // k × n
    let zc: Vec<f64> = (0..k)
        .map(|x| (0..k).map(|y| h.z[(x, y)] * h.c[y]).sum())
        .collect();
    let w_oh_minv = &w_oh * &h.minv; // n × k
    let a_minv = a * &h.minv;
    let a_z = a * &h.z;
    let a_zw = &a_z * &h.w_ho; // k × n
    let mut w = problem.w.clone();
    let mut q = problem.q.clone();
    for i in (0..n).filter(|&i| !in_h[i]) {
        for j in (0..n).filter(|&j| !in_h[j]) {
            w[(i, j)] -= (0..k).map(|x| w_oh[(i, x)] * zw[(x, j)]).sum::<f64>();
        }
        for (y, &hj) in h.rows.iter().enumerate() {
            w[(i, hj)] = w_oh_minv[(i, y)];
        }
        q[i] -= (0..k).map(|x| w_oh[(i, x)] * zc[x]).sum::<f64>();
    }
    for (x, &hi) in h.rows.iter().enumerate() {
        for j in (0..n).filter(|&j| !in_h[j]) {
            w[(hi, j)] = h.w_ho[(x, j)] - a_zw[(x, j)];
        }
        for (y, &hj) in h.rows.iter().enumerate() {
            w[(hi, hj)] = a_minv[(x, y)];
        }
        q[hi] -= (0..k).map(|y| a_z[(x, y)] * h.c[y]).sum::<f64>();
    }
    problem.w = Mat::from_fn(n, n, |i, j| 0.5 * (w[(i, j)] + w[(j, i)]));
    problem.q = q;
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

    /// The transformed problem of one rough point on a rigid support (W = 0,
    /// compliance 1/k_e) held by friction at the slider force ξ = ±μ p gives
    /// the return mapping's traction and slip.
    #[test]
    fn harden_recovers_the_return_mapping_at_one_point() {
        let (k, q, mp) = (1000.0, 250.0, 3.0);
        let (u, g_old) = (0.01, 0.0005);
        // Rows: 0 normal, 1 tangential. In the crate's signs the force is
        // λ = −t, the gap the slip increment Δg = (u − g_old) + λ/k_e (W = 0),
        // and the slider force λ + Q g = −ξ.
        let w = Mat::<f64>::from_fn(2, 2, |i, j| if i == 1 && j == 1 { 1.0 / k } else { 0.0 });
        let mut p = DelassusProblem::from_operator(w, vec![0.0, u - g_old]);
        let h = harden(&mut p, &[1], &[q], &[g_old]).unwrap();
        // Slipping: the slider force (λ + Q g in these signs) is −μp.
        let xi = -mp;
        let lambda = h.tractions(&[1.0, xi])[0];
        let dg = p.w[(1, 1)] * xi + p.q[1];
        let r = return_map(&[u], &[g_old], mp, k, q);
        assert!(
            (-lambda - r.traction[0]).abs() <= 1e-9 * mp,
            "{lambda} {r:?}"
        );
        assert!((g_old + dg - r.slip[0]).abs() <= 1e-12, "{dg} {r:?}");
    }
}
