//! FCLib global problems, condensed into local ones for `signorini local`.
//!
//! A global problem (`/fclib_global`) couples the n velocities (or
//! displacements) v to the contact forces r and local velocities u (m rows,
//! contact-wise, [n, t] or [n, t1, t2] per contact, r in the Coulomb cone):
//!
//! ```text
//! M v = H r + f,    u = Hᵀ v + w,
//! ```
//!
//! M (n × n) symmetric positive definite, H (n × m). Eliminating
//! v = M⁻¹ (H r + f) leaves the local problem u = W r + q with
//!
//! ```text
//! W = Hᵀ M⁻¹ H   (m × m, dense),    q = Hᵀ M⁻¹ f + w,
//! ```
//!
//! solved like any FCLib local problem. M is factorised once by the sparse
//! supernodal Cholesky factorisation condensation uses, ordered as a
//! subdomain's interior is (the cheaper of AMD and nested dissection,
//! [`signorini_condense::ordering`]); the m columns of H are solved for in
//! blocks of [`BLOCK`], X = M⁻¹ H_B, and W_{:,B} = Hᵀ X. After the solve the
//! same factor recovers v = M⁻¹ (H r + f), compared with the file's
//! `/solution/v` when it has one.
//!
//! Equality constraints (`G` with p ≥ 1 columns, `vectors/b`: M v = H r +
//! G λ + f, Gᵀ v + b = 0) are eliminated with the same factor of M
//! ([`super::equality_constraints`]): W and q are then those of v
//! restricted to Gᵀ v + b = 0, and v satisfies the constraints. Refused,
//! naming the dataset: `spacedim` other than 2 or 3, M not square, H or G
//! without n rows, `f`, `w` or `b` of the wrong length or not finite, M not
//! symmetric (a symmetric M stored as one triangle is completed,
//! `stored_triangle.rs`; with entries in both triangles they must agree)
//! or not positive definite, a column
//! of G that depends on the others, and, before anything of its size is
//! allocated, a dense W, M⁻¹ G or a factor of M past the memory budget.

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, MatMut, Side};
use serde::Serialize;

use super::equality_constraints::{transpose_times, EqualityConstraints};
use super::stored_triangle::{complete_sparse, Triangle};
use super::{
    dense_within_budget, entries, shape, solution, spacedim, FclibProblem, Reader, GLOBAL,
};
use signorini_report::budget::{human, Budget};

use crate::raw::NPY_COPIES;

const M: &str = "/fclib_global/M";
const H: &str = "/fclib_global/H";
const G: &str = "/fclib_global/G";

/// Columns of H solved for at once (a block of n × `BLOCK` right-hand sides).
pub const BLOCK: usize = 64;

/// What the condensation of a global problem keeps: the factor of M, H and
/// f (to recover v), the file's `/solution/v`, sizes and time.
pub struct GlobalCondensation {
    n: usize,
    nnz_m: usize,
    condense_s: f64,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    h: SparseColMat<usize, f64>,
    f: Vec<f64>,
    equality: Option<EqualityConstraints>,
    reference_v: Option<Vec<f64>>,
}

impl std::fmt::Debug for GlobalCondensation {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        out.debug_struct("GlobalCondensation")
            .field("summary", &self.summary())
            .finish_non_exhaustive()
    }
}

/// The global problem in the JSON line of `signorini local`.
#[derive(Debug, Clone, Serialize)]
pub struct GlobalSummary {
    /// Rows of M (degrees of freedom).
    pub n: usize,
    /// Stored entries of M (duplicates summed).
    #[serde(rename = "nnz_M")]
    pub nnz_m: usize,
    /// Stored entries of H.
    #[serde(rename = "nnz_H")]
    pub nnz_h: usize,
    /// Equality constraints (columns of G), eliminated.
    pub constraints: usize,
    /// Stored values of M's Cholesky factor.
    pub factor_values: usize,
    /// Time to factorise M and form W and q.
    pub condense_s: f64,
}

/// Reads `/fclib_global`, checks it and condenses it (module doc).
pub(super) fn read(f: &Reader) -> Result<FclibProblem, String> {
    let shown = f.shown;
    let dim = spacedim(f, GLOBAL)?;
    let (n, m) = sizes(f)?;
    let p = constraint_count(f, n)?;
    // The vectors first: n and m are backed by arrays the file holds
    // before anything of their size (pointers, W) is allocated.
    let load = vector(f, "f", n, "M has")?;
    let w = vector(f, "w", m, "H has")?;
    dense_within_budget(
        f.budget,
        &format!("{shown}: {H} is {n} × {m}: the condensed W = H^T M^-1 H is {m} × {m}"),
        m as f64,
    )?;
    let mu = f.floats(&format!("{GLOBAL}/vectors/mu"))?;
    let b = match p {
        0 => Vec::new(),
        _ => vector(f, "b", p, "one per column of G: G^T has")?,
    };
    let (mass, triangle) = complete_sparse(sparse(f, M, (n, n))?);
    check_symmetric(shown, &mass)?;
    let h = sparse(f, H, (n, m))?;
    let constraints = match p {
        0 => None,
        _ => Some(sparse(f, G, (n, p))?),
    };
    let reference_r = solution(f, "r", m, "H has")?;
    let reference_v = solution(f, "v", n, "M has")?;
    let t = Instant::now();
    let (symbolic, l_values) = factorise(shown, &mass, (m, p), f.budget)?;
    let mut g = GlobalCondensation {
        n,
        nnz_m: mass.compute_nnz(),
        condense_s: 0.0,
        symbolic,
        l_values,
        h,
        f: load,
        equality: None,
        reference_v,
    };
    if let Some(gm) = constraints {
        let solve = |x: MatMut<'_, f64>| g.solve_in_place(x);
        g.equality = Some(EqualityConstraints::new(shown, G, gm, b, solve)?);
    }
    let (wm, q) = g.condense(&w, BLOCK);
    g.condense_s = t.elapsed().as_secs_f64();
    let mut p = FclibProblem::contact_wise((wm, q, mu, dim), reference_r, Some(g));
    p.stored_triangle = triangle.map(Triangle::name);
    Ok(p)
}

/// The columns p of `G` (0 without one): its rows must be M's n, and p
/// at most n (more constraints than unknowns are dependent).
fn constraint_count(f: &Reader, n: usize) -> Result<usize, String> {
    if !f.has_group(G)? {
        return Ok(0);
    }
    let (rows, p) = shape(f, G)?;
    if p > 0 && rows != n {
        return Err(format!(
            "{}: {G} is {rows} × {p} ({G}/m, {G}/n) but {M} is {n} × {n}: G has a row per row of M",
            f.shown
        ));
    }
    if p > n {
        return Err(format!(
            "{}: {G} has {p} columns, more equality constraints than the {n} unknowns of {M}: some depend on the others",
            f.shown
        ));
    }
    Ok(p)
}

/// (n, m): M is n × n, H is n × m.
fn sizes(f: &Reader) -> Result<(usize, usize), String> {
    let shown = f.shown;
    let (n, n2) = shape(f, M)?;
    if n != n2 || n == 0 {
        return Err(format!(
            "{shown}: {M} is {n} × {n2} ({M}/m, {M}/n): a global problem's M is square, n × n with n ≥ 1"
        ));
    }
    let (rows, m) = shape(f, H)?;
    if rows != n {
        return Err(format!(
            "{shown}: {H} is {rows} × {m} ({H}/m, {H}/n) but {M} is {n} × {n}: H has a row per row of M"
        ));
    }
    Ok((n, m))
}

/// `/fclib_global/vectors/{name}`: `len` finite numbers.
fn vector(f: &Reader, name: &str, len: usize, whose: &str) -> Result<Vec<f64>, String> {
    f.finite_vector(&format!("{GLOBAL}/vectors/{name}"), len, whose)
}

/// The sparse matrix group `group` of the given shape, duplicates summed.
fn sparse(
    f: &Reader,
    group: &str,
    shape: (usize, usize),
) -> Result<SparseColMat<usize, f64>, String> {
    let mut triplets = Vec::new();
    entries(f, group, shape, |i, j, x| {
        triplets.push(Triplet::new(i, j, x))
    })?;
    SparseColMat::try_new_from_triplets(shape.0, shape.1, &triplets)
        .map_err(|e| format!("{}: {group} cannot be assembled ({e:?})", f.shown))
}

/// M equals its transpose to 1e-10 max |M| (the Cholesky factorisation of
/// the condensation needs a symmetric M).
fn check_symmetric(shown: &str, mass: &SparseColMat<usize, f64>) -> Result<(), String> {
    let scale = mass.val().iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for j in 0..mass.ncols() {
        let rows = mass.row_idx_of_col_raw(j).iter();
        for (&i, &v) in rows.zip(mass.val_of_col(j)) {
            let t = mass.get(j, i).copied().unwrap_or(0.0);
            if (v - t).abs() > 1e-10 * scale {
                return Err(format!(
                    "{shown}: {M} is not symmetric (M[{i}][{j}] = {v} but M[{j}][{i}] = {t}): its condensation W = H^T M^-1 H factorises M by Cholesky, which needs a symmetric positive definite M, stored in full or as one triangle"
                ));
            }
        }
    }
    Ok(())
}

/// The ordered symbolic and numerical Cholesky factor of M, refused when
/// it (with a block of right-hand sides and W) passes the memory budget,
/// or when M is not positive definite.
fn factorise(
    shown: &str,
    mass: &SparseColMat<usize, f64>,
    (m, p): (usize, usize),
    budget: Option<Budget>,
) -> Result<(SymbolicCholesky<usize>, Vec<f64>), String> {
    use signorini_condense::ordering::{order_and_analyse, OrderingChoice};
    let n = mass.nrows();
    let ordered = order_and_analyse(mass.as_ref(), n, OrderingChoice::Auto)
        .map_err(|e| format!("{shown}: {M} cannot be ordered for its factorisation ({e})"))?;
    let values = ordered.symbolic.len_val();
    let bytes = 8.0 * (values as f64 + (n * BLOCK.min(m)) as f64 + (n as f64) * (p as f64))
        + (NPY_COPIES * 8) as f64 * (m as f64) * (m as f64);
    if let Some(b) = budget {
        if bytes > b.bytes as f64 {
            return Err(format!(
                "{shown}: {M} ({n} × {n}) has a Cholesky factor of {values} values: with W (and M^-1 G) it takes {}, more than the {} {}",
                human(bytes),
                human(b.bytes as f64),
                b.source
            ));
        }
    }
    let mut l_values = vec![0.0f64; values];
    let par = faer::get_global_parallelism();
    let mut mem = MemBuffer::new(
        ordered
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default()),
    );
    let outcome = ordered.symbolic.factorize_numeric_llt::<f64>(
        &mut l_values,
        mass.as_ref(),
        Side::Lower,
        LltRegularization::default(),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    );
    match outcome {
        Ok(_) => Ok((ordered.symbolic, l_values)),
        Err(LltError::NonPositivePivot { index }) => Err(format!(
            "{shown}: {M} is not positive definite: its Cholesky factorisation meets a pivot <= 0 at row {} (a free rigid-body motion, a zero mass?)",
            ordered.fwd.get(index).copied().unwrap_or(index)
        )),
    }
}

impl GlobalCondensation {
    /// Overwrites the n × k block `x` with M⁻¹ x.
    fn solve_in_place(&self, x: MatMut<'_, f64>) {
        let par = faer::get_global_parallelism();
        let k = x.ncols();
        let mut mem = MemBuffer::new(StackReq::any_of(&[self
            .symbolic
            .solve_in_place_scratch::<f64>(k, par)]));
        LltRef::<usize, f64>::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            x,
            par,
            MemStack::new(&mut mem),
        );
    }

    /// W = Hᵀ M⁻¹ H (symmetrised) and q = Hᵀ M⁻¹ f + w, by blocks of
    /// `block` columns of H; with equality constraints, W and q of v
    /// restricted to them ([`EqualityConstraints`]).
    fn condense(&self, w: &[f64], block: usize) -> (Mat<f64>, Vec<f64>) {
        let (n, m) = (self.n, self.h.ncols());
        let mut wm = Mat::<f64>::zeros(m, m);
        let mut x = Mat::<f64>::zeros(n, block.min(m).max(1));
        for start in (0..m).step_by(block) {
            let b = block.min(m - start);
            x.fill(0.0);
            for c in 0..b {
                let rows = self.h.row_idx_of_col_raw(start + c).iter();
                for (&k, &v) in rows.zip(self.h.val_of_col(start + c)) {
                    x[(k, c)] = v;
                }
            }
            self.solve_in_place(x.as_mut().subcols_mut(0, b));
            let hx = transpose_times(&self.h, x.as_ref().subcols(0, b));
            wm.as_mut().subcols_mut(start, b).copy_from(&hx);
        }
        if let Some(e) = &self.equality {
            e.reduce_delassus(&self.h, &mut wm);
        }
        for j in 0..m {
            for i in j + 1..m {
                let mean = 0.5 * (wm[(i, j)] + wm[(j, i)]);
                wm[(i, j)] = mean;
                wm[(j, i)] = mean;
            }
        }
        let v0 = self.velocity(&[]);
        let hv = transpose_times(&self.h, faer::MatRef::from_column_major_slice(&v0, n, 1));
        let q = (0..m).map(|i| hv[(i, 0)] + w[i]).collect();
        (wm, q)
    }

    /// v = M⁻¹ (H r + f) for forces r (contact-wise, the file's order; a
    /// shorter r is completed by zeros), with equality constraints the v
    /// that also satisfies Gᵀ v + b = 0 (M v = H r + G λ + f).
    pub fn velocity(&self, r: &[f64]) -> Vec<f64> {
        let mut v = Mat::<f64>::from_fn(self.n, 1, |k, _| self.f[k]);
        for (i, &ri) in r.iter().enumerate().take(self.h.ncols()) {
            let rows = self.h.row_idx_of_col_raw(i).iter();
            for (&k, &hv) in rows.zip(self.h.val_of_col(i)) {
                v[(k, 0)] += hv * ri;
            }
        }
        self.solve_in_place(v.as_mut());
        let mut v: Vec<f64> = (0..self.n).map(|k| v[(k, 0)]).collect();
        if let Some(e) = &self.equality {
            e.project(&mut v);
        }
        v
    }

    /// With the file's `/solution/v`: ‖v − v_ref‖₂ / ‖v_ref‖₂ (the floor
    /// of the denominator the smallest positive number) for the v that
    /// forces r (the file's order) give.
    pub fn reference_v_error(&self, r: &[f64]) -> Option<f64> {
        let reference = self.reference_v.as_ref()?;
        let v = self.velocity(r);
        let norm = |it: &mut dyn Iterator<Item = f64>| it.map(|x| x * x).sum::<f64>().sqrt();
        let diff = norm(&mut v.iter().zip(reference).map(|(a, b)| a - b));
        Some(diff / norm(&mut reference.iter().copied()).max(f64::MIN_POSITIVE))
    }

    /// Sizes and time, for the JSON line.
    pub fn summary(&self) -> GlobalSummary {
        GlobalSummary {
            n: self.n,
            nnz_m: self.nnz_m,
            nnz_h: self.h.compute_nnz(),
            constraints: self.equality.as_ref().map_or(0, |e| e.len()),
            factor_values: self.l_values.len(),
            condense_s: self.condense_s,
        }
    }
}

#[cfg(test)]
mod tests {
    use signorini_report::budget::machine_memory;

    /// Blocks of any width, dividing m or not, give the same W and q.
    #[test]
    fn every_block_width_gives_the_same_condensation() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../tests/data/fclib/global3d.hdf5");
        let p = super::super::read(&path, machine_memory()).unwrap();
        let g = p.global.unwrap();
        let m = p.raw.q.len();
        let w: Vec<f64> = vec![0.0; m];
        let (w1, q1) = g.condense(&w, 1);
        for block in [5, 12, 64] {
            let (wb, qb) = g.condense(&w, block);
            assert!((&wb - &w1).norm_max() <= 1e-15 * w1.norm_max(), "{block}");
            assert_eq!(qb, q1, "{block}");
        }
        // With the file's w: the W and q the problem was given.
        assert!((&w1 - &p.raw.w).norm_max() <= 1e-15 * w1.norm_max());
    }
}
