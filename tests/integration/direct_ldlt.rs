//! The direct path's symmetric factorisation: the KKT
//! matrix is factorised by a quasi-definite LDLᵀ with the condensation's
//! ordering rule and refined to the exact solution, so it must give the
//! condensed path's answer, on held and floating bodies, in 2D and 3D, with
//! no LU fallback, and report its factor.

use crate::common;

use common::{converged, example, max_rel};
use signorini_scene::{Method, SolvePath};
use signorini_solver::{RunOptions, RunOutput};

fn on(path: SolvePath) -> RunOptions {
    RunOptions {
        method: Some(Method::Status),
        path: Some(path),
    }
}

/// Runs `text` on both paths; the direct path's displacements and contact
/// force equal the condensed path's to `tol`, and its factorisation is the
/// refined LDLᵀ without LU fallback.
fn direct_equals_condensed(text: &str, tol: f64) -> RunOutput {
    let a = converged(text, on(SolvePath::Condensed));
    let b = converged(text, on(SolvePath::Direct));
    let what = &a.report.title;
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        let r = max_rel(&x.last().displacement, &y.last().displacement);
        assert!(r <= tol, "{what}: displacement differs by {r:e}");
    }
    let (fa, fb) = (&a.report.contact_force, &b.report.contact_force);
    assert!(max_rel(fa, fb) <= tol, "{what}: {fa:?} vs {fb:?}");
    let factorisation = |o: &RunOutput| o.report.factorisation.clone().expect("a factorisation");
    let f = factorisation(&b);
    assert_eq!(f.kind, "ldlt");
    assert_eq!(f.lu_fallbacks, Some(0), "{what}");
    assert_eq!(
        f.factorisations,
        Some(b.report.steps.iter().map(|s| s.iterations).sum())
    );
    assert!(
        f.refinement_steps.unwrap() > 0,
        "{what}: δ is removed by refinement"
    );
    assert!(
        f.factor_nnz > 0 && f.factor_bytes >= 8 * f.factor_nnz && f.flops >= f.factor_nnz as f64
    );
    assert_eq!(f.candidates[0].ordering, f.ordering);
    let c = factorisation(&a);
    assert_eq!(c.kind, "cholesky");
    b
}

#[test]
fn symmetric_direct_path_equals_condensed_in_2d() {
    // Hertz cylinder (held), and two pads held by contact alone (floating:
    // K is singular, regularised by γ and refined).
    let hertz = example("hertz2d.toml");
    direct_equals_condensed(&hertz, 1e-9);
    direct_equals_condensed(&example("blocks.toml"), 1e-9);
}

#[test]
fn symmetric_direct_path_equals_condensed_in_3d() {
    let out = direct_equals_condensed(&example("hertz3d.toml"), 1e-9);
    // A 3D factor above 1e9 flops: nested dissection compared with AMD,
    // and kept (the cheaper).
    let f = out.report.factorisation.unwrap();
    assert_eq!(f.candidates.len(), 2);
    assert_eq!(f.ordering, "nested_dissection");
    assert!(f.candidates[0].flops < f.candidates[1].flops);
    // A box held by contact alone in three rigid modes.
    let floating = direct_equals_condensed(&example("floating3d.toml"), 1e-9);
    assert!(floating
        .report
        .messages
        .iter()
        .any(|m| m.contains("held by contact")));
}
