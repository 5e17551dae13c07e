//! A body whose mesh has disconnected parts: each part has its own
//! rigid modes, held or left free by its own supports, so the condensed path
//! must give each part its own floating-body treatment. Condensed and direct
//! paths agree, the contact carries the load, and a part that nothing holds
//! is refused by the body's name.

use crate::common;

use common::{assert_message, assert_same, contact_force, converged_on, fresh_dir, try_run};
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, SolveError};

/// One part of a Gmsh file: its nodes, cells and named facets, numbered from
/// `first` (node and element tags alike).
struct Part {
    first: usize,
    nodes: Vec<[f64; 3]>,
    /// (Gmsh element type, node tags).
    cells: Vec<(u32, Vec<usize>)>,
    /// (surface name, Gmsh element type, node tags).
    facets: Vec<(String, u32, Vec<usize>)>,
}

/// The rectangle [x0, x0 + w] × [0, h] in nx × ny quads, its sides named
/// `bottom_<tag>`, `top_<tag>`, `left_<tag>`, node tags from `first`.
fn rectangle(tag: &str, x0: f64, [w, h]: [f64; 2], [nx, ny]: [usize; 2], first: usize) -> Part {
    let id = |i: usize, j: usize| first + i + j * (nx + 1);
    let mut p = Part {
        first,
        nodes: Vec::new(),
        cells: Vec::new(),
        facets: Vec::new(),
    };
    for j in 0..=ny {
        for i in 0..=nx {
            p.nodes
                .push([x0 + w * i as f64 / nx as f64, h * j as f64 / ny as f64, 0.0]);
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            let q = vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            p.cells.push((3, q));
        }
    }
    for i in 0..nx {
        p.facets
            .push((format!("bottom_{tag}"), 1, vec![id(i, 0), id(i + 1, 0)]));
        p.facets
            .push((format!("top_{tag}"), 1, vec![id(i + 1, ny), id(i, ny)]));
    }
    for j in 0..ny {
        p.facets
            .push((format!("left_{tag}"), 1, vec![id(0, j + 1), id(0, j)]));
    }
    p
}

/// The box [x0, x0 + a] × [0, b] × [0, c] in n³ hexahedra, its faces
/// z = 0, z = c, x = x0 and y = 0 named `bottom_<tag>`, `top_<tag>`,
/// `xmin_<tag>`, `ymin_<tag>`, node tags from `first`.
fn cuboid(tag: &str, x0: f64, size: [f64; 3], n: usize, first: usize) -> Part {
    let id = |i: usize, j: usize, k: usize| first + i + (n + 1) * (j + (n + 1) * k);
    let mut p = Part {
        first,
        nodes: Vec::new(),
        cells: Vec::new(),
        facets: Vec::new(),
    };
    let at = |l: usize, s: f64| s * l as f64 / n as f64;
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                p.nodes
                    .push([x0 + at(i, size[0]), at(j, size[1]), at(k, size[2])]);
            }
        }
    }
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let face = |k| {
                    [
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                    ]
                };
                p.cells.push((5, [face(k), face(k + 1)].concat()));
            }
        }
    }
    for a in 0..n {
        for b in 0..n {
            let quad = |f: &dyn Fn(usize, usize) -> usize| {
                vec![f(a, b), f(a + 1, b), f(a + 1, b + 1), f(a, b + 1)]
            };
            p.facets
                .push((format!("bottom_{tag}"), 3, quad(&|a, b| id(a, b, 0))));
            p.facets
                .push((format!("top_{tag}"), 3, quad(&|a, b| id(a, b, n))));
            p.facets
                .push((format!("xmin_{tag}"), 3, quad(&|a, b| id(0, a, b))));
            p.facets
                .push((format!("ymin_{tag}"), 3, quad(&|a, b| id(a, 0, b))));
        }
    }
    p
}

/// The Gmsh 2.2 text of one body made of `parts` (`dim` its dimension),
/// with one physical group per surface name and one for the cells.
fn gmsh(dim: usize, parts: &[Part]) -> String {
    let mut names: Vec<&str> = parts
        .iter()
        .flat_map(|p| p.facets.iter().map(|f| f.0.as_str()))
        .collect();
    names.sort_unstable();
    names.dedup();
    let tag_of = |name: &str| 1 + names.iter().position(|&n| n == name).unwrap();
    let body_tag = names.len() + 1;
    let mut s = format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n{body_tag}\n");
    for (t, n) in names.iter().enumerate() {
        s += &format!("{} {} \"{n}\"\n", dim - 1, t + 1);
    }
    s += &format!("{dim} {body_tag} \"body\"\n$EndPhysicalNames\n$Nodes\n");
    let n_nodes: usize = parts.iter().map(|p| p.nodes.len()).sum();
    s += &format!("{n_nodes}\n");
    for p in parts {
        for (i, x) in p.nodes.iter().enumerate() {
            s += &format!("{} {:?} {:?} {:?}\n", p.first + i, x[0], x[1], x[2]);
        }
    }
    let mut elements = Vec::new();
    for p in parts {
        for (name, ty, nodes) in &p.facets {
            elements.push((*ty, tag_of(name), nodes));
        }
        for (ty, nodes) in &p.cells {
            elements.push((*ty, body_tag, nodes));
        }
    }
    s += &format!("$EndNodes\n$Elements\n{}\n", elements.len());
    for (e, (ty, tag, nodes)) in elements.iter().enumerate() {
        let list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
        s += &format!("{} {ty} 2 {tag} {tag} {}\n", e + 1, list.join(" "));
    }
    s + "$EndElements\n"
}

/// A scene of the body "block" meshed by `msh` (written to a scratch
/// directory of `test`) on the rigid ground z = 0 (y = 0 in 2D), with
/// `rest` (boundary conditions and contacts) appended.
fn scene(test: &str, dim: usize, msh: &str, rest: &str) -> String {
    let path = fresh_dir("disconnected_parts", test).join("block.msh");
    std::fs::write(&path, msh).unwrap();
    let (model, ground) = if dim == 2 {
        (
            "model = \"plane_strain\"\n",
            "[0.0, 0.0], normal = [0.0, 1.0]",
        )
    } else {
        ("", "[0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0]")
    };
    format!(
        "dimension = {dim}\n{model}[[materials]]\nname = \"steel\"\nyoung = 210e3\npoisson = 0.3\n\
         [[bodies]]\nname = \"block\"\nmaterial = \"steel\"\nmesh = {{ file = \"{}\" }}\n\
         [[bodies]]\nname = \"ground\"\nrigid = {{ shape = \"plane\", point = {ground} }}\n{rest}",
        path.display()
    )
}

/// A boundary condition of "block" on `surface`.
fn on(surface: &str, condition: &str) -> String {
    format!("[[boundary]]\nname = \"{surface}\"\nbody = \"block\"\nsurface = \"{surface}\"\n{condition}\n")
}

/// The frictionless contact of "block"'s `surface` with the ground.
fn on_ground(surface: &str) -> String {
    format!("[[contact]]\nname = \"{surface}\"\nslave = {{ body = \"block\", surface = \"{surface}\" }}\nmaster = {{ body = \"ground\" }}\n")
}

/// Two rectangles a = [0, 2] × [0, 1] and b = [10, 11.5] × [0, 0.75] in one
/// body; b is meshed more finely.
fn two_rectangles() -> String {
    gmsh(
        2,
        &[
            rectangle("a", 0.0, [2.0, 1.0], [4, 2], 1),
            rectangle("b", 10.0, [1.5, 0.75], [5, 3], 101),
        ],
    )
}

/// Solves on both paths, asserts that they agree to 1e-9 (contact forces,
/// displacements) and that each contact carries its part's load `loads`
/// (its vertical resultant); returns the condensed run's messages.
fn condensed_equals_direct(text: &str, loads: &[(&str, f64)]) -> Vec<String> {
    let condensed = converged_on(text, SolvePath::Condensed);
    let direct = converged_on(text, SolvePath::Direct);
    assert_same(&condensed, &direct, 1e-9);
    for &(contact, load) in loads {
        for out in [&condensed, &direct] {
            let f = contact_force(out, contact);
            let vertical = f[f.len() - 1];
            assert!(
                (vertical - load).abs() <= 1e-9 * load,
                "{contact}: contact force {f:?}, load {load}"
            );
        }
        let (fc, fd) = (
            contact_force(&condensed, contact),
            contact_force(&direct, contact),
        );
        let df = fc
            .iter()
            .zip(fd)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(df <= 1e-9 * load, "{contact}: {fc:?} vs {fd:?}");
    }
    condensed.report.messages
}

/// Both parts held in x on their left side, pressed on the ground: each has
/// its own vertical translation, held by its own contact (the reproducer of
/// D6, with unequal parts and loads).
#[test]
fn two_parts_each_held_by_contact_agree_on_both_paths_in_2d() {
    let rest = [
        on("left_a", "displacement = { x = 0.0 }"),
        on("left_b", "displacement = { x = 0.0 }"),
        on("top_a", "traction = [0.0, -100.0]"),
        on("top_b", "traction = [30.0, -250.0]"),
        on_ground("bottom_a"),
        on_ground("bottom_b"),
    ]
    .concat();
    let text = scene("held_by_contact_2d", 2, &two_rectangles(), &rest);
    let messages = condensed_equals_direct(&text, &[("bottom_a", 200.0), ("bottom_b", 375.0)]);
    common::assert_any_mentions(&messages, "held by contact in 2 rigid motion(s)");
}

/// Part a clamped on its left side and bent onto the ground, part b held in
/// x only and pressed on it: one part supported, the other held by contact.
#[test]
fn a_supported_part_and_a_part_held_by_contact_agree_on_both_paths_in_2d() {
    let rest = [
        on("left_a", "displacement = { x = 0.0, y = 0.0 }"),
        on("left_b", "displacement = { x = 0.0 }"),
        on("top_a", "traction = [0.0, -2000.0]"),
        on("top_b", "traction = [0.0, -80.0]"),
        on_ground("bottom_a"),
        on_ground("bottom_b"),
    ]
    .concat();
    let text = scene("supported_and_held_2d", 2, &two_rectangles(), &rest);
    let condensed = converged_on(&text, SolvePath::Condensed);
    let direct = converged_on(&text, SolvePath::Direct);
    assert_same(&condensed, &direct, 1e-9);
    assert_message(&condensed, "held by contact in 1 rigid motion(s)");
    // Part b carries its whole load on the ground; part a part of it only
    // (the clamp takes the rest), the same on both paths.
    for out in [&condensed, &direct] {
        let fb = contact_force(out, "bottom_b");
        assert!((fb[1] - 120.0).abs() <= 1e-9 * 120.0, "{fb:?}");
    }
    let (fa, fa_direct) = (
        contact_force(&condensed, "bottom_a")[1],
        contact_force(&direct, "bottom_a")[1],
    );
    assert!(fa > 0.0 && fa < 4000.0, "part a's contact force {fa}");
    assert!(
        (fa - fa_direct).abs() <= 1e-9 * 4000.0,
        "{fa} vs {fa_direct}"
    );
}

/// Two boxes of one body, each held in x and y on two sides, pressed on the
/// ground: each part's vertical translation is held by its own contact.
#[test]
fn two_boxes_each_held_by_contact_agree_on_both_paths_in_3d() {
    let msh = gmsh(
        3,
        &[
            cuboid("a", 0.0, [1.0, 1.0, 0.5], 2, 1),
            cuboid("b", 5.0, [0.5, 1.0, 0.5], 2, 101),
        ],
    );
    let rest = [
        on("xmin_a", "displacement = { x = 0.0 }"),
        on("ymin_a", "displacement = { y = 0.0 }"),
        on("xmin_b", "displacement = { x = 0.0 }"),
        on("ymin_b", "displacement = { y = 0.0 }"),
        on("top_a", "traction = [0.0, 0.0, -100.0]"),
        on("top_b", "traction = [0.0, 0.0, -300.0]"),
        on_ground("bottom_a"),
        on_ground("bottom_b"),
    ]
    .concat();
    let text = scene("held_by_contact_3d", 3, &msh, &rest);
    let messages = condensed_equals_direct(&text, &[("bottom_a", 100.0), ("bottom_b", 150.0)]);
    common::assert_any_mentions(&messages, "held by contact in 2 rigid motion(s)");
}

/// Runs `text` on the condensed and the direct path: each must refuse it
/// as bad input with a message holding every one of `needles`.
fn refused_on_both_paths(text: &str, needles: &[&str]) {
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let opts = RunOptions {
            method: None,
            path: Some(path),
        };
        match try_run(text, opts) {
            Err(SolveError::Input(msg)) => {
                for needle in needles {
                    assert!(msg.contains(needle), "{path:?}: {needle} in {msg}");
                }
            }
            other => panic!(
                "{path:?}: expected an input error, got {:?}",
                other.map(|o| o.report.converged)
            ),
        }
    }
}

/// Part b has no support at all: the frictionless ground holds neither its
/// horizontal translation nor, on its own, part a's support does: a clear
/// input error naming the body, on both paths.
#[test]
fn a_part_that_nothing_holds_is_refused_by_the_body_name() {
    let rest = [
        on("left_a", "displacement = { x = 0.0 }"),
        on("top_a", "traction = [0.0, -100.0]"),
        on("top_b", "traction = [0.0, -100.0]"),
        on_ground("bottom_a"),
        on_ground("bottom_b"),
    ]
    .concat();
    let text = scene("free_part", 2, &two_rectangles(), &rest);
    refused_on_both_paths(&text, &["body \"block\"", "free to move"]);
}

/// A body with no support and no contact at all: refused before anything
/// is factorised, naming it, on both paths (the condensed path ended on
/// "K_II is not positive definite" in its subdomain, the direct path said
/// the body is free to move).
#[test]
fn a_body_that_no_contact_touches_is_refused_on_both_paths() {
    let text = "title = \"loose\"\ndimension = 2\nmodel = \"plane_strain\"\n\
        [[materials]]\nname = \"m\"\nyoung = 100.0\npoisson = 0.3\n\
        [[bodies]]\nname = \"block\"\nmaterial = \"m\"\n\
        mesh = { generator = \"rectangle\", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [8, 4] }\n\
        [[bodies]]\nname = \"loose\"\nmaterial = \"m\"\n\
        mesh = { generator = \"rectangle\", origin = [0.0, 2.0], size = [1.0, 1.0], divisions = [4, 4] }\n\
        [[bodies]]\nname = \"floor\"\n\
        rigid = { shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }\n\
        [[boundary]]\nname = \"press\"\nbody = \"block\"\nsurface = \"top\"\n\
        displacement = { x = 0.0, y = -0.01 }\n\
        [[contact]]\nname = \"c\"\nslave = { body = \"block\", surface = \"bottom\" }\n\
        master = { body = \"floor\" }\n";
    refused_on_both_paths(
        text,
        &["body \"loose\" is free to move: 3 of its rigid motions"],
    );
}

/// Two quads of one body that meet at a single node: a hinge, which carries
/// no continuous displacement across and would leave the second quad free
/// to turn about that node. Refused when the mesh is read, on both paths,
/// naming the body's mesh and the shared node (before, the condensed path
/// refused S and the direct path solved it with a conditioning warning).
#[test]
fn a_hinged_mesh_is_refused_on_both_paths_naming_the_mesh() {
    let msh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n\
               1 1 \"bottom\"\n1 2 \"left\"\n1 3 \"top\"\n2 4 \"body\"\n$EndPhysicalNames\n\
               $Nodes\n7\n1 0 1 0\n2 1 1 0\n3 1 2 0\n4 0 2 0\n5 1 0 0\n6 2 0 0\n7 2 1 0\n$EndNodes\n\
               $Elements\n6\n1 1 2 1 1 5 6\n2 1 2 2 2 4 1\n3 1 2 3 3 7 2\n4 1 2 3 3 3 4\n\
               5 3 2 4 4 1 2 3 4\n6 3 2 4 4 5 6 7 2\n$EndElements\n";
    let rest = [
        on("left", "displacement = { x = 0.0, y = 0.0 }"),
        on("top", "traction = [0.0, -100.0]"),
        on_ground("bottom"),
    ]
    .concat();
    let text = scene("hinge", 2, msh, &rest);
    refused_on_both_paths(
        &text,
        &[
            "bodies[0].mesh",
            "share the node at [1.0, 1.0, 0.0]",
            "non-conforming",
        ],
    );
}

/// Three rectangles in one body (a Gmsh mesh of three pieces), each held in
/// x on its left side, pressed onto the ground: split into fewer
/// subdomains than pieces (whole pieces dealt out), as many, and more
/// (pieces split in proportion to their cells), the condensed path agrees
/// with the direct path to 1e-9 and each contact carries its piece's load.
/// It was refused: "the cells do not form one connected piece".
#[test]
fn a_body_of_several_pieces_splits_into_subdomains() {
    let msh = gmsh(
        2,
        &[
            rectangle("a", 0.0, [2.0, 1.0], [4, 2], 1),
            rectangle("b", 10.0, [1.5, 0.75], [5, 3], 101),
            rectangle("c", 20.0, [3.0, 1.0], [9, 3], 201),
        ],
    );
    let rest = [
        on("left_a", "displacement = { x = 0.0 }"),
        on("left_b", "displacement = { x = 0.0 }"),
        on("left_c", "displacement = { x = 0.0 }"),
        on("top_a", "traction = [0.0, -100.0]"),
        on("top_b", "traction = [30.0, -250.0]"),
        on("top_c", "traction = [0.0, -10.0]"),
        on_ground("bottom_a"),
        on_ground("bottom_b"),
        on_ground("bottom_c"),
    ]
    .concat();
    for n in [2, 3, 5, 8] {
        let text = scene(&format!("pieces_{n}"), 2, &msh, &rest).replace(
            "mesh = { file",
            &format!("subdomains = {n}\nmesh = {{ file"),
        );
        assert!(text.contains(&format!("subdomains = {n}")));
        condensed_equals_direct(
            &text,
            &[("bottom_a", 200.0), ("bottom_b", 375.0), ("bottom_c", 30.0)],
        );
        let out = converged_on(&text, SolvePath::Condensed);
        assert_eq!(out.report.subdomains, n);
    }
}
