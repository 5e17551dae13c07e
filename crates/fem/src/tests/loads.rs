//! Consistent surface loads and measures for every facet kind and model.

use super::meshes::{boxed, rect, single, single_2d};
use crate::*;
use signorini_mesh::{CellKind, Facet, Mesh, Surface};
use std::f64::consts::PI;

fn one_facet(nodes: Vec<usize>) -> Surface {
    Surface {
        facets: vec![Facet { nodes, cell: 0 }],
    }
}

/// The consistent load of the traction `t` on `s` sums, component by
/// component, to `t` times the surface's measure `area` (to 1e-13 `scale`).
fn assert_resultant(m: &Mesh, s: &Surface, t: &[f64], model: Model, (area, scale): (f64, f64)) {
    let f = traction_load(m, s, t, model);
    for (k, tk) in t.iter().enumerate() {
        let total: f64 = f.iter().skip(k).step_by(t.len()).sum();
        assert!(close(total, tk * area, scale));
    }
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-13 * scale
}

#[test]
fn segment_loads_plane_and_axisymmetric() {
    // one Q4 cell [ra, rb] × [0, 1]; its bottom edge nodes 0 (r = ra), 1 (r = rb)
    let (ra, rb) = (0.5, 2.0);
    let l = rb - ra;
    let m = single_2d(
        CellKind::Quad4,
        &[[ra, 0.0], [rb, 0.0], [rb, 1.0], [ra, 1.0]],
    );
    let s = one_facet(vec![0, 1]);
    let t = [0.25, -3.0];
    // plane: L/2 per node
    let f = traction_load(&m, &s, &t, Model::PlaneStress);
    for n in 0..2 {
        assert!(close(f[2 * n + 1], t[1] * l / 2.0, 3.0 * l));
    }
    // axisymmetric: the exact ∫ N_a 2π r ds
    let f = traction_load(&m, &s, &t, Model::Axisymmetric);
    let wa = 2.0 * PI * l * (2.0 * ra + rb) / 6.0;
    let wb = 2.0 * PI * l * (ra + 2.0 * rb) / 6.0;
    assert!(close(f[0], t[0] * wa, 10.0), "{} vs {}", f[0], t[0] * wa);
    assert!(close(f[1], t[1] * wa, 10.0));
    assert!(close(f[2], t[0] * wb, 10.0));
    assert!(close(f[3], t[1] * wb, 10.0));
    let trib = tributary_measure(&m, &s, Model::Axisymmetric);
    assert_eq!(trib.len(), 2);
    assert!(close(trib[0].1, wa, 10.0) && close(trib[1].1, wb, 10.0));
    // an annulus: π (rb² − ra²)
    let area = surface_measure(&m, &s, Model::Axisymmetric);
    assert!(close(area, PI * (rb * rb - ra * ra), 10.0));
    // the lateral surface r = rb, height 1: 2π rb
    let side = one_facet(vec![1, 2]);
    assert!(close(
        surface_measure(&m, &side, Model::Axisymmetric),
        2.0 * PI * rb,
        10.0
    ));
}

#[test]
fn quadratic_edge_loads() {
    // a straight edge from (ra, 0) to (rb, 0) with its mid-side node at the middle
    let (ra, rb) = (0.5, 2.0);
    let (l, rm) = (rb - ra, 0.5 * (ra + rb));
    let m = single_2d(
        CellKind::Tri6,
        &[
            [ra, 0.0],
            [rb, 0.0],
            [ra, 1.0],
            [rm, 0.0],
            [rm, 0.5],
            [ra, 0.5],
        ],
    );
    let s = one_facet(vec![0, 1, 3]);
    // plane: L/6, L/6, 2L/3
    let trib = tributary_measure(&m, &s, Model::PlaneStrain);
    assert_eq!(trib.iter().map(|x| x.0).collect::<Vec<_>>(), vec![0, 1, 3]);
    for (n, w) in [(0, l / 6.0), (1, l / 6.0), (3, 2.0 * l / 3.0)] {
        let got = trib.iter().find(|x| x.0 == n).unwrap().1;
        assert!(close(got, w, l), "node {n}: {got} vs {w}");
    }
    assert!(close(surface_measure(&m, &s, Model::PlaneStrain), l, l));
    // axisymmetric: ∫ N_a 2π r ds exactly, r = rm + s L/2 on s ∈ [−1, 1]
    let exact = [
        (0, PI * l * (rm / 3.0 - l / 6.0)),
        (1, PI * l * (rm / 3.0 + l / 6.0)),
        (3, PI * l * 4.0 * rm / 3.0),
    ];
    let trib = tributary_measure(&m, &s, Model::Axisymmetric);
    for (n, w) in exact {
        let got = trib.iter().find(|x| x.0 == n).unwrap().1;
        assert!(close(got, w, 10.0), "node {n}: {got} vs {w}");
    }
    let area = surface_measure(&m, &s, Model::Axisymmetric);
    assert!(close(area, PI * (rb * rb - ra * ra), 10.0));
    assert_resultant(&m, &s, &[1.0, 2.0], Model::Axisymmetric, (area, 10.0));
}

#[test]
fn face_loads_3d() {
    // a triangle face: A/3 per node
    let m = single(
        CellKind::Tet4,
        vec![
            [0.0, 0.0, 0.0],
            [2.0, 0.3, 0.1],
            [0.4, 1.5, -0.2],
            [0.3, 0.2, 1.0],
        ],
    );
    let s = one_facet(vec![0, 2, 1]);
    let (_, area) = m.facet_normal(&s.facets[0]);
    let trib = tributary_measure(&m, &s, Model::Solid);
    for (_, w) in &trib {
        assert!(close(*w, area / 3.0, area));
    }
    assert!(close(surface_measure(&m, &s, Model::Solid), area, area));
    // a planar, non-rectangular quadrilateral face (a trapezoid in z = 0):
    // ∫ N_a dS sums to the area and its first moments are the centroid's
    let mut h = boxed(CellKind::Hex8, [1.0; 3], [1, 1, 1], 0.0);
    h.coords[1] = [1.5, 0.0, 0.0];
    h.coords[3] = [0.8, 1.0, 0.0];
    let bottom = h.surface("zmin").unwrap().clone();
    let poly = [[0.0, 0.0], [1.5, 0.0], [0.8, 1.0], [0.0, 1.0]];
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..4 {
        let (p, q) = (poly[i], poly[(i + 1) % 4]);
        let c = p[0] * q[1] - q[0] * p[1];
        a2 += c;
        cx += (p[0] + q[0]) * c;
        cy += (p[1] + q[1]) * c;
    }
    let area = 0.5 * a2;
    let (cx, cy) = (cx / (3.0 * a2), cy / (3.0 * a2));
    let trib = tributary_measure(&h, &bottom, Model::Solid);
    assert_eq!(trib.len(), 4);
    let sum: f64 = trib.iter().map(|x| x.1).sum();
    let mx: f64 = trib.iter().map(|&(n, w)| w * h.coords[n][0]).sum();
    let my: f64 = trib.iter().map(|&(n, w)| w * h.coords[n][1]).sum();
    assert!(close(sum, area, 1.0) && close(mx, area * cx, 1.0) && close(my, area * cy, 1.0));
    assert!(close(surface_measure(&h, &bottom, Model::Solid), area, 1.0));
    assert_resultant(&h, &bottom, &[0.5, -1.0, 2.0], Model::Solid, (area, 3.0));
}

/// Every surface of meshes of every kind and model: the consistent load of a
/// constant traction sums to traction × measure, node by node equals
/// traction × tributary measure, and the tributary measures sum to the
/// measure.
#[test]
fn loads_sum_to_traction_times_measure() {
    let mut cases = Vec::new();
    for kind in [
        CellKind::Tri3,
        CellKind::Quad4,
        CellKind::Tri6,
        CellKind::Quad8,
    ] {
        for model in [Model::PlaneStrain, Model::PlaneStress, Model::Axisymmetric] {
            cases.push((rect(kind, [0.0, 0.0], [1.5, 1.0], [3, 2], 0.2), model));
        }
    }
    for kind in [CellKind::Tet4, CellKind::Hex8] {
        cases.push((boxed(kind, [1.5, 1.0, 0.5], [3, 2, 2], 0.2), Model::Solid));
    }
    for (m, model) in &cases {
        let dim = m.dim;
        for (name, s) in &m.surfaces {
            let measure = surface_measure(m, s, *model);
            // (the axisymmetric surface on the axis has zero measure)
            assert!(measure > 0.0 || (*model == Model::Axisymmetric && name == "left"));
            let scale = measure.max(1.0);
            let t: Vec<f64> = (0..dim).map(|k| 1.5 - k as f64).collect();
            let f = traction_load(m, s, &t, *model);
            let trib = tributary_measure(m, s, *model);
            assert_eq!(trib.iter().map(|x| x.0).collect::<Vec<_>>(), s.nodes());
            let total: f64 = trib.iter().map(|x| x.1).sum();
            assert!(close(total, measure, scale), "{name} {model:?}");
            for k in 0..dim {
                let fk: f64 = f.iter().skip(k).step_by(dim).sum();
                assert!(close(fk, t[k] * measure, scale), "{name} {model:?} [{k}]");
                for &(n, w) in &trib {
                    assert!(close(f[n * dim + k], t[k] * w, scale));
                }
            }
        }
    }
}

/// The axisymmetric measure of the flat end of a cylinder of radius R is the
/// disk's area π R², of its side 2π R H, whatever the cell kind.
#[test]
fn axisymmetric_disk_area() {
    let (r, h) = (1.7, 0.6);
    for kind in [
        CellKind::Tri3,
        CellKind::Quad4,
        CellKind::Tri6,
        CellKind::Quad8,
    ] {
        let m = rect(kind, [0.0, 0.0], [r, h], [5, 2], 0.2);
        for end in ["bottom", "top"] {
            let a = surface_measure(&m, m.surface(end).unwrap(), Model::Axisymmetric);
            assert!(
                (a - PI * r * r).abs() <= 1e-13 * r * r,
                "{kind:?} {end}: {a}"
            );
        }
        let side = surface_measure(&m, m.surface("right").unwrap(), Model::Axisymmetric);
        assert!((side - 2.0 * PI * r * h).abs() <= 1e-13 * r * h);
        // the surface on the axis has no area
        let axis = surface_measure(&m, m.surface("left").unwrap(), Model::Axisymmetric);
        assert_eq!(axis, 0.0);
    }
}

/// The consistent measures of a flat quadratic face: 0 at the Tri6
/// corners and A/3 at its mid-sides; −A/12 at the Quad8 corners and A/3 at
/// its mid-sides (the top of a one-cell Tet10 / Hex20 box of 2 × 1).
#[test]
fn quadratic_faces_have_their_consistent_measures() {
    use signorini_mesh::generators::box_mesh;
    for (kind, corner, mid) in [
        (CellKind::Hex20, -1.0 / 12.0, 1.0 / 3.0),
        (CellKind::Tet10, 0.0, 1.0 / 3.0),
    ] {
        let m = box_mesh([0.0; 3], [2.0, 1.0, 1.0], [1, 1, 1], kind, None).unwrap();
        let top = m.surface("zmax").unwrap();
        let area = 2.0;
        assert!((surface_measure(&m, top, Model::Solid) - area).abs() <= 1e-14 * area);
        for f in &top.facets {
            let mut one = top.clone();
            one.facets = vec![f.clone()];
            let a = m.facet_normal(f).1;
            let corners = signorini_mesh::facet_corners(3, f.nodes.len());
            for (n, w) in tributary_measure(&m, &one, Model::Solid) {
                let pos = f.nodes.iter().position(|&v| v == n).unwrap();
                let want = if pos < corners { corner } else { mid } * a;
                assert!(
                    (w - want).abs() <= 1e-14 * a,
                    "{kind:?} node {pos}: {w} vs {want}"
                );
            }
        }
    }
}

/// The nodal area vectors ∫ N_a n dS: on the flat faces of a box, of every
/// 3D kind, the outward normal times the consistent measure ∫ N_a dS; on the
/// top of a Hex20 / Tet10 box bent into the parabolic cylinder
/// z = 1 + x²/4 (which its quadratic faces represent exactly) they sum to
/// ∫ n dS = (−(z(2) − z(0)), 0, 2) = (−1, 0, 2) over [0, 2] × [0, 1].
#[test]
fn nodal_area_vectors_are_the_consistent_measures_along_the_normal() {
    use signorini_mesh::generators::box_mesh;
    use signorini_mesh::vec3::norm;
    for kind in [
        CellKind::Tet4,
        CellKind::Hex8,
        CellKind::Tet10,
        CellKind::Hex20,
    ] {
        let mut m = box_mesh([0.0; 3], [2.0, 1.0, 1.0], [2, 1, 1], kind, None).unwrap();
        for (name, s) in &m.surfaces {
            let n = m.facet_normal(&s.facets[0]).0;
            let trib = tributary_measure(&m, s, Model::Solid);
            let v = nodal_area_vectors(&m, s);
            assert_eq!(trib.iter().map(|x| x.0).collect::<Vec<_>>(), s.nodes());
            for ((a, w), (b, va)) in trib.iter().zip(&v) {
                assert_eq!(a, b);
                for k in 0..3 {
                    assert!((va[k] - n[k] * w).abs() <= 1e-14 * 2.0, "{kind:?} {name}");
                }
            }
        }
        if !matches!(kind, CellKind::Tet10 | CellKind::Hex20) {
            continue;
        }
        for x in &mut m.coords {
            x[2] += x[2] * x[0] * x[0] / 4.0;
        }
        let v = nodal_area_vectors(&m, m.surface("zmax").unwrap());
        let mut total = [0.0; 3];
        for (_, va) in &v {
            for k in 0..3 {
                total[k] += va[k];
            }
        }
        let want = [-1.0, 0.0, 2.0];
        let err = norm([total[0] - want[0], total[1] - want[1], total[2] - want[2]]);
        assert!(err <= 1e-14 * 2.0, "{kind:?}: ∫ n dS = {total:?}");
    }
}
