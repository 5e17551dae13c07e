//! Contact elements (course notes §7): zero-thickness elements between the
//! coincident nodes of two blocks, with the regularised normal law
//! λ_n = k_n A max(0, −g_n) and friction, solved by the return mapping and
//! Newton's method (`signorini_contact::contact_elements`).
//! - patch test, 2D and 3D: every pressure is p and every normal jump −p/k_n;
//! - the same answer as node-to-node with the same laws, and (frictionless)
//!   as the independent `method = "penalty"`;
//! - a stiff pad pressed by p and dragged by u on a stiff base: stick
//!   T = k_t u A, slip T = μ N, Tresca T = g A, roughness (course notes §6)
//!   T = μ N k_e/(k_e + Q) + k_e Q/(k_e + Q) u A, elastic unloading;
//! - bad input: no penalty law, non-coincident nodes, the direct path; a
//!   Newton that stops short exits 2.

use crate::common;

use common::input_error;
use signorini_solver::{RunOptions, RunOutput, SolveError};

const P: f64 = 1.0;
const K_N: f64 = 1000.0;

fn converged(text: &str) -> RunOutput {
    common::converged(text, RunOptions::default())
}

/// Two blocks (a soft pad on a steel base, ν ≠ 0) sharing the face y = 0.5
/// (z = 0.5 in 3D), the base on a frictionless support, each held sideways
/// on its x (and y) faces; the pad pressed by p. `base_div` / `pad_div`:
/// the divisions along the face.
fn blocks(dim: usize, base_div: usize, pad_div: usize, contact: &str) -> String {
    let (mesh, top, bottom, traction, holds): (fn(f64, usize) -> String, _, _, _, _) = if dim == 2 {
        (
            |o: f64, d: usize| {
                format!("{{ generator = \"rectangle\", origin = [0.0, {o:?}], size = [2.0, 0.5], divisions = [{d}, 2] }}")
            },
            "top",
            "bottom",
            format!("[0.0, {:?}]", -P),
            vec![("left", "x")],
        )
    } else {
        (
            |o: f64, d: usize| {
                format!("{{ generator = \"box\", origin = [0.0, 0.0, {o:?}], size = [1.0, 1.0, 0.5], divisions = [{d}, {d}, 2] }}")
            },
            "zmax",
            "zmin",
            format!("[0.0, 0.0, {:?}]", -P),
            vec![("xmin", "x"), ("ymin", "y")],
        )
    };
    let model = if dim == 2 { "plane_strain" } else { "solid" };
    let normal_dof = if dim == 2 { "y" } else { "z" };
    let mut holds_text = String::new();
    for body in ["base", "pad"] {
        for (surface, dof) in &holds {
            holds_text += &format!(
                "[[boundary]]\nname = \"{body}-{surface}\"\nbody = \"{body}\"\nsurface = \"{surface}\"\ndisplacement = {{ {dof} = 0.0 }}\n"
            );
        }
    }
    format!(
        r#"dimension = {dim}
model = "{model}"
[[materials]]
name = "soft"
young = 10.0
poisson = 0.45
[[materials]]
name = "steel"
young = 210.0
poisson = 0.3
[[bodies]]
name = "base"
material = "steel"
mesh = {}
[[bodies]]
name = "pad"
material = "soft"
mesh = {}
[[boundary]]
name = "support"
body = "base"
surface = "{bottom}"
displacement = {{ {normal_dof} = 0.0 }}
[[boundary]]
name = "pressure"
body = "pad"
surface = "{top}"
traction = {traction}
{holds_text}
[[contact]]
name = "joint"
slave = {{ body = "pad", surface = "{bottom}" }}
master = {{ body = "base", surface = "{top}" }}
{contact}
[solver]
tolerance = 1e-12
"#,
        mesh(0.0, base_div),
        mesh(0.5, pad_div)
    )
}

fn elements(law: &str, friction: &str) -> String {
    format!("discretization = \"contact_elements\"\nlaw = {law}\nfriction = {friction}\n")
}

fn penalty() -> String {
    format!("{{ penalty = {K_N:?} }}")
}

/// Every pressure is p and every normal jump −p/k_n (relative 1e-9).
fn patch_test(dim: usize) {
    let div = if dim == 2 { 8 } else { 4 };
    let out = converged(&blocks(dim, div, div, &elements(&penalty(), "\"none\"")));
    assert_eq!(out.report.method, "contact_elements_return_mapping");
    let n = if dim == 2 {
        div + 1
    } else {
        (div + 1) * (div + 1)
    };
    assert_eq!(out.contact_rows.len(), n);
    uniform_pressure_and_jump(&out);
}

/// Asserts that every contact row has the pressure p and the normal jump
/// −p/k_n (relative 1e-9); returns the resultant Σ normal_force.
fn uniform_pressure_and_jump(out: &RunOutput) -> f64 {
    let g = -P / K_N;
    for r in &out.contact_rows {
        assert!(
            (r.pressure - P).abs() <= 1e-9 * P,
            "pressure {}",
            r.pressure
        );
        assert!((r.gap - g).abs() <= 1e-9 * g.abs(), "gap {} vs {g}", r.gap);
    }
    out.contact_rows.iter().map(|r| r.normal_force).sum()
}

#[test]
fn patch_test_2d_gives_p_and_the_jump_minus_p_over_k_n_at_every_node() {
    patch_test(2);
}

#[test]
fn patch_test_3d_gives_p_and_the_jump_minus_p_over_k_n_at_every_node() {
    patch_test(3);
}

/// The base clamped on its bottom (ν ≠ 0: a non-uniform answer).
fn clamped(text: &str, dim: usize) -> String {
    let free = if dim == 2 {
        "displacement = { y = 0.0 }"
    } else {
        "displacement = { z = 0.0 }"
    };
    let clamp = if dim == 2 {
        "displacement = { x = 0.0, y = 0.0 }"
    } else {
        "displacement = { x = 0.0, y = 0.0, z = 0.0 }"
    };
    text.replacen(free, clamp, 1)
}

fn rows(o: &RunOutput) -> Vec<f64> {
    let r = o.contact_rows.iter();
    r.flat_map(|r| [r.normal_force, r.gap, r.tangential_force, r.slip])
        .collect()
}

/// Contact elements equal node-to-node with the same laws, and without
/// friction the independent penalty method, to 1e-9.
fn same_as_node_to_node(dim: usize) {
    let div = if dim == 2 { 8 } else { 3 };
    for friction in [
        "\"none\"",
        "{ coulomb = 0.3 }",
        "{ coulomb = 0.2, slip_stiffness = 50.0 }",
        "{ tresca = 0.05 }",
    ] {
        let el = blocks(dim, div, div, &elements(&penalty(), friction));
        let el = converged(&clamped(&el, dim));
        let nn = format!(
            "discretization = \"node_to_node\"\nlaw = {}\nfriction = {friction}\n",
            penalty()
        );
        let mut nn = clamped(&blocks(dim, div, div, &nn), dim);
        if friction == "\"none\"" {
            // Frictionless, node-to-node with a penalty law is the
            // independent regularised solver of course notes §3.6.
            nn = with_solver_line(&nn, "method = \"penalty\"");
        }
        let nn = converged(&nn);
        let d = common::max_rel(&rows(&el), &rows(&nn));
        assert!(
            d <= 1e-9,
            "{dim}D {friction}: {} differs by {d:e}",
            nn.report.method
        );
        let u = |o: &RunOutput| -> Vec<f64> {
            o.bodies
                .iter()
                .flat_map(|b| b.last().displacement.clone())
                .collect()
        };
        let d = common::max_rel(&u(&el), &u(&nn));
        assert!(
            d <= 1e-9,
            "{dim}D {friction}: displacements differ by {d:e}"
        );
    }
}

#[test]
fn contact_elements_equal_node_to_node_and_the_penalty_method_2d() {
    same_as_node_to_node(2);
}

#[test]
fn contact_elements_equal_node_to_node_and_the_penalty_method_3d() {
    same_as_node_to_node(3);
}

/// `text` (a scene of [`blocks`]) with `line` added to its `[solver]`.
fn with_solver_line(text: &str, line: &str) -> String {
    let added = text.replace(
        "tolerance = 1e-12\n",
        &format!("tolerance = 1e-12\n{line}\n"),
    );
    assert_ne!(added, text, "no [solver] tolerance to add {line:?} after");
    added
}

// ---- the drag: a stiff pad pressed by p, its top dragged by u ----

const K_E: f64 = 100.0;
const Q: f64 = 25.0;
const MU: f64 = 0.3;
const U: f64 = 0.01;
/// The thickness of the pad and the base: thin, so that the moment of the
/// drag about the interface turns the pad by little on its elements (its
/// shift h θ ≈ 2e-5 u when k_t = k_n).
const H: f64 = 0.004;
/// The pad's rotation, and its and the base's shear compliance against the
/// elements' (k h/G ≈ 1e-6), with margin.
const TOL: f64 = 1e-4;

/// A stiff pad (2 × H, or 2 × 2 × H) on a stiff clamped base of the
/// same size, joined by contact elements; the pad's top pressed by p and
/// dragged along x by the steps' scales of u (with a node at mid-height).
fn drag(dim: usize, friction: &str, scales: &[f64]) -> String {
    let steps = common::drag_steps(scales);
    // A point or vector (x, y, up) of the scene: (x, up) in 2D.
    let point = |x: f64, y: f64, up: f64| match dim {
        2 => format!("[{x:?}, {up:?}]"),
        _ => format!("[{x:?}, {y:?}, {up:?}]"),
    };
    let (model, generator, divisions) = match dim {
        2 => ("plane_strain", "rectangle", "[10, 2]"),
        _ => ("solid", "box", "[4, 4, 2]"),
    };
    let (top, bottom) = if dim == 2 {
        ("top", "bottom")
    } else {
        ("zmax", "zmin")
    };
    let fixed: Vec<String> = ["x", "y", "z"][..dim]
        .iter()
        .map(|a| format!("{a} = 0.0"))
        .collect();
    let clamp = format!("{{ {} }}", fixed.join(", "));
    // Along x, held in y in 3D.
    let drag = match dim {
        2 => format!("{{ x = {U:?} }}"),
        _ => format!("{{ x = {U:?}, y = 0.0 }}"),
    };
    let mesh = |o: f64| {
        format!(
            "{{ generator = \"{generator}\", origin = {}, size = {}, divisions = {divisions} }}",
            point(0.0, 0.0, o),
            point(2.0, 2.0, H)
        )
    };
    let (traction, mid) = (point(0.0, 0.0, -P), point(0.0, 1.0, 1.5 * H));
    let boundaries = common::press_drag_hold("pad", top, &traction, &drag, &mid);
    let clamp = common::boundary(
        "clamp",
        "base",
        &format!("surface = \"{bottom}\""),
        &format!("displacement = {clamp}"),
    );
    format!(
        r#"{}{}{}{clamp}{boundaries}[[contact]]
name = "joint"
slave = {{ body = "pad", surface = "{bottom}" }}
master = {{ body = "base", surface = "{top}" }}
discretization = "contact_elements"
law = {{ penalty = {K_N:?} }}
friction = {friction}
[solver]
tolerance = 1e-14
{steps}"#,
        common::material_head(dim, model, 1e7, 0.0),
        common::elastic_body("base", &mesh(0.0)),
        common::elastic_body("pad", &mesh(H)),
    )
}

/// (N, T) at a step (1-based): T the tangential force on the pad along the
/// drag, minus the reported force on the slave.
fn resultants(o: &RunOutput, step: usize) -> (f64, f64) {
    let rows = o.contact_rows.iter().filter(|r| r.step == step);
    rows.fold((0.0, 0.0), |(n, t), r| {
        (n + r.normal_force, t - r.tangential_force)
    })
}

fn assert_close(what: &str, got: f64, want: f64, scale: f64) {
    assert!(
        (got - want).abs() <= TOL * scale,
        "{what}: {got:e} vs the closed form {want:e}"
    );
}

fn drag_closed_forms(dim: usize) {
    let area = if dim == 2 { 2.0 } else { 4.0 };
    let n_total = P * area;
    let scale = MU * n_total;
    // Coulomb with the asperities' stiffness k_e: stick, then slip.
    let f = format!("{{ coulomb = {MU:?}, slip_stiffness = {K_E:?} }}");
    let out = converged(&drag(dim, &f, &[0.1, 1.0]));
    let (n, t) = resultants(&out, 1);
    assert_close("N", n, n_total, n_total);
    assert_close("stick T = k_e u A", t, K_E * 0.1 * U * area, scale);
    let (n, t) = resultants(&out, 2);
    assert_close("slip T = μ N", t, MU * n, scale);
    // Without slip_stiffness, k_t = k_n.
    let f = format!("{{ coulomb = {MU:?} }}");
    let out = converged(&drag(dim, &f, &[0.01, 1.0]));
    assert_close(
        "stick T = k_n u A",
        resultants(&out, 1).1,
        K_N * 0.01 * U * area,
        scale,
    );
    assert_close("slip T = μ N", resultants(&out, 2).1, MU * n_total, scale);
    // Tresca g: T = g A once slipping.
    let out = converged(&drag(dim, "{ tresca = 0.2 }", &[1.0]));
    assert_close("Tresca T = g A", resultants(&out, 1).1, 0.2 * area, scale);
    // Roughness: plastic T, then elastic unloading of slope k_e A.
    let f = format!("{{ coulomb = {MU:?}, slip_stiffness = {K_E:?}, roughness = {Q:?} }}");
    let out = converged(&drag(dim, &f, &[0.1, 1.0, 1.5, 1.3]));
    assert_close(
        "rough elastic T",
        resultants(&out, 1).1,
        K_E * 0.1 * U * area,
        scale,
    );
    for (step, s) in [(2, 1.0), (3, 1.5)] {
        let (n, t) = resultants(&out, step);
        let u = s * U;
        let want = MU * n * K_E / (K_E + Q) + K_E * Q / (K_E + Q) * u * area;
        assert_close(&format!("rough plastic T at step {step}"), t, want, scale);
    }
    let tip = resultants(&out, 3).1;
    let back = resultants(&out, 4).1;
    assert_close("unloading", back, tip + K_E * area * (1.3 - 1.5) * U, scale);
    // The slip carried: g = (k_e u − μ p)/(k_e + Q) at the tip with each
    // element's pressure p (the drag's moment varies it slightly), kept on
    // unloading.
    let at = |step: usize| out.contact_rows.iter().filter(move |r| r.step == step);
    for (tip, r) in at(3).zip(at(4)) {
        let g = (K_E * 1.5 * U - MU * tip.pressure) / (K_E + Q);
        assert!((r.slip - g).abs() <= TOL * g, "slip {} vs {g}", r.slip);
        assert!((tip.slip - g).abs() <= TOL * g, "slip {} vs {g}", tip.slip);
    }
}

#[test]
fn drag_2d_follows_stick_slip_tresca_and_roughness_closed_forms() {
    drag_closed_forms(2);
}

#[test]
fn drag_3d_follows_stick_slip_tresca_and_roughness_closed_forms() {
    drag_closed_forms(3);
}

// ---- bad input ----

#[test]
fn contact_elements_without_a_penalty_law_are_refused_naming_the_entry() {
    let text = blocks(2, 8, 8, "discretization = \"contact_elements\"\n");
    let m = input_error(&text);
    assert!(
        m.contains("contact \"joint\".law") && m.contains("penalty"),
        "{m}"
    );
}

#[test]
fn non_coincident_nodes_are_refused_naming_the_contact_and_the_node() {
    let m = input_error(&blocks(2, 8, 5, &elements(&penalty(), "\"none\"")));
    assert!(
        m.contains("contact \"joint\"") && m.contains("coincident") && m.contains("slave node"),
        "{m}"
    );
}

#[test]
fn the_direct_path_and_elliptic_or_norton_hoff_friction_are_refused() {
    let text = blocks(2, 8, 8, &elements(&penalty(), "{ coulomb = 0.3 }"));
    let direct = with_solver_line(&text, "path = \"direct\"");
    assert!(input_error(&direct).contains("solver.path"));
    let nh = blocks(
        2,
        8,
        8,
        &elements(&penalty(), "{ norton_hoff = 0.3, rho = 0.5 }"),
    );
    assert!(input_error(&nh).contains("Norton-Hoff"));
    let ell = blocks(3, 2, 2, &elements(&penalty(), "{ coulomb = [0.3, 0.2] }"));
    assert!(input_error(&ell).contains("elliptic"));
}

/// A method, in the scene or on the command line, does not apply to the
/// return mapping: refused naming the entry, never silently ignored.
#[test]
fn a_method_other_than_the_default_is_refused() {
    let text = blocks(2, 8, 8, &elements(&penalty(), "{ coulomb = 0.3 }"));
    let lemke = with_solver_line(&text, "method = \"lemke\"");
    assert_ne!(lemke, text);
    assert!(input_error(&lemke).contains("solver.method = \"lemke\""));
    let opts = RunOptions {
        method: Some(signorini_scene::Method::Uzawa),
        ..Default::default()
    };
    match common::try_run(&text, opts) {
        Err(SolveError::Input(m)) => assert!(m.contains("--method uzawa"), "{m}"),
        Err(e) => panic!("not an input error: {e}"),
        Ok(_) => panic!("accepted"),
    }
}

/// Node-to-node with a penalty law and friction, refused before, runs
/// through the same solver.
#[test]
fn a_penalty_law_with_friction_needs_no_method() {
    let nn = format!(
        "discretization = \"node_to_node\"\nlaw = {}\nfriction = {{ coulomb = 0.3 }}\n",
        penalty()
    );
    let out = converged(&blocks(2, 8, 8, &nn));
    assert_eq!(out.report.method, "contact_elements_return_mapping");
}

/// A Newton that stops at its iteration limit exits 2 with the reason.
#[test]
fn a_newton_stopped_short_exits_2() {
    let f = format!("{{ coulomb = {MU:?}, slip_stiffness = {K_E:?} }}");
    let text = drag(2, &f, &[1.0]).replace(
        "tolerance = 1e-14\n",
        "tolerance = 1e-14\nmax_iterations = 1\n",
    );
    let dir = common::fresh_dir("contact_elements", "newton_short");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = common::cli_run(&scene, dir.join("out"));
    let err = common::stderr_of_exit(&out, 2);
    assert!(!err.is_empty());
}

/// The shipped example runs from the command line.
#[test]
fn the_example_runs() {
    let dir = common::fresh_dir("contact_elements", "example");
    common::cli_run_ok(
        common::example_path("contact_elements.toml"),
        dir.join("out"),
    );
    let csv = std::fs::read_to_string(dir.join("out/contact.csv")).unwrap();
    assert!(csv.lines().count() > 1);
}

/// With friction, an independent check: as k_n grows the contact elements
/// tend to the unilateral node-to-node contact with the same regularised
/// Coulomb law solved by the friction fixed point (course notes §4.3), the
/// difference falling like 1/k_n.
#[test]
fn stiff_elements_tend_to_the_unilateral_friction_solver() {
    let friction = "{ coulomb = 0.2, slip_stiffness = 50.0 }";
    let uni = format!("discretization = \"node_to_node\"\nfriction = {friction}\n");
    let uni = converged(&clamped(&blocks(2, 8, 8, &uni), 2));
    let tangential = |o: &RunOutput| -> Vec<f64> {
        let r = o.contact_rows.iter();
        r.flat_map(|r| [r.normal_force, r.tangential_force])
            .collect()
    };
    let mut last = f64::INFINITY;
    for k_n in [1e4, 1e6] {
        let el = elements(&format!("{{ penalty = {k_n:?} }}"), friction);
        let el = converged(&clamped(&blocks(2, 8, 8, &el), 2));
        let d = common::max_rel(&tangential(&el), &tangential(&uni));
        assert!(d < last / 50.0, "k_n = {k_n:e}: {d:e} after {last:e}");
        last = d;
    }
    assert!(last <= 1e-4, "{last:e}");
}

/// 3D, dragged diagonally: the elements slip along the drag (the radial
/// return in the plane), ‖T‖ = μ N; below the threshold T = k_e u A.
#[test]
fn drag_3d_diagonal_slips_at_mu_n_along_the_drag() {
    let f = format!("{{ coulomb = {MU:?}, slip_stiffness = {K_E:?} }}");
    let d = U / 2f64.sqrt();
    let text = drag(3, &f, &[0.1, 1.0]);
    let along = format!("{{ x = {U:?}, y = 0.0 }}");
    assert!(text.contains(&along));
    let out = converged(&text.replace(&along, &format!("{{ x = {d:?}, y = {d:?} }}")));
    let (area, n_total) = (4.0, 4.0 * P);
    for (step, want) in [(1, K_E * 0.1 * U * area), (2, MU * n_total)] {
        let rows = out.contact_rows.iter().filter(|r| r.step == step);
        let (t1, t2) = rows.fold((0.0, 0.0), |(a, b), r| {
            (a - r.tangential_force, b - r.tangential_force_2)
        });
        assert_close(
            &format!("‖T‖ at step {step}"),
            t1.hypot(t2),
            want,
            MU * n_total,
        );
        let statuses = out.contact_rows.iter().filter(|r| r.step == step);
        let slipping = statuses.filter(|r| r.status == "slip").count();
        assert_eq!(slipping, if step == 1 { 0 } else { 25 });
    }
}

/// A 2D block [0, 2] × [y0, y0 + 0.5] of tri3 cells as a Gmsh 2.2 ASCII
/// file: columns at the abscissae `xs` (shared by both blocks, so the nodes
/// of the face y = 0.5 coincide), `rows` rows, diagonals one way or the
/// other; physical lines "bottom", "top", "left", physical surface "block".
fn gmsh_block(xs: &[f64], y0: f64, rows: usize, flip: bool) -> String {
    let nx = xs.len();
    let id = |i: usize, j: usize| 1 + j * nx + i;
    let mut nodes = String::new();
    for j in 0..=rows {
        for (i, x) in xs.iter().enumerate() {
            let y = y0 + 0.5 * j as f64 / rows as f64;
            nodes += &format!("{} {x:?} {y:?} 0\n", id(i, j));
        }
    }
    let mut cells = Vec::new();
    for i in 0..nx - 1 {
        cells.push(format!("1 2 1 1 {} {}", id(i, 0), id(i + 1, 0)));
        cells.push(format!("1 2 2 2 {} {}", id(i, rows), id(i + 1, rows)));
    }
    for j in 0..rows {
        cells.push(format!("1 2 3 3 {} {}", id(0, j), id(0, j + 1)));
        for i in 0..nx - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            let (t1, t2) = if flip ^ (i % 2 == 1) {
                ((a, b, d), (b, c, d))
            } else {
                ((a, b, c), (a, c, d))
            };
            cells.push(format!("2 2 4 4 {} {} {}", t1.0, t1.1, t1.2));
            cells.push(format!("2 2 4 4 {} {} {}", t2.0, t2.1, t2.2));
        }
    }
    let cells: String = cells
        .iter()
        .enumerate()
        .map(|(k, c)| format!("{} {c}\n", k + 1))
        .collect();
    format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"bottom\"\n1 2 \"top\"\n1 3 \"left\"\n2 4 \"block\"\n$EndPhysicalNames\n$Nodes\n{}\n{nodes}$EndNodes\n$Elements\n{}\n{cells}$EndElements\n",
        nx * (rows + 1),
        cells.lines().count()
    )
}

/// Contact elements between two Gmsh meshes (unstructured triangles whose
/// face nodes coincide, graded so that the tributary lengths differ):
/// every pressure is p and every jump −p/k_n, the resultant p × 2.
#[test]
fn contact_elements_between_two_gmsh_meshes_pass_the_patch_test() {
    let dir = common::fresh_dir("contact_elements", "gmsh");
    let xs: Vec<f64> = (0..=9).map(|i| 2.0 * (i as f64 / 9.0).powf(1.4)).collect();
    let (base, pad) = (dir.join("base.msh"), dir.join("pad.msh"));
    std::fs::write(&base, gmsh_block(&xs, 0.0, 3, false)).unwrap();
    std::fs::write(&pad, gmsh_block(&xs, 0.5, 2, true)).unwrap();
    let text = blocks(2, 8, 8, &elements(&penalty(), "\"none\""));
    let mut meshes = text.match_indices("mesh = { generator").map(|(i, _)| i);
    let (i, j) = (meshes.next().unwrap(), meshes.next().unwrap());
    let line_end = |k: usize| k + text[k..].find('\n').unwrap();
    let text = format!(
        "{}mesh = {{ file = {:?} }}{}mesh = {{ file = {:?} }}{}",
        &text[..i],
        base.to_str().unwrap(),
        &text[line_end(i)..j],
        pad.to_str().unwrap(),
        &text[line_end(j)..]
    );
    let out = converged(&text);
    assert_eq!(out.contact_rows.len(), xs.len());
    let resultant = uniform_pressure_and_jump(&out);
    assert!((resultant - 2.0 * P).abs() <= 1e-9 * P, "{resultant}");
}

/// Axisymmetric contact elements (the tributary area of a node is that of
/// its ring, 2π r ds): every pressure p, every jump −p/k_n, and the
/// resultant p π R² of the whole disc.
#[test]
fn axisymmetric_contact_elements_pass_the_patch_test() {
    let out = converged(&axi_patch());
    assert_eq!(out.contact_rows.len(), 9);
    let resultant = uniform_pressure_and_jump(&out);
    let whole = P * std::f64::consts::PI * 2.0 * 2.0;
    assert!(
        (resultant - whole).abs() <= 1e-9 * whole,
        "{resultant} vs {whole}"
    );
}

/// Two discs of radius 2 (a soft pad on a steel base) joined by contact
/// elements with k_n = 1000, the pad pressed by p = 1.
fn axi_patch() -> String {
    let disc = |y: f64| {
        format!("{{ generator = \"rectangle\", origin = [0.0, {y:?}], size = [2.0, 0.5], divisions = [8, 2] }}")
    };
    [
        "title = \"axisymmetric contact elements patch\"\ndimension = 2\nmodel = \"axisymmetric\"\n".to_string(),
        common::material("steel", 210.0, 0.3),
        common::material("soft", 10.0, 0.45),
        common::body("base", "steel", &disc(0.0)),
        common::body("pad", "soft", &disc(0.5)),
        common::boundary("support", "base", "surface = \"bottom\"", "displacement = { y = 0.0 }"),
        common::boundary("pressure", "pad", "surface = \"top\"", "traction = [0.0, -1.0]"),
        common::contact_between("joint", ("pad", "bottom"), ("base", "top")),
        r#"discretization = "contact_elements"
law = { penalty = 1000.0 }

[solver]
tolerance = 1e-12
"#
        .to_string(),
    ]
    .concat()
}

/// The example's pad dragged, released, pressed 100 times harder, then
/// unloaded to its first pressure: the last step's Newton, started from the
/// previous forces, cycled to the iteration limit (found by a robustness
/// sweep); it restarts from the elastic predictor and ends where the same
/// state reached by a 10-times load ends (the elements' law is path-free in
/// the normal direction, and no slip happens after the drag is released).
#[test]
fn a_large_unloading_converges_to_the_state_of_a_small_one() {
    let text = std::fs::read_to_string(common::example_path("contact_elements.toml")).unwrap();
    let steps = |peak: &str| {
        let at = text.find("[[steps]]").unwrap();
        format!(
            "{}[[steps]]\nscale = {{ pressure = 1.0, drag = 1.0 }}\n[[steps]]\nscale = {{ pressure = 1.0, drag = 0.0 }}\n[[steps]]\nscale = {{ pressure = {peak}, drag = 0.0 }}\n[[steps]]\nscale = {{ pressure = 1.0, drag = 0.0 }}\n",
            &text[..at]
        )
    };
    let big = converged(&steps("100.0"));
    let small = converged(&steps("10.0"));
    assert!(big.report.converged && small.report.converged);
    let last = |o: &RunOutput| -> Vec<f64> {
        (o.contact_rows.iter())
            .filter(|r| r.step == 4)
            .flat_map(|r| [r.normal_force, r.gap])
            .collect()
    };
    let d = common::max_rel(&last(&big), &last(&small));
    assert!(d <= 1e-8, "{d}");
}

/// Contact elements with friction run on the condensed path alone: the
/// direct path refuses them naming the return mapping, and `auto` takes
/// the condensed path.
#[test]
fn contact_elements_with_friction_are_refused_on_the_direct_path() {
    let text = clamped(
        &blocks(2, 8, 8, &elements(&penalty(), "{ coulomb = 0.3 }")),
        2,
    );
    common::twins::refused_on_direct(&text, &["return mapping", "solver.path"]);
}
