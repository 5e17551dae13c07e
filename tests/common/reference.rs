//! The scene's reference solution as the tests read it: the relative error
//! of one quantity, and the uniform-pressure patch test.

use signorini_solver::RunOutput;

/// The relative error of the reference quantity `q` of a run that has a
/// reference.
pub fn reference_error(out: &RunOutput, q: &str) -> f64 {
    out.report
        .reference
        .as_ref()
        .expect("a reference")
        .quantities[q]
        .relative_error
}

/// The uniform-pressure patch test of a run passed: every nodal pressure
/// within `tolerance` (relative) of the applied one, the resultant to
/// round-off; `what` names the case in a failure.
pub fn assert_patch_test_passes(out: &RunOutput, tolerance: f64, what: &str) {
    let pressure = reference_error(out, "pressure");
    assert!(pressure <= tolerance, "{what}: {pressure}");
    assert!(reference_error(out, "resultant") <= 1e-12, "{what}");
}

/// Each reference quantity of `bounds` within its relative error bound;
/// `what` names the case in a failure.
pub fn assert_reference_within(out: &RunOutput, bounds: &[(&str, f64)], what: &str) {
    for &(q, bound) in bounds {
        let error = reference_error(out, q);
        assert!(error <= bound, "{what}: {q} error {error}");
    }
}
