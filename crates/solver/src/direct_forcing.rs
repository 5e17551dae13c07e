//! The forcing terms of the inexact Newton method on the whole system
//! ([`crate::direct_newton`]): far from the solution the Newton equations
//! J d = −F need not be solved to rounding, only to a relative residual
//! ‖J d + F‖ ≤ η_k ‖F‖ (Dembo, Eisenstat & Steihaug 1982), which the
//! Krylov solve of [`crate::symmetric_part`] reaches in a step or two
//! where the exact direction takes twenty. The η_k are Eisenstat and
//! Walker's second choice (Eisenstat & Walker 1996, SIAM J. Sci. Comput.
//! 17(1), §2.2):
//!
//! ```text
//!   η_0 = η_max,   η_k = min(γ (r_k / r_{k−1})^α, η_max, r_k),   γ = 0.9, α = 2
//! ```
//!
//! with r_k the residual the Newton method stops on (relative, without
//! units): η_k shrinks as the iterates converge, at least as fast as r_k
//! (η_k = O(r_k) keeps Newton's local quadratic rate, Dembo, Eisenstat &
//! Steihaug 1982, §3, and of the semi-smooth Newton method, Martínez & Qi
//! 1995: without that bound the last iterations on the pads converged
//! more slowly, 30 iterations against 26 on the 48 × 48 pad). Eisenstat
//! and Walker's safeguard against a too fast decrease, max(η_k,
//! γ η_{k−1}^α) when γ η_{k−1}^α > 0.1, never acts under η_max = 0.1.
//!
//! Near the solution, r_k ≤ [`NEAR`], and wherever η_k < [`EXACT_BELOW`],
//! the direction is solved exactly (to the LU's backward error): once the
//! statuses have settled an exact step lands on the solution to rounding
//! (the Newton equations are then linear), as the exact method's does. An
//! inexact last step stops just within the tolerance instead, its residual
//! about η_k r_k: with exact steps from √tol only, the last iterates of
//! the cyclic example's steps (statuses settled at r_k ≈ 4e-5) stopped at
//! 1e-11 where the exact method reaches 1e-16, and its forces differed
//! from the condensed path's by 2e-8 where they agree to 1e-8. And as the
//! inexact iterates follow another path than the exact method's, they may
//! end on another point within the tolerance (the pushed three-body
//! assembly: 7.7e-9 at tolerance 1e-8, where the exact method ended at
//! 2.7e-10, its forces 1.3e-4 from the condensed path's against 7.8e-7):
//! so a solve that took an inexact step and meets the tolerance by more
//! than [`POLISH_ABOVE`] times it takes one exact step more before it
//! stops (the Newton driver's). The outer convergence test is unchanged.

/// The largest forcing term: a tenth (one or two Krylov steps of the
/// symmetric-part preconditioner, which divides the residual by about
/// fifteen each step on the pads of docs/performance).
pub(crate) const ETA_MAX: f64 = 0.1;
/// γ of the sequence (module doc).
const GAMMA: f64 = 0.9;
/// Forcing terms below this are solved exactly instead.
const EXACT_BELOW: f64 = 1e-10;
/// Iterates whose residual is below this are solved exactly (module doc).
pub(crate) const NEAR: f64 = 1e-3;
/// A solve that took an inexact step and stops at a residual above this
/// times its tolerance takes one exact step more (module doc).
pub(crate) const POLISH_ABOVE: f64 = 1e-3;

/// The forcing terms of one Newton solve.
#[derive(Debug, Default)]
pub(crate) struct Forcing {
    /// The residual of the previous iterate.
    previous: Option<f64>,
}

impl Forcing {
    /// η_k for the residual `residual` of the current iterate (module
    /// doc); `None` when the direction is to be solved exactly.
    pub(crate) fn next(&mut self, residual: f64) -> Option<f64> {
        let eta = match self.previous {
            None => ETA_MAX,
            Some(last_residual) => {
                let ratio = residual / last_residual;
                let eta = GAMMA * ratio * ratio;
                if eta.is_nan() {
                    ETA_MAX
                } else {
                    eta.min(ETA_MAX)
                }
            }
        };
        let eta = eta.min(residual);
        self.previous = Some(residual);
        (eta >= EXACT_BELOW && residual > NEAR).then_some(eta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first term is η_max; a residual divided by ten gives 0.9 / 100;
    /// a rising residual is capped at η_max; a residual a million times
    /// smaller gives 0.9e-12, below the exact threshold: `None`; a slow
    /// decrease is bounded by the residual itself; a residual within
    /// [`NEAR`] is solved exactly.
    #[test]
    fn follows_eisenstat_walker_choice_two() {
        let mut f = Forcing::default();
        assert_eq!(f.next(1.0), Some(ETA_MAX));
        let eta = f.next(0.1).expect("inexact");
        assert!((eta - 0.009).abs() <= 1e-15, "{eta}");
        assert_eq!(f.next(0.5), Some(ETA_MAX));
        assert_eq!(f.next(0.5e-6), None);
        let mut f = Forcing::default();
        f.next(4e-3);
        assert_eq!(f.next(2e-3), Some(2e-3));
        assert_eq!(f.next(1.5e-3), Some(1.5e-3));
        assert_eq!(f.next(0.9e-3), None);
    }
}
