//! The mean-dilatation B-bar formulation (Hughes 1980; [`crate::bbar`]):
//! patch test, kernel, the count of volumetric constraints, the equivalence
//! with selective reduced integration, the refusals, a locking-free Lamé
//! tube at ν = 0.4999, and the stress recovery with `B̄`.

use super::meshes::{boundary_nodes, boxed, rect, single, single_2d};
use super::{
    assert_cell_stress, fixed_at, linear_2d, linear_3d, mat, solve_dirichlet, strain_3d,
    tube_errors, E, NU,
};
use crate::*;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use signorini_mesh::{CellKind, Mesh};

fn bbar(model: Model, nu: f64) -> Elasticity {
    Elasticity::new(E, nu, model).with_formulation(Formulation::BBar)
}

/// max |x − y| over max |y|.
fn rel_err(x: &[f64], y: &[f64]) -> f64 {
    let top = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    x.iter()
        .zip(y)
        .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()))
        / top
}

/// Solves with the boundary nodes set to `exact` and checks that the
/// interior takes `exact` and every cell the stress `full`.
fn patch(name: &str, m: &Mesh, el: &Elasticity, exact: &[f64], full: &[f64; 6]) {
    let dim = m.dim;
    let fixed = fixed_at(dim, &boundary_nodes(m), exact);
    assert!(fixed.len() < exact.len(), "{name}: no interior node");
    let u = solve_dirichlet(m, el, &vec![0.0; exact.len()], &fixed);
    let err = rel_err(&u, exact);
    assert!(err <= 1e-9, "{name}: displacement error {err:e}");
    let smax = full.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert_cell_stress(m, el, &u, full, 1e-8 * smax, &format!("{name}:"));
}

/// A linear field `u = u0 + G x` imposed on the boundary of distorted Q4
/// (plane strain) and Hex8 meshes, and `u_r = a r`, `u_z = b z + d` on
/// distorted axisymmetric Q4 meshes on and off the axis, is reproduced
/// inside with the exact uniform stress (σ_zz = ν (σ_xx + σ_yy) in plane
/// strain), at ν = 0.3 and ν = 0.4999.
#[test]
fn patch_test_b_bar() {
    for nu in [NU, 0.4999] {
        // plane strain
        let g = [[1.0e-3, -4.0e-4], [2.5e-4, -7.0e-4]];
        let u0 = [3.0e-4, -1.0e-4];
        let m = rect(CellKind::Quad4, [0.5, -0.25], [2.0, 1.0], [5, 4], 0.3);
        let el = bbar(Model::PlaneStrain, nu);
        let exact = linear_2d(&m, u0, g);
        let s = el.d_matrix() * DVector::from_vec(vec![g[0][0], g[1][1], g[0][1] + g[1][0]]);
        let full = [s[0], s[1], nu * (s[0] + s[1]), s[2], 0.0, 0.0];
        patch(&format!("q4 plane strain ν = {nu}"), &m, &el, &exact, &full);

        // axisymmetric, touching the axis and off it
        let (a, b, d) = (4.0e-4, -7.0e-4, 1.0e-4);
        let el = bbar(Model::Axisymmetric, nu);
        for r0 in [0.0, 0.7] {
            let m = rect(CellKind::Quad4, [r0, -0.25], [2.0, 1.0], [5, 4], 0.25);
            let exact: Vec<f64> = m
                .coords
                .iter()
                .flat_map(|p| [a * p[0], b * p[1] + d])
                .collect();
            let s = el.d_matrix() * DVector::from_vec(vec![a, b, a, 0.0]);
            let full = [s[0], s[1], s[2], 0.0, 0.0, 0.0];
            patch(
                &format!("q4 axisymmetric r0 = {r0} ν = {nu}"),
                &m,
                &el,
                &exact,
                &full,
            );
        }

        // solid
        let g = [
            [1.0e-3, -4.0e-4, 2.0e-4],
            [2.5e-4, -7.0e-4, 3.0e-4],
            [-1.5e-4, 5.0e-4, 6.0e-4],
        ];
        let u0 = [3.0e-4, -1.0e-4, 2.0e-4];
        let m = boxed(CellKind::Hex8, [2.0, 1.0, 1.5], [4, 3, 3], 0.2);
        let el = bbar(Model::Solid, nu);
        let exact = linear_3d(&m, u0, g);
        let s = el.d_matrix() * strain_3d(g);
        let full = [s[0], s[1], s[2], s[3], s[4], s[5]];
        patch(&format!("hex8 ν = {nu}"), &m, &el, &exact, &full);
    }
}

/// A distorted Q4 (one corner on the axis) and a distorted Hex8.
fn distorted_cell(kind: CellKind) -> Mesh {
    match kind {
        CellKind::Quad4 => single(
            kind,
            vec![
                [0.0, 0.0, 0.0],
                [1.3, 0.2, 0.0],
                [1.1, 1.3, 0.0],
                [0.1, 0.9, 0.0],
            ],
        ),
        _ => {
            let mut c = Vec::new();
            for (z, k) in [(0.0, 0.0), (1.0, 1.0)] {
                for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                    c.push([x + 0.1 * y * k, y + 0.15 * x * z, z + 0.2 * x * y]);
                }
            }
            single(kind, c)
        }
    }
}

fn eigenvalues(k: &DMatrix<f64>) -> Vec<f64> {
    let mut e: Vec<f64> = SymmetricEigen::new(k.clone())
        .eigenvalues
        .iter()
        .copied()
        .collect();
    e.sort_by(f64::total_cmp);
    e
}

/// The B-bar element stiffness is symmetric, positive semi-definite, and
/// its kernel is exactly the rigid motions (3 in plane strain, the axial
/// translation in axisymmetry, 6 in 3D), as for the displacement element.
/// Near incompressibility (ν = 0.4999, κ ≈ 3300 μ) the displacement element
/// has one stiff (∝ κ) eigenvalue per independent Gauss-point dilatation: 3
/// for Q4 in plane strain (div u ∈ span{1, x, y} on a bilinear field), 4 in
/// axisymmetry (u_r / r adds one), 7 for Hex8; B-bar has exactly one, the
/// element's mean dilatation. That constraint count is what locks.
#[test]
fn b_bar_kernel_and_volumetric_constraints() {
    for (kind, model, rigid, stiff_disp) in [
        (CellKind::Quad4, Model::PlaneStrain, 3, 3),
        (CellKind::Quad4, Model::Axisymmetric, 1, 4),
        (CellKind::Hex8, Model::Solid, 6, 7),
    ] {
        let m = distorted_cell(kind);
        let k = element_stiffness(&m, 0, &bbar(model, NU));
        assert_eq!(k, k.transpose(), "{kind:?} {model:?}: not symmetric");
        let eig = eigenvalues(&k);
        let top = eig[eig.len() - 1];
        assert!(eig[0] > -1e-12 * top, "{kind:?} {model:?}: {eig:?}");
        let zero = eig.iter().filter(|l| l.abs() <= 1e-10 * top).count();
        assert_eq!(zero, rigid, "{kind:?} {model:?}: eigenvalues {eig:?}");
        assert!(eig[rigid] > 1e-4 * top, "{kind:?} {model:?}: {eig:?}");
        for (r, mode) in rigid_body_modes(&m, model).iter().enumerate() {
            let v = DVector::from_column_slice(mode);
            assert!(
                (&k * &v).norm() <= 1e-12 * top * v.norm(),
                "{kind:?} {model:?} mode {r}"
            );
        }
        // stiff eigenvalues near incompressibility
        let nu = 0.4999;
        let mu = E / (2.0 * (1.0 + nu));
        let count = |el: &Elasticity| {
            let eig = eigenvalues(&element_stiffness(&m, 0, el));
            // geometric mean of μ and κ, scaled by the cell's size (O(1) here;
            // the 2π r of axisymmetry is at most 2π · 1.3)
            let kappa = E / (3.0 * (1.0 - 2.0 * nu));
            let cut = (mu * kappa).sqrt()
                * if model == Model::Axisymmetric {
                    8.0
                } else {
                    1.0
                };
            eig.iter().filter(|&&l| l > cut).count()
        };
        let disp = Elasticity::new(E, nu, model);
        assert_eq!(count(&disp), stiff_disp, "{kind:?} {model:?} displacement");
        assert_eq!(count(&bbar(model, nu)), 1, "{kind:?} {model:?} b_bar");
    }
}

/// B-bar equals the selective reduced integration of the bulk term,
/// `K = Σ_g w_g Bᵀ D_dev B + κ V b(0)ᵀ b(0)` with `D_dev = D − κ m mᵀ`
/// (`κ = λ + 2μ/3`; the split of Hughes §4.5, not the λ / μ one), `V` the
/// cell's volume and `b(0)` the dilatation row at the centre, whenever the
/// mean dilatation is the centre's: for every Q4 in plane strain
/// (`det J ∇N` is bilinear in (ξ, η), so the 2×2 rule integrates it exactly
/// to 4 times its centre value, and `∫ det J = 4 det J(0)`), and for a
/// parallelepiped Hex8 (`det J` constant, `∇N` linear in each ξ_i). On a
/// distorted Hex8 they differ.
#[test]
fn b_bar_is_selective_reduced_integration() {
    let para = single_2d(
        CellKind::Quad4,
        &[[0.2, 0.1], [1.5, 0.4], [1.9, 1.3], [0.6, 1.0]],
    );
    let trapezoid = single_2d(
        CellKind::Quad4,
        &[[0.0, 0.0], [2.0, 0.0], [1.4, 1.0], [0.6, 1.0]],
    );
    // a parallelepiped: x = A ξ + c with a full A
    let a = [[0.6, 0.1, 0.05], [0.15, 0.5, -0.1], [0.05, 0.12, 0.7]];
    let pped = single(
        CellKind::Hex8,
        crate::isoparametric::reference_corners(CellKind::Hex8)
            .iter()
            .map(|c| {
                let mut x = [1.0, 2.0, 3.0];
                for (i, xi) in x.iter_mut().enumerate() {
                    *xi += (0..3).map(|j| a[i][j] * c[j]).sum::<f64>();
                }
                x
            })
            .collect(),
    );
    let nu = 0.45;
    let sri = |m: &Mesh, model: Model| -> DMatrix<f64> {
        let el = Elasticity::new(E, nu, model);
        let (lambda, mu) = el.lame();
        let kappa = lambda + 2.0 * mu / 3.0;
        let normal = if model == Model::Solid { 3 } else { 2 };
        // D_dev in the model's layout: in plane strain the zz row of B is
        // zero, so its (xx, yy, xy) block is all that acts
        let mut d_dev = el.d_matrix();
        for i in 0..normal {
            for j in 0..normal {
                d_dev[(i, j)] -= kappa;
            }
        }
        let kind = m.cells[0].kind;
        let n = kind.nodes() * model.dim();
        let mut k = DMatrix::zeros(n, n);
        let mut volume = 0.0;
        for q in quadrature(kind, model) {
            let (b, w) = b_matrix(m, 0, model, q).unwrap();
            k += w * b.transpose() * &d_dev * &b;
            volume += w;
        }
        let centre = QuadPoint {
            xi: [0.0; 3],
            w: 1.0,
        };
        let (b, _) = b_matrix(m, 0, model, &centre).unwrap();
        let b0 = b.rows(0, normal).row_sum();
        k + kappa * volume * b0.transpose() * b0
    };
    let distorted_quad = distorted_cell(CellKind::Quad4);
    let distorted_hex = distorted_cell(CellKind::Hex8);
    for (name, m, model, same) in [
        ("parallelogram", &para, Model::PlaneStrain, true),
        ("trapezoid", &trapezoid, Model::PlaneStrain, true),
        ("distorted quad", &distorted_quad, Model::PlaneStrain, true),
        ("parallelepiped", &pped, Model::Solid, true),
        ("distorted hex", &distorted_hex, Model::Solid, false),
    ] {
        let k = element_stiffness(m, 0, &bbar(model, nu));
        let diff = (&k - sri(m, model)).amax() / k.amax();
        if same {
            assert!(diff <= 1e-13, "{name}: B-bar − SRI = {diff:e} of max |K|");
        } else {
            assert!(diff >= 1e-3, "{name}: B-bar − SRI = {diff:e} of max |K|");
        }
    }
}

/// B-bar is refused where it does not apply: plane stress, triangles,
/// tetrahedra and Q8, with a message naming the cell and what is valid.
#[test]
fn b_bar_refusals() {
    let m = rect(CellKind::Quad4, [0.0, 0.0], [1.0, 1.0], [2, 2], 0.0);
    let err = try_assemble_stiffness(&m, &bbar(Model::PlaneStress, NU)).unwrap_err();
    assert!(
        err.to_string().contains("plane stress does not lock"),
        "{err}"
    );
    for kind in [CellKind::Tri3, CellKind::Tri6, CellKind::Quad8] {
        let m = rect(kind, [0.0, 0.0], [1.0, 1.0], [2, 2], 0.0);
        let err = try_assemble_stiffness(&m, &bbar(Model::PlaneStrain, NU)).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("cell 0") && msg.contains("quad4"), "{msg}");
        assert!(try_element_stiffness(&m, 0, &bbar(Model::PlaneStrain, NU)).is_err());
    }
    let m = boxed(CellKind::Tet4, [1.0; 3], [1, 1, 1], 0.0);
    let err = check_formulation(&m, &bbar(Model::Solid, NU)).unwrap_err();
    assert!(err.to_string().contains("hex8"), "{err}");
    // the displacement formulation takes them all
    assert!(check_formulation(&m, &mat(Model::Solid)).is_ok());
}

/// Thick-walled tube `1 ≤ r ≤ 2` under internal pressure, ends on rollers
/// (ε_z = 0), at ν = 0.4999: Lamé's `u_r = A r + B / r` (see
/// `axisymmetric::thick_walled_cylinder_lame`), 8 × 4 square Q4 cells. The
/// displacement Q4 locks: measured max nodal u_r error 0.80 of u_r(a) (the
/// wall moves 5 times too little) and hoop stress error 0.33 of σ_θθ(a);
/// B-bar: 1.1e-3 and 2.1e-3.
#[test]
fn lame_tube_near_incompressible() {
    let (a, b, h, p) = (1.0, 2.0, 0.5, 10.0);
    let nu = 0.4999;
    let big_a = (1.0 + nu) * (1.0 - 2.0 * nu) * p * a * a / (E * (b * b - a * a));
    let big_b = (1.0 + nu) * p * a * a * b * b / (E * (b * b - a * a));
    let ur = |r: f64| big_a * r + big_b / r;
    let hoop = |r: f64| p * a * a / (b * b - a * a) * (1.0 + b * b / (r * r));
    let m = rect(CellKind::Quad4, [a, 0.0], [b - a, h], [8, 4], 0.0);
    let model = Model::Axisymmetric;
    let f = traction_load(&m, m.surface("left").unwrap(), &[p, 0.0], model);
    let fixed: Vec<(usize, f64)> = ["bottom", "top"]
        .iter()
        .flat_map(|s| m.surface(s).unwrap().nodes())
        .map(|n| (2 * n + 1, 0.0))
        .collect();
    let errors = |el: &Elasticity| {
        let u = solve_dirichlet(&m, el, &f, &fixed);
        tube_errors(&m, el, &u, &ur, &hoop, a)
    };
    let disp = errors(&Elasticity::new(E, nu, model));
    let bb = errors(&bbar(model, nu));
    let msg = format!("displacement (u_r, hoop) errors {disp:?}, b_bar {bb:?}");
    assert!(bb.0 < 3e-3 && bb.1 < 5e-3, "{msg}");
    assert!(disp.0 > 0.5 && disp.1 > 0.2, "{msg}");
}

/// The stresses of a B-bar body are `D B̄ u_e` at the cell centres, with the
/// stiffness's `B̄`: on distorted Hex8 and axisymmetric Q4 meshes under a
/// quadratic field (non-uniform dilatation) they match `d_matrix_bbar ·
/// b_bar_matrix(centre) · u_e`, and differ from the displacement
/// formulation's `D B u_e` (so the check can tell them apart).
#[test]
fn b_bar_stress_recovery_uses_b_bar() {
    let cases = [
        (
            boxed(CellKind::Hex8, [2.0, 1.0, 1.5], [3, 2, 2], 0.2),
            Model::Solid,
        ),
        (
            rect(CellKind::Quad4, [0.3, 0.0], [1.0, 1.0], [3, 3], 0.25),
            Model::Axisymmetric,
        ),
    ];
    for (m, model) in cases {
        let dim = m.dim;
        let u: Vec<f64> = m
            .coords
            .iter()
            .flat_map(|p| {
                (0..dim).map(move |k| 1e-3 * (p[k] * p[k] + 0.5 * p[(k + 1) % dim] * p[k]))
            })
            .collect();
        let el = bbar(model, 0.49);
        let d = d_matrix_bbar(&el);
        let got = cell_stress(&m, &el, &u);
        let plain = cell_stress(&m, &Elasticity::new(E, 0.49, model), &u);
        let top = got.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut differs = 0.0f64;
        for (c, cell) in m.cells.iter().enumerate() {
            let q = QuadPoint {
                xi: [0.0; 3],
                w: 1.0,
            };
            let (b, _) = b_bar_matrix(&m, c, model, &q).unwrap();
            let u = &u;
            let ue = DVector::from_iterator(
                dim * cell.nodes.len(),
                cell.nodes
                    .iter()
                    .flat_map(|&n| (0..dim).map(move |k| u[dim * n + k])),
            );
            let s = &d * (&b * ue);
            for k in 0..s.len() {
                assert!(
                    (got[c][k] - s[k]).abs() <= 1e-12 * top,
                    "{model:?} cell {c} [{k}]: {} vs {}",
                    got[c][k],
                    s[k]
                );
            }
            for k in 0..6 {
                differs = differs.max((got[c][k] - plain[c][k]).abs() / top);
            }
        }
        assert!(
            differs > 1e-5,
            "{model:?}: B-bar and plain stresses differ by {differs:e}"
        );
    }
}
