//! An observer of the iterative contact methods: each iteration of the
//! status driver ([`crate::active_set::drive`], course notes §3.3 and §4.5) and of
//! the semi-smooth Newton method on the friction law reports what it is at,
//! so that a caller can show a long solve's progress.
//!
//! The methods know nothing of who listens: the caller wraps a solve in
//! [`observed`], which installs its observer for that call on this thread
//! (the methods iterate on the calling thread) and removes it afterwards, a
//! panic included. Without an observer an iteration costs one thread-local
//! read.

use std::cell::RefCell;
use std::rc::Rc;

/// One iteration of an iterative contact method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Iteration {
    /// "status" (the status driver: frictionless or friction statuses) or
    /// "newton" (semi-smooth Newton on the friction law).
    pub method: &'static str,
    /// The iteration, from 1 (the status method: its solves; Newton: its
    /// steps, 0 at the starting point) of this call.
    pub iteration: usize,
    /// Contact points in contact at this iterate (active, stick or slip).
    pub active: usize,
    /// The method's residual at this iterate relative to its tolerance
    /// (≤ 1: met): the largest status violation for the status method, the
    /// scaled natural residual for Newton.
    pub residual: f64,
}

type Observer = Rc<dyn Fn(&Iteration)>;

thread_local! {
    static OBSERVER: RefCell<Option<Observer>> = const { RefCell::new(None) };
}

/// Runs `f` with `observer` called at every iteration of the methods `f`
/// runs on this thread; the previous observer (if any) is back afterwards.
pub fn observed<T>(observer: impl Fn(&Iteration) + 'static, f: impl FnOnce() -> T) -> T {
    struct Restore(Option<Observer>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let previous = self.0.take();
            OBSERVER.with(|o| *o.borrow_mut() = previous);
        }
    }
    let previous = OBSERVER.with(|o| o.borrow_mut().replace(Rc::new(observer)));
    let _restore = Restore(previous);
    f()
}

/// Tells the observer of this thread (if any) about an iteration.
pub(crate) fn iteration(info: Iteration) {
    // The observer is cloned out so that it may itself run an observed solve.
    if let Some(o) = OBSERVER.with(|o| o.borrow().clone()) {
        o(&info);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    #[test]
    fn an_observer_sees_the_iterations_of_its_call_only() {
        let seen = Rc::new(Cell::new(0usize));
        let s = seen.clone();
        let info = Iteration {
            method: "status",
            iteration: 3,
            active: 2,
            residual: 0.5,
        };
        let got = observed(
            move |i: &Iteration| s.set(s.get() + i.iteration),
            || {
                iteration(info);
                iteration(info);
                7
            },
        );
        assert_eq!((got, seen.get()), (7, 6));
        iteration(info);
        assert_eq!(seen.get(), 6);
    }

    /// The status method reports each of its solves: the violated ones
    /// above the tolerance, the last with none and the answer's active set.
    #[test]
    fn the_status_method_reports_each_solve() {
        use crate::test_problems::{lcp_problem, random_spd, XorShift};
        use crate::{status_method, StatusOptions, StatusVariant};
        let mut rng = XorShift(7);
        let m = 30;
        let w = random_spd(m, &mut rng);
        let q: Vec<f64> = (0..m).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let mut p = lcp_problem(&w, &q);
        let opts = StatusOptions {
            variant: StatusVariant::All,
            max_iterations: 100,
            tolerance: 1e-12,
            force_scale: 1.0,
            gap_scale: 1.0,
            initial_active: Some(Vec::new()),
            deadline: None,
        };
        let seen: Rc<std::cell::RefCell<Vec<Iteration>>> = Rc::default();
        let log = seen.clone();
        let out = observed(
            move |i: &Iteration| log.borrow_mut().push(*i),
            || status_method(&mut p, &opts).unwrap(),
        );
        let seen = seen.borrow();
        assert!(out.report.converged && seen.len() > 2, "{seen:?}");
        assert_eq!(seen.len(), out.report.iterations);
        for (k, i) in seen.iter().enumerate() {
            assert_eq!((i.method, i.iteration), ("status", k + 1));
        }
        let (last, before) = seen.split_last().unwrap();
        assert_eq!((last.residual, last.active), (0.0, out.active.len()));
        assert!(before.iter().all(|i| i.residual > 1.0));
        assert_eq!(seen[0].active, 0);
    }
}
