//! Bodies held by contact alone (docs/theory/contact-problem.md): no
//! Dirichlet condition on some rigid motions, no artificial spring. The
//! status method solves the saddle-point systems with the equilibrium of the
//! rigid modes, every other method runs inside SMALBE (contact::smalbe) with
//! that equilibrium as the equality; all must give the same answer, and the
//! uniform-pressure patch test (docs/theory/validation-cases.md §3) exactly.

use crate::common;

use common::{
    assert_message, converged, converged_on, example, forces, max_rel, try_run, with_method,
};
use signorini_scene::Method;
use signorini_solver::{RunOptions, RunOutput, SolveError};

fn displacements(o: &RunOutput) -> Vec<f64> {
    o.bodies
        .iter()
        .flat_map(|b| b.last().displacement.clone())
        .collect()
}

const EXACT: [Method; 6] = [
    Method::Mprgp,
    Method::ProjectedGradient,
    Method::ProjectedConjugateGradient,
    Method::Lemke,
    Method::Uzawa,
    Method::AugmentedLagrangian,
];

/// examples/floating3d.toml: a box on a rigid plane with no support in z
/// (only two top corners pinned in the plane), so its z translation and both
/// tilts (three rigid modes) are held by the contact alone; a uniform
/// traction t on its top.
fn floating_box_3d(t: f64) -> String {
    let text = example("floating3d.toml");
    assert!(text.contains("traction = [0.0, 0.0, -0.5]") && text.contains("pressure = 0.5"));
    text.replace(
        "traction = [0.0, 0.0, -0.5]",
        &format!("traction = [0.0, 0.0, {t:e}]"),
    )
    .replace("pressure = 0.5", &format!("pressure = {:e}", -t))
}

/// Every method on one scene: converged, the certificate met, and forces
/// and displacements equal to the status method's.
fn every_method_equals_the_status_method(text: &str, what: &str) {
    let reference = converged(text, with_method(Method::Status));
    let f0 = forces(&reference);
    let u0 = displacements(&reference);
    for m in EXACT {
        let out = converged(text, with_method(m));
        let df = max_rel(&forces(&out), &f0);
        let du = max_rel(&displacements(&out), &u0);
        assert!(df <= 1e-9, "{what}, {m:?}: forces differ by {df:e}");
        assert!(du <= 1e-9, "{what}, {m:?}: displacements differ by {du:e}");
        if m == Method::Mprgp {
            assert!(
                out.report.steps[0].stopping_reason.contains("SMALBE"),
                "{}",
                out.report.steps[0].stopping_reason
            );
        }
        let q = &out.report.reference.as_ref().unwrap().quantities["pressure"];
        assert!(
            q.relative_error <= 1e-10,
            "{what}, {m:?}: pressure {} vs {}",
            q.computed,
            q.exact
        );
    }
}

#[test]
fn a_pad_held_by_contact_alone_is_solved_by_every_method_in_2d() {
    // examples/blocks.toml: the pad has two rigid modes (vertical
    // translation, rotation about its pinned corner) held by the contact.
    every_method_equals_the_status_method(&example("blocks.toml"), "blocks 2D");
}

#[test]
fn a_box_held_by_contact_alone_in_three_rigid_modes_is_solved_by_every_method_in_3d() {
    let text = floating_box_3d(-0.5);
    let out = converged(&text, with_method(Method::Status));
    assert_message(&out, "held by contact in 3 rigid motion(s)");
    every_method_equals_the_status_method(&text, "box 3D");
}

/// The load cannot be balanced by compressive contact forces: a clear input
/// error naming the body and its unbalanced resultant, whatever the method.
#[test]
fn a_floating_box_pulled_off_its_support_is_refused_by_name() {
    let text = floating_box_3d(0.5);
    for m in [Method::Status, Method::Mprgp] {
        match try_run(&text, with_method(m)) {
            Err(SolveError::Input(msg)) => {
                assert!(msg.contains("\"box\""), "{msg}");
                assert!(
                    msg.contains("unbalanced") || msg.contains("balance"),
                    "{msg}"
                );
            }
            other => panic!(
                "{m:?}: expected a clear input error, got {:?}",
                other.map(|o| o.report.converged)
            ),
        }
    }
}

/// The penalty method on a floating body solves its regularised law inside
/// SMALBE: the deviation from the exact forces shrinks with the stiffness.
#[test]
fn the_penalty_method_holds_a_floating_body_and_tends_to_the_exact_answer() {
    let text = example("blocks.toml");
    let exact = forces(&converged(&text, with_method(Method::Status)));
    let mut last = f64::INFINITY;
    for factor in [1e2, 1e4, 1e6] {
        let t = text.replace("[solver]", &format!("[solver]\npenalty = {factor:e}"));
        let t = if t.contains("[solver]") {
            t
        } else {
            format!("{t}\n[solver]\npenalty = {factor:e}\n")
        };
        let out = try_run(&t, with_method(Method::Penalty)).unwrap();
        let reg = out.report.steps[0].regularisation.as_ref().unwrap();
        let d = max_rel(&forces(&out), &exact);
        // The report's deviation is the same measure, relative to the exact
        // forces alone.
        let r = reg.force_deviation;
        assert!((d - r).abs() <= 0.01 * r, "reported {r:e}, measured {d:e}");
        assert!(d < last, "factor {factor:e}: deviation {d:e} ≥ {last:e}");
        last = d;
    }
    assert!(last <= 1e-4, "{last:e}");
}

/// A plate 1 × 1 × 1e-6, one Hex8 through its thickness, on a rigid plane,
/// pressed by a uniform traction: held in x and y, its z translation held by
/// the contact alone. Condensing the bottom face subtracts stiffnesses 1e12
/// times larger than the plate's (E A / t against E t), and S loses the
/// rigid mode to round-off: the condensed path refuses, naming the cause
/// and the direct path (it said "singular" and blamed the supports); the
/// direct path solves it, the pressure exact.
#[test]
fn a_plate_too_thin_to_condense_is_sent_to_the_direct_path() {
    let plate =
        "title = \"thin plate\"\ndimension = 3\nmodel = \"solid\"\n\
         [[materials]]\nname = \"steel\"\nyoung = 210.0\npoisson = 0.3\n\
         [[bodies]]\nname = \"plate\"\nmaterial = \"steel\"\n\
         mesh = { generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 1e-6], divisions = [8, 8, 1] }\n\
         [[bodies]]\nname = \"floor\"\n\
         rigid = { shape = \"plane\", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\n\
         [[boundary]]\nname = \"px\"\nbody = \"plate\"\nsurface = \"xmin\"\ndisplacement = { x = 0.0 }\n\
         [[boundary]]\nname = \"py\"\nbody = \"plate\"\nsurface = \"ymin\"\ndisplacement = { y = 0.0 }\n\
         [[boundary]]\nname = \"pressure\"\nbody = \"plate\"\nsurface = \"zmax\"\ntraction = [0.0, 0.0, -1.0]\n\
         [[contact]]\nname = \"c\"\nslave = { body = \"plate\", surface = \"zmin\" }\nmaster = { body = \"floor\" }\n\
         [reference]\nkind = \"uniform_pressure\"\npressure = 1.0\n"
    .to_string();
    match try_run(&plate, RunOptions::default()) {
        Err(SolveError::Input(m)) => assert!(
            m.contains("lost the body's rigid motions to round-off")
                && m.contains("solver.path = \"direct\""),
            "{m}"
        ),
        other => panic!(
            "expected the condensed path to refuse: {:?}",
            other.map(|o| o.report.converged)
        ),
    }
    let out = converged_on(&plate, signorini_scene::SolvePath::Direct);
    let p = &out.report.reference.as_ref().unwrap().quantities["pressure"];
    assert!(
        p.relative_error <= 1e-9,
        "pressure error {}",
        p.relative_error
    );
}

/// A pad held by contact alone, loaded then unloaded to no load at all
/// (found by a fourth robustness sweep): with no load, no prescribed
/// displacement and no initial gap, the certificate's force and length
/// scales are both the smallest double, their product underflowed to 0 and
/// the complementarity 0/0 was NaN: 'the certificate residual NaN exceeds the
/// tolerance', exit 2, on both paths and every method. The unloaded step is
/// solved: no force, no displacement.
#[test]
fn a_pad_unloaded_to_no_load_is_solved_with_no_force() {
    let text = example("blocks.toml")
        + "\n[[steps]]\nscale = { pressure = 1.0 }\n[[steps]]\nscale = { pressure = 0.0 }\n";
    for (opts, what) in [
        (with_method(Method::Status), "status"),
        (with_method(Method::Mprgp), "mprgp"),
        (
            RunOptions {
                method: None,
                path: Some(signorini_scene::SolvePath::Direct),
            },
            "direct",
        ),
    ] {
        let out = converged(&text, opts);
        let c = &out.report.certificate;
        assert_eq!(c.complementarity, 0.0, "{what}: {c:?}");
        let last = out.contact_rows.iter().filter(|r| r.step == 2);
        assert!(last.clone().count() == 17 && last.clone().all(|r| r.normal_force == 0.0));
        assert!(displacements(&out).iter().all(|u| *u == 0.0), "{what}");
        let first = out.contact_rows.iter().filter(|r| r.step == 1);
        assert!(
            first.clone().all(|r| (r.pressure - 1.0).abs() <= 1e-9),
            "{what}"
        );
    }
}
