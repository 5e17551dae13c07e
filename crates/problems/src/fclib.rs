//! FCLib local and global problems (the HDF5 format Siconos and the
//! Frictional Contact Library exchange problems in) for `signorini local`.
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
//! A W with one strictly triangular part empty is a symmetric W stored as
//! the other triangle (`fclib/stored_triangle.rs`), completed by symmetry.
//!
//! A global problem (`/fclib_global`: M, H, f, w, mu) is condensed into a
//! local one by [`condense_global`], which reads its sparse matrices with
//! the same reader ([`entries`]).
//!
//! What `signorini local` cannot solve is refused, naming the file and the
//! dataset: a mixed problem (`V`, `R`), a `spacedim` other than 2 or 3, a
//! W that is not square, indices out of range, arrays shorter than their
//! sizes say, a dense W past the memory
//! budget (checked from `m` before anything of its size is allocated), and
//! through `problem_file.rs`'s checks every other value (finite,
//! rows a multiple of `spacedim`, μ per contact, finite, ≥ 0). A W that is
//! not symmetric is read as it is: the methods that need symmetry refuse it
//! (`local.rs`).

use std::path::Path;

use faer::Mat;
use hdf5_reader::error::Error;
use hdf5_reader::{Dataset, Datatype, Hdf5File, OpenOptions};

use signorini_report::budget::{human, Budget};

use crate::raw::{regular_file, Raw, NPY_COPIES};

mod condense_global;
mod equality_constraints;
mod stored_triangle;
pub use condense_global::{GlobalCondensation, GlobalSummary};

const LOCAL: &str = "/fclib_local";
const GLOBAL: &str = "/fclib_global";
const W: &str = "/fclib_local/W";

/// An FCLib problem, before its layout is resolved, and the forces r of
/// the file's `/solution` (contact-wise, the file's order); a global
/// problem also gives what its condensation kept ([`GlobalCondensation`]).
pub(crate) struct FclibProblem {
    pub raw: Raw,
    pub reference_r: Option<Vec<f64>>,
    pub global: Option<GlobalCondensation>,
    /// W (local) or M (global) was stored as this triangle of a symmetric
    /// matrix ([`stored_triangle`]).
    pub stored_triangle: Option<&'static str>,
}

impl FclibProblem {
    /// The contact-wise problem W, q, μ of `dim` rows per contact (FCLib's
    /// layout), with the file's reference forces and, for a global problem,
    /// its condensation.
    fn contact_wise(
        (w, q, mu, dim): (Mat<f64>, Vec<f64>, Vec<f64>, usize),
        reference_r: Option<Vec<f64>>,
        global: Option<GlobalCondensation>,
    ) -> Self {
        let raw = Raw {
            w,
            q,
            mu: Some(mu),
            dim: Some(dim as f64),
            normal_first: false,
        };
        Self {
            raw,
            reference_r,
            global,
            stored_triangle: None,
        }
    }
}

/// Reads `/fclib_local` (and `/solution/r`) of an FCLib file, or condenses
/// its `/fclib_global` ([`condense_global`]).
pub(crate) fn read(path: &Path, budget: Option<Budget>) -> Result<FclibProblem, String> {
    regular_file(path)?;
    let shown = path.display().to_string();
    let f = Reader::open(path, &shown, budget)?;
    if f.is_global()? {
        return condense_global::read(&f);
    }
    let dim = spacedim(&f, LOCAL)?;
    let m = square_size(&f)?;
    // q first: a W whose m its file cannot back (q holds m numbers) is
    // refused before its dense m × m is allocated.
    let q = f.finite_vector(&format!("{LOCAL}/vectors/q"), m, "W has")?;
    let mu = f.floats(&format!("{LOCAL}/vectors/mu"))?;
    let reference_r = solution(&f, "r", m, "W has")?;
    let mut w = read_w(&f, m)?;
    let triangle = stored_triangle::complete_dense(&mut w);
    let mut p = FclibProblem::contact_wise((w, q, mu, dim), reference_r, None);
    p.stored_triangle = triangle.map(stored_triangle::Triangle::name);
    Ok(p)
}

/// `{problem}/spacedim`, 2 or 3.
fn spacedim(f: &Reader, problem: &str) -> Result<usize, String> {
    match f.int(&format!("{problem}/spacedim"))? {
        2 => Ok(2),
        3 => Ok(3),
        dim => Err(format!(
            "{}: {problem}/spacedim is {dim}: an FCLib problem has 2 or 3 rows per contact ([n, t] or [n, t1, t2])",
            f.shown
        )),
    }
}

/// `/solution/{name}` (forces r, velocities v), if the file has it: `len`
/// finite numbers (`rows` says whose, in messages: "W has").
fn solution(f: &Reader, name: &str, len: usize, rows: &str) -> Result<Option<Vec<f64>>, String> {
    if !f.has_group("/solution")? || !f.members("/solution")?.1.iter().any(|d| d == name) {
        return Ok(None);
    }
    f.finite_vector(&format!("/solution/{name}"), len, rows)
        .map(Some)
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
    dense_within_budget(f.budget, &format!("{shown}: {W} is {m} × {m}"), m as f64)?;
    usize::try_from(m).map_err(|_| format!("{shown}: {W}/m = {m} is too large"))
}

/// Refuses, with `what` first in the message, a dense m × m matrix whose
/// copies for a solve ([`NPY_COPIES`]) pass the memory budget.
fn dense_within_budget(budget: Option<Budget>, what: &str, m: f64) -> Result<(), String> {
    let bytes = 8.0 * m * m;
    match budget {
        Some(b) if NPY_COPIES as f64 * bytes > b.bytes as f64 => Err(format!(
            "{what}: held dense it takes {}, and solving it needs about {NPY_COPIES} times that, more than the {} {}",
            human(bytes),
            human(b.bytes as f64),
            b.source
        )),
        _ => Ok(()),
    }
}

/// The shape (`m` rows, `n` columns) of the sparse matrix group `group`.
fn shape(f: &Reader, group: &str) -> Result<(usize, usize), String> {
    let size = |what: &str| -> Result<usize, String> {
        let v = f.int(&format!("{group}/{what}"))?;
        usize::try_from(v).map_err(|_| {
            format!(
                "{}: {group}/{what} is {v}: a matrix has 0 or more rows and columns",
                f.shown
            )
        })
    };
    Ok((size("m")?, size("n")?))
}

/// How a sparse matrix is stored (its `nz`).
#[derive(Clone, Copy)]
enum Storage {
    Triplet(usize),
    Columns,
    Rows,
}

fn storage(f: &Reader, group: &str) -> Result<Storage, String> {
    match f.int(&format!("{group}/nz"))? {
        -1 => Ok(Storage::Columns),
        -2 => Ok(Storage::Rows),
        nz if nz >= 0 => usize::try_from(nz)
            .map(Storage::Triplet)
            .map_err(|_| format!("{}: {group}/nz = {nz} is too large", f.shown)),
        nz => Err(format!(
            "{}: {group}/nz is {nz}: FCLib's storages are nz ≥ 0 (triplets), -1 (compressed columns) or -2 (compressed rows)",
            f.shown
        )),
    }
}

/// The dense m × m W of the file's sparse one, duplicates summed.
fn read_w(f: &Reader, m: usize) -> Result<Mat<f64>, String> {
    let mut w = Mat::<f64>::zeros(m, m);
    entries(f, W, (m, m), |i, j, x| w[(i, j)] += x)?;
    Ok(w)
}

/// Calls `add(row, column, value)` for every stored entry of the sparse
/// matrix group `group` of shape (rows, columns), in the file's order
/// (duplicates are the caller's to sum), once its indices, pointers and
/// lengths are checked and its values are finite.
fn entries(
    f: &Reader,
    group: &str,
    (rows, cols): (usize, usize),
    mut add: impl FnMut(usize, usize, f64),
) -> Result<(), String> {
    let shown = f.shown;
    let storage = storage(f, group)?;
    let p = f.ints(&format!("{group}/p"))?;
    let i = f.ints(&format!("{group}/i"))?;
    let x = f.floats(&format!("{group}/x"))?;
    if let Some(k) = x.iter().position(|v| !v.is_finite()) {
        return Err(format!("{shown}: {group}/x[{k}] is not finite"));
    }
    let index = |name: &str, k: usize, v: i64, bound: usize, what: &str| {
        usize::try_from(v).ok().filter(|&v| v < bound).ok_or_else(|| {
            format!(
                "{shown}: {group}/{name}[{k}] = {v} is out of range: {group} is {rows} × {cols}, its {what} indices are 0 to {}",
                bound as i64 - 1
            )
        })
    };
    match storage {
        Storage::Triplet(nz) => {
            for (name, len) in [("i", i.len()), ("p", p.len()), ("x", x.len())] {
                if len < nz {
                    return Err(format!(
                        "{shown}: {group}/{name} has {len} entries, {group}/nz says {nz} triplets"
                    ));
                }
            }
            for k in 0..nz {
                let row = index("i", k, i[k], rows, "row")?;
                add(row, index("p", k, p[k], cols, "column")?, x[k]);
            }
        }
        Storage::Columns | Storage::Rows => {
            let by_columns = matches!(storage, Storage::Columns);
            let (outer, inner, what) = match by_columns {
                true => (cols, rows, "row"),
                false => (rows, cols, "column"),
            };
            let ranges = pointers(f, group, &p, outer, i.len().min(x.len()))?;
            for (a, range) in ranges.enumerate() {
                for k in range {
                    let b = index("i", k, i[k], inner, what)?;
                    match by_columns {
                        true => add(b, a, x[k]),
                        false => add(a, b, x[k]),
                    }
                }
            }
        }
    }
    Ok(())
}

/// The entries of each of the `outer` columns (or rows) of a compressed
/// matrix: `p` has outer + 1 pointers, non-decreasing, from 0 to at most
/// `len` (the entries `i` and `x` hold).
fn pointers<'a>(
    f: &Reader,
    group: &str,
    p: &'a [i64],
    outer: usize,
    len: usize,
) -> Result<impl Iterator<Item = std::ops::Range<usize>> + 'a, String> {
    let shown = f.shown;
    if p.len() != outer + 1 {
        return Err(format!(
            "{shown}: {group}/p has {} entries, a compressed matrix of {outer} columns (rows, compressed by rows) has {} pointers",
            p.len(),
            outer + 1
        ));
    }
    for k in 0..outer {
        if p[k] < 0 || p[k + 1] < p[k] {
            return Err(format!(
                "{shown}: {group}/p[{k}] = {} and {group}/p[{}] = {}: the pointers must start at 0 or more and never decrease",
                p[k],
                k + 1,
                p[k + 1]
            ));
        }
    }
    if p[outer] as u64 > len as u64 {
        return Err(format!(
            "{shown}: {group}/p[{outer}] = {} but {group}/i and {group}/x hold {len} entries",
            p[outer]
        ));
    }
    Ok(p.windows(2).map(|w| w[0] as usize..w[1] as usize))
}

/// An open HDF5 file and its name in messages.
struct Reader<'a> {
    file: Hdf5File,
    shown: &'a str,
    /// The memory a solve may use: larger datasets are refused unread.
    budget: Option<Budget>,
}

impl<'a> Reader<'a> {
    fn open(path: &Path, shown: &'a str, budget: Option<Budget>) -> Result<Self, String> {
        // The reader refuses, before allocating them, reads and chunks larger
        // than the share of the budget an array may take.
        let limit = budget
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
        Ok(Reader {
            file,
            shown,
            budget,
        })
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

    /// Whether the file holds a global problem (`/fclib_global`); a mixed
    /// problem, or neither a local nor a global one, is refused.
    fn is_global(&self) -> Result<bool, String> {
        let shown = self.shown;
        if self.has_group(GLOBAL)? {
            return Ok(true);
        }
        if !self.has_group(LOCAL)? {
            return Err(format!(
                "{shown}: no group {LOCAL} or {GLOBAL}: not an FCLib problem (a group {LOCAL} with spacedim, W and vectors/q, vectors/mu, or {GLOBAL} with spacedim, M, H and vectors/f, vectors/w, vectors/mu)"
            ));
        }
        let (groups, _) = self.members(LOCAL)?;
        if let Some(g) = groups.iter().find(|g| *g == "V" || *g == "R") {
            return Err(format!(
                "{shown}: {LOCAL}/{g}: a mixed FCLib problem (with V, R and s: equality constraints besides contact), which signorini local does not solve; give W, q and mu alone"
            ));
        }
        Ok(false)
    }

    fn dataset(&self, name: &str) -> Result<Dataset, String> {
        let d = self.file.dataset(name).map_err(|e| match not_found(&e) {
            true => format!("{}: no dataset {name}", self.shown),
            false => self.error(name, e),
        })?;
        // Compressed chunks can unpack to far more than the file: the
        // declared size must fit before anything is read.
        let elements = d.num_elements().map_err(|e| self.error(name, e))?;
        if let Some(b) = self.budget {
            if (NPY_COPIES * 8) as f64 * elements as f64 > b.bytes as f64 {
                return Err(format!(
                    "{}: {name} holds {elements} numbers, and solving needs about {NPY_COPIES} times their {}, more than the {} {}",
                    self.shown,
                    human(8.0 * elements as f64),
                    human(b.bytes as f64),
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

    /// The dataset `path`: `len` finite numbers (`whose` says whose rows, in
    /// messages: "W has").
    fn finite_vector(&self, path: &str, len: usize, whose: &str) -> Result<Vec<f64>, String> {
        let v = self.floats(path)?;
        if v.len() != len {
            return Err(format!(
                "{}: {path} has {} entries, {whose} {len} rows",
                self.shown,
                v.len()
            ));
        }
        if let Some(k) = v.iter().position(|x| !x.is_finite()) {
            return Err(format!("{}: {path}[{k}] is not finite", self.shown));
        }
        Ok(v)
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
