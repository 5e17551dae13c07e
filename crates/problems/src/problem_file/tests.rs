use super::*;
use signorini_report::budget::machine_memory;

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-pf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A 2-contact 2D problem, contact-wise: W[r][s] = 10·r + s made symmetric
/// (so that each entry tells where it came from), q[r] = r.
fn contact_wise_json(extra: &str) -> String {
    let w: Vec<String> = (0..4)
        .map(|r| {
            let row: Vec<String> = (0..4)
                .map(|s| {
                    format!(
                        "{}",
                        10 * r.max(s) + r.min(s) + if r == s { 100 } else { 0 }
                    )
                })
                .collect();
            format!("[{}]", row.join(", "))
        })
        .collect();
    format!(r#"{{"W": [{}], "q": [0, 1, 2, 3]{extra}}}"#, w.join(", "))
}

#[test]
fn contact_wise_rows_are_read_into_the_block_layout_and_written_back() {
    let path = temp("cw.json");
    std::fs::write(&path, contact_wise_json(r#", "mu": [0.3, 0.5], "dim": 2"#)).unwrap();
    let p = load(&path, machine_memory()).unwrap();
    assert_eq!((p.dim, p.contacts()), (2, 2));
    // Block rows: n0, n1, t0, t1 = file rows 0, 2, 1, 3.
    assert_eq!(p.file_row, vec![0, 2, 1, 3]);
    assert_eq!(p.q, vec![0.0, 2.0, 1.0, 3.0]);
    assert_eq!(p.w[(0, 1)], 20.0); // file W[0][2]
    assert_eq!(p.w[(2, 3)], 31.0); // file W[1][3]
    assert_eq!(p.mu, Some(vec![0.3, 0.5]));
    assert_eq!(p.to_file_order(&p.q), vec![0.0, 1.0, 2.0, 3.0]);
    // An empty mu is frictionless; the rows keep their layout.
    std::fs::write(&path, contact_wise_json(r#", "mu": [], "dim": 2"#)).unwrap();
    let p = load(&path, machine_memory()).unwrap();
    assert_eq!((p.dim, p.mu.is_none()), (2, true));
}

#[test]
fn a_layout_that_cannot_be_known_is_refused() {
    let path = temp("amb.json");
    let cases = [
        (r#", "mu": [0.3, 0.5]"#, "ambiguous"),
        (
            r#", "mu": [0.3, 0.5], "dim": 2, "layout": "normal_first""#,
            "not both",
        ),
        (r#", "mu": [0.3, 0.5], "dim": 4"#, "dim must be 1, 2 or 3"),
        (
            r#", "mu": [0.3], "dim": 2"#,
            "mu has 1 entries for 2 contacts",
        ),
        (r#", "mu": [0.3, 0.5], "dim": 1"#, "dim is 1"),
        (r#", "dim": 3"#, "multiple of 3"),
        (r#", "mu": [0.3, -1], "dim": 2"#, "mu[1]"),
        (
            r#", "mu": [0.3, 0.5], "layout": "rows""#,
            "\"normal_first\"",
        ),
    ];
    for (extra, message) in cases {
        std::fs::write(&path, contact_wise_json(extra)).unwrap();
        let e = load(&path, machine_memory()).unwrap_err();
        assert!(
            e.contains(message) && e.contains("amb.json"),
            "{extra}: {e}"
        );
    }
    // The same numbers with their order said are read.
    std::fs::write(
        &path,
        contact_wise_json(r#", "mu": [0.3, 0.5], "layout": "normal_first""#),
    )
    .unwrap();
    let p = load(&path, machine_memory()).unwrap();
    assert_eq!(p.file_row, vec![0, 1, 2, 3]);
}

#[test]
fn npz_written_here_reads_back_identically() {
    let path = temp("rt.npz");
    let n = 6;
    let w = Mat::<f64>::from_fn(n, n, |i, j| {
        (1 + i.min(j)) as f64 + if i == j { 10.0 } else { 0.0 }
    });
    let q: Vec<f64> = (0..n).map(|i| i as f64 - 2.5).collect();
    write_npz(&path, &w, &q, &[0.1, 0.2], 3).unwrap();
    let p = load(&path, machine_memory()).unwrap();
    assert_eq!((p.dim, p.contacts()), (3, 2));
    assert_eq!(p.mu, Some(vec![0.1, 0.2]));
    assert_eq!(p.file_row, vec![0, 3, 1, 2, 4, 5]);
    for i in 0..n {
        assert_eq!(p.q[i], q[p.file_row[i]]);
        for j in 0..n {
            assert_eq!(p.w[(i, j)], w[(p.file_row[i], p.file_row[j])]);
        }
    }
    // An LCP: no mu, dim 1.
    write_npz(&path, &w, &q, &[], 1).unwrap();
    let p = load(&path, machine_memory()).unwrap();
    assert_eq!((p.dim, p.contacts(), p.mu.is_none()), (1, 6, true));
    assert_eq!(p.file_row, (0..n).collect::<Vec<_>>());
}
