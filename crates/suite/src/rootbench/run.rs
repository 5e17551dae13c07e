//! `signorini bench --suite root`: every root method on the problems of
//! [`crate::rootbench::problem::Family`] over a range of sizes, through the same solve
//! functions as `signorini local`, so that the timings are those a user of
//! `local` sees and the files exported for other libraries hold the very
//! problems timed here.

use std::path::Path;

use signorini_contact::registry::{Algorithm, METHODS};
use signorini_problems::local::{self, FrictionMethod, LocalProblem, LocalResult};

use crate::rootbench::problem::Family;

/// One run of one method on one problem.
#[derive(Debug, Clone)]
pub struct RootRow {
    pub problem: String,
    pub family: &'static str,
    pub m: usize,
    pub method: String,
    pub converged: bool,
    pub iterations: usize,
    pub time_s: f64,
    /// The scaled residual `signorini local` reports.
    pub residual: f64,
    /// Points in contact, as a fraction of all.
    pub active_fraction: f64,
    /// max |λ − λ_ref| / max |λ_ref| against the family's reference method
    /// on the same problem (the status method; the friction status method
    /// in 2D friction; 0 for the reference itself).
    pub difference: f64,
}

/// What the suite runs.
#[derive(Debug, Clone)]
pub struct SuiteOptions {
    /// Contact points of each problem (3D: rounded up to a square), up to
    /// each family's [`Family::max_size`].
    pub sizes: Vec<usize>,
    pub families: Vec<Family>,
    /// Relative tolerance of every method.
    pub tolerance: f64,
    pub max_iterations: usize,
    /// A method whose time, extrapolated from the previous size as m³
    /// (dense factorisations), would exceed this (seconds) is not run on the
    /// larger sizes of its family.
    pub time_budget: f64,
    /// Runs per (problem, method); the median time is reported.
    pub repeat: usize,
}

/// The methods of a family, the reference first.
fn methods(family: Family) -> Vec<Method> {
    match family {
        f if f.is_lcp() => METHODS
            .iter()
            .filter_map(|m| Algorithm::by_name(m.name))
            .map(Method::Lcp)
            .collect(),
        f if f.layer_dim() == 2 => vec![
            Method::Friction(FrictionMethod::Status),
            Method::Friction(FrictionMethod::FixedPoint),
            Method::Friction(FrictionMethod::Newton),
        ],
        _ => vec![
            Method::Friction(FrictionMethod::FixedPoint),
            Method::Friction(FrictionMethod::Newton),
        ],
    }
}

#[derive(Debug, Clone, Copy)]
enum Method {
    Lcp(Algorithm),
    Friction(FrictionMethod),
}

impl Method {
    fn name(self) -> String {
        match self {
            Method::Lcp(a) => a.name().to_string(),
            Method::Friction(f) => format!("friction_{}", f.name()),
        }
    }

    fn solve(self, p: &LocalProblem, o: &SuiteOptions) -> Result<LocalResult, String> {
        let (tol, it) = (o.tolerance, o.max_iterations);
        local::repeated(o.repeat, || match self {
            Method::Lcp(a) => local::solve("root", p, a, tol, it, true),
            Method::Friction(f) => local::solve_friction("root", p, f, tol, it, true),
        })
    }
}

/// max |a − b| / max |b|.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
    if scale > 0.0 {
        diff / scale
    } else {
        diff
    }
}

/// Runs the suite; `export` writes each problem as `.npz` (contact-wise)
/// for other libraries; `progress(line)` after each run.
pub fn run_suite(
    o: &SuiteOptions,
    export: Option<&Path>,
    mut progress: impl FnMut(&RootRow),
) -> Result<Vec<RootRow>, String> {
    let mut rows = Vec::new();
    for &family in &o.families {
        // The last (m, time) of each method, to skip the sizes it cannot afford.
        let mut last: Vec<(String, usize, f64)> = Vec::new();
        for &m in o.sizes.iter().filter(|&&m| m <= family.max_size()) {
            let rp = family.problem(m)?;
            if let Some(dir) = export {
                let path = dir.join(format!("{}.npz", rp.name));
                signorini_problems::problem_file::write_npz(&path, &rp.w, &rp.q, &rp.mu, rp.dim)?;
            }
            let (name, m_contacts) = (rp.name.clone(), rp.contacts());
            // W goes into the block layout by value: one copy of it at a time
            // besides the one being reordered (512 MB each at m = 8000).
            let p = LocalProblem::contact_wise(&rp.name, rp.w, rp.q, rp.mu, rp.dim)?;
            let mut reference: Option<Vec<f64>> = None;
            for method in methods(family) {
                let affordable =
                    last.iter()
                        .find(|l| l.0 == method.name())
                        .is_none_or(|&(_, m0, t0)| {
                            t0 * (m_contacts as f64 / m0 as f64).powi(3) <= o.time_budget
                        });
                if !affordable {
                    continue;
                }
                let r = method.solve(&p, o)?;
                let lambda = r.lambda.clone().unwrap_or_default();
                let reference = reference.get_or_insert_with(|| lambda.clone());
                let row = RootRow {
                    problem: name.clone(),
                    family: family.name(),
                    m: r.m,
                    method: method.name(),
                    converged: r.converged,
                    iterations: r.iterations,
                    time_s: r.time_s,
                    residual: r.residual,
                    active_fraction: r.active as f64 / r.m.max(1) as f64,
                    difference: relative_difference(&lambda, reference),
                };
                last.retain(|l| l.0 != row.method);
                last.push((row.method.clone(), row.m, row.time_s));
                progress(&row);
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// The columns of the tables: a header and each row's cells.
const COLUMNS: [&str; 10] = [
    "problem",
    "family",
    "m",
    "method",
    "converged",
    "iterations",
    "time_s",
    "residual",
    "active_fraction",
    "difference",
];

fn cells(r: &RootRow) -> [String; 10] {
    [
        r.problem.clone(),
        r.family.to_string(),
        r.m.to_string(),
        r.method.clone(),
        r.converged.to_string(),
        r.iterations.to_string(),
        format!("{:.6}", r.time_s),
        format!("{:.2e}", r.residual),
        format!("{:.3}", r.active_fraction),
        format!("{:.2e}", r.difference),
    ]
}

/// The rows as CSV.
pub fn csv(rows: &[RootRow]) -> String {
    let mut out = COLUMNS.join(",") + "\n";
    for r in rows {
        out += &(cells(r).join(",") + "\n");
    }
    out
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[RootRow]) -> String {
    let mut out = format!(
        "| {} |\n|{}\n",
        COLUMNS.join(" | "),
        "---|".repeat(COLUMNS.len())
    );
    for r in rows {
        out += &format!("| {} |\n", cells(r).join(" | "));
    }
    out
}

/// The error (residual) of each method against its time, one line per
/// family and method over the sizes, log-log.
pub fn error_vs_time_svg(path: &Path, rows: &[RootRow]) -> Result<(), String> {
    let mut series: Vec<signorini_report::plot::Series> = Vec::new();
    for r in rows {
        let label = format!("{} {}", r.family, r.method);
        let point = (r.time_s.max(1e-6), r.residual.max(1e-16));
        match series.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(point),
            None => series.push(signorini_report::plot::Series {
                label,
                points: vec![point],
            }),
        }
    }
    signorini_report::plot::plot_svg(
        path,
        "root solvers: residual against time (each line over the sizes)",
        ("time (s)", "scaled residual"),
        &series,
        signorini_report::plot::Axes::LogLog,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every method gives the reference method's forces on small problems
    /// of every family and converges: the exact ones to their tolerance
    /// (forces to 1e-8 of the largest), the penalty ones to their
    /// regularisation (1e8 times the contact stiffness: about 1e-8).
    #[test]
    fn every_method_agrees_with_the_reference_on_small_problems() {
        let o = SuiteOptions {
            sizes: vec![49, 196],
            families: Family::ALL.to_vec(),
            tolerance: 1e-10,
            max_iterations: 2000,
            time_budget: f64::INFINITY,
            repeat: 1,
        };
        let rows = run_suite(&o, None, |_| {}).unwrap();
        // 9 LCP methods on four LCP families, 3 friction methods on the
        // two 2D frictional ones and 2 on the 3D ones; twice.
        assert_eq!(rows.len(), 2 * (4 * 9 + 2 * 3 + 2 * 2));
        for r in &rows {
            let id = r.method.parse().ok();
            let exact = id
                .map(signorini_contact::registry::find)
                .is_none_or(|m| m.exact);
            let what = format!(
                "{} {}: converged {}, residual {:.1e}, difference {:.1e}",
                r.problem, r.method, r.converged, r.residual, r.difference
            );
            assert!(r.converged, "{what}");
            assert!((0.3..0.7).contains(&r.active_fraction), "{what}");
            if exact {
                assert!(r.residual <= o.tolerance && r.difference <= 1e-8, "{what}");
            } else {
                assert!(r.difference <= 1e-7, "{what}");
            }
        }
    }
}
