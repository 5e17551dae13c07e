//! Condensing only what contact needs: a contact node whose
//! constraint rows all act along one direction n (frictionless contact
//! against a rigid surface, or along a fixed normal) has its DOFs rotated
//! into the frame (n, t1, t2) before condensation, and only its normal
//! component ũ_n = n·u is an interface DOF; its tangential components are
//! interior DOFs of its subdomain. A 3D frictionless contact node then adds
//! one Γ DOF instead of three.
//!
//! With Q = [n t1 t2] (orthonormal) on such a node and the identity
//! elsewhere, u = T ũ; the subdomain condenses K̃ = Tᵀ K T with the loads
//! f̃ = Tᵀ f, and recovers u = T ũ. A contact row Σ c·u on the node becomes
//! (c·n) ũ_n, since c ∥ n. A node is rotated only when nothing else needs
//! its Cartesian components on Γ: no prescribed DOF, not shared between
//! subdomains (glue is Cartesian), no tangential (friction) row, and a body
//! without rigid modes held by contact.

use crate::model::{BodyModel, PointModel};

/// The normal of each rotated node, per body and node (`None`: Cartesian).
#[derive(Debug, Clone, Default)]
pub struct ContactFrames {
    normal: Vec<Vec<Option<[f64; 3]>>>,
}

/// Two coefficient vectors are parallel when the part of c across n is
/// below this fraction of |c| (normals of one rigid plane agree to
/// round-off; those of a curved master differ by far more).
const PARALLEL: f64 = 1e-9;

impl ContactFrames {
    /// No rotated node (the direct path, or to turn the reduction off).
    pub fn none(bodies: &[BodyModel]) -> Self {
        Self {
            normal: bodies
                .iter()
                .map(|b| vec![None; b.mesh.n_nodes()])
                .collect(),
        }
    }

    /// The nodes whose every constraint row acts along one direction;
    /// `shared[b][node]`: the node is on the boundary between parts of body b.
    pub fn decide(bodies: &[BodyModel], points: &[PointModel], shared: &[Vec<bool>]) -> Self {
        let mut frames = Self::none(bodies);
        // Per node: the first direction seen, and whether it may rotate.
        let mut ok: Vec<Vec<bool>> = bodies
            .iter()
            .enumerate()
            .map(|(b, body)| {
                (0..body.mesh.n_nodes())
                    .map(|n| {
                        let dim = body.mesh.dim;
                        body.kernel.is_empty()
                            && !shared[b][n]
                            && (0..dim).all(|d| !body.prescribed[dim * n + d])
                    })
                    .collect()
            })
            .collect();
        for p in points {
            for row in [&p.trow, &p.trow2].into_iter().flatten() {
                for &(b, d, _) in row {
                    ok[b][d / bodies[b].mesh.dim] = false;
                }
            }
            for (b, node, c) in node_vectors(bodies, &p.row) {
                frames.meet(b, node, c, &mut ok[b][node]);
            }
        }
        for (b, nodes) in frames.normal.iter_mut().enumerate() {
            for (n, slot) in nodes.iter_mut().enumerate() {
                if !ok[b][n] {
                    *slot = None;
                }
            }
        }
        frames
    }

    /// Records the coefficient vector c of one row on a node: the first
    /// sets the node's direction, a later one not parallel to it clears `ok`.
    fn meet(&mut self, b: usize, node: usize, c: [f64; 3], ok: &mut bool) {
        let len = norm(c);
        if len.is_nan() || len <= 0.0 {
            return;
        }
        let unit = c.map(|x| x / len);
        match self.normal[b][node] {
            None => self.normal[b][node] = Some(unit),
            Some(n) => {
                let along = dot(c, n);
                let across = norm([
                    c[0] - along * n[0],
                    c[1] - along * n[1],
                    c[2] - along * n[2],
                ]);
                if across > PARALLEL * len {
                    *ok = false;
                }
            }
        }
    }

    /// The normal of body b's node, if it is rotated.
    pub fn normal(&self, b: usize, node: usize) -> Option<[f64; 3]> {
        self.normal
            .get(b)
            .and_then(|v| v.get(node).copied().flatten())
    }

    /// How many nodes are rotated.
    pub fn count(&self) -> usize {
        self.normal.iter().flatten().filter(|n| n.is_some()).count()
    }

    /// A row (body, DOF, coefficient) in the rotated components: on a
    /// rotated node the Cartesian terms merge into one on its component 0
    /// (the normal), with coefficient c·n.
    pub fn rotate_row(
        &self,
        bodies: &[BodyModel],
        row: &[(usize, usize, f64)],
    ) -> Vec<(usize, usize, f64)> {
        let mut out: Vec<(usize, usize, f64)> = Vec::with_capacity(row.len());
        for &(b, d, c) in row {
            let dim = bodies[b].mesh.dim;
            match self.normal(b, d / dim) {
                None => out.push((b, d, c)),
                Some(n) => {
                    let d0 = d - d % dim;
                    let v = c * n[d % dim];
                    match out.iter_mut().find(|e| e.0 == b && e.1 == d0) {
                        Some(e) => e.2 += v,
                        None => out.push((b, d0, v)),
                    }
                }
            }
        }
        out
    }

    /// A row (body, DOF, coefficient) on Γ: rotated ([`Self::rotate_row`]),
    /// prescribed DOFs left out, each DOF by its Γ index in `gamma_of`.
    pub fn gamma_row(
        &self,
        bodies: &[BodyModel],
        gamma_of: &[Vec<usize>],
        row: &[(usize, usize, f64)],
    ) -> Vec<(usize, f64)> {
        self.rotate_row(bodies, row)
            .iter()
            .filter(|&&(b, d, _)| !bodies[b].prescribed[d])
            .map(|&(b, d, c)| (gamma_of[b][d], c))
            .collect()
    }

    /// The rotations of body b's nodes `nodes` (all of them: `None`).
    pub fn local(&self, b: usize, dim: usize, nodes: Option<&[usize]>) -> LocalFrames {
        LocalFrames {
            dim,
            normal: match nodes {
                Some(nodes) => nodes.iter().map(|&n| self.normal[b][n]).collect(),
                None => self.normal[b].clone(),
            },
        }
    }
}

/// The coefficient vector of a row on each node it touches: (body, node, c).
fn node_vectors(
    bodies: &[BodyModel],
    row: &[(usize, usize, f64)],
) -> Vec<(usize, usize, [f64; 3])> {
    let mut out: Vec<(usize, usize, [f64; 3])> = Vec::new();
    for &(b, d, c) in row {
        let dim = bodies[b].mesh.dim;
        let node = d / dim;
        match out.iter_mut().find(|e| e.0 == b && e.1 == node) {
            Some(e) => e.2[d % dim] += c,
            None => {
                let mut v = [0.0; 3];
                v[d % dim] = c;
                out.push((b, node, v));
            }
        }
    }
    out
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// An orthonormal basis Q (Q[d][k]: component d of column k) whose first
/// column is the unit vector n: in 2D (n, n⊥), in 3D (n, t1, t2) with t1
/// across the axis along which n is smallest.
pub fn basis(n: [f64; 3], dim: usize) -> [[f64; 3]; 3] {
    let mut q = [[0.0; 3]; 3];
    if dim == 2 {
        let t = [-n[1], n[0], 0.0];
        for d in 0..2 {
            q[d][0] = n[d];
            q[d][1] = t[d];
        }
        return q;
    }
    let axis = (0..3)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[axis] = 1.0;
    let along = dot(e, n);
    let t1 = [
        e[0] - along * n[0],
        e[1] - along * n[1],
        e[2] - along * n[2],
    ];
    let l = norm(t1);
    let t1 = t1.map(|x| x / l);
    let t2 = [
        n[1] * t1[2] - n[2] * t1[1],
        n[2] * t1[0] - n[0] * t1[2],
        n[0] * t1[1] - n[1] * t1[0],
    ];
    for d in 0..3 {
        q[d][0] = n[d];
        q[d][1] = t1[d];
        q[d][2] = t2[d];
    }
    q
}

/// Rotations of one subdomain's local DOFs: the normal of each local node
/// (`None`: Cartesian), `dim` DOFs per node.
pub struct LocalFrames {
    pub dim: usize,
    pub normal: Vec<Option<[f64; 3]>>,
}

impl LocalFrames {
    pub fn is_identity(&self) -> bool {
        self.normal.iter().all(|n| n.is_none())
    }

    /// The entries of column l of T (u = T ũ): (row, value).
    fn t_col(&self, l: usize) -> Vec<(usize, f64)> {
        self.t_line(l, false)
    }

    /// The entries of column l of T (`row` false: (row, value)) or of its
    /// row l (`row` true: (column, value)); T is block diagonal, a node's
    /// block its frame Q, or 1 where the node has none.
    fn t_line(&self, l: usize, row: bool) -> Vec<(usize, f64)> {
        let (dim, node, k) = (self.dim, l / self.dim, l % self.dim);
        match self.normal[node] {
            None => vec![(l, 1.0)],
            Some(n) => {
                let q = basis(n, dim);
                let entry = |d: usize| if row { q[k][d] } else { q[d][k] };
                (0..dim).map(|d| (dim * node + d, entry(d))).collect()
            }
        }
    }

    /// K̃ = Tᵀ K T, in place when every rotated node's rows and columns
    /// form full `dim`-blocks of K's pattern (as the assembly makes them:
    /// then K̃ has K's pattern), else by [`Self::rotated_copy`].
    pub fn rotate_stiffness(
        &self,
        mut k: faer::sparse::SparseColMat<usize, f64>,
    ) -> Result<faer::sparse::SparseColMat<usize, f64>, String> {
        if !self.has_full_blocks(k.symbolic()) {
            return self.rotated_copy(k.as_ref());
        }
        let dim = self.dim;
        let (sym, val) = k.parts_mut();
        // Rows: each column's block of a rotated node ← Qᵀ block.
        for j in 0..sym.ncols() {
            let range = sym.col_range(j);
            let rows = &sym.row_idx()[range.clone()];
            let mut p = 0;
            while p < rows.len() {
                match self.normal[rows[p] / dim] {
                    Some(n) if rows[p] % dim == 0 => {
                        let q = basis(n, dim);
                        let v = &mut val[range.start + p..range.start + p + dim];
                        let old = [v[0], v[1], if dim == 3 { v[2] } else { 0.0 }];
                        for (c, vc) in v.iter_mut().enumerate() {
                            *vc = (0..dim).map(|d| q[d][c] * old[d]).sum();
                        }
                        p += dim;
                    }
                    _ => p += 1,
                }
            }
        }
        // Columns: the dim columns of a rotated node ← (columns) Q.
        for (node, n) in self.normal.iter().enumerate() {
            let Some(n) = n else { continue };
            let q = basis(*n, dim);
            let starts: Vec<usize> = (0..dim)
                .map(|c| sym.col_range(dim * node + c).start)
                .collect();
            for p in 0..sym.col_range(dim * node).len() {
                let old: Vec<f64> = starts.iter().map(|&s0| val[s0 + p]).collect();
                for (c, &s0) in starts.iter().enumerate() {
                    val[s0 + p] = (0..dim).map(|d| old[d] * q[d][c]).sum();
                }
            }
        }
        Ok(k)
    }

    /// Whether every rotated node's `dim` columns share one row pattern in
    /// which its own rows, where present, come as `dim` consecutive rows.
    fn has_full_blocks(&self, sym: faer::sparse::SymbolicSparseColMatRef<'_, usize>) -> bool {
        let dim = self.dim;
        let rotated = |r: usize| self.normal[r / dim].is_some();
        let columns_agree = self.normal.iter().enumerate().all(|(node, n)| {
            n.is_none() || {
                let first = sym.row_idx_of_col_raw(dim * node);
                (1..dim).all(|c| sym.row_idx_of_col_raw(dim * node + c) == first)
            }
        });
        columns_agree
            && (0..sym.ncols()).all(|j| {
                let rows = sym.row_idx_of_col_raw(j);
                let mut p = 0;
                while p < rows.len() {
                    if rotated(rows[p]) {
                        let r0 = rows[p];
                        let whole = r0 % dim == 0
                            && rows.len() >= p + dim
                            && (0..dim).all(|l| rows[p + l] == r0 + l);
                        if !whole {
                            return false;
                        }
                        p += dim;
                    } else {
                        p += 1;
                    }
                }
                true
            })
    }

    /// K̃ = Tᵀ K T built anew from triplets (T block diagonal: each entry of
    /// K spreads over the blocks of its row's and column's nodes).
    fn rotated_copy(
        &self,
        k: faer::sparse::SparseColMatRef<'_, usize, f64>,
    ) -> Result<faer::sparse::SparseColMat<usize, f64>, String> {
        // Tᵀ e_i = row i of T: (column k, Q[d][k]) for the node of i.
        let t_row = |i: usize| self.t_line(i, true);
        let mut t = Vec::with_capacity(k.compute_nnz());
        for j in 0..k.ncols() {
            let tj = t_row(j);
            for (&i, &v) in k.row_idx_of_col_raw(j).iter().zip(k.val_of_col(j)) {
                for (a, ta) in t_row(i) {
                    for &(b, tb) in &tj {
                        t.push(faer::sparse::Triplet::new(a, b, ta * v * tb));
                    }
                }
            }
        }
        faer::sparse::SparseColMat::try_new_from_triplets(k.nrows(), k.ncols(), &t)
            .map_err(|e| format!("rotating the stiffness into the contact frames: {e:?}"))
    }

    /// ũ = Tᵀ u.
    pub fn to_local(&self, u: &[f64]) -> Vec<f64> {
        (0..u.len())
            .map(|l| self.t_col(l).iter().map(|&(i, t)| t * u[i]).sum())
            .collect()
    }

    /// u = T ũ.
    pub fn to_cartesian(&self, ut: &[f64]) -> Vec<f64> {
        let mut u = vec![0.0; ut.len()];
        for (l, &x) in ut.iter().enumerate() {
            for (i, t) in self.t_col(l) {
                u[i] += t * x;
            }
        }
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In place (full node blocks) and by triplets (a block cut short), the
    /// rotated stiffness is the dense Tᵀ K T.
    #[test]
    fn the_rotated_stiffness_is_t_transpose_k_t() {
        use faer::sparse::{SparseColMat, Triplet};
        let (dim, nodes) = (3, 3);
        let n = dim * nodes;
        let value =
            |i: usize, j: usize| 1.0 / (1.0 + i.abs_diff(j) as f64) + (i == j) as usize as f64;
        let frames = LocalFrames {
            dim,
            normal: vec![None, Some([0.6, 0.0, 0.8]), Some([0.0, 1.0, 0.0])],
        };
        // node 0 does not touch node 2: a pattern of full node blocks
        let coupled = |a: usize, b: usize| a.abs_diff(b) <= 1;
        for cut in [false, true] {
            let mut t = Vec::new();
            for j in 0..n {
                for i in 0..n {
                    let dropped = cut && i == 4 && j == 0;
                    if coupled(i / dim, j / dim) && !dropped {
                        t.push(Triplet::new(i, j, value(i, j)));
                    }
                }
            }
            let k = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
            let dense = k.to_dense();
            let mut tm = faer::Mat::<f64>::zeros(n, n);
            for l in 0..n {
                for (i, v) in frames.t_col(l) {
                    tm[(i, l)] = v;
                }
            }
            let want = tm.transpose() * &dense * &tm;
            assert_eq!(frames.has_full_blocks(k.symbolic()), !cut);
            let got = frames.rotate_stiffness(k).unwrap().to_dense();
            for i in 0..n {
                for j in 0..n {
                    assert!((got[(i, j)] - want[(i, j)]).abs() <= 1e-14, "{cut} {i} {j}");
                }
            }
        }
    }

    #[test]
    fn the_basis_is_orthonormal_with_n_first() {
        for n in [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [1.0 / 3f64.sqrt(); 3]] {
            let q = basis(n, 3);
            for a in 0..3 {
                for b in 0..3 {
                    let ab: f64 = (0..3).map(|d| q[d][a] * q[d][b]).sum();
                    let want = if a == b { 1.0 } else { 0.0 };
                    assert!((ab - want).abs() <= 4.0 * f64::EPSILON, "{n:?} {a} {b}");
                }
            }
            assert!((0..3).all(|d| q[d][0] == n[d]));
        }
        let q = basis([0.6, 0.8, 0.0], 2);
        assert_eq!([q[0][1], q[1][1]], [-0.8, 0.6]);
    }
}
