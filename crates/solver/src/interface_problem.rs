//! The interface problem the root solves, as its step solvers read it: the
//! root's input (the scene, the model, the subdomains' condensed data), the
//! interface assembled once (S, the condensed loads, the rigid modes, the
//! contact rows), one step's load, and the statuses a step starts from. Below
//! the step solvers (frictionless, friction, contact elements), so that they
//! and the root's driver import it and not each other.

use crate::model::{BodyModel, FixedPoint, PointModel};
use crate::progress::Progress;
use crate::subdomain::{CondensedData, SubdomainSpec};
use faer::Mat;
use signorini_condense::interface::InterfaceStiffness;
use signorini_contact::friction::PointStatus;
use signorini_contact::registry::Algorithm;
use signorini_scene as scene;

/// What the root's solve reads: the scene, the chosen algorithm, the model
/// and the subdomains' condensed data on Γ.
pub(crate) struct RootInput<'a> {
    pub sc: &'a scene::Scene,
    /// Who hears of the run's progress.
    pub progress: &'a Progress,
    pub algorithm: Algorithm,
    /// Contact elements solved by the return mapping (course notes §7).
    pub return_mapping: bool,
    pub bodies: &'a [BodyModel],
    pub points: &'a [PointModel],
    pub fixed: &'a [FixedPoint],
    pub specs: &'a [SubdomainSpec],
    pub data: &'a [CondensedData],
    pub gamma_of: &'a [Vec<usize>],
    pub frames: &'a crate::contact_frames::ContactFrames,
    /// The size of the interface problem: Γ less the tied slave DOFs.
    pub n_gamma: usize,
    /// The elimination of the tied DOFs (`None` without a tie): rows and
    /// rigid modes over Γ go through it, and u_Γ = T v comes out.
    pub ties: Option<&'a crate::ties::TieReduction>,
}

/// The interface problem on Γ, assembled once per run: S = Σ S_i, the
/// condensed load F'_i of every load entry, the rigid modes R of the
/// floating bodies, and the contact rows (normal rows, then tangential).
pub(crate) struct Interface {
    /// S = Σ S_i, until the Delassus operator factorises it.
    pub s: Option<InterfaceStiffness>,
    /// Per body, per load entry: its condensed load on Γ at scale 1.
    pub fp_entries: Vec<Vec<Vec<f64>>>,
    pub kernel: Mat<f64>,
    pub rows: Vec<Vec<(usize, f64)>>,
    /// The tangential rows t1 (and t2 in 3D) of each point, if it has them.
    pub tangent_row: Vec<Option<usize>>,
    pub tangent_row2: Vec<Option<usize>>,
}

/// The load of one step on Γ, with its scales and the initial gaps.
pub(crate) struct StepLoad {
    pub fp: Vec<f64>,
    /// Prescribed displacement of every body (full DOFs).
    pub u_p: Vec<Vec<f64>>,
    pub f_scale: f64,
    pub length_scale: f64,
    pub gap0: Vec<f64>,
}

/// The statuses a friction solve starts from at its first step: closed
/// points stick, open ones are open, except that every point of a body held
/// by contact alone starts closed. While such a body's contacts are open
/// nothing determines its rigid motion along them (its position is a free
/// unknown, the saddle-point system of its equilibrium is singular): starting
/// closed, the status iterations open the points whose forces come out
/// tensile, so that a body with an initial gap reaches the closed state
/// directly, under displacement or force control (Code_Aster SSNV503).
pub(crate) fn initial_statuses(
    bodies: &[BodyModel],
    points: &[PointModel],
    gap0: &[f64],
    closed: f64,
    close_floating: bool,
) -> Vec<PointStatus> {
    points
        .iter()
        .zip(gap0)
        .map(|(p, &g)| {
            let floating =
                close_floating && p.row.iter().any(|&(b, _, _)| !bodies[b].kernel.is_empty());
            if g <= closed || floating {
                PointStatus::Stick
            } else {
                PointStatus::Open
            }
        })
        .collect()
}
