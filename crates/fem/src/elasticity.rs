//! Isotropic linear elasticity in 2D: the Hooke matrix `D` with `σ = D ε`
//! (Voigt `[σ_xx, σ_yy, σ_xy]`, `ε = [ε_xx, ε_yy, γ_xy]`, `γ_xy = 2 ε_xy`).

use crate::FemError;
use nalgebra::Matrix3;

/// 2D kinematic model (3D solids and axisymmetry come later).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Model {
    /// ε_zz = 0 (long bodies); σ_zz = ν (σ_xx + σ_yy).
    PlaneStrain,
    /// σ_zz = 0 (thin plates); ε_zz = −ν/(1−ν) (ε_xx + ε_yy).
    PlaneStress,
}

/// An isotropic linear elastic material in a 2D model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elasticity {
    pub young: f64,
    pub poisson: f64,
    pub model: Model,
}

impl Elasticity {
    /// Hooke matrix in Voigt notation `[xx, yy, xy (engineering)]`:
    ///
    /// plane strain: `E / ((1+ν)(1−2ν)) · [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]]`,
    ///
    /// plane stress: `E / (1−ν²) · [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]]`.
    ///
    /// In both the shear entry is the shear modulus `G = E / (2(1+ν))`.
    pub fn d_matrix(&self) -> Matrix3<f64> {
        let (e, nu) = (self.young, self.poisson);
        match self.model {
            Model::PlaneStrain => {
                let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
                Matrix3::new(
                    c * (1.0 - nu),
                    c * nu,
                    0.0,
                    c * nu,
                    c * (1.0 - nu),
                    0.0,
                    0.0,
                    0.0,
                    e / (2.0 * (1.0 + nu)),
                )
            }
            Model::PlaneStress => {
                let c = e / (1.0 - nu * nu);
                Matrix3::new(
                    c,
                    c * nu,
                    0.0,
                    c * nu,
                    c,
                    0.0,
                    0.0,
                    0.0,
                    e / (2.0 * (1.0 + nu)),
                )
            }
        }
    }

    /// The plane modulus `E'` of Hertz theory: `E / (1−ν²)` in plane strain,
    /// `E` in plane stress (the uniaxial-stress stiffness `σ_yy / ε_yy` with
    /// `σ_xx = 0`).
    pub fn plane_modulus(&self) -> f64 {
        match self.model {
            Model::PlaneStrain => self.young / (1.0 - self.poisson * self.poisson),
            Model::PlaneStress => self.young,
        }
    }

    /// The out-of-plane stress `σ_zz` from the in-plane ones: `ν (σ_xx + σ_yy)`
    /// in plane strain, 0 in plane stress.
    pub fn sigma_zz(&self, sxx: f64, syy: f64) -> f64 {
        match self.model {
            Model::PlaneStrain => self.poisson * (sxx + syy),
            Model::PlaneStress => 0.0,
        }
    }

    /// [`check_material`] on this material.
    pub fn check(&self) -> Result<(), FemError> {
        check_material(self.young, self.poisson)
    }
}

/// A usable isotropic material: `E > 0` finite and `−1 < ν < 1/2` (positive
/// definite strain energy in 3D, hence in plane strain and plane stress).
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
