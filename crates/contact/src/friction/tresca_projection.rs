//! Tresca in 2D as a box-constrained QP (Tresca's energy theorem, course
//! notes §4.1.1): min ½ rᵀ W r + qᵀ r over λ_n ≥ 0, −g ≤ λ_t ≤ g, by MPRGP for
//! simple bounds: the method of its own ([`tresca_projection`]) and the
//! fallback of the status method's inner Tresca problems ([`tresca_box`]).

use crate::active_set::friction_status::thresholds_from;
use crate::delassus::DelassusProblem;
use crate::law::FrictionLayout;
use crate::lcp::LcpOptions;
use crate::options::FrictionOptions;
use crate::solution::{ContactSolution, PointStatus};
use crate::ContactError;

/// Tresca by a projection method (course notes §3.2 on the forces; Dostál's MPRGP for
/// simple bounds): min ½ rᵀ W r + qᵀ r over λ_n ≥ 0, −g ≤ λ_t ≤ g. Unlike the
/// status method, the box lets an open point carry a tangential force up to
/// its threshold (Tresca's law does not depend on the normal force); on
/// contacts closed everywhere both give the same answer.
pub fn tresca_projection(
    problem: &DelassusProblem,
    layout: &FrictionLayout,
    opts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    layout.validate(problem.q.len(), 2)?;
    let thr = thresholds_from(layout, &vec![0.0; layout.n_points()]);
    let (mut sol, statuses) = tresca_box(problem, layout, &thr, opts)?;
    sol.gaps = crate::lcp::gaps(&problem.w, &problem.q, &sol.forces);
    sol.report.method = "tresca_mprgp_box".into();
    sol.set_points(statuses);
    Ok(sol)
}

/// The Tresca problem with the thresholds `thr` (a force per point) as the
/// box-constrained QP min ½ rᵀ W r + qᵀ r over λ_n ≥ 0, −g ≤ λ_t ≤ g, by
/// MPRGP for simple bounds (convex: it converges whatever the thresholds,
/// where the status method may cycle), with the statuses it implies.
pub(crate) fn tresca_box(
    problem: &DelassusProblem,
    layout: &FrictionLayout,
    thr: &[f64],
    opts: &FrictionOptions,
) -> Result<(crate::ContactSolution, Vec<PointStatus>), ContactError> {
    if problem.n_kernel() > 0 {
        return Err(ContactError::Singular(
            "the projection method for Tresca cannot hold bodies held by contact or friction alone; use method = \"status\"".into(),
        ));
    }
    let n = problem.q.len();
    let m = layout.n_points();
    let mut lower = vec![0.0; n];
    let mut upper = vec![f64::INFINITY; n];
    for (p, &g) in thr.iter().enumerate().take(m) {
        if let Some(t) = layout.tangent_row(p) {
            lower[t] = -g;
            upper[t] = g;
        }
    }
    let lcp_opts = LcpOptions {
        tolerance: opts.tolerance,
        max_iterations: opts.max_iterations,
        force_scale: opts.force_scale,
        gap_scale: opts.gap_scale,
        stiffness: None,
        deadline: opts.deadline,
    };
    let sol = crate::lcp::mprgp_box::mprgp_box(&problem.w, &problem.q, &lower, &upper, &lcp_opts)?;
    let tol = opts.tolerance
        * opts
            .force_scale
            .max(sol.forces.iter().fold(0.0f64, |a, v| a.max(v.abs())));
    let statuses = (0..m)
        .map(|p| {
            if sol.forces[p] <= tol {
                PointStatus::Open
            } else {
                match layout.tangent_row(p) {
                    Some(t) if sol.forces[t] >= upper[t] - tol => PointStatus::SlipPlus,
                    Some(t) if sol.forces[t] <= lower[t] + tol => PointStatus::SlipMinus,
                    _ => PointStatus::Stick,
                }
            }
        })
        .collect();
    Ok((sol, statuses))
}
