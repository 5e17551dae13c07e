//! Contact points of a contact pair (course notes §2.4 and §3.1.2), in 2D and 3D.
//!
//! Each slave node is a contact point (the mid-side nodes of second-order
//! slave edges included). Its normal n (unit, from master to slave) follows
//! the rule of course notes Fig. 3: the master's normal, the slave's (reversed), their
//! average, or the direction joining the two points at rest. Its initial gap
//! is g0 = n · (x_slave − x_master) (course notes eq. 10, j = g0) with x_master the
//! closest point of the master (master and points rules) or the point where
//! the line through x_slave along n meets a master facet facing it (slave and
//! average rules); a node with no such point within the search distance
//! (half the smaller body) is not a contact point, and [`Pairing`] counts it
//! (see [`node_to_segment_pairing`]). The row of B is n·(u_slave − Σ N_i u_i) with
//! N_i the master's shape functions at that point (course notes §3.1.2, Fig. 6:
//! ½(u_A + u_B) at a mid-segment projection); they sum to 1.
//!
//! Master surfaces:
//! - 2D linear edges: segments (the historical 2D code, kept bit-for-bit).
//! - 2D quadratic edges `[c0, c1, mid]`: taken as piecewise linear through
//!   the mid-side node, two straight segments c0–mid and mid–c1; the weights
//!   are the linear ones on the sub-segment that holds the projection (so
//!   nodes c0 and mid, or mid and c1), and the master normal is that
//!   sub-segment's.
//! - 3D triangles: exact closest point on the triangle, linear weights
//!   (barycentric coordinates).
//! - 3D quadrilaterals: bilinear patches; the closest point by Gauss–Newton on
//!   the bilinear map for (ξ, η), clamped to [−1, 1]² by comparing with the
//!   exact closest points on the four (straight) sides; the weights are the
//!   bilinear shape functions at (ξ, η) (see `closest::quad`).
//!
//! - Quadratic 3D faces (Tri6, Quad8): cut through their mid-side nodes into
//!   flat pieces (`search::quadratic_face_pieces`), the weights those of the
//!   piece; the normal the piece's own, or, when the caller gives the
//!   master's nodal normals ([`GivenNormals`]: its consistent ones), those
//!   interpolated with the piece's weights.
//!
//! The closest facet is found with an R*-tree of the facets' bounding boxes
//! (`search::MasterIndex`), exactly (same answer as a loop over all facets).
//!
//! Tangents: in 2D the tangent is the normal turned by −90° and `tangent2` is
//! zero. In 3D (`tangent`, `tangent2`, `normal`) is a right-handed
//! orthonormal frame built from n alone, see [`tangent_frame`].

use std::collections::BTreeMap;

use signorini_mesh::vec3::{cross, dot, norm, sub, unit};
use signorini_mesh::{Mesh, Surface};

use crate::error::GeometryError;
use crate::ray;
use crate::search::{self, is_3d, MasterIndex, NodeIndex};

/// Rule that chooses the contact normal (course notes §2.4, Fig. 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalRule {
    Master,
    Slave,
    Average,
    Points,
}

/// The master side of a contact pair.
pub enum MasterGeometry<'a> {
    /// A deformable body's surface: 2D edges (2 nodes, or 3 for quadratic
    /// edges), 3D triangles or quadrilaterals.
    Surface {
        mesh: &'a Mesh,
        surface: &'a Surface,
    },
    /// A rigid plane (2D: a line) through `point` with unit normal `normal`
    /// pointing towards the slave.
    Plane { point: [f64; 3], normal: [f64; 3] },
    /// A rigid ball (2D: a disc in the xy-plane, the centre's z ignored) of
    /// centre `center` and radius `radius`. The slave is outside it: the
    /// master normal is n = (x − c)/|x − c| and g0 = |x − c| − R (with the
    /// master normal rule).
    Sphere { center: [f64; 3], radius: f64 },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum TermSide {
    Slave,
    Master,
}

/// One term of a row of B: `weight` times n · u(node) of the given side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    pub side: TermSide,
    pub node: usize,
    pub weight: f64,
}

/// One term of a normal row whose direction varies along the row (mortar on
/// curved faces, the normal inside the integral): `coefficient` · u(node).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VectorTerm {
    pub side: TermSide,
    pub node: usize,
    pub coefficient: [f64; 3],
}

/// A contact point: a slave node and the row of B that gives its gap.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPoint {
    pub slave_node: usize,
    pub x: [f64; 3],
    /// Unit normal, from master to slave.
    pub normal: [f64; 3],
    /// Unit tangent. 2D: the normal turned by −90°, (n_y, −n_x, 0). 3D: the
    /// global axis least aligned with n (smallest |n_k|, ties to the lowest
    /// k), projected on the tangent plane and normalised; see
    /// [`tangent_frame`].
    pub tangent: [f64; 3],
    /// Second unit tangent: zero in 2D; in 3D n × `tangent`, so that
    /// (`tangent`, `tangent2`, `normal`) is right-handed and orthonormal.
    pub tangent2: [f64; 3],
    /// Initial gap g0 (negative: initial overlap).
    pub gap0: f64,
    /// g = g0 + Σ_terms weight · n · u(node); the tangential rows
    /// Σ_terms weight · t · u(node).
    pub terms: Vec<Term>,
    /// When not empty, the normal row instead: g = g0 + Σ coefficient ·
    /// u(node) (3D mortar on curved quadratic faces, `crate::mortar3d`).
    pub normal_row: Vec<VectorTerm>,
    /// When not empty, the tangential rows instead, along `tangent` and
    /// `tangent2` at the node and a frame turning with the surface along
    /// the row: Σ coefficient · u(node) (with `normal_row`).
    pub tangent_rows: [Vec<VectorTerm>; 2],
}

impl ContactPoint {
    /// The point of slave node `slave_node` at `x` with the unit normal
    /// `normal` and the master point `x_master` (mortar: the weighted mean
    /// of its master nodes): its tangents in a mesh of dimension 3
    /// (`three_d`) or 2, its initial gap g0 = n · (x − x_master), and its
    /// row `terms`.
    pub(crate) fn new(
        slave_node: usize,
        (x, x_master): ([f64; 3], [f64; 3]),
        normal: [f64; 3],
        terms: Vec<Term>,
        three_d: bool,
    ) -> Self {
        let (tangent, tangent2) = tangents(three_d, normal);
        ContactPoint {
            slave_node,
            x,
            normal,
            tangent,
            tangent2,
            gap0: dot(normal, sub(x, x_master)),
            terms,
            normal_row: Vec::new(),
            tangent_rows: [Vec::new(), Vec::new()],
        }
    }
}

impl Term {
    /// The slave node's term of a row: n · u(node).
    pub(crate) fn slave(node: usize) -> Self {
        Term {
            side: TermSide::Slave,
            node,
            weight: 1.0,
        }
    }

    /// A master node's term: −`weight` n · u(node), `weight` its shape
    /// function at the master point.
    pub(crate) fn master(node: usize, weight: f64) -> Self {
        Term {
            side: TermSide::Master,
            node,
            weight: -weight,
        }
    }
}

/// Tangents of a 3D unit normal n: `t1` is the global axis e_k least aligned
/// with n (smallest |n_k|; ties, up to 10⁻⁹ so that rounding noise in a
/// computed normal cannot flip the choice, go to the lowest k: n ≈ ±e_z gives
/// t1 ≈ e_x, n ≈ ±e_x gives t1 ≈ e_y, n ≈ ±e_y gives t1 ≈ e_x) projected on
/// the tangent plane, t1 = (e_k − n_k n)/|e_k − n_k n| (never degenerate:
/// |n_k| ≤ 1/√3); `t2` = n × t1. (t1, t2, n) is a right-handed orthonormal
/// frame that depends on n only, so friction rows are reproducible. It jumps
/// where two |n_k| swap order (for isotropic friction only the tangent plane
/// matters).
pub fn tangent_frame(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    const TIE: f64 = 1e-9;
    let a = [n[0].abs(), n[1].abs(), n[2].abs()];
    let least = a[0].min(a[1]).min(a[2]);
    let k = (0..3).find(|&k| a[k] <= least + TIE).unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let t1 = unit([e[0] - n[k] * n[0], e[1] - n[k] * n[1], e[2] - n[k] * n[2]]).unwrap_or(e);
    (t1, cross(n, t1))
}

/// The R*-tree of a master surface's facet boxes, for a search other than
/// node-to-face's: mortar's 3D overlap candidates (`crate::mortar3d`).
pub(crate) struct FacetSearch<'a>(MasterIndex<'a>);

impl<'a> FacetSearch<'a> {
    pub fn new(mesh: &'a Mesh, surface: &'a Surface) -> Result<Self, GeometryError> {
        MasterIndex::new(mesh, surface).map(FacetSearch)
    }

    /// The facets (indices in the surface, increasing) whose bounding
    /// boxes, padded by `pad`, the segment `from`–`to` crosses.
    pub fn crossed(&self, from: [f64; 3], to: [f64; 3], pad: f64) -> Vec<usize> {
        self.0.crossed(from, to, pad)
    }
}

/// Where the line x − g n meets the 3D face with `nodes` (a triangle, or a
/// bilinear quadrilateral by Newton's method on its map): the face's shape
/// functions there, in node order and clamped onto the face, and g; `None`
/// when the line misses the face (see `ray`). Mortar's 3D integration maps
/// its points on the auxiliary plane back to the faces with it.
pub(crate) fn meet_face(
    mesh: &Mesh,
    nodes: &[usize],
    x: [f64; 3],
    n: [f64; 3],
) -> Option<([f64; 4], f64)> {
    let c = |k: usize| mesh.coords[nodes[k]];
    let (hit, g) = match nodes.len() {
        3 => ray::triangle(x, n, c(0), c(1), c(2))?,
        4 => ray::quad(x, n, &[c(0), c(1), c(2), c(3)])?,
        _ => return None,
    };
    Some((hit.weights, g))
}

fn tangent_2d(n: [f64; 3]) -> [f64; 3] {
    [n[1], -n[0], 0.0]
}

/// (`tangent`, `tangent2`) of a contact point in a mesh of dimension `dim`.
pub(crate) fn tangents(three_d: bool, n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    if three_d {
        tangent_frame(n)
    } else {
        (tangent_2d(n), [0.0; 3])
    }
}

/// Outward unit normal at each node of a surface: the measure-weighted
/// average of the normals of the facets around it. 2D linear edges: their
/// length-weighted normals. 2D quadratic edges: the normals of their two
/// straight halves c0–mid and mid–c1, each weighted by its length (the
/// mid-side node gets the average of the two). 3D faces: area-weighted face
/// normals ([`Mesh::facet_normal`]; a quadrilateral's from its diagonals).
pub fn nodal_normals(mesh: &Mesh, surface: &Surface) -> Vec<(usize, [f64; 3])> {
    let mut acc: std::collections::BTreeMap<usize, [f64; 3]> = Default::default();
    let three_d = is_3d(mesh);
    for f in &surface.facets {
        if three_d {
            let (n, area) = mesh.facet_normal(f);
            for &v in &f.nodes {
                let e = acc.entry(v).or_insert([0.0; 3]);
                for k in 0..3 {
                    e[k] += n[k] * area;
                }
            }
        } else if f.nodes.len() >= 3 {
            let (n2, _) = mesh.facet_normal_2d(f);
            let outward = [n2[0], n2[1], 0.0];
            let (c0, c1, mid) = (f.nodes[0], f.nodes[1], f.nodes[2]);
            for (a, b) in [(c0, mid), (mid, c1)] {
                let (n, len) =
                    search::segment_normal(mesh, a, b, outward).unwrap_or((outward, 0.0));
                for v in [a, b] {
                    let e = acc.entry(v).or_insert([0.0; 3]);
                    e[0] += n[0] * len;
                    e[1] += n[1] * len;
                }
            }
        } else {
            let (n, len) = mesh.facet_normal_2d(f);
            for &v in &f.nodes {
                let e = acc.entry(v).or_insert([0.0; 3]);
                e[0] += n[0] * len;
                e[1] += n[1] * len;
            }
        }
    }
    acc.into_iter()
        .map(|(v, n)| (v, unit(n).unwrap_or([0.0, 0.0, 0.0])))
        .collect()
}

fn choose_normal(
    rule: NormalRule,
    n_master: [f64; 3],
    n_slave_out: [f64; 3],
    x_slave: [f64; 3],
    x_master: [f64; 3],
    length_scale: f64,
) -> [f64; 3] {
    match rule {
        NormalRule::Master => n_master,
        NormalRule::Slave => [-n_slave_out[0], -n_slave_out[1], -n_slave_out[2]],
        NormalRule::Average => unit(sub(n_master, n_slave_out)).unwrap_or(n_master),
        NormalRule::Points => {
            let d = sub(x_slave, x_master);
            if norm(d) <= 1e-9 * length_scale {
                n_master
            } else {
                let mut n = unit(d).unwrap_or(n_master);
                // An initial overlap reverses x_s − x_m: keep n from master to slave.
                if dot(n, n_master) < 0.0 {
                    n = [-n[0], -n[1], -n[2]];
                }
                n
            }
        }
    }
}

fn check_dims(slave_mesh: &Mesh, master: &MasterGeometry<'_>) -> Result<(), GeometryError> {
    if let MasterGeometry::Surface { mesh, .. } = master {
        if is_3d(mesh) != is_3d(slave_mesh) {
            return Err(GeometryError(format!(
                "the slave mesh is {}D and the master mesh {}D",
                if is_3d(slave_mesh) { 3 } else { 2 },
                if is_3d(mesh) { 3 } else { 2 },
            )));
        }
    }
    if let MasterGeometry::Sphere { radius, .. } = master {
        if !(*radius > 0.0 && radius.is_finite()) {
            return Err(GeometryError(format!(
                "the rigid sphere's radius must be positive and finite, not {radius}"
            )));
        }
    }
    Ok(())
}

/// Fraction of the body size within which a slave node looks for its master
/// point (see [`search_distance`]).
pub const SEARCH_FRACTION: f64 = 0.5;

/// How far from a slave node its master point may be: [`SEARCH_FRACTION`]
/// of the smaller body's size (the diagonal of its bounding box; against a
/// rigid obstacle, the slave body's).
///
/// Why so: the pairing itself is decided by the normal rule (the slave and
/// average rules take the master facet the normal meets, facing the node);
/// the search distance only keeps a node from being paired across the model.
/// A pair half a body apart has no common normal in the sense of course notes §2.4
/// ("le jeu se doit d'être petit", the two normals must be close), and its
/// gap cannot close in a small-perturbation solution. A tighter bound, in
/// element sizes, would be a risk: a node left out is not held at all, and
/// the gaps that close under a load can span many elements (on a graded mesh,
/// about 1.5 of the smallest at the pole of `examples/hertz_axi.toml`; under
/// a large prescribed translation, which linear elasticity allows, many
/// more).
pub fn search_distance(slave_mesh: &Mesh, master: &MasterGeometry<'_>) -> f64 {
    let size = match master {
        MasterGeometry::Surface { mesh, .. } => slave_mesh.size().min(mesh.size()),
        _ => slave_mesh.size(),
    };
    SEARCH_FRACTION * size
}

/// Slave nodes that are not contact points, by reason.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Dropped {
    /// Master and points rules: the node does not face the master (its
    /// projection on the closest facet falls outside it, see
    /// [`node_to_segment_pairing`]).
    pub off_surface: usize,
    /// The closest master point is farther than the search distance.
    pub far: usize,
    /// Slave and average rules: the line along the normal meets no master
    /// facet facing the node within the search distance.
    pub missed: usize,
    /// The search distance used ([`search_distance`]).
    pub search_distance: f64,
}

impl Dropped {
    /// No node dropped yet, within the search distance `reach`.
    pub(crate) fn within(reach: f64) -> Self {
        Dropped {
            search_distance: reach,
            ..Dropped::default()
        }
    }

    pub fn total(&self) -> usize {
        self.off_surface + self.far + self.missed
    }

    /// A note for the report (`None` if no node was dropped), e.g. "3 slave
    /// node(s) have no master point along their normal: ...".
    pub fn note(&self) -> Option<String> {
        if self.total() == 0 {
            return None;
        }
        let mut why = Vec::new();
        if self.off_surface > 0 {
            why.push(format!(
                "{} do not face the master (their projection on the closest master facet falls outside it)",
                self.off_surface
            ));
        }
        if self.far > 0 {
            why.push(format!(
                "{} are farther than the search distance {:.3e} (half the smaller body) from the master",
                self.far, self.search_distance
            ));
        }
        if self.missed > 0 {
            why.push(format!(
                "{} have a normal that meets no master facet facing them within the search distance {:.3e}",
                self.missed, self.search_distance
            ));
        }
        Some(format!(
            "{} slave node(s) are not contact points: {}",
            self.total(),
            why.join("; ")
        ))
    }
}

/// Contact points of a pair and the slave nodes left out.
#[derive(Debug, Clone, PartialEq)]
pub struct Pairing {
    pub points: Vec<ContactPoint>,
    pub dropped: Dropped,
}

/// Why a slave node has no master point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Unpaired {
    OffSurface,
    Far,
    Missed,
}

/// The master point paired with a slave node: where it is, the master's
/// outward unit normal there, and the master terms of the row.
struct MasterPoint {
    x: [f64; 3],
    normal: [f64; 3],
    terms: Vec<Term>,
}

/// The master side of a pair, ready for queries.
enum MasterSide<'a> {
    Plane { point: [f64; 3], normal: [f64; 3] },
    Sphere { center: [f64; 3], radius: f64 },
    Surface(MasterIndex<'a>, Option<BTreeMap<usize, [f64; 3]>>),
}

impl<'a> MasterSide<'a> {
    fn new(
        master: &MasterGeometry<'a>,
        normals: Option<BTreeMap<usize, [f64; 3]>>,
    ) -> Result<Self, GeometryError> {
        Ok(match master {
            MasterGeometry::Plane { point, normal } => MasterSide::Plane {
                point: *point,
                normal: *normal,
            },
            MasterGeometry::Sphere { center, radius } => MasterSide::Sphere {
                center: *center,
                radius: *radius,
            },
            MasterGeometry::Surface { mesh, surface } => {
                let index = MasterIndex::new(mesh, surface)?;
                if index.pieces.is_empty() {
                    return Err(GeometryError("the master surface has no facet".into()));
                }
                MasterSide::Surface(index, normals)
            }
        })
    }

    /// The closest master point to slave node `s` at x, its distance, and
    /// whether it lies off the master surface: clamped to a free side of it
    /// (2D linear edges: the unclamped projection is outside the edge by more
    /// than 10⁻⁶ of its length, the historical rule).
    fn closest(
        &self,
        s: usize,
        x: [f64; 3],
        three_d: bool,
    ) -> Result<(MasterPoint, f64, bool), GeometryError> {
        Ok(match self {
            MasterSide::Plane { point, normal } => {
                let d = dot(sub(x, *point), *normal);
                let xm = [
                    x[0] - d * normal[0],
                    x[1] - d * normal[1],
                    x[2] - d * normal[2],
                ];
                (rigid_point(xm, *normal), d.abs(), false)
            }
            MasterSide::Sphere { center, radius } => {
                let c = [center[0], center[1], if three_d { center[2] } else { x[2] }];
                let Some(n_m) = unit(sub(x, c)) else {
                    return Err(GeometryError(format!(
                        "slave node {s} is at the centre of the rigid sphere: its normal is undefined"
                    )));
                };
                let xm = [
                    c[0] + radius * n_m[0],
                    c[1] + radius * n_m[1],
                    c[2] + radius * n_m[2],
                ];
                (rigid_point(xm, n_m), norm(sub(x, xm)), false)
            }
            MasterSide::Surface(index, normals) => {
                let hit = index.closest(x).expect("the surface has facets");
                let c = &hit.closest;
                let off = if index.is_linear_2d() {
                    c.xi_raw < -1e-6 || c.xi_raw > 1.0 + 1e-6
                } else {
                    hit.off_surface
                };
                (surface_point(index, &hit, normals.as_ref()), c.dist, off)
            }
        })
    }

    /// Where the line x − g n meets the master, facing the slave (n_master ·
    /// n > 0), with |g| ≤ `reach` (the meeting of least |g|).
    fn along(&self, x: [f64; 3], n: [f64; 3], reach: f64, three_d: bool) -> Option<MasterPoint> {
        match self {
            MasterSide::Plane { point, normal } => {
                let cos = dot(n, *normal);
                if cos <= 0.0 {
                    return None;
                }
                let g = dot(sub(x, *point), *normal) / cos;
                (g.abs() <= reach).then(|| {
                    rigid_point([x[0] - g * n[0], x[1] - g * n[1], x[2] - g * n[2]], *normal)
                })
            }
            MasterSide::Sphere { center, radius } => {
                let c = [center[0], center[1], if three_d { center[2] } else { x[2] }];
                // |x − g n − c| = R: g² − 2 b g + |x − c|² − R² = 0; the root
                // b − √disc is where the line enters the ball, facing x.
                let xc = sub(x, c);
                let b = dot(n, xc);
                let disc = b * b - (dot(xc, xc) - radius * radius);
                if disc.is_nan() || disc < 0.0 {
                    return None;
                }
                let g = b - disc.sqrt();
                let xm = [x[0] - g * n[0], x[1] - g * n[1], x[2] - g * n[2]];
                let n_m = unit(sub(xm, c))?;
                (g.abs() <= reach && dot(n_m, n) > 0.0).then(|| rigid_point(xm, n_m))
            }
            MasterSide::Surface(index, normals) => {
                let (hit, _) = index.along(x, n, reach)?;
                Some(surface_point(index, &hit, normals.as_ref()))
            }
        }
    }
}

fn rigid_point(x: [f64; 3], normal: [f64; 3]) -> MasterPoint {
    MasterPoint {
        x,
        normal,
        terms: Vec::new(),
    }
}

/// The master point of a hit on a surface: the master's shape functions
/// there (zero weights left out) and its normal: the piece's own, or the
/// given nodal `normals` interpolated with those weights and normalised.
fn surface_point(
    index: &MasterIndex<'_>,
    hit: &search::Hit,
    normals: Option<&BTreeMap<usize, [f64; 3]>>,
) -> MasterPoint {
    let piece = &index.pieces[hit.piece];
    let at = || piece.nodes[..piece.len()].iter().zip(&hit.closest.weights);
    let terms = at()
        .filter(|&(_, &w)| w != 0.0)
        .map(|(&node, &w)| Term::master(node, w))
        .collect();
    let interpolated = normals.and_then(|normals| {
        let mut n = [0.0; 3];
        for (node, &w) in at() {
            let nn = normals.get(node)?;
            for k in 0..3 {
                n[k] += w * nn[k];
            }
        }
        unit(n)
    });
    MasterPoint {
        x: hit.closest.x,
        normal: interpolated.unwrap_or_else(|| index.normal(hit)),
        terms,
    }
}

/// The contact normal and the master point of slave node `s` at x (outward
/// normal `n_s`) by the rule (course notes §2.4, Fig. 3):
/// - master: the closest master point and the master's normal there;
/// - points: the closest master point, n along the two points;
/// - slave: n = −n_s, the master point where the line x − g n meets the
///   master (see [`MasterSide::along`]);
/// - average: n = (n_m − n_s)/|n_m − n_s| with n_m the master's normal where
///   the line along n meets the master: a fixed point, from n_m at the
///   closest point, on at most 4 meetings (on a faceted master it settles on
///   one facet, except at a kink the line keeps crossing, where the last
///   facet's normal is kept).
///
/// Every rule first asks the closest master point to lie within `reach`
/// (a meeting along a line is never closer).
fn pair(
    side: &MasterSide<'_>,
    rule: NormalRule,
    (s, x, n_s): (usize, [f64; 3], [f64; 3]),
    reach: f64,
    (three_d, scale): (bool, f64),
) -> Result<Result<([f64; 3], MasterPoint), Unpaired>, GeometryError> {
    let (near, dist, off) = side.closest(s, x, three_d)?;
    if dist > reach {
        return Ok(Err(Unpaired::Far));
    }
    // Slave and average: the line along the normal decides instead.
    if off && matches!(rule, NormalRule::Master | NormalRule::Points) {
        return Ok(Err(Unpaired::OffSurface));
    }
    let paired = match rule {
        NormalRule::Master | NormalRule::Points => {
            let n = choose_normal(rule, near.normal, n_s, x, near.x, scale);
            Some((n, near))
        }
        NormalRule::Slave => unit(n_s).and_then(|out| {
            let n = [-out[0], -out[1], -out[2]];
            side.along(x, n, reach, three_d).map(|m| (n, m))
        }),
        NormalRule::Average => {
            let mut n_m = near.normal;
            let mut found = None;
            for _ in 0..4 {
                let n = choose_normal(rule, n_m, n_s, x, near.x, scale);
                let Some(m) = side.along(x, n, reach, three_d) else {
                    found = None;
                    break;
                };
                let settled = dot(m.normal, n_m) >= 1.0 - 1e-12;
                n_m = m.normal;
                found = Some((n, m));
                if settled {
                    break;
                }
            }
            found
        }
    };
    Ok(paired.ok_or(Unpaired::Missed))
}

/// Node-to-segment contact points (course notes §3.1.2, Fig. 6), in 2D and
/// 3D (where it is node-to-face), and the slave nodes left out: each slave
/// node is paired with a point of the master surface (or of the rigid plane
/// or sphere) by the normal rule (see [`pair`]); the row's master weights
/// are the master's shape functions there.
///
/// A slave node is not a contact point when (counted in [`Dropped`]):
/// - its closest master point is farther than the [`search_distance`];
/// - master and points rules: it does not face the master. 2D linear edges
///   (the historical rule, kept bit-for-bit): the unclamped projection on the
///   closest edge falls outside it by more than 10⁻⁶ of its length, which
///   also drops a node whose closest master point is a convex corner between
///   two master edges. Quadratic edges and 3D faces: the node lies beyond a
///   free side of the master surface (an edge end or a face side that no
///   other facet of the surface shares), by more than 10⁻⁶ of the facet's
///   size, for one of the facets at the least distance. A node whose closest
///   point is clamped to a side or corner inside the surface (the kinks of a
///   faceted curved master, the mid-side node of a bent quadratic edge) keeps
///   that clamped point, with the normal of the facet chosen (the
///   lowest-numbered at the least distance);
/// - slave and average rules: the line through it along the normal meets no
///   master facet facing it (inside the facet up to 10⁻⁶ of its parameter
///   range) within the search distance. Without this bound, the closest
///   master point with the slave's normal gave nodes far from the contact
///   zone a gap near zero (a normal nearly tangent to the master).
pub fn node_to_segment_pairing(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
    rule: NormalRule,
) -> Result<Pairing, GeometryError> {
    let normals = GivenNormals {
        slave: nodal_normals(slave_mesh, slave_surface),
        master: None,
    };
    node_to_segment_pairing_with(slave_mesh, normals, master, rule)
}

/// Nodal normals that [`node_to_segment_pairing_with`] takes in place of its
/// own: a quadratic 3D surface's consistent normals
/// (`crate::quadratic_slave::consistent_normals`).
pub struct GivenNormals {
    /// Every slave node with its outward unit normal (the slave and average
    /// rules' n_s), in place of [`nodal_normals`].
    pub slave: Vec<(usize, [f64; 3])>,
    /// The master surface's outward unit normal at each of its nodes; when
    /// given, the master's normal at a point is these interpolated with the
    /// piece's weights there (normalised) instead of the flat piece's own.
    pub master: Option<BTreeMap<usize, [f64; 3]>>,
}

/// [`node_to_segment_pairing`] with the given nodal normals.
pub fn node_to_segment_pairing_with(
    slave_mesh: &Mesh,
    normals: GivenNormals,
    master: &MasterGeometry<'_>,
    rule: NormalRule,
) -> Result<Pairing, GeometryError> {
    check_dims(slave_mesh, master)?;
    let three_d = is_3d(slave_mesh);
    let scale = slave_mesh.size();
    let reach = search_distance(slave_mesh, master);
    let side = MasterSide::new(master, normals.master)?;
    let slave_normals = normals.slave;
    let mut out = Pairing {
        points: Vec::with_capacity(slave_normals.len()),
        dropped: Dropped::within(reach),
    };
    for (s, n_s) in slave_normals {
        let x = slave_mesh.coords[s];
        match pair(&side, rule, (s, x, n_s), reach, (three_d, scale))? {
            Ok((n, m)) => {
                let mut terms = vec![Term::slave(s)];
                terms.extend(m.terms);
                (out.points).push(ContactPoint::new(s, (x, m.x), n, terms, three_d));
            }
            Err(Unpaired::OffSurface) => out.dropped.off_surface += 1,
            Err(Unpaired::Far) => out.dropped.far += 1,
            Err(Unpaired::Missed) => out.dropped.missed += 1,
        }
    }
    Ok(out)
}

/// Node-to-node contact points for matching meshes (course notes §3.1.2,
/// Fig. 4), in 2D and 3D: each slave node faces the nearest master node
/// (R*-tree search; ties to the lowest node number); the pair must coincide
/// within a relative tolerance (10⁻⁶) of the slave body's size unless a gap
/// separates them along the normal. The slave nodes left out are those
/// whose nearest master node is farther than the [`search_distance`]
/// (counted as `far`; they are not asked to face a master node).
pub fn node_to_node_pairing(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
    rule: NormalRule,
) -> Result<Pairing, GeometryError> {
    let (mesh, surface) = match master {
        MasterGeometry::Plane { .. } | MasterGeometry::Sphere { .. } => {
            // Against a rigid obstacle, node-to-node and node-to-segment coincide.
            return node_to_segment_pairing(slave_mesh, slave_surface, master, rule);
        }
        MasterGeometry::Surface { mesh, surface } => (*mesh, *surface),
    };
    check_dims(slave_mesh, master)?;
    let three_d = is_3d(slave_mesh);
    let slave_normals = nodal_normals(slave_mesh, slave_surface);
    let nodes = MasterNodes::new(mesh, surface);
    let scale = slave_mesh.size();
    let reach = search_distance(slave_mesh, master);
    let mut out = Vec::with_capacity(slave_normals.len());
    let mut dropped = Dropped::within(reach);
    for (s, n_s) in slave_normals {
        let x = slave_mesh.coords[s];
        let Some((m, n_m)) = nodes.nearest(x) else {
            return Err(GeometryError("the master surface has no node".into()));
        };
        let xm = mesh.coords[m];
        let d = sub(x, xm);
        if norm(d) > reach {
            dropped.far += 1;
            continue;
        }
        let n = choose_normal(rule, n_m, n_s, x, xm, scale);
        // The facing node must lie along the surface's normal: a tangential
        // offset means the meshes do not match. The points rule's normal
        // joins the two nodes whatever their offset, so its check takes the
        // master's normal.
        let facing = if matches!(rule, NormalRule::Points) {
            n_m
        } else {
            n
        };
        let tangential = norm([
            d[0] - dot(d, facing) * facing[0],
            d[1] - dot(d, facing) * facing[1],
            d[2] - dot(d, facing) * facing[2],
        ]);
        if tangential > 1e-6 * scale.max(f64::MIN_POSITIVE) {
            let at = position(x, three_d, Some(6));
            return Err(GeometryError(format!(
                "node_to_node needs matching meshes: slave node {s} at {at} has no master node facing it (nearest is {tangential:.3e} off the normal); use discretization = \"node_to_segment\""
            )));
        }
        out.push(node_to_node_point(s, x, m, xm, n, three_d));
    }
    Ok(Pairing {
        points: out,
        dropped,
    })
}

/// The nodes of a master surface with their outward normals
/// ([`nodal_normals`]), for the nearest-node search of node-to-node and
/// contact elements.
struct MasterNodes {
    normals: Vec<(usize, [f64; 3])>,
    index: NodeIndex,
}

impl MasterNodes {
    fn new(mesh: &Mesh, surface: &Surface) -> Self {
        let normals = nodal_normals(mesh, surface);
        let index = NodeIndex::new(normals.iter().map(|&(m, _)| mesh.coords[m]).collect());
        MasterNodes { normals, index }
    }

    /// The master node nearest to x (R*-tree search; ties to the lowest
    /// node number) and its normal; `None` for a surface without nodes.
    fn nearest(&self, x: [f64; 3]) -> Option<(usize, [f64; 3])> {
        self.index.nearest(x).map(|i| self.normals[i])
    }
}

/// A slave node's position for a message: (x, y) in 2D, (x, y, z) in 3D,
/// with `digits` decimals (`None`: as Rust prints an f64).
fn position(x: [f64; 3], three_d: bool, digits: Option<usize>) -> String {
    let shown: Vec<String> = x[..if three_d { 3 } else { 2 }]
        .iter()
        .map(|v| match digits {
            Some(d) => format!("{v:.d$}"),
            None => format!("{v}"),
        })
        .collect();
    format!("({})", shown.join(", "))
}

/// The node-to-node point of slave node `s` at `x` facing master node `m`
/// at `xm` along the normal `n`: gap₀ = n·(x − xm), g = n·(u_s − u_m).
fn node_to_node_point(
    s: usize,
    x: [f64; 3],
    m: usize,
    xm: [f64; 3],
    n: [f64; 3],
    three_d: bool,
) -> ContactPoint {
    let terms = vec![Term::slave(s), Term::master(m, 1.0)];
    ContactPoint::new(s, (x, xm), n, terms, three_d)
}

/// The contact elements of course notes §7 between two surfaces whose nodes
/// coincide: each slave node pairs with the master node at the same place
/// (within 10⁻⁶ of the slave body's size), as a node-to-node point with a
/// zero initial gap. A slave node with no coincident master node is an
/// error naming it (contact elements need two layers of coincident nodes).
pub fn contact_element_pairing(
    slave_mesh: &Mesh,
    slave_surface: &Surface,
    master: &MasterGeometry<'_>,
    rule: NormalRule,
) -> Result<Pairing, GeometryError> {
    let MasterGeometry::Surface { mesh, surface } = master else {
        return Err(GeometryError(
            "contact elements join two deformable bodies: the master must be a deformable body with a surface".into(),
        ));
    };
    check_dims(slave_mesh, master)?;
    let three_d = is_3d(slave_mesh);
    let nodes = MasterNodes::new(mesh, surface);
    let scale = slave_mesh.size().max(f64::MIN_POSITIVE);
    let mut points = Vec::new();
    for (s, n_s) in nodal_normals(slave_mesh, slave_surface) {
        let x = slave_mesh.coords[s];
        let nearest = nodes.nearest(x);
        let d = nearest.map_or(f64::INFINITY, |(m, _)| norm(sub(x, mesh.coords[m])));
        let Some((m, n_m)) = nearest.filter(|_| d <= 1e-6 * scale) else {
            let at = position(x, three_d, None);
            return Err(GeometryError(format!(
                "contact elements need coincident nodes: slave node {s} at {at} has no master node within {:.3e} (10⁻⁶ of the body's size; nearest at {d:.3e}); for non-matching meshes use discretization = \"node_to_segment\" or \"mortar\"",
                1e-6 * scale
            )));
        };
        let xm = mesh.coords[m];
        let n = choose_normal(rule, n_m, n_s, x, xm, scale);
        points.push(node_to_node_point(s, x, m, xm, n, three_d));
    }
    Ok(Pairing {
        points,
        dropped: Dropped::default(),
    })
}

#[cfg(test)]
mod tests;
