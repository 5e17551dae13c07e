//! Friction by analogy with plasticity (course notes §6): the regularised Coulomb
//! law with roughness, linear kinematic hardening of the slip. A thin, very
//! stiff block under a uniform pressure p on a rigid plane, its top dragged
//! by a prescribed tangential displacement u through load steps: loading,
//! unloading and reversal against the closed forms (per unit area
//! t = k_e (u − g), ‖t − Q g‖ ≤ μ p):
//! - elastic: T = k_e u A;
//! - every point slipping: g = (k_e u − μ p)/(k_e + Q), so
//!   T = μ N k_e/(k_e + Q) + k_e Q/(k_e + Q) u A (N = p A);
//! - unloading: elastic, slope k_e A;
//! - reversal: yields when t − Q g reaches −μ p, i.e. at
//!   u = g + (Q g − μ p)/k_e, then T = −μ N k_e/(k_e + Q) + k_e Q/(k_e + Q) u A.

use crate::common;

use signorini_contact::law::hardening::return_map;
use signorini_solver::{RunOptions, RunOutput, SolveError};

const K_E: f64 = 100.0;
const Q: f64 = 25.0;
const MU: f64 = 0.3;
const P: f64 = 1.0;
/// The drag at scale 1.
const U: f64 = 0.01;
/// The drag scales of the steps: elastic loading, slip, elastic unloading,
/// reversal.
const SCALES: [f64; 9] = [0.1, 0.2, 1.0, 1.5, 1.3, 1.1, 0.95, 0.5, -1.0];

/// The block (2 × 0.05 in 2D, 2 × 2 × 0.05 in 3D, E = 1e7, ν = 0) pressed
/// by the traction p and dragged along x (and y in 3D when `diagonal`) by
/// its top and a node at mid-height of its side.
fn scene(dim: usize, friction: &str, diagonal: bool) -> String {
    let steps = common::drag_steps(&SCALES);
    let (mesh, top, bottom, normal, traction, drag) = if dim == 2 {
        (
            r#"{ generator = "rectangle", origin = [0.0, 0.0], size = [2.0, 0.05], divisions = [20, 2] }"#,
            "top",
            "bottom",
            "[0.0, 1.0]",
            format!("[0.0, {:?}]", -P),
            format!("{{ x = {U:?} }}"),
        )
    } else {
        let d = if diagonal { U / 2f64.sqrt() } else { 0.0 };
        let x = if diagonal { d } else { U };
        (
            r#"{ generator = "box", origin = [0.0, 0.0, 0.0], size = [2.0, 2.0, 0.05], divisions = [8, 8, 2] }"#,
            "zmax",
            "zmin",
            "[0.0, 0.0, 1.0]",
            format!("[0.0, 0.0, {:?}]", -P),
            format!("{{ x = {x:?}, y = {d:?} }}"),
        )
    };
    // A node at mid-height moves with the top: the block may not turn about
    // its top (a rigid mode the top's tangential support leaves free).
    let (origin, model, disc, mid) = if dim == 2 {
        (
            "[0.0, 0.0]",
            "plane_strain",
            "node_to_segment",
            "[0.0, 0.025]",
        )
    } else {
        (
            "[0.0, 0.0, 0.0]",
            "solid",
            "node_to_face",
            "[0.0, 1.0, 0.025]",
        )
    };
    let boundaries = common::press_drag_hold("block", top, &traction, &drag, mid);
    format!(
        r#"{}{}[[bodies]]
name = "floor"
rigid = {{ shape = "plane", point = {origin}, normal = {normal} }}
{boundaries}[[contact]]
name = "c"
slave = {{ body = "block", surface = "{bottom}" }}
master = {{ body = "floor" }}
discretization = "{disc}"
friction = {friction}
[solver]
tolerance = 1e-14
{steps}"#,
        common::material_head(dim, model, 1e7, 0.0),
        common::elastic_body("block", mesh),
    )
}

fn rough(q: f64) -> String {
    format!("{{ coulomb = {MU:?}, slip_stiffness = {K_E:?}, roughness = {q:?} }}")
}

fn converged(text: &str) -> RunOutput {
    common::converged(text, RunOptions::default())
}

/// (N, T1, T2) at a step (1-based), T the tangential traction on the block
/// along the drag: minus the reported friction force on the slave.
fn resultants(o: &RunOutput, step: usize) -> (f64, f64, f64) {
    let rows = o.contact_rows.iter().filter(|r| r.step == step);
    rows.fold((0.0, 0.0, 0.0), |(n, t, t2), r| {
        (
            n + r.normal_force,
            t - r.tangential_force,
            t2 - r.tangential_force_2,
        )
    })
}

/// The closed form of T on the plastic branch (sign +1 loading, −1 reversal).
fn plastic(n: f64, u: f64, area: f64, sign: f64) -> f64 {
    sign * MU * n * K_E / (K_E + Q) + K_E * Q / (K_E + Q) * u * area
}

/// Relative tolerance: the block's shear compliance against the asperities'
/// (k_e h/G = 1e-6), with margin. The solver's tolerance is 1e-14: its
/// force scale is that of the drag imposed on the stiff block (E u ≈ 1e5),
/// eight orders above the contact forces.
const TOL: f64 = 1e-5;

fn assert_close(what: &str, got: f64, want: f64, scale: f64) {
    assert!(
        (got - want).abs() <= TOL * scale,
        "{what}: {got:e} vs the closed form {want:e}"
    );
}

/// The scene without the node that keeps the block from turning about its
/// top: the block is free normal to the contact and to turn about its top.
fn free_to_turn(text: &str) -> String {
    let start = text.find("[[boundary]]\nname = \"hold\"").unwrap();
    let end = start + text[start..].find("[[contact]]").unwrap();
    let text = format!("{}{}", &text[..start], &text[end..]);
    let steps: Vec<String> = text
        .lines()
        .map(|l| match l.find(", hold = ") {
            Some(i) if l.starts_with("scale = {") => format!("{} }}", &l[..i]),
            _ => l.to_string(),
        })
        .collect();
    let out = steps.join("\n");
    assert!(!out.contains("hold") && out.contains("scale = { drag = 0.1 }"));
    out
}

/// Loading, unloading and reversal along x (2D, or 3D dragged along x).
fn drag_follows_the_closed_forms(dim: usize) {
    drag_of_the_scene_follows_the_closed_forms(dim, &scene(dim, &rough(Q), false));
}

/// [`drag_follows_the_closed_forms`] on the scene `text`.
fn drag_of_the_scene_follows_the_closed_forms(dim: usize, text: &str) {
    let area = if dim == 2 { 2.0 } else { 4.0 };
    let out = converged(text);
    let n_total = P * area;
    let scale = MU * n_total;
    for (i, &s) in SCALES.iter().enumerate() {
        let (n, t, t2) = resultants(&out, i + 1);
        let u = s * U;
        assert_close(&format!("N at step {}", i + 1), n, n_total, n_total);
        assert!(t2.abs() <= TOL * scale, "no force across the drag: {t2:e}");
        match i {
            // Elastic loading: T = k_e u A.
            0 | 1 => assert_close("elastic T", t, K_E * u * area, scale),
            // Every point slips.
            2 | 3 => assert_close("plastic T", t, plastic(n, u, area, 1.0), scale),
            _ => {}
        }
    }
    // Elastic unloading from the tip (steps 4 → 5 → 6): slope k_e A.
    let tip = resultants(&out, 4).1;
    for step in [5, 6] {
        let du = (SCALES[step - 1] - SCALES[3]) * U;
        let t = resultants(&out, step).1;
        assert_close(
            &format!("unloading step {step}"),
            t,
            tip + K_E * area * du,
            scale,
        );
    }
    // Reversal: u_rev = g + (Q g − μ p)/k_e with g the slip at the tip.
    let g = (K_E * SCALES[3] * U - MU * P) / (K_E + Q);
    let u_rev = g + (Q * g - MU * P) / K_E;
    assert!(SCALES[7] * U < u_rev && u_rev < SCALES[6] * U, "{u_rev}");
    let (n, t, _) = resultants(&out, 9);
    assert_close(
        "reversed T",
        t,
        plastic(n, SCALES[8] * U, area, -1.0),
        scale,
    );
    slips_follow_the_return_mapping(&out, dim);
    interior_points_reverse_at_the_closed_form(&out, dim);
}

/// Every point at every step: its traction and slip are the closed-form
/// return mapping from its slip at the previous step, at its own normal
/// force N_i (the block's edges carry a pressure concentration, and its
/// turning under the drag shifts the pressure: the points do not all yield
/// at once), with k_e and Q times its tributary area.
fn slips_follow_the_return_mapping(out: &RunOutput, dim: usize) {
    let h = if dim == 2 { 0.1 } else { 0.25 };
    let tributary = |x: &[f64; 3]| -> f64 {
        let edge = |c: f64| {
            if c.abs() < 1e-9 || (c - 2.0).abs() < 1e-9 {
                0.5
            } else {
                1.0
            }
        };
        if dim == 2 {
            h * edge(x[0])
        } else {
            h * h * edge(x[0]) * edge(x[1])
        }
    };
    let mut slip = std::collections::BTreeMap::<usize, f64>::new();
    let (mut yielded, mut elastic) = (0, 0);
    for (i, &s) in SCALES.iter().enumerate() {
        let u = s * U;
        for r in out.contact_rows.iter().filter(|r| r.step == i + 1) {
            let a = tributary(&r.x);
            let g_old = slip.get(&r.point).copied().unwrap_or(0.0);
            let mu_n = MU * r.normal_force;
            let rm = return_map(&[u], &[g_old], mu_n, K_E * a, Q * a);
            let what = format!("step {} point {} ({dim}D)", i + 1, r.point);
            let t = -r.tangential_force;
            assert_close(&format!("{what}: t"), t, rm.traction[0], MU * P * a);
            assert!(
                (r.slip - rm.slip[0]).abs() <= TOL * U,
                "{what}: g {} vs the return mapping {}",
                r.slip,
                rm.slip[0]
            );
            if rm.slipped {
                yielded += 1;
                // On the threshold: t − Q g = ±μ N_i.
                assert_close(&what, (t - Q * a * r.slip).abs(), mu_n, mu_n);
            } else {
                elastic += 1;
            }
            slip.insert(r.point, r.slip);
        }
    }
    assert!(yielded > 0 && elastic > 0, "{yielded} {elastic}");
}

/// The interior points (away from the edges' pressure concentration) leave
/// the elastic unloading for reverse slip between the closed-form
/// u_rev = g + (Q g − μ p)/k_e and below it: at step 7 (u above u_rev) they
/// hold with t − Q g > −μ p, at step 8 (u below) t − Q g = −μ p.
fn interior_points_reverse_at_the_closed_form(out: &RunOutput, dim: usize) {
    let h = if dim == 2 { 0.1 } else { 0.25 };
    let interior = |x: &[f64; 3]| (0..dim - 1).all(|c| x[c] > 2.5 * h && x[c] < 2.0 - 2.5 * h);
    let a = if dim == 2 { h } else { h * h };
    let g_tip = (K_E * SCALES[3] * U - MU * P) / (K_E + Q);
    for (step, reversed) in [(7, false), (8, true)] {
        let rows = out.contact_rows.iter().filter(|r| r.step == step);
        for r in rows.filter(|r| interior(&r.x)) {
            let xi = (-r.tangential_force - Q * a * r.slip) / a;
            let what = format!("step {step} point {} ({dim}D): t − Q g = {xi}", r.point);
            if reversed {
                assert!((xi + MU * P).abs() <= 1e-3 * MU * P, "{what}");
            } else {
                assert!(xi > -MU * P + 0.1 * MU * P, "{what}");
                assert!((r.slip - g_tip).abs() <= 1e-3 * g_tip, "{what}");
            }
        }
    }
}

#[test]
fn rough_friction_2d_loads_unloads_and_reverses_on_the_closed_forms() {
    drag_follows_the_closed_forms(2);
}

#[test]
fn rough_friction_3d_loads_unloads_and_reverses_on_the_closed_forms() {
    drag_follows_the_closed_forms(3);
}

/// Without the node that keeps it from turning, the block is free normal to
/// the contact and to turn about its top: its rigid modes move the rough
/// points' normal rows and slide them, and the contact holds them (the back
/// forces Q g as springs on the turn). Refused before; it solves, on the
/// same closed forms (resultants, every point's return mapping, the
/// reversal), in 2D. In 3D the 3D friction solvers do not reach the
/// tolerance on the problem the elimination leaves: refused, naming the
/// entry, rather than iterated for minutes.
#[test]
fn rough_drag_of_a_block_free_to_turn_about_its_top_follows_the_closed_forms() {
    let text = free_to_turn(&scene(2, &rough(Q), false));
    drag_of_the_scene_follows_the_closed_forms(2, &text);
    let text = free_to_turn(&scene(3, &rough(Q), false));
    match common::try_run(&text, RunOptions::default()) {
        Err(SolveError::Input(m)) => assert!(
            m.contains("contact \"c\".friction.roughness: in 3D a rigid motion"),
            "{m}"
        ),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("solved"),
    }
}

/// 3D, dragged diagonally: the force is along the drag, of the closed-form
/// magnitude (the return mapping in the plane, ġ along t − Q g).
#[test]
fn rough_friction_3d_diagonal_drag_slips_along_the_drag() {
    let area = 4.0;
    let out = converged(&scene(3, &rough(Q), true));
    for step in [1, 4, 9] {
        let (n, t1, t2) = resultants(&out, step);
        let u = SCALES[step - 1] * U;
        let want = match step {
            1 => K_E * u * area,
            4 => plastic(n, u, area, 1.0),
            _ => plastic(n, u, area, -1.0),
        };
        let mag = t1.hypot(t2) * t1.signum();
        assert_close(&format!("|T| step {step}"), mag, want, MU * n);
        assert_close(&format!("direction step {step}"), t1, t2, MU * n);
    }
}

/// Q = 0 is today's regularised Coulomb law: the same forces and slips as
/// without the key (to 1e-9), and a vanishing roughness tends to it.
#[test]
fn zero_roughness_is_the_regularised_coulomb_law() {
    for dim in [2, 3] {
        let plain = format!("{{ coulomb = {MU:?}, slip_stiffness = {K_E:?} }}");
        let a = converged(&scene(dim, &plain, false));
        for (q, tol) in [(0.0, 1e-9), (1e-9, 1e-8)] {
            let b = converged(&scene(dim, &rough(q), false));
            let scale = MU * P * 2.0;
            for (x, y) in a.contact_rows.iter().zip(&b.contact_rows) {
                for (v, w) in [
                    (x.tangential_force, y.tangential_force),
                    (x.normal_force, y.normal_force),
                    (x.tangential_force_2, y.tangential_force_2),
                ] {
                    assert!((v - w).abs() <= tol * scale, "{dim}D Q = {q}: {v} vs {w}");
                }
                assert!((x.slip - y.slip).abs() <= tol * U, "{dim}D Q = {q}: slip");
            }
        }
    }
}

/// Roughness changes the answer: the plastic branch hardens (T above μN at
/// the tip), where the regularised law stays at μN.
#[test]
fn roughness_hardens_the_slip_beyond_mu_n() {
    let plain = format!("{{ coulomb = {MU:?}, slip_stiffness = {K_E:?} }}");
    let a = converged(&scene(2, &plain, false));
    let b = converged(&scene(2, &rough(Q), false));
    let (na, ta, _) = resultants(&a, 4);
    let (_, tb, _) = resultants(&b, 4);
    assert_close("regularised at the tip", ta, MU * na, MU * na);
    assert!(tb > 1.5 * ta, "{tb} vs {ta}");
}

#[test]
fn bad_roughness_exits_1_naming_the_entry() {
    let dir = common::fresh_dir("friction_plasticity", "bad_roughness");
    for (friction, needle) in [
        (rough(-1.0), "contact \"c\".friction.roughness"),
        (
            format!("{{ coulomb = {MU:?}, roughness = 5.0 }}"),
            "contact \"c\".friction.roughness",
        ),
        ("{ tresca = 0.1, roughness = 5.0 }".to_string(), "roughness"),
    ] {
        let path = dir.join("scene.toml");
        std::fs::write(&path, scene(2, &friction, false)).unwrap();
        let out = common::cli_run(&path, dir.join("out"));
        let err = common::stderr_of_exit(&out, 1);
        assert!(err.contains(needle), "{friction}: {err}");
        assert!(!dir.join("out").exists(), "bad input writes nothing");
    }
}

/// examples/rough_drag.toml through the CLI: steps.csv's tangential force
/// against the closed forms of the uniform block (docs/theory/friction.md's table).
#[test]
fn rough_drag_example_matches_the_closed_forms_from_the_cli() {
    let dir = common::fresh_dir("friction_plasticity", "rough_drag");
    common::cli_run_ok(common::example_path("rough_drag.toml"), &dir);
    let text = std::fs::read_to_string(dir.join("steps.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (cu, ct) = (col("scale_drag"), col("tangential_force"));
    let (length, mut g, mut n) = (2.0, 0.0, 0);
    for line in lines {
        // the numeric columns (method and fallback are text)
        let f: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().unwrap_or(f64::NAN))
            .collect();
        let u = f[cu] * U;
        let rm = return_map(&[u], &[g], MU * P, K_E, Q);
        g = rm.slip[0];
        assert_close(
            &format!("T at u = {u}"),
            -f[ct],
            rm.traction[0] * length,
            MU * P * length,
        );
        n += 1;
    }
    assert_eq!(n, 10);
}

/// A rough contact that a rigid motion of a body held by contact alone would
/// slide (the block pushed by a force, no tangential support) is refused,
/// naming the entry, rather than solved wrongly.
#[test]
fn rough_contact_slid_by_a_rigid_motion_is_refused() {
    let text = scene(2, &rough(Q), false)
        .replace("displacement = { x = 0.01 }", "force = [0.1, 0.0]")
        .replace(
            "point = [0.0, 0.025]\nforce = [0.1, 0.0]",
            "point = [0.0, 0.025]\nforce = [0.0, 0.0]",
        );
    match common::try_run(&text, RunOptions::default()) {
        Err(SolveError::Input(m)) => {
            assert!(m.contains("contact \"c\".friction.roughness"), "{m}")
        }
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("solved"),
    }
}

/// The friction status method and the semi-smooth Newton method solve the
/// rough law as the fixed point does (the slider force obeys Coulomb's law):
/// the same tangential forces on the example, to 1e-8 μN_i (the solver
/// tolerance against the drag's force scale).
#[test]
fn every_friction_method_solves_the_rough_law_alike() {
    let text = common::example("rough_drag.toml").replace("tolerance = 1e-10", "tolerance = 1e-14");
    let base = converged(&text);
    for method in ["status", "newton"] {
        let other = converged(&text.replace(
            "tolerance = 1e-14",
            &format!("tolerance = 1e-14\nfriction = \"{method}\""),
        ));
        for (a, b) in base.contact_rows.iter().zip(&other.contact_rows) {
            let scale = MU * a.normal_force.abs().max(P * 0.1);
            assert!(
                (a.tangential_force - b.tangential_force).abs() <= 1e-8 * scale,
                "{method}: {} vs {}",
                a.tangential_force,
                b.tangential_force
            );
        }
    }
}

/// Rough contacts run on the condensed path alone: the direct path refuses
/// them naming the roughness, in 2D and 3D, and `auto` takes the condensed
/// path.
#[test]
fn rough_contacts_are_refused_on_the_direct_path() {
    for dim in [2, 3] {
        common::twins::refused_on_direct(&scene(dim, &rough(Q), false), &["roughness"]);
    }
}
