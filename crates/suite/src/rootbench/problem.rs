//! Delassus problems of a rigid indenter pressed (and, with friction, slid)
//! on the periodic elastic layer of [`crate::rootbench::layer`]: the condensed contact
//! problems on which the root solvers are compared with each other and with
//! other libraries.
//!
//! The indenter is a paraboloid of radius R (a cylinder in 2D) with a slight
//! roughness (a sum of waves fixed once for all sizes, a few per cent of
//! the approach), pressed by δ into the layer and, for the frictional problems,
//! moved by δ_t along x. The rows follow the exchange layout of Siconos and
//! FCLib: contact-wise, [n] (an LCP), [n, t] (2D) or [n, t1, t2] (3D) per
//! contact point. Conventions (docs/theory/contact-problem.md): the normal points from the
//! indenter (master) into the layer (slave), λ_n ≥ 0 is compressive, the
//! gap is g = W λ + q; the tangential "gap" is the slip increment of the
//! layer relative to the indenter.

use faer::Mat;

use crate::rootbench::compliance::Compliance;
use crate::rootbench::halfspace::HalfSpace;

/// A stand-alone contact problem: W (contact-wise rows), q, and μ per
/// contact (empty: frictionless).
#[derive(Debug, Clone)]
pub struct RootProblem {
    pub name: String,
    /// Rows per contact: 1 (LCP), 2 or 3.
    pub dim: usize,
    pub w: Mat<f64>,
    pub q: Vec<f64>,
    pub mu: Vec<f64>,
}

impl RootProblem {
    pub fn contacts(&self) -> usize {
        self.q.len() / self.dim
    }
}

/// The loading of the indenter, all lengths relative to the layer width L.
#[derive(Debug, Clone, Copy)]
pub struct Indentation {
    /// Radius of the indenter.
    pub radius: f64,
    /// Approach δ.
    pub approach: f64,
    /// Roughness amplitude, relative to δ.
    pub roughness: f64,
    /// Tangential displacement δ_t of the indenter (frictional problems).
    pub slide: f64,
    /// Friction coefficient (0: an LCP).
    pub mu: f64,
}

/// A uniform number in [−1, 1] from an index (splitmix64): the roughness is
/// the same for every run and every machine.
fn unit_noise(i: usize) -> f64 {
    let mut z = (i as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// The roughness at a point of the surface (coordinates relative to L): a
/// sum of 24 periodic waves of wavelengths L/4 to L/40 with amplitudes
/// falling as 1/k and pseudo-random phases and directions, scaled to a
/// largest height of about 1. It does not depend on the mesh, so that the
/// problems of every size discretise one surface.
fn roughness(p: [f64; 2], dim: usize) -> f64 {
    let tau = std::f64::consts::TAU;
    let mut h = 0.0;
    let mut norm = 0.0;
    for w in 0..24 {
        let k = 4.0 + (w as f64) * 36.0 / 23.0;
        let phase = std::f64::consts::PI * unit_noise(3 * w);
        let (kx, ky) = if dim == 2 {
            (k.round(), 0.0)
        } else {
            let angle = std::f64::consts::PI * unit_noise(3 * w + 1);
            ((k * angle.cos()).round(), (k * angle.sin()).round())
        };
        h += (tau * (kx * p[0] + ky * p[1]) + phase).sin() / k;
        norm += 1.0 / k;
    }
    2.0 * h / norm
}

/// Initial gap of surface node i: indenter profile plus roughness minus δ.
fn initial_gap(c: &impl Compliance, load: &Indentation, width: f64, i: usize) -> f64 {
    let centre = 0.5 * width;
    let p = c.position(i);
    let mut r2 = (p[0] - centre).powi(2);
    if c.dim() == 3 {
        r2 += (p[1] - centre).powi(2);
    }
    let rough = roughness([p[0] / width, p[1] / width], c.dim());
    r2 / (2.0 * load.radius * width) + (load.roughness * rough - 1.0) * load.approach * width
}

/// The problem of `load` on the layer of compliance `c` (width `width`):
/// an LCP when `load.mu` is 0, else a Coulomb problem with `c.dim` rows per
/// contact.
pub fn indentation_problem(
    name: &str,
    c: &impl Compliance,
    width: f64,
    load: &Indentation,
) -> RootProblem {
    let d = c.dim();
    let rows = if load.mu > 0.0 { d } else { 1 };
    let m = c.n_surface();
    // Row k of a contact: its direction and sign (normal = −e_vertical into
    // the layer, tangents = +e_x, +e_y).
    let dir = |k: usize| -> (usize, f64) {
        if k == 0 {
            (d - 1, -1.0)
        } else {
            (k - 1, 1.0)
        }
    };
    let w = Mat::<f64>::from_fn(m * rows, m * rows, |r, s| {
        let ((i, a), (j, b)) = ((r / rows, r % rows), (s / rows, s % rows));
        let ((da, sa), (db, sb)) = (dir(a), dir(b));
        sa * sb * c.entry(i, da, j, db)
    });
    let mut q = vec![0.0; m * rows];
    for i in 0..m {
        q[i * rows] = initial_gap(c, load, width, i);
        if rows > 1 {
            q[i * rows + 1] = -load.slide * width;
        }
    }
    RootProblem {
        name: name.to_string(),
        dim: rows,
        w,
        q,
        mu: if rows > 1 {
            vec![load.mu; m]
        } else {
            Vec::new()
        },
    }
}

/// The benchmark's problem families. On the layer: a cylinder (2D) or a
/// sphere (3D) of radius L on a layer of thickness L/4 (E = 1, ν = 0.3),
/// roughness heights up to about 4 % of the approach. The approaches and
/// slides were chosen (2D m = 400–1000, 3D m = 256–900) for about 45 % of the
/// points in contact and, with μ = 0.3, about 55 % of those slipping; the
/// roughness does not depend on the mesh, so the fractions hold at every
/// size, and the benchmark reports those it finds. On the half-space
/// ([`HalfSpace`], the grid covering a square or segment of side L, 2D
/// reference depth L): the same indenters and roughness, the approaches and
/// slides chosen alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    Lcp2d,
    Coulomb2d,
    Lcp3d,
    Coulomb3d,
    HalfspaceLcp2d,
    HalfspaceCoulomb2d,
    HalfspaceLcp3d,
    HalfspaceCoulomb3d,
}

impl Family {
    pub const ALL: [Family; 8] = [
        Family::Lcp2d,
        Family::Coulomb2d,
        Family::Lcp3d,
        Family::Coulomb3d,
        Family::HalfspaceLcp2d,
        Family::HalfspaceCoulomb2d,
        Family::HalfspaceLcp3d,
        Family::HalfspaceCoulomb3d,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Family::Lcp2d => "lcp_2d",
            Family::Coulomb2d => "coulomb_2d",
            Family::Lcp3d => "lcp_3d",
            Family::Coulomb3d => "coulomb_3d",
            Family::HalfspaceLcp2d => "halfspace_lcp_2d",
            Family::HalfspaceCoulomb2d => "halfspace_coulomb_2d",
            Family::HalfspaceLcp3d => "halfspace_lcp_3d",
            Family::HalfspaceCoulomb3d => "halfspace_coulomb_3d",
        }
    }

    /// The family of a name of [`Family::name`].
    pub fn by_name(name: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Is the body the elastic half-space (else the layer)?
    pub fn on_halfspace(self) -> bool {
        matches!(
            self,
            Family::HalfspaceLcp2d
                | Family::HalfspaceCoulomb2d
                | Family::HalfspaceLcp3d
                | Family::HalfspaceCoulomb3d
        )
    }

    /// Is it a frictionless problem (an LCP)?
    pub fn is_lcp(self) -> bool {
        matches!(
            self,
            Family::Lcp2d | Family::Lcp3d | Family::HalfspaceLcp2d | Family::HalfspaceLcp3d
        )
    }

    /// The largest size the suite runs (3D and frictional W grow fastest:
    /// W of 2025 3D contacts has 6075 rows, 295 MB).
    pub fn max_size(self) -> usize {
        match self {
            Family::Lcp2d | Family::HalfspaceLcp2d | Family::HalfspaceLcp3d => 8000,
            _ => 2025,
        }
    }

    /// Surface dimension of the body + 1.
    pub fn layer_dim(self) -> usize {
        match self {
            Family::Lcp2d
            | Family::Coulomb2d
            | Family::HalfspaceLcp2d
            | Family::HalfspaceCoulomb2d => 2,
            _ => 3,
        }
    }

    pub fn indentation(self) -> Indentation {
        let (approach, slide, mu) = match self {
            Family::Lcp2d => (0.035, 0.0, 0.0),
            Family::Coulomb2d => (0.035, 0.0165, 0.3),
            Family::Lcp3d => (0.08, 0.0, 0.0),
            Family::Coulomb3d => (0.08, 0.025, 0.3),
            Family::HalfspaceLcp2d => (HALFSPACE_APPROACH_2D, 0.0, 0.0),
            Family::HalfspaceCoulomb2d => (HALFSPACE_APPROACH_2D, HALFSPACE_SLIDE_2D, 0.3),
            Family::HalfspaceLcp3d => (HALFSPACE_APPROACH_3D, 0.0, 0.0),
            Family::HalfspaceCoulomb3d => (HALFSPACE_APPROACH_3D, HALFSPACE_SLIDE_3D, 0.3),
        };
        Indentation {
            radius: 1.0,
            approach,
            roughness: 0.02,
            slide,
            mu,
        }
    }

    /// Points along each surface direction for about `m` contact points
    /// (n = m in 2D, n = ⌈√m⌉ in 3D).
    fn divisions(self, m: usize) -> usize {
        let n = if self.layer_dim() == 2 {
            m
        } else {
            (m as f64).sqrt().ceil() as usize
        };
        n.max(2)
    }

    /// The layer whose surface has about `m` nodes.
    pub fn layer(self, m: usize) -> crate::rootbench::layer::Layer {
        crate::rootbench::layer::Layer {
            dim: self.layer_dim(),
            n: self.divisions(m),
            width: 1.0,
            depth: 0.25,
            young: 1.0,
            poisson: 0.3,
        }
    }

    /// The half-space with a grid of about `m` contact points.
    pub fn half_space(self, m: usize) -> HalfSpace {
        HalfSpace {
            dim: self.layer_dim(),
            n: self.divisions(m),
            width: 1.0,
            young: 1.0,
            poisson: 0.3,
            reference_depth: 1.0,
        }
    }

    /// The family's problem with about `m` contact points.
    pub fn problem(self, m: usize) -> Result<RootProblem, String> {
        let load = self.indentation();
        let (p, n) = if self.on_halfspace() {
            let c = self.half_space(m);
            (indentation_problem("", &c, c.width, &load), c.n_surface())
        } else {
            let layer = self.layer(m);
            let c = crate::rootbench::layer::surface_compliance(&layer)?;
            (
                indentation_problem("", &c, layer.width, &load),
                c.n_surface(),
            )
        };
        Ok(RootProblem {
            name: format!("{}_m{}", self.name(), n),
            ..p
        })
    }
}

/// Approaches and slides of the half-space families (relative to L).
const HALFSPACE_APPROACH_2D: f64 = 0.075;
const HALFSPACE_SLIDE_2D: f64 = 0.02;
const HALFSPACE_APPROACH_3D: f64 = 0.134;
const HALFSPACE_SLIDE_3D: f64 = 0.04;
