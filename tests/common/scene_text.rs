//! Tables of the small 2D test scenes, as TOML text to be joined: the
//! material "m", the elastic rectangle "block" of it, rigid planes, boundary
//! conditions and contacts.

use std::fmt;
use std::ops::Deref;

/// A scene text built once, on first use, and usable wherever a `&str`
/// constant was: as `&str` (by deref), in `format!` and as file contents.
#[derive(Clone, Copy)]
pub struct SceneText(pub fn() -> &'static str);

impl Deref for SceneText {
    type Target = str;
    fn deref(&self) -> &str {
        (self.0)()
    }
}

impl fmt::Display for SceneText {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self)
    }
}

impl AsRef<[u8]> for SceneText {
    fn as_ref(&self) -> &[u8] {
        self.as_bytes()
    }
}

/// `dimension = 2` and the material "m".
pub fn material_2d(young: f64, poisson: f64) -> String {
    format!("dimension = 2\n{}", material("m", young, poisson))
}

/// The material `name` of Young's modulus `young` and Poisson's ratio
/// `poisson`.
pub fn material(name: &str, young: f64, poisson: f64) -> String {
    format!("[[materials]]\nname = \"{name}\"\nyoung = {young:?}\npoisson = {poisson:?}\n")
}

/// `dimension = dim`, the `model` and the material "m".
pub fn material_head(dim: usize, model: &str, young: f64, poisson: f64) -> String {
    format!(
        "dimension = {dim}\nmodel = \"{model}\"\n{}",
        material("m", young, poisson)
    )
}

/// The rectangle "block" of material "m" from `origin`, of `size`, in
/// `divisions` cells; `mesh_extra` is appended to its mesh keys (such as
/// `, element = "tri6"`).
pub fn block_body(
    origin: [f64; 2],
    size: [f64; 2],
    divisions: [usize; 2],
    mesh_extra: &str,
) -> String {
    elastic_body(
        "block",
        &format!("{{ generator = \"rectangle\", origin = {origin:?}, size = {size:?}, divisions = {divisions:?}{mesh_extra} }}"),
    )
}

/// The body `name` of material "m" with the mesh entry `mesh` (an inline
/// table).
pub fn elastic_body(name: &str, mesh: &str) -> String {
    body(name, "m", mesh)
}

/// The body `name` of `material` with the mesh entry `mesh` (an inline
/// table).
pub fn body(name: &str, material: &str, mesh: &str) -> String {
    format!("[[bodies]]\nname = \"{name}\"\nmaterial = \"{material}\"\nmesh = {mesh}\n")
}

/// A rigid plane body `name` through `point` with the outward `normal`.
pub fn rigid_plane<const D: usize>(name: &str, point: [f64; D], normal: [f64; D]) -> String {
    format!("[[bodies]]\nname = \"{name}\"\nrigid = {{ shape = \"plane\", point = {point:?}, normal = {normal:?} }}\n")
}

/// A 3D scene's head: the material "m" (E = 1000, ν = 0.3), the Tet10 box
/// `name` from the origin, of `size`, in `divisions` cells, the rigid floor
/// z = 0 "floor", and the boundary condition `top` of the box's top face
/// named `load` (such as `force = [1.0, 0.0, -1.0]`).
pub fn tet10_box_on_floor(
    name: &str,
    size: [f64; 3],
    divisions: [usize; 3],
    (load, top): (&str, &str),
) -> String {
    let mesh = format!(
        "{{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = {size:?}, divisions = {divisions:?}, element = \"tet10\" }}"
    );
    format!(
        "{}{}{}[[boundary]]\nname = \"{load}\"\nbody = \"{name}\"\nsurface = \"zmax\"\n{top}\n",
        material_head(3, "solid", 1000.0, 0.3),
        elastic_body(name, &mesh),
        rigid_plane("floor", [0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    )
}

/// An unnamed boundary condition of "block": where (`surface = "top"`,
/// `point = [0.0, 0.0]`) and what (`displacement = { x = 0.0 }`, ...).
pub fn block_boundary(place: &str, condition: &str) -> String {
    format!("[[boundary]]\nbody = \"block\"\n{place}\n{condition}\n")
}

/// The boundary condition `name` of "block" (see [`block_boundary`]).
pub fn named_block_boundary(name: &str, place: &str, condition: &str) -> String {
    boundary(name, "block", place, condition)
}

/// The boundary condition `name` of `body` (see [`block_boundary`]).
pub fn boundary(name: &str, body: &str, place: &str, condition: &str) -> String {
    format!("[[boundary]]\nname = \"{name}\"\nbody = \"{body}\"\n{place}\n{condition}\n")
}

/// The contact `name` of the surface `surface` of `slave` against `master`.
pub fn contact(name: &str, slave: &str, surface: &str, master: &str) -> String {
    format!("[[contact]]\nname = \"{name}\"\nslave = {{ body = \"{slave}\", surface = \"{surface}\" }}\nmaster = {{ body = \"{master}\" }}\n")
}

/// The contact `name` of the surface `slave_surface` of `slave` against the
/// surface `master_surface` of `master`.
pub fn contact_between(
    name: &str,
    (slave, slave_surface): (&str, &str),
    (master, master_surface): (&str, &str),
) -> String {
    format!("[[contact]]\nname = \"{name}\"\nslave = {{ body = \"{slave}\", surface = \"{slave_surface}\" }}\nmaster = {{ body = \"{master}\", surface = \"{master_surface}\" }}\n")
}

/// The contact `name` of the surface `surface` of "block" against `master`.
pub fn block_contact(name: &str, surface: &str, master: &str) -> String {
    contact(name, "block", surface, master)
}

/// A 2 × 1 block "block" (E = 100, ν = 0.3, 8 × 4 quads) on the rigid plane
/// "floor", its top displaced by `top` (the condition "press"), with no
/// support in x: sideways it is held by friction alone.
pub fn block_pressed_on_floor(top: &str) -> String {
    [
        material_2d(100.0, 0.3),
        block_body([0.0, 0.0], [2.0, 1.0], [8, 4], ""),
        rigid_plane("floor", [0.0, 0.0], [0.0, 1.0]),
        named_block_boundary(
            "press",
            r#"surface = "top""#,
            &format!("displacement = {top}"),
        ),
    ]
    .concat()
}

/// The boundary conditions of the drag tests on `body`: "press" (the
/// traction `traction` on its surface `top`), "drag" (the displacement
/// `drag` of `top`) and "hold" (the same displacement of the node at `mid`,
/// so that the body may not turn about its top).
pub fn press_drag_hold(body: &str, top: &str, traction: &str, drag: &str, mid: &str) -> String {
    format!(
        r#"[[boundary]]
name = "press"
body = "{body}"
surface = "{top}"
traction = {traction}
[[boundary]]
name = "drag"
body = "{body}"
surface = "{top}"
displacement = {drag}
[[boundary]]
name = "hold"
body = "{body}"
point = {mid}
displacement = {drag}
"#
    )
}

/// One load step a scale of `scales`, applied to "drag" and "hold".
pub fn drag_steps(scales: &[f64]) -> String {
    scales
        .iter()
        .map(|s| format!("[[steps]]\nscale = {{ drag = {s:?}, hold = {s:?} }}\n"))
        .collect()
}

/// A plane-strain scene of the block "block" of the material "steel"
/// (E = 1, ν = 0.3) meshed by `mesh` (an inline table), then the tables
/// `rest`: each table after a blank line.
pub fn steel_block_scene(title: &str, mesh: &str, rest: &[String]) -> String {
    let mut tables = vec![
        format!("title = \"{title}\"\ndimension = 2\nmodel = \"plane_strain\"\n"),
        material("steel", 1.0, 0.3),
        body("block", "steel", mesh),
    ];
    tables.extend_from_slice(rest);
    tables.join("\n")
}
