//! The hemisphere in every solid cell kind: the Hex8 mesh of [`hemisphere`],
//! its hexahedra cut into tetrahedra (Tet4, Tet10:
//! [`hexes_to_tetrahedra`]) and made second-order (Tet10, Hex20:
//! [`to_second_order_3d`]), the mid-side nodes of the dome's faces then put
//! on the sphere, so that the quadratic faces follow its curvature.

use super::{hemisphere, quarter_hemisphere, HalfBall, HemisphereSector};
use crate::quadratic3d::{hexes_to_tetrahedra, to_second_order_3d};
use crate::{CellKind, Mesh, MeshError};

/// [`hemisphere`] with cells of `kind` (hex8, tet4, hex20 or tet10), whole
/// or a quarter of it ([`quarter_hemisphere`], cut before the cells are
/// split or made second-order): same corners and surfaces ("flat", "dome",
/// and the quarter's "symmetry_1", "symmetry_2"); Tet4 / Tet10 cut each
/// hexahedron into 12 tetrahedra about its centre. On the dome every
/// mid-side node is moved radially onto the sphere `c + R (x − c) / |x − c|`;
/// the flat face's stay on its plane.
pub fn hemisphere_of_kind(
    ball: &HalfBall<3>,
    kind: CellKind,
    sector: HemisphereSector,
) -> Result<Mesh, MeshError> {
    let whole = hemisphere(ball)?;
    let hexes = match sector {
        HemisphereSector::Whole => whole,
        HemisphereSector::Quarter => quarter_hemisphere(&whole, ball)?,
    };
    let split = |m: Mesh| match kind {
        CellKind::Tet4 | CellKind::Tet10 => hexes_to_tetrahedra(&m),
        _ => Ok(m),
    };
    let mesh = match kind {
        CellKind::Hex8 => return Ok(hexes),
        CellKind::Tet4 => return split(hexes),
        CellKind::Hex20 | CellKind::Tet10 => to_second_order_3d(&split(hexes)?)?,
        other => {
            return Err(MeshError::Invalid(format!(
                "hemisphere: cells must be hex8, tet4, hex20 or tet10, got {}",
                other.name()
            )))
        }
    };
    Ok(onto_sphere(mesh, ball.center, ball.radius))
}

/// Moves the mid-side nodes of the "dome" facets onto the sphere.
fn onto_sphere(mut mesh: Mesh, center: [f64; 3], radius: f64) -> Mesh {
    let mut mids: Vec<usize> = mesh
        .surfaces
        .get("dome")
        .map(|s| {
            s.facets
                .iter()
                .flat_map(|f| {
                    let corners = crate::facet_corners(3, f.nodes.len());
                    f.nodes[corners..].to_vec()
                })
                .collect()
        })
        .unwrap_or_default();
    mids.sort_unstable();
    mids.dedup();
    for v in mids {
        let x = mesh.coords[v];
        let d = [x[0] - center[0], x[1] - center[1], x[2] - center[2]];
        let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if r > 0.0 {
            for k in 0..3 {
                mesh.coords[v][k] = center[k] + radius * d[k] / r;
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_the_hexahedra_volume_and_its_dome_nodes_on_the_sphere() {
        let (c, r) = ([0.0, 0.0, 1.0], 1.0);
        let ball = HalfBall::new(c, r, 4, [0.0, 0.0, -1.0], 2.0);
        let hexes = hemisphere(&ball).unwrap();
        for (kind, cells) in [
            (CellKind::Tet4, 12),
            (CellKind::Hex20, 1),
            (CellKind::Tet10, 12),
        ] {
            let sector = HemisphereSector::Whole;
            let m = hemisphere_of_kind(&ball, kind, sector).unwrap();
            m.check().unwrap();
            assert_eq!(m.cells.len(), cells * hexes.cells.len());
            assert!(m.cells.iter().all(|cell| cell.kind == kind));
            let dome = m.surface("dome").unwrap();
            let per = if kind == CellKind::Hex20 { 1 } else { 2 };
            assert_eq!(
                dome.facets.len(),
                per * hexes.surface("dome").unwrap().facets.len()
            );
            for v in dome.nodes() {
                let x = m.coords[v];
                let d =
                    ((x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2) + (x[2] - c[2]).powi(2)).sqrt();
                assert!((d - r).abs() < 1e-12 * r, "{kind:?}: node {v} at {d}");
            }
            for v in m.surface("flat").unwrap().nodes() {
                assert!((m.coords[v][2] - c[2]).abs() < 1e-12 * r);
            }
            // the surface facets are boundary facets of the new mesh
            let boundary = m.boundary_facets();
            let total: usize = m.surfaces.values().map(|s| s.facets.len()).sum();
            assert_eq!(total, boundary.len());
        }
    }
}
