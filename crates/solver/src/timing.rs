//! The seconds each phase of a run takes, for the report's timings: a
//! phase is run through [`timed`], which adds its time to the figure that
//! holds it (a phase met once per step adds up over the steps).

use std::time::Instant;

/// Runs `phase`, adding the seconds it took to `seconds`.
pub fn timed<T>(seconds: &mut f64, phase: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = phase();
    *seconds += start.elapsed().as_secs_f64();
    out
}
