//! Surface loads, boundary measures and rigid-body modes.
//!
//! Every surface integral is computed on the facet's own parametrisation
//! (course notes §3.1.1: the load is discretised with the same `φ_a` as the
//! displacement): `∫_facet N_a dS ≈ Σ_g w_g N_a(s_g) |∂x/∂s|(s_g) · (2π r(s_g) in
//! axisymmetry)`, with
//!
//! * 2D linear segments `[a, b]`: `N = [(1−s)/2, (1+s)/2]` on `[−1, 1]`, 2-point
//!   Gauss: `L/2` per node, and in axisymmetry the exact
//!   `∫ N_a 2π r ds = 2π L (2 r_a + r_b) / 6` (`r` is linear);
//! * 2D quadratic edges `[corner, corner, mid-side]`: `N = [s(s−1)/2, s(s+1)/2,
//!   1−s²]`, 3-point Gauss: `L/6, L/6, 2L/3` on a straight edge with a centred
//!   mid-side node, exact in axisymmetry too on such an edge;
//! * 3D triangles: linear `N`, the 3-point rule of degree 2: `A/3` per node;
//! * 3D quadrilaterals: bilinear `N` on `[−1, 1]²` with `dS = |∂x/∂ξ × ∂x/∂η| dξ dη`,
//!   2×2 Gauss (exact on a planar face);
//! * 3D quadratic faces of Tet10 and Hex20 cells, Tri6 and Quad8 (the shape
//!   functions of [`crate::isoparametric`] on the face, `dS` from the curved
//!   map): the 6-point rule of degree 4 on the triangle, 3×3 Gauss on the
//!   quadrilateral. On a flat face with centred mid-side nodes the consistent
//!   measures are `0` at the Tri6 corners and `A/3` at its mid-sides, `−A/12`
//!   at the Quad8 corners and `A/3` at its mid-sides: a uniform traction pulls
//!   the corners of a serendipity face the other way.

use crate::isoparametric::shape;
use crate::quadrature::{QuadPoint, GAUSS_2X2, GAUSS_3X3, TRI_3, TRI_6};
use crate::Model;
use signorini_mesh::vec3::{cross, norm, sub};
use signorini_mesh::{CellKind, Facet, Mesh, Surface};

use std::f64::consts::PI;

/// Largest number of nodes of a supported facet.
const MAX_FACET_NODES: usize = 8;

fn check_model(mesh: &Mesh, model: Model, what: &str) {
    assert_eq!(
        mesh.dim,
        model.dim(),
        "{what}: the {} model needs a {}D mesh (the mesh is {}D)",
        model.name(),
        model.dim(),
        mesh.dim
    );
}

/// The consistent nodal measures `∫_facet N_a dS` of one facet in its node
/// order (see the module docs), written into `out`; returns the number of
/// nodes.
///
/// # Panics
/// On a facet that is not a 2- or 3-node segment in 2D, or a 3-, 4-, 6- or
/// 8-node face in 3D.
fn facet_measures(
    mesh: &Mesh,
    facet: &Facet,
    model: Model,
    out: &mut [f64; MAX_FACET_NODES],
) -> usize {
    let nn = facet.nodes.len();
    let x = |a: usize| mesh.coords[facet.nodes[a]];
    *out = [0.0; MAX_FACET_NODES];
    let axi = model == Model::Axisymmetric;
    // one quadrature point: shape values n[..nn], surface density |∂x/∂s| and the radius
    let mut add = |n: &[f64], density: f64, w: f64| {
        let r: f64 = (0..nn).map(|a| n[a] * x(a)[0]).sum();
        let ds = w * density * if axi { 2.0 * PI * r } else { 1.0 };
        for a in 0..nn {
            out[a] += n[a] * ds;
        }
    };
    match (mesh.dim, nn) {
        (2, 2) => {
            let (p, q) = (x(0), x(1));
            let half = 0.5 * (q[0] - p[0]).hypot(q[1] - p[1]);
            const G: f64 = 0.577_350_269_189_625_8; // 1/√3
            for s in [-G, G] {
                add(&[0.5 * (1.0 - s), 0.5 * (1.0 + s)], half, 1.0);
            }
        }
        (2, 3) => {
            const G: f64 = 0.774_596_669_241_483_4; // √(3/5)
            for (s, w) in [(-G, 5.0 / 9.0), (0.0, 8.0 / 9.0), (G, 5.0 / 9.0)] {
                let n = [0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s];
                let dn = [s - 0.5, s + 0.5, -2.0 * s];
                let (mut dx, mut dy) = (0.0, 0.0);
                for (a, d) in dn.iter().enumerate() {
                    dx += d * x(a)[0];
                    dy += d * x(a)[1];
                }
                add(&n, dx.hypot(dy), w);
            }
        }
        (3, 3 | 4 | 6 | 8) => face_points(mesh, facet, |n, a, w| add(n, norm(a), w)),
        (d, n) => {
            panic!(
                "unsupported facet: {n} nodes in a {d}D mesh (2D: 2 or 3 nodes; 3D: 3, 4, 6 or 8)"
            )
        }
    }
    nn
}

/// Visits the quadrature points of a 3D face (3, 4, 6 or 8 nodes; the rules
/// of the module docs) with its shape values there, the area vector
/// `a = ∂x/∂ξ × ∂x/∂η` (`dS = |a| dξ dη`, `n dS = ±a dξ dη` as the face's
/// node order turns) and the weight.
fn face_points(mesh: &Mesh, facet: &Facet, mut visit: impl FnMut(&[f64], [f64; 3], f64)) {
    let nn = facet.nodes.len();
    let x = |a: usize| mesh.coords[facet.nodes[a]];
    match nn {
        3 => {
            let (p0, p1, p2) = (x(0), x(1), x(2));
            let a = cross(sub(p1, p0), sub(p2, p0));
            for q in &TRI_3 {
                let [s, t, _] = q.xi;
                visit(&[1.0 - s - t, s, t], a, q.w);
            }
        }
        4 => {
            const C: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
            for q in &GAUSS_2X2 {
                let [s, t, _] = q.xi;
                let mut n = [0.0; 4];
                let (mut ds, mut dt) = ([0.0; 3], [0.0; 3]);
                for (a, c) in C.iter().enumerate() {
                    n[a] = 0.25 * (1.0 + c[0] * s) * (1.0 + c[1] * t);
                    let (da, db) = (
                        0.25 * c[0] * (1.0 + c[1] * t),
                        0.25 * c[1] * (1.0 + c[0] * s),
                    );
                    for k in 0..3 {
                        ds[k] += da * x(a)[k];
                        dt[k] += db * x(a)[k];
                    }
                }
                visit(&n, cross(ds, dt), q.w);
            }
        }
        _ => {
            let (kind, rule): (CellKind, &[QuadPoint]) = if nn == 6 {
                (CellKind::Tri6, &TRI_6)
            } else {
                (CellKind::Quad8, &GAUSS_3X3)
            };
            for q in rule {
                let s = shape(kind, q.xi);
                let (mut ds, mut dt) = ([0.0; 3], [0.0; 3]);
                for a in 0..nn {
                    for k in 0..3 {
                        ds[k] += s.dn[a][0] * x(a)[k];
                        dt[k] += s.dn[a][1] * x(a)[k];
                    }
                }
                visit(&s.n[..nn], cross(ds, dt), q.w);
            }
        }
    }
}

/// The consistent nodal area vectors `v_a = ∫_surface N_a n dS` of a 3D
/// surface (`n` its outward unit normal, [`Mesh::facet_normal`]'s side),
/// sorted by node index, with the rules of the module docs on each face's
/// own (curved) map: the consistent nodal forces of a unit pressure are
/// `−v_a`. On a flat face `v_a` is `n ∫ N_a dS` ([`tributary_measure`]).
///
/// # Panics
/// On a mesh that is not 3D or a face that is not a 3-, 4-, 6- or 8-node
/// face.
pub fn nodal_area_vectors(mesh: &Mesh, surface: &Surface) -> Vec<(usize, [f64; 3])> {
    assert_eq!(mesh.dim, 3, "nodal_area_vectors: the mesh must be 3D");
    let mut acc = std::collections::BTreeMap::<usize, [f64; 3]>::new();
    for f in &surface.facets {
        let nn = f.nodes.len();
        assert!(
            matches!(nn, 3 | 4 | 6 | 8),
            "unsupported facet: {nn} nodes in a 3D mesh (3, 4, 6 or 8)"
        );
        let mut v = [[0.0; 3]; MAX_FACET_NODES];
        face_points(mesh, f, |n, a, w| {
            for (va, na) in v.iter_mut().zip(n) {
                for k in 0..3 {
                    va[k] += na * a[k] * w;
                }
            }
        });
        let (outward, _) = mesh.facet_normal(f);
        let total: f64 = (0..3)
            .map(|k| v[..nn].iter().map(|va| va[k]).sum::<f64>() * outward[k])
            .sum();
        let sign = if total < 0.0 { -1.0 } else { 1.0 };
        for (&node, va) in f.nodes.iter().zip(&v[..nn]) {
            let e = acc.entry(node).or_insert([0.0; 3]);
            for k in 0..3 {
                e[k] += sign * va[k];
            }
        }
    }
    acc.into_iter().collect()
}

/// Consistent nodal forces `F_a = t ∫_facet N_a dS` of a constant traction
/// `t` (`traction.len() == mesh.dim`) on the facets of `surface` (see the
/// module docs). `t` is a force per unit measure of the real surface: per
/// unit length in the plane models (thickness 1), per unit area in 3D, and in
/// axisymmetry per unit area of the surface of revolution (`[t_r, t_z]`, the
/// nodal forces being totals over the ring: `Σ F = t · 2π ∫ r ds`). Full
/// length `n_dof`, DOF `node * dim + k`. The forces sum to
/// `t · surface_measure(mesh, surface, model)`.
///
/// # Panics
/// If `traction.len() != mesh.dim`, the mesh's dimension is not the model's,
/// or a facet is not supported (see the module docs).
pub fn traction_load(mesh: &Mesh, surface: &Surface, traction: &[f64], model: Model) -> Vec<f64> {
    check_model(mesh, model, "traction_load");
    let dim = mesh.dim;
    assert_eq!(
        traction.len(),
        dim,
        "traction_load: the traction has {} components, the mesh dimension is {dim}",
        traction.len()
    );
    let mut f = vec![0.0; mesh.n_nodes() * dim];
    let mut m = [0.0; MAX_FACET_NODES];
    for facet in &surface.facets {
        let nn = facet_measures(mesh, facet, model, &mut m);
        for (&n, &ma) in facet.nodes.iter().zip(&m[..nn]) {
            for (k, tk) in traction.iter().enumerate() {
                f[n * dim + k] += ma * tk;
            }
        }
    }
    f
}

/// Total measure of a surface: its length in the plane models, its area in
/// 3D, the area `2π ∫ r ds` of the surface of revolution in axisymmetry (a
/// flat disk of radius `R` gives `π R²`).
///
/// # Panics
/// As [`traction_load`].
pub fn surface_measure(mesh: &Mesh, surface: &Surface, model: Model) -> f64 {
    check_model(mesh, model, "surface_measure");
    let mut m = [0.0; MAX_FACET_NODES];
    surface
        .facets
        .iter()
        .map(|f| {
            let nn = facet_measures(mesh, f, model, &mut m);
            m[..nn].iter().sum::<f64>()
        })
        .sum()
}

/// The consistent nodal measure `∫_surface N_a dS` of each node of the
/// surface (with `2π r` in axisymmetry), sorted by node index; sums to
/// [`surface_measure`]. The consistent load of a constant traction is
/// traction × this measure.
///
/// # Panics
/// As [`traction_load`].
pub fn tributary_measure(mesh: &Mesh, surface: &Surface, model: Model) -> Vec<(usize, f64)> {
    check_model(mesh, model, "tributary_measure");
    let mut acc = std::collections::BTreeMap::<usize, f64>::new();
    let mut m = [0.0; MAX_FACET_NODES];
    for f in &surface.facets {
        let nn = facet_measures(mesh, f, model, &mut m);
        for (&n, &ma) in f.nodes.iter().zip(&m[..nn]) {
            *acc.entry(n).or_insert(0.0) += ma;
        }
    }
    acc.into_iter().collect()
}

/// Rigid-body modes (the kernel of an unconstrained `K`), each of length
/// `n_dof`, with `c` the centroid of the nodes:
///
/// * plane strain and plane stress (3): the x- and y-translations and the
///   infinitesimal rotation `u = (−(y − c_y), x − c_x)`;
/// * axisymmetric (1): the axial translation `u_z = 1` (a radial translation
///   or a rotation would strain the ring);
/// * solid (6): the x-, y- and z-translations, then the rotations about the
///   x, y and z axes through `c`, `u = e_k × (x − c)`.
///
/// # Panics
/// If the mesh's dimension is not the model's.
pub fn rigid_body_modes(mesh: &Mesh, model: Model) -> Vec<Vec<f64>> {
    check_model(mesh, model, "rigid_body_modes");
    let n = mesh.n_nodes();
    let dim = mesh.dim;
    let mut c = [0.0; 3];
    for p in &mesh.coords {
        for k in 0..3 {
            c[k] += p[k] / n as f64;
        }
    }
    let translation = |k: usize| {
        let mut t = vec![0.0; dim * n];
        t.iter_mut().skip(k).step_by(dim).for_each(|v| *v = 1.0);
        t
    };
    match model {
        Model::Axisymmetric => vec![translation(1)],
        Model::PlaneStrain | Model::PlaneStress => {
            let mut rz = vec![0.0; 2 * n];
            for (i, p) in mesh.coords.iter().enumerate() {
                rz[2 * i] = -(p[1] - c[1]);
                rz[2 * i + 1] = p[0] - c[0];
            }
            vec![translation(0), translation(1), rz]
        }
        Model::Solid => {
            let mut modes: Vec<Vec<f64>> = (0..3).map(translation).collect();
            for axis in 0..3 {
                let mut e = [0.0; 3];
                e[axis] = 1.0;
                let mut r = vec![0.0; 3 * n];
                for (i, p) in mesh.coords.iter().enumerate() {
                    let u = cross(e, sub(*p, c));
                    r[3 * i..3 * i + 3].copy_from_slice(&u);
                }
                modes.push(r);
            }
            modes
        }
    }
}
