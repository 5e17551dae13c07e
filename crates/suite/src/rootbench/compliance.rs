//! What an indentation problem ([`crate::rootbench::problem`]) needs of the
//! body it presses: its surface compliance at the contact points, from the
//! periodic layer's finite elements or the half-space's closed forms.

use crate::rootbench::layer::SurfaceCompliance;

/// The surface compliance of a body at its contact points: what a problem
/// of [`indentation_problem`] needs of the layer or the half-space.
pub trait Compliance {
    /// 2 or 3 (the surface's dimension + 1).
    fn dim(&self) -> usize;
    /// Number of contact points.
    fn n_surface(&self) -> usize;
    /// Position of point i in the surface (x, or (x, y)).
    fn position(&self, i: usize) -> [f64; 2];
    /// Displacement along axis `a` at point `i` under a unit force along
    /// axis `b` at point `j` (the last axis vertical, upward).
    fn entry(&self, i: usize, a: usize, j: usize, b: usize) -> f64;
}

impl Compliance for SurfaceCompliance {
    fn dim(&self) -> usize {
        self.dim
    }
    fn n_surface(&self) -> usize {
        SurfaceCompliance::n_surface(self)
    }
    fn position(&self, i: usize) -> [f64; 2] {
        SurfaceCompliance::position(self, i)
    }
    fn entry(&self, i: usize, a: usize, j: usize, b: usize) -> f64 {
        SurfaceCompliance::entry(self, i, a, j, b)
    }
}
