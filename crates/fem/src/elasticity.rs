//! Isotropic linear elasticity: the kinematic [`Model`] and the Hooke matrix
//! `D` with `σ = D ε` in the model's Voigt order (engineering shear strains,
//! `γ_ij = 2 ε_ij`):
//!
//! | model | strain vector `ε` |
//! |---|---|
//! | plane strain, plane stress | `[ε_xx, ε_yy, γ_xy]` |
//! | axisymmetric (`x = r`, `y = z`) | `[ε_rr, ε_zz, ε_θθ, γ_rz]` |
//! | solid (3D) | `[ε_xx, ε_yy, ε_zz, γ_xy, γ_yz, γ_xz]` |

use crate::FemError;
use nalgebra::DMatrix;
use signorini_mesh::CellKind;

/// Kinematic model of a body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Model {
    /// 2D, thickness 1: ε_zz = 0 (long bodies); σ_zz = ν (σ_xx + σ_yy).
    PlaneStrain,
    /// 2D, thickness 1: σ_zz = 0 (thin plates); ε_zz = −ν/(1−ν) (ε_xx + ε_yy).
    PlaneStress,
    /// 2D meridian half-plane of a body of revolution about the y axis:
    /// `x = r ≥ 0` (radius), `y = z` (axial). Displacement `(u_r, u_z)`, hoop
    /// strain `ε_θθ = u_r / r`. Every integral carries the weight `2π r`, so
    /// stiffness, forces and measures are those of the full 360° ring: a
    /// nodal force is the total force on the ring of that node.
    Axisymmetric,
    /// 3D solid.
    Solid,
}

impl Model {
    /// Space dimension of the model's meshes (and DOFs per node): 2 or 3.
    pub fn dim(self) -> usize {
        match self {
            Model::Solid => 3,
            _ => 2,
        }
    }

    /// Length of the model's strain (and stress) vector: 3, 4 or 6.
    pub fn n_strain(self) -> usize {
        match self {
            Model::PlaneStrain | Model::PlaneStress => 3,
            Model::Axisymmetric => 4,
            Model::Solid => 6,
        }
    }

    /// The scene-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            Model::PlaneStrain => "plane_strain",
            Model::PlaneStress => "plane_stress",
            Model::Axisymmetric => "axisymmetric",
            Model::Solid => "solid",
        }
    }
}

/// How a body's elements relate strains to displacements (scene key
/// `bodies.formulation`).
///
/// Low-order elements **lock** as ν → ½ in the models where the volume is
/// constrained (plane strain, axisymmetric, solid): the bulk modulus
/// `κ = λ + 2μ/3` grows without bound, and the pointwise constraint
/// `div u ≈ 0` at every Gauss point leaves a bilinear or trilinear field
/// almost no way to deform, so displacements come out far too small. The
/// mean-dilatation **B-bar** method (Hughes 1980, "Generalization of selective
/// integration procedures to anisotropic and nonlinear media", IJNME 15,
/// pp. 1413–1418; Hughes, *The Finite Element Method*, 1987/2000, §4.5)
/// enforces the volume change only in the element mean. It is offered for
/// Quad4 (plane strain and axisymmetric) and Hex8 (solid), see [`crate::bbar`];
/// plane stress does not lock (σ_zz = 0 leaves ε_zz free) and is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Formulation {
    /// The standard displacement formulation `K_e = ∫ Bᵀ D B dV`.
    #[default]
    Displacement,
    /// Mean-dilatation B-bar: `K_e = ∫ B̄ᵀ D B̄ dV` with the volumetric part of
    /// `B` replaced by its element mean ([`crate::bbar`]).
    BBar,
}

impl Formulation {
    /// The scene-file spelling: `displacement` or `b_bar`.
    pub fn name(self) -> &'static str {
        match self {
            Formulation::Displacement => "displacement",
            Formulation::BBar => "b_bar",
        }
    }

    /// Whether this formulation is available for `kind` cells in `model`:
    /// the displacement formulation everywhere; B-bar for Quad4 in plane
    /// strain and axisymmetry and Hex8 in 3D.
    pub fn supports(self, kind: CellKind, model: Model) -> bool {
        match self {
            Formulation::Displacement => true,
            Formulation::BBar => matches!(
                (kind, model),
                (CellKind::Quad4, Model::PlaneStrain | Model::Axisymmetric)
                    | (CellKind::Hex8, Model::Solid)
            ),
        }
    }
}

/// An isotropic linear elastic material in a kinematic model, with the
/// element [`Formulation`] that discretises it (the displacement formulation
/// unless asked otherwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elasticity {
    pub young: f64,
    pub poisson: f64,
    pub model: Model,
    pub formulation: Formulation,
}

impl Elasticity {
    /// A material in `model` with the displacement formulation.
    pub fn new(young: f64, poisson: f64, model: Model) -> Self {
        Elasticity {
            young,
            poisson,
            model,
            formulation: Formulation::Displacement,
        }
    }

    /// The same material with another element formulation.
    pub fn with_formulation(self, formulation: Formulation) -> Self {
        Elasticity {
            formulation,
            ..self
        }
    }

    /// Lamé's constants `(λ, μ)`: `λ = E ν / ((1+ν)(1−2ν))`, `μ = G = E / (2(1+ν))`.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }

    /// Hooke matrix `D` (`n_strain × n_strain`) in the model's Voigt order (see
    /// the module docs). With the normal components first and the shears after,
    ///
    /// ```text
    /// D_ij = λ' + 2μ δ_ij   (i, j normal),     D_kk = μ   (k shear),   0 elsewhere,
    /// ```
    ///
    /// over the normal components `[xx, yy]` (plane), `[rr, zz, θθ]`
    /// (axisymmetric) or `[xx, yy, zz]` (solid), with `λ' = λ` except in plane
    /// stress, where eliminating `σ_zz = 0` gives `λ' = 2λμ / (λ + 2μ) = E ν / (1−ν²)`:
    ///
    /// plane strain: `E / ((1+ν)(1−2ν)) · [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]]`,
    ///
    /// plane stress: `E / (1−ν²) · [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]]`;
    ///
    /// plane strain and axisymmetry are the 3D matrix restricted to their
    /// components.
    pub fn d_matrix(&self) -> DMatrix<f64> {
        let (lambda, mu) = self.lame();
        let (normal, lam) = match self.model {
            Model::PlaneStrain => (2, lambda),
            Model::PlaneStress => (2, 2.0 * lambda * mu / (lambda + 2.0 * mu)),
            Model::Axisymmetric | Model::Solid => (3, lambda),
        };
        let n = self.model.n_strain();
        DMatrix::from_fn(n, n, |i, j| match (i < normal, j < normal) {
            (true, true) => lam + if i == j { 2.0 * mu } else { 0.0 },
            _ if i == j => mu,
            _ => 0.0,
        })
    }

    /// The contact modulus `E'` of Hertz theory for this body (its compliance
    /// in `1/E* = 1/E'_1 + 1/E'_2`): `E / (1−ν²)` in plane strain,
    /// axisymmetry and 3D (a half-space), `E` in plane stress. In the two plane
    /// models it is also the uniaxial stiffness `σ_yy / ε_yy` with `σ_xx = 0`.
    pub fn plane_modulus(&self) -> f64 {
        match self.model {
            Model::PlaneStress => self.young,
            Model::PlaneStrain | Model::Axisymmetric | Model::Solid => {
                self.young / (1.0 - self.poisson * self.poisson)
            }
        }
    }

    /// The out-of-plane stress `σ_zz` of a plane model from the in-plane ones:
    /// `Some(ν (σ_xx + σ_yy))` in plane strain, `Some(0)` in plane stress.
    /// `None` for the axisymmetric and solid models, where the third normal
    /// stress (the hoop stress `σ_θθ`, or `σ_zz` in 3D) is an independent
    /// component of `D ε` (see [`Elasticity::full_stress`]).
    pub fn sigma_zz(&self, sxx: f64, syy: f64) -> Option<f64> {
        match self.model {
            Model::PlaneStrain => Some(self.poisson * (sxx + syy)),
            Model::PlaneStress => Some(0.0),
            Model::Axisymmetric | Model::Solid => None,
        }
    }

    /// A stress vector `s = D ε` of the model's Voigt order as the full 3D
    /// `[σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz]`:
    ///
    /// * plane: `[s_xx, s_yy, σ_zz, s_xy, 0, 0]` with [`Elasticity::sigma_zz`];
    /// * axisymmetric: `[σ_rr, σ_zz, σ_θθ, σ_rz, 0, 0]`, i.e. slot xx = radial,
    ///   yy = axial, **zz = hoop**, xy = rz (the mesh's `x` is `r` and its `y`
    ///   is the axis; the third direction is the circumferential one);
    /// * solid: `s` itself.
    ///
    /// # Panics
    /// If `s.len()` is not the model's [`Model::n_strain`].
    pub fn full_stress(&self, s: &[f64]) -> [f64; 6] {
        assert_eq!(s.len(), self.model.n_strain(), "full_stress: wrong length");
        match self.model {
            Model::PlaneStrain | Model::PlaneStress => {
                let zz = self.sigma_zz(s[0], s[1]).unwrap_or(0.0);
                [s[0], s[1], zz, s[2], 0.0, 0.0]
            }
            Model::Axisymmetric => [s[0], s[1], s[2], s[3], 0.0, 0.0],
            Model::Solid => [s[0], s[1], s[2], s[3], s[4], s[5]],
        }
    }

    /// [`check_material`] on this material (the same bounds in every model),
    /// and a formulation the model has: B-bar is refused in plane stress,
    /// which does not lock (the cell kinds are checked by
    /// [`crate::check_formulation`]).
    pub fn check(&self) -> Result<(), FemError> {
        check_material(self.young, self.poisson)?;
        if self.formulation == Formulation::BBar && self.model == Model::PlaneStress {
            return Err(FemError::Unsupported(
                "the b_bar formulation is for plane_strain, axisymmetric and solid models; plane stress does not lock as ν → 0.5 (σ_zz = 0 leaves ε_zz free), use the displacement formulation".into(),
            ));
        }
        Ok(())
    }
}

/// A usable isotropic material: `E > 0` finite and `−1 < ν < 1/2` (positive
/// definite strain energy in 3D, hence in every model: plane strain, plane
/// stress, axisymmetric and solid).
pub fn check_material(young: f64, poisson: f64) -> Result<(), FemError> {
    if !(young.is_finite() && young > 0.0) {
        return Err(FemError::Material(format!(
            "Young's modulus must be positive and finite, got {young}"
        )));
    }
    if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
        return Err(FemError::Material(format!(
            "Poisson's ratio must lie in (-1, 0.5), got {poisson}"
        )));
    }
    Ok(())
}
