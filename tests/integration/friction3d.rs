//! Friction in 3D (course notes §4.1.1–4.1.2, §4.3; docs/theory/validation-cases.md §5): two tangents
//! per contact point, the Tresca disc, the isotropic and the elliptic
//! Coulomb cone, on a box on a rigid plane.

use crate::common;

use common::{converged, example, try_run};
use signorini_solver::{RunOptions, RunOutput};

/// A 1 × 1 × 0.5 box on the rigid plane z = 0, its top pressed down by
/// 0.01 and, at step 2, moved by `drag` (x, y), or loaded by the traction
/// `traction` instead.
pub(crate) fn box_scene(friction: &str, drag: [f64; 2], top_traction: Option<[f64; 3]>) -> String {
    let load = match top_traction {
        Some([tx, ty, tz]) => format!(
            "[[boundary]]\nname = \"load\"\nbody = \"box\"\nsurface = \"zmax\"\ntraction = [{tx}, {ty}, {tz}]\n"
        ),
        None => format!(
            "[[boundary]]\nname = \"press\"\nbody = \"box\"\nsurface = \"zmax\"\ndisplacement = {{ z = -0.01 }}\n\n[[boundary]]\nname = \"drag\"\nbody = \"box\"\nsurface = \"zmax\"\ndisplacement = {{ x = {}, y = {} }}\n\n[[steps]]\nscale = {{ drag = 0.0 }}\n\n[[steps]]\nscale = {{ drag = 1.0 }}\n",
            drag[0], drag[1]
        ),
    };
    format!(
        r#"dimension = 3
model = "solid"
[[materials]]
name = "m"
young = 100.0
poisson = 0.3
[[bodies]]
name = "box"
material = "m"
mesh = {{ generator = "box", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = [3, 3, 2] }}
[[bodies]]
name = "floor"
rigid = {{ shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
{load}
{}discretization = "node_to_face"
friction = {friction}
"#,
        common::contact("c", "box", "zmin", "floor")
    )
}

/// Normal and tangential (x, y) resultants of the contact forces on the box
/// at the last step.
fn resultants(out: &RunOutput) -> (f64, f64, f64) {
    let f = &out.report.contact_force;
    (f[2], f[0], f[1])
}

/// Every slipping point lies on its cone (‖(λ_t1/μ1, λ_t2/μ2)‖ = λ_n) with
/// its tangential force opposite to its slip increment (maximal dissipation
/// on an isotropic cone); returns the number of slipping points.
fn slip_points_on_the_cone(out: &RunOutput, mu: [f64; 2], step: usize) -> usize {
    let n_max = out
        .contact_rows
        .iter()
        .fold(0.0f64, |a, r| a.max(r.normal_force));
    let mut slipping = 0;
    for r in out
        .contact_rows
        .iter()
        .filter(|r| r.step == step && r.status == "slip")
    {
        let (t1, t2) = (r.tangential_force, r.tangential_force_2);
        let on = ((t1 / mu[0]).powi(2) + (t2 / mu[1]).powi(2)).sqrt();
        // in force units along t1 (the certificate's cone measure)
        assert!(
            mu[0] * (on - r.normal_force).abs() <= 1e-9 * n_max,
            "{on} vs {}",
            r.normal_force
        );
        slipping += 1;
    }
    slipping
}

#[test]
fn box_dragged_past_the_isotropic_cone_slides_with_reaction_mu_n_in_any_direction() {
    for drag in [[0.1, 0.0], [0.0, 0.1], [0.06, -0.08]] {
        let out = converged(
            &box_scene("{ coulomb = 0.3 }", drag, None),
            RunOptions::default(),
        );
        assert_eq!(
            slip_points_on_the_cone(&out, [0.3, 0.3], 2),
            16,
            "drag {drag:?}"
        );
        let (n, tx, ty) = resultants(&out);
        let t = tx.hypot(ty);
        // every point slips, mostly along the drag (Poisson's effect adds a
        // small sideways slip that cancels in the resultant): |T| ≈ μN
        assert!(
            t <= 0.3 * n * (1.0 + 1e-9) && t >= 0.3 * n * 0.999,
            "drag {drag:?}: |T| = {t}, 0.3 N = {}",
            0.3 * n
        );
        // opposite to the motion
        let d = drag[0].hypot(drag[1]);
        assert!(
            (tx * drag[0] + ty * drag[1]) / (t * d) < -1.0 + 1e-9,
            "drag {drag:?}: T = ({tx}, {ty})"
        );
        assert!(out.report.certificate.dissipation <= 1e-9);
        // solved by the Newton method on Coulomb's law, and named so
        assert_eq!(
            out.report.steps[1].solver["method"], "coulomb_3d_semismooth_newton",
            "drag {drag:?}"
        );
        // the same friction in any direction: the same |T|/N up to the
        // sideways slip, which depends on the direction on a square mesh
        let x = converged(
            &box_scene("{ coulomb = 0.3 }", [0.1, 0.0], None),
            RunOptions::default(),
        );
        let (nx, ax, ay) = resultants(&x);
        assert!((ax.hypot(ay) / nx - t / n).abs() <= 1e-3 * 0.3, "{drag:?}");
    }
}

#[test]
fn elliptic_cone_gives_mu1_along_t1_and_mu2_along_t2() {
    for (drag, mu) in [([0.1, 0.0], 0.3), ([0.0, 0.1], 0.1)] {
        let out = converged(
            &box_scene("{ coulomb = [0.3, 0.1] }", drag, None),
            RunOptions::default(),
        );
        assert_eq!(slip_points_on_the_cone(&out, [0.3, 0.1], 2), 16);
        let (n, tx, ty) = resultants(&out);
        let t = tx.hypot(ty);
        // the sideways (Poisson) slip meets the other coefficient: within 0.5 %
        assert!(
            t <= 0.3 * n && (t - mu * n).abs() <= 5e-3 * mu * n,
            "drag {drag:?}: |T| = {t}, μN = {}",
            mu * n
        );
    }
}

#[test]
fn tresca_disc_slip_points_carry_the_threshold() {
    let g = 0.05;
    let out = converged(
        &box_scene(&format!("{{ tresca = {g} }}"), [0.1, 0.05], None),
        RunOptions::default(),
    );
    let rows: Vec<_> = out.contact_rows.iter().filter(|r| r.step == 2).collect();
    assert!(rows.iter().all(|r| r.status == "slip"));
    // the resultant of the thresholds g × area is g × 1 (the whole face slides)
    let (_, tx, ty) = resultants(&out);
    let t = tx.hypot(ty);
    assert!(t <= g * (1.0 + 1e-9) && t >= g * 0.999, "{t}");
    for r in rows {
        let t = r.tangential_force.hypot(r.tangential_force_2);
        assert!(t <= g * (1.0 + 1e-9), "{t}");
    }
}

#[test]
fn box_held_by_friction_alone_sticks_below_mu_n_with_the_exact_reaction() {
    // no support in x, y: the traction (q, q/2, −p) on the top is held by
    // friction, ‖q‖ < μ p
    let (p, q) = (1.0, 0.2);
    let out = converged(
        &box_scene("{ coulomb = 0.5 }", [0.0, 0.0], Some([q, q / 2.0, -p])),
        RunOptions::default(),
    );
    let (n, tx, ty) = resultants(&out);
    assert!((n - p).abs() <= 1e-9 * p, "{n}");
    assert!(
        (tx + q).abs() <= 1e-9 * p && (ty + q / 2.0).abs() <= 1e-9 * p,
        "({tx}, {ty})"
    );
    assert!(out.contact_rows.iter().all(|r| r.status == "stick"));
}

#[test]
fn zero_friction_equals_the_frictionless_answer_in_3d() {
    let a = converged(
        &box_scene("{ coulomb = 0.0 }", [0.05, 0.0], None),
        RunOptions::default(),
    );
    let b = converged(
        &box_scene("\"none\"", [0.05, 0.0], None),
        RunOptions::default(),
    );
    let fa: Vec<f64> = a.contact_rows.iter().map(|r| r.normal_force).collect();
    let fb: Vec<f64> = b.contact_rows.iter().map(|r| r.normal_force).collect();
    assert!(common::max_rel(&fa, &fb) <= 1e-9);
    assert!(a
        .contact_rows
        .iter()
        .all(|r| r.tangential_force == 0.0 || r.tangential_force.abs() <= 1e-12));
}

#[test]
fn sliding3d_example_meets_its_reference() {
    let out = converged(&example("sliding3d.toml"), RunOptions::default());
    let q = &out.report.reference.as_ref().unwrap().quantities;
    assert!(
        q["tangential_reaction"].relative_error <= 1e-3,
        "{:?}",
        q["tangential_reaction"]
    );
    assert!(out.report.certificate.cone <= 1e-9);
    assert!(out.report.certificate.dissipation <= 1e-9);
}

/// `friction = "nsgs"` in a scene: the sliding block by NSGS gives the
/// semi-smooth Newton method's normal and tangential forces (both to the
/// tolerance 1e-10: within 1e-8 of the largest) and meets the reference.
#[test]
fn sliding3d_by_nsgs_gives_the_newton_forces() {
    let text = example("sliding3d.toml");
    let newton = converged(&text, RunOptions::default());
    let nsgs_text = text.replacen("[solver]", "[solver]\nfriction = \"nsgs\"", 1);
    assert_ne!(nsgs_text, text);
    let nsgs = converged(&nsgs_text, RunOptions::default());
    assert_eq!(nsgs.report.solver["method"], "coulomb_3d_nsgs");
    let rows = |o: &RunOutput| -> Vec<f64> {
        let r = o.contact_rows.iter();
        r.flat_map(|r| [r.normal_force, r.tangential_force])
            .collect()
    };
    assert!(common::max_rel(&rows(&nsgs), &rows(&newton)) <= 1e-8);
    let q = &nsgs.report.reference.as_ref().unwrap().quantities;
    assert!(q["tangential_reaction"].relative_error <= 1e-3);
}

#[test]
fn force_above_mu_n_under_force_control_is_refused_in_3d() {
    let text = box_scene(
        "{ coulomb = [0.3, 0.2] }",
        [0.0, 0.0],
        Some([0.5, 0.0, -1.0]),
    );
    match common::try_run(&text, RunOptions::default()) {
        Err(signorini_solver::SolveError::Input(m)) => {
            assert!(
                m.contains("\"box\"") && m.contains("exceeds what friction can hold"),
                "{m}"
            )
        }
        Err(e) => panic!("expected bad input, got {e}"),
        Ok(_) => panic!("no equilibrium exists"),
    }
}

/// Regularised Coulomb (elastic slip k_e, course notes §4.1.3) in 3D tends to
/// Coulomb as k_e grows; a soft k_e lets the box move with less friction
/// mobilised at the same drag.
#[test]
fn regularised_coulomb_tends_to_coulomb_in_3d() {
    let exact = converged(
        &box_scene("{ coulomb = 0.3 }", [0.002, 0.001], None),
        RunOptions::default(),
    );
    let (_, ex, ey) = resultants(&exact);
    let previous = common::assert_falls_with_stiffness(&[1e2, 1e4, 1e6, 1e8], |k| {
        let out = converged(
            &box_scene(
                &format!("{{ coulomb = 0.3, slip_stiffness = {k:e} }}"),
                [0.002, 0.001],
                None,
            ),
            RunOptions::default(),
        );
        let (_, tx, ty) = resultants(&out);
        (tx - ex).hypot(ty - ey) / ex.hypot(ey)
    });
    assert!(previous <= 1e-4, "k_e = 1e8: error {previous}");
}

/// An elliptic cone with one zero coefficient is friction along one
/// direction alone, not a cone: refused when the scene is read, naming the
/// entry (it was accepted and then ended on a certificate of 3.7e-2, exit 2).
#[test]
fn an_elliptic_cone_with_one_zero_coefficient_is_refused() {
    for mu in ["[0.0, 0.3]", "[0.3, 0.0]"] {
        let scene = box_scene(&format!("{{ coulomb = {mu} }}"), [0.1, 0.0], None);
        let err = signorini_scene::parse_toml(&scene).unwrap_err().to_string();
        assert!(err.contains(".friction.coulomb"), "{err}");
        assert!(err.contains("both coefficients > 0"), "{err}");
    }
    // [0, 0] is frictionless, and solves.
    let scene = box_scene("{ coulomb = [0.0, 0.0] }", [0.1, 0.0], None);
    assert!(signorini_scene::parse_toml(&scene).is_ok());
}

/// One 3D contact point whose fixed point on the threshold leaves the
/// Newton step of the frictional status no unknown to fill: it ended in an
/// internal error ("chunk size must be non-zero"); it converges, as the
/// semi-smooth Newton method does on the same problem.
#[test]
fn a_one_point_3d_coulomb_problem_solves_by_the_fixed_point() {
    let dir = common::fresh_dir("friction3d", "one_point");
    let path = dir.join("problem.json");
    std::fs::write(
        &path,
        r#"{"W": [[5.962854287233117, -3.4251439003826314, 0.2294775135860126], [-3.4251439003826314, 4.955101867767738, -1.1370253499553562], [0.2294775135860126, -1.1370253499553562, 2.993911467343311]], "q": [-0.3455746252117428, 3.100763748567835, 1.5976508413735158], "mu": [1.0], "dim": 3}"#,
    )
    .unwrap();
    for friction in ["fixed_point", "newton"] {
        let out = std::process::Command::new(common::BIN)
            .args(["local", "--friction", friction])
            .arg(&path)
            .output()
            .unwrap();
        let text = common::stdout_of_success(&out, friction);
        let r: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
        assert_eq!(r["converged"], true, "{text}");
        assert!(r["residual"].as_f64().unwrap() < 1e-9, "{text}");
    }
}

/// Cattaneo–Mindlin for two spheres (docs/theory/validation-cases.md §6): a hemisphere
/// pressed on a block of the same material, then moved sideways. Found by a
/// sweep of unseen scenes: the reference used the cylinder's formulas,
/// c = a·sqrt(1 − Q/(μP)) with a = sqrt(4PR/(πE*)), 2.4 times smaller than
/// the sphere's c = a·(1 − Q/(μP))^(1/3), a = (3PR/(4E*))^(1/3).
#[test]
fn cattaneo_mindlin_sphere_stick_zone_is_the_sphere_formula() {
    let out = converged(&sphere_on_block(), RunOptions::default());
    let q = &out.report.reference.as_ref().unwrap().quantities;
    let (load, ratio) = (q["load"].computed, q["tangential_load_ratio"].computed);
    assert!(ratio > 0.2 && ratio < 0.6, "partial slip: Q/μP = {ratio}");
    let e_star = 1.0 / (2.0 * (1.0 - 0.3f64 * 0.3));
    let c = (3.0 * load / (4.0 * e_star)).cbrt() * (1.0 - ratio).cbrt();
    let sw = &q["stick_half_width"];
    assert!((sw.exact - c).abs() <= 1e-12 * c, "{sw:?} vs {c}");
    assert!(sw.relative_error <= 0.05, "stick half-width {sw:?}");
    let last = out.report.steps.last().unwrap();
    assert!(last.sticking > 0 && last.slipping > 0);
}

/// An axisymmetric model cannot carry a tangential load across the contact:
/// the reference is refused, naming the models that can.
#[test]
fn cattaneo_mindlin_is_refused_in_an_axisymmetric_model() {
    let text = example("hertz_axi.toml")
        .replace(
            "discretization = \"node_to_segment\"",
            "discretization = \"node_to_segment\"\nfriction = { coulomb = 0.3 }",
        )
        .replace("kind = \"hertz_sphere\"", "kind = \"cattaneo_mindlin\"");
    match try_run(&text, RunOptions::default()) {
        Err(e) => assert!(e.to_string().contains("axisymmetric"), "{e}"),
        Ok(_) => panic!("cattaneo_mindlin in an axisymmetric model was accepted"),
    }
}

/// A hemisphere pressed onto a graded box, then pulled sideways (Coulomb
/// friction 0.3): the Cattaneo–Mindlin reference.
pub(crate) fn sphere_on_block() -> String {
    let flat = "surface = \"flat\"";
    let no_y = "displacement = { y = 0.0 }";
    [
        "dimension = 3\nmodel = \"solid\"\n".to_string(),
        common::material("s", 1.0, 0.3),
        common::body("sph", "s", "{ generator = \"hemisphere\", center = [0.0, 0.0, 1.0], radius = 1.0, divisions = 12, pole = [0.0, 0.0, -1.0], grading = 10.0 }"),
        common::body("blk", "s", "{ generator = \"box\", origin = [-0.3, -0.3, -0.3], size = [0.6, 0.6, 0.3], divisions = [14, 14, 4], grading = { towards = \"zmax\", ratio = 6.0 } }"),
        common::boundary("press", "sph", flat, "displacement = { z = -0.01 }"),
        common::boundary("pull", "sph", flat, "displacement = { x = 0.0012 }"),
        common::boundary("pin", "sph", "point = [1.0, 0.0, 1.0]", no_y),
        common::boundary("pin2", "sph", "point = [-1.0, 0.0, 1.0]", no_y),
        common::boundary("clamp", "blk", "surface = \"zmin\"", "displacement = { x = 0.0, y = 0.0, z = 0.0 }"),
        common::contact_between("c", ("sph", "dome"), ("blk", "zmax")),
        r#"discretization = "node_to_face"
friction = { coulomb = 0.3 }
[[steps]]
scale = { press = 1.0, pull = 0.0 }
[[steps]]
scale = { press = 1.0, pull = 1.0 }
[solver]
method = "status"
path = "condensed"

[reference]
kind = "cattaneo_mindlin"
radius = 1.0
"#
        .to_string(),
    ]
    .concat()
}

/// Norton–Hoff in 3D (course notes §4.1.4, eq. 19, isotropic in the tangent plane):
/// on the box pressed, then dragged along (0.06, 0.08), every point in
/// contact carries |λ_t| = μ λ_n ‖Δs‖^ρ opposite to its slip increment Δs
/// over the step, and the resultant rises to Coulomb's μN as ρ → 0. At
/// some ρ (0.05 here) the fixed point of the first step, pressed without
/// drag (Poisson slips of 1e-4 and less), cycles between stick and slip:
/// it stops as stalled and says why, never converged.
#[test]
fn norton_hoff_in_3d_holds_its_law_and_tends_to_coulomb() {
    let drag = [0.06, 0.08];
    let stalled = try_run(
        &box_scene("{ norton_hoff = 0.3, rho = 0.05 }", drag, None),
        RunOptions::default(),
    );
    let stalled = stalled.expect("solved, converged or not");
    assert!(!stalled.report.converged);
    let reason = stalled.report.steps[0].solver["stopping_reason"].to_string();
    assert!(
        reason.contains("alternate between stick and slip"),
        "{reason}"
    );
    let mut last = 0.0;
    for rho in [0.2, 0.1, 0.01, 0.001] {
        let friction = format!("{{ norton_hoff = 0.3, rho = {rho} }}");
        let out = converged(&box_scene(&friction, drag, None), RunOptions::default());
        assert_eq!(out.report.steps[1].solver["method"], "norton_hoff_3d");
        let (n, tx, ty) = resultants(&out);
        let ratio = tx.hypot(ty) / n;
        assert!(
            ratio > last && ratio < 0.3,
            "ρ = {rho}: |T|/N = {ratio} (previous {last})"
        );
        last = ratio;
        let rows = |step: usize| out.contact_rows.iter().filter(move |r| r.step == step);
        let mut checked = 0;
        for (r1, r2) in rows(1).zip(rows(2)) {
            assert_eq!(r1.point, r2.point);
            let ds = [r2.slip - r1.slip, r2.slip_2 - r1.slip_2];
            let (ds_norm, lt) = (
                ds[0].hypot(ds[1]),
                [r2.tangential_force, r2.tangential_force_2],
            );
            if r2.normal_force <= 0.0 || ds_norm <= 1e-6 {
                continue;
            }
            let law = 0.3 * r2.normal_force * ds_norm.powf(rho);
            let lt_norm = lt[0].hypot(lt[1]);
            assert!((lt_norm - law).abs() <= 1e-6 * law, "ρ = {rho}: {r2:?}");
            let cosine = (lt[0] * ds[0] + lt[1] * ds[1]) / (lt_norm * ds_norm);
            assert!(cosine <= -1.0 + 1e-9, "ρ = {rho}: {r2:?}");
            checked += 1;
        }
        assert_eq!(checked, 16, "ρ = {rho}: slipping points");
    }
    assert!((last - 0.3).abs() <= 0.003, "ρ = 0.001: |T|/N = {last}");
}

/// examples/assembly3d.toml (a steel cylinder pressing a steel block into a
/// rubber pad, Gmsh tet4 meshes, mortar, Coulomb μ = 0.3 on both contacts)
/// with its mesh paths made absolute, the load of its third step,
/// `displacement = { x = 0.1 }`, replaced by `drag` (a displacement, or a
/// force with the cylinder then held sideways by friction alone) and, with
/// `swap`, the other body of each contact as slave.
fn assembly(drag: &str, swap: bool) -> String {
    let mut text =
        common::example_with_meshes("assembly3d.toml").replace("displacement = { x = 0.1 }", drag);
    if swap {
        for (upper, lower) in [("cylinder", "block"), ("block", "pad")] {
            let pair = |s: &str, m: &str, ss: &str, ms: &str| {
                format!("slave = {{ body = \"{s}\", surface = \"{ss}\" }}\nmaster = {{ body = \"{m}\", surface = \"{ms}\" }}")
            };
            let before = pair(upper, lower, "bottom", "top");
            assert!(text.contains(&before), "{before}");
            text = text.replace(&before, &pair(lower, upper, "top", "bottom"));
        }
    }
    text
}

/// The normal force and the tangential force (x, y) of a contact at the
/// last step, on its slave.
fn contact_nt(out: &RunOutput, name: &str) -> (f64, [f64; 2]) {
    let f = common::contact_force(out, name);
    (f[2].abs(), [f[0], f[1]])
}

/// The mean x displacement of a body at the last step.
fn mean_x(out: &RunOutput, body: &str) -> f64 {
    let b = out.bodies.iter().find(|b| b.name == body).unwrap();
    let u = &b.last().displacement;
    let n = u.len() / 3;
    (0..n).map(|i| u[3 * i]).sum::<f64>() / n as f64
}

/// Each step of an assembly run names the method that solved it, the same
/// as its solver report, and a fallback only with the method that gave way.
fn methods_named(out: &RunOutput) {
    for (i, s) in out.report.steps.iter().enumerate() {
        assert_eq!(s.solver["method"], s.method.as_str(), "step {}", i + 1);
        assert!(s.method.starts_with("coulomb_3d_"), "{}", s.method);
        if let Some(f) = &s.fallback {
            assert!(
                f.starts_with("coulomb_3d_semismooth_newton stopped: "),
                "{f}"
            );
            assert_eq!(s.method, "coulomb_3d_fixed_point");
        }
    }
}

/// The assembly dragged 0.1 mm (the case that ended with exit 1, 'singular
/// Newton system'): solved, with both slave choices, the tangential force of
/// each contact between that of the 0.07 mm drag and μ N, equal and opposite
/// at the two contacts of the block (held by them alone), against the drag
/// on the cylinder, and the cylinder moving further along the drag than the
/// block.
#[test]
fn a_stiff_block_on_a_soft_pad_dragged_0_1_mm_solves_between_the_known_bounds() {
    for swap in [false, true] {
        let small = converged(
            &assembly("displacement = { x = 0.07 }", swap),
            RunOptions::default(),
        );
        let out = converged(
            &assembly("displacement = { x = 0.1 }", swap),
            RunOptions::default(),
        );
        methods_named(&out);
        let sign = if swap { -1.0 } else { 1.0 };
        let (n, t) = contact_nt(&out, "cylinder-block");
        let (_, t_small) = contact_nt(&small, "cylinder-block");
        let (n2, t2) = contact_nt(&out, "block-pad");
        let tn = t[0].hypot(t[1]);
        assert!(
            sign * t[0] < 0.0,
            "{t:?}: friction on the cylinder against the drag"
        );
        assert!(
            tn > t_small[0].hypot(t_small[1]) && tn < 0.3 * n,
            "{tn} vs {t_small:?}, μN {}",
            0.3 * n
        );
        assert!(t2[0].hypot(t2[1]) < 0.3 * n2, "{t2:?} {n2}");
        // the block's equilibrium: the same resultant through both contacts
        let scale = n.max(n2);
        assert!((t[0] - t2[0]).abs() <= 1e-8 * scale, "{t:?} {t2:?}");
        assert!((n - n2).abs() <= 1e-8 * scale, "{n} {n2}");
        assert!(mean_x(&out, "cylinder") > mean_x(&out, "block") && mean_x(&out, "block") > 0.0);
    }
}

/// The assembly with its cylinder pushed sideways by `push` (its top held
/// along y and pressed 0.2 mm along z in one step, free along x: held along
/// x by friction alone), then pushed at step 2.
fn pushed_assembly(push: f64) -> String {
    let two_presses =
        "[[steps]]\nscale = { press = 1.0, drag = 0.0 }\n\n[[steps]]\nscale = { press = 2.0 }\n";
    let text = assembly(&format!("force = [{push}, 0.0, 0.0]"), false);
    assert!(text.contains(two_presses));
    text.replace(
        two_presses,
        "[[steps]]\nscale = { press = 2.0, drag = 0.0 }\n",
    )
}

/// The cylinder pushed sideways from 10 % to 85 % of μ N (N of the press
/// alone): solved, the push carried whole through both contacts (the
/// cylinder's and the block's equilibrium) within μ N of each at the normal
/// force reached, and both bodies moving along the push, the cylinder
/// further.
#[test]
fn a_sideways_push_below_mu_n_is_held_by_friction() {
    // the normal force of each contact once pressed (step 1 of every run)
    let n = 313.1;
    for fraction in [0.1, 0.5, 0.85] {
        let push = fraction * 0.3 * n;
        let out = converged(&pushed_assembly(push), RunOptions::default());
        let pressed = out.report.steps[0].normal_force / 2.0;
        assert!((pressed - n).abs() <= 1e-3 * n, "{pressed}");
        methods_named(&out);
        for contact in ["cylinder-block", "block-pad"] {
            let (nc, t) = contact_nt(&out, contact);
            let at = format!("{contact}, {fraction} μN: {t:?}, N {nc}");
            assert!((t[0] + push).abs() <= 1e-8 * n, "{at}");
            // y is held by the cylinder's support: a mesh's asymmetry only
            assert!(t[1].abs() <= 1e-3 * nc && push <= 0.3 * nc, "{at}");
        }
        let (uc, ub) = (mean_x(&out, "cylinder"), mean_x(&out, "block"));
        assert!(uc > ub && ub > 0.0, "{uc} {ub}");
    }
}

/// The assembly of [`pushed_assembly`] with the other body of each contact
/// as slave when `swap`.
fn pushed_assembly_with(push: f64, swap: bool) -> String {
    let text = pushed_assembly(push);
    if !swap {
        return text;
    }
    let pair = |s: &str, m: &str, ss: &str, ms: &str| {
        format!("slave = {{ body = \"{s}\", surface = \"{ss}\" }}\nmaster = {{ body = \"{m}\", surface = \"{ms}\" }}")
    };
    let mut text = text;
    for (upper, lower) in [("cylinder", "block"), ("block", "pad")] {
        let before = pair(upper, lower, "bottom", "top");
        assert!(text.contains(&before), "{before}");
        text = text.replace(&before, &pair(lower, upper, "top", "bottom"));
    }
    text
}

/// The push lowers the normal force (313 N pressed, block slave; 362.5 N
/// pad slave): pushes at 90, 95 and 99 % of μ N at the normal force they
/// reach (found by running: N 290.7, 288.4, 284.8 N; pad slave N 333.0,
/// 330.1, 325.9 N). Each solved by the Newton method on Coulomb's law
/// (it ended with exit 2 from 90 % of μ·313 N up: its floating bodies'
/// rigid motions came from a singular status solve; at half of μ N, pad
/// slave, it cycled for minutes), the push carried whole through both
/// contacts, the tangential force along it, every point inside its cone.
#[test]
fn a_sideways_push_close_to_mu_n_is_held_by_friction() {
    let cases = [
        (false, 78.6, 0.90),
        (false, 82.0, 0.95),
        (false, 84.71, 0.99),
        (true, 89.94, 0.90),
        (true, 94.08, 0.95),
        (true, 96.8, 0.99),
    ];
    for (swap, push, fraction) in cases {
        // the scene's tolerance (1e-8), not common::converged's 1e-9
        let out = try_run(&pushed_assembly_with(push, swap), RunOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(out.report.converged, "{:?}", out.report.failure);
        methods_named(&out);
        let step = &out.report.steps[1];
        assert_eq!(step.method, "coulomb_3d_semismooth_newton");
        let sign = if swap { 1.0 } else { -1.0 };
        for contact in ["cylinder-block", "block-pad"] {
            let (nc, t) = contact_nt(&out, contact);
            let at = format!("{contact}, swap {swap}, push {push}: {t:?}, N {nc}");
            assert!((t[0] - sign * push).abs() <= 1e-8 * nc, "{at}");
            assert!(t[1].abs() <= 1e-2 * t[0].abs(), "{at}");
            let ratio = push / (0.3 * nc);
            assert!(
                ratio <= 1.0 && (ratio - fraction).abs() <= 0.01,
                "{at}: {ratio}"
            );
        }
        let cert = &out.report.certificate;
        assert!(cert.max() <= cert.tolerance, "{cert:?}");
    }
}

/// Pushes beyond μ N (110 % of μ N at the largest push held, both slave
/// choices; pad slave also 102.5 % of it): exit 2 saying friction cannot
/// hold the load, step 1 solved.
#[test]
fn a_push_past_mu_n_at_the_normal_force_reached_says_friction_cannot_hold_it() {
    for (swap, push) in [(false, 94.0), (true, 108.2), (true, 99.3)] {
        let out = try_run(&pushed_assembly_with(push, swap), RunOptions::default())
            .unwrap_or_else(|e| panic!("a valid scene is not bad input: {e}"));
        assert!(!out.report.converged && out.report.steps[0].converged);
        let failure = out.report.failure.clone().unwrap_or_default();
        // the overload found (the holding check), or the inner solves
        // stalled and the note on the body held by friction alone
        let overload = failure.contains("the load friction cannot hold")
            || failure.contains("is held by friction alone in 1 rigid motion(s)");
        assert!(overload, "{failure}");
        assert!(failure.contains("body \"cylinder\""), "{failure}");
    }
    // 101 % of μ N at the largest push held (block slave): its inner solves
    // stall (they ran for minutes); exit 2 within a few seconds, naming the
    // body held by friction alone and the load beyond it
    let out = try_run(&pushed_assembly_with(86.3, false), RunOptions::default())
        .unwrap_or_else(|e| panic!("a valid scene is not bad input: {e}"));
    assert!(!out.report.converged && out.report.steps[0].converged);
    let failure = out.report.failure.clone().unwrap_or_default();
    let needles = [
        "step 2: coulomb_3d_fixed_point",
        "body \"cylinder\" is held by friction alone",
        "beyond what friction carries",
    ];
    for needle in needles {
        assert!(failure.contains(needle), "{needle} in {failure}");
    }
}

/// A 100 N push, beyond μ N (about 94 N): no static equilibrium. Exit 2
/// (not converged, not bad input) with a message that names the step, the
/// body, its load, what friction can hold and the contact; step 1 solved.
#[test]
fn a_push_beyond_mu_n_says_friction_cannot_hold_it() {
    let out = try_run(&pushed_assembly(100.0), RunOptions::default())
        .unwrap_or_else(|e| panic!("a valid scene is not bad input: {e}"));
    assert!(!out.report.converged && out.report.steps[0].converged);
    let n = out.report.steps[0].normal_force / 2.0;
    assert!(100.0 > 0.3 * n, "{n}");
    let failure = out.report.failure.clone().unwrap_or_default();
    let needles = [
        "step 2: coulomb_3d_",
        "the load friction cannot hold",
        "body \"cylinder\"",
        "1.0000e2",
        "over contact(s) \"cylinder-block\"",
    ];
    for needle in needles {
        assert!(failure.contains(needle), "{needle} in {failure}");
    }
    let holds: f64 = failure
        .rsplit("\"cylinder-block\", ")
        .next()
        .and_then(|t| t.split(':').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{failure}"));
    assert!(
        holds < 100.0 && holds > 0.9 * 0.3 * n,
        "{holds} vs μN {}",
        0.3 * n
    );
    methods_named(&out);
}

/// The box scenes of this module on the direct path: dragged past the
/// isotropic cone, within the Tresca disc, held by friction alone below
/// μ N, with zero friction and with regularised Coulomb give the condensed
/// path's forces, slips and displacements (the elliptic cone, sliding3d and
/// the Cattaneo–Mindlin sphere: tests/integration/direct_friction.rs).
#[test]
fn the_box_scenes_have_the_condensed_forces_on_the_direct_path() {
    use common::twins::on_both_paths;
    for drag in [[0.1, 0.0], [0.06, 0.08]] {
        on_both_paths(&box_scene("{ coulomb = 0.3 }", drag, None), 1e-8);
    }
    on_both_paths(&box_scene("{ tresca = 0.05 }", [0.1, 0.05], None), 1e-8);
    let (q, p) = (0.2, 1.0);
    on_both_paths(
        &box_scene("{ coulomb = 0.5 }", [0.0, 0.0], Some([q, q / 2.0, -p])),
        1e-8,
    );
    on_both_paths(&box_scene("{ coulomb = 0.0 }", [0.05, 0.0], None), 1e-8);
    for k in [1e2, 1e8] {
        let friction = format!("{{ coulomb = 0.3, slip_stiffness = {k:e} }}");
        on_both_paths(&box_scene(&friction, [0.002, 0.001], None), 1e-8);
    }
}

/// Norton–Hoff in 3D is left to the condensed path: refused on the direct
/// path naming the law, and `auto` takes the condensed path.
#[test]
fn norton_hoff_in_3d_is_refused_on_the_direct_path() {
    let text = box_scene("{ norton_hoff = 0.3, rho = 0.2 }", [0.1, 0.0], None);
    common::twins::refused_on_direct(&text, &["Norton-Hoff"]);
}

/// The pushed assembly (held along x by friction alone) on the direct path:
/// the push below μ N gives the condensed path's forces, within the
/// assembly's stopping tests.
#[test]
fn the_pushed_assembly_has_the_condensed_forces_on_the_direct_path() {
    let text = pushed_assembly(0.5 * 0.3 * 313.1).replace(
        "tolerance = 1e-8\n",
        "tolerance = 1e-8\ntime_limit = 3600.0\n",
    );
    assert!(text.contains("time_limit"));
    // 7.9e-7 measured: the stopping tests' force scales of
    // `the_assembly_agrees_on_both_paths_within_each_paths_stopping_test`
    // (tolerance 1e-8 times 1.9e5 N against point forces of 13 N) admit
    // up to 1.6e-4
    common::twins::on_both_paths(&text, 1e-5);
}

/// The three-body assembly dragged 0.07 mm on both paths: the contact
/// forces agree within what each path's stopping test admits, the
/// tolerance times its force scale (report `certificate.force_scale`).
/// They do not agree to 1e-8 relative: the direct path's force scale is
/// that of its whole system's load (K u_p of the pressed steel cylinder at
/// the free DOFs beside its top, 1.9e5 N), the condensed path's that of
/// its load on the interface (2.5e4 N), both far above the contact forces
/// (13 N at most a point): at the scene's tolerance 1e-8 the direct path
/// stops 3.8e-5 (relative to the largest point force) from its own answer
/// at 1e-10, which is within 4.1e-7 of the condensed path's
/// (docs/performance/condensed-vs-direct.md). The same rigid modes, a
/// stopping test on another scale.
#[test]
fn the_assembly_agrees_on_both_paths_within_each_paths_stopping_test() {
    use signorini_scene::SolvePath;
    // a time limit well above the run (the direct path's first step takes
    // 78 Newton iterations: on a loaded machine over the default limit)
    let text = assembly("displacement = { x = 0.07 }", false).replace(
        "tolerance = 1e-8\n",
        "tolerance = 1e-8\ntime_limit = 3600.0\n",
    );
    assert!(text.contains("time_limit"));
    let on = |path| {
        let out = try_run(
            &text,
            RunOptions {
                method: None,
                path: Some(path),
            },
        )
        .unwrap_or_else(|e| panic!("{e}"));
        assert!(out.report.converged, "{path:?}: {:?}", out.report.failure);
        out
    };
    let (c, d) = (on(SolvePath::Condensed), on(SolvePath::Direct));
    let forces = common::twins::contact_forces;
    let (fc, fd) = (forces(&c), forces(&d));
    let difference = fc
        .iter()
        .zip(&fd)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    let (cc, cd) = (&c.report.certificate, &d.report.certificate);
    let bound = cc.tolerance * cc.force_scale + cd.tolerance * cd.force_scale;
    assert!(difference <= bound, "{difference:e} against {bound:e}");
    // the bound is not vacuous: well below the largest point force
    let largest = fc.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(bound <= 1e-3 * largest, "{bound:e} vs {largest:e}");
    // and the direct path's scale is the larger (what the bound explains)
    assert!(cd.force_scale > 4.0 * cc.force_scale, "{cc:?} {cd:?}");
}
