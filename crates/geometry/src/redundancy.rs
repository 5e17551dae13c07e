//! Redundant contact constraints.
//!
//! Two contact points whose gap rows are parallel and point the same way,
//! g₁ = a₁ + c₁ r·u and g₂ = a₂ + c₂ r·u with c₁, c₂ > 0, are one constraint:
//! g₁ ≥ 0 implies g₂ ≥ 0 when a₁/c₁ ≤ a₂/c₂. Keeping both makes the
//! Delassus operator W = B S⁻¹ Bᵀ singular (two equal rows of B), the split
//! of the force between them arbitrary, and the status method's systems
//! W_AA λ_A = −q_A singular. This happens with a slave surface listed in two
//! contacts against the same master, with two-pass node-to-node contact
//! (each surface slave of the other: the rows are equal), or with a slave
//! node shared by two contacts against the same rigid plane. Such duplicates
//! are found exactly here and the less restrictive of each pair is dropped,
//! which does not change the problem. Points whose rows are antiparallel
//! (a box constraint) or merely close are kept; their conditioning shows in
//! the report's estimate of κ(W).

use std::collections::BTreeMap;

/// Relative tolerance of "parallel": 1 − cos(r₁, r₂) ≤ this.
const PARALLEL: f64 = 1e-10;

/// For each constraint (row over DOF keys K, initial gap), `Some(j)` when it
/// duplicates the kept constraint j (same DOFs, parallel rows pointing the
/// same way) and is the less restrictive (its normalised gap a/‖r‖ is not
/// smaller; ties drop the later one), `None` when it is kept. The gap
/// tolerance `gap_tol` (a length) decides equal gaps.
pub fn duplicate_constraints<K: Ord + Clone>(
    rows: &[(Vec<(K, f64)>, f64)],
    gap_tol: f64,
) -> Vec<Option<usize>> {
    // Group the rows by their sorted set of DOFs with a non-zero coefficient.
    let mut groups: BTreeMap<Vec<K>, Vec<usize>> = BTreeMap::new();
    let normalised: Vec<(BTreeMap<K, f64>, f64)> = rows
        .iter()
        .map(|(row, gap)| {
            let (m, norm) = unit_row(row);
            (m, if norm > 0.0 { gap / norm } else { *gap })
        })
        .collect();
    for (i, (m, _)) in normalised.iter().enumerate() {
        if !m.is_empty() {
            groups
                .entry(m.keys().cloned().collect())
                .or_default()
                .push(i);
        }
    }
    let mut out = vec![None; rows.len()];
    for members in groups.values() {
        let mut kept: Vec<usize> = Vec::new();
        for &i in members {
            let (mi, gi) = &normalised[i];
            let twin = (kept.iter()).position(|&j| cosine(&normalised[j].0, mi) >= 1.0 - PARALLEL);
            match twin {
                None => kept.push(i),
                Some(t) => {
                    let j = kept[t];
                    if *gi < normalised[j].1 - gap_tol {
                        // The newcomer is the more restrictive: it replaces j.
                        out[j] = Some(i);
                        for o in out.iter_mut() {
                            if *o == Some(j) {
                                *o = Some(i);
                            }
                        }
                        kept[t] = i;
                    } else {
                        out[i] = Some(j);
                    }
                }
            }
        }
    }
    out
}

/// For each point p with a tangential row, `Some(q)` when that row is
/// parallel (either sign) to the normal row of another point q over the
/// same DOFs: a corner node in a frictional contact and in a second contact
/// whose normal lies along the first one's tangent (a block on a floor
/// against a wall). Stuck on the floor and closed on the wall, both rows fix
/// the same motion (W singular); the friction solve then lets the normal
/// row alone hold it. `rows[..m]` are the normal rows.
pub fn tangent_shadows(
    rows: &[Vec<(usize, f64)>],
    m: usize,
    tangent_row: &[Option<usize>],
) -> Vec<Option<usize>> {
    let normalised = |r: &Vec<(usize, f64)>| unit_row(r).0;
    type Unit = BTreeMap<usize, f64>;
    let mut by_dofs: BTreeMap<Vec<usize>, Vec<(usize, Unit)>> = BTreeMap::new();
    for (q, r) in rows.iter().enumerate().take(m) {
        let a = normalised(r);
        if !a.is_empty() {
            by_dofs
                .entry(a.keys().copied().collect())
                .or_default()
                .push((q, a));
        }
    }
    tangent_row
        .iter()
        .enumerate()
        .map(|(p, t)| {
            let a = normalised(&rows[(*t)?]);
            let key: Vec<usize> = a.keys().copied().collect();
            by_dofs
                .get(&key)?
                .iter()
                .find_map(|(q, b)| (*q != p && cosine(&a, b).abs() >= 1.0 - PARALLEL).then_some(*q))
        })
        .collect()
}

/// A row over DOF keys as a map (repeated keys summed, entries below 10⁻¹⁴
/// of the largest dropped) scaled to unit length, and its length before
/// (0: no entry left, the map empty).
fn unit_row<K: Ord + Clone>(row: &[(K, f64)]) -> (BTreeMap<K, f64>, f64) {
    let mut m: BTreeMap<K, f64> = BTreeMap::new();
    for (k, c) in row {
        *m.entry(k.clone()).or_insert(0.0) += c;
    }
    let scale = m.values().fold(0.0f64, |a, c| a.max(c.abs()));
    m.retain(|_, c| c.abs() > 1e-14 * scale);
    let norm = m.values().map(|c| c * c).sum::<f64>().sqrt();
    if norm > 0.0 {
        m.values_mut().for_each(|c| *c /= norm);
    }
    (m, norm)
}

/// The cosine of two unit rows: the sum over the keys of `a` of a_k b_k.
fn cosine<K: Ord>(a: &BTreeMap<K, f64>, b: &BTreeMap<K, f64>) -> f64 {
    a.iter()
        .map(|(k, c)| c * b.get(k).copied().unwrap_or(0.0))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_rows_are_one_constraint_and_opposite_rows_are_two() {
        let rows = vec![
            (vec![(0usize, 1.0), (1, -1.0)], 0.0),
            // the same row scaled, same gap per unit row: a duplicate of 0
            (vec![(1usize, -2.0), (0, 2.0)], 0.0),
            // opposite direction: a box with 0, kept
            (vec![(0usize, -1.0), (1, 1.0)], 0.5),
            // other DOFs
            (vec![(2usize, 1.0)], 0.0),
            // parallel to 3 with a smaller gap: the more restrictive, keeps
            (vec![(2usize, 1.0)], -0.25),
        ];
        let d = duplicate_constraints(&rows, 1e-12);
        assert_eq!(d, vec![None, Some(0), None, Some(4), None]);
    }

    #[test]
    fn rows_that_are_merely_close_are_kept() {
        let rows = vec![
            (vec![(0usize, 1.0), (1, 0.0)], 0.0),
            (vec![(0usize, 1.0), (1, 1e-3)], 0.0),
        ];
        assert_eq!(duplicate_constraints(&rows, 1e-12), vec![None, None]);
    }

    #[test]
    fn a_tangential_row_along_another_points_normal_is_shadowed() {
        // Point 0: a corner on a floor (normal y = DOF 1, tangent x = DOF 0);
        // point 1: the same node on a wall (normal −x). Point 2: another
        // floor node, its tangent (DOF 2) along nobody's normal.
        let rows = vec![
            vec![(1usize, 1.0)],
            vec![(0usize, -1.0)],
            vec![(3usize, 1.0)],
            vec![(0usize, 2.0)],
            vec![(2usize, 1.0)],
        ];
        let tangent = [Some(3), None, Some(4)];
        assert_eq!(
            tangent_shadows(&rows, 3, &tangent),
            vec![Some(1), None, None]
        );
    }
}
