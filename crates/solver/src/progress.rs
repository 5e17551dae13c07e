//! What a run is doing, for an observer outside the solver (the command line
//! shows it on a terminal): the stage, the subdomain being condensed, the
//! load step, and each iteration of the contact method. The solver knows
//! nothing of how it is shown; without an observer (the default) an event
//! costs one uncontended lock read.
//!
//! The observer is the run's, passed in by the caller
//! (`RunEnvironment::observer`). Under MPI each rank has its own; the command
//! line gives one to the root only, which hears of the other ranks'
//! subdomains when their condensed data arrive ([`Event::RanksCondensed`]).

use std::sync::Arc;

pub use signorini_contact::observe::Iteration;

/// A stage of the run (docs/architecture.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Meshes, models and the contact search.
    Meshing,
    /// The whole sparse stiffness (the direct path).
    Assembling,
    /// Each rank its subdomains ([`Event::Subdomain`]).
    Condensing,
    /// The root: the interface problem and its contact solve at every step.
    Contact,
    /// Each rank the interiors of its subdomains.
    Recovering,
    /// The certificate and the report.
    Certifying,
}

/// One piece of news of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event<'a> {
    Phase(Phase),
    /// This rank starts its `index`-th subdomain (from 1) of its `of`;
    /// `total` subdomains on all ranks.
    Subdomain {
        index: usize,
        of: usize,
        total: usize,
    },
    /// What the current subdomain or step is doing ("assembling",
    /// "factorising", "Delassus operator").
    Detail(&'static str),
    /// On the root: every rank's condensed data arrived; how many
    /// subdomains each rank condensed.
    RanksCondensed(&'a [usize]),
    /// Load step `step` (from 1) of `of` begins.
    Step {
        step: usize,
        of: usize,
    },
    /// An iteration of the contact method of the current step.
    Iteration(&'a Iteration),
}

/// Who hears of the run's progress.
pub trait Observer: Send + Sync {
    fn event(&self, event: &Event);
}

/// Who hears of one run's progress: the caller's observer, or nobody.
#[derive(Clone, Default)]
pub(crate) struct Progress(Option<Arc<dyn Observer>>);

impl Progress {
    pub(crate) fn new(observer: Option<Arc<dyn Observer>>) -> Self {
        Progress(observer)
    }

    /// Tells the observer (if any).
    pub(crate) fn emit(&self, event: Event) {
        if let Some(o) = &self.0 {
            o.event(&event);
        }
    }

    pub(crate) fn phase(&self, p: Phase) {
        self.emit(Event::Phase(p));
    }

    /// Load step `index` (from 0) of `of` begins.
    pub(crate) fn step(&self, index: usize, of: usize) {
        self.emit(Event::Step {
            step: index + 1,
            of,
        });
    }

    /// Runs `f` (a contact solve) with the contact methods' iterations
    /// passed on to the observer.
    pub(crate) fn observed<T>(&self, f: impl FnOnce() -> T) -> T {
        match &self.0 {
            Some(o) => {
                let o = o.clone();
                signorini_contact::observe::observed(move |i| o.event(&Event::Iteration(i)), f)
            }
            None => f(),
        }
    }

    /// This rank starts its subdomain `index` (from 0) of `of`; `total` on
    /// all ranks.
    pub(crate) fn subdomain(&self, index: usize, of: usize, total: usize) {
        self.emit(Event::Subdomain {
            index: index + 1,
            of,
            total,
        });
    }

    /// On the root: how many subdomains each rank condensed, from the
    /// gathered condensed data (a rank that failed counts 0).
    pub(crate) fn ranks_condensed<T, E>(&self, gathered: Option<&Vec<Result<Vec<T>, E>>>) {
        if let Some(all) = gathered {
            let counts: Vec<usize> = all
                .iter()
                .map(|r| r.as_ref().map_or(0, |v| v.len()))
                .collect();
            self.emit(Event::RanksCondensed(&counts));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// The events of one thread (other tests may run meanwhile).
    struct Log(std::thread::ThreadId, Mutex<Vec<String>>);
    impl Observer for Log {
        fn event(&self, e: &Event) {
            if std::thread::current().id() != self.0 {
                return;
            }
            if let Ok(mut l) = self.1.lock() {
                l.push(format!("{e:?}"));
            }
        }
    }

    /// The stages, subdomains, steps and iterations of a small run reach
    /// the observer in order, and nothing once it is removed.
    #[test]
    fn a_run_tells_its_observer_its_stages_steps_and_iterations() {
        let sc = signorini_scene::parse_toml(include_str!("../../../examples/blocks.toml"))
            .expect("the example parses");
        let log = Arc::new(Log(std::thread::current().id(), Mutex::new(Vec::new())));
        let env = crate::options::RunEnvironment {
            observer: Some(log.clone()),
            ..crate::options::RunEnvironment::machine()
        };
        let out = crate::pipeline::run_with(
            &sc,
            "blocks",
            &crate::options::RunOptions::default(),
            &env,
            &signorini_comm::Local,
        );
        assert!(out.is_ok());
        let events = log.1.lock().map(|l| l.clone()).unwrap_or_default();
        let at = |s: &str| events.iter().position(|e| e.starts_with(s));
        let order = [
            at("Phase(Meshing)"),
            at("Phase(Condensing)"),
            at("Subdomain { index: 1"),
            at("RanksCondensed"),
            at("Phase(Contact)"),
            at("Step { step: 1"),
            at("Iteration"),
            at("Detail(\"recovering\")"),
            at("Phase(Certifying)"),
        ];
        assert!(order.iter().all(|p| p.is_some()), "{events:?}");
        assert!(order.windows(2).all(|w| w[0] < w[1]), "{events:?}");
        let n = events.len();
        let _ = crate::pipeline::run(
            &sc,
            "blocks",
            &crate::options::RunOptions::default(),
            &signorini_comm::Local,
        );
        assert_eq!(log.1.lock().map(|l| l.len()).unwrap_or(0), n);
    }
}
