//! The options of the contact solvers that more than one method reads (the
//! LCP methods' own are [`crate::lcp::LcpOptions`]).

use serde::Serialize;
use std::time::Instant;

/// How many statuses change per iteration of the status method.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StatusVariant {
    /// Every violated status changes at each iteration.
    #[default]
    All,
    /// Only the most violated status changes (the variant with the proof).
    Single,
}

/// The options of a friction solver.
#[derive(Debug, Clone)]
pub struct FrictionOptions {
    pub max_iterations: usize,
    pub max_fixed_point: usize,
    pub tolerance: f64,
    pub force_scale: f64,
    pub gap_scale: f64,
    /// The wall-clock time at which a solve stops, converged or not
    /// (`None`: no time limit).
    pub deadline: Option<Instant>,
}

/// The default wall-clock budget of a friction solve of `rows` rows, in
/// seconds: 10 s, plus 2e-9 s × rows³ (about six dense factorisations of
/// W at 1 GFlop/s for every second past the first ten: 11 s at 858 rows,
/// 460 s at 6 075), so that a large problem is not cut short and a small
/// one that does not converge ends soon.
pub fn default_time_limit(rows: usize) -> f64 {
    10.0 + 2e-9 * (rows as f64).powi(3)
}

/// Whether the wall-clock `deadline` has passed (`None`: no time limit):
/// the one test of every method's time limit.
pub fn deadline_passed(deadline: Option<Instant>) -> bool {
    deadline.is_some_and(|d| Instant::now() >= d)
}

/// The stall rule and the time limit of an iterative friction solver, one
/// for every method that has them (the semi-smooth Newton method, condensed
/// and on the whole system, NSGS and the fixed point on the threshold,
/// which has no deadline of its own): the method stops as stalled when
/// `after` iterations have not brought its residual below `decrease` times
/// the best so far, and at the deadline, converged or not.
#[derive(Debug, Clone, Copy)]
pub struct StallWatch {
    decrease: f64,
    after: usize,
    deadline: Option<Instant>,
    /// The best residual so far and the iteration of it.
    best: (f64, usize),
}

/// Where a stalled method stood: its best residual, the iteration of it and
/// the iterations since.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stall {
    pub best: f64,
    pub at: usize,
    pub since: usize,
}

impl StallWatch {
    /// A watch of the rule (`decrease`, `after`) and the `deadline`.
    pub fn new(decrease: f64, after: usize, deadline: Option<Instant>) -> Self {
        let best = (f64::INFINITY, 0);
        Self {
            decrease,
            after,
            deadline,
            best,
        }
    }

    /// Whether the deadline has passed.
    pub fn time_up(&self) -> bool {
        deadline_passed(self.deadline)
    }

    /// Records the `residual` of iteration `iteration`: the stall when the
    /// method has stalled, `None` while it progresses.
    pub fn stalled(&mut self, residual: f64, iteration: usize) -> Option<Stall> {
        if residual < self.decrease * self.best.0 {
            self.best = (residual, iteration);
            return None;
        }
        let since = iteration - self.best.1;
        (since >= self.after).then_some(Stall {
            best: self.best.0,
            at: self.best.1,
            since,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A residual that halves for 3 iterations, then creeps by 1 %: with
    /// the rule (0.9, 5) the best is the last halving (iteration 3) and the
    /// watch reports the stall 5 iterations later; no deadline, no time up.
    #[test]
    fn the_watch_stalls_after_iterations_without_the_decrease() {
        let mut watch = StallWatch::new(0.9, 5, None);
        let mut residual = 1.0;
        let mut stall = None;
        for it in 0..20 {
            residual *= if it <= 3 { 0.5 } else { 0.99 };
            if let Some(s) = watch.stalled(residual, it) {
                stall = Some((it, s));
                break;
            }
        }
        let (it, s) = stall.expect("a stall");
        assert_eq!((it, s.at, s.since), (8, 3, 5));
        assert_eq!(s.best, 0.5f64.powi(4));
        assert!(!watch.time_up());
        let past = StallWatch::new(0.9, 5, Some(Instant::now()));
        assert!(past.time_up());
    }
}
