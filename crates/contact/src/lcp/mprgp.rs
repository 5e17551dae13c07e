//! MPRGP as an LCP method: the box-constrained MPRGP of
//! [`crate::lcp::mprgp_box`] (Dostál 2009, ch. 8) on the box λ ≥ 0, the
//! frictionless LCP(W, q) of docs/theory/contact-problem.md (x = λ the
//! contact forces, g = w the gaps). Its residual is the natural residual
//! [`crate::lcp_residual`]; polishing is left to the callers
//! ([`crate::registry`], [`crate::lcp::smalbe`]).

use faer::Mat;

use crate::lcp::clamp;
use crate::lcp::mprgp_box::{check_start, minimise, Flavour};
use crate::lcp::{check_input, LcpOptions};
use crate::solution::{ContactSolution, Measure};
use crate::ContactError;

/// λ ≥ 0: the LCP, polished by the callers.
const LCP: Flavour = Flavour {
    method: "mprgp",
    residual: Measure::Natural,
    polish: false,
};

/// Dostál's MPRGP on LCP(W, q), i.e. on the box λ ≥ 0 (see the module
/// documentation), from λ = 0.
///
/// `report.iterations` counts CG, expansion and proportioning steps;
/// `operator_applications` the products W·v (power iterations for ‖W‖
/// included; one per CG or proportioning step, two per expansion step).
/// The stop reason also gives the number of steps of each kind.
pub fn mprgp(w: &Mat<f64>, q: &[f64], opts: &LcpOptions) -> Result<ContactSolution, ContactError> {
    mprgp_from(w, q, &vec![0.0; q.len()], opts)
}

/// [`mprgp`] from a warm start λ0 (its negative entries are set to zero):
/// the inner solver of [`crate::lcp::smalbe`], whose successive problems differ
/// little. A λ0 of the wrong length or with a non-finite entry is an error.
pub fn mprgp_from(
    w: &Mat<f64>,
    q: &[f64],
    lambda0: &[f64],
    opts: &LcpOptions,
) -> Result<ContactSolution, ContactError> {
    check_input(w, q, LCP.method)?;
    check_start(lambda0, q.len(), LCP.method)?;
    if q.is_empty() {
        return Ok(ContactSolution::empty(LCP.method));
    }
    let m = q.len();
    let (lower, upper) = (vec![0.0; m], vec![f64::INFINITY; m]);
    let mut sol = minimise(w, q, (&lower, &upper), lambda0, opts, LCP)?;
    sol.forces = clamp(std::mem::take(&mut sol.forces));
    Ok(sol)
}

#[cfg(test)]
mod tests;
