//! Minimum degree on indistinguishable blocks: the fill-reducing ordering of
//! a matrix made of overlapping dense blocks, such as the interface
//! stiffness S = Σ_i S_i of several subdomains (seed §8.3; each S_i is dense
//! on its interface DOFs).
//!
//! Two vertices are indistinguishable when their closed neighbourhoods
//! (adjacent vertices and themselves) are equal: in S, every Γ DOF shared by
//! the same subdomains (a face, an edge or a corner of the decomposition, or
//! the contact DOFs of one subdomain). Eliminating them one after the other
//! creates the same fill as eliminating them together, so the ordering is
//! computed on the quotient graph of these blocks, a few dozen to a few
//! thousand vertices whatever the number of DOFs, by the minimum degree rule
//! weighted by block size (Tinney–Walker scheme 2; George & Liu, "The
//! evolution of the minimum degree ordering algorithm", SIAM Review 1989):
//! eliminate the block whose neighbours hold the fewest DOFs, make those
//! neighbours a clique, repeat. Each block's DOFs stay consecutive, so the
//! supernodal factor sees them as dense columns.

use std::cmp::Reverse;
use std::collections::{BTreeSet, BinaryHeap, HashMap};

/// Above this many blocks the quotient graph is no longer small (the matrix
/// is not made of a few dense blocks): the caller should order by AMD.
pub const MAX_BLOCKS: usize = 20_000;

/// The blocks of indistinguishable vertices of a graph in CSR form (no self
/// loops): `block[v]` for each vertex, and the number of blocks.
fn indistinguishable_blocks(xadj: &[usize], adjncy: &[usize]) -> (Vec<usize>, usize) {
    let n = xadj.len() - 1;
    let closed = |v: usize| {
        let mut c: Vec<usize> = adjncy[xadj[v]..xadj[v + 1]].to_vec();
        c.push(v);
        c.sort_unstable();
        c.dedup();
        c
    };
    let mut by_pattern: HashMap<Vec<usize>, usize> = HashMap::new();
    let mut block = vec![0; n];
    for (v, b) in block.iter_mut().enumerate() {
        let next = by_pattern.len();
        *b = *by_pattern.entry(closed(v)).or_insert(next);
    }
    (block, by_pattern.len())
}

/// The order of elimination of the blocks by weighted minimum degree on
/// their quotient graph `adj` (weights = DOFs per block).
fn minimum_degree(mut adj: Vec<BTreeSet<usize>>, weight: &[usize]) -> Vec<usize> {
    let g = adj.len();
    let degree = |adj: &[BTreeSet<usize>], v: usize| adj[v].iter().map(|&u| weight[u]).sum();
    let mut current: Vec<usize> = (0..g).map(|v| degree(&adj, v)).collect();
    let mut heap: BinaryHeap<Reverse<(usize, usize)>> =
        (0..g).map(|v| Reverse((current[v], v))).collect();
    let mut eliminated = vec![false; g];
    let mut order = Vec::with_capacity(g);
    while let Some(Reverse((d, v))) = heap.pop() {
        if eliminated[v] || d != current[v] {
            continue;
        }
        eliminated[v] = true;
        order.push(v);
        let neighbours: Vec<usize> = std::mem::take(&mut adj[v]).into_iter().collect();
        for &a in &neighbours {
            adj[a].remove(&v);
            adj[a].extend(neighbours.iter().copied().filter(|&b| b != a));
        }
        for &a in &neighbours {
            current[a] = degree(&adj, a);
            heap.push(Reverse((current[a], a)));
        }
    }
    order
}

/// Ordering (forward, inverse) of a graph in CSR form (symmetric, no self
/// loops) by minimum degree on its blocks of indistinguishable vertices;
/// `None` when it has more than [`MAX_BLOCKS`] blocks.
pub fn block_minimum_degree(xadj: &[usize], adjncy: &[usize]) -> Option<(Vec<usize>, Vec<usize>)> {
    let n = xadj.len() - 1;
    let (block, g) = indistinguishable_blocks(xadj, adjncy);
    if g > MAX_BLOCKS {
        return None;
    }
    let mut weight = vec![0usize; g];
    let mut representative = vec![usize::MAX; g];
    for (v, &b) in block.iter().enumerate() {
        weight[b] += 1;
        if representative[b] == usize::MAX {
            representative[b] = v;
        }
    }
    let adj: Vec<BTreeSet<usize>> = (0..g)
        .map(|b| {
            let v = representative[b];
            adjncy[xadj[v]..xadj[v + 1]]
                .iter()
                .map(|&u| block[u])
                .filter(|&c| c != b)
                .collect()
        })
        .collect();
    let order = minimum_degree(adj, &weight);
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); g];
    for (v, &b) in block.iter().enumerate() {
        members[b].push(v);
    }
    let fwd: Vec<usize> = order
        .iter()
        .flat_map(|&b| members[b].iter().copied())
        .collect();
    let mut inv = vec![0; n];
    for (i, &v) in fwd.iter().enumerate() {
        inv[v] = i;
    }
    Some((fwd, inv))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CSR graph of the union of cliques on the given vertex sets.
    fn cliques(n: usize, sets: &[Vec<usize>]) -> (Vec<usize>, Vec<usize>) {
        let mut adj: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
        for s in sets {
            for &a in s {
                adj[a].extend(s.iter().copied().filter(|&b| b != a));
            }
        }
        let mut xadj = vec![0];
        let mut adjncy = Vec::new();
        for a in adj {
            adjncy.extend(a);
            xadj.push(adjncy.len());
        }
        (xadj, adjncy)
    }

    #[test]
    fn blocks_of_two_overlapping_cliques_are_found_and_the_shared_block_goes_last() {
        // Subdomain A holds 0..6, B holds 4..10: blocks {0..4}, {4, 5}, {6..10}.
        let (xadj, adjncy) = cliques(10, &[(0..6).collect(), (4..10).collect()]);
        let (block, g) = indistinguishable_blocks(&xadj, &adjncy);
        assert_eq!(g, 3);
        assert!((0..4).all(|v| block[v] == block[0]));
        assert_eq!(block[4], block[5]);
        assert!((6..10).all(|v| block[v] == block[6]));
        let (fwd, inv) = block_minimum_degree(&xadj, &adjncy).unwrap();
        // Eliminating a private block first makes no fill; the glue last.
        assert_eq!(&fwd[8..], &[4, 5]);
        assert!((0..10).all(|v| fwd[inv[v]] == v));
    }

    #[test]
    fn ring_of_subdomains_keeps_blocks_together_and_starts_with_a_private_one() {
        // Eight subdomains in a ring, each holding 5 DOFs of its own and
        // sharing a block of 3 with the next.
        let parts = 8;
        let mut sets = Vec::new();
        for p in 0..parts {
            let own: Vec<usize> = (0..5).map(|i| 8 * p + i).collect();
            let left: Vec<usize> = (0..3).map(|i| 8 * p + 5 + i).collect();
            let right: Vec<usize> = (0..3).map(|i| 8 * ((p + 1) % parts) + 5 + i).collect();
            sets.push([own, left, right].concat());
        }
        let (xadj, adjncy) = cliques(8 * parts, &sets);
        let (block, g) = indistinguishable_blocks(&xadj, &adjncy);
        assert_eq!(g, 2 * parts);
        let (fwd, inv) = block_minimum_degree(&xadj, &adjncy).unwrap();
        assert!((0..8 * parts).all(|v| fwd[inv[v]] == v));
        // a private block (degree 6) before any glue (degree 16)
        assert!(fwd[..5].iter().all(|&v| v % 8 < 5), "{fwd:?}");
        // every block's vertices are consecutive
        let changes = fwd
            .windows(2)
            .filter(|w| block[w[0]] != block[w[1]])
            .count();
        assert_eq!(changes, g - 1, "{fwd:?}");
    }
}
