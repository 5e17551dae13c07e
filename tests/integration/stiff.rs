//! The stiff and extreme cases of docs/theory/validation-cases.md §8: the quick suite
//! of `signorini bench --suite stiff --quick` (crates/suite/cases.toml),
//! run once in process and asserted over the whole suite — no NaN anywhere, no
//! `converged: true` with a certificate above its tolerance, every case meets
//! its expectation — plus family-specific numbers.

use std::sync::OnceLock;

use signorini_suite::stiff::{self, StiffRow};

/// The quick suite, run once for every test of this file.
fn suite() -> &'static [StiffRow] {
    static ROWS: OnceLock<Vec<StiffRow>> = OnceLock::new();
    ROWS.get_or_init(|| {
        let rows = stiff::run_suite(true, |i, n, r| {
            eprintln!(
                "[{i}/{n}] {} ({}): exit {} in {:.3} s: {}",
                r.case,
                r.parameter,
                r.exit_code,
                r.time_s,
                stiff::verdict_text(&r.verdict)
            )
        });
        eprintln!("{}", stiff::markdown(&rows));
        rows
    })
}

fn family(name: &str) -> Vec<&'static StiffRow> {
    suite().iter().filter(|r| r.family == name).collect()
}

fn error(r: &StiffRow, quantity: &str) -> f64 {
    r.errors
        .iter()
        .find(|e| e.name == quantity)
        .unwrap_or_else(|| panic!("{}: no {quantity} in {:?}", r.case, r.errors))
        .error
}

#[test]
fn no_case_returns_nan_anywhere() {
    let bad: Vec<&str> = suite()
        .iter()
        .filter(|r| r.any_nan)
        .map(|r| r.case.as_str())
        .collect();
    assert!(bad.is_empty(), "NaN or infinity in {bad:?}");
}

#[test]
fn no_case_converges_with_a_certificate_above_its_tolerance() {
    for r in suite() {
        if r.converged {
            assert!(
                r.certificate <= r.tolerance,
                "{}: converged with a certificate {:e} above its tolerance {:e}",
                r.case,
                r.certificate,
                r.tolerance
            );
        }
        // and "solved" means converged: exit 0 exactly when converged
        assert_eq!(r.exit_code == 0, r.converged, "{}: {}", r.case, r.outcome);
    }
}

#[test]
fn every_case_meets_its_expectation() {
    let failed: Vec<String> = suite()
        .iter()
        .filter(|r| r.failed())
        .map(|r| format!("{}: {}", r.case, stiff::verdict_text(&r.verdict)))
        .collect();
    assert!(failed.is_empty(), "{}", failed.join("\n"));
    for r in suite() {
        assert!(
            r.passed(),
            "{}: {}",
            r.case,
            stiff::verdict_text(&r.verdict)
        );
        assert_ne!(r.exit_code, 3, "{}: internal error: {}", r.case, r.outcome);
    }
}

#[test]
fn every_family_of_the_issue_is_covered_over_its_whole_range() {
    let values = |f: &str| -> Vec<f64> { family(f).iter().map(|r| r.value).collect() };
    let covers = |f: &str, want: &[f64]| {
        let have = values(f);
        for w in want {
            assert!(
                have.iter()
                    .any(|h| (h - w).abs() <= 1e-9 * w.abs().max(1.0)),
                "{f}: no case at {w:e} (have {have:?})"
            );
        }
    };
    covers("contrast", &[1e-6, 1e-3, 1.0, 1e3, 1e6]);
    covers("poisson", &[0.49, 0.499, 0.4999]);
    covers("load", &[1e-12, 1e-6, 1.0, 1e3, 1e6]);
    covers("gap", &[0.0, 1.0, 10.0, 1e3]);
    covers("mesh_ratio", &[100.0, 0.01]);
    covers("penalty", &[1e0, 1e4, 1e8, 1e12, 1e16]);
    covers("mu_ge_1", &[1.0, 2.0, 5.0]);
    for f in [
        "single_node",
        "held_by_contact",
        "held_by_friction",
        "load_reversal",
        "stops",
    ] {
        assert!(!family(f).is_empty(), "{f}");
    }
    for r in family("single_node") {
        assert_eq!(r.contact_points, 1, "{}", r.case);
    }
    let many = family("many_active");
    assert!(
        many.iter()
            .any(|r| r.contact_points >= 500 && r.active == r.contact_points),
        "hundreds of contact nodes, all active: {:?}",
        many.iter()
            .map(|r| (r.contact_points, r.active))
            .collect::<Vec<_>>()
    );
    // Both exit classes of the "stops" branch are shown.
    let stops = family("stops");
    assert!(stops.iter().any(|r| r.exit_code == 1 && r.passed()));
    assert!(stops.iter().any(|r| r.exit_code == 2 && r.passed()));
}

/// Between stacked blocks of any stiffness ratio the contact pressure is the
/// traction, to round-off scaled by the problem's size and contrast, and the
/// run converges with its certificate (relative to the internal forces |K||u|
/// of the stiff body, whose terms cancel).
#[test]
fn contrast_pressure_equals_the_traction_at_every_ratio() {
    let rows = family("contrast");
    assert_eq!(
        rows.len(),
        9,
        "5 ratios by status, 2 by mprgp and projected_gradient"
    );
    for r in rows {
        assert_eq!(r.exit_code, 0, "{}: {}", r.case, r.outcome);
        assert!(r.converged && r.certificate <= r.tolerance, "{}", r.case);
        let contrast = r.value.max(1.0 / r.value);
        let dofs = r.dofs as f64;
        let tol = stiff::roundoff(dofs * contrast);
        let e = error(r, "pressure");
        assert!(e <= tol, "{}: pressure error {e:e} > {tol:e}", r.case);
        assert!(error(r, "resultant") <= tol, "{}", r.case);
    }
}

/// The penalty's force deviation from the unilateral answer falls like 1/k
/// until round-off, then stays there: exactly 1/(1 + k) for the regularised
/// law on the uniform block, and between 0.1/k and 10/k (or at round-off) for
/// the method's stiffness factor on the tilted block, whose soft values stop
/// on the certificate (exit 2) and stiff values solve.
#[test]
fn penalty_deviation_falls_like_one_over_k_until_round_off() {
    let rows = family("penalty");
    let law: Vec<&&StiffRow> = rows
        .iter()
        .filter(|r| r.case.starts_with("penalty_law"))
        .collect();
    assert_eq!(law.len(), 5);
    for r in &law {
        let k = r.value;
        let dev = r
            .force_deviation
            .expect("the penalty reports its deviation");
        let floor = stiff::roundoff(r.dofs as f64);
        assert!(
            (dev - 1.0 / (1.0 + k)).abs() <= floor,
            "{}: deviation {dev:e} vs 1/(1 + k) = {:e}",
            r.case,
            1.0 / (1.0 + k)
        );
        assert_eq!(r.exit_code, 0, "{}: {}", r.case, r.outcome);
    }
    let factor: Vec<&&StiffRow> = rows
        .iter()
        .filter(|r| r.case.starts_with("penalty_factor"))
        .collect();
    assert_eq!(factor.len(), 5);
    let mut last = f64::INFINITY;
    for r in &factor {
        let k = r.value;
        let dev = r
            .force_deviation
            .expect("the penalty reports its deviation");
        let floor = stiff::roundoff(r.contact_points as f64 * 2.0);
        assert!(dev <= 10.0 / k + floor, "{}: {dev:e}", r.case);
        if 0.1 / k > floor {
            assert!(dev >= 0.1 / k, "{}: {dev:e} fell faster than 1/k", r.case);
            assert!(dev < last, "{}: {dev:e} did not fall", r.case);
        }
        last = dev;
        // Converged exactly when the penetration is within the tolerance.
        assert!(r.exit_code == 0 || r.exit_code == 2, "{}", r.case);
    }
    assert_eq!(factor[0].exit_code, 2, "k = 1 penetrates visibly");
    assert_eq!(factor[4].exit_code, 0, "k = 1e16 solves");
}

/// Friction: held by friction alone, μ ≥ 1 and load reversal reproduce the
/// exact reactions (equilibrium, docs/theory/validation-cases.md §5) at every step.
#[test]
fn friction_reactions_are_exact_through_reversal_and_at_large_mu() {
    for r in family("held_by_friction") {
        assert!(r.passed(), "{}", r.case);
        assert!(error(r, "normal_reaction") <= stiff::FRICTION_TOLERANCE);
        assert!(error(r, "slip_points_on_cone") <= stiff::FRICTION_TOLERANCE);
    }
    let reversal = family("load_reversal");
    let force = reversal
        .iter()
        .find(|r| r.case == "load_reversal_force")
        .unwrap();
    assert_eq!(
        force
            .errors
            .iter()
            .filter(|e| e.name.starts_with("tangential_reaction_step_"))
            .count(),
        10
    );
    for r in family("mu_ge_1")
        .into_iter()
        .filter(|r| r.case.ends_with("stick"))
    {
        assert!(error(r, "tangential_reaction") <= stiff::FRICTION_TOLERANCE);
    }
}

/// The suite's friction cases on the direct path: held by friction alone
/// (2D and 3D), μ ≥ 1 and load reversal give the condensed path's forces,
/// slips and displacements; those asking for the friction status method
/// are refused there naming it.
#[test]
fn the_friction_cases_have_the_condensed_forces_on_the_direct_path() {
    use crate::common::twins::{on_both_paths, refused_on_direct};
    let families = ["held_by_friction", "mu_ge_1", "load_reversal"];
    let mut twins = 0;
    for case in stiff::cases(true) {
        let solves = matches!(case.expect, stiff::Expectation::Solves(_));
        if !families.contains(&case.family.as_str()) || !solves {
            continue;
        }
        if case.text.contains("friction = \"status\"") {
            refused_on_direct(&case.text, &["solver.friction = \"status\""]);
        } else {
            on_both_paths(&case.text, 1e-8);
            twins += 1;
        }
    }
    assert!(twins >= 4, "{twins} friction cases twinned");
}
