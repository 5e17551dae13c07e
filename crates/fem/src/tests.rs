//! Tests of the element, the assembly and the loads against exact solutions.
//! This file: the 2D T3/Q4 tests on generated meshes and the shared helpers;
//! `tests/` holds the tests of every cell kind and model on hand-built meshes.

mod axisymmetric;
mod b_bar;
mod elements;
mod loads;
mod meshes;
mod solid;

use crate::*;
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use signorini_mesh::generators::{half_disk, rectangle, HalfBall, RectSide};
use signorini_mesh::{CellKind, Mesh};

const E: f64 = 210e3;
const NU: f64 = 0.3;

/// The 2D cell kinds.
const KINDS_2D: [CellKind; 4] = [
    CellKind::Tri3,
    CellKind::Quad4,
    CellKind::Tri6,
    CellKind::Quad8,
];

/// Every cell kind.
const KINDS: [CellKind; 8] = [
    CellKind::Tri3,
    CellKind::Quad4,
    CellKind::Tri6,
    CellKind::Quad8,
    CellKind::Tet4,
    CellKind::Hex8,
    CellKind::Tet10,
    CellKind::Hex20,
];

fn mat(model: Model) -> Elasticity {
    Elasticity::new(E, NU, model)
}

/// A rectangle whose interior nodes are moved by up to `amp` of the local
/// element size (deterministic pseudo-random), so no element is a parallelogram.
fn distorted_rectangle(kind: CellKind, amp: f64) -> Mesh {
    let (nx, ny) = (5, 4);
    let (w, h) = (2.0, 1.0);
    let mut m = rectangle(
        [0.5, -0.25],
        [w, h],
        [nx, ny],
        kind,
        Some((RectSide::Bottom, 3.0)),
    )
    .unwrap();
    let boundary: Vec<usize> = m.surfaces.values().flat_map(|s| s.nodes()).collect();
    let mut seed: u64 = 12345;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let hy_min = h * 0.1; // smallest graded row is ~0.12 h
    for n in 0..m.n_nodes() {
        if !boundary.contains(&n) {
            m.coords[n][0] += amp * (w / nx as f64) * rnd();
            m.coords[n][1] += amp * hy_min * rnd();
        }
    }
    m.check().unwrap();
    m
}

/// Solves `K u = f` with `u = g` on the `fixed` DOFs, by sparse Cholesky of the
/// free-free block.
fn solve_dirichlet(mesh: &Mesh, el: &Elasticity, f: &[f64], fixed: &[(usize, f64)]) -> Vec<f64> {
    let n = mesh.n_nodes() * mesh.dim;
    let mut u = vec![0.0; n];
    let mut is_fixed = vec![false; n];
    for &(d, v) in fixed {
        is_fixed[d] = true;
        u[d] = v;
    }
    let mut map = vec![usize::MAX; n];
    let mut nf = 0;
    for d in 0..n {
        if !is_fixed[d] {
            map[d] = nf;
            nf += 1;
        }
    }
    let mut rhs = Mat::<f64>::zeros(nf, 1);
    for d in 0..n {
        if !is_fixed[d] {
            rhs[(map[d], 0)] = f[d];
        }
    }
    let mut tff = Vec::new();
    for t in stiffness_triplets(mesh, el) {
        match (is_fixed[t.row], is_fixed[t.col]) {
            (false, false) => tff.push(Triplet::new(map[t.row], map[t.col], t.val)),
            (false, true) => rhs[(map[t.row], 0)] -= t.val * u[t.col],
            _ => {}
        }
    }
    let kff = SparseColMat::<usize, f64>::try_new_from_triplets(nf, nf, &tff).unwrap();
    let llt = kff.sp_cholesky(Side::Lower).unwrap();
    llt.solve_in_place(rhs.as_mut());
    for d in 0..n {
        if !is_fixed[d] {
            u[d] = rhs[(map[d], 0)];
        }
    }
    u
}

/// The dofs of the `boundary` nodes of a `dim`-dimensional mesh, each fixed
/// at its value in `exact`.
fn fixed_at(dim: usize, boundary: &[usize], exact: &[f64]) -> Vec<(usize, f64)> {
    boundary
        .iter()
        .flat_map(|&n| (0..dim).map(move |k| dim * n + k))
        .map(|d| (d, exact[d]))
        .collect()
}

/// Patch test solve: no load, the `boundary` nodes fixed at `exact`.
/// Returns the solution, max |u − exact| and max |exact|.
fn solve_patch(
    m: &Mesh,
    el: &Elasticity,
    exact: &[f64],
    boundary: &[usize],
) -> (Vec<f64>, f64, f64) {
    let fixed = fixed_at(m.dim, boundary, exact);
    let u = solve_dirichlet(m, el, &vec![0.0; exact.len()], &fixed);
    let umax = exact.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let err = u
        .iter()
        .zip(exact)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    (u, err, umax)
}

/// The field `u = u0 + G x` at every node of a 3D mesh `m`, interleaved.
fn linear_3d(m: &Mesh, u0: [f64; 3], g: [[f64; 3]; 3]) -> Vec<f64> {
    m.coords
        .iter()
        .flat_map(|p| {
            let mut u = u0;
            for (i, ui) in u.iter_mut().enumerate() {
                *ui += (0..3).map(|j| g[i][j] * p[j]).sum::<f64>();
            }
            u
        })
        .collect()
}

/// The engineering strain `[xx, yy, zz, γxy, γyz, γxz]` of the displacement
/// gradient `g`.
fn strain_3d(g: [[f64; 3]; 3]) -> nalgebra::DVector<f64> {
    nalgebra::DVector::from_vec(vec![
        g[0][0],
        g[1][1],
        g[2][2],
        g[0][1] + g[1][0],
        g[1][2] + g[2][1],
        g[0][2] + g[2][0],
    ])
}

/// The plane field `u = u0 + G x` at every node of `m`, interleaved.
fn linear_2d(m: &Mesh, u0: [f64; 2], gr: [[f64; 2]; 2]) -> Vec<f64> {
    m.coords
        .iter()
        .flat_map(|p| {
            [
                u0[0] + gr[0][0] * p[0] + gr[0][1] * p[1],
                u0[1] + gr[1][0] * p[0] + gr[1][1] * p[1],
            ]
        })
        .collect()
}

/// A thick tube's errors against the exact radial displacement `ur(r)` and
/// hoop stress `hoop(r)`: max over the nodes of |u_r − ur| and over the cell
/// centroids of |σ_θθ − hoop|, each over its value at the inner radius `a`.
fn tube_errors(
    m: &Mesh,
    el: &Elasticity,
    u: &[f64],
    ur: &dyn Fn(f64) -> f64,
    hoop: &dyn Fn(f64) -> f64,
    a: f64,
) -> (f64, f64) {
    let e_u = m
        .coords
        .iter()
        .enumerate()
        .map(|(n, x)| (u[2 * n] - ur(x[0])).abs())
        .fold(0.0f64, f64::max)
        / ur(a);
    let e_hoop = cell_stress(m, el, u)
        .iter()
        .enumerate()
        .map(|(c, s)| (s[2] - hoop(m.cell_centroid(c)[0])).abs())
        .fold(0.0f64, f64::max)
        / hoop(a);
    (e_u, e_hoop)
}

/// Asserts that every cell of `m` has the stress `full` (6 components) within
/// `bound`; `what` opens the failure message.
fn assert_cell_stress(m: &Mesh, el: &Elasticity, u: &[f64], full: &[f64], bound: f64, what: &str) {
    for (c, sc) in cell_stress(m, el, u).iter().enumerate() {
        for k in 0..6 {
            assert!(
                (sc[k] - full[k]).abs() <= bound,
                "{what} cell {c} [{k}]: {} vs {}",
                sc[k],
                full[k]
            );
        }
    }
}

fn dense(k: &SparseColMat<usize, f64>) -> Mat<f64> {
    k.to_dense()
}

fn matvec(k: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    (0..k.nrows())
        .map(|i| (0..k.ncols()).map(|j| k[(i, j)] * x[j]).sum())
        .collect()
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

fn test_meshes() -> Vec<(&'static str, Mesh)> {
    let ball = HalfBall::new([0.0, 1.0], 1.0, 16, [0.3, -1.0], 4.0);
    vec![
        ("q4 distorted", distorted_rectangle(CellKind::Quad4, 0.3)),
        ("t3 distorted", distorted_rectangle(CellKind::Tri3, 0.3)),
        ("q4 half disk", half_disk(&ball, CellKind::Quad4).unwrap()),
        ("t3 half disk", half_disk(&ball, CellKind::Tri3).unwrap()),
    ]
}

#[test]
fn d_matrix_and_plane_modulus() {
    let ps = mat(Model::PlaneStrain);
    let d = ps.d_matrix();
    let c = E / ((1.0 + NU) * (1.0 - 2.0 * NU));
    assert!((d[(0, 0)] - c * (1.0 - NU)).abs() < 1e-12 * E);
    assert!((d[(0, 1)] - c * NU).abs() < 1e-12 * E);
    assert!((d[(2, 2)] - E / (2.0 * (1.0 + NU))).abs() < 1e-12 * E);
    // uniaxial stress in plane strain: σ_xx = 0 -> σ_yy / ε_yy = E'
    let ep = d[(1, 1)] - d[(0, 1)] * d[(1, 0)] / d[(0, 0)];
    assert!((ep - ps.plane_modulus()).abs() < 1e-12 * E);
    assert!((ps.plane_modulus() - E / (1.0 - NU * NU)).abs() < 1e-12 * E);
    let pt = mat(Model::PlaneStress);
    let d = pt.d_matrix();
    let ep = d[(1, 1)] - d[(0, 1)] * d[(1, 0)] / d[(0, 0)];
    assert!((ep - E).abs() < 1e-12 * E);
    assert_eq!(pt.plane_modulus(), E);
    assert!(check_material(E, NU).is_ok());
    assert!(check_material(-1.0, NU).is_err());
    assert!(check_material(E, 0.5).is_err());
    assert!(check_material(E, -1.0).is_err());
    assert!(check_material(f64::NAN, 0.2).is_err());
}

#[test]
fn rigid_body_modes_in_kernel_and_symmetry() {
    for (name, m) in test_meshes() {
        for model in [Model::PlaneStrain, Model::PlaneStress] {
            let k = dense(&assemble_stiffness(&m, &mat(model)));
            let n = k.nrows();
            assert_eq!(n, 2 * m.n_nodes());
            let mut kf = 0.0;
            let mut kmax: f64 = 0.0;
            let mut asym: f64 = 0.0;
            for i in 0..n {
                for j in 0..n {
                    kf += k[(i, j)] * k[(i, j)];
                    kmax = kmax.max(k[(i, j)].abs());
                    asym = asym.max((k[(i, j)] - k[(j, i)]).abs());
                }
            }
            let kf = kf.sqrt();
            assert!(asym <= 1e-14 * kmax, "{name}: asymmetry {asym:e}");
            for (r, mode) in rigid_body_modes(&m, model).iter().enumerate() {
                let kr = norm(&matvec(&k, mode));
                assert!(
                    kr <= 1e-12 * kf * norm(mode),
                    "{name}: mode {r}: |K r| = {kr:e}, |K| |r| = {:e}",
                    kf * norm(mode)
                );
            }
            // positive diagonal
            for i in 0..n {
                assert!(k[(i, i)] > 0.0);
            }
        }
    }
}

#[test]
fn element_matrices_exact_values() {
    // unit right triangle, plane stress: K_e = A Bᵀ D B known in closed form
    let m = Mesh {
        dim: 2,
        coords: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        cells: vec![signorini_mesh::Cell {
            kind: CellKind::Tri3,
            nodes: vec![0, 1, 2],
        }],
        surfaces: Default::default(),
        regions: Default::default(),
        node_sets: Default::default(),
    };
    let el = mat(Model::PlaneStress);
    let k = element_stiffness(&m, 0, &el);
    let c = E / (1.0 - NU * NU);
    let g = E / (2.0 * (1.0 + NU));
    // node 1 (1,0): dN/dx = 1, dN/dy = 0 -> K_11xx = A (D_00) = c/2 ; K_11yy = G/2
    assert!((k[(2, 2)] - 0.5 * c).abs() < 1e-12 * E);
    assert!((k[(3, 3)] - 0.5 * g).abs() < 1e-12 * E);
    // node 1 x with node 2 y: A (D_01 dN1/dx dN2/dy + G dN1/dy dN2/dx) = c ν / 2
    assert!((k[(2, 5)] - 0.5 * c * NU).abs() < 1e-12 * E);
    // unit square Q4, plane stress: the classical K_11 = c (1/3 ... ) values:
    // K_xx(1,1) = E/(1-ν²) (1/2 - ν/6) for the unit square
    let q = Mesh {
        dim: 2,
        coords: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        cells: vec![signorini_mesh::Cell {
            kind: CellKind::Quad4,
            nodes: vec![0, 1, 2, 3],
        }],
        surfaces: Default::default(),
        regions: Default::default(),
        node_sets: Default::default(),
    };
    let k = element_stiffness(&q, 0, &el);
    assert!((k[(0, 0)] - c * (0.5 - NU / 6.0)).abs() < 1e-12 * E);
    assert!((k[(0, 1)] - c * (1.0 + NU) / 8.0).abs() < 1e-12 * E);
}

#[test]
fn bad_jacobian_names_the_cell() {
    let mut m = rectangle([0.0, 0.0], [1.0, 1.0], [2, 1], CellKind::Quad4, None).unwrap();
    m.cells[1].nodes.reverse();
    let err = try_assemble_stiffness(&m, &mat(Model::PlaneStrain)).unwrap_err();
    assert!(
        matches!(err, FemError::BadJacobian { cell: 1, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("cell 1"));
    // a non-convex quad is caught at its corners
    let mut m = rectangle([0.0, 0.0], [1.0, 1.0], [1, 1], CellKind::Quad4, None).unwrap();
    m.coords[2] = [0.2, 0.2, 0.0];
    assert!(matches!(
        check_mesh(&m, Model::PlaneStrain),
        Err(FemError::BadJacobian { cell: 0, .. })
    ));
}

#[test]
fn patch_test_uniform_strain() {
    // u = u0 + G x, uniform strain ε = [g00, g11, g01 + g10]
    let gr = [[1.0e-3, -4.0e-4], [2.5e-4, -7.0e-4]];
    let u0 = [3.0e-4, -1.0e-4];
    for (name, m) in test_meshes() {
        for model in [Model::PlaneStrain, Model::PlaneStress] {
            let el = mat(model);
            let exact = linear_2d(&m, u0, gr);
            let boundary: Vec<usize> = m.surfaces.values().flat_map(|s| s.nodes()).collect();
            let interior = m.n_nodes() - {
                let mut b = boundary.clone();
                b.sort_unstable();
                b.dedup();
                b.len()
            };
            assert!(interior >= 4, "{name}: {interior} interior nodes");
            let (u, err, umax) = solve_patch(&m, &el, &exact, &boundary);
            assert!(err <= 1e-10 * umax, "{name} {model:?}: error {err:e}");
            let d = el.d_matrix();
            let eps = nalgebra::DVector::from_vec(vec![gr[0][0], gr[1][1], gr[0][1] + gr[1][0]]);
            let s = d * eps;
            let szz = match model {
                Model::PlaneStrain => NU * (s[0] + s[1]),
                _ => 0.0,
            };
            let smax = s.amax();
            for (c, sc) in cell_stress(&m, &el, &u).iter().enumerate() {
                for (k, v) in [s[0], s[1], szz, s[2], 0.0, 0.0].iter().enumerate() {
                    assert!(
                        (sc[k] - v).abs() <= 1e-10 * smax,
                        "{name} {model:?}: cell {c} component {k}: {} vs {v}",
                        sc[k]
                    );
                }
            }
        }
    }
}

#[test]
fn uniaxial_compression() {
    let p = 7.5;
    let (w, h) = (2.0, 1.0);
    for kind in [CellKind::Quad4, CellKind::Tri3] {
        for model in [Model::PlaneStrain, Model::PlaneStress] {
            let el = mat(model);
            let mut m =
                rectangle([0.0, 0.0], [w, h], [6, 5], kind, Some((RectSide::Top, 4.0))).unwrap();
            // distort interior nodes: a uniform stress field is still exact
            let boundary: Vec<usize> = m.surfaces.values().flat_map(|s| s.nodes()).collect();
            for n in 0..m.n_nodes() {
                if !boundary.contains(&n) {
                    let x = m.coords[n];
                    m.coords[n][0] += 0.04 * (7.0 * x[1]).sin();
                    m.coords[n][1] += 0.01 * (5.0 * x[0]).cos();
                }
            }
            m.check().unwrap();
            let top = m.surface("top").unwrap();
            let f = traction_load(&m, top, &[0.0, -p], model);
            let mut fixed = Vec::new();
            for n in m.surface("bottom").unwrap().nodes() {
                fixed.push((2 * n + 1, 0.0));
            }
            for n in m.surface("left").unwrap().nodes() {
                fixed.push((2 * n, 0.0));
            }
            let u = solve_dirichlet(&m, &el, &f, &fixed);
            let uy_top = -p * h / el.plane_modulus();
            let expect = match model {
                Model::PlaneStrain => -p * h * (1.0 - NU * NU) / E,
                _ => -p * h / E,
            };
            assert!((uy_top - expect).abs() <= 1e-15 * expect.abs());
            for n in top.nodes() {
                assert!(
                    (u[2 * n + 1] - expect).abs() <= 1e-10 * expect.abs(),
                    "{kind:?} {model:?}: top u_y {} vs {expect}",
                    u[2 * n + 1]
                );
            }
            // lateral expansion: ε_xx = ν(1+ν) p / E (plane strain), ν p / E (stress)
            let exx = match model {
                Model::PlaneStrain => NU * (1.0 + NU) * p / E,
                _ => NU * p / E,
            };
            for n in m.surface("right").unwrap().nodes() {
                assert!((u[2 * n] - exx * w).abs() <= 1e-10 * (exx * w));
            }
            for (c, s) in cell_stress(&m, &el, &u).iter().enumerate() {
                assert!((s[1] + p).abs() <= 1e-10 * p, "cell {c}: σ_yy = {}", s[1]);
                assert!(s[0].abs() <= 1e-10 * p && s[3].abs() <= 1e-10 * p);
                let szz = match model {
                    Model::PlaneStrain => -NU * p,
                    _ => 0.0,
                };
                assert!((s[2] - szz).abs() <= 1e-10 * p);
                assert!(s[4] == 0.0 && s[5] == 0.0);
                let vm = von_mises(s);
                let vm_exact = match model {
                    Model::PlaneStrain => p * (1.0 - NU + NU * NU).sqrt(),
                    _ => p,
                };
                assert!((vm - vm_exact).abs() <= 1e-10 * p);
            }
        }
    }
}

#[test]
fn traction_and_tributary_measures() {
    let ball = HalfBall::new([0.0, 0.0], 2.0, 32, [0.0, -1.0], 8.0);
    let m = half_disk(&ball, CellKind::Tri3).unwrap();
    for name in ["arc", "flat"] {
        let s = m.surface(name).unwrap();
        let len = surface_measure(&m, s, Model::PlaneStrain);
        if name == "flat" {
            assert!((len - 4.0).abs() < 1e-12);
        } else {
            // inscribed polygon, slightly shorter than π R
            assert!(len < 2.0 * std::f64::consts::PI && len > 0.999 * 2.0 * std::f64::consts::PI);
        }
        let t = [1.5, -0.25];
        let f = traction_load(&m, s, &t, Model::PlaneStrain);
        let fx: f64 = f.iter().step_by(2).sum();
        let fy: f64 = f.iter().skip(1).step_by(2).sum();
        assert!((fx - t[0] * len).abs() <= 1e-13 * len);
        assert!((fy - t[1] * len).abs() <= 1e-13 * len);
        let trib = tributary_measure(&m, s, Model::PlaneStrain);
        assert_eq!(trib.iter().map(|x| x.0).collect::<Vec<_>>(), s.nodes());
        let total: f64 = trib.iter().map(|x| x.1).sum();
        assert!((total - len).abs() <= 1e-13 * len);
        // the consistent load of a constant traction is traction × tributary length
        for (n, l) in trib {
            assert!((f[2 * n] - t[0] * l).abs() <= 1e-14 * len);
        }
    }
}

/// The element matrices integrated on several threads are added in the
/// cells' order: K is the same to the last bit as on one thread (a mesh of
/// several batches per thread, its last batch short), and of two bad cells
/// in different threads' batches the first in the mesh is named.
#[test]
fn assembly_on_threads_equals_one_thread_bit_for_bit() {
    let m = distorted_rectangle(CellKind::Quad4, 0.1);
    let big = rectangle([0.0, 0.0], [3.0, 1.0], [61, 23], CellKind::Quad4, None).unwrap();
    for mesh in [m, big] {
        let el = mat(Model::PlaneStrain);
        let one = try_assemble_stiffness(&mesh, &el).unwrap();
        for threads in [2, 3] {
            let many = try_assemble_stiffness_par(&mesh, &el, faer::Par::rayon(threads)).unwrap();
            assert_eq!(one.col_ptr(), many.col_ptr());
            assert_eq!(one.row_idx(), many.row_idx());
            let same = (one.val().iter().zip(many.val())).all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "{threads} threads: K differs from one thread's");
        }
    }
    // Cells 100 and 300 fall in the first batches of two threads.
    for (bad, named) in [(vec![300], 300), (vec![300, 100], 100)] {
        let mut m = rectangle([0.0, 0.0], [3.0, 1.0], [61, 23], CellKind::Quad4, None).unwrap();
        for &c in &bad {
            m.cells[c].nodes.reverse();
        }
        let err = try_assemble_stiffness_par(&m, &mat(Model::PlaneStrain), faer::Par::rayon(2));
        assert!(
            matches!(err, Err(FemError::BadJacobian { cell, .. }) if cell == named),
            "bad cells {bad:?}: {err:?}"
        );
    }
}
