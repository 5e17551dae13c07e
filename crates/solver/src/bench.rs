//! `signorini bench`: a scene over refinement levels, subdomain counts and
//! paths, each run timed per phase with its errors (DESIGN.md §6: speed is
//! measured here and in `cargo bench`, never in timed unit tests).

use serde::Serialize;
use signorini_comm::Local;
use signorini_scene as scene;

use crate::{run, RunOptions, SolveError};

/// One run of the benchmark.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRow {
    pub scene: String,
    pub level: f64,
    pub subdomains: usize,
    pub method: String,
    pub path: String,
    pub dofs: usize,
    pub interface_dofs: usize,
    pub contact_points: usize,
    pub iterations: usize,
    pub converged: bool,
    pub assemble_s: f64,
    pub condense_s: f64,
    pub contact_s: f64,
    pub recover_s: f64,
    pub total_s: f64,
    pub peak_rss_bytes: u64,
    pub dense_interface_bytes: u64,
    /// Relative error of each reference quantity, "name=value;..."
    pub errors: String,
}

pub struct BenchCase {
    pub name: String,
    pub scene: scene::Scene,
}

/// Runs every combination; `progress(done, total, label)` is called before each run.
pub fn bench(
    cases: &[BenchCase],
    levels: &[f64],
    subdomains: &[usize],
    paths: &[scene::SolvePath],
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<Vec<BenchRow>, SolveError> {
    let total = cases.len() * levels.len() * subdomains.len() * paths.len();
    let mut rows = Vec::new();
    let mut done = 0;
    for case in cases {
        for &level in levels {
            for &n in subdomains {
                for &path in paths {
                    if path == scene::SolvePath::Direct && n > 1 && subdomains.contains(&1) {
                        // The direct path ignores subdomains: run it once per level.
                        done += 1;
                        continue;
                    }
                    let label = format!(
                        "{} level {level} subdomains {n} {}",
                        case.name,
                        path.as_str()
                    );
                    progress(done, total, &label);
                    done += 1;
                    let sc = case.scene.refined(level).with_subdomains(n);
                    let out = run(
                        &sc,
                        &case.name,
                        &RunOptions {
                            method: None,
                            path: Some(path),
                        },
                        &Local,
                    )?
                    .ok_or_else(|| SolveError::Internal("no output in process".into()))?;
                    let r = &out.report;
                    let errors = r
                        .reference
                        .as_ref()
                        .map(|rf| {
                            rf.quantities
                                .iter()
                                .map(|(k, q)| format!("{k}={:.4e}", q.relative_error))
                                .collect::<Vec<_>>()
                                .join(";")
                        })
                        .unwrap_or_default();
                    rows.push(BenchRow {
                        scene: case.name.clone(),
                        level,
                        subdomains: r.subdomains,
                        method: r.method.clone(),
                        path: r.path.clone(),
                        dofs: r.dofs,
                        interface_dofs: r.interface_dofs,
                        contact_points: r.contact_points,
                        iterations: r.steps.iter().map(|s| s.iterations).sum(),
                        converged: r.converged,
                        assemble_s: r.timings_s.assemble,
                        condense_s: r.timings_s.condense,
                        contact_s: r.timings_s.contact,
                        recover_s: r.timings_s.recover,
                        total_s: r.timings_s.total,
                        peak_rss_bytes: r.memory.peak_rss_bytes,
                        dense_interface_bytes: r.memory.dense_interface_bytes,
                        errors,
                    });
                }
            }
        }
    }
    progress(total, total, "done");
    Ok(rows)
}

/// bench.csv: one line per run.
pub fn write_csv(path: &std::path::Path, rows: &[BenchRow]) -> std::io::Result<()> {
    use std::io::Write;
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(
        w,
        "scene,level,subdomains,method,path,dofs,interface_dofs,contact_points,iterations,converged,assemble_s,condense_s,contact_s,recover_s,total_s,peak_rss_bytes,dense_interface_bytes,errors"
    )?;
    for r in rows {
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{},{},{}",
            r.scene,
            r.level,
            r.subdomains,
            r.method,
            r.path,
            r.dofs,
            r.interface_dofs,
            r.contact_points,
            r.iterations,
            r.converged,
            r.assemble_s,
            r.condense_s,
            r.contact_s,
            r.recover_s,
            r.total_s,
            r.peak_rss_bytes,
            r.dense_interface_bytes,
            r.errors
        )?;
    }
    w.flush()
}
