//! The `signorini` command line: `run` and `check` (docs/reference/scene-format.md, "Commands").
//! No numerics here: the pipeline is `signorini_solver::run`.
//!
//! Under `mpirun` (built with the cargo feature `mpi`) every rank runs the
//! same command: rank k owns its subdomains, rank 0 is the root and writes
//! the output; errors are printed once, by rank 0, and every rank exits with
//! the same code.
//!
//! Exit codes: 0 solved within tolerance; 1 bad input (nothing is written);
//! 2 solved but a tolerance or iteration limit was not met (the report says
//! which); 3 internal error.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{CommandFactory, Parser, Subcommand};

mod bench;
mod docs;
mod local;
mod progress;
mod run;
mod validation;
use signorini_comm::{Local, Transport};
use signorini_scene::{Method, SolvePath};
use signorini_solver::{RunEnvironment, RunOptions};

#[derive(Parser)]
// term_width = 0: the help is never wrapped, whatever the terminal and
// whether a dependency turns clap's `wrap_help` on (it does in a workspace
// build), so that every build prints the same help as docs/reference/cli.md.
#[command(
    name = "signorini",
    version,
    about = "Unilateral contact between linear elastic solids by static condensation",
    term_width = 0
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a scene and write DIR/report.json, DIR/contact.csv and the fields.
    Run {
        /// The scene file (TOML, or JSON with a .json extension).
        scene: PathBuf,
        /// Contact algorithm, overriding [solver] method.
        #[arg(long)]
        method: Option<Method>,
        /// condensed | direct | auto, overriding [solver] path.
        #[arg(long)]
        path: Option<SolvePath>,
        /// Output directory, overriding [output] directory (default out/<scene stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Memory the run may use, e.g. 64G, 500M (powers of 1024), instead
        /// of the machine's available memory: a scene estimated to need more
        /// is refused before anything is built.
        #[arg(long, value_name = "SIZE", value_parser = memory_size, allow_hyphen_values = true)]
        max_memory: Option<u64>,
        /// No progress line. Without it, when stderr is a terminal, the
        /// run shows its stage, the subdomain being condensed, the load
        /// step and the contact method's iterations (points in contact,
        /// residual) on stderr, and each stage's time as it ends (under MPI,
        /// on the root's terminal). Never in the output files.
        #[arg(long, short, conflicts_with = "progress")]
        quiet: bool,
        /// Show the progress line even when stderr is not a terminal (under
        /// an MPI launcher other than Open MPI's mpirun on this machine, or
        /// into a file).
        #[arg(long)]
        progress: bool,
    },
    /// Parse and validate a scene and estimate its memory, writing nothing.
    Check {
        scene: PathBuf,
        /// The path whose memory to estimate (default: the scene's).
        #[arg(long)]
        path: Option<SolvePath>,
        /// As for `run`: the memory the run may use.
        #[arg(long, value_name = "SIZE", value_parser = memory_size, allow_hyphen_values = true)]
        max_memory: Option<u64>,
    },
    /// Solve a stand-alone condensed problem LCP(W, q) given as JSON
    /// {"W": [[...]], "q": [...]}, NumPy .npz (arrays W, q) or an FCLib
    /// local problem (.hdf5, .h5); prints one JSON line of timings and
    /// residuals.
    Local {
        problem: PathBuf,
        #[arg(long, default_value = "status")]
        method: Method,
        #[arg(long, default_value_t = 1e-10)]
        tolerance: f64,
        #[arg(long, default_value_t = 10_000, value_parser = at_least_one)]
        max_iterations: usize,
        /// Include the contact forces λ in the JSON line.
        #[arg(long)]
        lambda: bool,
        /// Frictional problems (with mu): `auto` (default: the fastest
        /// verified method for the problem, docs/guide/choosing.md),
        /// `fixed_point`, `status` (2D), `newton` (semi-smooth Newton on
        /// Coulomb's law) or `nsgs` (nonsmooth Gauss–Seidel).
        #[arg(long, default_value = "auto")]
        friction: String,
        /// Stop the solve, by any --method or --friction, after SECONDS of
        /// wall-clock time (checked between iterations), not converged
        /// (exit 2) (default: 10 + 2e-9 × rows³).
        #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
        time_limit: Option<f64>,
        /// Solve N times and report the median time.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=1000))]
        repeat: u64,
        /// The memory the solve may use (default: the machine's available
        /// memory): a .npz whose arrays unpack to more, or an FCLib file
        /// whose dense W would not fit, is refused before they are read.
        #[arg(long, value_name = "SIZE", value_parser = memory_size, allow_hyphen_values = true)]
        max_memory: Option<u64>,
    },
    /// Time scenes over refinement levels, subdomain counts and paths; writes
    /// DIR/bench.csv and prints a table. With `--suite stiff`: the stiff and
    /// extreme cases (docs/theory/validation-cases.md §8), DIR/stiff.csv and DIR/stiff.md, exit 1
    /// if a case fails its expectation.
    Bench {
        /// Scene files.
        #[arg(required_unless_present_any = ["suite", "plot"])]
        scenes: Vec<PathBuf>,
        /// Draw the plots of bench.csv files instead of running (their rows
        /// together, e.g. levels run separately) into --out.
        #[arg(long, value_delimiter = ',', value_name = "CSV", conflicts_with_all = ["scenes", "suite"])]
        plot: Vec<PathBuf>,
        /// A built-in suite instead of scene files: `stiff`, or `root` (every
        /// root method on Delassus problems of an elastic layer and of an
        /// elastic half-space: DIR/root.csv, DIR/root.md,
        /// DIR/root_error_vs_time.svg).
        #[arg(long, value_parser = ["stiff", "root"], conflicts_with = "scenes")]
        suite: Option<String>,
        /// With --suite: the smaller meshes (stiff) or sizes (root) of the test suite.
        #[arg(long, requires = "suite")]
        quick: bool,
        /// With --suite root: the contact points of the problems (each
        /// family up to its largest size; default 49,196,784,2025,8000).
        #[arg(long, value_delimiter = ',', requires = "suite")]
        sizes: Vec<usize>,
        /// With --suite root: the problem families to run (default all):
        /// lcp_2d, coulomb_2d, lcp_3d, coulomb_3d (the layer), halfspace_lcp_2d,
        /// halfspace_coulomb_2d, halfspace_lcp_3d, halfspace_coulomb_3d.
        #[arg(long, value_delimiter = ',', requires = "suite")]
        families: Vec<String>,
        /// With --suite root: also write each problem as DIR/problems/NAME.npz
        /// (contact-wise W, q, mu, dim) for other libraries.
        #[arg(long, requires = "suite")]
        export: bool,
        /// Refinement factors applied to the generators' divisions.
        #[arg(long, value_delimiter = ',', default_value = "1")]
        levels: Vec<f64>,
        /// Subdomains per deformable body.
        #[arg(long, value_delimiter = ',', default_value = "1")]
        subdomains: Vec<usize>,
        /// Contact algorithms to run (the direct path runs the status method only).
        #[arg(long, value_delimiter = ',', default_value = "status")]
        methods: Vec<Method>,
        /// Paths to run (beside the condensed path, the direct one is left
        /// out of scenes it refuses: contact elements, and the friction laws
        /// and solvers it leaves to the condensed path).
        #[arg(long, value_delimiter = ',', default_value = "condensed,direct")]
        paths: Vec<SolvePath>,
        /// Output directory.
        #[arg(long, default_value = "out/bench")]
        out: PathBuf,
        /// As for `run`: the memory each run may use.
        #[arg(long, value_name = "SIZE", value_parser = memory_size, allow_hyphen_values = true)]
        max_memory: Option<u64>,
    },
    /// Generate the documentation that a run of this build measures: the
    /// validation and examples tables, the command-line reference.
    Docs {
        #[command(subcommand)]
        what: Docs,
    },
}

#[derive(Subcommand)]
enum Docs {
    /// Run every scene of the examples directory at its shipped size and
    /// write OUT/README.md (each benchmark with a reference: the quantities
    /// compared, computed, exact and their relative error) and
    /// OUT/examples.md (each example: what it solves, DOFs, Γ DOFs,
    /// iterations, its largest error). No timings. Exit 2 if an example
    /// does not converge (the tables are written and say so).
    Validation {
        /// The directory of the scenes (*.toml).
        #[arg(long, default_value = "examples")]
        examples: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "docs/validation")]
        out: PathBuf,
    },
    /// Print every command's --help as one Markdown file (the command-line
    /// reference, docs/reference/cli.md).
    Cli {
        /// Write it to this file instead of printing it.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
}

fn memory_size(text: &str) -> Result<u64, String> {
    signorini_solver::memory::parse_size(text)
}

/// A count of at least 1 (an iteration limit).
fn at_least_one(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(0) => Err("must be at least 1, got 0".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!("expected a whole number >= 1, got \"{text}\"")),
    }
}

/// A panic is a bug: one line on stderr and exit 3, never a backtrace (set
/// SIGNORINI_BACKTRACE=1 for Rust's report). Under MPI the transport's hook
/// runs this one and then aborts every rank (crates/comm), so that no rank
/// waits forever for a dead one.
fn install_panic_hook() {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::env::var_os("SIGNORINI_BACKTRACE").is_some() {
            default_hook(info);
        }
        let what = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".to_string());
        let what = what.lines().next().unwrap_or_default();
        let what: String = what.chars().take(300).collect();
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        progress::clear_line();
        eprintln!("error: internal error: {what}{place} (please report)");
    }));
}

fn main() -> ExitCode {
    install_panic_hook();
    // A bad command line is bad input: exit 1 (clap's own code is 2, which
    // here means "not converged"); help and version exit 0.
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(u8::from(e.use_stderr()));
        }
    };
    // The hook has printed the line; a panic anywhere (in faer's threads too,
    // which hand it to the caller) ends here with exit 3.
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| command(cli)))
        .unwrap_or(ExitCode::from(3))
}

/// This process's rank as an MPI launcher numbers it (0 when not launched
/// by one).
fn launcher_rank() -> usize {
    ["OMPI_COMM_WORLD_RANK", "PMI_RANK"]
        .iter()
        .find_map(|v| std::env::var(v).ok().and_then(|s| s.parse::<usize>().ok()))
        .unwrap_or(0)
}

fn command(cli: Cli) -> ExitCode {
    // `check`, `local`, `bench` and `docs` are one process's work: under an MPI
    // launcher the first rank does it once, and the others stop (they
    // printed and wrote the same files at once).
    if !matches!(cli.command, Command::Run { .. }) && launcher_rank() > 0 {
        return ExitCode::SUCCESS;
    }
    match cli.command {
        Command::Docs {
            what: Docs::Validation { examples, out },
        } => validation::validation(&examples, &out),
        Command::Docs {
            what: Docs::Cli { out },
        } => docs::write_or_print(&docs::cli_reference(Cli::command()), out.as_deref()),
        Command::Check {
            scene,
            path,
            max_memory,
        } => run::check(&scene, path, budget(max_memory)),
        Command::Local {
            problem,
            method,
            tolerance,
            max_iterations,
            lambda,
            friction,
            time_limit,
            repeat,
            max_memory,
        } => local::local(
            &problem,
            method,
            local::LocalOptions {
                budget: budget(max_memory),
                tolerance,
                max_iterations,
                time_limit,
                with_lambda: lambda,
                friction,
                repeat: repeat as usize,
            },
        ),
        Command::Bench {
            suite: Some(suite),
            quick,
            out,
            export,
            sizes,
            families,
            ..
        } => match suite.as_str() {
            "root" => bench::root_suite(quick, export, (&sizes, &families), &out),
            _ if export || !sizes.is_empty() || !families.is_empty() => {
                fail(1, "--export, --sizes, --families: only with --suite root")
            }
            _ => bench::stiff_suite(quick, &out),
        },
        Command::Bench {
            suite: None,
            quick: true,
            ..
        } => fail(1, "--quick: only with --suite stiff"),
        Command::Bench { plot, out, .. } if !plot.is_empty() => bench::plot(&plot, &out),
        Command::Bench {
            scenes,
            levels,
            subdomains,
            methods,
            paths,
            out,
            max_memory,
            ..
        } => {
            let env = environment(max_memory);
            bench::bench(&scenes, &levels, &subdomains, &methods, &paths, &env, &out)
        }
        Command::Run {
            scene,
            method,
            path,
            out,
            max_memory,
            quiet,
            progress,
        } => {
            let env = environment(max_memory);
            let comm = transport();
            // For the tests of the panic path: a panic on that rank.
            if let Ok(r) = std::env::var("SIGNORINI_INJECT_PANIC") {
                if r.parse::<usize>().ok() == Some(comm.rank()) {
                    panic!("panic injected on rank {r} (SIGNORINI_INJECT_PANIC)");
                }
            }
            let show = match (quiet, progress) {
                (true, _) => progress::Show::Never,
                (false, true) => progress::Show::Always,
                (false, false) => progress::Show::OnTerminal,
            };
            run::run(
                &scene,
                RunOptions { method, path },
                &env,
                out,
                show,
                comm.as_ref(),
            )
        }
    }
}

/// The memory a command may use: `--max-memory`, else the machine's.
fn budget(max_memory: Option<u64>) -> Option<signorini_solver::memory::Budget> {
    signorini_report::budget::budget(max_memory)
}

/// What a run gets from this process: the memory it may use, and for the
/// tests of the MPI path a rank to fail (SIGNORINI_FAIL_RANK); the progress
/// line, if any, is added by `run::run`.
fn environment(max_memory: Option<u64>) -> RunEnvironment {
    RunEnvironment {
        budget: budget(max_memory),
        observer: None,
        fail_rank: std::env::var("SIGNORINI_FAIL_RANK")
            .ok()
            .and_then(|r| r.parse().ok()),
    }
}

/// MPI when launched by an MPI launcher (and built with `--features mpi`),
/// else every subdomain in this process. Under MPI each rank gets
/// max(1, cores / ranks on its machine) threads for faer, or
/// RAYON_NUM_THREADS when set (`signorini_comm::threads_per_rank`); Open MPI
/// binds a rank to one core unless told `--bind-to none`, and then each rank
/// sees one core and has one thread.
fn transport() -> Box<dyn Transport> {
    // A build without MPI started by an MPI launcher would run the whole
    // problem once per rank, every copy writing the same output: refuse.
    #[cfg(not(feature = "mpi"))]
    {
        let ranks = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"]
            .iter()
            .find_map(|v| std::env::var(v).ok().and_then(|s| s.parse::<usize>().ok()));
        if let Some(n) = ranks.filter(|&n| n > 1) {
            if launcher_rank() == 0 {
                eprintln!(
                    "error: started on {n} MPI ranks, but this signorini was built without MPI; rebuild with `cargo build --release --features mpi`"
                );
            }
            std::process::exit(1);
        }
    }
    #[cfg(feature = "mpi")]
    if signorini_comm::Mpi::launched() {
        if let Some(m) = signorini_comm::Mpi::init() {
            let cores = std::thread::available_parallelism()
                .map(|n| n.get())
                .unwrap_or(1);
            let user = std::env::var("RAYON_NUM_THREADS").ok();
            let threads =
                signorini_comm::threads_per_rank(cores, m.ranks_on_this_node(), user.as_deref());
            // The one process-wide setting kept: faer's parallelism is global
            // by faer's design (every factorisation of the process shares its
            // thread pool), and a rank's share of the machine's cores is the
            // process's, set once here before any run.
            faer::set_global_parallelism(faer::Par::rayon(threads));
            return Box::new(m);
        }
    }
    Box::new(Local)
}

pub(crate) fn fail(code: u8, msg: &str) -> ExitCode {
    tell(&format!("error: {msg}"));
    ExitCode::from(code)
}

/// Prints to stdout; a closed or full stdout loses the text, not the run
/// (its files are written and its exit code stands).
pub(crate) fn say(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let _ = out.write_all(text.as_bytes()).and_then(|()| out.flush());
}

/// One line on stderr; a closed stderr loses it, not the exit code.
pub(crate) fn tell(line: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}
