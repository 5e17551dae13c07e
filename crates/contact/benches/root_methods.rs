//! `cargo bench -p signorini-contact --bench root_methods`: the root
//! algorithms of [`signorini_contact::registry`] on LCP(W, q) at
//! 50, 200, 800 and 2000 contact points.
//!
//! The problems look like real Delassus operators: the m contact points are
//! the bottom row of an m × h grid graph Laplacian K (5-point stencil, the
//! row above the top one fixed, so K is SPD; h = clamp(m/4, 8, 20)), and
//! W = (K⁻¹)_{bottom,bottom} = B K⁻¹ Bᵀ with B the selection of the bottom
//! row, computed by a faer sparse Cholesky solve with the m unit vectors.
//! q is a Hertz-like gap profile q_p = (x_p² − c)/(1 − c) on x ∈ [−1, 1]
//! (max |q| = 1), with c chosen so that 20–40 % of the points are active.
//!
//! Each problem is built once (a static cache, outside the timed part), and
//! at that point every benched method is solved once and its λ checked
//! against the status method to 1e-6 relative (max norm): a bench that
//! measures a wrong answer is useless. The active fraction and the time of
//! that single solve are printed once per size (stderr).

use std::sync::OnceLock;
use std::time::Instant;

use divan::Bencher;
use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use signorini_contact::registry::{Algorithm, Constraints, MethodId, METHODS};
use signorini_contact::StatusVariant;
use signorini_contact::{lcp_residual, LcpOptions};

const SIZES: [usize; 4] = [50, 200, 800, 2000];

/// Offset c of the gap profile: the initially penetrating zone is
/// |x| < √c (≈ 39 % of the points); the elastic coupling through W shrinks
/// the contact zone to 24–38 % of the points (printed per size).
const GAP_OFFSET: f64 = 0.15;

/// Relative agreement (max norm) with the status method required of every method.
const AGREEMENT: f64 = 1e-6;

fn main() {
    // Build (and check) every problem before divan prints its table, so that
    // the summary per size is not interleaved with it; `--list` needs none.
    if !std::env::args().any(|a| a == "--list") {
        for m in SIZES {
            problem(m);
        }
    }
    divan::main();
}

fn options() -> LcpOptions {
    LcpOptions {
        tolerance: 1e-10,
        max_iterations: 100_000,
        // q is normalised to max |q| = 1 and W = O(1), so the forces are O(1).
        force_scale: 1.0,
        gap_scale: 1.0,
        stiffness: None,
        deadline: None,
    }
}

/// The registry's method `id`, with multipliers, every status changing at once.
fn algorithm(id: MethodId) -> Algorithm {
    Algorithm::of(id, Constraints::Multipliers, StatusVariant::All)
}

struct Problem {
    w: Mat<f64>,
    q: Vec<f64>,
}

/// W = (K⁻¹)_{bottom,bottom} for the m × h grid Laplacian described in the
/// module documentation. Node (i, j), i = 0..m along the contact, j = 0..h
/// upwards, has index j·m + i, so the contact row is 0..m.
fn delassus(m: usize) -> Mat<f64> {
    let h = (m / 4).clamp(8, 20);
    let n = m * h;
    let idx = |i: usize, j: usize| j * m + i;
    let mut t = Vec::with_capacity(5 * n);
    for j in 0..h {
        for i in 0..m {
            let p = idx(i, j);
            // The neighbour above always exists (row h is the fixed one).
            let mut diag = 1.0;
            let mut free = Vec::with_capacity(4);
            if j + 1 < h {
                free.push(idx(i, j + 1));
            }
            if j > 0 {
                diag += 1.0;
                free.push(idx(i, j - 1));
            }
            if i > 0 {
                diag += 1.0;
                free.push(idx(i - 1, j));
            }
            if i + 1 < m {
                diag += 1.0;
                free.push(idx(i + 1, j));
            }
            t.push(Triplet::new(p, p, diag));
            t.extend(free.into_iter().map(|r| Triplet::new(r, p, -1.0)));
        }
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).expect("grid Laplacian");
    let llt = k
        .sp_cholesky(Side::Lower)
        .expect("the grid Laplacian is SPD");
    let mut w = Mat::<f64>::zeros(m, m);
    // Unit right-hand sides in chunks, to keep the dense n × chunk block small.
    const CHUNK: usize = 250;
    for c0 in (0..m).step_by(CHUNK) {
        let nc = CHUNK.min(m - c0);
        let mut x = Mat::<f64>::zeros(n, nc);
        for c in 0..nc {
            x[(c0 + c, c)] = 1.0;
        }
        llt.solve_in_place(x.as_mut());
        for c in 0..nc {
            for r in 0..m {
                w[(r, c0 + c)] = x[(r, c)];
            }
        }
    }
    for j in 0..m {
        for i in j + 1..m {
            let v = 0.5 * (w[(i, j)] + w[(j, i)]);
            w[(i, j)] = v;
            w[(j, i)] = v;
        }
    }
    w
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

fn build(m: usize) -> Problem {
    let t0 = Instant::now();
    let w = delassus(m);
    let t_w = t0.elapsed();
    let q: Vec<f64> = (0..m)
        .map(|p| {
            let x = -1.0 + 2.0 * p as f64 / (m - 1) as f64;
            (x * x - GAP_OFFSET) / (1.0 - GAP_OFFSET)
        })
        .collect();
    let opts = options();
    let mut reference: Option<Vec<f64>> = None;
    let mut line = String::new();
    // Every method of the registry but status_penalty, the status method
    // first: it is the reference. All of them take < 5 s per solve up to
    // m = 2000 (Lemke, the slowest, ≈ 4.6 s on 2 cores), so none is skipped
    // at the large sizes; the penalty method (k = 1e8 / mean diag W) is
    // within the 1e-6 agreement too (rel. diff printed).
    let ids = METHODS
        .iter()
        .map(|m| m.id)
        .filter(|&id| id != MethodId::StatusPenalty);
    for alg in ids.map(algorithm) {
        let t = Instant::now();
        let sol = alg
            .solve(&w, &q, None, &opts)
            .unwrap_or_else(|e| panic!("{} at m = {m}: {e}", alg.name()));
        let dt = t.elapsed();
        assert!(
            sol.report.converged,
            "{} at m = {m} did not converge: {}",
            alg.name(),
            sol.report.stop
        );
        let rel = match &reference {
            None => {
                // The reference itself must solve the LCP.
                let res = lcp_residual(&w, &q, &sol.forces, &opts);
                assert!(res <= 1e-8, "status at m = {m}: natural residual {res:.3e}");
                let active = sol.forces.iter().filter(|&&l| l > 0.0).count();
                line += &format!(
                    "m = {m}: grid {m} x {}, W built in {:.2} s, active fraction {:.1} % ({active}/{m}), max λ {:.3e}; single solve, λ vs status:",
                    (m / 4).clamp(8, 20),
                    t_w.as_secs_f64(),
                    100.0 * active as f64 / m as f64,
                    max_abs(&sol.forces),
                );
                reference = Some(sol.forces);
                0.0
            }
            Some(r) => {
                let diff = r
                    .iter()
                    .zip(&sol.forces)
                    .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
                let rel = diff / max_abs(r);
                assert!(
                    rel <= AGREEMENT,
                    "{} at m = {m}: λ differs from the status method by {rel:.3e} (relative, max norm)",
                    alg.name()
                );
                rel
            }
        };
        line += &format!(
            "\n    {:<30} {:>9.4} s   rel. diff {rel:.1e}",
            alg.name(),
            dt.as_secs_f64()
        );
    }
    eprintln!("{line}");
    Problem { w, q }
}

fn problem(m: usize) -> &'static Problem {
    static CACHE: [OnceLock<Problem>; 4] = [const { OnceLock::new() }; 4];
    let k = SIZES.iter().position(|&s| s == m).expect("a benched size");
    CACHE[k].get_or_init(|| build(m))
}

fn run(bencher: Bencher, name: &str, m: usize) {
    let p = problem(m);
    let opts = options();
    let id = name.parse().unwrap_or_else(|e| panic!("{e}"));
    let alg = algorithm(id);
    bencher.bench(|| {
        alg.solve(&p.w, &p.q, None, &opts)
            .expect("solved in the setup")
    });
}

/// One divan benchmark a method, named after it, each over `SIZES`.
macro_rules! method_benches {
    ($($name:ident)*) => {
        $(
            #[divan::bench(args = SIZES, sample_count = 10, sample_size = 1)]
            fn $name(bencher: Bencher, m: usize) {
                run(bencher, stringify!($name), m);
            }
        )*
    };
}

method_benches! {
    status
    lemke
    projected_gradient
    projected_conjugate_gradient
    mprgp
    uzawa
    augmented_lagrangian
    penalty
}
