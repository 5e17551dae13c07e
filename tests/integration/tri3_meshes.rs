//! Hertz with `element = "tri3"` on the generated disks (docs/theory/validation-cases.md §1-2):
//! the half disk (plane strain) and the quarter disk (axisymmetric) give p0
//! within 2 %, like quad4, and a smooth pressure at the pole. Their quads were
//! cut in two along mirrored diagonals on either side of the pole, which set
//! the pole apart from its neighbours: its force came out 8 % (plane strain)
//! and 10 % (axisymmetric) above what they imply, and p0 as much.

use crate::common;

use common::{converged, example};
use signorini_solver::{RunOptions, RunOutput};

/// Runs a shipped Hertz example with its disk meshed in Tri3.
fn tri3_example(name: &str) -> RunOutput {
    let text = example(name);
    let tri3 = text.replace("grading = 16.0 }", "grading = 16.0, element = \"tri3\" }");
    assert_ne!(text, tri3, "{name}: the mesh entry is not where expected");
    converged(&tri3, RunOptions::default())
}

/// The reference's relative error of p0.
fn p0_error(out: &RunOutput) -> f64 {
    out.report.reference.as_ref().unwrap().quantities["p0"].relative_error
}

/// (pressure at the pole, the pressure there implied by the `k` contact nodes
/// nearest to it): the least-squares fit `p0 + c r²` to those, `r` the distance
/// from the pole's axis `x = 0` (Hertz's profile in both models, whose next
/// term `r⁴ / 8a⁴` is below 1e-4 that close to the pole).
fn pole_and_neighbours(out: &RunOutput, k: usize) -> (f64, f64) {
    let mut rows: Vec<(f64, f64)> = out
        .contact_rows
        .iter()
        .filter(|r| r.normal_force > 0.0)
        .map(|r| (r.x[0].abs(), r.pressure))
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(rows.len() > k, "only {} nodes in contact", rows.len());
    let (r0, pole) = rows[0];
    assert!(r0 <= 1e-12, "the pole is not a node in contact: {r0}");
    // normal equations of p = a + c r² over rows 1..=k
    let (mut s1, mut s2, mut s4, mut sp, mut sp2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(r, p) in &rows[1..=k] {
        let r2 = r * r;
        s1 += 1.0;
        s2 += r2;
        s4 += r2 * r2;
        sp += p;
        sp2 += p * r2;
    }
    let implied = (sp * s4 - sp2 * s2) / (s1 * s4 - s2 * s2);
    (pole, implied)
}

/// Runs the example `name` with Tri3 cells (`what` in the messages): its p0
/// error at most `p0_tol`, the pole pressure within `pole_tol` of the one its
/// 6 nearest neighbours imply.
fn check_tri3_hertz(name: &str, what: &str, p0_tol: f64, pole_tol: f64) {
    let out = tri3_example(name);
    let e = p0_error(&out);
    assert!(e <= p0_tol, "{what}: p0 error {e}");
    let (pole, implied) = pole_and_neighbours(&out, 6);
    assert!(
        (pole / implied - 1.0).abs() <= pole_tol,
        "{what}: pole pressure {pole} vs {implied} from its neighbours"
    );
}

#[test]
fn tri3_half_disk_hertz_p0_within_2_percent_and_smooth_at_the_pole() {
    // p0 measured 0.28 % (quad4 0.22 %); 8.2 % with the quads cut in two.
    // 3 nodes on either side of the pole; measured 0.00 % (8.2 % before)
    check_tri3_hertz("hertz2d.toml", "tri3 half disk", 0.02, 0.01);
}

#[test]
fn tri3_quarter_disk_axisymmetric_hertz_p0_within_2_percent_and_smooth_at_the_pole() {
    // p0 measured 1.5 % (quad4 0.4 %); 10.2 % with the quads cut in two.
    // 6 nodes on one side of the pole; measured +1.7 % (quad4 −1.1 %, 10.2 %
    // before)
    check_tri3_hertz("hertz_axi.toml", "tri3 quarter disk", 0.02, 0.03);
}
