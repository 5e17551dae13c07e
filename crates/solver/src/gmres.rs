//! GMRES (Saad & Schultz 1986) with right preconditioning, unrestarted and
//! short: A x = b is solved as A M⁻¹ z = b, x = M⁻¹ z, over the Krylov space
//! of A M⁻¹ and b built by modified Gram–Schmidt (Saad, *Iterative Methods
//! for Sparse Linear Systems*, 2003, Alg. 9.5), the least-squares problem
//! of the Hessenberg matrix by Givens rotations, and the residual norm of
//! each iterate read from the rotated right-hand side without a product.
//! The whole-system Newton method of friction on the direct path solves its
//! Jacobian so with the LDLᵀ of its symmetric part as M
//! ([`crate::symmetric_part`]).

/// The iterate x of at most `max_iterations` Krylov steps whose residual
/// ‖b − A x‖₂ is at most `tolerance` ‖b‖₂ (by the rotated right-hand side),
/// with the steps taken; `None` when that is not reached or the products
/// are not finite. `apply` is A, `precondition` M⁻¹.
pub(crate) fn gmres(
    mut apply: impl FnMut(&[f64]) -> Vec<f64>,
    mut precondition: impl FnMut(&[f64]) -> Vec<f64>,
    b: &[f64],
    tolerance: f64,
    max_iterations: usize,
) -> Option<(Vec<f64>, usize)> {
    let beta = norm(b);
    if beta == 0.0 {
        return Some((vec![0.0; b.len()], 0));
    }
    let mut v: Vec<Vec<f64>> = vec![b.iter().map(|x| x / beta).collect()];
    let mut z: Vec<Vec<f64>> = Vec::new();
    let mut h: Vec<Vec<f64>> = Vec::new();
    let mut rotations: Vec<(f64, f64)> = Vec::new();
    let mut g = vec![beta];
    for j in 0..max_iterations {
        z.push(precondition(&v[j]));
        let mut w = apply(&z[j]);
        let mut column = vec![0.0; j + 2];
        for (i, vi) in v.iter().enumerate() {
            column[i] = dot(&w, vi);
            w.iter_mut().zip(vi).for_each(|(a, b)| *a -= column[i] * b);
        }
        column[j + 1] = norm(&w);
        if !column.iter().all(|x| x.is_finite()) {
            return None;
        }
        for (i, &(c, s)) in rotations.iter().enumerate() {
            let (a, b) = (column[i], column[i + 1]);
            column[i] = c * a + s * b;
            column[i + 1] = -s * a + c * b;
        }
        let (a, b) = (column[j], column[j + 1]);
        let r = a.hypot(b);
        let (c, s) = if r > 0.0 { (a / r, b / r) } else { (1.0, 0.0) };
        column[j] = r;
        column[j + 1] = 0.0;
        rotations.push((c, s));
        g.push(-s * g[j]);
        g[j] *= c;
        let breakdown = column[j] == 0.0;
        let lucky = norm(&w) == 0.0;
        h.push(column);
        if g[j + 1].abs() <= tolerance * beta || lucky {
            return (!breakdown).then(|| (combine(&h, &g, &z), j + 1));
        }
        let wn = norm(&w);
        v.push(w.iter().map(|x| x / wn).collect());
    }
    None
}

/// x = Σ z_j y_j with y solving the rotated triangular system H y = g.
fn combine(h: &[Vec<f64>], g: &[f64], z: &[Vec<f64>]) -> Vec<f64> {
    let k = h.len();
    let mut y = vec![0.0; k];
    for i in (0..k).rev() {
        let s: f64 = ((i + 1)..k).map(|l| h[l][i] * y[l]).sum();
        y[i] = (g[i] - s) / h[i][i];
    }
    let mut x = vec![0.0; z[0].len()];
    for (zj, yj) in z.iter().zip(&y) {
        x.iter_mut().zip(zj).for_each(|(a, b)| *a += yj * b);
    }
    x
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A nonsymmetric 4 × 4 system: unpreconditioned GMRES ends in at most
    /// four steps (the Krylov space is the whole space) at A x = b to a few
    /// roundings of ‖b‖; preconditioned by the exact inverse, in one step.
    #[test]
    fn solves_a_nonsymmetric_system() {
        let a = [
            [4.0, 1.0, 0.0, 2.0],
            [-1.0, 3.0, 1.0, 0.0],
            [0.0, 2.0, 5.0, -1.0],
            [1.0, 0.0, -2.0, 6.0],
        ];
        let apply = |x: &[f64]| -> Vec<f64> {
            a.iter()
                .map(|row| row.iter().zip(x).map(|(p, q)| p * q).sum())
                .collect()
        };
        let b = [1.0, -2.0, 3.0, 0.5];
        let (x, steps) = gmres(apply, |r| r.to_vec(), &b, 1e-14, 10).expect("converges");
        assert!(steps <= 4, "{steps}");
        let r: Vec<f64> = apply(&x).iter().zip(&b).map(|(p, q)| p - q).collect();
        assert!(norm(&r) <= 64.0 * f64::EPSILON * norm(&b), "{:e}", norm(&r));
        let x_exact = x.clone();
        let exact_inverse = |r: &[f64]| {
            gmres(apply, |v| v.to_vec(), r, 1e-15, 10)
                .expect("converges")
                .0
        };
        let (x, steps) = gmres(apply, exact_inverse, &b, 1e-12, 10).expect("converges");
        assert_eq!(steps, 1);
        for (p, q) in x.iter().zip(&x_exact) {
            assert!((p - q).abs() <= 1e-12 * norm(&x_exact), "{p} vs {q}");
        }
    }
}
