//! `signorini local` on FCLib local and global problems (HDF5): the files
//! of tests/data/fclib were written by the FCLib C library
//! (make_fclib.c: fclib_write_local, fclib_write_global,
//! fclib_write_solution) and solved by Siconos (make_fclib.py: fc2d / fc3d
//! NSGS to 1e-14; the global ones condensed by NumPy, and in 3D without
//! equality constraints also gfc3d), whose forces are the files' /solution/r (and velocities
//! /solution/v). Both friction solvers must find Siconos' forces, the
//! same problem as .npz and JSON must give the same forces, and whatever
//! `local` cannot solve is refused (exit 1, naming the file and the
//! dataset, nothing on stdout).

use crate::common;

use common::{max_rel, run_limited, BIN};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fclib")
        .join(name)
}

/// `signorini local ARGS...` within 60 s.
fn local<S: AsRef<OsStr>>(args: &[S]) -> Output {
    let mut cmd = Command::new(BIN);
    cmd.arg("local").args(args);
    let (out, elapsed) = run_limited(cmd, Duration::from_secs(60));
    assert!(elapsed < Duration::from_secs(30), "{elapsed:?}");
    out
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The JSON line of a solve that must succeed.
fn solved<S: AsRef<OsStr>>(args: &[S]) -> serde_json::Value {
    let out = local(args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The JSON line of `signorini local rigid_spheres.hdf5 ARGS...`, which
/// must stop unconverged (exit 2).
fn stopped_on_spheres(args: &[&str]) -> serde_json::Value {
    let mut all = vec![data("rigid_spheres.hdf5").into_os_string()];
    all.extend(args.iter().map(|a| a.into()));
    let out = local(&all);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[derive(Debug, PartialEq, Clone, Copy)]
enum Status {
    Open,
    Stick,
    Slip,
}
use Status::*;

/// Siconos' forces for the two problems (they are the manufactured ones of
/// make_fclib.c to 1e-15), μ and the status of each contact.
fn reference(dim: usize) -> (Vec<f64>, Vec<f64>, Vec<Status>) {
    if dim == 2 {
        (
            vec![1.0, 0.2, 1.5, 0.45, 0.0, 0.0, 2.5, 1.5, 3.0, 0.24],
            vec![0.5, 0.3, 0.4, 0.6, 0.2],
            vec![Stick, Slip, Open, Slip, Stick],
        )
    } else {
        (
            vec![
                1.0, 0.16, -0.12, 1.5, -0.36, 0.27, 0.0, 0.0, 0.0, 2.5, -1.2, 0.9,
            ],
            vec![0.5, 0.3, 0.4, 0.6],
            vec![Stick, Slip, Open, Slip],
        )
    }
}

/// The status of each contact of forces λ (contact-wise rows).
fn statuses(lambda: &[f64], mu: &[f64], dim: usize) -> Vec<Status> {
    lambda
        .chunks(dim)
        .zip(mu)
        .map(|(c, &mu)| {
            let t = c[1..].iter().map(|v| v * v).sum::<f64>().sqrt();
            if c[0] <= 1e-12 {
                Open
            } else if t >= mu * c[0] * (1.0 - 1e-8) {
                Slip
            } else {
                Stick
            }
        })
        .collect()
}

#[test]
fn fclib_problems_are_solved_to_siconos_forces_by_both_friction_solvers() {
    for (name, dim) in [
        ("fc2d_triplet.hdf5", 2),
        ("fc3d_csc.hdf5", 3),
        ("fc3d_csr.hdf5", 3),
        ("fc3d_csc_latest.hdf5", 3),
    ] {
        let (r, mu, expected) = reference(dim);
        for friction in ["fixed_point", "newton"] {
            let path = data(name);
            let v = solved(&[
                path.as_os_str(),
                "--friction".as_ref(),
                friction.as_ref(),
                "--lambda".as_ref(),
            ]);
            let what = format!("{name}, {friction}: {v}");
            assert_eq!(v["converged"], true, "{what}");
            assert_eq!(v["dim"].as_u64(), Some(dim as u64), "{what}");
            assert_eq!(v["m"].as_u64(), Some(mu.len() as u64), "{what}");
            // The default tolerance is 1e-10: the residual is within it,
            // and the forces within 100 times it of Siconos'.
            assert!(v["residual"].as_f64().unwrap() <= 1e-10, "{what}");
            let lambda = numbers(&v["lambda"]);
            assert!(max_rel(&lambda, &r) <= 1e-8, "{what}");
            assert_eq!(statuses(&lambda, &mu, dim), expected, "{what}");
            // reference_r_error is ‖λ − r‖ / ‖r‖ with the file's r.
            let e = v["reference_r_error"].as_f64().unwrap();
            let diff: f64 = lambda.iter().zip(&r).map(|(a, b)| (a - b).powi(2)).sum();
            let norm: f64 = r.iter().map(|b| b * b).sum();
            assert!(e <= 1e-8, "{what}");
            assert!((e - (diff / norm).sqrt()).abs() <= 1e-13, "{what}");
        }
    }
}

/// W in the file's row order (the problem is held in the block layout).
fn file_order_w(p: &signorini_problems::problem_file::LocalProblem) -> faer::Mat<f64> {
    let n = p.q.len();
    let mut w = faer::Mat::<f64>::zeros(n, n);
    for (i, &ri) in p.file_row.iter().enumerate() {
        for (j, &rj) in p.file_row.iter().enumerate() {
            w[(ri, rj)] = p.w[(i, j)];
        }
    }
    w
}

#[test]
fn the_same_problem_as_npz_or_json_gives_the_same_forces() {
    let dir = common::fresh_dir("fclib", "npz_json");
    for (name, friction) in [
        ("fc2d_triplet.hdf5", "fixed_point"),
        ("fc2d_triplet.hdf5", "newton"),
        ("fc3d_csc.hdf5", "fixed_point"),
        ("fc3d_csc.hdf5", "newton"),
    ] {
        let p = signorini_problems::problem_file::load(
            &data(name),
            signorini_report::budget::machine_memory(),
        )
        .unwrap();
        let (w, q, mu) = (
            file_order_w(&p),
            p.to_file_order(&p.q),
            p.mu.clone().unwrap(),
        );
        let npz = dir.join(name.replace(".hdf5", ".npz"));
        signorini_problems::problem_file::write_npz(&npz, &w, &q, &mu, p.dim).unwrap();
        let rows: Vec<Vec<f64>> = (0..q.len())
            .map(|i| (0..q.len()).map(|j| w[(i, j)]).collect())
            .collect();
        let json = dir.join(name.replace(".hdf5", ".json"));
        let text = serde_json::json!({"W": rows, "q": q, "mu": mu, "dim": p.dim});
        std::fs::write(&json, text.to_string()).unwrap();
        let lambda = |path: &Path| {
            let v = solved(&[
                path.as_os_str(),
                "--friction".as_ref(),
                friction.as_ref(),
                "--lambda".as_ref(),
            ]);
            (numbers(&v["lambda"]), v)
        };
        let (from_hdf5, v) = lambda(&data(name));
        for other in [&npz, &json] {
            let (forces, w) = lambda(other);
            assert!(max_rel(&forces, &from_hdf5) <= 1e-14, "{name}: {v}\n{w}");
            // Only the FCLib file carries another solver's forces.
            assert!(w.get("reference_r_error").is_none(), "{w}");
        }
        assert!(v["reference_r_error"].as_f64().unwrap() <= 1e-8, "{v}");
    }
}

/// Exit 1, a short message naming the file and every needle, no panic,
/// nothing on stdout.
fn assert_refused(path: &Path, extra: &[&str], needles: &[&str]) {
    let mut args: Vec<&OsStr> = vec![path.as_os_str()];
    args.extend(extra.iter().map(OsStr::new));
    let out = local(&args);
    let err = stderr(&out);
    let name = path.file_name().unwrap().to_string_lossy();
    assert_eq!(out.status.code(), Some(1), "{name}: {err}");
    assert!(out.stdout.is_empty(), "{name}: wrote {:?}", out.stdout);
    assert!(err.contains(&*name), "{name}: {err}");
    for n in needles {
        assert!(err.contains(n), "{name}: no {n:?} in: {err}");
    }
    assert!(
        err.lines().count() == 1 && err.len() < 600 && !err.contains("panicked"),
        "{name}: {err}"
    );
}

#[test]
fn what_local_cannot_solve_is_refused_naming_the_dataset() {
    let cases: &[(&str, &[&str])] = &[
        (
            "bad_global_g_dependent.hdf5",
            &["column 1 of /fclib_global/G depends on the columns before it"],
        ),
        (
            "bad_global_g_rows.hdf5",
            &["/fclib_global/G is 14 × 2", "/fclib_global/M is 15 × 15"],
        ),
        (
            "bad_global_b_length.hdf5",
            &["/fclib_global/vectors/b has 3 entries", "G^T has 2 rows"],
        ),
        (
            "bad_global_no_b.hdf5",
            &["no dataset /fclib_global/vectors/b"],
        ),
        (
            "bad_global_indefinite.hdf5",
            &["/fclib_global/M is not positive definite", "row 0"],
        ),
        (
            "bad_global_asymmetric.hdf5",
            &["/fclib_global/M is not symmetric", "M[1][0] = 7"],
        ),
        (
            "bad_global_h_rows.hdf5",
            &["/fclib_global/H is 12 × 12", "/fclib_global/M is 15 × 15"],
        ),
        (
            "bad_global_h_index.hdf5",
            &["/fclib_global/H/i[3] = 99 is out of range", "0 to 14"],
        ),
        (
            "bad_global_m_index.hdf5",
            &["/fclib_global/M/p[4] = 15 is out of range", "0 to 14"],
        ),
        (
            "bad_global_f_length.hdf5",
            &["/fclib_global/vectors/f has 14 entries", "15 rows"],
        ),
        (
            "bad_global_w_nan.hdf5",
            &["/fclib_global/vectors/w[2] is not finite"],
        ),
        ("bad_global_no_h.hdf5", &["no dataset /fclib_global/H/m"]),
        (
            "bad_global_spacedim.hdf5",
            &["/fclib_global/spacedim is 4", "2 or 3"],
        ),
        // M and H of 2·10⁹ rows: refused from f's length before anything of
        // that size is allocated.
        (
            "bad_global_huge.hdf5",
            &["/fclib_global/vectors/f has 15 entries", "2000000000 rows"],
        ),
        ("mixed.hdf5", &["mixed", "/fclib_local/R"]),
        (
            "bad_spacedim.hdf5",
            &["/fclib_local/spacedim is 4", "2 or 3"],
        ),
        ("bad_rows.hdf5", &["multiple of 3 rows, have 10"]),
        ("bad_mu_length.hdf5", &["mu has 4 entries for 5 contacts"]),
        ("bad_mu_negative.hdf5", &["mu[2]", ">= 0"]),
        ("bad_w_nan.hdf5", &["/fclib_local/W/x[3] is not finite"]),
        ("bad_q_inf.hdf5", &["/fclib_local", "q[1] is not finite"]),
        (
            "bad_q_length.hdf5",
            &["/fclib_local/vectors/q has 9 entries", "12 rows"],
        ),
        ("bad_no_q.hdf5", &["no dataset /fclib_local/vectors/q"]),
        (
            "bad_row_index.hdf5",
            &["/fclib_local/W/i[5] = 10 is out of range", "0 to 9"],
        ),
        (
            "bad_column_index.hdf5",
            &["/fclib_local/W/p[7] = -1 is out of range"],
        ),
        (
            "bad_csc_index.hdf5",
            &["/fclib_local/W/i[4] = 12 is out of range"],
        ),
        (
            "bad_csc_pointers.hdf5",
            &["/fclib_local/W/p[3] = 40", "never decrease"],
        ),
        (
            "bad_csr_pointers.hdf5",
            &["/fclib_local/W/p[12] = 1000", "hold 90 entries"],
        ),
        (
            "bad_short_x.hdf5",
            &["/fclib_local/W/x has 20 entries", "nz says 62"],
        ),
        (
            "bad_not_square.hdf5",
            &["/fclib_local/W is 10 × 12", "square"],
        ),
        (
            "bad_storage.hdf5",
            &["/fclib_local/W/nz is -3", "-1 (compressed columns)"],
        ),
    ];
    for (name, needles) in cases {
        assert_refused(&data(name), &[], needles);
    }
    // A nonsymmetric W is refused by the methods that need symmetry, naming
    // the one that does not (the default, auto, solves it by NSGS:
    // nonsymmetric_w_is_solved_by_nsgs_and_refused_by_the_others).
    for friction in ["newton", "fixed_point"] {
        let needles = ["not symmetric", "W[0][1]", "--friction nsgs"];
        assert_refused(
            &data("bad_asymmetric.hdf5"),
            &["--friction", friction],
            &needles,
        );
    }
}

/// A W declared 2·10⁹ × 2·10⁹ (dense: 32 EB) is refused from its size
/// before anything of that size is allocated; --max-memory sets the budget.
#[test]
fn a_w_past_the_memory_budget_is_refused_before_it_is_allocated() {
    assert_refused(
        &data("bad_huge.hdf5"),
        &["--max-memory", "1G"],
        &[
            "/fclib_local/W is 2000000000 × 2000000000",
            "more than the 1.0 GiB --max-memory",
        ],
    );
    assert_refused(
        &data("fc3d_csc.hdf5"),
        &["--max-memory", "1K"],
        &["/fclib_local/W is 12 × 12", "--max-memory"],
    );
    assert_refused(
        &data("global3d.hdf5"),
        &["--max-memory", "1K"],
        &[
            "/fclib_global/H is 15 × 12",
            "W = H^T M^-1 H is 12 × 12",
            "--max-memory",
        ],
    );
}

/// make_fclib.c's manufactured velocities of the global problems,
/// v_i = 0.3 sin(1.7 i + 0.37·25 + 0.55 i + 0.5) (Siconos' to 7e-14).
fn reference_v(dim: usize) -> Vec<f64> {
    let n = if dim == 2 { 12 } else { 15 };
    (0..n)
        .map(|i| {
            let i = i as f64;
            0.3 * (1.7 * i + 0.37 * 25.0 + 0.11 * i * 5.0 + 0.5).sin()
        })
        .collect()
}

/// The global problems (FCLib's fclib_write_global: a chain of springs and
/// masses, M n × n sparse SPD, H n × m; global3d_g.hdf5 also with two
/// equality constraints G, b), condensed and solved: Siconos' forces (its
/// fc2d/fc3d NSGS on NumPy's condensation and, in 3D without G, its global
/// gfc3d Newton solver, agreeing to 4e-15) and velocities — with G, the
/// manufactured ones, which satisfy Gᵀ v + b = 0 (ignoring G moves the
/// forces: f holds −G λ).
#[test]
fn global_problems_are_condensed_and_solved_to_siconos_forces_and_velocities() {
    let problems = [
        ("global2d.hdf5", 2, 12, 64, 0),
        ("global3d.hdf5", 3, 15, 117, 0),
        ("global3d_g.hdf5", 3, 15, 117, 2),
    ];
    for (name, dim, n, nnz_m, constraints) in problems {
        let (r, mu, expected) = reference(dim);
        for friction in ["fixed_point", "newton"] {
            let v = solved(&[
                data(name).as_os_str(),
                "--friction".as_ref(),
                friction.as_ref(),
                "--lambda".as_ref(),
            ]);
            let what = format!("{name}, {friction}: {v}");
            assert_eq!(v["converged"], true, "{what}");
            assert_eq!(v["m"].as_u64(), Some(mu.len() as u64), "{what}");
            assert!(v["residual"].as_f64().unwrap() <= 1e-10, "{what}");
            // Forces within 100 times the tolerance of Siconos', relative
            // to the largest (the force scale of the problem).
            let lambda = numbers(&v["lambda"]);
            assert!(max_rel(&lambda, &r) <= 1e-8, "{what}");
            assert_eq!(statuses(&lambda, &mu, dim), expected, "{what}");
            assert!(v["reference_r_error"].as_f64().unwrap() <= 1e-8, "{what}");
            // v = M⁻¹ (H λ + f) against Siconos' /solution/v.
            assert!(v["reference_v_error"].as_f64().unwrap() <= 1e-8, "{what}");
            let g = &v["global"];
            assert_eq!(g["n"].as_u64(), Some(n), "{what}");
            assert_eq!(g["nnz_M"].as_u64(), Some(nnz_m), "{what}");
            assert_eq!(g["constraints"].as_u64(), Some(constraints), "{what}");
            assert!(g["condense_s"].as_f64().unwrap() >= 0.0, "{what}");
        }
        let p = signorini_problems::problem_file::load(
            &data(name),
            signorini_report::budget::machine_memory(),
        )
        .unwrap();
        let vref = reference_v(dim);
        let g = p.global.as_ref().unwrap();
        assert!(max_rel(&g.velocity(&r), &vref) <= 1e-12, "{name}");
    }
}

/// The condensed W and q equal NumPy's (dense solves of the same file,
/// make_fclib.py: NAME_condensed.npz) to 1e-12 relative, and the two
/// problems give the same forces.
#[test]
fn global_condensation_equals_numpys() {
    for name in ["global2d", "global3d", "global3d_g"] {
        let ours = signorini_problems::problem_file::load(
            &data(&format!("{name}.hdf5")),
            signorini_report::budget::machine_memory(),
        )
        .unwrap();
        let npz = data(&format!("{name}_condensed.npz"));
        let numpy = signorini_problems::problem_file::load(
            &npz,
            signorini_report::budget::machine_memory(),
        )
        .unwrap();
        assert_eq!(ours.file_row, numpy.file_row, "{name}");
        let dw = (&ours.w - &numpy.w).norm_max();
        assert!(dw <= 1e-12 * numpy.w.norm_max(), "{name}: {dw:e}");
        assert!(max_rel(&ours.q, &numpy.q) <= 1e-12, "{name}");
        let lambda =
            |path: &Path| numbers(&solved(&[path.as_os_str(), "--lambda".as_ref()])["lambda"]);
        let (a, b) = (lambda(&data(&format!("{name}.hdf5"))), lambda(&npz));
        assert!(max_rel(&a, &b) <= 1e-10, "{name}");
    }
}

#[test]
fn damaged_files_and_other_formats_are_refused_and_extensions_are_read_in_any_case() {
    let dir = common::fresh_dir("fclib", "damaged");
    let good = std::fs::read(data("fc3d_csc.hdf5")).unwrap();
    // Truncated: in the superblock, in the groups, in the data.
    for cut in [0, 40, 800, 4000, 9000, good.len() - 100] {
        let path = dir.join(format!("cut{cut}.hdf5"));
        std::fs::write(&path, &good[..cut]).unwrap();
        assert_refused(&path, &[], &[]);
    }
    let text = dir.join("text.h5");
    std::fs::write(&text, "{\"W\": [[1]], \"q\": [-1]}").unwrap();
    assert_refused(&text, &[], &["not an HDF5 file"]);
    let folder = dir.join("folder.hdf5");
    std::fs::create_dir_all(&folder).unwrap();
    assert_refused(&folder, &[], &["not a regular file"]);
    assert_refused(&dir.join("absent.hdf5"), &[], &["cannot read"]);
    // .H5 and .HDF5 are FCLib files too, as .NPZ is a .npz.
    for upper in ["P.H5", "P.HDF5"] {
        let path = dir.join(upper);
        std::fs::write(&path, &good).unwrap();
        let v = solved(&[path.as_os_str()]);
        assert!(v["reference_r_error"].as_f64().unwrap() <= 1e-8, "{v}");
    }
}

/// The natural map of Coulomb's law at forces λ of a contact-wise 3D problem
/// (W, q in the file's order), computed here: max over the contacts of
/// |min(λ_n/F, u_n/G)| and |λ_t − proj_{μλ_n}(λ_t − (F/G) u_t)| / F, with
/// u = W λ + q, F = max |λ|, G = max |q|.
fn coulomb_residual(w: &faer::Mat<f64>, q: &[f64], mu: &[f64], lambda: &[f64]) -> f64 {
    let n = q.len();
    let u: Vec<f64> = (0..n)
        .map(|i| q[i] + (0..n).map(|j| w[(i, j)] * lambda[j]).sum::<f64>())
        .collect();
    let f = lambda.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let g = q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut worst = 0.0f64;
    for (c, &mu) in mu.iter().enumerate() {
        let (r, v) = (&lambda[3 * c..3 * c + 3], &u[3 * c..3 * c + 3]);
        worst = worst.max((r[0] / f).min(v[0] / g).abs());
        let trial = [r[1] - f / g * v[1], r[2] - f / g * v[2]];
        let norm = trial[0].hypot(trial[1]);
        let radius = mu * r[0].max(0.0);
        let s = if norm > radius { radius / norm } else { 1.0 };
        worst = worst.max((r[1] - s * trial[0]).abs().max((r[2] - s * trial[1]).abs()) / f);
    }
    worst
}

/// The problems multibody codes write (make_rigid.py): rigid boxes and
/// spheres (W rank deficient: 96 of 192 rows, 285 of 360), the spheres' W
/// stored as its upper triangle, a W nonsymmetric by 2e-3, a global
/// problem whose M is stored as its upper triangle. Each is solved from the
/// file as written by the default method (auto), exit 0, to a natural-map
/// residual ≤ 1e-8 computed here.
#[test]
fn multibody_problems_are_solved_as_written() {
    let cases = [
        ("rigid_boxes.hdf5", None, "coulomb_3d_nsgs"),
        ("rigid_spheres.hdf5", Some("upper"), "coulomb_3d_nsgs"),
        ("rigid_spheres_asymmetric.hdf5", None, "coulomb_3d_nsgs"),
        ("fe_block_upper.hdf5", Some("upper"), "coulomb_3d_nsgs"),
    ];
    for (name, triangle, method) in cases {
        let v = solved(&[data(name).as_os_str(), "--lambda".as_ref()]);
        let what = format!("{name}: {v}");
        assert_eq!(v["converged"], true, "{what}");
        assert_eq!(v["method"], method, "{what}");
        assert!(v["picked"].as_str().is_some(), "{what}");
        assert_eq!(v["stored_triangle"].as_str(), triangle, "{what}");
        let p = signorini_problems::problem_file::load(
            &data(name),
            signorini_report::budget::machine_memory(),
        )
        .unwrap();
        let (w, q) = (file_order_w(&p), p.to_file_order(&p.q));
        let res = coulomb_residual(&w, &q, p.mu.as_ref().unwrap(), &numbers(&v["lambda"]));
        assert!(res <= 1e-8, "{what}: residual {res:e}");
    }
    // The triangle is the symmetric W: the same forces as the full one
    // written by NumPy from the same numbers.
    let p = signorini_problems::problem_file::load(
        &data("rigid_spheres.hdf5"),
        signorini_report::budget::machine_memory(),
    )
    .unwrap();
    assert!(p.asymmetry.is_none());
}

/// The semi-smooth Newton method on the rank-deficient spheres converges
/// itself (no fallback); cut short, it falls back to the fixed point and
/// the JSON line says from which method and why, exit 2.
#[test]
fn newton_solves_rank_deficient_problems_and_says_when_it_falls_back() {
    let v = solved(&[
        data("rigid_spheres.hdf5").as_os_str(),
        "--friction".as_ref(),
        "newton".as_ref(),
    ]);
    assert_eq!(v["method"], "coulomb_3d_semismooth_newton", "{v}");
    assert!(v.get("fallback").is_none(), "{v}");
    let v = stopped_on_spheres(&["--friction", "newton", "--max-iterations", "2"]);
    assert_eq!(v["method"], "coulomb_3d_fixed_point", "{v}");
    assert_eq!(v["fallback"]["from"], "coulomb_3d_semismooth_newton", "{v}");
    assert!(
        v["fallback"]["reason"]
            .as_str()
            .unwrap()
            .contains("stopped"),
        "{v}"
    );
}

/// --time-limit ends a run that would take seconds (the fixed point on the
/// spheres: about 8 s) with exit 2, the reason and the residual reached;
/// a limit that is not a positive number is refused.
#[test]
fn a_time_limit_ends_a_long_run_with_exit_2() {
    let started = std::time::Instant::now();
    let v = stopped_on_spheres(&["--friction", "fixed_point", "--time-limit", "0.2"]);
    assert_eq!(v["converged"], false, "{v}");
    assert!(
        v["stopping_reason"]
            .as_str()
            .unwrap()
            .contains("time limit"),
        "{v}"
    );
    assert!(
        started.elapsed() < Duration::from_secs(20),
        "{:?}",
        started.elapsed()
    );
    for bad in ["0", "-1", "nan"] {
        let path = data("fc3d_csc.hdf5");
        let out = local(&[path.as_os_str(), "--time-limit".as_ref(), bad.as_ref()]);
        assert_eq!(out.status.code(), Some(1), "{bad}: {}", stderr(&out));
        let refused = stderr(&out).contains("--time-limit: must be");
        assert!(out.stdout.is_empty() && refused, "{bad}");
    }
}

/// A stored /solution/r of zeros, which does not solve its problem, is
/// reported as such rather than as a distance to our forces.
#[test]
fn a_stored_zero_solution_is_reported_as_not_a_solution() {
    let v = solved(&[data("zero_solution.hdf5").as_os_str()]);
    assert_eq!(v["reference"], "not a solution (r = 0)", "{v}");
    assert!(v.get("reference_r_error").is_none(), "{v}");
    // A stored solution that is one is still compared.
    let v = solved(&[data("fc3d_csc.hdf5").as_os_str()]);
    assert!(v.get("reference").is_none(), "{v}");
    assert!(v["reference_r_error"].as_f64().unwrap() <= 1e-8, "{v}");
}
