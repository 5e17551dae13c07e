//! `signorini bench`: a scene over refinement levels, subdomain counts and
//! paths, each run timed per phase with its errors (docs/architecture.md: speed is
//! measured here and in `cargo bench`, never in timed unit tests).

use serde::Serialize;
use signorini_comm::Local;
use signorini_scene as scene;

use signorini_solver::{check_options, run_with, RunEnvironment, RunOptions, SolveError};

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
    env: &RunEnvironment,
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
                        // The direct path ignores subdomains and runs the status
                        // method, frictionless: beside the condensed path it is
                        // left out where it cannot run the scene.
                        let skip = path == scene::SolvePath::Direct
                            && ((n > 1 && subdomains.contains(&1))
                                || method != scene::Method::Status
                                || (paths.contains(&scene::SolvePath::Condensed)
                                    && !direct_runs(&case.scene)));
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
                        // each row's peak memory its own, not the largest so far
                        signorini_report::reset_peak_rss();
                        let opts = RunOptions {
                            method: Some(method),
                            path: Some(path),
                        };
                        let out = run_with(&sc, &case.name, &opts, env, &Local)?
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

/// Whether the direct path runs the scene (not contact elements, nor the
/// friction it leaves to the condensed path: `plan` refuses those there).
fn direct_runs(sc: &scene::Scene) -> bool {
    let opts = RunOptions {
        method: Some(scene::Method::Status),
        path: Some(scene::SolvePath::Direct),
    };
    check_options(sc, &opts).is_ok()
}

/// The benchmark's plots: error against run time (log-log, one line per
/// scene/method/path) and condensed against direct time against DOFs.
pub fn write_plots(
    dir: &std::path::Path,
    rows: &[BenchRow],
) -> Result<Vec<std::path::PathBuf>, String> {
    use signorini_report::plot::{plot_svg, Axes, Series};
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
        (
            "memory_vs_dofs.svg",
            "Peak memory against DOFs",
            "DOFs",
            "peak resident set [MiB]",
            series(&|r| r.peak_rss_bytes as f64 / MIB, &|r| r.dofs as f64),
        ),
    ];
    for (file, title, x_label, y_label, lines) in plots {
        if !lines.is_empty() {
            let p = dir.join(file);
            plot_svg(&p, title, (x_label, y_label), &lines, Axes::LogLog)?;
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

/// A column of the bench table: its CSV name, its Markdown heading (`None`:
/// in the CSV only) and its cell.
type Column = (&'static str, Option<&'static str>, fn(&BenchRow) -> String);

/// The columns of bench.csv and of the printed table, in order: one list
/// for both, so that they cannot disagree.
const COLUMNS: &[Column] = &[
    ("scene", Some("scene"), |r| r.scene.clone()),
    ("level", Some("level"), |r| r.level.to_string()),
    ("subdomains", Some("subdomains"), |r| {
        r.subdomains.to_string()
    }),
    ("method", Some("method"), |r| r.method.clone()),
    ("path", Some("path"), |r| r.path.clone()),
    ("dofs", Some("DOFs"), |r| r.dofs.to_string()),
    ("interface_dofs", Some("Γ DOFs"), |r| {
        r.interface_dofs.to_string()
    }),
    ("contact_points", Some("contact pts"), |r| {
        r.contact_points.to_string()
    }),
    ("iterations", Some("iterations"), |r| {
        r.iterations.to_string()
    }),
    ("converged", Some("converged"), |r| r.converged.to_string()),
    ("assemble_s", None, |r| format!("{:.6}", r.assemble_s)),
    ("condense_s", Some("condense s"), |r| {
        format!("{:.6}", r.condense_s)
    }),
    ("contact_s", Some("root s"), |r| {
        format!("{:.6}", r.contact_s)
    }),
    ("recover_s", Some("recover s"), |r| {
        format!("{:.6}", r.recover_s)
    }),
    ("total_s", Some("total s"), |r| format!("{:.6}", r.total_s)),
    ("peak_rss_bytes", None, |r| r.peak_rss_bytes.to_string()),
    ("dense_interface_bytes", None, |r| {
        r.dense_interface_bytes.to_string()
    }),
    ("error", Some("error"), |r| format!("{:.4e}", r.error)),
    ("error_vs_finest", Some("vs finest"), |r| {
        format!("{:.4e}", r.error_vs_finest)
    }),
    ("errors", None, |r| r.errors.clone()),
];

/// Bytes per MiB.
const MIB: f64 = 1024.0 * 1024.0;

/// The rows of a bench.csv that [`write_csv`] wrote (its header names the
/// columns, in any order); a malformed file is an error naming the line and
/// the column. The computed reference quantities are not in the file.
pub fn read_csv(text: &str) -> Result<Vec<BenchRow>, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, head) = lines.next().ok_or("empty file: no header")?;
    let header: Vec<&str> = head.split(',').map(str::trim).collect();
    for c in COLUMNS {
        if !header.contains(&c.0) {
            return Err(format!("the header has no column \"{}\"", c.0));
        }
    }
    lines
        .map(|(i, line)| bench_row(&header, line, i + 1))
        .collect()
}

/// One line of bench.csv (line number `at`, for errors).
fn bench_row(header: &[&str], line: &str, at: usize) -> Result<BenchRow, String> {
    let cells: Vec<&str> = line.split(',').map(str::trim).collect();
    if cells.len() != header.len() {
        return Err(format!(
            "line {at}: {} cells where the header has {}",
            cells.len(),
            header.len()
        ));
    }
    let cell = |name: &str| cells[header.iter().position(|h| *h == name).unwrap_or(0)];
    fn parse<T: std::str::FromStr>(at: usize, name: &str, v: &str) -> Result<T, String> {
        v.parse()
            .map_err(|_| format!("line {at}, column \"{name}\": \"{v}\" is not a valid value"))
    }
    macro_rules! num {
        ($name:literal) => {
            parse(at, $name, cell($name))?
        };
    }
    // Times, errors and levels: 0 or within 1e±100 (the plots' log axes
    // cannot span more; no run measures less or more), or NaN (a scene
    // without a reference has no error; the plots leave it out).
    macro_rules! real {
        ($name:literal) => {{
            let v: f64 = parse(at, $name, cell($name))?;
            if !(v.is_nan() || v == 0.0 || (1e-100..=1e100).contains(&v.abs())) {
                return Err(format!(
                    "line {at}, column \"{}\": {v:e} is not a value a run measures (0, 1e-100 to 1e100 in magnitude, or NaN)",
                    $name
                ));
            }
            v
        }};
    }
    Ok(BenchRow {
        scene: cell("scene").to_string(),
        level: real!("level"),
        subdomains: num!("subdomains"),
        method: cell("method").to_string(),
        path: cell("path").to_string(),
        dofs: num!("dofs"),
        interface_dofs: num!("interface_dofs"),
        contact_points: num!("contact_points"),
        iterations: num!("iterations"),
        converged: num!("converged"),
        assemble_s: real!("assemble_s"),
        condense_s: real!("condense_s"),
        contact_s: real!("contact_s"),
        recover_s: real!("recover_s"),
        total_s: real!("total_s"),
        peak_rss_bytes: num!("peak_rss_bytes"),
        dense_interface_bytes: num!("dense_interface_bytes"),
        errors: cell("errors").to_string(),
        error: real!("error"),
        error_vs_finest: real!("error_vs_finest"),
        computed: Vec::new(),
    })
}

/// bench.csv: one line per run.
pub fn write_csv(path: &std::path::Path, rows: &[BenchRow]) -> std::io::Result<()> {
    let header: Vec<&str> = COLUMNS.iter().map(|c| c.0).collect();
    signorini_report::write_lines(
        path,
        &header.join(","),
        rows.iter()
            .map(|r| COLUMNS.iter().map(|c| c.2(r)).collect::<Vec<_>>().join(",")),
    )
}

/// The printed table: the Markdown columns of [`COLUMNS`].
pub fn markdown(rows: &[BenchRow]) -> String {
    let shown: Vec<&Column> = COLUMNS.iter().filter(|c| c.1.is_some()).collect();
    let line = |cells: Vec<String>| format!("| {} |\n", cells.join(" | "));
    let mut out = line(
        shown
            .iter()
            .map(|c| c.1.unwrap_or_default().to_string())
            .collect(),
    );
    out += &line(shown.iter().map(|_| "---".to_string()).collect());
    for r in rows {
        out += &line(shown.iter().map(|c| c.2(r)).collect());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CSV and the printed table come from one column list: every
    /// Markdown cell is the CSV cell of the same name.
    #[test]
    fn table_and_csv_show_the_same_cells() {
        let row = BenchRow {
            scene: "s.toml".into(),
            level: 2.0,
            subdomains: 3,
            method: "status".into(),
            path: "condensed".into(),
            dofs: 1234,
            interface_dofs: 56,
            contact_points: 7,
            iterations: 8,
            converged: true,
            assemble_s: 0.5,
            condense_s: 1.25,
            contact_s: 0.125,
            recover_s: 0.0625,
            total_s: 2.0,
            peak_rss_bytes: 99,
            dense_interface_bytes: 98,
            errors: "p0=1e-3".into(),
            error: 1e-3,
            error_vs_finest: 2e-3,
            computed: Vec::new(),
        };
        let dir = std::env::temp_dir().join(format!("bench-cells-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bench.csv");
        write_csv(&path, std::slice::from_ref(&row)).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0].len(), 20);
        let csv = |name: &str| lines[1][lines[0].iter().position(|h| *h == name).unwrap()];
        assert_eq!(csv("total_s"), "2.000000");
        assert_eq!(csv("interface_dofs"), "56");
        let table = markdown(std::slice::from_ref(&row));
        let rows: Vec<Vec<&str>> = table
            .lines()
            .map(|l| l.trim_matches('|').split('|').map(str::trim).collect())
            .collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[0].len(), 16);
        let md = |heading: &str| rows[2][rows[0].iter().position(|h| *h == heading).unwrap()];
        assert_eq!(md("total s"), csv("total_s"));
        assert_eq!(md("root s"), csv("contact_s"));
        assert_eq!(md("Γ DOFs"), "56");
        // and the CSV reads back to the same row
        let back = read_csv(&text).unwrap();
        assert_eq!(back.len(), 1);
        assert_eq!(format!("{:?}", back[0]), format!("{row:?}"));
    }

    /// Found by a fourth robustness sweep: `signorini bench` on a scene
    /// with friction the direct path cannot solve, at the default `--paths
    /// condensed,direct`, was refused as a whole (exit 1). The direct path
    /// is left out beside the condensed one, as for methods other than
    /// status; asked for alone it is still refused. Coulomb friction runs on
    /// both paths, with the same contact forces.
    #[test]
    fn the_direct_path_is_left_out_of_a_bench_of_a_scene_with_friction_it_cannot_solve() {
        let text = "dimension = 2\n[[materials]]\nname = \"m\"\nyoung = 1.0\npoisson = 0.3\n\
            [[bodies]]\nname = \"block\"\nmaterial = \"m\"\n\
            mesh = { generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }\n\
            [[bodies]]\nname = \"ground\"\nrigid = { shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }\n\
            [[boundary]]\nbody = \"block\"\nsurface = \"top\"\ndisplacement = { x = 0.01, y = -0.01 }\n\
            [[contact]]\nname = \"c\"\nslave = { body = \"block\", surface = \"bottom\" }\n\
            master = { body = \"ground\" }\nfriction = { coulomb = 0.3 }\n";
        let case = |text: &str| BenchCase {
            name: "s.toml".into(),
            scene: scene::parse_toml(text).unwrap(),
        };
        let both = [scene::SolvePath::Condensed, scene::SolvePath::Direct];
        let status = [scene::Method::Status];
        let machine = RunEnvironment::machine();
        let run = |text: &str, paths: &[scene::SolvePath]| {
            bench(
                &[case(text)],
                &[1.0],
                &[1],
                &status,
                paths,
                &machine,
                |_, _, _| {},
            )
        };
        let rows = run(text, &both).unwrap();
        let paths: Vec<&str> = rows.iter().map(|r| r.path.as_str()).collect();
        assert_eq!(paths, ["condensed", "direct"]);
        assert!(rows.iter().all(|r| r.converged));
        let norton_hoff = text.replace(
            "friction = { coulomb = 0.3 }",
            "friction = { norton_hoff = 0.3, rho = 0.2 }",
        );
        let rows = run(&norton_hoff, &both).unwrap();
        let paths: Vec<&str> = rows.iter().map(|r| r.path.as_str()).collect();
        assert_eq!(paths, ["condensed"]);
        assert!(rows[0].converged);
        let direct = [scene::SolvePath::Direct];
        match run(&norton_hoff, &direct) {
            Err(SolveError::Input(m)) => assert!(m.contains("contact \"c\".friction"), "{m}"),
            other => panic!("{:?}", other.map(|r| r.len())),
        }
        // frictionless, both paths run
        let text = text.replace("friction = { coulomb = 0.3 }\n", "");
        let text = text.replace("{ x = 0.01, y = -0.01 }", "{ x = 0.0, y = -0.01 }");
        let rows = run(&text, &both).unwrap();
        assert_eq!(rows.len(), 2);
    }

    #[test]
    fn a_malformed_bench_csv_is_refused_naming_the_line_and_column() {
        let header = COLUMNS.iter().map(|c| c.0).collect::<Vec<_>>().join(",");
        let good = "s.toml,1,1,status,direct,10,0,3,2,true,0,0,0.1,0,0.2,1000,0,1e-2,0,p0=1e-2";
        assert_eq!(read_csv(&format!("{header}\n{good}\n")).unwrap().len(), 1);
        let bad_dofs = good.replace(",10,0,3,", ",ten,0,3,");
        let e = read_csv(&format!("{header}\n{good}\n{bad_dofs}\n")).unwrap_err();
        assert!(
            e.contains("line 3") && e.contains("\"dofs\"") && e.contains("ten"),
            "{e}"
        );
        let e = read_csv(&format!("{header}\n{good},extra\n")).unwrap_err();
        assert!(e.contains("line 2") && e.contains("21 cells"), "{e}");
        let e = read_csv(&header.replace("total_s,", "")).unwrap_err();
        assert!(e.contains("\"total_s\""), "{e}");
        assert!(read_csv("").unwrap_err().contains("empty"));
        // Values no run measures (they hung the plots' log axes, or made
        // them fail as an internal error): refused, named.
        for total in ["1e308", "5e-324", "inf", "-inf"] {
            let row = good.replace(",0.2,1000,", &format!(",{total},1000,"));
            let e = read_csv(&format!("{header}\n{row}\n")).unwrap_err();
            assert!(e.contains("line 2") && e.contains("\"total_s\""), "{e}");
        }
    }
}
