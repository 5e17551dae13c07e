//! Every cell kind in every model: the Hooke matrices, the element kernel,
//! the 2D patch test of T6/Q8 (and T3/Q4 on the hand-built meshes), mesh
//! checks and the von Mises stress.

use super::meshes::{boundary_nodes, rect, single};
use super::{assert_cell_stress, linear_2d, mat, solve_patch, E, KINDS, KINDS_2D, NU};
use crate::*;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use signorini_mesh::CellKind;

const PLANE: [Model; 2] = [Model::PlaneStrain, Model::PlaneStress];

#[test]
fn d_matrix_every_model() {
    let solid = mat(Model::Solid).d_matrix();
    assert_eq!(solid.shape(), (6, 6));
    let (lambda, mu) = mat(Model::Solid).lame();
    assert!((mu - E / (2.0 * (1.0 + NU))).abs() < 1e-12 * E);
    for i in 0..6 {
        for j in 0..6 {
            let expect = match (i < 3, j < 3) {
                (true, true) => lambda + if i == j { 2.0 * mu } else { 0.0 },
                _ if i == j => mu,
                _ => 0.0,
            };
            assert!((solid[(i, j)] - expect).abs() < 1e-12 * E, "({i}, {j})");
        }
    }
    // the inverse is the compliance: 1/E on the diagonal, −ν/E off it, 1/G in shear
    let s = solid.clone().try_inverse().unwrap();
    assert!((s[(0, 0)] * E - 1.0).abs() < 1e-12);
    assert!((s[(0, 1)] * E + NU).abs() < 1e-12);
    assert!((s[(4, 4)] * mu - 1.0).abs() < 1e-12);
    // plane strain and axisymmetry: the 3D matrix restricted to their components
    let restrict =
        |rows: &[usize]| DMatrix::from_fn(rows.len(), rows.len(), |i, j| solid[(rows[i], rows[j])]);
    let diff = |a: &DMatrix<f64>, b: &DMatrix<f64>| (a - b).amax();
    assert!(diff(&mat(Model::PlaneStrain).d_matrix(), &restrict(&[0, 1, 3])) < 1e-12 * E);
    assert!(
        diff(
            &mat(Model::Axisymmetric).d_matrix(),
            &restrict(&[0, 1, 2, 3])
        ) < 1e-12 * E
    );
    // plane stress: σ_zz = 0 eliminated from the 3D law
    let ps = mat(Model::PlaneStress).d_matrix();
    let c = E / (1.0 - NU * NU);
    assert!((ps[(0, 0)] - c).abs() < 1e-12 * E);
    assert!((ps[(0, 1)] - c * NU).abs() < 1e-12 * E);
    assert!((ps[(2, 2)] - mu).abs() < 1e-12 * E);
    // contact moduli and the out-of-plane stress
    for model in [Model::PlaneStrain, Model::Axisymmetric, Model::Solid] {
        assert!((mat(model).plane_modulus() - E / (1.0 - NU * NU)).abs() < 1e-12 * E);
    }
    assert_eq!(mat(Model::PlaneStress).plane_modulus(), E);
    assert_eq!(mat(Model::PlaneStrain).sigma_zz(1.0, 2.0), Some(3.0 * NU));
    assert_eq!(mat(Model::PlaneStress).sigma_zz(1.0, 2.0), Some(0.0));
    assert_eq!(mat(Model::Axisymmetric).sigma_zz(1.0, 2.0), None);
    assert_eq!(mat(Model::Solid).sigma_zz(1.0, 2.0), None);
    for (model, dim, n) in [
        (Model::PlaneStrain, 2, 3),
        (Model::PlaneStress, 2, 3),
        (Model::Axisymmetric, 2, 4),
        (Model::Solid, 3, 6),
    ] {
        assert_eq!((model.dim(), model.n_strain()), (dim, n));
        assert_eq!(mat(model).d_matrix().shape(), (n, n));
    }
}

/// The corners of a 2D cell followed by the middles of its edges (corner k
/// to corner k + 1), the middle of edge `bent.0` moved by `bent.1` in x.
/// A solid's corners then the midpoints of its `edges`, the first one's
/// moved by `bent` along x.
fn with_edge_midsides(corners: &[[f64; 3]], edges: &[[usize; 2]], bent: f64) -> Vec<[f64; 3]> {
    let mids = edges.iter().enumerate().map(|(e, &[i, j])| {
        let (p, q) = (corners[i], corners[j]);
        let mut m = [
            0.5 * (p[0] + q[0]),
            0.5 * (p[1] + q[1]),
            0.5 * (p[2] + q[2]),
        ];
        if e == 0 {
            m[0] += bent;
        }
        m
    });
    corners.iter().copied().chain(mids).collect()
}

fn with_midsides(corners: &[[f64; 3]], bent: (usize, f64)) -> Vec<[f64; 3]> {
    let n = corners.len();
    let mids = (0..n).map(|k| {
        let (p, q) = (corners[k], corners[(k + 1) % n]);
        let mut m = [
            0.5 * (p[0] + q[0]),
            0.5 * (p[1] + q[1]),
            0.5 * (p[2] + q[2]),
        ];
        if k == bent.0 {
            m[0] += bent.1;
        }
        m
    });
    corners.iter().copied().chain(mids).collect()
}

/// One distorted cell of each kind; in 2D with every x ≥ 0 and one corner on
/// the axis x = 0 (so the axisymmetric element touches the axis).
fn one_cell(kind: CellKind) -> signorini_mesh::Mesh {
    let tri = [[0.0, 0.1, 0.0], [1.3, 0.0, 0.0], [0.5, 1.2, 0.0]];
    let quad = [
        [0.1, 0.0, 0.0],
        [1.3, 0.2, 0.0],
        [1.1, 1.3, 0.0],
        [0.0, 0.9, 0.0],
    ];
    let tet = [
        [0.0, 0.0, 0.0],
        [1.2, 0.1, -0.1],
        [0.2, 1.1, 0.1],
        [0.1, 0.3, 0.9],
    ];
    let mut hex = Vec::new();
    for (z, k) in [(0.0, 0.0), (1.0, 1.0)] {
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            hex.push([x + 0.1 * y * k, y + 0.15 * x * z, z + 0.2 * x * y]);
        }
    }
    let coords = match kind {
        CellKind::Tri3 => tri.to_vec(),
        CellKind::Quad4 => quad.to_vec(),
        // one slightly curved edge
        CellKind::Tri6 => with_midsides(&tri, (2, 0.05)),
        CellKind::Quad8 => with_midsides(&quad, (1, 0.06)),
        CellKind::Tet4 => tet.to_vec(),
        CellKind::Hex8 => hex.clone(),
        // one slightly bent edge
        CellKind::Tet10 => with_edge_midsides(&tet, &signorini_mesh::TET10_EDGES, 0.04),
        CellKind::Hex20 => with_edge_midsides(&hex, &signorini_mesh::HEX20_EDGES, 0.05),
    };
    single(kind, coords)
}

fn models_of(kind: CellKind) -> Vec<Model> {
    if kind.dim() == 3 {
        vec![Model::Solid]
    } else {
        vec![Model::PlaneStrain, Model::PlaneStress, Model::Axisymmetric]
    }
}

#[test]
fn element_kernel_is_exactly_the_rigid_modes() {
    for kind in KINDS {
        let m = one_cell(kind);
        for model in models_of(kind) {
            check_mesh(&m, model).unwrap();
            let k = element_stiffness(&m, 0, &mat(model));
            let n = kind.nodes() * model.dim();
            assert_eq!(k.shape(), (n, n));
            assert_eq!(k, k.transpose(), "{kind:?} {model:?}: not symmetric");
            let eig = SymmetricEigen::new(k.clone()).eigenvalues;
            let top = eig.amax();
            assert!(
                top > 0.1 * E && top < 100.0 * E,
                "{kind:?} {model:?}: {top:e}"
            );
            assert!(
                eig.min() > -1e-12 * top,
                "{kind:?} {model:?}: negative eigenvalue"
            );
            let zero = eig.iter().filter(|&&l| l.abs() <= 1e-10 * top).count();
            let modes = rigid_body_modes(&m, model);
            let expect = match model {
                Model::Axisymmetric => 1,
                Model::Solid => 6,
                _ => 3,
            };
            assert_eq!(modes.len(), expect);
            assert_eq!(
                zero,
                expect,
                "{kind:?} {model:?}: rank {} of {n}, eigenvalues {eig}",
                n - zero
            );
            for (r, mode) in modes.iter().enumerate() {
                let v = DVector::from_column_slice(mode);
                let kv = (&k * &v).norm();
                assert!(
                    kv <= 1e-12 * top * v.norm(),
                    "{kind:?} {model:?} mode {r}: {kv:e}"
                );
            }
            // the smallest non-zero eigenvalue is well away from zero
            let mut sorted: Vec<f64> = eig.iter().copied().collect();
            sorted.sort_by(f64::total_cmp);
            assert!(
                sorted[expect] > 1e-4 * top,
                "{kind:?} {model:?}: {:e}",
                sorted[expect]
            );
        }
    }
}

#[test]
fn quadrature_weights_sum_to_the_reference_measure() {
    for kind in KINDS {
        let reference = match kind {
            CellKind::Tri3 | CellKind::Tri6 => 0.5,
            CellKind::Quad4 | CellKind::Quad8 => 4.0,
            CellKind::Tet4 | CellKind::Tet10 => 1.0 / 6.0,
            CellKind::Hex8 | CellKind::Hex20 => 8.0,
        };
        for model in models_of(kind) {
            let w: f64 = quadrature(kind, model).iter().map(|q| q.w).sum();
            assert!((w - reference).abs() < 1e-14, "{kind:?} {model:?}");
            // and the weights times det J sum to the cell's measure
            let m = one_cell(kind);
            let vol: f64 = quadrature(kind, model)
                .iter()
                .map(|q| b_matrix(&m, 0, model, q).unwrap().1)
                .sum();
            assert!(vol > 0.0);
        }
    }
    // the area of a straight-sided T6 and of a parallelogram Q8 are exact
    let t = rect(CellKind::Tri6, [0.0, 0.0], [2.0, 1.0], [1, 1], 0.0);
    let q = rect(CellKind::Quad8, [0.0, 0.0], [2.0, 1.0], [1, 1], 0.0);
    for (m, model) in [(&t, Model::PlaneStrain), (&q, Model::PlaneStress)] {
        let area: f64 = (0..m.cells.len())
            .flat_map(|c| {
                quadrature(m.cells[c].kind, model)
                    .iter()
                    .map(move |qp| b_matrix(m, c, model, qp).unwrap().1)
            })
            .sum();
        assert!((area - 2.0).abs() < 1e-14);
        // axisymmetric volume of the ring [0, 2] × [0, 1]: π r² h = 4π
        let vol: f64 = (0..m.cells.len())
            .flat_map(|c| {
                quadrature(m.cells[c].kind, Model::Axisymmetric)
                    .iter()
                    .map(move |qp| b_matrix(m, c, Model::Axisymmetric, qp).unwrap().1)
            })
            .sum();
        assert!((vol - 4.0 * std::f64::consts::PI).abs() < 1e-13);
    }
}

/// Patch test in the plane models on distorted hand-built meshes of every 2D
/// kind: with `u = u0 + G x` on the boundary, the interior nodes take the
/// same linear field and every cell the uniform stress `D ε`.
#[test]
fn patch_test_every_2d_kind() {
    let gr = [[1.0e-3, -4.0e-4], [2.5e-4, -7.0e-4]];
    let u0 = [3.0e-4, -1.0e-4];
    for kind in KINDS_2D {
        let m = rect(kind, [0.5, -0.25], [2.0, 1.0], [5, 4], 0.25);
        let boundary = boundary_nodes(&m);
        assert!(m.n_nodes() - boundary.len() >= 12, "{kind:?}");
        let exact = linear_2d(&m, u0, gr);
        for model in PLANE {
            let el = mat(model);
            let (u, err, umax) = solve_patch(&m, &el, &exact, &boundary);
            assert!(err <= 1e-10 * umax, "{kind:?} {model:?}: error {err:e}");
            let eps = DVector::from_vec(vec![gr[0][0], gr[1][1], gr[0][1] + gr[1][0]]);
            let s = el.full_stress((el.d_matrix() * eps).as_slice());
            let smax = s.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert_cell_stress(&m, &el, &u, &s, 1e-9 * smax, &format!("{kind:?} {model:?}"));
        }
    }
}

#[test]
fn check_mesh_errors() {
    // model and mesh dimensions
    let m2 = rect(CellKind::Quad4, [0.0, 0.0], [1.0, 1.0], [2, 2], 0.0);
    let err = check_mesh(&m2, Model::Solid).unwrap_err();
    assert!(
        matches!(err, FemError::Unsupported(_)) && err.to_string().contains("3D"),
        "{err}"
    );
    let m3 = super::meshes::boxed(CellKind::Hex8, [1.0; 3], [1, 1, 1], 0.0);
    assert!(matches!(
        check_mesh(&m3, Model::PlaneStrain),
        Err(FemError::Unsupported(_))
    ));
    assert!(check_mesh(&m3, Model::Solid).is_ok());
    // an inverted hexahedron names its cell
    let mut m = super::meshes::boxed(CellKind::Hex8, [1.0; 3], [2, 1, 1], 0.0);
    m.cells[1].nodes.swap(0, 4);
    m.cells[1].nodes.swap(1, 5);
    m.cells[1].nodes.swap(2, 6);
    m.cells[1].nodes.swap(3, 7);
    let err = check_mesh(&m, Model::Solid).unwrap_err();
    assert!(
        matches!(err, FemError::BadJacobian { cell: 1, .. }),
        "{err}"
    );
    assert!(try_element_stiffness(&m, 1, &mat(Model::Solid)).is_err());
    // a tetrahedron of negative volume
    let mut t = super::meshes::boxed(CellKind::Tet4, [1.0; 3], [1, 1, 1], 0.0);
    t.cells[3].nodes.swap(1, 2);
    assert!(matches!(
        check_mesh(&t, Model::Solid),
        Err(FemError::BadJacobian { cell: 3, .. })
    ));
    // a hexahedron folded at one corner only (positive at the Gauss points)
    let mut h = super::meshes::boxed(CellKind::Hex8, [1.0; 3], [1, 1, 1], 0.0);
    h.coords[7] = [0.6, 0.6, 0.4];
    for q in quadrature(CellKind::Hex8, Model::Solid) {
        assert!(b_matrix(&h, 0, Model::Solid, q).is_ok());
    }
    let err = check_mesh(&h, Model::Solid).unwrap_err();
    assert!(
        matches!(err, FemError::BadJacobian { cell: 0, .. }),
        "{err}"
    );
    // axisymmetric: a node at x < 0 is named; round-off on the axis is fine
    let mut a = rect(CellKind::Tri6, [0.0, 0.0], [1.0, 1.0], [2, 2], 0.0);
    assert!(check_mesh(&a, Model::Axisymmetric).is_ok());
    let on_axis = (0..a.n_nodes()).find(|&n| a.coords[n][0] == 0.0).unwrap();
    a.coords[on_axis][0] = -1e-15;
    assert!(check_mesh(&a, Model::Axisymmetric).is_ok());
    assert!(check_mesh(&a, Model::PlaneStrain).is_ok());
    a.coords[on_axis][0] = -1e-3;
    let err = check_mesh(&a, Model::Axisymmetric).unwrap_err();
    assert!(
        matches!(err, FemError::NegativeRadius { node, .. } if node == on_axis),
        "{err}"
    );
    assert!(
        err.to_string().contains(&format!("node {on_axis}")),
        "{err}"
    );
    // the same mesh is fine in plane strain
    assert!(check_mesh(&a, Model::PlaneStrain).is_ok());
    // a cell of the wrong dimension
    let err = try_element_stiffness(&m2, 0, &mat(Model::Solid)).unwrap_err();
    assert!(matches!(err, FemError::Unsupported(_)), "{err}");
}

#[test]
fn von_mises_of_full_stress() {
    let t = 5.0;
    // pure shear in any plane: √3 τ
    for k in 3..6 {
        let mut s = [0.0; 6];
        s[k] = t;
        assert!((von_mises(&s) - 3f64.sqrt() * t).abs() < 1e-12 * t);
    }
    // hydrostatic: 0; uniaxial: |σ|
    assert!(von_mises(&[t, t, t, 0.0, 0.0, 0.0]).abs() < 1e-12 * t);
    for k in 0..3 {
        let mut s = [0.0; 6];
        s[k] = -t;
        assert!((von_mises(&s) - t).abs() < 1e-12 * t);
    }
    // full_stress layouts
    let ps = mat(Model::PlaneStrain).full_stress(&[1.0, 2.0, 3.0]);
    assert_eq!(ps, [1.0, 2.0, 3.0 * NU, 3.0, 0.0, 0.0]);
    let ax = mat(Model::Axisymmetric).full_stress(&[1.0, 2.0, 3.0, 4.0]);
    assert_eq!(ax, [1.0, 2.0, 3.0, 4.0, 0.0, 0.0]);
}

/// The isotropic solid's block kernel (crate::solid_stiffness) is the dense
/// `Σ_g w_g Bᵀ D B` of the same quadrature points, on distorted cells of every
/// 3D kind (round-off apart: 1e-13 of the largest entry).
#[test]
fn solid_block_kernel_is_the_dense_b_d_b_product() {
    for kind in KINDS.into_iter().filter(|k| k.dim() == 3) {
        let m = one_cell(kind);
        let material = mat(Model::Solid);
        let k = element_stiffness(&m, 0, &material);
        let d = material.d_matrix();
        let n = kind.nodes() * 3;
        let mut dense = DMatrix::zeros(n, n);
        for q in quadrature(kind, Model::Solid) {
            let (b, w) = b_matrix(&m, 0, Model::Solid, q).unwrap();
            dense += w * b.transpose() * &d * &b;
        }
        let scale = dense.amax();
        let diff = (&k - &dense).amax();
        assert!(diff <= 1e-13 * scale, "{kind:?}: {diff:e} of {scale:e}");
    }
}
