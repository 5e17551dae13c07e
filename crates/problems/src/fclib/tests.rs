//! The FCLib files of tests/data/fclib, written by the FCLib C library
//! (make_fclib.c) and solved by Siconos (make_fclib.py), read back.

use crate::problem_file::{load, LocalProblem};
use signorini_report::budget::machine_memory;
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/fclib")
        .join(name)
}

/// make_fclib.c's pseudo(i, j), in the same order of operations.
fn pseudo(i: usize, j: usize) -> f64 {
    let (i, j) = (i as f64, j as f64);
    (1.7 * i + 0.37 * j * j + 0.11 * i * j + 0.5).sin()
}

/// make_fclib.c's W = A Aᵀ + I/2 (A contact-block bidiagonal), row-major.
fn generator_w(n: usize, d: usize) -> Vec<f64> {
    let a = |i: usize, j: usize| match (i / d, j / d) {
        (bi, bj) if bi == bj => (if i == j { 1.0 } else { 0.3 }) * (1.0 + 0.5 * pseudo(i, j)),
        (bi, bj) if bi == bj + 1 => 0.4 * pseudo(i, j),
        _ => 0.0,
    };
    let mut w = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let s: f64 = (0..n).map(|k| a(i, k) * a(j, k)).sum();
            w[i * n + j] = s + if i == j { 0.5 } else { 0.0 };
        }
    }
    w
}

/// make_fclib.c's manufactured forces r and velocities u, contact-wise:
/// 2D stick, slip, open, slip, stick; 3D stick, slip, open, slip.
fn generator_r_u(d: usize) -> (Vec<f64>, Vec<f64>) {
    if d == 2 {
        (
            vec![1.0, 0.2, 1.5, 0.45, 0.0, 0.0, 2.5, 1.5, 3.0, 0.24],
            vec![0.0, 0.0, 0.0, -0.25, 0.5, 0.2, 0.0, -0.25, 0.0, 0.0],
        )
    } else {
        (
            vec![
                1.0, 0.16, -0.12, 1.5, -0.36, 0.27, 0.0, 0.0, 0.0, 2.5, -1.2, 0.9,
            ],
            vec![
                0.0, 0.0, 0.0, 0.0, 0.2, -0.15, 0.5, 0.16, -0.12, 0.0, 0.2, -0.15,
            ],
        )
    }
}

/// W of a problem back in the file's row order, row-major.
fn file_order_w(p: &LocalProblem) -> Vec<f64> {
    let n = p.q.len();
    let mut w = vec![0.0; n * n];
    for (i, &ri) in p.file_row.iter().enumerate() {
        for (j, &rj) in p.file_row.iter().enumerate() {
            w[ri * n + rj] = p.w[(i, j)];
        }
    }
    w
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn every_storage_reads_the_matrix_the_generator_built() {
    for (name, d, mu) in [
        ("fc2d_triplet.hdf5", 2, vec![0.5, 0.3, 0.4, 0.6, 0.2]),
        ("fc3d_csc.hdf5", 3, vec![0.5, 0.3, 0.4, 0.6]),
        ("fc3d_csr.hdf5", 3, vec![0.5, 0.3, 0.4, 0.6]),
        ("fc3d_csc_latest.hdf5", 3, vec![0.5, 0.3, 0.4, 0.6]),
    ] {
        let p = load(&data(name), machine_memory()).unwrap();
        let n = mu.len() * d;
        assert_eq!(
            (p.dim, p.contacts(), p.mu.as_ref()),
            (d, mu.len(), Some(&mu))
        );
        let w = generator_w(n, d);
        // The triplets split some entries into 1/4 + 3/4: summed back to
        // round-off. Some entries are zero (W is block tridiagonal).
        assert!(w.iter().filter(|v| **v == 0.0).count() > n, "{name}");
        assert!(max_diff(&file_order_w(&p), &w) <= 1e-15 * 8.0, "{name}");
        // q = u − W r of the manufactured solution.
        let (r, u) = generator_r_u(d);
        let q = p.to_file_order(&p.q);
        let wr_q: Vec<f64> = (0..n)
            .map(|i| q[i] + (0..n).map(|j| w[i * n + j] * r[j]).sum::<f64>())
            .collect();
        assert!(max_diff(&wr_q, &u) < 1e-14, "{name}: {wr_q:?}");
        // Siconos' forces, stored by fclib_write_solution, are the
        // manufactured ones.
        let reference = p.reference_r.as_ref().unwrap();
        assert!(max_diff(reference, &r) < 1e-13, "{name}: {reference:?}");
    }
}

#[test]
fn reference_error_is_the_relative_distance_to_the_files_forces() {
    let p = load(&data("fc3d_csc.hdf5"), machine_memory()).unwrap();
    let r = p.reference_r.clone().unwrap();
    // Forces in the block layout: block row k is file row file_row[k].
    let mut forces: Vec<f64> = p.file_row.iter().map(|&f| r[f]).collect();
    assert_eq!(crate::local::reference_error(&p, &forces), Some(0.0));
    forces[0] += 0.01;
    let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
    let e = crate::local::reference_error(&p, &forces).unwrap();
    assert!((e - 0.01 / norm).abs() < 1e-15, "{e}");
    // No /solution: no reference.
    let json = std::env::temp_dir().join(format!("signorini-fclib-{}.json", std::process::id()));
    std::fs::write(&json, r#"{"W": [[2]], "q": [-1]}"#).unwrap();
    assert_eq!(
        crate::local::reference_error(&load(&json, machine_memory()).unwrap(), &[0.5]),
        None
    );
}

/// Damaged files (truncated anywhere, bytes overwritten; local and global
/// problems) are read or refused, never a panic, a hang or a large
/// allocation.
#[test]
fn damaged_files_are_refused_without_a_panic() {
    let dir = std::env::temp_dir().join(format!("signorini-fclib-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let (mut refused, mut read) = (0, 0);
    for name in ["fc3d_csc.hdf5", "fc3d_csc_latest.hdf5", "global3d.hdf5"] {
        let good = std::fs::read(data(name)).unwrap();
        let mut cases: Vec<Vec<u8>> = (0..good.len())
            .step_by(64)
            .map(|k| good[..k].to_vec())
            .collect();
        for _ in 0..500 {
            let mut b = good.clone();
            for _ in 0..1 + next() % 4 {
                let k = next() as usize % b.len();
                b[k] = next() as u8;
            }
            cases.push(b);
        }
        for (k, bytes) in cases.into_iter().enumerate() {
            let path = dir.join(format!("case{k}.h5"));
            std::fs::write(&path, &bytes).unwrap();
            let t = std::time::Instant::now();
            match std::panic::catch_unwind(|| load(&path, machine_memory())) {
                Ok(Ok(_)) => read += 1,
                Ok(Err(e)) => {
                    assert!(e.contains(&*path.display().to_string()), "{e}");
                    refused += 1
                }
                Err(_) => panic!("{name}, case {k}: a panic"),
            }
            assert!(t.elapsed().as_secs_f64() < 2.0, "{name}, case {k}");
        }
    }
    // Every truncation is refused; some overwritten bytes change nothing read.
    assert!(refused > 400 && read > 0, "refused {refused}, read {read}");
}

/// make_fclib.c's M of a chain of `nodes` nodes of d DOFs, row-major.
fn generator_m(nodes: usize, d: usize) -> Vec<f64> {
    let n = nodes * d;
    let mut m = vec![0.0; n * n];
    for e in 0..nodes {
        let k = 1.0 + 0.5 * pseudo(e, 2 * e + 1);
        for a in 0..d {
            for b in 0..d {
                let s = k * if a == b { 1.0 } else { 0.1 };
                let (i, j) = (e * d + a, e * d + b);
                m[i * n + j] += s;
                if e > 0 {
                    let (i0, j0) = (i - d, j - d);
                    m[i0 * n + j0] += s;
                    m[i0 * n + j] -= s;
                    m[i * n + j0] -= s;
                }
            }
        }
    }
    for i in 0..n {
        m[i * n + i] += 0.2 + 0.05 * i as f64;
    }
    m
}

/// make_fclib.c's frame of contact c (columns n, t or n, t1, t2).
fn generator_frame(c: usize, d: usize) -> Vec<f64> {
    let (th, ph) = (0.4 * c as f64 + 0.3, 0.25 * c as f64 - 0.2);
    let (ct, st, cp, sp) = (th.cos(), th.sin(), ph.cos(), ph.sin());
    if d == 2 {
        return vec![ct, -st, st, ct];
    }
    let rz = [ct, -st, 0.0, st, ct, 0.0, 0.0, 0.0, 1.0];
    let rx = [1.0, 0.0, 0.0, 0.0, cp, -sp, 0.0, sp, cp];
    (0..9)
        .map(|ij| {
            (0..3)
                .map(|k| rz[ij / 3 * 3 + k] * rx[k * 3 + ij % 3])
                .sum()
        })
        .collect()
}

/// make_fclib.c's H (n × m, row-major) of nc contacts.
fn generator_h(nc: usize, d: usize) -> Vec<f64> {
    let (n, m) = ((nc + 1) * d, nc * d);
    let mut h = vec![0.0; n * m];
    for c in 0..nc {
        let f = generator_frame(c, d);
        for a in 0..d {
            for k in 0..d {
                h[((c + 1) * d + a) * m + c * d + k] = f[a * d + k];
                h[(c * d + a) * m + c * d + k] = -0.3 * f[a * d + k];
            }
        }
    }
    h
}

/// The global problems' W = Hᵀ M⁻¹ H and q = Hᵀ M⁻¹ f + w (f = M v − H r,
/// w = u − Hᵀ v of the manufactured solution), by a dense Cholesky of
/// the generator's M, and the manufactured (r, v).
fn dense_condensation(d: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    use faer::prelude::Solve;
    let nc = if d == 2 { 5 } else { 4 };
    let (n, m) = ((nc + 1) * d, nc * d);
    let mm = faer::Mat::<f64>::from_fn(n, n, |i, j| generator_m(nc + 1, d)[i * n + j]);
    let h = faer::Mat::<f64>::from_fn(n, m, |i, j| generator_h(nc, d)[i * m + j]);
    let (r, u) = generator_r_u(d);
    let v: Vec<f64> = (0..n).map(|i| 0.3 * pseudo(i, 5)).collect();
    let col = |x: &[f64]| faer::Mat::<f64>::from_fn(x.len(), 1, |i, _| x[i]);
    let f = &mm * col(&v) - &h * col(&r);
    let w = col(&u) - h.transpose() * col(&v);
    let llt = mm.llt(faer::Side::Lower).unwrap();
    let wm = h.transpose() * llt.solve(&h);
    let q = h.transpose() * llt.solve(&f) + w;
    let wm = (0..m * m).map(|k| wm[(k / m, k % m)]).collect();
    (wm, (0..m).map(|i| q[(i, 0)]).collect(), r, v)
}

#[test]
fn global_problems_condense_to_the_dense_reference() {
    for (name, d) in [("global2d.hdf5", 2), ("global3d.hdf5", 3)] {
        let p = load(&data(name), machine_memory()).unwrap();
        let (w, q, r, v) = dense_condensation(d);
        let wmax = w.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let qmax = q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let (dw, dq) = (
            max_diff(&file_order_w(&p), &w),
            max_diff(&p.to_file_order(&p.q), &q),
        );
        assert!(
            dw <= 1e-12 * wmax && dq <= 1e-12 * qmax,
            "{name}: {dw:e}, {dq:e}"
        );
        // The same factor recovers the manufactured v from the manufactured r.
        let g = p.global.as_ref().unwrap();
        let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        assert!(max_diff(&g.velocity(&r), &v) <= 1e-12 * vmax, "{name}");
        // Siconos' r and v are the file's /solution: their distance to ours.
        assert!(g.reference_v_error(&r).unwrap() < 1e-12, "{name}");
        let s = g.summary();
        let n = (if d == 2 { 6 } else { 5 }) * d;
        assert_eq!(
            (s.n, s.nnz_m),
            (n, 3 * d * d * (n / d) - 2 * d * d),
            "{name}"
        );
    }
}
