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
    /// The largest relative error over the reference quantities (the load excluded).
    pub error: f64,
    /// The largest relative difference of the computed reference quantities
    /// from the finest level's (same method and path): the discretisation error
    /// where no closed form is exact.
    pub error_vs_finest: f64,
    /// Computed value of each reference quantity (for error_vs_finest).
    #[serde(skip)]
    computed: Vec<(String, f64)>,
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
    methods: &[scene::Method],
    paths: &[scene::SolvePath],
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<Vec<BenchRow>, SolveError> {
    let total = cases.len() * levels.len() * subdomains.len() * paths.len() * methods.len();
    let mut rows = Vec::new();
    let mut done = 0;
    for case in cases {
        for &level in levels {
            for &n in subdomains {
                for &method in methods {
                    for &path in paths {
                        // The direct path ignores subdomains and runs the status method.
                        let skip = path == scene::SolvePath::Direct
                            && ((n > 1 && subdomains.contains(&1))
                                || method != scene::Method::Status);
                        done += 1;
                        if skip {
                            continue;
                        }
                        let label = format!(
                            "{} level {level} subdomains {n} {} {}",
                            case.name,
                            method.as_str(),
                            path.as_str()
                        );
                        progress(done - 1, total, &label);
                        let sc = case.scene.refined(level).with_subdomains(n);
                        let opts = RunOptions {
                            method: Some(method),
                            path: Some(path),
                        };
                        let out = run(&sc, &case.name, &opts, &Local)?
                            .ok_or_else(|| SolveError::Internal("no output in process".into()))?;
                        rows.push(row(&case.name, level, &out.report));
                    }
                }
            }
        }
    }
    // Error against the finest level of the same scene, subdomains, method and path.
    let finest = levels.iter().fold(f64::NEG_INFINITY, |a, &l| a.max(l));
    for i in 0..rows.len() {
        let key = |r: &BenchRow| {
            (
                r.scene.clone(),
                r.subdomains,
                r.method.clone(),
                r.path.clone(),
            )
        };
        let Some(f) = rows
            .iter()
            .find(|f| f.level == finest && key(f) == key(&rows[i]))
        else {
            continue;
        };
        let diff = rows[i]
            .computed
            .iter()
            .filter(|(k, _)| k != "load" && k != "profile_l2" && !k.contains("last"))
            .filter_map(|(k, v)| {
                f.computed
                    .iter()
                    .find(|(kf, _)| kf == k)
                    .map(|(_, vf)| ((v - vf) / vf).abs())
            })
            .fold(0.0f64, f64::max);
        rows[i].error_vs_finest = diff;
    }
    progress(total, total, "done");
    Ok(rows)
}

/// The benchmark's plots: error against run time (log-log, one line per
/// scene/method/path) and condensed against direct time against DOFs.
pub fn write_plots(
    dir: &std::path::Path,
    rows: &[BenchRow],
) -> Result<Vec<std::path::PathBuf>, String> {
    use signorini_report::plot::{loglog_svg, Series};
    let mut written = Vec::new();
    let mut keys: Vec<(String, usize, String, String)> = Vec::new();
    for r in rows {
        let k = (
            r.scene.clone(),
            r.subdomains,
            r.method.clone(),
            r.path.clone(),
        );
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let series = |y: &dyn Fn(&BenchRow) -> f64, x: &dyn Fn(&BenchRow) -> f64| -> Vec<Series> {
        keys.iter()
            .map(|k| Series {
                label: format!("{} {} {} ({} sub.)", k.0, k.2, k.3, k.1),
                points: rows
                    .iter()
                    .filter(|r| {
                        (
                            r.scene.clone(),
                            r.subdomains,
                            r.method.clone(),
                            r.path.clone(),
                        ) == *k
                    })
                    .map(|r| (x(r), y(r)))
                    .collect(),
            })
            .filter(|s| s.points.iter().any(|(x, y)| *x > 0.0 && *y > 0.0))
            .collect()
    };
    let plots = [
        (
            "error_vs_time.svg",
            "Error against run time",
            "total run time [s]",
            "max relative error vs reference",
            series(&|r| r.error, &|r| r.total_s),
        ),
        (
            "time_vs_dofs.svg",
            "Solve time against DOFs",
            "DOFs",
            "condense + contact + recover [s]",
            series(&|r| r.condense_s + r.contact_s + r.recover_s, &|r| {
                r.dofs as f64
            }),
        ),
    ];
    for (file, title, x_label, y_label, lines) in plots {
        if !lines.is_empty() {
            let p = dir.join(file);
            loglog_svg(&p, title, x_label, y_label, &lines)?;
            written.push(p);
        }
    }
    Ok(written)
}

fn row(scene: &str, level: f64, r: &signorini_report::Report) -> BenchRow {
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
    let (error, computed) = r
        .reference
        .as_ref()
        .map(|rf| {
            let e = rf
                .quantities
                .iter()
                .filter(|(k, _)| k.as_str() != "load" && !k.contains("last"))
                .fold(0.0f64, |a, (_, q)| a.max(q.relative_error));
            (
                e,
                rf.quantities
                    .iter()
                    .map(|(k, q)| (k.clone(), q.computed))
                    .collect(),
            )
        })
        .unwrap_or((f64::NAN, Vec::new()));
    BenchRow {
        scene: scene.to_string(),
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
        error,
        error_vs_finest: f64::NAN,
        computed,
    }
}

/// bench.csv: one line per run.
pub fn write_csv(path: &std::path::Path, rows: &[BenchRow]) -> std::io::Result<()> {
    signorini_report::write_lines(
        path,
        "scene,level,subdomains,method,path,dofs,interface_dofs,contact_points,iterations,converged,assemble_s,condense_s,contact_s,recover_s,total_s,peak_rss_bytes,dense_interface_bytes,error,error_vs_finest,errors",
        rows.iter().map(|r| {
            format!(
                "{},{},{},{},{},{},{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{},{},{:.4e},{:.4e},{}",
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
            r.error,
            r.error_vs_finest,
            r.errors
            )
        }),
    )
}
