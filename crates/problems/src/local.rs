//! `signorini local PROBLEM`: a stand-alone condensed contact problem (the
//! file format and its row layouts: [`crate::problem_file`]) solved by any
//! root algorithm, so that the root solvers can be compared with other
//! libraries on identical data (docs/theory/algorithms.md): an LCP by any method of the
//! registry, 2D Coulomb friction by the fixed point on the threshold
//! (course notes §4.3), the friction status method (§4.5) or the fixed point with
//! semi-smooth Newton on Coulomb's law itself, 3D Coulomb friction by the
//! fixed point with its semi-smooth Newton inner solves or the semi-smooth
//! Newton method on Coulomb's law itself.

use std::time::{Duration, Instant};

use serde::Serialize;
use signorini_contact::friction::driver;
use signorini_contact::friction::{FrictionLaw, FrictionLayout, FrictionOptions, PointStatus};
use signorini_contact::law::natural_residual;
use signorini_contact::lcp::{lcp_residual, LcpOptions};
use signorini_contact::options::default_time_limit;
use signorini_contact::registry::Algorithm;

pub use crate::fclib::{GlobalCondensation, GlobalSummary};
pub use crate::problem_file::{load, LocalProblem};

/// The friction solvers of `signorini local --friction` (fixed point,
/// status, newton).
pub use signorini_contact::friction::driver::FrictionSolver as FrictionMethod;

/// The scales of the data: gaps relative to max |q|, forces relative to
/// max |q| / max diag W.
fn scales(p: &LocalProblem) -> (f64, f64) {
    let qmax =
        p.q.iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
    let dmax = (0..p.q.len())
        .fold(0.0f64, |a, i| a.max(p.w[(i, i)].abs()))
        .max(f64::MIN_POSITIVE);
    (qmax / dmax, qmax)
}

/// The JSON line `signorini local` prints.
#[derive(Debug, Serialize)]
pub struct LocalResult {
    pub problem: String,
    pub method: String,
    /// Contact points.
    pub m: usize,
    /// Rows per contact point (1: an LCP).
    pub dim: usize,
    pub converged: bool,
    pub iterations: usize,
    pub operator_applications: usize,
    /// The solve's time (with `--repeat`, the median).
    pub time_s: f64,
    /// How many times it was solved (`--repeat`).
    pub repeats: usize,
    /// Scaled natural residual of the LCP (see the contact crate's
    /// `lcp_residual`), with friction the natural residual of the law
    /// ([`signorini_contact::law::natural_residual`]).
    pub residual: f64,
    pub active: usize,
    pub stopping_reason: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lambda: Option<Vec<f64>>,
    /// With an FCLib file's `/solution/r` (another solver's forces): the
    /// distance of ours to them, [`reference_error`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_r_error: Option<f64>,
    /// When the file's reference forces do not solve its own problem
    /// (their natural residual above 1e-6, [`reference_fields`]): what
    /// they are, e.g. "not a solution (r = 0)"; `reference_r_error` is
    /// then left out.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<String>,
    /// An FCLib global problem, condensed: its sizes and time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub global: Option<GlobalSummary>,
    /// With a global problem's `/solution/v`: the distance of the v our
    /// forces give to it ([`GlobalCondensation::reference_v_error`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_v_error: Option<f64>,
    /// With `--friction auto`: why its method was picked ([`pick_friction`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub picked: Option<String>,
    /// When the method asked for gave up and another one answered: which
    /// and why (the answer's `method` is the one that answered).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fallback: Option<Fallback>,
    /// An FCLib W (or global M) stored as one triangle of a symmetric
    /// matrix: "upper" or "lower".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stored_triangle: Option<&'static str>,
}

/// A method that gave up, and why, in the JSON line.
#[derive(Debug, Serialize)]
pub struct Fallback {
    pub from: String,
    pub reason: String,
}

/// The reference forces' fields of the JSON line for our `forces` (block
/// layout): their distance to ours ([`reference_error`]) when the file's
/// r solves its own problem (natural residual ≤ 1e-6 in the scales of
/// the data), else what they are: "not a solution (r = 0)" or "not a
/// solution (natural residual X)".
fn reference_fields(p: &LocalProblem, forces: &[f64]) -> (Option<f64>, Option<String>) {
    let Some(r) = p.reference_r.as_ref() else {
        return (None, None);
    };
    let blocks: Vec<f64> = p.file_row.iter().map(|&row| r[row]).collect();
    let residual = law_residual(p, &blocks);
    if residual <= 1e-6 {
        return (reference_error(p, forces), None);
    }
    let what = match r.iter().all(|&v| v == 0.0) {
        true => "not a solution (r = 0)".to_string(),
        false => format!("not a solution (natural residual {residual:.2e})"),
    };
    (None, Some(what))
}

/// The scaled natural residual of forces (block layout): of Coulomb's law
/// with μ, else of the LCP of the normal rows.
fn law_residual(p: &LocalProblem, forces: &[f64]) -> f64 {
    let (force_scale, gap_scale) = scales(p);
    let force = force_scale.max(signorini_contact::norms::max_abs(forces));
    match p.mu.as_ref() {
        Some(mu) => {
            let gaps = signorini_contact::lcp::gaps(&p.w, &p.q, forces);
            natural_residual(&coulomb_layout(p, mu), forces, &gaps, force, gap_scale)
        }
        None => {
            let m = p.contacts();
            let (w, q) = (p.w.submatrix(0, 0, m, m).to_owned(), &p.q[..m]);
            let opts = LcpOptions {
                tolerance: 0.0,
                max_iterations: 1,
                force_scale,
                gap_scale,
                ..Default::default()
            };
            lcp_residual(&w, q, &forces[..m], &opts)
        }
    }
}

/// The global problem's summary and v error for forces (block layout).
fn global_fields(p: &LocalProblem, forces: &[f64]) -> (Option<GlobalSummary>, Option<f64>) {
    let Some(g) = p.global.as_ref() else {
        return (None, None);
    };
    (
        Some(g.summary()),
        g.reference_v_error(&p.to_file_order(forces)),
    )
}

/// The distance of forces (block layout) to the file's reference forces r:
/// ‖λ − r‖ / max(‖r‖, 1e-12 F), 2-norms, F the force scale max |q| / max
/// diag W (a zero r, every contact open, is matched by zero forces; forces
/// 1e-12 F off it read 1).
pub fn reference_error(p: &LocalProblem, forces: &[f64]) -> Option<f64> {
    let r = p.reference_r.as_ref()?;
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    let lambda = p.to_file_order(forces);
    let diff = norm(&mut lambda.iter().zip(r).map(|(a, b)| a - b));
    let floor = (1e-12 * scales(p).0).max(f64::MIN_POSITIVE);
    Some(diff / norm(&mut r.iter().copied()).max(floor))
}

/// Whether a method's converged answer solves the LCP: its scaled natural
/// residual within 1000 times the tolerance. A method's own stop (the
/// penalty method's repeated active set) can be reached by forces that do
/// not: on an LCP with no solution the penalty method converged with a
/// residual of 1.06. The margin keeps what penalty does to a solvable
/// problem, a deviation ~1/k (1e-8 at its default stiffness).
fn solves_the_lcp(residual: f64, tolerance: f64) -> bool {
    residual <= 1e3 * tolerance
}

/// What `--friction` asks for: a method, or `auto`, the method
/// [`pick_friction`] picks for the problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionChoice {
    Auto,
    Method(FrictionMethod),
}

impl FrictionChoice {
    /// `auto` or a method's name; an error lists the valid ones.
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            "auto" => Ok(FrictionChoice::Auto),
            _ => FrictionMethod::from_name(name)
                .map(FrictionChoice::Method)
                .map_err(|e| format!("{e} or auto")),
        }
    }
}

/// Contact points up to which `auto` solves 3D Coulomb by NSGS: measured
/// (docs/performance/root-solvers.md) NSGS is the faster below (rigid
/// bodies' rank-deficient W: 0.05–0.2 s where the semi-smooth Newton
/// method needs 1–2 s or its fixed-point fallback; an elastic half-space
/// at m = 784: 0.16 s against 0.24 s), the semi-smooth Newton method above
/// (m = 2025: 1.9 s against 2.9 s).
pub const NSGS_UP_TO: usize = 1000;

/// The friction method `auto` picks for a problem and why (the JSON's
/// `picked`; docs/guide/choosing.md):
/// - W not symmetric: NSGS, which needs no symmetry;
/// - 2D: the semi-smooth Newton method on Coulomb's law (measured,
///   docs/performance/root-solvers.md: the fastest or as fast on every 2D
///   family, the layer and the half-space at 196–2025 contact points and
///   the FCLib 2D files, where the fixed point on the threshold took up to
///   twice its CPU time on the layer at m = 784 and 20× its time on the
///   half-space at m = 2025);
/// - 3D up to [`NSGS_UP_TO`] contact points: NSGS;
/// - 3D beyond: the semi-smooth Newton method on Coulomb's law.
pub fn pick_friction(p: &LocalProblem) -> (FrictionMethod, &'static str) {
    if p.asymmetry.is_some() {
        return (
            FrictionMethod::Nsgs,
            "W is not symmetric: nsgs needs no symmetry",
        );
    }
    if p.dim == 2 {
        return (
            FrictionMethod::Newton,
            "2D Coulomb: the semi-smooth Newton method",
        );
    }
    if p.contacts() <= NSGS_UP_TO {
        return (
            FrictionMethod::Nsgs,
            "3D Coulomb, up to 1000 contact points: nsgs",
        );
    }
    (
        FrictionMethod::Newton,
        "3D Coulomb, more than 1000 contact points: the semi-smooth Newton method",
    )
}

/// Refuses a nonsymmetric W for a method that needs a symmetric one (all
/// but NSGS for friction, `auto` picking it; all but Lemke's method for
/// the LCP), naming the file and the method that accepts it.
pub fn accepts(
    name: &str,
    p: &LocalProblem,
    friction: Option<FrictionChoice>,
    lcp: Option<Algorithm>,
) -> Result<(), String> {
    match (friction, lcp) {
        (Some(FrictionChoice::Auto | FrictionChoice::Method(FrictionMethod::Nsgs)), _) => Ok(()),
        (Some(FrictionChoice::Method(m)), _) => {
            p.require_symmetric(name, &format!("--friction {}", m.name()), "--friction nsgs")
        }
        (None, Some(a)) if a.name() != "lemke" => {
            p.require_symmetric(name, &format!("--method {}", a.name()), "--method lemke")
        }
        _ => Ok(()),
    }
}

/// Limits of a solve: tolerance, iterations and wall-clock seconds.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Seconds; `None`: [`default_time_limit`] of the problem's rows.
    pub time_limit: Option<f64>,
}

/// Solves a frictional local problem by `method` (see [`solve_friction_by`]),
/// within the default time limit.
pub fn solve_friction(
    name: &str,
    p: &LocalProblem,
    method: FrictionMethod,
    tolerance: f64,
    max_iterations: usize,
    with_lambda: bool,
) -> Result<LocalResult, String> {
    let limits = Limits {
        tolerance,
        max_iterations,
        time_limit: None,
    };
    solve_friction_by(name, p, FrictionChoice::Method(method), limits, with_lambda)
}

/// The layout of a contact-wise problem held in the block layout.
fn coulomb_layout(p: &LocalProblem, mu: &[f64]) -> FrictionLayout {
    let (m, d) = (p.contacts(), p.dim);
    FrictionLayout {
        tangent_rows: (0..m)
            .map(|c| (0..d - 1).map(|k| m + (d - 1) * c + k).collect())
            .collect(),
        law: mu.iter().map(|&u| FrictionLaw::coulomb(u)).collect(),
        shadow: vec![None; m],
    }
}

/// Solves a frictional local problem: 2D by the fixed point on the
/// threshold (course notes §4.3), the friction status method (§4.5), the
/// semi-smooth Newton method or NSGS; 3D by the fixed point with
/// semi-smooth Newton inner solves, the semi-smooth Newton method on
/// Coulomb's law or NSGS; `auto` as [`pick_friction`] says. A nonsymmetric
/// W is refused by the methods that need symmetry (all but NSGS).
pub fn solve_friction_by(
    name: &str,
    p: &LocalProblem,
    choice: FrictionChoice,
    limits: Limits,
    with_lambda: bool,
) -> Result<LocalResult, String> {
    let mu = p.mu.as_ref().ok_or("no mu")?;
    let (method, picked) = match choice {
        FrictionChoice::Auto => {
            let (m, why) = pick_friction(p);
            (m, Some(why.to_string()))
        }
        FrictionChoice::Method(m) => (m, None),
    };
    accepts(name, p, Some(FrictionChoice::Method(method)), None)?;
    let layout = coulomb_layout(p, mu);
    let opts = friction_options(p, &limits);
    let Some(chosen) = driver::FrictionMethod::choose(method, p.dim, &layout, false) else {
        return Err(format!("--friction {}: a 2D method", method.name()));
    };
    let statuses = (0..p.contacts())
        .map(|i| match p.q[i] <= 0.0 {
            true => PointStatus::Stick,
            false => PointStatus::Open,
        })
        .collect();
    let start = driver::FrictionStart {
        statuses,
        forces: None,
        predict: true,
        zone: true,
    };
    let mut problem = signorini_contact::DelassusProblem::from_operator(p.w.clone(), p.q.clone());
    let t = Instant::now();
    let answer = driver::solve_friction(&mut problem, &layout, chosen, start, &opts)
        .map_err(|e| e.to_string())?;
    let time_s = t.elapsed().as_secs_f64();
    let mut r = friction_result(name, p, answer, limits.tolerance, with_lambda);
    (r.time_s, r.operator_applications) = (time_s, problem.solves);
    r.picked = picked;
    Ok(r)
}

/// The options of a friction solve: the limits, the scales of the data and
/// the deadline.
fn friction_options(p: &LocalProblem, limits: &Limits) -> FrictionOptions {
    let (force_scale, gap_scale) = scales(p);
    let seconds = limits
        .time_limit
        .unwrap_or_else(|| default_time_limit(p.q.len()));
    FrictionOptions {
        max_iterations: limits.max_iterations,
        max_fixed_point: limits.max_iterations,
        tolerance: limits.tolerance,
        force_scale,
        gap_scale,
        deadline: Some(Instant::now() + Duration::from_secs_f64(seconds.min(1e9))),
    }
}

/// The JSON line of a friction answer (time and operator applications
/// left to the caller).
fn friction_result(
    name: &str,
    p: &LocalProblem,
    answer: driver::FrictionAnswer,
    tolerance: f64,
    with_lambda: bool,
) -> LocalResult {
    let (out, residual) = (answer.solution, answer.residual);
    let (global, reference_v_error) = global_fields(p, &out.forces);
    let fallback = out.friction.fallback.as_ref().map(|reason| Fallback {
        from: reason
            .split(" stopped")
            .next()
            .unwrap_or_default()
            .to_string(),
        reason: reason.clone(),
    });
    let (reference_r_error, reference) = reference_fields(p, &out.forces);
    LocalResult {
        problem: name.to_string(),
        method: out.report.method.clone(),
        m: p.contacts(),
        dim: p.dim,
        converged: out.report.converged && solves_the_lcp(residual, tolerance),
        iterations: out.report.iterations,
        operator_applications: 0,
        time_s: 0.0,
        repeats: 1,
        residual,
        active: out
            .friction
            .points
            .iter()
            .filter(|s| **s != PointStatus::Open)
            .count(),
        stopping_reason: out.report.stop.to_string(),
        lambda: with_lambda.then(|| p.to_file_order(&out.forces)),
        reference_r_error,
        reference,
        global,
        reference_v_error,
        picked: None,
        fallback,
        stored_triangle: p.stored_triangle,
    }
}

/// Solves a frictionless problem (an LCP, or the normal rows of a
/// contact-wise problem without μ: its tangential forces are zero) by
/// `algorithm`, within the default time limit.
pub fn solve(
    name: &str,
    p: &LocalProblem,
    algorithm: Algorithm,
    tolerance: f64,
    max_iterations: usize,
    with_lambda: bool,
) -> Result<LocalResult, String> {
    let limits = Limits {
        tolerance,
        max_iterations,
        time_limit: None,
    };
    solve_within(name, p, algorithm, limits, with_lambda)
}

/// [`solve`] within `limits`: every method stops at the time limit
/// (`None`: [`default_time_limit`] of the rows), not converged.
pub fn solve_within(
    name: &str,
    p: &LocalProblem,
    algorithm: Algorithm,
    limits: Limits,
    with_lambda: bool,
) -> Result<LocalResult, String> {
    let Limits {
        tolerance,
        max_iterations,
        time_limit,
    } = limits;
    let m = p.contacts();
    accepts(name, p, None, Some(algorithm))?;
    let (force_scale, gap_scale) = scales(p);
    // The normal rows of a contact-wise problem; an LCP's W as it is (a
    // copy of W took as long as a status iteration at m = 2025).
    let normal;
    let w = if p.dim == 1 {
        &p.w
    } else {
        normal = p.w.submatrix(0, 0, m, m).to_owned();
        &normal
    };
    let q = &p.q[..m];
    let seconds = time_limit.unwrap_or_else(|| default_time_limit(m));
    let t = Instant::now();
    let opts = LcpOptions {
        tolerance,
        max_iterations,
        force_scale,
        gap_scale,
        stiffness: None,
        deadline: Some(t + Duration::from_secs_f64(seconds.clamp(0.0, 1e9))),
    };
    let sol = algorithm
        .solve(w, q, None, &opts)
        .map_err(|e| e.to_string())?;
    let time_s = t.elapsed().as_secs_f64();
    let mut forces = sol.forces.clone();
    forces.resize(p.q.len(), 0.0);
    let residual = lcp_residual(w, q, &sol.forces, &opts);
    let (global, reference_v_error) = global_fields(p, &forces);
    let (reference_r_error, reference) = reference_fields(p, &forces);
    Ok(LocalResult {
        problem: name.to_string(),
        method: algorithm.name().to_string(),
        m,
        dim: p.dim,
        converged: sol.report.converged && solves_the_lcp(residual, tolerance),
        iterations: sol.report.iterations,
        operator_applications: sol.report.operator_applications,
        time_s,
        repeats: 1,
        residual,
        active: sol.forces.iter().filter(|&&l| l > 0.0).count(),
        stopping_reason: sol.report.stop.to_string(),
        lambda: with_lambda.then(|| p.to_file_order(&forces)),
        reference_r_error,
        reference,
        global,
        reference_v_error,
        picked: None,
        fallback: None,
        stored_triangle: p.stored_triangle,
    })
}

/// Runs `solve` `n` times (at least once) and returns the last result with
/// the median of the times (`--repeat N`).
pub fn repeated(
    n: usize,
    mut solve: impl FnMut() -> Result<LocalResult, String>,
) -> Result<LocalResult, String> {
    let mut times = Vec::new();
    let mut last = solve()?;
    times.push(last.time_s);
    for _ in 1..n {
        last = solve()?;
        times.push(last.time_s);
    }
    times.sort_by(f64::total_cmp);
    last.time_s = times[times.len() / 2];
    last.repeats = times.len();
    Ok(last)
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_contact::norms::{max_abs, natural_map};
    use signorini_report::budget::machine_memory;

    #[test]
    fn json_problem_solves_to_the_known_answer_with_every_method() {
        let dir = std::env::temp_dir().join(format!("signorini-local-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.json");
        // W = [[2, 1], [1, 2]], q = [-1, 1]: λ = (0.5, 0), w = (0, 1.5).
        std::fs::write(&path, r#"{"W": [[2, 1], [1, 2]], "q": [-1, 1]}"#).unwrap();
        let p = load(&path, machine_memory()).unwrap();
        for a in ["status", "lemke", "mprgp"].map(|name| Algorithm::by_name(name).unwrap()) {
            let r = solve("p", &p, a, 1e-12, 1000, true).unwrap();
            assert!(r.converged);
            let l = r.lambda.unwrap();
            assert!((l[0] - 0.5).abs() <= 1e-12 && l[1] == 0.0, "{a:?}: {l:?}");
        }
        // The penalty method's converged answer is within 1/k of it.
        let penalty = Algorithm::by_name("penalty").unwrap();
        let r = solve("p", &p, penalty, 1e-10, 1000, true).unwrap();
        assert!(r.converged && r.residual <= 1e-7, "{}", r.residual);
        // W positive semi-definite of rank 1 and no solution (found by a
        // robustness sweep): the penalty method's active set repeats, with a
        // residual of 0.095; that is not converged.
        std::fs::write(
            &path,
            r#"{"W": [[1.408652942488979, -0.7921747294545434, -0.3087110487808439], [-0.7921747294545434, 0.44549000187197535, 0.1736077668041407], [-0.3087110487808439, 0.1736077668041407, 0.0676550687289777]], "q": [0.7540333794321797, -0.6414795084271917, 1.7380087577355086]}"#,
        )
        .unwrap();
        let r = solve(
            "p",
            &load(&path, machine_memory()).unwrap(),
            penalty,
            1e-10,
            1000,
            true,
        )
        .unwrap();
        assert!(!r.converged && r.residual > 0.01, "{}", r.residual);
        // A nonsymmetric W is read as it is (it was refused on reading):
        // the status method, which needs symmetry, refuses it naming Lemke's
        // method, which solves it: λ = (0.5, 0), w = (0, 1).
        std::fs::write(&path, r#"{"W": [[2, 1], [0, 2]], "q": [-1, 1]}"#).unwrap();
        let p = load(&path, machine_memory()).unwrap();
        let status = Algorithm::by_name("status").unwrap();
        let e = solve("p", &p, status, 1e-12, 100, true).unwrap_err();
        assert!(
            e.contains("not symmetric") && e.contains("--method lemke"),
            "{e}"
        );
        let lemke = Algorithm::by_name("lemke").unwrap();
        let r = solve("p", &p, lemke, 1e-12, 100, true).unwrap();
        let l = r.lambda.unwrap();
        assert!(
            r.converged && (l[0] - 0.5).abs() <= 1e-12 && l[1] == 0.0,
            "{l:?}"
        );
        std::fs::write(&path, r#"{"W": [[2]], "q": [-1, 1]}"#).unwrap();
        assert!(load(&path, machine_memory()).unwrap_err().contains("2 × 2"));
    }

    #[test]
    fn frictional_json_problem_sticks_or_slips_like_the_hand_solution() {
        let dir = std::env::temp_dir().join(format!("signorini-localmu-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.json");
        // One point: W = diag(1/5, 1/2) (normal, tangential compliances); pressed
        // by N = 3 (q_n = −3/5) and pulled by Q = 2 (q_t = 2/2): μN = 1.5 < 2, it slips.
        std::fs::write(
            &path,
            r#"{"W": [[0.2, 0], [0, 0.5]], "q": [-0.6, 1.0], "mu": [0.5], "layout": "normal_first"}"#,
        )
        .unwrap();
        let p = load(&path, machine_memory()).unwrap();
        for method in FrictionMethod::ALL {
            let r = solve_friction("p", &p, method, 1e-12, 100, true).unwrap();
            assert!(r.converged, "{}", r.stopping_reason);
            let l = r.lambda.unwrap();
            assert!(
                (l[0] - 3.0).abs() < 1e-10 && (l[1] + 1.5).abs() < 1e-10,
                "{l:?}"
            );
        }
        // A symmetric 2D problem: `auto` picks the semi-smooth Newton method.
        assert_eq!(pick_friction(&p).0, FrictionMethod::Newton);
        std::fs::write(
            &path,
            r#"{"W": [[0.2, 0], [0, 0.5]], "q": [-0.6, 1.0], "mu": [0.5, 0.2], "layout": "normal_first"}"#,
        )
        .unwrap();
        assert!(load(&path, machine_memory())
            .unwrap_err()
            .contains("mu has 2 entries for 1 contacts"));
    }

    use crate::problem_file::npy_bytes as npy;

    /// Writes an .npz archive of the named arrays (`.npy` bytes).
    fn write_npz(
        path: &std::path::Path,
        arrays: &[(&str, &[u8])],
        o: zip::write::SimpleFileOptions,
    ) {
        use std::io::Write;
        let mut z = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
        for (name, bytes) in arrays {
            z.start_file(*name, o).unwrap();
            z.write_all(bytes).unwrap();
        }
        z.finish().unwrap();
    }

    #[test]
    fn npz_problem_in_either_order_gives_the_json_answer() {
        let dir = std::env::temp_dir().join(format!("signorini-npz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // W = [[4, 1, 0], [1, 3, 1], [0, 1, 2]] is symmetric: both orders store the same bytes,
        // so use a non-symmetric-looking layout check through q instead.
        let w = [4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0];
        let q = [-1.0, 0.5, -2.0];
        for fortran in [false, true] {
            let path = dir.join(format!("p{fortran}.npz"));
            let o = zip::write::SimpleFileOptions::default()
                .compression_method(zip::CompressionMethod::Deflated);
            let (w_npy, q_npy) = (npy(&[3, 3], fortran, &w), npy(&[3], false, &q));
            write_npz(&path, &[("W.npy", &w_npy), ("q.npy", &q_npy)], o);
            let p = load(&path, machine_memory()).unwrap();
            let r = solve(
                "p",
                &p,
                Algorithm::status(signorini_contact::StatusVariant::All),
                1e-12,
                100,
                true,
            )
            .unwrap();
            let l = r.lambda.unwrap();
            // Check the LCP directly: λ ≥ 0, w = Wλ + q ≥ 0, λ·w = 0.
            for i in 0..3 {
                let wi: f64 = q[i] + (0..3).map(|j| w[3 * i + j] * l[j]).sum::<f64>();
                assert!(
                    l[i] >= 0.0 && wi >= -1e-12 && (l[i] * wi).abs() <= 1e-12,
                    "{l:?}"
                );
            }
            assert!(l[0] > 0.0 && l[2] > 0.0);
        }
        let bad = dir.join("bad.npz");
        let q_npy = npy(&[3], false, &q);
        write_npz(&bad, &[("q.npy", &q_npy)], Default::default());
        assert!(load(&bad, machine_memory())
            .unwrap_err()
            .contains("no array named W"));
    }

    /// Shapes are the file's word: a header that lies about them (or that
    /// overflows) is an error naming the file, never an out-of-bounds read
    /// or a huge allocation.
    #[test]
    fn npz_shapes_that_lie_are_refused() {
        let dir = std::env::temp_dir().join(format!("signorini-npz-lies-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |name: &str, w: Vec<u8>, q: Vec<u8>| {
            let path = dir.join(name);
            write_npz(&path, &[("W.npy", &w), ("q.npy", &q)], Default::default());
            load(&path, machine_memory()).unwrap_err()
        };
        let q3 = npy(&[3], false, &[1.0, 2.0, 3.0]);
        // W says 3 × 3 but holds 4 numbers
        let e = write("short.npz", npy(&[3, 3], false, &[1.0; 4]), q3.clone());
        assert!(e.contains("short.npz") || e.contains("W.npy"), "{e}");
        // W is 2^32 × 2^32: its element count overflows
        let e = write("huge.npz", npy(&[1 << 32, 1 << 32], false, &[]), q3.clone());
        assert!(e.contains("huge.npz"), "{e}");
        // q's shape overflows
        let e = write(
            "qhuge.npz",
            npy(&[3, 3], false, &[1.0; 9]),
            npy(&[1 << 40, 1 << 40], false, &[]),
        );
        assert!(e.contains("qhuge.npz") || e.contains("q.npy"), "{e}");
    }

    /// W = Hᵀ M⁻¹ H of a 3 × 3 × 3 pile of rigid unit spheres (six DOFs
    /// each, inertia 0.1) on the ground: 63 contacts, 189 rows of rank 159
    /// — the Delassus operators multibody codes export (FCLib) are rank
    /// deficient, the normal forces not unique. q: gravity and a sideways
    /// push per sphere.
    fn rigid_sphere_pile() -> String {
        let k = 3usize;
        let pos: Vec<[f64; 3]> = (0..k * k * k)
            .map(|i| {
                [
                    (i % k) as f64,
                    ((i / k) % k) as f64,
                    0.5 + (i / (k * k)) as f64,
                ]
            })
            .collect();
        let mut contacts: Vec<(usize, Option<usize>, [f64; 3])> = Vec::new();
        for (i, a) in pos.iter().enumerate() {
            if a[2] < 0.6 {
                contacts.push((i, None, [0.0, 0.0, 1.0]));
            }
            for (j, b) in pos.iter().enumerate().skip(i + 1) {
                let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() < 1.01 {
                    contacts.push((i, Some(j), d));
                }
            }
        }
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let ndof = 6 * pos.len();
        // Columns of H scaled by M^{-1/2}: W = Hsᵀ Hs.
        let mut hs = Vec::new();
        for &(i, j, n) in &contacts {
            let a = if n[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let t1 = cross(n, a);
            let l1 = (t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]).sqrt();
            let t1 = t1.map(|v| v / l1);
            for e in [n, t1, cross(n, t1)] {
                let mut c = vec![0.0; ndof];
                for (body, sign) in [(Some(i), 1.0), (j, -1.0)] {
                    let Some(b) = body else { continue };
                    let arm = n.map(|v| -0.5 * sign * v);
                    let moment = cross(arm, e);
                    for d in 0..3 {
                        c[6 * b + d] += sign * e[d];
                        c[6 * b + 3 + d] += sign * moment[d] / 0.1f64.sqrt();
                    }
                }
                hs.push(c);
            }
        }
        let m = contacts.len();
        let f: Vec<f64> = (0..ndof)
            .map(|d| match d % 6 {
                2 => -0.0981,
                0 => 0.002 * ((d / 6) as f64 * 1.7).sin(),
                _ => 0.0,
            })
            .collect();
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let w: Vec<Vec<f64>> = hs
            .iter()
            .map(|a| hs.iter().map(|b| dot(a, b)).collect())
            .collect();
        // q = Hᵀ M⁻¹ f: the rotational rows of f are zero, so Hsᵀ f works.
        let q: Vec<f64> = hs.iter().map(|a| dot(a, &f)).collect();
        serde_json::json!({"W": w, "q": q, "mu": vec![0.3; m], "dim": 3}).to_string()
    }

    /// On a rank-deficient pile the semi-smooth Newton method and NSGS converge, and
    /// the fixed point either converges or stops as stalled (it wandered for
    /// hundreds of iterations, and on a larger pile broke down into NaN
    /// forces that were reported converged): never a converged answer off
    /// Coulomb's law, checked here independently of the solver's residual.
    #[test]
    fn a_rank_deficient_pile_of_rigid_spheres_is_solved_or_honestly_not() {
        let dir = std::env::temp_dir().join(format!("signorini-pile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pile.json");
        std::fs::write(&path, rigid_sphere_pile()).unwrap();
        let p = load(&path, machine_memory()).unwrap();
        let m = p.contacts();
        for method in [
            FrictionMethod::Newton,
            FrictionMethod::FixedPoint,
            FrictionMethod::Nsgs,
        ] {
            let r = solve_friction("pile", &p, method, 1e-10, 10_000, true).unwrap();
            if method != FrictionMethod::FixedPoint {
                assert!(r.converged, "{}", r.stopping_reason);
            }
            if !r.converged {
                assert!(
                    r.stopping_reason.contains("stalled"),
                    "{}",
                    r.stopping_reason
                );
                continue;
            }
            // Independent check, contact-wise rows (λ_n, λ_t1, λ_t2).
            let l = r.lambda.unwrap();
            assert!(l.iter().all(|v| v.is_finite()));
            let w = serde_json::from_str::<serde_json::Value>(&rigid_sphere_pile()).unwrap();
            let g: Vec<f64> = (0..3 * m)
                .map(|i| {
                    let row = w["W"][i].as_array().unwrap();
                    row.iter()
                        .zip(&l)
                        .map(|(a, b)| a.as_f64().unwrap() * b)
                        .sum::<f64>()
                        + w["q"][i].as_f64().unwrap()
                })
                .collect();
            let (fmax, gmax) = (max_abs(&l), max_abs(&g));
            for c in 0..m {
                let (ln, gn) = (l[3 * c], g[3 * c]);
                assert!(
                    natural_map(ln / fmax, gn / gmax) <= 1e-7,
                    "{method:?} contact {c}"
                );
                let lt = l[3 * c + 1].hypot(l[3 * c + 2]);
                assert!(
                    lt <= 0.3 * ln * (1.0 + 1e-9) + 1e-9 * fmax,
                    "{method:?} cone {c}"
                );
            }
        }
    }
}
