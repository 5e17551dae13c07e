//! Coulomb friction on the condensed problem (docs/theory/validation-cases.md §5, §7; course notes §4).

use crate::common;

use common::{block_body, block_contact, example, named_block_boundary, rigid_plane};
use signorini_solver::{RunOptions, RunOutput, SolveError};

fn solve(text: &str) -> Result<RunOutput, SolveError> {
    common::try_run(text, RunOptions::default())
}

/// Solves, asserting convergence and the certificate.
fn converged(text: &str) -> RunOutput {
    common::converged(text, RunOptions::default())
}

/// Resultants (normal, tangential) of the contact forces at a step.
fn resultants(o: &RunOutput, step: usize) -> (f64, f64) {
    o.contact_rows
        .iter()
        .filter(|r| r.step == step)
        .fold((0.0, 0.0), |(n, t), r| {
            (n + r.normal_force, t + r.tangential_force)
        })
}

/// A block on a rigid plane, pressed down by an imposed displacement of its
/// top, with no support in x: sideways it is held by friction alone.
fn block(friction: &str, top: &str, left_force: f64, extra: &str) -> String {
    [
        common::block_pressed_on_floor(top),
        named_block_boundary(
            "push",
            r#"surface = "left""#,
            &format!("force = [{left_force}, 0.0]"),
        ),
        block_contact("c", "bottom", "floor"),
        format!("friction = {friction}\n{extra}\n"),
    ]
    .concat()
}

#[test]
fn sliding_block_sticks_below_mu_n_with_the_exact_reaction() {
    for (mu, q) in [(0.3, 0.1), (0.3, 0.5), (1.0, 1.5), (2.0, 3.0)] {
        let out = converged(&block(
            &format!("{{ coulomb = {mu} }}"),
            "{ y = -0.01 }",
            q,
            "",
        ));
        let (n, t) = resultants(&out, 1);
        assert!(q < mu * n, "the case must stick: Q = {q}, μN = {}", mu * n);
        assert!(
            (t + q).abs() <= 1e-9 * q,
            "μ = {mu}: tangential reaction {t} vs −{q}"
        );
        assert!(out.report.steps[0].sticking > 0);
    }
}

#[test]
fn sliding_block_driven_past_mu_n_slides_with_reaction_mu_n() {
    for mu in [0.3, 1.0, 2.0] {
        for solver in ["fixed_point", "status", "newton"] {
            let text = block(
                &format!("{{ coulomb = {mu} }}"),
                "{ x = 0.2, y = -0.01 }",
                0.0,
                &format!("[solver]\nfriction = \"{solver}\""),
            );
            let out = converged(&text);
            let (n, t) = resultants(&out, 1);
            assert!(
                t < 0.0,
                "the friction on the block opposes its motion in +x"
            );
            // Every slipping point is on the cone, every sticking one inside it.
            for r in &out.contact_rows {
                match r.status {
                    "slip" => assert!(
                        (r.tangential_force.abs() - mu * r.normal_force).abs() <= 1e-9 * mu * n
                    ),
                    "stick" => {
                        assert!(r.tangential_force.abs() <= mu * r.normal_force * (1.0 + 1e-9))
                    }
                    _ => assert_eq!(r.normal_force, 0.0),
                }
            }
            if mu < 0.5 {
                // A low friction lets the whole block slide: the reaction is μN.
                assert!(
                    (t.abs() - mu * n).abs() <= 1e-9 * mu * n,
                    "μ = {mu} ({solver}): |T| = {t}, μN = {}",
                    mu * n
                );
                assert!(out
                    .contact_rows
                    .iter()
                    .all(|r| r.status == "slip" && r.slip > 0.0));
            }
        }
    }
}

#[test]
fn zero_friction_equals_the_frictionless_answer() {
    let hertz = std::fs::read_to_string(format!(
        "{}/examples/hertz2d.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace("divisions = 160", "divisions = 64");
    let with = common::with_friction(&hertz, "node_to_segment", "{ coulomb = 0.0 }");
    assert_ne!(with, hertz);
    let a = converged(&hertz);
    let b = converged(&with);
    for (x, y) in a.contact_rows.iter().zip(&b.contact_rows) {
        assert!(
            (x.normal_force - y.normal_force).abs() <= 1e-10 * a.report.contact_force[1],
            "{} vs {}",
            x.normal_force,
            y.normal_force
        );
        assert!(y.tangential_force.abs() <= 1e-12 * a.report.contact_force[1]);
    }
}

/// The block with `friction`, its top displaced by `top` and no push, solved
/// (converged, certified).
fn pressed(friction: &str, top: &str) -> RunOutput {
    converged(&block(friction, top, 0.0, ""))
}

/// The block with `friction`, its top displaced by `top`, solved as it is
/// and with the `[solver]` line `solver`; asserts that the first is a
/// partial slip case.
fn partial_slip_two_ways(friction: &str, top: &str, solver: &str) -> (RunOutput, RunOutput) {
    let base = block(friction, top, 0.0, "");
    let a = converged(&base);
    let b = converged(&base.replace(
        &format!("friction = {friction}"),
        &format!("friction = {friction}\n[solver]\n{solver}"),
    ));
    assert!(
        a.report.steps[0].sticking > 0 && a.report.steps[0].slipping > 0,
        "a partial slip case"
    );
    (a, b)
}

#[test]
fn friction_status_method_and_fixed_point_agree() {
    let (a, b) = partial_slip_two_ways(
        "{ coulomb = 0.4 }",
        "{ x = 0.004, y = -0.01 }",
        "friction = \"status\"",
    );
    for (x, y) in a.contact_rows.iter().zip(&b.contact_rows) {
        assert_eq!(x.status, y.status);
        assert!(
            (x.tangential_force - y.tangential_force).abs() <= 1e-8,
            "{} vs {}",
            x.tangential_force,
            y.tangential_force
        );
    }
    assert_eq!(a.report.steps[0].solver["method"], "coulomb_fixed_point");
    assert_eq!(b.report.steps[0].solver["method"], "friction_status");
}

#[test]
fn regularised_coulomb_tends_to_coulomb_as_the_slip_stiffness_grows() {
    let exact = pressed("{ coulomb = 0.4 }", "{ x = 0.004, y = -0.01 }");
    let last = common::assert_falls_with_stiffness(&[1e2, 1e4, 1e6, 1e8], |k| {
        let out = pressed(
            &format!("{{ coulomb = 0.4, slip_stiffness = {k:e} }}"),
            "{ x = 0.004, y = -0.01 }",
        );
        (exact.contact_rows.iter().zip(&out.contact_rows)).fold(0.0f64, |a, (x, y)| {
            a.max((x.tangential_force - y.tangential_force).abs())
        })
    });
    assert!(last <= 1e-5, "{last:e}");
}

#[test]
fn load_reversal_reverses_the_friction_and_keeps_the_slip_history() {
    // Push to +x past μN (slide), then back to −x: the friction force reverses.
    let text = block(
        "{ coulomb = 0.3 }",
        "{ x = 0.05, y = -0.01 }",
        0.0,
        "[[steps]]\nscale = { press = 1.0 }\n[[steps]]\nscale = { press = -1.0 }\n",
    );
    // Keep the normal displacement fixed: split the imposed displacement in two entries.
    let text = text.replace(
        "displacement = { x = 0.05, y = -0.01 }",
        "displacement = { x = 0.05 }\n[[boundary]]\nname = \"down\"\nbody = \"block\"\nsurface = \"top\"\ndisplacement = { y = -0.01 }",
    );
    let out = converged(&text);
    let (n1, t1) = resultants(&out, 1);
    let (n2, t2) = resultants(&out, 2);
    assert!(
        (t1 + 0.3 * n1).abs() <= 1e-9 * n1,
        "step 1 slides in +x: {t1}"
    );
    assert!(
        (t2 - 0.3 * n2).abs() <= 1e-9 * n2,
        "step 2 slides back: {t2}"
    );
    // The slip history: the total slip at step 2 is that of step 1 plus the increment.
    let slips = |step: usize| common::at_step(&out, step, |r| r.slip);
    let (s1, s2) = (slips(1), slips(2));
    assert!(
        s1.iter().all(|&s| s > 0.0) && s2.iter().all(|&s| s < 0.0),
        "{s1:?} {s2:?}"
    );
}

#[test]
fn a_tangential_force_above_mu_n_has_no_equilibrium_and_says_so() {
    match solve(&block("{ coulomb = 0.3 }", "{ y = -0.01 }", 1.0, "")) {
        Err(SolveError::Input(m)) => assert!(
            m.contains("floating body") || m.contains("equilibrium"),
            "{m}"
        ),
        Ok(o) => assert!(!o.report.converged, "a force above μN cannot be held"),
        Err(e) => panic!("{e}"),
    }
}

/// docs/theory/validation-cases.md §6 on the shipped example: the stick zone of two elastically
/// similar bodies is a·sqrt(1 − Q/(μP)) within 5 %.
#[test]
fn cattaneo_mindlin_stick_zone_matches_the_analytic_half_width() {
    let out = converged(&example("cattaneo.toml"));
    let q = &out.report.reference.as_ref().unwrap().quantities;
    let c = &q["stick_half_width"];
    assert!(
        c.relative_error <= 0.05,
        "stick half-width {} vs {}",
        c.computed,
        c.exact
    );
    let ratio = q["tangential_load_ratio"].computed;
    assert!(
        ratio > 0.2 && ratio < 0.8,
        "a partial-slip case: Q/μP = {ratio}"
    );
    let last = out.report.steps.last().unwrap();
    assert!(last.sticking > 0 && last.slipping > 0);
    // The slip zones are at the edges: every slipping point lies outside the stick zone.
    let rows: Vec<_> = out
        .contact_rows
        .iter()
        .filter(|r| r.step == 2 && r.status != "open")
        .collect();
    let centre = rows.iter().map(|r| r.normal_force * r.x[0]).sum::<f64>()
        / rows.iter().map(|r| r.normal_force).sum::<f64>();
    let stick_max = rows
        .iter()
        .filter(|r| r.status == "stick")
        .map(|r| (r.x[0] - centre).abs())
        .fold(0.0, f64::max);
    assert!(rows
        .iter()
        .filter(|r| r.status == "slip")
        .all(|r| (r.x[0] - centre).abs() > stick_max * 0.9));
}

/// Cattaneo–Mindlin unloaded (found by a fourth robustness sweep): the
/// example pulled to Q* then back to Q = Q*/2 has the stick zone of Mindlin
/// and Deresiewicz, c' = a·sqrt(1 − (Q* − Q)/(2μP)); the reference compared
/// it with monotone loading to Q, c = a·sqrt(1 − Q/(μP)), and reported a
/// 9.4 % error (and 51 % on the shear profile) where the computed stick zone
/// is within 1.6 % of c'.
#[test]
fn cattaneo_mindlin_unloaded_is_compared_with_mindlin_deresiewicz() {
    let text = example("cattaneo.toml") + "\n[[steps]]\nscale = { press = 1.0, pull = 0.5 }\n";
    let out = converged(&text);
    let reference = out.report.reference.as_ref().unwrap();
    let q = &reference.quantities;
    let steps = &out.report.steps;
    let (peak, now) = (
        steps[1].contact_force[0].abs(),
        steps[2].contact_force[0].abs(),
    );
    assert!((now / peak - 0.5).abs() <= 1e-9, "{peak} {now}");
    let (load, mu) = (q["load"].computed, 0.3);
    let e_star = 1.0 / (2.0 * (1.0 - 0.3f64 * 0.3));
    let a = (4.0 * load / (std::f64::consts::PI * e_star)).sqrt();
    let c = a * (1.0 - (peak - now) / (2.0 * mu * load)).sqrt();
    let sw = &q["stick_half_width"];
    assert!((sw.exact - c).abs() <= 1e-9 * c, "{sw:?} vs {c}");
    assert!(sw.relative_error <= 0.03, "stick half-width {sw:?}");
    assert!(q["shear_profile_l2"].relative_error <= 0.4, "{q:?}");
    assert!(
        reference.notes.iter().any(|n| n.contains("not monotone")),
        "{:?}",
        reference.notes
    );
}

/// Cyclic tangential loading +Q → −Q → +Q: the force–slip curve is a loop
/// that returns to its +Q tip, and the contact unloaded to Q = 0 keeps a slip
/// that the first loading did not have (the state depends on the history).
#[test]
fn cyclic_tangential_loading_traces_a_closed_hysteresis_loop() {
    let out = converged(&example("cyclic.toml"));
    let s = &out.report.steps;
    assert_eq!(s.len(), 11);
    let q = s[2].tangential_force;
    assert!(
        (s[10].tangential_force - q).abs() <= 1e-9 * q.abs(),
        "the +Q tips: {} vs {q}",
        s[10].tangential_force
    );
    assert!(
        (s[6].tangential_force + q).abs() <= 1e-9 * q.abs(),
        "the −Q tip"
    );
    // The loop closes at +Q (within the discrete stick/slip transition of one node).
    let (a, b) = (s[2].mean_slip, s[10].mean_slip);
    assert!(
        (a - b).abs() <= 0.05 * a.abs(),
        "slip at the +Q tips: {a:e} vs {b:e}"
    );
    // Unloaded to 0 after +Q and after −Q: opposite locked-in slips, not the virgin state.
    assert!(s[0].mean_slip.abs() <= 1e-6 * a.abs());
    assert!(
        s[4].mean_slip > 0.3 * a && s[8].mean_slip < -0.3 * a,
        "{} {}",
        s[4].mean_slip,
        s[8].mean_slip
    );
    // Going up and coming down at the same load differ: hysteresis.
    assert!((s[1].mean_slip - s[3].mean_slip).abs() > 0.5 * s[1].mean_slip.abs());
}

/// Tresca (course notes §4.1.1) by the projection method (box-constrained MPRGP on
/// the forces) and by the status method: the same answer where the contact
/// is closed everywhere, partly sticking and partly slipping.
#[test]
fn tresca_by_projection_equals_tresca_by_statuses() {
    // Pinned in x at the top so that the projection method (no rigid modes) applies.
    let (a, b) = partial_slip_two_ways(
        "{ tresca = 0.12 }",
        "{ x = 0.003, y = -0.01 }",
        "method = \"mprgp\"",
    );
    assert!(a.contact_rows.iter().all(|r| r.status != "open"));
    assert_eq!(b.report.steps[0].solver["method"], "tresca_mprgp_box");
    for (x, y) in a.contact_rows.iter().zip(&b.contact_rows) {
        assert_eq!(x.status, y.status);
        assert!(
            (x.tangential_force - y.tangential_force).abs() <= 1e-8 * 0.12,
            "{} vs {}",
            x.tangential_force,
            y.tangential_force
        );
        assert!(
            (x.normal_force - y.normal_force).abs() <= 1e-8,
            "{} vs {}",
            x.normal_force,
            y.normal_force
        );
        // Slipping points carry exactly the threshold: g times the tributary
        // length (normal force / pressure).
        if x.status == "slip" {
            let tributary = x.normal_force / x.pressure;
            assert!(
                (x.tangential_force.abs() - 0.12 * tributary).abs() <= 1e-9,
                "{}",
                x.tangential_force
            );
        }
    }
}

/// Norton–Hoff (course notes §4.1.4) tends to Coulomb as ρ → 0: on a block driven
/// past μN the tangential reaction μN·|Δs|^ρ rises monotonically to μN.
#[test]
fn norton_hoff_tends_to_coulomb_as_rho_goes_to_zero() {
    let coulomb = pressed("{ coulomb = 0.3 }", "{ x = 0.2, y = -0.01 }");
    let (n, t) = resultants(&coulomb, 1);
    assert!((t.abs() - 0.3 * n).abs() <= 1e-9 * n);
    let mut last = 0.0;
    for rho in [0.2, 0.05, 0.01, 0.001] {
        let out = pressed(
            &format!("{{ norton_hoff = 0.3, rho = {rho} }}"),
            "{ x = 0.2, y = -0.01 }",
        );
        assert_eq!(out.report.steps[0].solver["method"], "norton_hoff");
        let (n, t) = resultants(&out, 1);
        let ratio = t.abs() / n;
        assert!(
            ratio > last && ratio < 0.3,
            "ρ = {rho}: T/N = {ratio} (previous {last})"
        );
        last = ratio;
        // Point by point: |λ_t| = μ λ_n |Δs|^ρ.
        for r in out.contact_rows.iter().filter(|r| r.normal_force > 0.0) {
            let slip = r.slip.abs();
            assert!(
                (r.tangential_force.abs() - 0.3 * r.normal_force * slip.powf(rho)).abs()
                    <= 1e-8 * n,
                "ρ = {rho}"
            );
        }
    }
    assert!((last - 0.3).abs() <= 0.003, "ρ = 0.001: T/N = {last}");
}

/// Tiny loads (1e-12 of the others): the same answer, scaled — every
/// tolerance is relative to the problem's own force and length scales.
#[test]
fn tiny_loads_give_the_scaled_answer() {
    let big = converged(&block("{ coulomb = 0.3 }", "{ y = -0.01 }", 0.5, ""));
    let tiny = converged(&block("{ coulomb = 0.3 }", "{ y = -1e-14 }", 5e-13, ""));
    for (a, b) in big.contact_rows.iter().zip(&tiny.contact_rows) {
        assert_eq!(a.status, b.status);
        assert!(
            (a.normal_force * 1e-12 - b.normal_force).abs()
                <= 1e-9 * 1e-12 * big.report.contact_force[1]
        );
        assert!(
            (a.tangential_force * 1e-12 - b.tangential_force).abs()
                <= 1e-9 * 1e-12 * big.report.contact_force[1]
        );
    }
}

/// Under force control a block pushed past μN has no equilibrium
/// (docs/theory/validation-cases.md §5): bad input naming the body and both forces, not a
/// failing solve.
#[test]
fn force_above_mu_n_under_force_control_is_refused_with_the_numbers() {
    let text = block("{ coulomb = 0.3 }", "{ y = -0.01 }", 0.0, "")
        .replace("displacement = { y = -0.01 }", "traction = [0.0, -1.0]")
        .replace("force = [0, 0.0]", "force = [1.0, 0.0]");
    assert!(text.contains("force = [1.0, 0.0]"), "{text}");
    match solve(&text) {
        Err(SolveError::Input(m)) => {
            assert!(
                m.contains("\"block\"") && m.contains("exceeds what friction can hold"),
                "{m}"
            );
            assert!(
                m.contains("6e-1") || m.contains("5.99999"),
                "μ|N| = 0.6 named: {m}"
            );
        }
        Err(e) => panic!("expected bad input, got {e}"),
        Ok(_) => panic!("a block pushed past μN under force control has no equilibrium"),
    }
    // below μN it sticks with the exact reaction
    let below = text.replace("force = [1.0, 0.0]", "force = [0.5, 0.0]");
    let out = converged(&below);
    let (n, t) = resultants(&out, 1);
    assert!(
        (n - 2.0).abs() <= 1e-9 * 2.0 && (t + 0.5).abs() <= 1e-9,
        "({n}, {t})"
    );
}

/// The `contact.csv` rows of a CLI run: (step, point, status) and the
/// normal and tangential forces.
fn contact_csv(out: &std::path::Path) -> (Vec<String>, Vec<f64>) {
    let text = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (step, point, status) = (col("step"), col("point"), col("status"));
    let (normal, tangential) = (col("normal_force"), col("tangential_force"));
    let (mut keys, mut forces) = (Vec::new(), Vec::new());
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        keys.push(format!("{} {} {}", f[step], f[point], f[status]));
        forces.push(f[normal].parse().unwrap());
        forces.push(f[tangential].parse().unwrap());
    }
    (keys, forces)
}

#[test]
fn newton_gives_the_contact_forces_of_the_default_method_on_the_cattaneo_example() {
    let dir = common::fresh_dir("friction", "newton");
    let scene = dir.join("cattaneo_newton.toml");
    let text = example("cattaneo.toml") + "\n[solver]\nfriction = \"newton\"\n";
    std::fs::write(&scene, text).unwrap();
    common::cli_run_ok(common::example_path("cattaneo.toml"), dir.join("default"));
    common::cli_run_ok(&scene, dir.join("newton"));
    let (keys_d, forces_d) = contact_csv(&dir.join("default"));
    let (keys_n, forces_n) = contact_csv(&dir.join("newton"));
    assert_eq!(keys_d, keys_n, "steps, points and statuses");
    assert!(
        keys_d.iter().any(|k| k.ends_with("slip")) && keys_d.iter().any(|k| k.ends_with("stick"))
    );
    let rel = common::max_rel(&forces_d, &forces_n);
    assert!(rel < 1e-8, "contact forces differ by {rel:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// examples/ssnv128.toml (a plate pressed, then pushed sideways below μN,
/// held in x by friction alone): the friction forces balance the push and
/// the pressure exactly, part of the face sticks and part slips on the
/// cone, and the fixed point, the friction status method and the 2D Newton
/// give the same forces.
#[test]
fn ssnv128_like_plate_balances_the_push_by_partial_slip() {
    let text = example("ssnv128.toml").replace("divisions = [160, 40]", "divisions = [80, 20]");
    let runs: Vec<RunOutput> = ["fixed_point", "status", "newton"]
        .iter()
        .map(|f| converged(&format!("{text}\n[solver]\nfriction = \"{f}\"\n")))
        .collect();
    let (n, t) = resultants(&runs[0], 2);
    assert!((n - 200.0).abs() <= 1e-9 * 200.0, "normal {n}");
    assert!((t - 150.0).abs() <= 1e-9 * 200.0, "tangential {t}");
    let step = &runs[0].report.steps[1];
    assert!(step.sticking > 0 && step.slipping > 0, "{step:?}");
    for r in runs[0].contact_rows.iter().filter(|r| r.step == 2) {
        assert!(r.tangential_force.abs() <= r.normal_force * (1.0 + 1e-9) + 1e-9 * 200.0);
        if r.status == "slip" {
            assert!((r.tangential_force.abs() - r.normal_force).abs() <= 1e-8 * 200.0);
        }
    }
    for other in &runs[1..] {
        for (x, y) in runs[0].contact_rows.iter().zip(&other.contact_rows) {
            assert!(
                (x.tangential_force - y.tangential_force).abs() <= 1e-6 * 200.0,
                "{} vs {}",
                x.tangential_force,
                y.tangential_force
            );
        }
    }
}

/// A block pressed on a rigid plane with Norton–Hoff friction, dragged by
/// 0.02 × `drag` at step 1 and by 0.02 at step 2.
fn norton_hoff_block(rho: f64, drag: [f64; 2]) -> String {
    common::material_head(2, "plane_strain", 100.0, 0.3)
        + &block_body([0.0, 0.0], [1.0, 0.5], [8, 4], "")
        + &rigid_plane("floor", [0.0, 0.0], [0.0, 1.0])
        + &named_block_boundary("press", "surface = \"top\"", "displacement = { y = -0.01 }")
        + &named_block_boundary("drag", "surface = \"top\"", "displacement = { x = 0.02 }")
        + &block_contact("c", "bottom", "floor")
        + &format!("discretization = \"node_to_segment\"\nfriction = {{ norton_hoff = 0.3, rho = {rho} }}\n")
        + &format!("[[steps]]\nscale = {{ press = 1.0, drag = {} }}\n", drag[0])
        + &format!("[[steps]]\nscale = {{ press = 1.0, drag = {} }}\n", drag[1])
}

/// Norton–Hoff over two load steps: the law holds on the second step's slip
/// increment, |λ_t| = μ λ_n |Δs|^ρ (the second step was refused as "singular:
/// the statuses do not hold a floating body", started from the first
/// step's statuses; found by a robustness sweep). Pressed without drag at
/// the first step (Poisson slips only, and none at the middle node), the
/// fixed point used to stop as stalled: a stuck point (no slip) asked its
/// force to oppose a slip of zero; a slip below the floor is now no slip,
/// its force within the floor's threshold.
#[test]
fn norton_hoff_over_two_steps_holds_its_law_on_each_increment() {
    for (rho, drag) in [(0.2, [0.5, 1.0]), (0.2, [0.0, 1.0]), (0.001, [0.0, 1.0])] {
        let out = common::converged(&norton_hoff_block(rho, drag), RunOptions::default());
        let rows = |step: usize| out.contact_rows.iter().filter(move |r| r.step == step);
        let mut checked = 0;
        for (r1, r2) in rows(1).zip(rows(2)) {
            assert_eq!(r1.point, r2.point);
            let ds = (r2.slip - r1.slip).abs();
            if r2.normal_force > 0.0 && ds > 1e-6 {
                let law = 0.3 * r2.normal_force * ds.powf(rho);
                assert!(
                    (r2.tangential_force.abs() - law).abs() <= 1e-6 * law,
                    "ρ = {rho}, drag {drag:?}: {r2:?}"
                );
                checked += 1;
            }
        }
        assert!(
            checked >= 5,
            "ρ = {rho}, drag {drag:?}: {checked} slipping points"
        );
    }
}

/// blocks.toml with Coulomb friction (μ = 0.3), pressed then unloaded to no
/// load over two more steps.
fn pad_unloaded_to_no_load() -> String {
    common::with_friction(&example("blocks.toml"), "node_to_node", "{ coulomb = 0.3 }")
        + "\n[[steps]]\nscale = { pressure = 1.0 }\n[[steps]]\nscale = { pressure = 0.0 }\n"
}

/// A pad held by contact alone with friction, pressed then unloaded to no
/// load at all (found by a fourth robustness sweep): the unloaded step's
/// force and length scales were its own round-off (2.5e-32 and 6.7e-16), the
/// inner Tresca problem cycled on forces of 1e-32 and the run ended with
/// exit 2 ("cycling even with one status change per iteration", certificate
/// tension 1.0). A friction step's scales are now at least those of the
/// steps before: the unloaded step is solved, with no force left.
#[test]
fn a_pad_with_friction_unloaded_to_no_load_is_solved_with_no_force() {
    let out = converged(&pad_unloaded_to_no_load());
    let force = |step: usize| {
        let forces = common::at_step(&out, step, |r| {
            r.normal_force.abs().max(r.tangential_force.abs())
        });
        forces.into_iter().fold(0.0, f64::max)
    };
    assert!(force(1) > 0.1, "pressed: {}", force(1));
    assert!(force(2) <= 1e-12 * force(1), "unloaded: {}", force(2));
}

/// The scenes of this module on the direct path (its semi-smooth Newton
/// method on the whole system): the block sticking below μN with the push
/// held by friction alone, sliding past μN (fixed point and Newton asked
/// for), partly slipping with Coulomb and regularised Coulomb, and at tiny
/// loads, give the condensed path's forces, slips and displacements.
#[test]
fn the_block_scenes_have_the_condensed_forces_on_the_direct_path() {
    use common::twins::on_both_paths;
    for (mu, q) in [(0.3, 0.1), (2.0, 3.0)] {
        let friction = format!("{{ coulomb = {mu} }}");
        on_both_paths(&block(&friction, "{ y = -0.01 }", q, ""), 1e-8);
    }
    for (mu, solver) in [(0.3, "fixed_point"), (1.0, "newton"), (2.0, "fixed_point")] {
        let text = block(
            &format!("{{ coulomb = {mu} }}"),
            "{ x = 0.2, y = -0.01 }",
            0.0,
            &format!("[solver]\nfriction = \"{solver}\""),
        );
        on_both_paths(&text, 1e-8);
    }
    for friction in [
        "{ coulomb = 0.4 }",
        "{ coulomb = 0.4, slip_stiffness = 1e2 }",
        "{ coulomb = 0.4, slip_stiffness = 1e8 }",
        "{ tresca = 0.12 }",
    ] {
        on_both_paths(&block(friction, "{ x = 0.004, y = -0.01 }", 0.0, ""), 1e-8);
    }
    on_both_paths(
        &block("{ coulomb = 0.3 }", "{ y = -1e-14 }", 5e-13, ""),
        1e-8,
    );
}

/// The shipped and derived examples of this module on the direct path:
/// Cattaneo–Mindlin unloaded, the cyclic loading, the pad unloaded to no
/// load, Hertz with zero friction and a push held under force control.
#[test]
fn the_friction_examples_have_the_condensed_forces_on_the_direct_path() {
    use common::twins::on_both_paths;
    let unloaded = example("cattaneo.toml") + "\n[[steps]]\nscale = { press = 1.0, pull = 0.5 }\n";
    on_both_paths(&unloaded, 1e-8);
    on_both_paths(&example("cyclic.toml"), 1e-8);
    on_both_paths(&pad_unloaded_to_no_load(), 1e-8);
    let hertz = example("hertz2d.toml").replace("divisions = 160", "divisions = 64");
    let hertz = common::with_friction(&hertz, "node_to_segment", "{ coulomb = 0.0 }");
    on_both_paths(&hertz, 1e-8);
    let held = block("{ coulomb = 0.3 }", "{ y = -0.01 }", 0.0, "")
        .replace("displacement = { y = -0.01 }", "traction = [0.0, -1.0]")
        .replace("force = [0, 0.0]", "force = [0.5, 0.0]");
    on_both_paths(&held, 1e-8);
}

/// What the direct path leaves to the condensed path, refused there as bad
/// input naming the entry (and `auto` takes the condensed path): the
/// friction status method, Tresca by the box-constrained MPRGP, and
/// Norton–Hoff friction (one step and two).
#[test]
fn the_direct_path_refuses_the_status_method_mprgp_and_norton_hoff_naming_them() {
    use common::twins::refused_on_direct;
    let partial = "{ x = 0.004, y = -0.01 }";
    let status = "[solver]\nfriction = \"status\"";
    let mprgp = "[solver]\nmethod = \"mprgp\"";
    for (friction, top, extra, needle) in [
        (
            "{ coulomb = 0.4 }",
            partial,
            status,
            "solver.friction = \"status\"",
        ),
        (
            "{ tresca = 0.12 }",
            "{ x = 0.003, y = -0.01 }",
            mprgp,
            "mprgp",
        ),
        (
            "{ norton_hoff = 0.3, rho = 0.2 }",
            "{ x = 0.2, y = -0.01 }",
            "",
            "Norton-Hoff",
        ),
    ] {
        refused_on_direct(&block(friction, top, 0.0, extra), &[needle]);
    }
    refused_on_direct(&norton_hoff_block(0.2, [0.5, 1.0]), &["Norton-Hoff"]);
}
