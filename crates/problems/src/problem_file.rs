//! The stand-alone problem file of `signorini local` (docs/theory/algorithms.md): a
//! Delassus operator W (dense; a nonsymmetric one is read as it is, for
//! the methods that do not need symmetry), its free gaps q and, for
//! friction, a coefficient μ per contact, so that the root solvers can be
//! compared with other libraries on identical data.
//!
//! Formats: JSON `{"W": [[...], ...], "q": [...], "mu": [...], "dim": d}`
//! (W by rows), a NumPy `.npz` archive with arrays `W` (either order), `q`,
//! optionally `mu` and `dim` (a scalar), or an FCLib local problem (HDF5,
//! `.hdf5` or `.h5`: `fclib.rs`), contact-wise, or an FCLib global one
//! condensed into a local one (`fclib/condense_global.rs`). Row layouts:
//! - `dim` = 1, or neither `dim` nor `mu`: an LCP, one row per contact;
//! - `dim` = 2 or 3: contact-wise rows, [n, t] or [n, t1, t2] per contact
//!   (the layout of Siconos and FCLib); `mu` has one entry per contact, an
//!   empty or absent `mu` meaning frictionless;
//! - JSON only, `"layout": "normal_first"`: the m normal rows, then the m
//!   tangential rows (2D), with `mu` of m entries.
//!
//! With `mu` and neither `dim` nor `layout`, the order of the rows cannot be
//! known, and the file is refused: it is never solved in the wrong order.
//! Once read, a problem is held in this project's block layout (normal rows
//! 0..m, then the tangential rows of each contact in turn).

use std::io::{Read, Write};
use std::path::Path;

use faer::Mat;
use serde::Deserialize;
use signorini_report::budget::{human, Budget};

use crate::fclib::{self, GlobalCondensation};
use crate::raw::{regular_file, Raw, NPY_COPIES};

/// A stand-alone problem in the block layout, with the file row of each row.
#[derive(Debug)]
pub struct LocalProblem {
    pub w: Mat<f64>,
    pub q: Vec<f64>,
    /// Rows per contact: 1 (an LCP), 2 or 3.
    pub dim: usize,
    /// μ per contact; `None`: frictionless (an LCP on the normal rows).
    pub mu: Option<Vec<f64>>,
    /// The file's row of each block row.
    pub file_row: Vec<usize>,
    /// Another solver's forces for this problem, in the file's row order
    /// (an FCLib file's `/solution/r`).
    pub reference_r: Option<Vec<f64>>,
    /// An FCLib global problem's condensation (to recover its velocities v).
    pub global: Option<GlobalCondensation>,
    /// Where W is not symmetric ([`Asymmetry`]); `None`: symmetric to
    /// 1e-10 max |W|.
    pub asymmetry: Option<Asymmetry>,
    /// An FCLib file's W (or global M) stored as this triangle of a
    /// symmetric matrix (`"upper"`, `"lower"`), completed on reading.
    pub stored_triangle: Option<&'static str>,
}

/// A W that is not symmetric: its first entry (file rows, by rows) off its
/// transpose by more than 1e-10 max |W|, both values, and the largest
/// |W_ij − W_ji| / max |W|.
#[derive(Debug, Clone, Copy)]
pub struct Asymmetry {
    pub i: usize,
    pub j: usize,
    pub wij: f64,
    pub wji: f64,
    pub relative: f64,
}

impl LocalProblem {
    /// Refuses a nonsymmetric W for `method`, which needs a symmetric one,
    /// naming the methods that accept it (`accepted`); `name`: the file.
    pub fn require_symmetric(
        &self,
        name: &str,
        method: &str,
        accepted: &str,
    ) -> Result<(), String> {
        let Some(a) = self.asymmetry else {
            return Ok(());
        };
        Err(format!(
            "{name}: W is not symmetric (W[{}][{}] = {} but W[{}][{}] = {}; max |W - W^T| = {:.1e} max |W|): {method} needs a symmetric W; {accepted} solve(s) it as it is",
            a.i, a.j, a.wij, a.j, a.i, a.wji, a.relative
        ))
    }
}

impl LocalProblem {
    pub fn contacts(&self) -> usize {
        self.q.len() / self.dim
    }

    /// Forces of the block layout in the file's row order.
    pub fn to_file_order(&self, forces: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; forces.len()];
        for (k, &r) in self.file_row.iter().enumerate() {
            out[r] = forces[k];
        }
        out
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonProblem {
    #[serde(rename = "W")]
    w: Vec<Vec<f64>>,
    q: Vec<f64>,
    #[serde(default)]
    mu: Option<serde_json::Value>,
    #[serde(default)]
    dim: Option<serde_json::Value>,
    #[serde(default)]
    layout: Option<String>,
}

/// Shape, Fortran order, data (float64).
type NpyArray = (Vec<u64>, bool, Vec<f64>);

fn read_npy(
    archive: &mut zip::ZipArchive<std::fs::File>,
    shown: &str,
    name: &str,
    budget: Option<Budget>,
) -> Result<Option<NpyArray>, String> {
    let Some(bytes) = read_member(archive, shown, &format!("{name}.npy"), budget)? else {
        return Ok(None);
    };
    let member = format!("{shown}: {name}.npy");
    let npy = npyz::NpyFile::new(&bytes[..]).map_err(|e| format!("{member}: {e}"))?;
    let shape = npy.shape().to_vec();
    let fortran = npy.order() == npyz::Order::Fortran;
    // float64, or integers (NumPy's default for `np.array(2)`), read as f64.
    let data = match npy.into_vec::<f64>() {
        Ok(data) => data,
        Err(e) => npyz::NpyFile::new(&bytes[..])
            .and_then(|n| n.into_vec::<i64>())
            .map(|v| v.into_iter().map(|x| x as f64).collect())
            .map_err(|_| format!("{member}: expected float64 or integer data ({e})"))?,
    };
    Ok(Some((shape, fortran, data)))
}

/// The bytes of the archive's member `member`, or `None` if it has none;
/// refused when they would not fit in memory, or when their CRC-32 is not
/// the one the archive records (a damaged file never gives an answer).
fn read_member(
    archive: &mut zip::ZipArchive<std::fs::File>,
    shown: &str,
    member: &str,
    budget: Option<Budget>,
) -> Result<Option<Vec<u8>>, String> {
    let mut file = match archive.by_name(member) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(format!("{shown}: {member}: {e}")),
    };
    // A few kilobytes of deflated zeros can unpack to gigabytes: the array,
    // its f64 copy and the solver's dense copies must fit before any is made.
    let unpacked = file.size();
    if let Some(b) = budget {
        if (NPY_COPIES * unpacked) as f64 > b.bytes as f64 {
            return Err(format!(
                "{shown}: {member} unpacks to {}, and solving it needs about {NPY_COPIES} times that, more than the {} {}",
                human(unpacked as f64),
                human(b.bytes as f64),
                b.source
            ));
        }
    }
    let mut bytes = Vec::new();
    (&mut file)
        .take(unpacked)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("{shown}: {member} is damaged ({e})"))?;
    if bytes.len() as u64 != unpacked {
        return Err(format!(
            "{shown}: {member} is damaged: it holds {} bytes, the archive records {unpacked}",
            bytes.len()
        ));
    }
    check_crc(shown, member, crc32fast::hash(&bytes), file.crc32())?;
    Ok(Some(bytes))
}

/// Refuses a member whose CRC-32 `computed` is not the `recorded` one.
fn check_crc(shown: &str, member: &str, computed: u32, recorded: u32) -> Result<(), String> {
    if computed == recorded {
        return Ok(());
    }
    Err(format!(
        "{shown}: {member} is damaged: its CRC-32 is {computed:08x}, the archive records {recorded:08x} (the file was altered after it was written); write it again"
    ))
}

/// Checks the CRC-32 of the members other than `read` (those [`read_member`]
/// checked), streaming them: no member of a damaged archive is trusted.
fn check_other_members(
    archive: &mut zip::ZipArchive<std::fs::File>,
    shown: &str,
    read: &[&str],
) -> Result<(), String> {
    /// Hashes what is written to it.
    struct Crc(crc32fast::Hasher);
    impl Write for Crc {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.update(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    for i in 0..archive.len() {
        let mut file = archive
            .by_index(i)
            .map_err(|e| format!("{shown}: member {i}: {e}"))?;
        let member = String::from_utf8_lossy(file.name_raw()).into_owned();
        if read.contains(&member.as_str()) || file.is_dir() {
            continue;
        }
        let mut crc = Crc(crc32fast::Hasher::new());
        let size = file.size();
        std::io::copy(&mut (&mut file).take(size), &mut crc)
            .map_err(|e| format!("{shown}: {member} is damaged ({e})"))?;
        check_crc(shown, &member, crc.0.finalize(), file.crc32())?;
    }
    Ok(())
}

fn read_npz(path: &Path, budget: Option<Budget>) -> Result<Raw, String> {
    let shown = path.display();
    regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
    let mut archive =
        zip::ZipArchive::new(file).map_err(|e| format!("{shown}: not a .npz archive ({e})"))?;
    let shown = shown.to_string();
    let (ws, wf, wd) =
        read_npy(&mut archive, &shown, "W", budget)?.ok_or(format!("{shown}: no array named W"))?;
    let (qs, _, qd) =
        read_npy(&mut archive, &shown, "q", budget)?.ok_or(format!("{shown}: no array named q"))?;
    let mu = read_npy(&mut archive, &shown, "mu", budget)?.map(|(_, _, d)| d);
    let dim = match read_npy(&mut archive, &shown, "dim", budget)? {
        None => None,
        Some((_, _, d)) if d.len() == 1 => Some(d[0]),
        Some((s, _, _)) => return Err(format!("{shown}: dim must be one number, has shape {s:?}")),
    };
    check_other_members(
        &mut archive,
        &shown,
        &["W.npy", "q.npy", "mu.npy", "dim.npy"],
    )?;
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
    Ok(Raw {
        w,
        q: qd,
        mu,
        dim,
        normal_first: false,
    })
}

fn read_json(path: &Path) -> Result<Raw, String> {
    let shown = path.display();
    regular_file(path)?;
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
    let p: JsonProblem = serde_json::from_str(&text).map_err(|e| {
        if e.is_syntax() || e.is_eof() {
            format!("{shown}: not a JSON problem ({e}); {FORMATS}")
        } else {
            format!("{shown}: {e}")
        }
    })?;
    let mu = match p.mu {
        None => None,
        Some(v) => Some(
            serde_json::from_value::<Vec<f64>>(v)
                .map_err(|e| format!("{shown}: mu must be a list of numbers ({e})"))?,
        ),
    };
    let dim = match p.dim {
        None => None,
        Some(v) => Some(
            v.as_f64()
                .ok_or(format!("{shown}: dim must be 1, 2 or 3, got {v}"))?,
        ),
    };
    let normal_first = match p.layout.as_deref() {
        None => false,
        Some("normal_first") => true,
        Some(other) => {
            return Err(format!(
                "{shown}: layout \"{other}\" is not known: the one layout name is \"normal_first\" (give \"dim\" for contact-wise rows)"
            ))
        }
    };
    let m = p.q.len();
    if p.w.len() != m || p.w.iter().any(|r| r.len() != m) {
        return Err(format!("{shown}: W must be {m} × {m} to match q"));
    }
    Ok(Raw {
        w: Mat::<f64>::from_fn(m, m, |i, j| p.w[i][j]),
        q: p.q,
        mu,
        dim,
        normal_first,
    })
}

/// W finite, q finite; where W is not symmetric ([`Asymmetry`]).
fn check_values(shown: &str, w: &Mat<f64>, q: &[f64]) -> Result<Option<Asymmetry>, String> {
    let m = q.len();
    let wmax = w.norm_max();
    let mut asymmetry: Option<Asymmetry> = None;
    for i in 0..m {
        for j in 0..m {
            if !w[(i, j)].is_finite() {
                return Err(format!("{shown}: W[{i}][{j}] is not finite"));
            }
            let off = (w[(i, j)] - w[(j, i)]).abs();
            if off > 1e-10 * wmax {
                let relative = off / wmax;
                match asymmetry.as_mut() {
                    Some(a) => a.relative = a.relative.max(relative),
                    None => {
                        let (wij, wji) = (w[(i, j)], w[(j, i)]);
                        asymmetry = Some(Asymmetry {
                            i,
                            j,
                            wij,
                            wji,
                            relative,
                        });
                    }
                }
            }
        }
    }
    if let Some(i) = q.iter().position(|v| !v.is_finite()) {
        return Err(format!("{shown}: q[{i}] is not finite"));
    }
    Ok(asymmetry)
}

/// The rows per contact and, for each block row, its file row.
fn resolve_layout(shown: &str, raw: &Raw) -> Result<(usize, Vec<usize>), String> {
    let n = raw.q.len();
    let friction = raw.mu.as_ref().is_some_and(|mu| !mu.is_empty());
    let dim = match (raw.dim, raw.normal_first) {
        (Some(_), true) => {
            return Err(format!(
                "{shown}: give either \"dim\" (contact-wise rows) or \"layout\": \"normal_first\", not both"
            ))
        }
        (Some(d), false) if d == 1.0 || d == 2.0 || d == 3.0 => d as usize,
        (Some(d), false) => return Err(format!("{shown}: dim must be 1, 2 or 3, got {d}")),
        (None, true) => 2,
        (None, false) if friction => {
            return Err(format!(
                "{shown}: the order of the rows is ambiguous: with mu, give \"dim\": 2 or 3 (contact-wise rows [n, t] or [n, t1, t2] per contact, as Siconos and FCLib write them) or, in JSON, \"layout\": \"normal_first\" (the m normal rows, then the m tangential rows)"
            ))
        }
        (None, false) => 1,
    };
    if !n.is_multiple_of(dim) {
        return Err(format!(
            "{shown}: with {dim} rows per contact, W and q need a multiple of {dim} rows, have {n}"
        ));
    }
    let m = n / dim;
    if let Some(mu) = raw.mu.as_ref().filter(|mu| !mu.is_empty()) {
        if dim == 1 {
            return Err(format!(
                "{shown}: mu is given but dim is 1 (an LCP has no tangential rows)"
            ));
        }
        if mu.len() != m {
            return Err(format!(
                "{shown}: mu has {} entries for {m} contacts ({n} rows, {dim} per contact)",
                mu.len()
            ));
        }
        if let Some(i) = mu.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(format!("{shown}: mu[{i}] must be a finite number >= 0"));
        }
    }
    let order = if raw.normal_first {
        (0..n).collect()
    } else {
        let normals = (0..m).map(|p| p * dim);
        normals
            .chain((0..m).flat_map(|p| (1..dim).map(move |k| p * dim + k)))
            .collect()
    };
    Ok((dim, order))
}

/// The formats [`load`] reads, for its messages.
const FORMATS: &str = "a problem file is JSON, NumPy .npz or FCLib .hdf5/.h5 (by its extension)";

/// Reads a problem; errors name the file and what is wrong. The format
/// follows the extension (any case): `.npz`, `.hdf5` or `.h5` (FCLib), else
/// JSON. A file, or an array in it, whose solve would need more than
/// `budget` is refused before it is read.
pub fn load(path: &Path, budget: Option<Budget>) -> Result<LocalProblem, String> {
    let is = |ext: &str| {
        path.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case(ext))
    };
    let shown = path.display().to_string();
    if is("hdf5") || is("h5") {
        let file = fclib::read(path, budget)?;
        // Its checks name W, q (vectors/q) and mu (vectors/mu) of
        // /fclib_local, or of the local problem a global one condenses to.
        let what = match file.global {
            None => "(/fclib_local)",
            Some(_) => "(/fclib_global condensed: W = H^T M^-1 H, q = H^T M^-1 f + w)",
        };
        let mut p = into_blocks(&format!("{shown} {what}"), file.raw)?;
        p.reference_r = file.reference_r;
        p.global = file.global;
        p.stored_triangle = file.stored_triangle;
        return Ok(p);
    }
    if is("toml") {
        return Err(format!(
            "{shown}: a .toml file is a scene, solved by `signorini run`; {FORMATS}"
        ));
    }
    let raw = if is("npz") {
        read_npz(path, budget)?
    } else {
        read_json(path)?
    };
    into_blocks(&shown, raw)
}

impl LocalProblem {
    /// A problem given in the contact-wise layout (`dim` rows per contact,
    /// `mu` per contact or empty), checked as a file would be; `name` is
    /// the problem's name in messages.
    pub fn contact_wise(
        name: &str,
        w: Mat<f64>,
        q: Vec<f64>,
        mu: Vec<f64>,
        dim: usize,
    ) -> Result<Self, String> {
        if w.nrows() != q.len() || w.ncols() != q.len() {
            return Err(format!("{name}: W must be {0} × {0} to match q", q.len()));
        }
        let raw = Raw {
            w,
            q,
            mu: Some(mu),
            dim: Some(dim as f64),
            normal_first: false,
        };
        into_blocks(name, raw)
    }
}

/// Checks a problem and puts its rows in the block layout.
fn into_blocks(shown: &str, raw: Raw) -> Result<LocalProblem, String> {
    let asymmetry = check_values(shown, &raw.w, &raw.q)?;
    let (dim, file_row) = resolve_layout(shown, &raw)?;
    let w = Mat::<f64>::from_fn(file_row.len(), file_row.len(), |i, j| {
        raw.w[(file_row[i], file_row[j])]
    });
    let q = file_row.iter().map(|&r| raw.q[r]).collect();
    let mu = raw.mu.filter(|mu| !mu.is_empty());
    Ok(LocalProblem {
        w,
        q,
        dim,
        mu,
        file_row,
        reference_r: None,
        global: None,
        asymmetry,
        stored_triangle: None,
    })
}

/// A .npy v1.0 file of little-endian float64 in C or (`fortran`) column
/// order (the format NumPy writes).
pub(crate) fn npy_bytes(shape: &[usize], fortran: bool, data: &[f64]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape = match dims.len() {
        0 => "()".to_string(),
        1 => format!("({},)", dims[0]),
        _ => format!("({})", dims.join(", ")),
    };
    let order = if fortran { "True" } else { "False" };
    let mut header = format!("{{'descr': '<f8', 'fortran_order': {order}, 'shape': {shape}, }}");
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

/// Writes a problem in the contact-wise layout as `.npz` (W, q, mu, dim),
/// readable by [`load`] and by NumPy (`numpy.load`).
pub fn write_npz(
    path: &Path,
    w: &Mat<f64>,
    q: &[f64],
    mu: &[f64],
    dim: usize,
) -> Result<(), String> {
    let shown = path.display();
    let io = |e: std::io::Error| format!("cannot write {shown}: {e}");
    let n = q.len();
    let data: Vec<f64> = (0..n * n).map(|k| w[(k / n, k % n)]).collect();
    let file = std::fs::File::create(path).map_err(io)?;
    let mut z = zip::ZipWriter::new(file);
    let o = zip::write::SimpleFileOptions::default();
    let arrays: [(&str, Vec<usize>, &[f64]); 4] = [
        ("W", vec![n, n], &data),
        ("q", vec![n], q),
        ("mu", vec![mu.len()], mu),
        ("dim", vec![], &[dim as f64]),
    ];
    for (name, shape, values) in arrays {
        z.start_file(format!("{name}.npy"), o)
            .map_err(|e| format!("cannot write {shown}: {e}"))?;
        z.write_all(&npy_bytes(&shape, false, values)).map_err(io)?;
    }
    z.finish()
        .map_err(|e| format!("cannot write {shown}: {e}"))?;
    Ok(())
}

#[cfg(test)]
mod tests;
