//! Condition estimates for the report (report.json `conditioning`, see
//! [`signorini_report::Conditioning`] and docs/reference/outputs.md).
//!
//! Every estimate is κ₁ = ‖A‖₁ ‖A⁻¹‖₁ with ‖A⁻¹‖₁ from the Hager–Higham
//! estimator (`signorini_linalg::conditioning`) on a factorisation the run
//! makes anyway, except W (one dense Cholesky of the m × m Delassus operator,
//! once per run, m ≤ [`MAX_W_SIZE`]) and, on the direct path, K (one sparse
//! LDLᵀ of the whole stiffness in the KKT's ordering, timed apart:
//! `timings_s.conditioning`, only with `solver.condition_estimate = true`).
//!
//! Condensed path: κ(K_II) per subdomain (computed by the rank that owns it
//! and sent with its Schur complement), κ(S) from the root's Cholesky of S
//! (S + ρRRᵀ with floating bodies), κ(W) at the first step. Direct path: κ(K).
//!
//! The warning rule: digits_lost = log10 max κ, digits_available =
//! 15.65 − digits_lost, digits_needed = −log10(tolerance); warn when
//! digits_available < digits_needed.

use faer::Mat;
use signorini_condense::interface::{InterfaceFactorStats, InterfaceOperator, InterfaceStiffness};
use signorini_contact::{ContactError, DelassusOperator};
use signorini_linalg::conditioning::{dense_spd_condition, digits_lost, F64_DIGITS};
use signorini_linalg::sparse::SparseRow;
use signorini_report::Conditioning;

use crate::kkt::KktSystem;
use crate::subdomain::CondensedData;

/// W is estimated by a dense Cholesky only up to this many contact rows
/// (m³/3 flops: about a second at m = 4000).
pub const MAX_W_SIZE: usize = 4000;

/// The name of the estimator in the report.
pub const METHOD: &str = "hager_higham_1norm";

/// The root's estimates, made when the first Delassus problem is built.
#[derive(Debug, Default)]
pub(crate) struct RootConditioning {
    s: Option<f64>,
    w: Option<f64>,
    notes: Vec<String>,
    /// Notes that are warnings too (they go to the report's messages).
    warnings: Vec<String>,
    done: bool,
    /// How the first operator factorised S (report.json
    /// `factorisation.interface`).
    interface: Option<signorini_report::InterfaceFactorisation>,
}

impl RootConditioning {
    /// The interface factorisation of the first operator built.
    pub(crate) fn interface_factorisation(
        &self,
    ) -> Option<signorini_report::InterfaceFactorisation> {
        self.interface.clone()
    }
}

/// The note for κ(K) left out on the direct path.
pub const NOT_ASKED_K: &str = "k: not estimated: it costs a factorisation of K of its own, about one status iteration (solver.condition_estimate = true estimates it)";

/// The note for a W singular by the choice of generalised inverse.
const FIXING_DOFS_W: &str = "w: not estimated: with floating bodies in several subdomains, W is formed with the generalised inverse of S by fixing DOFs (zero on them), singular when a contact DOF is a fixing DOF whatever the contact rows; the forces do not depend on that choice";

/// `DelassusOperator::new`, and, the first time, the estimates of κ(S)
/// (from the factorisation `new` makes) and κ(W) (before any slip
/// compliance is added to W).
pub(crate) fn delassus_operator(
    s: InterfaceStiffness,
    rows: &[SparseRow],
    kernel: &Mat<f64>,
    cond: &mut RootConditioning,
) -> Result<DelassusOperator, ContactError> {
    if cond.done {
        return Ok(operator_of(s, rows, kernel, false)?.0);
    }
    let n = s.nrows();
    let (p, stats) = operator_of(s, rows, kernel, true)?;
    cond.done = true;
    cond.interface = Some(interface_report(&stats, n));
    cond.s = p.s_condition();
    if p.n_kernel() > 0 {
        cond.notes.push(format!(
            "s is the condition of S + ρRRᵀ, the matrix factorised: S itself is singular on the {} rigid mode(s) of the floating bodies",
            p.n_kernel()
        ));
    }
    let m = p.w().nrows();
    if m == 0 {
        cond.notes.push("w: no contact rows".into());
    } else if m > MAX_W_SIZE {
        cond.notes
            .push(format!("w: not estimated (m = {m} > {MAX_W_SIZE})"));
    } else {
        match dense_spd_condition(p.w().as_ref()) {
            Some(k) if k * f64::EPSILON < 1.0 => cond.w = Some(k),
            // W = B S⁺ Bᵀ through the fixing DOFs' generalised inverse,
            // zero on them: singular when a contact DOF is one of them,
            // whatever the contact rows.
            _ if stats.fixing_dofs > 0 => cond.notes.push(FIXING_DOFS_W.into()),
            Some(k) => {
                cond.warnings.push(format!(
                    "W is singular: redundant contact constraints (κ₁(W) ≈ {k:.1e} ≥ 1/ε); w is left out of digits_lost"
                ));
            }
            None => {
                cond.warnings.push(
                    "W is singular: redundant contact constraints (its Cholesky factorisation fails); w is left out of digits_lost".into(),
                );
            }
        }
    }
    Ok(p)
}

/// The Delassus operator of S (the condensation's factor of it) and how S
/// was factorised.
fn operator_of(
    s: InterfaceStiffness,
    rows: &[SparseRow],
    kernel: &Mat<f64>,
    estimate_condition: bool,
) -> Result<(DelassusOperator, InterfaceFactorStats), ContactError> {
    let op = InterfaceOperator::new(s, rows, kernel, estimate_condition)?;
    let stats = op.factor.stats().clone();
    let factor = std::sync::Arc::new(op.factor);
    let p = DelassusOperator::from_factor(factor, rows, op.r, op.w, op.s_condition);
    Ok((p, stats))
}

fn interface_report(
    st: &InterfaceFactorStats,
    rows: usize,
) -> signorini_report::InterfaceFactorisation {
    signorini_report::InterfaceFactorisation {
        storage: st.storage.into(),
        rows: rows as u64,
        matrix_nnz: st.matrix_nnz as u64,
        ordering: st.tree.map(|_| "subdomain_tree".to_string()),
        sparse_flops: st.tree.map(|(flops, _)| flops),
        sparse_factor_nnz: st.tree.map(|(_, entries)| entries as u64),
        factor_bytes: st.factor_bytes as u64,
        fixing_dofs: st.fixing_dofs as u64,
    }
}

/// The report's entry on the condensed path, from the subdomains' κ(K_II)
/// and the root's estimates. Pushes the warnings to `messages`.
pub(crate) fn condensed(
    data: &[CondensedData],
    root: RootConditioning,
    tolerance: f64,
    messages: &mut Vec<String>,
) -> Conditioning {
    let per: Vec<Option<f64>> = data.iter().map(|d| d.k_ii_condition).collect();
    let k_ii = per.iter().flatten().copied().reduce(f64::max);
    let mut notes = root.notes;
    if k_ii.is_none() {
        notes.push("k_ii: no subdomain has interior DOFs".into());
    }
    if !root.done {
        notes.push("s, w: no Delassus problem was built".into());
    }
    notes.push("k: the whole stiffness is factorised on the direct path only".into());
    for w in &root.warnings {
        messages.push(format!("conditioning: {w}"));
    }
    notes.extend(root.warnings);
    let mut c = Conditioning {
        method: METHOD.into(),
        k_ii,
        k_ii_per_subdomain: per,
        s: root.s,
        w: root.w,
        k: None,
        notes,
        ..Default::default()
    };
    apply_rule(
        &mut c,
        &[("K_II", k_ii), ("S", root.s), ("W", root.w)],
        tolerance,
        messages,
    );
    c
}

/// The report's entry on the direct path: κ(K) of the whole stiffness on the
/// free DOFs, by one factorisation of K in the KKT system's ordering
/// ([`KktSystem::stiffness_condition`]) when `estimate` (the scene's
/// `solver.condition_estimate`: it costs about one status iteration); none
/// when a body is floating.
pub(crate) fn direct(
    kkt: &mut KktSystem,
    (floating, estimate): (bool, bool),
    tolerance: f64,
    messages: &mut Vec<String>,
) -> Conditioning {
    let mut notes = vec![
        "k_ii, s, w: the direct path does not condense (it factorises [K Bᵀ; B −δI] by sparse LDLᵀ)"
            .to_string(),
    ];
    let kappa = if floating {
        notes.push("k: a floating body makes K singular".into());
        None
    } else if !estimate {
        notes.push(NOT_ASKED_K.into());
        None
    } else {
        let est = kkt.stiffness_condition();
        if est.is_none() {
            notes.push("k: the factorisation of K fails (K is singular)".into());
        }
        est
    };
    let mut c = Conditioning {
        method: METHOD.into(),
        k: kappa,
        notes,
        ..Default::default()
    };
    apply_rule(&mut c, &[("K", kappa)], tolerance, messages);
    c
}

/// Fills the digits and the warning: digits_lost = log10 of the largest
/// estimate, available = 15.65 − lost, needed = −log10(tolerance); warns when
/// available < needed.
fn apply_rule(
    c: &mut Conditioning,
    estimates: &[(&str, Option<f64>)],
    tolerance: f64,
    messages: &mut Vec<String>,
) {
    c.digits_needed = -tolerance.log10();
    let worst = estimates
        .iter()
        .filter_map(|&(name, k)| k.filter(|k| k.is_finite()).map(|k| (name, k)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let Some((name, kappa)) = worst else {
        return;
    };
    let lost = digits_lost(kappa);
    let available = F64_DIGITS - lost;
    c.digits_lost = Some(lost);
    c.digits_available = Some(available);
    if available < c.digits_needed {
        let w = format!(
            "conditioning: κ₁({name}) ≈ {kappa:.2e} leaves about {available:.1} of the {F64_DIGITS:.2} decimal digits of a double, fewer than the {:.1} that solver.tolerance = {tolerance:e} asks for: the answer may not be accurate to the tolerance (relax the tolerance, or reduce the stiffness contrast, the mesh grading or the refinement)",
            c.digits_needed
        );
        messages.push(w.clone());
        c.warning = Some(w);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rule_warns_only_when_the_tolerance_needs_more_digits_than_are_left() {
        let mut messages = Vec::new();
        // κ = 1e6: 9.65 digits left; a tolerance of 1e-9 needs 9, 1e-10 needs 10.
        let mut c = Conditioning::default();
        apply_rule(
            &mut c,
            &[("A", Some(1e6)), ("B", None)],
            1e-9,
            &mut messages,
        );
        assert!((c.digits_lost.unwrap() - 6.0).abs() < 1e-12);
        assert!((c.digits_available.unwrap() - 9.6536).abs() < 1e-3);
        assert!((c.digits_needed - 9.0).abs() < 1e-12);
        assert!(c.warning.is_none() && messages.is_empty());
        let mut c = Conditioning::default();
        apply_rule(
            &mut c,
            &[("A", Some(1e6)), ("B", Some(10.0))],
            1e-10,
            &mut messages,
        );
        let w = c.warning.expect("warning");
        assert!(w.contains("κ₁(A)"), "{w}");
        assert_eq!(messages, vec![w]);
        // nothing estimated: no digits, no warning
        let mut c = Conditioning::default();
        apply_rule(&mut c, &[("A", None)], 1e-15, &mut messages);
        assert!(c.digits_lost.is_none() && c.warning.is_none());
    }

    #[test]
    fn first_delassus_problem_estimates_s_and_w_once() {
        // S = diag(1, 4, 2): κ₁(S) = 4; rows e0 and e1 + e2:
        // W = [[1, 0], [0, 1/4 + 1/2]], κ₁(W) = 1/0.75.
        let s = Mat::<f64>::from_fn(3, 3, |i, j| if i == j { [1.0, 4.0, 2.0][i] } else { 0.0 });
        let rows: Vec<SparseRow> = vec![vec![(0, 1.0)], vec![(1, 1.0), (2, 1.0)]];
        let kernel = Mat::<f64>::zeros(3, 0);
        let stiffness = || InterfaceStiffness::Dense(s.clone());
        let mut cond = RootConditioning::default();
        let p = delassus_operator(stiffness(), &rows, &kernel, &mut cond).unwrap();
        assert_eq!(p.s_condition(), Some(4.0));
        assert!((cond.s.unwrap() - 4.0).abs() < 1e-14);
        assert!((cond.w.unwrap() - 1.0 / 0.75).abs() < 1e-14, "{:?}", cond.w);
        assert!(cond.warnings.is_empty());
        // later steps do not estimate again
        let p = delassus_operator(stiffness(), &rows, &kernel, &mut cond).unwrap();
        assert_eq!(p.s_condition(), None);
        assert!((cond.s.unwrap() - 4.0).abs() < 1e-14);
    }

    #[test]
    fn redundant_rows_make_w_singular_with_a_message() {
        let s = Mat::<f64>::identity(2, 2);
        let rows: Vec<SparseRow> = vec![vec![(0, 1.0)], vec![(0, 1.0)]];
        let mut cond = RootConditioning::default();
        delassus_operator(
            InterfaceStiffness::Dense(s),
            &rows,
            &Mat::zeros(2, 0),
            &mut cond,
        )
        .unwrap();
        assert!(cond.w.is_none());
        let mut messages = Vec::new();
        let c = condensed(&[], cond, 1e-10, &mut messages);
        assert!(c.w.is_none());
        assert!(
            messages
                .iter()
                .any(|m| m.contains("W is singular: redundant contact constraints")),
            "{messages:?}"
        );
        // S = I: κ = 1, no digit lost, no warning
        assert_eq!(c.digits_lost, Some(0.0));
        assert!(c.warning.is_none());
    }

    #[test]
    fn sparse_estimate_of_a_1d_laplacian() {
        // tridiag(−1, 2, −1), n = 99: κ₁ = 4 ‖A⁻¹‖₁ = (n+1)²/2 = 5000.
        let n = 99;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(faer::sparse::Triplet::new(i, i, 2.0));
            if i + 1 < n {
                t.push(faer::sparse::Triplet::new(i, i + 1, -1.0));
                t.push(faer::sparse::Triplet::new(i + 1, i, -1.0));
            }
        }
        let k = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        // by the KKT system of the direct path, with two contact rows (inactive
        // in the estimate: they must not change it)
        let rows: Vec<SparseRow> = vec![vec![(0, 1.0)], vec![(n - 1, -1.0), (n - 2, 1.0)]];
        let mut kkt = KktSystem::new(&k, &rows, false).unwrap();
        let est = kkt.stiffness_condition().unwrap();
        assert!(
            (5000.0 / 3.0..=5000.0 * (1.0 + 1e-9)).contains(&est),
            "{est}"
        );
    }
}
