//! The mean-dilatation **B-bar** formulation against volumetric locking
//! (Hughes 1980, "Generalization of selective integration procedures to
//! anisotropic and nonlinear media", IJNME 15, pp. 1413–1418; Hughes, *The
//! Finite Element Method: Linear Static and Dynamic Finite Element
//! Analysis*, §4.5).
//!
//! As ν → ½ the bulk modulus `κ = λ + 2μ/3` dominates `D`, and the
//! displacement formulation asks for `div u ≈ 0` at every Gauss point: a
//! bilinear Q4 or trilinear Hex8 field meets that many constraints only by
//! hardly moving (locking; the contact patch of a Hertz cylinder comes out
//! 25 % too narrow at ν = 0.4999, see docs/theory/elements.md). B-bar keeps the
//! deviatoric part of `B` and replaces its volumetric part by the element
//! mean, so the incompressibility is enforced once per element:
//!
//! ```text
//! B̄ = B − B_vol + B̄_vol,   B_vol = ⅓ m mᵀ B,   B̄_vol = (∫_e B_vol dV) / (∫_e dV),
//! K_e = ∫_e B̄ᵀ D B̄ dV,
//! ```
//!
//! with `m = 1` on the three normal strain components and 0 on the shears,
//! `mᵀ B u_e = div u` the dilatation, and `dV` carrying `2π r` in
//! axisymmetry (the mean is over the ring's volume). Both integrals use the
//! cell's Gauss rule (2×2 for Q4, 2×2×2 for Hex8).
//!
//! **Strain layout.** The volumetric part involves all three normal strains,
//! so the B-bar strain vector always has them, normal components first:
//!
//! | model | B-bar strain vector | `D` |
//! |---|---|---|
//! | plane strain | `[ε_xx, ε_yy, ε_zz, γ_xy]` | the 4×4 (xx, yy, zz, xy) block of the 3D `D` |
//! | axisymmetric | `[ε_rr, ε_zz, ε_θθ, γ_rz]` (as [`crate::Elasticity::d_matrix`]) | the model's `D` |
//! | solid | `[ε_xx, ε_yy, ε_zz, γ_xy, γ_yz, γ_xz]` | the model's `D` |
//!
//! In plane strain the row ε_zz of `B` is zero but that of `B̄` is not:
//! `ε̄_zz = ⅓ (θ̄ − θ)` (θ the dilatation at the point, θ̄ its element mean),
//! zero in the element mean only. The recovered stress ([`crate::cell_stress`])
//! is `D B̄ u_e`, σ_zz included. (It is recovered at the cell centre, and the
//! mean dilatation of a plane-strain Q4 is the one at its centre (see below),
//! so there `B̄ = B`, `ε̄_zz = 0` and σ_zz = ν (σ_xx + σ_yy); not so at the
//! Gauss points, nor in axisymmetry and 3D.)
//! In axisymmetry the hoop strain `u_r / r` is a normal strain, part of the
//! dilatation `∂u_r/∂r + u_r/r + ∂u_z/∂z`.
//!
//! **Properties** (tested in `src/tests/b_bar.rs`): for a displacement
//! field of uniform dilatation (a linear field in the plane and 3D models,
//! among others) `B̄ u_e = B u_e`, so B-bar passes the patch test; its kernel
//! is the displacement element's (the rigid motions); and since
//! `D_dev m = 0` for `D = D_dev + κ m mᵀ` (`κ = λ + 2μ/3`),
//! `K_e = ∫ Bᵀ D_dev B dV + κ V b̄ᵀ b̄` (`b̄ = mᵀ B̄_vol`, `V` the element's
//! volume): one volumetric constraint per element instead of one per Gauss
//! point. When the mean dilatation is the one at the centre, this is the
//! selective reduced integration of the bulk term: for every Q4 in plane
//! strain (`det J ∇N` is bilinear in (ξ, η)) and for parallelepipeds.
//!
//! Plane stress does not lock (σ_zz = 0 leaves ε_zz free) and the B-bar
//! formulation is refused there; triangles and tetrahedra (T3, T6, Tet4) and
//! Q8 have no B-bar here ([`crate::Formulation::supports`]).

use crate::isoparametric::{check_kind, fill_b};
use crate::quadrature::{quadrature, QuadPoint};
use crate::{Elasticity, FemError, Formulation, Model};
use nalgebra::{DMatrix, DVector};
use signorini_mesh::Mesh;

/// Length of the B-bar strain vector of `model`: 4 in plane strain
/// (`[xx, yy, zz, xy]`) and axisymmetry, 6 in 3D (and 3 in plane stress,
/// where B-bar is not used).
pub fn n_strain_bbar(model: Model) -> usize {
    match model {
        Model::PlaneStrain => 4,
        m => m.n_strain(),
    }
}

/// Hooke matrix in the B-bar strain layout (module docs): in plane strain
/// the 4×4 block `(xx, yy, zz, xy)` of the 3D isotropic `D`,
/// `D_ij = λ + 2μ δ_ij` on the normals and `μ` on the shear; otherwise
/// [`Elasticity::d_matrix`].
pub fn d_matrix_bbar(mat: &Elasticity) -> DMatrix<f64> {
    match mat.model {
        // the axisymmetric D is exactly that block: three normals, one shear
        Model::PlaneStrain => Elasticity {
            model: Model::Axisymmetric,
            ..*mat
        }
        .d_matrix(),
        _ => mat.d_matrix(),
    }
}

/// Fills `b` (`n_strain_bbar × dim·n`) with the plain `B` of `cell` at `q`
/// in the B-bar layout (a zero ε_zz row inserted in plane strain), using
/// `tmp` (`n_strain × dim·n`) as scratch; returns the quadrature weight.
fn fill_b_layout(
    mesh: &Mesh,
    cell: usize,
    model: Model,
    q: &QuadPoint,
    tmp: &mut DMatrix<f64>,
    b: &mut DMatrix<f64>,
) -> Result<f64, FemError> {
    if model != Model::PlaneStrain {
        return fill_b(mesh, cell, model, q, b);
    }
    let w = fill_b(mesh, cell, model, q, tmp)?;
    b.fill(0.0);
    for (to, from) in [(0, 0), (1, 1), (3, 2)] {
        b.row_mut(to).copy_from(&tmp.row(from));
    }
    Ok(w)
}

/// The dilatation row `mᵀ B` (sum of the three normal rows).
fn dilatation(b: &DMatrix<f64>) -> DVector<f64> {
    (b.row(0) + b.row(1) + b.row(2)).transpose()
}

/// `B → B̄ = B + ⅓ m (b̄ − mᵀB)`: adds the same row to the three normal rows.
fn to_b_bar(b: &mut DMatrix<f64>, mean: &DVector<f64>) {
    let shift = (mean - dilatation(b)) / 3.0;
    for r in 0..3 {
        let mut row = b.row_mut(r);
        row += shift.transpose();
    }
}

/// Checks that B-bar applies to `cell` in `model`.
fn check_bbar(mesh: &Mesh, cell: usize, model: Model) -> Result<(), FemError> {
    check_kind(mesh, cell, model)?;
    let kind = mesh.cells[cell].kind;
    if Formulation::BBar.supports(kind, model) {
        Ok(())
    } else {
        Err(unsupported(cell, kind.name(), model))
    }
}

pub(crate) fn unsupported(cell: usize, kind: &str, model: Model) -> FemError {
    FemError::Unsupported(format!(
        "cell {cell} is a {kind} cell in the {} model; the b_bar formulation takes quad4 cells (plane_strain, axisymmetric) and hex8 cells (solid), not tri3, tri6, quad8 or tet4 cells nor plane_stress; use the displacement formulation there",
        model.name()
    ))
}

/// A strain–displacement matrix at a Gauss point with its quadrature weight.
type WeightedB = (DMatrix<f64>, f64);

/// The plain `B` (B-bar layout) and weight at every Gauss point of `cell`,
/// and the element mean of the dilatation row `b̄ = ∫ mᵀB dV / ∫ dV`.
fn gauss_b(
    mesh: &Mesh,
    cell: usize,
    model: Model,
) -> Result<(Vec<WeightedB>, DVector<f64>), FemError> {
    check_bbar(mesh, cell, model)?;
    let kind = mesh.cells[cell].kind;
    let n = kind.nodes() * model.dim();
    let mut tmp = DMatrix::zeros(model.n_strain(), n);
    let mut mean = DVector::zeros(n);
    let mut volume = 0.0;
    let mut out = Vec::with_capacity(8);
    for q in quadrature(kind, model) {
        let mut b = DMatrix::zeros(n_strain_bbar(model), n);
        let w = fill_b_layout(mesh, cell, model, q, &mut tmp, &mut b)?;
        mean.axpy(w, &dilatation(&b), 1.0);
        volume += w;
        out.push((b, w));
    }
    mean /= volume;
    Ok((out, mean))
}

/// `B̄` of `cell` (Quad4 in plane strain or axisymmetry, Hex8 in 3D) at the
/// reference point `q.xi`, in the B-bar strain layout of the module docs
/// (`n_strain_bbar(model) × dim·n`), with the weight `q.w · det J` (`· 2π r`
/// in axisymmetry) as [`crate::b_matrix`]; `B̄ u_e` is the B-bar strain there.
///
/// # Errors
/// [`FemError::Unsupported`] for another cell kind or model, and the errors
/// of [`crate::b_matrix`] at `q` or at the cell's Gauss points.
pub fn b_bar_matrix(
    mesh: &Mesh,
    cell: usize,
    model: Model,
    q: &QuadPoint,
) -> Result<(DMatrix<f64>, f64), FemError> {
    let (_, mean) = gauss_b(mesh, cell, model)?;
    let n = mesh.cells[cell].kind.nodes() * model.dim();
    let mut tmp = DMatrix::zeros(model.n_strain(), n);
    let mut b = DMatrix::zeros(n_strain_bbar(model), n);
    let w = fill_b_layout(mesh, cell, model, q, &mut tmp, &mut b)?;
    to_b_bar(&mut b, &mean);
    Ok((b, w))
}

/// `K_e = Σ_g w_g B̄_gᵀ D B̄_g` with `d` = [`d_matrix_bbar`], symmetrised.
pub(crate) fn stiffness_bbar(
    mesh: &Mesh,
    cell: usize,
    model: Model,
    d: &DMatrix<f64>,
) -> Result<DMatrix<f64>, FemError> {
    let (points, mean) = gauss_b(mesh, cell, model)?;
    let n = mean.len();
    let mut k = DMatrix::zeros(n, n);
    let mut db = DMatrix::zeros(d.nrows(), n);
    for (mut b, w) in points {
        to_b_bar(&mut b, &mean);
        db.gemm(1.0, d, &b, 0.0);
        k.gemm_tr(w, &b, &db, 1.0);
    }
    let ks = (&k + k.transpose()) * 0.5;
    Ok(ks)
}

/// A B-bar stress `D B̄ u_e` (B-bar layout) as the full 3D
/// `[σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz]` (axisymmetric: `[σ_rr, σ_zz, σ_θθ,
/// σ_rz, 0, 0]`).
pub(crate) fn full_stress_bbar(model: Model, s: &[f64]) -> [f64; 6] {
    match model {
        Model::Solid => [s[0], s[1], s[2], s[3], s[4], s[5]],
        _ => [s[0], s[1], s[2], s[3], 0.0, 0.0],
    }
}
