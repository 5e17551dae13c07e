//! From a step's contact solution to its report: the certificate of
//! docs/theory/algorithms.md, the per-step and per-point rows, and the final report.

use crate::checks::inf_norm;
use crate::checks::{friction_overload_message, held_by_friction};
use crate::compare::compare_reference;
use crate::element_step::RETURN_MAPPING;
use crate::error::SolveError;
use crate::model::{BodyModel, PointModel};
use crate::pressure::nodal_pressures;
use crate::reactions::{step_contacts, step_reactions};
use crate::root::{net_force, point_force};
use crate::run_context::{RunContext, RunLog};
use crate::step::{Partial, Residuals, StepSolution};
use crate::subdomain::{CondensedData, FactorSummary, RecoveredStep};
use crate::{memory, model};
use signorini_contact::friction::PointStatus;
use signorini_contact::norms::nan_max;
use signorini_contact::registry::MethodId;
use signorini_contact::{SolverReport, StatusVariant, StopReason};
use signorini_report::results::{RunOutput, StepFields};
use signorini_report::{
    Certificate, ContactRow, ContactSummary, Memory, Probe, RankStats, Report, StepReport, Timings,
};
use signorini_scene as scene;

/// The certificate of docs/theory/algorithms.md at one step, from the equilibrium
/// residual and the final gaps and forces.
pub(crate) fn certificate_of(
    res: &Residuals,
    gaps: &[f64],
    lambda: &[f64],
    sol: &StepSolution,
    umax: f64,
    tolerance: f64,
) -> Certificate {
    let lmax = inf_norm(lambda);
    let lscale = sol.length_scale.max(umax).max(f64::MIN_POSITIVE);
    let fscale = sol.f_scale.max(lmax).max(f64::MIN_POSITIVE);
    // the scale of a work, not 0 when both are the smallest double (a step
    // with no load: 0/0 made its certificate NaN, never converged)
    let wscale = (lscale * fscale).max(f64::MIN_POSITIVE);
    // Points of a regularised law obey λ = k max(0, −g) instead of g ≥ 0, λ g = 0.
    // Its residual is over the larger of the force scale and k times the
    // length scale: a stiff law (k·L ≫ F) is then checked on its gap,
    // |λ/k − max(0, −g)| / L, which round-off in g cannot blow up by k.
    let unilateral = |p: &usize| sol.law_k.get(*p).is_none_or(|k| *k == 0.0);
    let law = (0..lambda.len())
        .filter(|p| !unilateral(p))
        .fold(0.0f64, |a, p| {
            let k = sol.law_k[p];
            nan_max(
                a,
                (lambda[p] - k * (-gaps[p]).max(0.0)).abs() / fscale.max(k * lscale),
            )
        });
    Certificate {
        equilibrium: res.equilibrium / res.force_scale.max(fscale),
        penetration: (0..gaps.len())
            .filter(unilateral)
            .fold(0.0f64, |a, p| nan_max(a, -gaps[p]))
            / lscale,
        tension: lambda.iter().fold(0.0f64, |a, &l| nan_max(a, -l)) / fscale,
        complementarity: (0..gaps.len())
            .filter(unilateral)
            .fold(0.0f64, |a, p| nan_max(a, (gaps[p] * lambda[p]).abs()))
            / wscale,
        cone: sol.friction.as_ref().map_or(0.0, |f| {
            f.cone_excess.iter().fold(0.0f64, |a, &c| nan_max(a, c)) / fscale
        }),
        dissipation: sol.friction.as_ref().map_or(0.0, |f| {
            (0..lambda.len()).fold(0.0f64, |a, p| {
                nan_max(
                    a,
                    (f.tangential[p] + f.back_force[p]) * f.slip_increment[p]
                        + (f.tangential2[p] + f.back_force2[p]) * f.slip_increment2[p],
                )
            }) / wscale
        }),
        law,
        tolerance: tolerance.max(1e-9),
        force_scale: fscale,
        length_scale: lscale,
    }
}

/// What a solved step leaves for its certificate: the solution, the final
/// gaps, the residuals and the largest displacement; and its load scales.
#[derive(Clone, Copy)]
pub(crate) struct StepEvidence<'a> {
    pub sol: &'a StepSolution,
    pub gaps: &'a [f64],
    pub res: &'a Residuals,
    pub umax: f64,
    pub scale: &'a std::collections::BTreeMap<String, f64>,
}

/// Certificate, contact.csv rows and the step report of one step; updates
/// the run's convergence.
pub(crate) fn conclude_step(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    si: usize,
    step: &StepEvidence,
    partial: &mut Partial,
    messages: &mut Vec<String>,
) {
    let StepEvidence {
        sol,
        gaps,
        res,
        umax,
        scale,
    } = *step;
    let lambda = &sol.outcome.forces;
    let cert = certificate_of(res, gaps, lambda, sol, umax, sc.solver.tolerance);
    let first_failure = partial.failure.is_none();
    record_convergence(partial, si, sol, &cert);
    // A step stopped by its iteration limit says to raise it: the note
    // would blame a load that may well be within friction (a first step
    // with no tangential load at all).
    let overload = sol.outcome.report.stop.friction_overload();
    if let (true, Some(o)) = (first_failure, overload) {
        let method = sol.outcome.report.method.as_str();
        partial.failure = Some(friction_overload_message(
            sc,
            (bodies, points),
            (si, method),
            &sol.outcome.forces,
            o,
        ));
    }
    // Only a solver that did not converge may be facing a load beyond
    // friction: a converged one whose certificate fails is not (its forces
    // are within the cones).
    let limited = sol.outcome.report.stop.iteration_limit() || overload.is_some();
    let solver_failed = !sol.outcome.report.converged;
    if let (true, true, false, Some(failure), Some(_)) = (
        first_failure,
        solver_failed,
        limited,
        &mut partial.failure,
        &sol.friction,
    ) {
        for (name, k) in held_by_friction(bodies, points) {
            failure.push_str(&format!(
                "; body \"{name}\" is held by friction alone in {k} rigid motion(s) its supports leave free: a load along them beyond what friction carries (μ times the normal force) has no static equilibrium, and no solver converges on it; impose that motion (a displacement) instead of a force"
            ));
        }
    }
    let statuses = &sol.outcome.statuses;
    match (statuses.cycle_detected_at, statuses.cycle_left_by_pivoting_at) {
        (Some(c), Some(l)) if statuses.variant_used == StatusVariant::All => messages.push(format!(
            "step {}: the status method cycled (flip-flop) at iteration {c}; it left the cycle at iteration {l} by complementary pivoting (Lemke's method), which cannot cycle",
            si + 1
        )),
        (Some(c), _) => messages.push(format!(
            "step {}: the status method cycled (flip-flop) at iteration {c}; it fell back to one status change per iteration, the most violated first",
            si + 1
        )),
        _ => {}
    }
    push_contact_rows(sc, bodies, points, si, sol, gaps, partial);
    let mut report = step_report(sc, points, scale, sol, &cert);
    let friction = sol.friction.as_ref();
    report.reactions = step_reactions(sc, bodies, points, &res.support, lambda, friction);
    for (ci, force) in &res.ties {
        report.contacts[*ci].force = net_force(sc.model, force.clone());
    }
    partial.steps.push(report);
    if let Some(w) = sol.regularisation.as_ref().and_then(|r| r.warning.clone()) {
        messages.push(format!("step {}: {w}", si + 1));
    }
    partial.solver = serde_json::to_value(&sol.outcome.report).unwrap_or_default();
    partial.certificate = cert;
    partial.lambda = lambda.clone();
    partial.friction = sol.friction.clone();
}

/// Marks the run as not converged, with the first failure, when the step's
/// solver did not converge or its certificate exceeds the tolerance.
fn record_convergence(partial: &mut Partial, si: usize, sol: &StepSolution, cert: &Certificate) {
    let report = &sol.outcome.report;
    if !report.converged {
        partial.converged = false;
        let failure = format!(
            "step {}: {}: {}{}",
            si + 1,
            report.method,
            report.stop,
            failure_advice(report, cert.tolerance, sol.friction.is_none())
        );
        partial.failure.get_or_insert(failure);
    } else if !cert.met() {
        partial.converged = false;
        let mut failure = format!(
            "step {}: the certificate residual {:.3e} exceeds the tolerance {:.1e}",
            si + 1,
            cert.max(),
            cert.tolerance
        );
        if let Some(r) = &sol.regularisation {
            let allowed = cert.penetration.max(cert.complementarity);
            if allowed >= cert.max() {
                failure += &format!(
                    ": it is the penetration of the {} method ({:.3e}, over the length scale {:.3e}), the O(1/k) that its stiffness k = [solver] penalty = {:e} times the contact stiffness allows (forces {:.1e} from the exact ones): raise [solver] penalty, or use an exact method",
                    report.method,
                    r.max_penetration,
                    cert.length_scale,
                    r.stiffness_factor,
                    r.force_deviation
                );
            }
        }
        partial.failure.get_or_insert(failure);
    }
}

/// What to do after a solver that did not converge: a method that can help
/// (never the one that failed; Lemke's method after the frictionless status
/// method), and raising `[solver] max_iterations` only when it can help:
/// never after a cycle of the statuses, and after a
/// projection or dual method only when the rate of its last iterations
/// would reach the tolerance within ten times as many.
pub(crate) fn failure_advice(report: &SolverReport, tolerance: f64, frictionless: bool) -> String {
    const LEMKE: &str =
        "; use method = \"lemke\" (complementary pivoting: a finite number of pivots, it cannot cycle)";
    match report.stop {
        StopReason::Cycling { .. } => {
            return format!(
                "{LEMKE}; raising [solver] max_iterations does not help statuses that cycle"
            )
        }
        StopReason::StatusLimit { .. } if frictionless => return LEMKE.into(),
        _ => {}
    }
    let stop = &report.stop;
    if !stop.out_of_iterations() {
        return if stop.iteration_limit() {
            "; raise [solver] max_iterations".into()
        } else {
            String::new()
        };
    }
    let failed = report.method.parse::<MethodId>().ok();
    let others: Vec<&str> = [MethodId::Status, MethodId::Lemke]
        .into_iter()
        .filter(|&m| Some(m) != failed)
        .map(MethodId::as_str)
        .collect();
    let mut advice = format!(
        "; use method = \"{}\" (exact in a finite number of steps)",
        others.join("\" or \"")
    );
    let history = &report.residual_history;
    match iterations_to_tolerance(history, tolerance) {
        Some(more) if more <= 10 * history.len() => advice += &format!(
            ", or raise [solver] max_iterations (at the rate of the last iterations, about {more} more)"
        ),
        None if history.len() < 5 => advice += ", or raise [solver] max_iterations",
        _ => {}
    }
    advice
}

/// How many more iterations a residual history needs to reach `tolerance`
/// at the mean rate of its last fifth; `None` when it did not fall there
/// (or is too short to tell).
fn iterations_to_tolerance(history: &[f64], tolerance: f64) -> Option<usize> {
    let n = history.len();
    if n < 5 {
        return None;
    }
    let k = n / 5;
    let (before, last) = (history[n - 1 - k], history[n - 1]);
    if !(last.is_finite() && before.is_finite() && last > 0.0 && last < before) {
        return None;
    }
    if last <= tolerance {
        return Some(0);
    }
    let rate = (last / before).ln() / k as f64;
    Some(((tolerance / last).ln() / rate).ceil() as usize)
}

/// The contact.csv rows of a step: each point's gap, forces, slip,
/// pressure and status (open, contact, stick or slip).
fn push_contact_rows(
    sc: &scene::Scene,
    bodies: &[BodyModel],
    points: &[PointModel],
    si: usize,
    sol: &StepSolution,
    gaps: &[f64],
    partial: &mut Partial,
) {
    let lambda = &sol.outcome.forces;
    let pressure = nodal_pressures(points, lambda);
    for (pi, p) in points.iter().enumerate() {
        // an open point carries no pressure, also one without a measure of
        // its own that nodal_pressures gives its neighbour's
        let open = sol.outcome.active.binary_search(&pi).is_err();
        partial.contact_rows.push(ContactRow {
            step: si + 1,
            contact: sc.contact[p.contact].name.clone(),
            body: bodies[p.slave_body].name.clone(),
            point: p.point.slave_node,
            x: p.point.x,
            gap: gaps[pi],
            normal_force: lambda[pi],
            tangential_force: sol.friction.as_ref().map_or(0.0, |f| f.tangential[pi]),
            slip: sol.friction.as_ref().map_or(0.0, |f| f.slip_total[pi]),
            tangential_force_2: sol.friction.as_ref().map_or(0.0, |f| f.tangential2[pi]),
            slip_2: sol.friction.as_ref().map_or(0.0, |f| f.slip_total2[pi]),
            pressure: if open { 0.0 } else { pressure[pi] },
            status: contact_status(p, pi, sol),
            normal: p.point.normal,
            tangent: p.point.tangent,
            tangent2: p.point.tangent2,
        });
    }
}

/// The status of a contact point in contact.csv: open, stick or slip for a
/// point with friction, else contact (a frictionless point, or one whose
/// slip a support holds); a point a support drags slides (course notes §4).
fn contact_status(p: &PointModel, pi: usize, sol: &StepSolution) -> &'static str {
    let active = sol.outcome.active.binary_search(&pi).is_ok();
    match (active, sol.friction.as_ref().map(|f| f.statuses[pi])) {
        (false, _) => "open",
        (true, Some(s)) if s.is_slip() && p.reports_friction(s) => "slip",
        (true, Some(s)) if p.reports_friction(s) => "stick",
        _ => "contact",
    }
}

/// The report of one step: its net contact force, the sums of the normal
/// and tangential forces, the mean slip of the active points with friction,
/// the sticking and slipping counts and the solver's outcome.
fn step_report(
    sc: &scene::Scene,
    points: &[PointModel],
    scale: &std::collections::BTreeMap<String, f64>,
    sol: &StepSolution,
    cert: &Certificate,
) -> StepReport {
    let (outcome, lambda) = (&sol.outcome, &sol.outcome.forces);
    let friction_points = |keep: &dyn Fn(PointStatus) -> bool| match &sol.friction {
        Some(f) => (0..points.len())
            .filter(|&p| points[p].reports_friction(f.statuses[p]) && keep(f.statuses[p]))
            .count(),
        None => 0,
    };
    let sticking = friction_points(&|s| s == PointStatus::Stick);
    let slipping = friction_points(&|s| s.is_slip());
    let mut step_force = vec![0.0f64; sc.dimension as usize];
    let mut tangential_resultant = [0.0f64; 3];
    for (pi, p) in points.iter().enumerate() {
        let force = point_force(p, pi, lambda[pi], sol.friction.as_ref());
        for (f, fk) in step_force.iter_mut().zip(force) {
            *f += fk;
        }
        let t = point_force(p, pi, 0.0, sol.friction.as_ref());
        (0..3).for_each(|k| tangential_resultant[k] += t[k]);
    }
    let sums = FrictionSums::of(points, sol);
    let in_3d = |x: f64| (sc.dimension == 3).then_some(x);
    StepReport {
        scale: scale.clone(),
        contact_force: net_force(sc.model, step_force),
        normal_force: lambda[..points.len()].iter().sum(),
        tangential_force: sums.tangential[0],
        tangential_force_2: in_3d(sums.tangential[1]),
        tangential_resultant,
        mean_slip: sums.mean_slip(0),
        mean_slip_2: in_3d(sums.mean_slip(1)),
        iterations: outcome.report.iterations,
        active: outcome.active.len(),
        sticking,
        slipping,
        converged: outcome.report.converged && cert.met(),
        stopping_reason: outcome.report.stop.to_string(),
        active_history: outcome.statuses.active_history.clone(),
        cycle_detected_at: outcome.statuses.cycle_detected_at,
        solver: serde_json::to_value(&outcome.report).unwrap_or_default(),
        method: outcome.report.method.clone(),
        fallback: outcome.friction.fallback.clone(),
        regularisation: sol.regularisation.clone(),
        solve_s: sol.solve_s,
        reactions: Vec::new(),
        contacts: step_contacts(sc, points, lambda, sol.friction.as_ref()),
    }
}

/// A step's sums over its contact points along the two tangents (the
/// second 0 in 2D): the tangential forces, and the total slips of the
/// active points with friction, with their count.
struct FrictionSums {
    tangential: [f64; 2],
    slip: [f64; 2],
    slipping_points: usize,
}

impl FrictionSums {
    fn of(points: &[PointModel], sol: &StepSolution) -> Self {
        let mut sums = FrictionSums {
            tangential: [0.0; 2],
            slip: [0.0; 2],
            slipping_points: 0,
        };
        let Some(f) = &sol.friction else {
            return sums;
        };
        for (pi, p) in points.iter().enumerate() {
            sums.tangential[0] += f.tangential[pi];
            sums.tangential[1] += f.tangential2[pi];
            let active = sol.outcome.active.binary_search(&pi).is_ok();
            if active && p.reports_friction(f.statuses[pi]) {
                sums.slip[0] += f.slip_total[pi];
                sums.slip[1] += f.slip_total2[pi];
                sums.slipping_points += 1;
            }
        }
        sums
    }

    /// The mean total slip along tangent `k` of the active points with
    /// friction (0 without any).
    fn mean_slip(&self, k: usize) -> f64 {
        match self.slipping_points {
            0 => 0.0,
            n => self.slip[k] / n as f64,
        }
    }
}

pub(crate) fn empty_partial() -> Partial {
    Partial {
        steps: vec![],
        certificate: Certificate::default(),
        converged: true,
        failure: None,
        contact_rows: vec![],
        lambda: vec![],
        u_last: vec![],
        bodies: vec![],
        excluded_gaps: vec![],
        dense_interface_bytes: 0,
        factor_bytes: 0,
        factorisation: None,
        n_gamma: 0,
        dofs: 0,
        solver: serde_json::Value::Null,
        friction: None,
        conditioning: None,
    }
}

/// One step of the condensed path on the root, from the subdomains' recovered
/// step: the full displacement of every body, the equilibrium residuals
/// (interior ones as sent; on Γ Σ_i (K_i u_i − f_i)_Γ − Bᵀλ) and the final
/// gaps g0 + B u_Γ.
pub(crate) fn condensed_step(
    ctx: RunContext,
    sol: &StepSolution,
    u_gamma: &[f64],
    recovered: &[RecoveredStep],
) -> (Vec<f64>, Residuals, Vec<Vec<f64>>) {
    let model = ctx.model;
    let (bodies, points, frames) = (&model.bodies, &model.points, &model.frames);
    let mut u_full: Vec<Vec<f64>> = bodies.iter().map(|b| vec![0.0; b.n_dof]).collect();
    let lambda = &sol.outcome.forces;
    let mut r_gamma = vec![0.0; u_gamma.len()];
    let mut interior = 0.0f64;
    let mut force_scale = 0.0f64;
    let mut support = Vec::new();
    for r in recovered {
        let spec = &model.specs[r.id];
        support.extend(r.support_residual.iter().map(|&(d, v)| (spec.body, d, v)));
        let dim = bodies[spec.body].mesh.dim;
        let u = &mut u_full[spec.body];
        for (l, &n) in spec.nodes.iter().enumerate() {
            u[dim * n..dim * (n + 1)].copy_from_slice(&r.displacement[dim * l..dim * (l + 1)]);
        }
        for &(g, v) in &r.gamma_residual {
            r_gamma[g] += v;
        }
        interior = interior.max(r.interior_residual);
        force_scale = force_scale.max(r.force_scale);
    }
    let mut gaps = sol.gap0.clone();
    for (pi, p) in points.iter().enumerate() {
        for (g, c) in frames.gamma_row(bodies, &model.gamma_of, &p.row) {
            r_gamma[g] -= c * lambda[pi];
            gaps[pi] += c * u_gamma[g];
        }
        if let (Some(t), Some(fr)) = (&p.trow, &sol.friction) {
            for (g, c) in frames.gamma_row(bodies, &model.gamma_of, t) {
                r_gamma[g] -= c * fr.tangential[pi];
            }
        }
        if let (Some(t), Some(fr)) = (&p.trow2, &sol.friction) {
            for (g, c) in frames.gamma_row(bodies, &model.gamma_of, t) {
                r_gamma[g] -= c * fr.tangential2[pi];
            }
        }
    }
    // a tie's forces are internal: the residual of the kept DOFs is Tᵀ r
    let dim = ctx.sc.dimension as usize;
    let ties = model.tied.forces(dim, |b, d| {
        r_gamma.get(model.gamma_of[b][d]).copied().unwrap_or(0.0)
    });
    if let Some(t) = &model.ties {
        r_gamma = t.fold(&r_gamma);
    }
    let res = Residuals {
        equilibrium: interior.max(inf_norm(&r_gamma)),
        force_scale: force_scale.max(inf_norm(lambda)),
        support,
        ties,
    };
    (gaps, res, u_full)
}

/// The sizes of the condensed path for the report: the dense interface
/// problem, the subdomains' factors and their factorisation, n_Γ and the
/// free DOFs.
pub(crate) fn condensed_sizes(
    partial: &mut Partial,
    bodies: &[BodyModel],
    points: &[PointModel],
    data: &[CondensedData],
    n_gamma: usize,
) {
    let m = points.len();
    partial.dense_interface_bytes = 8 * (n_gamma * n_gamma + m * m) as u64;
    partial.factor_bytes = data.iter().map(|d| d.factor_bytes as u64).sum();
    partial.factorisation = Some(condensed_factorisation(data));
    partial.n_gamma = n_gamma;
    partial.dofs = bodies
        .iter()
        .map(|b| b.prescribed.iter().filter(|p| !**p).count())
        .sum();
}

/// The subdomains' factorisations summed: the ordering each kept ("mixed"
/// when they differ), and per ordering compared the factor it gives.
fn condensed_factorisation(data: &[CondensedData]) -> signorini_report::Factorisation {
    let kept: Vec<&FactorSummary> = data.iter().filter_map(|d| d.factor.first()).collect();
    let ordering = match kept.first() {
        Some(k) if kept.iter().all(|o| o.ordering == k.ordering) => k.ordering.clone(),
        Some(_) => "mixed".to_string(),
        None => String::new(),
    };
    let mut candidates: Vec<signorini_report::OrderingCandidate> = Vec::new();
    for f in data.iter().flat_map(|d| &d.factor) {
        match candidates.iter_mut().find(|c| c.ordering == f.ordering) {
            Some(c) => {
                c.factor_nnz += f.nnz as u64;
                c.flops += f.flops;
            }
            None => candidates.push(signorini_report::OrderingCandidate {
                ordering: f.ordering.clone(),
                factor_nnz: f.nnz as u64,
                flops: f.flops,
            }),
        }
    }
    candidates.sort_by_key(|c| c.ordering != ordering);
    signorini_report::Factorisation {
        kind: "cholesky".into(),
        ordering,
        factor_nnz: kept.iter().map(|k| k.nnz as u64).sum(),
        factor_bytes: kept.iter().map(|k| 8 * k.values as u64).sum(),
        flops: kept.iter().map(|k| k.flops).sum(),
        candidates,
        ..Default::default()
    }
}

/// What the run found beyond its steps: the net contact force, each
/// contact's summary, the probes and the comparison with a reference.
struct Findings {
    contact_force: Vec<f64>,
    contacts: Vec<ContactSummary>,
    probes: Vec<Probe>,
    reference: Option<signorini_report::ReferenceReport>,
}

/// Fills the report common to both paths.
pub(crate) fn finish_report(
    ctx: RunContext,
    mut partial: Partial,
    mut log: RunLog,
    communication_bytes: u64,
    rank_stats: Vec<RankStats>,
) -> Result<RunOutput, SolveError> {
    let sc = ctx.sc;
    let (bodies, points) = (&ctx.model.bodies, &ctx.model.points);
    let (contact_force, contacts) =
        contact_summaries(sc, points, &partial.lambda, partial.steps.last());
    let probes = probes_of(sc, bodies, &partial.u_last);
    let reference = match &sc.reference {
        None => None,
        Some(r) => Some(compare_reference(
            sc,
            r,
            points,
            &partial.lambda,
            partial.friction.as_ref(),
            &partial.steps,
        )?),
    };
    let want_stress = sc.output.wants("stress");
    if want_stress {
        log.stages.push("stress".into());
    }
    if partial.steps.len() > 1 {
        log.stages.push(format!("steps ({})", partial.steps.len()));
    }
    let mut results = std::mem::take(&mut partial.bodies);
    for (r, b) in results.iter_mut().zip(bodies) {
        if r.history.is_empty() {
            r.history.push(StepFields {
                displacement: vec![0.0; b.n_dof],
                stress: Vec::new(),
                von_mises: Vec::new(),
            });
        }
    }
    let contact_rows = std::mem::take(&mut partial.contact_rows);
    let findings = Findings {
        contact_force,
        contacts,
        probes,
        reference,
    };
    let report = report_of(
        ctx,
        partial,
        log,
        (communication_bytes, rank_stats),
        findings,
    );
    Ok(RunOutput {
        report,
        contact_rows,
        bodies: results,
    })
}

/// The net contact force and each contact's summary (its points, active
/// points and net force) at the last step: its report's resultants
/// (zeros without a step), and its final contact forces `lambda`.
fn contact_summaries(
    sc: &scene::Scene,
    points: &[PointModel],
    lambda: &[f64],
    last: Option<&StepReport>,
) -> (Vec<f64>, Vec<ContactSummary>) {
    let dim = sc.dimension as usize;
    let mut summaries: Vec<ContactSummary> = sc
        .contact
        .iter()
        .enumerate()
        .map(|(ci, c)| ContactSummary {
            name: c.name.clone(),
            points: 0,
            active: 0,
            force: last.map_or(vec![0.0; dim], |s| s.contacts[ci].force.clone()),
        })
        .collect();
    for (pi, p) in points.iter().enumerate() {
        let s = &mut summaries[p.contact];
        s.points += 1;
        if lambda[pi] != 0.0 {
            s.active += 1;
        }
    }
    let contact_force = last.map_or(vec![0.0; dim], |s| s.contact_force.clone());
    (contact_force, summaries)
}

/// The displacement at the mesh node nearest each probe point of the scene,
/// over all bodies (`u_full`: the final displacement of each body).
fn probes_of(sc: &scene::Scene, bodies: &[BodyModel], u_full: &[Vec<f64>]) -> Vec<Probe> {
    let dim = sc.dimension as usize;
    let mut probes = Vec::new();
    for pr in &sc.output.probes {
        let x = model::point3(pr);
        let best = bodies
            .iter()
            .enumerate()
            .filter_map(|(bi, b)| b.mesh.nearest_node(x).map(|(n, d)| (bi, n, d)))
            .min_by(|a, b| a.2.total_cmp(&b.2));
        if let Some((bi, n, d)) = best {
            probes.push(Probe {
                point: pr.clone(),
                body: bodies[bi].name.clone(),
                node: n,
                distance: d,
                displacement: u_full
                    .get(bi)
                    .map_or(vec![0.0; dim], |u| u[n * dim..(n + 1) * dim].to_vec()),
            });
        }
    }
    probes
}

/// The report.json of a run: its plan, sizes, steps, timings, memory,
/// the ranks' traffic (`ranks`: bytes sent, per-rank statistics), the
/// certificate and what the run found.
#[allow(clippy::too_many_arguments)]
fn report_of(
    ctx: RunContext,
    partial: Partial,
    log: RunLog,
    ranks: (u64, Vec<RankStats>),
    findings: Findings,
) -> Report {
    let RunContext {
        sc,
        scene_name,
        plan,
        model,
        comm,
        ..
    } = ctx;
    let (method, path) = (plan.method, plan.path);
    let RunLog {
        t_total,
        timings,
        messages,
        stages,
    } = log;
    let (communication_bytes, rank_stats) = ranks;
    Report {
        scene: scene_name.to_string(),
        title: sc.title.clone(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        ranks: comm.size(),
        transport: comm.kind().to_string(),
        subdomains: model.specs.len(),
        dofs: partial.dofs,
        interface_dofs: partial.n_gamma,
        contact_points: model.points.len(),
        converged: partial.converged,
        method: match plan.return_mapping {
            true => RETURN_MAPPING.to_string(),
            false => method.as_str().to_string(),
        },
        path: path.as_str().to_string(),
        path_choice: Some(plan.choice.clone()),
        solver: partial.solver,
        stages,
        steps: partial.steps,
        timings_s: Timings {
            total: t_total.elapsed().as_secs_f64(),
            ..timings
        },
        memory: Memory {
            peak_rss_bytes: signorini_report::peak_rss_bytes(),
            dense_interface_bytes: partial.dense_interface_bytes,
            factor_bytes: partial.factor_bytes,
            estimated_bytes: memory::estimate(
                sc,
                path,
                comm.size(),
                memory::ContactCounts::Built(&model.kept),
            )
            .bytes(),
        },
        factorisation: partial.factorisation,
        communication_bytes,
        rank_timings_s: signorini_report::RankTimings::of(&rank_stats),
        rank_stats,
        certificate: partial.certificate,
        contact_force: findings.contact_force,
        contacts: findings.contacts,
        probes: findings.probes,
        reference: findings.reference,
        conditioning: partial.conditioning,
        messages,
        failure: partial.failure,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_contact::solution::Measure;

    fn report(method: &str, stop: StopReason, residual_history: Vec<f64>) -> SolverReport {
        SolverReport {
            method: method.into(),
            stop,
            residual_history,
            ..Default::default()
        }
    }

    fn out_of_iterations(limit: usize) -> StopReason {
        StopReason::IterationLimit {
            limit,
            measure: Measure::Natural,
            residual: 1e-6,
            tolerance: 1e-10,
            steps: None,
        }
    }

    #[test]
    fn the_advice_names_a_method_that_can_help_and_raising_the_limit_only_when_it_can() {
        // The status method's statuses cycled: Lemke, never the limit.
        let cycled = failure_advice(
            &report("status", StopReason::Cycling { iteration: 40 }, vec![]),
            1e-10,
            true,
        );
        assert!(cycled.contains("method = \"lemke\""), "{cycled}");
        assert!(cycled.contains("does not help"), "{cycled}");
        assert!(!cycled.contains("method = \"status\""), "{cycled}");
        // MPRGP stalled at 1e-6 over its last fifth: the exact methods
        // other than itself, no limit to raise.
        let flat = vec![1e-6; 100];
        let stalled = failure_advice(&report("mprgp", out_of_iterations(100), flat), 1e-10, true);
        assert_eq!(
            stalled,
            "; use method = \"status\" or \"lemke\" (exact in a finite number of steps)"
        );
        // A residual falling by 10× per 20 iterations from 1e-2: 1.1e-7 at
        // iteration 99; 2e-10 needs 20 log10(1.1e-7 / 2e-10) = 54.98 more,
        // within ten times as many.
        let falling: Vec<f64> = (0..100)
            .map(|i| 1e-2 * 10f64.powf(-i as f64 / 20.0))
            .collect();
        let more = failure_advice(
            &report("projected_gradient", out_of_iterations(100), falling),
            2e-10,
            true,
        );
        assert!(more.contains("\"status\" or \"lemke\""), "{more}");
        assert!(
            more.ends_with(
                "raise [solver] max_iterations (at the rate of the last iterations, about 55 more)"
            ),
            "{more}"
        );
        // The status method of friction at its limit: raise it (no Lemke).
        let friction = failure_advice(
            &report("status", StopReason::StatusLimit { limit: 1 }, vec![]),
            1e-10,
            false,
        );
        assert_eq!(friction, "; raise [solver] max_iterations");
    }
}
