//! The Cholesky factor of the active block W_AA that follows the active set
//! from one status iteration to the next (course notes §3.3): when few statuses
//! change, removing a row (a rank-one update of the trailing factor) and
//! appending one (a triangular solve) cost O(n²) each, against n³/3 for a
//! new factorisation; when the set repeats, the factor is reused as it is.
//!
//! With L Lᵀ = W_AA in the order of `rows`:
//! - removing row k leaves [L₁₁ 0; L₃₁ L₃₃'] with L₃₃' L₃₃'ᵀ = L₃₃ L₃₃ᵀ + l₃₂ l₃₂ᵀ;
//! - appending row r adds [l; d] with L l = W_A,r and d² = W_rr − lᵀl.
//!
//! Removing row k costs about 2 (n − k)² flops: a new factor orders its
//! rows by q, the nearly closed gaps (the points the status method releases,
//! at the edge of the contact zone) last, so that their removal touches only
//! a small trailing block and leaves the leading rows, and the forward
//! substitution y = L⁻¹ b on them, as they were. Whether to update or to
//! factorise afresh is decided by the cost of each ([`update_cost`]).
//!
//! An update whose new pivot is not safely positive gives up, and the caller
//! factorises afresh (or falls back to its rank-tested solve).

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Accum, Mat, Par, Side};

use crate::pivot_policy::cholesky_pivots_are_safe;

/// L Lᵀ = W restricted to `rows` (in that order).
#[derive(Debug, Clone)]
pub struct ActiveFactor {
    rows: Vec<usize>,
    l: Mat<f64>,
    forward: Forward,
}

/// The right-hand side b of the last [`ActiveFactor::solve_reusing`] and its
/// forward substitution y = L⁻¹ b, still valid on the first `valid` rows
/// (those before every row an update has touched since).
#[derive(Debug, Clone, Default)]
struct Forward {
    b: Vec<f64>,
    y: Vec<f64>,
    valid: usize,
}

/// W_AA λ_A = −q_A with the factor carried in `slot` from the previous
/// active set (updated, or made afresh when the change is large); λ on
/// every row (zero off A). `None` (and an empty slot) when W_AA is not
/// safely positive definite: the caller's rank-tested solve decides.
pub fn solve_on_active_set(
    slot: &mut Option<ActiveFactor>,
    w: &Mat<f64>,
    q: &[f64],
    active: &[usize],
) -> Option<Vec<f64>> {
    let updated = slot
        .take()
        .and_then(|mut f| f.update_to(w, active).then_some(f));
    let factor = match updated {
        Some(f) => f,
        None => ActiveFactor::new(w, &releases_last(q, active))?,
    };
    let mut factor = factor;
    let rhs: Vec<f64> = factor.rows.iter().map(|&p| -q[p]).collect();
    let x = factor.solve_reusing(&rhs);
    let mut lambda = vec![0.0; q.len()];
    for (&p, xi) in factor.rows.iter().zip(x) {
        lambda[p] = xi;
    }
    *slot = Some(factor);
    Some(lambda)
}

/// How many times longer a flop of the Givens sweeps of a row removal takes
/// than one of a fresh (blocked) Cholesky factorisation: 3–3.5 measured at
/// n ≈ 1000 (the sweeps are bound by the loads of L's columns, the
/// factorisation by the multiply-adds of its blocks).
const GIVENS_SLOWDOWN: f64 = 3.5;

/// The cost of an update of a factor of order n, in flops of a fresh
/// factorisation (n³/3 for order n): removing the row at position k rotates
/// the trailing (n − k)²/2 entries, 4 flops each at [`GIVENS_SLOWDOWN`];
/// appending e rows to the n' kept ones solves L X = W_{A,E} (n'² e), forms
/// W_EE − XᵀX (n' e²) and factorises it (e³/3).
fn update_cost(n: usize, leaving: &[usize], entering: usize) -> f64 {
    let removals: f64 = leaving
        .iter()
        .map(|&k| 2.0 * ((n - k) as f64).powi(2))
        .sum();
    let (kept, e) = ((n - leaving.len()) as f64, entering as f64);
    GIVENS_SLOWDOWN * removals + kept * kept * e + kept * e * e + e.powi(3) / 3.0
}

/// `active` in the order of q, the most penetrating points first (stable:
/// by index among equal gaps). The points whose gap is nearly closed, at the
/// edge of the contact zone, are those the status method releases: last in
/// the factor, their removal touches only a small trailing block.
fn releases_last(q: &[f64], active: &[usize]) -> Vec<usize> {
    let mut rows = active.to_vec();
    rows.sort_by(|&a, &b| q[a].total_cmp(&q[b]));
    rows
}

impl ActiveFactor {
    /// Factorises W on `rows`; `None` if not safely positive definite.
    pub fn new(w: &Mat<f64>, rows: &[usize]) -> Option<Self> {
        let n = rows.len();
        // The lower triangle of W on `rows`, column by column, factorised in
        // place (the upper triangle stays zero).
        let mut l = Mat::<f64>::zeros(n, n);
        for (j, &c) in rows.iter().enumerate() {
            let wc = w.col_as_slice(c);
            for (lij, &r) in l.col_as_slice_mut(j)[j..].iter_mut().zip(&rows[j..]) {
                *lij = wc[r];
            }
        }
        let par = faer::get_global_parallelism();
        crate::recursive_cholesky::cholesky(l.as_mut(), par).ok()?;
        let w_diag = rows.iter().map(|&r| w[(r, r)]);
        let safe = cholesky_pivots_are_safe((0..n).map(|i| l[(i, i)]), w_diag, n);
        safe.then(|| Self {
            rows: rows.to_vec(),
            l,
            forward: Forward::default(),
        })
    }

    /// The rows of the factor, in its order.
    pub fn rows(&self) -> &[usize] {
        &self.rows
    }

    /// Brings the factor to the set `target` (any order) by row removals
    /// and appends, if that costs less than a new factorisation
    /// ([`update_cost`]); `false` (factor unusable) if an update met a pivot
    /// that is not safely positive or the change is too large.
    pub fn update_to(&mut self, w: &Mat<f64>, target: &[usize]) -> bool {
        let n_max = w.nrows();
        let mut wanted = vec![false; n_max];
        target.iter().for_each(|&r| wanted[r] = true);
        let mut present = vec![false; n_max];
        self.rows.iter().for_each(|&r| present[r] = true);
        let leaving: Vec<usize> = (0..self.rows.len())
            .filter(|&k| !wanted[self.rows[k]])
            .collect();
        let entering: Vec<usize> = target.iter().copied().filter(|&r| !present[r]).collect();
        let fresh = (target.len() as f64).powi(3) / 3.0;
        if update_cost(self.rows.len(), &leaving, entering.len()) > fresh {
            return false;
        }
        self.remove(&leaving);
        self.append(w, &entering)
    }

    /// Removes the factor's rows and columns `leaving` (ascending), in
    /// place: one compaction of the kept entries (only the rows after the
    /// first removed one move), then for each removed k,
    /// from the last, the rank-one update of the trailing block by the kept
    /// part of L's column k below the diagonal (a later update touches only
    /// columns after its k, so every such column is L's original one).
    fn remove(&mut self, leaving: &[usize]) {
        let Some(&first) = leaving.first() else {
            return;
        };
        let n = self.rows.len();
        let mut gone = vec![false; n];
        leaving.iter().for_each(|&k| gone[k] = true);
        let kept: Vec<usize> = (0..n).filter(|&i| !gone[i]).collect();
        let m = kept.len();
        // Each removed k: its position among the kept rows and its vector.
        let updates: Vec<(usize, Vec<f64>)> = leaving
            .iter()
            .map(|&k| {
                let col = self.l.col_as_slice(k);
                let at = kept.partition_point(|&i| i < k);
                (at, kept[at..].iter().map(|&i| col[i]).collect())
            })
            .collect();
        // Rows before `first` keep their place: in column jj only the rows
        // from max(jj, first) on move up.
        let mut moved = vec![0.0; n];
        for (jj, &j) in kept.iter().enumerate() {
            let from = jj.max(first);
            let col = self.l.col_as_slice(j);
            for (v, &i) in moved[from..m].iter_mut().zip(&kept[from..]) {
                *v = col[i];
            }
            self.l.col_as_slice_mut(jj)[from..m].copy_from_slice(&moved[from..m]);
        }
        self.l.truncate(m, m);
        self.rank_one_updates(updates);
        self.rows = kept.iter().map(|&i| self.rows[i]).collect();
        self.forward.valid = self.forward.valid.min(first);
    }

    /// L L ᵀ + Σ v vᵀ for the vectors `updates` (each (at, v): v starts at
    /// row `at`), by Givens rotations swept column by column: each column is
    /// loaded once for all the updates that reach it (the vectors stay in
    /// cache), the same arithmetic as one update after the other.
    fn rank_one_updates(&mut self, mut updates: Vec<(usize, Vec<f64>)>) {
        updates.sort_by_key(|u| u.0);
        let m = self.l.nrows();
        let first = updates.first().map_or(m, |u| u.0);
        for j in first..m {
            let col = &mut self.l.col_as_slice_mut(j)[j..];
            for (at, v) in updates.iter_mut().take_while(|u| u.0 <= j) {
                let v = &mut v[j - *at..];
                let ljj = col[0];
                let r = ljj.hypot(v[0]);
                let (c, s) = (r / ljj, v[0] / ljj);
                let inv_c = ljj / r;
                col[0] = r;
                for (lij, vi) in col[1..].iter_mut().zip(&mut v[1..]) {
                    *lij = (*lij + s * *vi) * inv_c;
                    *vi = c * *vi - s * *lij;
                }
            }
        }
    }

    /// Appends the rows `entering`: with B = W_{A,E}, L X = B and the new
    /// block's factor L₂₂ L₂₂ᵀ = W_EE − Xᵀ X (one triangular solve with |E|
    /// right-hand sides and one small Cholesky); `false` if a new pivot is
    /// not safely positive.
    fn append(&mut self, w: &Mat<f64>, entering: &[usize]) -> bool {
        let (n, k) = (self.rows.len(), entering.len());
        if k == 0 {
            return true;
        }
        let mut x = Mat::<f64>::from_fn(n, k, |i, j| w[(self.rows[i], entering[j])]);
        solve_lower_triangular_in_place(self.l.as_ref(), x.as_mut(), Par::Seq);
        let mut c = Mat::<f64>::from_fn(k, k, |i, j| w[(entering[i], entering[j])]);
        matmul(
            c.as_mut(),
            Accum::Add,
            x.transpose(),
            x.as_ref(),
            -1.0,
            Par::Seq,
        );
        let Ok(llt) = c.llt(Side::Lower) else {
            return false;
        };
        let l22 = llt.L();
        let a_diag = entering.iter().map(|&r| w[(r, r)]);
        if !cholesky_pivots_are_safe((0..k).map(|i| l22[(i, i)]), a_diag, n + k) {
            return false;
        }
        self.l
            .resize_with(n + k, n + k, |i, j| match (i >= n, j >= n) {
                (true, false) => x[(j, i - n)],
                (true, true) if j <= i => l22[(i - n, j - n)],
                _ => 0.0,
            });
        self.rows.extend_from_slice(entering);
        true
    }

    /// Solves W_AA x = b like [`Self::solve`], reusing the forward
    /// substitution y = L⁻¹ b of the previous call on the leading rows where
    /// neither b nor L changed since: after removals at the tail of the
    /// factor (and appends) only its trailing rows are substituted again,
    /// y₂ = L₂₂⁻¹ (b₂ − L₂₁ y₁).
    pub fn solve_reusing(&mut self, b: &[f64]) -> Vec<f64> {
        let n = self.rows.len();
        let f = &mut self.forward;
        let valid = f.valid.min(n);
        let keep = (0..valid).find(|&i| f.b[i] != b[i]).unwrap_or(valid);
        let mut y = Mat::<f64>::zeros(n, 1);
        let yc = y.col_as_slice_mut(0);
        yc[..keep].copy_from_slice(&f.y[..keep]);
        yc[keep..].copy_from_slice(&b[keep..]);
        let (y1, mut y2) = y.as_mut().split_at_row_mut(keep);
        let l = self.l.as_ref();
        let (l21, l22) = (
            l.submatrix(keep, 0, n - keep, keep),
            l.submatrix(keep, keep, n - keep, n - keep),
        );
        matmul(y2.as_mut(), Accum::Add, l21, y1.as_ref(), -1.0, Par::Seq);
        solve_lower_triangular_in_place(l22, y2, Par::Seq);
        f.b = b.to_vec();
        f.y = y.col_as_slice(0).to_vec();
        f.valid = n;
        solve_upper_triangular_in_place(l.transpose(), y.as_mut(), Par::Seq);
        y.col_as_slice(0).to_vec()
    }

    /// Solves W_AA x = b (b and x in the order of [`Self::rows`]).
    pub fn solve(&self, b: &Mat<f64>) -> Mat<f64> {
        let mut x = b.to_owned();
        solve_lower_triangular_in_place(self.l.as_ref(), x.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.l.transpose(), x.as_mut(), Par::Seq);
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd(n: usize) -> Mat<f64> {
        Mat::<f64>::from_fn(n, n, |i, j| {
            1.0 / (1.0 + (i as f64 - j as f64).abs()) + if i == j { 2.0 } else { 0.0 }
        })
    }

    /// After removals and appends, the factor solves the new block as a
    /// fresh factorisation does.
    #[test]
    fn updated_factor_solves_like_a_new_one() {
        let w = spd(200);
        let mut f = ActiveFactor::new(&w, &(0..150).collect::<Vec<_>>()).unwrap();
        // Rows 0, 1, 3, 70, 149 leave; 160, 171, 199 enter.
        let target: Vec<usize> = (2..149)
            .filter(|&r| r != 3 && r != 70)
            .chain([171, 160, 199])
            .collect();
        assert!(f.update_to(&w, &target));
        let rows = f.rows().to_vec();
        let mut sorted = rows.clone();
        sorted.sort_unstable();
        let mut want = target.clone();
        want.sort_unstable();
        assert_eq!(sorted, want);
        let b = Mat::<f64>::from_fn(rows.len(), 1, |i, _| (i as f64).sin());
        let x = f.solve(&b);
        let fresh = ActiveFactor::new(&w, &rows).unwrap().solve(&b);
        for i in 0..rows.len() {
            assert!((x[(i, 0)] - fresh[(i, 0)]).abs() <= 1e-12, "{i}");
        }
    }

    /// The largest difference between the solutions of `f` and of a fresh
    /// factor of its rows, relative to the largest entry of the latter.
    fn gap_to_fresh(w: &Mat<f64>, f: &ActiveFactor) -> f64 {
        let rows = f.rows().to_vec();
        let b = Mat::<f64>::from_fn(rows.len(), 1, |i, _| (i as f64 * 0.7).cos());
        let (x, fresh) = (f.solve(&b), ActiveFactor::new(w, &rows).unwrap().solve(&b));
        let scale = (0..rows.len()).fold(0.0f64, |a, i| a.max(fresh[(i, 0)].abs()));
        (0..rows.len()).fold(0.0f64, |a, i| a.max((x[(i, 0)] - fresh[(i, 0)]).abs())) / scale
    }

    /// Removing 30 of 200 rows from the tail of the factor is an update;
    /// removing 30 from its head costs more than a new factorisation
    /// (GIVENS_SLOWDOWN · Σ 2 (200 − k)² ≈ 7·10⁶ > 170³/3 ≈ 1.6·10⁶), and
    /// the factor is given up.
    #[test]
    fn removals_are_updates_when_they_are_cheaper_than_a_new_factor() {
        let w = spd(200);
        let all: Vec<usize> = (0..200).collect();
        let mut tail = ActiveFactor::new(&w, &all).unwrap();
        assert!(tail.update_to(&w, &all[..170]));
        assert_eq!(tail.rows(), &all[..170]);
        assert!(gap_to_fresh(&w, &tail) <= 1e-13);
        // Rows 40..70 leave from the middle: Σ 2 (200 − k)² · 3.5 ≈ 4.4·10⁶.
        let middle: Vec<usize> = (0..40).chain(70..200).collect();
        let mut mid = ActiveFactor::new(&w, &all).unwrap();
        assert!(!mid.update_to(&w, &middle));
        // From the tail of 170 rows, 5 in the middle leave and 8 enter.
        let target: Vec<usize> = (0..170)
            .filter(|r| !(100..105).contains(r))
            .chain([199, 180, 175, 190, 171, 186, 194, 177])
            .collect();
        assert!(tail.update_to(&w, &target));
        assert!(gap_to_fresh(&w, &tail) <= 1e-13);
        let mut head = ActiveFactor::new(&w, &all).unwrap();
        assert!(!head.update_to(&w, &all[30..]));
    }

    /// The first factor of an active set orders its rows by q (the most
    /// penetrating first), and the forces solve W_AA λ_A = −q_A.
    #[test]
    fn a_new_factor_puts_the_nearly_closed_gaps_last() {
        let w = spd(12);
        let q: Vec<f64> = (0..12).map(|i| -((i * 5 % 12) as f64) - 1.0).collect();
        let active: Vec<usize> = (0..12).filter(|&p| p != 4).collect();
        let mut slot = None;
        let lambda = solve_on_active_set(&mut slot, &w, &q, &active).unwrap();
        let rows = slot.unwrap().rows().to_vec();
        assert!(rows.windows(2).all(|r| q[r[0]] < q[r[1]]), "{rows:?}");
        let scale = lambda.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert_eq!(lambda[4], 0.0);
        for &i in &active {
            let wl: f64 = active.iter().map(|&j| w[(i, j)] * lambda[j]).sum();
            assert!((wl + q[i]).abs() <= 1e-14 * scale * 12.0, "{i}");
        }
    }

    /// The solve that reuses the leading forward substitution agrees with a
    /// fresh factor's after tail removals (all of y kept), a change of b
    /// (kept up to it), removals in the middle and appends.
    #[test]
    fn reused_forward_substitution_solves_like_a_new_factor() {
        let w = spd(200);
        let all: Vec<usize> = (0..200).collect();
        let b_of = |rows: &[usize], bump: usize| -> Vec<f64> {
            let b = rows.iter().map(|&r| (r as f64 * 0.3).sin() + 0.1);
            b.enumerate()
                .map(|(i, v)| if i == bump { v + 1.0 } else { v })
                .collect()
        };
        let mut f = ActiveFactor::new(&w, &all).unwrap();
        let middle: Vec<usize> = (0..170)
            .filter(|r| !(100..104).contains(r))
            .chain([185, 172, 199])
            .collect();
        let steps: [(&[usize], usize); 4] = [
            (&all, 200),
            (&all[..170], 200),
            (&all[..170], 50),
            (&middle, 200),
        ];
        for (target, bump) in steps {
            assert!(f.update_to(&w, target));
            let b = b_of(f.rows(), bump);
            let x = f.solve_reusing(&b);
            let fresh = ActiveFactor::new(&w, f.rows()).unwrap();
            let want = fresh.solve(&Mat::<f64>::from_fn(b.len(), 1, |i, _| b[i]));
            let scale = (0..b.len()).fold(0.0f64, |a, i| a.max(want[(i, 0)].abs()));
            for (i, xi) in x.iter().enumerate() {
                assert!((xi - want[(i, 0)]).abs() <= 1e-13 * scale, "{i}");
            }
        }
    }

    /// A row that makes the block singular is not appended.
    #[test]
    fn a_dependent_row_is_refused() {
        // Rows 0 and 1 of W are equal: W_{01,01} is singular.
        let mut w = spd(4);
        for j in 0..4 {
            w[(1, j)] = w[(0, j)];
            w[(j, 1)] = w[(j, 0)];
        }
        let mut f = ActiveFactor::new(&w, &[0, 2, 3]).unwrap();
        assert!(!f.append(&w, &[1]));
        assert!(ActiveFactor::new(&w, &[0, 1]).is_none());
    }
}
