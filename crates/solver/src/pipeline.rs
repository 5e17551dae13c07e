//! A run as a sequence of named stages (DESIGN.md §2): plan → model and
//! partition → condense (each rank its subdomains) → root: the interface
//! problem and its contact solve at every step → recover (each rank its
//! subdomains) → certify and report. Only this module calls the transport
//! (gather, broadcast, deal).

use super::*;

/// What a run keeps for its report as it goes.
pub(crate) struct RunLog {
    pub t_total: Instant,
    pub timings: Timings,
    pub messages: Vec<String>,
    pub stages: Vec<String>,
}

/// What every stage after the model stage reads of the run: the scene, its
/// name, the plan, the model and the transport.
#[derive(Clone, Copy)]
pub(crate) struct RunContext<'a> {
    pub sc: &'a scene::Scene,
    pub scene_name: &'a str,
    pub plan: &'a plan::Plan,
    pub model: &'a partition::ModelData,
    pub comm: &'a dyn Transport,
}

/// Per-rank figures for the report (report.json `rank_stats`).
#[derive(Serialize, Deserialize, Clone, Default)]
pub(crate) struct RankFigures {
    threads: usize,
    setup_s: f64,
    condense_s: f64,
    contact_s: f64,
    recover_s: f64,
    peak_rss_bytes: u64,
    setup_peak_rss_bytes: u64,
    bytes_sent: u64,
    subdomains: usize,
    factor_bytes: u64,
    dense_bytes: u64,
}

impl RankFigures {
    /// The sizes of this rank's subdomains: their sparse factors (the kept
    /// ordering's stored values) and their dense S_i.
    fn of_condensed(data: &Result<Vec<CondensedData>, String>) -> Self {
        let data = data.as_deref().unwrap_or_default();
        let threads = match faer::get_global_parallelism() {
            faer::Par::Seq => 1,
            faer::Par::Rayon(n) => n.get(),
        };
        Self {
            threads,
            subdomains: data.len(),
            factor_bytes: (data.iter().filter_map(|d| d.factor.first()))
                .map(|k| 8 * k.values as u64)
                .sum(),
            dense_bytes: data.iter().map(|d| 8 * (d.gamma.len() as u64).pow(2)).sum(),
            ..Self::default()
        }
    }
}

/// What the root keeps of its solve for the report: the step solutions and
/// the subdomains' condensed data, with the conditioning estimates.
type RootState = (
    Vec<StepSolution>,
    Vec<CondensedData>,
    conditioning::RootConditioning,
);

/// Runs a scene on every rank of `comm`. Returns the output on the root,
/// `None` on the other ranks; an error is returned identically on every rank.
///
/// When a contact's candidate zone (`search_distance`) left out a slave node
/// that penetrates its master in the answer, the run is solved again with
/// the zone widened (model::check_excluded), and the report says so.
pub fn run(
    sc: &scene::Scene,
    scene_name: &str,
    opts: &RunOptions,
    comm: &dyn Transport,
) -> Result<Option<RunOutput>, SolveError> {
    let t_total = Instant::now();
    let plan = plan::plan(sc, opts)?;
    // Refuse a scene that cannot fit before building anything (the root's
    // verdict on every rank: the machines' memory may differ).
    let fits = comm
        .is_root()
        .then(|| memory::check(sc, plan.path, comm.size()).map(|_| ()));
    wire(broadcast(comm, fits.as_ref()))??;
    let mut zone = None;
    let mut notes = Vec::new();
    let mut widenings = 0;
    loop {
        let log = RunLog {
            t_total,
            timings: Timings::default(),
            messages: notes.clone(),
            stages: vec!["mesh".to_string(), "assemble".to_string()],
        };
        let attempt = Attempt {
            sc,
            scene_name,
            plan: &plan,
            comm,
            zone: zone.as_ref(),
            widenings,
        };
        match attempt.solve(log)? {
            Outcome::Done(out) => return Ok(out.map(|o| *o)),
            Outcome::Widen(w) => {
                notes.extend(w.notes);
                zone = Some(w.zone);
                widenings += 1;
            }
        }
    }
}

/// One solve of the run with a candidate zone (`None`: the scene's).
struct Attempt<'a> {
    sc: &'a scene::Scene,
    scene_name: &'a str,
    plan: &'a plan::Plan,
    comm: &'a dyn Transport,
    zone: Option<&'a model::Zone>,
    /// How many times the zone was widened before this solve.
    widenings: usize,
}

/// What a solve ends with: the output (on the root), or the zone to solve
/// again with.
enum Outcome {
    Done(Option<Box<RunOutput>>),
    Widen(model::Widening),
}

impl Attempt<'_> {
    /// Model, then the direct path on the root or the condensed path on
    /// every rank.
    fn solve(&self, mut log: RunLog) -> Result<Outcome, SolveError> {
        let (sc, comm) = (self.sc, self.comm);
        let condensed_path = self.plan.path == scene::SolvePath::Condensed;
        let t = Instant::now();
        let ranks = if condensed_path { comm.size() } else { 1 };
        progress::phase(progress::Phase::Meshing);
        let model = partition::model_stage(sc, ranks, self.zone, &mut log.messages)?;
        log.timings.setup = t.elapsed().as_secs_f64();
        let setup_peak_rss_bytes = signorini_report::peak_rss_bytes();
        let ctx = RunContext {
            sc,
            scene_name: self.scene_name,
            plan: self.plan,
            model: &model,
            comm,
        };
        if !condensed_path {
            return self.direct_stage(ctx, log);
        }
        log.stages.push("condense".into());
        let (local, condensed, condense_s) = condense_stage(comm, &model, &mut log.messages);
        let sizes = RankFigures::of_condensed(&condensed);
        let gathered = wire(gather(comm, &condensed))?;
        // Sent: the root keeps the gathered copy, the other ranks none.
        drop(condensed);
        progress::ranks_condensed(gathered.as_ref());
        let t_root = Instant::now();
        let (answer, root_state) = root_stage(sc, self.plan, &model, gathered);
        let contact_s = t_root.elapsed().as_secs_f64();
        let answer: Result<RootAnswer, SolveError> =
            wire(broadcast(comm, comm.is_root().then_some(&answer)))?;
        let answer = answer?;
        let t = Instant::now();
        let recovered = recover_stage(&model, &local, &answer);
        let figures = RankFigures {
            setup_s: log.timings.setup,
            condense_s,
            contact_s: if comm.is_root() { contact_s } else { 0.0 },
            recover_s: t.elapsed().as_secs_f64(),
            peak_rss_bytes: signorini_report::peak_rss_bytes(),
            setup_peak_rss_bytes,
            bytes_sent: comm.bytes_sent(),
            ..sizes
        };
        let gathered = wire(gather(comm, &(recovered, figures)))?;
        log.timings.contact = contact_s;
        let partial = gathered.map(|all| {
            let state =
                root_state.ok_or_else(|| SolveError::Internal("root state missing".into()))?;
            condensed_partial(ctx, &mut log, state, all, &answer)
        });
        // The root's verdict on the excluded points, on every rank.
        let widen = partial
            .as_ref()
            .and_then(|p| p.as_ref().ok())
            .and_then(|(p, _)| self.check_zone(&model, p));
        let widen: Option<model::Widening> =
            wire(broadcast(comm, comm.is_root().then_some(&widen)))?;
        if let Some(w) = widen {
            return Ok(Outcome::Widen(w));
        }
        let Some(partial) = partial else {
            return Ok(Outcome::Done(None));
        };
        let (partial, (bytes, stats)) = partial?;
        finish_report(ctx, partial, log, bytes, stats).map(|o| Outcome::Done(Some(Box::new(o))))
    }

    /// The direct path on the root (the other ranks have nothing to do).
    fn direct_stage(&self, ctx: RunContext, mut log: RunLog) -> Result<Outcome, SolveError> {
        let (sc, model) = (ctx.sc, ctx.model);
        if !ctx.comm.is_root() {
            return Ok(Outcome::Done(None));
        }
        log.stages.push("contact".into());
        let partial = progress::observed(|| {
            run_direct(
                sc,
                &model.bodies,
                &model.points,
                &model.fixed,
                &model.scales,
                &mut log.timings,
                &mut log.messages,
            )
        })?;
        if let Some(w) = self.check_zone(model, &partial) {
            return Ok(Outcome::Widen(w));
        }
        progress::phase(progress::Phase::Certifying);
        finish_report(ctx, partial, log, 0, vec![]).map(|o| Outcome::Done(Some(Box::new(o))))
    }

    /// The excluded points of the model against the solved displacements:
    /// the widened zone if one of them penetrates (the penetration tolerance
    /// of the certificate, in its length scale).
    fn check_zone(
        &self,
        model: &partition::ModelData,
        partial: &Partial,
    ) -> Option<model::Widening> {
        let cert = &partial.certificate;
        model::check_excluded(
            self.sc,
            &model.zone,
            &model.excluded,
            &partial.u_steps,
            cert.tolerance * cert.length_scale,
            self.widenings,
        )
    }
}

type Condensed = (Vec<Subdomain>, Result<Vec<CondensedData>, String>, f64);

/// Condensation, on the rank that owns each subdomain (subdomains dealt to
/// the ranks by cost): this rank's subdomains, their S_i and F'_i (or the
/// first error), and the seconds it took.
fn condense_stage(
    comm: &dyn Transport,
    model: &partition::ModelData,
    messages: &mut Vec<String>,
) -> Condensed {
    let specs = &model.specs;
    let costs: Vec<f64> = specs.iter().map(|s| s.cost()).collect();
    let owner_rank = deal(&costs, comm.size());
    if comm.size() > specs.len() && comm.is_root() {
        messages.push(format!(
            "{} ranks for {} subdomains: {} ranks idle (use subdomains = \"auto\" to split bodies over every rank)",
            comm.size(),
            specs.len(),
            comm.size() - specs.len()
        ));
    }
    progress::phase(progress::Phase::Condensing);
    let t = Instant::now();
    let par = faer::get_global_parallelism();
    let condense = |i: usize, spec: &SubdomainSpec| {
        let b = &model.bodies[spec.body];
        let (gamma, owner) = (&model.gamma_of[spec.body], &model.owner_part[spec.body]);
        let frames = model.frames.local(spec.body, b.mesh.dim, Some(&spec.nodes));
        Subdomain::condense(i, spec, b, gamma, owner, frames, par).map_err(|e| {
            format!(
                "bodies[{}] \"{}\", subdomain {} (rank {}): {e}",
                b.scene_index,
                b.name,
                spec.part,
                comm.rank()
            )
        })
    };
    let mine: Result<Vec<(Subdomain, CondensedData)>, String> = injected_failure(comm).map_or_else(
        || {
            let mine: Vec<usize> = (0..specs.len())
                .filter(|&i| owner_rank[i] == comm.rank())
                .collect();
            (mine.iter().enumerate())
                .map(|(k, &i)| {
                    progress::subdomain(k, mine.len(), specs.len());
                    condense(i, &specs[i])
                })
                .collect()
        },
        Err,
    );
    let condense_s = t.elapsed().as_secs_f64();
    if comm.size() > 1 {
        progress::emit(progress::Event::Detail("waiting for the other ranks"));
    }
    match mine {
        Ok(v) => {
            let (a, b): (Vec<_>, Vec<_>) = v.into_iter().unzip();
            (a, Ok(b), condense_s)
        }
        Err(e) => (Vec::new(), Err(e), condense_s),
    }
}

/// A failure injected on this rank by SIGNORINI_FAIL_RANK (the failure
/// test of the MPI path).
fn injected_failure(comm: &dyn Transport) -> Option<String> {
    let r = std::env::var("SIGNORINI_FAIL_RANK").ok()?;
    (r.parse::<usize>().ok() == Some(comm.rank())).then(|| {
        format!(
            "failure injected on rank {} (SIGNORINI_FAIL_RANK)",
            comm.rank()
        )
    })
}

/// The root: the subdomains' condensed data (or the first error of any
/// rank) to the contact solve on Γ at every step. Other ranks get `None`
/// from the gather and answer nothing.
fn root_stage(
    sc: &scene::Scene,
    plan: &plan::Plan,
    model: &partition::ModelData,
    gathered: Option<Vec<Result<Vec<CondensedData>, String>>>,
) -> (Result<RootAnswer, SolveError>, Option<RootState>) {
    let Some(all) = gathered else {
        return (Err(SolveError::Internal("no answer".into())), None);
    };
    let mut data = Vec::new();
    for r in all {
        match r {
            Ok(v) => data.extend(v),
            Err(e) => return (Err(SolveError::Input(e)), None),
        }
    }
    data.sort_by_key(|d| d.id);
    let input = RootInput {
        sc,
        algorithm: plan.algorithm,
        bodies: &model.bodies,
        points: &model.points,
        fixed: &model.fixed,
        specs: &model.specs,
        data: &data,
        gamma_of: &model.gamma_of,
        frames: &model.frames,
        n_gamma: model.n_gamma,
    };
    let mut cond = conditioning::RootConditioning::default();
    progress::phase(progress::Phase::Contact);
    progress::emit(progress::Event::Detail("assembling the interface problem"));
    match progress::observed(|| solve_root(&input, &model.scales, &mut cond)) {
        Ok((answer, steps)) => (Ok(answer), Some((steps, data, cond))),
        Err(e) => (Err(e), None),
    }
}

/// Every rank recovers its subdomains' interiors at every step.
fn recover_stage(
    model: &partition::ModelData,
    local: &[Subdomain],
    answer: &RootAnswer,
) -> Vec<RecoveredData> {
    progress::phase(progress::Phase::Recovering);
    local
        .iter()
        .map(|s| {
            let b = model.specs[s.id].body;
            let sc_b: Vec<Vec<f64>> = model.scales.iter().map(|st| st[b].clone()).collect();
            s.recover(&sc_b, &answer.u_gamma)
        })
        .collect()
}

/// The root: the recovered fields of every rank, the certificate per step
/// and the conditioning into the run's partial report, with the bytes sent
/// and the per-rank statistics.
fn condensed_partial(
    ctx: RunContext,
    log: &mut RunLog,
    (steps, data, root_cond): RootState,
    all: Vec<(Vec<RecoveredData>, RankFigures)>,
    answer: &RootAnswer,
) -> Result<(Partial, (u64, Vec<RankStats>)), SolveError> {
    let (sc, model) = (ctx.sc, ctx.model);
    progress::phase(progress::Phase::Certifying);
    log.timings.delassus = steps.iter().map(|st| st.operator_s).sum();
    let mut recovered: Vec<RecoveredData> = Vec::new();
    let mut figures = Vec::new();
    for (r, f) in all {
        recovered.extend(r);
        figures.push(f);
    }
    recovered.sort_by_key(|r| r.id);
    log.stages.push("contact".into());
    log.stages.push("recover".into());
    log.timings.condense = figures.iter().fold(0.0f64, |a, f| a.max(f.condense_s));
    log.timings.recover = figures.iter().fold(0.0f64, |a, f| a.max(f.recover_s));
    let mut partial = finish_condensed(
        sc,
        &model.bodies,
        &model.points,
        &model.specs,
        &data,
        (&model.gamma_of, &model.frames),
        &recovered,
        steps,
        &answer.u_gamma,
        &mut log.messages,
    )?;
    if let (Some(f), Some(i)) = (
        partial.factorisation.as_mut(),
        root_cond.interface_factorisation(),
    ) {
        let m = model.points.len() as u64;
        partial.dense_interface_bytes = i.factor_bytes + 8 * m * m;
        f.interface = Some(i);
    }
    partial.conditioning = Some(conditioning::condensed(
        &data,
        root_cond,
        sc.solver.tolerance,
        &mut log.messages,
    ));
    let bytes: u64 = figures.iter().map(|f| f.bytes_sent).sum();
    let stats: Vec<RankStats> = figures
        .iter()
        .enumerate()
        .map(|(r, f)| RankStats {
            rank: r,
            subdomains: f.subdomains,
            threads: f.threads,
            setup_s: f.setup_s,
            condense_s: f.condense_s,
            contact_s: f.contact_s,
            recover_s: f.recover_s,
            peak_rss_bytes: f.peak_rss_bytes,
            setup_peak_rss_bytes: f.setup_peak_rss_bytes,
            factor_bytes: f.factor_bytes,
            dense_bytes: f.dense_bytes,
            bytes_sent: f.bytes_sent,
        })
        .collect();
    Ok((partial, (bytes, stats)))
}
