//! Friction where supports meet contacts, and bodies held by friction whose
//! contacts start open:
//! - a tangential row whose slip a support prescribes (a symmetry plane, the
//!   axis r = 0) carries a support reaction, not a friction unknown: half
//!   and quarter models with symmetry planes give the full model's forces;
//! - a pad pressed onto a plane across an initial gap and held sideways by
//!   friction alone (Code_Aster SSNV503) solves under displacement and force
//!   control, in 2D and 3D, by the fixed point and the status method;
//! - the friction-capacity pre-check counts every contact of a body;
//! - an axisymmetric contact force has no radial component.

use crate::common;

use common::{contact_force, converged, example, try_run};
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, RunOutput};

fn run(text: &str) -> signorini_solver::RunOutput {
    converged(text, RunOptions::default())
}

/// A block (2D: `[[x0, y0], [w, h]]`, 3D with a z extent) on the rigid plane
/// through the origin with normal `normal`, Coulomb μ, its top loaded by
/// `top` (a boundary entry body) and extra `boundary` entries.
#[allow(clippy::too_many_arguments)] // a scene template: one argument per scene entry
fn block(
    dim: usize,
    origin: &[f64],
    size: &[f64],
    div: &[usize],
    normal: &[f64],
    mu: f64,
    top: &str,
    extra: &str,
    friction_solver: &str,
) -> String {
    let v = |x: &[f64]| format!("{x:?}");
    let (model, top_face, bottom, disc) = if dim == 2 {
        ("plane_strain", "top", "bottom", "node_to_segment")
    } else {
        ("solid", "zmax", "zmin", "node_to_face")
    };
    let generator = if dim == 2 { "rectangle" } else { "box" };
    let point = vec![0.0; dim];
    format!(
        r#"{}{}[[bodies]]
name = "ground"
rigid = {{ shape = "plane", point = {}, normal = {} }}
[[boundary]]
name = "top"
body = "pad"
surface = "{top_face}"
{top}
{extra}
{}discretization = "{disc}"
friction = {{ coulomb = {mu} }}
[solver]
method = "status"
path = "condensed"
friction = "{friction_solver}"
"#,
        common::material_head(dim, model, 1000.0, 0.3),
        common::elastic_body(
            "pad",
            &format!(
                "{{ generator = \"{generator}\", origin = {}, size = {}, divisions = {div:?} }}",
                v(origin),
                v(size)
            )
        ),
        v(&point),
        v(normal),
        common::contact("c", "pad", bottom, "ground")
    )
}

fn symmetry(surface: &str, axis: &str) -> String {
    format!("[[boundary]]\nname = \"sym-{surface}\"\nbody = \"pad\"\nsurface = \"{surface}\"\ndisplacement = {{ {axis} = 0.0 }}\n")
}

#[test]
fn a_quarter_model_with_symmetry_planes_gives_a_quarter_of_the_full_force() {
    // The box expands sideways under the press; friction holds it. Nodes on
    // a symmetry plane keep one tangent, the corner node on both keeps none.
    let press = "displacement = { x = 0.0, y = 0.0, z = -0.02 }";
    let full = block(
        3,
        &[-1.0, -1.0, 0.0],
        &[2.0, 2.0, 0.5],
        &[8, 8, 2],
        &[0.0, 0.0, 1.0],
        0.2,
        press,
        "",
        "fixed_point",
    );
    let sym = symmetry("xmin", "x") + &symmetry("ymin", "y");
    let quarter = block(
        3,
        &[0.0, 0.0, 0.0],
        &[1.0, 1.0, 0.5],
        &[4, 4, 2],
        &[0.0, 0.0, 1.0],
        0.2,
        press,
        &sym,
        "fixed_point",
    );
    let f = run(&full).report.contact_force[2];
    let q = run(&quarter);
    let fq = q.report.contact_force[2];
    assert!(f > 0.0);
    assert!(
        (4.0 * fq - f).abs() <= 1e-8 * f,
        "quarter ×4 {} vs full {f}",
        4.0 * fq
    );
    // Friction is active: some points slip, and the tangential force at the
    // quarter's outer corner points inwards (it resists the expansion).
    assert!(q.contact_rows.iter().any(|r| r.status == "slip"));
    let corner = q
        .contact_rows
        .iter()
        .find(|r| r.x[0] >= 1.0 - 1e-12 && r.x[1] >= 1.0 - 1e-12)
        .expect("the outer corner is a contact point");
    assert!(corner.tangential_force.abs() + corner.tangential_force_2.abs() > 0.0);
}

#[test]
fn a_half_model_with_a_symmetry_plane_gives_half_of_the_full_force_in_2d() {
    let press = "displacement = { x = 0.0, y = -0.02 }";
    for solver in ["fixed_point", "status"] {
        let full = block(
            2,
            &[-1.0, 0.0],
            &[2.0, 0.5],
            &[16, 4],
            &[0.0, 1.0],
            0.2,
            press,
            "",
            solver,
        );
        let half = block(
            2,
            &[0.0, 0.0],
            &[1.0, 0.5],
            &[8, 4],
            &[0.0, 1.0],
            0.2,
            press,
            &symmetry("left", "x"),
            solver,
        );
        let f = run(&full).report.contact_force[1];
        let h = run(&half).report.contact_force[1];
        assert!(
            (2.0 * h - f).abs() <= 1e-8 * f,
            "{solver}: half ×2 {} vs full {f}",
            2.0 * h
        );
    }
}

#[test]
fn the_axisymmetric_hertz_sphere_with_friction_solves() {
    let frictionless = example("hertz_axi.toml").replace("divisions = 80", "divisions = 40");
    let with = |mu: f64| {
        frictionless.replace(
            "discretization = \"node_to_segment\"",
            &format!("discretization = \"node_to_segment\"\nfriction = {{ coulomb = {mu} }}"),
        )
    };
    let p0 = run(&frictionless).report.contact_force[1];
    let p_mu = run(&with(0.3));
    let p1 = p_mu.report.contact_force[1];
    let p_stick = run(&with(1e3)).report.contact_force[1];
    // Friction holds the surface's inward motion: the load at the same
    // approach rises a little, at most to that of full adhesion.
    assert!(
        p1 > p0 && p1 <= p_stick * (1.0 + 1e-9),
        "{p0} {p1} {p_stick}"
    );
    assert!(
        (p1 - p0) / p0 <= 0.02,
        "friction changed the load by {}",
        (p1 - p0) / p0
    );
    // A ring has no net radial force.
    assert_eq!(p_mu.report.contact_force[0], 0.0);
    assert_eq!(p_mu.report.contacts[0].force[0], 0.0);
    assert!(p_mu.report.steps.iter().all(|s| s.contact_force[0] == 0.0));
}

/// 2D pad 1 × 0.5 starting 0.05 above the plane; x is held by friction only.
fn gap_pad(dim: usize, normal: &[f64], top: &str, solver: &str) -> String {
    if dim == 2 {
        block(
            2,
            &[0.0, 0.05],
            &[1.0, 0.5],
            &[8, 4],
            normal,
            0.5,
            top,
            "",
            solver,
        )
    } else {
        block(
            3,
            &[0.0, 0.0, 0.05],
            &[1.0, 1.0, 0.5],
            &[4, 4, 2],
            normal,
            0.5,
            top,
            "",
            solver,
        )
    }
}

#[test]
fn a_pad_pressed_across_a_gap_onto_a_flat_and_held_by_friction_solves() {
    // Uniform compression: closing the gap takes 0.05 of the 0.2 approach,
    // so the force is 3/4 of the force without a gap.
    for solver in ["fixed_point", "status"] {
        let gap = gap_pad(2, &[0.0, 1.0], "displacement = { y = -0.2 }", solver);
        let no_gap = gap.replace("origin = [0.0, 0.05]", "origin = [0.0, 0.0]");
        let fg = run(&gap).report.contact_force[1];
        let f0 = run(&no_gap).report.contact_force[1];
        assert!(
            (fg - 0.75 * f0).abs() <= 1e-8 * f0,
            "{solver}: {fg} vs 3/4 of {f0}"
        );
    }
}

#[test]
fn a_pad_on_an_inclined_plane_across_a_gap_is_held_by_friction() {
    // SSNV503-like: the plane's slope 0.1 is below μ = 0.5, so friction holds
    // the pad; the contact forces balance the load exactly.
    let incline2 = [0.1, 1.0];
    let incline3 = [0.1, 0.0, 1.0];
    for solver in ["fixed_point", "status"] {
        let o = run(&gap_pad(2, &incline2, "traction = [0.0, -10.0]", solver));
        assert!((o.report.contact_force[1] - 10.0).abs() <= 1e-9 * 10.0);
        assert!(o.report.contact_force[0].abs() <= 1e-9 * 10.0);
        assert!(o.contact_rows.iter().any(|r| r.tangential_force != 0.0));
        let d = run(&gap_pad(
            2,
            &incline2,
            "displacement = { y = -0.2 }",
            solver,
        ));
        // The top is pushed straight down, x is free: no net x force.
        assert!(d.report.contact_force[0].abs() <= 1e-9 * d.report.contact_force[1]);
        assert!(d.report.contact_force[1] > 0.0);
    }
    let o = run(&gap_pad(
        3,
        &incline3,
        "traction = [0.0, 0.0, -10.0]",
        "fixed_point",
    ));
    assert!((o.report.contact_force[2] - 10.0).abs() <= 1e-9 * 10.0);
    let d = run(&gap_pad(
        3,
        &incline3,
        "displacement = { z = -0.2 }",
        "fixed_point",
    ));
    assert!(d.report.contact_force[0].abs() <= 1e-9 * d.report.contact_force[2]);
}

/// A block on a floor (μ = 0.2) loaded by N = 10 down and pushed sideways
/// by 8 × 0.5 = 4 > μN against a frictionless rigid `wall`.
fn pushed_block(wall: &str, friction_solver: &str) -> String {
    let extra = format!(
        r#"
[[bodies]]
name = "wall"
rigid = {wall}
[[contact]]
name = "w"
slave = {{ body = "pad", surface = "right" }}
master = {{ body = "wall" }}
[[boundary]]
name = "push"
body = "pad"
surface = "left"
traction = [8.0, 0.0]
"#
    );
    pad_on_floor(&extra, friction_solver)
}

/// The block of `pushed_block` on its floor (μ = 0.2, N = 10 down), with
/// `extra` appended.
fn pad_on_floor(extra: &str, friction_solver: &str) -> String {
    block(
        2,
        &[0.0, 0.0],
        &[1.0, 0.5],
        &[8, 4],
        &[0.0, 1.0],
        0.2,
        "traction = [0.0, -10.0]",
        extra,
        friction_solver,
    )
}

/// Asserts the balance of `pushed_block`'s answer (the floor carries N =
/// 10 and at most μN = 2 sideways, the wall the rest of the push of 4);
/// returns the wall's force.
fn held_by_floor_and_wall(o: &RunOutput, what: &str) -> f64 {
    let f = &o.report.contact_force;
    assert!((f[0] + 4.0).abs() <= 1e-9 * 10.0, "{what}: {f:?}");
    assert!((f[1] - 10.0).abs() <= 1e-9 * 10.0, "{what}: {f:?}");
    let floor = contact_force(o, "c")[0];
    assert!(
        floor.abs() <= 0.2 * 10.0 * (1.0 + 1e-9),
        "{what}: friction within μN: {floor}"
    );
    let w = contact_force(o, "w")[0];
    assert!(
        w <= -2.0 * (1.0 - 1e-9),
        "{what}: the wall takes at least 4 − μN: {w}"
    );
    assert!(
        (floor + w + 4.0).abs() <= 1e-9 * 10.0,
        "{what}: floor {floor} and wall {w} balance the push"
    );
    w
}

#[test]
fn the_friction_capacity_check_counts_a_frictionless_wall() {
    // The wall takes what friction does not: in equilibrium, not refused.
    // A disc touching the block's side at mid-height, and a flat wall whose
    // contact shares the block's corner node with the floor's (the corner's
    // slip along the floor is the wall's gap: one constraint, not two).
    let disc = r#"{ shape = "circle", center = [1.5, 0.25], radius = 0.5 }"#;
    let flat = r#"{ shape = "plane", point = [1.0, 0.0], normal = [-1.0, 0.0] }"#;
    for wall in [disc, flat] {
        let mut wall_forces = Vec::new();
        for solver in ["fixed_point", "status"] {
            let o = run(&pushed_block(wall, solver));
            wall_forces.push(held_by_floor_and_wall(&o, &format!("{wall} {solver}")));
        }
        assert!(
            (wall_forces[0] - wall_forces[1]).abs() <= 1e-6 * 4.0,
            "{wall}: {wall_forces:?}"
        );
        // The direct path: the flat wall's corner node is held along x twice
        // (its floor friction sticking, the wall), the Newton matrix singular
        // however the forces split; it solves it with its redundant-rows
        // shift. The split at that node is not unique, the balance is.
        let d = common::converged_on(&pushed_block(wall, "fixed_point"), SolvePath::Direct);
        held_by_floor_and_wall(&d, &format!("{wall} direct"));
    }
    // Without the wall, the same push beyond μN is refused (exit 1).
    let push = "[[boundary]]\nname = \"push\"\nbody = \"pad\"\nsurface = \"left\"\ntraction = [8.0, 0.0]\n";
    let alone = pad_on_floor(push, "fixed_point");
    let err = try_run(&alone, RunOptions::default())
        .err()
        .expect("refused");
    assert!(
        err.to_string().contains("exceeds what friction can hold"),
        "{err}"
    );
}

/// A block pressed by a displacement of its top (free in x) and pushed
/// sideways on its left face, held in x by friction alone: under the
/// friction it carries it converges; pushed past it (3 against
/// μN ≈ 2 at the last iterate) there is no static equilibrium, the friction
/// solve stops (exit 2), and the failure says which body and what to do
/// (it said only that the inner Tresca problem cycled).
#[test]
fn a_body_pushed_past_its_friction_under_displacement_control_says_why() {
    let text = |push: f64| {
        format!(
            "dimension = 2\nmodel = \"plane_strain\"\n\
             [[materials]]\nname = \"m\"\nyoung = 100.0\npoisson = 0.3\n\
             [[bodies]]\nname = \"block\"\nmaterial = \"m\"\n\
             mesh = {{ generator = \"rectangle\", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [8, 4] }}\n\
             [[bodies]]\nname = \"floor\"\n\
             rigid = {{ shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }}\n\
             [[boundary]]\nname = \"press\"\nbody = \"block\"\nsurface = \"top\"\ndisplacement = {{ y = -0.01 }}\n\
             [[boundary]]\nname = \"push\"\nbody = \"block\"\nsurface = \"left\"\ntraction = [{push:e}, 0.0]\n\
             [[contact]]\nname = \"c\"\nslave = {{ body = \"block\", surface = \"bottom\" }}\n\
             master = {{ body = \"floor\" }}\nfriction = {{ coulomb = 0.5 }}\n"
        )
    };
    let held = run(&text(1.0));
    assert!((contact_force(&held, "c")[0] + 1.0).abs() <= 1e-9);
    let out = try_run(&text(3.0), RunOptions::default()).unwrap();
    assert!(!out.report.converged);
    let failure = out.report.failure.unwrap();
    assert!(
        failure.contains("body \"block\" is held by friction alone in 1 rigid motion(s)"),
        "{failure}"
    );
}

/// The same block pushed within its friction (1 against μN ≈ 2), each
/// friction solver cut off by `max_iterations = 1`: exit 2 saying to raise
/// the limit. Found by the fifth robustness sweep: the failure had no advice
/// but the note above, which blames a load beyond friction (and said so on
/// a first step with no tangential load at all).
#[test]
fn a_friction_step_out_of_iterations_says_to_raise_the_limit() {
    let text = "dimension = 2\nmodel = \"plane_strain\"\n\
         [[materials]]\nname = \"m\"\nyoung = 100.0\npoisson = 0.3\n\
         [[bodies]]\nname = \"block\"\nmaterial = \"m\"\n\
         mesh = { generator = \"rectangle\", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [8, 4] }\n\
         [[bodies]]\nname = \"floor\"\n\
         rigid = { shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }\n\
         [[boundary]]\nname = \"press\"\nbody = \"block\"\nsurface = \"top\"\ndisplacement = { y = -0.01 }\n\
         [[boundary]]\nname = \"push\"\nbody = \"block\"\nsurface = \"left\"\ntraction = [1.0, 0.0]\n\
         [[contact]]\nname = \"c\"\nslave = { body = \"block\", surface = \"bottom\" }\n\
         master = { body = \"floor\" }\nfriction = { coulomb = 0.5 }\n";
    for friction in ["fixed_point", "status"] {
        let scene = format!("{text}[solver]\nmax_iterations = 1\nfriction = \"{friction}\"\n");
        let out = try_run(&scene, RunOptions::default()).unwrap();
        assert!(!out.report.converged, "{friction}");
        let failure = out.report.failure.unwrap();
        assert!(
            failure.contains("iteration limit 1 reached")
                && failure.ends_with("; raise [solver] max_iterations")
                && !failure.contains("held by friction alone"),
            "{friction}: {failure}"
        );
    }
}

/// A block dragged past μN by its left face, whose bottom corner is a
/// contact node: that node's slip is prescribed, so it has no friction
/// unknown; dragged, it slides, and Coulomb's law gives its force −μ λ_n
/// along the drag (status `slip`), so the friction reaction is μN. Found by
/// a sweep of unseen scenes: the sliding_block reference took that node for
/// a sticking one and compared the reaction with itself; then the node had
/// status `contact` and no force, and the reaction fell short of μN by μ
/// times its normal force (3.9 %).
#[test]
fn sliding_block_reference_compares_a_dragged_block_with_mu_n() {
    let mu = 0.35;
    let out = run(&dragged_block());
    let q = &out.report.reference.as_ref().unwrap().quantities;
    let n = q["normal_load"].computed;
    let t = &q["tangential_reaction"];
    assert!(
        (t.exact - mu * n).abs() <= 1e-12 * n,
        "{t:?} against μN = {}",
        mu * n
    );
    let last: Vec<_> = out.contact_rows.iter().filter(|r| r.step == 2).collect();
    let dragged = last
        .iter()
        .find(|r| r.x[0] == 0.0)
        .expect("the dragged corner");
    assert_eq!(dragged.status, "slip");
    // The tangent of the plane of normal +y is +x: the drag is +x.
    let expected = -mu * dragged.normal_force;
    assert!(
        (dragged.tangential_force - expected).abs() <= 1e-12 * expected.abs(),
        "{} against −μ N_corner = {expected}",
        dragged.tangential_force
    );
    let drag = 0.05;
    assert!(
        (dragged.slip - drag).abs() <= 1e-12 * drag,
        "{}",
        dragged.slip
    );
    assert!(last
        .iter()
        .filter(|r| r.normal_force > 0.0)
        .all(|r| r.status == "slip"));
    assert!(
        (t.computed - t.exact).abs() <= 1e-9 * t.exact,
        "reaction {} against μN {}",
        t.computed,
        t.exact
    );
    assert!(t.relative_error <= 1e-9, "{t:?}");
    // Step 1 holds the corner (no drag): it stays in contact, with no force.
    let held = out
        .contact_rows
        .iter()
        .find(|r| r.step == 1 && r.x[0] == 0.0)
        .expect("the corner");
    assert_eq!(held.status, "contact");
    assert_eq!(held.tangential_force, 0.0);
}

/// A block pressed onto a rigid plane, then dragged by its left side
/// (Coulomb friction 0.35): the sliding block reference.
fn dragged_block() -> String {
    [
        common::material_head(2, "plane_strain", 50.0, 0.3),
        common::elastic_body(
            "blk",
            "{ generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.4], divisions = [10, 4] }",
        ),
        common::rigid_plane("g", [0.0, 0.0], [0.0, 1.0]),
        common::boundary("press", "blk", "surface = \"top\"", "traction = [0.0, -2.0]"),
        common::boundary("drag", "blk", "surface = \"left\"", "displacement = { x = 0.05 }"),
        common::contact("c", "blk", "bottom", "g"),
        r#"discretization = "node_to_segment"
friction = { coulomb = 0.35 }
[[steps]]
scale = { press = 1.0, drag = 0.0 }
[[steps]]
scale = { drag = 1.0 }
[solver]
method = "status"
path = "condensed"

[reference]
kind = "sliding_block"

"#
        .to_string(),
    ]
    .concat()
}

/// The scenes of this module on the direct path: the quarter and half
/// models with symmetry planes, the axisymmetric Hertz sphere with
/// friction, the pads pressed across a gap onto a flat and an incline
/// (2D and 3D, displacement and force control) and the dragged block of the sliding-block reference
/// give the condensed path's forces, slips and displacements.
#[test]
fn the_supported_and_gapped_scenes_have_the_condensed_forces_on_the_direct_path() {
    let sym = symmetry("xmin", "x") + &symmetry("ymin", "y");
    let press3 = "displacement = { x = 0.0, y = 0.0, z = -0.02 }";
    let (o3, o2, up3, up2) = ([0.0; 3], [0.0; 2], [0.0, 0.0, 1.0], [0.0, 1.0]);
    let press2 = "displacement = { x = 0.0, y = -0.02 }";
    let mut scenes = vec![
        (
            "quarter",
            block(
                3,
                &o3,
                &[1.0, 1.0, 0.5],
                &[4, 4, 2],
                &up3,
                0.2,
                press3,
                &sym,
                "fixed_point",
            ),
        ),
        (
            "half",
            block(
                2,
                &o2,
                &[1.0, 0.5],
                &[8, 4],
                &up2,
                0.2,
                press2,
                &symmetry("left", "x"),
                "fixed_point",
            ),
        ),
    ];
    let axi = example("hertz_axi.toml")
        .replace("divisions = 80", "divisions = 40")
        .replace(
            "discretization = \"node_to_segment\"",
            "discretization = \"node_to_segment\"\nfriction = { coulomb = 0.3 }",
        );
    scenes.push(("axisymmetric", axi));
    let (incline2, incline3) = ([0.1, 1.0], [0.1, 0.0, 1.0]);
    for (name, dim, normal, top) in [
        ("gap", 2, &up2[..], "displacement = { y = -0.2 }"),
        ("incline force", 2, &incline2[..], "traction = [0.0, -10.0]"),
        (
            "incline displacement",
            2,
            &incline2[..],
            "displacement = { y = -0.2 }",
        ),
        (
            "incline force 3d",
            3,
            &incline3[..],
            "traction = [0.0, 0.0, -10.0]",
        ),
        (
            "incline displacement 3d",
            3,
            &incline3[..],
            "displacement = { z = -0.2 }",
        ),
    ] {
        scenes.push((name, gap_pad(dim, normal, top, "fixed_point")));
    }
    scenes.push(("dragged", dragged_block()));
    // The block pushed against a disc (the flat wall's split of the corner
    // node's force between the floor and the wall is not unique:
    // `the_friction_capacity_check_counts_a_frictionless_wall`).
    let disc = r#"{ shape = "circle", center = [1.5, 0.25], radius = 0.5 }"#;
    scenes.push(("pushed against a disc", pushed_block(disc, "fixed_point")));
    for (name, text) in scenes {
        eprintln!("{name}");
        common::twins::on_both_paths(&text, 1e-8);
    }
}
