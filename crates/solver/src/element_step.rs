//! One load step of the contact elements of course notes §7 on the condensed
//! problem: the run picks this solve for `discretization =
//! "contact_elements"`, and for any contact with a regularised normal law
//! (`law = { penalty }`) and friction: each point is an element with the
//! stiffnesses of its contact times its tributary measure, solved by the
//! return mapping and Newton's method of
//! [`signorini_contact::contact_elements`]; the slip history g goes from
//! step to step.

use crate::error::{contact_error, SolveError};
use crate::friction_step::row_gaps;
use crate::interface_problem::{Interface, RootInput, StepLoad};
use crate::step::{FrictionStep, StepSolution};
use signorini_contact::contact_elements::{self, ContactElement, ElementOptions, SlipThreshold};
use signorini_contact::friction::{FrictionLaw, PointStatus};
use signorini_contact::{ContactSolution, DelassusOperator};
use signorini_scene as scene;

/// The run's method (report.json `method`) when it solves contact elements.
pub(crate) const RETURN_MAPPING: &str = "contact_elements_return_mapping";

/// Whether the scene's contacts are solved as contact elements: some
/// contact is `contact_elements`, or has a penalty law with friction.
pub(crate) fn uses_return_mapping(sc: &scene::Scene) -> bool {
    sc.contact.iter().any(|c| {
        c.discretization == scene::Discretization::ContactElements
            || (matches!(c.law, scene::Law::Penalty { .. }) && c.friction != scene::Friction::None)
    })
}

/// Refuses what the contact elements' solve cannot run: the direct path, a
/// contact without a penalty law, Norton–Hoff friction, the elliptic
/// (anisotropic) Coulomb cone.
pub(crate) fn check_return_mapping(
    sc: &scene::Scene,
    path: scene::SolvePath,
) -> Result<(), SolveError> {
    let why = "the contact elements' return mapping (course notes §7)";
    if path == scene::SolvePath::Direct {
        return Err(SolveError::Input(format!(
            "solver.path: {why} runs on path = \"condensed\", not \"direct\""
        )));
    }
    for c in &sc.contact {
        let entry = format!("contact \"{}\"", c.name);
        if c.law == scene::Law::Unilateral {
            let what = if c.discretization == scene::Discretization::ContactElements {
                "discretization = \"contact_elements\" needs a regularised normal law"
            } else {
                "the scene's contacts are solved by the contact elements' return mapping (course notes §7), which needs a regularised normal law on every contact"
            };
            return Err(SolveError::Input(format!(
                "{entry}.law: {what}: give law = {{ penalty = <k_n> }} (normal stiffness per unit area)"
            )));
        }
        match &c.friction {
            scene::Friction::NortonHoff { .. } => {
                return Err(SolveError::Input(format!(
                    "{entry}.friction: Norton-Hoff friction has no return mapping in {why}; use \"none\", tresca or coulomb (with slip_stiffness, roughness)"
                )))
            }
            scene::Friction::Coulomb { coefficient, .. }
                if coefficient.len() > 1 && coefficient[0] != coefficient[1] =>
            {
                return Err(SolveError::Input(format!(
                    "{entry}.friction: the elliptic Coulomb cone (two coefficients) has no closed-form radial return in {why}; give one coefficient"
                )))
            }
            _ => {}
        }
    }
    Ok(())
}

/// The slip g of every row at the end of the last step (zero on normal
/// rows), and the last forces (the next step's start).
pub(crate) struct ElementHistory {
    slip: Vec<f64>,
    forces: Option<Vec<f64>>,
}

impl ElementHistory {
    pub(crate) fn new(n_rows: usize) -> Self {
        Self {
            slip: vec![0.0; n_rows],
            forces: None,
        }
    }
}

/// How many times the bodies' own stiffness at a point, 1/W_ii, an
/// element's k_n A may be: beyond it the Newton matrix of the return mapping
/// (I + W K_e) keeps fewer digits than its solve checks (1e-8), and a
/// stiffer element joins the bodies no more rigidly.
const ELEMENT_STIFFNESS_RATIO: f64 = 1e7;

/// Refuses a contact's `law.penalty` whose elements are stiffer than
/// [`ELEMENT_STIFFNESS_RATIO`] times the bodies at some point (the Delassus
/// operator `w`: before any solve), with the largest penalty that is not.
fn check_element_stiffness(
    input: &RootInput,
    elements: &[ContactElement],
    w: &faer::Mat<f64>,
) -> Result<(), SolveError> {
    for (ci, c) in input.sc.contact.iter().enumerate() {
        let scene::Law::Penalty { penalty } = c.law else {
            continue;
        };
        let ratio = (input.points.iter().zip(elements))
            .filter(|(p, _)| p.contact == ci)
            .map(|(_, e)| e.normal_stiffness * w[(e.normal_row, e.normal_row)])
            .fold(0.0f64, f64::max);
        if ratio > ELEMENT_STIFFNESS_RATIO {
            return Err(SolveError::Input(format!(
                "contact \"{}\".law.penalty: {} makes its elements {ratio:.1e} times stiffer than the bodies they join (1/W_ii at a point), more than the {ELEMENT_STIFFNESS_RATIO:e} double precision can solve; give law.penalty <= {:.2e} (a stiffer element joins the bodies no more rigidly)",
                c.name,
                scene::Shown(penalty),
                penalty * ELEMENT_STIFFNESS_RATIO / ratio
            )));
        }
    }
    Ok(())
}

/// Each contact point as an element: its rows, k_n A, k_t A (the contact's
/// slip_stiffness, else k_t = k_n), Q A, and its threshold.
fn elements(input: &RootInput, interface: &Interface) -> Vec<ContactElement> {
    let sc = input.sc;
    input
        .points
        .iter()
        .enumerate()
        .map(|(pi, p)| {
            let c = &sc.contact[p.contact];
            let k_n = match c.law {
                scene::Law::Penalty { penalty } => penalty * p.tributary,
                scene::Law::Unilateral | scene::Law::Tied => 0.0,
            };
            let roughness = match &c.friction {
                scene::Friction::Coulomb {
                    roughness: Some(q), ..
                } => q * p.tributary,
                _ => 0.0,
            };
            let threshold = match p.friction {
                FrictionLaw::Tresca(g) => SlipThreshold::Tresca(g),
                FrictionLaw::Coulomb { mu } => SlipThreshold::Coulomb(mu[0]),
                _ => SlipThreshold::None,
            };
            ContactElement {
                normal_row: pi,
                tangent_rows: [interface.tangent_row[pi], interface.tangent_row2[pi]]
                    .into_iter()
                    .flatten()
                    .collect(),
                normal_stiffness: k_n,
                tangential_stiffness: p.slip_stiffness.unwrap_or(k_n),
                roughness,
                threshold,
            }
        })
        .collect()
}

/// One step of the contact elements: the problem with the total tangential
/// jumps as the tangential rows' values, solved from the last step's forces
/// with its slips; returns the step and u_Γ, and updates the history.
pub(crate) fn element_step(
    input: &RootInput,
    interface: &Interface,
    history: &mut ElementHistory,
    op: &DelassusOperator,
    load: StepLoad,
) -> Result<(StepSolution, Vec<f64>), SolveError> {
    let m = input.points.len();
    let gap0 = row_gaps(input, &load, |_| (0.0, 0.0));
    let mut problem = op.problem(&gap0, &load.fp);
    let elements = elements(input, interface);
    check_element_stiffness(input, &elements, &problem.w)?;
    let opts = ElementOptions {
        max_iterations: input.sc.solver.max_iterations,
        tolerance: input.sc.solver.tolerance,
        force_scale: load.f_scale,
    };
    let start = history.forces.as_deref();
    let out = contact_elements::solve(&mut problem, &elements, &history.slip, start, &opts)
        .map_err(contact_error)?;
    let mut sol = out.solution;
    let u = problem.displacement(&sol.forces);
    let friction = interface
        .tangent_row
        .iter()
        .any(Option::is_some)
        .then(|| friction_of(&elements, &sol, &history.slip, &out.slip, m));
    history.slip = out.slip;
    history.forces = Some(sol.forces.clone());
    sol.forces.truncate(m);
    sol.gaps.truncate(m);
    sol.alpha = vec![];
    sol.report.operator_applications = problem.solves;
    let law_k = elements.iter().map(|e| e.normal_stiffness).collect();
    Ok((
        StepSolution {
            outcome: sol,
            gap0: load.gap0,
            f_scale: load.f_scale,
            length_scale: load.length_scale,
            regularisation: None,
            law_k,
            friction,
            solve_s: 0.0,
            operator_s: 0.0,
        },
        u,
    ))
}

/// The friction state of the step per element: tangential forces, slip
/// increments and totals (the plastic slip g), the threshold, the excess of
/// the slider force λ_t + Q g over it, and the back force Q g.
fn friction_of(
    elements: &[ContactElement],
    sol: &ContactSolution,
    slip_old: &[f64],
    slip: &[f64],
    m: usize,
) -> FrictionStep {
    let mut f = FrictionStep::zeros(sol.friction.points.clone(), m);
    for (p, e) in elements.iter().enumerate() {
        let ln = sol.forces[p];
        f.threshold[p] = match e.threshold {
            SlipThreshold::None => 0.0,
            SlipThreshold::Tresca(g) if ln > 0.0 => g,
            SlipThreshold::Tresca(_) => 0.0,
            SlipThreshold::Coulomb(mu) => mu * ln.max(0.0),
        };
        let mut slider = 0.0f64;
        for (i, &t) in e.tangent_rows.iter().enumerate() {
            // Open, the asperities are unloaded: no back force.
            let open = f.statuses[p] == PointStatus::Open;
            let back = if open { 0.0 } else { e.roughness * slip[t] };
            let lt = sol.forces[t];
            let (force, inc, total, b) = match i {
                0 => (
                    &mut f.tangential,
                    &mut f.slip_increment,
                    &mut f.slip_total,
                    &mut f.back_force,
                ),
                _ => (
                    &mut f.tangential2,
                    &mut f.slip_increment2,
                    &mut f.slip_total2,
                    &mut f.back_force2,
                ),
            };
            force[p] = lt;
            inc[p] = slip[t] - slip_old[t];
            total[p] = slip[t];
            b[p] = back;
            slider = slider.hypot(lt + back);
        }
        if !e.tangent_rows.is_empty() {
            f.cone_excess[p] = slider - f.threshold[p];
        }
    }
    f
}
