//! `signorini run`'s progress on a terminal: one status line on stderr (the
//! stage, the subdomain being condensed, the load step, the contact
//! method's iteration with its points in contact and residual) and a line
//! per finished stage with its time. Nothing when stderr is not a terminal
//! or with `--quiet`. The report files never see it (it goes to stderr,
//! and only through indicatif).
//!
//! Under MPI the root alone shows it. A rank's stderr is a pipe to the
//! launcher, so the root asks whether the launcher's stderr is a terminal
//! (Linux: its parent's fd 2, as under Open MPI's `mpirun` on the root's
//! node); `--progress` shows it regardless. The root shows its own
//! subdomains as it condenses them, and every rank's count when their
//! condensed data arrive (the transport has collectives only: a live
//! report from the other ranks would need point-to-point messages polled
//! by the root during its own condensation).
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

/// Whether a status line is on stderr (for the panic hook's message).
static ACTIVE: AtomicBool = AtomicBool::new(false);

/// Clears the status line, if any, so that a message printed now (the
/// panic hook's) starts a line of its own.
pub(crate) fn clear_line() {
    if ACTIVE.load(Ordering::Relaxed) {
        let _ = indicatif::TermLike::clear_line(&AnsiStderr);
    }
}

/// When to show the progress (`run --quiet`, `--progress`, neither).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Show {
    Never,
    /// When stderr is a terminal, or under MPI the launcher's stderr.
    OnTerminal,
    Always,
}

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
    /// On the root under MPI: every rank's condensed subdomains.
    ranks_done: Option<Vec<usize>>,
}

impl State {
    fn new(stage: &'static str) -> Self {
        Self {
            stage,
            since: Instant::now(),
            subdomain: None,
            detail: None,
            step: None,
            iteration: None,
            ranks_done: None,
        }
    }
}

/// Whether the MPI launcher that started this process writes its stderr to
/// a terminal (Linux: the parent's fd 2 is a terminal device).
fn launcher_on_terminal() -> bool {
    let parent = std::os::unix::process::parent_id();
    std::fs::read_link(format!("/proc/{parent}/fd/2")).is_ok_and(|p| {
        let p = p.to_string_lossy();
        p.starts_with("/dev/pts/") || p.starts_with("/dev/tty")
    })
}

/// stderr as a terminal of 80 columns, when it is a pipe to one (an MPI
/// launcher's) or `--progress` asks: indicatif draws nothing on a stderr
/// that is not a terminal.
#[derive(Debug)]
struct AnsiStderr;

impl AnsiStderr {
    fn put(&self, s: &str) -> std::io::Result<()> {
        std::io::Write::write_all(&mut std::io::stderr(), s.as_bytes())
    }

    /// Moves the cursor `n` cells (none for 0: CSI 0 A moves one).
    fn csi(&self, n: usize, direction: char) -> std::io::Result<()> {
        match n {
            0 => Ok(()),
            _ => self.put(&format!("\x1b[{n}{direction}")),
        }
    }
}

impl indicatif::TermLike for AnsiStderr {
    fn width(&self) -> u16 {
        80
    }
    fn move_cursor_up(&self, n: usize) -> std::io::Result<()> {
        self.csi(n, 'A')
    }
    fn move_cursor_down(&self, n: usize) -> std::io::Result<()> {
        self.csi(n, 'B')
    }
    fn move_cursor_right(&self, n: usize) -> std::io::Result<()> {
        self.csi(n, 'C')
    }
    fn move_cursor_left(&self, n: usize) -> std::io::Result<()> {
        self.csi(n, 'D')
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        self.put(&format!("{s}\n"))
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        self.put(s)
    }
    fn clear_line(&self) -> std::io::Result<()> {
        self.put("\r\x1b[2K")
    }
    fn flush(&self) -> std::io::Result<()> {
        std::io::Write::flush(&mut std::io::stderr())
    }
}

/// The terminal's view of a run, on the root (`ranks`: the run's ranks).
pub(crate) struct Terminal {
    bar: ProgressBar,
    ranks: usize,
    state: Mutex<State>,
    stop: AtomicBool,
}

impl Terminal {
    /// A terminal view, or `None` on a rank other than the root and when
    /// `show` says not to (`mpi`: started by an MPI launcher).
    pub(crate) fn start(show: Show, root: bool, mpi: bool, ranks: usize) -> Option<Progress> {
        let on_terminal = std::io::stderr().is_terminal();
        let shown = match show {
            Show::Never => false,
            Show::OnTerminal => on_terminal || (mpi && launcher_on_terminal()),
            Show::Always => true,
        };
        if !root || !shown {
            return None;
        }
        let target = if on_terminal {
            ProgressDrawTarget::stderr_with_hz(REDRAW_HZ)
        } else {
            ProgressDrawTarget::term_like_with_hz(Box::new(AnsiStderr), REDRAW_HZ)
        };
        let bar = ProgressBar::with_draw_target(None, target);
        if let Ok(style) = ProgressStyle::with_template("{spinner} {elapsed:>4} {wide_msg}") {
            bar.set_style(style);
        }
        let view = Arc::new(Terminal {
            bar,
            ranks,
            state: Mutex::new(State::new("reading the scene")),
            stop: AtomicBool::new(false),
        });
        let drawer = view.clone();
        let thread = std::thread::spawn(move || {
            while !drawer.stop.load(Ordering::Relaxed) {
                drawer.draw();
                std::thread::park_timeout(Duration::from_millis(1000 / REDRAW_HZ as u64));
            }
        });
        ACTIVE.store(true, Ordering::Relaxed);
        Some(Progress {
            view,
            thread: Some(thread),
        })
    }

    /// Redraws the status line (the state's lock is not held while the
    /// terminal is written to).
    fn draw(&self) {
        let line = self.state.lock().map(|s| self.line(&s));
        if let Ok(line) = line {
            self.bar.set_message(line);
            self.bar.tick();
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
        match (s.subdomain, &s.ranks_done) {
            (_, Some(done)) => {
                let per: Vec<String> = (done.iter().enumerate())
                    .map(|(r, n)| format!("rank {r}: {n}"))
                    .collect();
                let total: usize = done.iter().sum();
                line += &format!(
                    " {total} subdomain(s) on {} ranks ({})",
                    done.len(),
                    per.join(", ")
                );
            }
            (Some((_, of, _)), None) => line += &format!(" {of} subdomain(s)"),
            (None, None) => {}
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
        let ended = self.state.lock().ok().and_then(|mut s| {
            (s.stage != stage).then(|| {
                let seconds = s.since.elapsed().as_secs_f64();
                let line = format!("  {}: {seconds:.1} s", self.summary(&s));
                *s = State::new(stage);
                line
            })
        });
        if let Some(line) = ended {
            self.bar.println(line);
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
            Event::RanksCondensed(counts) if self.ranks > 1 => s.ranks_done = Some(counts.to_vec()),
            Event::RanksCondensed(_) | Event::Phase(_) => {}
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

    /// The view, as the observer of the run it shows.
    pub(crate) fn observer(&self) -> Arc<dyn Observer> {
        self.view.clone()
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.view.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            t.thread().unpark();
            let _ = t.join();
        }
        self.view.stage("done");
        self.view.bar.finish_and_clear();
        ACTIVE.store(false, Ordering::Relaxed);
    }
}
