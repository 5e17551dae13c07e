//! The memory a scene needs, estimated from the sizes of its meshes before
//! anything is built, and the memory the machine has: a scene that cannot fit
//! is refused (exit 1) with the estimate, instead of aborting on a failed
//! allocation minutes later.
//!
//! The estimate follows the pipeline of [`crate::run`] on the condensed path
//! (the direct path where it differs), per subdomain of `n` DOFs, `n_b` of
//! them on its interface, `n_I = n − n_b` interior:
//!
//! * **sparse**: the element triplets (24 bytes each, `(d p)²` per cell of `p`
//!   nodes) and three copies of the stiffness (K, K_ff, the interior block:
//!   16 bytes per entry, `d² q` entries per node with `q` the nodes a node
//!   shares a cell with), and a few vectors per DOF and load entry;
//! * **factor**: the sparse Cholesky factor of K with the interface ordered
//!   last (AMD on the interior; `crates/condense`). Its interior block has
//!   O(n log n) entries in 2D, as nested dissection would give (George
//!   1973): measured with faer 0.24, 6.2–7.7 n log₂ n (quad4 to quad8), taken
//!   as 8. In 3D nested dissection would give O(n^{4/3}), but AMD grows
//!   faster: measured 6.1–6.8 n^{3/2} on cubes of 11 000 to 135 000 DOFs
//!   (29 to 49 n^{4/3}), taken as 7 n^{3/2} (with the width of a flat or long
//!   box instead of a cube's). Its interface rows fill in: about 10 n_b
//!   entries per interface DOF (measured 8–11 on squares and cubes), at most
//!   n_I, and the dense trailing block n_b²/2. Since the interior is ordered
//!   by the cheaper of AMD and nested dissection (`signorini_condense::ordering`)
//!   the 3D factor is often smaller (the Hertz sphere at 127 000 DOFs: half
//!   of AMD's), so the 3D term is conservative there. The direct path
//!   factorises the whole stiffness with its contact constraints by a sparse
//!   LDLᵀ at each status iteration, in a nested-dissection ordering with no
//!   interface kept last: its entries are those of the model of
//!   [`fill_model`] on the body's grid (a flat pad's factor is far smaller
//!   than a cube's of as many nodes: the n^{3/2} term above made the
//!   101 × 101 × 3-node pad's factor 3 times too large);
//! * **dense interface** (condensed path only: the direct path's KKT matrix
//!   holds the contact rows sparse): 8 bytes per entry of S_i (n_b², three
//!   copies: the factorisation's, the one sent to the root, its encoding), of
//!   the assembled S on Γ (n_Γ², two: S and its factor; with several
//!   subdomains S is a sparse matrix of their blocks, Σ n_b² entries at 16
//!   bytes, and its sparse factor measured with no more entries), of the
//!   Delassus operator W (m², three) and of S⁻¹Bᵀ (n_Γ × 256 columns at a
//!   time), m the contact rows;
//! * **fields**: the displacement three times (recovered, gathered, kept)
//!   and the stresses of every cell, of two steps (the step that ends and
//!   the last step's kept for the report: the steps stream to disk, issue
//!   16), one step's contact rows, and each step's report (5 kB a step).
//!
//! Measured against the peak resident set of the runs it was fitted on
//! (squares of 100² to 800² quad4, 200² quad8 and tri6, 400² tri3, cubes of
//! 10³ to 35³ hex8 and 20³ tet4, plates 40×40×4 and 60×60×3, a bar
//! 10×10×80, a strip 2000×20, both paths) the estimate lies between 1.0 and
//! 1.6 times the peak (tiny scenes: up to 2, the fixed part). It is an
//! estimate: `--max-memory` overrides the machine's figure either way.
//!
//! A Gmsh file's node count is read from its `$Nodes` header (the file is not
//! parsed); a file mesh is taken as compact (a square or a cube), with its
//! contact surfaces as two faces' worth of nodes.

use std::path::Path;

use signorini_scene as scene;

pub use signorini_report::budget::{human, machine_memory, parse_size, Budget, GIB};

use crate::error::SolveError;
use crate::fill_model;

/// What the process holds before any mesh (code, libraries, buffers, the
/// threads' stacks): 24 MiB keeps the smallest measured runs (11k-DOF 2D
/// Hertz, 40 MiB) 1.1 times under their estimate.
const BASE_BYTES: f64 = 24.0 * 1024.0 * 1024.0;
/// Entries of the interior factor: `C2 n log₂ n` (2D), `C3 n^{3/2}` (3D, a
/// compact body; `C3 n (d (ab)^{3/2})^{1/2}` for a box of a ≤ b ≤ c nodes
/// per side, the same for a cube). C3 was 7 when 3D interiors were ordered
/// by AMD; with nested dissection (every 3D body above 1e9 flops) the
/// measured factors are 2.3–2.6× smaller (cubes of 20³ and 30³ cells, the
/// Hertz hemisphere at 12k, 42k and 100k DOFs), so 3.5 keeps the estimate
/// 1.15–1.3× above them.
const C2: f64 = 8.0;
const C3: f64 = 3.5;
/// Fill of the interface rows of the factor, entries per interface DOF, as a
/// multiple of the interface DOFs (at most the interior's DOFs). Measured:
/// 2 to 4 (the Hertz hemisphere's 2 089 contact DOFs at 100k DOFs, the 2D
/// cylinder in 8 parts); 10 made those estimates 1.5 to 2 times the factor.
const INTERFACE_FILL: f64 = 5.0;
/// The direct path's sparse LDLᵀ (the stiffness and the contact rows, one
/// nested-dissection ordering) against [`fill_model::nested_dissection`]'s
/// entries for the stiffness alone: measured 0.53 to 1.17 (its module doc).
const DIRECT_LDLT: f64 = 1.0;
/// Bytes per entry of the free DOFs' stiffness on the direct path (beside
/// K's 16): the global stiffness, the KKT pattern, its sort, and the exact
/// and regularised matrices (pattern and values); fitted with the element
/// triplets on the Hertz half disk at 11 000 to 700 000 DOFs (peak RSS 0.8
/// to 1.0 times the estimate).
const DIRECT_KKT: f64 = 80.0;

/// The estimate of a run's peak memory, in bytes (as f64: a scene can ask
/// for more than u64 holds), with its parts and the sizes it comes from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Estimate {
    pub total: f64,
    pub sparse: f64,
    pub factor: f64,
    pub dense: f64,
    pub fields: f64,
    pub nodes: f64,
    pub dofs: f64,
    /// DOFs of the interface Γ (condensed path).
    pub interface_dofs: f64,
    /// Contact rows (normal and tangential).
    pub contact_rows: f64,
    /// Flops of one sparse factorisation along the path: the subdomains'
    /// partial Cholesky factorisations (condensed, once a run) or the KKT
    /// LDLᵀ (direct, once per status iteration), by
    /// [`fill_model::nested_dissection`].
    pub factor_flops: f64,
    /// Condensed path: flops of the dense interface work done once a run:
    /// forming and factorising S (n_b³ per subdomain, 2/3 of it), and
    /// W = B S⁻¹ Bᵀ (2 n_Γ² m, Σ of the blocks' entries × 2m with several
    /// subdomains). 0 on the direct path.
    pub dense_flops: f64,
    /// The contacts whose unknowns are not counted yet (a candidate zone
    /// before the model is built, [`ContactCounts::Surfaces`]).
    pub uncounted: Vec<String>,
}

impl Estimate {
    /// `total` as whole bytes (saturating).
    pub fn bytes(&self) -> u64 {
        if self.total >= u64::MAX as f64 {
            u64::MAX
        } else {
            self.total as u64
        }
    }

    /// "about 41 GiB (factor 30 GiB, ...) for 9.0e6 nodes".
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        for (what, b) in [
            ("factor", self.factor),
            ("stiffness", self.sparse),
            ("dense interface", self.dense),
            ("fields", self.fields),
        ] {
            if b >= 0.05 * self.total {
                parts.push(format!("{what} {}", human(b)));
            }
        }
        let parts = if parts.is_empty() {
            String::new()
        } else {
            format!(" ({})", parts.join(", "))
        };
        let uncounted = match self.uncounted.as_slice() {
            [] => String::new(),
            names => format!(
                " (without the contact unknowns of {}: counted once its candidate zone, search_distance, is built)",
                names.join(", ")
            ),
        };
        format!(
            "about {}{parts} for {} nodes, {} DOFs, {} interface DOFs, {} contact rows{uncounted}",
            human(self.total),
            count(self.nodes),
            count(self.dofs),
            count(self.interface_dofs),
            count(self.contact_rows)
        )
    }
}

fn count(x: f64) -> String {
    if x < 1e6 {
        format!("{x:.0}")
    } else {
        format!("{x:.2e}")
    }
}

/// The size of one deformable body, from its generator (or file header).
#[derive(Debug, Clone)]
struct BodySize {
    nodes: f64,
    cells: f64,
    /// Nodes per cell.
    per_cell: f64,
    /// Nodes sharing a cell with a node, itself included (average).
    neighbours: f64,
    dim: usize,
    /// The width of the mesh in nodes, the cube root of the nodes for a
    /// compact 3D body; for a box of a ≤ b ≤ c nodes per side, √(ab) (the
    /// separators of nested dissection cut across the long side).
    width: f64,
    /// Nodes along each side of the grid the mesh is (its bounding grid for
    /// a box, a compact one of as many nodes for the others; 2D: one side
    /// 1), for [`fill_model::nested_dissection`].
    sides: [f64; 3],
    /// Nodes on each named surface (unknown names: none).
    surfaces: Vec<(&'static str, f64)>,
    /// A file mesh: its surfaces are unknown, each taken as two faces' worth.
    any_surface: Option<f64>,
}

impl BodySize {
    fn surface(&self, name: &str) -> f64 {
        self.surfaces
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| *v)
            .or(self.any_surface)
            .unwrap_or(0.0)
    }
}

/// 2D element data: nodes of the first-order grid `n1` with `quads`
/// quadrilaterals, made into `element`; returns (nodes, cells, per_cell,
/// neighbours, order).
fn planar(n1: f64, quads: f64, element: scene::Element) -> (f64, f64, f64, f64, f64) {
    // Euler: a mesh of n1 nodes and f faces has n1 + f − 1 edges (mid-side nodes).
    match element {
        scene::Element::Tri3 => (n1, 2.0 * quads, 3.0, 7.0, 1.0),
        scene::Element::Quad8 => (2.0 * n1 + quads - 1.0, quads, 8.0, 16.0, 2.0),
        scene::Element::Tri6 => (2.0 * n1 + 2.0 * quads - 1.0, 2.0 * quads, 6.0, 15.0, 2.0),
        _ => (n1, quads, 4.0, 9.0, 1.0),
    }
}

/// As [`planar`] for the disk generators, whose triangles are cut four to a
/// quadrilateral about a centre node (`crates/mesh` generators/split.rs).
fn planar_disk(n1: f64, quads: f64, element: scene::Element) -> (f64, f64, f64, f64, f64) {
    // Tri3: n1 + quads nodes and 4 quads cells, so n1 + 5 quads − 1 edges.
    match element {
        scene::Element::Tri3 => (n1 + quads, 4.0 * quads, 3.0, 7.0, 1.0),
        scene::Element::Tri6 => (2.0 * n1 + 6.0 * quads - 1.0, 4.0 * quads, 6.0, 15.0, 2.0),
        other => planar(n1, quads, other),
    }
}

/// The index k at which a graded spacing of `2 half` elements, symmetric
/// about its middle with largest / smallest = `grading` over `span` growth
/// steps (`crates/mesh` `symmetric_graded_spacing`), reaches a quarter of its
/// length: where the generators put the corner of their inner block (45°).
/// In closed form, so that a huge `divisions` costs nothing:
/// t_k = (1 − q^{−k}) / (2 (1 − q^{−half})), q = grading^{1/span}.
fn quarter_index(half: f64, grading: f64, span: f64) -> f64 {
    let ln_g = grading.max(1.0).ln();
    if span <= 0.0 || ln_g < 1e-12 {
        return half / 2.0;
    }
    -((1.0 + (-ln_g * half / span).exp()) / 2.0).ln() * span / ln_g
}

/// Nodes and quadrilaterals of the first-order half disk of `n` arc
/// divisions (`crates/mesh` `half_disk`: an inner block of (n − 2m) × m, m
/// the arc index nearest 45°, and a ring of n × ⌈n/8⌉), and its (ns, m, nr).
fn half_disk_grid(n: f64, grading: f64) -> (f64, f64, f64, f64, f64) {
    let span = if n % 2.0 == 0.0 {
        n / 2.0 - 1.0
    } else {
        (n - 1.0) / 2.0
    };
    let m = quarter_index(n / 2.0, grading, span)
        .round()
        .clamp(1.0, ((n - 1.0) / 2.0).floor().max(1.0));
    let ns = (n - 2.0 * m).max(1.0);
    let nr = (n / 8.0).ceil().max(1.0);
    let nodes = (ns + 1.0) * (m + 1.0) + (n + 1.0) * nr;
    let quads = ns * m + n * nr;
    (nodes, quads, ns, m, nr)
}

/// The named surfaces of a body's generator mesh, as the generator names
/// them (`None` for a Gmsh file or a rigid body): what `check` compares the
/// scene's surfaces with without building the mesh.
pub fn generator_surfaces(body: &scene::Body, dim: usize) -> Option<Vec<&'static str>> {
    match body.mesh.as_ref()? {
        scene::MeshSpec::Generator(_) => {
            body_size(body, dim).map(|s| s.surfaces.iter().map(|&(name, _)| name).collect())
        }
        scene::MeshSpec::File { .. } => None,
    }
}

/// The estimated size of a deformable body's mesh: its generator's counts
/// in closed form, or a Gmsh file's announced node count.
fn body_size(body: &scene::Body, dim: usize) -> Option<BodySize> {
    use scene::Generator as G;
    let g = match body.mesh.as_ref()? {
        scene::MeshSpec::Generator(g) => g,
        scene::MeshSpec::File { file, .. } => return file_size(file, dim),
    };
    Some(match g {
        G::Rectangle(b) => rectangle_size(b.divisions, b.element),
        G::HalfDisk(d) => half_disk_size(d.divisions as f64, d.grading, d.element),
        G::QuarterDisk(d) => quarter_disk_size(d.divisions as f64, d.grading, d.element),
        G::Box(b) => solid_kind(
            box_size(b.divisions.map(|d| d as f64), b.element),
            b.element,
            6.0,
        ),
        G::Hemisphere(h) => {
            let whole = hemisphere_size(h.divisions as f64, h.grading);
            let size = match h.sector {
                scene::Sector::Whole => whole,
                scene::Sector::Quarter => quarter_of(whole),
            };
            solid_kind(size, h.element, 12.0)
        }
    })
}

/// A Gmsh file's mesh: its announced nodes, simplices (five tetrahedra or
/// two triangles a node) and surfaces of two faces' worth of nodes.
fn file_size(file: &Path, dim: usize) -> Option<BodySize> {
    let nodes = gmsh_nodes(file)?;
    let d = dim as f64;
    let (cells, per_cell, neighbours) = if dim == 3 {
        (5.0 * nodes, 4.0, 15.0)
    } else {
        (2.0 * nodes, 3.0, 7.0)
    };
    Some(BodySize {
        nodes,
        cells,
        per_cell,
        neighbours,
        dim,
        width: nodes.cbrt(),
        sides: compact_sides(nodes, dim),
        surfaces: Vec::new(),
        any_surface: Some((2.0 * nodes.powf((d - 1.0) / d)).min(nodes)),
    })
}

/// A 2D body from its (nodes, cells, nodes per cell, neighbours) and the
/// nodes of its named surfaces.
fn planar_size(counts: (f64, f64, f64, f64), surfaces: Vec<(&'static str, f64)>) -> BodySize {
    let (nodes, cells, per_cell, neighbours) = counts;
    BodySize {
        nodes,
        cells,
        per_cell,
        neighbours,
        dim: 2,
        width: 0.0,
        sides: compact_sides(nodes, 2),
        surfaces,
        any_surface: None,
    }
}

/// `crates/mesh` `rectangle`: an nx × ny grid.
fn rectangle_size(divisions: [usize; 2], element: scene::Element) -> BodySize {
    let [nx, ny] = divisions.map(|d| d as f64);
    let (nodes, cells, per_cell, neighbours, o) = planar((nx + 1.0) * (ny + 1.0), nx * ny, element);
    let mut size = planar_size(
        (nodes, cells, per_cell, neighbours),
        vec![
            ("bottom", o * nx + 1.0),
            ("top", o * nx + 1.0),
            ("left", o * ny + 1.0),
            ("right", o * ny + 1.0),
        ],
    );
    // the grid's aspect, at the element's node count
    let aspect = (nx + 1.0) / (ny + 1.0);
    size.sides = [(nodes * aspect).sqrt(), (nodes / aspect).sqrt(), 1.0];
    size
}

/// The sides of a compact grid of `nodes` nodes: a square (2D) or a cube.
fn compact_sides(nodes: f64, dim: usize) -> [f64; 3] {
    if dim == 3 {
        [nodes.cbrt(); 3]
    } else {
        [nodes.sqrt(), nodes.sqrt(), 1.0]
    }
}

/// The sides of one of `parts` equal parts of a grid of `sides`: the
/// longest side halved as often as the parts double.
fn part_sides(sides: [f64; 3], parts: f64) -> [f64; 3] {
    let mut s = sides;
    let mut left = parts;
    while left > 1.0 {
        let longest = (0..3).max_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap_or(0);
        s[longest] = (s[longest] / 2.0).max(1.0);
        left /= 2.0;
    }
    s
}

/// `crates/mesh` `half_disk` of `n` arc divisions.
fn half_disk_size(n: f64, grading: f64, element: scene::Element) -> BodySize {
    let (n1, quads, ns, _, nr) = half_disk_grid(n, grading);
    let (nodes, cells, per_cell, neighbours, o) = planar_disk(n1, quads, element);
    planar_size(
        (nodes, cells, per_cell, neighbours),
        vec![("arc", o * n + 1.0), ("flat", o * (ns + 2.0 * nr) + 1.0)],
    )
}

/// `crates/mesh` `quarter_disk` of `n` arc divisions: the half disk of 2n
/// divisions, cut along its axis.
fn quarter_disk_size(n: f64, grading: f64, element: scene::Element) -> BodySize {
    let (n1, quads, ns, m, nr) = half_disk_grid(2.0 * n, grading);
    let (nodes, cells, per_cell, neighbours, o) =
        planar_disk(n1 / 2.0 + m + nr + 1.0, quads / 2.0, element);
    planar_size(
        (nodes, cells, per_cell, neighbours),
        vec![
            ("arc", o * n + 1.0),
            ("flat", o * (ns / 2.0 + nr) + 1.0),
            ("axis", o * (m + nr) + 1.0),
        ],
    )
}

/// The DOFs of body `name` that a `displacement` on one of its surfaces
/// prescribes (each surface counted once, with the most components any of
/// its conditions imposes), at most its DOFs.
fn prescribed_dofs(sc: &scene::Scene, name: &str, size: &BodySize) -> f64 {
    let mut surfaces: Vec<(&str, f64)> = Vec::new();
    for b in sc.boundary.iter().filter(|b| b.body == name) {
        let (Some(surface), Some(u)) = (b.surface.as_deref(), b.displacement) else {
            continue;
        };
        let components = u.components().iter().flatten().count() as f64;
        match surfaces.iter_mut().find(|(s, _)| *s == surface) {
            Some((_, c)) => *c = c.max(components),
            None => surfaces.push((surface, components)),
        }
    }
    let dofs: f64 = surfaces.iter().map(|&(s, c)| size.surface(s) * c).sum();
    dofs.min(size.dim as f64 * size.nodes)
}

/// A solid generator's hexahedral size made into `element`: tetrahedra
/// (`tets_per_hex` a hexahedron: 6 for the box, 12 about a centre node for
/// the hemisphere; one node a hexahedron more there), and second order:
/// one node more per edge (3 edges a node on hexahedra, 7 on tetrahedra),
/// 20 or 10 nodes a cell, about 3× the neighbours of a node, 3× (Quad8)
/// or 4× (Tri6) the nodes of a surface.
fn solid_kind(mut size: BodySize, element: scene::Element, tets_per_hex: f64) -> BodySize {
    use scene::Element as E;
    let hexes = size.cells;
    if matches!(element, E::Tet4 | E::Tet10) && tets_per_hex > 6.0 {
        size.nodes += hexes;
        size.cells = tets_per_hex * hexes;
        (size.per_cell, size.neighbours) = (4.0, 15.0);
    }
    let (nodes, surface) = match element {
        E::Hex20 => (4.0, 3.0),
        E::Tet10 => (8.0, 4.0),
        _ => return size,
    };
    size.nodes *= nodes;
    size.per_cell = if element == E::Hex20 { 20.0 } else { 10.0 };
    size.neighbours *= 3.0;
    size.width = size.nodes.cbrt().max(size.width);
    for s in &mut size.surfaces {
        s.1 *= surface;
    }
    size
}

/// `crates/mesh` `box_mesh`: an nx × ny × nz grid of hexahedra, or six
/// tetrahedra a hexahedron.
fn box_size([nx, ny, nz]: [f64; 3], element: scene::Element) -> BodySize {
    let (px, py, pz) = (nx + 1.0, ny + 1.0, nz + 1.0);
    // a node of a line of p nodes has 3 neighbours on it, itself included,
    // but the two ends 2: (3p − 2)/p on average
    let line = |p: f64| (3.0 * p - 2.0) / p;
    let (cells, per_cell, neighbours) =
        if matches!(element, scene::Element::Tet4 | scene::Element::Tet10) {
            (6.0 * nx * ny * nz, 4.0, 15.0)
        } else {
            (nx * ny * nz, 8.0, line(px) * line(py) * line(pz))
        };
    let mut sides = [px, py, pz];
    sides.sort_by(f64::total_cmp);
    BodySize {
        nodes: px * py * pz,
        cells,
        per_cell,
        neighbours,
        dim: 3,
        width: (sides[0] * sides[1]).sqrt(),
        sides,
        surfaces: vec![
            ("xmin", py * pz),
            ("xmax", py * pz),
            ("ymin", px * pz),
            ("ymax", px * pz),
            ("zmin", px * py),
            ("zmax", px * py),
        ],
        any_surface: None,
    }
}

/// `crates/mesh` `hemisphere` of `n` divisions: (ns + 1)² (m + 1) +
/// ((ns + 1)² + 4 ns m) n_r nodes, m the meridian index nearest 45°,
/// ns = 2n − 2m, n_r = max(2, ⌈n/2⌉).
fn hemisphere_size(n: f64, grading: f64) -> BodySize {
    let m = quarter_index(n, grading, n - 1.0)
        .round()
        .clamp(1.0, (n - 1.0).max(1.0));
    let ns = (2.0 * n - 2.0 * m).max(1.0);
    let nr = (n / 2.0).ceil().max(2.0);
    let block = (ns + 1.0) * (ns + 1.0);
    let nodes = block * (m + 1.0) + (block + 4.0 * ns * m) * nr;
    BodySize {
        nodes,
        width: nodes.cbrt(),
        sides: compact_sides(nodes, 3),
        cells: ns * ns * m + (ns * ns + 4.0 * ns * m) * nr,
        per_cell: 8.0,
        neighbours: 27.0,
        dim: 3,
        surfaces: vec![
            ("dome", block + 4.0 * ns * m),
            ("flat", block + 4.0 * ns * nr),
        ],
        any_surface: None,
    }
}

/// A quarter of a hemisphere: a quarter of its nodes, cells and surfaces,
/// its width and sides divided by the cube root of 4; each cut plane (a
/// quarter disk, as the flat face's quarter) as many nodes as that.
fn quarter_of(whole: BodySize) -> BodySize {
    let plane = whole
        .surfaces
        .iter()
        .find(|(name, _)| *name == "flat")
        .map_or(0.0, |&(_, n)| n / 4.0);
    BodySize {
        nodes: whole.nodes / 4.0,
        width: whole.width / 4f64.cbrt(),
        sides: whole.sides.map(|s| s / 4.0f64.cbrt()),
        cells: whole.cells / 4.0,
        surfaces: whole
            .surfaces
            .into_iter()
            .map(|(name, n)| (name, n / 4.0))
            .chain(["symmetry_1", "symmetry_2"].map(|name| (name, plane)))
            .collect(),
        ..whole
    }
}

/// The node count announced by a Gmsh file's `$Nodes` header (MSH 2.2: the
/// count; MSH 4.1 ASCII: the second number; binary: the second size_t), at
/// most one node per 4 bytes of file, else one node per 32 bytes. `None` if
/// the file cannot be read (the solver reports that).
fn gmsh_nodes(path: &Path) -> Option<f64> {
    use std::io::Read;
    // The headers come first: read at most 16 MiB, not a file that may not fit.
    let file = std::fs::File::open(path).ok()?;
    let len = file.metadata().ok()?.len() as f64;
    let mut bytes = Vec::new();
    file.take(16 << 20).read_to_end(&mut bytes).ok()?;
    let fallback = Some(len / 32.0);
    let find = |tag: &[u8]| bytes.windows(tag.len()).position(|w| w == tag);
    let Some(fmt) = find(b"$MeshFormat") else {
        return fallback;
    };
    let header: Vec<&str> = std::str::from_utf8(&bytes[fmt..(fmt + 64).min(bytes.len())])
        .unwrap_or("")
        .lines()
        .nth(1)
        .unwrap_or("")
        .split_whitespace()
        .collect();
    let (version, binary, size_t) = match header.as_slice() {
        [v, b, s, ..] => (*v, *b == "1", s.parse::<usize>().unwrap_or(8)),
        _ => return fallback,
    };
    let Some(start) = find(b"$Nodes") else {
        return fallback;
    };
    let body = &bytes[start + b"$Nodes".len()..];
    let body = body.strip_prefix(b"\r").unwrap_or(body);
    let body = body.strip_prefix(b"\n").unwrap_or(body);
    let count = if version.starts_with('4') && binary {
        if size_t != 4 && size_t != 8 {
            return fallback;
        }
        let raw = body.get(size_t..2 * size_t)?;
        let big_endian = bytes
            .get(fmt..)
            .and_then(|b| b.iter().position(|&c| c == b'\n').map(|e| fmt + e + 1))
            .and_then(|e| bytes.get(e..))
            .and_then(|b| b.iter().position(|&c| c == b'\n').map(|e| (e, b)))
            .and_then(|(e, b)| b.get(e + 1..e + 5))
            == Some(&[0, 0, 0, 1][..]);
        signorini_mesh::gmsh::uint_of_bytes(raw, big_endian) as f64
    } else {
        let text = String::from_utf8_lossy(&body[..body.len().min(200)]).into_owned();
        let mut numbers = text.split_whitespace().map(|t| t.parse::<f64>().ok());
        let first = numbers.next().flatten();
        let second = numbers.next().flatten();
        match (version.starts_with('4'), first, second) {
            (true, _, Some(n)) => n,
            (false, Some(n), _) => n,
            _ => return fallback,
        }
    };
    // A header can claim anything: the file cannot hold more nodes than its
    // bytes allow (a node is at least a few bytes).
    Some(count.min(len / 4.0))
}

/// Entries of the Cholesky factor of a subdomain of `n` DOFs in `dim`
/// dimensions, `nb` of them on its interface (ordered last), part of a body
/// of `body_n` DOFs and `width` (see [`BodySize::width`]).
fn factor_entries(n: f64, nb: f64, dim: usize, body_n: f64, width: f64) -> f64 {
    let ni = (n - nb).max(0.0);
    let interior = if dim == 3 {
        // n^{3/2} = n (d N)^{1/2}, N = width³ for a cube
        let part = ni / body_n.max(1.0);
        C3 * ni * (3.0 * width.powi(3) * part).sqrt()
    } else {
        C2 * ni * ni.max(2.0).log2()
    };
    interior + nb * (INTERFACE_FILL * nb).min(ni) + 0.5 * nb * nb
}

/// The contact unknowns a contact brings to a run (after its candidate
/// zone and redundant rows are dropped).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeptContact {
    /// Contact points (one per kept slave node).
    pub points: f64,
    /// DOFs of a deformable master that the kept points' rows hold.
    pub master_dofs: f64,
}

/// What an estimate knows of the contact unknowns.
#[derive(Debug, Clone, Copy)]
pub enum ContactCounts<'a> {
    /// Nothing is built: a contact brings its whole slave and master
    /// surfaces, except one with a candidate zone (`search_distance`),
    /// whose nodes are not known yet and count as none (the estimate after
    /// the model is built counts them).
    Surfaces,
    /// The model is built: per contact of the scene, what it keeps.
    Built(&'a [KeptContact]),
}

/// The contact rows of the scene, the interface DOFs contact puts on each
/// body (d per node, one per slave node condensed on its normal alone:
/// frictionless against a rigid master, crates/solver/src/contact_frames.rs),
/// and the contacts whose points could not be counted.
fn contact_sizes(
    sc: &scene::Scene,
    sizes: &[Option<BodySize>],
    counts: ContactCounts,
) -> (Vec<f64>, f64, Vec<String>) {
    let body_of = |name: &str| sc.body_index(name).and_then(|i| sizes[i].as_ref());
    let dim = sc.dimension as usize;
    let mut contact_dofs = vec![0.0; sc.bodies.len()];
    let mut rows = 0.0;
    let mut uncounted = Vec::new();
    for (ci, c) in sc.contact.iter().enumerate() {
        let surface = |side: &scene::ContactSide| {
            side.surface
                .as_deref()
                .and_then(|s| body_of(&side.body).map(|b| b.surface(s)))
                .unwrap_or(0.0)
        };
        let kept = match counts {
            ContactCounts::Built(kept) => kept.get(ci).copied(),
            ContactCounts::Surfaces if c.search_distance.is_some() => None,
            ContactCounts::Surfaces => Some(KeptContact {
                points: surface(&c.slave),
                master_dofs: dim as f64 * surface(&c.master),
            }),
        };
        let KeptContact {
            points: slave,
            master_dofs,
        } = kept.unwrap_or_else(|| {
            uncounted.push(format!("contact \"{}\"", c.name));
            KeptContact {
                points: 0.0,
                master_dofs: 0.0,
            }
        });
        let rigid_master = c.master.surface.is_none();
        let normal_only = rigid_master && matches!(c.friction, scene::Friction::None);
        if let Some(i) = sc.body_index(&c.slave.body) {
            contact_dofs[i] += slave * if normal_only { 1.0 } else { dim as f64 };
        }
        if let Some(i) = sc.body_index(&c.master.body).filter(|_| !rigid_master) {
            contact_dofs[i] += master_dofs;
        }
        let tangential = match c.friction {
            scene::Friction::None => 0.0,
            _ => (dim - 1) as f64,
        };
        rows += slave * (1.0 + tangential);
    }
    (contact_dofs, rows, uncounted)
}

/// Estimates the peak memory of `signorini run` on this scene, along
/// `path`, with `ranks` MPI ranks (for `subdomains = "auto"`), the contact
/// unknowns counted as `counts` says. Nothing is built; a Gmsh file's header
/// is read.
pub fn estimate(
    sc: &scene::Scene,
    path: scene::SolvePath,
    ranks: usize,
    counts: ContactCounts,
) -> Estimate {
    let dim = sc.dimension as usize;
    let direct = path == scene::SolvePath::Direct;
    let steps = sc.step_scales().len().max(1) as f64;
    let sizes: Vec<Option<BodySize>> = sc.bodies.iter().map(|b| body_size(b, dim)).collect();
    let autos = sc
        .bodies
        .iter()
        .filter(|b| b.is_deformable() && b.subdomains == scene::Subdomains::Auto)
        .count()
        .max(1);
    let (contact_dofs, rows, uncounted) = contact_sizes(sc, &sizes, counts);
    let mut e = Estimate {
        contact_rows: rows,
        uncounted,
        ..Default::default()
    };
    let mut subdomain_dense = 0.0;
    let (mut blocks, mut block_entries) = (0.0, 0.0);
    let loads = |name: &str| sc.boundary.iter().filter(|b| b.body == name).count() as f64;
    for (i, b) in sc.bodies.iter().enumerate() {
        let Some(s) = &sizes[i] else { continue };
        let d = s.dim as f64;
        let parts = if direct {
            1.0
        } else {
            match b.subdomains {
                scene::Subdomains::Count(k) => k as f64,
                scene::Subdomains::Auto => (ranks / autos).max(1) as f64,
            }
        }
        .clamp(1.0, s.cells.max(1.0));
        // nodes on the cuts between parts (METIS separators): about
        // 1.25 d (k^{1/d} − 1) c for k parts, c the nodes of one cut across
        // the body: n^{1/2} in 2D, width² in 3D (n^{2/3} for a compact body:
        // the hemisphere of 4 100 nodes has 3.65 n^{2/3} in 8 parts, 6.6 in
        // 32, against 3.75 and 8.1; a flat box a ≤ b ≤ c is cut across its
        // long sides, a·b nodes), at least 1.25 c
        let shared = if parts > 1.0 {
            let cuts = (1.25 * d * (parts.powf(1.0 / d) - 1.0)).max(1.25);
            let cut = if s.dim == 3 {
                s.width * s.width
            } else {
                s.nodes.sqrt()
            };
            (cuts * cut).min(s.nodes)
        } else {
            0.0
        };
        let n = d * s.nodes;
        e.nodes += s.nodes;
        e.dofs += n;
        e.interface_dofs += (contact_dofs[i] + d * shared).min(n);
        // per part
        let n_part = n / parts;
        let nb_part = ((contact_dofs[i] + 2.0 * d * shared) / parts).min(n_part);
        let triplets = s.cells * (d * s.per_cell).powi(2);
        let entries = s.nodes * d * d * s.neighbours;
        let per_dof = 8.0 * (12.0 + 5.0 * loads(&b.name));
        let nd = fill_model::nested_dissection(part_sides(s.sides, parts), d);
        e.factor_flops += parts * nd.flops;
        if direct {
            // the element triplets, and the copies of K that the KKT
            // factorisation holds
            let free = 1.0 - prescribed_dofs(sc, &b.name, s) / n.max(1.0);
            e.sparse += 24.0 * triplets + (16.0 + free * DIRECT_KKT) * entries + per_dof * n;
            e.factor += 8.0 * DIRECT_LDLT * free * nd.entries;
        } else {
            e.sparse += 24.0 * triplets + 48.0 * entries + per_dof * n;
            e.dense_flops += parts * 2.0 / 3.0 * nb_part.powi(3);
            e.factor += 8.0 * parts * factor_entries(n_part, nb_part, s.dim, n, s.width);
            // each part's S, held until the interface is assembled
            subdomain_dense += parts * nb_part * nb_part;
            blocks += parts;
            block_entries += parts * nb_part * nb_part;
        }
        // two steps: displacement (recovered, gathered, kept) and the stresses
        e.fields += 2.0 * 8.0 * (3.0 * n + 7.0 * s.cells);
    }
    let (g, m) = (e.interface_dofs, e.contact_rows);
    // Friction on the direct path: the Newton direction is the LDLᵀ of the
    // Jacobian's symmetric part (the frictionless KKT factor's size) and
    // GMRES, with the Jacobian, the symmetric part and the factor's scratch
    // on a fixed pattern: twice the LDLᵀ, which puts the estimate at 1.1
    // to 1.6 times the measured peaks of
    // docs/performance/condensed-vs-direct.md; the sparse LU, five times the LDLᵀ in its COLAMD order, is
    // a fallback built only when that direction fails, nothing dense.
    let direct_friction = direct
        && sc
            .contact
            .iter()
            .any(|c| c.friction != scene::Friction::None);
    e.factor *= if direct_friction { 2.0 } else { 1.0 };
    e.dense = if direct {
        // the KKT matrix holds the contact rows sparse: no dense block
        0.0
    } else {
        // one subdomain: the factor of S, dense; several: the assembled
        // interface (values and indices) and its factor, which measured
        // (3D sphere in 8 and 32 parts, 2D cylinder in 8, slab in 4) at most
        // 1.2 times the parts' blocks' entries
        let interface = if blocks > 1.0 {
            1.5 * block_entries
        } else {
            g * g
        };
        8.0 * (subdomain_dense + interface + 3.0 * m * m + g * m.min(256.0))
    };
    if !direct {
        // W = B S⁻¹ Bᵀ: two triangular solves with S's factor per row
        let s_factor = if blocks > 1.0 {
            1.5 * block_entries
        } else {
            g * g
        };
        e.dense_flops += 2.0 * s_factor * m;
    }
    e.fields += 200.0 * m + steps * 5000.0;
    e.total = BASE_BYTES + e.sparse + e.factor + e.dense + e.fields;
    e
}

/// [`estimate`], refused with [`SolveError::Input`] when it exceeds
/// `budget` (the machine's memory or `--max-memory`; `None`: unknown, nothing
/// is refused).
pub fn check(
    sc: &scene::Scene,
    (path, ranks): (scene::SolvePath, usize),
    counts: ContactCounts,
    budget: Option<Budget>,
) -> Result<Estimate, SolveError> {
    let e = estimate(sc, path, ranks, counts);
    let Some(budget) = budget else {
        return Ok(e);
    };
    if e.total <= budget.bytes as f64 {
        return Ok(e);
    }
    let has = match budget.source {
        "--max-memory" => format!("--max-memory is {}", human(budget.bytes as f64)),
        "available" => format!("the machine has {} available", human(budget.bytes as f64)),
        "cgroup limit" => format!(
            "the process may use {} (cgroup limit)",
            human(budget.bytes as f64)
        ),
        _ => format!("the machine has {}", human(budget.bytes as f64)),
    };
    let dim = sc.dimension as usize;
    let biggest = sc
        .bodies
        .iter()
        .enumerate()
        .filter_map(|(i, b)| body_size(b, dim).map(|s| (i, b, s.nodes)))
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .map(|(i, b, _)| {
            let key = match b.mesh {
                Some(scene::MeshSpec::File { .. }) => "file",
                _ => "divisions",
            };
            format!(
                "; the largest mesh is bodies[{i}] \"{}\" (bodies[{i}].mesh.{key})",
                b.name
            )
        })
        .unwrap_or_default();
    // --max-memory is for an estimate that is wrong, not for 1000 times too much
    let remedy = if e.total < 16.0 * budget.bytes as f64 {
        format!(
            "use coarser divisions, or --max-memory {} if the estimate is wrong for this machine",
            suggest(e.total)
        )
    } else {
        "use coarser divisions".to_string()
    };
    Err(SolveError::Input(format!(
        "memory: the scene needs {}, {has}{biggest}; {remedy}",
        e.describe()
    )))
}

/// A `--max-memory` value just above `bytes`.
fn suggest(bytes: f64) -> String {
    let g = (bytes / GIB).ceil();
    if g < 1e6 {
        format!("{g:.0}G")
    } else {
        format!("{g:.1e}G")
    }
}

#[cfg(test)]
mod tests;
