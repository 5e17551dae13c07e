use super::*;

fn scene(mesh: &str, dim: u8) -> scene::Scene {
    let (surface, rigid) = if dim == 3 {
        (
            "zmin",
            "rigid = { shape = \"plane\", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }",
        )
    } else {
        (
            "bottom",
            "rigid = { shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }",
        )
    };
    scene::parse_toml(&format!(
        "dimension = {dim}\n[[materials]]\nname = \"s\"\nyoung = 1.0\npoisson = 0.3\n[[bodies]]\nname = \"b\"\nmaterial = \"s\"\nmesh = {mesh}\n[[bodies]]\nname = \"g\"\n{rigid}\n[[contact]]\nname = \"c\"\nslave = {{ body = \"b\", surface = \"{surface}\" }}\nmaster = {{ body = \"g\" }}\n"
    ))
    .unwrap()
}

/// A deformable body "b" meshed by `generator`.
fn generated(generator: scene::Generator) -> scene::Body {
    scene::Body {
        name: "b".into(),
        material: None,
        subdomains: Default::default(),
        mesh: Some(scene::MeshSpec::Generator(generator)),
        rigid: None,
        formulation: Default::default(),
    }
}

#[test]
fn sizes_match_the_generators() {
    use signorini_mesh::generators as g;
    use signorini_mesh::CellKind;
    let close = |what: &str, est: f64, real: usize| {
        let r = est / real as f64;
        assert!(
            (0.97..=1.1).contains(&r),
            "{what}: estimated {est}, real {real}"
        );
    };
    for (el, kind) in [
        (scene::Element::Quad4, CellKind::Quad4),
        (scene::Element::Tri3, CellKind::Tri3),
        (scene::Element::Quad8, CellKind::Quad8),
        (scene::Element::Tri6, CellKind::Tri6),
    ] {
        let m = g::rectangle([0.0, 0.0], [1.0, 1.0], [7, 3], kind, None).unwrap();
        let body = generated(scene::Generator::Rectangle(scene::Block {
            origin: [0.0, 0.0],
            size: [1.0, 1.0],
            divisions: [7, 3],
            element: el,
            grading: None,
        }));
        let s = body_size(&body, 2).unwrap();
        assert_eq!(s.nodes as usize, m.n_nodes(), "{el:?}");
        assert_eq!(s.cells as usize, m.cells.len(), "{el:?}");
        let bottom = m.surface("bottom").unwrap().nodes().len();
        assert_eq!(s.surface("bottom") as usize, bottom, "{el:?}");
        for (n, grading) in [(8, 1.0), (40, 1.0), (160, 16.0)] {
            let m = g::half_disk(
                &g::HalfBall::new([0.0, 1.0], 1.0, n, [0.0, -1.0], grading),
                kind,
            )
            .unwrap();
            let body = generated(scene::Generator::HalfDisk(scene::HalfDisk {
                center: [0.0, 1.0],
                radius: 1.0,
                divisions: n,
                pole: [0.0, -1.0],
                grading,
                element: el,
            }));
            let s = body_size(&body, 2).unwrap();
            close(&format!("half_disk {n} {el:?} nodes"), s.nodes, m.n_nodes());
            close(
                &format!("half_disk {n} {el:?} cells"),
                s.cells,
                m.cells.len(),
            );
            let arc = m.surface("arc").unwrap().nodes().len();
            close(&format!("half_disk {n} {el:?} arc"), s.surface("arc"), arc);
            let m = g::quarter_disk([0.0, 1.0], 1.0, n, grading, kind).unwrap();
            let body = generated(scene::Generator::QuarterDisk(scene::QuarterDisk {
                center: [0.0, 1.0],
                radius: 1.0,
                divisions: n,
                grading,
                element: el,
            }));
            let s = body_size(&body, 2).unwrap();
            close(
                &format!("quarter_disk {n} {el:?} nodes"),
                s.nodes,
                m.n_nodes(),
            );
            close(
                &format!("quarter_disk {n} {el:?} cells"),
                s.cells,
                m.cells.len(),
            );
        }
    }
    for (el, kind) in [
        (scene::Element::Hex8, CellKind::Hex8),
        (scene::Element::Tet4, CellKind::Tet4),
    ] {
        let m = g::box_mesh([0.0; 3], [1.0; 3], [4, 3, 2], kind, None).unwrap();
        let sc = scene(
            &format!("{{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 1.0], divisions = [4, 3, 2], element = \"{}\" }}", el.as_str()),
            3,
        );
        let s = body_size(&sc.bodies[0], 3).unwrap();
        assert_eq!(s.nodes as usize, m.n_nodes());
        assert_eq!(s.cells as usize, m.cells.len());
        let zmin = m.surface("zmin").unwrap().nodes().len();
        assert_eq!(s.surface("zmin") as usize, zmin);
    }
    for (n, grading) in [(4, 1.0), (12, 8.0), (20, 1.0)] {
        let m = g::hemisphere(&g::HalfBall::new(
            [0.0, 0.0, 1.0],
            1.0,
            n,
            [0.0, 0.0, -1.0],
            grading,
        ))
        .unwrap();
        let sc = scene(
            &format!("{{ generator = \"hemisphere\", center = [0.0, 0.0, 1.0], radius = 1.0, divisions = {n}, grading = {grading:.1} }}"),
            3,
        );
        let s = body_size(&sc.bodies[0], 3).unwrap();
        close(&format!("hemisphere {n} nodes"), s.nodes, m.n_nodes());
        close(&format!("hemisphere {n} cells"), s.cells, m.cells.len());
        let dome = m.surface("dome").unwrap().nodes().len();
        close(&format!("hemisphere {n} dome"), s.surface("dome"), dome);
    }
}

#[test]
fn the_3000_square_does_not_fit_in_24_gib_and_the_small_ones_do() {
    let rect = |k: usize| {
        scene(
            &format!("{{ generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 1.0], divisions = [{k}, {k}] }}"),
            2,
        )
    };
    let path = scene::SolvePath::Condensed;
    let big = estimate(&rect(3000), path, 1, ContactCounts::Surfaces);
    assert!(big.total > 24.0 * GIB, "{}", big.describe());
    assert!(big.total < 200.0 * GIB, "{}", big.describe());
    // measured peaks (faer 0.24): 400²: 895 MiB, 800²: 3.6 GiB
    let mid = estimate(&rect(400), path, 1, ContactCounts::Surfaces);
    assert!(
        (0.9..1.6).contains(&(mid.total / (895.0 * 1024.0 * 1024.0))),
        "{}",
        mid.describe()
    );
    let small = estimate(&rect(40), path, 1, ContactCounts::Surfaces);
    assert!(small.total < 0.1 * GIB, "{}", small.describe());
    // no overflow, however large
    let huge = estimate(&rect(usize::MAX / 2), path, 1, ContactCounts::Surfaces);
    assert!(huge.total.is_finite() && huge.bytes() == u64::MAX);
}

#[test]
fn sizes_parse_with_units() {
    assert_eq!(parse_size("64G").unwrap(), 64 << 30);
    assert_eq!(parse_size("1.5 GiB").unwrap(), 3 << 29);
    assert_eq!(parse_size("500m").unwrap(), 500 << 20);
    assert_eq!(parse_size("2T").unwrap(), 2 << 40);
    assert_eq!(parse_size("4096").unwrap(), 4096);
    assert!(parse_size("lots").is_err());
    assert!(parse_size("-3G").is_err());
    assert!(parse_size("3 parsecs").is_err());
    assert!(parse_size("nan").is_err());
}

#[test]
fn meminfo_is_read_here() {
    if std::path::Path::new("/proc/meminfo").exists() {
        let m = machine_memory().expect("/proc/meminfo has MemAvailable or MemTotal");
        assert!(m.bytes > 64 << 20, "{m:?}");
    }
}

/// A flat body split into parts is cut across its long sides: the cuts hold
/// about a·b nodes each (a ≤ b ≤ c nodes per side), not the n^{2/3} of a
/// compact body. Measured: an 81 × 81 × 5-node slab in 4 METIS parts has
/// 2 411 Γ DOFs besides contact (the estimate before: 11 700, and its dense
/// interface 7.7 times the run's peak).
#[test]
fn the_cuts_of_a_flat_box_in_parts_scale_with_its_thickness() {
    let with_parts = |divisions: &str, parts: usize| {
        let sc = scene(
            &format!("{{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [2.0, 2.0, 0.1], divisions = {divisions} }}"),
            3,
        )
        .with_subdomains(parts);
        let kept = [KeptContact {
            points: 0.0,
            master_dofs: 0.0,
        }];
        estimate(
            &sc,
            scene::SolvePath::Condensed,
            1,
            ContactCounts::Built(&kept),
        )
    };
    let slab = with_parts("[80, 80, 4]", 4).interface_dofs;
    assert!((2411.0..=2.0 * 2411.0).contains(&slab), "{slab}");
    // twice as thick: twice the cut
    let thick = with_parts("[80, 80, 8]", 4).interface_dofs;
    assert!((1.6..=2.0).contains(&(thick / slab)), "{thick} / {slab}");
    assert_eq!(with_parts("[80, 80, 4]", 1).interface_dofs, 0.0);
}

/// Sizes below a MiB in KiB (a `--max-memory 1K` was said to be 1 MiB).
#[test]
fn sizes_below_a_mib_are_said_in_kib() {
    assert_eq!(human(1024.0), "1 KiB");
    assert_eq!(human(1500.0), "2 KiB");
    assert_eq!(human(1024.0 * 1024.0), "1 MiB");
    assert_eq!(human(3.5 * 1024.0 * 1024.0 * 1024.0), "3.5 GiB");
}

/// `check` compares the scene's surfaces with these lists without building
/// the mesh: they are the generators' own names, on every shipped example.
#[test]
fn generator_surfaces_are_those_the_generators_name() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut compared = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let sc = signorini_scene::load(&path).unwrap();
        for b in &sc.bodies {
            let Some(mut names) = generator_surfaces(b, sc.dimension as usize) else {
                continue;
            };
            let mesh = crate::model::build_mesh(b, "body", sc.dimension as usize).unwrap();
            let mut built: Vec<&str> = mesh.surfaces.keys().map(String::as_str).collect();
            names.sort();
            built.sort();
            assert_eq!(names, built, "{}: body {}", path.display(), b.name);
            compared += 1;
        }
    }
    assert!(compared >= 10, "{compared} generator bodies compared");
}
