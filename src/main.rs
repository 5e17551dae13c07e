//! The `signorini` command line: `run` and `check` (SCENE.md, "Commands").
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

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand};
use signorini_comm::{Local, Transport};
use signorini_report::output::{summary, write_outputs, OutputRequest};
use signorini_scene::{Method, SolvePath};
use signorini_solver::{RunOptions, SolveError};

#[derive(Parser)]
#[command(
    name = "signorini",
    version,
    about = "Unilateral contact between linear elastic solids by static condensation"
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
        /// condensed | direct, overriding [solver] path.
        #[arg(long)]
        path: Option<SolvePath>,
        /// Output directory, overriding [output] directory (default out/<scene stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Memory the run may use, e.g. 64G, 500M (powers of 1024), instead
        /// of the machine's available memory: a scene estimated to need more
        /// is refused before anything is built.
        #[arg(long, value_name = "SIZE", value_parser = memory_size)]
        max_memory: Option<u64>,
    },
    /// Parse and validate a scene and estimate its memory, writing nothing.
    Check {
        scene: PathBuf,
        /// The path whose memory to estimate (default: the scene's).
        #[arg(long)]
        path: Option<SolvePath>,
        /// As for `run`: the memory the run may use.
        #[arg(long, value_name = "SIZE", value_parser = memory_size)]
        max_memory: Option<u64>,
    },
    /// Solve a stand-alone condensed problem LCP(W, q) given as JSON
    /// {"W": [[...]], "q": [...]} or NumPy .npz (arrays W, q); prints one JSON
    /// line of timings and residuals.
    Local {
        problem: PathBuf,
        #[arg(long, default_value = "status")]
        method: Method,
        #[arg(long, default_value_t = 1e-10)]
        tolerance: f64,
        #[arg(long, default_value_t = 10_000)]
        max_iterations: usize,
        /// Include the contact forces λ in the JSON line.
        #[arg(long)]
        lambda: bool,
        /// Frictional problems (with mu): `fixed_point` (default) or `status`.
        #[arg(long, default_value = "fixed_point")]
        friction: String,
        /// Solve N times and report the median time.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=1000))]
        repeat: u64,
    },
    /// Time scenes over refinement levels, subdomain counts and paths; writes
    /// DIR/bench.csv and prints a table. With `--suite stiff`: the stiff and
    /// extreme cases (VALIDATION.md §8), DIR/stiff.csv and DIR/stiff.md, exit 1
    /// if a case fails its expectation.
    Bench {
        /// Scene files.
        #[arg(required_unless_present = "suite")]
        scenes: Vec<PathBuf>,
        /// A built-in suite instead of scene files: `stiff`, or `root` (every
        /// root method on Delassus problems of an elastic layer: DIR/root.csv,
        /// DIR/root.md, DIR/root_error_vs_time.svg).
        #[arg(long, value_parser = ["stiff", "root"], conflicts_with = "scenes")]
        suite: Option<String>,
        /// With --suite: the smaller meshes (stiff) or sizes (root) of the test suite.
        #[arg(long, requires = "suite")]
        quick: bool,
        /// With --suite root: the contact points of the problems (each
        /// family up to its largest size; default 49,196,784,2025,8000).
        #[arg(long, value_delimiter = ',', requires = "suite")]
        sizes: Vec<usize>,
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
        /// Paths to run.
        #[arg(long, value_delimiter = ',', default_value = "condensed,direct")]
        paths: Vec<SolvePath>,
        /// Output directory.
        #[arg(long, default_value = "out/bench")]
        out: PathBuf,
        /// As for `run`: the memory each run may use.
        #[arg(long, value_name = "SIZE", value_parser = memory_size)]
        max_memory: Option<u64>,
    },
}

fn memory_size(text: &str) -> Result<u64, String> {
    signorini_solver::memory::parse_size(text)
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
        eprintln!("error: internal error: {what}{place} (please report)");
    }));
}

fn main() -> ExitCode {
    install_panic_hook();
    let cli = Cli::parse();
    // The hook has printed the line; a panic anywhere (in faer's threads too,
    // which hand it to the caller) ends here with exit 3.
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| command(cli)))
        .unwrap_or(ExitCode::from(3))
}

fn command(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Check {
            scene,
            path,
            max_memory,
        } => {
            signorini_solver::memory::set_budget(max_memory);
            check(&scene, path)
        }
        Command::Local {
            problem,
            method,
            tolerance,
            max_iterations,
            lambda,
            friction,
            repeat,
        } => local(
            &problem,
            method,
            LocalOptions {
                tolerance,
                max_iterations,
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
            ..
        } => match suite.as_str() {
            "root" => root_suite(quick, export, &sizes, &out),
            _ if export || !sizes.is_empty() => {
                fail(1, "--export, --sizes: only with --suite root")
            }
            _ => stiff_suite(quick, &out),
        },
        Command::Bench {
            suite: None,
            quick: true,
            ..
        } => fail(1, "--quick: only with --suite stiff"),
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
            signorini_solver::memory::set_budget(max_memory);
            bench(&scenes, &levels, &subdomains, &methods, &paths, &out)
        }
        Command::Run {
            scene,
            method,
            path,
            out,
            max_memory,
        } => {
            signorini_solver::memory::set_budget(max_memory);
            let comm = transport();
            // For the tests of the panic path: a panic on that rank.
            if let Ok(r) = std::env::var("SIGNORINI_INJECT_PANIC") {
                if r.parse::<usize>().ok() == Some(comm.rank()) {
                    panic!("panic injected on rank {r} (SIGNORINI_INJECT_PANIC)");
                }
            }
            run(&scene, RunOptions { method, path }, out, comm.as_ref())
        }
    }
}

/// MPI when launched by an MPI launcher (and built with `--features mpi`),
/// else every subdomain in this process. Under MPI each rank gets
/// cores/ranks threads for faer; Open MPI binds a rank to one core unless
/// told `--bind-to none`, and then each rank has one thread.
fn transport() -> Box<dyn Transport> {
    // A build without MPI started by an MPI launcher would run the whole
    // problem once per rank, every copy writing the same output: refuse.
    #[cfg(not(feature = "mpi"))]
    {
        let ranks = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"]
            .iter()
            .find_map(|v| std::env::var(v).ok().and_then(|s| s.parse::<usize>().ok()));
        if let Some(n) = ranks.filter(|&n| n > 1) {
            let rank = ["OMPI_COMM_WORLD_RANK", "PMI_RANK"]
                .iter()
                .find_map(|v| std::env::var(v).ok().and_then(|s| s.parse::<usize>().ok()))
                .unwrap_or(0);
            if rank == 0 {
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
            let threads = (cores / m.size()).max(1);
            faer::set_global_parallelism(faer::Par::rayon(threads));
            return Box::new(m);
        }
    }
    Box::new(Local)
}

fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("error: {msg}");
    ExitCode::from(code)
}

fn bench(
    scenes: &[PathBuf],
    levels: &[f64],
    subdomains: &[usize],
    methods: &[Method],
    paths: &[SolvePath],
    out: &Path,
) -> ExitCode {
    if levels.iter().any(|l| !(*l > 0.0 && l.is_finite())) {
        return fail(1, "--levels: refinement factors must be positive numbers");
    }
    if subdomains.contains(&0) {
        return fail(1, "--subdomains: counts must be at least 1");
    }
    let mut cases = Vec::new();
    for p in scenes {
        match signorini_scene::load(p) {
            Ok(scene) => cases.push(signorini_solver::bench::BenchCase {
                name: p
                    .file_name()
                    .map(|s| s.to_string_lossy().to_string())
                    .unwrap_or_default(),
                scene,
            }),
            Err(e) => return fail(1, &e.to_string()),
        }
    }
    // A progress bar on a terminal; nothing when stderr is not one.
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new(0)
    } else {
        indicatif::ProgressBar::hidden()
    };
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed_precise} {msg}")
    {
        bar.set_style(style);
    }
    let rows = signorini_solver::bench::bench(
        &cases,
        levels,
        subdomains,
        methods,
        paths,
        |done, total, label| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            bar.set_message(label.to_string());
        },
    );
    bar.finish_and_clear();
    let rows = match rows {
        Ok(r) => r,
        Err(SolveError::Input(m)) => return fail(1, &m),
        Err(e) => return fail(3, &e.to_string()),
    };
    if let Err(e) = std::fs::create_dir_all(out)
        .and_then(|_| signorini_solver::bench::write_csv(&out.join("bench.csv"), &rows))
    {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    let plots = signorini_solver::bench::write_plots(out, &rows);
    println!(
        "| scene | level | subdomains | method | path | DOFs | Γ DOFs | contact pts | iterations | converged | condense s | root s | recover s | total s | error | vs finest |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.2e} | {:.2e} |",
            r.scene,
            r.level,
            r.subdomains,
            r.method,
            r.path,
            r.dofs,
            r.interface_dofs,
            r.contact_points,
            r.iterations,
            if r.converged { "yes" } else { "**no**" },
            r.condense_s,
            r.contact_s,
            r.recover_s,
            r.total_s,
            r.error,
            r.error_vs_finest
        );
    }
    match plots {
        Ok(p) => println!("bench.csv and {} plot(s) in {}", p.len(), out.display()),
        Err(e) => println!("bench.csv in {} (no plot: {e})", out.display()),
    }
    if rows.iter().all(|r| r.converged) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    }
}

/// `signorini bench --suite root`: every root method on the Delassus
/// problems of an elastic layer (issue 14), one line per run on stderr.
fn root_suite(quick: bool, export: bool, sizes: &[usize], out: &Path) -> ExitCode {
    use signorini_rootbench::{problem::Family, run};
    if let Some(m) = sizes.iter().find(|&&m| !(2..=8192).contains(&m)) {
        return fail(
            1,
            &format!("--sizes: {m} contact points; each size must be in 2..=8192 (W is dense)"),
        );
    }
    let problems = out.join("problems");
    let made = std::fs::create_dir_all(if export { &problems } else { out });
    if let Err(e) = made {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    let o = run::SuiteOptions {
        sizes: match (quick, sizes.is_empty()) {
            (_, false) => sizes.to_vec(),
            (true, true) => vec![49, 196],
            (false, true) => vec![49, 196, 784, 2025, 8000],
        },
        families: Family::ALL.to_vec(),
        tolerance: 1e-10,
        max_iterations: 5000,
        time_budget: 20.0,
        repeat: if quick { 1 } else { 3 },
    };
    let rows = run::run_suite(&o, export.then_some(problems.as_path()), |r| {
        eprintln!(
            "{} {}: {} in {:.4} s, residual {:.1e}, difference {:.1e}",
            r.problem,
            r.method,
            if r.converged {
                "converged"
            } else {
                "NOT converged"
            },
            r.time_s,
            r.residual,
            r.difference
        )
    });
    let rows = match rows {
        Ok(rows) => rows,
        Err(e) => return fail(3, &e),
    };
    let written = std::fs::write(out.join("root.csv"), run::csv(&rows))
        .and_then(|_| std::fs::write(out.join("root.md"), run::markdown(&rows)))
        .map_err(|e| e.to_string())
        .and_then(|_| run::error_vs_time_svg(&out.join("root_error_vs_time.svg"), &rows));
    if let Err(e) = written {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    print!("{}", run::markdown(&rows));
    ExitCode::SUCCESS
}

/// `signorini bench --suite stiff`: every case of the stiff suite in this
/// process, a line on stderr as each ends, the table on stdout,
/// DIR/stiff.csv, DIR/stiff.md and each case's scene in DIR/stiff/; exit 1
/// naming the cases that fail their expectation.
fn stiff_suite(quick: bool, out: &Path) -> ExitCode {
    use signorini_stiff as stiff;
    // Every case's scene beside the table, so that any case can be rerun
    // alone with `signorini run DIR/stiff/<case>.toml`.
    let cases = stiff::cases(quick);
    let scenes = out.join("stiff");
    if let Err(e) = std::fs::create_dir_all(&scenes).and_then(|_| {
        cases.iter().try_for_each(|c| {
            std::fs::write(
                scenes.join(format!("{}.toml", c.name)),
                format!(
                    "# signorini bench --suite stiff{}: case {} ({}, {})\n{}",
                    if quick { " --quick" } else { "" },
                    c.name,
                    c.family,
                    c.parameter,
                    c.text
                ),
            )
        })
    }) {
        return fail(3, &format!("cannot write {}: {e}", scenes.display()));
    }
    let n = cases.len();
    let mut rows = Vec::with_capacity(n);
    for (i, c) in cases.iter().enumerate() {
        let r = stiff::run_case(c);
        eprintln!(
            "[{}/{n}] {} ({}): {} in {:.3} s: {}",
            i + 1,
            r.case,
            r.parameter,
            if r.exit_code == 0 {
                "solved".to_string()
            } else {
                format!("exit {}", r.exit_code)
            },
            r.time_s,
            stiff::verdict_text(&r.verdict)
        );
        rows.push(r);
    }
    let table = stiff::markdown(&rows);
    println!("{table}");
    if let Err(e) = std::fs::create_dir_all(out)
        .and_then(|_| stiff::write_csv(&out.join("stiff.csv"), &rows))
        .and_then(|_| std::fs::write(out.join("stiff.md"), &table))
    {
        return fail(3, &format!("cannot write {}: {e}", out.display()));
    }
    let failed: Vec<&stiff::StiffRow> = rows.iter().filter(|r| r.failed()).collect();
    println!(
        "{} cases: {} passed, {} failed; stiff.csv, stiff.md and the scenes (stiff/<case>.toml) in {}",
        rows.len(),
        rows.iter().filter(|r| r.passed()).count(),
        failed.len(),
        out.display()
    );
    if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        for r in &failed {
            eprintln!("error: {}: {}", r.case, stiff::verdict_text(&r.verdict));
        }
        ExitCode::from(1)
    }
}

/// The options of `signorini local`.
struct LocalOptions {
    tolerance: f64,
    max_iterations: usize,
    with_lambda: bool,
    friction: String,
    repeat: usize,
}

fn local(path: &Path, method: Method, o: LocalOptions) -> ExitCode {
    if !(o.tolerance > 0.0 && o.tolerance < 1.0) {
        return fail(
            1,
            &format!("--tolerance: must be in (0, 1), got {}", o.tolerance),
        );
    }
    let problem = match signorini_solver::local::load(path) {
        Ok(p) => p,
        Err(e) => return fail(1, &e),
    };
    // The scene's defaults for the status variant and the constraints.
    let algorithm = signorini_solver::algorithm_of(&signorini_scene::Solver::default(), method);
    let name = path.display().to_string();
    let friction = if problem.mu.is_some() {
        if method != Method::Status {
            return fail(
                1,
                "--method: frictional local problems are solved by the friction solvers (--friction fixed_point or status)",
            );
        }
        match signorini_solver::local::FrictionMethod::from_name(&o.friction) {
            Ok(f) if problem.dim == 3 && !f.solves_3d() => {
                return fail(
                    1,
                    &format!(
                        "--friction {}: a 2D method; 3D problems are solved by fixed_point",
                        f.name()
                    ),
                )
            }
            Ok(f) => Some(f),
            Err(e) => return fail(1, &e),
        }
    } else {
        None
    };
    let solve = || match friction {
        Some(f) => signorini_solver::local::solve_friction(
            &name,
            &problem,
            f,
            o.tolerance,
            o.max_iterations,
            o.with_lambda,
        ),
        None => signorini_solver::local::solve(
            &name,
            &problem,
            algorithm,
            o.tolerance,
            o.max_iterations,
            o.with_lambda,
        ),
    };
    let result = signorini_solver::local::repeated(o.repeat, solve);
    match result {
        Ok(r) => {
            println!("{}", serde_json::to_string(&r).unwrap_or_default());
            if r.converged {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(2)
            }
        }
        Err(e) => fail(2, &e),
    }
}

fn check(path: &Path, solve_path: Option<SolvePath>) -> ExitCode {
    use signorini_solver::memory;
    let sc = match signorini_scene::load(path) {
        Ok(sc) => sc,
        Err(e) => return fail(1, &e.to_string()),
    };
    let solve_path = solve_path.unwrap_or(sc.solver.path);
    // The memory of one process (under mpirun, `run` estimates for its ranks).
    let estimate = match memory::check(&sc, solve_path, 1) {
        Ok(e) => e,
        Err(e) => return fail(1, &e.to_string()),
    };
    println!(
        "{}: valid scene \"{}\" ({} bodies, {} boundary conditions, {} contacts, {} steps)",
        path.display(),
        sc.title,
        sc.bodies.len(),
        sc.boundary.len(),
        sc.contact.len(),
        sc.step_scales().len()
    );
    let budget = memory::budget()
        .map(|b| format!("; {} {}", memory::human(b.bytes as f64), b.source))
        .unwrap_or_default();
    println!(
        "  memory ({} path): {}{budget}",
        solve_path.as_str(),
        estimate.describe()
    );
    ExitCode::SUCCESS
}

fn run(path: &Path, opts: RunOptions, out: Option<PathBuf>, comm: &dyn Transport) -> ExitCode {
    let t0 = Instant::now();
    // Every rank meets the same error; rank 0 alone prints it.
    let root = comm.is_root();
    let fail = |code: u8, msg: &str| {
        if root {
            fail(code, msg)
        } else {
            ExitCode::from(code)
        }
    };
    let sc = match signorini_scene::load(path) {
        Ok(sc) => sc,
        Err(e) => return fail(1, &e.to_string()),
    };
    let setup = t0.elapsed().as_secs_f64();
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let mut output = match signorini_solver::run(&sc, &name, &opts, comm) {
        Ok(Some(o)) => o,
        Ok(None) => return ExitCode::SUCCESS,
        Err(SolveError::Input(m)) => return fail(1, &m),
        Err(e @ SolveError::Internal(_)) => return fail(3, &e.to_string()),
    };
    let dir = out.unwrap_or_else(|| sc.output.directory_for(path));
    let t = Instant::now();
    output.report.timings_s.setup += setup;
    let request = OutputRequest {
        dim: sc.dimension as usize,
        fields: sc.output.fields.clone(),
    };
    if let Err(e) = write_outputs(&dir, &request, &mut output, t) {
        return fail(
            3,
            &format!("cannot write the output in {}: {e}", dir.display()),
        );
    }
    print!("{}", summary(&dir, &output));
    if output.report.converged {
        ExitCode::SUCCESS
    } else {
        eprintln!(
            "not converged: {}",
            output.report.failure.as_deref().unwrap_or("see the report")
        );
        ExitCode::from(2)
    }
}
