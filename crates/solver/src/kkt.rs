//! The direct path: the contact problem on the whole sparse stiffness,
//! refactorised at each status iteration as seed §3.3 describes ("il faut
//! procéder à une factorisation de la matrice de raideur globale à chaque
//! itération"). For checking the condensed path and for benchmarking it.
//!
//! For an active set A it solves the saddle-point system
//! [K B_Aᵀ; B_A 0] [u; −λ_A] = [F; −g0_A] by a sparse LU, with the constraint
//! rows scaled by s = the mean of |diag K| ([K s B_Aᵀ; s B_A 0]
//! [u; −λ_A / s] = [F; −s g0_A]) so that the pivots of both blocks have the same
//! magnitude whatever the units (without it, E = 210e9 against unit rows
//! loses seven digits).

use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

use signorini_contact::delassus::SparseRow;
use signorini_contact::ActiveSetSolve;
use signorini_contact::ContactError;

pub struct DirectProblem<'a> {
    pub k: &'a SparseColMat<usize, f64>,
    pub f: &'a [f64],
    pub rows: &'a [SparseRow],
    pub gap0: &'a [f64],
    k_triplets: Vec<Triplet<usize, usize, f64>>,
    /// The scale s of the constraint rows (mean |diag K|).
    row_scale: f64,
    /// Displacement of the last solve.
    pub u: Vec<f64>,
    pub factorisations: usize,
}

impl<'a> DirectProblem<'a> {
    pub fn new(
        k: &'a SparseColMat<usize, f64>,
        f: &'a [f64],
        rows: &'a [SparseRow],
        gap0: &'a [f64],
    ) -> Self {
        let mut t = Vec::with_capacity(k.compute_nnz());
        let mut diag = 0.0;
        for j in 0..k.ncols() {
            for (&i, &v) in k.row_idx_of_col_raw(j).iter().zip(k.val_of_col(j)) {
                t.push(Triplet::new(i, j, v));
                if i == j {
                    diag += v.abs();
                }
            }
        }
        let mean = diag / k.ncols().max(1) as f64;
        let row_scale = if mean.is_finite() && mean > 0.0 {
            mean
        } else {
            1.0
        };
        Self {
            k,
            f,
            rows,
            gap0,
            k_triplets: t,
            row_scale,
            u: vec![0.0; k.nrows()],
            factorisations: 0,
        }
    }
}

impl ActiveSetSolve for DirectProblem<'_> {
    fn n_points(&self) -> usize {
        self.rows.len()
    }

    fn solve_active(&mut self, active: &[usize]) -> Result<(Vec<f64>, Vec<f64>), ContactError> {
        let n = self.k.nrows();
        let na = active.len();
        let mut t = self.k_triplets.clone();
        for (a, &p) in active.iter().enumerate() {
            for &(i, c) in &self.rows[p] {
                t.push(Triplet::new(i, n + a, self.row_scale * c));
                t.push(Triplet::new(n + a, i, self.row_scale * c));
            }
        }
        let kkt = SparseColMat::<usize, f64>::try_new_from_triplets(n + na, n + na, &t)
            .map_err(|e| ContactError::Solve(format!("{e:?}")))?;
        let lu = kkt.sp_lu().map_err(|e| {
            ContactError::Singular(format!("sparse LU of the constrained stiffness: {e:?}"))
        })?;
        self.factorisations += 1;
        let mut rhs = Mat::<f64>::zeros(n + na, 1);
        for i in 0..n {
            rhs[(i, 0)] = self.f[i];
        }
        for (a, &p) in active.iter().enumerate() {
            rhs[(n + a, 0)] = -self.row_scale * self.gap0[p];
        }
        let x = lu.solve(&rhs);
        if !x.norm_max().is_finite() {
            return Err(ContactError::Singular(
                "the constrained stiffness is singular: a body is free to move in a way that neither its supports nor its active contacts prevent".into(),
            ));
        }
        self.u = (0..n).map(|i| x[(i, 0)]).collect();
        let mut lambda = vec![0.0; self.rows.len()];
        for (a, &p) in active.iter().enumerate() {
            lambda[p] = -self.row_scale * x[(n + a, 0)];
        }
        let g = self
            .rows
            .iter()
            .zip(self.gap0)
            .map(|(row, g0)| g0 + row.iter().map(|&(i, c)| c * self.u[i]).sum::<f64>())
            .collect();
        Ok((lambda, g))
    }
}
