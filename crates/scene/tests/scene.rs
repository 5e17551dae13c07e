//! The scene format of docs/reference/scene-format.md: parsing, defaults and error messages.

use signorini_scene::*;
use std::path::Path;

const HERTZ: &str = include_str!("data/hertz2d.toml");

mod common;
use common::*;

#[test]
fn hertz_example_of_scene_md_parses() {
    let s = parse_toml(HERTZ).unwrap();
    assert_eq!(s.dimension, 2);
    assert_eq!(s.model, Model::PlaneStrain);
    assert_eq!(
        s.title,
        "Hertz: elastic cylinder on a rigid plane, plane strain"
    );
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.material("steel").unwrap().poisson, 0.3);
    let cyl = s.body("cylinder").unwrap();
    assert!(cyl.is_deformable());
    assert_eq!(cyl.subdomains, Subdomains::Count(1));
    assert_eq!(
        cyl.mesh,
        Some(MeshSpec::Generator(Generator::HalfDisk(HalfDisk {
            center: [0.0, 1.0],
            radius: 1.0,
            divisions: 32,
            pole: [0.0, -1.0],
            grading: 4.0,
            element: Element::Quad4,
        })))
    );
    let ground = s.body("ground").unwrap();
    assert!(ground.is_rigid());
    assert_eq!(
        ground.rigid,
        Some(RigidShape::Plane {
            point: vec![0.0, 0.0],
            normal: vec![0.0, 1.0]
        })
    );
    assert_eq!(s.boundary[0].name.as_deref(), Some("press"));
    assert_eq!(
        s.boundary[0].displacement,
        Some(Displacement {
            x: None,
            y: Some(-0.01),
            z: None
        })
    );
    let c = &s.contact[0];
    assert_eq!(c.name, "cyl-ground");
    assert_eq!(c.slave.surface.as_deref(), Some("arc"));
    assert_eq!(c.master.surface, None);
    assert_eq!(c.discretization, Discretization::NodeToSegment);
    assert_eq!(c.normal, NormalRule::Master);
    assert_eq!(c.law, Law::Unilateral);
    assert_eq!(c.friction, Friction::None);
    assert_eq!(c.gap, Gap::Geometric);
    assert_eq!(s.steps.len(), 1);
    assert_eq!(s.steps[0].scale["press"], 1.0);
    assert_eq!(s.solver, Solver::default());
    let r = s.reference.as_ref().unwrap();
    assert_eq!(r.kind, ReferenceKind::HertzCylinder);
    assert_eq!(r.radius, Some(1.0));
    assert_eq!(
        s.output.directory.as_deref(),
        Some(Path::new("out/hertz2d"))
    );
    assert_eq!(s.output.fields, ["displacement", "stress", "contact"]);
    assert_eq!(s.output.probes, vec![vec![0.0, 0.0], vec![0.00125, 0.0]]);
}

#[test]
fn json_equivalent_and_round_trips() {
    let s = parse_toml(HERTZ).unwrap();
    let json = serde_json::to_string_pretty(&s).unwrap();
    let back = parse_json(&json).unwrap();
    assert_eq!(s, back);
    // TOML round trip too
    let toml_text = toml::to_string(&s).unwrap();
    assert_eq!(parse_toml(&toml_text).unwrap(), s);

    let hand = r#"{
      "dimension": 2,
      "materials": [ { "name": "steel", "young": 1, "poisson": 0.3 } ],
      "bodies": [
        { "name": "cylinder", "material": "steel", "subdomains": "auto",
          "mesh": { "generator": "half_disk", "center": [0, 1], "radius": 1, "divisions": 32, "grading": 4 } },
        { "name": "ground", "rigid": { "shape": "plane", "point": [0, 0], "normal": [0, 1] } }
      ],
      "boundary": [ { "name": "press", "body": "cylinder", "surface": "flat", "displacement": { "y": -0.01 } } ],
      "contact": [ { "name": "cyl-ground", "slave": { "body": "cylinder", "surface": "arc" },
                     "master": { "body": "ground" }, "law": { "penalty": 1000 },
                     "friction": { "coulomb": 0.3 }, "gap": 0 } ],
      "solver": { "method": "lemke", "path": "direct" }
    }"#;
    let s = parse_json(hand).unwrap();
    assert_eq!(s.model, Model::PlaneStrain);
    assert_eq!(s.bodies[0].subdomains, Subdomains::Auto);
    assert_eq!(s.contact[0].law, Law::Penalty { penalty: 1000.0 });
    assert_eq!(
        s.contact[0].friction,
        Friction::Coulomb {
            coefficient: vec![0.3],
            slip_stiffness: None,
            roughness: None
        }
    );
    assert_eq!(s.contact[0].gap, Gap::Uniform(0.0));
    assert_eq!(s.solver.method, Method::Lemke);
    assert_eq!(s.solver.path, SolvePath::Direct);

    let bad = hand.replace("\"radius\": 1,", "\"radus\": 1,");
    let e = parse_json(&bad).unwrap_err().to_string();
    assert!(e.contains("radus") && e.contains("line"), "{e}");
}

#[test]
fn load_reads_toml_and_json_and_resolves_mesh_files() {
    let dir = std::env::temp_dir().join(format!("signorini-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let toml_path = dir.join("hertz2d.toml");
    std::fs::write(&toml_path, HERTZ).unwrap();
    let s = load(&toml_path).unwrap();
    let json_path = dir.join("hertz2d.json");
    std::fs::write(&json_path, serde_json::to_string(&s).unwrap()).unwrap();
    assert_eq!(load(&json_path).unwrap(), s);
    assert_eq!(s.output.directory_for(&toml_path), Path::new("out/hertz2d"));

    let file_scene = BASE.replace(
        r#"mesh = { generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }"#,
        r#"mesh = { file = "part.msh" }"#,
    );
    let p = dir.join("file.toml");
    std::fs::write(&p, &file_scene).unwrap();
    let s = load(&p).unwrap();
    assert_eq!(
        s.bodies[0].mesh,
        Some(MeshSpec::File {
            file: dir.join("part.msh"),
            volume: None
        })
    );
    assert_eq!(Output::default().directory_for(&p), Path::new("out/file"));

    let p = dir.join("broken.toml");
    std::fs::write(&p, "dimension = 2\nfoo = 1\n").unwrap();
    let e = load(&p).unwrap_err().to_string();
    assert!(
        e.contains("broken.toml") && e.contains("foo") && e.contains("line 2"),
        "{e}"
    );

    let e = load(&dir.join("missing.toml")).unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }), "{e:?}");
    assert!(e.to_string().contains("missing.toml"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn defaults() {
    let s = parse_toml(BASE).unwrap();
    assert_eq!(s.model, Model::PlaneStrain);
    assert_eq!(s.solver.tolerance, 1e-10);
    assert_eq!(s.solver.max_iterations, 500);
    assert_eq!(s.solver.method, Method::Status);
    // the default path is chosen by cost (solver::path_choice); it was condensed
    assert_eq!(s.solver.path, SolvePath::Auto);
    assert!(!s.solver.condition_estimate);
    assert_eq!(s.solver.friction, FrictionSolver::FixedPoint);
    assert_eq!(s.output, Output::default());
    assert_eq!(s.output.probes.len(), 0);
    assert!(s.reference.is_none());
    assert_eq!(s.step_scales().len(), 1);
    assert_eq!(s.step_scales()[0]["press"], 1.0);
    match &s.bodies[0].mesh {
        Some(MeshSpec::Generator(Generator::Rectangle(Block {
            element, grading, ..
        }))) => {
            assert_eq!(*element, Element::Quad4);
            assert!(grading.is_none());
        }
        other => panic!("{other:?}"),
    }

    let s3 = parse_toml(
        r#"
dimension = 3
[[materials]]
name = "m"
young = 2
poisson = 0
[[bodies]]
name = "ball"
material = "m"
mesh = { generator = "hemisphere", center = [0, 0, 1], radius = 1, divisions = 8 }
[[bodies]]
name = "block"
material = "m"
subdomains = 4
mesh = { generator = "box", origin = [0, 0, 0], size = [1, 1, 1], divisions = [2, 2, 2], grading = { towards = "zmax", ratio = 3 } }
"#,
    )
    .unwrap();
    assert_eq!(s3.model, Model::Solid);
    assert_eq!(s3.bodies[1].subdomains, Subdomains::Count(4));
    match &s3.bodies[0].mesh {
        Some(MeshSpec::Generator(Generator::Hemisphere(Hemisphere { pole, grading, .. }))) => {
            assert_eq!(*pole, [0.0, 0.0, -1.0]);
            assert_eq!(*grading, 1.0);
        }
        other => panic!("{other:?}"),
    }
    match &s3.bodies[1].mesh {
        Some(MeshSpec::Generator(Generator::Box(Block {
            element, grading, ..
        }))) => {
            assert_eq!(*element, Element::Hex8);
            assert_eq!(
                grading,
                &Some(Grading {
                    towards: "zmax".into(),
                    ratio: 3.0
                })
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn step_scales_keep_previous_values() {
    let s = parse_toml(&with(
        r#"
[[boundary]]
name = "push"
body = "plate"
surface = "left"
traction = [1.0, 0.0]

[[steps]]
scale = { press = 0.5 }
[[steps]]
scale = { push = 2.0 }
"#,
    ))
    .unwrap();
    let sc = s.step_scales();
    assert_eq!(sc.len(), 2);
    assert_eq!((sc[0]["press"], sc[0]["push"]), (0.5, 1.0));
    assert_eq!((sc[1]["press"], sc[1]["push"]), (0.5, 2.0));
}

#[test]
fn unknown_top_level_key_names_key_and_line() {
    let m = parse_err(&format!("{BASE}\ntolerence = 1e-8\n"));
    assert!(m.contains("tolerence"), "{m}");
    assert!(m.contains("line"), "{m}");
    let line = BASE.lines().count() + 2;
    assert!(m.contains(&format!("line {line}")), "{m}");
}

#[test]
fn unknown_key_in_materials_names_key_and_line() {
    let text = BASE.replace("poisson = 0.3", "poisson = 0.3\nyoungs = 2.0");
    let m = parse_err(&text);
    assert!(m.contains("youngs") && m.contains("line 8"), "{m}");
}

#[test]
fn unknown_key_in_bodies_and_solver_names_key_and_line() {
    let text = BASE.replace("name = \"plate\"", "name = \"plate\"\nmaterail = \"steel\"");
    let m = parse_err(&text);
    assert!(m.contains("materail") && m.contains("line 11"), "{m}");
    let m = parse_err(&with("[solver]\nmethod = \"status\"\ntol = 1e-3\n"));
    assert!(m.contains("tol") && m.contains("line"), "{m}");
    let m = parse_err(&with("[solver]\nmethod = \"newton\"\n"));
    assert!(
        m.contains("newton") && m.contains("projected_gradient"),
        "{m}"
    );
}

#[test]
fn unknown_key_in_generator_names_key() {
    let text = BASE.replace("size = [1.0, 0.5]", "radus = 1.0, size = [1.0, 0.5]");
    let m = parse_err(&text);
    assert!(m.contains("radus"), "{m}");
    assert!(m.contains("line 12"), "{m}");
    let text = BASE.replace("\"rectangle\"", "\"disk\"");
    let m = parse_err(&text);
    assert!(m.contains("disk") && m.contains("half_disk"), "{m}");
    let text = BASE.replace("generator = \"rectangle\",", "");
    let m = parse_err(&text);
    assert!(m.contains("generator") && m.contains("file"), "{m}");
    let text = BASE.replace("origin = [0.0, 0.0], ", "");
    let m = parse_err(&text);
    assert!(m.contains("origin"), "{m}");
    let m = parse_err(&BASE.replace("size = [1.0, 0.5]", "size = [1.0, 0.5, 2.0]"));
    assert!(m.contains("mesh.size") && m.contains("line 12"), "{m}");
    let m = parse_err(&BASE.replace("normal = [0.0, 1.0]", "normal = [0.0, 1.0], radius = 1.0"));
    assert!(m.contains("radius") && m.contains("line 16"), "{m}");
}

#[test]
fn toml_syntax_error_is_a_parse_error_with_line() {
    let m = parse_err("dimension = 2\n[[materials]\nname = 1\n");
    assert!(m.contains("line"), "{m}");
    let m = parse_err("dimension = \n");
    assert!(m.contains("line 1"), "{m}");
}

#[test]
fn material_constants() {
    let (e, m) = invalid_entry(&BASE.replace("young = 1.0", "young = -1.0"));
    assert_eq!(e, "materials[0].young");
    assert_eq!(m, "must be > 0, got -1");
    let (e, _) = invalid_entry(&BASE.replace("young = 1.0", "young = 0.0"));
    assert_eq!(e, "materials[0].young");
    let (e, m) = invalid_entry(&BASE.replace("poisson = 0.3", "poisson = 0.5"));
    assert_eq!(e, "materials[0].poisson");
    assert!(m.contains("0.5"), "{m}");
    let (e, _) = invalid_entry(&BASE.replace("poisson = 0.3", "poisson = -1.0"));
    assert_eq!(e, "materials[0].poisson");
    let text = with("[[materials]]\nname = \"steel\"\nyoung = 2.0\npoisson = 0.2\n");
    let (e, m) = invalid_entry(&text);
    assert_eq!(e, "materials[1].name");
    assert!(m.contains("unique"), "{m}");
    let t = err(&BASE.replace("young = 1.0", "young = -1.0"));
    assert_eq!(t, "materials[0].young: must be > 0, got -1");
}

#[test]
fn unknown_material_lists_known_ones() {
    let (e, m) = invalid_entry(&BASE.replace("material = \"steel\"", "material = \"rubber\""));
    assert_eq!(e, "bodies[0].material");
    assert!(m.contains("rubber") && m.contains("\"steel\""), "{m}");
    let (e, m) = invalid_entry(&BASE.replace("material = \"steel\"\n", ""));
    assert_eq!(e, "bodies[0].material");
    assert!(m.contains("\"steel\""), "{m}");
    let (e, _) =
        invalid_entry(&BASE.replace("rigid = { shape", "material = \"steel\"\nrigid = { shape"));
    assert_eq!(e, "bodies[1].material");
}

#[test]
fn empty_scene() {
    let (e, m) = invalid_entry("dimension = 2\n");
    assert_eq!(e, "bodies");
    assert_eq!(
        m,
        "the scene has no deformable body; add a [[bodies]] entry with a mesh"
    );
    let (e, _) = invalid_entry(
        "dimension = 2\n[[bodies]]\nname = \"g\"\nrigid = { shape = \"plane\", point = [0, 0], normal = [0, 1] }\n",
    );
    assert_eq!(e, "bodies");
    let m = parse_err("title = \"x\"\n");
    assert!(m.contains("dimension"), "{m}");
}

#[test]
fn dimension_and_model() {
    let (e, _) = invalid_entry(&BASE.replace("dimension = 2", "dimension = 4"));
    assert_eq!(e, "dimension");
    let (e, m) = invalid_entry(&BASE.replace("dimension = 2", "dimension = 2\nmodel = \"solid\""));
    assert_eq!(e, "model");
    assert!(m.contains("plane_strain"), "{m}");
    let (e, _) = invalid_entry(&BASE.replace("dimension = 2", "dimension = 3"));
    assert_eq!(e, "bodies[0].mesh.generator");
    let m = parse_err(&BASE.replace("dimension = 2", "dimension = 2\nmodel = \"plain_strain\""));
    assert!(
        m.contains("plain_strain") && m.contains("plane_strain") && m.contains("line 3"),
        "{m}"
    );
}

#[test]
fn generator_checks() {
    let half = |extra: &str| {
        BASE.replace(
            r#"{ generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }"#,
            &format!(r#"{{ generator = "half_disk", center = [0.0, 1.0], {extra} }}"#),
        )
    };
    assert!(parse_toml(&half("radius = 1.0, divisions = 8")).is_ok());
    let (e, m) = invalid_entry(&half("radius = -1.0, divisions = 8"));
    assert_eq!(
        (e.as_str(), m.as_str()),
        ("bodies[0].mesh.radius", "must be > 0, got -1")
    );
    let (e, _) = invalid_entry(&half("radius = 1.0, divisions = 3"));
    assert_eq!(e, "bodies[0].mesh.divisions");
    let (e, _) = invalid_entry(&half("radius = 1.0, divisions = 8, grading = 0.5"));
    assert_eq!(e, "bodies[0].mesh.grading");
    let (e, _) = invalid_entry(&half("radius = 1.0, divisions = 8, pole = [0, 0]"));
    assert_eq!(e, "bodies[0].mesh.pole");
    let (e, m) = invalid_entry(&half("radius = 1.0, divisions = 8, element = \"hex8\""));
    assert_eq!(e, "bodies[0].mesh.element");
    assert!(m.contains("quad4 or tri3"), "{m}");

    let rect = |r: &str| BASE.replace("size = [1.0, 0.5], divisions = [4, 2]", r);
    let (e, _) = invalid_entry(&rect("size = [1.0, 0.0], divisions = [4, 2]"));
    assert_eq!(e, "bodies[0].mesh.size");
    let (e, _) = invalid_entry(&rect("size = [1.0, 1.0], divisions = [0, 2]"));
    assert_eq!(e, "bodies[0].mesh.divisions");
    let (e, m) = invalid_entry(&rect(
        "size = [1.0, 1.0], divisions = [4, 2], grading = { towards = \"zmax\", ratio = 2 }",
    ));
    assert_eq!(e, "bodies[0].mesh.grading.towards");
    assert!(m.contains("bottom"), "{m}");
    let (e, _) = invalid_entry(&rect(
        "size = [1.0, 1.0], divisions = [4, 2], grading = { towards = \"top\", ratio = 0.9 }",
    ));
    assert_eq!(e, "bodies[0].mesh.grading.ratio");
    let ok = parse_toml(&rect(
        "size = [1.0, 1.0], divisions = [4, 2], element = \"tri3\", grading = { towards = \"top\", ratio = 2 }",
    ));
    assert!(ok.is_ok(), "{ok:?}");

    let quarter = BASE.replace(
        r#"{ generator = "rectangle", origin = [0.0, 0.0], size = [1.0, 0.5], divisions = [4, 2] }"#,
        r#"{ generator = "quarter_disk", center = [0.0, 1.0], radius = 1.0, divisions = 8, grading = 2.0 }"#,
    );
    let (e, m) = invalid_entry(&quarter);
    assert_eq!(e, "bodies[0].mesh.generator");
    assert!(m.contains("axisymmetric"), "{m}");
    let axi = quarter.replace("dimension = 2", "dimension = 2\nmodel = \"axisymmetric\"");
    assert!(parse_toml(&axi).is_ok());
}

#[test]
fn body_checks() {
    #[rustfmt::skip]
    let edits: [(&str, &str, &str, &[&str]); 6] = [
        ("name = \"ground\"", "name = \"plate\"", "bodies[1].name", &[]),
        ("rigid = { shape = \"plane\"", "mesh = { file = \"a.msh\" }\nrigid = { shape = \"plane\"", "bodies[1]", &["not both"]),
        ("name = \"plate\"", "name = \"plate\"\nsubdomains = 0", "bodies[0].subdomains", &[]),
        ("normal = [0.0, 1.0]", "normal = [0.0, 0.0]", "bodies[1].rigid.normal", &[]),
        ("normal = [0.0, 1.0]", "normal = [0.0, 1.0, 0.0]", "bodies[1].rigid.normal", &[]),
        ("{ shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }", "{ shape = \"sphere\", center = [0.0, 0.0], radius = 1.0 }", "bodies[1].rigid.shape", &[]),
    ];
    assert_invalid_edits(&edits);
    let ok = parse_toml(&BASE.replace(
        "{ shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }",
        "{ shape = \"circle\", center = [0.0, -1.0], radius = 1.0 }",
    ));
    assert!(ok.is_ok(), "{ok:?}");
}

#[test]
fn subdomains_both_forms() {
    let s = parse_toml(&BASE.replace(
        "name = \"plate\"",
        "name = \"plate\"\nsubdomains = \"auto\"",
    ))
    .unwrap();
    assert_eq!(s.bodies[0].subdomains, Subdomains::Auto);
    let s =
        parse_toml(&BASE.replace("name = \"plate\"", "name = \"plate\"\nsubdomains = 3")).unwrap();
    assert_eq!(s.bodies[0].subdomains, Subdomains::Count(3));
    let m = parse_err(&BASE.replace(
        "name = \"plate\"",
        "name = \"plate\"\nsubdomains = \"many\"",
    ));
    assert!(m.contains("auto") && m.contains("line 11"), "{m}");
    let m = parse_err(&BASE.replace("name = \"plate\"", "name = \"plate\"\nsubdomains = -2"));
    assert!(m.contains("auto"), "{m}");
}

#[test]
fn boundary_checks() {
    let press = "displacement = { y = -0.01 }";
    #[rustfmt::skip]
    let edits: [(&str, &str, &str, &[&str]); 9] = [
        ("body = \"plate\"", "body = \"plat\"", "boundary[0].body", &["\"plate\"", "\"ground\""]),
        ("body = \"plate\"", "body = \"ground\"", "boundary[0].body", &["rigid"]),
        ("surface = \"top\"\n", "", "boundary[0]", &[]),
        ("surface = \"top\"", "surface = \"top\"\npoint = [0, 0]", "boundary[0]", &[]),
        ("surface = \"top\"", "point = [0, 0, 0]", "boundary[0].point", &[]),
        (press, "displacement = {}", "boundary[0].displacement", &[]),
        (press, "displacement = { z = 1 }", "boundary[0].displacement.z", &[]),
        (press, "displacement = { y = -0.01 }\nforce = [0, 1]", "boundary[0]", &["exactly one"]),
        (press, "traction = [0, 1, 2]", "boundary[0].traction", &[]),
    ];
    assert_invalid_edits(&edits);
    let m = parse_err(&BASE.replace("displacement = { y = -0.01 }", "displacement = { w = 1 }"));
    assert!(m.contains("`w`") && m.contains("line"), "{m}");
    let text = with(
        "[[boundary]]\nname = \"press\"\nbody = \"plate\"\nsurface = \"left\"\nforce = [1, 0]\n",
    );
    let (e, _) = invalid_entry(&text);
    assert_eq!(e, "boundary[1].name");
}

/// `moment_about`: a point of `dimension` finite coordinates, on a
/// displacement entry only, not in an axisymmetric model.
#[test]
fn moment_about_checks() {
    let about = |p: &str| {
        BASE.replace(
            "displacement = { y = -0.01 }",
            &format!("displacement = {{ y = -0.01 }}\nmoment_about = {p}"),
        )
    };
    let s = parse_toml(&about("[0.5, 0.25]")).unwrap();
    assert_eq!(s.boundary[0].moment_about, Some(vec![0.5, 0.25]));
    assert_eq!(parse_toml(BASE).unwrap().boundary[0].moment_about, None);
    let (e, m) = invalid_entry(&about("[0.5, 0.25, 1.0]"));
    assert_eq!(e, "boundary[0].moment_about");
    assert!(m.contains("needs 2 components"), "{m}");
    let (e, _) = invalid_entry(&about("[0.5, nan]"));
    assert_eq!(e, "boundary[0].moment_about");
    let (e, m) = invalid_entry(
        &about("[0.5, 0.25]").replace("displacement = { y = -0.01 }", "traction = [0.0, -1.0]"),
    );
    assert_eq!(e, "boundary[0].moment_about");
    assert!(
        m.contains("only a `displacement` entry has a reaction"),
        "{m}"
    );
    let (e, m) = invalid_entry(&about("[0.5, 0.25]").replace(
        "dimension = 2\n",
        "dimension = 2\nmodel = \"axisymmetric\"\n",
    ));
    assert_eq!(e, "boundary[0].moment_about");
    assert!(m.contains("axisymmetric"), "{m}");
}

#[test]
fn contact_checks() {
    assert!(parse_toml(&contact("")).is_ok());
    const SLAVE: &str = "slave = { body = \"plate\", surface = \"bottom\" }";
    const MASTER: &str = "master = { body = \"ground\" }";
    /// Replacements in the valid contact, the entry refused, words of its message.
    type Refusal<'a> = (&'a [(&'a str, &'a str)], &'a str, &'a [&'a str]);
    let cases: [Refusal; 6] = [
        // slave without surface
        (
            &[(SLAVE, "slave = { body = \"plate\" }")],
            "contact \"c\".slave.surface",
            &["surface"],
        ),
        // unknown master
        (
            &[(MASTER, "master = { body = \"floor\" }")],
            "contact \"c\".master.body",
            &["floor", "\"ground\""],
        ),
        // rigid slave
        (
            &[
                (SLAVE, "slave = { body = \"ground\", surface = \"x\" }"),
                (
                    MASTER,
                    "master = { body = \"plate\", surface = \"bottom\" }",
                ),
            ],
            "contact \"c\".slave.body",
            &[],
        ),
        // deformable master without surface, self contact
        (
            &[(MASTER, "master = { body = \"plate\" }")],
            "contact \"c\".master.surface",
            &[],
        ),
        (
            &[(MASTER, "master = { body = \"plate\", surface = \"top\" }")],
            "contact \"c\"",
            &["not supported"],
        ),
        // rigid master with a surface
        (
            &[(MASTER, "master = { body = \"ground\", surface = \"top\" }")],
            "contact \"c\".master.surface",
            &[],
        ),
    ];
    for (swaps, entry, words) in cases {
        let text = swaps.iter().fold(contact(""), |t, (a, b)| t.replace(a, b));
        let (e, m) = invalid_entry(&text);
        assert_eq!(e, entry);
        for word in words {
            assert!(m.contains(word), "{m}");
        }
    }
    // duplicate names
    let text = format!("{}\n[[contact]]\nname = \"c\"\nslave = {{ body = \"plate\", surface = \"left\" }}\nmaster = {{ body = \"ground\" }}\n", contact(""));
    let (e, _) = invalid_entry(&text);
    assert_eq!(e, "contact \"c\".name");
    // numeric checks
    for (line, entry) in [
        ("law = { penalty = 0 }", "law.penalty"),
        ("friction = { coulomb = -0.1 }", "friction.coulomb"),
        ("friction = { coulomb = [0.3, 0.1] }", "friction.coulomb"),
        (
            "friction = { coulomb = 0.3, slip_stiffness = 0 }",
            "friction.slip_stiffness",
        ),
        (
            "friction = { norton_hoff = 0.3, rho = 1.0 }",
            "friction.rho",
        ),
        ("friction = { tresca = -1 }", "friction.tresca"),
        ("gap = nan", "gap"),
    ] {
        let (e, _) = invalid_entry(&contact(line));
        assert_eq!(e, format!("contact \"c\".{entry}"), "{line}");
    }
    let m = parse_err(&contact("normal = \"outward\""));
    assert!(m.contains("outward") && m.contains("average"), "{m}");
    let m = parse_err(&contact("discretization = \"nts\""));
    assert!(m.contains("node_to_segment"), "{m}");
}

#[test]
fn law_both_forms_and_bad_law() {
    let s = parse_toml(&contact("law = \"unilateral\"")).unwrap();
    assert_eq!(s.contact[0].law, Law::Unilateral);
    let s = parse_toml(&contact("law = { penalty = 1e3 }")).unwrap();
    assert_eq!(s.contact[0].law, Law::Penalty { penalty: 1e3 });
    let s = parse_toml(&contact("law = { penalty = 1000 }")).unwrap();
    assert_eq!(s.contact[0].law, Law::Penalty { penalty: 1e3 });

    let m = parse_err(&contact("law = \"elastic\""));
    assert!(
        m.contains(
            r#"law: expected "unilateral", "tied" or { penalty = <stiffness> }, got "elastic""#
        ),
        "{m}"
    );
    assert!(m.contains("line"), "{m}");
    let m = parse_err(&contact("law = \"penalty\""));
    assert!(m.contains("penalty = <stiffness>"), "{m}");
    let m = parse_err(&contact("law = { stiffness = 1e3 }"));
    assert!(m.contains("stiffness") && m.contains("unilateral"), "{m}");
    let m = parse_err(&contact("law = { penalty = \"big\" }"));
    assert!(m.contains("law.penalty"), "{m}");
    let m = parse_err(&contact("law = 3"));
    assert!(m.contains("unilateral"), "{m}");
}

#[test]
fn friction_all_forms() {
    let f = |line: &str| {
        parse_toml(&contact(line)).unwrap().contact[0]
            .friction
            .clone()
    };
    assert_eq!(f("friction = \"none\""), Friction::None);
    assert_eq!(f("friction = { tresca = 0.1 }"), Friction::Tresca(0.1));
    assert_eq!(
        f("friction = { coulomb = 0.3 }"),
        Friction::Coulomb {
            coefficient: vec![0.3],
            slip_stiffness: None,
            roughness: None
        }
    );
    assert_eq!(
        f("friction = { coulomb = 0.3, slip_stiffness = 1e4 }"),
        Friction::Coulomb {
            coefficient: vec![0.3],
            slip_stiffness: Some(1e4),
            roughness: None
        }
    );
    assert_eq!(
        f("friction = { coulomb = 0.3, slip_stiffness = 1e4, roughness = 50.0 }"),
        Friction::Coulomb {
            coefficient: vec![0.3],
            slip_stiffness: Some(1e4),
            roughness: Some(50.0)
        }
    );
    assert_eq!(
        f("friction = { norton_hoff = 0.3, rho = 0.2 }"),
        Friction::NortonHoff {
            coefficient: 0.3,
            rho: 0.2
        }
    );
    let m = parse_err(&contact("friction = \"coulomb\""));
    assert!(m.contains("{ coulomb = <value> }"), "{m}");
    let m = parse_err(&contact("friction = \"sticky\""));
    assert!(m.contains("sticky") && m.contains("\"none\""), "{m}");
    let m = parse_err(&contact("friction = { coulomb = 0.3, tresca = 0.1 }"));
    assert!(m.contains("exactly one"), "{m}");
    let m = parse_err(&contact("friction = { norton_hoff = 0.3 }"));
    assert!(m.contains("rho"), "{m}");
    let m = parse_err(&contact("friction = { coulomb = 0.3, rho = 0.2 }"));
    assert!(m.contains("rho"), "{m}");
    let m = parse_err(&contact("friction = { colomb = 0.3 }"));
    assert!(m.contains("colomb") && m.contains("line"), "{m}");
}

#[test]
fn anisotropic_coulomb_in_3d() {
    let text = r#"
dimension = 3
[[materials]]
name = "m"
young = 1
poisson = 0.25
[[bodies]]
name = "block"
material = "m"
mesh = { generator = "box", origin = [0, 0, 0], size = [1, 1, 1], divisions = [2, 2, 2], element = "tet4" }
[[bodies]]
name = "ball"
rigid = { shape = "sphere", center = [0.5, 0.5, 2.0], radius = 1.0 }
[[contact]]
name = "c"
slave = { body = "block", surface = "zmax" }
master = { body = "ball" }
friction = { coulomb = [0.3, 0.1] }
discretization = "mortar"
normal = "average"
"#;
    let s = parse_toml(text).unwrap();
    assert_eq!(
        s.contact[0].friction,
        Friction::Coulomb {
            coefficient: vec![0.3, 0.1],
            slip_stiffness: None,
            roughness: None
        }
    );
    assert_eq!(s.contact[0].discretization, Discretization::Mortar);
    assert_eq!(s.contact[0].normal, NormalRule::Average);
    let json = serde_json::to_value(&s.contact[0].friction).unwrap();
    assert_eq!(json, serde_json::json!({ "coulomb": [0.3, 0.1] }));
}

#[test]
fn gap_both_forms() {
    let g = |line: &str| parse_toml(&contact(line)).unwrap().contact[0].gap;
    assert_eq!(g("gap = \"geometric\""), Gap::Geometric);
    assert_eq!(g("gap = 0.01"), Gap::Uniform(0.01));
    assert_eq!(g("gap = 0"), Gap::Uniform(0.0));
    let m = parse_err(&contact("gap = \"uniform\""));
    assert!(m.contains("geometric") && m.contains("number"), "{m}");
}

#[test]
fn steps_must_name_boundary_entries() {
    let (e, m) = invalid_entry(&with("[[steps]]\nscale = { pres = 1.0 }\n"));
    assert_eq!(e, "steps[0].scale.pres");
    assert!(m.contains("pres") && m.contains("\"press\""), "{m}");
    let (e, _) = invalid_entry(&with("[[steps]]\nscale = { press = inf }\n"));
    assert_eq!(e, "steps[0].scale.press");
}

#[test]
fn solver_reference_output_checks() {
    let (e, _) = invalid_entry(&with("[solver]\ntolerance = 0.0\n"));
    assert_eq!(e, "solver.tolerance");
    let (e, _) = invalid_entry(&with("[solver]\ntolerance = 1.5\n"));
    assert_eq!(e, "solver.tolerance");
    let (e, _) = invalid_entry(&with("[solver]\nmax_iterations = 0\n"));
    assert_eq!(e, "solver.max_iterations");
    let s = parse_toml(&with(
        "[solver]\nmethod = \"augmented_lagrangian\"\npath = \"direct\"\nfriction = \"status\"\n",
    ))
    .unwrap();
    assert_eq!(s.solver.method, Method::AugmentedLagrangian);
    assert_eq!(s.solver.friction, FrictionSolver::Status);
    let s = parse_toml(&with("[solver]\nfriction = \"newton\"\n")).unwrap();
    assert_eq!(s.solver.friction, FrictionSolver::Newton);
    assert_eq!(s.solver.friction.as_str(), "newton");
    let s = parse_toml(&with("[solver]\nfriction = \"nsgs\"\ntime_limit = 2.5\n")).unwrap();
    assert_eq!(s.solver.friction, FrictionSolver::Nsgs);
    assert_eq!(s.solver.time_limit, Some(2.5));
    assert_eq!(parse_toml(&with("")).unwrap().solver.time_limit, None);
    for bad in ["0", "-1.0", "nan", "inf"] {
        let (e, m) = invalid_entry(&with(&format!("[solver]\ntime_limit = {bad}\n")));
        assert_eq!(e, "solver.time_limit", "{bad}: {m}");
    }

    let (e, m) = invalid_entry(&with("[reference]\nkind = \"hertz_cylinder\"\n"));
    assert_eq!(e, "reference.radius");
    assert!(m.contains("hertz_cylinder"), "{m}");
    let (e, _) = invalid_entry(&with("[reference]\nkind = \"flat_punch\"\nradius = -1\n"));
    assert_eq!(e, "reference.radius");
    // Two-body Hertz: the combined radius 1/R = 1/radius + 1/radius2.
    let s = parse_toml(&with(
        "[reference]\nkind = \"hertz_cylinder\"\nradius = 1.0\nradius2 = 3.0\n",
    ))
    .unwrap();
    assert_eq!(s.reference.unwrap().effective_radius(), Some(0.75));
    let s = parse_toml(&with(
        "[reference]\nkind = \"hertz_cylinder\"\nradius = 1.0\nradius2 = -4.0\n",
    ))
    .unwrap();
    let r = s.reference.unwrap().effective_radius().unwrap();
    assert!((r - 4.0 / 3.0).abs() < 1e-15, "{r}");
    for (extra, needle) in [
        ("radius = 1.0\nradius2 = -1.0", "wider"),
        ("radius = 1.0\nradius2 = 0.0", "non-zero"),
        ("radius2 = 2.0", "needs `radius`"),
    ] {
        let (e, m) = invalid_entry(&with(&format!(
            "[reference]\nkind = \"hertz_cylinder\"\n{extra}\n"
        )));
        assert_eq!(e, "reference.radius2", "{m}");
        assert!(m.contains(needle), "{m}");
    }
    let (e, m) = invalid_entry(&with(
        "[reference]\nkind = \"uniform_pressure\"\nradius2 = 2.0\n",
    ));
    assert_eq!(e, "reference.radius2");
    assert!(m.contains("hertz_cylinder"), "{m}");
    let s = parse_toml(&with(
        "[reference]\nkind = \"uniform_pressure\"\npressure = 2.0\n",
    ))
    .unwrap();
    assert_eq!(s.reference.unwrap().kind, ReferenceKind::UniformPressure);
    let m = parse_err(&with("[reference]\nkind = \"hertz\"\n"));
    assert!(m.contains("hertz_cylinder"), "{m}");

    let (e, m) = invalid_entry(&with("[output]\nfields = [\"strain\"]\n"));
    assert_eq!(e, "output.fields[0]");
    assert!(m.contains("displacement"), "{m}");
    let (e, _) = invalid_entry(&with("[output]\nprobes = [[0.0, 0.0, 0.0]]\n"));
    assert_eq!(e, "output.probes[0]");
    let s = parse_toml(&with("[output]\nfields = []\n")).unwrap();
    assert!(s.output.fields.is_empty() && s.output.directory.is_none());
}

#[test]
fn method_and_path_from_str() {
    for m in Method::ALL {
        assert_eq!(m.as_str().parse::<Method>().unwrap(), m);
        assert_eq!(m.to_string(), m.as_str());
    }
    assert_eq!(
        "projected-gradient".parse::<Method>().unwrap(),
        Method::ProjectedGradient
    );
    let e = "newton".parse::<Method>().unwrap_err();
    assert!(
        e.contains("newton") && e.contains("mprgp") && e.contains("augmented_lagrangian"),
        "{e}"
    );
    assert_eq!("direct".parse::<SolvePath>().unwrap(), SolvePath::Direct);
    assert_eq!(
        "condensed".parse::<SolvePath>().unwrap(),
        SolvePath::Condensed
    );
    assert_eq!("auto".parse::<SolvePath>().unwrap(), SolvePath::Auto);
    let e = "dense".parse::<SolvePath>().unwrap_err();
    assert!(
        e.contains("condensed") && e.contains("direct") && e.contains("auto"),
        "{e}"
    );
    assert_eq!(ReferenceKind::CattaneoMindlin.as_str(), "cattaneo_mindlin");
    // as_str agrees with serde
    for k in [
        ReferenceKind::HertzCylinder,
        ReferenceKind::HertzSphere,
        ReferenceKind::FlatPunch,
        ReferenceKind::UniformPressure,
        ReferenceKind::CattaneoMindlin,
        ReferenceKind::SlidingBlock,
    ] {
        assert_eq!(serde_json::to_value(k).unwrap(), k.as_str());
    }
    for m in Method::ALL {
        assert_eq!(serde_json::to_value(m).unwrap(), m.as_str());
    }
}

#[test]
fn body_formulation() {
    // default, spellings, and JSON / TOML round trips
    let s = parse_toml(BASE).unwrap();
    assert_eq!(s.bodies[0].formulation, Formulation::Displacement);
    assert!(!toml::to_string(&s).unwrap().contains("formulation"));
    let text = BASE.replacen(
        "material = \"steel\"\n",
        "material = \"steel\"\nformulation = \"b_bar\"\n",
        1,
    );
    let s = parse_toml(&text).unwrap();
    assert_eq!(s.bodies[0].formulation, Formulation::BBar);
    assert_eq!(s.bodies[0].formulation.as_str(), "b_bar");
    let json = serde_json::to_string(&s).unwrap();
    assert!(json.contains("\"formulation\":\"b_bar\""), "{json}");
    assert_eq!(parse_json(&json).unwrap(), s);
    assert_eq!(parse_toml(&toml::to_string(&s).unwrap()).unwrap(), s);
    let explicit = text.replace("\"b_bar\"", "\"displacement\"");
    assert_eq!(
        parse_toml(&explicit).unwrap().bodies[0].formulation,
        Formulation::Displacement
    );

    // an unknown value names itself, the valid ones and the line
    let e = parse_err(&text.replace("\"b_bar\"", "\"bbar\""));
    assert!(
        e.contains("bbar")
            && e.contains("b_bar")
            && e.contains("displacement")
            && e.contains("line"),
        "{e}"
    );

    // plane stress does not lock
    let (entry, msg) = invalid_entry(&text.replace(
        "dimension = 2\n",
        "dimension = 2\nmodel = \"plane_stress\"\n",
    ));
    assert_eq!(entry, "bodies[0].formulation");
    assert!(
        msg.contains("plane_stress") && msg.contains("quad4"),
        "{msg}"
    );

    // triangles (and second-order cells) have no B-bar
    for el in ["tri3", "tri6", "quad8"] {
        let (entry, msg) = invalid_entry(&text.replace(
            "divisions = [4, 2] }",
            &format!("divisions = [4, 2], element = \"{el}\" }}"),
        ));
        assert_eq!(entry, "bodies[0].formulation");
        assert!(msg.contains(el) && msg.contains("hex8"), "{msg}");
    }

    // axisymmetric quad4 and 3D hex8 (the hemisphere's cells) are fine,
    // tet4 is not
    let axi = text.replace(
        "dimension = 2\n",
        "dimension = 2\nmodel = \"axisymmetric\"\n",
    );
    assert!(parse_toml(&axi).is_ok());
    let solid = |mesh: &str| {
        format!(
            "dimension = 3\n[[materials]]\nname = \"m\"\nyoung = 1.0\npoisson = 0.49\n[[bodies]]\nname = \"b\"\nmaterial = \"m\"\nformulation = \"b_bar\"\nmesh = {mesh}\n"
        )
    };
    let hemi = solid(
        "{ generator = \"hemisphere\", center = [0.0, 0.0, 1.0], radius = 1.0, divisions = 4 }",
    );
    assert!(parse_toml(&hemi).is_ok(), "{:?}", parse_toml(&hemi).err());
    let tets = solid("{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 1.0], divisions = [2, 2, 2], element = \"tet4\" }");
    let (entry, msg) = invalid_entry(&tets);
    assert_eq!(entry, "bodies[0].formulation");
    assert!(msg.contains("tet4"), "{msg}");

    // a rigid body has no elements
    let rigid = text.replacen(
        "name = \"ground\"\n",
        "name = \"ground\"\nformulation = \"b_bar\"\n",
        1,
    );
    let (entry, _) = invalid_entry(&rigid);
    assert_eq!(entry, "bodies[1].formulation");
}
