//! Roughness on the condensed problem (course notes §6): elastic asperities
//! and linear kinematic hardening of the slip, the law and its return
//! mapping being [`crate::law::hardening`]'s.
//!
//! On the condensed problem the point's unknown is taken as the slider force
//! ξ = t − Q g instead of t ([`harden`]): with the slip increments Δg as the
//! tangential gaps (course notes §4.4) and the compliance 1/k_e already on W's
//! tangential diagonal, ξ and Δg obey Coulomb's law exactly as the
//! regularised law's force and slip do, so every friction solver of the
//! crate (the fixed point on the normal forces, the status and Newton
//! methods, 3D) solves the hardened law, each point's stick/slip split being
//! the return mapping ([`crate::law::hardening::return_map`]). Eliminating
//! t = ξ − Q (g_old + Δg) from the gaps Δg = W_ho r_o + A t + q_h (A = W_hh + 1/k_e) gives, with
//! M = I + D A (D = diag Q) and Z = M⁻¹ D, c = g_old + q_h:
//!
//!   W'_oo = W_oo − W_oh Z W_ho,  W'_oh = W_oh M⁻¹,  W'_hh = A M⁻¹,
//!   q'_o = q_o − W_oh Z c,       q'_h = q_h − A Z c,
//!
//! symmetric (A M⁻¹ = (A⁻¹ + D)⁻¹) and positive; t = M⁻¹ ξ − Z (W_ho r_o + c)
//! recovers the traction for the displacement and the report.
//!
//! Floating bodies. When rigid modes α move the hardened rows (G_h ≠ 0: a
//! block dragged by its top, free to turn about it), the gaps gain G α and
//! the equilibrium Gᵀ r = e reads, in (r', α) with r' = (r_o, ξ),
//!
//!   G'ᵀ r' − C α = e',  G' = [G_o − W_oh Z G_h ; M⁻ᵀ G_h],
//!   C = G_hᵀ Z G_h,     e' = e + G_hᵀ Z c,
//!
//! the gaps being W' r' + G' α + q' (M⁻ᵀ = I − A Z, Z symmetric): the back
//! forces Q g hold the modes that slide rough points as springs. With V2
//! the modes that move hardened rows (C22 = V2ᵀ C V2 positive) and V1 the
//! others (G_h V1 = 0), β2 = C22⁻¹ (G'_2ᵀ r' − V2ᵀ e') is eliminated:
//! W'' = W' + G'_2 C22⁻¹ G'_2ᵀ, q'' = q' − G'_2 C22⁻¹ V2ᵀ e', and the modes V1
//! keep the usual equilibrium (G' V1)ᵀ r' = V1ᵀ e. A mode that slides rough
//! points and moves no other row (a block pushed sideways with no support)
//! would be held by the roughness alone, however far it slides: refused.

use faer::prelude::Solve;
use faer::Mat;

use crate::delassus::DelassusProblem;
use crate::ContactError;

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
    /// G's hardened rows, G_h = B_h R.
    g_h: Mat<f64>,
    /// The floating bodies' modes that slide rough points, eliminated.
    held: Option<HeldModes>,
}

/// The modes α = V1 β1 + V2 β2 of the floating bodies when some slide rough
/// points (G_h V2 ≠ 0, G_h V1 = 0): the back forces Q g hold those, and β2
/// is eliminated (module doc, "Floating bodies").
#[derive(Debug, Clone)]
struct HeldModes {
    v1: Mat<f64>,
    v2: Mat<f64>,
    /// C22⁻¹, C22 = V2ᵀ G_hᵀ Z G_h V2.
    c22_inv: Mat<f64>,
    /// G' V2 (m × k2) and V2ᵀ e'.
    g2: Mat<f64>,
    e2: Vec<f64>,
    /// The operator's basis R of all the modes.
    r_full: Mat<f64>,
}

impl Hardened {
    /// The tractions t of the hardened rows from the forces `r` of the
    /// transformed problem (ξ on the hardened rows) and the amplitudes
    /// `alpha` of all the modes: t = M⁻¹ ξ − Z (W_ho r_o + G_h α + c).
    pub fn tractions(&self, r: &[f64], alpha: &[f64]) -> Vec<f64> {
        let k = self.rows.len();
        let xi: Vec<f64> = self.rows.iter().map(|&i| r[i]).collect();
        let wr: Vec<f64> = (0..k)
            .map(|a| {
                let row = (0..r.len()).map(|j| self.w_ho[(a, j)] * r[j]);
                let modes = (0..alpha.len()).map(|j| self.g_h[(a, j)] * alpha[j]);
                row.sum::<f64>() + modes.sum::<f64>() + self.c[a]
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

    /// Whether rigid modes that slide rough points were eliminated.
    pub fn holds_modes(&self) -> bool {
        self.held.is_some()
    }

    /// The forces of the original problem: `r` with the hardened rows' ξ
    /// replaced by the tractions t. When modes were eliminated, gives
    /// `problem` back all of them with their amplitudes (for
    /// [`DelassusProblem::displacement`]).
    pub fn physical_forces(&self, problem: &mut DelassusProblem, r: &[f64]) -> Vec<f64> {
        let alpha = match &self.held {
            None => problem.alpha().to_vec(),
            Some(h) => {
                let beta1 = problem.alpha().to_vec();
                let k2 = h.v2.ncols();
                let rhs: Vec<f64> = (0..k2)
                    .map(|j| (0..r.len()).map(|i| h.g2[(i, j)] * r[i]).sum::<f64>() - h.e2[j])
                    .collect();
                let beta2: Vec<f64> = (0..k2)
                    .map(|a| (0..k2).map(|b| h.c22_inv[(a, b)] * rhs[b]).sum())
                    .collect();
                let alpha: Vec<f64> = (0..h.v1.nrows())
                    .map(|x| {
                        let one = (0..beta1.len()).map(|j| h.v1[(x, j)] * beta1[j]);
                        let two = (0..k2).map(|j| h.v2[(x, j)] * beta2[j]);
                        one.sum::<f64>() + two.sum::<f64>()
                    })
                    .collect();
                problem.set_kernel_basis(h.r_full.clone());
                problem.set_alpha(&alpha);
                alpha
            }
        };
        let mut out = r.to_vec();
        for (&i, t) in self.rows.iter().zip(self.tractions(r, &alpha)) {
            out[i] = t;
        }
        out
    }
}

/// Takes the slider force ξ = t − Q g as the unknown of the tangential rows
/// `rows` with roughness `roughness` (> 0) and slip `slip_old` at the start
/// of the step (module doc): transforms the problem's W and q in place, and
/// when rigid modes of floating bodies move the hardened rows (G_h ≠ 0), its
/// G and e too, eliminating those modes. Call it on a fresh step problem,
/// after [`DelassusProblem::add_compliance`] and before any solve; after the
/// solve, [`Hardened::physical_forces`]. A rigid motion that slides rough
/// points and moves no other row (held by the roughness alone) is refused.
pub fn harden(
    problem: &mut DelassusProblem,
    rows: &[usize],
    roughness: &[f64],
    slip_old: &[f64],
) -> Result<Hardened, ContactError> {
    let (n, k) = (problem.w.nrows(), rows.len());
    let mut in_h = vec![false; n];
    rows.iter().for_each(|&i| in_h[i] = true);
    let split = split_modes(&problem.g_mat, &in_h)?;
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
    let g_h = Mat::<f64>::from_fn(k, problem.g_mat.ncols(), |x, j| problem.g_mat[(rows[x], j)]);
    let mut hardened = Hardened {
        rows: rows.to_vec(),
        roughness: roughness.to_vec(),
        minv,
        z,
        w_ho,
        c,
        g_h,
        held: None,
    };
    transform(problem, &hardened, &a, &in_h);
    if let Some((v1, v2)) = split {
        hardened.held = Some(hold_modes(problem, &hardened, &in_h, v1, v2));
    }
    Ok(hardened)
}

/// The bases (V1, V2) of the modes that do not and that do move the
/// hardened rows.
type ModeSplit = (Mat<f64>, Mat<f64>);

/// The modes split by whether they move the hardened rows (`in_h`): `None`
/// when none does (G_h = 0 to round-off against G's largest entry), else
/// orthonormal V1 (G_h V1 = 0) and V2 (the rest). Refused: a mode that
/// moves hardened rows and no other row.
fn split_modes(g: &Mat<f64>, in_h: &[bool]) -> Result<Option<ModeSplit>, ContactError> {
    let (m, k) = (g.nrows(), g.ncols());
    let g_max = (0..m).fold(0.0f64, |a, i| (0..k).fold(a, |a, j| a.max(g[(i, j)].abs())));
    let tol = 1e-10 * g_max * (m as f64).sqrt();
    // Eigenvectors of Σ g_i g_iᵀ over the rows `on`, by increasing
    // eigenvalue, and the count of those that move them (√s > tol).
    let gram = |on: bool| {
        let mut s = Mat::<f64>::zeros(k, k);
        for i in (0..m).filter(|&i| in_h[i] == on) {
            for a in 0..k {
                for b in 0..k {
                    s[(a, b)] += g[(i, a)] * g[(i, b)];
                }
            }
        }
        let eig = s.self_adjoint_eigen(faer::Side::Lower).ok()?;
        let moving = (0..k).filter(|&j| eig.S()[j].max(0.0).sqrt() > tol).count();
        Some((eig.U().to_owned(), moving))
    };
    let singular =
        || ContactError::Singular("friction roughness: the modes' eigenproblem failed".into());
    let (u_h, moving_h) = gram(true).ok_or_else(singular)?;
    if k == 0 || moving_h == 0 {
        return Ok(None);
    }
    let (u_o, moving_o) = gram(false).ok_or_else(singular)?;
    // The modes that move no other row: must not move the hardened ones.
    for j in 0..k - moving_o {
        let slides = (0..m).filter(|&i| in_h[i]).any(|i| {
            let v = (0..k).map(|a| g[(i, a)] * u_o[(a, j)]).sum::<f64>();
            v.abs() > tol
        });
        if slides {
            return Err(ContactError::Geometry(
                "friction roughness: a rigid motion of a floating body slides rough contact points and moves no other contact row (only the roughness would hold it); hold the body tangentially (a support) to use roughness".into(),
            ));
        }
    }
    let k1 = k - moving_h;
    let v1 = Mat::<f64>::from_fn(k, k1, |a, j| u_h[(a, j)]);
    let v2 = Mat::<f64>::from_fn(k, moving_h, |a, j| u_h[(a, k1 + j)]);
    Ok(Some((v1, v2)))
}

/// Eliminates the modes V2 that slide rough points from the transformed
/// problem (module doc, "Floating bodies"): W'' = W' + G'_2 C22⁻¹ G'_2ᵀ,
/// q'' = q' − G'_2 C22⁻¹ V2ᵀ e', and the modes V1 left with G' V1, V1ᵀ e.
fn hold_modes(
    problem: &mut DelassusProblem,
    h: &Hardened,
    in_h: &[bool],
    v1: Mat<f64>,
    v2: Mat<f64>,
) -> HeldModes {
    let (n, k) = (problem.w.nrows(), problem.g_mat.ncols());
    let g = &problem.g_mat;
    // G' = [G_o − W_oh Z G_h ; M⁻ᵀ G_h], e' = e + G_hᵀ Z c.
    let zg = &h.z * &h.g_h;
    let w_oh_zg = h.w_ho.transpose() * &zg;
    let mt_g = h.minv.transpose() * &h.g_h;
    let mut g_new = Mat::<f64>::from_fn(n, k, |i, j| {
        if in_h[i] {
            0.0
        } else {
            g[(i, j)] - w_oh_zg[(i, j)]
        }
    });
    for (x, &hi) in h.rows.iter().enumerate() {
        for j in 0..k {
            g_new[(hi, j)] = mt_g[(x, j)];
        }
    }
    let zc: Vec<f64> = (0..h.rows.len())
        .map(|x| (0..h.rows.len()).map(|y| h.z[(x, y)] * h.c[y]).sum())
        .collect();
    let e_new: Vec<f64> = (0..k)
        .map(|j| {
            problem.e[j]
                + (0..h.rows.len())
                    .map(|x| h.g_h[(x, j)] * zc[x])
                    .sum::<f64>()
        })
        .collect();
    let c_modes = h.g_h.transpose() * &zg;
    let c22 = v2.transpose() * &c_modes * &v2;
    let k2 = v2.ncols();
    let c22_inv = c22.full_piv_lu().solve(&Mat::<f64>::identity(k2, k2));
    let g2 = &g_new * &v2;
    let e2: Vec<f64> = (0..k2)
        .map(|j| (0..k).map(|a| v2[(a, j)] * e_new[a]).sum())
        .collect();
    let g2c = &g2 * &c22_inv;
    let w = &problem.w + &g2c * g2.transpose();
    problem.w = Mat::from_fn(n, n, |i, j| 0.5 * (w[(i, j)] + w[(j, i)]));
    for i in 0..n {
        problem.q[i] -= (0..k2).map(|j| g2c[(i, j)] * e2[j]).sum::<f64>();
    }
    let r_full = problem.kernel_basis().clone();
    problem.g_mat = &g_new * &v1;
    problem.e = (0..v1.ncols())
        .map(|j| (0..k).map(|a| v1[(a, j)] * problem.e[a]).sum())
        .collect();
    problem.set_kernel_basis(&r_full * &v1);
    HeldModes {
        v1,
        v2,
        c22_inv,
        g2,
        e2,
        r_full,
    }
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
    use crate::law::hardening::return_map;

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
        let lambda = h.tractions(&[1.0, xi], &[])[0];
        let dg = p.w[(1, 1)] * xi + p.q[1];
        let r = return_map(&[u], &[g_old], mp, k, q);
        assert!(
            (-lambda - r.traction[0]).abs() <= 1e-9 * mp,
            "{lambda} {r:?}"
        );
        assert!((g_old + dg - r.slip[0]).abs() <= 1e-12, "{dg} {r:?}");
    }
}
