//! Units (docs/theory/validation-cases.md §8): the same scene in Pa and m and in MPa
//! and mm gives the same answer after conversion (forces per unit thickness
//! ×1000 from N/mm to N/m in plane strain, displacements ×1/1000), to 1e-10,
//! because every tolerance of the solver is relative to the problem's own
//! force and length scales.

use crate::common;

use common::{converged, example, forces, hertz_in_units as hertz, max_rel, patch3d_in_pa_and_m};
use signorini_scene::SolvePath;
use signorini_solver::RunOptions;

#[test]
fn hertz_in_pa_and_m_equals_hertz_in_mpa_and_mm() {
    for path in [SolvePath::Condensed, SolvePath::Direct] {
        let opts = RunOptions {
            path: Some(path),
            ..Default::default()
        };
        let si = converged(&hertz("210e9", 0.01), opts.clone());
        let mm = converged(&hertz("210e3", 10.0), opts);
        // N/m against N/mm per unit thickness
        let f_mm: Vec<f64> = forces(&mm).iter().map(|f| 1000.0 * f).collect();
        let r = max_rel(&forces(&si), &f_mm);
        assert!(r <= 1e-10, "{path:?}: forces differ by {r:e}");
        let u_mm: Vec<f64> = mm.bodies[0]
            .last()
            .displacement
            .iter()
            .map(|u| u / 1000.0)
            .collect();
        let r = max_rel(&si.bodies[0].last().displacement, &u_mm);
        assert!(r <= 1e-10, "{path:?}: displacements differ by {r:e}");
        assert_eq!(
            si.report.steps[0].active, mm.report.steps[0].active,
            "{path:?}: the same active set"
        );
    }
}

#[test]
fn box_patch_in_pa_and_m_equals_mpa_and_mm_in_3d() {
    // patch3d.toml is in consistent units of its own: read it as MPa and mm,
    // then as Pa and m (E × 1e6, lengths × 1e-3, traction × 1e6)
    let mm = example("patch3d.toml");
    let si = patch3d_in_pa_and_m();
    let a = converged(&mm, RunOptions::default());
    let b = converged(&si, RunOptions::default());
    // forces in N both ways
    let r = max_rel(&forces(&a), &forces(&b));
    assert!(r <= 1e-10, "forces differ by {r:e}");
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        let y_mm: Vec<f64> = y.last().displacement.iter().map(|u| u * 1000.0).collect();
        let r = max_rel(&x.last().displacement, &y_mm);
        assert!(r <= 1e-10, "displacements differ by {r:e}");
    }
}
