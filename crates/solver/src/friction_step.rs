//! One load step with friction on the condensed problem (course notes §4): the
//! tangential rows' "gaps" (slip increments, §4.4), the regularised law's
//! compliance, the choice of the friction algorithm (Tresca status or
//! projection, Coulomb fixed point, status method or semi-smooth Newton
//! method, Norton–Hoff, the 3D semi-smooth Newton method), the roughness of
//! the plasticity analogy (course notes §6: the rough rows' unknown is the slider
//! force, [`signorini_contact::friction::kinematic_hardening`]), and the slip
//! history carried to the next step.

use std::time::{Duration, Instant};

use crate::error::{contact_error, SolveError};
use crate::interface_problem::{initial_statuses, Interface, RootInput, StepLoad};
use crate::model::{BodyModel, PointModel};
use crate::step::{FrictionStep, StepSolution};
use signorini_contact::friction::driver::{
    solve_friction as solve_friction_by, FrictionMethod, FrictionSolver, FrictionStart,
};
use signorini_contact::friction::kinematic_hardening::{self, Hardened};
use signorini_contact::friction::{FrictionLaw, FrictionLayout, FrictionOptions, PointStatus};
use signorini_contact::law::regularised;
use signorini_contact::options::default_time_limit;
use signorini_contact::registry::FrictionSupport;
use signorini_contact::{ContactError, ContactSolution, DelassusOperator, DelassusProblem};
use signorini_scene as scene;

/// The friction layout of the interface problem, built once per run.
pub(crate) struct FrictionRows {
    pub(crate) layout: FrictionLayout,
    /// Every point's friction law at the current load step (its contact's
    /// own, or what a step's `friction` set; `crate::step_friction`).
    laws: Vec<FrictionLaw>,
    /// Some contact has Norton–Hoff friction (then all frictional ones do).
    pub(crate) norton_hoff: bool,
    pub(crate) three_d: bool,
}

/// What a friction step carries to the next: total slips, the last
/// statuses and forces.
pub(crate) struct FrictionHistory {
    pub(crate) slip_total: Vec<f64>,
    pub(crate) slip_total2: Vec<f64>,
    previous: Option<(Vec<PointStatus>, Vec<f64>)>,
    /// The largest force and length scales of the steps so far.
    scales: (f64, f64),
}

impl FrictionHistory {
    pub(crate) fn new(m: usize) -> Self {
        Self {
            slip_total: vec![0.0; m],
            slip_total2: vec![0.0; m],
            previous: None,
            scales: (0.0, 0.0),
        }
    }

    /// The step's load with its force and length scales at least those of
    /// the steps before: the slips and stresses left by them stay, and a step
    /// unloaded to no load is judged against them, not against its own
    /// round-off.
    fn scaled(&mut self, mut load: StepLoad) -> StepLoad {
        (load.f_scale, load.length_scale) = self.scales(load.f_scale, load.length_scale);
        load
    }

    /// The force and length scales of a step, at least those of the steps
    /// before (see [`FrictionHistory::scaled`]).
    pub(crate) fn scales(&mut self, f_scale: f64, length_scale: f64) -> (f64, f64) {
        self.scales = (self.scales.0.max(f_scale), self.scales.1.max(length_scale));
        self.scales
    }
}

/// The friction layout (`None` without a tangential row), and the
/// combination refused: Norton–Hoff mixed with Tresca or Coulomb (the
/// friction status method in 3D is refused by `plan`).
pub(crate) fn friction_rows(
    input: &RootInput,
    interface: &Interface,
) -> Result<Option<FrictionRows>, SolveError> {
    let tangent_rows = (&interface.tangent_row[..], &interface.tangent_row2[..]);
    layout_of(input.sc, input.points, &interface.rows, tangent_rows)
}

/// [`friction_rows`] of the `points`' contact rows `rows` (normal rows,
/// then the tangential ones at `tangent_row`, `tangent_row2`).
pub(crate) fn layout_of(
    sc: &scene::Scene,
    points: &[PointModel],
    rows: &[Vec<(usize, f64)>],
    (tangent_row, tangent_row2): (&[Option<usize>], &[Option<usize>]),
) -> Result<Option<FrictionRows>, SolveError> {
    if tangent_row.iter().all(|t| t.is_none()) {
        return Ok(None);
    }
    let m = points.len();
    let three_d = sc.dimension == 3;
    let is_norton_hoff = |p: &PointModel| matches!(p.friction, FrictionLaw::NortonHoff { .. });
    let norton_hoff = points.iter().any(is_norton_hoff);
    let mixed = points.iter().any(|p| {
        matches!(
            p.friction,
            FrictionLaw::Tresca(_) | FrictionLaw::Coulomb { .. }
        )
    });
    if norton_hoff && mixed {
        return Err(SolveError::Input(
            "contact.friction: Norton-Hoff cannot be mixed with Tresca or Coulomb contacts in one scene yet".into(),
        ));
    }
    let layout = FrictionLayout {
        tangent_rows: (0..m)
            .map(|p| {
                [tangent_row[p], tangent_row2[p]]
                    .into_iter()
                    .flatten()
                    .collect()
            })
            .collect(),
        // A point whose slip is prescribed by a support has no tangential
        // unknown (see model::contacts::free_tangential_rows).
        law: points
            .iter()
            .map(|p| match p.trow {
                None => FrictionLaw::None,
                Some(_) => p.friction,
            })
            .collect(),
        shadow: signorini_geometry::redundancy::tangent_shadows(rows, m, tangent_row),
    };
    Ok(Some(FrictionRows {
        layout,
        laws: points.iter().map(|p| p.friction).collect(),
        norton_hoff,
        three_d,
    }))
}

impl FrictionRows {
    /// Sets every point's friction law for load step `si`
    /// ([`crate::step_friction::step_laws`]); a point without a friction
    /// unknown keeps none in the layout.
    pub(crate) fn at_step(&mut self, input: &RootInput, si: usize) {
        let Some(laws) = crate::step_friction::step_laws(input.sc, input.points, si) else {
            return;
        };
        for ((l, p), law) in self.layout.law.iter_mut().zip(input.points).zip(&laws) {
            if p.trow.is_some() {
                *l = *law;
            }
        }
        self.laws = laws;
    }
}

/// The gaps of every row: the normal ones, then the tangential "gaps": the
/// prescribed part of the slip minus the slip at the end of the previous
/// step, so that the tangential rows give slip increments (course notes §4.4); in
/// the order of the rows, t1 then t2 of each point.
fn tangential_gaps(input: &RootInput, load: &StepLoad, history: &FrictionHistory) -> Vec<f64> {
    let (bodies, points) = (input.bodies, input.points);
    row_gaps(bodies, points, &load.gap0, &load.u_p, |pi| {
        (history.slip_total[pi], history.slip_total2[pi])
    })
}

/// The gaps of every row: the normal ones, then, in the order of the rows
/// (t1 then t2 of each point), the prescribed part of the tangential jump
/// minus `slip(point)` (along t1, t2).
pub(crate) fn row_gaps(
    bodies: &[BodyModel],
    points: &[PointModel],
    gap0: &[f64],
    u_p: &[Vec<f64>],
    slip: impl Fn(usize) -> (f64, f64),
) -> Vec<f64> {
    let mut gap0_all = gap0.to_vec();
    let prescribed = |t: &[(usize, usize, f64)]| prescribed_jump(bodies, u_p, t);
    for (pi, p) in points.iter().enumerate() {
        let (s1, s2) = slip(pi);
        if let Some(t) = &p.trow {
            gap0_all.push(prescribed(t) - s1);
        }
        if let Some(t) = &p.trow2 {
            gap0_all.push(prescribed(t) - s2);
        }
    }
    gap0_all
}

/// The elastic slip compliance 1/k_e of a regularised law on the diagonal
/// of W's tangential rows (course notes §4.1.3).
fn slip_compliance(input: &RootInput, interface: &Interface) -> Vec<f64> {
    let rows = |pi: usize| [interface.tangent_row[pi], interface.tangent_row2[pi]];
    let points = input.points.iter().enumerate();
    regularised::slip_compliance(
        interface.rows.len(),
        points.map(|(pi, p)| (p.slip_stiffness, rows(pi))),
    )
}

/// The roughness Q (force per unit slip: the scene's per-area value times
/// the point's tributary measure) of each point with a tangential unknown
/// and a rough regularised Coulomb law (course notes §6); 0 elsewhere.
fn point_roughness(input: &RootInput) -> Vec<f64> {
    let rough = |p: &PointModel| match &input.sc.contact[p.contact].friction {
        scene::Friction::Coulomb {
            roughness: Some(q),
            slip_stiffness: Some(_),
            ..
        } if p.trow.is_some() => q * p.tributary,
        _ => 0.0,
    };
    input.points.iter().map(rough).collect()
}

/// The slider force ξ = t − Q g as the unknown of the rough points'
/// tangential rows (course notes §6); `None` without roughness.
fn harden_rough_rows(
    input: &RootInput,
    interface: &Interface,
    history: &FrictionHistory,
    problem: &mut DelassusProblem,
) -> Result<Option<Hardened>, SolveError> {
    let (mut rows, mut q, mut slip) = (vec![], vec![], vec![]);
    let mut entry = String::new();
    for (pi, &qp) in point_roughness(input).iter().enumerate() {
        if qp <= 0.0 {
            continue;
        }
        if entry.is_empty() {
            let name = &input.sc.contact[input.points[pi].contact].name;
            entry = format!("contact \"{name}\".friction.roughness");
        }
        let along = [
            (interface.tangent_row[pi], history.slip_total[pi]),
            (interface.tangent_row2[pi], history.slip_total2[pi]),
        ];
        for (row, g) in along {
            if let Some(t) = row {
                rows.push(t);
                q.push(qp);
                slip.push(g);
            }
        }
    }
    if rows.is_empty() {
        return Ok(None);
    }
    let hardened = kinematic_hardening::harden(problem, &rows, &q, &slip)
        .map_err(|e| SolveError::Input(format!("{entry}: {e}")))?;
    // The eliminated modes leave a W whose rank-k term (the modes' spring)
    // dwarfs the bodies' compliance: the 2D status methods solve it, the 3D
    // fixed point's inner iterations do not reach the tolerance.
    if hardened.holds_modes() && input.sc.dimension == 3 {
        return Err(SolveError::Input(format!(
            "{entry}: in 3D a rigid motion of a body held by contact alone that slides rough contact points (a block free to turn about its top) is not supported; hold the body so that no rigid motion slides them (a support that keeps it from turning), or solve it in 2D"
        )));
    }
    Ok(Some(hardened))
}

/// The time at which a friction solve of `rows` rows stops: `solver.time_limit`
/// seconds from now, by default [`default_time_limit`].
pub(crate) fn deadline(time_limit: Option<f64>, rows: usize) -> Instant {
    let seconds = time_limit.unwrap_or_else(|| default_time_limit(rows));
    Instant::now() + Duration::from_secs_f64(seconds.min(1e9))
}

/// One friction step: the problem with the tangential gaps and compliance,
/// solved by the algorithm the scene asks for; returns the step and u_Γ,
/// and updates the slip history.
pub(crate) fn friction_step(
    input: &RootInput,
    interface: &Interface,
    fr: &FrictionRows,
    history: &mut FrictionHistory,
    op: &DelassusOperator,
    load: StepLoad,
) -> Result<(StepSolution, Vec<f64>), SolveError> {
    let m = input.points.len();
    let load = history.scaled(load);
    let mut problem = op.problem(&tangential_gaps(input, &load, history), &load.fp);
    problem.add_compliance(&slip_compliance(input, interface));
    let hardened = harden_rough_rows(input, interface, history, &mut problem)?;
    let fopts = FrictionOptions {
        max_iterations: input.sc.solver.max_iterations,
        max_fixed_point: input.sc.solver.max_iterations,
        tolerance: input.sc.solver.tolerance,
        force_scale: load.f_scale,
        gap_scale: load.length_scale,
        deadline: Some(deadline(input.sc.solver.time_limit, problem.q.len())),
    };
    let out = solve_friction(input, fr, history, &mut problem, &load, &fopts);
    let mut out = out.map_err(contact_error)?;
    let tangent_rows = (&interface.tangent_row[..], &interface.tangent_row2[..]);
    let mut friction = friction_state(tangent_rows, fr, history, &out, m);
    let (bodies, points) = (input.bodies, input.points);
    let slip = (&load.u_p[..], load.length_scale);
    let lambda = &out.forces[..m];
    prescribed_slip_friction(bodies, points, fr, slip, history, &mut friction, lambda);
    let physical = match &hardened {
        Some(h) => {
            let t = h.physical_forces(&mut problem, &out.forces);
            rough_tractions(interface, &mut friction, &out.forces, &t);
            t
        }
        None => out.forces.clone(),
    };
    let u = problem.displacement(&physical);
    let (forces, gaps) = (out.forces[..m].to_vec(), out.gaps[..m].to_vec());
    let previous_forces = std::mem::replace(&mut out.forces, forces);
    history.previous = Some((out.friction.points.clone(), previous_forces));
    out.gaps = gaps;
    out.alpha = vec![];
    out.report.operator_applications = problem.solves;
    Ok((
        StepSolution {
            outcome: out,
            gap0: load.gap0,
            f_scale: load.f_scale,
            length_scale: load.length_scale,
            regularisation: None,
            law_k: vec![0.0; m],
            friction: Some(friction),
            solve_s: 0.0,
            operator_s: 0.0,
        },
        u,
    ))
}

/// The friction algorithm of the scene on the step's problem, by the
/// friction driver ([`signorini_contact::friction::driver`]); in 3D the
/// semi-smooth Newton method (the fixed point is its fallback). A body held
/// by contact alone starts closed at the first step; if that start is
/// singular (e.g. a corner stuck on one contact and closed on another along
/// the same DOF), the 2D solves start again from the gaps.
fn solve_friction(
    input: &RootInput,
    fr: &FrictionRows,
    history: &FrictionHistory,
    problem: &mut DelassusProblem,
    load: &StepLoad,
    fopts: &FrictionOptions,
) -> Result<ContactSolution, ContactError> {
    let (bodies, points) = (input.bodies, input.points);
    let asked = match (fr.three_d, input.sc.solver.friction) {
        (_, scene::FrictionSolver::Nsgs) => FrictionSolver::Nsgs,
        (true, _) | (false, scene::FrictionSolver::Newton) => FrictionSolver::Newton,
        (false, scene::FrictionSolver::Status) => FrictionSolver::Status,
        (false, scene::FrictionSolver::FixedPoint) => FrictionSolver::FixedPoint,
    };
    let dim = if fr.three_d { 3 } else { 2 };
    let tresca_box = input.algorithm.friction() == FrictionSupport::TrescaBox;
    let method = FrictionMethod::choose(asked, dim, &fr.layout, tresca_box).ok_or_else(|| {
        ContactError::Geometry("the friction status method is a 2D method".into())
    })?;
    let start = history.previous.as_ref().map(|p| p.1.clone());
    let closed = input.sc.solver.tolerance * load.length_scale;
    // Norton–Hoff starts every step from the statuses of the gaps, as its
    // first step does (from the previous step's statuses its second step
    // was refused as singular); its fixed point restarts from stick anyway.
    let initial = match &history.previous {
        Some(p) if !fr.norton_hoff => p.0.clone(),
        _ => initial_statuses(bodies, points, &load.gap0, closed, true),
    };
    let retry_from_gaps =
        !fr.three_d && history.previous.is_none() && bodies.iter().any(|b| !b.kernel.is_empty());
    // The status methods from a cold start without floating bodies: slip
    // predicted from q.
    let predict = history.previous.is_none() && problem.n_kernel() == 0;
    let solve = |problem: &mut DelassusProblem, statuses: Vec<PointStatus>| {
        let from = FrictionStart {
            statuses,
            forces: start.as_deref(),
            predict,
            zone: false,
        };
        solve_friction_by(problem, &fr.layout, method, from, fopts).map(|a| a.solution)
    };
    match solve(problem, initial) {
        Err(ContactError::Singular(_)) if retry_from_gaps => solve(
            problem,
            initial_statuses(bodies, points, &load.gap0, closed, false),
        ),
        other => other,
    }
}

/// The rough points' tangential forces: the tractions t (the report, the
/// equilibrium) in place of the slider forces ξ, whose difference ξ − t = Q g
/// is kept as the back force (the cone and the dissipation are ξ's).
fn rough_tractions(interface: &Interface, f: &mut FrictionStep, xi: &[f64], t: &[f64]) {
    for pi in 0..f.tangential.len() {
        if let Some(r) = interface.tangent_row[pi] {
            f.tangential[pi] = t[r];
            f.back_force[pi] = xi[r] - t[r];
        }
        if let Some(r) = interface.tangent_row2[pi] {
            f.tangential2[pi] = t[r];
            f.back_force2[pi] = xi[r] - t[r];
        }
    }
}

/// The friction state of the step per point (tangential forces, slip
/// increments and totals, thresholds, cone excess), and the slip totals
/// carried to the next step.
pub(crate) fn friction_state(
    (tangent_row, tangent_row2): (&[Option<usize>], &[Option<usize>]),
    fr: &FrictionRows,
    history: &mut FrictionHistory,
    out: &ContactSolution,
    m: usize,
) -> FrictionStep {
    let lambda = &out.forces[..m];
    let mut f = FrictionStep::zeros(out.friction.points.clone(), m);
    for (pi, &ln) in lambda.iter().enumerate() {
        if let Some(t) = tangent_row[pi] {
            f.tangential[pi] = out.forces[t];
            f.slip_increment[pi] = out.gaps[t];
            history.slip_total[pi] += out.gaps[t];
            f.threshold[pi] = fr.layout.law[pi].semi_axes(ln)[0];
            f.cone_excess[pi] = fr.layout.law[pi].cone_excess(ln, &[f.tangential[pi]]);
        }
        if let Some(t2) = tangent_row2[pi] {
            f.tangential2[pi] = out.forces[t2];
            f.slip_increment2[pi] = out.gaps[t2];
            history.slip_total2[pi] += out.gaps[t2];
            let lt = [f.tangential[pi], f.tangential2[pi]];
            f.cone_excess[pi] = fr.layout.law[pi].cone_excess(ln, &lt);
        }
        f.slip_total[pi] = history.slip_total[pi];
        f.slip_total2[pi] = history.slip_total2[pi];
    }
    f
}

/// The slip below which a prescribed slip increment is round-off, relative
/// to the step's length scale.
const SLIP_ROUND_OFF: f64 = 64.0 * f64::EPSILON;

/// The friction of the points whose slip a support prescribes (no tangential
/// row with a free DOF: `model::contacts::free_tangential_rows`). Their slip
/// is the prescribed motion along their dropped rows, carried in the slip
/// totals. A support that holds the slip (a symmetry plane) leaves the point
/// in contact with no friction force: the support reaction holds it. One
/// that drags it (a non-zero slip increment) makes it slide, and Coulomb's
/// law (course notes §4) gives its force on the boundary of its cone, opposite to
/// the slip increment. That force acts on prescribed DOFs only: it changes
/// no free displacement, so it is computed here, at the end of the step.
pub(crate) fn prescribed_slip_friction(
    bodies: &[BodyModel],
    points: &[PointModel],
    fr: &FrictionRows,
    (u_p, length_scale): (&[Vec<f64>], f64),
    history: &mut FrictionHistory,
    f: &mut FrictionStep,
    lambda: &[f64],
) {
    let round_off = SLIP_ROUND_OFF * length_scale;
    for (pi, p) in points.iter().enumerate() {
        let Some(rows) = &p.prescribed_slip else {
            continue;
        };
        let along = |r: Option<&Vec<(usize, usize, f64)>>| {
            r.map_or(0.0, |r| prescribed_jump(bodies, u_p, r))
        };
        let total = [along(Some(&rows.t1)), along(rows.t2.as_ref())];
        let increment = [
            total[0] - history.slip_total[pi],
            total[1] - history.slip_total2[pi],
        ];
        (history.slip_total[pi], history.slip_total2[pi]) = (total[0], total[1]);
        (f.slip_total[pi], f.slip_total2[pi]) = (total[0], total[1]);
        (f.slip_increment[pi], f.slip_increment2[pi]) = (increment[0], increment[1]);
        let sliding = lambda[pi] > 0.0 && increment[0].hypot(increment[1]) > round_off;
        let force = sliding
            .then(|| sliding_force(p, fr.laws[pi], lambda[pi], increment))
            .flatten();
        let Some(force) = force else {
            if f.statuses[pi].is_slip() {
                f.statuses[pi] = PointStatus::Stick;
            }
            continue;
        };
        (f.tangential[pi], f.tangential2[pi]) = (force[0], force[1]);
        f.threshold[pi] = fr.laws[pi].semi_axes(lambda[pi])[0];
        f.statuses[pi] = match (rows.t2.is_some(), force[0] > 0.0) {
            (true, _) => PointStatus::Slip,
            (false, true) => PointStatus::SlipPlus,
            (false, false) => PointStatus::SlipMinus,
        };
    }
}

/// The tangential jump the prescribed displacements `u_p` give along a row
/// (its prescribed DOFs only).
fn prescribed_jump(bodies: &[BodyModel], u_p: &[Vec<f64>], row: &[(usize, usize, f64)]) -> f64 {
    row.iter()
        .filter(|&&(b, d, _)| bodies[b].prescribed[d])
        .map(|&(b, d, c)| c * u_p[b][d])
        .sum()
}

/// The friction force of a point sliding by `increment` (along t1, t2) with
/// normal force `normal` (course notes §4): on the boundary of its law's disc or
/// ellipse (semi-axes a₁, a₂: Tresca g, Coulomb μᵢ λ_n), the point of
/// maximal dissipation, λ_tᵢ = −aᵢ² Δsᵢ / ‖(a₁ Δs₁, a₂ Δs₂)‖, which is
/// −a Δs/|Δs| on a disc. `None` for the laws whose force is not a threshold
/// (Norton–Hoff) or depends on the elastic slip (a slip stiffness).
fn sliding_force(
    p: &PointModel,
    law: FrictionLaw,
    normal: f64,
    increment: [f64; 2],
) -> Option<[f64; 2]> {
    if p.slip_stiffness.is_some() {
        return None;
    }
    let axes = match law {
        FrictionLaw::Tresca(_) | FrictionLaw::Coulomb { .. } => law.semi_axes(normal),
        _ => return None,
    };
    let weighted = (axes[0] * increment[0]).hypot(axes[1] * increment[1]);
    (weighted > 0.0).then(|| [0, 1].map(|k| -axes[k] * axes[k] * increment[k] / weighted))
}
