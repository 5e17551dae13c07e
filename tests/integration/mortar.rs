//! Mortar contact in 2D: the contact patch test on non-matching
//! meshes with linear and quadratic edges, Hertz between two deformable
//! bodies against node-to-segment (a cylinder on a block, two cylinders),
//! every contact method, both solution paths, `mpirun -n 2`, friction, and
//! what is refused (3D:
//! tests/integration/mortar3d.rs).

use crate::common;

use common::{converged, converged_on, example, hertz_errors, max_rel, pressure_error, try_run};
use signorini_scene::{Method, SolvePath};
use signorini_solver::{RunOptions, RunOutput};

/// examples/mortar_patch.toml (soft pad, 10 elements along the interface,
/// slave; steel base, 7 elements, master) with `discretization`; with
/// `stiff_slave` the roles are swapped (the base's top is the slave).
fn patch(discretization: &str, stiff_slave: bool) -> String {
    let faces = ("bottom", "top");
    common::mortar_patch_as("mortar_patch.toml", discretization, stiff_slave, faces)
}

/// [`patch`] with the base's and the pad's elements (`quad4`, `tri3`,
/// `quad8`, `tri6`).
fn patch_with(discretization: &str, stiff_slave: bool, base: &str, pad: &str) -> String {
    patch(discretization, stiff_slave)
        .replace(
            "divisions = [7, 3] }",
            &format!("divisions = [7, 3], element = \"{base}\" }}"),
        )
        .replace(
            "divisions = [10, 4] }",
            &format!("divisions = [10, 4], element = \"{pad}\" }}"),
        )
}

#[test]
fn mortar_passes_the_patch_test_on_non_matching_meshes_and_node_to_segment_does_not() {
    // Traction 1 over a width of 2: the resultant is 2.
    for stiff_slave in [false, true] {
        let o = converged_on(&patch("mortar", stiff_slave), SolvePath::Condensed);
        let (dev, total) = pressure_error(&o, 1.0);
        assert!(
            dev <= 1e-8,
            "stiff slave {stiff_slave}: pressure off by {dev:e}"
        );
        assert!((total - 2.0).abs() <= 1e-12 * 2.0, "resultant {total}");
        let n = if stiff_slave { 8 } else { 11 };
        assert_eq!(o.contact_rows.len(), n);
        let r = &o.report.reference.as_ref().unwrap().quantities["pressure"];
        assert!(r.relative_error <= 1e-8, "{r:?}");
        // Node-to-segment on the same meshes: 0.74 % (soft slave) and 29 %
        // (stiff slave) off, with the exact resultant.
        let nts = converged_on(&patch("node_to_segment", stiff_slave), SolvePath::Condensed);
        let (dev_nts, total_nts) = pressure_error(&nts, 1.0);
        let want = if stiff_slave { 0.29 } else { 0.0074 };
        assert!(
            (dev_nts - want).abs() <= 0.01 * want,
            "node_to_segment off by {dev_nts}"
        );
        assert!((total_nts - 2.0).abs() <= 1e-12 * 2.0);
    }
}

#[test]
fn mortar_passes_the_patch_test_with_quadratic_edges() {
    // Quadratic slave and master edges, a quadratic slave on a linear
    // master and the reverse, each side as the slave: curved-capable
    // geometry, 3-node dual basis, Newton projections.
    for (base, pad) in [("quad8", "quad8"), ("quad4", "tri6"), ("tri6", "quad4")] {
        for stiff_slave in [false, true] {
            let o = converged_on(
                &patch_with("mortar", stiff_slave, base, pad),
                SolvePath::Condensed,
            );
            let (dev, total) = pressure_error(&o, 1.0);
            let case = format!("base {base}, pad {pad}, stiff slave {stiff_slave}");
            assert!(dev <= 1e-8, "{case}: pressure off by {dev:e}");
            assert!(
                (total - 2.0).abs() <= 1e-12 * 2.0,
                "{case}: resultant {total}"
            );
            // Every node of the slave edges, mid-side nodes included.
            let slave = if stiff_slave { (base, 7) } else { (pad, 10) };
            let quadratic = matches!(slave.0, "quad8" | "tri6");
            let n = if quadratic {
                2 * slave.1 + 1
            } else {
                slave.1 + 1
            };
            assert_eq!(o.contact_rows.len(), n, "{case}");
        }
    }
    // Node-to-segment on the quadratic meshes: 3.6 % (soft slave) and 85 %
    // (stiff slave) off.
    for (stiff_slave, want) in [(false, 0.036), (true, 0.85)] {
        let nts = converged_on(
            &patch_with("node_to_segment", stiff_slave, "quad8", "quad8"),
            SolvePath::Condensed,
        );
        let (dev, _) = pressure_error(&nts, 1.0);
        assert!(
            (dev - want).abs() <= 0.02 * want,
            "node_to_segment, stiff slave {stiff_slave}: off by {dev}"
        );
    }
}

#[test]
fn mortar_condensed_and_direct_paths_agree() {
    for (stiff_slave, base, pad) in [
        (false, "quad4", "quad4"),
        (true, "quad4", "quad4"),
        (false, "quad8", "tri6"),
    ] {
        let text = patch_with("mortar", stiff_slave, base, pad);
        let a = converged_on(&text, SolvePath::Condensed);
        let b = converged_on(&text, SolvePath::Direct);
        common::assert_same(&a, &b, 1e-9);
        let (dev, _) = pressure_error(&b, 1.0);
        assert!(dev <= 1e-8, "direct path: pressure off by {dev:e}");
    }
}

/// A half-disk R = 1 (arc, slave; graded towards the pole) pressed on a
/// block [−0.5, 0.5] × [−0.5, 0] of the same material (top, master; 160 × 40
/// elements), with `discretization`.
fn hertz_two_bodies(discretization: &str) -> String {
    example("hertz2d.toml")
        .replace("divisions = 160", "divisions = 80")
        .replace("displacement = { y = -0.015 }", "displacement = { y = -0.02 }")
        .replace(
            "rigid = { shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }",
            "material = \"steel\"\nmesh = { generator = \"rectangle\", origin = [-0.5, -0.5], size = [1.0, 0.5], divisions = [160, 40] }",
        )
        .replace(
            "[[contact]]",
            "[[boundary]]\nname = \"support\"\nbody = \"ground\"\nsurface = \"bottom\"\ndisplacement = { y = 0.0 }\n\n[[boundary]]\nname = \"pin-ground\"\nbody = \"ground\"\npoint = [0.0, -0.5]\ndisplacement = { x = 0.0 }\n\n[[contact]]",
        )
        .replace(
            "master = { body = \"ground\" }\ndiscretization = \"node_to_segment\"",
            &format!("master = {{ body = \"ground\", surface = \"top\" }}\ndiscretization = \"{discretization}\""),
        )
}

#[test]
fn mortar_hertz_between_two_bodies_is_at_least_as_accurate_as_node_to_segment() {
    // Measured: p0 1.7 % vs 4.5 %, profile 4.5 % vs 6.2 %, a 2.0 % vs 1.1 %.
    common::assert_mortar_at_least_as_accurate(
        hertz_two_bodies,
        "node_to_segment",
        [0.02, 0.05, 0.025],
        false,
    );
}

/// examples/mortar_cylinders.toml (radii 1 and 2, non-matching graded
/// arcs) with `discretization` and `element` on both bodies.
fn cylinders(discretization: &str, element: &str) -> String {
    example("mortar_cylinders.toml")
        .replace("\"mortar\"", &format!("\"{discretization}\""))
        .replace(
            "grading = 16.0 }",
            &format!("grading = 16.0, element = \"{element}\" }}"),
        )
        .replace(
            "grading = 24.0 }",
            &format!("grading = 24.0, element = \"{element}\" }}"),
        )
}

#[test]
fn two_cylinders_match_hertz_with_the_combined_curvature() {
    for element in ["quad4", "quad8"] {
        let text = cylinders("mortar", element);
        for g in ["16.0", "24.0"] {
            assert!(text.contains(&format!("grading = {g}, element = \"{element}\"")));
        }
        let o = converged_on(&text, SolvePath::Condensed);
        let (p0, a, l2, a_exact) = hertz_errors(&o);
        let nts = converged_on(&cylinders("node_to_segment", element), SolvePath::Condensed);
        let (p0_n, a_n, l2_n, _) = hertz_errors(&nts);
        if element == "quad8" {
            // Node-to-segment's nodal forces on quadratic edges alternate
            // between corners and mid-side nodes: profile 12 % against 2.0 %.
            assert!(
                l2 <= 0.025 && l2_n >= 4.0 * l2,
                "profile: mortar {l2}, nts {l2_n}"
            );
        }
        eprintln!("{element}: mortar p0 {p0:.4} a {a:.4}; node_to_segment p0 {p0_n:.4} a {a_n:.4}");
        // Measured: quad4 mortar p0 0.68 %, a 1.4 % (node_to_segment 0.48 %,
        // 0.90 %); quad8 mortar 0.61 %, 1.3 % (node_to_segment 0.51 %, 0.67 %).
        assert!(p0 <= 0.02 && a <= 0.02, "{element}: mortar p0 {p0}, a {a}");
        assert!(
            p0_n <= 0.02 && a_n <= 0.02,
            "{element}: node_to_segment p0 {p0_n}, a {a_n}"
        );
        // The combined radius 2/3: with the first radius alone, a would be
        // √(3/2) times larger.
        let load: f64 = o.contact_rows.iter().map(|r| r.normal_force).sum();
        let e_star = 1.0 / (2.0 * (1.0 - 0.3f64 * 0.3));
        let a_want = (4.0 * load * (2.0 / 3.0) / (std::f64::consts::PI * e_star)).sqrt();
        assert!(
            (a_exact - a_want).abs() <= 1e-12 * a_want,
            "{a_exact} vs {a_want}"
        );
    }
}

fn pressures(o: &RunOutput) -> Vec<f64> {
    o.contact_rows.iter().map(|r| r.pressure).collect()
}

/// Every method of the registry on the mortar patch test (the pad is held
/// by contact alone: SMALBE around every method but the status method) and
/// on the two cylinders (a non-trivial active set): the status method's
/// pressures, to round-off for the exact methods (they end with a solve on
/// the active set they found), and within the deviation the penalty method
/// reports of itself (≈ 1/k).
#[test]
fn every_contact_method_gives_the_mortar_answer() {
    let cases = [
        patch_with("mortar", false, "quad4", "quad8"),
        cylinders("mortar", "quad4"),
    ];
    for (c, text) in cases.iter().enumerate() {
        let text = text.replace(
            "[[contact]]",
            "[solver]\nmax_iterations = 100000\npenalty = 1e10\n\n[[contact]]",
        );
        let run = |m: Method| {
            let opts = RunOptions {
                method: Some(m),
                path: Some(SolvePath::Condensed),
            };
            let o = try_run(&text, opts).unwrap_or_else(|e| panic!("{m:?}: {e}"));
            assert!(
                o.report.converged,
                "case {c}, {m:?}: {:?}",
                o.report.failure
            );
            o
        };
        let reference = run(Method::Status);
        let active = reference.report.steps[0].active;
        if c == 0 {
            let (dev, _) = pressure_error(&reference, 1.0);
            assert!(dev <= 1e-8, "patch: pressure off by {dev:e}");
        } else {
            assert!(
                active > 5 && active < reference.report.contact_points,
                "{active}"
            );
        }
        for m in Method::ALL.into_iter().filter(|&m| m != Method::Status) {
            let o = run(m);
            assert_eq!(o.report.solver["method"], m.as_str());
            let d = max_rel(&pressures(&o), &pressures(&reference));
            let tol = match &o.report.steps[0].regularisation {
                // The penalty method: its own measure of its deviation.
                Some(r) => {
                    assert!(r.force_deviation <= 1e-6, "{m:?}: {r:?}");
                    2.0 * r.force_deviation + 1e-9
                }
                None => 1e-9,
            };
            eprintln!("case {c} {m:?}: pressures differ by {d:.2e} (tolerance {tol:.1e})");
            assert!(d <= tol, "case {c}, {m:?}: pressures differ by {d:e}");
        }
        // The registry's other entries: the status method with penalty-
        // imposed constraints (status_penalty) and with single changes.
        for (extra, name) in [
            (
                "constraints = \"penalty\"\npenalty = 1e12",
                "status_penalty",
            ),
            ("status_changes = \"single\"", "status"),
        ] {
            let o = converged(
                &text.replace("penalty = 1e10", extra),
                RunOptions::default(),
            );
            assert_eq!(o.report.solver["method"], name);
            let d = max_rel(&pressures(&o), &pressures(&reference));
            assert!(d <= 1e-8, "case {c}, {extra}: pressures differ by {d:e}");
        }
    }
}

/// The patch test (quadratic pad on a linear base) with the pad free in x
/// and a sideways traction 0.1 (a tenth of the pressure) carried by friction
/// alone, `friction` on the contact: resultant 0.2.
fn sideways_patch(friction: &str) -> String {
    patch_with("mortar", false, "quad4", "quad8")
        .replace(
            "discretization = \"mortar\"\n\n[reference]",
            &format!("discretization = \"mortar\"\nfriction = {friction}\n\n[reference]"),
        )
        .replace("traction = [0.0, -1.0]", "traction = [0.1, -1.0]")
        .replace(
            "[[boundary]]\nname = \"pin-pad\"\nbody = \"pad\"\npoint = [0.0, 1.0]\ndisplacement = { x = 0.0 }\n",
            "",
        )
}

#[test]
fn mortar_with_coulomb_friction_holds_a_sideways_load() {
    // Coulomb μ = 0.3 by each friction solver: the same answer.
    let text = sideways_patch("{ coulomb = 0.3 }");
    let o = converged_on(&text, SolvePath::Condensed);
    let n: f64 = o.contact_rows.iter().map(|r| r.normal_force).sum();
    let t: f64 = o.contact_rows.iter().map(|r| r.tangential_force).sum();
    assert!((n - 2.0).abs() <= 1e-9 * 2.0, "normal resultant {n}");
    assert!(
        (t.abs() - 0.2).abs() <= 1e-9 * 0.2,
        "tangential resultant {t}"
    );
    for r in &o.contact_rows {
        assert!(r.tangential_force.abs() <= 0.3 * r.normal_force * (1.0 + 1e-9));
    }
    // Not a trivial case: the ends slip (the pads' Poisson expansions
    // differ), the middle sticks.
    let status = |s: &str| o.contact_rows.iter().filter(|r| r.status == s).count();
    assert!(
        status("slip") >= 2 && status("stick") >= 2,
        "{:?}",
        o.contact_rows
    );
    let tangential =
        |o: &RunOutput| -> Vec<f64> { o.contact_rows.iter().map(|r| r.tangential_force).collect() };
    for solver in ["status", "newton"] {
        let other = converged_on(
            &text.replace(
                "[reference]",
                &format!("[solver]\nfriction = \"{solver}\"\n\n[reference]"),
            ),
            SolvePath::Condensed,
        );
        assert_ne!(other.report.solver["method"], o.report.solver["method"]);
        let dn = max_rel(&common::forces(&other), &common::forces(&o));
        let dt = max_rel(&tangential(&other), &tangential(&o));
        assert!(
            dn <= 1e-8 && dt <= 1e-8,
            "friction = {solver}: {dn:e} {dt:e}"
        );
    }
}

/// The mortar patch with a Tresca threshold 0.1, the pad's top pushed down
/// and sideways (every point closed, most slipping, some sticking).
fn tresca_patch() -> String {
    patch_with("mortar", false, "quad4", "quad8")
        .replace(
            "discretization = \"mortar\"\n\n[reference]",
            "discretization = \"mortar\"\nfriction = { tresca = 0.1 }\n\n[reference]",
        )
        .replace(
            "traction = [0.0, -1.0]",
            "displacement = { x = 0.002, y = -0.02 }",
        )
        .replace(
            "[[boundary]]\nname = \"pin-pad\"\nbody = \"pad\"\npoint = [0.0, 1.0]\ndisplacement = { x = 0.0 }\n",
            "",
        )
        .replace("[reference]\nkind = \"uniform_pressure\"\npressure = 1.0\n", "")
}

#[test]
fn mortar_with_tresca_friction_by_mprgp_equals_the_status_method() {
    // The pad's top pushed down and sideways (no body held by contact
    // alone, which the box method cannot solve; every point closed, where
    // the box and the status method solve the same Tresca problem), with a
    // Tresca threshold 0.1 (a traction): most points slip, some stick.
    let text = tresca_patch();
    let a = converged_on(&text, SolvePath::Condensed);
    let b = converged(
        &text,
        RunOptions {
            method: Some(Method::Mprgp),
            path: Some(SolvePath::Condensed),
        },
    );
    assert_eq!(a.report.solver["method"], "tresca_status");
    assert_eq!(b.report.solver["method"], "tresca_mprgp_box");
    common::assert_same(&a, &b, 1e-8);
    let status = |s: &str| a.contact_rows.iter().filter(|r| r.status == s).count();
    assert!(status("slip") >= 2 && status("stick") >= 2 && status("open") == 0);
    for r in &a.contact_rows {
        // The threshold is a traction: the force bound is 0.1 D_jj.
        let bound = 0.1 * r.normal_force / r.pressure;
        assert!(r.tangential_force.abs() <= bound * (1.0 + 1e-9), "{r:?}");
        if r.status == "slip" {
            assert!(
                (r.tangential_force.abs() - bound).abs() <= 1e-9 * bound,
                "{r:?}"
            );
        }
    }
}

#[test]
fn mortar_refuses_axisymmetric_and_rigid_masters() {
    let refused = common::assert_mortar_refused;
    refused(
        "hertz_axi.toml",
        "node_to_segment",
        &[".discretization", "axisymmetric"],
    );
    let rigid = ["contact \"cyl-ground\"", "deformable master"];
    refused("hertz2d.toml", "node_to_segment", &rigid);
}

#[cfg(feature = "mpi")]
#[test]
fn mortar_patch_under_mpirun_2_equals_the_in_process_run() {
    // The pressure column (the last number before the frame's n_x, n_y, t1_x, t1_y): the traction.
    let scene = common::example_path("mortar_patch.toml");
    let Some(d) = common::patch_under_mpirun_2("mortar", &scene, 11, 5) else {
        return;
    };
    // Coulomb friction on quadratic slave edges (the sideways patch test):
    // the same rows under mpirun.
    let friction = d.join("friction.toml");
    std::fs::write(&friction, sideways_patch("{ coulomb = 0.3 }")).unwrap();
    let a = common::contact_csv_of_run(false, &friction, &d.join("local-friction"));
    let b = common::contact_csv_of_run(true, &friction, &d.join("mpi-friction"));
    assert_eq!(a.len(), 21);
    assert_eq!(a.len(), b.len());
    // step, point, x, y, gap, normal_force, tangential_force, slip, pressure
    let tangential: f64 = b.iter().map(|r| r[6]).sum();
    assert!((tangential.abs() - 0.2).abs() <= 1e-9 * 0.2, "{tangential}");
    for (x, y) in a.iter().zip(&b) {
        assert!(max_rel(x, y) <= 1e-10, "{x:?} vs {y:?}");
    }
}

/// The mortar patches with friction on the direct path: Coulomb holding a
/// sideways load and Tresca pushed sideways give the condensed path's
/// forces, slips and displacements.
#[test]
fn mortar_with_friction_has_the_condensed_forces_on_the_direct_path() {
    common::twins::on_both_paths(&sideways_patch("{ coulomb = 0.3 }"), 1e-8);
    common::twins::on_both_paths(&tresca_patch(), 1e-8);
}
