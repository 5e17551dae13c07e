//! Condition estimates in the report: κ₁ of K_II, S and W
//! by the Hager–Higham estimator, and the warning when the tolerance asks for
//! more digits than the worst conditioned operator leaves (docs/reference/outputs.md;
//! docs/reference/scene-format.md).

use crate::common;

use common::{converged, example, try_run};
use signorini_report::Conditioning;
use signorini_scene::SolvePath;
use signorini_solver::{RunOptions, RunOutput};

/// hertz2d.toml with `divisions` on the arc and Young's modulus `young`.
fn hertz(divisions: usize, young: &str) -> String {
    example("hertz2d.toml")
        .replace("divisions = 160", &format!("divisions = {divisions}"))
        .replace("young = 1.0", &format!("young = {young}"))
}

fn conditioning(o: &RunOutput) -> &Conditioning {
    o.report
        .conditioning
        .as_ref()
        .expect("the report has a conditioning entry")
}

fn finite_positive(name: &str, v: Option<f64>) -> f64 {
    let v = v.unwrap_or_else(|| panic!("{name} is null"));
    assert!(v.is_finite() && v >= 1.0, "{name} = {v}");
    v
}

#[test]
fn hertz_estimates_are_finite_and_k_ii_grows_like_h_to_the_minus_2() {
    let opts = RunOptions::default();
    let runs: Vec<RunOutput> = [20, 40, 80]
        .iter()
        .map(|&d| converged(&hertz(d, "1.0"), opts.clone()))
        .collect();
    let mut previous: Option<(f64, f64)> = None;
    for o in &runs {
        let c = conditioning(o);
        assert_eq!(c.method, "hager_higham_1norm");
        let k_ii = finite_positive("k_ii", c.k_ii);
        let s = finite_positive("s", c.s);
        let w = finite_positive("w", c.w);
        assert!(c.k.is_none(), "k is the direct path's");
        assert_eq!(c.k_ii_per_subdomain, vec![Some(k_ii)]);
        // The rule's arithmetic.
        let worst = k_ii.max(s).max(w);
        assert!((c.digits_lost.unwrap() - worst.log10()).abs() < 1e-12);
        assert!((c.digits_available.unwrap() - (15.6536 - worst.log10())).abs() < 1e-3);
        assert!((c.digits_needed - 10.0).abs() < 1e-12);
        assert!(c.warning.is_none(), "{:?}", c.warning);
        if let Some((k0, s0)) = previous {
            // Halving h: κ(K_II) ~ h⁻² (×4), κ(S) ~ h⁻¹ (×2).
            let rk = k_ii / k0;
            let rs = s / s0;
            assert!((3.0..6.0).contains(&rk), "κ(K_II) ratio {rk}");
            assert!((1.4..3.2).contains(&rs), "κ(S) ratio {rs}");
        }
        previous = Some((k_ii, s));
    }
    // κ is dimensionless: E = 210e9 instead of 1 changes no estimate.
    let steel = converged(&hertz(40, "210e9"), opts);
    let (a, b) = (conditioning(&runs[1]), conditioning(&steel));
    for (x, y) in [(a.k_ii, b.k_ii), (a.s, b.s), (a.w, b.w)] {
        let (x, y) = (x.unwrap(), y.unwrap());
        assert!((x - y).abs() <= 1e-8 * x, "{x} vs {y}");
    }
}

#[test]
fn stiffness_contrast_raises_the_condition_of_s_and_w_not_of_k_ii() {
    // blocks.toml: a pad (E = 10) on a steel base (E = 210); the pad is held
    // by the contact alone (S + ρRRᵀ is what the root factorises).
    let mut previous: Option<Conditioning> = None;
    for young in ["10.0", "0.1"] {
        let text = example("blocks.toml").replace("young = 10.0", &format!("young = {young}"));
        let o = converged(&text, RunOptions::default());
        let c = conditioning(&o).clone();
        assert_eq!(c.k_ii_per_subdomain.len(), 2);
        finite_positive("s", c.s);
        finite_positive("w", c.w);
        assert!(
            c.notes.iter().any(|n| n.contains("S + ρRRᵀ")),
            "{:?}",
            c.notes
        );
        if let Some(p) = previous {
            // Each K_II is homogeneous: its κ does not see the contrast.
            let rk = c.k_ii.unwrap() / p.k_ii.unwrap();
            assert!((rk - 1.0).abs() < 1e-8, "κ(K_II) ratio {rk}");
            // A 100 times softer pad: κ(S) about 100 times larger.
            let rs = c.s.unwrap() / p.s.unwrap();
            assert!((30.0..300.0).contains(&rs), "κ(S) ratio {rs}");
            let rw = c.w.unwrap() / p.w.unwrap();
            assert!((10.0..300.0).contains(&rw), "κ(W) ratio {rw}");
        }
        previous = Some(c);
    }
}

#[test]
fn warning_when_the_tolerance_needs_more_digits_than_are_left() {
    // The default example at its default tolerance (1e-10): no warning.
    let o = converged(&example("hertz2d.toml"), RunOptions::default());
    let c = conditioning(&o);
    assert!(c.warning.is_none(), "{:?}", c.warning);
    assert!(c.digits_available.unwrap() > 10.0);
    assert!(!o.report.messages.iter().any(|m| m.contains("conditioning")));
    // Tolerance 1e-15 asks for 15 digits: more than any mesh leaves.
    let text = hertz(40, "1.0").replace(
        "path = \"condensed\"",
        "path = \"condensed\"\ntolerance = 1e-15",
    );
    let o = try_run(&text, RunOptions::default()).unwrap();
    let c = conditioning(&o);
    assert!((c.digits_needed - 15.0).abs() < 1e-12);
    let w = c.warning.as_ref().expect("a warning at tolerance 1e-15");
    assert!(w.contains("solver.tolerance = 1e-15"), "{w}");
    assert!(o.report.messages.contains(w), "{:?}", o.report.messages);
    // A stiff contrast at the default tolerance: the pad 2·10⁵ times softer
    // than the base costs S about 8 digits, more than 15.65 − 10 allows.
    let text = example("blocks.toml").replace("young = 10.0", "young = 0.001");
    let o = converged(&text, RunOptions::default());
    let c = conditioning(&o);
    assert!(c.digits_available.unwrap() < 10.0, "{c:?}");
    let w = c.warning.as_ref().expect("a warning for the contrast");
    assert!(w.contains("κ₁(S)"), "{w}");
    // In the JSON: null entries, never a missing key.
    let json = serde_json::to_value(&o.report).unwrap();
    let cj = &json["conditioning"];
    assert!(cj["k"].is_null() && cj["warning"].is_string(), "{cj}");
    assert!(cj["k_ii"].as_f64().unwrap() > 1.0);
}

#[test]
fn direct_path_reports_the_condition_of_k() {
    let opts = RunOptions {
        path: Some(SolvePath::Direct),
        ..Default::default()
    };
    // κ(K) costs a factorisation of its own: asked for by the scene
    let asked = hertz(40, "1.0").replace("[solver]", "[solver]\ncondition_estimate = true");
    let direct = converged(&asked, opts.clone());
    let c = conditioning(&direct);
    let k = finite_positive("k", c.k);
    assert!(c.k_ii.is_none() && c.s.is_none() && c.w.is_none());
    assert!(c.k_ii_per_subdomain.is_empty());
    assert!((c.digits_lost.unwrap() - k.log10()).abs() < 1e-12);
    // K_II is K with the interface DOFs removed: no worse conditioned than K
    // (up to the estimator's factor 3).
    let condensed = converged(&hertz(40, "1.0"), RunOptions::default());
    let k_ii = conditioning(&condensed).k_ii.unwrap();
    assert!(k >= k_ii / 3.0, "κ(K) = {k}, κ(K_II) = {k_ii}");
    // κ(K) costs the direct path a factorisation of its own, timed apart and
    // counted in the total; the condensed path's estimates reuse its factors.
    let (td, tc) = (&direct.report.timings_s, &condensed.report.timings_s);
    assert!(td.conditioning > 0.0 && tc.conditioning == 0.0);
    let phases = td.setup + td.assemble + td.contact + td.output + td.conditioning;
    assert!(phases <= td.total, "{td:?}");
    // Not asked for: k is null with the reason, nothing is spent on it, and
    // the solution is the same
    let plain = converged(&hertz(40, "1.0"), opts.clone());
    let c = conditioning(&plain);
    assert!(c.k.is_none() && c.digits_lost.is_none());
    assert!(
        c.notes
            .iter()
            .any(|n| n.contains("solver.condition_estimate = true")),
        "{:?}",
        c.notes
    );
    assert_eq!(plain.report.timings_s.conditioning, 0.0);
    assert_eq!(plain.report.contact_force, direct.report.contact_force);
    // A floating body (blocks.toml's pad): K is singular, k is null with the reason.
    let o = converged(&example("blocks.toml"), opts);
    let c = conditioning(&o);
    assert!(c.k.is_none() && c.digits_lost.is_none());
    assert!(
        c.notes.iter().any(|n| n.contains("floating body")),
        "{:?}",
        c.notes
    );
}

/// A block held by its contact with a rigid plane alone along y, split in
/// `parts` subdomains.
fn floating_block(parts: usize) -> String {
    format!(
        "dimension = 2\nmodel = \"plane_strain\"\n\
         [[materials]]\nname = \"steel\"\nyoung = 210e3\npoisson = 0.3\n\
         [[bodies]]\nname = \"block\"\nmaterial = \"steel\"\nsubdomains = {parts}\n\
         mesh = {{ generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [8, 4] }}\n\
         [[bodies]]\nname = \"ground\"\n\
         rigid = {{ shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }}\n\
         [[boundary]]\nname = \"symmetry\"\nbody = \"block\"\nsurface = \"left\"\ndisplacement = {{ x = 0.0 }}\n\
         [[boundary]]\nname = \"pressure\"\nbody = \"block\"\nsurface = \"top\"\ntraction = [0.0, -100.0]\n\
         [[contact]]\nname = \"c\"\nslave = {{ body = \"block\", surface = \"bottom\" }}\nmaster = {{ body = \"ground\" }}\n"
    )
}

/// The same floating block in one subdomain and in two (as `subdomains =
/// "auto"` makes under mpirun -n 2): W is the contact problem's in one, and
/// in two it is formed with the subdomain tree's generalised inverse of S
/// (fixing DOFs, here a contact DOF), singular by that choice. Found by the
/// fifth robustness sweep: the split runs warned "W is singular: redundant
/// contact constraints" (there are none; the one-subdomain run did not).
#[test]
fn a_floating_block_in_several_subdomains_is_not_said_to_have_redundant_constraints() {
    let one = converged(&floating_block(1), RunOptions::default());
    finite_positive("w", conditioning(&one).w);
    for parts in [2, 4] {
        let o = converged(&floating_block(parts), RunOptions::default());
        let c = conditioning(&o);
        assert!(c.w.is_none() && c.warning.is_none(), "{c:?}");
        assert!(
            c.notes.iter().any(|n| n.contains("by fixing DOFs")),
            "{c:?}"
        );
        let said: Vec<&String> = (o.report.messages.iter())
            .filter(|m| m.contains("redundant"))
            .collect();
        assert!(said.is_empty(), "{said:?}");
        assert!((o.report.contact_force[1] - 100.0).abs() <= 1e-9 * 100.0);
    }
}
