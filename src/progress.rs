//! `signorini run`'s progress on a terminal: one status line on stderr (the
//! stage, the subdomain being condensed, the load step, the contact
//! method's iteration with its points in contact and residual) and a line
//! per finished stage with its time. Nothing when stderr is not a terminal
//! or with `--quiet`; under MPI on the root only. The report files never
//! see it (it goes to stderr, and only through indicatif).
//!
//! The solver's events (signorini_solver::progress) only update a state;
//! a drawing thread turns it into the status line 10 times a second, so
//! that a fast loop of iterations or steps costs a lock per event.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use signorini_solver::progress::{Event, Iteration, Observer, Phase};

/// Redraws of the status line per second (at most).
const REDRAW_HZ: u8 = 10;

/// What the status line shows.
struct State {
    /// The stage and when it began.
    stage: &'static str,
    since: Instant,
    /// This rank's subdomain (i, of, total on all ranks).
    subdomain: Option<(usize, usize, usize)>,
    detail: Option<&'static str>,
    step: Option<(usize, usize)>,
    iteration: Option<Iteration>,
}

/// The terminal's view of a run, on the root (`ranks`: the run's ranks).
pub(crate) struct Terminal {
    bar: ProgressBar,
    ranks: usize,
    state: Mutex<State>,
    stop: AtomicBool,
}

impl Terminal {
    /// A terminal view, or `None` when stderr is not a terminal, with
    /// `quiet`, or on a rank other than the root.
    pub(crate) fn start(quiet: bool, root: bool, ranks: usize) -> Option<Progress> {
        if quiet || !root || !std::io::stderr().is_terminal() {
            return None;
        }
        let bar =
            ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(REDRAW_HZ));
        if let Ok(style) = ProgressStyle::with_template("{spinner} {elapsed:>4} {wide_msg}") {
            bar.set_style(style);
        }
        let view = Arc::new(Terminal {
            bar,
            ranks,
            state: Mutex::new(State {
                stage: "reading the scene",
                since: Instant::now(),
                subdomain: None,
                detail: None,
                step: None,
                iteration: None,
            }),
            stop: AtomicBool::new(false),
        });
        let drawer = view.clone();
        let thread = std::thread::spawn(move || {
            while !drawer.stop.load(Ordering::Relaxed) {
                drawer.draw();
                std::thread::sleep(Duration::from_millis(1000 / REDRAW_HZ as u64));
            }
        });
        signorini_solver::progress::set_observer(Some(view.clone()));
        Some(Progress {
            view,
            thread: Some(thread),
        })
    }

    fn draw(&self) {
        if let Ok(s) = self.state.lock() {
            self.bar.set_message(self.line(&s));
        }
    }

    /// The status line of a state.
    fn line(&self, s: &State) -> String {
        let mut line = s.stage.to_string();
        if let Some((i, of, total)) = s.subdomain {
            line += &if self.ranks > 1 {
                format!(
                    " subdomain {i}/{of} of rank 0 ({total} on {} ranks)",
                    self.ranks
                )
            } else {
                format!(" subdomain {i}/{of}")
            };
        }
        if let Some((k, n)) = s.step {
            line += &format!(" · step {k}/{n}");
        }
        if let Some(d) = s.detail {
            line += &format!(" · {d}");
        }
        if let Some(it) = &s.iteration {
            line += &format!(
                " · {} iteration {}: {} in contact, residual {:.1e}×tol",
                it.method, it.iteration, it.active, it.residual
            );
        }
        line
    }

    /// What a stage did, when it ends: its subdomains, its steps and the
    /// last iteration of the contact method.
    fn summary(&self, s: &State) -> String {
        let mut line = s.stage.to_string();
        if let Some((_, of, total)) = s.subdomain {
            line += &match self.ranks {
                1 => format!(" {of} subdomain(s)"),
                _ => format!(
                    " {of} subdomain(s) on rank 0 ({total} on {} ranks)",
                    self.ranks
                ),
            };
        }
        if let Some((_, n)) = s.step {
            line += &format!(", {n} step(s)");
        }
        if let Some(it) = &s.iteration {
            line += &format!(
                " (last: {} iteration {}, {} in contact)",
                it.method, it.iteration, it.active
            );
        }
        line
    }

    /// A new stage: the last one's line with its time, then the new one.
    fn stage(&self, stage: &'static str) {
        if let Ok(mut s) = self.state.lock() {
            if s.stage != stage {
                let seconds = s.since.elapsed().as_secs_f64();
                self.bar
                    .println(format!("  {}: {seconds:.1} s", self.summary(&s)));
                *s = State {
                    stage,
                    since: Instant::now(),
                    subdomain: None,
                    detail: None,
                    step: None,
                    iteration: None,
                };
            }
        }
        self.draw();
    }
}

fn stage_name(p: Phase) -> &'static str {
    match p {
        Phase::Meshing => "meshing and contact search",
        Phase::Assembling => "assembling",
        Phase::Condensing => "condensing",
        Phase::Contact => "contact solve",
        Phase::Recovering => "recovering the interiors",
        Phase::Certifying => "certifying",
    }
}

impl Observer for Terminal {
    fn event(&self, event: &Event) {
        if let Event::Phase(p) = event {
            return self.stage(stage_name(*p));
        }
        if let Event::RanksCondensed(counts) = event {
            if self.ranks > 1 {
                let per: Vec<String> = (counts.iter().enumerate())
                    .map(|(r, n)| format!("rank {r}: {n}"))
                    .collect();
                self.bar
                    .println(format!("  subdomains condensed: {}", per.join(", ")));
            }
            return;
        }
        let Ok(mut s) = self.state.lock() else {
            return;
        };
        match *event {
            Event::Subdomain { index, of, total } => {
                (s.subdomain, s.detail) = (Some((index, of, total)), None)
            }
            Event::Detail(d) => s.detail = Some(d),
            Event::Step { step, of } => {
                (s.step, s.detail, s.iteration) = (Some((step, of)), None, None)
            }
            Event::Iteration(i) => (s.detail, s.iteration) = (None, Some(*i)),
            Event::Phase(_) | Event::RanksCondensed(_) => {}
        }
    }
}

/// The terminal view of a run while it lasts; [`Progress::stage`] for the
/// command line's own stages; dropping it clears the line.
pub(crate) struct Progress {
    view: Arc<Terminal>,
    thread: Option<JoinHandle<()>>,
}

impl Progress {
    pub(crate) fn stage(&self, stage: &'static str) {
        self.view.stage(stage);
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        signorini_solver::progress::set_observer(None);
        self.view.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        self.view.stage("done");
        self.view.bar.finish_and_clear();
    }
}
