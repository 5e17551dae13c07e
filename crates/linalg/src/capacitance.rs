//! The status system of one iteration of the friction status method (course notes
//! §4.5) solved with the factor of an earlier iteration's system, by the
//! capacitance (Sherman–Morrison–Woodbury) formula on the rows whose
//! equation changed.
//!
//! Written over every force row, the system M r = b of a status vector has
//! one row per force ([`VarEquation`]): a zero gap W_i· r = −q_i, a given
//! value r_i = c, or a ratio r_i − f r_o = 0. From one status iteration to
//! the next only the rows R of the points whose status changed differ
//! (their equations N_R replace the base's), so with M₀ the base system,
//! factorised once through its reduction ([`crate::reduced`]), and
//! Z = M₀⁻¹ E_R:
//!
//! ```text
//!   M₀ r = b⁰ + E_R s        (b⁰: b with the rows R zeroed, s unknown)
//!   r = y + Z s,   y = M₀⁻¹ b⁰,   (N_R Z) s = b_R − N_R y
//! ```
//!
//! The capacitance matrix K = N_R Z is |R| × |R|. Each column of Z is one
//! solve with the base factor (2 n₀² flops), made once and kept while the
//! base lasts; a new factorisation (⅔ n³ for an LU) is made instead when
//! the new columns would cost more. The answer is checked by its residual
//! on the zero-gap rows (one step of iterative refinement if needed); a
//! near-singular K or a residual that stays large hands the system back to
//! a fresh factorisation, which keeps the fast path's pivot test and the
//! rank-tested full solve behind it.

use std::collections::HashMap;

use faer::Mat;

use crate::growing_lu::GrowingLu;
use crate::pivot_policy::pivots_are_safe;
use crate::reduced::{factorise_reduced, reduce, reduced_block, Factor, Reduction, VarEquation};

/// Whether two equations have the same row of M (they may differ in their
/// right-hand side: a given value).
fn same_row(a: &VarEquation, b: &VarEquation) -> bool {
    match (a, b) {
        (VarEquation::Gap, VarEquation::Gap) | (VarEquation::Value(_), VarEquation::Value(_)) => {
            true
        }
        (VarEquation::Ratio { of: o, factor: f }, VarEquation::Ratio { of: p, factor: g }) => {
            o == p && f == g
        }
        _ => false,
    }
}

/// The factor of a base status system and the columns of Z = M₀⁻¹ E_R made
/// so far.
pub struct StatusFactor {
    base: Vec<VarEquation>,
    red: Reduction,
    /// Position of each zero-gap row among the unknowns.
    position: Vec<Option<usize>>,
    /// Ratio rows of a given-value row: (ratio row, factor), by given row.
    children: HashMap<usize, Vec<(usize, f64)>>,
    factor: Factor,
    /// Columns of Z over every row (column major), and the row of each.
    z: Vec<f64>,
    z_col: HashMap<usize, usize>,
    /// ‖W‖∞ (W symmetric: its largest column sum), for the residual test.
    w_norm: f64,
    /// The capacitance system of the last update, grown by the next one
    /// when its rows are among the next one's.
    last: Option<Capacitance>,
}

/// The capacitance system of a status vector against the base.
struct Capacitance {
    /// The changed rows, in the order of K's rows and columns, and the
    /// equation each had when K was made.
    rows: Vec<usize>,
    eqs: Vec<VarEquation>,
    /// Row equilibration of K and its LU.
    scale: Vec<f64>,
    lu: GrowingLu,
}

impl Capacitance {
    /// The rows of `rows` not yet in this system, when every row of it is
    /// among `rows` with the same equation (then K grows by a border);
    /// `None` otherwise.
    fn border(&self, eqs: &[VarEquation], rows: &[usize]) -> Option<Vec<usize>> {
        let mut listed = vec![false; eqs.len()];
        for &r in rows {
            listed[r] = true;
        }
        let mut kept = self.rows.iter().zip(&self.eqs);
        if !kept.all(|(&r, e)| listed[r] && same_row(&eqs[r], e)) {
            return None;
        }
        for &r in &self.rows {
            listed[r] = false;
        }
        Some(rows.iter().copied().filter(|&r| listed[r]).collect())
    }
}

impl StatusFactor {
    /// Factorises the reduced system of `eqs`; `None` when the
    /// factorisation fails or is near singular (see [`crate::reduced`]).
    /// `w_norm`: ‖W‖₁ when already known (a previous factor of the same W).
    fn new(w: &Mat<f64>, eqs: &[VarEquation], w_norm: Option<f64>) -> Option<Self> {
        let red = reduce(eqs)?;
        let factor = factorise_reduced(&reduced_block(w, &red), &red)?;
        let mut position = vec![None; eqs.len()];
        for (x, &u) in red.unknown.iter().enumerate() {
            position[u] = Some(x);
        }
        let mut children: HashMap<usize, Vec<(usize, f64)>> = HashMap::new();
        for (i, eq) in eqs.iter().enumerate() {
            if let VarEquation::Ratio { of, factor } = *eq {
                if position[of].is_none() {
                    children.entry(of).or_default().push((i, factor));
                }
            }
        }
        Some(Self {
            base: eqs.to_vec(),
            red,
            position,
            children,
            factor,
            z: Vec::new(),
            z_col: HashMap::new(),
            last: None,
            w_norm: w_norm.unwrap_or_else(|| {
                (0..w.ncols())
                    .map(|j| w.col_as_slice(j).iter().map(|v| v.abs()).sum::<f64>())
                    .fold(0.0, f64::max)
            }),
        })
    }

    /// M₀⁻¹ B for the sparse columns `cols` of B (row, value): each column
    /// over every row.
    fn base_solve(&self, w: &Mat<f64>, cols: &[Vec<(usize, f64)>]) -> Mat<f64> {
        let (n, nu, c) = (self.base.len(), self.red.unknown.len(), cols.len());
        // The known part h of each column (given and ratio rows) and the
        // right-hand side b_U − W_U· h of the unknowns.
        let mut h = Mat::<f64>::zeros(n, c);
        let mut rhs = Mat::<f64>::zeros(nu, c);
        for (j, col) in cols.iter().enumerate() {
            let mut known: Vec<(usize, f64)> = Vec::new();
            for &(i, v) in col {
                if let Some(x) = self.position[i] {
                    rhs[(x, j)] += v;
                    continue;
                }
                known.push((i, v));
                for &(k, f) in self.children.get(&i).into_iter().flatten() {
                    known.push((k, f * v));
                }
            }
            for (i, v) in known {
                h[(i, j)] += v;
                let wi = w.col_as_slice(i);
                for (x, &u) in self.red.unknown.iter().enumerate() {
                    rhs[(x, j)] -= wi[u] * v;
                }
            }
        }
        let x = self.factor.solve(&rhs);
        for j in 0..c {
            for (xi, &u) in self.red.unknown.iter().enumerate() {
                h[(u, j)] = x[(xi, j)];
            }
            for &(i, col, f) in &self.red.dependent {
                h[(i, j)] += f * x[(col, j)];
            }
        }
        h
    }

    /// The rows whose equation differs from the base's.
    fn changed_rows(&self, eqs: &[VarEquation]) -> Vec<usize> {
        let pairs = eqs.iter().zip(&self.base).enumerate();
        pairs
            .filter(|(_, (a, b))| !same_row(a, b))
            .map(|(i, _)| i)
            .collect()
    }

    /// Whether updating for the changed `rows` costs less than factorising
    /// the reduced system of `eqs` afresh (flop counts).
    fn worth_updating(&self, eqs: &[VarEquation], rows: &[usize]) -> bool {
        let n0 = self.red.unknown.len() as f64;
        let fresh_rows = rows.iter().filter(|r| !self.z_col.contains_key(r)).count();
        let r = rows.len() as f64;
        let update = 2.0 * n0 * n0 * fresh_rows as f64 + 2.0 / 3.0 * r * r * r;
        let nn = eqs.iter().filter(|e| **e == VarEquation::Gap).count() as f64;
        let symmetric = !eqs.iter().any(|e| {
            matches!(*e, VarEquation::Ratio { of, .. } if eqs.get(of) == Some(&VarEquation::Gap))
        });
        let fresh = if symmetric { 1.0 } else { 2.0 } * nn * nn * nn / 3.0;
        update < fresh && 2.0 * r <= nn.max(1.0)
    }

    /// Makes the columns of Z missing for `rows` and returns M₀⁻¹ b⁰ (b
    /// with the rows `rows` zeroed), all in one solve with the base factor.
    fn extend_z(&mut self, w: &Mat<f64>, rows: &[usize], b: &[f64]) -> Vec<f64> {
        let missing: Vec<usize> = rows
            .iter()
            .copied()
            .filter(|r| !self.z_col.contains_key(r))
            .collect();
        let mut cols: Vec<Vec<(usize, f64)>> = missing.iter().map(|&r| vec![(r, 1.0)]).collect();
        cols.push(zeroed_column(b, rows));
        let z = self.base_solve(w, &cols);
        for (j, &r) in missing.iter().enumerate() {
            self.z_col.insert(r, self.z_col.len());
            self.z.extend_from_slice(z.col_as_slice(j));
        }
        z.col_as_slice(missing.len()).to_vec()
    }

    /// The entries of K = N_R Z on the rows `a` and columns `b` (rows of
    /// the system).
    fn entries(&self, w: &Mat<f64>, eqs: &[VarEquation], a: &[usize], b: &[usize]) -> Mat<f64> {
        let n = eqs.len();
        let mut k = Mat::<f64>::zeros(a.len(), b.len());
        for (j, rb) in b.iter().enumerate() {
            let zb = &self.z[self.z_col[rb] * n..][..n];
            for (i, &ra) in a.iter().enumerate() {
                k[(i, j)] = row_apply(w, eqs, ra, |t| zb[t]);
            }
        }
        k
    }

    /// K = N_R Z for the changed rows, equilibrated by rows and factorised:
    /// the last update's K grown by a border when its rows are among these
    /// with the same equations, else made afresh; `None` when near singular.
    fn capacitance(
        &self,
        w: &Mat<f64>,
        eqs: &[VarEquation],
        rows: &[usize],
        last: Option<Capacitance>,
    ) -> Option<Capacitance> {
        let grown = last.and_then(|c| {
            let border = c.border(eqs, rows)?;
            self.grow(w, eqs, c, &border)
        });
        grown.or_else(|| {
            let mut k = self.entries(w, eqs, rows, rows);
            let scale = equilibrate(k.as_mut());
            let lu = GrowingLu::new(k.as_ref());
            pivots_are_safe(lu.pivots(), rows.len()).then(|| Capacitance {
                rows: rows.to_vec(),
                eqs: rows.iter().map(|&r| eqs[r]).collect(),
                scale,
                lu,
            })
        })
    }

    /// `c` grown by the rows and columns `border`; `None` when its pivots
    /// are not safe.
    fn grow(
        &self,
        w: &Mat<f64>,
        eqs: &[VarEquation],
        mut c: Capacitance,
        border: &[usize],
    ) -> Option<Capacitance> {
        if border.is_empty() {
            return Some(c);
        }
        let mut k12 = self.entries(w, eqs, &c.rows, border);
        for (i, s) in c.scale.iter().enumerate() {
            for j in 0..border.len() {
                k12[(i, j)] *= s;
            }
        }
        let mut k2 = self.entries(w, eqs, border, &[&c.rows[..], border].concat());
        let scale = equilibrate(k2.as_mut());
        let r = c.rows.len();
        let (k21, k22) = k2.as_ref().split_at_col(r);
        c.lu.extend(k12.as_ref(), k21, k22);
        c.rows.extend_from_slice(border);
        c.eqs.extend(border.iter().map(|&b| eqs[b]));
        c.scale.extend(scale);
        pivots_are_safe(c.lu.pivots(), c.rows.len()).then_some(c)
    }
}

/// Scales each row of `k` by the inverse of its largest magnitude (rows
/// without a finite nonzero entry are left) and returns the scales.
fn equilibrate(mut k: faer::MatMut<'_, f64>) -> Vec<f64> {
    let (r, c) = k.shape();
    (0..r)
        .map(|a| {
            let m = (0..c).fold(0.0f64, |m, b| m.max(k[(a, b)].abs()));
            let s = if m > 0.0 && m.is_finite() {
                1.0 / m
            } else {
                1.0
            };
            for b in 0..c {
                k[(a, b)] *= s;
            }
            s
        })
        .collect()
}

/// The column b⁰ (b with the rows `rows` zeroed) as (row, value) pairs.
fn zeroed_column(b: &[f64], rows: &[usize]) -> Vec<(usize, f64)> {
    let mut b0 = b.to_vec();
    for &r in rows {
        b0[r] = 0.0;
    }
    let nonzero = b0.into_iter().enumerate().filter(|e| e.1 != 0.0);
    nonzero.collect()
}

/// Row `i` of the system of `eqs` applied to the vector `v` (W_i· v for a
/// zero-gap row).
fn row_apply(w: &Mat<f64>, eqs: &[VarEquation], i: usize, v: impl Fn(usize) -> f64) -> f64 {
    match eqs[i] {
        VarEquation::Gap => (0..eqs.len()).map(|k| w[(i, k)] * v(k)).sum(),
        VarEquation::Value(_) => v(i),
        VarEquation::Ratio { of, factor } => v(i) - factor * v(of),
    }
}

/// The right-hand side b of the system of `eqs`.
fn rhs_of(q: &[f64], eqs: &[VarEquation]) -> Vec<f64> {
    let each = eqs.iter().zip(q);
    each.map(|(eq, &qi)| match *eq {
        VarEquation::Gap => -qi,
        VarEquation::Value(c) => c,
        VarEquation::Ratio { .. } => 0.0,
    })
    .collect()
}

/// Sets the given and ratio rows of `x` from their equations (exact after
/// the round-off of the capacitance solve).
fn enforce(eqs: &[VarEquation], x: &mut [f64]) {
    for (xi, eq) in x.iter_mut().zip(eqs) {
        if let VarEquation::Value(c) = *eq {
            *xi = c;
        }
    }
    for (i, eq) in eqs.iter().enumerate() {
        if let VarEquation::Ratio { of, factor } = *eq {
            x[i] = factor * x[of];
        }
    }
}

/// Whether every ratio refers to a zero-gap or given row (the reduction
/// handles nothing else).
fn reducible(eqs: &[VarEquation]) -> bool {
    eqs.iter().all(|e| match *e {
        VarEquation::Ratio { of, .. } => {
            matches!(eqs.get(of), Some(VarEquation::Gap | VarEquation::Value(_)))
        }
        _ => true,
    })
}

impl StatusFactor {
    /// M⁻¹ b with the base factor and, for the changed rows, the
    /// capacitance system `cap`.
    fn solve_rhs(
        &self,
        w: &Mat<f64>,
        eqs: &[VarEquation],
        cap: Option<&Capacitance>,
        b: &[f64],
    ) -> Vec<f64> {
        let rows = cap.map_or(&[][..], |c| &c.rows[..]);
        let y = self
            .base_solve(w, &[zeroed_column(b, rows)])
            .col_as_slice(0)
            .to_vec();
        match cap {
            Some(cap) => self.correct(w, eqs, cap, b, y),
            None => y,
        }
    }

    /// x = y + Z s with (N_R Z) s = b_R − N_R y, from y = M₀⁻¹ b⁰.
    fn correct(
        &self,
        w: &Mat<f64>,
        eqs: &[VarEquation],
        cap: &Capacitance,
        b: &[f64],
        mut x: Vec<f64>,
    ) -> Vec<f64> {
        let (n, rows) = (eqs.len(), &cap.rows);
        let rhs = Mat::<f64>::from_fn(rows.len(), 1, |a, _| {
            let i = rows[a];
            cap.scale[a] * (b[i] - row_apply(w, eqs, i, |k| x[k]))
        });
        let s = cap.lu.solve(rhs.as_ref());
        for (a, ra) in rows.iter().enumerate() {
            let za = &self.z[self.z_col[ra] * n..][..n];
            let sa = s[(a, 0)];
            for (xi, zi) in x.iter_mut().zip(za) {
                *xi += sa * zi;
            }
        }
        x
    }

    /// The solution of `eqs` when its rows are the base's (only given
    /// values may differ): one solve with the base factor.
    fn direct(&self, w: &Mat<f64>, q: &[f64], eqs: &[VarEquation]) -> Option<(Vec<f64>, Vec<f64>)> {
        let mut x = self.solve_rhs(w, eqs, None, &rhs_of(q, eqs));
        enforce(eqs, &mut x);
        if !x.iter().all(|v| v.is_finite()) {
            return None;
        }
        let g = crate::products::affine(w, &x, q);
        Some((x, g))
    }

    /// The solution of `eqs` by the capacitance formula on the changed
    /// `rows`, checked by its residual (refined once); `None` when K is
    /// near singular or the residual stays large.
    fn update(
        &mut self,
        w: &Mat<f64>,
        q: &[f64],
        eqs: &[VarEquation],
        rows: &[usize],
    ) -> Option<(Vec<f64>, Vec<f64>)> {
        let b = rhs_of(q, eqs);
        let y = self.extend_z(w, rows, &b);
        let last = self.last.take();
        let cap = self.capacitance(w, eqs, rows, last)?;
        let mut x = self.correct(w, eqs, &cap, &b, y);
        enforce(eqs, &mut x);
        let mut g = crate::products::affine(w, &x, q);
        for pass in 0..2 {
            let worst = eqs
                .iter()
                .zip(&g)
                .filter(|(e, _)| **e == VarEquation::Gap)
                .fold(0.0f64, |m, (_, gi)| m.max(gi.abs()));
            let xmax = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let qmax = q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let eta = worst / (self.w_norm * xmax + qmax).max(f64::MIN_POSITIVE);
            if eta <= BACKWARD_ERROR && x.iter().all(|v| v.is_finite()) {
                self.last = Some(cap);
                return Some((x, g));
            }
            if pass == 1 {
                break;
            }
            let rho: Vec<f64> = eqs
                .iter()
                .zip(&g)
                .map(|(e, gi)| if *e == VarEquation::Gap { -gi } else { 0.0 })
                .collect();
            let d = self.solve_rhs(w, eqs, Some(&cap), &rho);
            for (xi, di) in x.iter_mut().zip(d) {
                *xi += di;
            }
            enforce(eqs, &mut x);
            g = crate::products::affine(w, &x, q);
        }
        None
    }
}

/// The largest normwise backward error ‖g_U‖∞ / (‖W‖∞ ‖r‖∞ + ‖q‖∞) an
/// updated solution may have.
const BACKWARD_ERROR: f64 = 1e3 * f64::EPSILON;

/// Solves the status system of `eqs` (no floating bodies) with the factor
/// carried in `slot` from the previous status iteration, updated by the
/// capacitance formula when that is cheaper, else a new one; returns
/// (r, W r + q), or `None` for the caller's rank-tested full solve.
pub fn solve_status_system(
    slot: &mut Option<StatusFactor>,
    w: &Mat<f64>,
    q: &[f64],
    eqs: &[VarEquation],
) -> Option<(Vec<f64>, Vec<f64>)> {
    if !reducible(eqs) {
        *slot = None;
        return None;
    }
    // The slot holds a factor of this W (one friction solve), if any.
    let w_norm = slot.as_ref().map(|f| f.w_norm);
    if let Some(f) = slot.as_mut().filter(|f| f.base.len() == eqs.len()) {
        let rows = f.changed_rows(eqs);
        if rows.is_empty() {
            return f.direct(w, q, eqs);
        }
        if f.worth_updating(eqs, &rows) {
            if let Some(out) = f.update(w, q, eqs, &rows) {
                return Some(out);
            }
        }
    }
    *slot = None;
    let f = StatusFactor::new(w, eqs, w_norm)?;
    let out = f.direct(w, q, eqs)?;
    *slot = Some(f);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense SPD "Delassus" operator over `n` rows.
    fn spd(n: usize) -> Mat<f64> {
        Mat::<f64>::from_fn(n, n, |i, j| {
            let d = (i as f64 - j as f64).abs();
            1.0 / (1.0 + d)
                + if i == j {
                    3.0 + (i % 7) as f64 * 0.1
                } else {
                    0.0
                }
        })
    }

    /// The equations of `m` points (normal row p, tangent row m + p) with
    /// the statuses 'o' open, 's' stick, '+' / '-' slip (λ_t = ±μ λ_n).
    fn equations(statuses: &str, mu: f64) -> Vec<VarEquation> {
        let m = statuses.len();
        let mut eqs = vec![VarEquation::Gap; 2 * m];
        for (p, c) in statuses.chars().enumerate() {
            match c {
                'o' => {
                    eqs[p] = VarEquation::Value(0.0);
                    eqs[m + p] = VarEquation::Value(0.0);
                }
                '+' | '-' => {
                    let sign = if c == '+' { 1.0 } else { -1.0 };
                    eqs[m + p] = VarEquation::Ratio {
                        of: p,
                        factor: sign * mu,
                    };
                }
                _ => {}
            }
        }
        eqs
    }

    fn fresh(w: &Mat<f64>, q: &[f64], eqs: &[VarEquation]) -> Vec<f64> {
        let g = Mat::<f64>::zeros(q.len(), 0);
        crate::reduced::solve_reduced(w, q, &g, &[], eqs).unwrap().0
    }

    /// From a base factor, each later status vector (points closing,
    /// opening, starting and stopping to slip, changing direction, a
    /// Tresca value changing) is solved by the capacitance update, and the
    /// forces and gaps equal a fresh solve's.
    #[test]
    fn updated_solves_equal_fresh_ones() {
        let m = 40;
        let w = spd(2 * m);
        let q: Vec<f64> = (0..2 * m)
            .map(|i| ((i * 37 % 11) as f64 - 5.0) * 0.3)
            .collect();
        let base = "ssssssssss+sssss-sssssoooosssssssss+ssss";
        let mut slot = None;
        let (r0, _) = solve_status_system(&mut slot, &w, &q, &equations(base, 0.3)).unwrap();
        let r0_fresh = fresh(&w, &q, &equations(base, 0.3));
        let scale = r0_fresh.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(r0
            .iter()
            .zip(&r0_fresh)
            .all(|(a, b)| (a - b).abs() <= 1e-12 * scale));
        let later = [
            "ssssssssss+sssss-sssssoooosssssssss+ssso",
            "s+sssssoss+sssss-sssssoooosssssssss+ssso",
            "s+sssssoss-ssssss+ssssoosssssssssss+ssso",
            "s+sssssoss-ssssss+ssssoossssssss-ss+sss+",
        ];
        for statuses in later {
            let mut eqs = equations(statuses, 0.3);
            eqs[2 * m - 5] = VarEquation::Value(0.25);
            let (r, g) = solve_status_system(&mut slot, &w, &q, &eqs).unwrap();
            // The base is kept: the capacitance update solved it.
            let base_eqs = &slot.as_ref().unwrap().base;
            assert_eq!(base_eqs, &equations(base, 0.3), "{statuses}");
            let expected = fresh(&w, &q, &eqs);
            let scale = expected.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (a, b) in r.iter().zip(&expected) {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "{statuses}: {a} against {b}"
                );
            }
            let g_expected = crate::products::affine(&w, &expected, &q);
            let gscale = q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (a, b) in g.iter().zip(&g_expected) {
                assert!(
                    (a - b).abs() <= 1e-11 * gscale,
                    "{statuses}: gap {a} against {b}"
                );
            }
        }
    }

    /// The reduced block of a status vector with a few slipping points is
    /// factorised by blocks (Cholesky of the stuck part, LU of the Schur
    /// complement on the slipping points' normal columns), and solves as
    /// the LU of the whole block does.
    #[test]
    fn the_block_factor_solves_like_the_lu() {
        let m = 40;
        let w = spd(2 * m);
        let eqs = equations("ssss+sssssssss-ssssooosssssssssssss+sss", 0.3);
        let red = reduce(&eqs).unwrap();
        let a = reduced_block(&w, &red);
        let block = factorise_reduced(&a, &red).unwrap();
        assert!(matches!(block, Factor::Block(_)));
        let lu = crate::reduced::factorise(&a, false).unwrap();
        let n = a.nrows();
        let rhs = Mat::<f64>::from_fn(n, 2, |i, j| ((i * 7 + j * 3) % 5) as f64 - 2.0);
        let (x, y) = (block.solve(&rhs), lu.solve(&rhs));
        let scale = y.norm_max();
        assert!(
            (&x - &y).norm_max() <= 1e-13 * scale,
            "{}",
            (&x - &y).norm_max()
        );
        // And it solves the system: A x = rhs.
        assert!((&a * &x - &rhs).norm_max() <= 1e-12 * rhs.norm_max());
    }

    /// A status vector whose system is singular (two identical rows both
    /// closed) is not answered by the update: the caller's rank-tested
    /// solve decides, as without a carried factor.
    #[test]
    fn a_singular_update_is_left_to_the_full_solve() {
        let m = 30;
        let mut w = spd(2 * m);
        for j in 0..2 * m {
            let v = w[(0, j)];
            w[(1, j)] = v;
        }
        for i in 0..2 * m {
            let v = w[(i, 0)];
            w[(i, 1)] = v;
        }
        let q: Vec<f64> = (0..2 * m).map(|i| -1.0 - (i % 5) as f64).collect();
        let base = format!("so{}", "s".repeat(m - 2));
        let mut slot = None;
        assert!(solve_status_system(&mut slot, &w, &q, &equations(&base, 0.3)).is_some());
        let both = "s".repeat(m);
        assert!(solve_status_system(&mut slot, &w, &q, &equations(&both, 0.3)).is_none());
        assert!(slot.is_none());
    }
}
