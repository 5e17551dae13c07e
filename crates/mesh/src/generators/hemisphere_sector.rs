//! A quarter of the hemisphere ([`quarter_hemisphere`]): the cells of
//! [`hemisphere`](super::hemisphere) on one side of its two symmetry planes
//! through the pole, for a model that uses the symmetry of a load about the
//! pole (a quarter of the unknowns).

use super::{name_boundary, pole_frame, HalfBall};
use crate::{Cell, Mesh, MeshError};
use std::collections::{BTreeMap, BTreeSet};

/// The part of the hemisphere a generator makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HemisphereSector {
    #[default]
    Whole,
    /// [`quarter_hemisphere`].
    Quarter,
}

/// The surfaces of a quarter hemisphere: those of the whole one, then the
/// cut planes `(x − c) · e1 = 0` and `(x − c) · e2 = 0` (the pole's local
/// frame, see [`hemisphere`](super::hemisphere)).
pub const QUARTER_SURFACES: [&str; 4] = ["flat", "dome", "symmetry_1", "symmetry_2"];

/// The Hex8 cells of the hemisphere `hexes` (made by
/// [`hemisphere`](super::hemisphere) about `center` with `pole`) whose
/// centres have `(x − c) · e1 > 0` and `(x − c) · e2 > 0` in the pole's local
/// frame `(e1, e2, e_p)`, the nodes renumbered in their first order. The
/// lattice lines through the pole are cell boundaries and their nodes lie on
/// the planes, so the cut follows the cells' faces. Surfaces: "flat" and
/// "dome" (what is left of them) and the cut planes "symmetry_1"
/// (normal e1) and "symmetry_2" (normal e2); for the default pole
/// `[0, 0, −1]`, e1 = x and e2 = −y: the quarter x ≥ c_x, y ≤ c_y.
pub fn quarter_hemisphere(hexes: &Mesh, ball: &HalfBall<3>) -> Result<Mesh, MeshError> {
    let HalfBall {
        center,
        radius,
        pole,
        ..
    } = *ball;
    let [e1, e2, _] = pole_frame(pole)?;
    let local =
        |x: [f64; 3], e: [f64; 3]| -> f64 { (0..3).map(|k| (x[k] - center[k]) * e[k]).sum() };
    let mut renumber: BTreeMap<usize, usize> = BTreeMap::new();
    let mut coords = Vec::new();
    let mut cells = Vec::new();
    for cell in &hexes.cells {
        let n = cell.nodes.len() as f64;
        let mut centre = [0.0; 3];
        for &v in &cell.nodes {
            (0..3).for_each(|k| centre[k] += hexes.coords[v][k] / n);
        }
        if local(centre, e1) <= 0.0 || local(centre, e2) <= 0.0 {
            continue;
        }
        let nodes = cell
            .nodes
            .iter()
            .map(|&v| {
                *renumber.entry(v).or_insert_with(|| {
                    coords.push(hexes.coords[v]);
                    coords.len() - 1
                })
            })
            .collect();
        cells.push(Cell {
            kind: cell.kind,
            nodes,
        });
    }
    let flat: BTreeSet<usize> = surface_nodes(hexes, "flat", &renumber);
    let mut mesh = Mesh {
        dim: 3,
        coords,
        cells,
        surfaces: BTreeMap::new(),
        regions: Default::default(),
        node_sets: Default::default(),
    };
    let on_plane = |f: &[usize], e: [f64; 3], mesh_coords: &[[f64; 3]]| {
        f.iter()
            .all(|&v| local(mesh_coords[v], e).abs() <= 1e-12 * radius)
    };
    let xs = mesh.coords.clone();
    name_boundary(&mut mesh, &QUARTER_SURFACES, |f| {
        if on_plane(f, e1, &xs) {
            2
        } else if on_plane(f, e2, &xs) {
            3
        } else if f.iter().all(|v| flat.contains(v)) {
            0
        } else {
            1
        }
    })?;
    mesh.check()?;
    Ok(mesh)
}

/// The nodes of surface `name` of `mesh`, renumbered (those kept).
fn surface_nodes(mesh: &Mesh, name: &str, renumber: &BTreeMap<usize, usize>) -> BTreeSet<usize> {
    mesh.surfaces
        .get(name)
        .map(|s| {
            s.nodes()
                .into_iter()
                .filter_map(|v| renumber.get(&v).copied())
                .collect()
        })
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::hemisphere;

    /// A quarter of the hemisphere has a quarter of its cells and of the
    /// facets of its flat face and dome; the nodes of its cut planes lie on
    /// them.
    #[test]
    fn a_quarter_hemisphere_has_a_quarter_of_the_cells_and_its_planes() {
        let (c, r, pole) = ([0.0, 0.0, 1.0], 1.0, [0.0, 0.0, -1.0]);
        let ball = HalfBall::new(c, r, 6, pole, 8.0);
        let whole = hemisphere(&ball).unwrap();
        let q = quarter_hemisphere(&whole, &ball).unwrap();
        assert_eq!(4 * q.cells.len(), whole.cells.len());
        for (name, whole_facets) in [("flat", 4), ("dome", 4)] {
            let n = whole.surface(name).unwrap().facets.len();
            assert_eq!(whole_facets * q.surface(name).unwrap().facets.len(), n);
        }
        for (name, k) in [("symmetry_1", 0), ("symmetry_2", 1)] {
            let s = q.surface(name).unwrap();
            assert!(!s.facets.is_empty());
            for v in s.nodes() {
                assert!(
                    (q.coords[v][k] - c[k]).abs() <= 1e-12 * r,
                    "{name}: node {v}"
                );
            }
        }
        // the quarter x ≥ 0, y ≤ 0 of the default frame (e1 = x, e2 = −y)
        assert!(q.coords.iter().all(|x| x[0] >= -1e-12 && x[1] <= 1e-12));
    }
}
