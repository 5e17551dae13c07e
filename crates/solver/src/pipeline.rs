//! A run as a sequence of named stages (docs/architecture.md): plan → model and
//! partition → condense (each rank its subdomains) → the load steps, one at
//! a time: the root's contact solve of the step on Γ, every rank's recovery
//! of its subdomains at that step, the root's certificate and the step's
//! fields to the output (step_end.rs) → report. No rank holds more than one
//! step's per-DOF data. Only this module calls the transport
//! (gather, broadcast, deal).

use crate::certify::{condensed_sizes, condensed_step, finish_report};
use crate::checks::{check_held_by_contacts, check_nsgs};
use crate::direct_path::run_direct;
use crate::error::{wire, SolveError};
use crate::interface_problem::RootInput;
use crate::options::{RunEnvironment, RunOptions};
use crate::root::{take_interface_stiffness, RootSolve};
use crate::step::Partial;
use crate::step_end::StepLoop;
use crate::subdomain::{CondensedData, RecoveredStep, Subdomain, SubdomainSpec};
use crate::{conditioning, memory, model, partition, pieces, plan};
use serde::{Deserialize, Serialize};
use signorini_comm::{broadcast, deal, gather, Transport};
use signorini_report::results::RunOutput;
use signorini_report::stream::{StepSink, StepsInMemory};
use signorini_report::{RankStats, Timings};
use signorini_scene as scene;
use std::time::Instant;

use crate::progress::{Event, Phase, Progress};
use crate::run_context::{RunContext, RunLog};
use crate::timing::timed;

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
    /// The first error writing this rank's pieces (`[output] pieces`).
    output_error: Option<String>,
}

impl RankFigures {
    /// The sizes of this rank's subdomains: their sparse factors (the kept
    /// ordering's stored values) and their dense S_i.
    fn of_condensed(data: &Result<Vec<CondensedData>, String>) -> Self {
        let data = data.as_deref().unwrap_or_default();
        let threads = faer::get_global_parallelism().degree();
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

/// Runs a scene on every rank of `comm`, keeping every step in memory (the
/// contact rows of every step and the fields of the steps `[output] steps`
/// selects: `RunOutput::contact_rows`, `BodyResult::history`), within the
/// machine's memory. Returns the output on the root, `None` on the other
/// ranks; an error is returned identically on every rank.
pub fn run(
    sc: &scene::Scene,
    scene_name: &str,
    opts: &RunOptions,
    comm: &dyn Transport,
) -> Result<Option<RunOutput>, SolveError> {
    run_with(sc, scene_name, opts, &RunEnvironment::machine(), comm)
}

/// [`run`] with what the process gives the run ([`RunEnvironment`]).
pub fn run_with(
    sc: &scene::Scene,
    scene_name: &str,
    opts: &RunOptions,
    env: &RunEnvironment,
    comm: &dyn Transport,
) -> Result<Option<RunOutput>, SolveError> {
    let mut kept = StepsInMemory::default();
    let out = run_streamed(sc, scene_name, opts, env, comm, &mut kept)?;
    Ok(out.map(|mut o| {
        kept.fill(&mut o);
        o
    }))
}

/// Runs a scene on every rank of `comm`, handing each load step to `sink` on
/// the root as it ends (its contact rows, and its fields when `[output]
/// steps` selects it), so that memory does not grow with the number of
/// steps. Returns the output on the root (the last step's fields in
/// `BodyResult::history`, no contact rows), `None` on the other ranks; an
/// error is returned identically on every rank.
///
/// When a contact's candidate zone (`search_distance`) left out a slave node
/// that penetrates its master in the answer, the run is solved again with
/// the zone widened (model::check_excluded), and the report says so; the
/// sink is told to forget the steps of the first solve.
pub fn run_streamed(
    sc: &scene::Scene,
    scene_name: &str,
    opts: &RunOptions,
    env: &RunEnvironment,
    comm: &dyn Transport,
    sink: &mut dyn StepSink,
) -> Result<Option<RunOutput>, SolveError> {
    let t_total = Instant::now();
    // The root's plan on every rank: `path = "auto"` weighs the machine's
    // memory, which may differ between ranks.
    let root_plan = comm
        .is_root()
        .then(|| plan::plan(sc, opts, comm.size(), env.budget));
    let verdict = root_plan
        .as_ref()
        .map(|p| p.as_ref().map(|p| p.path).map_err(Clone::clone));
    let path = wire(broadcast(comm, verdict.as_ref()))??;
    let plan = match root_plan {
        Some(p) => p?,
        None => {
            let opts = RunOptions {
                path: Some(path),
                ..opts.clone()
            };
            plan::plan(sc, &opts, comm.size(), None)?
        }
    };
    // Refuse a scene that cannot fit before building anything (the root's
    // verdict on every rank: the machines' memory may differ).
    let fits = comm.is_root().then(|| {
        memory::check(
            sc,
            (plan.path, comm.size()),
            memory::ContactCounts::Surfaces,
            env.budget,
        )
        .map(|_| ())
    });
    wire(broadcast(comm, fits.as_ref()))??;
    let progress = Progress::new(env.observer.clone());
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
            budget: env.budget,
            progress: &progress,
            fail_rank: env.fail_rank,
        };
        match attempt.solve(log, sink)? {
            Outcome::Done(out) => return Ok(out.map(|o| *o)),
            Outcome::Widen(w) => {
                sink.restart();
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
    /// The memory the run may use.
    budget: Option<memory::Budget>,
    progress: &'a Progress,
    /// The rank made to fail its condensation (a test of the MPI path).
    fail_rank: Option<usize>,
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
    fn solve(&self, mut log: RunLog, sink: &mut dyn StepSink) -> Result<Outcome, SolveError> {
        let (sc, comm) = (self.sc, self.comm);
        let condensed_path = self.plan.path == scene::SolvePath::Condensed;
        let ranks = if condensed_path { comm.size() } else { 1 };
        let model = timed(&mut log.timings.setup, || -> Result<_, SolveError> {
            self.progress.phase(Phase::Meshing);
            let model = partition::model_stage(sc, ranks, self.zone, &mut log.messages)?;
            // Every rank built the same model: each refuses it alike.
            check_held_by_contacts(&model.bodies, &model.points)?;
            if condensed_path {
                check_nsgs(sc, &model.bodies, &model.points)?;
            }
            // Again with the contact unknowns the candidate zones kept.
            let fits = comm.is_root().then(|| {
                memory::check(
                    sc,
                    (self.plan.path, comm.size()),
                    memory::ContactCounts::Built(&model.kept),
                    self.budget,
                )
                .map(|_| ())
                .map_err(|e| match (e, self.widenings) {
                    (SolveError::Input(m), 1..) => SolveError::Input(format!(
                        "an excluded slave node penetrated its master, and the candidate zone widened to hold it does not fit: {m}"
                    )),
                    (e, _) => e,
                })
            });
            wire(broadcast(comm, fits.as_ref()))??;
            Ok(model)
        })?;
        let setup_peak_rss_bytes = signorini_report::peak_rss_bytes();
        let ctx = RunContext {
            sc,
            progress: self.progress,
            scene_name: self.scene_name,
            plan: self.plan,
            model: &model,
            comm,
        };
        if !condensed_path {
            return self.direct_stage(ctx, log, sink);
        }
        log.stages.push("condense".into());
        let (local, condensed, condense_s) = condense_stage(
            (comm, self.fail_rank),
            &model,
            self.progress,
            &mut log.messages,
        );
        let sizes = RankFigures::of_condensed(&condensed);
        // Moved: the root keeps the gathered data, the other ranks none.
        let gathered = wire(gather(comm, condensed))?;
        self.progress.ranks_condensed(gathered.as_ref());
        let data = gathered.map(root_data);
        // The root's sink ends the steps; every rank's writes its pieces.
        let (mut steps, other) = match comm.is_root() {
            true => (Some(StepLoop::new(sc, &model, sink)), None),
            false => (None, Some(sink)),
        };
        let walked = steps_stage(ctx, &local, data, steps.as_mut(), other, &mut log)?;
        let figures = RankFigures {
            setup_s: log.timings.setup,
            condense_s,
            contact_s: match &walked.root {
                Some(Ok(r)) => r.contact_s,
                _ => 0.0,
            },
            recover_s: walked.recover_s,
            peak_rss_bytes: signorini_report::peak_rss_bytes(),
            setup_peak_rss_bytes,
            bytes_sent: comm.bytes_sent(),
            output_error: walked.output_error,
            ..sizes
        };
        let gathered = wire(gather(comm, figures))?;
        let output_error = (gathered.iter().flatten()).find_map(|f| f.output_error.clone());
        let partial = match (steps, walked.root, output_error) {
            (Some(_), Some(_), Some(e)) => Some(Err(SolveError::Internal(e))),
            (Some(steps), Some(root), None) => Some(condensed_partial(ctx, &mut log, steps, root)),
            _ => None,
        };
        // The root's verdict (an error that ended it, or the excluded
        // points), on every rank.
        let verdict = partial.as_ref().map(|p| match p {
            Ok(p) => Ok(self.check_zone(&model, p)),
            Err(e) => Err(e.clone()),
        });
        let verdict: Result<Option<model::Widening>, SolveError> =
            wire(broadcast(comm, verdict.as_ref()))?;
        if let Some(w) = verdict? {
            return Ok(Outcome::Widen(w));
        }
        let (Some(partial), Some(figures)) = (partial, gathered) else {
            return Ok(Outcome::Done(None));
        };
        let stats = rank_stats(&mut log, &figures);
        let bytes = figures.iter().map(|f| f.bytes_sent).sum();
        finish_report(ctx, partial?, log, bytes, stats).map(|o| Outcome::Done(Some(Box::new(o))))
    }

    /// The direct path on the root (the other ranks have nothing to do).
    fn direct_stage(
        &self,
        ctx: RunContext,
        mut log: RunLog,
        sink: &mut dyn StepSink,
    ) -> Result<Outcome, SolveError> {
        if !ctx.comm.is_root() {
            return Ok(Outcome::Done(None));
        }
        log.stages.push("contact".into());
        let ranks = ctx.comm.size();
        if ranks > 1 {
            log.messages.push(format!("path = \"direct\": the root (rank 0) solves the whole system alone; the other {} rank(s) wait", ranks - 1));
        }
        let mut steps = StepLoop::new(ctx.sc, ctx.model, sink);
        steps.all_pieces = true;
        ctx.progress
            .observed(|| run_direct(ctx, &mut steps, &mut log))?;
        let partial = steps.partial;
        if let Some(w) = self.check_zone(ctx.model, &partial) {
            return Ok(Outcome::Widen(w));
        }
        ctx.progress.phase(Phase::Certifying);
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
            &partial.excluded_gaps,
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
    (comm, fail_rank): (&dyn Transport, Option<usize>),
    model: &partition::ModelData,
    progress: &Progress,
    messages: &mut Vec<String>,
) -> Condensed {
    let specs = &model.specs;
    let costs: Vec<f64> = specs.iter().map(|s| s.cost()).collect();
    let owner_rank = deal(&costs, comm.size());
    if comm.size() > specs.len() && comm.is_root() {
        messages.push(format!(
            "{} ranks for {} subdomains: {} ranks idle (use subdomains = \"auto\" to split bodies over every rank; an \"auto\" body gets no more parts than it has cells)",
            comm.size(),
            specs.len(),
            comm.size() - specs.len()
        ));
    }
    progress.phase(Phase::Condensing);
    let mut condense_s = 0.0;
    let rank = comm.rank();
    let condense = |i: usize, spec: &SubdomainSpec, par: faer::Par| {
        let b = &model.bodies[spec.body];
        let (gamma, owner) = (&model.gamma_of[spec.body], &model.owner_part[spec.body]);
        let frames = model.frames.local(spec.body, b.mesh.dim, Some(&spec.nodes));
        Subdomain::condense(i, spec, b, (gamma, owner), frames, (par, progress)).map_err(|e| {
            format!(
                "bodies[{}] \"{}\", subdomain {} (rank {}): {e}",
                b.scene_index, b.name, spec.part, rank
            )
        })
    };
    let mine: Result<Vec<(Subdomain, CondensedData)>, String> = timed(&mut condense_s, || {
        injected_failure(comm, fail_rank).map_or_else(
            || {
                let mine: Vec<usize> = (0..specs.len())
                    .filter(|&i| owner_rank[i] == comm.rank())
                    .collect();
                let par = faer::get_global_parallelism();
                condense_side_by_side(&mine, &costs, specs.len(), (par, progress), |i, par| {
                    condense(i, &specs[i], par)
                })
            },
            Err,
        )
    });
    if comm.size() > 1 {
        progress.emit(Event::Detail("waiting for the other ranks"));
    }
    match mine {
        Ok(v) => {
            let (a, b): (Vec<_>, Vec<_>) = v.into_iter().unzip();
            (a, Ok(b), condense_s)
        }
        Err(e) => (Vec::new(), Err(e), condense_s),
    }
}

/// Condenses this rank's subdomains `mine` (indices of the run's `total`
/// subdomains, whose costs are `costs`) with the parallelism `par` the rank
/// has, the results in the order of `mine`.
/// With several cores and several subdomains none of which outweighs the
/// others together, they are condensed side by side, one per core, each
/// factorisation on one core: faer's supernodal Cholesky runs in parallel
/// only inside its large supernodes, so two factorisations side by side
/// keep two cores busier than one after the other on two cores each. The
/// first error stops the others from starting new subdomains.
fn condense_side_by_side<T: Send>(
    mine: &[usize],
    costs: &[f64],
    total: usize,
    (par, progress): (faer::Par, &Progress),
    condense: impl Fn(usize, faer::Par) -> Result<T, String> + Sync,
) -> Result<Vec<T>, String> {
    let cores = par.degree();
    let workers = side_by_side_workers(mine.iter().map(|&i| costs[i]), cores);
    if workers <= 1 {
        let each = |(k, &i): (usize, &usize)| {
            progress.subdomain(k, mine.len(), total);
            condense(i, par)
        };
        return mine.iter().enumerate().map(each).collect();
    }
    let par = faer::Par::rayon(cores / workers);
    let mut order: Vec<usize> = (0..mine.len()).collect();
    order.sort_by(|&a, &b| costs[mine[b]].total_cmp(&costs[mine[a]]));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failed = std::sync::atomic::AtomicBool::new(false);
    let slots: Vec<std::sync::Mutex<Option<Result<T, String>>>> =
        mine.iter().map(|_| std::sync::Mutex::new(None)).collect();
    use std::sync::atomic::Ordering::Relaxed;
    // `first`: a subdomain claimed before the workers start (the calling
    // thread's, so that its observer always hears of subdomain 1).
    let work = |reports: bool, mut first: Option<usize>| {
        while !failed.load(Relaxed) {
            let k = first.take().unwrap_or_else(|| next.fetch_add(1, Relaxed));
            let Some(&slot) = order.get(k) else { break };
            if reports {
                progress.subdomain(k, mine.len(), total);
            }
            let out = condense(mine[slot], par);
            failed.fetch_or(out.is_err(), Relaxed);
            *slots[slot].lock().unwrap_or_else(|e| e.into_inner()) = Some(out);
        }
    };
    std::thread::scope(|s| {
        let first = next.fetch_add(1, Relaxed);
        for _ in 1..workers {
            s.spawn(|| work(false, None));
        }
        work(true, Some(first));
    });
    // Without an error every slot is filled; with one, the first error in
    // the order of `mine` is the answer.
    slots
        .into_iter()
        .filter_map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()))
        .collect()
}

/// faer's supernodal Cholesky on k cores is taken to run k^this faster than
/// on one (it is parallel only inside large supernodes). Measured on the
/// 127k-DOF sphere on a loaded machine: 28.0 s of condensation on one core
/// and 23.9 s on two (2^0.23), and in two parts 1.3× faster side by side
/// than one after the other; 0.5 leans towards one at a time.
const CORES_SPEEDUP_EXPONENT: f64 = 0.5;

/// How many subdomains of these costs to condense side by side on `cores`,
/// each worker with cores / workers of them: as many workers as cores and
/// subdomains when the longest worker's share (the largest first, each to
/// the least loaded worker) ends before all of them one after the other
/// on every core would ([`CORES_SPEEDUP_EXPONENT`]); else one at a time
/// with every core.
fn side_by_side_workers(costs: impl Iterator<Item = f64>, cores: usize) -> usize {
    let mut costs: Vec<f64> = costs.collect();
    let workers = cores.min(costs.len());
    if workers < 2 {
        return 1;
    }
    costs.sort_by(|a, b| b.total_cmp(a));
    let mut load = vec![0.0f64; workers];
    for c in &costs {
        let least = (0..workers)
            .min_by(|&a, &b| load[a].total_cmp(&load[b]))
            .unwrap_or(0);
        load[least] += c;
    }
    let speedup = |k: usize| (k as f64).powf(CORES_SPEEDUP_EXPONENT);
    let side_by_side = load.iter().copied().fold(0.0, f64::max) / speedup(cores / workers);
    let together = costs.iter().sum::<f64>() / speedup(cores);
    if side_by_side < together {
        workers
    } else {
        1
    }
}

/// A failure injected on this rank when it is `fail_rank` (the failure test
/// of the MPI path: `RunEnvironment::fail_rank`).
fn injected_failure(comm: &dyn Transport, fail_rank: Option<usize>) -> Option<String> {
    (fail_rank == Some(comm.rank())).then(|| {
        format!(
            "failure injected on rank {} (SIGNORINI_FAIL_RANK)",
            comm.rank()
        )
    })
}

/// The root: the subdomains' condensed data in subdomain order, or the
/// first error of any rank.
fn root_data(
    all: Vec<Result<Vec<CondensedData>, String>>,
) -> Result<Vec<CondensedData>, SolveError> {
    let mut data = Vec::new();
    for r in all {
        data.extend(r.map_err(SolveError::Input)?);
    }
    data.sort_by_key(|d| d.id);
    Ok(data)
}

/// What the load steps leave: this rank's recovery seconds, the first error
/// writing its pieces, and on the root its contact solve state (the
/// condensed data, the conditioning estimates, the seconds of the contact
/// solves and of the Delassus operator) or the error that ended the run.
struct Walked {
    recover_s: f64,
    output_error: Option<String>,
    root: Option<Result<RootWalk, SolveError>>,
}

/// The root's side of the load steps.
struct RootWalk {
    data: Vec<CondensedData>,
    cond: conditioning::RootConditioning,
    contact_s: f64,
    delassus_s: f64,
    output_s: f64,
}

/// The load steps of the condensed path, one at a time on every rank: the
/// root solves step k on Γ and broadcasts u_Γ (or the error that ends the
/// run), every rank recovers its subdomains at step k and sends them back,
/// and the root ends the step (`steps`: certificate, rows, fields to the
/// sink: the root's, held by `steps`; `other` on another rank) before it
/// solves the next; then, with `[output] pieces`, every
/// rank writes the pieces of its subdomains (pieces.rs). An error of the
/// root while ending a step goes to every rank with the next step's
/// broadcast (or the verdict after the last step).
fn steps_stage(
    ctx: RunContext,
    local: &[Subdomain],
    data: Option<Result<Vec<CondensedData>, SolveError>>,
    mut steps: Option<&mut StepLoop>,
    mut other: Option<&mut dyn StepSink>,
    log: &mut RunLog,
) -> Result<Walked, SolveError> {
    let (comm, model) = (ctx.comm, ctx.model);
    let mut error = None;
    let mut data = data.and_then(|d| d.map_err(|e| error = Some(e)).ok());
    let progress = ctx.progress;
    progress.phase(Phase::Contact);
    progress.emit(Event::Detail("assembling the interface problem"));
    // Part of the root's contact solve and of its interface operator.
    let mut assembly_s = 0.0;
    let (input, stiffness) = timed(&mut assembly_s, || {
        let stiffness = data.as_deref_mut().map(|d| {
            if let Some(t) = &model.ties {
                t.reduce(d);
            }
            take_interface_stiffness(d, root_gamma(model))
        });
        (data.as_deref().map(|d| root_input(ctx, d)), stiffness)
    });
    let mut root = timed(&mut assembly_s, || {
        input
            .as_ref()
            .zip(stiffness)
            .and_then(|(i, s)| RootSolve::new(i, s).map_err(|e| error = Some(e)).ok())
    });
    let mut cond = conditioning::RootConditioning::default();
    let (mut recover_s, mut contact_s, mut delassus_s, mut output_s) =
        (0.0, assembly_s, assembly_s, 0.0);
    let mut output_error = None;
    for (si, st) in model.scales.iter().enumerate() {
        progress.step(si, model.scales.len());
        let mut solved = None;
        let msg = timed(&mut contact_s, || {
            comm.is_root().then(|| match (error.take(), root.as_mut()) {
                (Some(e), _) => Err(e),
                (None, None) => Err(SolveError::Internal("the root solve is missing".into())),
                (None, Some(r)) => {
                    progress
                        .observed(|| r.step(si, st, &mut cond))
                        .map(|(sol, u)| {
                            solved = Some(sol);
                            u
                        })
                }
            })
        });
        let u_gamma: Result<Vec<f64>, SolveError> = wire(broadcast(comm, msg.as_ref()))?;
        let u_gamma = u_gamma?;
        // Steps interleave solve and recovery: one stage, a detail per step.
        progress.emit(Event::Detail("recovering"));
        let mine: Vec<RecoveredStep> = timed(&mut recover_s, || {
            local
                .iter()
                .map(|s| s.recover_step(&st[model.specs[s.id].body], &u_gamma))
                .collect()
        });
        let gathered = wire(gather(comm, mine.clone()))?;
        if let (Some(all), Some(sol), Some(steps)) = (gathered, solved, steps.as_deref_mut()) {
            delassus_s += sol.operator_s;
            timed(&mut output_s, || {
                let recovered: Vec<RecoveredStep> = all.into_iter().flatten().collect();
                let (gaps, res, u_full) = condensed_step(ctx, &sol, &u_gamma, &recovered);
                if let Err(e) = steps.end_step(si, &sol, &gaps, &res, u_full, &mut log.messages) {
                    error = Some(e);
                }
            });
        }
        let written = step_pieces(ctx, si, &mine, steps.as_deref_mut(), other.as_deref_mut())?;
        output_error = output_error.or(written.err());
    }
    let root = comm.is_root().then(|| match (error, data) {
        (Some(e), _) => Err(e),
        (None, None) => Err(SolveError::Internal("the root's data is missing".into())),
        (None, Some(data)) => Ok(RootWalk {
            data,
            cond,
            contact_s,
            delassus_s,
            output_s,
        }),
    });
    Ok(Walked {
        recover_s,
        output_error,
        root,
    })
}

/// `[output] pieces` at load step `si` (when it writes fields): the root
/// (`steps`) sends the step's contact values, and this rank writes the
/// pieces of the subdomains it recovered (`mine`) to its sink (the root's,
/// or `other`). The inner Err: the error writing them (the transport's
/// ends the run at once).
fn step_pieces<'s>(
    ctx: RunContext,
    si: usize,
    mine: &[RecoveredStep],
    steps: Option<&mut StepLoop>,
    other: Option<&mut (dyn StepSink + 's)>,
) -> Result<Result<(), String>, SolveError> {
    let (sc, model) = (ctx.sc, ctx.model);
    if !pieces::wanted(sc) || !sc.output.steps.selects(si + 1, model.scales.len()) {
        return Ok(Ok(()));
    }
    let nodal: Vec<_> = wire(broadcast(ctx.comm, steps.as_deref().map(|s| &s.nodal)))?;
    let sink = match (steps, other) {
        (Some(s), _) => s.sink(),
        (None, Some(o)) => o,
        (None, None) => return Ok(Err("no sink on this rank".into())),
    };
    Ok(pieces::write_recovered(
        sc,
        model,
        mine,
        si + 1,
        &nodal,
        sink,
    ))
}

/// What the root's solve reads of the run: the scene, the algorithm, the
/// model and the subdomains' condensed data.
fn root_input<'a>(ctx: RunContext<'a>, data: &'a [CondensedData]) -> RootInput<'a> {
    let model = ctx.model;
    RootInput {
        progress: ctx.progress,
        sc: ctx.sc,
        algorithm: ctx.plan.algorithm,
        return_mapping: ctx.plan.return_mapping,
        bodies: &model.bodies,
        points: &model.points,
        fixed: &model.fixed,
        specs: &model.specs,
        data,
        gamma_of: &model.gamma_of,
        frames: &model.frames,
        n_gamma: root_gamma(model),
        ties: model.ties.as_ref(),
    }
}

/// The size of the root's interface problem: Γ, less the tied slave DOFs
/// (`crate::ties`).
fn root_gamma(model: &partition::ModelData) -> usize {
    model.ties.as_ref().map_or(model.n_gamma, |t| t.n_kept)
}

/// The root: the steps' partial report completed with the sizes, the
/// conditioning and the timings of the condensed path.
fn condensed_partial(
    ctx: RunContext,
    log: &mut RunLog,
    steps: StepLoop,
    root: Result<RootWalk, SolveError>,
) -> Result<Partial, SolveError> {
    let (sc, model) = (ctx.sc, ctx.model);
    ctx.progress.phase(Phase::Certifying);
    let root = root?;
    let mut partial = steps.partial;
    log.stages.push("contact".into());
    log.stages.push("recover".into());
    log.timings.contact = root.contact_s;
    log.timings.delassus = root.delassus_s;
    log.timings.output += root.output_s;
    condensed_sizes(
        &mut partial,
        &model.bodies,
        &model.points,
        &root.data,
        model.n_gamma,
    );
    if let (Some(f), Some(i)) = (
        partial.factorisation.as_mut(),
        root.cond.interface_factorisation(),
    ) {
        let m = model.points.len() as u64;
        partial.dense_interface_bytes = i.factor_bytes + 8 * m * m;
        f.interface = Some(i);
    }
    partial.conditioning = Some(conditioning::condensed(
        &root.data,
        root.cond,
        sc.solver.tolerance,
        &mut log.messages,
    ));
    Ok(partial)
}

/// Per-rank statistics for the report, and the run's condensation and
/// recovery times (the slowest rank's).
fn rank_stats(log: &mut RunLog, figures: &[RankFigures]) -> Vec<RankStats> {
    log.timings.condense = figures.iter().fold(0.0f64, |a, f| a.max(f.condense_s));
    log.timings.recover = figures.iter().fold(0.0f64, |a, f| a.max(f.recover_s));
    figures
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
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One subdomain, one core, or one subdomain that would keep one core
    /// busy long after the others: one at a time; else one per core.
    #[test]
    fn subdomains_go_side_by_side_only_when_they_balance() {
        let w = |c: &[f64], cores| side_by_side_workers(c.iter().copied(), cores);
        assert_eq!(w(&[5.0], 2), 1);
        assert_eq!(w(&[1.0, 1.0], 1), 1);
        assert_eq!(w(&[5.0, 1.0, 1.0], 2), 1);
        assert_eq!(w(&[3.0, 1.0, 1.0], 2), 2);
        assert_eq!(w(&[1.2, 1.0], 2), 2);
        assert_eq!(w(&[3.0, 1.0], 2), 1);
        assert_eq!(w(&[2.0, 1.0, 1.0], 2), 2);
        assert_eq!(w(&[1.0; 8], 4), 4);
        assert_eq!(w(&[1.0; 3], 8), 3);
    }

    /// Side by side, the results come back in the order of `mine` and the
    /// first error is the answer.
    #[test]
    fn side_by_side_keeps_the_order_and_the_error() {
        let par = faer::Par::rayon(2);
        let mine = [4, 0, 2, 1];
        let costs = [1.0, 2.0, 3.0, 1.5, 2.5];
        let out = condense_side_by_side(&mine, &costs, 5, (par, &Progress::default()), |i, _| {
            Ok::<_, String>(10 * i)
        });
        assert_eq!(out, Ok(vec![40, 0, 20, 10]));
        let out = condense_side_by_side(&mine, &costs, 5, (par, &Progress::default()), |i, _| {
            if i == 2 {
                Err("subdomain 2 failed".to_string())
            } else {
                Ok(i)
            }
        });
        assert_eq!(out, Err("subdomain 2 failed".to_string()));
    }
}
