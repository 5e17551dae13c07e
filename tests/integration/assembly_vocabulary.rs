//! The vocabulary of assemblies: bodies read from one Gmsh file by their
//! physical volume, forces on a point or a node set, tied surfaces with
//! non-matching meshes, and a friction coefficient changed by a load step
//! (docs/reference/scene-format.md, "Assemblies"; docs/theory/mortar.md,
//! "Ties").

use super::common::bad_scene::assert_edits_refused;
use super::common::{
    block_body, block_contact, boundary, contact_between, converged, converged_on, elastic_body,
    example_with_meshes, material_head, named_block_boundary, rigid_plane,
};
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, RunOutput};

const E: f64 = 1000.0;
const NU: f64 = 0.3;

/// Two blocks of one material, the upper tied to the lower (non-matching
/// meshes, `lower` and `upper` the generators), pulled by a uniform traction
/// `t` on the upper's top; the lower on rollers at its bottom (and the
/// faces x = 0, y = 0 in 3D), pinned in x at the origin in 2D.
pub(super) fn tied_blocks(dim: usize, lower: &str, upper: &str, t: f64) -> String {
    let (model, top, supports) = if dim == 2 {
        (
            "plane_strain",
            format!("surface = \"top\"\ntraction = [0.0, {t}]"),
            "[[boundary]]\nbody = \"lower\"\nsurface = \"bottom\"\ndisplacement = { y = 0.0 }\n\
             [[boundary]]\nbody = \"lower\"\npoint = [0.0, 0.0]\ndisplacement = { x = 0.0 }\n",
        )
    } else {
        (
            "solid",
            format!("surface = \"zmax\"\ntraction = [0.0, 0.0, {t}]"),
            "[[boundary]]\nbody = \"lower\"\nsurface = \"zmin\"\ndisplacement = { z = 0.0 }\n\
             [[boundary]]\nbody = \"lower\"\nsurface = \"xmin\"\ndisplacement = { x = 0.0 }\n\
             [[boundary]]\nbody = \"lower\"\nsurface = \"ymin\"\ndisplacement = { y = 0.0 }\n",
        )
    };
    let (bottom, top_face) = if dim == 2 {
        ("bottom", "top")
    } else {
        ("zmin", "zmax")
    };
    [
        material_head(dim, model, E, NU),
        elastic_body("lower", lower),
        elastic_body("upper", upper),
        supports.to_string(),
        format!("[[boundary]]\nbody = \"upper\"\n{top}\n"),
        contact_between("bond", ("upper", bottom), ("lower", top_face)),
        "law = \"tied\"\n".to_string(),
    ]
    .concat()
}

/// The largest error of every node's displacement against the uniform
/// stress state σ = t along the last axis (the monolithic answer: a linear
/// field, which any mesh of the two blocks holds exactly), relative to the
/// largest displacement.
pub(super) fn patch_error(out: &RunOutput, dim: usize, t: f64) -> f64 {
    // plane strain: ε_yy = (1 − ν²) t / E, ε_xx = −ν (1 + ν) t / E; solid:
    // ε_zz = t / E, ε_xx = ε_yy = −ν t / E
    let (along, across) = if dim == 2 {
        ((1.0 - NU * NU) * t / E, -NU * (1.0 + NU) * t / E)
    } else {
        (t / E, -NU * t / E)
    };
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    for b in &out.bodies {
        let u = &b.last().displacement;
        for (n, x) in b.coords.iter().enumerate() {
            for k in 0..dim {
                let exact = x[k] * if k == dim - 1 { along } else { across };
                err = err.max((u[n * dim + k] - exact).abs());
                scale = scale.max(exact.abs());
            }
        }
    }
    err / scale
}

#[test]
fn two_blocks_tied_with_non_matching_meshes_pass_the_patch_test_on_both_paths_2d() {
    let lower = r#"{ generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 1.0], divisions = [3, 3] }"#;
    let upper = r#"{ generator = "rectangle", origin = [0.0, 1.0], size = [1.0, 1.0], divisions = [5, 4], element = "tri3" }"#;
    // a tension: a unilateral contact would open, the tie holds
    let text = tied_blocks(2, lower, upper, 2.0);
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let out = converged_on(&text, path);
        let err = patch_error(&out, 2, 2.0);
        assert!(err <= 1e-10, "{path:?}: patch test error {err:e}");
    }
    // the same with the blocks split in METIS parts (S over the tree)
    let split = text.replace("material = \"m\"\n", "material = \"m\"\nsubdomains = 3\n");
    let err = patch_error(&converged_on(&split, SolvePath::Condensed), 2, 2.0);
    assert!(
        err <= 1e-10,
        "three parts per body: patch test error {err:e}"
    );
}

#[test]
fn a_tie_between_coincident_nodes_joins_them() {
    let lower = r#"{ generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 1.0], divisions = [3, 3] }"#;
    let upper = r#"{ generator = "rectangle", origin = [0.0, 1.0], size = [1.0, 1.0], divisions = [3, 2] }"#;
    let out = converged_on(&tied_blocks(2, lower, upper, 2.0), SolvePath::Condensed);
    let err = patch_error(&out, 2, 2.0);
    assert!(err <= 1e-10, "patch test error {err:e}");
    // each node of the upper block's bottom moves with the lower block's
    // node at the same place
    let (lo, up) = (&out.bodies[0], &out.bodies[1]);
    let mut joined = 0;
    for (n, x) in up.coords.iter().enumerate().filter(|(_, x)| x[1] == 1.0) {
        let m = lo.coords.iter().position(|y| y == x).unwrap();
        for k in 0..2 {
            let (a, b) = (
                up.last().displacement[2 * n + k],
                lo.last().displacement[2 * m + k],
            );
            assert!(
                (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-3),
                "{x:?}: {a:e} {b:e}"
            );
        }
        joined += 1;
    }
    assert_eq!(joined, 4);
}

#[test]
fn two_blocks_tied_with_non_matching_meshes_pass_the_patch_test_on_both_paths_3d() {
    let lower = r#"{ generator = "box", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 1.0], divisions = [2, 2, 2] }"#;
    let upper = r#"{ generator = "box", origin = [0.0, 0.0, 1.0], size = [1.0, 1.0, 1.0], divisions = [3, 3, 2], element = "tet4" }"#;
    let text = tied_blocks(3, lower, upper, -2.0);
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let out = converged_on(&text, path);
        let err = patch_error(&out, 3, -2.0);
        assert!(err <= 1e-10, "{path:?}: patch test error {err:e}");
    }
}

#[test]
fn two_volumes_of_one_gmsh_file_tied_equal_the_analytic_answer() {
    let dir = format!("{}/tests/data", env!("CARGO_MANIFEST_DIR"));
    let text = tied_blocks(
        2,
        &format!("{{ file = \"{dir}/tied_blocks_2d.msh\", volume = \"lower\" }}"),
        &format!("{{ file = \"{dir}/tied_blocks_2d.msh\", volume = \"upper\" }}"),
        2.0,
    )
    .replace("surface = \"bottom\" }", "surface = \"upper_bottom\" }")
    .replace("surface = \"top\" }", "surface = \"lower_top\" }")
    .replace("surface = \"bottom\"", "surface = \"lower_bottom\"")
    .replace("surface = \"top\"", "surface = \"upper_top\"");
    let out = converged_on(&text, SolvePath::Condensed);
    // each body holds the nodes of its own physical surface alone: the two
    // share none, though their faces at y = 1 coincide
    assert_eq!(out.bodies.len(), 2);
    let n: Vec<usize> = out.bodies.iter().map(|b| b.coords.len()).collect();
    assert!(n[0] > 0 && n[1] > 0 && n[0] != n[1], "{n:?}");
    let err = patch_error(&out, 2, 2.0);
    assert!(err <= 1e-10, "patch test error {err:e}");
}

/// A block clamped at its bottom with a force `force` on `place` at its top.
fn block_with_force(place: &str, force: &str) -> String {
    [
        material_head(2, "plane_strain", E, NU),
        block_body([0.0, 0.0], [2.0, 1.0], [4, 2], ""),
        named_block_boundary(
            "clamp",
            "surface = \"bottom\"",
            "displacement = { x = 0.0, y = 0.0 }",
        ),
        named_block_boundary("load", place, &format!("force = {force}")),
    ]
    .concat()
}

#[test]
fn a_point_load_is_balanced_by_the_reaction_on_both_paths() {
    let text = block_with_force("point = [1.0, 1.0]", "[0.3, -1.0]");
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let out = converged_on(&text, path);
        let r = &out.report.steps[0].reactions[0];
        assert_eq!(r.boundary, "clamp");
        for (k, f) in [0.3, -1.0].iter().enumerate() {
            assert!(
                (r.force[k] + f).abs() <= 1e-10,
                "{path:?}: reaction {:?}",
                r.force
            );
        }
    }
}

#[test]
fn a_force_on_a_node_set_is_a_total_shared_equally() {
    // the physical point group "top_corners" of the upper block: two nodes,
    // half the force each; the reaction of the lower block's support
    // balances the whole force through the tie
    let dir = format!("{}/tests/data", env!("CARGO_MANIFEST_DIR"));
    let volume = |v: &str| format!("{{ file = \"{dir}/tied_blocks_2d.msh\", volume = \"{v}\" }}");
    let text = [
        material_head(2, "plane_strain", E, NU),
        elastic_body("lower", &volume("lower")),
        elastic_body("upper", &volume("upper")),
        boundary(
            "clamp",
            "lower",
            "surface = \"lower_bottom\"",
            "displacement = { x = 0.0, y = 0.0 }",
        ),
        boundary(
            "pull",
            "upper",
            "nodes = \"top_corners\"",
            "force = [0.0, 4.0]",
        ),
        contact_between("bond", ("upper", "upper_bottom"), ("lower", "lower_top")),
        "law = \"tied\"\n".to_string(),
    ]
    .concat();
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let out = converged_on(&text, path);
        let r = &out.report.steps[0].reactions[0];
        assert!(
            r.force[0].abs() <= 1e-10 && (r.force[1] + 4.0).abs() <= 1e-10,
            "{path:?}: reaction {:?}",
            r.force
        );
        // equal shares on a block symmetric but for its unstructured mesh:
        // the corners move alike (one node loaded alone would move far more)
        let upper = &out.bodies[1];
        let corner = |x: f64| {
            let n = (upper.coords.iter())
                .position(|c| (c[0] - x).abs() < 1e-12 && (c[1] - 2.0).abs() < 1e-12)
                .unwrap();
            upper.last().displacement[2 * n + 1]
        };
        let (a, b) = (corner(0.0), corner(1.0));
        assert!(
            a > 0.0 && (a - b).abs() <= 1e-2 * a,
            "{path:?}: corners {a:e}, {b:e}"
        );
    }
}

/// A block pressed on a rigid plane by its top and dragged along x by
/// `drag`, Coulomb μ = 0.5; step 2 lowers μ to 0.1 under the same load.
fn dragged_block(drag: f64) -> String {
    [
        material_head(2, "plane_strain", E, NU),
        block_body([0.0, 0.0], [1.0, 0.5], [6, 3], ""),
        rigid_plane("ground", [0.0, 0.0], [0.0, 1.0]),
        named_block_boundary(
            "press",
            "surface = \"top\"",
            &format!("displacement = {{ x = {drag}, y = -0.01 }}"),
        ),
        block_contact("slide", "bottom", "ground"),
        "friction = { coulomb = 0.5 }\n[[steps]]\nscale = { press = 1.0 }\n\
         [[steps]]\nfriction = { slide = { coulomb = 0.1 } }\n"
            .to_string(),
    ]
    .concat()
}

#[test]
fn a_block_that_sticks_at_mu_0_5_slips_when_a_step_lowers_mu_to_0_1() {
    let out = converged(&dragged_block(0.005), RunOptions::default());
    let steps = &out.report.steps;
    let ratio = |s: usize| steps[s].tangential_force.abs() / steps[s].normal_force;
    // step 1: every point sticks, the friction force below μ N
    assert_eq!(steps[0].slipping, 0, "step 1: {:?}", steps[0]);
    assert!(steps[0].sticking > 0);
    assert!(
        ratio(0) < 0.5 && ratio(0) > 0.1,
        "step 1: T/N = {}",
        ratio(0)
    );
    // step 2, the same load, μ = 0.1: the points slide, each on its cone
    // |λ_t| = 0.1 λ_n (Coulomb), none beyond it, and the friction force drops
    assert!(steps[1].slipping > 0, "step 2: {:?}", steps[1]);
    for r in out.contact_rows.iter().filter(|r| r.step == 2) {
        let (t, n) = (r.tangential_force.abs(), r.normal_force);
        assert!(t <= 0.1 * n + 1e-9 * n.max(1.0), "{r:?}");
        if r.status.starts_with("slip") {
            assert!((t - 0.1 * n).abs() <= 1e-8 * n.max(1.0), "{r:?}");
        }
    }
    assert!(
        ratio(1) <= 0.1 + 1e-9 && ratio(1) < ratio(0),
        "T/N {} then {}",
        ratio(0),
        ratio(1)
    );
    let slip = |s: usize| {
        (out.contact_rows.iter())
            .filter(|r| r.step == s)
            .fold(0.0f64, |m, r| m.max(r.slip.abs()))
    };
    assert!(slip(1) <= 1e-12, "step 1 slips {}", slip(1));
    assert!(slip(2) > 1e-6, "step 2 does not slip: {}", slip(2));
}

#[test]
fn three_bodies_from_one_gmsh_file_with_a_tie_a_node_set_force_and_friction() {
    let text = example_with_meshes("assembly_one_file.toml");
    {
        let out = converged_on(&text, SolvePath::Condensed);
        let last = out.report.steps.last().unwrap();
        let force = |name: &str| {
            (last.reactions.iter())
                .find(|r| r.boundary == name)
                .unwrap()
                .force
                .clone()
        };
        let (clamp, press) = (force("clamp"), force("press"));
        // the bond carries the press and the pull (1 along x) to the base
        for k in 0..3 {
            let pull = if k == 0 { 1.0 } else { 0.0 };
            let sum = clamp[k] + press[k] + pull;
            assert!(sum.abs() <= 1e-9 * press[2].abs(), "component {k}: {sum:e}");
        }
        // the slider holds: its friction balances the pull
        let slide = super::common::contact_force(&out, "slide");
        assert!((slide[0] + 1.0).abs() <= 1e-9, "{slide:?}");
        // step 3 lowers μ to 0.15: more points slip (the bodies' Poisson
        // expansions differ), each on its cone |λ_t| = 0.15 λ_n
        let slipping: Vec<usize> = out.report.steps.iter().map(|s| s.slipping).collect();
        assert!(slipping[2] > slipping[1], "{slipping:?}");
        for r in out.contact_rows.iter().filter(|r| r.step == 3) {
            let t = r.tangential_force.hypot(r.tangential_force_2);
            let on_cone = (t - 0.15 * r.normal_force).abs() <= 1e-8 * r.normal_force.max(1.0);
            assert!(r.status != "slip" || on_cone, "{r:?}");
            assert!(t <= 0.15 * r.normal_force + 1e-8, "{r:?}");
        }
    }
}

#[test]
fn bad_assemblies_are_refused_naming_the_entry() {
    let asm = example_with_meshes("assembly_one_file.toml");
    let bond2 = "[[contact]]\nname = \"bond2\"\nslave = { body = \"pad\", surface = \"pad_bottom\" }\nmaster = { body = \"base\", surface = \"base_top\" }\nlaw = \"tied\"\n\n[[contact]]\nname = \"slide\"";
    #[rustfmt::skip]
    let edits: [(&str, &str, &str, &[&str]); 6] = [
        ("unknown_volume", "volume = \"pad\"", "volume = \"padd\"", &["bodies[1].mesh.volume", "\"padd\"", "\"base\", \"pad\", \"slider\""]),
        ("point_far", "nodes = \"pull\"\nforce", "point = [0.5, 0.5, 2.3]\nforce", &["boundary[2].point", "away"]),
        ("unknown_node_set", "nodes = \"pull\"\nforce", "nodes = \"push\"\nforce", &["boundary[2].nodes", "\"push\"", "\"pull\""]),
        ("tie_unknown_surface", "surface = \"pad_bottom\"", "surface = \"pad_bot\"", &["contact \"bond\".slave.surface", "pad_bot"]),
        ("tie_apart", "master = { body = \"base\", surface = \"base_top\" }", "master = { body = \"base\", surface = \"base_bottom\" }", &["contact \"bond\"", "does not face the master"]),
        ("tie_overlapping", "[[contact]]\nname = \"slide\"", bond2, &["contact \"bond2\"", "overlaps", "contact \"bond\""]),
    ];
    assert_edits_refused("assembly", &asm, &edits);
}

#[test]
fn a_step_friction_of_another_kind_or_contact_is_refused() {
    #[rustfmt::skip]
    let edits: [(&str, &str, &str, &[&str]); 2] = [
        ("step_friction_unknown_contact", "friction = { slide = {", "friction = { slid = {", &["steps[1].friction.slid", "\"slide\""]),
        ("step_friction_kind", "{ slide = { coulomb = 0.1 } }", "{ slide = { tresca = 0.1 } }", &["steps[1].friction.slide", "kind"]),
    ];
    assert_edits_refused("assembly", &dragged_block(0.005), &edits);
}

/// What the direct path leaves to the condensed path, refused there as bad
/// input naming the entry before anything is built (and taken by `auto` to
/// the condensed path, not to a refusal): a friction law changed by a load
/// step, and friction beside a tied contact. The dragged block with one μ
/// for both steps has the condensed forces on the direct path.
#[test]
fn step_friction_and_friction_beside_ties_are_left_to_the_condensed_path() {
    use super::common::twins::{on_both_paths, refused_on_direct};
    let stepped = dragged_block(0.005);
    refused_on_direct(&stepped, &["steps[1].friction"]);
    let one_mu = stepped.replace(
        "friction = { slide = { coulomb = 0.1 } }\n",
        "scale = { press = 1.0 }\n",
    );
    assert_ne!(one_mu, stepped);
    on_both_paths(&one_mu, 1e-8);
    let tied = example_with_meshes("assembly_one_file.toml");
    refused_on_direct(&tied, &["contact \"bond\"", "tied"]);
}
