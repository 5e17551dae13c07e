//! Bad input is rejected up front (docs/reference/scene-format.md, "Commands"): `signorini run` exits
//! with code 1, prints one short error on stderr that names the offending entry
//! or key, and writes nothing, not even the output directory. One module a
//! topic: the scene's entries, the sweep of malformed and oversized scenes,
//! and the inputs a hostile sweep found mishandled (problem files, options).

mod hostile;
mod nsgs_held_by_contacts;
mod scene;
mod sweep;

use crate::common::bad_scene::block_meshed;

/// A 3D box resting on a rigid plane, pinned sideways at two corners, pressed
/// on its top: the 3D base of the sweep (it runs fine as it is).
pub const BOX_ON_PLANE: &str = r#"dimension = 3

[[materials]]
name = "steel"
young = 1.0
poisson = 0.3

[[bodies]]
name = "box"
material = "steel"
mesh = { generator = "box", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = [2, 2, 1] }

[[bodies]]
name = "ground"
rigid = { shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }

[[boundary]]
body = "box"
surface = "xmin"
displacement = { x = 0.0 }

[[boundary]]
body = "box"
surface = "ymin"
displacement = { y = 0.0 }

[[boundary]]
body = "box"
surface = "zmax"
traction = [0.0, 0.0, -1.0]

[[contact]]
name = "box-ground"
slave = { body = "box", surface = "zmin" }
master = { body = "ground" }
"#;

/// A Gmsh 2.2 file of two triangles with physical names, valid as it is.
pub const TWO_TRIANGLES_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n2 2 \"block\"\n$EndPhysicalNames\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n3\n1 1 2 1 1 1 2\n2 2 2 2 1 1 2 3\n3 2 2 2 1 1 3 4\n$EndElements\n";

/// `BLOCK_ON_PLANE` meshed by the Gmsh file `file`.
pub fn block_from_file(file: &str) -> String {
    block_meshed(&format!("{{ file = \"{file}\" }}"))
}
