//! `signorini local PROBLEM`: a stand-alone condensed contact problem, the
//! Delassus operator W (dense, symmetric) and the gaps q, solved by any root
//! algorithm, so that the root solvers can be compared with other libraries
//! on identical data (DESIGN.md §4).
//!
//! Formats: JSON `{"W": [[...], ...], "q": [...]}` (rows of W), or a NumPy
//! `.npz` archive with arrays `W` (m × m, either order) and `q` (m). An
//! optional `mu` (friction coefficients) is recognised and rejected until
//! friction exists.

use std::io::Read;
use std::path::Path;
use std::time::Instant;

use faer::Mat;
use serde::{Deserialize, Serialize};
use signorini_contact::lcp::{lcp_residual, LcpOptions};
use signorini_contact::registry::Algorithm;

/// A stand-alone problem LCP(W, q), or with `mu` a frictional one: then W
/// and q have 2m rows, the m normal rows first and the m tangential rows
/// after them (point p's tangential row is m + p), and `mu` has m entries.
#[derive(Debug)]
pub struct LocalProblem {
    pub w: Mat<f64>,
    pub q: Vec<f64>,
    pub mu: Option<Vec<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonProblem {
    #[serde(rename = "W")]
    w: Vec<Vec<f64>>,
    q: Vec<f64>,
    #[serde(default)]
    mu: Option<serde_json::Value>,
}

/// Shape, Fortran order, data (float64).
type NpyArray = (Vec<u64>, bool, Vec<f64>);

fn read_npy(
    archive: &mut zip::ZipArchive<std::fs::File>,
    name: &str,
) -> Result<Option<NpyArray>, String> {
    let mut file = match archive.by_name(&format!("{name}.npy")) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(format!("{name}.npy: {e}")),
    };
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes)
        .map_err(|e| format!("{name}.npy: {e}"))?;
    let npy = npyz::NpyFile::new(&bytes[..]).map_err(|e| format!("{name}.npy: {e}"))?;
    let shape = npy.shape().to_vec();
    let fortran = npy.order() == npyz::Order::Fortran;
    let data = npy
        .into_vec::<f64>()
        .map_err(|e| format!("{name}.npy: expected float64 data ({e})"))?;
    Ok(Some((shape, fortran, data)))
}

/// Reads a problem; errors name the file and what is wrong.
pub fn load(path: &Path) -> Result<LocalProblem, String> {
    let shown = path.display();
    let (w, q, mu) = if path.extension().is_some_and(|e| e == "npz") {
        let file = std::fs::File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
        let mut archive =
            zip::ZipArchive::new(file).map_err(|e| format!("{shown}: not a .npz archive ({e})"))?;
        let (ws, wf, wd) =
            read_npy(&mut archive, "W")?.ok_or(format!("{shown}: no array named W"))?;
        let (qs, _, qd) =
            read_npy(&mut archive, "q")?.ok_or(format!("{shown}: no array named q"))?;
        let mu_npz = read_npy(&mut archive, "mu")?.map(|(_, _, d)| d);
        if ws.len() != 2 || ws[0] != ws[1] {
            return Err(format!("{shown}: W must be square, has shape {ws:?}"));
        }
        let m = usize::try_from(ws[0]).map_err(|_| format!("{shown}: W is too large"))?;
        // The shapes are the file's word; the data must be there too.
        let q_len = qs.iter().try_fold(1u64, |a, &d| a.checked_mul(d));
        if q_len != Some(m as u64) || qd.len() != m {
            return Err(format!("{shown}: q has shape {qs:?}, W is {m} × {m}"));
        }
        if m.checked_mul(m) != Some(wd.len()) {
            return Err(format!(
                "{shown}: W has shape {ws:?} but holds {} numbers",
                wd.len()
            ));
        }
        let w = Mat::<f64>::from_fn(m, m, |i, j| if wf { wd[i + m * j] } else { wd[i * m + j] });
        (w, qd, mu_npz)
    } else {
        let text =
            std::fs::read_to_string(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
        let p: JsonProblem = serde_json::from_str(&text).map_err(|e| format!("{shown}: {e}"))?;
        let mu = match p.mu {
            None => None,
            Some(v) => Some(
                serde_json::from_value::<Vec<f64>>(v)
                    .map_err(|e| format!("{shown}: mu must be a list of numbers ({e})"))?,
            ),
        };
        let m = p.q.len();
        if p.w.len() != m || p.w.iter().any(|r| r.len() != m) {
            return Err(format!("{shown}: W must be {m} × {m} to match q"));
        }
        (Mat::<f64>::from_fn(m, m, |i, j| p.w[i][j]), p.q, mu)
    };
    let m = q.len();
    let wmax = w.norm_max();
    for i in 0..m {
        for j in 0..m {
            if !w[(i, j)].is_finite() {
                return Err(format!("{shown}: W[{i}][{j}] is not finite"));
            }
            if (w[(i, j)] - w[(j, i)]).abs() > 1e-10 * wmax {
                return Err(format!(
                    "{shown}: W is not symmetric (W[{i}][{j}] = {} but W[{j}][{i}] = {})",
                    w[(i, j)],
                    w[(j, i)]
                ));
            }
        }
    }
    if let Some(i) = q.iter().position(|v| !v.is_finite()) {
        return Err(format!("{shown}: q[{i}] is not finite"));
    }
    if let Some(mu) = &mu {
        if 2 * mu.len() != m {
            return Err(format!(
                "{shown}: with mu, W and q have 2m rows (m normal rows, then m tangential rows): q has {m} rows, mu has {} entries",
                mu.len()
            ));
        }
        if let Some(i) = mu.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(format!("{shown}: mu[{i}] must be a finite number >= 0"));
        }
    }
    Ok(LocalProblem { w, q, mu })
}

/// The JSON line `signorini local` prints.
#[derive(Debug, Serialize)]
pub struct LocalResult {
    pub problem: String,
    pub method: String,
    pub m: usize,
    pub converged: bool,
    pub iterations: usize,
    pub operator_applications: usize,
    pub time_s: f64,
    /// Scaled natural residual of the LCP (see the contact crate's `lcp_residual`).
    pub residual: f64,
    pub active: usize,
    pub stopping_reason: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lambda: Option<Vec<f64>>,
}

/// Solves a frictional local problem by the Coulomb fixed point (seed §4.3)
/// or, with `status`, the friction status method (§4.5).
pub fn solve_friction(
    name: &str,
    p: &LocalProblem,
    status: bool,
    tolerance: f64,
    max_iterations: usize,
    with_lambda: bool,
) -> Result<LocalResult, String> {
    use signorini_contact::friction::{
        coulomb_fixed_point, coulomb_status, FrictionLaw, FrictionLayout, FrictionOptions,
        PointStatus,
    };
    let mu = p.mu.as_ref().ok_or("no mu")?;
    let m = mu.len();
    let qmax =
        p.q.iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
    let dmax = (0..2 * m)
        .fold(0.0f64, |a, i| a.max(p.w[(i, i)].abs()))
        .max(f64::MIN_POSITIVE);
    let layout = FrictionLayout {
        tangent_rows: (0..m).map(|i| vec![m + i]).collect(),
        law: mu.iter().map(|&u| FrictionLaw::coulomb(u)).collect(),
        shadow: vec![None; m],
    };
    let opts = FrictionOptions {
        max_iterations,
        max_fixed_point: max_iterations,
        tolerance,
        force_scale: qmax / dmax,
        gap_scale: qmax,
    };
    let initial = (0..m)
        .map(|i| {
            if p.q[i] <= 0.0 {
                PointStatus::Stick
            } else {
                PointStatus::Open
            }
        })
        .collect();
    let mut problem = signorini_contact::DelassusProblem::from_operator(p.w.clone(), p.q.clone());
    let t = Instant::now();
    let out = if status {
        coulomb_status(&mut problem, &layout, initial, &opts)
    } else {
        coulomb_fixed_point(&mut problem, &layout, initial, None, &opts)
    }
    .map_err(|e| e.to_string())?;
    let time_s = t.elapsed().as_secs_f64();
    // Residual: the LCP of the normal part plus the cone violation, scaled.
    let f = opts
        .force_scale
        .max(out.forces.iter().fold(0.0f64, |a, v| a.max(v.abs())));
    let normal = (0..m)
        .map(|i| (out.forces[i] / f).min(out.gaps[i] / qmax).abs())
        .fold(0.0, f64::max);
    let cone = (0..m)
        .map(|i| (out.forces[m + i].abs() - mu[i] * out.forces[i].max(0.0)).max(0.0) / f)
        .fold(0.0, f64::max);
    Ok(LocalResult {
        problem: name.to_string(),
        method: if status {
            "friction_status"
        } else {
            "coulomb_fixed_point"
        }
        .to_string(),
        m,
        converged: out.converged,
        iterations: out.iterations,
        operator_applications: problem.solves,
        time_s,
        residual: normal.max(cone),
        active: out
            .statuses
            .iter()
            .filter(|s| **s != PointStatus::Open)
            .count(),
        stopping_reason: out.stopping_reason,
        lambda: with_lambda.then_some(out.forces),
    })
}

/// Solves a problem; the scales are those of the data: gaps relative to
/// max |q|, forces relative to max |q| / max diag W.
pub fn solve(
    name: &str,
    p: &LocalProblem,
    algorithm: Algorithm,
    tolerance: f64,
    max_iterations: usize,
    with_lambda: bool,
) -> Result<LocalResult, String> {
    let m = p.q.len();
    let qmax =
        p.q.iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
    let dmax = (0..m)
        .fold(0.0f64, |a, i| a.max(p.w[(i, i)].abs()))
        .max(f64::MIN_POSITIVE);
    let opts = LcpOptions {
        tolerance,
        max_iterations,
        force_scale: qmax / dmax,
        gap_scale: qmax,
        stiffness: None,
    };
    let t = Instant::now();
    let sol = algorithm
        .solve(&p.w, &p.q, None, &opts)
        .map_err(|e| e.to_string())?;
    let time_s = t.elapsed().as_secs_f64();
    Ok(LocalResult {
        problem: name.to_string(),
        method: algorithm.name().to_string(),
        m,
        converged: sol.report.converged,
        iterations: sol.report.iterations,
        operator_applications: sol.report.operator_applications,
        time_s,
        residual: lcp_residual(&p.w, &p.q, &sol.forces, &opts),
        active: sol.forces.iter().filter(|&&l| l > 0.0).count(),
        stopping_reason: sol.report.stop.to_string(),
        lambda: with_lambda.then_some(sol.forces),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_problem_solves_to_the_known_answer_with_every_method() {
        let dir = std::env::temp_dir().join(format!("signorini-local-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.json");
        // W = [[2, 1], [1, 2]], q = [-1, 1]: λ = (0.5, 0), w = (0, 1.5).
        std::fs::write(&path, r#"{"W": [[2, 1], [1, 2]], "q": [-1, 1]}"#).unwrap();
        let p = load(&path).unwrap();
        for a in ["status", "lemke", "mprgp"].map(|name| Algorithm::by_name(name).unwrap()) {
            let r = solve("p", &p, a, 1e-12, 1000, true).unwrap();
            assert!(r.converged);
            let l = r.lambda.unwrap();
            assert!((l[0] - 0.5).abs() <= 1e-12 && l[1] == 0.0, "{a:?}: {l:?}");
        }
        std::fs::write(&path, r#"{"W": [[2, 1], [0, 2]], "q": [-1, 1]}"#).unwrap();
        assert!(load(&path).unwrap_err().contains("not symmetric"));
        std::fs::write(&path, r#"{"W": [[2]], "q": [-1, 1]}"#).unwrap();
        assert!(load(&path).unwrap_err().contains("2 × 2"));
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
            r#"{"W": [[0.2, 0], [0, 0.5]], "q": [-0.6, 1.0], "mu": [0.5]}"#,
        )
        .unwrap();
        let p = load(&path).unwrap();
        for status in [false, true] {
            let r = solve_friction("p", &p, status, 1e-12, 100, true).unwrap();
            assert!(r.converged, "{}", r.stopping_reason);
            let l = r.lambda.unwrap();
            assert!(
                (l[0] - 3.0).abs() < 1e-10 && (l[1] + 1.5).abs() < 1e-10,
                "{l:?}"
            );
        }
        std::fs::write(
            &path,
            r#"{"W": [[0.2, 0], [0, 0.5]], "q": [-0.6, 1.0], "mu": [0.5, 0.2]}"#,
        )
        .unwrap();
        assert!(load(&path).unwrap_err().contains("2m rows"));
    }

    /// A .npy v1.0 file of little-endian float64 (the format NumPy writes).
    fn npy(shape: &[usize], fortran: bool, data: &[f64]) -> Vec<u8> {
        let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
        let shape = if dims.len() == 1 {
            format!("({},)", dims[0])
        } else {
            format!("({})", dims.join(", "))
        };
        let mut header = format!(
            "{{'descr': '<f8', 'fortran_order': {}, 'shape': {shape}, }}",
            if fortran { "True" } else { "False" }
        );
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend((header.len() as u16).to_le_bytes());
        out.extend(header.as_bytes());
        for v in data {
            out.extend(v.to_le_bytes());
        }
        out
    }

    #[test]
    fn npz_problem_in_either_order_gives_the_json_answer() {
        use std::io::Write;
        let dir = std::env::temp_dir().join(format!("signorini-npz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // W = [[4, 1, 0], [1, 3, 1], [0, 1, 2]] is symmetric: both orders store the same bytes,
        // so use a non-symmetric-looking layout check through q instead.
        let w = [4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0];
        let q = [-1.0, 0.5, -2.0];
        for fortran in [false, true] {
            let path = dir.join(format!("p{fortran}.npz"));
            let mut z = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
            let o = zip::write::SimpleFileOptions::default()
                .compression_method(zip::CompressionMethod::Deflated);
            z.start_file("W.npy", o).unwrap();
            z.write_all(&npy(&[3, 3], fortran, &w)).unwrap();
            z.start_file("q.npy", o).unwrap();
            z.write_all(&npy(&[3], false, &q)).unwrap();
            z.finish().unwrap();
            let p = load(&path).unwrap();
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
        let mut z = zip::ZipWriter::new(std::fs::File::create(&bad).unwrap());
        z.start_file("q.npy", zip::write::SimpleFileOptions::default())
            .unwrap();
        z.write_all(&npy(&[3], false, &q)).unwrap();
        z.finish().unwrap();
        assert!(load(&bad).unwrap_err().contains("no array named W"));
    }

    /// Shapes are the file's word: a header that lies about them (or that
    /// overflows) is an error naming the file, never an out-of-bounds read
    /// or a huge allocation.
    #[test]
    fn npz_shapes_that_lie_are_refused() {
        use std::io::Write;
        let dir = std::env::temp_dir().join(format!("signorini-npz-lies-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |name: &str, w: Vec<u8>, q: Vec<u8>| {
            let path = dir.join(name);
            let mut z = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
            let o = zip::write::SimpleFileOptions::default();
            z.start_file("W.npy", o).unwrap();
            z.write_all(&w).unwrap();
            z.start_file("q.npy", o).unwrap();
            z.write_all(&q).unwrap();
            z.finish().unwrap();
            load(&path).unwrap_err()
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
}
