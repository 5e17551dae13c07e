//! FCLib local problems (the HDF5 format Siconos and the Frictional Contact
//! Library exchange problems in) for `signorini local`.
//!
//! A file holds a group `/fclib_local` with `spacedim` (2 or 3), the
//! Delassus operator `W` as a sparse matrix group (integers `m`, `n`, `nz`,
//! `nzmax`, arrays `p`, `i`, `x`: `nz` ≥ 0 triplets, CSparse's (`i` the
//! rows, `p` the columns, duplicates summed), `nz` = −1 compressed columns
//! (`p` the n + 1 column pointers, `i` the rows), `nz` = −2 compressed rows
//! (`p` the m + 1 row pointers, `i` the columns)), and `vectors/q`,
//! `vectors/mu`; rows contact-wise, [n, t] or [n, t1, t2], u = W r + q with
//! r in the Coulomb cone: this project's contact-wise layout and sign (λ ≥ 0
//! compressive, gap g = Wλ + q). An optional `/solution/r` is another
//! solver's forces, compared with ours in the JSON line.
//!
//! What `signorini local` cannot solve is refused, naming the file and the
//! dataset: a global problem (`/fclib_global`), a mixed one (`V`, `R`), a
//! `spacedim` other than 2 or 3, a W that is not square, indices out of
//! range, arrays shorter than their sizes say, a dense W past the memory
//! budget (checked from `m` before anything of its size is allocated), and
//! through [`crate::problem_file`]'s checks every other value (finite,
//! symmetric W, rows a multiple of `spacedim`, μ per contact, finite, ≥ 0).

use std::path::Path;

use faer::Mat;
use hdf5_reader::error::Error;
use hdf5_reader::{Dataset, Datatype, Hdf5File, OpenOptions};

use crate::problem_file::{regular_file, Raw, NPY_COPIES};

const LOCAL: &str = "/fclib_local";
const W: &str = "/fclib_local/W";

/// An FCLib local problem, before its layout is resolved, and the forces
/// r of the file's `/solution` (contact-wise, the file's order).
pub(crate) struct FclibProblem {
    pub raw: Raw,
    pub reference_r: Option<Vec<f64>>,
}

/// Reads `/fclib_local` (and `/solution/r`) of an FCLib file.
pub(crate) fn read(path: &Path) -> Result<FclibProblem, String> {
    regular_file(path)?;
    let shown = path.display().to_string();
    let f = Reader::open(path, &shown)?;
    f.refuse_what_is_not_local()?;
    let dim = f.int(&format!("{LOCAL}/spacedim"))?;
    if !(dim == 2 || dim == 3) {
        return Err(format!(
            "{shown}: {LOCAL}/spacedim is {dim}: an FCLib problem has 2 or 3 rows per contact ([n, t] or [n, t1, t2])"
        ));
    }
    let m = square_size(&f)?;
    // q first: a W whose m its file cannot back (q holds m numbers) is
    // refused before its dense m × m is allocated.
    let q = f.floats(&format!("{LOCAL}/vectors/q"))?;
    if q.len() != m {
        return Err(format!(
            "{shown}: {LOCAL}/vectors/q has {} entries, W has {m} rows",
            q.len()
        ));
    }
    let mu = f.floats(&format!("{LOCAL}/vectors/mu"))?;
    let reference_r = solution_r(&f, m)?;
    let w = read_w(&f, m)?;
    let raw = Raw {
        w,
        q,
        mu: Some(mu),
        dim: Some(dim as f64),
        normal_first: false,
    };
    Ok(FclibProblem { raw, reference_r })
}

/// The forces of `/solution/r`, if the file has them.
fn solution_r(f: &Reader, m: usize) -> Result<Option<Vec<f64>>, String> {
    if !f.has_group("/solution")? || !f.members("/solution")?.1.iter().any(|d| d == "r") {
        return Ok(None);
    }
    let r = f.floats("/solution/r")?;
    if r.len() != m {
        return Err(format!(
            "{}: /solution/r has {} entries, W has {m} rows",
            f.shown,
            r.len()
        ));
    }
    if let Some(k) = r.iter().position(|v| !v.is_finite()) {
        return Err(format!("{}: /solution/r[{k}] is not finite", f.shown));
    }
    Ok(Some(r))
}

/// W's order m: W square, and its dense copies within the memory budget.
fn square_size(f: &Reader) -> Result<usize, String> {
    let shown = f.shown;
    let (m, n) = (f.int(&format!("{W}/m"))?, f.int(&format!("{W}/n"))?);
    if m != n || m < 0 {
        return Err(format!(
            "{shown}: {W} is {m} × {n} ({W}/m, {W}/n): the Delassus operator of a local problem is square, m × m with m ≥ 0"
        ));
    }
    let bytes = 8.0 * (m as f64) * (m as f64);
    if let Some(b) = crate::memory::budget() {
        if NPY_COPIES as f64 * bytes > b.bytes as f64 {
            return Err(format!(
                "{shown}: {W} is {m} × {m}: held dense it takes {}, and solving it needs about {NPY_COPIES} times that, more than the {} {}",
                crate::memory::human(bytes),
                crate::memory::human(b.bytes as f64),
                b.source
            ));
        }
    }
    usize::try_from(m).map_err(|_| format!("{shown}: {W}/m = {m} is too large"))
}

/// How W is stored (`W/nz`).
#[derive(Clone, Copy)]
enum Storage {
    Triplet(usize),
    Columns,
    Rows,
}

/// The dense m × m W of the file's sparse one, duplicates summed.
fn read_w(f: &Reader, m: usize) -> Result<Mat<f64>, String> {
    let shown = f.shown;
    let storage = match f.int(&format!("{W}/nz"))? {
        -1 => Storage::Columns,
        -2 => Storage::Rows,
        nz if nz >= 0 => Storage::Triplet(nz as usize),
        nz => {
            return Err(format!(
                "{shown}: {W}/nz is {nz}: FCLib's storages are nz ≥ 0 (triplets), -1 (compressed columns) or -2 (compressed rows)"
            ))
        }
    };
    let p = f.ints(&format!("{W}/p"))?;
    let i = f.ints(&format!("{W}/i"))?;
    let x = f.floats(&format!("{W}/x"))?;
    if let Some(k) = x.iter().position(|v| !v.is_finite()) {
        return Err(format!("{shown}: {W}/x[{k}] is not finite"));
    }
    let mut w = Mat::<f64>::zeros(m, m);
    let index = |name: &str, k: usize, v: i64| index(shown, m, name, k, v);
    match storage {
        Storage::Triplet(nz) => {
            for (name, len) in [("i", i.len()), ("p", p.len()), ("x", x.len())] {
                if len < nz {
                    return Err(format!(
                        "{shown}: {W}/{name} has {len} entries, {W}/nz says {nz} triplets"
                    ));
                }
            }
            for k in 0..nz {
                w[(index("i", k, i[k])?, index("p", k, p[k])?)] += x[k];
            }
        }
        Storage::Columns | Storage::Rows => {
            let ranges = pointers(shown, &p, m, i.len().min(x.len()))?;
            for (a, range) in ranges.enumerate() {
                for k in range {
                    let b = index("i", k, i[k])?;
                    let (row, col) = if let Storage::Columns = storage {
                        (b, a)
                    } else {
                        (a, b)
                    };
                    w[(row, col)] += x[k];
                }
            }
        }
    }
    Ok(w)
}

/// The entry k of W/`name`, a row or column index of an m × m W.
fn index(shown: &str, m: usize, name: &str, k: usize, v: i64) -> Result<usize, String> {
    usize::try_from(v).ok().filter(|&v| v < m).ok_or_else(|| {
        format!(
            "{shown}: {W}/{name}[{k}] = {v} is out of range: W is {m} × {m}, its indices are 0 to {}",
            m.saturating_sub(1)
        )
    })
}

/// The entries of each of the m columns (or rows) of a compressed W:
/// `p` has m + 1 pointers, non-decreasing, from 0 to at most `len`
/// (the entries `i` and `x` hold).
fn pointers<'a>(
    shown: &str,
    p: &'a [i64],
    m: usize,
    len: usize,
) -> Result<impl Iterator<Item = std::ops::Range<usize>> + 'a, String> {
    if p.len() != m + 1 {
        return Err(format!(
            "{shown}: {W}/p has {} entries, a compressed {m} × {m} W has {} pointers",
            p.len(),
            m + 1
        ));
    }
    for k in 0..m {
        if p[k] < 0 || p[k + 1] < p[k] {
            return Err(format!(
                "{shown}: {W}/p[{k}] = {} and {W}/p[{}] = {}: the pointers must start at 0 or more and never decrease",
                p[k],
                k + 1,
                p[k + 1]
            ));
        }
    }
    if p[m] as u64 > len as u64 {
        return Err(format!(
            "{shown}: {W}/p[{m}] = {} but {W}/i and {W}/x hold {len} entries",
            p[m]
        ));
    }
    Ok(p.windows(2).map(|w| w[0] as usize..w[1] as usize))
}

/// An open HDF5 file and its name in messages.
struct Reader<'a> {
    file: Hdf5File,
    shown: &'a str,
}

impl<'a> Reader<'a> {
    fn open(path: &Path, shown: &'a str) -> Result<Self, String> {
        // The reader refuses, before allocating them, reads and chunks larger
        // than the share of the budget an array may take.
        let limit = crate::memory::budget()
            .map(|b| usize::try_from(b.bytes / NPY_COPIES).unwrap_or(usize::MAX))
            .unwrap_or(usize::MAX);
        let options = OpenOptions::default()
            .with_max_read_bytes(limit)
            .with_max_chunk_bytes(limit.min(hdf5_reader::DEFAULT_MAX_CHUNK_BYTES))
            .with_chunk_cache_bytes(1 << 20);
        let file = Hdf5File::open_with_options(path, options).map_err(|e| match e {
            Error::Io(e) => format!("cannot read {shown}: {e}"),
            e => format!("{shown}: not an HDF5 file, or a damaged one ({e}); FCLib problems are HDF5 files with a group {LOCAL}"),
        })?;
        Ok(Reader { file, shown })
    }

    /// Whether the group exists (an error if the file cannot tell).
    fn has_group(&self, path: &str) -> Result<bool, String> {
        match self.file.group(path) {
            Ok(_) => Ok(true),
            Err(e) if not_found(&e) => Ok(false),
            Err(e) => Err(self.error(path, e)),
        }
    }

    /// The names of a group's groups and datasets.
    fn members(&self, path: &str) -> Result<(Vec<String>, Vec<String>), String> {
        self.file
            .group(path)
            .and_then(|g| g.member_names())
            .map_err(|e| self.error(path, e))
    }

    /// A global or mixed problem, or no local one, is refused.
    fn refuse_what_is_not_local(&self) -> Result<(), String> {
        let shown = self.shown;
        if self.has_group("/fclib_global")? {
            return Err(format!(
                "{shown}: an FCLib global problem (/fclib_global: M, H, f, w): signorini local solves local problems ({LOCAL}: W, q, mu); condense it first (W = H^T M^-1 H, q = H^T M^-1 f + w)"
            ));
        }
        if !self.has_group(LOCAL)? {
            return Err(format!(
                "{shown}: no group {LOCAL}: not an FCLib local problem (a group {LOCAL} with spacedim, W and vectors/q, vectors/mu)"
            ));
        }
        let (groups, _) = self.members(LOCAL)?;
        if let Some(g) = groups.iter().find(|g| *g == "V" || *g == "R") {
            return Err(format!(
                "{shown}: {LOCAL}/{g}: a mixed FCLib problem (with V, R and s: equality constraints besides contact), which signorini local does not solve; give W, q and mu alone"
            ));
        }
        Ok(())
    }

    fn dataset(&self, name: &str) -> Result<Dataset, String> {
        let d = self.file.dataset(name).map_err(|e| match not_found(&e) {
            true => format!("{}: no dataset {name}", self.shown),
            false => self.error(name, e),
        })?;
        // Compressed chunks can unpack to far more than the file: the
        // declared size must fit before anything is read.
        let elements = d.num_elements().map_err(|e| self.error(name, e))?;
        if let Some(b) = crate::memory::budget() {
            if (NPY_COPIES * 8) as f64 * elements as f64 > b.bytes as f64 {
                return Err(format!(
                    "{}: {name} holds {elements} numbers, and solving needs about {NPY_COPIES} times their {}, more than the {} {}",
                    self.shown,
                    crate::memory::human(8.0 * elements as f64),
                    crate::memory::human(b.bytes as f64),
                    b.source
                ));
            }
        }
        Ok(d)
    }

    fn error(&self, name: &str, e: Error) -> String {
        format!(
            "{}: {name} cannot be read: a damaged or truncated file? ({e})",
            self.shown
        )
    }

    /// A dataset of numbers (floating point or integer) as f64.
    fn floats(&self, name: &str) -> Result<Vec<f64>, String> {
        let d = self.dataset(name)?;
        let e = |e| self.error(name, e);
        match d.dtype() {
            Datatype::FloatingPoint { size: 8, .. } => d
                .read_array::<f64>()
                .map(|a| a.into_iter().collect())
                .map_err(e),
            Datatype::FloatingPoint { size: 4, .. } => d
                .read_array::<f32>()
                .map(|a| a.into_iter().map(f64::from).collect())
                .map_err(e),
            Datatype::FixedPoint { .. } => {
                Ok(self.ints(name)?.into_iter().map(|v| v as f64).collect())
            }
            other => Err(format!(
                "{}: {name} holds {other:?}, not numbers (float64 or integers)",
                self.shown
            )),
        }
    }

    /// A dataset of integers as i64 (an unsigned value past i64::MAX reads
    /// as i64::MAX, out of every range checked).
    fn ints(&self, name: &str) -> Result<Vec<i64>, String> {
        let d = self.dataset(name)?;
        fn all<T: hdf5_reader::H5Type + TryInto<i64>>(d: &Dataset) -> Result<Vec<i64>, Error> {
            let a = d.read_array::<T>()?;
            Ok(a.into_iter()
                .map(|v| v.try_into().unwrap_or(i64::MAX))
                .collect())
        }
        let other = |what: String| format!("{}: {name} holds {what}, not integers", self.shown);
        let &Datatype::FixedPoint { size, signed, .. } = d.dtype() else {
            return Err(other(format!("{:?}", d.dtype())));
        };
        let values = match (size, signed) {
            (1, true) => all::<i8>(&d),
            (1, false) => all::<u8>(&d),
            (2, true) => all::<i16>(&d),
            (2, false) => all::<u16>(&d),
            (4, true) => all::<i32>(&d),
            (4, false) => all::<u32>(&d),
            (8, true) => all::<i64>(&d),
            (8, false) => all::<u64>(&d),
            _ => return Err(other(format!("{size}-byte integers"))),
        };
        values.map_err(|e| self.error(name, e))
    }

    /// A dataset of one integer (FCLib writes a one-element array).
    fn int(&self, name: &str) -> Result<i64, String> {
        match self.ints(name)?[..] {
            [v] => Ok(v),
            ref v => Err(format!(
                "{}: {name} must be one integer, holds {} values",
                self.shown,
                v.len()
            )),
        }
    }
}

/// Whether an error says an object is absent (not that the file is damaged).
fn not_found(e: &Error) -> bool {
    match e {
        Error::GroupNotFound(_) | Error::DatasetNotFound(_) => true,
        Error::Context { source, .. } => not_found(source),
        _ => false,
    }
}

#[cfg(test)]
mod tests;
