//! `signorini check` and `signorini run`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use signorini_comm::Transport;
use signorini_report::output::{summary, write_outputs};
use signorini_report::results::OutputRequest;
use signorini_report::stream::FieldWriter;
use signorini_scene::SolvePath;
use signorini_solver::memory::Budget;
use signorini_solver::timing::timed;
use signorini_solver::{RunEnvironment, RunOptions, RunOutput, SolveError};

use crate::progress::{Progress, Show, Terminal};
use crate::{fail, say};

pub(crate) fn check(
    path: &Path,
    solve_path: Option<SolvePath>,
    budget: Option<Budget>,
) -> ExitCode {
    use signorini_solver::memory;
    let sc = match signorini_scene::load(path) {
        Ok(sc) => sc,
        Err(e) => return fail(1, &e.to_string()),
    };
    let opts = RunOptions {
        method: None,
        path: solve_path,
    };
    // The memory of one process (under mpirun, `run` estimates for its ranks).
    let choice = match signorini_solver::choose_path(&sc, &opts, 1, budget) {
        Ok(c) => c,
        Err(e) => return fail(1, &e.to_string()),
    };
    let auto = choice.requested == SolvePath::Auto.as_str();
    // `chosen` is a path's own spelling
    let solve_path = choice.chosen.parse().unwrap_or(SolvePath::Condensed);
    let counts = memory::ContactCounts::Surfaces;
    let estimate = match memory::check(&sc, (solve_path, 1), counts, budget) {
        Ok(e) => e,
        Err(e) => return fail(1, &e.to_string()),
    };
    if let Err(e) = read_file_meshes(&sc)
        .and_then(|files| signorini_solver::model::check_surface_names(&sc, &files))
    {
        return fail(1, &e.to_string());
    }
    say(&format!(
        "{}: valid scene \"{}\" ({} bodies, {} boundary conditions, {} contacts, {} steps)\n",
        path.display(),
        sc.title,
        sc.bodies.len(),
        sc.boundary.len(),
        sc.contact.len(),
        sc.step_scales().len()
    ));
    let budget = budget
        .map(|b| format!("; {} {}", memory::human(b.bytes as f64), b.source))
        .unwrap_or_default();
    say(&format!(
        "  memory ({} path): {}{budget}\n",
        solve_path.as_str(),
        estimate.describe()
    ));
    if auto {
        say(&format!(
            "  path auto: {} ({})\n",
            choice.chosen, choice.reason
        ));
    }
    ExitCode::SUCCESS
}

/// Reads the Gmsh files of the scene's bodies, as `run` would, for their
/// errors (an unsupported element type, lost physical groups...): `check`
/// must not call valid a scene whose mesh `run` refuses. Generator meshes
/// are not built (their parameters are checked with the scene, and their
/// size is what the memory estimate is for). Returns the surface names of
/// each body read from a file, for [`signorini_solver::model::check_surface_names`].
fn read_file_meshes(
    sc: &signorini_scene::Scene,
) -> Result<BTreeMap<String, Vec<String>>, SolveError> {
    let mut surfaces = BTreeMap::new();
    for (bi, body) in sc.bodies.iter().enumerate() {
        if let Some(signorini_scene::MeshSpec::File { .. }) = &body.mesh {
            let entry = format!("bodies[{bi}]");
            let mesh = signorini_solver::model::build_mesh(body, &entry, sc.dimension as usize)?;
            surfaces.insert(body.name.clone(), mesh.surfaces.keys().cloned().collect());
        }
    }
    Ok(surfaces)
}

pub(crate) fn run(
    path: &Path,
    opts: RunOptions,
    env: &RunEnvironment,
    out: Option<PathBuf>,
    show: Show,
    comm: &dyn Transport,
) -> ExitCode {
    // The progress line ends before anything else is printed.
    let mpi = comm.kind() == "mpi";
    let progress = Terminal::start(show, comm.is_root(), mpi, comm.size());
    let env = RunEnvironment {
        observer: progress.as_ref().map(Progress::observer),
        ..env.clone()
    };
    let solved = solve_and_write(path, (opts, &env), out, progress.as_ref(), comm);
    drop(progress);
    // Every rank meets the same error; rank 0 alone prints it.
    let (dir, output) = match solved {
        Ok(Some(o)) => o,
        Ok(None) => return ExitCode::SUCCESS,
        Err((code, msg)) if comm.is_root() => return fail(code, &msg),
        Err((code, _)) => return ExitCode::from(code),
    };
    say(&summary(&dir, &output));
    if output.report.converged {
        ExitCode::SUCCESS
    } else {
        crate::tell(&format!(
            "not converged: {}",
            output.report.failure.as_deref().unwrap_or("see the report")
        ));
        ExitCode::from(2)
    }
}

/// Reads, solves and (on the root) writes the output: its directory and
/// the output, `None` on the other ranks, or the exit code and message.
fn solve_and_write(
    path: &Path,
    (opts, env): (RunOptions, &RunEnvironment),
    out: Option<PathBuf>,
    progress: Option<&Progress>,
    comm: &dyn Transport,
) -> Result<Option<(PathBuf, RunOutput)>, (u8, String)> {
    let mut setup = 0.0;
    let sc = timed(&mut setup, || signorini_scene::load(path)).map_err(|e| (1, e.to_string()))?;
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let dir = out.unwrap_or_else(|| sc.output.directory_for(path));
    // The root checks before solving that it can write the output; every
    // rank learns its answer (a rank that stopped alone would leave the
    // others waiting).
    let usable = comm.is_root().then(|| output_directory_usable(&dir));
    // What the run creates of `dir`'s path (nothing exists yet: every rank
    // waits for the broadcast below before it writes).
    let created = (comm.is_root())
        .then(|| {
            (dir.ancestors())
                .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
                .last()
                .map(Path::to_path_buf)
        })
        .flatten();
    signorini_comm::broadcast(comm, usable.as_ref())
        .map_err(|e| (3, e))?
        .map_err(|m| (1, m))?;
    let request = OutputRequest {
        dim: sc.dimension as usize,
        fields: sc.output.fields.clone(),
    };
    // Each step's fields go to disk as the step ends (the root alone writes).
    let mut writer = FieldWriter::new(&dir, request);
    let mut output = match signorini_solver::run_streamed(&sc, &name, &opts, env, comm, &mut writer)
    {
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
        Err(e) => {
            drop(writer);
            remove_created(comm, &dir, created.as_deref());
            return Err(match e {
                SolveError::Input(m) => (1, m),
                e @ SolveError::Internal(_) => (3, e.to_string()),
            });
        }
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

/// After a run that failed on every rank alike: once every rank has
/// removed what it staged (the gather waits for them), the root removes the
/// directories the run created for `dir`, from `dir` up to `top`, if they
/// are empty. A rank's own writer cannot: under mpirun another rank's stage
/// may still be in them when it tries (an error at a later step with
/// `[output] pieces` left the empty directories behind).
fn remove_created(comm: &dyn Transport, dir: &Path, top: Option<&Path>) {
    let _ = signorini_comm::gather(comm, ());
    let Some(top) = top else {
        return;
    };
    for d in dir.ancestors() {
        if std::fs::remove_dir(d).is_err() || d == top {
            break;
        }
    }
}

/// Whether the output directory `dir` can be created and written, checked
/// before anything is solved: the error names it and says why, and nothing
/// is left behind (a probe directory is made and removed).
fn output_directory_usable(dir: &Path) -> Result<(), String> {
    let shown = dir.display();
    let advice = "choose another with --out or [output] directory";
    let existing = (dir.ancestors())
        .find(|a| a.as_os_str().is_empty() || a.exists())
        .unwrap_or(dir);
    let existing = if existing.as_os_str().is_empty() {
        Path::new(".")
    } else {
        existing
    };
    if !existing.is_dir() {
        let what = match existing == dir {
            true => "exists".to_string(),
            false => format!("{} exists", existing.display()),
        };
        return Err(format!(
            "output directory {shown}: {what} and is not a directory; {advice}"
        ));
    }
    let probe = existing.join(format!(".signorini-probe-{}", std::process::id()));
    std::fs::create_dir(&probe)
        .and_then(|()| std::fs::remove_dir(&probe))
        .map_err(|e| {
            format!(
                "output directory {shown}: cannot write in {} ({e}); {advice}",
                existing.display()
            )
        })
}
