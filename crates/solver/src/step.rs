//! What a step's solve and a run's paths hand on: the root's solution of
//! one step (with its friction state), the residual pieces of a step for the
//! certificate, and what both paths hand to the report.

use signorini_contact::friction::PointStatus;
use signorini_contact::ContactSolution;
use signorini_report::results::BodyResult;
use signorini_report::{Certificate, ContactRow, Regularisation, StepReport};

use crate::model::PointModel;

/// One step solved on the root.
pub(crate) struct StepSolution {
    /// The contact problem's answer, with the report of the method that ran.
    pub(crate) outcome: ContactSolution,
    pub(crate) gap0: Vec<f64>,
    pub(crate) f_scale: f64,
    pub(crate) length_scale: f64,
    pub(crate) regularisation: Option<Regularisation>,
    /// Penalty stiffness of each point whose contact has a regularised law (0: unilateral).
    pub(crate) law_k: Vec<f64>,
    /// Friction state at the end of the step, when a contact has friction.
    pub(crate) friction: Option<FrictionStep>,
    /// Seconds of this step's root solve, and of building the Delassus
    /// operator when this step built it (the first step), else 0.
    pub(crate) solve_s: f64,
    pub(crate) operator_s: f64,
}

/// Friction at one step, per contact point (zeros for frictionless points).
#[derive(Clone)]
pub(crate) struct FrictionStep {
    pub(crate) statuses: Vec<PointStatus>,
    pub(crate) tangential: Vec<f64>,
    pub(crate) slip_increment: Vec<f64>,
    pub(crate) slip_total: Vec<f64>,
    /// Along the second tangent (3D; zeros in 2D).
    pub(crate) tangential2: Vec<f64>,
    pub(crate) slip_increment2: Vec<f64>,
    pub(crate) slip_total2: Vec<f64>,
    /// The threshold in force at the solution (Tresca g or μ λ_n).
    pub(crate) threshold: Vec<f64>,
    /// How far the tangential force lies outside its admissible set, in
    /// force (≤ 0 inside): |λ_t| − g in 2D, ‖λ_t‖ − g on the Tresca disc,
    /// μ₁ (‖(λ_t1/μ₁, λ_t2/μ₂)‖ − λ_n) on the (elliptic) Coulomb cone;
    /// with roughness, of the slider force λ_t + Q g (course notes §6).
    pub(crate) cone_excess: Vec<f64>,
    /// The back force Q g of a rough point (course notes §6; zero without
    /// roughness), along t1 and t2: the slider force is λ_t + Q g.
    pub(crate) back_force: Vec<f64>,
    pub(crate) back_force2: Vec<f64>,
}

impl FrictionStep {
    /// The statuses of `m` points with every force, slip, threshold and
    /// excess zero, for the step's solver to fill in.
    pub(crate) fn zeros(statuses: Vec<PointStatus>, m: usize) -> Self {
        FrictionStep {
            statuses,
            tangential: vec![0.0; m],
            slip_increment: vec![0.0; m],
            slip_total: vec![0.0; m],
            tangential2: vec![0.0; m],
            slip_increment2: vec![0.0; m],
            slip_total2: vec![0.0; m],
            threshold: vec![0.0; m],
            cone_excess: vec![0.0; m],
            back_force: vec![0.0; m],
            back_force2: vec![0.0; m],
        }
    }
}

/// What both paths hand to the report.
pub(crate) struct Partial {
    pub(crate) steps: Vec<StepReport>,
    pub(crate) certificate: Certificate,
    pub(crate) converged: bool,
    pub(crate) failure: Option<String>,
    pub(crate) contact_rows: Vec<ContactRow>,
    pub(crate) lambda: Vec<f64>,
    /// Full displacement of each body at the last step.
    pub(crate) u_last: Vec<Vec<f64>>,
    /// Each body's mesh, and (once the last step ended) its fields at the
    /// last step.
    pub(crate) bodies: Vec<BodyResult>,
    /// The lowest gap over the steps of each point left out of the contact
    /// zone (`ModelData::excluded`), for the check that none penetrates.
    pub(crate) excluded_gaps: Vec<f64>,
    pub(crate) dense_interface_bytes: u64,
    pub(crate) factor_bytes: u64,
    /// Ordering, size and flops of the factorisation (report.json
    /// `factorisation`).
    pub(crate) factorisation: Option<signorini_report::Factorisation>,
    pub(crate) n_gamma: usize,
    pub(crate) dofs: usize,
    pub(crate) solver: serde_json::Value,
    /// Friction at the last step.
    pub(crate) friction: Option<FrictionStep>,
    /// Condition estimates (report.json `conditioning`).
    pub(crate) conditioning: Option<signorini_report::Conditioning>,
}

/// Residual pieces of one step for the certificate.
pub(crate) struct Residuals {
    /// Largest equilibrium residual (interior and Γ, contact forces included).
    pub(crate) equilibrium: f64,
    /// Largest internal or external force entry.
    pub(crate) force_scale: f64,
    /// K u − f on the prescribed DOFs, as (body, DOF, value); a DOF shared
    /// by subdomains appears once per subdomain, their values to be summed.
    pub(crate) support: Vec<(usize, usize, f64)>,
    /// The force of each tie's master on its slave: (contact, resultant).
    pub(crate) ties: Vec<(usize, Vec<f64>)>,
}

/// Every contact row's force on its DOFs, as (body, DOF, coefficient ×
/// force): each point's normal row times λ_n, and its tangential rows (those
/// with a friction unknown, and those a support drags) times the tangential
/// forces of `friction`; rows whose force is zero are left out.
pub(crate) fn contact_row_forces<'a>(
    points: &'a [PointModel],
    lambda: &'a [f64],
    friction: Option<&'a FrictionStep>,
) -> impl Iterator<Item = (usize, usize, f64)> + 'a {
    points.iter().enumerate().flat_map(move |(pi, p)| {
        let (t1, t2) = friction.map_or((0.0, 0.0), |f| (f.tangential[pi], f.tangential2[pi]));
        let dragged = p.prescribed_slip.as_ref();
        let rows = [
            (Some(&p.row), lambda[pi]),
            (p.trow.as_ref(), t1),
            (p.trow2.as_ref(), t2),
            (dragged.map(|s| &s.t1), t1),
            (dragged.and_then(|s| s.t2.as_ref()), t2),
        ];
        rows.into_iter()
            .filter_map(|(row, force)| row.map(|r| (r, force)))
            .filter(|&(_, force)| force != 0.0)
            .flat_map(move |(row, force)| row.iter().map(move |&(b, d, c)| (b, d, c * force)))
    })
}
