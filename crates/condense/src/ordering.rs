//! Fill-reducing ordering of a sparse symmetric matrix with some trailing
//! rows kept last (the interface of a subdomain, docs/architecture.md, "Libraries"), and
//! the symbolic supernodal Cholesky factor it gives.
//!
//! Two orderings of the leading `n_ordered` rows are available: approximate
//! minimum degree (AMD, faer's) and nested dissection (METIS_NodeND, through
//! `signorini_mesh::nested_dissection`). Minimum degree is local and greedy:
//! on 2D meshes and small problems it is as good as nested dissection and
//! cheaper to compute; on 3D meshes its factor fills far more (O(n^{5/3})
//! against O(n^{4/3}) entries for a cube of n nodes). [`OrderingChoice::Auto`]
//! orders by AMD first; when that factor costs at least
//! [`ND_WORTH_TRYING_FLOPS`] it also orders by nested dissection, builds both
//! symbolic factors (cheap: no floating-point work) and keeps the one that
//! needs fewer factorisation flops ([`FactorStats::flops`]; ties go to AMD).
//! Measured (docs/performance/scale-3d.md): the Hertz sphere at 127k DOFs, 4.0× fewer
//! flops and half the factor with nested dissection (12k DOFs: 1.8× fewer
//! flops, 10–15 % less CPU time); the 2D Hertz cylinder at 11k DOFs
//! (AMD 1.7e8 flops), 1.8× fewer flops but no faster: METIS's ordering and
//! the second symbolic factor cost what the factorisation saves. Hence the
//! threshold of 1e9 flops (about 0.1 s of factorisation on 2 cores). On
//! graphs of [`BOTH_AT_ONCE_EDGES`] edges or more, where AMD always costs more
//! than that, the two orderings and their symbolic factors are computed at
//! once on two threads (the 127k-DOF sphere: 0.9–1.3 s less of 15–16 s).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::Side;

use crate::CondenseError;

/// Under [`OrderingChoice::Auto`], nested dissection is tried only when the
/// AMD factor costs at least this many flops (about 0.1 s of
/// factorisation: below, METIS costs what it could save).
pub const ND_WORTH_TRYING_FLOPS: f64 = 1e9;

/// Under [`OrderingChoice::Auto`], a graph of at least this many edges
/// (3D meshes from about 12k DOFs, 2D from about 60k, where AMD's factor
/// always costs more than [`ND_WORTH_TRYING_FLOPS`]) is ordered by AMD and
/// by nested dissection at once on two threads, each with its symbolic
/// factor: the slower of the two instead of their sum.
const BOTH_AT_ONCE_EDGES: usize = 1_000_000;

/// A fill-reducing ordering.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ordering {
    /// Approximate minimum degree (faer).
    Amd,
    /// Nested dissection (METIS_NodeND).
    NestedDissection,
}

impl Ordering {
    /// The name used in report.json.
    pub fn as_str(self) -> &'static str {
        match self {
            Ordering::Amd => "amd",
            Ordering::NestedDissection => "nested_dissection",
        }
    }
}

/// Which ordering to use: one of them, or the cheaper of both.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OrderingChoice {
    /// Both orderings, the one whose factor needs fewer flops kept.
    #[default]
    Auto,
    /// This ordering only.
    Only(Ordering),
}

/// Size and cost of a Cholesky factor, from its symbolic structure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FactorStats {
    pub ordering: Ordering,
    /// Entries of L as stored (supernodes are dense blocks: their upper
    /// triangles count in `values`, not here).
    pub nnz: usize,
    /// Stored values of L (f64), the factor's memory is 8 × `values` bytes.
    pub values: usize,
    /// Factorisation cost Σ_j c_j² over the columns j of L, c_j the entries
    /// of column j (diagonal included): the usual count of floating-point
    /// operations of a sparse Cholesky (one multiply-add = 2 flops).
    pub flops: f64,
}

/// An ordering with its symbolic factor: `fwd[i]` is the row eliminated
/// i-th, `inv` its inverse; the rows from `n_ordered` on keep their place.
pub struct OrderedSymbolic {
    pub symbolic: SymbolicCholesky<usize>,
    pub fwd: Vec<usize>,
    pub inv: Vec<usize>,
    /// The kept ordering's factor.
    pub stats: FactorStats,
    /// Every ordering computed (one, or both under `Auto`), kept one first.
    pub candidates: Vec<FactorStats>,
}

/// The graph of the rows `lead` (in that order, ascending) of a matrix with
/// a symmetric pattern, read from its strictly lower entries (row > column)
/// and mirrored, so that both triangles or the lower one alone may be
/// stored; `position[r]` is the place of row r in `lead` (usize::MAX for
/// the other rows): CSR arrays without the diagonal, each row ascending.
fn leading_graph(
    a: SymbolicSparseColMatRef<'_, usize>,
    lead: &[usize],
    position: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let below = |k: usize| {
        let c = lead[k];
        (a.row_idx_of_col_raw(c).iter())
            .filter(move |&&r| r > c)
            .map(|&r| position[r])
            .filter(|&p| p != usize::MAX)
    };
    let mut xadj = vec![0usize; lead.len() + 1];
    for k in 0..lead.len() {
        for p in below(k) {
            xadj[k + 1] += 1;
            xadj[p + 1] += 1;
        }
    }
    for k in 0..lead.len() {
        xadj[k + 1] += xadj[k];
    }
    // Column k appends its lower neighbours to row k and itself to theirs:
    // every row gets its smaller neighbours first, then its larger ones.
    let mut next = xadj[..lead.len()].to_vec();
    let mut adjncy = vec![0usize; xadj[lead.len()]];
    for k in 0..lead.len() {
        for p in below(k) {
            adjncy[next[k]] = p;
            next[k] += 1;
            adjncy[next[p]] = k;
            next[p] += 1;
        }
    }
    (xadj, adjncy)
}

/// AMD ordering (forward, inverse) of a graph in CSR form.
fn amd_of_graph(
    xadj: &[usize],
    adjncy: &[usize],
) -> Result<(Vec<usize>, Vec<usize>), CondenseError> {
    let n = xadj.len() - 1;
    let mut fwd = vec![0usize; n];
    let mut inv = vec![0usize; n];
    if n == 0 {
        return Ok((fwd, inv));
    }
    let graph = SymbolicSparseColMatRef::new_unsorted_checked(n, n, xadj, None, adjncy);
    let mut mem = MemBuffer::new(amd::order_maybe_unsorted_scratch::<usize>(n, adjncy.len()));
    amd::order_maybe_unsorted(
        &mut fwd,
        &mut inv,
        graph,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| CondenseError::Factorisation(format!("AMD: {e:?}")))?;
    Ok((fwd, inv))
}

/// Size and flops of a symbolic Cholesky factor.
pub fn factor_stats(symbolic: &SymbolicCholesky<usize>, ordering: Ordering) -> FactorStats {
    let mut nnz = 0usize;
    let mut flops = 0.0f64;
    let mut count = |c: usize| {
        nnz += c;
        flops += (c as f64) * (c as f64);
    };
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => {
            let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
            let ptr = sn.col_ptr_for_row_idx();
            for s in 0..sn.n_supernodes() {
                let ncols = end[s] - begin[s];
                let below = ptr[s + 1] - ptr[s];
                for jj in 0..ncols {
                    count(ncols - jj + below);
                }
            }
        }
        SymbolicCholeskyRaw::Simplicial(sp) => {
            // Each column of L stores its diagonal first.
            for w in sp.col_ptr().windows(2) {
                count(w[1] - w[0]);
            }
        }
    }
    FactorStats {
        ordering,
        nnz,
        values: symbolic.len_val(),
        flops,
    }
}

/// The supernodal symbolic factor of `a` in the ordering (fwd, inv);
/// refused when the final permutation does not end with `last`.
fn symbolic_in(
    a: SymbolicSparseColMatRef<'_, usize>,
    fwd: &[usize],
    inv: &[usize],
    last: &[usize],
) -> Result<SymbolicCholesky<usize>, CondenseError> {
    let n = a.nrows();
    let symbolic = factorize_symbolic_cholesky(
        a,
        Side::Lower,
        SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n)),
        CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        },
    )
    .map_err(|e| CondenseError::Factorisation(format!("{e:?}")))?;
    if let Some(p) = symbolic.perm() {
        let (f, _) = p.arrays();
        if f[n - last.len()..] != *last {
            return Err(CondenseError::Factorisation(
                "the ordering did not keep the interface last".into(),
            ));
        }
    }
    Ok(symbolic)
}

/// Orders the leading `n_ordered` rows of `a` (symmetric pattern, both
/// triangles or the lower one stored) by `choice`, keeps the other rows last in their order,
/// and returns the supernodal symbolic Cholesky factor of the ordering kept
/// (module doc: under `Auto`, AMD, or the one with fewer flops when AMD's
/// factor costs [`ND_WORTH_TRYING_FLOPS`] or more).
pub fn order_and_analyse<T>(
    a: SparseColMatRef<'_, usize, T>,
    n_ordered: usize,
    choice: OrderingChoice,
) -> Result<OrderedSymbolic, CondenseError> {
    let last: Vec<usize> = (n_ordered..a.nrows()).collect();
    order_and_analyse_with_last(a, &last, choice)
}

/// As [`order_and_analyse`] with the rows `last` (distinct, in that order)
/// eliminated last wherever they are in `a`: the others are ordered by
/// `choice` (the factor's numbering is `fwd`, ending with `last`).
pub fn order_and_analyse_with_last<T>(
    a: SparseColMatRef<'_, usize, T>,
    last: &[usize],
    choice: OrderingChoice,
) -> Result<OrderedSymbolic, CondenseError> {
    let n = a.nrows();
    let mut position = vec![0usize; n];
    for &r in last {
        position[r] = usize::MAX;
    }
    let lead: Vec<usize> = (0..n).filter(|&r| position[r] != usize::MAX).collect();
    for (k, &r) in lead.iter().enumerate() {
        position[r] = k;
    }
    let (xadj, adjncy) = leading_graph(a.symbolic(), &lead, &position);
    let pattern = a.symbolic();
    let analyse = |kind: Ordering| -> Result<OrderedSymbolic, CondenseError> {
        let (fwd, kind) = match kind {
            Ordering::Amd => (amd_of_graph(&xadj, &adjncy)?.0, kind),
            Ordering::NestedDissection => {
                let (f, _) = signorini_mesh::nested_dissection::nested_dissection(&xadj, &adjncy)
                    .map_err(|e| CondenseError::Factorisation(e.to_string()))?;
                (f, kind)
            }
        };
        let (fwd, inv) = with_last(&lead, &fwd, last);
        let symbolic = symbolic_in(pattern, &fwd, &inv, last)?;
        let stats = factor_stats(&symbolic, kind);
        Ok(OrderedSymbolic {
            symbolic,
            fwd,
            inv,
            stats,
            candidates: Vec::new(),
        })
    };
    let tried: Vec<OrderedSymbolic> = match choice {
        OrderingChoice::Only(kind) => vec![analyse(kind)?],
        OrderingChoice::Auto => {
            let at_once =
                adjncy.len() >= BOTH_AT_ONCE_EDGES && faer::get_global_parallelism().degree() >= 2;
            let (amd, nd) = if at_once {
                std::thread::scope(|s| {
                    let nd = s.spawn(|| analyse(Ordering::NestedDissection));
                    let amd = analyse(Ordering::Amd);
                    let nd = nd.join().unwrap_or_else(|_| {
                        Err(CondenseError::Factorisation(
                            "nested dissection failed".into(),
                        ))
                    });
                    (amd, Some(nd))
                })
            } else {
                (analyse(Ordering::Amd), None)
            };
            let amd = amd?;
            if amd.stats.flops < ND_WORTH_TRYING_FLOPS {
                vec![amd]
            } else {
                let nd = nd.unwrap_or_else(|| analyse(Ordering::NestedDissection))?;
                vec![amd, nd]
            }
        }
    };
    let mut candidates: Vec<FactorStats> = tried.iter().map(|t| t.stats).collect();
    // The fewest flops; a tie goes to the first tried (AMD).
    let best = tried
        .into_iter()
        .reduce(|b, t| if t.stats.flops < b.stats.flops { t } else { b });
    let mut best = best.expect("at least one ordering is tried");
    candidates.sort_by_key(|c| c.ordering != best.stats.ordering);
    best.candidates = candidates;
    Ok(best)
}

/// The whole ordering: `lead[fwd_lead[k]]` for k in order, then `last`;
/// (forward, inverse).
fn with_last(lead: &[usize], fwd_lead: &[usize], last: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let fwd: Vec<usize> = fwd_lead
        .iter()
        .map(|&k| lead[k])
        .chain(last.iter().copied())
        .collect();
    let mut inv = vec![0; fwd.len()];
    for (i, &r) in fwd.iter().enumerate() {
        inv[r] = i;
    }
    (fwd, inv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_matrices::grid3;
    use faer::sparse::{SparseColMat, Triplet};

    #[test]
    fn auto_keeps_the_cheaper_ordering_and_the_trailing_rows_last() {
        let m = 32;
        let a = grid3(m, true);
        let n = a.nrows();
        let n_ordered = n - m * m; // top layer last
        let auto = order_and_analyse(a.as_ref(), n_ordered, OrderingChoice::Auto).unwrap();
        assert!(auto.candidates[1].flops >= ND_WORTH_TRYING_FLOPS);
        assert_eq!(auto.candidates.len(), 2);
        assert_eq!(auto.candidates[0], auto.stats);
        let other = auto.candidates[1];
        assert!(auto.stats.flops <= other.flops);
        assert!((n_ordered..n).all(|i| auto.fwd[i] == i && auto.inv[i] == i));
        // On a 3D grid nested dissection is the cheaper one.
        assert_eq!(auto.stats.ordering, Ordering::NestedDissection);
        // The counts are those of the factor: at least the lower triangle of
        // the matrix, and flops ≥ nnz.
        assert!(auto.stats.nnz >= (a.compute_nnz() + n) / 2);
        assert!(auto.stats.flops >= auto.stats.nnz as f64);
        assert!(auto.stats.values >= auto.stats.nnz);
        // A small problem keeps AMD without calling METIS.
        let small = grid3(4, true);
        let auto = order_and_analyse(small.as_ref(), 48, OrderingChoice::Auto).unwrap();
        assert_eq!(auto.candidates.len(), 1);
        assert_eq!(auto.stats.ordering, Ordering::Amd);
        assert!(auto.stats.flops < ND_WORTH_TRYING_FLOPS);
    }

    /// A graph large enough to be ordered by both at once (on two threads
    /// when there are two cores): the same choice, ordering and flops as
    /// the two orderings one after the other.
    #[test]
    fn both_orderings_at_once_choose_as_one_after_the_other() {
        let m = 58;
        let a = grid3(m, true);
        let n = a.nrows();
        assert!(a.compute_nnz() - n >= BOTH_AT_ONCE_EDGES);
        let n_ordered = n - m * m;
        let auto = order_and_analyse(a.as_ref(), n_ordered, OrderingChoice::Auto).unwrap();
        let amd =
            order_and_analyse(a.as_ref(), n_ordered, OrderingChoice::Only(Ordering::Amd)).unwrap();
        let nd = order_and_analyse(
            a.as_ref(),
            n_ordered,
            OrderingChoice::Only(Ordering::NestedDissection),
        )
        .unwrap();
        let best = if nd.stats.flops < amd.stats.flops {
            &nd
        } else {
            &amd
        };
        assert_eq!(auto.stats, best.stats);
        assert_eq!(auto.fwd, best.fwd);
        assert_eq!(auto.candidates.len(), 2);
        assert_eq!(
            auto.candidates[1],
            if best.stats == nd.stats {
                amd.stats
            } else {
                nd.stats
            }
        );
    }

    /// The Schur complement and condensed load do not depend on the
    /// ordering: AMD and nested dissection agree to rounding (relative to
    /// ‖K‖), on a held and on a floating 3D block.
    #[test]
    fn amd_and_nested_dissection_give_the_same_schur_complement() {
        use crate::Condensed;
        use faer::Par;
        let m = 10;
        for held in [true, false] {
            // Floating: zero row sums (a pure Neumann block).
            let a = grid3(m, held);
            let n = a.nrows();
            let interface: Vec<usize> = (n - m * m..n).chain([0, 37, 501]).collect();
            let f: Vec<f64> = (0..n).map(|i| ((i * 13) % 7) as f64 - 3.0).collect();
            let condensed = |o: Ordering| {
                Condensed::with_ordering(a.as_ref(), &interface, OrderingChoice::Only(o), Par::Seq)
                    .unwrap()
            };
            let (amd, nd) = (
                condensed(Ordering::Amd),
                condensed(Ordering::NestedDissection),
            );
            assert_eq!(amd.factor_stats().ordering, Ordering::Amd);
            assert_eq!(nd.factor_stats().ordering, Ordering::NestedDissection);
            assert_ne!(amd.factor_stats().nnz, nd.factor_stats().nnz);
            let k_norm = a.val().iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let nb = interface.len();
            for j in 0..nb {
                for i in 0..nb {
                    let d = (amd.schur[(i, j)] - nd.schur[(i, j)]).abs();
                    assert!(
                        d <= 1e-12 * k_norm,
                        "held {held}: S[{i},{j}] differs by {d:e}"
                    );
                }
            }
            let (fa, fn_) = (amd.condensed_load(&f), nd.condensed_load(&f));
            let f_norm = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (x, y) in fa.iter().zip(&fn_) {
                assert!((x - y).abs() <= 1e-12 * f_norm, "F' {x} vs {y}");
            }
        }
    }

    /// The lower triangle alone orders as both triangles do: the same
    /// graph, hence the same orderings and factor.
    #[test]
    fn the_lower_triangle_alone_gives_the_same_graph_and_factor() {
        let a = grid3(9, true);
        let n = a.nrows();
        let lower: Vec<Triplet<usize, usize, f64>> = (0..n)
            .flat_map(|c| {
                let (rows, vals) = (a.row_idx_of_col_raw(c), a.val_of_col(c));
                rows.iter()
                    .zip(vals)
                    .filter(move |(&r, _)| r >= c)
                    .map(move |(&r, &v)| Triplet::new(r, c, v))
                    .collect::<Vec<_>>()
            })
            .collect();
        let l = SparseColMat::try_new_from_triplets(n, n, &lower).unwrap();
        let lead: Vec<usize> = (0..n - 20).collect();
        let mut position = vec![usize::MAX; n];
        lead.iter().enumerate().for_each(|(k, &r)| position[r] = k);
        let full = leading_graph(a.symbolic(), &lead, &position);
        assert_eq!(leading_graph(l.symbolic(), &lead, &position), full);
        assert!(full.1.len() > 4 * lead.len());
        for choice in [Ordering::Amd, Ordering::NestedDissection] {
            let f = order_and_analyse(a.as_ref(), n - 20, OrderingChoice::Only(choice)).unwrap();
            let g = order_and_analyse(l.as_ref(), n - 20, OrderingChoice::Only(choice)).unwrap();
            assert_eq!((f.fwd, f.stats), (g.fwd, g.stats));
        }
    }
}
