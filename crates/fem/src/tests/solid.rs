//! 3D solids: patch test, uniaxial compression of a box, assembled kernel.

use super::meshes::{boundary_nodes, boxed};
use super::{
    assert_cell_stress, dense, linear_3d, mat, matvec, norm, solve_dirichlet, solve_patch,
    strain_3d, E, NU,
};
use crate::*;
use signorini_mesh::CellKind;

const SIZE: [f64; 3] = [2.0, 1.0, 1.5];

/// The solid kinds, first and second order.
const SOLIDS: [CellKind; 4] = [
    CellKind::Hex8,
    CellKind::Tet4,
    CellKind::Hex20,
    CellKind::Tet10,
];

/// [`boxed`] in cells of `kind`: Hex20 and Tet10 are the Hex8 and Tet4 box
/// made second-order (straight edges, mid-side nodes at their midpoints).
fn solid_box(kind: CellKind, div: [usize; 3], amp: f64) -> signorini_mesh::Mesh {
    let first = match kind {
        CellKind::Hex20 => CellKind::Hex8,
        CellKind::Tet10 => CellKind::Tet4,
        other => other,
    };
    let m = boxed(first, SIZE, div, amp);
    if kind.order() == 2 {
        signorini_mesh::quadratic3d::to_second_order_3d(&m).unwrap()
    } else {
        m
    }
}

/// `u = u0 + G x` on the boundary of a distorted box of hexahedra or
/// tetrahedra: the interior takes the same linear field, every cell the
/// uniform stress `D ε`.
#[test]
fn patch_test_hex_and_tet() {
    let g = [
        [1.0e-3, -4.0e-4, 2.0e-4],
        [2.5e-4, -7.0e-4, 3.0e-4],
        [-1.5e-4, 5.0e-4, 6.0e-4],
    ];
    let u0 = [3.0e-4, -1.0e-4, 2.0e-4];
    let el = mat(Model::Solid);
    for kind in SOLIDS {
        let m = solid_box(kind, [4, 3, 3], 0.2);
        let boundary = boundary_nodes(&m);
        assert!(m.n_nodes() - boundary.len() >= 6, "{kind:?}");
        let exact = linear_3d(&m, u0, g);
        let (u, err, umax) = solve_patch(&m, &el, &exact, &boundary);
        assert!(err <= 1e-10 * umax, "{kind:?}: error {err:e}");
        // ε = [xx, yy, zz, γxy, γyz, γxz]
        let s = el.d_matrix() * strain_3d(g);
        let smax = s.amax();
        assert_cell_stress(&m, &el, &u, s.as_slice(), 1e-9 * smax, &format!("{kind:?}"));
    }
}

/// A box pressed by `p` on its top `z = c`, on rollers on `z = 0`, `x = 0`,
/// `y = 0`, sides free: `σ_zz = −p` everywhere, the rest zero, `u_z = −p z / E`,
/// lateral expansion `u_x = ν p x / E`, `u_y = ν p y / E`.
#[test]
fn uniaxial_compression_of_a_box() {
    let p = 7.5;
    let el = mat(Model::Solid);
    for kind in SOLIDS {
        let m = solid_box(kind, [3, 2, 4], 0.2);
        let top = m.surface("zmax").unwrap();
        let f = traction_load(&m, top, &[0.0, 0.0, -p], Model::Solid);
        // the load sums to −p × the top area
        let fz: f64 = f.iter().skip(2).step_by(3).sum();
        let area = SIZE[0] * SIZE[1];
        assert!((fz + p * area).abs() <= 1e-13 * p * area, "{kind:?}: {fz}");
        assert!((surface_measure(&m, top, Model::Solid) - area).abs() <= 1e-13 * area);
        let mut fixed = Vec::new();
        for (surface, k) in [("xmin", 0), ("ymin", 1), ("zmin", 2)] {
            for n in m.surface(surface).unwrap().nodes() {
                fixed.push((3 * n + k, 0.0));
            }
        }
        let u = solve_dirichlet(&m, &el, &f, &fixed);
        let scale = p * SIZE[2] / E;
        for (n, x) in m.coords.iter().enumerate() {
            let exact = [NU * p * x[0] / E, NU * p * x[1] / E, -p * x[2] / E];
            for k in 0..3 {
                assert!(
                    (u[3 * n + k] - exact[k]).abs() <= 1e-10 * scale,
                    "{kind:?} node {n} u_{k}: {} vs {}",
                    u[3 * n + k],
                    exact[k]
                );
            }
        }
        for (c, s) in cell_stress(&m, &el, &u).iter().enumerate() {
            for (k, v) in [0.0, 0.0, -p, 0.0, 0.0, 0.0].iter().enumerate() {
                assert!(
                    (s[k] - v).abs() <= 1e-9 * p,
                    "{kind:?} cell {c} [{k}]: {}",
                    s[k]
                );
            }
            assert!((von_mises(s) - p).abs() <= 1e-9 * p);
        }
    }
}

#[test]
fn assembled_3d_stiffness_kernel() {
    for kind in SOLIDS {
        let m = solid_box(kind, [2, 2, 2], 0.2);
        let k = dense(&assemble_stiffness(&m, &mat(Model::Solid)));
        let n = k.nrows();
        assert_eq!(n, 3 * m.n_nodes());
        let mut kf = 0.0;
        let mut asym: f64 = 0.0;
        for i in 0..n {
            for j in 0..n {
                kf += k[(i, j)] * k[(i, j)];
                asym = asym.max((k[(i, j)] - k[(j, i)]).abs());
            }
            assert!(k[(i, i)] > 0.0);
        }
        let kf: f64 = kf.sqrt();
        assert!(asym <= 1e-14 * kf, "{kind:?}: asymmetry {asym:e}");
        let modes = rigid_body_modes(&m, Model::Solid);
        assert_eq!(modes.len(), 6);
        for (r, mode) in modes.iter().enumerate() {
            let kr = norm(&matvec(&k, mode));
            assert!(kr <= 1e-12 * kf * norm(mode), "{kind:?} mode {r}: {kr:e}");
        }
        // rotations are rigid: u = ω × (x − c) has zero strain in every cell
        let s = cell_stress(&m, &mat(Model::Solid), &modes[4]);
        assert!(s.iter().flatten().all(|v| v.abs() <= 1e-9 * E));
    }
}
