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
use signorini_contact::methods::{solve_lcp, Algorithm};

/// A stand-alone problem LCP(W, q).
#[derive(Debug)]
pub struct LocalProblem {
    pub w: Mat<f64>,
    pub q: Vec<f64>,
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
    let (w, q) = if path.extension().is_some_and(|e| e == "npz") {
        let file = std::fs::File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
        let mut archive =
            zip::ZipArchive::new(file).map_err(|e| format!("{shown}: not a .npz archive ({e})"))?;
        let (ws, wf, wd) =
            read_npy(&mut archive, "W")?.ok_or(format!("{shown}: no array named W"))?;
        let (qs, _, qd) =
            read_npy(&mut archive, "q")?.ok_or(format!("{shown}: no array named q"))?;
        if read_npy(&mut archive, "mu")?.is_some() {
            return Err(format!(
                "{shown}: mu (friction) is not supported yet by signorini local"
            ));
        }
        if ws.len() != 2 || ws[0] != ws[1] {
            return Err(format!("{shown}: W must be square, has shape {ws:?}"));
        }
        let m = ws[0] as usize;
        if qs.iter().product::<u64>() as usize != m {
            return Err(format!("{shown}: q has shape {qs:?}, W is {m} × {m}"));
        }
        let w = Mat::<f64>::from_fn(m, m, |i, j| if wf { wd[i + m * j] } else { wd[i * m + j] });
        (w, qd)
    } else {
        let text =
            std::fs::read_to_string(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
        let p: JsonProblem = serde_json::from_str(&text).map_err(|e| format!("{shown}: {e}"))?;
        if p.mu.is_some() {
            return Err(format!(
                "{shown}: mu (friction) is not supported yet by signorini local"
            ));
        }
        let m = p.q.len();
        if p.w.len() != m || p.w.iter().any(|r| r.len() != m) {
            return Err(format!("{shown}: W must be {m} × {m} to match q"));
        }
        (Mat::<f64>::from_fn(m, m, |i, j| p.w[i][j]), p.q)
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
    Ok(LocalProblem { w, q })
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
    let sol = solve_lcp(algorithm, &p.w, &p.q, None, &opts).map_err(|e| e.to_string())?;
    let time_s = t.elapsed().as_secs_f64();
    Ok(LocalResult {
        problem: name.to_string(),
        method: algorithm.name().to_string(),
        m,
        converged: sol.report.converged,
        iterations: sol.report.iterations,
        operator_applications: sol.report.operator_applications,
        time_s,
        residual: lcp_residual(&p.w, &p.q, &sol.lambda, &opts),
        active: sol.lambda.iter().filter(|&&l| l > 0.0).count(),
        stopping_reason: sol.report.stopping_reason,
        lambda: with_lambda.then_some(sol.lambda),
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
        for a in [
            Algorithm::Status(signorini_contact::StatusVariant::All),
            Algorithm::Lemke,
            Algorithm::Mprgp,
        ] {
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
                Algorithm::Status(signorini_contact::StatusVariant::All),
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
}
