//! The suite's data (cases.toml, scenes/*.toml) is whole: every case of the
//! quick and the full suite builds, every template placeholder is filled,
//! every scene parses and validates, and nothing in the data is left over.

use std::collections::BTreeSet;

use signorini_suite::stiff::data::{self, placeholders, template, TEMPLATES};
use signorini_suite::stiff::Expectation;

#[test]
fn every_case_builds_and_its_scene_parses_as_a_valid_scene() {
    for quick in [true, false] {
        let cases = data::load(quick).unwrap_or_else(|e| panic!("quick = {quick}: {e}"));
        assert_eq!(cases.len(), 72, "quick = {quick}");
        let mut names = BTreeSet::new();
        for c in &cases {
            assert!(names.insert(c.name.clone()), "{} twice", c.name);
            if let Err(e) = &c.scene {
                panic!("{} (quick = {quick}): {e}\n{}", c.name, c.text);
            }
            assert!(
                placeholders(&c.text).is_empty(),
                "{}: unfilled {:?}",
                c.name,
                placeholders(&c.text)
            );
            let refs = match &c.expect {
                Expectation::Solves(r) => r.iter().collect::<Vec<_>>(),
                Expectation::Stops { references, .. } => references.iter().collect(),
                Expectation::Either {
                    references,
                    on_stop,
                    ..
                } => references.iter().chain(on_stop).collect(),
            };
            for r in refs {
                assert!(r.tolerance.is_finite() && r.tolerance >= 0.0, "{}", c.name);
            }
        }
    }
}

#[test]
fn the_quick_and_full_suites_have_the_same_families_in_the_same_order() {
    let families =
        |quick| -> Vec<String> { data::cases(quick).into_iter().map(|c| c.family).collect() };
    assert_eq!(families(true), families(false));
}

#[test]
fn every_parameter_of_a_case_fills_a_placeholder_of_its_scene() {
    let suite: toml::Value = toml::from_str(data::CASES).unwrap();
    for family in suite["family"].as_array().unwrap() {
        let family_scene = family.get("scene");
        for case in family["cases"].as_array().unwrap() {
            let parts = case.get("scene").or(family_scene).unwrap();
            let used: BTreeSet<&str> = parts
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|p| placeholders(template(p.as_str().unwrap()).unwrap()))
                .map(|(_, _, name)| name)
                .collect();
            for key in case
                .get("params")
                .and_then(|p| p.as_table())
                .into_iter()
                .flatten()
            {
                assert!(
                    used.contains(key.0.as_str()),
                    "{}: parameter {} fills nothing",
                    case["name"],
                    key.0
                );
            }
        }
    }
}

#[test]
fn every_template_file_is_compiled_in_and_used() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let files: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let listed: BTreeSet<String> = TEMPLATES.iter().map(|(n, _)| format!("{n}.toml")).collect();
    assert_eq!(files, listed);
    let used: BTreeSet<String> = data::CASES
        .lines()
        .filter(|l| l.starts_with("scene = "))
        .flat_map(|l| l.split('"').skip(1).step_by(2).map(String::from))
        .map(|n| format!("{n}.toml"))
        .collect();
    assert_eq!(used, listed);
}

#[test]
fn placeholders_are_identifiers_in_braces_not_inline_tables() {
    let p = placeholders("a = { x = 0.0 }\nb = [{w}, {h_2}]\nc = {}\nd = {X}");
    let names: Vec<&str> = p.iter().map(|(_, _, n)| *n).collect();
    assert_eq!(names, ["w", "h_2"]);
}
