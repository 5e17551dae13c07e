//! `solver.path = "auto"`: the path of a run chosen by its estimated cost
//! before anything is built (docs/guide/choosing.md).
//!
//! Each path's memory is [`memory::estimate`] along it; its time is counted
//! in flops from the same mesh and contact sizes:
//!
//! * condensed: the subdomains' sparse partial factorisations, once
//!   ([`Estimate::factor_flops`]), the dense interface work, once (S_i, S
//!   and W = B S⁻¹ Bᵀ, [`Estimate::dense_flops`]), and at each status
//!   iteration of each step a dense factorisation of W's active block,
//!   m³/3 for m contact rows;
//! * direct: at each status iteration of each step one sparse LDLᵀ of the
//!   KKT matrix ([`Estimate::factor_flops`]).
//!
//! The status method takes [`ITERATIONS`] a step, the friction loops
//! [`FRICTION_ITERATIONS`] (both paths alike; measured 1 to 7 on the
//! examples and the pads of docs/performance/path-choice.md). Flops become
//! seconds at [`SPARSE_RATE`] and [`DENSE_RATE`], measured on the 2-core
//! machine of docs/performance: only the ratio of the paths matters.
//!
//! The rule is [`rule`]: an explicit path is honoured; `auto` leaves out a
//! path that cannot run the scene (today the direct path with friction, a
//! method other than the status method, or contact elements: the plan's own
//! checks say so), then a path whose estimate exceeds the memory budget, and
//! takes the direct path when it is estimated [`MARGIN`] times faster on a
//! run of over [`PAYS`] seconds, else the condensed path. A contact with a
//! candidate zone (`search_distance`) counts no contact points here (its
//! zone is not built yet), which favours the condensed path.

use signorini_report::{PathChoice, PathEstimate};
use signorini_scene as scene;

use crate::memory::{self, Budget, ContactCounts, Estimate};

/// Status iterations expected a load step (the status method).
pub const ITERATIONS: f64 = 4.0;
/// Iterations expected a load step with friction (the fixed point or the
/// Newton method on the threshold: 7 on the 24 × 24 pad).
pub const FRICTION_ITERATIONS: f64 = 8.0;
/// Flops a second of faer's sparse supernodal factorisation on 2 cores
/// (the 101 × 101 × 3-node pad's LDLᵀ: 4.0e9 flops in about 1.3 s).
pub const SPARSE_RATE: f64 = 3e9;
/// Flops a second of the dense interface work on 2 cores (W of the 49 × 49
/// pad, 2.8e10 flops in 2.2 s).
pub const DENSE_RATE: f64 = 1e10;

/// The direct path is taken for speed only when it is estimated this many
/// times faster ...
pub const MARGIN: f64 = 2.0;
/// ... on a run estimated over this many seconds condensed (below, either
/// path is quick, and the estimates are rough: the condensed path, the
/// default of the examples and tests, stays).
pub const PAYS: f64 = 1.0;

/// What the rule weighs of one path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathCost {
    pub memory_bytes: f64,
    pub sparse_flops: f64,
    pub dense_flops: f64,
    pub fits: bool,
}

impl PathCost {
    pub fn seconds(&self) -> f64 {
        self.sparse_flops / SPARSE_RATE + self.dense_flops / DENSE_RATE
    }

    fn report(&self) -> PathEstimate {
        PathEstimate {
            memory_bytes: self.memory_bytes,
            sparse_flops: self.sparse_flops,
            dense_flops: self.dense_flops,
            seconds: self.seconds(),
            fits: self.fits,
        }
    }
}

/// The path of a run: `requested` ("auto" or an explicit path), the
/// condensed path's cost, and the direct path's (`Err`: why it cannot run
/// the scene). Returns the path and why.
pub fn rule(
    requested: scene::SolvePath,
    condensed: &PathCost,
    direct: &Result<PathCost, String>,
) -> (scene::SolvePath, String) {
    use scene::SolvePath::{Auto, Condensed, Direct};
    if requested != Auto {
        return (requested, "asked for".into());
    }
    let direct = match direct {
        Err(why) => {
            let mut reason = format!("the direct path cannot run this scene ({why})");
            if !condensed.fits {
                reason += "; the condensed estimate exceeds the memory budget";
            }
            return (Condensed, reason);
        }
        Ok(d) => d,
    };
    let (tc, td) = (condensed.seconds(), direct.seconds());
    let times = format!("estimated {} condensed, {} direct", secs(tc), secs(td));
    match (condensed.fits, direct.fits) {
        (true, false) => (
            Condensed,
            format!("the direct estimate exceeds the memory budget ({times})"),
        ),
        (false, true) => (
            Direct,
            format!("the condensed estimate exceeds the memory budget ({times})"),
        ),
        _ if tc > PAYS && td * MARGIN < tc => (Direct, format!("faster: {times}")),
        _ if td < tc => (
            Condensed,
            format!(
                "the direct path is not {MARGIN} times faster on a run of over {PAYS} s ({times})"
            ),
        ),
        _ => (Condensed, format!("faster: {times}")),
    }
}

fn secs(s: f64) -> String {
    if s < 0.1 {
        format!("{s:.1e} s")
    } else {
        format!("{s:.1} s")
    }
}

/// The cost of `path` for the scene, from its estimate.
pub fn cost(
    sc: &scene::Scene,
    path: scene::SolvePath,
    ranks: usize,
    budget: Option<Budget>,
) -> PathCost {
    let e = memory::estimate(sc, path, ranks, ContactCounts::Surfaces);
    let iterations = expected_iterations(sc);
    let fits = budget.is_none_or(|b| e.total <= b.bytes as f64);
    let (sparse_flops, dense_flops) = if path == scene::SolvePath::Direct {
        (iterations * e.factor_flops, 0.0)
    } else {
        (e.factor_flops, e.dense_flops + iterations * root_flops(&e))
    };
    PathCost {
        memory_bytes: e.total,
        sparse_flops,
        dense_flops,
        fits,
    }
}

/// One dense factorisation of the m contact rows' block of W.
fn root_flops(e: &Estimate) -> f64 {
    e.contact_rows.powi(3) / 3.0
}

/// Status iterations of the whole run: per step, [`ITERATIONS`], or
/// [`FRICTION_ITERATIONS`] with friction.
fn expected_iterations(sc: &scene::Scene) -> f64 {
    let frictional = sc
        .contact
        .iter()
        .any(|c| c.friction != scene::Friction::None);
    let per_step = if frictional {
        FRICTION_ITERATIONS
    } else {
        ITERATIONS
    };
    per_step * sc.step_scales().len().max(1) as f64
}

/// The report's account of the choice.
pub fn report(
    requested: scene::SolvePath,
    chosen: scene::SolvePath,
    reason: &str,
    condensed: &PathCost,
    direct: &Result<PathCost, String>,
) -> PathChoice {
    PathChoice {
        requested: requested.as_str().into(),
        chosen: chosen.as_str().into(),
        reason: reason.into(),
        condensed: condensed.report(),
        direct: direct.as_ref().ok().map(PathCost::report),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene::SolvePath::{Auto, Condensed, Direct};

    fn cost(sparse: f64, dense: f64, fits: bool) -> PathCost {
        PathCost {
            memory_bytes: 1e6,
            sparse_flops: sparse,
            dense_flops: dense,
            fits,
        }
    }

    #[test]
    fn auto_takes_the_faster_path_that_fits_and_an_explicit_path_stays() {
        let small = cost(1e9, 1e8, true);
        let direct = Ok(cost(4e9, 0.0, true));
        assert_eq!(rule(Auto, &small, &direct).0, Condensed);
        let large_face = cost(1e9, 1e12, true);
        let (path, why) = rule(Auto, &large_face, &direct);
        assert_eq!(path, Direct);
        assert!(
            why.contains("faster") && why.contains("100.3 s condensed"),
            "{why}"
        );
        // explicit: honoured whatever the costs
        assert_eq!(rule(Condensed, &large_face, &direct).0, Condensed);
        assert_eq!(rule(Direct, &small, &direct).0, Direct);
        // memory first: the faster path does not fit
        let (path, why) = rule(Auto, &cost(1e9, 1e12, false), &direct);
        assert_eq!(path, Direct);
        assert!(why.contains("condensed estimate exceeds"), "{why}");
        let (path, _) = rule(Auto, &small, &Ok(cost(1e6, 0.0, false)));
        assert_eq!(path, Condensed);
        // a tie, or a direct path not twice faster, or a quick run: condensed
        assert_eq!(
            rule(Auto, &cost(3e9, 0.0, true), &Ok(cost(3e9, 0.0, true))).0,
            Condensed
        );
        let (path, why) = rule(Auto, &cost(6e9, 0.0, true), &Ok(cost(4e9, 0.0, true)));
        assert_eq!(path, Condensed);
        assert!(why.contains("not 2 times faster"), "{why}");
        assert_eq!(
            rule(Auto, &cost(1e6, 1e9, true), &Ok(cost(1e6, 0.0, true))).0,
            Condensed
        );
    }

    #[test]
    fn auto_keeps_the_condensed_path_when_the_direct_one_cannot_run() {
        let why = Err("friction".to_string());
        let (path, reason) = rule(Auto, &cost(1e9, 1e14, true), &why);
        assert_eq!(path, Condensed);
        assert!(reason.contains("cannot run") && reason.contains("friction"));
        let (path, reason) = rule(Auto, &cost(1e9, 1e14, false), &why);
        assert_eq!(path, Condensed);
        assert!(reason.contains("exceeds the memory budget"), "{reason}");
    }
}
