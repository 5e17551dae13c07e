//! The quarter hemisphere (`sector = "quarter"`) with its symmetry planes
//! held, and the Hertz reference told of the symmetry (`reference.symmetry`,
//! `reference.center`): the same contact as the whole hemisphere of the same
//! mesh, with a quarter of the unknowns; and the entries refused.

use crate::common;

use common::{converged, example};
use signorini_solver::RunOptions;

/// examples/hertz3d_quadratic.toml made coarse (divisions 6) and whole:
/// no sector, no symmetry planes, no symmetry in the reference.
fn whole_coarse() -> String {
    let quarter = quarter_coarse();
    let whole = quarter
        .replace(", sector = \"quarter\"", "")
        .replace("symmetry = \"quarter\"\n", "");
    let cut = whole.find("# symmetry planes of the quarter").unwrap();
    let end = whole[cut..].find("[[contact]]").unwrap() + cut;
    format!("{}{}", &whole[..cut], &whole[end..])
}

fn quarter_coarse() -> String {
    example("hertz3d_quadratic.toml").replace("divisions = 13,", "divisions = 6,")
}

/// The quarter with its planes held gives the whole hemisphere's Hertz
/// quantities (the load ×4 by the reference) to round-off, with a quarter
/// of the contact points (on the planes: shared) and fewer unknowns.
#[test]
fn the_quarter_hemisphere_gives_the_whole_ones_contact() {
    let (whole, quarter) = (whole_coarse(), quarter_coarse());
    assert!(!whole.contains("symmetry_1") && !whole.contains("symmetry = "));
    assert!(quarter.contains("sector = \"quarter\""));
    let w = converged(&whole, RunOptions::default());
    let q = converged(&quarter, RunOptions::default());
    let (rw, rq) = (
        w.report.reference.as_ref().unwrap(),
        q.report.reference.as_ref().unwrap(),
    );
    for name in ["load", "p0", "a", "a_last_node", "profile_l2"] {
        let (a, b) = (rw.quantities[name].computed, rq.quantities[name].computed);
        assert!(
            (a - b).abs() <= 1e-8 * a.abs(),
            "{name}: whole {a}, quarter {b}"
        );
    }
    // the reference's load is 4 × the quarter's resultant
    let fz = q.report.contact_force[2].abs();
    assert!((rq.quantities["load"].computed - 4.0 * fz).abs() <= 1e-12 * 4.0 * fz);
    assert!(4 * q.report.dofs < w.report.dofs + w.report.dofs / 4);
    assert!(rq
        .notes
        .iter()
        .any(|n| n.contains("symmetry = \"quarter\"")));
}

/// A bad sector, a symmetry without its centre or on another reference, a
/// centre of the wrong size: refused, naming the entry.
#[test]
fn the_symmetry_entries_are_refused_where_they_do_not_apply() {
    let base = example("hertz3d_quadratic.toml");
    let cases = [
        (
            base.replace("sector = \"quarter\"", "sector = \"eighth\""),
            vec!["sector: expected \"whole\" or \"quarter\"", "eighth"],
        ),
        (
            base.replace("center = [0.0, 0.0, 0.0]\n", ""),
            vec!["reference.center", "symmetry = \"quarter\" needs"],
        ),
        (
            base.replace("center = [0.0, 0.0, 0.0]", "center = [0.0, 0.0]"),
            vec!["reference.center", "3 finite coordinates"],
        ),
        (
            base.replace("kind = \"hertz_sphere\"", "kind = \"flat_punch\""),
            vec!["reference.symmetry", "hertz_sphere"],
        ),
    ];
    for (text, needles) in cases {
        let e = signorini_scene::parse_toml(&text)
            .err()
            .unwrap_or_else(|| panic!("accepted: {needles:?}"))
            .to_string();
        for n in needles {
            assert!(e.contains(n), "{e} lacks {n}");
        }
    }
    // the whole hemisphere has no symmetry surface
    let whole = base.replace(", sector = \"quarter\"", "");
    let e = match signorini_scene::parse_toml(&whole) {
        Err(e) => e.to_string(),
        Ok(_) => common::try_run(&whole, RunOptions::default())
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default(),
    };
    assert!(e.contains("symmetry_1"), "{e}");
}
