//! Nested-dissection fill-reducing ordering of a sparse symmetric matrix
//! graph by METIS (`METIS_NodeND`, George's nested dissection with multilevel
//! vertex separators): the graph is split by a small separator, the two
//! halves are ordered first (recursively) and the separator last, so that
//! eliminating one half never fills the other. For the stiffness of a 3D mesh
//! the Cholesky factor holds O(n^{4/3}) entries and costs O(n²) flops, against
//! the larger fill a minimum-degree ordering leaves on such meshes.
//!
//! `metis` 0.2 does not wrap `METIS_NodeND`; it is called through `metis-sys`
//! (the same vendored METIS, docs/architecture.md, "Libraries"), holding the lock that every METIS
//! call in this crate holds ([`crate::partition`]), with a fixed seed.
//! METIS compresses vertices with identical adjacency (the `dim` DOFs of a
//! node) before ordering (its default `METIS_OPTION_COMPRESS`), so a DOF graph
//! is ordered node by node.

use metis::Idx;

use crate::MeshError;

/// Nested-dissection ordering (forward, inverse) of the graph with `n`
/// vertices whose neighbours of vertex v are `adjncy[xadj[v]..xadj[v + 1]]`
/// (CSR; symmetric, no self loops). `fwd[i]` is the vertex eliminated i-th and
/// `inv[fwd[i]] = i` (faer's `PermRef` convention). Errors: a graph too large
/// for METIS's 32-bit indices, a malformed graph, or a METIS failure.
pub fn nested_dissection(
    xadj: &[usize],
    adjncy: &[usize],
) -> Result<(Vec<usize>, Vec<usize>), MeshError> {
    let n = xadj.len().saturating_sub(1);
    if n == 0 {
        return Ok((Vec::new(), Vec::new()));
    }
    let to_idx = |v: usize| {
        Idx::try_from(v).map_err(|_| {
            MeshError::Invalid(format!(
                "nested dissection: the graph ({n} vertices, {} edges) does not fit METIS's 32-bit indices",
                adjncy.len()
            ))
        })
    };
    let mut x: Vec<Idx> = xadj.iter().map(|&v| to_idx(v)).collect::<Result<_, _>>()?;
    let mut a: Vec<Idx> = adjncy
        .iter()
        .map(|&v| to_idx(v))
        .collect::<Result<_, _>>()?;
    if xadj[n] != adjncy.len() || a.iter().any(|&v| v as usize >= n) {
        return Err(MeshError::Invalid(
            "nested dissection: malformed graph (CSR arrays do not match)".into(),
        ));
    }
    let mut nv = to_idx(n)?;
    let mut perm = vec![0 as Idx; n];
    let mut iperm = vec![0 as Idx; n];
    let mut options = [0 as Idx; metis_sys::METIS_NOPTIONS as usize];
    // A panic elsewhere while holding the lock leaves nothing half-done here.
    let _metis = crate::partition::METIS
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    // SAFETY: every array has the length METIS_NodeND reads (nv + 1, the
    // edge count, nv, nv, METIS_NOPTIONS), the graph was checked above, and
    // vwgt = NULL asks for unit vertex weights.
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        options[metis_sys::moptions_et_METIS_OPTION_SEED as usize] = crate::partition::SEED;
        metis_sys::METIS_NodeND(
            &mut nv,
            x.as_mut_ptr(),
            a.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(MeshError::Invalid(format!(
            "nested dissection: METIS_NodeND failed (status {status}) on a graph of {n} vertices"
        )));
    }
    let fwd: Vec<usize> = perm.iter().map(|&p| p as usize).collect();
    let inv: Vec<usize> = iperm.iter().map(|&p| p as usize).collect();
    Ok((fwd, inv))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CSR graph of an nx × ny grid (4-neighbour).
    fn grid(nx: usize, ny: usize) -> (Vec<usize>, Vec<usize>) {
        let mut xadj = vec![0];
        let mut adj = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                if i > 0 {
                    adj.push(i - 1 + nx * j);
                }
                if i + 1 < nx {
                    adj.push(i + 1 + nx * j);
                }
                if j > 0 {
                    adj.push(i + nx * (j - 1));
                }
                if j + 1 < ny {
                    adj.push(i + nx * (j + 1));
                }
                xadj.push(adj.len());
            }
        }
        (xadj, adj)
    }

    #[test]
    fn ordering_is_a_permutation_with_a_separator_last() {
        let (nx, ny) = (15, 15);
        let (xadj, adj) = grid(nx, ny);
        let (fwd, inv) = nested_dissection(&xadj, &adj).unwrap();
        let n = nx * ny;
        let mut seen = vec![false; n];
        for (i, &v) in fwd.iter().enumerate() {
            assert!(!seen[v]);
            seen[v] = true;
            assert_eq!(inv[v], i);
        }
        // The top-level separator of a 15 × 15 grid is one line of at most
        // ~15 vertices, ordered last: removing the last 20 vertices of the
        // ordering disconnects the grid.
        let removed: Vec<bool> = (0..n).map(|v| inv[v] >= n - 20).collect();
        let start = (0..n).find(|&v| !removed[v]).unwrap();
        let mut reached = vec![false; n];
        let mut stack = vec![start];
        reached[start] = true;
        while let Some(v) = stack.pop() {
            for &w in &adj[xadj[v]..xadj[v + 1]] {
                if !removed[w] && !reached[w] {
                    reached[w] = true;
                    stack.push(w);
                }
            }
        }
        let kept = removed.iter().filter(|r| !**r).count();
        let hit = reached.iter().filter(|r| **r).count();
        assert!(hit < kept, "{hit} of {kept} reached: no separator last");
        // Reproducible.
        assert_eq!(nested_dissection(&xadj, &adj).unwrap().0, fwd);
    }

    #[test]
    fn malformed_graph_is_refused() {
        assert!(nested_dissection(&[0, 1, 2], &[1, 5]).is_err());
        assert!(nested_dissection(&[0], &[]).unwrap().0.is_empty());
    }
}
