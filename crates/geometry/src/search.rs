//! Closest-facet search on a master surface with an R*-tree (`rstar`) of the
//! facets' bounding boxes.
//!
//! The surface is cut into primitives ("pieces"): a 2D linear edge is one
//! segment; a 2D quadratic edge `[c0, c1, mid]` is two segments c0–mid and
//! mid–c1 (piecewise linear through the mid-side node); a 3D triangle is a
//! triangle; a 3D quadrilateral is a bilinear patch; a quadratic face (Tri6 of
//! a Tet10, Quad8 of a Hex20) is cut through its mid-side nodes, as the 2D
//! quadratic edge is: one triangle at each corner `[c_k, m_k, m_(k−1)]` (`m_k`
//! the mid-side of the side from corner k to k+1) and the inner face of the
//! mid-side nodes (a triangle for Tri6, a quadrilateral for Quad8), so that
//! the master is the piecewise flat surface through all its nodes, with the
//! linear (bilinear) weights of its pieces. Pieces are numbered facet
//! by facet, so for linear 2D edges and linear faces piece k is facet k.
//!
//! The query visits the pieces in increasing distance of their bounding box
//! (a lower bound of the exact distance) and stops at the first box farther
//! than the best exact distance so far: the answer is exactly the one of a
//! loop over all pieces, the piece of least distance with ties going to the
//! lowest piece index (the 2D code's loop kept the first minimum).

use std::collections::HashMap;

use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, RTreeObject, SelectionFunction, AABB};
use signorini_mesh::{Facet, Mesh, Surface};

use crate::closest::{self, Closest};
use crate::error::GeometryError;
use crate::ray;
use signorini_mesh::vec3::{cross, dot, norm, sub, unit};

type Boxed = GeomWithData<Rectangle<[f64; 3]>, usize>;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PieceKind {
    Segment,
    Triangle,
    Quad,
}

/// One primitive of the master surface.
#[derive(Debug, Clone)]
pub(super) struct Piece {
    /// Index of the facet in the surface.
    pub facet: usize,
    pub kind: PieceKind,
    /// Mesh nodes (the first 2, 3 or 4 are used).
    pub nodes: [usize; 4],
    /// Side k lies on the free boundary of the master surface (segments: end
    /// node k belongs to no other edge; faces: side k–k+1 belongs to no other
    /// face). The mid-side node of a quadratic edge is never free.
    pub free: [bool; 4],
}

impl Piece {
    pub fn len(&self) -> usize {
        match self.kind {
            PieceKind::Segment => 2,
            PieceKind::Triangle => 3,
            PieceKind::Quad => 4,
        }
    }
}

/// Result of a closest-point query.
#[derive(Debug, Clone, Copy)]
pub(super) struct Hit {
    pub piece: usize,
    pub closest: Closest,
    /// Some piece at the least distance (ties included) has the query point
    /// beyond one of its free sides: the point lies off the master surface.
    pub off_surface: bool,
}

/// The master surface's pieces and their R*-tree.
pub(super) struct MasterIndex<'a> {
    pub mesh: &'a Mesh,
    pub surface: &'a Surface,
    pub pieces: Vec<Piece>,
    tree: RTree<Boxed>,
    /// Diameter of the pieces' bounding box.
    scale: f64,
}

/// Whether a mesh is 3D (anything else is taken as 2D, z = 0).
pub(super) fn is_3d(mesh: &Mesh) -> bool {
    mesh.dim == 3
}

impl<'a> MasterIndex<'a> {
    pub fn new(mesh: &'a Mesh, surface: &'a Surface) -> Result<Self, GeometryError> {
        let three_d = is_3d(mesh);
        for (k, f) in surface.facets.iter().enumerate() {
            let ok = if three_d {
                matches!(f.nodes.len(), 3 | 4 | 6 | 8)
            } else {
                matches!(f.nodes.len(), 2 | 3)
            };
            if !ok || f.nodes.iter().any(|&v| v >= mesh.n_nodes()) {
                return Err(GeometryError(format!(
                    "master facet {k} has nodes {:?}: expected {} nodes of the mesh",
                    f.nodes,
                    if three_d {
                        "3 (triangle), 4 (quadrilateral), 6 (tri6) or 8 (quad8)"
                    } else {
                        "2 (edge) or 3 (quadratic edge)"
                    }
                )));
            }
        }
        let pieces = if three_d {
            face_pieces(surface)
        } else {
            edge_pieces(surface)
        };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let boxes: Vec<Boxed> = pieces
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mut a = [f64::INFINITY; 3];
                let mut b = [f64::NEG_INFINITY; 3];
                for &v in &p.nodes[..p.len()] {
                    let x = mesh.coords[v];
                    for d in 0..3 {
                        a[d] = a[d].min(x[d]);
                        b[d] = b[d].max(x[d]);
                        lo[d] = lo[d].min(x[d]);
                        hi[d] = hi[d].max(x[d]);
                    }
                }
                GeomWithData::new(Rectangle::from_corners(a, b), i)
            })
            .collect();
        let scale = if pieces.is_empty() {
            0.0
        } else {
            norm(sub(hi, lo))
        };
        Ok(MasterIndex {
            mesh,
            surface,
            pieces,
            tree: RTree::bulk_load(boxes),
            scale,
        })
    }

    /// Whether the surface is made of linear 2D edges only (the historical
    /// 2D case, whose results are kept bit-for-bit).
    pub fn is_linear_2d(&self) -> bool {
        !is_3d(self.mesh) && self.surface.facets.iter().all(|f| f.nodes.len() == 2)
    }

    /// Closest point of piece `i` to x.
    pub fn project(&self, i: usize, x: [f64; 3]) -> Closest {
        let p = &self.pieces[i];
        let c = |k: usize| self.mesh.coords[p.nodes[k]];
        match p.kind {
            PieceKind::Segment => closest::segment(x, c(0), c(1)),
            PieceKind::Triangle => closest::triangle(x, c(0), c(1), c(2)),
            PieceKind::Quad => closest::quad(x, &[c(0), c(1), c(2), c(3)]),
        }
    }

    fn off_surface(&self, i: usize, c: &Closest) -> bool {
        let p = &self.pieces[i];
        (0..p.len()).any(|k| c.beyond[k] && p.free[k])
    }

    /// Ties: distances within this of the least one.
    fn tie_tol(&self, d: f64) -> f64 {
        1e-9 * d + 1e-12 * self.scale
    }

    /// Closest piece to x (`None` if the surface has no facet).
    pub fn closest(&self, x: [f64; 3]) -> Option<Hit> {
        self.closest_counting(x).0
    }

    /// [`Self::closest`] and the number of pieces it projected on.
    pub fn closest_counting(&self, x: [f64; 3]) -> (Option<Hit>, usize) {
        let mut best: Option<(usize, Closest)> = None;
        let mut seen: Vec<(f64, bool)> = Vec::new();
        for (obj, lb2) in self.tree.nearest_neighbor_iter_with_distance_2(x) {
            if let Some((_, b)) = &best {
                if lb2.sqrt() > b.dist + self.tie_tol(b.dist) {
                    break;
                }
            }
            let i = obj.data;
            let c = self.project(i, x);
            seen.push((c.dist, self.off_surface(i, &c)));
            if best.is_none_or(|(bi, b)| c.dist < b.dist || (c.dist == b.dist && i < bi)) {
                best = Some((i, c));
            }
        }
        let Some((piece, closest)) = best else {
            return (None, 0);
        };
        let lim = closest.dist + self.tie_tol(closest.dist);
        let off_surface = seen.iter().any(|&(d, off)| off && d <= lim);
        (
            Some(Hit {
                piece,
                closest,
                off_surface,
            }),
            seen.len(),
        )
    }

    /// Where the line x − g n (n unit, from master to slave) meets a piece
    /// whose outward normal there faces the slave (n_master · n > 0), with
    /// |g| ≤ `reach`: the meeting of least |g| (ties to the lowest piece),
    /// and g, which is the initial gap along n. `None` if the line meets no
    /// facing piece within `reach` (see [`ray`] for "meets").
    pub fn along(&self, x: [f64; 3], n: [f64; 3], reach: f64) -> Option<(Hit, f64)> {
        let span = AlongSegment {
            from: [
                x[0] - reach * n[0],
                x[1] - reach * n[1],
                x[2] - reach * n[2],
            ],
            to: [
                x[0] + reach * n[0],
                x[1] + reach * n[1],
                x[2] + reach * n[2],
            ],
            pad: 1e-6 * self.scale,
        };
        let mut best: Option<(Hit, f64)> = None;
        for obj in self.tree.locate_with_selection_function(span) {
            let i = obj.data;
            let Some((closest, g)) = self.meet(i, x, n) else {
                continue;
            };
            let hit = Hit {
                piece: i,
                closest,
                off_surface: false,
            };
            if g.abs() > reach || dot(self.normal(&hit), n) <= 0.0 {
                continue;
            }
            if best
                .as_ref()
                .is_none_or(|(b, bg)| g.abs() < bg.abs() || (g.abs() == bg.abs() && i < b.piece))
            {
                best = Some((hit, g));
            }
        }
        best
    }

    /// The facets (their indices in the surface, increasing) of the pieces
    /// whose bounding boxes, padded by `pad`, the segment `from`–`to`
    /// crosses: the candidate master faces of a slave face in mortar's 3D
    /// overlap search (`crate::mortar3d`).
    pub fn crossed(&self, from: [f64; 3], to: [f64; 3], pad: f64) -> Vec<usize> {
        let span = AlongSegment { from, to, pad };
        let mut out: Vec<usize> = self
            .tree
            .locate_with_selection_function(span)
            .map(|obj| self.pieces[obj.data].facet)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Where the line x − g n meets piece `i`.
    fn meet(&self, i: usize, x: [f64; 3], n: [f64; 3]) -> Option<(Closest, f64)> {
        let p = &self.pieces[i];
        let c = |k: usize| self.mesh.coords[p.nodes[k]];
        match p.kind {
            PieceKind::Segment => ray::segment(x, n, c(0), c(1)),
            PieceKind::Triangle => ray::triangle(x, n, c(0), c(1), c(2)),
            PieceKind::Quad => ray::quad(x, n, &[c(0), c(1), c(2), c(3)]),
        }
    }

    /// The same answer by a loop over all pieces (tests and checks).
    #[cfg(test)]
    pub fn closest_brute_force(&self, x: [f64; 3]) -> Option<(usize, Closest)> {
        let mut best: Option<(usize, Closest)> = None;
        for i in 0..self.pieces.len() {
            let c = self.project(i, x);
            if best.is_none_or(|(_, b)| c.dist < b.dist) {
                best = Some((i, c));
            }
        }
        best
    }

    /// Outward unit normal of the master at a hit: the facet's normal (2D
    /// linear edge, 3D triangle), the sub-segment's (quadratic edge), the
    /// bilinear patch's ∂x/∂ξ × ∂x/∂η at the point (quadrilateral), oriented
    /// as the facet's outward normal.
    pub fn normal(&self, hit: &Hit) -> [f64; 3] {
        let p = &self.pieces[hit.piece];
        let f = &self.surface.facets[p.facet];
        if !is_3d(self.mesh) {
            let (n2, _) = self.mesh.facet_normal_2d(f);
            let n_facet = [n2[0], n2[1], 0.0];
            if f.nodes.len() == 2 {
                return n_facet;
            }
            return segment_normal(self.mesh, p.nodes[0], p.nodes[1], n_facet)
                .map_or(n_facet, |(n, _)| n);
        }
        let (n_facet, _) = self.mesh.facet_normal(f);
        if matches!(f.nodes.len(), 6 | 8) {
            // a piece of a quadratic face: its own normal, outward as the face
            let c = |k: usize| self.mesh.coords[p.nodes[k]];
            let own = if p.kind == PieceKind::Triangle {
                unit(cross(sub(c(1), c(0)), sub(c(2), c(0))))
            } else {
                closest::quad_normal(&[c(0), c(1), c(2), c(3)], hit.closest.xi_eta)
            };
            if let Some(n) = own {
                return if dot(n, n_facet) < 0.0 {
                    [-n[0], -n[1], -n[2]]
                } else {
                    n
                };
            }
            return n_facet;
        }
        if p.kind == PieceKind::Quad {
            let c = |k: usize| self.mesh.coords[p.nodes[k]];
            if let Some(n) = closest::quad_normal(&[c(0), c(1), c(2), c(3)], hit.closest.xi_eta) {
                return if dot(n, n_facet) < 0.0 {
                    [-n[0], -n[1], -n[2]]
                } else {
                    n
                };
            }
        }
        n_facet
    }
}

/// R*-tree selection of the boxes (padded by `pad`) that the segment
/// `from`–`to` crosses (slab test).
struct AlongSegment {
    from: [f64; 3],
    to: [f64; 3],
    pad: f64,
}

impl AlongSegment {
    fn crosses(&self, env: &AABB<[f64; 3]>) -> bool {
        let (lo, hi) = (env.lower(), env.upper());
        let (mut s0, mut s1) = (0.0f64, 1.0f64);
        for k in 0..3 {
            let (l, h) = (lo[k] - self.pad, hi[k] + self.pad);
            let (a, d) = (self.from[k], self.to[k] - self.from[k]);
            if d == 0.0 {
                if a < l || a > h {
                    return false;
                }
                continue;
            }
            let (t0, t1) = ((l - a) / d, (h - a) / d);
            s0 = s0.max(t0.min(t1));
            s1 = s1.min(t0.max(t1));
            if s0 > s1 {
                return false;
            }
        }
        true
    }
}

impl SelectionFunction<Boxed> for AlongSegment {
    fn should_unpack_parent(&self, envelope: &AABB<[f64; 3]>) -> bool {
        self.crosses(envelope)
    }

    fn should_unpack_leaf(&self, leaf: &Boxed) -> bool {
        self.crosses(&leaf.envelope())
    }
}

/// Unit normal and length of the 2D segment a–b, oriented like `outward`.
pub(super) fn segment_normal(
    mesh: &Mesh,
    a: usize,
    b: usize,
    outward: [f64; 3],
) -> Option<([f64; 3], f64)> {
    let (pa, pb) = (mesh.coords[a], mesh.coords[b]);
    let (dx, dy) = (pb[0] - pa[0], pb[1] - pa[1]);
    let len = (dx * dx + dy * dy).sqrt();
    let n = unit([dy, -dx, 0.0])?;
    Some((
        if dot(n, outward) < 0.0 {
            [-n[0], -n[1], 0.0]
        } else {
            n
        },
        len,
    ))
}

/// 2D pieces: one segment per linear edge, two per quadratic edge.
fn edge_pieces(surface: &Surface) -> Vec<Piece> {
    let mut count: HashMap<usize, usize> = HashMap::new();
    for f in &surface.facets {
        for &v in &f.nodes[..2] {
            *count.entry(v).or_insert(0) += 1;
        }
    }
    let free = |v: usize| count[&v] == 1;
    let mut out = Vec::new();
    for (k, f) in surface.facets.iter().enumerate() {
        let seg = |a: usize, b: usize, fa: bool, fb: bool| Piece {
            facet: k,
            kind: PieceKind::Segment,
            nodes: [a, b, 0, 0],
            free: [fa, fb, false, false],
        };
        let (c0, c1) = (f.nodes[0], f.nodes[1]);
        if let Some(&mid) = f.nodes.get(2) {
            out.push(seg(c0, mid, free(c0), false));
            out.push(seg(mid, c1, false, free(c1)));
        } else {
            out.push(seg(c0, c1, free(c0), free(c1)));
        }
    }
    out
}

/// The sides of a face, corner k to corner k+1, as sorted node pairs.
fn face_sides(f: &Facet) -> impl Iterator<Item = (usize, usize)> + '_ {
    let m = signorini_mesh::facet_corners(3, f.nodes.len());
    (0..m).map(move |k| {
        let (a, b) = (f.nodes[k], f.nodes[(k + 1) % m]);
        (a.min(b), a.max(b))
    })
}

/// 3D pieces: one per face.
fn face_pieces(surface: &Surface) -> Vec<Piece> {
    let mut count: HashMap<(usize, usize), usize> = HashMap::new();
    for f in &surface.facets {
        for e in face_sides(f) {
            *count.entry(e).or_insert(0) += 1;
        }
    }
    let mut out = Vec::with_capacity(surface.facets.len());
    for (k, f) in surface.facets.iter().enumerate() {
        let mut free = [false; 4];
        for (s, e) in face_sides(f).enumerate() {
            free[s] = count[&e] == 1;
        }
        let m = signorini_mesh::facet_corners(3, f.nodes.len());
        if f.nodes.len() == m {
            let mut nodes = [0; 4];
            nodes[..m].copy_from_slice(&f.nodes);
            out.push(face_piece(k, m, nodes, free));
            continue;
        }
        out.extend(quadratic_face_pieces(k, f, m, free));
    }
    out
}

/// The triangle (`m` = 3 corners) or quadrilateral piece of facet `facet`
/// on `nodes`, with its `free` sides.
fn face_piece(facet: usize, m: usize, nodes: [usize; 4], free: [bool; 4]) -> Piece {
    let kind = if m == 3 {
        PieceKind::Triangle
    } else {
        PieceKind::Quad
    };
    Piece {
        facet,
        kind,
        nodes,
        free,
    }
}

/// The pieces of a quadratic face `f` (`m` corners, then the mid-side of
/// each side k → k+1) whose sides k are `free`: the corner triangles
/// `[c_k, m_k, m_(k−1)]` (free on the halves of the free sides) and the inner
/// face of the mid-side nodes (never free), all oriented as the face.
pub(super) fn quadratic_face_pieces(k: usize, f: &Facet, m: usize, free: [bool; 4]) -> Vec<Piece> {
    let mid = |s: usize| f.nodes[m + s % m];
    let mut out: Vec<Piece> = (0..m)
        .map(|c| {
            let before = (c + m - 1) % m;
            Piece {
                facet: k,
                kind: PieceKind::Triangle,
                nodes: [f.nodes[c], mid(c), mid(before), 0],
                free: [free[c], false, free[before], false],
            }
        })
        .collect();
    let mut inner = [0; 4];
    for (s, v) in inner.iter_mut().enumerate().take(m) {
        *v = mid(s);
    }
    out.push(face_piece(k, m, inner, [false; 4]));
    out
}

/// Nearest-node search on a node set (node-to-node), with the ties of a loop
/// in the set's order (the first, i.e. lowest position, wins).
pub(super) struct NodeIndex {
    tree: RTree<GeomWithData<[f64; 3], usize>>,
    pts: Vec<[f64; 3]>,
}

impl NodeIndex {
    pub fn new(pts: Vec<[f64; 3]>) -> Self {
        let tree = RTree::bulk_load(
            pts.iter()
                .enumerate()
                .map(|(i, &p)| GeomWithData::new(p, i))
                .collect(),
        );
        NodeIndex { tree, pts }
    }

    /// Position (in the set) of the point nearest to x.
    pub fn nearest(&self, x: [f64; 3]) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (obj, d2) in self.tree.nearest_neighbor_iter_with_distance_2(x) {
            if let Some((_, bd)) = best {
                if d2.sqrt() > bd * (1.0 + 1e-9) + 1e-300 {
                    break;
                }
            }
            let i = obj.data;
            let d = norm(sub(self.pts[i], x));
            if best.is_none_or(|(bi, bd)| d < bd || (d == bd && i < bi)) {
                best = Some((i, d));
            }
        }
        best.map(|(i, _)| i)
    }
}
