//! The surface compliance of an elastic half-space at a regular grid of
//! contact points: the Delassus operator of a rigid indenter on a massive
//! body, denser and less diagonally dominant than that of the layer of
//! [`crate::rootbench::layer`] (the influence of a point decays as 1/r in 3D
//! and as log r in 2D instead of within the layer's thickness).
//!
//! 3D (Johnson, *Contact Mechanics*, §3.2): the surface displacements under a
//! point force, G = E / (2(1 + ν)), r the distance in the surface, x, y its
//! components (from the load to the observed point):
//! - normal force P (Boussinesq): u_z = (1 − ν²) P / (π E r) into the body,
//!   u_x = −(1 − 2ν)(1 + ν) P x / (2π E r²) (towards the load);
//! - tangential force Q along x (Cerruti): u_x = Q / (2π G r) (1 − ν + ν x²/r²),
//!   u_y = Q ν x y / (2π G r³), and u_z by Maxwell–Betti from the above.
//!
//! 2D plane strain (Flamant, Johnson §2.2), with a reference depth d where
//! the displacement is taken as zero: u_z = 2(1 − ν²) P ln(d / r) / (π E),
//! u_x alike under Q, and u_x = −(1 − 2ν)(1 + ν) P sign(x) / (2E).
//!
//! Each grid point carries the force on a square (a segment in 2D) of side
//! h around it: its own (self) compliance is the mean displacement at the
//! centre of that uniformly loaded cell (∫ 1/r over a square of side h from
//! its centre is 4 h ln(1 + √2); the mean of ln(d/|x|) over a segment of
//! length h is ln(2d/h) + 1), the other entries are the point-force kernel.
//! The axes are those of the layer: the body below the surface (z < 0), the
//! last axis vertical upward.

use crate::rootbench::compliance::Compliance;

/// The half-space and the grid of contact points on its surface.
#[derive(Debug, Clone, Copy)]
pub struct HalfSpace {
    /// 2 (plane strain) or 3.
    pub dim: usize,
    /// Points along each surface direction (n, or n × n).
    pub n: usize,
    /// Side of the square (segment) the grid covers.
    pub width: f64,
    pub young: f64,
    pub poisson: f64,
    /// 2D: the depth at which the displacement is zero (Flamant's solution is
    /// defined up to a rigid motion).
    pub reference_depth: f64,
}

impl HalfSpace {
    /// Grid spacing h: the points sit at the centres of n cells.
    pub fn spacing(&self) -> f64 {
        self.width / self.n as f64
    }

    /// Surface offset from the load at j to the observed point i.
    fn offset(&self, i: usize, j: usize) -> [f64; 2] {
        let (pi, pj) = (self.position(i), self.position(j));
        [pi[0] - pj[0], pi[1] - pj[1]]
    }

    /// The 3D compliance: displacement along a at i under a unit force
    /// along b at j (axes x, y, z upward).
    fn entry_3d(&self, i: usize, a: usize, j: usize, b: usize) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        let shear = e / (2.0 * (1.0 + nu));
        let pi = std::f64::consts::PI;
        if i == j {
            // Mean of 1/r over the own cell, its mean of x²/r³ half of it.
            let inv_r = 4.0 * (1.0 + 2f64.sqrt()).ln() / self.spacing();
            return match (a, b) {
                (2, 2) => (1.0 - nu * nu) / (pi * e) * inv_r,
                (0, 0) | (1, 1) => (1.0 - 0.5 * nu) / (2.0 * pi * shear) * inv_r,
                _ => 0.0,
            };
        }
        let d = self.offset(i, j);
        let r = d[0].hypot(d[1]);
        // Pulling the surface up at j moves i up and away from j.
        let coupling = (1.0 - 2.0 * nu) * (1.0 + nu) / (2.0 * pi * e) / (r * r);
        match (a, b) {
            (2, 2) => (1.0 - nu * nu) / (pi * e * r),
            (0, 0) | (1, 1) => (1.0 - nu + nu * d[a] * d[a] / (r * r)) / (2.0 * pi * shear * r),
            (0, 1) | (1, 0) => nu * d[0] * d[1] / (2.0 * pi * shear * r.powi(3)),
            (t, 2) => coupling * d[t],
            (2, t) => -coupling * d[t],
            _ => unreachable!("axes are 0, 1, 2"),
        }
    }

    /// The 2D (plane strain) compliance: axes x, z upward.
    fn entry_2d(&self, i: usize, a: usize, j: usize, b: usize) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        let pi = std::f64::consts::PI;
        let flamant = 2.0 * (1.0 - nu * nu) / (pi * e);
        let x = self.offset(i, j)[0];
        if a == b {
            let log = if i == j {
                (2.0 * self.reference_depth / self.spacing()).ln() + 1.0
            } else {
                (self.reference_depth / x.abs()).ln()
            };
            return flamant * log;
        }
        if i == j {
            return 0.0;
        }
        let coupling = (1.0 - 2.0 * nu) * (1.0 + nu) / (2.0 * e) * x.signum();
        if b == 1 {
            coupling
        } else {
            -coupling
        }
    }
}

impl Compliance for HalfSpace {
    fn dim(&self) -> usize {
        self.dim
    }

    fn n_surface(&self) -> usize {
        self.n.pow(self.dim as u32 - 1)
    }

    fn position(&self, i: usize) -> [f64; 2] {
        let h = self.spacing();
        if self.dim == 2 {
            [(i as f64 + 0.5) * h, 0.0]
        } else {
            [
                ((i % self.n) as f64 + 0.5) * h,
                ((i / self.n) as f64 + 0.5) * h,
            ]
        }
    }

    fn entry(&self, i: usize, a: usize, j: usize, b: usize) -> f64 {
        if self.dim == 2 {
            self.entry_2d(i, a, j, b)
        } else {
            self.entry_3d(i, a, j, b)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rootbench::problem::{indentation_problem, Indentation};
    use faer::{Mat, Side};

    fn half_space(dim: usize, n: usize) -> HalfSpace {
        HalfSpace {
            dim,
            n,
            width: 1.0,
            young: 1.0,
            poisson: 0.3,
            reference_depth: 1.0,
        }
    }

    /// The full compliance matrix (dim rows per point).
    fn matrix(c: &HalfSpace) -> Mat<f64> {
        let d = c.dim;
        Mat::from_fn(c.n_surface() * d, c.n_surface() * d, |r, s| {
            c.entry(r / d, r % d, s / d, s % d)
        })
    }

    /// Maxwell–Betti: W is symmetric; and it is positive definite (a
    /// Cholesky factorisation exists) with the normal and tangential
    /// couplings, in 2D and 3D.
    #[test]
    fn compliance_is_symmetric_and_positive_definite() {
        for (dim, n) in [(2, 60), (3, 12)] {
            let w = matrix(&half_space(dim, n));
            let scale = w[(0, 0)];
            for r in 0..w.nrows() {
                for s in 0..r {
                    assert!(
                        (w[(r, s)] - w[(s, r)]).abs() <= 1e-14 * scale,
                        "{dim}D ({r},{s})"
                    );
                }
            }
            assert!(w.llt(Side::Lower).is_ok(), "{dim}D compliance not SPD");
        }
    }

    /// A uniform pressure p on the square of side L settles its centre by
    /// 4 (1 − ν²) p L ln(1 + √2) / (π E) and its corners by half of that
    /// (Love): the grid's sums, to the midpoint rule's accuracy.
    #[test]
    fn uniform_pressure_gives_the_settlement_of_a_loaded_square() {
        let c = half_space(3, 41);
        let area = c.spacing().powi(2);
        let m = c.n_surface();
        let settle = |i: usize| -> f64 { (0..m).map(|j| c.entry(i, 2, j, 2) * area).sum() };
        let nu = c.poisson;
        let centre = 4.0 * (1.0 - nu * nu) * c.width * (1.0 + 2f64.sqrt()).ln()
            / (std::f64::consts::PI * c.young);
        let got = settle(m / 2);
        assert!(
            (got - centre).abs() <= 0.01 * centre,
            "centre {got} vs {centre}"
        );
        // The corner point sits h/2 in from the corner: the settlement there
        // differs from the corner's by O(h ln h).
        let corner = settle(0);
        assert!(
            (corner - 0.5 * centre).abs() <= 0.1 * centre,
            "corner {corner} vs {}",
            0.5 * centre
        );
    }

    /// The smooth paraboloid of radius R pressed by δ: Hertz's contact
    /// radius a = √(Rδ) and load P = 4 E* √R δ^{3/2} / 3 (E* = E / (1 − ν²)),
    /// from the LCP of the normal rows solved by the status method, within
    /// the grid's resolution (the contact radius to two spacings, the load
    /// to 3 %).
    #[test]
    fn paraboloid_gives_the_hertz_load_and_contact_radius() {
        let c = half_space(3, 41);
        let load = Indentation {
            radius: 1.0,
            approach: 0.09,
            roughness: 0.0,
            slide: 0.0,
            mu: 0.0,
        };
        let p = indentation_problem("hertz", &c, c.width, &load);
        let lp =
            signorini_problems::local::LocalProblem::contact_wise("hertz", p.w, p.q, vec![], 1)
                .unwrap();
        let status = signorini_contact::registry::Algorithm::by_name("status").unwrap();
        let r = signorini_problems::local::solve("hertz", &lp, status, 1e-12, 100, true).unwrap();
        assert!(r.converged);
        let lambda = r.lambda.unwrap();
        let e_star = c.young / (1.0 - c.poisson.powi(2));
        let (radius, delta) = (load.radius, load.approach);
        let hertz_load = 4.0 / 3.0 * e_star * radius.sqrt() * delta.powf(1.5);
        let total: f64 = lambda.iter().sum();
        assert!(
            (total - hertz_load).abs() <= 0.03 * hertz_load,
            "load {total} vs {hertz_load}"
        );
        let a = (radius * delta).sqrt();
        let centre = 0.5 * c.width;
        let reach = (0..lambda.len())
            .filter(|&i| lambda[i] > 0.0)
            .map(|i| {
                let p = c.position(i);
                (p[0] - centre).hypot(p[1] - centre)
            })
            .fold(0.0f64, f64::max);
        assert!(
            (reach - a).abs() <= 2.0 * c.spacing(),
            "contact radius {reach} vs {a}"
        );
    }
}
