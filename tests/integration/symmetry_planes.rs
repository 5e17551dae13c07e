//! Frictional mortar contact with symmetry planes (rollers) on both bodies:
//! a tangential direction the supports hold at both bodies carries no
//! friction unknown (docs/theory/mortar.md, "Symmetry planes on both
//! bodies"), so that
//! - the non-matching parabolic Hex20 blocks and the flat Hex20 boxes with
//!   rollers on both bodies converge on both paths, in equilibrium;
//! - a quarter of flat boxes with rollers equals the full model's quarter,
//!   point by point;
//! - a slave guided by a roller against a master free along the roller's
//!   direction keeps its friction there.

use crate::common;

use common::{converged_on, max_rel};
use signorini_report::ContactRow;
use signorini_scene::SolvePath;
use signorini_solver::RunOutput;

/// Rollers on x = 0 and y = 0 of `bodies`.
fn rollers(bodies: &[&str]) -> String {
    let mut text = String::new();
    for body in bodies {
        for axis in ["x", "y"] {
            text += &format!(
                "[[boundary]]\nbody = \"{body}\"\nsurface = \"{axis}min\"\ndisplacement = {{ {axis} = 0.0 }}\n"
            );
        }
    }
    text
}

/// A soft pad (E = 10, ν = 0.45, `pad` Hex20 divisions) pressed by 0.05 at
/// its top, held there, onto a clamped steel base (`base` divisions) through
/// a mortar Coulomb 0.3 contact: the boxes span `[x0, x0 + w]` in x and y
/// (the base `base_x` in x), with `extra` boundary entries.
fn boxes(
    x0: f64,
    w: f64,
    base_x: [f64; 2],
    base: [usize; 2],
    pad: [usize; 2],
    extra: &str,
) -> String {
    format!(
        "title = \"flat boxes\"\ndimension = 3\nmodel = \"solid\"\n\
         [[materials]]\nname = \"rubber\"\nyoung = 10.0\npoisson = 0.45\n\
         [[materials]]\nname = \"steel\"\nyoung = 210.0\npoisson = 0.3\n\
         [[bodies]]\nname = \"base\"\nmaterial = \"steel\"\n\
         mesh = {{ generator = \"box\", origin = [{}, {x0}, 0.0], size = [{}, {w}, 0.5], divisions = [{}, {}, 2], element = \"hex20\" }}\n\
         [[bodies]]\nname = \"pad\"\nmaterial = \"rubber\"\n\
         mesh = {{ generator = \"box\", origin = [{x0}, {x0}, 0.5], size = [{w}, {w}, 0.5], divisions = [{}, {}, 2], element = \"hex20\" }}\n\
         [[boundary]]\nbody = \"base\"\nsurface = \"zmin\"\ndisplacement = {{ x = 0.0, y = 0.0, z = 0.0 }}\n\
         [[boundary]]\nbody = \"pad\"\nsurface = \"zmax\"\ndisplacement = {{ x = 0.0, y = 0.0, z = -0.05 }}\n\
         {extra}\
         [[contact]]\nname = \"pad-base\"\nslave = {{ body = \"pad\", surface = \"zmin\" }}\n\
         master = {{ body = \"base\", surface = \"zmax\" }}\ndiscretization = \"mortar\"\n\
         friction = {{ coulomb = 0.3 }}\n",
        base_x[0],
        base_x[1] - base_x[0],
        base[0],
        base[1],
        pad[0],
        pad[1],
    )
}

/// The contact force of a contact.csv row on the slave, as a vector.
fn force(r: &ContactRow) -> [f64; 3] {
    let t = r.tangential_vector();
    [0, 1, 2].map(|k| r.normal_force * r.normal[k] + t[k])
}

/// The sum of every support reaction of the last step, with the largest
/// magnitude of one.
fn reactions(o: &RunOutput) -> ([f64; 3], f64) {
    let step = o.report.steps.last().expect("a step");
    let (mut sum, mut largest) = ([0.0; 3], 0.0f64);
    for r in &step.reactions {
        for (s, f) in sum.iter_mut().zip(&r.force) {
            *s += f;
            largest = largest.max(f.abs());
        }
    }
    (sum, largest)
}

/// Runs a scene on both paths: each converges (certificate ≤ 1e-9), and
/// their contact forces and displacements agree to `tol`.
fn both_paths(text: &str, tol: f64) -> [RunOutput; 2] {
    let c = converged_on(text, SolvePath::Condensed);
    let d = converged_on(text, SolvePath::Direct);
    let fc: Vec<f64> = c.contact_rows.iter().flat_map(force).collect();
    let fd: Vec<f64> = d.contact_rows.iter().flat_map(force).collect();
    assert!(max_rel(&fc, &fd) <= tol, "forces: {:e}", max_rel(&fc, &fd));
    for (x, y) in c.bodies.iter().zip(&d.bodies) {
        let r = max_rel(&x.last().displacement, &y.last().displacement);
        assert!(r <= tol, "body {}: displacements differ by {r:e}", x.name);
    }
    [c, d]
}

#[test]
fn parabolic_hex20_blocks_with_rollers_on_both_bodies_converge_on_both_paths() {
    // Non-matching (3 × 3 under 4 × 4) curved mortar, Coulomb 1, σ_zz = −1
    // on the top: before, both paths stalled (the plane nodes' tangential
    // rows acted on a few shared free master DOFs: rank 29 of 30).
    let interface = "discretization = \"mortar\"\nfriction = { coulomb = 1.0 }";
    let text = common::curved_patch::rollers_on_both("hex20_3", "hex20_4", interface);
    for o in both_paths(&text, 1e-8) {
        // The supports carry the load: their reactions sum to −(0, 0, −1).
        let (sum, largest) = reactions(&o);
        let expected = [0.0, 0.0, 1.0];
        for k in 0..3 {
            assert!((sum[k] - expected[k]).abs() <= 1e-10 * largest, "{sum:?}");
        }
    }
}

#[test]
fn a_quarter_of_flat_hex20_boxes_with_rollers_on_both_equals_the_full_model() {
    let full = boxes(-1.0, 2.0, [-1.0, 1.0], [6, 6], [8, 8], "");
    let quarter = boxes(
        0.0,
        1.0,
        [0.0, 1.0],
        [3, 3],
        [4, 4],
        &rollers(&["base", "pad"]),
    );
    let [f, _] = both_paths(&full, 1e-8);
    for q in both_paths(&quarter, 1e-8) {
        let scale = f
            .contact_rows
            .iter()
            .flat_map(force)
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let mut compared = 0;
        for r in &q.contact_rows {
            let twin = (f.contact_rows.iter())
                .find(|s| (0..3).all(|k| (s.x[k] - r.x[k]).abs() <= 1e-9))
                .expect("the quarter's point is a point of the full model");
            // On a plane the full model's node has both sides: twice the
            // quarter's force across it, none along its normal.
            let on = [r.x[0].abs() <= 1e-9, r.x[1].abs() <= 1e-9];
            let times = on
                .iter()
                .map(|&o| if o { 2.0 } else { 1.0 })
                .product::<f64>();
            let fq = force(r);
            let expected = [0, 1, 2].map(|k| if k < 2 && on[k] { 0.0 } else { times * fq[k] });
            let ff = force(twin);
            for k in 0..3 {
                assert!(
                    (ff[k] - expected[k]).abs() <= 1e-8 * scale,
                    "at {:?}: full {ff:?}, quarter {fq:?} × {times}",
                    r.x
                );
            }
            compared += 1;
        }
        assert_eq!(compared, 25 + 40, "Quad8 nodes of the 4 × 4 quarter");
        assert!(q
            .contact_rows
            .iter()
            .any(|r| r.tangential_vector() != [0.0; 3]));
    }
}

#[test]
fn a_guided_slave_against_a_free_master_keeps_its_friction_along_the_guide() {
    // The pad's roller x = 0 crosses the base, which extends to x = −0.5 and
    // is free along x there: friction along x at the pad's plane nodes is
    // real. On y = 0 both bodies have rollers: no friction along y there.
    let guided = boxes(0.0, 1.0, [-0.5, 1.0], [4, 3], [4, 4], &rollers(&["pad"]))
        + "[[boundary]]\nbody = \"base\"\nsurface = \"ymin\"\ndisplacement = { y = 0.0 }\n";
    for o in both_paths(&guided, 1e-8) {
        let normal: f64 = o.contact_rows.iter().map(|r| r.normal_force).sum();
        let along = |axis: usize| -> f64 {
            (o.contact_rows.iter())
                .filter(|r| r.x[axis].abs() <= 1e-9)
                .map(|r| r.tangential_vector()[axis])
                .sum()
        };
        // Measured 0.0283 of a normal force 1.72.
        assert!(along(0).abs() >= 1e-2 * normal, "{} of {normal}", along(0));
        assert!(along(1).abs() <= 1e-12 * normal, "{} of {normal}", along(1));
    }
}
