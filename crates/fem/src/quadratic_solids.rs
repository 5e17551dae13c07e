//! Second-order solid cells: the shape functions of the quadratic
//! tetrahedron (Tet10) and of the serendipity hexahedron (Hex20) (their
//! quadrature rules: [`crate::quadrature`]; node orders of [`signorini_mesh::CellKind`]: corners,
//! then the mid-sides of [`signorini_mesh::TET10_EDGES`] /
//! [`signorini_mesh::HEX20_EDGES`]).
//!
//! * Tet10 on the reference tetrahedron `(0,0,0), (1,0,0), (0,1,0), (0,0,1)`,
//!   barycentric `L = [1−ξ−η−ζ, ξ, η, ζ]`: corners `N_i = L_i (2 L_i − 1)`,
//!   mid-side of edge i-j `N = 4 L_i L_j`.
//! * Hex20 on `[−1, 1]³` (corners `ξ_a ∈ {−1, 1}³`): corners
//!   `⅛ (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ)(ξ_a ξ + η_a η + ζ_a ζ − 2)`; a
//!   mid-side with `ξ_a = 0`: `¼ (1 − ξ²)(1 + η_a η)(1 + ζ_a ζ)` (and likewise
//!   along η and ζ).

use signorini_mesh::{HEX20_EDGES, HEX8_REFERENCE_CORNERS, TET10_EDGES};

/// Tet10 shape functions and their reference derivatives at `xi`, written
/// into `n[..10]`, `dn[..10]`.
pub(crate) fn tet10(xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    let [x, y, z] = xi;
    let l = [1.0 - x - y - z, x, y, z];
    let dl = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        let f = 4.0 * l[i] - 1.0;
        dn[i] = [f * dl[i][0], f * dl[i][1], f * dl[i][2]];
    }
    for (e, &[i, j]) in TET10_EDGES.iter().enumerate() {
        n[4 + e] = 4.0 * l[i] * l[j];
        for k in 0..3 {
            dn[4 + e][k] = 4.0 * (dl[i][k] * l[j] + l[i] * dl[j][k]);
        }
    }
}

/// Hex20 shape functions and their reference derivatives at `xi`, written
/// into `n[..20]`, `dn[..20]`.
pub(crate) fn hex20(xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    for (a, c) in HEX8_REFERENCE_CORNERS.iter().enumerate() {
        let f = [1.0 + c[0] * xi[0], 1.0 + c[1] * xi[1], 1.0 + c[2] * xi[2]];
        let g = c[0] * xi[0] + c[1] * xi[1] + c[2] * xi[2] - 2.0;
        let prod = f[0] * f[1] * f[2];
        n[a] = 0.125 * prod * g;
        for k in 0..3 {
            let others = prod / f[k];
            // ∂/∂ξ_k of ⅛ f0 f1 f2 g = ⅛ c_k (others g + prod)
            dn[a][k] = 0.125 * c[k] * (others * g + prod);
        }
    }
    for (e, &[i, j]) in HEX20_EDGES.iter().enumerate() {
        let (p, q) = (HEX8_REFERENCE_CORNERS[i], HEX8_REFERENCE_CORNERS[j]);
        // the mid-side's reference point: 0 along the edge's axis
        let m = [
            0.5 * (p[0] + q[0]),
            0.5 * (p[1] + q[1]),
            0.5 * (p[2] + q[2]),
        ];
        let axis = (0..3).find(|&k| m[k] == 0.0).unwrap_or(0);
        let mut f = [0.0; 3];
        let mut df = [0.0; 3];
        for k in 0..3 {
            if k == axis {
                f[k] = 1.0 - xi[k] * xi[k];
                df[k] = -2.0 * xi[k];
            } else {
                f[k] = 1.0 + m[k] * xi[k];
                df[k] = m[k];
            }
        }
        let a = 8 + e;
        n[a] = 0.25 * f[0] * f[1] * f[2];
        dn[a] = [
            0.25 * df[0] * f[1] * f[2],
            0.25 * f[0] * df[1] * f[2],
            0.25 * f[0] * f[1] * df[2],
        ];
    }
}

/// The reference coordinates of the nodes of a Tet10 (corners, then the
/// edge midpoints).
pub fn tet10_reference_nodes() -> [[f64; 3]; 10] {
    let c = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    with_midsides(&c, &TET10_EDGES)
}

/// The reference coordinates of the nodes of a Hex20 (corners, then the
/// edge midpoints).
pub fn hex20_reference_nodes() -> [[f64; 3]; 20] {
    with_midsides(&HEX8_REFERENCE_CORNERS, &HEX20_EDGES)
}

/// The corners `c`, then the midpoint of each edge of `edges`: the `N`
/// reference nodes of a second-order cell.
fn with_midsides<const N: usize>(c: &[[f64; 3]], edges: &[[usize; 2]]) -> [[f64; 3]; N] {
    let mut out = [[0.0; 3]; N];
    out[..c.len()].copy_from_slice(c);
    for (e, &[i, j]) in edges.iter().enumerate() {
        for k in 0..3 {
            out[c.len() + e][k] = 0.5 * (c[i][k] + c[j][k]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kronecker property at the nodes, partition of unity and derivatives
    /// against central differences, at an interior point.
    fn check(nodes: &[[f64; 3]], f: fn([f64; 3], &mut [f64], &mut [[f64; 3]]), inner: [f64; 3]) {
        let m = nodes.len();
        let (mut n, mut dn) = (vec![0.0; m], vec![[0.0; 3]; m]);
        for (a, x) in nodes.iter().enumerate() {
            f(*x, &mut n, &mut dn);
            for (b, v) in n.iter().enumerate() {
                let want = if a == b { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-14, "N_{b} at node {a} = {v}");
            }
        }
        f(inner, &mut n, &mut dn);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        let h = 1e-6;
        for k in 0..3 {
            let (mut p, mut q) = (inner, inner);
            p[k] += h;
            q[k] -= h;
            let (mut np, mut nq, mut d) = (vec![0.0; m], vec![0.0; m], vec![[0.0; 3]; m]);
            f(p, &mut np, &mut d);
            f(q, &mut nq, &mut d);
            for a in 0..m {
                let fd = (np[a] - nq[a]) / (2.0 * h);
                assert!((fd - dn[a][k]).abs() < 1e-8, "dN_{a}/dξ_{k}");
            }
        }
    }

    #[test]
    fn tet10_and_hex20_shape_functions_interpolate_and_differentiate() {
        check(&tet10_reference_nodes(), tet10, [0.2, 0.15, 0.3]);
        check(&hex20_reference_nodes(), hex20, [0.3, -0.4, 0.55]);
    }
}
