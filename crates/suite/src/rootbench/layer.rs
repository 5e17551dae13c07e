//! The surface compliance of an elastic layer on a rigid base, periodic along
//! its surface, computed by this project's finite elements: the Delassus
//! operator of contact points on that surface (docs/theory/algorithms.md, course notes §2.3:
//! W = B K⁻¹ Bᵀ).
//!
//! The layer is the cell [0, L] × [−H, 0] (2D, plane strain, Quad4) or
//! [0, L]² × [−H, 0] (3D, Hex8) with `n` elements along each surface
//! direction, graded in depth (the smallest elements at the surface, about as
//! thick as they are wide), clamped at its base and periodic in x (and y):
//! the nodes of the face x = L are those of x = 0. Translation invariance
//! then makes the surface compliance a (block) circulant: the displacement in
//! direction a of surface node i under a unit force in direction b at
//! surface node j depends only on i − j (mod n). One factorisation of K and
//! `dim` solves give every column of W, so that problems of thousands of
//! contact points cost seconds to build.

use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use signorini_fem::elasticity::{Elasticity, Model};
use signorini_mesh::generators::{box_mesh, rectangle, BoxSide, RectSide};
use signorini_mesh::{CellKind, Mesh};

/// The layer: its dimension, surface divisions and material.
#[derive(Debug, Clone, Copy)]
pub struct Layer {
    /// 2 (plane strain) or 3.
    pub dim: usize,
    /// Elements (and surface nodes) along each surface direction.
    pub n: usize,
    /// Period L (the layer's width).
    pub width: f64,
    /// Thickness H.
    pub depth: f64,
    pub young: f64,
    pub poisson: f64,
}

/// The surface Green's function of the periodic layer:
/// `g[((k · dim) + a) · dim + b]` is the displacement in direction a of the
/// surface node at offset k from the loaded one (k = kx, or kx + n·ky in 3D)
/// under a unit force in direction b.
#[derive(Debug, Clone)]
pub struct SurfaceCompliance {
    pub dim: usize,
    pub n: usize,
    pub spacing: f64,
    g: Vec<f64>,
    /// Unknowns of the layer's finite-element system.
    pub dofs: usize,
}

impl SurfaceCompliance {
    /// Displacement in direction `a` at surface node `i` under a unit force
    /// in direction `b` at surface node `j` (nodes numbered ix + n·iy).
    pub fn entry(&self, i: usize, a: usize, j: usize, b: usize) -> f64 {
        let n = self.n;
        let k = if self.dim == 2 {
            (i + n - j) % n
        } else {
            let (ix, iy, jx, jy) = (i % n, i / n, j % n, j / n);
            (ix + n - jx) % n + n * ((iy + n - jy) % n)
        };
        self.g[(k * self.dim + a) * self.dim + b]
    }

    /// Position of surface node i in the surface (x, or (x, y)).
    pub fn position(&self, i: usize) -> [f64; 2] {
        let n = self.n;
        if self.dim == 2 {
            [i as f64 * self.spacing, 0.0]
        } else {
            [(i % n) as f64 * self.spacing, (i / n) as f64 * self.spacing]
        }
    }

    /// Number of surface nodes.
    pub fn n_surface(&self) -> usize {
        self.n.pow(self.dim as u32 - 1)
    }
}

/// Depth divisions and grading ratio (largest / smallest) such that the
/// elements grow geometrically by at most 20 % from a surface element about
/// as thick as it is wide to the base.
fn depth_grading(layer: &Layer) -> (usize, f64) {
    let h0 = layer.width / layer.n as f64;
    let growth: f64 = 1.2;
    let levels = (1.0 + layer.depth * (growth - 1.0) / h0).ln() / growth.ln();
    let nz = (levels.ceil() as usize).max(1);
    (nz, growth.powi(nz as i32 - 1).max(1.0))
}

fn layer_mesh(layer: &Layer) -> Result<Mesh, String> {
    let (nz, ratio) = depth_grading(layer);
    let (w, h, n) = (layer.width, layer.depth, layer.n);
    let mesh = if layer.dim == 2 {
        rectangle(
            [0.0, -h],
            [w, h],
            [n, nz],
            CellKind::Quad4,
            (ratio > 1.0).then_some((RectSide::Top, ratio)),
        )
    } else {
        box_mesh(
            [0.0, 0.0, -h],
            [w, w, h],
            [n, n, nz],
            CellKind::Hex8,
            (ratio > 1.0).then_some((BoxSide::Zmax, ratio)),
        )
    };
    mesh.map_err(|e| format!("layer mesh: {e}"))
}

/// Index of each node in the periodic, clamped layer: surface position
/// (ix, iy) wrapped modulo n and depth level (from the surface, 0 = surface);
/// `None` for the clamped base.
fn periodic_nodes(mesh: &Mesh, layer: &Layer) -> Vec<Option<usize>> {
    let d = layer.dim;
    let h = layer.width / layer.n as f64;
    let mut levels: Vec<f64> = mesh.coords.iter().map(|p| p[d - 1]).collect();
    levels.sort_by(|a, b| b.total_cmp(a));
    levels.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * layer.depth);
    let per_level = layer.n.pow(d as u32 - 1);
    mesh.coords
        .iter()
        .map(|p| {
            let level = levels
                .iter()
                .position(|z| (z - p[d - 1]).abs() <= 1e-9 * layer.depth)
                .unwrap_or(levels.len() - 1);
            if level == levels.len() - 1 {
                return None;
            }
            let ix = (p[0] / h).round() as usize % layer.n;
            let iy = if d == 3 {
                (p[1] / h).round() as usize % layer.n
            } else {
                0
            };
            Some(level * per_level + ix + layer.n * iy)
        })
        .collect()
}

/// The layer's stiffness on its periodic, unclamped DOFs (lower triangle),
/// each element's matrix computed once per depth level (the elements of a
/// level are translates of one another).
fn periodic_stiffness(
    mesh: &Mesh,
    layer: &Layer,
    ids: &[Option<usize>],
) -> Result<SparseColMat<usize, f64>, String> {
    let d = layer.dim;
    let model = if d == 2 {
        Model::PlaneStrain
    } else {
        Model::Solid
    };
    let mat = Elasticity::new(layer.young, layer.poisson, model);
    let n_dofs = ids.iter().flatten().max().map_or(0, |&i| (i + 1) * d);
    let mut cache: Vec<(f64, faer::Mat<f64>)> = Vec::new();
    let mut triplets = Vec::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        let top = cell
            .nodes
            .iter()
            .map(|&v| mesh.coords[v][d - 1])
            .fold(f64::NEG_INFINITY, f64::max);
        let ke = match cache
            .iter()
            .find(|(z, _)| (z - top).abs() <= 1e-9 * layer.depth)
        {
            Some((_, k)) => k,
            None => {
                let k = signorini_fem::element::try_element_stiffness(mesh, c, &mat)
                    .map_err(|e| format!("layer element {c}: {e}"))?;
                let k = faer::Mat::<f64>::from_fn(k.nrows(), k.ncols(), |i, j| k[(i, j)]);
                cache.push((top, k));
                &cache[cache.len() - 1].1
            }
        };
        let dofs: Vec<Option<usize>> = cell
            .nodes
            .iter()
            .flat_map(|&v| (0..d).map(move |a| ids[v].map(|i| i * d + a)))
            .collect();
        for (j, gj) in dofs.iter().enumerate() {
            for (i, gi) in dofs.iter().enumerate() {
                if let (Some(gi), Some(gj)) = (gi, gj) {
                    if gi >= gj {
                        triplets.push(Triplet::new(*gi, *gj, ke[(i, j)]));
                    }
                }
            }
        }
    }
    SparseColMat::try_new_from_triplets(n_dofs, n_dofs, &triplets)
        .map_err(|e| format!("layer stiffness: {e:?}"))
}

/// Computes the surface compliance of `layer` by one sparse Cholesky
/// factorisation and `dim` solves.
pub fn surface_compliance(layer: &Layer) -> Result<SurfaceCompliance, String> {
    if !(layer.dim == 2 || layer.dim == 3) || layer.n < 2 {
        return Err(format!(
            "layer: dim must be 2 or 3 and n at least 2 (got dim {}, n {})",
            layer.dim, layer.n
        ));
    }
    let mesh = layer_mesh(layer)?;
    let ids = periodic_nodes(&mesh, layer);
    let k = periodic_stiffness(&mesh, layer, &ids)?;
    let d = layer.dim;
    let llt = k
        .sp_cholesky(Side::Lower)
        .map_err(|e| format!("layer stiffness is not positive definite: {e:?}"))?;
    // Surface node i has periodic index i (level 0): its DOFs are i·d + a.
    let mut rhs = Mat::<f64>::zeros(k.nrows(), d);
    for b in 0..d {
        rhs[(b, b)] = 1.0;
    }
    let u = llt.solve(&rhs);
    let n_surface = layer.n.pow(d as u32 - 1);
    let mut g = vec![0.0; n_surface * d * d];
    for s in 0..n_surface {
        for a in 0..d {
            for b in 0..d {
                g[(s * d + a) * d + b] = u[(s * d + a, b)];
            }
        }
    }
    Ok(SurfaceCompliance {
        dim: d,
        n: layer.n,
        spacing: layer.width / layer.n as f64,
        g,
        dofs: k.nrows(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer(dim: usize, n: usize) -> Layer {
        Layer {
            dim,
            n,
            width: 1.0,
            depth: 0.25,
            young: 1.0,
            poisson: 0.3,
        }
    }

    /// Maxwell–Betti: the compliance is symmetric, G_ab(i, j) = G_ba(j, i),
    /// and a push into the layer moves the surface inward, most under the load.
    #[test]
    fn compliance_is_symmetric_and_pointwise_largest_under_the_load() {
        for dim in [2, 3] {
            let c = surface_compliance(&layer(dim, 8)).unwrap();
            let ns = c.n_surface();
            let scale = c.entry(0, dim - 1, 0, dim - 1);
            assert!(scale > 0.0);
            for i in 0..ns {
                for j in 0..ns {
                    for a in 0..dim {
                        for b in 0..dim {
                            let (x, y) = (c.entry(i, a, j, b), c.entry(j, b, i, a));
                            assert!((x - y).abs() <= 1e-9 * scale, "dim {dim} ({i},{a},{j},{b})");
                        }
                    }
                    assert!(c.entry(i, dim - 1, j, dim - 1) <= scale * (1.0 + 1e-12));
                }
            }
        }
    }

    /// A uniform pressure p on the whole periodic surface compresses the
    /// layer uniaxially (oedometric): the surface moves by
    /// p H (1 + ν)(1 − 2ν) / (E (1 − ν)), in 2D plane strain as in 3D.
    #[test]
    fn uniform_pressure_gives_the_oedometric_settlement() {
        for dim in [2, 3] {
            let l = layer(dim, 6);
            let c = surface_compliance(&l).unwrap();
            let ns = c.n_surface();
            let area = c.spacing.powi(dim as i32 - 1);
            let settle: f64 = (0..ns)
                .map(|j| c.entry(0, dim - 1, j, dim - 1) * area)
                .sum();
            let nu = l.poisson;
            let exact = l.depth * (1.0 + nu) * (1.0 - 2.0 * nu) / (l.young * (1.0 - nu));
            assert!(
                (settle - exact).abs() <= 1e-8 * exact,
                "dim {dim}: {settle} vs {exact}"
            );
        }
    }
}
