//! `signorini check` and `signorini run`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use signorini_comm::Transport;
use signorini_report::output::{summary, write_outputs, OutputRequest};
use signorini_report::stream::FieldWriter;
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, SolveError};

use crate::fail;

pub(crate) fn check(path: &Path, solve_path: Option<SolvePath>) -> ExitCode {
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

pub(crate) fn run(
    path: &Path,
    opts: RunOptions,
    out: Option<PathBuf>,
    comm: &dyn Transport,
) -> ExitCode {
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
    let dir = out.unwrap_or_else(|| sc.output.directory_for(path));
    let request = OutputRequest {
        dim: sc.dimension as usize,
        fields: sc.output.fields.clone(),
    };
    // Each step's fields go to disk as the step ends (the root alone writes).
    let mut writer = FieldWriter::new(&dir, request);
    let mut output = match signorini_solver::run_streamed(&sc, &name, &opts, comm, &mut writer) {
        Ok(Some(o)) => o,
        Ok(None) => return ExitCode::SUCCESS,
        Err(SolveError::Input(m)) => return fail(1, &m),
        Err(e @ SolveError::Internal(_)) => return fail(3, &e.to_string()),
    };
    let t = Instant::now();
    output.report.timings_s.setup += setup;
    if let Err(e) = write_outputs(&mut writer, &mut output, t) {
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
