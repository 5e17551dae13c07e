//! Units with the LCP methods, through the CLI: the same scene in other units
//! converges the same way and gives the same relative errors. Lemke on the
//! plane-strain Hertz cylinder at E = 1 and E = 2.1e11 (it ended above
//! tolerance at E = 2.1e11, its pivot test relative to the largest entry of
//! a column mixing compliances and pure numbers); the projected gradient on
//! the axisymmetric Hertz sphere in Pa and m and in MPa and mm (the length
//! scale of the gap tolerance was ‖F‖/E, an area in that model).

use crate::common;

use common::{example, hertz_lengths_scaled, max_rel};
use serde_json::Value;

/// `signorini run <scene> --method <method>` on `text` in a fresh directory:
/// (exit code, report.json).
fn run(test: &str, text: &str, method: &str) -> (i32, Value) {
    let dir = common::fresh_dir("units_methods", test);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = common::signorini(&[
        "run",
        scene.to_str().unwrap(),
        "--method",
        method,
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    let report = std::fs::read_to_string(dir.join("out/report.json")).unwrap_or_else(|e| {
        panic!(
            "{test}: no report ({e}): {}",
            String::from_utf8_lossy(&out.stderr)
        )
    });
    let _ = std::fs::remove_dir_all(&dir);
    (
        out.status.code().unwrap(),
        serde_json::from_str(&report).unwrap(),
    )
}

/// The relative errors of the reference quantities, in name order.
fn errors(report: &Value) -> Vec<f64> {
    let q = report["reference"]["quantities"].as_object().unwrap();
    q.values()
        .map(|v| v["relative_error"].as_f64().unwrap())
        .collect()
}

fn iterations(report: &Value) -> u64 {
    report["steps"][0]["iterations"].as_u64().unwrap()
}

/// The two runs agree: exit code, iterations, relative errors to 1e-6.
fn assert_same(a: &(i32, Value), b: &(i32, Value), what: &str) {
    assert_eq!(a.0, b.0, "{what}: exit codes");
    assert_eq!(iterations(&a.1), iterations(&b.1), "{what}: iterations");
    let (ea, eb) = (errors(&a.1), errors(&b.1));
    assert!(ea.len() >= 4, "{what}: {ea:?}");
    let r = max_rel(&ea, &eb);
    assert!(r <= 1e-6, "{what}: relative errors {ea:?} against {eb:?}");
}

#[test]
fn lemke_on_hertz2d_is_the_same_at_e_1_and_e_2_1e11() {
    let scene = |e: &str| {
        example("hertz2d.toml")
            .replace("young = 1.0", &format!("young = {e}"))
            .replace("divisions = 160", "divisions = 80")
    };
    let one = run("lemke-e1", &scene("1.0"), "lemke");
    let steel = run("lemke-e211", &scene("2.1e11"), "lemke");
    assert_eq!(one.0, 0, "E = 1: {}", one.1["failure"]);
    assert_eq!(steel.0, 0, "E = 2.1e11: {}", steel.1["failure"]);
    assert_same(&one, &steel, "lemke");
    // p0 within 1 % of Hertz, as the status method gives
    let p0 = steel.1["reference"]["quantities"]["p0"]["relative_error"]
        .as_f64()
        .unwrap();
    assert!(p0 < 1e-2, "p0 error {p0}");
}

/// hertz_axi.toml (coarsened) with steel in Pa and m (`mm = false`) or in
/// MPa and mm, and the iteration limit `limit`.
fn axi(mm: bool, limit: usize) -> String {
    let (e, l) = if mm {
        ("2.1e5", 1000.0)
    } else {
        ("2.1e11", 1.0)
    };
    let scene = example("hertz_axi.toml")
        .replace("young = 1.0", &format!("young = {e}"))
        .replace(
            "center = [0.0, 1.0], radius = 1.0, divisions = 80",
            "center = [0.0, 1.0], radius = 1.0, divisions = 60",
        );
    assert!(scene.contains("divisions = 60"), "hertz_axi.toml changed");
    hertz_lengths_scaled(&scene, l, -0.01).replace(
        "path = \"condensed\"",
        &format!("path = \"condensed\"\nmax_iterations = {limit}"),
    )
}

#[test]
fn projected_gradient_on_hertz_axi_is_the_same_in_m_and_mm() {
    for limit in [2000, 500] {
        let m = run(
            &format!("axi-m-{limit}"),
            &axi(false, limit),
            "projected_gradient",
        );
        let mm = run(
            &format!("axi-mm-{limit}"),
            &axi(true, limit),
            "projected_gradient",
        );
        if limit == 2000 {
            assert_eq!(m.0, 0, "m: {}", m.1["failure"]);
        } else {
            // Out of iterations: exit 2, naming the limit to raise.
            assert_eq!(m.0, 2);
            let failure = m.1["failure"].as_str().unwrap();
            assert!(
                failure.contains("iteration limit 500")
                    && failure.contains("raise [solver] max_iterations"),
                "{failure}"
            );
        }
        assert_same(&m, &mm, &format!("projected gradient, limit {limit}"));
    }
}

/// The penalty method's answer is judged against Signorini's conditions,
/// and the penetration O(1/k) its stiffness allows can exceed their
/// tolerance: on the pad of `blocks.toml` (held by contact alone) the
/// default factor 1e8 leaves a penetration of 8.7e-9 of the length scale,
/// exit 2 with the reason and the remedy; [solver] penalty = 1e11 meets the
/// tolerance, with the exact total force.
#[test]
fn a_penalty_too_soft_for_the_tolerance_says_why_and_what_to_raise() {
    let (code, report) = run("penalty-blocks", &example("blocks.toml"), "penalty");
    assert_eq!(code, 2);
    let failure = report["failure"].as_str().unwrap();
    assert!(
        failure.contains("penetration of the penalty method")
            && failure.contains("raise [solver] penalty"),
        "{failure}"
    );
    let stiff = format!("{}\n[solver]\npenalty = 1e11\n", example("blocks.toml"));
    let (code, report) = run("penalty-blocks-stiff", &stiff, "penalty");
    assert_eq!(code, 0, "{}", report["failure"]);
    let penetration = report["certificate"]["penetration"].as_f64().unwrap();
    assert!(penetration > 0.0 && penetration <= 1e-9, "{penetration:e}");
    let force = report["contact_force"][1].as_f64().unwrap();
    assert!((force - 2.0).abs() <= 1e-9, "resultant {force}");
}
