//! The size and flops of a sparse Cholesky (or LDLᵀ) factor of a grid-like
//! stiffness ordered by nested dissection, from the grid's sides alone,
//! before anything is built: what the memory estimate and the choice of
//! path (`path = "auto"`) need of the direct path's factorisation.
//!
//! Nested dissection (George 1973) cuts a box of a ≤ b ≤ c nodes across its
//! longest side by a separator of S = a b nodes, eliminated last, and orders
//! the two halves the same way. A separator is a dense front of F = S + B
//! rows, B the nodes of the earlier separators that bound the box (at most
//! the box's surface, about B/2 + S for each half): its columns hold
//! S (S/2 + B) entries of L and cost Σ_{k<S} (F − k)² = S F² − S² F + S³/3
//! flops (report.json `factorisation.flops`: Σ_j c_j², c_j the entries of
//! column j). With d DOFs a node, entries scale by d², flops by d³.
//!
//! Measured against faer 0.24's factors (the direct path's KKT LDLᵀ in its
//! own nested-dissection ordering): a pad of 101 × 101 × 3 nodes 0.53 of the
//! model's entries and 0.34 of its flops (49 × 49 × 3: 0.58, 0.43), the 3D
//! Hertz hemisphere of 4 100 nodes as a cube 1.09, 0.98, a slab of
//! 41 × 41 × 2 nodes 1.17, 1.44, the 2D Hertz half disk (5 500 nodes as a
//! square) 1.16, 1.20: the model is within a factor 3 in flops and 2 in
//! entries on flat, compact and planar bodies.

/// A box of at most this many nodes is one dense front.
const LEAF_NODES: f64 = 8.0;

/// The entries of L and the flops of one numerical factorisation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FactorCost {
    pub entries: f64,
    pub flops: f64,
}

/// The factor of a grid of `sides` nodes (a 2D grid: one side 1), `dofs`
/// unknowns a node, ordered by nested dissection (module doc).
pub fn nested_dissection(sides: [f64; 3], dofs: f64) -> FactorCost {
    let nodes = dissect(sides.map(|s| s.max(1.0)), 0.0);
    FactorCost {
        entries: nodes.entries * dofs * dofs,
        flops: nodes.flops * dofs * dofs * dofs,
    }
}

/// [`nested_dissection`] in nodes, of a box bounded by `bound` nodes of
/// earlier separators.
fn dissect(sides: [f64; 3], bound: f64) -> FactorCost {
    let mut s = sides;
    s.sort_by(f64::total_cmp);
    let nodes = s[0] * s[1] * s[2];
    if nodes <= LEAF_NODES || s[2] < 3.0 {
        return front(nodes, bound);
    }
    let separator = s[0] * s[1];
    let half = [s[0], s[1], (s[2] - 1.0) / 2.0];
    let surface = if s[0] > 1.0 {
        2.0 * (half[0] * half[1] + half[1] * half[2] + half[0] * half[2])
    } else {
        2.0 * (half[1] + half[2])
    };
    let child = dissect(half, (separator + bound / 2.0).min(surface));
    let top = front(separator, bound);
    FactorCost {
        entries: top.entries + 2.0 * child.entries,
        flops: top.flops + 2.0 * child.flops,
    }
}

/// The columns of `pivots` rows eliminated in a dense front bounded by
/// `bound` more rows.
fn front(pivots: f64, bound: f64) -> FactorCost {
    let f = pivots + bound;
    FactorCost {
        entries: pivots * (pivots / 2.0 + bound),
        flops: pivots * f * f - pivots * pivots * f + pivots.powi(3) / 3.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dense_front_costs_a_cholesky() {
        // one front of n rows: n²/2 entries, n³/3 flops
        let c = front(30.0, 0.0);
        assert_eq!(c.entries, 450.0);
        assert!((c.flops - 9000.0).abs() < 1e-9);
        // a small box is one front, with d DOFs a node
        let c = nested_dissection([2.0, 2.0, 2.0], 3.0);
        assert_eq!(c.entries, 32.0 * 9.0);
    }

    #[test]
    fn grows_as_nested_dissection_does() {
        // 2D: entries O(n log n), flops O(n^{3/2}); 3D: O(n^{4/3}), O(n²)
        let ratio = |f: fn(f64) -> [f64; 3], k: f64| {
            let (a, b) = (
                nested_dissection(f(k), 1.0),
                nested_dissection(f(2.0 * k), 1.0),
            );
            (b.entries / a.entries, b.flops / a.flops)
        };
        let (e, fl) = ratio(|k| [k, k, 1.0], 400.0);
        assert!((4.0..5.0).contains(&e), "{e}");
        assert!((7.0..9.5).contains(&fl), "{fl}");
        let (e, fl) = ratio(|k| [k, k, k], 40.0);
        assert!((13.0..19.0).contains(&e), "{e}");
        assert!((50.0..72.0).contains(&fl), "{fl}");
    }

    #[test]
    fn measured_factors_are_within_the_stated_factors() {
        // faer's LDLᵀ of the direct path (module doc): (sides, d, nnz, flops)
        for (sides, d, nnz, flops) in [
            ([101.0, 101.0, 3.0], 3.0, 11_502_095.0, 4.022e9),
            ([49.0, 49.0, 3.0], 3.0, 2_188_979.0, 5.142e8),
            ([16.0, 16.0, 16.07], 3.0, 4_369_319.0, 2.245e9),
            ([41.0, 41.0, 2.0], 3.0, 1_392_103.0, 2.964e8),
            ([74.2, 74.2, 1.0], 2.0, 672_316.0, 6.218e7),
        ] {
            let c = nested_dissection(sides, d);
            let (re, rf) = (nnz / c.entries, flops / c.flops);
            assert!((0.5..=2.0).contains(&re), "{sides:?}: entries {re}");
            assert!((1.0 / 3.0..=3.0).contains(&rf), "{sides:?}: flops {rf}");
        }
    }
}
