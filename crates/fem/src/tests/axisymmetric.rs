//! Axisymmetric model (x = r, y = z): patch test, a compressed solid
//! cylinder, and the thick-walled cylinder under internal pressure (Lamé).

use super::meshes::{boundary_nodes, rect};
use super::{
    assert_cell_stress, dense, mat, matvec, norm, solve_dirichlet, solve_patch, tube_errors, E,
    KINDS_2D, NU,
};
use crate::*;
use signorini_mesh::CellKind;
use std::f64::consts::PI;

const AXI: Model = Model::Axisymmetric;

/// The linear fields of an axisymmetric body in equilibrium without body
/// force, `u_r = a r`, `u_z = b z + d` (uniform `σ_rr = σ_θθ`, `σ_zz`), imposed
/// on the boundary of distorted meshes touching the axis and off it, are
/// reproduced inside, with the uniform stress in every cell.
#[test]
fn patch_test_every_kind() {
    let (a, b, d) = (4.0e-4, -7.0e-4, 1.0e-4);
    let el = mat(AXI);
    for kind in KINDS_2D {
        for r0 in [0.0, 0.7] {
            let m = rect(kind, [r0, -0.25], [2.0, 1.0], [5, 4], 0.25);
            let exact: Vec<f64> = m
                .coords
                .iter()
                .flat_map(|p| [a * p[0], b * p[1] + d])
                .collect();
            let (u, err, umax) = solve_patch(&m, &el, &exact, &boundary_nodes(&m));
            assert!(err <= 1e-10 * umax, "{kind:?} r0 = {r0}: error {err:e}");
            // [rr, zz, θθ, rz] = D [a, b, a, 0]
            let s = el.d_matrix() * nalgebra::DVector::from_vec(vec![a, b, a, 0.0]);
            let full = [s[0], s[1], s[2], 0.0, 0.0, 0.0];
            let what = format!("{kind:?} r0 = {r0}");
            assert_cell_stress(&m, &el, &u, &full, 1e-9 * s.amax(), &what);
        }
    }
}

/// A solid cylinder of radius R, height H, on rollers at z = 0, pressed by
/// `p` on its top: `σ_zz = −p`, `σ_rr = σ_θθ = σ_rz = 0`, `u_z = −p z / E`,
/// `u_r = −ν ε_z r = ν p r / E` (nodes on the axis are not constrained: the
/// only rigid motion of an axisymmetric body is the axial translation).
#[test]
fn solid_cylinder_under_axial_stress() {
    let (r, h, p) = (1.5, 2.0, 3.0);
    let el = mat(AXI);
    for kind in KINDS_2D {
        let m = rect(kind, [0.0, 0.0], [r, h], [4, 5], 0.25);
        let top = m.surface("top").unwrap();
        let f = traction_load(&m, top, &[0.0, -p], AXI);
        // the total force on the top disk: −p π R²
        let fz: f64 = f.iter().skip(1).step_by(2).sum();
        assert!(
            (fz + p * PI * r * r).abs() <= 1e-13 * p * r * r,
            "{kind:?}: {fz}"
        );
        let fixed: Vec<(usize, f64)> = m
            .surface("bottom")
            .unwrap()
            .nodes()
            .iter()
            .map(|&n| (2 * n + 1, 0.0))
            .collect();
        let u = solve_dirichlet(&m, &el, &f, &fixed);
        let eps_z = -p / E;
        let scale = p * h / E;
        for (n, x) in m.coords.iter().enumerate() {
            let (ur, uz) = (-NU * eps_z * x[0], eps_z * x[1]);
            assert!(
                (u[2 * n] - ur).abs() <= 1e-10 * scale,
                "{kind:?} node {n}: u_r {}",
                u[2 * n]
            );
            assert!(
                (u[2 * n + 1] - uz).abs() <= 1e-10 * scale,
                "{kind:?} node {n}: u_z"
            );
        }
        for (c, s) in cell_stress(&m, &el, &u).iter().enumerate() {
            // [rr, zz (axial), θθ (hoop), rz, 0, 0]
            for (k, v) in [0.0, -p, 0.0, 0.0, 0.0, 0.0].iter().enumerate() {
                assert!(
                    (s[k] - v).abs() <= 1e-9 * p,
                    "{kind:?} cell {c} [{k}]: {}",
                    s[k]
                );
            }
            assert!((von_mises(s) - p).abs() <= 1e-9 * p);
        }
        // the assembled stiffness has the axial translation, and only it, as rigid mode
        let k = dense(&assemble_stiffness(&m, &el));
        let modes = rigid_body_modes(&m, AXI);
        assert_eq!(modes.len(), 1);
        let kf = (0..k.nrows())
            .flat_map(|i| (0..k.ncols()).map(move |j| (i, j)))
            .map(|(i, j)| k[(i, j)] * k[(i, j)])
            .sum::<f64>()
            .sqrt();
        assert!(norm(&matvec(&k, &modes[0])) <= 1e-12 * kf * norm(&modes[0]));
        // a radial translation is not rigid: it strains the hoop
        let radial: Vec<f64> = (0..2 * m.n_nodes()).map(|d| ((d + 1) % 2) as f64).collect();
        assert!(norm(&matvec(&k, &radial)) > 1e-3 * kf * norm(&radial) / (m.n_nodes() as f64));
    }
}

/// Thick-walled tube `a ≤ r ≤ b` under internal pressure `p`, rollers on its
/// ends (ε_z = 0): the Lamé solution `u_r = A r + B / r` with
/// `A = (1+ν)(1−2ν) p a² / (E (b² − a²))`, `B = (1+ν) p a² b² / (E (b² − a²))`,
/// `σ_θθ = p a² / (b² − a²) (1 + b²/r²)`. The error falls with refinement at the
/// rate of each cell kind.
#[test]
fn thick_walled_cylinder_lame() {
    let (a, b, h, p) = (1.0, 2.0, 0.5, 10.0);
    let big_a = (1.0 + NU) * (1.0 - 2.0 * NU) * p * a * a / (E * (b * b - a * a));
    let big_b = (1.0 + NU) * p * a * a * b * b / (E * (b * b - a * a));
    let ur = |r: f64| big_a * r + big_b / r;
    let hoop = |r: f64| p * a * a / (b * b - a * a) * (1.0 + b * b / (r * r));
    let el = mat(AXI);
    for kind in KINDS_2D {
        let mut errors = Vec::new();
        let mut hoop_errors = Vec::new();
        for nr in [2, 4, 8, 16] {
            // square cells: nr across the wall, nr / 2 along the axis
            let m = rect(kind, [a, 0.0], [b - a, h], [nr, nr / 2], 0.0);
            let inner = m.surface("left").unwrap();
            // pressure on the inner wall pushes it outwards (+r); total force p 2π a h
            let f = traction_load(&m, inner, &[p, 0.0], AXI);
            let fr: f64 = f.iter().step_by(2).sum();
            assert!((fr - p * 2.0 * PI * a * h).abs() <= 1e-12 * p * a * h);
            let mut fixed = Vec::new();
            for s in ["bottom", "top"] {
                for n in m.surface(s).unwrap().nodes() {
                    fixed.push((2 * n + 1, 0.0));
                }
            }
            let u = solve_dirichlet(&m, &el, &f, &fixed);
            let (err, hoop_err) = tube_errors(&m, &el, &u, &ur, &hoop, a);
            errors.push(err);
            hoop_errors.push(hoop_err);
        }
        // observed convergence order of the nodal u_r: 2 for T3 and Q4, 3 for
        // T6, 4 for Q8 (nodal superconvergence on this regular mesh); the
        // last halving must show at least 70 % of 2^order, every halving a
        // factor 2, and the finest mesh a small error
        let (order, finest) = match kind {
            CellKind::Tri3 => (2, 5e-3),
            CellKind::Quad4 => (2, 1e-3),
            CellKind::Tri6 => (3, 3e-5),
            _ => (4, 1e-6),
        };
        let msg = format!("{kind:?}: u_r errors {errors:?}, hoop errors {hoop_errors:?}");
        for w in errors.windows(2) {
            assert!(w[0] / w[1] > 2.0, "{msg}");
        }
        let last = errors[2] / errors[3];
        assert!(last > 0.7 * 2f64.powi(order), "{msg}: last ratio {last}");
        assert!(errors[3] < finest, "{msg}");
        // the hoop stress at the cell centres converges too (order 1 for T3)
        assert!(
            hoop_errors[3] < 0.7 * hoop_errors[2] && hoop_errors[3] < 0.02,
            "{msg}"
        );
    }
}
