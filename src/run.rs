//! `signorini check` and `signorini run`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use signorini_comm::Transport;
use signorini_report::output::{summary, write_outputs, OutputRequest};
use signorini_report::stream::FieldWriter;
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, RunOutput, SolveError};

use crate::fail;
use crate::progress::{Progress, Show, Terminal};

pub(crate) fn check(path: &Path, solve_path: Option<SolvePath>) -> ExitCode {
    use signorini_solver::memory;
    let sc = match signorini_scene::load(path) {
        Ok(sc) => sc,
        Err(e) => return fail(1, &e.to_string()),
    };
    let solve_path = solve_path.unwrap_or(sc.solver.path);
    // The memory of one process (under mpirun, `run` estimates for its ranks).
    let estimate = match memory::check(&sc, solve_path, 1, memory::ContactCounts::Surfaces) {
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

pub(crate) fn run(
    path: &Path,
    opts: RunOptions,
    out: Option<PathBuf>,
    show: Show,
    comm: &dyn Transport,
) -> ExitCode {
    // The progress line ends before anything else is printed.
    let mpi = comm.kind() == "mpi";
    let progress = Terminal::start(show, comm.is_root(), mpi, comm.size());
    let solved = solve_and_write(path, opts, out, progress.as_ref(), comm);
    drop(progress);
    // Every rank meets the same error; rank 0 alone prints it.
    let (dir, output) = match solved {
        Ok(Some(o)) => o,
        Ok(None) => return ExitCode::SUCCESS,
        Err((code, msg)) if comm.is_root() => return fail(code, &msg),
        Err((code, _)) => return ExitCode::from(code),
    };
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

/// Reads, solves and (on the root) writes the output: its directory and
/// the output, `None` on the other ranks, or the exit code and message.
fn solve_and_write(
    path: &Path,
    opts: RunOptions,
    out: Option<PathBuf>,
    progress: Option<&Progress>,
    comm: &dyn Transport,
) -> Result<Option<(PathBuf, RunOutput)>, (u8, String)> {
    let t0 = Instant::now();
    let sc = signorini_scene::load(path).map_err(|e| (1, e.to_string()))?;
    let setup = t0.elapsed().as_secs_f64();
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let dir = out.unwrap_or_else(|| sc.output.directory_for(path));
    let request = OutputRequest {
        dim: sc.dimension as usize,
        fields: sc.output.fields.clone(),
    };
    // Each step's fields go to disk as the step ends (the root alone writes).
    let mut writer = FieldWriter::new(&dir, request);
    let mut output = match signorini_solver::run_streamed(&sc, &name, &opts, comm, &mut writer) {
        Ok(Some(o)) => o,
        // Another rank: its pieces (`[output] pieces`) into place.
        Ok(None) => {
            return match writer.commit_pieces() {
                Ok(()) => Ok(None),
                Err(e) => Err((
                    3,
                    format!("cannot write the output in {}: {e}", dir.display()),
                )),
            }
        }
        Err(SolveError::Input(m)) => return Err((1, m)),
        Err(e @ SolveError::Internal(_)) => return Err((3, e.to_string())),
    };
    if let Some(p) = progress {
        p.stage("writing the output");
    }
    let t = Instant::now();
    output.report.timings_s.setup += setup;
    write_outputs(&mut writer, &mut output, t).map_err(|e| {
        let msg = format!("cannot write the output in {}: {e}", dir.display());
        (3, msg)
    })?;
    Ok(Some((dir, output)))
}
