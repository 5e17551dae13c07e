//! No input crashes, hangs or allocates without a check, and every message
//! names the key: a sweep of malformed and oversized scenes.

use super::{BOX_ON_PLANE, TWO_TRIANGLES_MSH};
use crate::common::bad_scene::{
    block_meshed, block_with, block_with_all, fresh_dir, BLOCK_MESH, BLOCK_ON_PLANE,
};
use crate::common::{run_limited, BIN};
use std::path::Path;
use std::process::{Command, Output};
use std::time::Duration;

fn box_meshed(mesh: &str) -> String {
    let from = "mesh = { generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = [2, 2, 1] }";
    assert!(BOX_ON_PLANE.contains(from));
    BOX_ON_PLANE.replacen(from, &format!("mesh = {mesh}"), 1)
}

/// One entry of the sweep: a scene (and files beside it), extra arguments,
/// and what its one-line error must contain.
struct Bad {
    name: &'static str,
    scene: String,
    needles: Vec<&'static str>,
    args: Vec<&'static str>,
    files: Vec<(&'static str, Vec<u8>)>,
}

fn bad(name: &'static str, scene: String, needles: &[&'static str]) -> Bad {
    Bad {
        name,
        scene,
        needles: needles.to_vec(),
        args: Vec::new(),
        files: Vec::new(),
    }
}

impl Bad {
    fn args(mut self, args: &[&'static str]) -> Bad {
        self.args = args.to_vec();
        self
    }

    fn file(mut self, name: &'static str, bytes: Vec<u8>) -> Bad {
        self.files.push((name, bytes));
        self
    }
}

/// What is wrong with the answer to a bad scene, if anything: exit 1 within
/// a few seconds, a few lines on stderr naming the entry (every needle), no
/// panic or backtrace, nothing written.
fn judge(dir: &Path, output: &Output, elapsed: Duration, needles: &[&str]) -> Option<String> {
    let err = String::from_utf8_lossy(&output.stderr);
    let mut wrong = Vec::new();
    if output.status.code() != Some(1) {
        wrong.push(format!(
            "exit status {:?}, expected 1",
            output.status.code()
        ));
    }
    if elapsed > Duration::from_secs(10) {
        wrong.push(format!("took {elapsed:?}"));
    }
    let lines = err.lines().count();
    if err.trim().is_empty() || lines > 6 || err.len() > 800 {
        wrong.push(format!("{lines} lines, {} characters on stderr", err.len()));
    }
    for word in [
        "panicked",
        "backtrace",
        "internal error",
        "memory allocation",
    ] {
        if err.contains(word) {
            wrong.push(format!("stderr mentions {word:?}"));
        }
    }
    for n in needles {
        if !err.contains(n) {
            wrong.push(format!("stderr does not mention {n:?}"));
        }
    }
    if dir.join("out").exists() {
        wrong.push("the output directory was created".into());
    }
    (!wrong.is_empty()).then(|| {
        format!(
            "{}\n--- stderr ---\n{}",
            wrong.join("; "),
            err.chars().take(1500).collect::<String>()
        )
    })
}

/// Three quads with a hanging node at (1, 0.5): the left quad's edge
/// (1, 0)–(1, 1) meets the two right quads' half edges, no whole edge.
const HANGING_NODE_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n2 2 \"block\"\n$EndPhysicalNames\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n6 2 0.5 0\n7 1 0.5 0\n8 2 1 0\n$EndNodes\n$Elements\n5\n1 1 2 1 1 1 2\n2 1 2 1 1 2 5\n3 3 2 2 1 1 2 3 4\n4 3 2 2 1 2 5 6 7\n5 3 2 2 1 7 6 8 3\n$EndElements\n";

fn sweep() -> Vec<Bad> {
    let half = |rest: &str| {
        block_meshed(&format!(
            "{{ generator = \"half_disk\", center = [0.0, 1.0], radius = 1.0, {rest} }}"
        ))
    };
    let quarter = |rest: &str| {
        block_with_all(&[
            ("model = \"plane_strain\"", "model = \"axisymmetric\""),
            (
                BLOCK_MESH,
                &format!(
                    "mesh = {{ generator = \"quarter_disk\", center = [0.0, 1.0], radius = 1.0, {rest} }}"
                ),
            ),
        ])
    };
    let hemisphere = |rest: &str| {
        box_meshed(&format!(
            "{{ generator = \"hemisphere\", center = [0.0, 0.0, 1.0], radius = 1.0, {rest} }}"
        ))
    };
    let boxed = |divisions: &str| {
        box_meshed(&format!(
            "{{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 1.0, 0.5], divisions = {divisions} }}"
        ))
    };
    let gmsh = || block_with(BLOCK_MESH, "mesh = { file = \"part.msh\" }");
    let msh = TWO_TRIANGLES_MSH.as_bytes();
    let many_steps = format!(
        "steps = [{}]\n{BLOCK_ON_PLANE}",
        vec!["{ scale = { press = 1.0 } }"; 20_000].join(", ")
    );
    let contact = "[[contact]]\nname = \"block-ground\"";
    let mut garbage = Vec::new();
    let mut x: u32 = 12345;
    for _ in 0..4000 {
        x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
        garbage.push((x >> 16) as u8);
    }
    vec![
        // divisions: negative, fractional, zero, not a number, huge, for every generator
        bad("rectangle_divisions_negative", block_with("divisions = [4, 2]", "divisions = [-8, 4]"), &["mesh.divisions", "positive whole numbers", "got -8", "line 13"]),
        bad("rectangle_divisions_fractional", block_with("divisions = [4, 2]", "divisions = [8.5, 4]"), &["mesh.divisions", "got 8.5"]),
        bad("rectangle_divisions_zero", block_with("divisions = [4, 2]", "divisions = [0, 4]"), &["bodies[0].mesh.divisions", ">= 1"]),
        bad("rectangle_divisions_text", block_with("divisions = [4, 2]", "divisions = \"many\""), &["mesh.divisions", "\"many\""]),
        bad("rectangle_100000_squared", block_with("divisions = [4, 2]", "divisions = [100000, 100000]"), &["memory", "GiB", "bodies[0].mesh.divisions", "coarser"]),
        bad("rectangle_1e9_by_4", block_with("divisions = [4, 2]", "divisions = [1000000000, 4]"), &["memory", "bodies[0].mesh.divisions"]),
        bad("rectangle_3000_squared_on_24_gib", block_with("divisions = [4, 2]", "divisions = [3000, 3000]"), &["memory", "GiB", "--max-memory is 24 GiB"]).args(&["--max-memory", "24G"]),
        bad("half_disk_divisions_1e9", half("divisions = 1e9"), &["memory", "bodies[0].mesh.divisions"]),
        bad("half_disk_divisions_negative", half("divisions = -3"), &["mesh.divisions", "got -3", "elements along the arc"]),
        bad("half_disk_divisions_fractional", half("divisions = 2.5"), &["mesh.divisions", "got 2.5"]),
        bad("half_disk_divisions_array", half("divisions = [8]"), &["mesh.divisions", "an array"]),
        bad("half_disk_divisions_3", half("divisions = 3"), &["bodies[0].mesh.divisions", ">= 4"]),
        bad("quarter_disk_divisions_1e9", quarter("divisions = 1000000000"), &["memory", "bodies[0].mesh.divisions"]),
        bad("quarter_disk_divisions_negative", quarter("divisions = -1"), &["mesh.divisions", "got -1"]),
        bad("box_2000_cubed", boxed("[2000, 2000, 2000]"), &["memory", "bodies[0].mesh.divisions"]),
        bad("box_divisions_negative", boxed("[4, -1, 2]"), &["mesh.divisions", "got -1"]),
        bad("box_divisions_fractional", boxed("[4, 1.5, 2]"), &["mesh.divisions", "got 1.5"]),
        bad("hemisphere_divisions_1e6", hemisphere("divisions = 1000000"), &["memory", "bodies[0].mesh.divisions"]),
        bad("hemisphere_divisions_fractional", hemisphere("divisions = 0.5"), &["mesh.divisions", "got 0.5", "quarter meridian"]),
        // sizes and radii
        bad("rectangle_size_zero", block_with("size = [1.0, 0.5]", "size = [1.0, 0.0]"), &["bodies[0].mesh.size", "> 0"]),
        bad("rectangle_size_negative", block_with("size = [1.0, 0.5]", "size = [-1.0, 0.5]"), &["bodies[0].mesh.size"]),
        bad("rectangle_size_text", block_with("size = [1.0, 0.5]", "size = [1.0, \"big\"]"), &["mesh.size", "\"big\""]),
        bad("half_disk_radius_zero", half("divisions = 8").replace("radius = 1.0", "radius = 0.0"), &["bodies[0].mesh.radius", "> 0"]),
        bad("half_disk_radius_negative", half("divisions = 8").replace("radius = 1.0", "radius = -1.0"), &["bodies[0].mesh.radius"]),
        bad("box_size_zero", box_meshed("{ generator = \"box\", origin = [0.0, 0.0, 0.0], size = [1.0, 0.0, 0.5], divisions = [2, 2, 1] }"), &["bodies[0].mesh.size"]),
        bad("hemisphere_radius_negative", hemisphere("divisions = 4").replace("radius = 1.0", "radius = -2.0"), &["bodies[0].mesh.radius"]),
        bad("rigid_circle_radius_zero", block_with("rigid = { shape = \"plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }", "rigid = { shape = \"circle\", center = [0.0, -1.0], radius = 0.0 }"), &["bodies[1].rigid.radius"]),
        // NaN and infinities in every kind of float key
        bad("nan_in_size", block_with("size = [1.0, 0.5]", "size = [nan, 0.5]"), &["bodies[0].mesh.size", "NaN"]),
        bad("inf_in_origin", block_with("origin = [0.0, 0.0]", "origin = [inf, 0.0]"), &["bodies[0].mesh.origin", "inf"]),
        bad("nan_in_grading_ratio", block_with("divisions = [4, 2]", "divisions = [4, 2], grading = { towards = \"top\", ratio = nan }"), &["bodies[0].mesh.grading.ratio", "NaN"]),
        bad("inf_in_half_disk_grading", half("divisions = 8, grading = inf"), &["bodies[0].mesh.grading", "inf"]),
        bad("nan_in_half_disk_center", half("divisions = 8").replace("center = [0.0, 1.0]", "center = [0.0, nan]"), &["bodies[0].mesh.center", "NaN"]),
        bad("nan_in_pole", half("divisions = 8, pole = [nan, -1.0]"), &["bodies[0].mesh.pole", "NaN"]),
        bad("nan_in_young", block_with("young = 1.0", "young = nan"), &["materials[0].young", "NaN"]),
        bad("inf_in_young", block_with("young = 1.0", "young = inf"), &["materials[0].young", "inf"]),
        bad("nan_in_poisson", block_with("poisson = 0.3", "poisson = nan"), &["materials[0].poisson", "NaN"]),
        bad("nan_in_rigid_point", block_with("point = [0.0, 0.0]", "point = [nan, 0.0]"), &["bodies[1].rigid.point", "NaN"]),
        bad("inf_in_rigid_normal", block_with("normal = [0.0, 1.0]", "normal = [0.0, -inf]"), &["bodies[1].rigid.normal", "inf"]),
        bad("nan_in_boundary_point", block_with("point = [0.0, 0.5]", "point = [nan, 0.5]"), &["boundary[0].point", "NaN"]),
        bad("nan_in_displacement", block_with("displacement = { x = 0.0 }", "displacement = { x = nan }"), &["boundary[0].displacement.x", "NaN"]),
        bad("inf_in_traction", block_with("traction = [0.0, -1.0]", "traction = [0.0, -inf]"), &["boundary[1].traction", "inf"]),
        bad("nan_in_gap", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\ngap = nan"), &["contact \"block-ground\".gap", "NaN"]),
        bad("nan_in_coulomb", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\nfriction = { coulomb = nan }"), &["contact \"block-ground\".friction.coulomb", "NaN"]),
        bad("penalty_law_1e-300", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\nlaw = { penalty = 1e-300 }"), &["contact \"block-ground\".law.penalty", "outside", "other units"]),
        bad("inf_in_penalty_law", block_with("discretization = \"node_to_segment\"", "discretization = \"node_to_segment\"\nlaw = { penalty = inf }"), &["contact \"block-ground\".law.penalty", "inf"]),
        bad("nan_in_step_scale", format!("{BLOCK_ON_PLANE}\n[[steps]]\nscale = {{ press = nan }}\n"), &["steps[0].scale.press", "NaN"]),
        bad("nan_in_tolerance", format!("{BLOCK_ON_PLANE}\n[solver]\ntolerance = nan\n"), &["solver.tolerance", "NaN"]),
        bad("inf_in_solver_penalty", format!("{BLOCK_ON_PLANE}\n[solver]\npenalty = inf\n"), &["solver.penalty", "inf"]),
        bad("nan_in_reference_radius", format!("{BLOCK_ON_PLANE}\n[reference]\nkind = \"hertz_cylinder\"\nradius = nan\n"), &["reference.radius", "NaN"]),
        bad("nan_in_probe", format!("{BLOCK_ON_PLANE}\n[output]\nprobes = [[nan, 0.0]]\n"), &["output.probes[0]", "NaN"]),
        // materials
        bad("young_zero", block_with("young = 1.0", "young = 0.0"), &["materials[0].young", "> 0"]),
        bad("young_negative", block_with("young = 1.0", "young = -2.0"), &["materials[0].young"]),
        bad("poisson_one_half", block_with("poisson = 0.3", "poisson = 0.5"), &["materials[0].poisson", "0.5"]),
        bad("poisson_above_one_half", block_with("poisson = 0.3", "poisson = 0.7"), &["materials[0].poisson"]),
        bad("poisson_minus_one", block_with("poisson = 0.3", "poisson = -1.0"), &["materials[0].poisson", "-1"]),
        // whole numbers elsewhere
        bad("dimension_negative", block_with("dimension = 2", "dimension = -2"), &["dimension: expected 2 or 3, got -2"]),
        bad("dimension_four", block_with("dimension = 2", "dimension = 4"), &["dimension", "2 or 3"]),
        bad("max_iterations_negative", format!("{BLOCK_ON_PLANE}\n[solver]\nmax_iterations = -3\n"), &["solver.max_iterations", "got -3"]),
        bad("subdomains_negative", block_with("name = \"block\"\nmaterial", "name = \"block\"\nsubdomains = -2\nmaterial"), &["subdomains", "-2"]),
        bad("subdomains_more_than_cells", block_with("name = \"block\"\nmaterial", "name = \"block\"\nsubdomains = 1000000000\nmaterial"), &["bodies[0].subdomains", "8 cells", "give at most 8, or \"auto\""]),
        // structure: unknown keys, missing bodies, wrong references
        bad("unknown_top_level_key", format!("frobnicate = 1\n{BLOCK_ON_PLANE}"), &["frobnicate", "line 1"]),
        bad("unknown_generator_key", block_with("divisions = [4, 2]", "divisions = [4, 2], radus = 1.0"), &["radus"]),
        bad("unknown_generator", block_with("\"rectangle\"", "\"disk\""), &["disk", "half_disk"]),
        bad("no_bodies", "dimension = 2\n[[materials]]\nname = \"steel\"\nyoung = 1.0\npoisson = 0.3\n".into(), &["bodies", "no deformable body"]),
        bad("contact_to_missing_surface", block_with("surface = \"bottom\"", "surface = \"underside\""), &["underside", "block-ground", "bottom"]),
        bad("contact_to_missing_body", block_with("master = { body = \"ground\" }", "master = { body = \"nowhere\" }"), &["contact \"block-ground\".master.body", "nowhere"]),
        bad("boundary_on_missing_body", block_with("name = \"press\"\nbody = \"block\"", "name = \"press\"\nbody = \"blok\""), &["boundary[1].body", "blok"]),
        bad("unknown_body_among_thousands", format!("{}{}", block_with("master = { body = \"ground\" }", "master = { body = \"nowhere\" }"), (0..5000).map(|i| format!("\n[[bodies]]\nname = \"g{i}\"\nrigid = {{ shape = \"plane\", point = [0.0, -{i}.0], normal = [0.0, 1.0] }}\n")).collect::<String>()), &["contact \"block-ground\".master.body", "nowhere", "and 4990 more"]),
        bad("duplicate_contact_name", format!("{BLOCK_ON_PLANE}\n{contact}\nslave = {{ body = \"block\", surface = \"bottom\" }}\nmaster = {{ body = \"ground\" }}\n"), &["block-ground", "unique"]),
        // steps
        bad("step_scale_not_a_number", format!("{BLOCK_ON_PLANE}\n[[steps]]\nscale = {{ press = \"half\" }}\n"), &["scale = { press = \"half\" }", "f64"]),
        bad("too_many_steps", many_steps, &["steps", "20000 load steps, at most 10000", "a row of steps.csv"]),
        // Gmsh files: missing, garbage, truncated, lying about its size
        bad("gmsh_missing", block_with(BLOCK_MESH, "mesh = { file = \"nowhere.msh\" }"), &["bodies[0].mesh", "nowhere.msh"]),
        bad("gmsh_garbage", gmsh(), &["bodies[0].mesh", "part.msh"]).file("part.msh", garbage),
        bad("gmsh_truncated", gmsh(), &["bodies[0].mesh", "part.msh"]).file("part.msh", msh[..msh.len() / 2].to_vec()),
        bad("gmsh_huge_node_count", gmsh(), &["bodies[0].mesh", "part.msh", "announces 99999999999999 nodes"]).file("part.msh", TWO_TRIANGLES_MSH.replace("$Nodes\n4\n", "$Nodes\n99999999999999\n").into_bytes()),
        bad("gmsh_empty", gmsh(), &["bodies[0].mesh", "part.msh"]).file("part.msh", Vec::new()),
        bad("gmsh_nan_coordinate", gmsh(), &["bodies[0].mesh", "part.msh", "node 3", "not a finite number"]).file("part.msh", TWO_TRIANGLES_MSH.replace("3 1 1 0\n", "3 nan 1 0\n").into_bytes()),
        // a hanging node: the left quad's right edge against two half edges
        bad("gmsh_hanging_node", gmsh(), &["bodies[0].mesh", "part.msh", "non-conforming", "share the node at [1.0, 0.0, 0.0]"]).file("part.msh", HANGING_NODE_MSH.as_bytes().to_vec()),
        // a modulus whose stiffness overflows or underflows double precision
        bad("young_1e308", block_with("young = 1.0", "young = 1e308"), &["materials[0].young", "outside", "other units"]),
        bad("young_1e-310", block_with("young = 1.0", "young = 1e-310"), &["materials[0].young", "outside"]),
        // extreme numbers are shown as written (1e-300), not as hundreds of
        // digits; a 3D point has its z (found by a third robustness sweep)
        bad("grading_1e-300", half("divisions = 8, grading = 1e-300"), &["bodies[0].mesh.grading", "got 1e-300"]),
        bad("tolerance_1e300", format!("{BLOCK_ON_PLANE}\n[solver]\ntolerance = 1e300\n"), &["solver.tolerance", "got 1e300"]),
        bad("pin_at_1e300", block_with("point = [0.0, 0.5]", "point = [1e300, 0.5]"), &["boundary[0].point", "no node at (1e300, 0.5)"]),
        bad("pin_above_a_3d_box", BOX_ON_PLANE.replacen("surface = \"xmin\"", "point = [0.0, 0.0, 0.7]", 1), &["boundary[0].point", "no node at (0, 0, 0.7)", "nearest is (0, 0, 0.5)"]),
        // inputs that ended in an internal error (exit 3): a grading whose
        // smallest cells are NaN, μ·λ_n overflowing the 3D thresholds, a plane
        // normal whose length underflows (found by a third robustness sweep)
        bad("hemisphere_grading_1e100", hemisphere("divisions = 4, grading = 1e100"), &["bodies[0].mesh.grading", "between 1 and 1e12", "got 1e100"]),
        bad("coulomb_1e200_in_3d", BOX_ON_PLANE.replacen("master = { body = \"ground\" }", "master = { body = \"ground\" }\nfriction = { coulomb = 1e200 }", 1), &["contact \"box-ground\".friction", "<= 1e100", "got 1e200"]),
        bad("plane_normal_1e-300", BOX_ON_PLANE.replacen("normal = [0.0, 0.0, 1.0]", "normal = [1e-300, 1e-300, 1e-300]", 1), &["bodies[1].rigid.normal", "normalised"]),
        // a line of 200 000 characters: the message quotes a window of it
        bad("very_long_line", format!("x = [{}]\n{BLOCK_ON_PLANE}", vec!["1"; 40_000].join(", ")), &["unknown field `x`", "line 1"]),
    ]
}

#[test]
fn sweep_of_malformed_and_oversized_scenes_exits_1_naming_the_entry() {
    let cases = sweep();
    assert!(cases.len() >= 30);
    let mut failures = Vec::new();
    for case in &cases {
        let dir = fresh_dir(&format!("sweep/{}", case.name));
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, &case.scene).unwrap();
        for (name, bytes) in &case.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let mut cmd = Command::new(BIN);
        cmd.arg("run")
            .arg(&scene)
            .arg("--out")
            .arg(dir.join("out"))
            .args(&case.args)
            .current_dir(&dir);
        let (output, elapsed) = run_limited(cmd, Duration::from_secs(60));
        if let Some(why) = judge(&dir, &output, elapsed, &case.needles) {
            failures.push(format!("== {}: {why}", case.name));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} bad scenes were not refused as they should:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
