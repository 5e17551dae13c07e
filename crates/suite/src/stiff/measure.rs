//! How a reference quantity is read from a run: the named measures of
//! `cases.toml` (`measure = "force", component = 1, contact = "c"`), each
//! giving (computed, exact).

use serde::Deserialize;
use signorini_report::ContactRow;
use signorini_solver::RunOutput;

/// One measure of a reference, as written in `cases.toml`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "measure", rename_all = "snake_case", deny_unknown_fields)]
pub enum Measure {
    /// The nodal pressure farthest from `exact` at the last step (every
    /// point: an open point has pressure 0), of `contact` or all.
    Pressure { exact: f64, contact: Option<String> },
    /// Component `component` of the resultant contact force on the slaves
    /// (of `contact`, or all) at the last step.
    Force {
        component: usize,
        exact: f64,
        contact: Option<String>,
    },
    /// Component `component` of the resultant contact force at step `step`
    /// (1-based).
    StepForce {
        step: usize,
        component: usize,
        exact: f64,
    },
    /// Component 0 of the resultant at step `step` (1-based) against
    /// −`sign` μ × its component 1: the reaction of a block dragged along
    /// x, following the motion.
    StepFriction { step: usize, mu: f64, sign: f64 },
    /// The number of contact points at the last step whose status is not
    /// `status`; exact 0.
    CountNot { status: String },
    /// A quantity of the report's `[reference]` comparison (computed, exact).
    Report { quantity: String },
    /// The penalty's force deviation from the exact solution at the last step.
    ForceDeviation { exact: f64 },
    /// The gap farthest from `exact` at the last step.
    Gap { exact: f64 },
    /// The Coulomb law at the last step: the slipping points carry exactly
    /// μ times their normal force (‖λ_t‖ = μ λ_n, summed).
    SlipOnCone { mu: f64 },
    /// The Coulomb law on the resultant at the last step: how far its
    /// tangential part exceeds μN, relative to μN (the normal along axis
    /// `normal`); exact 0.
    AboveMuN { mu: f64, normal: usize },
}

/// The contact rows of the last step (of one contact, or all).
fn last_rows<'a>(
    o: &'a RunOutput,
    contact: Option<&'a str>,
) -> impl Iterator<Item = &'a ContactRow> + 'a {
    let last = o.contact_rows.iter().map(|r| r.step).max().unwrap_or(0);
    o.contact_rows
        .iter()
        .filter(move |r| r.step == last && contact.is_none_or(|c| r.contact == c))
}

/// The value of `values` farthest from `exact`, with `exact`.
fn farthest(values: impl Iterator<Item = f64>, exact: f64) -> Option<(f64, f64)> {
    values
        .max_by(|a, b| (a - exact).abs().total_cmp(&(b - exact).abs()))
        .map(|v| (v, exact))
}

impl Measure {
    /// (computed, exact) on a run, or `None` when the run does not have
    /// the quantity.
    pub fn read(&self, o: &RunOutput) -> Option<(f64, f64)> {
        match self {
            Measure::Pressure { exact, contact } => {
                farthest(last_rows(o, contact.as_deref()).map(|r| r.pressure), *exact)
            }
            Measure::Force {
                component,
                exact,
                contact,
            } => force(o, *component, contact.as_deref()).map(|f| (f, *exact)),
            Measure::StepForce {
                step,
                component,
                exact,
            } => o
                .report
                .steps
                .get(step - 1)
                .and_then(|s| s.contact_force.get(*component))
                .map(|f| (*f, *exact)),
            Measure::StepFriction { step, mu, sign } => {
                let f = &o.report.steps.get(step - 1)?.contact_force;
                Some((f[0], -sign * mu * f[1]))
            }
            Measure::CountNot { status } => Some((
                last_rows(o, None).filter(|r| r.status != *status).count() as f64,
                0.0,
            )),
            Measure::Report { quantity } => o
                .report
                .reference
                .as_ref()
                .and_then(|r| r.quantities.get(quantity.as_str()))
                .map(|q| (q.computed, q.exact)),
            Measure::ForceDeviation { exact } => o
                .report
                .steps
                .last()
                .and_then(|s| s.regularisation.as_ref())
                .map(|r| (r.force_deviation, *exact)),
            Measure::Gap { exact } => farthest(last_rows(o, None).map(|r| r.gap), *exact),
            Measure::SlipOnCone { mu } => Some(slip_on_cone(o, *mu)),
            Measure::AboveMuN { mu, normal } => Some(above_mu_n(o, *mu, *normal)),
        }
    }
}

/// Component `k` of the resultant contact force on the slaves (one contact,
/// or all) at the last step.
fn force(o: &RunOutput, k: usize, contact: Option<&str>) -> Option<f64> {
    match contact {
        None => o.report.contact_force.get(k).copied(),
        Some(c) => o
            .report
            .contacts
            .iter()
            .find(|s| s.name == c)
            .and_then(|s| s.force.get(k))
            .copied(),
    }
}

fn slip_on_cone(o: &RunOutput, mu: f64) -> (f64, f64) {
    let (t, n) = last_rows(o, None)
        .filter(|r| r.status == "slip")
        .fold((0.0, 0.0), |(t, n), r| {
            (
                t + r.tangential_force.hypot(r.tangential_force_2),
                n + r.normal_force,
            )
        });
    (t, mu * n)
}

fn above_mu_n(o: &RunOutput, mu: f64, normal: usize) -> (f64, f64) {
    let f = &o.report.contact_force;
    let t = (0..f.len())
        .filter(|&k| k != normal)
        .map(|k| f[k] * f[k])
        .sum::<f64>()
        .sqrt();
    ((t - mu * f[normal]).max(0.0) / (mu * f[normal]), 0.0)
}
