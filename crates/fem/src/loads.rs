//! Surface loads, boundary measures and rigid-body modes.

use signorini_mesh::{Mesh, Surface};

/// Consistent nodal forces of a constant traction `t` (force per unit length,
/// `traction.len() == mesh.dim`) on the facets of `surface`:
/// `F_a = ∫_facet N_a t ds = t L / 2` for each end node of a linear segment of
/// length `L` (exact). Full length `n_dof`, DOF `node * dim + k`.
///
/// # Panics
/// If `traction.len() != mesh.dim` or the mesh is not 2D.
pub fn traction_load(mesh: &Mesh, surface: &Surface, traction: &[f64]) -> Vec<f64> {
    let dim = mesh.dim;
    assert_eq!(dim, 2, "traction_load: 2D meshes only");
    assert_eq!(
        traction.len(),
        dim,
        "traction_load: the traction has {} components, the mesh dimension is {dim}",
        traction.len()
    );
    let mut f = vec![0.0; mesh.n_nodes() * dim];
    for facet in &surface.facets {
        let l = segment_length(mesh, facet.nodes[0], facet.nodes[1]);
        for &n in &facet.nodes {
            for k in 0..dim {
                f[n * dim + k] += 0.5 * l * traction[k];
            }
        }
    }
    f
}

fn segment_length(mesh: &Mesh, a: usize, b: usize) -> f64 {
    let (p, q) = (mesh.coords[a], mesh.coords[b]);
    (q[0] - p[0]).hypot(q[1] - p[1])
}

/// Total measure of a surface: its length in 2D.
pub fn surface_measure(mesh: &Mesh, surface: &Surface) -> f64 {
    surface
        .facets
        .iter()
        .map(|f| segment_length(mesh, f.nodes[0], f.nodes[1]))
        .sum()
}

/// Tributary length of each surface node: half the lengths of its adjacent
/// facets in the surface (the lumped `∫ N_a ds`), sorted by node index. Sums to
/// [`surface_measure`].
pub fn tributary_measure(mesh: &Mesh, surface: &Surface) -> Vec<(usize, f64)> {
    let mut m = std::collections::BTreeMap::<usize, f64>::new();
    for f in &surface.facets {
        let l = segment_length(mesh, f.nodes[0], f.nodes[1]);
        for &n in &f.nodes {
            *m.entry(n).or_insert(0.0) += 0.5 * l;
        }
    }
    m.into_iter().collect()
}

/// Rigid-body modes (the kernel of an unconstrained `K`), each of length
/// `n_dof`: in 2D the x-translation, the y-translation and the infinitesimal
/// rotation about the centroid `c` of the nodes, `u = (−(y − c_y), x − c_x)`.
///
/// # Panics
/// If the mesh is not 2D.
pub fn rigid_body_modes(mesh: &Mesh) -> Vec<Vec<f64>> {
    assert_eq!(mesh.dim, 2, "rigid_body_modes: 2D meshes only");
    let n = mesh.n_nodes();
    let mut c = [0.0; 2];
    for p in &mesh.coords {
        c[0] += p[0];
        c[1] += p[1];
    }
    if n > 0 {
        c[0] /= n as f64;
        c[1] /= n as f64;
    }
    let mut tx = vec![0.0; 2 * n];
    let mut ty = vec![0.0; 2 * n];
    let mut rz = vec![0.0; 2 * n];
    for (i, p) in mesh.coords.iter().enumerate() {
        tx[2 * i] = 1.0;
        ty[2 * i + 1] = 1.0;
        rz[2 * i] = -(p[1] - c[1]);
        rz[2 * i + 1] = p[0] - c[0];
    }
    vec![tx, ty, rz]
}
