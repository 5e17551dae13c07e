//! Bad inputs a hostile sweep found mishandled (problem files, options of
//! the commands, Gmsh files, keys a discretization does not use): each
//! refused (exit 1) with the entry or file and what would be valid, nothing
//! written, by `check` as by `run` when the scene alone shows it.

use super::{block_from_file, TWO_TRIANGLES_MSH};
use crate::common;
use common::bad_scene::{block_with, fresh_dir, run_in, run_scene, scene_dir, BLOCK_ON_PLANE};
use common::BIN;
use std::path::Path;
use std::process::{Command, Output};

/// Runs `signorini ARGS...` in `dir`.
fn signorini_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("cannot start the signorini binary")
}

/// Exit 1, every needle on stderr, nothing on stdout (`local` writes its
/// answer there) and nothing written in `dir` but the `inputs`.
fn assert_refused(dir: &Path, out: &Output, needles: &[&str], inputs: &[&str]) {
    let err = common::stderr_of_exit(out, 1);
    for n in needles {
        assert!(err.contains(n), "stderr does not mention {n:?}\n{err}");
    }
    assert!(err.len() < 600 && !err.contains("panicked"), "{err}");
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let mut written: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !inputs.contains(&n.as_str()))
        .collect();
    written.sort();
    assert!(written.is_empty(), "written: {written:?}");
}

/// `scene` (and `files`) refused by both `check` and `run`, naming `needles`.
fn check_and_run_refuse(test: &str, scene: &str, files: &[(&str, &str)], needles: &[&str]) {
    for command in ["check", "run"] {
        let dir = scene_dir(&format!("{test}_{command}"), scene, files);
        run_in(dir, command, &[]).assert_bad_input(needles);
    }
}

/// The NumPy problem of tests/data (stored members W, q, mu, dim).
fn numpy_problem() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/local_int_dim.npz"))
        .unwrap()
}

/// The offset of the first value of the first array (W) of a stored .npz.
fn first_array_data(npz: &[u8]) -> usize {
    let magic = npz.windows(6).position(|w| w == b"\x93NUMPY").unwrap();
    let header_len = u16::from_le_bytes([npz[magic + 8], npz[magic + 9]]) as usize;
    magic + 10 + header_len
}

/// A flipped bit in W's numbers left a valid-looking array that was solved
/// with exit 0: every member's CRC-32 is checked against the archive's.
#[test]
fn a_flipped_byte_inside_a_npz_array_is_refused_by_its_crc() {
    let mut npz = numpy_problem();
    let at = first_array_data(&npz) + 6;
    npz[at] ^= 0x10;
    let dir = fresh_dir("npz_flipped_byte");
    std::fs::write(dir.join("flipped.npz"), &npz).unwrap();
    let out = signorini_in(&dir, &["local", "flipped.npz"]);
    assert_refused(
        &dir,
        &out,
        &["flipped.npz: W.npy is damaged", "CRC-32"],
        &["flipped.npz"],
    );
}

/// The CRC-32 of `bytes` (zip's polynomial), to damage a member and record
/// the damage in the archive as a writer would.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// A member that is not a NumPy array (its magic changed, its CRC-32
/// recorded anew in the local and central headers) is refused naming the
/// file and the member (it named the member alone).
#[test]
fn a_damaged_npz_member_names_the_file() {
    let mut npz = numpy_problem();
    let magic = npz.windows(6).position(|w| w == b"\x93NUMPY").unwrap();
    npz[magic + 1] = b'X';
    // W.npy is the first member (stored, its sizes in a zip64 field): its
    // data ends where the next member's local header starts.
    let end = magic
        + npz[magic..]
            .windows(4)
            .position(|w| w == b"PK\x03\x04")
            .unwrap();
    let crc = crc32(&npz[magic..end]).to_le_bytes();
    npz[14..18].copy_from_slice(&crc);
    let central = npz.windows(4).position(|w| w == b"PK\x01\x02").unwrap();
    npz[central + 16..central + 20].copy_from_slice(&crc);
    let dir = fresh_dir("npz_damaged_member");
    std::fs::write(dir.join("damaged.npz"), &npz).unwrap();
    let out = signorini_in(&dir, &["local", "damaged.npz"]);
    assert_refused(&dir, &out, &["damaged.npz: W.npy"], &["damaged.npz"]);
}

/// `local` reads problem files: a scene named it "expected value at line 1
/// column 1"; the refusal says which formats `local` reads.
#[test]
fn local_on_a_scene_says_which_formats_it_reads() {
    let dir = fresh_dir("local_on_a_scene");
    std::fs::write(dir.join("scene.toml"), BLOCK_ON_PLANE).unwrap();
    std::fs::write(dir.join("scene.txt"), BLOCK_ON_PLANE).unwrap();
    let inputs = ["scene.toml", "scene.txt"];
    let out = signorini_in(&dir, &["local", "scene.toml"]);
    let needles = [
        "scene.toml",
        "signorini run",
        "JSON, NumPy .npz or FCLib .hdf5/.h5",
    ];
    assert_refused(&dir, &out, &needles, &inputs);
    let out = signorini_in(&dir, &["local", "scene.txt"]);
    let needles = [
        "scene.txt: not a JSON problem",
        "JSON, NumPy .npz or FCLib .hdf5/.h5",
    ];
    assert_refused(&dir, &out, &needles, &inputs);
}

/// `local --max-iterations 0` ran (a solve of no iteration): at least 1.
#[test]
fn local_refuses_zero_iterations() {
    let dir = fresh_dir("local_zero_iterations");
    std::fs::write(dir.join("p.npz"), numpy_problem()).unwrap();
    let out = signorini_in(&dir, &["local", "--max-iterations", "0", "p.npz"]);
    assert_refused(
        &dir,
        &out,
        &["--max-iterations", "must be at least 1, got 0"],
        &["p.npz"],
    );
}

/// `--max-memory -5G` as a separate argument was read as an unknown option
/// `-5`: the refusal names --max-memory and the valid form, for every
/// command that takes it.
#[test]
fn a_negative_max_memory_names_the_option() {
    let dir = fresh_dir("max_memory_negative");
    std::fs::write(dir.join("scene.toml"), BLOCK_ON_PLANE).unwrap();
    std::fs::write(dir.join("p.npz"), numpy_problem()).unwrap();
    for args in [
        ["run", "scene.toml", "--max-memory", "-5G"],
        ["check", "scene.toml", "--max-memory", "-5G"],
        ["local", "p.npz", "--max-memory", "-5G"],
    ] {
        let out = signorini_in(&dir, &args);
        let needles = ["--max-memory", "-5G", "expected a positive size"];
        assert_refused(&dir, &out, &needles, &["scene.toml", "p.npz"]);
    }
}

/// A Gmsh file with physical names and no element: the refusal spoke of
/// physical groups; it says the file has no elements.
#[test]
fn a_gmsh_file_without_elements_says_so() {
    let empty = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n2 2 \"block\"\n$EndPhysicalNames\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 1 1 0\n$EndNodes\n$Elements\n0\n$EndElements\n";
    let needles = [
        "bodies[0].mesh",
        "empty.msh",
        "the file has no elements",
        "gmsh -2",
    ];
    let scene = block_from_file("empty.msh");
    check_and_run_refuse(
        "gmsh_no_elements",
        &scene,
        &[("empty.msh", empty)],
        &needles,
    );
    let dir = scene_dir("gmsh_no_elements_words", &scene, &[("empty.msh", empty)]);
    let err = run_in(dir, "run", &[]).stderr();
    assert!(!err.contains("physical"), "{err}");
}

/// Two `$PhysicalNames` entries of one dimension and tag replaced one
/// another, and two groups of one name and dimension merged into one
/// surface: both refused, naming the tags.
#[test]
fn gmsh_physical_names_that_clash_are_refused() {
    let twice = TWO_TRIANGLES_MSH.replace(
        "$PhysicalNames\n2\n1 1 \"bottom\"\n",
        "$PhysicalNames\n3\n1 1 \"bottom\"\n1 1 \"base\"\n",
    );
    let one_name = TWO_TRIANGLES_MSH
        .replace(
            "$PhysicalNames\n2\n1 1 \"bottom\"\n",
            "$PhysicalNames\n3\n1 1 \"bottom\"\n1 3 \"bottom\"\n",
        )
        .replace("$Elements\n3\n", "$Elements\n4\n")
        .replace("$EndElements", "4 1 2 3 3 2 3\n$EndElements");
    assert!(twice.contains("\"base\"") && one_name.contains("4 1 2 3 3 2 3"));
    let scene = block_from_file("part.msh");
    check_and_run_refuse(
        "gmsh_tag_named_twice",
        &scene,
        &[("part.msh", &twice)],
        &[
            "bodies[0].mesh",
            "part.msh",
            "dimension 1 and tag 1 twice",
            "\"bottom\" and \"base\"",
        ],
    );
    check_and_run_refuse(
        "gmsh_one_name_two_groups",
        &scene,
        &[("part.msh", &one_name)],
        &[
            "bodies[0].mesh",
            "two physical groups of dimension 1 \"bottom\" (tags 1 and 3)",
        ],
    );
}

/// `normal = "slave"` on a mortar contact was silently ignored (mortar
/// uses the slave's averaged normal whatever the key says); and
/// `solver.friction` with contact elements, solved by the return mapping.
#[test]
fn keys_a_discretization_does_not_use_are_refused() {
    let mortar = common::example("mortar_patch.toml").replacen(
        "discretization = \"mortar\"\n",
        "discretization = \"mortar\"\nnormal = \"slave\"\n",
        1,
    );
    assert!(mortar.contains("normal = \"slave\""));
    check_and_run_refuse(
        "mortar_normal_slave",
        &mortar,
        &[],
        &[
            "contact \"pad-base\".normal",
            "\"slave\" is not used by mortar",
            "leave the key out",
        ],
    );
    let elements = format!(
        "{}\n[solver]\nfriction = \"newton\"\n",
        common::example("contact_elements.toml")
    );
    check_and_run_refuse(
        "contact_elements_friction_method",
        &elements,
        &[],
        &[
            "solver.friction = \"newton\"",
            "return mapping",
            "remove the key",
        ],
    );
}

/// `roughness = 1e300` was accepted while `law.penalty = 1e300` was refused:
/// the same range of representable stiffnesses.
#[test]
fn a_roughness_out_of_double_precision_is_refused_like_a_penalty() {
    let scene = block_with(
        "discretization = \"node_to_segment\"\n",
        "discretization = \"node_to_segment\"\nfriction = { coulomb = 0.3, slip_stiffness = 1.0, roughness = 1e300 }\n",
    );
    check_and_run_refuse(
        "roughness_1e300",
        &scene,
        &[],
        &[
            "contact \"block-ground\".friction.roughness",
            "1e300 is outside [1e-100, 1e100]",
            "other units",
        ],
    );
}

/// Contact elements of `penalty = 1e100` ended in "the Newton matrix ... is
/// singular", naming no key: refused before the solve, naming
/// `law.penalty` and the largest penalty that solves, which does
/// (examples/contact_elements.toml, E = 210 000, h = 0.25).
#[test]
fn contact_elements_too_stiff_for_double_precision_name_the_penalty() {
    let scene =
        common::example("contact_elements.toml").replace("penalty = 10000.0", "penalty = 1e100");
    assert!(scene.contains("penalty = 1e100"));
    let run = run_scene("contact_elements_1e100", Some(&scene), &[]);
    run.assert_bad_input(&[
        "contact \"joint\".law.penalty: 1e100",
        "give law.penalty <= ",
    ]);
    let err = run.stderr();
    let at = err.find("give law.penalty <= ").unwrap() + "give law.penalty <= ".len();
    let largest: f64 = err[at..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(largest > 1e9 && largest < 1e15, "{largest:e}");
    let at_limit = common::example("contact_elements.toml").replace(
        "penalty = 10000.0",
        &format!("penalty = {:e}", 0.99 * largest),
    );
    let run = run_scene("contact_elements_at_the_limit", Some(&at_limit), &[]);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.describe());
}
