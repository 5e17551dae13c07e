//! The scene format: numbers that serde would reject or lose name their key
//! and their value, step limits and the output steps.

mod common;

use common::*;
use signorini_scene::*;

#[test]
fn divisions_name_the_key_the_value_and_what_is_valid() {
    for (bad, shown) in [
        ("[-8, 4]", "-8"),
        ("[8.5, 4]", "8.5"),
        ("[4, \"many\"]", "\"many\""),
    ] {
        let m = parse_err(&BASE.replace("divisions = [4, 2]", &format!("divisions = {bad}")));
        assert!(
            m.contains("mesh.divisions: expected positive whole numbers")
                && m.contains(&format!("got {shown}"))
                && m.contains("line 12"),
            "{bad}: {m}"
        );
        assert!(!m.contains("usize"), "{bad}: {m}");
    }
    let half = |d: &str| {
        BASE.replace(
            r#"{ generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }"#,
            &format!(r#"{{ generator = "half_disk", center = [0.0, 1.0], radius = 1.0, divisions = {d} }}"#),
        )
    };
    for (bad, shown) in [
        ("-3", "-3"),
        ("2.5", "2.5"),
        ("[8]", "an array"),
        ("nan", "NaN"),
    ] {
        let m = parse_err(&half(bad));
        assert!(
            m.contains("mesh.divisions: expected a positive whole number (elements along the arc)")
                && m.contains(&format!("got {shown}")),
            "{bad}: {m}"
        );
    }
    // a whole number written as a float is one
    let s = parse_toml(&half("1e3")).unwrap();
    match &s.bodies[0].mesh {
        Some(MeshSpec::Generator(Generator::HalfDisk(HalfDisk { divisions, .. }))) => {
            assert_eq!(*divisions, 1000)
        }
        other => panic!("{other:?}"),
    }
    // JSON takes the same path
    let json = r#"{ "dimension": 2,
        "materials": [ { "name": "s", "young": 1, "poisson": 0.3 } ],
        "bodies": [ { "name": "b", "material": "s",
          "mesh": { "generator": "rectangle", "origin": [0, 0], "size": [1, 1], "divisions": [-8, 4] } } ] }"#;
    let m = match parse_json(json) {
        Err(SceneError::Parse { message }) => message,
        other => panic!("{other:?}"),
    };
    assert!(m.contains("mesh.divisions") && m.contains("got -8"), "{m}");
}

#[test]
fn nan_and_inf_in_a_mesh_reach_the_validation_that_names_the_entry() {
    for (from, to, entry, shown) in [
        (
            "size = [1.0, 0.5]",
            "size = [nan, 0.5]",
            "bodies[0].mesh.size",
            "NaN",
        ),
        (
            "size = [1.0, 0.5]",
            "size = [1.0, -inf]",
            "bodies[0].mesh.size",
            "-inf",
        ),
        (
            "origin = [0.0, 0.0]",
            "origin = [inf, 0.0]",
            "bodies[0].mesh.origin",
            "inf",
        ),
        (
            "divisions = [4, 2]",
            "divisions = [4, 2], grading = { towards = \"top\", ratio = nan }",
            "bodies[0].mesh.grading.ratio",
            "NaN",
        ),
    ] {
        let (e, m) = invalid_entry(&BASE.replace(from, to));
        assert_eq!(e, entry, "{to}: {m}");
        assert!(m.contains(shown), "{to}: {m}");
    }
    let half = BASE.replace(
        r#"{ generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }"#,
        r#"{ generator = "half_disk", center = [0.0, 1.0], radius = nan, divisions = 8, grading = inf }"#,
    );
    let (e, m) = invalid_entry(&half);
    assert_eq!(e, "bodies[0].mesh.radius", "{m}");
    let (e, m) = invalid_entry(&half.replace("radius = nan", "radius = 1.0"));
    assert_eq!(e, "bodies[0].mesh.grading", "{m}");
    assert!(m.contains("inf"), "{m}");
    // a number of the wrong type names its key
    let m = parse_err(&BASE.replace("size = [1.0, 0.5]", "size = [1.0, \"big\"]"));
    assert!(m.contains("mesh.size") && m.contains("\"big\""), "{m}");
}

#[test]
fn integer_keys_name_the_key_and_the_value() {
    let m = parse_err(&BASE.replace("dimension = 2", "dimension = -2"));
    assert!(m.contains("dimension: expected 2 or 3, got -2"), "{m}");
    let m = parse_err(&BASE.replace("dimension = 2", "dimension = 2.5"));
    assert!(m.contains("dimension: expected 2 or 3, got 2.5"), "{m}");
    let m = parse_err(&with("[solver]\nmax_iterations = -3\n"));
    assert!(
        m.contains("solver.max_iterations: expected a whole number >= 1, got -3"),
        "{m}"
    );
    let m = parse_err(&BASE.replace("name = \"plate\"", "name = \"plate\"\nsubdomains = 2.5"));
    assert!(m.contains("subdomains") && m.contains("2.5"), "{m}");
    let s = parse_toml(&BASE.replace("name = \"plate\"", "name = \"plate\"\nsubdomains = 2.0"))
        .unwrap();
    assert_eq!(s.bodies[0].subdomains, Subdomains::Count(2));
}

#[test]
fn too_many_steps_are_refused() {
    let ok = format!("steps = [{}]\n{BASE}", vec!["{}"; MAX_STEPS].join(", "));
    assert!(parse_toml(&ok).is_ok());
    let many = format!("steps = [{}]\n{BASE}", vec!["{}"; MAX_STEPS + 1].join(", "));
    let (e, m) = invalid_entry(&many);
    assert_eq!(e, "steps");
    assert!(m.contains("10001") && m.contains("at most 10000"), "{m}");
}

#[test]
fn a_very_long_line_is_quoted_around_the_error_only() {
    let long = format!("x = [{}]\n{BASE}", vec!["1"; 50_000].join(", "));
    let m = parse_err(&long);
    assert!(m.len() < 600, "{} characters: {m}", m.len());
    assert!(m.contains("unknown field `x`") && m.contains('^'), "{m}");
    let deep = format!(
        "dimension = 2\nx = {}{}\n",
        "[".repeat(100_000),
        "]".repeat(100_000)
    );
    let m = parse_err(&deep);
    assert!(m.len() < 600, "{} characters: {m}", m.len());
}

/// `[output] steps`: the four forms, which steps each selects, and the
/// entries refused with the entry named and the valid range.
#[test]
fn output_steps_forms_and_checks() {
    let three = "[[steps]]\nscale = { press = 0.5 }\n[[steps]]\nscale = { press = 1.0 }\n[[steps]]\nscale = { press = 1.5 }\n";
    let steps = |o: &str| {
        let s = parse_toml(&with(&format!("{three}[output]\nsteps = {o}\n"))).unwrap();
        let n = s.step_scales().len();
        assert_eq!(n, 3);
        (1..=n)
            .filter(|&k| s.output.steps.selects(k, n))
            .collect::<Vec<_>>()
    };
    assert_eq!(steps("\"all\""), [1, 2, 3]);
    assert_eq!(steps("\"last\""), [3]);
    assert_eq!(steps("{ every = 2 }"), [2, 3]);
    assert_eq!(steps("{ every = 5 }"), [3]);
    assert_eq!(steps("[3, 1]"), [1, 3]);
    let s = parse_toml(&with(three)).unwrap();
    assert_eq!(s.output.steps, OutputSteps::All, "the default");

    let bad = |o: &str| invalid_entry(&with(&format!("{three}[output]\nsteps = {o}\n")));
    let (e, m) = bad("[1, 4]");
    assert_eq!(e, "output.steps[1]");
    assert!(m.contains("step 4") && m.contains("1 to 3"), "{m}");
    let (e, m) = bad("[0]");
    assert_eq!(e, "output.steps[0]");
    assert!(m.contains("1 to 3"), "{m}");
    let (e, _) = bad("[-2]");
    assert_eq!(e, "output.steps[0]");
    let (e, m) = bad("[2, 2]");
    assert_eq!(e, "output.steps[1]");
    assert!(m.contains("twice"), "{m}");
    let (e, _) = bad("[]");
    assert_eq!(e, "output.steps");
    let (e, m) = bad("{ every = 0 }");
    assert_eq!(e, "output.steps.every");
    assert!(m.contains(">= 1"), "{m}");
    for o in ["\"first\"", "[1.5]", "{ each = 2 }", "true"] {
        let m = parse_err(&with(&format!("{three}[output]\nsteps = {o}\n")));
        assert!(m.contains("output.steps"), "{o}: {m}");
    }
    // JSON round trip keeps the selection.
    let s = parse_toml(&with(&format!(
        "{three}[output]\nsteps = {{ every = 2 }}\n"
    )))
    .unwrap();
    let back: Scene = serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap();
    assert_eq!(back.output.steps, OutputSteps::Every(2));
}
