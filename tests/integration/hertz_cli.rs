//! `signorini run examples/hertz2d.toml` as a user runs it: the report has
//! every key of docs/reference/scene-format.md and Hertz's p0 and a within 2 % and 3 %
//! (docs/theory/validation-cases.md §1).

use crate::common;

use common::cli_run_ok;

#[test]
fn hertz_cylinder_on_a_rigid_plane_from_the_command_line() {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("hertz_cli");
    let _ = std::fs::remove_dir_all(&out);
    cli_run_ok(format!("{root}/examples/hertz2d.toml"), &out);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    for key in [
        "scene",
        "version",
        "ranks",
        "subdomains",
        "dofs",
        "interface_dofs",
        "contact_points",
        "converged",
        "method",
        "path",
        "steps",
        "timings_s",
        "memory",
        "certificate",
        "contact_force",
        "probes",
        "reference",
    ] {
        assert!(report.get(key).is_some(), "report.json lacks {key}");
    }
    for key in [
        "setup", "assemble", "condense", "contact", "recover", "output", "total",
    ] {
        assert!(
            report["timings_s"][key].as_f64().unwrap() >= 0.0,
            "timings_s.{key}"
        );
    }
    assert!(report["memory"]["peak_rss_bytes"].as_u64().unwrap() > 0);
    assert!(report["memory"]["dense_interface_bytes"].as_u64().unwrap() > 0);
    assert_eq!(report["converged"], true);
    for key in [
        "equilibrium",
        "penetration",
        "tension",
        "complementarity",
        "cone",
    ] {
        assert!(
            report["certificate"][key].as_f64().unwrap() <= 1e-9,
            "certificate.{key}"
        );
    }
    let q = &report["reference"]["quantities"];
    let p0 = q["p0"]["relative_error"].as_f64().unwrap();
    let a = q["a"]["relative_error"].as_f64().unwrap();
    assert!(p0 <= 0.02, "p0 error {p0}");
    assert!(a <= 0.03, "a error {a}");
    // a/R ≈ 0.1, where Hertz's half-space is a fair model of the half-disk.
    let a_exact = q["a"]["exact"].as_f64().unwrap();
    assert!((0.05..0.15).contains(&a_exact), "a/R = {a_exact}");
    let csv = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "step,contact,body,point,x,y,gap,normal_force,tangential_force,slip,pressure,status,n_x,n_y,t1_x,t1_y"
    );
    assert_eq!(
        lines.count() as u64,
        report["contact_points"].as_u64().unwrap()
    );
}
