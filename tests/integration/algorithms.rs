//! The course's algorithm family on the same condensed problem
//! (docs/theory/validation-cases.md §7): every exact method equals the status method; the
//! penalty methods converge to it as their stiffness grows.

use crate::common;

use common::{
    block_body, block_boundary, block_contact, example, forces, material_2d, max_rel, rigid_plane,
    try_run,
};
use signorini_scene::Method;
use signorini_solver::{RunOutput, SolveError};

fn run_with(text: &str, method: Method) -> Result<RunOutput, SolveError> {
    try_run(text, common::with_method(method))
}

/// A supported block pressed on a rigid plane with a gap profile that leaves
/// part of it open: a non-trivial active set without floating bodies.
fn tilted_block() -> String {
    [
        material_2d(100.0, 0.3),
        block_body([0.0, 0.0], [2.0, 1.0], [20, 8], ""),
        rigid_plane("floor", [0.0, -0.001], [0.05, 1.0]),
        block_boundary(
            r#"surface = "top""#,
            "displacement = { x = 0.0, y = -0.02 }",
        ),
        block_contact("c", "bottom", "floor"),
    ]
    .concat()
}

#[test]
fn every_exact_method_equals_the_status_method_on_hertz_and_a_tilted_block() {
    let hertz = example("hertz2d.toml").replace("divisions = 160", "divisions = 64");
    for text in [hertz, tilted_block()] {
        let reference = run_with(&text, Method::Status).unwrap();
        assert!(reference.report.converged);
        let active = reference.report.steps[0].active;
        assert!(
            active > 1 && active < reference.report.contact_points,
            "a non-trivial active set: {active}"
        );
        for method in [
            Method::Lemke,
            Method::ProjectedGradient,
            Method::ProjectedConjugateGradient,
            Method::Mprgp,
            Method::AugmentedLagrangian,
        ] {
            let out = run_with(&text, method).unwrap();
            assert!(out.report.converged, "{method:?}: {:?}", out.report.failure);
            assert!(
                out.report.certificate.max() <= 1e-9,
                "{method:?}: {:?}",
                out.report.certificate
            );
            let fr = max_rel(&forces(&out), &forces(&reference));
            assert!(fr <= 1e-8, "{method:?}: forces differ by {fr:e}");
            let ur = max_rel(
                &out.bodies[0].last().displacement,
                &reference.bodies[0].last().displacement,
            );
            assert!(ur <= 1e-8, "{method:?}: displacements differ by {ur:e}");
            assert_eq!(out.report.solver["method"], method.as_str());
            assert!(out.report.solver["iterations"].as_u64().unwrap() >= 1);
        }
    }
}

#[test]
fn uzawa_converges_given_iterations_and_says_so_when_it_does_not() {
    let text = tilted_block().replace(
        "[[contact]]",
        "[solver]\nmax_iterations = 100000\n[[contact]]",
    );
    let reference = run_with(&tilted_block(), Method::Status).unwrap();
    let out = run_with(&text, Method::Uzawa).unwrap();
    assert!(out.report.converged, "{:?}", out.report.failure);
    assert!(max_rel(&forces(&out), &forces(&reference)) <= 1e-8);
    // Three iterations are not enough: not converged, and the report says why.
    let short = tilted_block().replace("[[contact]]", "[solver]\nmax_iterations = 3\n[[contact]]");
    let out = run_with(&short, Method::Uzawa).unwrap();
    assert!(!out.report.converged);
    let failure = out.report.failure.as_deref().unwrap_or("");
    assert!(
        failure.contains("uzawa") && failure.contains("iteration limit 3"),
        "{failure}"
    );
    assert_eq!(out.report.solver["converged"], false);
}

/// Penalty: the deviation from the exact solution falls as the stiffness
/// grows (like 1/k) until round-off stops it; the report shows it per step.
#[test]
fn penalty_converges_to_the_exact_solution_as_the_stiffness_grows() {
    let hertz = example("hertz2d.toml").replace("divisions = 160", "divisions = 64");
    let exact = run_with(&hertz, Method::Status).unwrap();
    let mut last = f64::INFINITY;
    let mut deviations = Vec::new();
    for k in [1e0, 1e2, 1e4, 1e6, 1e8] {
        let text = hertz.replace("[solver]", &format!("[solver]\npenalty = {k:e}"));
        let out = run_with(&text, Method::Penalty).unwrap();
        let reg = out.report.steps[0]
            .regularisation
            .as_ref()
            .expect("penalty reports its regularisation");
        let dev = max_rel(&forces(&out), &forces(&exact));
        assert!(
            (reg.force_deviation - dev).abs() <= 1e-6 + 1e-3 * dev,
            "{} vs {dev}",
            reg.force_deviation
        );
        assert!(
            dev < last,
            "k = {k:e}: deviation {dev:e} did not fall (previous {last:e})"
        );
        deviations.push(dev);
        last = dev;
        if k <= 1e0 {
            assert!(
                reg.warning.is_some(),
                "a soft penalty penetrates more than 1 % of an element: {reg:?}"
            );
            assert!(
                !out.report.converged,
                "a visible penetration is not a converged unilateral answer"
            );
        }
    }
    assert!(last <= 1e-6, "{deviations:?}");
}

#[test]
fn status_variants_and_penalty_imposed_constraints_agree_with_the_default() {
    let hertz = example("hertz2d.toml").replace("divisions = 160", "divisions = 64");
    let reference = run_with(&hertz, Method::Status).unwrap();
    for extra in [
        "status_changes = \"single\"",
        "constraints = \"penalty\"\npenalty = 1e12",
    ] {
        let text = hertz.replace("[solver]", &format!("[solver]\n{extra}"));
        let out = run_with(&text, Method::Status).unwrap();
        assert!(out.report.converged, "{extra}: {:?}", out.report.failure);
        let d = max_rel(&forces(&out), &forces(&reference));
        assert!(d <= 1e-8, "{extra}: {d:e}");
    }
    // One change per iteration takes at least as many iterations as active points changed.
    let single = run_with(
        &hertz.replace("[solver]", "[solver]\nstatus_changes = \"single\""),
        Method::Status,
    )
    .unwrap();
    assert!(single.report.steps[0].iterations > reference.report.steps[0].iterations);
}

/// The regularised law of course notes §3.6, pressure = k × penetration: a block of
/// height H whose top is pushed down by d onto a rigid plane through that law
/// is a spring E'/H in series with k: the penetration is
/// δ = (E'/H) d / (k + E'/H) and the pressure k δ, exactly (uniform state).
/// The certificate checks the law instead of g ≥ 0.
#[test]
fn regularised_law_gives_the_closed_form_penetration() {
    let (e, nu, h, d, k) = (100.0f64, 0.3f64, 1.0f64, 0.01f64, 5.0e3f64);
    let text = [
        material_2d(e, nu),
        block_body([0.0, 0.0], [2.0, h], [8, 4], ""),
        rigid_plane("floor", [0.0, 0.0], [0.0, 1.0]),
        block_boundary(
            r#"surface = "top""#,
            &format!("displacement = {{ y = -{d} }}"),
        ),
        block_boundary("point = [0.0, 0.0]", "displacement = { x = 0.0 }"),
        block_contact("c", "bottom", "floor"),
        format!("law = {{ penalty = {k} }}\n"),
    ]
    .concat();
    let out = run_with(&text, Method::Penalty).unwrap();
    assert!(out.report.converged, "{:?}", out.report.failure);
    assert!(
        out.report.certificate.law <= 1e-12,
        "{:?}",
        out.report.certificate
    );
    let stiff = e / (1.0 - nu * nu) / h;
    let delta = stiff * d / (k + stiff);
    for r in &out.contact_rows {
        assert!(
            (r.gap + delta).abs() <= 1e-10 * delta,
            "gap {} vs {}",
            r.gap,
            -delta
        );
        assert!(
            (r.pressure - k * delta).abs() <= 1e-10 * k * delta,
            "pressure {}",
            r.pressure
        );
    }
    // The exact (status) method refuses a penalty law rather than ignore it.
    assert!(
        matches!(run_with(&text, Method::Status), Err(SolveError::Input(m)) if m.contains("penalty"))
    );
}

#[test]
fn a_method_stopped_by_its_iteration_limit_exits_2_with_its_residuals() {
    let out = std::process::Command::new(common::BIN)
        .args([
            "run",
            &format!("{}/examples/hertz2d.toml", env!("CARGO_MANIFEST_DIR")),
            "--method",
            "uzawa",
            "--out",
        ])
        .arg(std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("uzawa-limit"))
        .output()
        .unwrap();
    let err = common::stderr_of_exit(&out, 2);
    assert!(
        err.contains("not converged") && err.contains("iteration"),
        "{err}"
    );
    let report: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("uzawa-limit/report.json"),
        )
        .unwrap(),
    )
    .unwrap();
    assert_eq!(report["converged"], false);
    assert!(
        report["solver"]["residual_history"]
            .as_array()
            .unwrap()
            .len()
            >= 100
    );
}
