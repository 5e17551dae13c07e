//! The curved contact patch test whose interface two non-matching quadratic
//! meshes represent exactly (tests/integration/quadratic_patch.rs, tests/mpi.rs).

/// The exactly represented curved patch test
/// (tests/data/quadratic_patch/parabolic.geo): the box [0, 1]² × [0, 1] cut
/// along the parabolic cylinder z = 0.5 + x²/4 into a lower block (master,
/// `lower` = "hex20_3" or "tet10_3") and an upper one (slave, `upper`:
/// "hex20_3", "hex20_4", "tet10_3" or "tet10_4"), whose Quad8 or Tri6 faces
/// both interpolate the parabola exactly, matching or not; the hydrostatic
/// state σ = −p I of a material E = 100, ν = 0.3 (p = 1: −p n on x = 1,
/// y = 1 and the top z = 1, rollers on x = 0, y = 0 and the bottom z = 0,
/// the upper block held in z by the contact alone); `interface` is the
/// contact's discretization line.
pub fn parabolic(lower: &str, upper: &str, interface: &str) -> String {
    let mesh = |side: &str, m: &str| {
        format!(
            "{}/tests/data/quadratic_patch/parabolic_{side}_{m}.msh",
            env!("CARGO_MANIFEST_DIR")
        )
    };
    let (lower, upper) = (mesh("lower", lower), mesh("upper", upper));
    let mut text = format!(
        "title = \"parabolic patch test\"\ndimension = 3\nmodel = \"solid\"\n\
         [[materials]]\nname = \"m\"\nyoung = 100.0\npoisson = 0.3\n\
         [[bodies]]\nname = \"lower\"\nmaterial = \"m\"\nmesh = {{ file = \"{lower}\" }}\n\
         [[bodies]]\nname = \"upper\"\nmaterial = \"m\"\nmesh = {{ file = \"{upper}\" }}\n\
         [[boundary]]\nbody = \"lower\"\nsurface = \"bottom\"\ndisplacement = {{ z = 0.0 }}\n\
         [[boundary]]\nbody = \"upper\"\nsurface = \"top\"\ntraction = [0.0, 0.0, -1.0]\n"
    );
    for body in ["lower", "upper"] {
        text += &format!(
            "[[boundary]]\nbody = \"{body}\"\nsurface = \"xmin\"\ndisplacement = {{ x = 0.0 }}\n\
             [[boundary]]\nbody = \"{body}\"\nsurface = \"ymin\"\ndisplacement = {{ y = 0.0 }}\n\
             [[boundary]]\nbody = \"{body}\"\nsurface = \"xmax\"\ntraction = [-1.0, 0.0, 0.0]\n\
             [[boundary]]\nbody = \"{body}\"\nsurface = \"ymax\"\ntraction = [0.0, -1.0, 0.0]\n"
        );
    }
    text + &format!(
        "[[contact]]\nname = \"parabolic\"\nslave = {{ body = \"upper\", surface = \"bottom\" }}\n\
         master = {{ body = \"lower\", surface = \"top\" }}\n{interface}\n"
    )
}

/// The parabolic blocks of [`parabolic`] with the upper block held along x
/// and y by the contact alone (its rollers on x = 0 and y = 0 taken off):
/// under the hydrostatic state (`uniaxial` false) those faces carry the
/// pressure p = 1 instead; under the uniaxial σ_zz = −1 (`uniaxial`) every
/// side is free of traction, the lower block keeping its rollers. The
/// rollers of both blocks on a common plane would leave a curved node's
/// tangential rows with fewer free DOFs of the relative motion than rows,
/// the friction multipliers there undetermined (measured: the semismooth
/// Newton stalls on some of the cases below, and nodes on those planes
/// report a friction force up to 7e-3 of the total normal force).
pub fn held_by_friction(lower: &str, upper: &str, interface: &str, uniaxial: bool) -> String {
    let mut text = parabolic(lower, upper, interface);
    for (axis, load) in [("x", "[1.0, 0.0, 0.0]"), ("y", "[0.0, 1.0, 0.0]")] {
        let roller = format!(
            "[[boundary]]\nbody = \"upper\"\nsurface = \"{axis}min\"\ndisplacement = {{ {axis} = 0.0 }}\n"
        );
        assert!(text.contains(&roller), "{roller}");
        let replacement = if uniaxial {
            String::new()
        } else {
            format!("[[boundary]]\nbody = \"upper\"\nsurface = \"{axis}min\"\ntraction = {load}\n")
        };
        text = text.replace(&roller, &replacement);
        if uniaxial {
            for body in ["lower", "upper"] {
                let side = format!(
                    "[[boundary]]\nbody = \"{body}\"\nsurface = \"{axis}max\"\ntraction = {}\n",
                    load.replace("1.0", "-1.0")
                );
                assert!(text.contains(&side), "{side}");
                text = text.replace(&side, "");
            }
        }
    }
    text
}

/// The parabolic blocks of [`parabolic`] under σ_zz = −1 (the top loaded,
/// the sides x = 1, y = 1 free) with the rollers on x = 0 and y = 0 of both
/// blocks: symmetry planes through the contact, which hold the tangential
/// directions across them at both bodies (no friction unknown there,
/// docs/theory/mortar.md "Symmetry planes on both bodies").
pub fn rollers_on_both(lower: &str, upper: &str, interface: &str) -> String {
    let mut text = parabolic(lower, upper, interface);
    for body in ["lower", "upper"] {
        for (axis, load) in [("x", "[-1.0, 0.0, 0.0]"), ("y", "[0.0, -1.0, 0.0]")] {
            let side = format!(
                "[[boundary]]\nbody = \"{body}\"\nsurface = \"{axis}max\"\ntraction = {load}\n"
            );
            assert!(text.contains(&side), "{side}");
            text = text.replace(&side, "");
        }
    }
    text
}
