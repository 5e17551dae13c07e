//! The run report (docs/reference/scene-format.md, "The report"): report.json, contact.csv, and the
//! analytic references a run is compared with (docs/theory/validation-cases.md).
//!
//! The report crate owns the output files, the terminal summary and the
//! analytic references; it must not know the scene format or the solver.

pub mod budget;
pub mod output;
pub mod pieces;
pub mod plot;
pub mod reference;
pub mod results;
pub mod stale;
mod steps_csv;
pub mod stream;
pub mod vtu;

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use serde::Serialize;
pub use steps_csv::{csv_field, write_steps_csv};

/// One load step of the run.
#[derive(Debug, Clone, Serialize)]
pub struct StepReport {
    pub scale: BTreeMap<String, f64>,
    /// Resultant contact force on the slaves at this step (normal and friction).
    pub contact_force: Vec<f64>,
    /// Sum of the normal and of the tangential contact forces.
    pub normal_force: f64,
    pub tangential_force: f64,
    /// The vector sum of the tangential contact forces (not in report.json:
    /// the load history of the Cattaneo–Mindlin reference).
    #[serde(skip)]
    pub tangential_resultant: [f64; 3],
    /// Mean total slip of the frictional contact points in contact.
    pub mean_slip: f64,
    /// 3D: the same sum and mean along the second tangent (contact.csv's
    /// `tangential_force_2`, `slip_2`); absent in 2D.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_force_2: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean_slip_2: Option<f64>,
    pub iterations: usize,
    pub active: usize,
    pub sticking: usize,
    pub slipping: usize,
    pub converged: bool,
    pub stopping_reason: String,
    /// Active-set size at each status iteration.
    pub active_history: Vec<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycle_detected_at: Option<usize>,
    /// What the contact algorithm did at this step.
    pub solver: serde_json::Value,
    /// Penalty methods: deviation from the exact unilateral solution.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub regularisation: Option<Regularisation>,
    /// Wall-clock seconds of this step's contact solve on the root (its
    /// right-hand side and the algorithm; the Delassus operator, built once
    /// per run, is `timings_s.delassus`).
    pub solve_s: f64,
    /// The reaction of every prescribed-displacement boundary entry, in
    /// scene order.
    pub reactions: Vec<Reaction>,
    /// Every contact pair's sums, in scene order.
    pub contacts: Vec<StepContact>,
    /// The method that solved this step (`solver.method`, repeated here).
    pub method: String,
    /// When `method` took over from another method: that method and why it
    /// stopped; `null` otherwise.
    pub fallback: Option<String>,
}

/// The reaction of one prescribed-displacement boundary entry at one step:
/// the force its support exerts on the body, K u − f − Bᵀλ summed over the
/// DOFs it prescribes (external forces and contact forces on those DOFs
/// taken out), and its moment.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Reaction {
    /// The entry's `name`, or `boundary[i]` when it has none.
    pub boundary: String,
    pub body: String,
    /// The resultant force (axisymmetric: that of the whole ring, axial
    /// alone).
    pub force: Vec<f64>,
    /// Σ (x − moment_about) × the nodal reactions: [M_z] in 2D,
    /// [M_x, M_y, M_z] in 3D; absent in an axisymmetric model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub moment: Option<Vec<f64>>,
    /// The point of the moment: the entry's `moment_about`, default the
    /// origin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub moment_about: Option<Vec<f64>>,
}

/// One contact pair at one step: its sums over its points.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct StepContact {
    pub name: String,
    /// Σ of its points' normal forces (≥ 0 in compression).
    pub normal_force: f64,
    /// Σ of its points' tangential forces along their first tangent.
    pub tangential_force: f64,
    /// 3D: along their second tangent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_force_2: Option<f64>,
    /// The resultant force of its masters on its slaves (normal and
    /// friction parts; axisymmetric: axial alone).
    pub force: Vec<f64>,
}

/// How far a penalty (regularised) solution is from the exact unilateral one.
#[derive(Debug, Clone, Serialize)]
pub struct Regularisation {
    /// Penalty stiffness as a multiple of the contact stiffness 1/mean diag(W).
    pub stiffness_factor: f64,
    /// max |λ − λ_exact| / max |λ_exact|.
    pub force_deviation: f64,
    /// Largest penetration max(−g).
    pub max_penetration: f64,
    /// Largest penetration over the local element size (tributary length).
    pub penetration_over_element_size: f64,
    /// Set when the penetration exceeds the stated fraction of the element size.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
}

/// Wall-clock time per phase, in seconds.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Timings {
    pub setup: f64,
    pub assemble: f64,
    pub condense: f64,
    pub contact: f64,
    /// Building the Delassus operator W = B S⁻¹ Bᵀ, once per run (part of
    /// `contact`; 0 on the direct path).
    pub delassus: f64,
    pub recover: f64,
    pub output: f64,
    /// The condition estimate that needs a factorisation of its own: κ(K)
    /// on the direct path, one sparse Cholesky of the whole stiffness (0 on
    /// the condensed path, whose estimates reuse its factors).
    pub conditioning: f64,
    pub total: f64,
}

#[derive(Debug, Clone, Default, Serialize)]
pub struct Memory {
    /// Peak resident set size of the process (VmHWM), 0 where unknown.
    pub peak_rss_bytes: u64,
    /// Bytes of the dense interface problem: S (n_Γ²) and W (m²) in f64.
    pub dense_interface_bytes: u64,
    /// Bytes of the subdomains' sparse factors and dense Schur blocks.
    pub factor_bytes: u64,
    /// The peak the run was estimated to need before it started, from the
    /// mesh sizes (`signorini_solver::memory`; a scene estimated above the
    /// machine's memory is refused).
    pub estimated_bytes: u64,
}

/// The sparse factorisation of the run (report.json `factorisation`): the
/// fill-reducing ordering kept, the factor's size and the flops of one
/// factorisation, summed over the subdomains (condensed path) or of the
/// KKT matrix (direct path).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Factorisation {
    /// "cholesky": the subdomains' partial LLᵀ with the interface last
    /// (condensed path); "ldlt": the quasi-definite LDLᵀ of the KKT matrix
    /// (direct path).
    pub kind: String,
    /// "amd" or "nested_dissection" (the cheaper of the two in flops, see
    /// docs/performance/scale-3d.md), "mixed" when the subdomains differ.
    pub ordering: String,
    /// Entries of the sparse factor L.
    pub factor_nnz: u64,
    /// Bytes of the factor's stored values (8 per value; supernodes are
    /// stored as dense blocks).
    pub factor_bytes: u64,
    /// Σ_j c_j² over the columns of L (c_j entries in column j): the flops
    /// of one numerical factorisation.
    pub flops: f64,
    /// Every ordering compared, with the factor it would give (summed over
    /// the subdomains), the kept one first.
    pub candidates: Vec<OrderingCandidate>,
    /// Direct path: numerical factorisations (one per status iteration).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub factorisations: Option<usize>,
    /// Direct path: iterative refinement steps over all solves (the LDLᵀ is
    /// of the regularised matrix; refinement recovers the exact solution).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refinement_steps: Option<usize>,
    /// Direct path: solves where the LDLᵀ failed or refinement did not
    /// reach the exact solution, solved by sparse LU instead.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lu_fallbacks: Option<usize>,
    /// Condensed path: the root's factorisation of the interface stiffness
    /// S = Σ S_i.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interface: Option<InterfaceFactorisation>,
}

/// The root's factorisation of S on Γ (report.json
/// `factorisation.interface`): one subdomain's S is dense; several
/// subdomains' blocks are factorised over the tree of subdomains
/// (docs/reference/scene-format.md).
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct InterfaceFactorisation {
    /// "dense" (one subdomain) or "tree" (several).
    pub storage: String,
    /// Interface DOFs n_Γ.
    pub rows: u64,
    /// Stored entries of S: n_Γ² dense, Σ_i n_i² in the subdomains' blocks.
    pub matrix_nnz: u64,
    /// The tree factor's ordering ("subdomain_tree"), flops and entries.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ordering: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sparse_flops: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sparse_factor_nnz: Option<u64>,
    /// Bytes of the factor kept.
    pub factor_bytes: u64,
    /// Fixing DOFs of the floating bodies' rigid modes (tree factor; the
    /// dense one factorises S + ρRRᵀ instead).
    pub fixing_dofs: u64,
}

/// One fill-reducing ordering compared for the factorisation.
#[derive(Debug, Clone, Default, Serialize)]
pub struct OrderingCandidate {
    pub ordering: String,
    pub factor_nnz: u64,
    pub flops: f64,
}

/// The contact conditions checked on the final solution, each relative to
/// the scale of the problem (see docs/theory/contact-problem.md): equilibrium residual over the
/// load, penetration and complementarity over the displacement scale,
/// tension over the force scale, cone violation over μλ_n.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Certificate {
    pub equilibrium: f64,
    pub penetration: f64,
    pub tension: f64,
    pub complementarity: f64,
    pub cone: f64,
    /// Dissipation sign: max over slipping points of λ_t Δs (the friction force
    /// must oppose the slip, λ_t Δs ≤ 0), over force × length scales.
    pub dissipation: f64,
    /// Regularised (penalty) law residual max |λ − k max(0, −g)| over the
    /// larger of the force scale and k × the length scale, on the points of
    /// a `law = { penalty = k }` contact; part of [`Certificate::max`].
    pub law: f64,
    /// The tolerance these were checked against.
    pub tolerance: f64,
    /// Force and length scales used to make the residuals relative.
    pub force_scale: f64,
    pub length_scale: f64,
}

impl Certificate {
    /// Whether every residual is within the tolerance (false when one is NaN).
    pub fn met(&self) -> bool {
        self.max() <= self.tolerance
    }

    /// The largest residual; NaN when one is NaN (an answer that broke
    /// down), so that `max() <= tolerance` fails.
    pub fn max(&self) -> f64 {
        [
            self.equilibrium,
            self.penetration,
            self.tension,
            self.complementarity,
            self.cone,
            self.law,
        ]
        .into_iter()
        .fold(0.0, |a: f64, b| {
            if a.is_nan() || b.is_nan() {
                f64::NAN
            } else {
                a.max(b)
            }
        })
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Probe {
    pub point: Vec<f64>,
    pub body: String,
    pub node: usize,
    pub distance: f64,
    pub displacement: Vec<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Quantity {
    pub computed: f64,
    pub exact: f64,
    pub relative_error: f64,
}

impl Quantity {
    pub fn new(computed: f64, exact: f64) -> Self {
        let relative_error = if exact != 0.0 {
            ((computed - exact) / exact).abs()
        } else {
            computed.abs()
        };
        Self {
            computed,
            exact,
            relative_error,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct ReferenceReport {
    pub kind: String,
    pub quantities: BTreeMap<String, Quantity>,
    /// What the comparison assumes (e.g. Hertz's half-space).
    pub notes: Vec<String>,
}

/// Per-pair contact summary.
#[derive(Debug, Clone, Serialize)]
pub struct ContactSummary {
    pub name: String,
    pub points: usize,
    pub active: usize,
    pub force: Vec<f64>,
}

/// report.json.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub scene: String,
    pub title: String,
    pub version: String,
    pub ranks: usize,
    /// "local" (every subdomain in one process) or "mpi".
    pub transport: String,
    pub subdomains: usize,
    pub dofs: usize,
    pub interface_dofs: usize,
    pub contact_points: usize,
    pub converged: bool,
    pub method: String,
    pub path: String,
    /// How the path was chosen: asked for, or estimated (`path = "auto"`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_choice: Option<PathChoice>,
    /// The contact algorithm's account of the last step (iterations, operator
    /// applications, residual history, stopping reason).
    pub solver: serde_json::Value,
    /// Which stages ran (docs/architecture.md).
    pub stages: Vec<String>,
    pub steps: Vec<StepReport>,
    pub timings_s: Timings,
    pub memory: Memory,
    /// Ordering, size and flops of the sparse factorisation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub factorisation: Option<Factorisation>,
    /// Bytes sent between ranks (0 in one process).
    pub communication_bytes: u64,
    /// Per rank: subdomains, condensation and recovery time, peak memory,
    /// bytes sent (condensed path).
    pub rank_stats: Vec<RankStats>,
    /// Min and max over ranks of the condensation and recovery times.
    pub rank_timings_s: RankTimings,
    pub certificate: Certificate,
    pub contact_force: Vec<f64>,
    pub contacts: Vec<ContactSummary>,
    pub probes: Vec<Probe>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<ReferenceReport>,
    /// Condition estimates of the factorised operators and the digits they
    /// cost against the tolerance (see [`Conditioning`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conditioning: Option<Conditioning>,
    /// Warnings and notes for the user.
    pub messages: Vec<String>,
    /// Why the run is not converged, when it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// How the run's path was chosen (report.json `path_choice`): the path
/// asked for (`solver.path` or `--path`: "condensed", "direct" or "auto"),
/// the path run, why, and each path's estimates from the mesh and contact
/// sizes made before anything is built (docs/guide/choosing.md).
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct PathChoice {
    pub requested: String,
    pub chosen: String,
    pub reason: String,
    pub condensed: PathEstimate,
    /// `null` when the direct path cannot run the scene (`reason` says why).
    pub direct: Option<PathEstimate>,
}

/// One path's estimates (report.json `path_choice.condensed`, `.direct`).
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct PathEstimate {
    /// The peak memory estimate (as `memory.estimated_bytes`).
    pub memory_bytes: f64,
    /// Flops of the sparse factorisations of the run (condensed: the
    /// subdomains', once; direct: the KKT LDLᵀ at each expected iteration).
    pub sparse_flops: f64,
    /// Flops of the dense interface work (condensed: S, W, and the active
    /// blocks of W at each expected iteration; direct: 0).
    pub dense_flops: f64,
    /// Both flop counts at the rates of a 2-core machine: a figure to
    /// compare the paths by, not a forecast of the run's time.
    pub seconds: f64,
    /// Whether `memory_bytes` is within the memory the run may use.
    pub fits: bool,
}

/// Condition estimates of the operators a run factorises (report.json
/// `conditioning`), each the 1-norm condition number κ₁ = ‖A‖₁ ‖A⁻¹‖₁ with
/// ‖A‖₁ exact and ‖A⁻¹‖₁ estimated by the Hager–Higham estimator (LAPACK
/// `dlacon`) from solves with the run's own factorisations: a lower bound of
/// κ₁, in practice within a factor 3. An entry is `null` when it does not
/// apply or was not estimated (`notes` says why); a singular operator is
/// `null` too (JSON has no infinity).
///
/// The rule: a solve with A may lose log10 κ of the 15.65 decimal digits of
/// an f64 (−log10 ε). `digits_lost` = log10 of the largest estimated κ,
/// `digits_available` = 15.65 − `digits_lost`, `digits_needed` =
/// −log10(solver.tolerance); `warning` is set when `digits_available` <
/// `digits_needed`: the tolerance asks for more digits than the worst
/// conditioned operator leaves.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Conditioning {
    /// How κ was estimated: "hager_higham_1norm".
    pub method: String,
    /// Condensed path: the largest κ₁(K_II) over the subdomains (the interior
    /// stiffness each subdomain factorises by sparse Cholesky).
    pub k_ii: Option<f64>,
    /// κ₁(K_II) of each subdomain, in subdomain order (`null` for a subdomain
    /// without interior DOFs).
    pub k_ii_per_subdomain: Vec<Option<f64>>,
    /// Condensed path: κ₁ of the assembled interface Schur complement S as the
    /// root factorises it (S + ρRRᵀ when a body is floating).
    pub s: Option<f64>,
    /// Condensed path: κ₁ of the Delassus operator W = B S⁻¹ Bᵀ (normal and
    /// tangential rows) at the first step, by a dense Cholesky of W when
    /// m ≤ 4000; `null` when W is singular (redundant contact constraints)
    /// or m is larger.
    pub w: Option<f64>,
    /// Direct path: κ₁ of the whole stiffness K on the free DOFs (`null` when
    /// a body is floating: K is then singular).
    pub k: Option<f64>,
    /// log10 of the largest κ above (`null` when none was estimated).
    pub digits_lost: Option<f64>,
    /// 15.65 − `digits_lost`: the decimal digits a solve can still get right.
    pub digits_available: Option<f64>,
    /// −log10(solver.tolerance): the digits the tolerance asks for.
    pub digits_needed: f64,
    /// Set when `digits_available` < `digits_needed` (also in `messages`).
    pub warning: Option<String>,
    /// Why an entry is `null`, and remarks (e.g. W singular).
    pub notes: Vec<String>,
}

/// What one rank did (report.json `rank_stats`, condensed path).
#[derive(Debug, Clone, Serialize)]
pub struct RankStats {
    pub rank: usize,
    pub subdomains: usize,
    /// Threads of this rank's dense and sparse kernels (faer): its share of
    /// the cores of its machine, or RAYON_NUM_THREADS when set.
    pub threads: usize,
    /// Seconds of this rank's model stage (meshes, loads, contacts, partition).
    pub setup_s: f64,
    pub condense_s: f64,
    /// Seconds of the interface problem and its contact solve (the root
    /// only; 0 on the other ranks, which wait for its answer).
    pub contact_s: f64,
    pub recover_s: f64,
    /// Peak resident set size of this rank's process (VmHWM).
    pub peak_rss_bytes: u64,
    /// Its peak resident set size at the end of the model stage: what every
    /// rank holds of the whole scene (the bodies' meshes, per-DOF vectors
    /// and loads, the contact points and the partition), before any matrix.
    pub setup_peak_rss_bytes: u64,
    /// Bytes of the sparse factors of this rank's subdomains (8 per stored
    /// value); summed over the ranks: `factorisation.factor_bytes`.
    pub factor_bytes: u64,
    /// Bytes of the dense Schur complements S_i of this rank's subdomains
    /// (8 n_b² each).
    pub dense_bytes: u64,
    pub bytes_sent: u64,
}

/// Min and max over ranks.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RankTimings {
    pub condense_min: f64,
    pub condense_max: f64,
    pub recover_min: f64,
    pub recover_max: f64,
}

impl RankTimings {
    pub fn of(stats: &[RankStats]) -> Self {
        let mm = |f: &dyn Fn(&RankStats) -> f64| {
            stats
                .iter()
                .map(f)
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                })
        };
        let (cmin, cmax) = mm(&|s| s.condense_s);
        let (rmin, rmax) = mm(&|s| s.recover_s);
        if stats.is_empty() {
            return Self::default();
        }
        Self {
            condense_min: cmin,
            condense_max: cmax,
            recover_min: rmin,
            recover_max: rmax,
        }
    }
}

/// Writes a CSV file: its header line, then one line per item.
pub fn write_lines(
    path: &Path,
    header: &str,
    lines: impl IntoIterator<Item = String>,
) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "{header}")?;
    for line in lines {
        writeln!(w, "{line}")?;
    }
    w.flush()
}

/// One row of contact.csv.
#[derive(Debug, Clone)]
pub struct ContactRow {
    pub step: usize,
    pub contact: String,
    pub body: String,
    pub point: usize,
    pub x: [f64; 3],
    pub gap: f64,
    pub normal_force: f64,
    pub tangential_force: f64,
    pub slip: f64,
    /// Along the second tangent (3D; 0 in 2D).
    pub tangential_force_2: f64,
    pub slip_2: f64,
    pub pressure: f64,
    pub status: &'static str,
    /// The point's frame in global coordinates: the normal n (from the
    /// master towards the slave, the direction of `normal_force` on the
    /// slave), the tangent t1 of `tangential_force` and `slip`, and in 3D
    /// the tangent t2 of `tangential_force_2` and `slip_2` (n, t1, t2
    /// right-handed; zero in 2D).
    pub normal: [f64; 3],
    pub tangent: [f64; 3],
    pub tangent2: [f64; 3],
}

impl ContactRow {
    /// The tangential force as a vector in global coordinates,
    /// `tangential_force` t1 + `tangential_force_2` t2.
    pub fn tangential_vector(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| {
            self.tangential_force * self.tangent[k] + self.tangential_force_2 * self.tangent2[k]
        })
    }

    /// The total slip as a vector in global coordinates, `slip` t1 +
    /// `slip_2` t2.
    pub fn slip_vector(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| self.slip * self.tangent[k] + self.slip_2 * self.tangent2[k])
    }
}

/// The header of contact.csv in 2D (docs/reference/scene-format.md), up to `status`;
/// the frame's columns [`CONTACT_CSV_FRAME_2D`] follow.
pub const CONTACT_CSV_HEADER_2D: &str =
    "step,contact,body,point,x,y,gap,normal_force,tangential_force,slip,pressure,status";

/// The header of contact.csv in 3D: 2D's with `z`, `tangential_force_2` and
/// `slip_2` (docs/reference/scene-format.md), up to `status`; the frame's columns
/// [`CONTACT_CSV_FRAME_3D`] follow.
pub const CONTACT_CSV_HEADER_3D: &str = "step,contact,body,point,x,y,z,gap,normal_force,tangential_force,slip,tangential_force_2,slip_2,pressure,status";

/// The columns after `status` in 2D: each point's normal and tangent in
/// global coordinates.
pub const CONTACT_CSV_FRAME_2D: &str = "n_x,n_y,t1_x,t1_y";

/// The columns after `status` in 3D: each point's normal and tangents.
pub const CONTACT_CSV_FRAME_3D: &str = "n_x,n_y,n_z,t1_x,t1_y,t1_z,t2_x,t2_y,t2_z";

/// Writes contact.csv with the columns of the dimension `dim` (2 or 3).
pub fn write_contact_csv(path: &Path, rows: &[ContactRow], dim: usize) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    write_contact_header(&mut w, dim)?;
    for r in rows {
        write_contact_row(&mut w, r, dim)?;
    }
    w.flush()
}

/// The header line of contact.csv in dimension `dim`.
pub fn write_contact_header(w: &mut impl Write, dim: usize) -> std::io::Result<()> {
    if dim == 3 {
        writeln!(w, "{CONTACT_CSV_HEADER_3D},{CONTACT_CSV_FRAME_3D}")
    } else {
        writeln!(w, "{CONTACT_CSV_HEADER_2D},{CONTACT_CSV_FRAME_2D}")
    }
}

/// One line of contact.csv in dimension `dim`.
pub fn write_contact_row(w: &mut impl Write, r: &ContactRow, dim: usize) -> std::io::Result<()> {
    write!(
        w,
        "{},{},{},{},{:e},{:e},",
        r.step, r.contact, r.body, r.point, r.x[0], r.x[1]
    )?;
    if dim == 3 {
        write!(w, "{:e},", r.x[2])?;
    }
    write!(
        w,
        "{:e},{:e},{:e},{:e},",
        r.gap, r.normal_force, r.tangential_force, r.slip
    )?;
    if dim == 3 {
        write!(w, "{:e},{:e},", r.tangential_force_2, r.slip_2)?;
    }
    write!(w, "{:e},{}", r.pressure, r.status)?;
    let vectors: &[&[f64; 3]] = match dim {
        3 => &[&r.normal, &r.tangent, &r.tangent2],
        _ => &[&r.normal, &r.tangent],
    };
    for v in vectors {
        for x in &v[..dim] {
            write!(w, ",{x:e}")?;
        }
    }
    writeln!(w)
}

pub fn write_report(path: &Path, report: &Report) -> std::io::Result<()> {
    let text = serde_json::to_string_pretty(report).map_err(std::io::Error::other)?;
    std::fs::write(path, text + "\n")
}

/// Peak resident set size of this process (Linux VmHWM), 0 elsewhere.
pub fn peak_rss_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| {
                l.split_whitespace()
                    .nth(1)
                    .and_then(|v| v.parse::<u64>().ok())
            })
        })
        .map(|kb| kb * 1024)
        .unwrap_or(0)
}

/// Resets the peak resident set size of this process to its current size
/// (Linux: `5` written to /proc/self/clear_refs), so that
/// [`peak_rss_bytes`] measures from here: a benchmark running several cases
/// in one process reports each case's own peak, not the largest so far.
/// Returns whether the reset was made (not on other systems, nor where
/// /proc is read-only).
pub fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// A directory of this process for the files a unit test writes:
/// `signorini-{tag}-{pid}` in the system's temporary directory, created.
#[cfg(test)]
pub(crate) fn test_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[cfg(test)]
mod peak_tests {
    use super::*;

    #[test]
    fn the_peak_is_reset_to_the_current_size() {
        if !std::path::Path::new("/proc/self/clear_refs").exists() {
            return; // not Linux: nothing to reset, peak_rss_bytes is 0
        }
        let big = std::hint::black_box(vec![1u8; 256 << 20]); // written, so resident
        let before = peak_rss_bytes();
        assert!(before >= 256 << 20, "{before}");
        drop(big);
        assert!(reset_peak_rss());
        let after = peak_rss_bytes();
        assert!(after + (128 << 20) < before, "{before} → {after}");
    }
}

#[cfg(test)]
mod certificate_tests {
    use super::*;

    /// A run converges only when every residual of its certificate is
    /// within the tolerance: the regularised law's too (it was left out, so a
    /// penalty-law contact far off its law was reported converged).
    #[test]
    fn the_largest_residual_counts_the_law() {
        let c = Certificate {
            equilibrium: 1e-15,
            law: 3e-3,
            tolerance: 1e-9,
            ..Default::default()
        };
        assert_eq!(c.max(), 3e-3);
    }
}
